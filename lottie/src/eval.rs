//! Lottie properties at a time: keyframes with per-component Bézier easing, holds, legacy
//! end values, spatial tangents on positions; transforms as affine maps; outlines as
//! Bézier paths.

use kurbo::{Affine, BezPath, CubicBez, ParamCurve, ParamCurveArclen, Point, Vec2};

use gmotion::signals::easing::solve_bezier_x;

use crate::model::{Bezier, Keyframe, Num, Position, Prop, PropValue, Property, Transform};

/// The eased progress, per component, at `x ∈ [0, 1]` of a keyframe's span.
fn eased(k: &Keyframe<impl PropValue>, x: f64, dims: usize) -> Vec<f64> {
    let (Some(o), Some(i)) = (&k.o, &k.i) else {
        return vec![x];
    };
    let comp = |v: &[f64], d: usize, default: f64| {
        v.get(d)
            .or(v.last())
            .copied()
            .filter(|x| x.is_finite())
            .unwrap_or(default)
    };
    (0..dims.max(1))
        .map(|d| {
            let (x1, y1) = (comp(&o.x, d, 0.0).clamp(0.0, 1.0), comp(&o.y, d, 0.0));
            let (x2, y2) = (comp(&i.x, d, 1.0).clamp(0.0, 1.0), comp(&i.y, d, 1.0));
            let curve = CubicBez::new((0.0, 0.0), (x1, y1), (x2, y2), (1.0, 1.0));
            curve.eval(solve_bezier_x(&curve, x)).y
        })
        .collect()
}

/// The number of components a value has, for per-component easing.
trait Dims {
    fn dims(&self) -> usize;
}

impl Dims for Vec<f64> {
    fn dims(&self) -> usize {
        self.len()
    }
}

impl Dims for Bezier {
    fn dims(&self) -> usize {
        1
    }
}

/// A property's value at `t` (frames, in the property's own time), and the keyframe
/// span `t` lies in with its progress when it moves along spatial tangents.
fn sample<T: PropValue + Dims>(p: &Prop<T>, t: f64) -> Option<(T, Option<(usize, f64)>)> {
    let keys = match p {
        Prop::Static(v) => return Some((v.clone(), None)),
        Prop::Animated(keys) => keys,
    };
    // The value a keyframe starts with, else the previous keyframe's end value.
    let start = |i: usize| -> Option<T> {
        keys[i]
            .s
            .clone()
            .or_else(|| i.checked_sub(1).and_then(|j| keys[j].e.clone()))
    };
    let first = keys.first()?;
    if t <= first.t || keys.len() == 1 {
        return start(0).or_else(|| first.e.clone()).map(|v| (v, None));
    }
    // The last keyframe at or before t (keys are in time order in every real file; a
    // file that is not gets the first match, never a panic).
    let k = keys
        .iter()
        .rposition(|k| k.t <= t)
        .unwrap_or(0)
        .min(keys.len() - 1);
    let from = start(k)?;
    if k + 1 >= keys.len() {
        return Some((from.clone(), None));
    }
    let key = &keys[k];
    if key.hold {
        return Some((from, None));
    }
    let Some(to) = key.e.clone().or_else(|| keys[k + 1].s.clone()) else {
        return Some((from, None));
    };
    let span = keys[k + 1].t - key.t;
    if span <= 0.0 {
        return Some((to, None));
    }
    let x = ((t - key.t) / span).clamp(0.0, 1.0);
    let p = eased(key, x, from.dims());
    let moving = p.first().copied().unwrap_or(x);
    Some((from.lerp(&to, &p), Some((k, moving))))
}

/// A numeric property at `t`, or `default` when absent or empty.
pub fn num(p: Option<&Num>, t: f64, default: &[f64]) -> Vec<f64> {
    let Some(p) = p else {
        return default.to_vec();
    };
    match sample(&p.value, t) {
        Some((v, Some((k, progress)))) if v.len() >= 2 => {
            spatial(&p.value, k, progress).unwrap_or(v)
        }
        Some((v, _)) if !v.is_empty() => v,
        _ => default.to_vec(),
    }
}

