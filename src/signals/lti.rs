//! Continuous-time LTI systems by poles and zeros, and their discretisation into
//! cascades of biquads (paper sec. 6 and 9: "design in continuous time, then transform
//! the system into a discretised version").
//!
//! An [`Lti`] is `H(s) = g·Π(s − zᵢ)/Π(s − pᵢ)` with the gain `g` chosen so that
//! `H(0) = 1`: every system here is *affine* (sec. 4: its impulse response integrates to
//! one), so a constant input gives the same constant output.
//!
//! [`Lti::discretize`] maps it to a [`BiquadCascade`] at a frame rate `fps` (`T = 1/fps`)
//! by one of four methods ([`Discretization`]). Each biquad is scaled to unit DC gain.

use super::biquad::{Biquad, BiquadCascade};
use super::complex::Complex;
use super::error::{SignalError, finite, positive, whole};
use super::matrix::Mat;
use super::poly;
use super::spring::Spring;
use super::statespace::{MAX_ORDER, StateSpace};
use super::vector::Vector;

/// How a continuous-time system becomes a discrete-time one (paper sec. 6 and 9).
///
/// Measured against the closed-form spring at 60 fps, for `duration ∈ [0.2, 2] s` and
/// `bounce ∈ [−0.5, 0.9]`, the largest error of the unit step response over its first
/// five durations is (see `tests/engine/signals.rs`, which enforces these bounds):
///
/// | method | error bound |
/// |---|---|
/// | [`ZeroOrderHold`](Discretization::ZeroOrderHold) | 1e-9 (exact up to rounding) |
/// | [`ImpulseInvariant`](Discretization::ImpulseInvariant) | 0.08 |
/// | [`Bilinear`](Discretization::Bilinear) | 0.06 |
/// | [`Matched`](Discretization::Matched) | 0.06 |
///
/// The errors of the last three are about half a frame of time shift; they shrink
/// linearly with the frame period.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Discretization {
    /// Zero-order hold (step invariance): exact for inputs held over each frame, which
    /// sampled animation channels are. `A_d = e^{AT}`, `B_d = ∫₀ᵀe^{Aτ}dτ·B`.
    #[default]
    ZeroOrderHold,
    /// Impulse invariance: `h[n] = T·h(nT)` (with `h[0] = T·h(0)/2` when the impulse
    /// response jumps at 0), then scaled to unit DC gain. Poles map by `z = e^{pT}`.
    ImpulseInvariant,
    /// The bilinear transform (Tustin): `s = (2/T)(z − 1)/(z + 1)`, so
    /// `z = (1 + pT/2)/(1 − pT/2)`; zeros at infinity map to `z = −1`. No aliasing, but
    /// frequencies are warped. DC gain is preserved exactly.
    Bilinear,
    /// The matched z-transform: poles and finite zeros map by `z = e^{sT}`; of the zeros
    /// at infinity one becomes a one-frame delay and the rest go to `z = −1` (the
    /// "modified" matched transform, so the output, like the continuous one, does not
    /// jump on the frame of a step). Gain set for unit DC gain.
    Matched,
}

/// A stable, affine, strictly proper continuous-time system given by its poles and
/// zeros (conjugate-closed sets), with the gain fixed by `H(0) = 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct Lti {
    zeros: Vec<Complex>,
    poles: Vec<Complex>,
}

