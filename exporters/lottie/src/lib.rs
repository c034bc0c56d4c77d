//! Lottie export: an [`Animation`] (or a still [`Scene`]) as Lottie JSON that validates
//! against the official schema and plays in lottie-web, rlottie and ThorVG.
//!
//! What is written:
//!
//! - one shape layer per animated shape, named after its tag: `letter_G` for a tag's only
//!   shape, `Wheel 1`, `Wheel 2`… for the shapes of a tag with several ([`layer_names`]; a
//!   still shape is a group of that name), in paint order;
//! - the source's named groups (`<g id>`, and the `<svg>`'s own id) whose content makes
//!   layers as null layers of that name, parents of those layers, so that the layer tree
//!   reads as the designer's groups (`Layer_1` › `Wheel` › `Wheel 1`, `Wheel 2`); the nulls
//!   are the identity, group transforms and opacity staying where they were;
//! - paths as Bézier outlines (quadratics raised to cubics, one `sh` per subpath); fills
//!   and strokes, solid or linear/radial gradient with colour and opacity stops, fill
//!   rule, opacity, caps, joins, miter limit and dashes, in SVG paint order; group
//!   transforms as skew-free levels (a skew is written as a rotation·scale·rotation pair,
//!   since rlottie cannot draw skew);
//! - clip paths as layer masks, or as alpha track mattes when they are more than a union
//!   of simple outlines; masks as luma or alpha track mattes; group opacity over several
//!   paints as layer opacity; patterns as tiles under an alpha matte of the outline;
//! - motion exactly where Lottie can say it (see the `animate` module): nested transform levels
//!   with keyframes at window boundaries and the ends of the active interval, eased by the
//!   motion's Bézier, holds where the motion jumps; colour tints, opacity and stroke-width
//!   multipliers as keyframes on `fl.c`/`st.c`/gradient stops, layer `o` and `st.w`;
//! - elsewhere (Alexa interpolation, bilinear blends, skew and matrix components,
//!   non-Bézier easing, per-vertex deformation) sampled per frame and reduced greedily
//!   within [`LottieOptions::tolerance`] canvas units (the `bake` module).
//!
//! A scene imported from Lottie is written back over its source instead ([`layered`]): the
//! document as it was read, with gmotion's motion layered on top.
//!
//! What is approximated, with a warning naming the element: focal radii of radial
//! gradients, radial gradients stretched on strokes, `miter-clip` joins, repeating
//! gradients with a focal point, patterns too fine to tile. Lottie players loop by
//! default and the format has no "play once" flag, so a non-looping animation is written
//! the same way (the player decides).

mod animate;
mod bake;
mod fold;
mod follow;
mod geometry;
mod keys;
pub mod layered;
mod layers;
mod model;
mod pack;
mod paint;
mod restyle;
pub mod slots;
mod text;

use std::ops::Range;

use rayon::prelude::*;

use animate::{Bakes, UnitInfo, UnitMotion, may_stroke, unit_motion};
use gmotion::Warning;
use gmotion::canvas::{Fit, OutputSize, pixels};
use gmotion::engine::markers::Marker;
use gmotion::engine::slots::SlotKinds;
use gmotion::motion::{Animation, Track};
use gmotion::scene::Scene;
use layers::Source;
pub use layers::layer_names;
pub use text::LottieText;

/// Options of the Lottie export.
#[derive(Clone, Debug, PartialEq)]
pub struct LottieOptions {
    /// Error bound (canvas units) for motion that has to be sampled and reduced.
    pub tolerance: f64,
    /// The animation's name (`nm`).
    pub name: String,
    /// The composition's size `w` × `h`, the art scaled to fit (see [`OutputSize`]).
    /// Default: the scene's size.
    pub size: OutputSize,
    /// Named spans written as the document's `markers` (the grammar's `markers`).
    pub markers: Vec<Marker>,
    /// The properties given Lottie slots (the grammar's `slots`; see [`slots`]).
    pub slots: SlotKinds,
    /// Whether runs of plain shape layers are written as one layer of named groups
    /// (`--pack`): faster to play, one layer where After Effects saw many (see the `pack`
    /// module).
    pub pack: bool,
}

impl Default for LottieOptions {
    fn default() -> Self {
        LottieOptions {
            tolerance: 0.25,
            name: "gmotion".to_string(),
            size: OutputSize::default(),
            markers: Vec::new(),
            slots: SlotKinds::default(),
            pack: false,
        }
    }
}

