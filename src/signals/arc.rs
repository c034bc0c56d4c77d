//! Constant-speed elliptical arcs as a matrix easing (paper sec. 8.2).
//!
//! An item on a line moving by `Δ` follows the half ellipse
//! `x(θ) = ½·[cos θ + 1, α·sin θ]`, `θ: π → 2π`, scaled by `Δ`: it leaves sideways,
//! arcs over (items moving in opposite directions arc on opposite sides, so they do not
//! collide) and lands. To move at constant speed whatever the aspect `α`, `θ` is found
//! from the fraction of arc length travelled,
//!
//! `σ(θ) = s(π, θ)/s(π, 2π)`, `s(θ₁, θ₂) = (α/2)·(E(θ₂|m) − E(θ₁|m))`, `m = 1 − 1/α²`,
//!
//! where `E(φ|m) = ∫₀^φ √(1 − m·sin²ϑ) dϑ` is the incomplete elliptic integral of the
//! second kind (evaluated with Carlson's symmetric integrals `R_F`, `R_D`), inverted
//! numerically (Newton's method safeguarded by bisection). An inner scalar easing `g`
//! (the paper suggests a four-pole cascade) makes the speed start and end at zero:
//! the step response is `x(σ⁻¹(g(t/d)))`.
//!
//! Because the response is linear in `Δ`, it is an LTI FIR system with a 2×2
//! lower-triangular matrix easing `[[eₓ, 0], [e_y, eₓ]]`: a step `(Δx, Δy)` gives
//! `(Δx·eₓ, Δy·eₓ + Δx·e_y)`.

use super::easing::Easing;
use super::error::{SignalError, finite, positive};
use super::fir::Response;
use super::vector::Vector;

use std::f64::consts::{FRAC_PI_2, PI};

/// The elliptical-arc matrix easing of sec. 8.2.
#[derive(Clone, Debug, PartialEq)]
pub struct ArcEasing {
    aspect: f64,
    inner: Easing,
    duration: f64,
    /// `m = 1 − 1/α²`.
    m: f64,
    /// `E(π|m) = 2·E(m)`: the normalising arc length (over `α/2`).
    half_turn: f64,
}

impl ArcEasing {
    /// An arc of aspect `aspect` (height over half the distance travelled: 1 is a
    /// semicircle, 0 a straight line, negative values arc the other way), with progress
    /// eased by `inner` over `duration` seconds.
    pub fn new(aspect: f64, inner: Easing, duration: f64) -> Result<ArcEasing, SignalError> {
        finite("arc aspect", aspect)?;
        positive("arc duration", duration)?;
        if aspect != 0.0 && !(1e-3..=1e3).contains(&aspect.abs()) {
            return Err(SignalError::OutOfRange {
                what: "arc aspect",
                range: "0 or 1e-3 ≤ |aspect| ≤ 1e3",
                value: aspect,
            });
        }
        let a = aspect.abs();
        let m = if a > 0.0 {
            1.0 - 1.0 / (a * a)
        } else {
            f64::NEG_INFINITY
        };
        let half_turn = if a > 0.0 {
            2.0 * elliptic_e(FRAC_PI_2, m)
        } else {
            0.0
        };
        Ok(ArcEasing {
            aspect,
            inner,
            duration,
            m,
            half_turn,
        })
    }

    /// The aspect `α`.
    pub fn aspect(&self) -> f64 {
        self.aspect
    }

    /// The point `(eₓ, e_y)` of the unit arc (from `(0, 0)` to `(1, 0)`) at linear
    /// progress `u ∈ [0, 1]`, after the inner easing.
    pub fn point(&self, u: f64) -> [f64; 2] {
        let g = self.inner.apply(u);
        if g <= 0.0 {
            return [0.0, 0.0];
        }
        if g >= 1.0 {
            return [1.0, 0.0];
        }
        if self.aspect == 0.0 {
            // A straight line at constant speed.
            return [g, 0.0];
        }
        let psi = self.inverse_sigma(g);
        let theta = PI + psi;
        [0.5 * (theta.cos() + 1.0), 0.5 * self.aspect * theta.sin()]
    }

    /// The fraction of arc length travelled at `ψ = θ − π ∈ [0, π]`. Since `sin²` has
    /// period π, `E(θ) − E(π) = E(ψ)`.
    fn sigma(&self, psi: f64) -> f64 {
        let e = if psi <= FRAC_PI_2 {
            elliptic_e(psi, self.m)
        } else {
            self.half_turn - elliptic_e(PI - psi, self.m)
        };
        e / self.half_turn
    }

    /// `σ⁻¹`: Newton steps from the circular guess, kept inside a bisection bracket.
    fn inverse_sigma(&self, s: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, PI);
        let mut psi = PI * s;
        for _ in 0..60 {
            let f = self.sigma(psi) - s;
            if f.abs() < 1e-14 {
                break;
            }
            if f > 0.0 {
                hi = psi;
            } else {
                lo = psi;
            }
            let slope = (1.0 - self.m * psi.sin().powi(2)).sqrt() / self.half_turn;
            let next = psi - f / slope;
            psi = if next > lo && next < hi {
                next
            } else {
                0.5 * (lo + hi)
            };
        }
        psi
    }
}

impl<V: Vector> Response<V> for ArcEasing {
    fn duration(&self) -> f64 {
        self.duration
    }

    fn step_response(&self, t: f64, delta: V) -> V {
        let [ex, ey] = if t <= 0.0 {
            [0.0, 0.0]
        } else if t >= self.duration {
            [1.0, 0.0]
        } else {
            self.point(t / self.duration)
        };
        let dx = delta.get(0);
        V::from_fn(|i| delta.get(i) * ex + if i == 1 { dx * ey } else { 0.0 })
    }
}

