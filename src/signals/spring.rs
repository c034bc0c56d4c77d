//! The spring–mass–damper (paper sec. 6, Fig. 1): `m·ÿ = k·(u − y) − c·ẏ`.
//!
//! Two parameterisations:
//! - physical: mass `m`, stiffness `k`, damping coefficient `c`;
//! - perceptual (SwiftUI `Spring(duration:bounce:)`, Flutter
//!   `SpringDescription.withDurationAndBounce`): `duration` sets the pace, `bounce` the
//!   shape. The conversion, identical in both toolkits, is
//!
//!   ```text
//!   m = 1,   k = (2π / duration)²,   c = 2ζ·√(m·k)
//!   ζ = 1 − bounce        for bounce ≥ 0   (0: critically damped, → 1: undamped)
//!   ζ = 1 / (1 + bounce)  for bounce < 0   (overdamped)
//!   ```
//!
//!   so `duration` is the undamped period `2π/ω₀`, and the inverse is
//!   `duration = 2π·√(m/k)`, `bounce = 1 − ζ` if `ζ < 1` else `1/ζ − 1`.
//!   Here `bounce` must lie in `(−1, 1)`: at 1 the spring never settles, at −1 it never moves.

use super::error::{SignalError, finite, positive};

/// A spring–mass–damper driven by its input position `u`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring {
    mass: f64,
    stiffness: f64,
    damping: f64,
}

impl Spring {
    /// The physical parameterisation. All three must be finite and `> 0` (zero damping
    /// oscillates forever, so it is rejected too).
    pub fn new(mass: f64, stiffness: f64, damping: f64) -> Result<Spring, SignalError> {
        positive("spring mass", mass)?;
        positive("spring stiffness", stiffness)?;
        positive("spring damping", damping)?;
        Ok(Spring {
            mass,
            stiffness,
            damping,
        })
    }

    /// The perceptual parameterisation (see the module docs for the formulas):
    /// `duration > 0` seconds, `bounce ∈ (−1, 1)`.
    pub fn from_duration_bounce(duration: f64, bounce: f64) -> Result<Spring, SignalError> {
        positive("spring duration", duration)?;
        finite("spring bounce", bounce)?;
        if bounce <= -1.0 || bounce >= 1.0 {
            return Err(SignalError::OutOfRange {
                what: "spring bounce",
                range: "(-1, 1)",
                value: bounce,
            });
        }
        let stiffness = (std::f64::consts::TAU / duration).powi(2);
        let zeta = if bounce >= 0.0 {
            1.0 - bounce
        } else {
            1.0 / (1.0 + bounce)
        };
        Spring::new(1.0, stiffness, 2.0 * zeta * stiffness.sqrt())
    }

    /// Mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// Stiffness `k`.
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// Damping coefficient `c`.
    pub fn damping(&self) -> f64 {
        self.damping
    }

    /// Undamped natural frequency `ω₀ = √(k/m)` (rad/s).
    pub fn natural_frequency(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }

    /// Damping ratio `ζ = c / (2√(k·m))`.
    pub fn damping_ratio(&self) -> f64 {
        self.damping / (2.0 * (self.stiffness * self.mass).sqrt())
    }

    /// The perceptual duration `2π/ω₀`.
    pub fn duration(&self) -> f64 {
        std::f64::consts::TAU / self.natural_frequency()
    }

    /// The perceptual bounce: `1 − ζ` when underdamped, `1/ζ − 1` otherwise.
    pub fn bounce(&self) -> f64 {
        let z = self.damping_ratio();
        if z < 1.0 { 1.0 - z } else { 1.0 / z - 1.0 }
    }

    /// Closed-form position and velocity at `t` after a unit step of the input at
    /// `t = 0`, starting at rest at 0 (the reference the discretisations are tested
    /// against).
    pub fn step_state(&self, t: f64) -> (f64, f64) {
        if t <= 0.0 {
            return (0.0, 0.0);
        }
        let w = self.natural_frequency();
        let z = self.damping_ratio();
        if (z - 1.0).abs() < 1e-7 {
            let e = (-w * t).exp();
            (1.0 - e * (1.0 + w * t), w * w * t * e)
        } else if z < 1.0 {
            let wd = w * (1.0 - z * z).sqrt();
            let s = z * w;
            let e = (-s * t).exp();
            let (sin, cos) = (wd * t).sin_cos();
            (1.0 - e * (cos + s / wd * sin), e * w * w / wd * sin)
        } else {
            let r = (z * z - 1.0).sqrt();
            let (r1, r2) = (-w * (z + r), -w * (z - r));
            let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
            (
                1.0 + (r2 * e1 - r1 * e2) / (r1 - r2),
                r1 * r2 * (e1 - e2) / (r1 - r2),
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perceptual_parameters_follow_the_published_formula() {
        // SwiftUI's and Flutter's spring: mass 1, stiffness (2π/duration)², damping
        // 4π(1 − bounce)/duration for bounce ≥ 0, 4π/(duration·(1 + bounce)) below.
        let pi = std::f64::consts::PI;
        for (d, b, k, c) in [
            (0.5, 0.3, (4.0 * pi).powi(2), 4.0 * pi * 0.7 / 0.5),
            (1.0, 0.0, (2.0 * pi).powi(2), 4.0 * pi),
            (0.8, -0.5, (2.0 * pi / 0.8).powi(2), 4.0 * pi / (0.8 * 0.5)),
        ] {
            let s = Spring::from_duration_bounce(d, b).unwrap();
            assert!((s.mass() - 1.0).abs() < 1e-12);
            assert!((s.stiffness() - k).abs() < 1e-9 * k, "{d} {b}");
            assert!((s.damping() - c).abs() < 1e-9 * c, "{d} {b}");
        }
    }

    #[test]
    fn perceptual_round_trip() {
        for (d, b) in [(0.5, 0.0), (0.8, 0.3), (1.2, -0.4), (0.3, 0.95)] {
            let s = Spring::from_duration_bounce(d, b).unwrap();
            assert!((s.duration() - d).abs() < 1e-12);
            assert!((s.bounce() - b).abs() < 1e-12);
        }
    }

    #[test]
    fn invalid_parameters_are_rejected() {
        assert!(matches!(
            Spring::new(-1.0, 1.0, 1.0),
            Err(SignalError::NotPositive { .. })
        ));
        assert!(Spring::new(1.0, 0.0, 1.0).is_err());
        assert!(Spring::new(1.0, 1.0, f64::NAN).is_err());
        assert!(Spring::from_duration_bounce(0.0, 0.0).is_err());
        assert!(Spring::from_duration_bounce(0.5, 1.0).is_err());
        assert!(Spring::from_duration_bounce(0.5, -1.0).is_err());
        let msg = Spring::from_duration_bounce(0.5, 1.5)
            .unwrap_err()
            .to_string();
        assert!(msg.contains("bounce") && msg.contains("(-1, 1)"), "{msg}");
    }

    #[test]
    fn closed_form_satisfies_the_ode() {
        for (d, b) in [(0.5, 0.0), (0.5, 0.4), (0.5, -0.5)] {
            let s = Spring::from_duration_bounce(d, b).unwrap();
            let (m, k, c) = (s.mass(), s.stiffness(), s.damping());
            let h = 1e-5;
            for t in [0.05, 0.2, 0.7] {
                let (y, v) = s.step_state(t);
                let (_, vp) = s.step_state(t + h);
                let (_, vm) = s.step_state(t - h);
                let acc = (vp - vm) / (2.0 * h);
                assert!((m * acc - (k * (1.0 - y) - c * v)).abs() < 1e-4 * k);
            }
        }
    }
}
