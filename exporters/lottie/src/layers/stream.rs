//! The root's layers of a large scene built as the writer reaches them, a run of the
//! root's children at a time, instead of all held before the first is written: at 999 000
//! animated shapes the layers' models (904 bytes each) and texts (857) were most of the
//! export's 6 GB.
//!
//! The root's layers are written topmost first, that is from its last child back, but
//! numbered (`ind`) and their precompositions named (`comp_N`) from its first child on,
//! and the document's head (its assets) precedes them. So the children are built from the
//! first on, a run at a time, and each run's text goes to a temporary file
//! ([`Builder::spill_root`]), copied to the output last run first once the head is known.
//! When the layers' parent is the null that fits the canvas to another size, numbered
//! after them all, or no temporary file can be written, they are built twice instead: a
//! first pass ([`Builder::plan_root`]) keeps what the head and the numbering need (the
//! assets, the warnings, where each child's numbers start) and drops the layers; the
//! second ([`Builder::write_root`]) builds them again a run at a time from the last run
//! back, numbers them as planned and writes them. Each child is built on its own (as
//! [`Builder::children_in_parallel`] builds it), so every way builds the same layers and
//! the document is the same, byte for byte, as when it is built whole (tested).

use std::io::{self, Write};

use kurbo::Affine;
use rayon::prelude::*;

use std::ops::Range;

use gmotion::scene::Node;

use super::{Builder, Env, Item, PARALLEL_CHILDREN, Seed, Source, paints, renumber};
use crate::animate::UnitMotion;
use crate::model::{Layer, write_layers};

/// Bakes the motions of a range of shapes ([`Source::motions`]).
pub(crate) type Bake<'b> = dyn Fn(Range<usize>) -> Vec<UnitMotion> + Sync + 'b;

/// How many of the root's children are built at a time, and the fewest for which the
/// root is built in runs at all: a run's layers are a few megabytes, and below one run
/// building twice would save nothing.
pub(crate) const RUN: usize = 4096;

/// What the first pass learned: enough to number the root's layers and write the head.
pub(crate) struct Plan {
    /// Per child of the root: the layer indices and the precompositions made before it.
    starts: Vec<(u32, u32)>,
    /// The highest index among the root's layers (0 when it has none).
    pub max_ind: u32,
    /// The root's transform, with which its children are drawn.
    acc: Affine,
    /// What applies to the root's children.
    env: Env,
}

impl<'a> Builder<'a> {
    /// The first pass over the root's children, for a root that is a plain group of at
    /// least [`RUN`] children that each make only layers (animated shapes, named groups
    /// of them): `None` for any other root, which is built whole ([`Builder::layers`]).
    /// Takes every child's warnings and precompositions as the whole build would.
    /// The root's children's motions are baked by `bake` a run at a time, as in
    /// [`Builder::write_root`], rather than all held.
    pub(crate) fn plan_root(&mut self, size: (u32, u32), bake: &Bake) -> Option<Plan> {
        let (acc, env) = self.plain_root(size)?;
        let scene: &'a gmotion::scene::Scene = self.src.scene;
        let root = &scene.root;
        let mut starts = Vec::with_capacity(root.children.len());
        let (mut next, mut max_ind) = (0u32, 0u32);
        for run in root.children.chunks(RUN) {
            let units = units_in(run);
            let motions = bake(units.clone());
            let seed = self.seed_for(&motions, units.start);
            // Only counted and dropped: not written.
            let parts: Vec<_> = (run.par_iter())
                .map(|c| seed.part(c, acc, env, false))
                .collect();
            for mut part in parts {
                // Still shapes among the root's children are merged with their
                // neighbours' into shape layers, across runs: built whole.
                let mut layers = Vec::new();
                for item in &part.items {
                    match item {
                        Item::Shape(_) => return None,
                        Item::Layers(ls) => layers.extend(ls.iter().map(|l| l.ind)),
                    }
                }
                let asset = self.adopt(&mut part);
                max_ind = layers.into_iter().map(|i| i + next).fold(max_ind, u32::max);
                starts.push((next, u32::try_from(asset).ok()?));
                next += part.inds;
            }
        }
        Some(Plan {
            starts,
            max_ind,
            acc,
            env,
        })
    }

    /// The transform and the settings the root's children are drawn with, for a root that
    /// is a plain group of at least [`RUN`] children (one that `group` hands straight to
    /// `children`, which builds them in parallel); `None` for any other.
    fn plain_root(&self, size: (u32, u32)) -> Option<(Affine, Env)> {
        let root = &self.src.scene.root;
        let plain = root.unit.is_none()
            && root.opacity > 0.0
            && root.children.len() >= RUN.max(PARALLEL_CHILDREN)
            && root.clip_path.is_none()
            && root.mask.is_none()
            && root.filter.is_none()
            && !(root.opacity < 1.0 && paints(root) > 1)
            && root.id.is_empty();
        let env = Env {
            alpha: root.opacity as f64,
            unit: None,
            to_canvas: Affine::IDENTITY,
            size,
        };
        plain.then_some((root.transform, env))
    }

