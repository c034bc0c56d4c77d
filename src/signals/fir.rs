//! Finite impulse response transitions (paper sec. 5): the output is the input convolved
//! with the derivative of an easing function, `y = x * ṡ` (Definition 4).
//!
//! For a step input this is `y(t) = x₀ + Σᵢ (xᵢ − xᵢ₋₁)·s(t − tᵢ)` (Claim 2), which
//! [`FirTransition`] evaluates with a queue of in-flight targets (Alg. 2). [`Fir`] is the
//! discrete-time filter of Alg. 3 with taps `h[k] = s(kT) − s((k−1)T)`, which gives
//! exactly the same samples when targets change on frames. When transitions are never
//! interrupted both equal the simple transition algorithm (Claim 3).

use std::collections::VecDeque;

use super::easing::Ease;
use super::error::{SignalError, finite, positive};
use super::system::System;
use super::transition::Transition;
use super::vector::Vector;

/// Largest number of taps a discrete FIR filter may have (duration × frame rate).
pub const MAX_TAPS: usize = 1 << 16;

/// A step response of finite duration: how the output answers a step of the input.
/// Scalar easings scale the step; a matrix easing (sec. 5: "the algorithms work as
/// written" for a matrix-valued easing) may mix components, as [`super::ArcEasing`] does.
pub trait Response<V: Vector> {
    /// The duration `d`: the response is complete (equal to the step) for `t ≥ d`.
    fn duration(&self) -> f64;

    /// `S(t)·Δ`: the response at time `t` after a step of size `delta`. Zero for `t ≤ 0`,
    /// `delta` for `t ≥ d`, linear in `delta`.
    fn step_response(&self, t: f64, delta: V) -> V;

    /// `Some(s(t))` when the response is a scalar easing (a multiple of the identity),
    /// which lets discrete filters store one number per tap.
    fn scalar_at(&self, _t: f64) -> Option<f64> {
        None
    }
}

impl<V: Vector> Response<V> for Ease {
    fn duration(&self) -> f64 {
        Ease::duration(self)
    }
    fn step_response(&self, t: f64, delta: V) -> V {
        delta.scale(self.at(t))
    }
    fn scalar_at(&self, t: f64) -> Option<f64> {
        Some(self.at(t))
    }
}

/// Continuous-time FIR transitions for step inputs (paper Alg. 2): a queue of the targets
/// set within the last `d` seconds; the output is the settled value plus each in-flight
/// step's partial response. Cost per sample is proportional to the number of targets in
/// flight (compare the IIR blocks, whose cost is constant).
///
/// (The listing's `target.value − last` means the previous target, `prev`.)
#[derive(Clone, Debug)]
pub struct FirTransition<V, R = Ease> {
    response: R,
    value: V,
    targets: VecDeque<(f64, V)>,
}

impl<V: Vector, R: Response<V>> FirTransition<V, R> {
    /// At rest on `x0`.
    pub fn new(response: R, x0: V) -> FirTransition<V, R> {
        FirTransition {
            response,
            value: x0,
            targets: VecDeque::new(),
        }
    }

    /// Number of targets still in flight.
    pub fn in_flight(&self) -> usize {
        self.targets.len()
    }
}

impl<V: Vector, R: Response<V>> Transition<V> for FirTransition<V, R> {
    fn retarget(&mut self, t: f64, target: V) {
        self.targets.push_back((t, target));
    }

    fn sample(&mut self, t: f64) -> V {
        let d = self.response.duration();
        while let Some(&(ti, u)) = self.targets.front() {
            if ti >= t - d {
                break;
            }
            self.value = u;
            self.targets.pop_front();
        }
        // The settled value passes through the response's steady state S(d) (the identity
        // for every affine response here), then each in-flight step adds its part.
        let mut out = self.response.step_response(d, self.value);
        let mut prev = self.value;
        for &(ti, u) in &self.targets {
            out = out.add(self.response.step_response(t - ti, u.sub(prev)));
            prev = u;
        }
        out
    }

    fn reset(&mut self, x: V) {
        self.value = x;
        self.targets.clear();
    }
}

#[derive(Clone, Debug)]
enum Taps<V> {
    /// One coefficient per tap.
    Scalar(Vec<f64>),
    /// `V::DIM` columns per tap: column `j` of tap `k` is the response to a unit step
    /// in component `j`.
    Matrix(Vec<V>),
}

/// The discrete-time FIR filter of paper Alg. 3, `y[n] = Σₖ h[k]·x[n − k]`, computed
/// from the input's changes: with `S[k] = Σ_{i≤k} h[i]` and `x` changing by `Δ_c` at step
/// `n_c`, `y[n] = S[len − 1]·x_before + Σ_c S[n − n_c]·Δ_c` over the changes still within
/// the window. An input that holds between targets (what the transitions feed it) costs
/// one term per change in flight instead of one per tap: a 60 s arc at 60 fps has 3 600
/// taps, and sliding them over every frame of every channel took 20 s where this takes
/// milliseconds. An input that changes every step costs what the ring buffer did.
#[derive(Clone, Debug)]
pub struct Fir<V> {
    taps: Taps<V>,
    /// `S[k]`, laid out as [`Self::taps`].
    sums: Taps<V>,
    len: usize,
    /// The input before the changes in [`Self::changes`].
    settled: V,
    /// The last input.
    last: V,
    /// The changes within the window, oldest first: the step, the change and the input
    /// after it.
    changes: VecDeque<(u64, V, V)>,
    /// Steps taken.
    now: u64,
}

