//! Easing functions (paper, Definition 1): maps from linear progress `u ∈ [0, 1]` to
//! eased progress, and [`Ease`], an easing stretched to any duration.
//!
//! Besides the CSS curves, two families come from the paper's discussion (sec. 9):
//! B-spline windows ("equivalent to box filters connected in series", symmetric motion)
//! and cascades of one-pole filters (sec. 8.2, fast-in slow-out motion). Both are the
//! step responses of low-pass filters, so they are convex easings: monotone, within
//! `[0, 1]`, and with zero initial velocity from order 2 on (the hypothesis of Claim 1).

use kurbo::CubicBez;

use super::error::{SignalError, finite, positive, whole};

/// Largest B-spline order accepted by [`Easing::BSpline`].
pub const MAX_BSPLINE_ORDER: u32 = 32;
/// Largest number of poles accepted by [`Easing::Poles`].
pub const MAX_POLES: u32 = 16;
/// The step-response tail cut off by [`Easing::poles`]'s default time constant.
pub const POLES_DEFAULT_TAIL: f64 = 1e-3;

/// An easing curve. `apply(0) = 0` and `apply(1) = 1` for every variant.
#[derive(Clone, Debug, PartialEq)]
pub enum Easing {
    /// Identity.
    Linear,
    /// CSS `cubic-bezier(x1, y1, x2, y2)` (CSS Easing Functions Level 1).
    CubicBezier([f64; 4]),
    /// The integral of the cardinal B-spline window of order `k` (degree `k − 1`)
    /// stretched onto `[0, 1]`: the step response of `k` equal box filters in series
    /// (paper sec. 9). `k = 1` is linear; order `k` is `C^(k−1)` smooth. Evaluated with
    /// the Cox–de Boor recursion (all terms positive, so stable for every order).
    BSpline(u32),
    /// The step response of `n` one-pole low-pass filters `ẋ = (u − x)/τ` in series
    /// (paper sec. 8.2), i.e. the Erlang CDF `g(u) = P(n, u/τ)`, truncated at `u = 1`.
    /// Truncation leaves a gap `ε = 1 − g(1)` and a final slope `δ = g'(1)`; both are
    /// closed by two small cubic terms that vanish with their slope at `u = 0`:
    /// `s(u) = g(u) + ε·(3u² − 2u³) − δ·(u³ − u²)`, so `s(1) = 1` and `s'(1) = 0` — the
    /// curve ends at rest and FIR transitions built on it keep velocity continuous.
    /// (For the default time constant `ε` is 0.1 %.) `tau` is in units of the easing's
    /// duration; the curve is monotone for `tau ≤ 1/(n+1)` (tested), so it makes a
    /// convex filter.
    Poles {
        /// Number of poles (`1..=16`).
        n: u32,
        /// Time constant of each pole as a fraction of the duration (`> 0`).
        tau: f64,
    },
    /// CSS `steps(n, jump-end)`: `n` equal jumps, the value `⌊u·n⌋/n` holding in between and
    /// the last jump landing on 1 at the end of the change (`u = 1`). `hold` is `steps(1)`: the
    /// value holds for the whole change and jumps at its end. Jumps are right-continuous in
    /// `u` (at `u = k/n` the value is already `k/n`), so a reversed change — progress
    /// `apply(1 − u)` — is the exact time reverse: it drops at the very start of its slice
    /// and the value at each jump instant is the one before the jump.
    Steps(u32),
}

/// Largest number of jumps accepted by [`Easing::Steps`].
pub const MAX_STEPS: u32 = 1000;

/// How close `u·n` must come to a whole number to count as on it: the jump instants are
/// computed from times, and the rounding of `(t − start)/span` must not move a jump that
/// falls on a frame to the next frame.
const STEP_SNAP: f64 = 1e-9;