/// A position moving along the spatial tangents of keyframe `k` at `progress`, a fraction
/// of the path's length.
fn spatial(p: &Prop<Vec<f64>>, k: usize, progress: f64) -> Option<Vec<f64>> {
    let Prop::Animated(keys) = p else {
        return None;
    };
    let key = keys.get(k)?;
    let (to, ti) = (key.to.as_ref()?, key.ti.as_ref()?);
    if to.iter().chain(ti).all(|x| *x == 0.0) {
        return None;
    }
    let s = key.s.as_ref()?;
    let e = key.e.as_ref().or(keys.get(k + 1)?.s.as_ref())?;
    let pt = |v: &[f64]| Point::new(v.first().copied()?, v.get(1).copied()?).into();
    let (p0, p3): (Option<Point>, Option<Point>) = (pt(s), pt(e));
    let (p0, p3) = (p0?, p3?);
    let (o, i): (Option<Point>, Option<Point>) = (pt(to), pt(ti));
    // Players travel the path at the eased fraction of its length (lottie-web samples it
    // and walks the samples), stopping at its ends when an easing overshoots.
    let curve = CubicBez::new(p0, p0 + o?.to_vec2(), p3 + i?.to_vec2(), p3);
    let length = curve.arclen(1e-3);
    let c = curve.eval(curve.inv_arclen(progress.clamp(0.0, 1.0) * length, 1e-3));
    let mut out = s.clone();
    out[0] = c.x;
    out[1] = c.y;
    Some(out)
}

/// A scalar property at `t`.
pub fn scalar(p: Option<&Num>, t: f64, default: f64) -> f64 {
    num(p, t, &[default]).first().copied().unwrap_or(default)
}

/// A 2D property at `t`.
pub fn vec2(p: Option<&Num>, t: f64, default: Vec2) -> Vec2 {
    let v = num(p, t, &[default.x, default.y]);
    Vec2::new(
        v.first().copied().unwrap_or(default.x),
        v.get(1).copied().unwrap_or(default.y),
    )
}

/// A position at `t`.
pub fn position(p: Option<&Position>, t: f64) -> Vec2 {
    match p {
        None => Vec2::ZERO,
        Some(Position::Joined(p)) => vec2(Some(p), t, Vec2::ZERO),
        Some(Position::Split { x, y }) => {
            Vec2::new(scalar(Some(x), t, 0.0), scalar(Some(y), t, 0.0))
        }
    }
}

/// The transform's map at `t`: `T(p)·R(r)·Skew·S(s)·T(-a)` (lottie-web's order).
pub fn matrix(tr: &Transform, t: f64) -> Affine {
    let a = vec2(tr.a.as_ref(), t, Vec2::ZERO);
    let p = position(tr.p.as_ref(), t);
    let s = vec2(tr.s.as_ref(), t, Vec2::new(100.0, 100.0)) / 100.0;
    let mut r = scalar(tr.r.as_ref(), t, 0.0).to_radians();
    if tr.auto_orient {
        r += heading(tr.p.as_ref(), t);
    }
    let sk = scalar(tr.sk.as_ref(), t, 0.0).to_radians();
    let sa = scalar(tr.sa.as_ref(), t, 0.0).to_radians();
    let skew = skew(sk, sa);
    let rx = scalar(tr.rx.as_ref(), t, 0.0).to_radians();
    let ry = scalar(tr.ry.as_ref(), t, 0.0).to_radians();
    let or = num(tr.or.as_ref(), t, &[0.0, 0.0, 0.0]);
    let or: Vec<f64> = (0..3)
        .map(|k| or.get(k).copied().unwrap_or(0.0).to_radians())
        .collect();
    if rx == 0.0 && ry == 0.0 && or.iter().all(|x| *x == 0.0) {
        return Affine::translate(p)
            * Affine::rotate(r)
            * skew
            * Affine::scale_non_uniform(s.x, s.y)
            * Affine::translate(-a);
    }
    // A 3D layer turned out of the picture plane, seen as players without a camera show
    // it: projected straight onto the plane. lottie-web's order, with its anchor depth.
    let az = num(tr.a.as_ref(), t, &[0.0, 0.0, 0.0])
        .get(2)
        .copied()
        .unwrap_or(0.0);
    let sz = num(tr.s.as_ref(), t, &[100.0, 100.0, 100.0])
        .get(2)
        .copied()
        .unwrap_or(100.0)
        / 100.0;
    let flat = skew * Affine::scale_non_uniform(s.x, s.y) * Affine::translate(-a);
    let turns: [(usize, f64); 6] = [(2, r), (1, ry), (0, rx), (2, or[2]), (1, or[1]), (0, or[0])];
    let project = |x: f64, y: f64| -> Point {
        let q = flat * Point::new(x, y);
        let mut v = [q.x, q.y, az * sz];
        for (axis, angle) in turns {
            let (sin, cos) = angle.sin_cos();
            // lottie-web's rotateX, rotateY and rotateZ(-angle), for points as columns.
            let (i, j) = match axis {
                0 => (2, 1),
                1 => (0, 2),
                _ => (0, 1),
            };
            let (vi, vj) = (v[i], v[j]);
            v[i] = vi * cos - vj * sin;
            v[j] = vi * sin + vj * cos;
        }
        Point::new(v[0] + p.x, v[1] + p.y)
    };
    let (o, ex, ey) = (project(0.0, 0.0), project(1.0, 0.0), project(0.0, 1.0));
    Affine::new([ex.x - o.x, ex.y - o.y, ey.x - o.x, ey.y - o.y, o.x, o.y])
}

