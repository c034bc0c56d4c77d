//! Biquads in transposed direct form II (paper Alg. 4) and cascades of them (Fig. 2:
//! an order-`n` IIR filter as `⌈n/2⌉` biquads in series).

use super::error::{SignalError, finite};
use super::system::System;
use super::vector::Vector;

/// One second-order section
/// `H(z) = (b₀ + b₁z⁻¹ + b₂z⁻²) / (1 + a₁z⁻¹ + a₂z⁻²)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
}

impl Biquad {
    /// A section with numerator `b = [b₀, b₁, b₂]` and denominator `a = [a₁, a₂]`
    /// (`a₀ = 1`). Rejects non-finite coefficients and poles on or outside the unit circle
    /// (stable iff `|a₂| < 1` and `|a₁| < 1 + a₂`).
    pub fn new(b: [f64; 3], a: [f64; 2]) -> Result<Biquad, SignalError> {
        for v in b.iter().chain(&a) {
            finite("biquad coefficient", *v)?;
        }
        let [a1, a2] = a;
        if a2.abs() >= 1.0 || a1.abs() >= 1.0 + a2 {
            // Report the pole of largest modulus.
            let disc = a1 * a1 - 4.0 * a2;
            let (re, im) = if disc >= 0.0 {
                let r1 = (-a1 + disc.sqrt()) / 2.0;
                let r2 = (-a1 - disc.sqrt()) / 2.0;
                (if r1.abs() >= r2.abs() { r1 } else { r2 }, 0.0)
            } else {
                (-a1 / 2.0, (-disc).sqrt() / 2.0)
            };
            return Err(SignalError::Unstable {
                domain: "discrete-time",
                re,
                im,
                hint: "a biquad needs |a2| < 1 and |a1| < 1 + a2 (poles inside the unit circle)",
            });
        }
        Ok(Biquad { b, a })
    }

    /// `[b₀, b₁, b₂]`.
    pub fn b(&self) -> [f64; 3] {
        self.b
    }

    /// `[a₁, a₂]`.
    pub fn a(&self) -> [f64; 2] {
        self.a
    }

    /// The gain at DC, `H(1) = Σb / (1 + a₁ + a₂)`.
    pub fn dc_gain(&self) -> f64 {
        (self.b[0] + self.b[1] + self.b[2]) / (1.0 + self.a[0] + self.a[1])
    }
}

/// Biquads in series, each run by Alg. 4 (transposed direct form II):
///
/// ```text
/// y  ← s₁ + b₀x
/// s₁ ← s₂ + b₁x − a₁y
/// s₂ ← b₂x − a₂y
/// ```
///
/// Constant cost per sample (5 multiplies per section per component), whatever the
/// input's history — unlike the continuous FIR queue.
#[derive(Clone, Debug)]
pub struct BiquadCascade<V> {
    sections: Vec<Biquad>,
    state: Vec<[V; 2]>,
}

impl<V: Vector> BiquadCascade<V> {
    /// A cascade of at least one section.
    pub fn new(sections: Vec<Biquad>) -> Result<BiquadCascade<V>, SignalError> {
        if sections.is_empty() {
            return Err(SignalError::Invalid(
                "a biquad cascade needs at least one section".into(),
            ));
        }
        let state = vec![[V::zero(); 2]; sections.len()];
        Ok(BiquadCascade { sections, state })
    }

    /// The sections in signal order.
    pub fn sections(&self) -> &[Biquad] {
        &self.sections
    }

    /// The gain at DC (1 for the affine cascades built by [`super::Lti::discretize`]).
    pub fn dc_gain(&self) -> f64 {
        self.sections.iter().map(Biquad::dc_gain).product()
    }
}

impl<V: Vector> System<V> for BiquadCascade<V> {
    fn step(&mut self, x: V) -> V {
        let mut x = x;
        for (q, s) in self.sections.iter().zip(&mut self.state) {
            let [b0, b1, b2] = q.b;
            let [a1, a2] = q.a;
            let y = s[0].add_scaled(x, b0);
            s[0] = s[1].add_scaled(x, b1).add_scaled(y, -a1);
            s[1] = x.scale(b2).add_scaled(y, -a2);
            x = y;
        }
        x
    }

    fn reset(&mut self, x: V) {
        // At rest each section outputs G·(its input); its states follow from Alg. 4 with
        // constant input and output.
        let mut x = x;
        for (q, s) in self.sections.iter().zip(&mut self.state) {
            let y = x.scale(q.dc_gain());
            s[1] = x.scale(q.b[2]).add_scaled(y, -q.a[1]);
            s[0] = s[1].add_scaled(x, q.b[1]).add_scaled(y, -q.a[0]);
            x = y;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_pole_section_matches_its_recurrence() {
        // y[n] = 0.8·y[n−1] + 0.2·x[n]
        let q = Biquad::new([0.2, 0.0, 0.0], [-0.8, 0.0]).unwrap();
        let mut c: BiquadCascade<f64> = BiquadCascade::new(vec![q]).unwrap();
        let mut y = 0.0;
        for _ in 0..20 {
            let want = 0.8 * y + 0.2;
            y = c.step(1.0);
            assert!((y - want).abs() < 1e-15);
        }
    }

    #[test]
    fn reset_is_a_fixed_point() {
        let q1 = Biquad::new([0.1, 0.2, 0.05], [-0.9, 0.25]).unwrap();
        let q2 = Biquad::new([0.0, 0.3, 0.0], [-0.5, 0.0]).unwrap();
        let mut c: BiquadCascade<[f64; 2]> = BiquadCascade::new(vec![q1, q2]).unwrap();
        c.reset([3.0, -1.0]);
        // Each section's DC gain is Σb / (1 + Σa): 0.35 / 0.35 = 1 and 0.3 / 0.5 = 0.6.
        let g = 0.6;
        assert!((c.dc_gain() - g).abs() < 1e-12);
        for _ in 0..5 {
            let y = c.step([3.0, -1.0]);
            assert!((y[0] - 3.0 * g).abs() < 1e-12 && (y[1] + g).abs() < 1e-12);
        }
    }

    #[test]
    fn unstable_sections_are_rejected() {
        assert!(matches!(
            Biquad::new([1.0, 0.0, 0.0], [-2.0, 1.0]),
            Err(SignalError::Unstable { .. })
        ));
        assert!(Biquad::new([1.0, 0.0, 0.0], [-1.1, 0.0]).is_err());
        assert!(Biquad::new([f64::INFINITY, 0.0, 0.0], [0.0, 0.0]).is_err());
    }
}
