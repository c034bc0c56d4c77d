//! [`Format::UnitBox`](super::Format::UnitBox): a motion's progress over one window as SMIL
//! keyframes: holds, linear runs and `keySplines` pieces that reproduce
//! [`Timing::progress`] exactly.
//!
//! SMIL splines map an interval's time fraction to its value fraction with a cubic whose
//! control points must lie in `[0, 1]²`. An easing curve cut to a window, or one that
//! overshoots, does not satisfy that as a whole, so the curve is cut at the window's ends and
//! at its extrema in value (each piece is then monotone) and halved until every piece's
//! normalised control points fit.

use kurbo::{CubicBez, ParamCurve, Point};

use super::{Ease, Key, Piece, Same, steps};
use crate::motion::Timing;
use crate::signals::easing::solve_bezier_x;
use crate::tolerance::{PROGRESS, Tolerance};

/// Smallest time step treated as an interval (shorter pieces become jumps).
pub(super) const TIME_EPS: f64 = 1e-9;
/// How far a normalised control point may stray outside `[0, 1]` before a piece is halved.
const BOX_EPS: f64 = 1e-7;
/// Halvings allowed per monotone piece; a piece this short is within rounding of any fit.
const MAX_DEPTH: u32 = 10;

/// The keys of a channel that holds `default` before its first piece and
/// `value(piece, progress)` within each piece: the first at the first piece's start, the
/// last at the last piece's end; equal times in consecutive keys mark a jump (between
/// pieces too). `None` when an easing is not a cubic Bézier with `x1, x2 ∈ [0, 1]` (the
/// caller bakes such motion by sampling).
pub fn keys<V: Clone + Same>(
    pieces: &[Piece],
    default: V,
    value: impl Fn(usize, f64) -> V,
) -> Option<Vec<Key<V>>> {
    let Some(first) = pieces.first() else {
        return Some(Vec::new());
    };
    let mut keys = vec![Key::linear(first.t0, default)];
    for (k, piece) in pieces.iter().enumerate() {
        let ps = window(piece.timing, piece.t0, piece.t1)?;
        let mut ps = ps.into_iter().map(|p| Key {
            t: p.t,
            v: value(k, p.v),
            ease: p.ease,
        });
        let start = ps.next().expect("a window has a first key");
        let last = keys.last().expect("the default's key").clone();
        if !last.v.same(&start.v) {
            // Hold the value up to the piece, then jump: SMIL spells both as keys.
            if last.t < start.t {
                keys.push(Key::linear(start.t, last.v));
            }
            keys.push(start);
        } else if start.t - last.t > TIME_EPS {
            // The same value after a gap (a morph held until its inverted twin): the piece's
            // first key still begins its run, which would otherwise reach back over the gap.
            keys.push(start);
        }
        keys.extend(ps);
    }
    Some(keys)
}