/// Running sums of taps laid out as [`Taps`]: `V::DIM` columns per tap for matrices.
fn running_sums<V: Vector>(taps: &Taps<V>) -> Taps<V> {
    match taps {
        Taps::Scalar(h) => Taps::Scalar(
            h.iter()
                .scan(0.0, |acc, &x| {
                    *acc += x;
                    Some(*acc)
                })
                .collect(),
        ),
        Taps::Matrix(cols) => {
            let mut sums: Vec<V> = Vec::with_capacity(cols.len());
            for (i, &c) in cols.iter().enumerate() {
                let before = i.checked_sub(V::DIM).map_or(V::zero(), |b| sums[b]);
                sums.push(before.add(c));
            }
            Taps::Matrix(sums)
        }
    }
}

impl<V: Vector> Fir<V> {
    /// A filter with the given scalar taps `h[0..n]` (finite, at least one, at most
    /// [`MAX_TAPS`]). Its rest output for a constant input `x` is `(Σ h)·x`.
    pub fn new(taps: Vec<f64>) -> Result<Fir<V>, SignalError> {
        if taps.is_empty() || taps.len() > MAX_TAPS {
            return Err(SignalError::Invalid(format!(
                "a FIR filter needs between 1 and {MAX_TAPS} taps, got {}",
                taps.len()
            )));
        }
        for &h in &taps {
            finite("FIR tap", h)?;
        }
        Ok(Fir::with_taps(Taps::Scalar(taps)))
    }

    /// At rest on zero.
    fn with_taps(taps: Taps<V>) -> Fir<V> {
        let len = match &taps {
            Taps::Scalar(h) => h.len(),
            Taps::Matrix(cols) => cols.len() / V::DIM,
        };
        Fir {
            sums: running_sums(&taps),
            taps,
            len,
            settled: V::zero(),
            last: V::zero(),
            changes: VecDeque::new(),
            now: 0,
        }
    }

    /// `S[k]·x`.
    fn sum_times(&self, k: usize, x: V) -> V {
        match &self.sums {
            Taps::Scalar(s) => x.scale(s[k]),
            Taps::Matrix(cols) => (0..V::DIM).fold(V::zero(), |out, j| {
                out.add_scaled(cols[k * V::DIM + j], x.get(j))
            }),
        }
    }

    /// Samples a step response at `fps` (impulse invariance for FIR filters, sec. 9):
    /// `h[k] = S(kT) − S((k−1)T)` for `k = 0..=⌈d·fps⌉`, `T = 1/fps`. The taps sum to
    /// `S(d)`, so an affine response gives an affine filter, and a monotone easing gives
    /// non-negative taps (a convex filter). On a step input that changes on frames the
    /// output equals [`FirTransition`] sampled at the frames, to rounding.
    pub fn from_response<R: Response<V>>(response: &R, fps: f64) -> Result<Fir<V>, SignalError> {
        positive("frame rate", fps)?;
        let d = response.duration();
        positive("response duration", d)?;
        let n = (d * fps).ceil();
        if n + 1.0 > MAX_TAPS as f64 {
            return Err(SignalError::Invalid(format!(
                "a {d} s response at {fps} fps needs {} taps, more than the {MAX_TAPS} allowed",
                n + 1.0
            )));
        }
        let n = n as usize;
        let time = |k: usize| k as f64 / fps;
        let len = n + 1;
        if response.scalar_at(0.0).is_some() {
            let s = |k: usize| response.scalar_at(time(k)).unwrap_or(0.0);
            let taps = (0..=n)
                .map(|k| s(k) - if k == 0 { 0.0 } else { s(k - 1) })
                .collect();
            return Fir::new(taps);
        }
        let mut cols = Vec::with_capacity(len * V::DIM);
        for k in 0..=n {
            for j in 0..V::DIM {
                let unit = V::from_fn(|i| if i == j { 1.0 } else { 0.0 });
                let now = response.step_response(time(k), unit);
                let before = if k == 0 {
                    V::zero()
                } else {
                    response.step_response(time(k - 1), unit)
                };
                let col = now.sub(before);
                if !col.is_finite() {
                    return Err(SignalError::NotFinite {
                        what: "FIR tap",
                        value: f64::NAN,
                    });
                }
                cols.push(col);
            }
        }
        debug_assert_eq!(cols.len(), len * V::DIM);
        Ok(Fir::with_taps(Taps::Matrix(cols)))
    }

    /// The number of taps.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True for a filter without taps (never: constructors require one).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The scalar taps, if the filter has them.
    pub fn scalar_taps(&self) -> Option<&[f64]> {
        match &self.taps {
            Taps::Scalar(h) => Some(h),
            Taps::Matrix(_) => None,
        }
    }
}