    /// The root's layers built once, a run of children at a time from the first, for a
    /// root that [`Builder::plan_root`] would plan and layers that need no parent: each
    /// run's text, topmost first and each layer after a comma, is written to `spill` and
    /// the run freed. Returns the length of each run's text in `spill`, first run first;
    /// `None` for a root built otherwise. Takes every child's warnings and
    /// precompositions as the whole build would.
    pub(crate) fn spill_root(
        &mut self,
        size: (u32, u32),
        bake: &Bake,
        spill: &mut dyn Write,
    ) -> io::Result<Option<Vec<u64>>> {
        let Some((acc, env)) = self.plain_root(size) else {
            return Ok(None);
        };
        let scene: &'a gmotion::scene::Scene = self.src.scene;
        let mut runs = Vec::new();
        let mut next = 0u32;
        for run in scene.root.children.chunks(RUN) {
            let units = units_in(run);
            let motions = bake(units.clone());
            let seed = self.seed_for(&motions, units.start);
            let parts: Vec<_> = (run.par_iter())
                .map(|c| seed.part(c, acc, env, true))
                .collect();
            let mut layers = Vec::new();
            for mut part in parts {
                // As in `plan_root`: still shapes are merged across children.
                if part.items.iter().any(|i| matches!(i, Item::Shape(_))) {
                    return Ok(None);
                }
                let asset = self.adopt(&mut part);
                renumber(&mut part.items, next, asset);
                next += part.inds;
                for item in part.items {
                    if let Item::Layers(ls) = item {
                        layers.extend(ls);
                    }
                }
            }
            // Bottom first in each child and from child to child: reversed, topmost
            // first; each after a comma (as any but the document's first layer).
            layers.reverse();
            let mut counted = Counted { out: spill, n: 0 };
            write_layers(&mut counted, 1, layers)?;
            runs.push(counted.n);
        }
        Ok(Some(runs))
    }

    /// What builds a part with `motions`, the motions of the shapes from `first` on.
    fn seed_for<'m>(&self, motions: &'m [UnitMotion], first: usize) -> Seed<'m>
    where
        'a: 'm,
    {
        Seed {
            src: Source {
                motions,
                first_motion: first,
                ..self.src
            },
            ..self.seed()
        }
    }

    /// The second pass: the root's layers, topmost first, written to `out` as
    /// [`crate::model::Animation::write_with`] asks, numbered as `plan` says and parented
    /// to `parent` (the null that fits the canvas to the output) when given.
    pub(crate) fn write_root(
        &self,
        plan: &Plan,
        parent: Option<u32>,
        bake: &Bake,
        out: &mut dyn Write,
    ) -> io::Result<usize> {
        let children = &self.src.scene.root.children;
        let mut written = 0;
        let mut end = children.len();
        while end > 0 {
            // Runs start where the first pass's did, so each bakes the same shapes.
            let start = (end - 1) / RUN * RUN;
            let units = units_in(&children[start..end]);
            let motions = bake(units.clone());
            let seed = self.seed_for(&motions, units.start);
            let built: Vec<Vec<Layer>> = (start..end)
                .into_par_iter()
                .map(|k| {
                    let mut part = seed.part(&children[k], plan.acc, plan.env, true);
                    let (ind, asset) = plan.starts[k];
                    renumber(&mut part.items, ind, asset as usize);
                    let mut layers = Vec::new();
                    for item in part.items {
                        if let Item::Layers(ls) = item {
                            layers.extend(ls);
                        }
                    }
                    if let Some(p) = parent {
                        for l in layers.iter_mut().filter(|l| l.parent.is_none()) {
                            l.parent = Some(p);
                        }
                    }
                    layers
                })
                .collect();
            // Bottom first in each child and from child to child: reversed, topmost first.
            let run: Vec<Layer> = built.into_iter().flatten().rev().collect();
            written = write_layers(out, written, run)?;
            end = start;
        }
        Ok(written)
    }
}

/// A writer that counts the bytes written through it.
struct Counted<'w> {
    out: &'w mut dyn Write,
    n: u64,
}