/// The progress `f(t)` of `timing` over `[a, b]` as keys, the first at `a` and the last at
/// `b`; equal times in consecutive keys mark a jump. `None` when the easing is not a cubic
/// Bézier with `x1, x2 ∈ [0, 1]`.
fn window(timing: &Timing, a: f64, b: f64) -> Option<Vec<Key<f64>>> {
    let b = b.max(a);
    let mut keys = vec![Key::linear(a, timing.progress(a))];
    let span = timing.end - timing.start - timing.delay;
    if span <= 0.0 {
        // The change is a step: it happens all at once at one instant.
        let tj = if timing.reversed {
            timing.start
        } else {
            timing.start + timing.delay
        };
        if a < tj && tj <= b {
            keys.push(Key::linear(tj, timing.progress(a)));
            keys.push(Key::linear(tj, timing.progress(tj)));
        }
        push_hold(&mut keys, b, timing.progress(b));
        return Some(keys);
    }
    let (a0, a1) = timing.active();
    let (m0, m1) = (a0.clamp(a, b), a1.clamp(a, b));
    if m1 - m0 > TIME_EPS {
        push_hold(&mut keys, m0, timing.progress(m0));
        let base = if timing.reversed {
            timing.start
        } else {
            timing.start + timing.delay
        };
        let u = |t: f64| ((t - base) / span).clamp(0.0, 1.0);
        let time = |x: f64| base + x * span;
        if timing.ease.steps().is_some() {
            // Holds and jumps: two keys at one time per jump. A forward jump is written
            // `LATE` early: Chromium's SMIL time is not exact, and at a frame landing on a
            // jump it showed some paths before it and some after.
            for j in steps::jumps(timing, m0, m1) {
                let t = if timing.reversed {
                    j.t
                } else {
                    (j.t - steps::LATE).max(m0)
                };
                push_hold(&mut keys, t, j.before);
                keys.push(Key::linear(t, j.after));
            }
            push_hold(&mut keys, b, timing.progress(b));
            return Some(keys);
        }
        let [x1, y1, x2, y2] = timing.ease.as_cubic_bezier()?;
        if !(0.0..=1.0).contains(&x1)
            || !(0.0..=1.0).contains(&x2)
            || ![y1, y2].iter().all(|v| v.is_finite())
        {
            return None;
        }
        // The eased progress as a curve in (u, p): forward 0→1, reversed the mirror 1→0.
        let curve = if timing.reversed {
            CubicBez::new((0.0, 1.0), (1.0 - x2, y2), (1.0 - x1, y1), (1.0, 0.0))
        } else {
            CubicBez::new((0.0, 0.0), (x1, y1), (x2, y2), (1.0, 1.0))
        };
        let (s0, s1) = (solve_bezier_x(&curve, u(m0)), solve_bezier_x(&curve, u(m1)));
        let sub = curve.subsegment(s0..s1);
        let mut cuts = y_extrema(&sub);
        cuts.push(1.0);
        let mut prev = 0.0;
        for c in cuts {
            fit(&sub.subsegment(prev..c), &time, &mut keys, 0);
            prev = c;
        }
        // Land exactly on the model's own value at the end of the run.
        if let Some(last) = keys.last_mut() {
            last.t = m1;
            last.v = timing.progress(m1);
        }
    }
    push_hold(&mut keys, b, timing.progress(b));
    Some(keys)
}

/// Appends a key holding `v` until `t`, unless the channel is already there.
fn push_hold(keys: &mut Vec<Key<f64>>, t: f64, v: f64) {
    if let Some(last) = keys.last()
        && t - last.t <= TIME_EPS
        && PROGRESS.same(v, last.v)
    {
        return;
    }
    keys.push(Key::linear(t, v));
}

/// Appends the key ending monotone piece `c`, halving it until its spline fits the box.
fn fit(c: &CubicBez, time: &impl Fn(f64) -> f64, keys: &mut Vec<Key<f64>>, depth: u32) {
    let (dx, dy) = (c.p3.x - c.p0.x, c.p3.y - c.p0.y);
    let t = time(c.p3.x);
    if dx <= TIME_EPS * 1e-3 || dy.abs() <= 1e-12 {
        keys.push(Key::linear(t, c.p3.y));
        return;
    }
    let norm = |p: Point| ((p.x - c.p0.x) / dx, (p.y - c.p0.y) / dy);
    let (x1, y1) = norm(c.p1);
    let (x2, y2) = norm(c.p2);
    let spline = [x1, y1, x2, y2];
    let fits = spline
        .iter()
        .all(|v| (-BOX_EPS..=1.0 + BOX_EPS).contains(v));
    if fits || depth >= MAX_DEPTH {
        let spline = spline.map(|v| v.clamp(0.0, 1.0));
        let ease = if is_linear(spline) {
            Ease::Linear
        } else {
            Ease::Bezier(spline)
        };
        keys.push(Key { t, v: c.p3.y, ease });
        return;
    }
    fit(&c.subsegment(0.0..0.5), time, keys, depth + 1);
    fit(&c.subsegment(0.5..1.0), time, keys, depth + 1);
}

/// True when a spline is the straight line (its control points on the diagonal).
fn is_linear([x1, y1, x2, y2]: [f64; 4]) -> bool {
    let diagonal = Tolerance::Below(1e-12);
    diagonal.same(x1, y1) && diagonal.same(x2, y2)
}