/// The JSON text and the warnings: features dropped or approximated, each naming the
/// element.
pub type LottieOutput = (String, Vec<Warning>);

/// Why an export failed.
#[derive(Debug, thiserror::Error)]
pub enum LottieError {
    /// The canvas is empty or not finite.
    #[error("the canvas is {width}×{height}; Lottie needs a positive, finite size")]
    Size {
        /// Width.
        width: f64,
        /// Height.
        height: f64,
    },
    /// Frame rate or duration unusable.
    #[error(
        "the animation's frame rate ({fps}) and duration ({duration} s) must be positive and finite"
    )]
    Timing {
        /// Frames per second.
        fps: f64,
        /// Seconds.
        duration: f64,
    },
    /// The animation has a different number of tracks than shapes.
    #[error("the animation has {tracks} tracks for {shapes} shapes")]
    Tracks {
        /// Tracks.
        tracks: usize,
        /// Shapes.
        shapes: usize,
    },
}

/// Shapes from which an export bakes their motions in parallel.
const PARALLEL_UNITS: usize = 64;

/// Writes an animation as Lottie JSON.
pub fn to_lottie(anim: &Animation, opts: &LottieOptions) -> Result<LottieOutput, LottieError> {
    to_lottie_text(anim, opts).map(|(text, warnings)| (text.into_string(), warnings))
}

/// [`to_lottie`] with the text not yet written: [`LottieText::write_to`] writes it to a
/// file a run of layers at a time, never holding the whole text, and for a large scene
/// builds the layers as it writes them, so they are never all held either.
pub fn to_lottie_text<'a>(
    anim: &'a Animation,
    opts: &LottieOptions,
) -> Result<(LottieText<'a>, Vec<Warning>), LottieError> {
    if !(anim.fps.is_finite() && anim.fps > 0.0 && anim.duration.is_finite() && anim.duration > 0.0)
    {
        return Err(LottieError::Timing {
            fps: anim.fps,
            duration: anim.duration,
        });
    }
    if anim.tracks.len() != anim.scene.shapes.len() {
        return Err(LottieError::Tracks {
            tracks: anim.tracks.len(),
            shapes: anim.scene.shapes.len(),
        });
    }
    let parts = Parts {
        scene: &anim.scene,
        tracks: &anim.tracks,
        baked_from: Some((anim, opts.tolerance)),
        bakes: Bakes::default(),
        motions: Vec::new(),
        names: layer_names(&anim.scene),
        fps: anim.fps,
        op: anim.frame_count() as f64,
    };
    write(parts, opts, true)
}

/// Writes a still scene as a one-frame Lottie.
pub fn still_to_lottie(scene: &Scene, opts: &LottieOptions) -> Result<LottieOutput, LottieError> {
    let parts = Parts {
        scene,
        tracks: &[],
        baked_from: None,
        bakes: Bakes::default(),
        motions: Vec::new(),
        names: layer_names(scene),
        fps: 30.0,
        op: 1.0,
    };
    write(parts, opts, false).map(|(text, warnings)| (text.into_string(), warnings))
}

/// What a document's layers are built from ([`Source`]), owning the motions and names,
/// which a document written as it is built ([`write`]) needs until it is written.
struct Parts<'a> {
    scene: &'a Scene,
    tracks: &'a [Track],
    /// The animation whose tracks the motions are baked from, and within what tolerance
    /// (none for a still).
    baked_from: Option<(&'a Animation, f64)>,
    /// The bakes shared by shapes that move alike.
    bakes: Bakes,
    /// Every shape's motion, once [`Parts::bake_all`] baked them (a root built as it is
    /// written bakes its children's a run at a time instead: [`Parts::bake`]).
    motions: Vec<UnitMotion>,
    names: Vec<String>,
    fps: f64,
    op: f64,
}

