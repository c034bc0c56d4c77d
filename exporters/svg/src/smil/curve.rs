//! A motion's progress over one window as SMIL keyframes: holds, linear runs and
//! `keySplines` pieces that reproduce [`Timing::progress`] exactly.
//!
//! SMIL splines map an interval's time fraction to its value fraction with a cubic whose
//! control points must lie in `[0, 1]²`. An easing curve cut to a window, or one that
//! overshoots, does not satisfy that as a whole, so the curve is cut at the window's ends and
//! at its extrema in value (each piece is then monotone) and halved until every piece's
//! normalised control points fit.

use gmotion::motion::reduce::ramer_douglas_peucker;
use kurbo::{CubicBez, ParamCurve, Point};

use gmotion::motion::Timing;
use gmotion::signals::easing::solve_bezier_x;

/// How a channel arrives at a key from the key before it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ease {
    /// Straight interpolation (also used for holds, where both values are equal).
    Linear,
    /// A SMIL key spline `x1 y1 x2 y2`, every number in `[0, 1]`.
    Spline([f64; 4]),
}

/// A keyframe: at time `t` the channel has value `v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Key<V> {
    /// Seconds from the start of the document's animation.
    pub t: f64,
    /// The value.
    pub v: V,
    /// How the channel gets here from the previous key (ignored on the first key).
    pub ease: Ease,
}

impl<V> Key<V> {
    /// A key reached by straight interpolation.
    pub fn linear(t: f64, v: V) -> Key<V> {
        Key {
            t,
            v,
            ease: Ease::Linear,
        }
    }
}

/// Smallest time step treated as an interval (shorter pieces become jumps).
const TIME_EPS: f64 = 1e-9;
/// How far a normalised control point may stray outside `[0, 1]` before a piece is halved.
const BOX_EPS: f64 = 1e-7;
/// Halvings allowed per monotone piece; a piece this short is within rounding of any fit.
const MAX_DEPTH: u32 = 10;

/// The progress `f(t)` of `timing` over `[a, b]` as keys, the first at `a` and the last at
/// `b`; equal times in consecutive keys mark a jump. `None` when the easing is not a cubic
/// Bézier with `x1, x2 ∈ [0, 1]` (the caller bakes such motion by sampling).
pub fn progress_keys(timing: &Timing, a: f64, b: f64) -> Option<Vec<Key<f64>>> {
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
        && (v - last.v).abs() <= 1e-12
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
            Ease::Spline(spline)
        };
        keys.push(Key { t, v: c.p3.y, ease });
        return;
    }
    fit(&c.subsegment(0.0..0.5), time, keys, depth + 1);
    fit(&c.subsegment(0.5..1.0), time, keys, depth + 1);
}

