//! Morphing paths as Lottie path keyframes: the track's outlines of one structure
//! ([`gmotion::morph`]) written as animated shapes (`ks`), one property per subpath, keyed
//! at each morph's ends (and where its easing is no cubic Bézier, sampled and thinned).
//! Players interpolate the vertices and tangents of consecutive keyframes linearly along
//! the keyframe's easing: the model's in-between exactly.

use gmotion::keyframe::{Format, Piece, progress_keys};
use gmotion::morph::Outline;

use super::*;

impl<'a> Builder<'a> {
    /// Where path `p` of unit `u` is among the unit's paths (document order), when the
    /// unit's track morphs.
    pub(super) fn morph_leaf(&self, u: usize, p: &PathNode) -> Option<(&'a Track, usize)> {
        let tracks: &'a [Track] = self.src.tracks;
        let track = tracks.get(u).filter(|t| !t.morphs.is_empty())?;
        let mut paths = Vec::new();
        leaves(self.src.scene.unit_node(u)?, &mut paths);
        let leaf = paths.iter().position(|q| std::ptr::eq(*q, p))?;
        Some((track, leaf))
    }

    /// Path `leaf`'s subpaths through the track's morphs, in coordinates mapped by
    /// `space` (whose lengths the composition magnifies by `gain`).
    pub(super) fn morphed(
        &self,
        track: &Track,
        leaf: usize,
        space: Affine,
        gain: f64,
    ) -> Vec<Prop> {
        let segs = &track.morphs;
        let outline = |k: usize, p: f64| -> BezPath {
            let s = &segs[k];
            match (s.from.get(leaf), s.to.get(leaf)) {
                (Some(a), Some(b)) => gmotion::morph::lerp(a, b, p),
                _ => BezPath::new(),
            }
        };
        // How far a point travels in a morph bounds the error of a sampled progress.
        let reach = segs
            .iter()
            .filter_map(|s| Some((s.from.get(leaf)?, s.to.get(leaf)?)))
            .flat_map(|(a, b)| {
                gmotion::morph::cubics(a)
                    .into_iter()
                    .zip(gmotion::morph::cubics(b))
                    .map(|(x, y)| (x.p0 - y.p0).hypot().max((x.p1 - y.p1).hypot()))
            })
            .fold(0.0, f64::max)
            * gain;
        let pieces: Vec<Piece> = segs
            .iter()
            .enumerate()
            .map(|(k, s)| Piece {
                t0: s.t0,
                t1: s.t1.min(segs.get(k + 1).map_or(f64::INFINITY, |n| n.t0)),
                timing: &s.timing,
            })
            .collect();
        let format = Format::Spaced {
            fps: self.src.fps,
            tolerance: self.tolerance / reach.max(1e-9),
        };
        // A key's value is the outline itself: where one morph ends and the next begins
        // (an inverted twin, a chained morph) the outline is the same, so no jump.
        let keys = progress_keys(
            &pieces,
            Outline(outline(0, 0.0)),
            |k, p| Outline(outline(k, p)),
            format,
        )
        .expect("spaced keys sample what is not a Bézier");
        let inv = space.inverse();
        let count = subpaths(&outline(0, 0.0)).len();
        (0..count)
            .map(|c| {
                Prop::keyed(to_keyframes(&keys, |o| {
                    let shape = subpaths(&o.0);
                    Value::Bezier(Box::new(shape[c].transformed(inv).to_bezier()))
                }))
            })
            .collect()
    }
}

/// The paths of a unit node in document order.
fn leaves<'n>(node: &'n Node, out: &mut Vec<&'n PathNode>) {
    match node {
        Node::Path(p) => out.push(p),
        Node::Group(g) => g.children.iter().for_each(|c| leaves(c, out)),
        Node::Image(_) => {}
    }
}

/// The subpaths of a morph outline as Lottie contours, by its structure (a move, cubics,
/// and a close when closed: the last cubic of a closed subpath returns to its start), not
/// by comparing points, so every outline of one structure has the same vertex counts.
pub(super) fn subpaths(path: &BezPath) -> Vec<Contour> {
    let mut out: Vec<Contour> = Vec::new();
    for el in path.elements() {
        match *el {
            kurbo::PathEl::MoveTo(p) => out.push(Contour {
                closed: false,
                v: vec![p],
                i: vec![p],
                o: vec![p],
            }),
            kurbo::PathEl::CurveTo(a, b, p) => {
                if let Some(c) = out.last_mut() {
                    if let Some(o) = c.o.last_mut() {
                        *o = a;
                    }
                    c.v.push(p);
                    c.i.push(b);
                    c.o.push(p);
                }
            }
            kurbo::PathEl::ClosePath => {
                if let Some(c) = out.last_mut()
                    && c.v.len() > 1
                {
                    // The last vertex is the start again: its entering handle is the
                    // start's.
                    c.v.pop();
                    c.o.pop();
                    let entering = c.i.pop().unwrap_or(c.v[0]);
                    c.i[0] = entering;
                    c.closed = true;
                }
            }
            kurbo::PathEl::LineTo(p) | kurbo::PathEl::QuadTo(_, p) => {
                if let Some(c) = out.last_mut() {
                    c.v.push(p);
                    c.i.push(p);
                    c.o.push(p);
                }
            }
        }
    }
    out
}
