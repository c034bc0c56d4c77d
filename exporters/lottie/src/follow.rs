//! A follow (motion along a path, [`gmotion::motion::follow`]) as Lottie writes it
//! natively: position keyframes with spatial tangents (`to`/`ti`), one keyframe where each
//! of the path's segments begins, and the rotation as keyframes at the same times.
//!
//! Players move a position with spatial tangents along the Bézier between two keyframes
//! by arc length, at the keyframe's easing, so the keys are exact when each interval's
//! easing says how far along the interval's arc the centroid is at each instant. The
//! rule's easing is a cubic Bézier from time to the fraction of the whole path; the piece
//! of it between two keys, scaled to the unit box, is again a cubic Bézier (the curve cut
//! with de Casteljau), from time to the fraction of that interval: exact, not fitted.
//!
//! The heading is not linear in arc length along a curve, so a turning shape gets more
//! keys: an interval is halved (at its arc-length middle, its spatial tangents cut
//! exactly) until the rotation interpolated between its keys stays within the tolerance
//! at the shape's farthest corner. Lottie's auto-orient (`ao`) is a layer's, and the
//! exporter writes motion on shape groups (see [`crate::model`]), so it is not used.

use kurbo::{CubicBez, ParamCurve, PathSeg, Point, Vec2};

use super::model::{Easing, Keyframe, LINEAR, N, Prop, Transform, Value, from_css};
use gmotion::motion::follow::{Follow, as_cubic};
use gmotion::motion::{MotionKind, MotionSeg, Timing};

/// How many times an interval may be halved for the rotation.
const MAX_DEPTH: u32 = 10;

/// The level moving the shape for `seg` over `[seg.t0, end]`: `F(p)` about the centroid
/// (its anchor), without undoing `F(p₀)` (the caller does). `None` when the motion is not
/// exactly a follow Lottie can say: carried by a frame, a `world` route that starts away
/// from the centroid (a jump), or an easing that is not a cubic Bézier staying within
/// the path's ends. `radius` is the shape's farthest point from its centroid.
pub fn level(
    seg: &MotionSeg,
    end: f64,
    fps: f64,
    radius: f64,
    tolerance: f64,
) -> Option<Transform> {
    let MotionKind::Follow(f) = &seg.kind else {
        return None;
    };
    let ease = seg.timing.ease.as_cubic_bezier()?;
    let monotone = (0.0..=1.0).contains(&ease[1]) && (0.0..=1.0).contains(&ease[3]);
    if !monotone || f.frame != kurbo::Affine::IDENTITY || f.lead.hypot() > 1e-9 {
        return None;
    }
    let curve = progress_curve(&seg.timing, ease);
    let (a, b) = seg.timing.active();
    let (ta, tb) = (a.max(seg.t0), b.min(end));
    let c = f.pivot.to_vec2();
    let anchor = Some(Prop::fixed(Value::Vec(vec![N(c.x), N(c.y)])));
    if ta >= tb {
        return Some(Transform {
            a: anchor,
            p: Some(Prop::fixed(pos(f, c, seg.timing.progress(seg.t0)))),
            ..Transform::empty()
        });
    }
    let (pa, pb) = (seg.timing.progress(ta), seg.timing.progress(tb));
    // Breakpoints in time order: the window's ends and every segment start between them.
    let (lo, hi) = (pa.min(pb), pa.max(pb));
    let mut us: Vec<f64> = vec![pa];
    let mut inner: Vec<f64> = f
        .route
        .fractions()
        .filter(|u| *u > lo + 1e-12 && *u < hi - 1e-12)
        .collect();
    if pb < pa {
        inner.reverse();
    }
    us.extend(inner);
    us.push(pb);
    let mut keys: Vec<f64> = vec![us[0]];
    for w in us.windows(2) {
        split(f, w[0], w[1], radius, 0.5 * tolerance, 0, &mut keys);
    }
    let span = seg.timing.end - seg.timing.start - seg.timing.delay;
    let begin = if seg.timing.reversed {
        seg.timing.start
    } else {
        seg.timing.start + seg.timing.delay
    };
    let taus: Vec<f64> = keys
        .iter()
        .map(|&u| {
            if u == pa {
                (ta - begin) / span
            } else if u == pb {
                (tb - begin) / span
            } else {
                tau_at(&curve, u)
            }
        })
        .collect();
    let mut p_keys = Vec::with_capacity(keys.len());
    let mut r_keys = Vec::with_capacity(keys.len());
    for (k, &u) in keys.iter().enumerate() {
        let frame = N::coord((begin + taus[k] * span) * fps);
        let next = keys.get(k + 1);
        let ease = next.map(|_| interval_ease(&curve, taus[k], taus[k + 1]));
        let mut key = Keyframe::written(frame, pos(f, c, u), ease, false);
        if let Some(&v) = next {
            let (to, ti) = tangents(f, u, v);
            key.to = Some(vec![to.x, to.y]);
            key.ti = Some(vec![ti.x, ti.y]);
        }
        p_keys.push(key);
        r_keys.push(Keyframe::written(
            frame,
            Value::Scalar(N(f.turn_at(u).to_degrees())),
            ease,
            false,
        ));
    }
    Some(Transform {
        a: anchor,
        p: Some(Prop::Animated(p_keys)),
        r: f.orient.then(|| Prop::keyed(r_keys)),
        ..Transform::empty()
    })
}