/// Parameters in `(0, 1)` where the curve's y turns, sorted.
fn y_extrema(c: &CubicBez) -> Vec<f64> {
    // y'(s) = 3[(1-s)²d0 + 2(1-s)s·d1 + s²d2] with dᵢ the control point differences.
    let (d0, d1, d2) = (c.p1.y - c.p0.y, c.p2.y - c.p1.y, c.p3.y - c.p2.y);
    let (qa, qb, qc) = (d0 - 2.0 * d1 + d2, 2.0 * (d1 - d0), d0);
    let mut roots: Vec<f64> = kurbo::common::solve_quadratic(qc, qb, qa)
        .into_iter()
        .filter(|s| *s > 1e-9 && *s < 1.0 - 1e-9)
        .collect();
    roots.sort_by(f64::total_cmp);
    roots.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    roots
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::keyframe::tests::play;
    use crate::signals::Easing;

    fn check(timing: Timing, a: f64, b: f64) {
        let keys = window(&timing, a, b).unwrap();
        assert_eq!(keys[0].t, a);
        assert!((keys[keys.len() - 1].t - b).abs() < 1e-12);
        for w in keys.windows(2) {
            assert!(w[1].t >= w[0].t);
            if let Ease::Bezier(s) = w[1].ease {
                assert!(s.iter().all(|v| (0.0..=1.0).contains(v)), "{s:?}");
            }
        }
        for i in 0..=1000 {
            let t = a + (b - a) * i as f64 / 1000.0;
            let (got, want) = (play(&keys, t), timing.progress(t));
            assert!(
                (got - want).abs() < 1e-6,
                "{timing:?} at {t}: {got} vs {want}"
            );
        }
    }

    fn timing(ease: Easing, reversed: bool, delay: f64) -> Timing {
        Timing {
            start: 1.0,
            end: 3.0,
            delay,
            ease,
            reversed,
        }
    }

    #[test]
    fn windows_of_eased_motion_are_exact() {
        let eases = [
            Easing::Linear,
            Easing::CubicBezier([0.42, 0.0, 0.58, 1.0]),
            Easing::CubicBezier([0.3, -0.6, 0.4, 1.7]),
            Easing::CubicBezier([0.9, 0.1, 0.1, 0.9]),
        ];
        for ease in eases {
            for reversed in [false, true] {
                for delay in [0.0, 0.5] {
                    let tm = timing(ease.clone(), reversed, delay);
                    check(tm.clone(), 0.0, 4.0);
                    check(tm.clone(), 1.0, 3.0);
                    check(tm.clone(), 1.3, 2.2);
                    check(tm, 2.2, 3.0);
                }
            }
        }
    }

    #[test]
    fn reversed_spline_mirrors_the_curve() {
        let tm = timing(Easing::CubicBezier([0.1, 0.2, 0.6, 0.9]), true, 0.0);
        let keys = window(&tm, 1.0, 3.0).unwrap();
        assert_eq!(keys.len(), 2);
        let Ease::Bezier(s) = keys[1].ease else {
            panic!("not a spline")
        };
        let want = [1.0 - 0.6, 1.0 - 0.9, 1.0 - 0.1, 1.0 - 0.2];
        assert!(
            s.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-9),
            "{s:?}"
        );
    }

    #[test]
    fn instant_changes_jump() {
        let tm = Timing {
            start: 1.0,
            end: 1.0,
            delay: 0.0,
            ease: Easing::Linear,
            reversed: false,
        };
        let keys = window(&tm, 0.0, 2.0).unwrap();
        let jump: Vec<(f64, f64)> = keys.iter().map(|k| (k.t, k.v)).collect();
        assert_eq!(jump, vec![(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (2.0, 1.0)]);
    }

    #[test]
    fn other_easings_are_not_splines() {
        let tm = timing(Easing::BSpline(3), false, 0.0);
        assert!(window(&tm, 1.0, 3.0).is_none());
    }
}