impl<V: Vector> System<V> for Fir<V> {
    fn step(&mut self, u: V) -> V {
        let delta = u.sub(self.last);
        if (0..V::DIM).any(|j| delta.get(j) != 0.0) {
            self.changes.push_back((self.now, delta, u));
            self.last = u;
        }
        // A change `len − 1` steps old has passed every tap: it joins the settled input.
        while let Some(&(at, _, after)) = self.changes.front() {
            if self.now - at < (self.len - 1) as u64 {
                break;
            }
            self.settled = after;
            self.changes.pop_front();
        }
        let mut out = self.sum_times(self.len - 1, self.settled);
        for &(at, delta, _) in &self.changes {
            out = out.add(self.sum_times((self.now - at) as usize, delta));
        }
        self.now += 1;
        out
    }

    fn reset(&mut self, x: V) {
        self.settled = x;
        self.last = x;
        self.changes.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signals::Easing;

    /// `y[n] = Σₖ h[k]·x[n − k]` summed directly, the input zero before it starts.
    fn convolved<V: Vector>(fir: &Fir<V>, input: &[V]) -> Vec<V> {
        (0..input.len())
            .map(|n| {
                (0..fir.len.min(n + 1)).fold(V::zero(), |out, k| {
                    let x = input[n - k];
                    match &fir.taps {
                        Taps::Scalar(h) => out.add_scaled(x, h[k]),
                        Taps::Matrix(cols) => (0..V::DIM)
                            .fold(out, |o, j| o.add_scaled(cols[k * V::DIM + j], x.get(j))),
                    }
                })
            })
            .collect()
    }

    /// Holds, jumps, changes every step and changes closer than the window, as
    /// [`convolved`] sums them, for scalar and matrix taps.
    #[test]
    fn filtering_changes_is_the_convolution() {
        let input: Vec<f64> = (0..120)
            .map(|n| match n {
                0..10 => 0.0,
                10..14 => 5.0,
                14..40 => -3.0 + (n as f64 * 0.7).sin(),
                40..42 => 8.0,
                _ => 2.5,
            })
            .collect();
        let ease = Ease::new(Easing::poles(4).unwrap(), 0.9).unwrap();
        let mut fir: Fir<f64> = Fir::from_response(&ease, 30.0).unwrap();
        let want = convolved(&fir, &input);
        for (n, (&x, y)) in input.iter().zip(want).enumerate() {
            let got = fir.step(x);
            assert!((got - y).abs() < 1e-12, "step {n}: {got} vs {y}");
        }
        let arc = crate::signals::ArcEasing::new(0.8, Easing::Linear, 0.7).unwrap();
        let mut fir: Fir<kurbo::Vec2> = Fir::from_response(&arc, 30.0).unwrap();
        let input: Vec<kurbo::Vec2> = input
            .iter()
            .enumerate()
            .map(|(n, &x)| kurbo::Vec2::new(x, if n % 50 < 25 { 1.0 } else { -x }))
            .collect();
        let want = convolved(&fir, &input);
        for (n, (&x, y)) in input.iter().zip(want).enumerate() {
            let got = fir.step(x);
            assert!((got - y).hypot() < 1e-12, "step {n}: {got:?} vs {y:?}");
        }
        // After a reset to `x` the filter rests on `x` (times the taps' sum).
        fir.reset(kurbo::Vec2::new(1.0, 2.0));
        let rest = fir.step(kurbo::Vec2::new(1.0, 2.0));
        assert!((rest - fir.sum_times(fir.len - 1, kurbo::Vec2::new(1.0, 2.0))).hypot() < 1e-15);
    }

    #[test]
    fn taps_of_linear_easing_are_a_box() {
        let ease = Ease::new(Easing::Linear, 0.5).unwrap();
        let fir: Fir<f64> = Fir::from_response(&ease, 10.0).unwrap();
        let h = fir.scalar_taps().unwrap();
        assert_eq!(h.len(), 6);
        assert_eq!(h[0], 0.0);
        for &v in &h[1..] {
            assert!((v - 0.2).abs() < 1e-15);
        }
    }

    #[test]
    fn continuous_fir_settles_queued_targets() {
        let ease = Ease::new(Easing::Linear, 1.0).unwrap();
        let mut f = FirTransition::new(ease, 0.0);
        f.retarget(0.0, 1.0);
        f.retarget(0.5, 3.0);
        // At t = 1: first step done (1), second half way (+1).
        assert!((f.sample(1.0) - 2.0).abs() < 1e-12);
        assert_eq!(f.in_flight(), 2);
        assert_eq!(f.sample(2.0), 3.0);
        assert_eq!(f.in_flight(), 0);
    }

    #[test]
    fn too_many_taps_is_an_error() {
        let ease = Ease::new(Easing::Linear, 1e6).unwrap();
        assert!(Fir::<f64>::from_response(&ease, 60.0).is_err());
        assert!(Fir::<f64>::new(vec![]).is_err());
        assert!(Fir::<f64>::new(vec![f64::NAN]).is_err());
    }
}