impl Easing {
    /// Eased progress at linear progress `u` (clamped to `[0,1]`).
    #[inline]
    pub fn apply(&self, u: f64) -> f64 {
        let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) };
        if u == 0.0 || u == 1.0 {
            return u;
        }
        match self {
            Easing::Linear => u,
            Easing::CubicBezier(p) => cubic_bezier(*p, u),
            Easing::BSpline(k) => bspline_cdf(*k, u),
            Easing::Poles { n, tau } => poles_easing(*n, *tau, u),
            Easing::Steps(n) => {
                let n = f64::from(*n);
                (u * n + STEP_SNAP).floor().min(n) / n
            }
        }
    }

    /// The number of jumps of a [`Easing::Steps`] curve (exporters write its jumps as hold
    /// keys), `None` for continuous curves.
    pub fn steps(&self) -> Option<u32> {
        match self {
            Easing::Steps(n) => Some(*n),
            _ => None,
        }
    }

    /// The stepped easing with `n` jumps (`1..=1000`).
    pub fn stepped(n: u32) -> Result<Easing, SignalError> {
        whole("number of steps", f64::from(n), 1, MAX_STEPS, "1..=1000")?;
        Ok(Easing::Steps(n))
    }

    /// The CSS cubic-bezier control points, when the curve is one (exporters use them as
    /// keyframe tangents). B-spline and pole easings are not cubic Béziers (except the
    /// linear `bspline(1)`), so exporters must sample them.
    pub fn as_cubic_bezier(&self) -> Option<[f64; 4]> {
        match self {
            Easing::Linear | Easing::BSpline(1) => Some([0.0, 0.0, 1.0, 1.0]),
            Easing::CubicBezier(p) => Some(*p),
            Easing::BSpline(_) | Easing::Poles { .. } | Easing::Steps(_) => None,
        }
    }

    /// The B-spline window easing of order `k` (`1..=32`).
    pub fn bspline(k: u32) -> Result<Easing, SignalError> {
        whole(
            "B-spline order",
            f64::from(k),
            1,
            MAX_BSPLINE_ORDER,
            "1..=32",
        )?;
        Ok(Easing::BSpline(k))
    }

    /// The `n`-pole cascade easing with the default time constant: the one whose
    /// truncated tail `1 − P(n, 1/τ)` is [`POLES_DEFAULT_TAIL`] (0.1 %), so the curve
    /// ends with a velocity jump of at most a few tenths of a percent of its peak speed.
    pub fn poles(n: u32) -> Result<Easing, SignalError> {
        whole("number of poles", f64::from(n), 1, MAX_POLES, "1..=16")?;
        Ok(Easing::Poles {
            n,
            tau: 1.0 / erlang_quantile(n, POLES_DEFAULT_TAIL),
        })
    }

    /// The `n`-pole cascade easing with time constant `tau` (a fraction of the duration).
    pub fn poles_with_tau(n: u32, tau: f64) -> Result<Easing, SignalError> {
        whole("number of poles", f64::from(n), 1, MAX_POLES, "1..=16")?;
        positive("pole time constant", tau)?;
        Ok(Easing::Poles { n, tau })
    }

    /// Every name [`Easing::from_call`] knows, in its preferred spelling.
    pub const NAMES: [&'static str; 10] = [
        "linear",
        "ease",
        "ease-in",
        "ease-out",
        "ease-in-out",
        "cubic-bezier",
        "bspline",
        "poles",
        "steps",
        "hold",
    ];

    /// Builds an easing from its grammar spelling: a name and numeric arguments.
    ///
    /// | spelling | curve |
    /// |---|---|
    /// | `linear` | identity |
    /// | `ease`, `ease-in`, `ease-out`, `ease-in-out` (or with `_`) | the CSS keywords |
    /// | `cubic(x1, y1, x2, y2)` (also `cubic-bezier`, `cubic_bezier`) | CSS cubic Bézier, `x1, x2 ∈ [0, 1]` |
    /// | `bspline(k)` | B-spline window of order `k ∈ 1..=32` (`bspline(3)`: quadratic B-spline, C²) |
    /// | `poles(n)` | `n` one-pole filters in series, `n ∈ 1..=16`, default time constant (0.1 % tail) |
    /// | `poles(n, tau)` | the same with time constant `tau` as a fraction of the duration |
    /// | `steps(n)` | `n ∈ 1..=1000` equal jumps, CSS `steps(n, jump-end)`: the last lands at the end |
    /// | `hold` | `steps(1)`: the value holds and jumps at the end of the change |
    pub fn from_call(name: &str, args: &[f64]) -> Result<Easing, String> {
        Easing::try_from_call(name, args).map_err(|e| e.to_string())
    }

    /// [`Easing::from_call`] with a typed error.
    pub fn try_from_call(name: &str, args: &[f64]) -> Result<Easing, SignalError> {
        let arity = |n: usize, usage: &str| {
            if args.len() == n {
                Ok(())
            } else {
                Err(SignalError::Invalid(format!(
                    "easing `{name}` takes {usage}, got {} argument(s)",
                    args.len()
                )))
            }
        };
        for &a in args {
            finite("easing argument", a)?;
        }
        let keyword = |e: Easing| arity(0, "no arguments").map(|_| e);
        match name {
            "linear" => keyword(Easing::Linear),
            "hold" => keyword(Easing::Steps(1)),
            "steps" => {
                arity(1, "one number, the number of jumps n")?;
                Easing::stepped(whole("number of steps", args[0], 1, MAX_STEPS, "1..=1000")?)
            }
            "ease" => keyword(Easing::CubicBezier([0.25, 0.1, 0.25, 1.0])),
            "ease_in" | "ease-in" => keyword(Easing::CubicBezier([0.42, 0.0, 1.0, 1.0])),
            "ease_out" | "ease-out" => keyword(Easing::CubicBezier([0.0, 0.0, 0.58, 1.0])),
            "ease_in_out" | "ease-in-out" => keyword(Easing::CubicBezier([0.42, 0.0, 0.58, 1.0])),
            "cubic" | "cubic_bezier" | "cubic-bezier" => {
                arity(4, "four numbers x1, y1, x2, y2")?;
                for (what, x) in [("cubic-bezier x1", args[0]), ("cubic-bezier x2", args[2])] {
                    if !(0.0..=1.0).contains(&x) {
                        return Err(SignalError::OutOfRange {
                            what,
                            range: "[0, 1]",
                            value: x,
                        });
                    }
                }
                Ok(Easing::CubicBezier([args[0], args[1], args[2], args[3]]))
            }
            "bspline" => {
                arity(1, "one number, the order k")?;
                Easing::bspline(whole(
                    "B-spline order",
                    args[0],
                    1,
                    MAX_BSPLINE_ORDER,
                    "1..=32",
                )?)
            }
            "poles" => {
                if args.len() == 2 {
                    let n = whole("number of poles", args[0], 1, MAX_POLES, "1..=16")?;
                    return Easing::poles_with_tau(n, args[1]);
                }
                arity(
                    1,
                    "the number of poles n and optionally the time constant tau",
                )?;
                Easing::poles(whole("number of poles", args[0], 1, MAX_POLES, "1..=16")?)
            }
            _ => Err(SignalError::Unknown {
                kind: "easing",
                name: name.to_string(),
                expected: "linear, ease, ease-in, ease-out, ease-in-out, cubic, bspline, poles, steps, hold",
            }),
        }
    }
}