impl Write for Counted<'_> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.out.write(buf)?;
        self.n += n as u64;
        Ok(n)
    }

    fn write_vectored(&mut self, bufs: &[io::IoSlice<'_>]) -> io::Result<usize> {
        let n = self.out.write_vectored(bufs)?;
        self.n += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

/// The shapes `nodes` hold (the units of their nodes and of every node inside), as the
/// range from the first to one past the last.
fn units_in(nodes: &[Node]) -> Range<usize> {
    fn walk(node: &Node, lo: &mut usize, hi: &mut usize) {
        if let Some(u) = node.unit() {
            *lo = (*lo).min(u);
            *hi = (*hi).max(u + 1);
        }
        if let Node::Group(g) = node {
            g.children.iter().for_each(|c| walk(c, lo, hi));
        }
    }
    let (mut lo, mut hi) = (usize::MAX, 0);
    nodes.iter().for_each(|n| walk(n, &mut lo, &mut hi));
    lo.min(hi)..hi
}

#[cfg(test)]
mod tests {
    use std::fmt::Write as _;

    use gmotion::canvas::OutputSize;

    use crate::{LottieOptions, Parts, layer_names, write};

    /// `n` children of the root, every one an animated shape: squares, squares clipped
    /// by a circle (a layer mask) or by a frame (a track matte, its `tp` a layer number),
    /// and groups of two squares with group opacity (a precomposition, by `refId`).
    fn scene(n: usize) -> String {
        let mut svg = String::from(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="1000">
<defs><clipPath id="one"><circle cx="5" cy="5" r="4"/></clipPath>
<clipPath id="two"><path clip-rule="evenodd" d="M0 0h10v10h-10z M2 2h6v6h-6z"/></clipPath></defs>
"#,
        );
        for i in 0..n {
            let (x, y) = ((i % 100) * 10, (i / 100) * 10 % 1000);
            let rect = format!(r##"x="{x}" y="{y}" width="8" height="8" fill="#e4572e""##);
            let _ = match i % 4 {
                0 => writeln!(svg, r#"<rect data-tag="s" {rect}/>"#),
                1 => writeln!(svg, r#"<rect data-tag="s" clip-path="url(#one)" {rect}/>"#),
                2 => writeln!(svg, r#"<rect data-tag="s" clip-path="url(#two)" {rect}/>"#),
                _ => writeln!(
                    svg,
                    r#"<g id="g{i}" opacity="0.5"><rect data-tag="s" {rect}/><rect data-tag="s" {rect} transform="translate(1 1)"/></g>"#
                ),
            };
        }
        svg.push_str("</svg>\n");
        svg
    }

    /// The document written as it is built, once through a file or twice, is the
    /// document built whole, byte for byte, over several runs of children (the last one
    /// partial); and it is indeed written as it is built.
    #[test]
    fn a_root_written_as_it_is_built_is_the_root_built_whole() {
        let n = 2 * super::RUN + 100;
        let imported =
            gmotion_import_svg::parse(&scene(n), "many.svg", &Default::default()).unwrap();
        let gm = gmotion::grammar::parse(
            "duration 1s\nfps 10\n\
             timesplit(0.5, 0.5) : [all, s] -> [a, b]\n\
             animate(affine, world, 0, translate(2, 0)) : [a, s] -> [t]\n\
             animate(opacity, local, 0.00001 * id, 0.5) : [b, s] -> [o]\n",
        )
        .unwrap();
        let anim = gmotion::engine::run(imported.scene, &gm, &Default::default())
            .unwrap()
            .0;
        assert!(anim.scene.root.children.len() >= n);
        // Fitted to another size, the root's layers take the fitting null as their parent,
        // numbered after them all: built twice. Else built once, through a file.
        for (size, held) in [(None, "spilled"), (Some(500), "stream")] {
            let opts = LottieOptions {
                size: OutputSize {
                    width: size,
                    height: None,
                },
                ..LottieOptions::default()
            };
            let parts = || Parts {
                scene: &anim.scene,
                tracks: &anim.tracks,
                baked_from: Some((&anim, opts.tolerance)),
                bakes: Default::default(),
                motions: Vec::new(),
                names: layer_names(&anim.scene),
                fps: anim.fps,
                op: anim.frame_count() as f64,
            };
            let (streamed, warned) = write(parts(), &opts, true).unwrap();
            assert_eq!(streamed.held(), held, "the root was built otherwise");
            let (whole, warned_whole) = write(parts(), &opts, false).unwrap();
            assert_eq!(whole.held(), "document");
            let (streamed, whole) = (streamed.into_string(), whole.into_string());
            assert!(whole.contains("\"tp\":") && whole.contains("\"refId\":"));
            assert!(streamed == whole, "the documents differ ({size:?})");
            assert_eq!(warned, warned_whole);
        }
    }
}