/// A skew by `sk` radians along the axis at `sa` radians, as lottie-web's
/// `skewFromAxis(-sk, sa)`: rotate by `sa`, shear x by `tan(-sk)`, rotate back.
pub fn skew(sk: f64, sa: f64) -> Affine {
    if sk == 0.0 {
        return Affine::IDENTITY;
    }
    let tan = (-sk).tan().clamp(-1e6, 1e6);
    Affine::rotate(-sa) * Affine::new([1.0, 0.0, tan, 1.0, 0.0, 0.0]) * Affine::rotate(sa)
}

/// The direction, in radians, an auto-oriented layer faces at `t`: along its position's
/// motion, as lottie-web finds it (from a hundredth of a frame before, or after at the
/// start; before the first keyframe and after the last, the path's end directions).
fn heading(p: Option<&Position>, t: f64) -> f64 {
    let Some(Position::Joined(Property {
        value: Prop::Animated(keys),
        ..
    })) = p
    else {
        return 0.0;
    };
    let (Some(first), Some(last)) = (keys.first(), keys.last()) else {
        return 0.0;
    };
    let (from, to) = if t <= first.t {
        (first.t, first.t + 0.01)
    } else if t >= last.t {
        (last.t - 0.05, last.t)
    } else {
        (t - 0.01, t)
    };
    let d = position(p, to) - position(p, from);
    if d.hypot2() == 0.0 { 0.0 } else { d.atan2() }
}

/// The transform's opacity at `t`, in `0..=1`.
pub fn opacity(tr: &Transform, t: f64) -> f64 {
    (scalar(tr.o.as_ref(), t, 100.0) / 100.0).clamp(0.0, 1.0)
}

/// An outline property at `t` as a path; `closed` is the item's legacy flag.
pub fn outline(p: &Property<Bezier>, t: f64, closed: Option<bool>) -> BezPath {
    let Some((b, _)) = sample(&p.value, t) else {
        return BezPath::new();
    };
    bezier_path(&b, b.closed.or(closed).unwrap_or(false))
}

/// A Lottie outline as a kurbo path.
pub fn bezier_path(b: &Bezier, closed: bool) -> BezPath {
    let mut path = BezPath::new();
    let n = b.v.len();
    if n == 0 {
        return path;
    }
    let at = |v: &[[f64; 2]], k: usize| v.get(k).map_or(Vec2::ZERO, |p| Vec2::new(p[0], p[1]));
    let vertex = |k: usize| Point::new(b.v[k][0], b.v[k][1]);
    path.move_to(vertex(0));
    let segments = if closed { n } else { n - 1 };
    for k in 0..segments {
        let next = (k + 1) % n;
        let (p0, p3) = (vertex(k), vertex(next));
        let c1 = p0 + at(&b.o, k);
        let c2 = p3 + at(&b.i, next);
        // Controls on the ends, or at the thirds (as gmotion writes a straight segment, to
        // the 1/1000 its coordinates are written to): a line.
        let third = |c: Point, a: Point, b: Point| (c - a.lerp(b, 1.0 / 3.0)).hypot() <= 1e-3;
        if (c1 == p0 && c2 == p3) || (p0 != p3 && third(c1, p0, p3) && third(c2, p3, p0)) {
            path.line_to(p3);
        } else {
            path.curve_to(c1, c2, p3);
        }
    }
    if closed {
        path.close_path();
    }
    path
}