/// True when a spline is the straight line (its control points on the diagonal).
fn is_linear([x1, y1, x2, y2]: [f64; 4]) -> bool {
    (x1 - y1).abs() < 1e-12 && (x2 - y2).abs() < 1e-12
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

/// The progress of `timing` at the sample instants `ts` as few keys as keep
/// `err(i, played, true)` within `tolerance` at every sample `i` (`err` measures what a
/// progress error costs, e.g. on the canvas). For easings that are not cubic Béziers: each
/// run between kept samples is a cubic Hermite piece with the curve's own slopes at its ends
/// (a key spline with `x1 = 1/3, x2 = 2/3`) where that fits the spline box, else straight.
pub fn sampled_progress(
    timing: &Timing,
    ts: &[f64],
    tolerance: f64,
    err: impl Fn(usize, f64, f64) -> f64,
) -> Vec<Key<f64>> {
    let ps: Vec<f64> = ts.iter().map(|&t| timing.progress(t)).collect();
    // One-sided slopes: the curve may kink where the change starts and stops.
    let h = 1e-6 * (timing.end - timing.start).abs().max(1e-3);
    let slopes: Vec<(f64, f64)> = ts
        .iter()
        .zip(&ps)
        .map(|(&t, &p)| {
            (
                (p - timing.progress(t - h)) / h,
                (timing.progress(t + h) - p) / h,
            )
        })
        .collect();
    let piece = |i: usize, j: usize| -> Ease {
        let (dt, dp) = (ts[j] - ts[i], ps[j] - ps[i]);
        if dt <= TIME_EPS || dp.abs() <= 1e-12 {
            return Ease::Linear;
        }
        let y1 = slopes[i].1 * dt / (3.0 * dp);
        let y2 = 1.0 - slopes[j].0 * dt / (3.0 * dp);
        if (0.0..=1.0).contains(&y1) && (0.0..=1.0).contains(&y2) {
            Ease::Spline([1.0 / 3.0, y1, 2.0 / 3.0, y2])
        } else {
            Ease::Linear
        }
    };
    let keep = ramer_douglas_peucker(ts.len(), tolerance, |k, i, j| {
        let x = super::bake::fraction(ts, k, i, j);
        let y = match piece(i, j) {
            // With x1 = 1/3 and x2 = 2/3 the spline's x is its parameter.
            Ease::Spline([_, y1, _, y2]) => {
                3.0 * (1.0 - x) * x * ((1.0 - x) * y1 + x * y2) + x * x * x
            }
            Ease::Linear => x,
        };
        err(k, ps[i] + (ps[j] - ps[i]) * y, ps[k])
    });
    let mut keys = vec![Key::linear(ts[keep[0]], ps[keep[0]])];
    for w in keep.windows(2) {
        keys.push(Key {
            t: ts[w[1]],
            v: ps[w[1]],
            ease: piece(w[0], w[1]),
        });
    }
    keys
}

#[cfg(test)]
mod tests {
    use super::*;
    use gmotion::signals::Easing;

    /// What a SMIL player computes from the keys at time `t`.
    fn play(keys: &[Key<f64>], t: f64) -> f64 {
        let i = keys.partition_point(|k| k.t <= t);
        if i == 0 {
            return keys[0].v;
        }
        if i == keys.len() {
            return keys[i - 1].v;
        }
        let (a, b) = (&keys[i - 1], &keys[i]);
        let x = (t - a.t) / (b.t - a.t);
        let y = match b.ease {
            Ease::Linear => x,
            Ease::Spline(s) => Easing::CubicBezier(s).apply(x),
        };
        a.v + (b.v - a.v) * y
    }

    fn check(timing: Timing, a: f64, b: f64) {
        let keys = progress_keys(&timing, a, b).unwrap();
        assert_eq!(keys[0].t, a);
        assert!((keys[keys.len() - 1].t - b).abs() < 1e-12);
        for w in keys.windows(2) {
            assert!(w[1].t >= w[0].t);
            if let Ease::Spline(s) = w[1].ease {
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
        let keys = progress_keys(&tm, 1.0, 3.0).unwrap();
        assert_eq!(keys.len(), 2);
        let Ease::Spline(s) = keys[1].ease else {
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
        let keys = progress_keys(&tm, 0.0, 2.0).unwrap();
        let jump: Vec<(f64, f64)> = keys.iter().map(|k| (k.t, k.v)).collect();
        assert_eq!(jump, vec![(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (2.0, 1.0)]);
    }

    #[test]
    fn sampled_easings_stay_within_tolerance_with_few_keys() {
        for ease in [Easing::BSpline(4), Easing::poles(3).unwrap()] {
            for reversed in [false, true] {
                let tm = timing(ease.clone(), reversed, 0.3);
                let ts = crate::smil::bake::sample_times(0.5, 3.5, 240.0, 8, &[1.3, 3.0]);
                // An error of one progress unit costs 100 canvas units.
                let keys = sampled_progress(&tm, &ts, 0.05, |_, a, b| 100.0 * (a - b).abs());
                assert!(keys.len() < 16, "{ease:?}: {} keys", keys.len());
                for i in 0..=2000 {
                    let t = 0.5 + 3.0 * i as f64 / 2000.0;
                    let err = 100.0 * (play(&keys, t) - tm.progress(t)).abs();
                    assert!(err < 0.1, "{ease:?} reversed {reversed} at {t}: {err}");
                }
            }
        }
    }

    #[test]
    fn other_easings_are_not_splines() {
        let tm = timing(Easing::BSpline(3), false, 0.0);
        assert!(progress_keys(&tm, 1.0, 3.0).is_none());
    }
}