/// An easing function with a duration (paper, Definition 1): `s(t) = 0` for `t ≤ 0`,
/// `s(t) = 1` for `t ≥ d`, and `s(t) = easing(t/d)` in between.
#[derive(Clone, Debug, PartialEq)]
pub struct Ease {
    easing: Easing,
    duration: f64,
}

impl Ease {
    /// `easing` stretched over `duration` seconds (must be finite and `> 0`).
    pub fn new(easing: Easing, duration: f64) -> Result<Ease, SignalError> {
        positive("easing duration", duration)?;
        if let Easing::CubicBezier(p) = &easing {
            for &v in p {
                finite("cubic-bezier control point", v)?;
            }
        }
        Ok(Ease { easing, duration })
    }

    /// `s(t)`.
    pub fn at(&self, t: f64) -> f64 {
        if t <= 0.0 {
            0.0
        } else if t >= self.duration {
            1.0
        } else {
            self.easing.apply(t / self.duration)
        }
    }

    /// The duration `d` in seconds.
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// The normalised curve.
    pub fn easing(&self) -> &Easing {
        &self.easing
    }
}

/// Solves the CSS cubic-bezier timing function at `x`: Newton's method from `t = x`, which
/// converges in a few steps on most curves (the engine evaluates easings every frame), and
/// [`solve_bezier_x`] where Newton stalls on a flat stretch.
fn cubic_bezier([x1, y1, x2, y2]: [f64; 4], x: f64) -> f64 {
    let bez = |a: f64, b: f64, t: f64| {
        let mt = 1.0 - t;
        3.0 * mt * mt * t * a + 3.0 * mt * t * t * b + t * t * t
    };
    let dbez = |a: f64, b: f64, t: f64| {
        let mt = 1.0 - t;
        3.0 * mt * mt * a + 6.0 * mt * t * (b - a) + 3.0 * t * t * (1.0 - b)
    };
    let mut t = x;
    for _ in 0..8 {
        let err = bez(x1, x2, t) - x;
        if err.abs() < 1e-12 {
            return bez(y1, y2, t);
        }
        let d = dbez(x1, x2, t);
        if d.abs() < 1e-7 {
            break;
        }
        t = (t - err / d).clamp(0.0, 1.0);
    }
    let curve = CubicBez::new((0.0, 0.0), (x1, y1), (x2, y2), (1.0, 1.0));
    bez(y1, y2, solve_bezier_x(&curve, x))
}