impl Parts<'_> {
    fn source(&self) -> Source<'_> {
        Source {
            scene: self.scene,
            tracks: self.tracks,
            motions: &self.motions,
            first_motion: 0,
            names: &self.names,
            fps: self.fps,
            op: self.op,
        }
    }

    /// The motions of the shapes `units`, as their layers key them.
    fn bake(&self, units: Range<usize>) -> Vec<UnitMotion> {
        let Some((anim, tolerance)) = self.baked_from else {
            return Vec::new();
        };
        let n = anim.tracks.len();
        let units = units.start.min(n)..units.end.min(n);
        let frames = anim.frame_count();
        let motion = |u: usize| {
            let shape = &anim.scene.shapes[u];
            let info = UnitInfo {
                bbox: shape.bbox,
                centroid: shape.centroid,
                strokes: anim.scene.unit_node(u).is_none_or(may_stroke),
            };
            unit_motion(
                &anim.tracks[u],
                info,
                anim.fps,
                frames,
                tolerance,
                &self.bakes,
            )
        };
        // Shapes are independent, and baking what Lottie cannot say (skews, blends)
        // samples and fits every frame of a moving window: most of an export's time on
        // large scenes. A handful of shapes is not worth waking the thread pool for.
        if units.len() >= PARALLEL_UNITS {
            units.into_par_iter().map(motion).collect()
        } else {
            units.map(motion).collect()
        }
    }

    /// Bakes every shape's motion.
    fn bake_all(&mut self) {
        self.motions = self.bake(0..self.tracks.len());
    }

    /// Frees the motions: many (every shape's keys, 7 ms at the intersections scale) on
    /// the thread pool, while the caller writes or returns.
    fn free(self) {
        let motions = self.motions;
        if motions.len() >= PARALLEL_UNITS {
            rayon::spawn(move || drop(motions));
        }
    }
}

/// The document `parts` make. With `stream`, a large root's layers are built a run at a
/// time, through a temporary file or as the text is written ([`layers::stream`]), rather
/// than all before, when the document is not rewritten afterwards (slots, packing).
fn write<'a>(
    mut parts: Parts<'a>,
    opts: &LottieOptions,
    stream: bool,
) -> Result<(LottieText<'a>, Vec<Warning>), LottieError> {
    let (w, h) = (parts.scene.width, parts.scene.height);
    let (fps, op) = (parts.fps, parts.op);
    if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
        return Err(LottieError::Size {
            width: w,
            height: h,
        });
    }
    // The one rule every output follows (`gmotion::canvas`): whole pixels, rounded half
    // up, and the art at exactly the asked scale, never stretched onto the rounded sides.
    let Some(fit) = opts.size.fit(w, h) else {
        return Err(LottieError::Size {
            width: w,
            height: h,
        });
    };
    let fitted = fit.scale != 1.0 || fit.offset != kurbo::Vec2::ZERO;
    let tolerance = if opts.tolerance.is_finite() && opts.tolerance > 0.0 {
        opts.tolerance
    } else {
        0.25
    };
    // Precompositions are as large as the canvas in whole pixels (and a margin): drawn at
    // the canvas's own scale, inside the null that `fit_layers` adds.
    let canvas = (pixels(w), pixels(h));
    // A large root is built as it is written: once, its runs' text spilled to a
    // temporary file and copied to the output in reverse; or, when its layers take the
    // parent that fits the canvas (numbered after them all), or the file cannot be
    // written, twice ([`layers::Builder::plan_root`]).
    let mut streamable = stream && !opts.slots.any() && !opts.pack;
    let mut built = None;
    if streamable
        && !fitted
        && let Ok(mut spill) = text::Spill::create()
    {
        let mut builder = layers::Builder::new(parts.source(), tolerance);
        builder.slots = opts.slots;
        match builder.spill_root(canvas, &|units| parts.bake(units), spill.file()) {
            Ok(Some(runs)) => {
                built = Some((Root::Spilled(spill, runs), builder.assets, builder.warnings));
            }
            Ok(None) => streamable = false,
            Err(_) => {}
        }
    }
    if built.is_none() && streamable {
        let mut builder = layers::Builder::new(parts.source(), tolerance);
        builder.slots = opts.slots;
        let plan = builder.plan_root(canvas, &|units| parts.bake(units));
        built = plan.map(|plan| (Root::Planned(plan), builder.assets, builder.warnings));
    }
    let (root, layers, assets, mut warnings) = match built {
        Some((root, assets, warnings)) => (root, Vec::new(), assets, warnings),
        None => {
            parts.bake_all();
            let mut builder = layers::Builder::new(parts.source(), tolerance);
            builder.slots = opts.slots;
            let mut layers = builder.layers(canvas);
            if fitted {
                fit_layers(&mut layers, &fit, op);
            }
            (Root::Whole, layers, builder.assets, builder.warnings)
        }
    };
    let size = (fit.width, fit.height);
    let doc = model::Animation {
        v: "5.7.0",
        fr: model::N::coord(fps),
        ip: model::N(0.0),
        op: model::N::coord(op),
        w: size.0,
        h: size.1,
        nm: opts.name.clone(),
        markers: opts
            .markers
            .iter()
            .map(|m| model::MarkerOut::of(m, 0.0, fps))
            .collect(),
        assets,
        layers,
    };
    let json = match root {
        Root::Spilled(spill, runs) => LottieText::spilled(doc, spill, runs),
        Root::Whole => {
            parts.free();
            let mut json = LottieText::document(doc);
            if opts.slots.any() {
                json = with_slots(json, &mut warnings);
            }
            if opts.pack {
                json = packed(json);
            }
            json
        }
        Root::Planned(plan) => {
            // The null that fits the canvas is numbered after the root's layers and is
            // their parent, as `fit_layers` makes it.
            let null = fitted.then_some(plan.max_ind + 1);
            LottieText::stream(move |out| {
                let builder = layers::Builder::new(parts.source(), tolerance);
                doc.write_with(out, |out| {
                    let written = builder.write_root(&plan, null, &|u| parts.bake(u), out)?;
                    if let Some(ind) = null {
                        model::write_layers(out, written, vec![fit_null(ind, &fit, op)])?;
                    }
                    Ok(())
                })
            })
        }
    };
    // Some warnings are about the document rather than one element (effects, for one):
    // each is said once.
    let mut seen = std::collections::HashSet::new();
    warnings.retain(|w| seen.insert(w.clone()));
    Ok((json, warnings.into_iter().map(Warning::from).collect()))
}