/// Incomplete elliptic integral of the second kind `E(φ|m)` for `φ ∈ [0, π/2]` and
/// `m < 1` (any negative `m`): `E = sin φ·R_F(c², q, 1) − (m/3)·sin³φ·R_D(c², q, 1)`
/// with `c = cos φ`, `q = 1 − m·sin²φ` (Carlson 1995, eq. 4.6 of DLMF 19.25.9).
pub fn elliptic_e(phi: f64, m: f64) -> f64 {
    let (s, c) = phi.sin_cos();
    let q = 1.0 - m * s * s;
    s * carlson_rf(c * c, q, 1.0) - m / 3.0 * s * s * s * carlson_rd(c * c, q, 1.0)
}

/// Carlson's `R_F(x, y, z)` by the duplication theorem.
fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    let (mut x, mut y, mut z) = (x, y, z);
    // Each step shrinks the spread by 4; the cap only guards against NaN inputs.
    for _ in 0..100 {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lam = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
        let a = (x + y + z) / 3.0;
        let (dx, dy, dz) = ((a - x) / a, (a - y) / a, (a - z) / a);
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-4 {
            let e2 = dx * dy - dz * dz;
            let e3 = dx * dy * dz;
            return (1.0 + (e2 / 24.0 - 0.1 - 3.0 / 44.0 * e3) * e2 + e3 / 14.0) / a.sqrt();
        }
    }
    f64::NAN
}

/// Carlson's `R_D(x, y, z)` by the duplication theorem.
fn carlson_rd(x: f64, y: f64, z: f64) -> f64 {
    let (mut x, mut y, mut z) = (x, y, z);
    let (mut sum, mut fac) = (0.0, 1.0);
    // Each step shrinks the spread by 4; the cap only guards against NaN inputs.
    for _ in 0..100 {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lam = sx * (sy + sz) + sy * sz;
        sum += fac / (sz * (z + lam));
        fac *= 0.25;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
        let a = 0.2 * (x + y + 3.0 * z);
        let (dx, dy, dz) = ((a - x) / a, (a - y) / a, (a - z) / a);
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-4 {
            let (c1, c2, c3, c4) = (3.0 / 14.0, 1.0 / 6.0, 9.0 / 22.0, 3.0 / 26.0);
            let (c5, c6) = (0.25 * c3, 1.5 * c4);
            let ea = dx * dy;
            let eb = dz * dz;
            let ec = ea - eb;
            let ed = ea - 6.0 * eb;
            let ee = ed + ec + ec;
            let series = 1.0
                + ed * (-c1 + c5 * ed - c6 * dz * ee)
                + dz * (c2 * ee + dz * (-c3 * ec + dz * c4 * ea));
            return 3.0 * sum + fac * series / (a * a.sqrt());
        }
    }
    f64::NAN
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Composite Simpson quadrature, the independent reference.
    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let mut s = f(a) + f(b);
        for i in 1..n {
            s += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    }

    #[test]
    fn elliptic_e_matches_quadrature() {
        for m in [-15.0, -1.0, 0.0, 0.3, 0.9, 0.999] {
            for phi in [0.1, 0.7, FRAC_PI_2] {
                let want = simpson(|t: f64| (1.0 - m * t.sin().powi(2)).sqrt(), 0.0, phi, 2000);
                assert!((elliptic_e(phi, m) - want).abs() < 1e-10, "m={m} phi={phi}");
            }
        }
        // A tabulated value: E(0.5) = 1.3506438810476755 (complete, parameter m = 0.5).
        assert!((elliptic_e(FRAC_PI_2, 0.5) - 1.350_643_881_047_675_5).abs() < 1e-14);
    }

    #[test]
    fn arc_moves_at_constant_speed() {
        for aspect in [0.3, 1.0, 2.5] {
            let arc = ArcEasing::new(aspect, Easing::Linear, 1.0).unwrap();
            let n = 400;
            let pts: Vec<[f64; 2]> = (0..=n).map(|i| arc.point(i as f64 / n as f64)).collect();
            let steps: Vec<f64> = pts
                .windows(2)
                .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
                .collect();
            let mean = steps.iter().sum::<f64>() / n as f64;
            for s in &steps {
                assert!(
                    (s / mean - 1.0).abs() < 1e-3,
                    "aspect {aspect}: step {s} vs mean {mean}"
                );
            }
            assert_eq!(arc.point(0.0), [0.0, 0.0]);
            let end = arc.point(1.0);
            assert!((end[0] - 1.0).abs() < 1e-12 && end[1].abs() < 1e-12);
            // Peak height α/2 at the midpoint (moving right arcs towards −y, i.e. up on screen).
            let mid = arc.point(0.5);
            assert!((mid[1] + aspect / 2.0).abs() < 1e-9);
        }
    }

    #[test]
    fn matrix_response_mixes_x_into_y() {
        let arc = ArcEasing::new(1.0, Easing::Linear, 2.0).unwrap();
        let r: [f64; 2] = arc.step_response(1.0, [10.0, 4.0]);
        // Half way on a semicircle of diameter 10: x = 5, y = −5 (+ half the Δy).
        assert!((r[0] - 5.0).abs() < 1e-9 && (r[1] - (-5.0 + 2.0)).abs() < 1e-9);
        let l: [f64; 2] = arc.step_response(1.0, [-10.0, 0.0]);
        assert!((l[1] - 5.0).abs() < 1e-9, "moving left arcs the other way");
    }
}