impl Lti {
    /// Builds a system from its zeros and poles. Rejects: no poles or more than 16;
    /// non-finite values; poles with `Re p ≥ 0` (unstable or never settling); as many
    /// zeros as poles (the output would jump with the input); a zero at `s = 0` (the DC
    /// gain would be 0, so it cannot be affine); complex values without their conjugate.
    pub fn new(zeros: Vec<Complex>, poles: Vec<Complex>) -> Result<Lti, SignalError> {
        if poles.is_empty() || poles.len() > MAX_ORDER {
            return Err(SignalError::Invalid(format!(
                "a system needs 1 to {MAX_ORDER} poles, got {}",
                poles.len()
            )));
        }
        if zeros.len() >= poles.len() {
            return Err(SignalError::Invalid(format!(
                "a system needs more poles than zeros (strictly proper), got {} zeros and {} poles",
                zeros.len(),
                poles.len()
            )));
        }
        for z in zeros.iter().chain(&poles) {
            finite("pole or zero (real part)", z.re)?;
            finite("pole or zero (imaginary part)", z.im)?;
        }
        for p in &poles {
            if p.re >= 0.0 {
                return Err(SignalError::Unstable {
                    domain: "continuous-time",
                    re: p.re,
                    im: p.im,
                    hint: "every pole needs a negative real part",
                });
            }
        }
        if let Some(z) = zeros.iter().find(|z| z.abs() < 1e-12) {
            return Err(SignalError::Invalid(format!(
                "zero {z} at s = 0 makes the DC gain 0, so the system cannot be affine"
            )));
        }
        let zeros = conjugate_closed(zeros, "zeros")?;
        let poles = conjugate_closed(poles, "poles")?;
        Ok(Lti { zeros, poles })
    }

    /// The spring–mass–damper `m·ÿ = k(u − y) − c·ẏ`: `H(s) = (k/m)/(s² + (c/m)s + k/m)`.
    pub fn spring(spring: &Spring) -> Lti {
        let w = spring.natural_frequency();
        let z = spring.damping_ratio();
        let poles = if z < 1.0 {
            let wd = w * (1.0 - z * z).sqrt();
            vec![Complex::new(-z * w, wd), Complex::new(-z * w, -wd)]
        } else {
            let r = (z * z - 1.0).sqrt();
            vec![Complex::real(-w * (z - r)), Complex::real(-w * (z + r))]
        };
        Lti {
            zeros: Vec::new(),
            poles,
        }
    }

    /// `n` one-pole low-pass filters `ẋ = (u − x)/τ` in series (sec. 8.2): an `n`-fold
    /// pole at `−1/τ`; `n ∈ 1..=16`, `tau > 0` seconds.
    pub fn lowpass(n: u32, tau: f64) -> Result<Lti, SignalError> {
        let n = whole(
            "number of poles",
            f64::from(n),
            1,
            MAX_ORDER as u32,
            "1..=16",
        )?;
        positive("low-pass time constant", tau)?;
        Ok(Lti {
            zeros: Vec::new(),
            poles: vec![Complex::real(-1.0 / tau); n as usize],
        })
    }

    /// The system that spline transitions of duration `d` tend to under continual
    /// retargeting (sec. 3): `ÿ = (6(u − y) − 4d·ẏ)/d²`, poles `(−2 ± i√2)/d`
    /// (damping ratio `√(2/3) ≈ 0.816`: it overshoots very slightly).
    pub fn spline_limit(duration: f64) -> Result<Lti, SignalError> {
        let d = positive("spline duration", duration)?;
        let (re, im) = (-2.0 / d, 2f64.sqrt() / d);
        Ok(Lti {
            zeros: Vec::new(),
            poles: vec![Complex::new(re, im), Complex::new(re, -im)],
        })
    }

    /// The poles and zeros of a state-space system (eigenvalues of `A`; roots of the
    /// transfer function's numerator). The system must be affine (DC gain 1 within
    /// 1e-6) — scale `C` and `D` otherwise.
    pub fn from_state_space(ss: &StateSpace) -> Result<Lti, SignalError> {
        let dc = ss.dc_gain();
        if (dc - 1.0).abs() > 1e-6 || dc.is_nan() {
            return Err(SignalError::Invalid(format!(
                "the state-space system has DC gain {dc}, not 1: a constant input would not give the same constant output"
            )));
        }
        let (num, _) = ss.transfer_function();
        Lti::new(poly::roots(&num), ss.poles())
    }

    /// The poles.
    pub fn poles(&self) -> &[Complex] {
        &self.poles
    }

    /// The finite zeros.
    pub fn zeros(&self) -> &[Complex] {
        &self.zeros
    }