/// Where the anchor is at progress `u`.
fn pos(f: &Follow, c: Vec2, u: f64) -> Value {
    let p = c + f.offset_at(u);
    Value::Vec(vec![N(p.x), N(p.y)])
}

/// Pushes the keys after `a` up to `b`, halving the interval while the rotation
/// interpolated between its ends strays more than `tolerance` at `radius`.
fn split(f: &Follow, a: f64, b: f64, radius: f64, tolerance: f64, depth: u32, keys: &mut Vec<f64>) {
    let straight = |y: f64| f.turn_at(a) + (f.turn_at(b) - f.turn_at(a)) * y;
    let off = [0.25, 0.5, 0.75]
        .iter()
        .map(|&y| (f.turn_at(a + (b - a) * y) - straight(y)).abs() * radius)
        .fold(0.0, f64::max);
    if f.orient && depth < MAX_DEPTH && off > tolerance {
        let m = 0.5 * (a + b);
        split(f, a, m, radius, tolerance, depth + 1, keys);
        split(f, m, b, radius, tolerance, depth + 1, keys);
        return;
    }
    keys.push(b);
}

/// The spatial tangents of the route from fraction `a` to `b` (within one segment):
/// `to` from the start, `ti` from the end; zero for a straight piece.
fn tangents(f: &Follow, a: f64, b: f64) -> (Vec2, Vec2) {
    let (i, _) = f.route.locate((a + b) * 0.5);
    let seg = &f.route.segments()[i];
    if matches!(seg, PathSeg::Line(_)) {
        return (Vec2::ZERO, Vec2::ZERO);
    }
    let param = |u: f64| {
        let (j, t) = f.route.locate(u);
        // A key on the segment's end is found at the start of the next one.
        if j == i {
            t
        } else if j > i {
            1.0
        } else {
            0.0
        }
    };
    let (sa, sb) = (param(a), param(b));
    let sub = as_cubic(seg).subsegment(sa.min(sb)..sa.max(sb));
    let sub = if sa <= sb {
        sub
    } else {
        CubicBez::new(sub.p3, sub.p2, sub.p1, sub.p0)
    };
    (sub.p1 - sub.p0, sub.p2 - sub.p3)
}

/// The progress as a cubic Bézier from the time fraction of the active span (x) to the
/// fraction of the path (y).
fn progress_curve(timing: &Timing, [x1, y1, x2, y2]: [f64; 4]) -> CubicBez {
    if timing.reversed {
        CubicBez::new((0.0, 1.0), (1.0 - x2, y2), (1.0 - x1, y1), (1.0, 0.0))
    } else {
        CubicBez::new((0.0, 0.0), (x1, y1), (x2, y2), (1.0, 1.0))
    }
}

/// The curve parameter where its x is `x` (x grows along the curve).
fn param_at_x(c: &CubicBez, x: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if c.eval(m).x < x {
            lo = m;
        } else {
            hi = m;
        }
    }
    0.5 * (lo + hi)
}

/// The time fraction at which the progress is `u` (monotone curves only).
fn tau_at(c: &CubicBez, u: f64) -> f64 {
    let rising = c.p3.y >= c.p0.y;
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if (c.eval(m).y < u) == rising {
            lo = m;
        } else {
            hi = m;
        }
    }
    c.eval(0.5 * (lo + hi)).x
}

/// The easing of the interval from time fraction `a` to `b`: the curve cut there and
/// scaled to the unit box (linear when it is straight).
fn interval_ease(c: &CubicBez, a: f64, b: f64) -> Easing {
    let sub = c.subsegment(param_at_x(c, a)..param_at_x(c, b));
    let (w, h) = (sub.p3.x - sub.p0.x, sub.p3.y - sub.p0.y);
    if w.abs() < 1e-12 || h.abs() < 1e-12 {
        return LINEAR;
    }
    let norm = |p: Point| [(p.x - sub.p0.x) / w, (p.y - sub.p0.y) / h];
    let ([x1, y1], [x2, y2]) = (norm(sub.p1), norm(sub.p2));
    let straight = (x1 - y1).abs() < 1e-9 && (x2 - y2).abs() < 1e-9;
    if straight {
        return LINEAR;
    }
    from_css([x1, y1, x2, y2])
}