/// The parameter where a cubic Bézier whose x grows monotonically (a timing curve, or a
/// piece or mirror of one) reaches `x`; 0 before its start and 1 past its end. Bisection, to
/// full `f64` precision in 64 halvings: robust on the flat ends where Newton stalls. This is
/// the one solver the engine and both exporters use for eased keyframes.
pub fn solve_bezier_x(curve: &CubicBez, x: f64) -> f64 {
    if x <= curve.p0.x {
        return 0.0;
    }
    if x >= curve.p3.x {
        return 1.0;
    }
    let [x0, x1, x2, x3] = [curve.p0.x, curve.p1.x, curve.p2.x, curve.p3.x];
    // kurbo's `eval`, its x alone: the same operations in the same order, so the same bits
    // at half the work (the exporters solve this for every eased key of every shape).
    let x_at = |t: f64| {
        let mt = 1.0 - t;
        x0 * (mt * mt * mt) + (x1 * (mt * mt * 3.0) + (x2 * (mt * 3.0) + x3 * t) * t) * t
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        // `lo` and `hi` are neighbours: every further halving keeps them (the side `mid`
        // equals already passed its test), so the answer is the one 64 halvings give.
        if mid == lo || mid == hi {
            break;
        }
        if x_at(mid) < x {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The CDF of the cardinal B-spline of order `k` stretched onto `[0, 1]`, at `u ∈ (0, 1)`.
///
/// The window `M_k` on `[0, k]` integrates to the sum of the order-`k+1` basis functions
/// `N_j` with `j ≥ 0`; those are evaluated at `x = k·u` by Cox–de Boor on integer knots.
fn bspline_cdf(k: u32, u: f64) -> f64 {
    let x = f64::from(k) * u;
    let m = x.floor();
    // b[i] holds N_{j, r}(x) for j = m − r + 1 + i.
    let mut b = vec![1.0];
    for r in 2..=k as usize + 1 {
        let rf = r as f64;
        let next: Vec<f64> = (0..r)
            .map(|i| {
                let j = m - rf + 1.0 + i as f64;
                let left = if i >= 1 { b[i - 1] } else { 0.0 };
                let right = if i < r - 1 { b[i] } else { 0.0 };
                ((x - j) * left + (j + rf - x) * right) / (rf - 1.0)
            })
            .collect();
        b = next;
    }
    // With r = k + 1, index i is j = m − k + i; keep j ≥ 0.
    let first = (f64::from(k) - m).max(0.0) as usize;
    b[first..].iter().sum::<f64>().clamp(0.0, 1.0)
}

/// The pole-cascade easing with its end gap and end slope closed (see [`Easing::Poles`]).
fn poles_easing(n: u32, tau: f64, u: f64) -> f64 {
    let x = 1.0 / tau;
    let gap = erlang_tail(n, x);
    let slope = x * erlang_density(n, x);
    erlang_cdf(n, u * x) + gap * u * u * (3.0 - 2.0 * u) - slope * u * u * (u - 1.0)
}

/// The Erlang density `xⁿ⁻¹e⁻ˣ/(n−1)!`, the derivative of `P(n, x)`.
fn erlang_density(n: u32, x: f64) -> f64 {
    let mut d = (-x).exp();
    for i in 1..n {
        d *= x / f64::from(i);
    }
    d
}

/// The regularised lower incomplete gamma function `P(n, x)` for integer `n`: the
/// probability that a sum of `n` unit exponentials is at most `x` (Erlang CDF).
pub(crate) fn erlang_cdf(n: u32, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x < f64::from(n) {
        // Positive series e^{-x} Σ_{i≥n} x^i/i!, no cancellation for small x.
        let mut term = (-x).exp();
        for i in 1..=n {
            term *= x / f64::from(i);
        }
        let mut sum = 0.0;
        let mut i = n;
        while term > sum * 1e-17 {
            sum += term;
            i += 1;
            term *= x / f64::from(i);
        }
        sum.min(1.0)
    } else {
        1.0 - erlang_tail(n, x)
    }
}

/// `Q(n, x) = 1 − P(n, x) = e^{-x} Σ_{i<n} x^i/i!`.
fn erlang_tail(n: u32, x: f64) -> f64 {
    let mut term = (-x).exp();
    let mut sum = 0.0;
    for i in 0..n {
        if i > 0 {
            term *= x / f64::from(i);
        }
        sum += term;
    }
    sum
}

/// The `x` where the Erlang tail `Q(n, x)` falls to `tail` (bisection; `Q` decreases).
fn erlang_quantile(n: u32, tail: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    while erlang_tail(n, hi) > tail {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if erlang_tail(n, mid) > tail {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::ParamCurve;

    /// The solver as first written: 64 halvings, each evaluating the whole point.
    fn solve_by_64_halvings(curve: &CubicBez, x: f64) -> f64 {
        if x <= curve.p0.x {
            return 0.0;
        }
        if x >= curve.p3.x {
            return 1.0;
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if curve.eval(mid).x < x {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    proptest::proptest! {
        /// Stopping once the bracket cannot shrink, and evaluating x alone, change no bit
        /// of any answer: on timing curves, on the pieces and mirrors the exporters make of
        /// them, at any x (ends, tiny and NaN included).
        #[test]
        fn the_solver_answers_as_64_halvings_do(
            c in proptest::array::uniform4(-0.5f64..1.5),
            piece in (0.0f64..1.0, 0.0f64..1.0),
            x in proptest::prop_oneof![
                -0.1f64..1.1,
                0.0f64..1e-12,
                proptest::num::f64::ANY,
                proptest::strategy::Just(f64::NAN),
            ],
        ) {
            let timing = CubicBez::new(
                (0.0, 0.0),
                (c[0].clamp(0.0, 1.0), c[1]),
                (c[2].clamp(0.0, 1.0), c[3]),
                (1.0, 1.0),
            );
            let (a, b) = (piece.0.min(piece.1), piece.0.max(piece.1));
            for curve in [timing, timing.subsegment(a..b)] {
                let (new, old) = (solve_bezier_x(&curve, x), solve_by_64_halvings(&curve, x));
                proptest::prop_assert_eq!(new.to_bits(), old.to_bits(), "{:?} at {}", curve, x);
            }
        }
    }

    #[test]
    fn endpoints_hold_for_every_variant() {
        let all = [
            Easing::Linear,
            Easing::CubicBezier([0.42, 0.0, 0.58, 1.0]),
            Easing::bspline(1).unwrap(),
            Easing::bspline(4).unwrap(),
            Easing::bspline(32).unwrap(),
            Easing::poles(1).unwrap(),
            Easing::poles(16).unwrap(),
            Easing::poles_with_tau(4, 5.0).unwrap(),
        ];
        for e in &all {
            assert_eq!(e.apply(0.0), 0.0, "{e:?}");
            assert_eq!(e.apply(1.0), 1.0, "{e:?}");
            assert_eq!(e.apply(-3.0), 0.0);
            assert_eq!(e.apply(7.0), 1.0);
        }
    }

    #[test]
    fn bspline_orders_match_closed_forms() {
        // Order 2: the triangle window; its CDF is 2u² below one half.
        let e = Easing::BSpline(2);
        assert!((e.apply(0.25) - 2.0 * 0.25 * 0.25).abs() < 1e-14);
        assert!((e.apply(0.75) - (1.0 - 2.0 * 0.25 * 0.25)).abs() < 1e-14);
        // Order 3: Irwin–Hall CDF of the mean of three uniforms at x = 3u ∈ [0, 1]: x³/6.
        let u = 0.2;
        assert!((Easing::BSpline(3).apply(u) - (3.0 * u).powi(3) / 6.0).abs() < 1e-14);
        // Symmetry s(1 − u) = 1 − s(u) for a high order.
        let e = Easing::BSpline(20);
        assert!((e.apply(0.3) + e.apply(0.7) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn pole_easing_is_the_corrected_erlang_cdf() {
        // One pole: g(u) = 1 − e^{−u/τ}, gap e^{−1/τ}, end slope e^{−1/τ}/τ.
        let tau = 0.25;
        let e = Easing::poles_with_tau(1, tau).unwrap();
        let u = 0.5f64;
        let (gap, slope) = ((-1.0 / tau).exp(), (-1.0 / tau).exp() / tau);
        let want = 1.0 - (-u / tau).exp() + gap * (3.0 * u * u - 2.0 * u.powi(3))
            - slope * (u.powi(3) - u * u);
        assert!((e.apply(u) - want).abs() < 1e-14);
        // Two poles, both branches of erlang_cdf: P(2, x) = 1 − e^{−x}(1 + x).
        for x in [0.3, 1.9, 2.0, 7.5] {
            assert!((erlang_cdf(2, x) - (1.0 - (-x).exp() * (1.0 + x))).abs() < 1e-14);
        }
        let Easing::Poles { tau, .. } = Easing::poles(4).unwrap() else {
            unreachable!()
        };
        assert!((erlang_tail(4, 1.0 / tau) - POLES_DEFAULT_TAIL).abs() < 1e-12);
    }

    #[test]
    fn pole_easings_end_at_rest_and_are_monotone() {
        for n in 1..=16 {
            let mut taus = vec![Easing::poles(n).unwrap()];
            for tau in [0.02, 0.1, 1.0 / f64::from(n + 1)] {
                taus.push(Easing::poles_with_tau(n, tau).unwrap());
            }
            for e in taus {
                let h = 1e-6;
                let end_slope = (e.apply(1.0) - e.apply(1.0 - h)) / h;
                assert!(end_slope.abs() < 1e-4, "{e:?}: end slope {end_slope}");
                let mut prev = 0.0;
                for i in 1..=2000 {
                    let v = e.apply(f64::from(i) / 2000.0);
                    assert!(v >= prev - 1e-15, "{e:?} decreases at {i}");
                    prev = v;
                }
            }
        }
    }

    #[test]
    fn from_call_spellings_and_errors() {
        assert_eq!(Easing::from_call("bspline", &[3.0]), Ok(Easing::BSpline(3)));
        assert_eq!(
            Easing::from_call("poles", &[4.0, 0.2]),
            Ok(Easing::Poles { n: 4, tau: 0.2 })
        );
        assert!(Easing::from_call("bspline", &[0.0]).is_err());
        assert!(Easing::from_call("bspline", &[2.5]).is_err());
        assert!(Easing::from_call("poles", &[4.0, -1.0]).is_err());
        assert!(Easing::from_call("poles", &[f64::NAN]).is_err());
        assert!(Easing::from_call("cubic", &[1.5, 0.0, 0.5, 1.0]).is_err());
        assert!(Easing::from_call("linear", &[1.0]).is_err());
        let msg = Easing::from_call("bounce", &[]).unwrap_err();
        assert!(msg.contains("unknown easing `bounce`"), "{msg}");
        assert!(Ease::new(Easing::Linear, 0.0).is_err());
        assert!(Ease::new(Easing::Linear, f64::INFINITY).is_err());
    }
}
