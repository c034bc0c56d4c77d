//! A follow ([`gmotion::motion::follow`]) as SMIL says it natively: an `animateMotion`
//! along the route, its `keyPoints` the arc-length fractions travelled.
//!
//! An `animateMotion`'s `keyPoints` are fractions of the path's length, which is exactly a
//! follow's progress, so the rule's easing, when it is a cubic Bézier, is the keys'
//! `keySplines` as any other segment's. The motion moves the group's content by the path's
//! point `P(p)` and, with `rotate="auto"`, turns it by the tangent's angle `θ(p)`, after the
//! group's static transform. The follow is `F(p) = T(c − P(0))·T(P(p))·R(θ(p))·R(−θ(0))·T(−c)`
//! about the centroid `c`, so the group's transform is `T(c − P(0))` and the next inner
//! group's `R(−θ(0))·T(−c)·F(p₀)⁻¹`: the shape starts as drawn, turned relative to the
//! start tangent. The path is written [`MAGNIFY`] times larger, with the groups around
//! the motion scaling it back (a uniform scale commutes with the turn).
//!
//! What SMIL cannot say this way is sampled like any other motion, as the Lottie exporter
//! does: a follow carried by an enclosing motion, a `world` route starting away from the
//! centroid (the jump onto it), an easing that is not a cubic Bézier or overshoots the
//! path's ends, and a route of several subpaths (an `animateMotion` would measure the jumps
//! between them differently).

use kurbo::{Affine, ParamCurve, PathSeg};

use super::{Kind, RawLayer, SegLayer, TransformAnim, Window, invert};
use crate::smil::xml::{COORD, push_num};

/// How much larger the path is written than the route, the group around the motion
/// scaling it back: Chromium measures a path's length to about half a unit (Skia's contour
/// measure), which on the canvas puts a shape up to half a pixel off along quadratics; on a
/// path this much larger the error shrinks by as much. A power of two, so the scale and
/// its inverse are exact.
const MAGNIFY: f64 = 16.0;
use gmotion::keyframe::{Format, Key, Piece, progress_keys};
use gmotion::motion::follow::Follow;
use gmotion::tolerance::PROGRESS;

/// The layer moving the shape along `f` over the window, if SMIL can say it exactly.
pub(super) fn layer(w: &Window<'_>, f: &Follow) -> Option<SegLayer> {
    let seg = w.seg();
    let ease = seg.timing.ease.as_cubic_bezier()?;
    let within = (0.0..=1.0).contains(&ease[1]) && (0.0..=1.0).contains(&ease[3]);
    let segs = f.route.segments();
    let joined = segs
        .windows(2)
        .all(|s| (s[0].end() - s[1].start()).hypot() <= 1e-9);
    if !within || !joined || f.frame != Affine::IDENTITY || f.lead.hypot() > 1e-9 {
        return None;
    }
    let piece = Piece {
        t0: w.a,
        t1: w.b,
        timing: &seg.timing,
    };
    let p0 = seg.timing.progress(seg.t0);
    let keys = progress_keys(
        &[piece],
        seg.timing.progress(w.a),
        |_, p| p,
        Format::UnitBox,
    )?;
    if keys.iter().all(|k| PROGRESS.same(k.v, p0)) {
        return Some(SegLayer::Identity);
    }
    let held = invert(f.at(p0))?;
    let c = f.pivot.to_vec2();
    let turn_back = if f.orient {
        Affine::rotate(-f.route.heading_at(0.0))
    } else {
        Affine::IDENTITY
    };
    let anim = TransformAnim {
        kind: Kind::Motion { auto: f.orient },
        keys: keys
            .iter()
            .map(|k| Key {
                t: k.t,
                v: [k.v, 0.0],
                ease: k.ease,
            })
            .collect(),
        discrete: false,
        path: Some(path_data(segs, MAGNIFY)),
    };
    let layer = RawLayer {
        prefix: Affine::translate(c - f.route.start().to_vec2()) * Affine::scale(1.0 / MAGNIFY),
        anims: vec![anim],
        suffix: Affine::scale(MAGNIFY) * turn_back * Affine::translate(-c) * held,
    };
    Some(SegLayer::Exact(layer, false))
}

/// SVG path data for joined segments scaled by `k`: one move, then each segment as it is.
fn path_data(segs: &[PathSeg], k: f64) -> String {
    let mut d = String::new();
    let point = |d: &mut String, cmd: &str, p: kurbo::Point| {
        d.push_str(cmd);
        push_num(d, k * p.x, COORD);
        d.push(' ');
        push_num(d, k * p.y, COORD);
    };
    point(&mut d, "M", segs[0].start());
    for s in segs {
        match s {
            PathSeg::Line(l) => point(&mut d, " L", l.p1),
            PathSeg::Quad(q) => {
                point(&mut d, " Q", q.p1);
                point(&mut d, " ", q.p2);
            }
            PathSeg::Cubic(c) => {
                point(&mut d, " C", c.p1);
                point(&mut d, " ", c.p2);
                point(&mut d, " ", c.p3);
            }
        }
    }
    d
}
