//! Morphs as `<animate attributeName="d">`: every outline of a track's morphs has one
//! structure ([`gmotion::morph`]), so every value has the same commands and browsers
//! interpolate it point by point, along each key's `keySplines`: the model's in-between
//! exactly. Keys sit at each morph's ends (and where its easing is no cubic Bézier SMIL
//! can say, at sampled instants thinned to the progress error).

use gmotion::keyframe::reduce::ramer_douglas_peucker;
use gmotion::keyframe::sample::{fraction, frame_times, sample_times};
use gmotion::keyframe::{Format, Key, Piece, progress_keys};
use gmotion::morph::Outline;
use gmotion::motion::{Animation, MorphSeg};
use gmotion::scene::{Node, PathNode};
use kurbo::{Affine, BezPath, Point};

use super::deform::{path_data, points};

/// The morphs of unit `u` and where `path` is among the unit's paths (document order),
/// when it is one of them and the unit morphs.
pub fn leaf<'a>(anim: &'a Animation, u: usize, path: &PathNode) -> Option<(&'a [MorphSeg], usize)> {
    let segs = &anim.tracks.get(u)?.morphs;
    if segs.is_empty() {
        return None;
    }
    let mut paths = Vec::new();
    leaves(anim.scene.unit_node(u)?, &mut paths);
    let leaf = paths.iter().position(|q| std::ptr::eq(*q, path))?;
    Some((segs, leaf))
}

/// The keys of path `leaf`'s `d` through the morphs `segs` of its unit; the path is `abs`
/// away from the canvas, where a sampled easing's keys keep within `tolerance` (and hit
/// every frame at `fps`).
pub fn d_keys(
    segs: &[MorphSeg],
    leaf: usize,
    abs: Affine,
    rate: f64,
    fps: f64,
    tolerance: f64,
) -> Vec<Key<String>> {
    let outline = |k: usize, p: f64| -> BezPath {
        let s = &segs[k];
        match (s.from.get(leaf), s.to.get(leaf)) {
            (Some(a), Some(b)) => gmotion::morph::lerp(a, b, p),
            _ => BezPath::new(),
        }
    };
    let d = |o: &BezPath| path_data(o, points(o).into_iter());
    let pieces: Vec<Piece> = segs
        .iter()
        .enumerate()
        .map(|(k, s)| Piece {
            t0: s.t0,
            t1: s.t1.min(segs.get(k + 1).map_or(f64::INFINITY, |n| n.t0)),
            timing: &s.timing,
        })
        .collect();
    // A key's value is the outline itself: where one morph ends and the next begins (an
    // inverted twin, a chained morph) the outline is the same, so no jump.
    let value = |k: usize, p: f64| Outline(outline(k, p));
    let keys = match progress_keys(&pieces, value(0, 0.0), value, Format::UnitBox) {
        Some(keys) => keys,
        // An easing SMIL cannot say: the outline at sampled instants (every frame among
        // them), linear between, thinned where the points stray less than the tolerance.
        None => {
            let end = segs.last().map_or(0.0, |s| s.t1);
            let mut extra: Vec<f64> = Vec::new();
            for s in segs {
                let (x, y) = s.timing.active();
                extra.extend([s.t0, s.t1, x, y]);
            }
            extra.extend(frame_times(0.0, end, fps));
            let ts = sample_times(0.0, end, rate, 8, &extra);
            let outlines: Vec<BezPath> = ts
                .iter()
                .map(|&t| {
                    let k = segs.partition_point(|s| s.t0 <= t).saturating_sub(1);
                    outline(k, segs[k].progress(t))
                })
                .collect();
            let canvas: Vec<Vec<Point>> = outlines
                .iter()
                .map(|o| points(o).into_iter().map(|q| abs * q).collect())
                .collect();
            let keep = ramer_douglas_peucker(ts.len(), tolerance, |k, lo, hi| {
                let s = fraction(&ts, k, lo, hi);
                canvas[k]
                    .iter()
                    .zip(canvas[lo].iter().zip(&canvas[hi]))
                    .map(|(q, (a, b))| (a.lerp(*b, s) - *q).hypot())
                    .fold(0.0, f64::max)
            });
            keep.into_iter()
                .map(|k| Key::linear(ts[k], Outline(outlines[k].clone())))
                .collect()
        }
    };
    keys.into_iter()
        .map(|k| Key {
            t: k.t,
            v: d(&k.v.0),
            ease: k.ease,
        })
        .collect()
}

/// The paths of a unit node in document order.
fn leaves<'n>(node: &'n Node, out: &mut Vec<&'n PathNode>) {
    match node {
        Node::Path(p) => out.push(p),
        Node::Group(g) => g.children.iter().for_each(|c| leaves(c, out)),
        Node::Image(_) => {}
    }
}
