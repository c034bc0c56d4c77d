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
//! The heading is not linear in arc length along a curve: the rotation's keyframes, at
//! the same times, each get an easing of their own fitted to the heading (least squares),
//! and an interval is halved (at its arc-length middle, its spatial tangents cut exactly)
//! until that easing stays within the tolerance at the shape's farthest corner. Lottie's auto-orient (`ao`) is a layer's, and the
//! exporter writes motion on shape groups (see [`crate::model`]), so it is not used.
//!
//! rlottie and ThorVG (and so dotlottie-web) measure the length along a spatial Bézier
//! with the octagonal norm `max(|dx|, |dy|) + 3/8·min(|dx|, |dy|)` (rlottie's
//! `VLine::length`, ThorVG's `bezLengthApprox`), which overstates a chord by up to 6.8%
//! depending on its direction, not with the Euclidean one lottie-web and the spec use: on
//! a curve that turns, the same eased fraction lands elsewhere on it (0.8 px on the 120 px
//! arch of the conformance matrix's gm-0035). An interval whose two measures put the
//! shape more than half the tolerance apart ([`octagonal_gap`]) and holds a frame is
//! halved too, when that closes the gap in fewer keys than a key at each frame inside it,
//! and otherwise keyed at those frames, where every player then reads a key.

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
    let span = seg.timing.end - seg.timing.start - seg.timing.delay;
    let begin = if seg.timing.reversed {
        seg.timing.start
    } else {
        seg.timing.start + seg.timing.delay
    };
    let tau = |u: f64| {
        if u == pa {
            (ta - begin) / span
        } else if u == pb {
            (tb - begin) / span
        } else {
            tau_at(&curve, u)
        }
    };
    // Keys (progress, time fraction), and the rotation's easing into each.
    // The frames strictly inside the window, as time fractions of the active span.
    let frames: Vec<f64> = ((ta * fps).floor() as i64 + 1..=(tb * fps).ceil() as i64 - 1)
        .map(|n| (n as f64 / fps - begin) / span)
        .collect();
    let fit = Fit {
        f,
        curve: &curve,
        radius,
        tolerance: 0.5 * tolerance,
        frames,
    };
    let mut keys: Vec<(f64, f64)> = vec![(us[0], tau(us[0]))];
    let mut turns: Vec<Easing> = Vec::new();
    for w in us.windows(2) {
        fit.split(
            (w[0], tau(w[0])),
            (w[1], tau(w[1])),
            0,
            &mut keys,
            &mut turns,
        );
    }
    let mut p_keys = Vec::with_capacity(keys.len());
    let mut r_keys = Vec::with_capacity(keys.len());
    for (k, &(u, t)) in keys.iter().enumerate() {
        let frame = N::coord((begin + t * span) * fps);
        let next = keys.get(k + 1);
        let ease = next.map(|&(_, t1)| interval_ease(&curve, t, t1));
        let mut key = Keyframe::written(frame, pos(f, c, u), ease, false);
        if let Some(&(v, _)) = next {
            let (to, ti) = tangents(f, u, v);
            key.to = Some(vec![to.x, to.y]);
            key.ti = Some(vec![ti.x, ti.y]);
        }
        p_keys.push(key);
        r_keys.push(Keyframe::written(
            frame,
            Value::Scalar(N(f.turn_at(u).to_degrees())),
            next.map(|_| turns[k]),
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

/// What fitting the rotation's easings reads.
struct Fit<'a> {
    f: &'a Follow,
    curve: &'a CubicBez,
    radius: f64,
    tolerance: f64,
    /// The time fractions of the frames inside the window.
    frames: Vec<f64>,
}

impl Fit<'_> {
    /// Pushes the keys after `a` up to `b` (progress, time fraction) and the rotation's
    /// easing into each, halving the interval (at its arc-length middle) while the
    /// rotation its easing plays strays more than the tolerance at the shape's radius, and
    /// while rlottie and ThorVG would play it more than the tolerance off at a frame
    /// ([`octagonal_gap`]; keyed at its frames instead when that takes fewer keys).
    fn split(
        &self,
        a: (f64, f64),
        b: (f64, f64),
        depth: u32,
        keys: &mut Vec<(f64, f64)>,
        turns: &mut Vec<Easing>,
    ) {
        let (ease, off) = self.turn_ease(a, b);
        let halve = |keys: &mut Vec<(f64, f64)>, turns: &mut Vec<Easing>| {
            let m = 0.5 * (a.0 + b.0);
            let mid = (m, tau_at(self.curve, m));
            self.split(a, mid, depth + 1, keys, turns);
            self.split(mid, b, depth + 1, keys, turns);
        };
        if self.f.orient && depth < MAX_DEPTH && off > self.tolerance {
            halve(keys, turns);
            return;
        }
        let inside = self.frames_inside(a, b);
        if !inside.is_empty() && octagonal_gap(self.f, a.0, b.0) > self.tolerance {
            // Halving, if it closes the gap in fewer keys than a key at each frame inside
            // (where rlottie and ThorVG then read a key, exactly).
            if self.halvings(a, b, depth, inside.len()).is_some() {
                halve(keys, turns);
                return;
            }
            let mut prev = a;
            for t in inside {
                let k = (self.curve.eval(param_at_x(self.curve, t)).y, t);
                keys.push(k);
                turns.push(self.turn_ease(prev, k).0);
                prev = k;
            }
            keys.push(b);
            turns.push(self.turn_ease(prev, b).0);
            return;
        }
        keys.push(b);
        turns.push(ease);
    }

    /// The time fractions of the frames strictly between keys `a` and `b`.
    fn frames_inside(&self, a: (f64, f64), b: (f64, f64)) -> Vec<f64> {
        self.frames
            .iter()
            .copied()
            .filter(|&t| t > a.1 + 1e-9 && t < b.1 - 1e-9)
            .collect()
    }

    /// How many intervals halving from key `a` to `b` (at arc-length middles) makes until
    /// each one's [`octagonal_gap`] is within the tolerance or no frame falls inside it;
    /// `None` beyond `budget` intervals or [`MAX_DEPTH`].
    fn halvings(&self, a: (f64, f64), b: (f64, f64), depth: u32, budget: usize) -> Option<usize> {
        if self.frames_inside(a, b).is_empty() || octagonal_gap(self.f, a.0, b.0) <= self.tolerance
        {
            return (budget >= 1).then_some(1);
        }
        if depth >= MAX_DEPTH || budget < 2 {
            return None;
        }
        let m = 0.5 * (a.0 + b.0);
        let mid = (m, tau_at(self.curve, m));
        let left = self.halvings(a, mid, depth + 1, budget - 1)?;
        let right = self.halvings(mid, b, depth + 1, budget - left)?;
        Some(left + right)
    }

    /// The easing of the rotation from key `a` to key `b` (progress, time fraction), fitted
    /// by least squares with its handles' times at a third and two thirds (the time a
    /// player reads is then the curve parameter), and its largest error in canvas units.
    fn turn_ease(&self, (ua, ta): (f64, f64), (ub, tb): (f64, f64)) -> (Easing, f64) {
        let f = self.f;
        let (ra, rb) = (f.turn_at(ua), f.turn_at(ub));
        let samples: Vec<(f64, f64)> = (1..16)
            .map(|j| {
                let x = j as f64 / 16.0;
                let tau = ta + x * (tb - ta);
                let u = self.curve.eval(param_at_x(self.curve, tau)).y;
                (x, f.turn_at(u))
            })
            .collect();
        let b1 = |x: f64| 3.0 * (1.0 - x) * (1.0 - x) * x;
        let b2 = |x: f64| 3.0 * (1.0 - x) * x * x;
        let (y1, y2) = if (rb - ra).abs() < 1e-12 {
            (1.0 / 3.0, 2.0 / 3.0)
        } else {
            let (mut s11, mut s12, mut s22, mut r1, mut r2) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for &(x, r) in &samples {
                let v = (r - ra) / (rb - ra) - x * x * x;
                s11 += b1(x) * b1(x);
                s12 += b1(x) * b2(x);
                s22 += b2(x) * b2(x);
                r1 += b1(x) * v;
                r2 += b2(x) * v;
            }
            let det = s11 * s22 - s12 * s12;
            ((r1 * s22 - r2 * s12) / det, (s11 * r2 - s12 * r1) / det)
        };
        let off = samples
            .iter()
            .map(|&(x, r)| {
                let played = ra + (rb - ra) * (b1(x) * y1 + b2(x) * y2 + x * x * x);
                (played - r).abs() * self.radius
            })
            .fold(0.0, f64::max);
        let straight = (y1 - 1.0 / 3.0).abs() < 1e-9 && (y2 - 2.0 / 3.0).abs() < 1e-9;
        let ease = if straight {
            LINEAR
        } else {
            from_css([1.0 / 3.0, y1, 2.0 / 3.0, y2])
        };
        (ease, off)
    }
}

/// Where the anchor is at progress `u`.
fn pos(f: &Follow, c: Vec2, u: f64) -> Value {
    let p = c + f.offset_at(u);
    Value::Vec(vec![N(p.x), N(p.y)])
}

/// How far apart (canvas units, at worst) the shape is, on the route from fraction `a` to
/// `b` (within one segment), where lottie-web puts it and where rlottie and ThorVG do:
/// they measure the Bézier's length with the octagonal norm `max(|dx|, |dy|) + 3/8·min(|dx|,
/// |dy|)`, not the Euclidean one, so along a curve that turns the two fractions of its
/// length differ. Zero on a straight piece.
fn octagonal_gap(f: &Follow, a: f64, b: f64) -> f64 {
    const K: usize = 64;
    let (to, ti) = tangents(f, a, b);
    if to == Vec2::ZERO && ti == Vec2::ZERO {
        return 0.0;
    }
    let (p0, p3) = (f.offset_at(a).to_point(), f.offset_at(b).to_point());
    let bez = CubicBez::new(p0, p0 + to, p3 + ti, p3);
    let (mut euclid, mut octa) = ([0.0; K + 1], [0.0; K + 1]);
    let mut prev = p0;
    for j in 1..=K {
        let p = bez.eval(j as f64 / K as f64);
        let (dx, dy) = ((p.x - prev.x).abs(), (p.y - prev.y).abs());
        euclid[j] = euclid[j - 1] + dx.hypot(dy);
        octa[j] = octa[j - 1] + dx.max(dy) + 0.375 * dx.min(dy);
        prev = p;
    }
    let (e, o) = (euclid[K], octa[K]);
    if e <= 0.0 || o <= 0.0 {
        return 0.0;
    }
    (0..=K)
        .map(|j| (octa[j] / o - euclid[j] / e).abs())
        .fold(0.0, f64::max)
        * e
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