/// How the root's layers are held until written.
enum Root {
    /// In the document.
    Whole,
    /// To be built as they are written.
    Planned(layers::stream::Plan),
    /// Written to a temporary file, a run of them at a time: each run's length there.
    Spilled(text::Spill, Vec<u64>),
}

/// `json` with its slot marks written as slots ([`slots::write`]), what that leaves out
/// added to `warnings`.
fn with_slots<'a>(json: LottieText<'a>, warnings: &mut Vec<String>) -> LottieText<'a> {
    let text = json.into_string();
    // The builder writes JSON, so this parses; were it not to, the document is kept as
    // written (its marks unknown keys players skip) and the slots are said to be missing.
    match serde_json::from_str::<serde_json::Value>(&text) {
        Ok(mut doc) => {
            warnings.extend(slots::write(&mut doc));
            LottieText::from(doc.to_string())
        }
        Err(e) => {
            warnings.push(format!("slots are not written: {e}"));
            LottieText::from(text)
        }
    }
}

/// `json` with runs of plain layers packed into one ([`pack_json`]).
fn packed(json: LottieText<'_>) -> LottieText<'_> {
    LottieText::from(pack_json(json.into_string()))
}

/// A Lottie document's text with runs of plain shape layers packed into one layer of
/// named groups, in its own layer list and every precomposition's: what
/// [`LottieOptions::pack`] asks of an export, for a document written elsewhere (an After
/// Effects export converted with `--pack`). Text that is not JSON is returned as it is
/// (a document that does not parse has no layers to pack).
pub fn pack_json(text: String) -> String {
    match serde_json::from_str::<serde_json::Value>(&text) {
        Ok(mut doc) => {
            pack::pack(&mut doc);
            doc.to_string()
        }
        Err(_) => text,
    }
}

/// Places the root layers, drawn at the canvas's own scale, where `fit` puts the canvas:
/// through a null parent that scales and moves them (exact for every layer whatever its
/// own transform).
fn fit_layers(layers: &mut Vec<model::Layer>, fit: &Fit, op: f64) {
    let ind = layers.iter().map(|l| l.ind).max().unwrap_or(0) + 1;
    for l in layers.iter_mut().filter(|l| l.parent.is_none()) {
        l.parent = Some(ind);
    }
    layers.push(fit_null(ind, fit, op));
}

/// The null layer numbered `ind` that scales and moves the root layers where `fit` puts
/// the canvas.
fn fit_null(ind: u32, fit: &Fit, op: f64) -> model::Layer {
    use model::{Layer, LayerKind, N, Prop, WriteLayer};
    let mut null = Layer::new(LayerKind::Null, "output".to_string(), ind, 0.0, op);
    null.ks.s = Some(Prop::vec(vec![
        N::fine(fit.scale * 100.0),
        N::fine(fit.scale * 100.0),
    ]));
    null.ks.p = Some(Prop::vec(vec![
        N::coord(fit.offset.x),
        N::coord(fit.offset.y),
    ]));
    null
}