    /// The slowest time constant `1 / min |Re p|` in seconds (how long the system takes
    /// to forget, to within a factor `e`).
    pub fn time_constant(&self) -> f64 {
        1.0 / self
            .poles
            .iter()
            .map(|p| -p.re)
            .fold(f64::INFINITY, f64::min)
    }

    /// A state-space realisation: first- and second-order sections in series, each a
    /// controllable canonical form with unit DC gain (keeps the matrix entries on the
    /// scale of each section's own poles).
    pub fn state_space(&self) -> StateSpace {
        let mut acc: Option<StateSpace> = None;
        for (poles, zeros) in sections(&self.poles, &self.zeros) {
            let den = poly::from_roots(&poles);
            let mut num = poly::from_roots(&zeros);
            let k = den[0] / num[0];
            num.iter_mut().for_each(|v| *v *= k);
            let p = poles.len();
            let d = if zeros.len() == p { num[p] } else { 0.0 };
            let mut a = Mat::zeros(p, p);
            for i in 0..p - 1 {
                a[(i, i + 1)] = 1.0;
            }
            for j in 0..p {
                a[(p - 1, j)] = -den[j];
            }
            let b: Vec<f64> = (0..p).map(|i| if i == p - 1 { 1.0 } else { 0.0 }).collect();
            let c: Vec<f64> = (0..p)
                .map(|i| num.get(i).copied().unwrap_or(0.0) - d * den[i])
                .collect();
            let section = StateSpace { a, b, c, d };
            acc = Some(match acc {
                None => section,
                Some(prev) => series(&prev, &section),
            });
        }
        acc.expect("an Lti has at least one pole")
    }

    /// The exact unit step response at `t` (from rest at 0).
    pub fn step_response(&self, t: f64) -> f64 {
        self.state_space().step_response(t)
    }

    /// The discrete-time system at `fps` frames per second, as biquads in series. Fails
    /// when a discrete pole is not strictly inside the unit circle (which the four
    /// methods only produce from numerically marginal systems, e.g. a time constant of
    /// 10¹⁵ frames).
    pub fn discretize<V: Vector>(
        &self,
        method: Discretization,
        fps: f64,
    ) -> Result<BiquadCascade<V>, SignalError> {
        positive("frame rate", fps)?;
        let t = 1.0 / fps;
        let relative_degree = self.poles.len() - self.zeros.len();
        let (poles, zeros): (Vec<Complex>, Vec<Complex>) = match method {
            Discretization::Bilinear => {
                let map = |s: &Complex| {
                    (Complex::real(1.0) + *s * (t / 2.0)) / (Complex::real(1.0) - *s * (t / 2.0))
                };
                let mut zeros: Vec<Complex> = self.zeros.iter().map(map).collect();
                zeros.extend(std::iter::repeat_n(Complex::real(-1.0), relative_degree));
                (self.poles.iter().map(map).collect(), zeros)
            }
            Discretization::Matched => {
                let mut zeros: Vec<Complex> = self.zeros.iter().map(|z| (*z * t).exp()).collect();
                zeros.extend(std::iter::repeat_n(
                    Complex::real(-1.0),
                    relative_degree - 1,
                ));
                (self.poles.iter().map(|p| (*p * t).exp()).collect(), zeros)
            }
            Discretization::ZeroOrderHold | Discretization::ImpulseInvariant => {
                let ss = self.state_space();
                let (ad, gamma) = ss.exp_pair(t);
                let (bd, cd, dd) = if method == Discretization::ZeroOrderHold {
                    (gamma, ss.c.clone(), ss.d)
                } else {
                    // h[n] = T·C·e^{AnT}·B: state x[n+1] = A_d x[n] + A_d B u[n], output
                    // T·C·x[n] + (T/2)·C·B·u[n] (the half-sample term at the jump).
                    let adb: Vec<f64> = (0..ss.order())
                        .map(|i| (0..ss.order()).map(|j| ad[(i, j)] * ss.b[j]).sum())
                        .collect();
                    let cb: f64 = ss.c.iter().zip(&ss.b).map(|(c, b)| c * b).sum();
                    (adb, ss.c.iter().map(|c| c * t).collect(), t * cb / 2.0)
                };
                let num = numerator(&ad, &bd, &cd, dd, &self.poles, t);
                (
                    self.poles.iter().map(|p| (*p * t).exp()).collect(),
                    poly::roots(&num),
                )
            }
        };
        let mut biquads = Vec::new();
        for (p, z) in sections(&poles, &zeros) {
            for q in &p {
                if q.abs() >= 1.0 || q.abs().is_nan() {
                    return Err(SignalError::Unstable {
                        domain: "discrete-time",
                        re: q.re,
                        im: q.im,
                        hint: "the discretised pole is not inside the unit circle; use a faster system",
                    });
                }
            }
            biquads.push(section_biquad(&p, &z)?);
        }
        BiquadCascade::new(biquads)
    }
}

/// Checks that complex entries come in conjugate pairs (within 1e-9 relative) and
/// returns the set with exact conjugates and exactly real reals.
fn conjugate_closed(values: Vec<Complex>, what: &str) -> Result<Vec<Complex>, SignalError> {
    let tol = |z: Complex| 1e-9 * (1.0 + z.abs());
    let mut out = Vec::with_capacity(values.len());
    let mut pending: Vec<Complex> = Vec::new();
    for z in values {
        if z.im.abs() <= tol(z) {
            out.push(Complex::real(z.re));
        } else if let Some(i) = pending.iter().position(|w| (w.conj() - z).abs() <= tol(z)) {
            let w = pending.swap_remove(i);
            let upper = if w.im > 0.0 { w } else { w.conj() };
            out.push(upper);
            out.push(upper.conj());
        } else {
            pending.push(z);
        }
    }
    if let Some(z) = pending.first() {
        return Err(SignalError::Invalid(format!(
            "{what} must come in conjugate pairs for a real system; {z} has no conjugate"
        )));
    }
    Ok(out)
}

/// Groups poles into sections of one or two (conjugate pairs together, reals two by two,
/// slowest first) and hands each section the zeros nearest its poles, at most as many as
/// it has poles.
fn sections(poles: &[Complex], zeros: &[Complex]) -> Vec<(Vec<Complex>, Vec<Complex>)> {
    let mut out: Vec<(Vec<Complex>, Vec<Complex>)> = Vec::new();
    let mut reals: Vec<Complex> = Vec::new();
    for p in poles {
        if p.im > 0.0 {
            out.push((vec![*p, p.conj()], Vec::new()));
        } else if p.im == 0.0 {
            reals.push(*p);
        }
    }
    // Slowest (largest real part, or largest modulus for discrete poles) first.
    reals.sort_by(|a, b| b.re.total_cmp(&a.re));
    for pair in reals.chunks(2) {
        out.push((pair.to_vec(), Vec::new()));
    }
    let nearest = |out: &Vec<(Vec<Complex>, Vec<Complex>)>, z: Complex, need: usize| {
        out.iter()
            .enumerate()
            .filter(|(_, (p, zs))| p.len() - zs.len() >= need)
            .map(|(i, (p, _))| {
                (
                    i,
                    p.iter()
                        .map(|q| (*q - z).abs())
                        .fold(f64::INFINITY, f64::min),
                )
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    };
    let mut real_zeros: Vec<Complex> = Vec::new();
    for z in zeros {
        if z.im > 0.0 {
            if let Some(i) = nearest(&out, *z, 2) {
                out[i].1.extend([*z, z.conj()]);
            }
        } else if z.im == 0.0 {
            real_zeros.push(*z);
        }
    }
    for z in real_zeros {
        if let Some(i) = nearest(&out, z, 1) {
            out[i].1.push(z);
        }
    }
    out
}

/// The biquad `z^{Z−P}·Π(1 − zᵢz⁻¹)/Π(1 − pᵢz⁻¹)` scaled to unit DC gain.
fn section_biquad(poles: &[Complex], zeros: &[Complex]) -> Result<Biquad, SignalError> {
    // Polynomials in z⁻¹: Π(1 − r z⁻¹) has the reversed coefficients of Π(z − r).
    let rev = |roots: &[Complex]| {
        let mut c = poly::from_roots(roots);
        c.reverse();
        c
    };
    let den = rev(poles);
    let num = rev(zeros);
    let delay = poles.len() - zeros.len();
    let mut b = [0.0; 3];
    for (i, v) in num.iter().enumerate() {
        b[i + delay] = *v;
    }
    let a = [
        den.get(1).copied().unwrap_or(0.0),
        den.get(2).copied().unwrap_or(0.0),
    ];
    let sum_b: f64 = b.iter().sum();
    if sum_b.abs() < 1e-300 {
        return Err(SignalError::Invalid(
            "a discretised section has a zero at z = 1 (DC gain 0)".into(),
        ));
    }
    let g = (1.0 + a[0] + a[1]) / sum_b;
    Biquad::new(b.map(|v| v * g), a)
}

/// The numerator of `H(z) = C_d(zI − A_d)⁻¹B_d + D_d` over the known denominator
/// `Π(z − e^{pT})`, by evaluating `H` at the `(n+1)`-th roots of unity (where the
/// resolvent is well conditioned: every pole is inside the circle) and interpolating.
fn numerator(ad: &Mat, bd: &[f64], cd: &[f64], dd: f64, poles: &[Complex], t: f64) -> Vec<f64> {
    let n = bd.len();
    let m = n + 1;
    let zpoles: Vec<Complex> = poles.iter().map(|p| (*p * t).exp()).collect();
    let values: Vec<Complex> = (0..m)
        .map(|k| {
            let ang = std::f64::consts::TAU * k as f64 / m as f64;
            let z = Complex::new(ang.cos(), ang.sin());
            // (zI − A_d)x = B_d as a real 2n×2n system [[Re, −Im], [Im, Re]].
            let mut big = Mat::zeros(2 * n, 2 * n);
            for i in 0..n {
                for j in 0..n {
                    let re = if i == j { z.re } else { 0.0 } - ad[(i, j)];
                    let im = if i == j { z.im } else { 0.0 };
                    big[(i, j)] = re;
                    big[(i, j + n)] = -im;
                    big[(i + n, j)] = im;
                    big[(i + n, j + n)] = re;
                }
            }
            let mut rhs = Mat::zeros(2 * n, 1);
            for i in 0..n {
                rhs[(i, 0)] = bd[i];
            }
            let x = big
                .solve(&rhs)
                .map(|x| x.data)
                .unwrap_or_else(|| vec![0.0; 2 * n]);
            let h = (0..n).fold(Complex::real(dd), |acc, i| {
                acc + Complex::new(cd[i] * x[i], cd[i] * x[i + n])
            });
            let den = zpoles
                .iter()
                .fold(Complex::real(1.0), |acc, p| acc * (z - *p));
            h * den
        })
        .collect();
    (0..m)
        .map(|j| {
            let sum = values
                .iter()
                .enumerate()
                .fold(Complex::default(), |acc, (k, v)| {
                    let ang = -std::f64::consts::TAU * (j * k) as f64 / m as f64;
                    acc + *v * Complex::new(ang.cos(), ang.sin())
                });
            sum.re / m as f64
        })
        .collect()
}

/// `second ∘ first`: `first`'s output drives `second`.
fn series(first: &StateSpace, second: &StateSpace) -> StateSpace {
    let (n1, n2) = (first.order(), second.order());
    let mut a = Mat::zeros(n1 + n2, n1 + n2);
    for i in 0..n1 {
        for j in 0..n1 {
            a[(i, j)] = first.a[(i, j)];
        }
    }
    for i in 0..n2 {
        for j in 0..n2 {
            a[(n1 + i, n1 + j)] = second.a[(i, j)];
        }
        for j in 0..n1 {
            a[(n1 + i, j)] = second.b[i] * first.c[j];
        }
    }
    let b = first
        .b
        .iter()
        .copied()
        .chain(second.b.iter().map(|b| b * first.d))
        .collect();
    let c = first
        .c
        .iter()
        .map(|c| c * second.d)
        .chain(second.c.iter().copied())
        .collect();
    StateSpace {
        a,
        b,
        c,
        d: first.d * second.d,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signals::System;

    fn run(mut sys: BiquadCascade<f64>, frames: usize) -> Vec<f64> {
        sys.reset(0.0);
        (0..frames).map(|_| sys.step(1.0)).collect()
    }

    #[test]
    fn lowpass_zoh_matches_erlang_cdf() {
        let lti = Lti::lowpass(4, 0.05).unwrap();
        let y = run(
            lti.discretize(Discretization::ZeroOrderHold, 60.0).unwrap(),
            60,
        );
        for (n, v) in y.iter().enumerate() {
            let x = n as f64 / 60.0 / 0.05;
            let want = 1.0 - (-x).exp() * (1.0 + x + x * x / 2.0 + x * x * x / 6.0);
            assert!((v - want).abs() < 1e-10, "frame {n}: {v} vs {want}");
        }
    }

    #[test]
    fn every_method_is_affine_and_stable() {
        let spring = Spring::from_duration_bounce(0.5, 0.3).unwrap();
        for lti in [
            Lti::spring(&spring),
            Lti::lowpass(3, 0.1).unwrap(),
            Lti::spline_limit(0.4).unwrap(),
        ] {
            for m in [
                Discretization::ZeroOrderHold,
                Discretization::ImpulseInvariant,
                Discretization::Bilinear,
                Discretization::Matched,
            ] {
                let c: BiquadCascade<f64> = lti.discretize(m, 60.0).unwrap();
                assert!((c.dc_gain() - 1.0).abs() < 1e-12, "{m:?}");
                let y = run(c, 600);
                assert!((y[599] - 1.0).abs() < 1e-6, "{m:?} ends at {}", y[599]);
            }
        }
    }

    #[test]
    fn state_space_realisation_keeps_the_response() {
        let spring = Spring::from_duration_bounce(0.7, -0.3).unwrap();
        let lti = Lti::spring(&spring);
        for t in [0.1, 0.4, 1.3] {
            assert!((lti.step_response(t) - spring.step_state(t).0).abs() < 1e-12);
        }
        let back = Lti::from_state_space(&StateSpace::spring(&spring)).unwrap();
        let mut p: Vec<f64> = back.poles().iter().map(|p| p.re).collect();
        p.sort_by(f64::total_cmp);
        let mut q: Vec<f64> = lti.poles().iter().map(|p| p.re).collect();
        q.sort_by(f64::total_cmp);
        for (a, b) in p.iter().zip(&q) {
            assert!((a - b).abs() < 1e-8 * b.abs());
        }
    }

    #[test]
    fn invalid_systems_are_rejected() {
        assert!(matches!(
            Lti::new(vec![], vec![Complex::real(0.5)]),
            Err(SignalError::Unstable { .. })
        ));
        assert!(Lti::new(vec![], vec![Complex::new(-1.0, 2.0)]).is_err());
        assert!(Lti::new(vec![Complex::real(-1.0)], vec![Complex::real(-2.0)]).is_err());
        assert!(
            Lti::new(
                vec![Complex::real(0.0)],
                vec![Complex::real(-2.0), Complex::real(-3.0)]
            )
            .is_err()
        );
        assert!(Lti::lowpass(0, 0.1).is_err());
        assert!(Lti::lowpass(2, -0.1).is_err());
        assert!(Lti::spline_limit(f64::NAN).is_err());
        let tiny = Lti::lowpass(1, 1e300).unwrap();
        assert!(
            tiny.discretize::<f64>(Discretization::ZeroOrderHold, 60.0)
                .is_err()
        );
    }
}
