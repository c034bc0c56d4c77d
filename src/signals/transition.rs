//! Event-driven transitions in continuous time: the simple transition algorithm
//! (paper Alg. 1, the baseline) and spline transitions (sec. 3). The FIR transition of
//! Alg. 2 lives in [`super::fir`]; all three implement [`Transition`].

use super::easing::Ease;
use super::error::{SignalError, positive};
use super::vector::Vector;

/// A transition driven by target changes at arbitrary instants.
///
/// Calls must come in non-decreasing time order: `retarget(t, u)` says the input
/// (target) signal steps to `u` at time `t`; `sample(t)` gives the output at `t`.
pub trait Transition<V: Vector> {
    /// The target changes to `target` at time `t`.
    fn retarget(&mut self, t: f64, target: V);
    /// The output at time `t`.
    fn sample(&mut self, t: f64) -> V;
    /// Forgets all history: at rest on `x`.
    fn reset(&mut self, x: V);
}

/// The simple transition algorithm (paper Alg. 1, eq. 1): on each target change, start a
/// fresh eased transition from the *current output* to the new target, discarding the
/// velocity. With an easing whose derivative vanishes at 0, frequent interruptions make
/// the output stall (Claim 1) and every interruption is a velocity discontinuity.
///
/// (The paper's listing evaluates `f(t − t₀)`; the definition in eq. 1 uses the time of
/// the last change, `f(t − t₁)`, which is what this implements.)
#[derive(Clone, Debug)]
pub struct SimpleTransition<V> {
    ease: Ease,
    /// Time of the last target change.
    t1: f64,
    /// Target at `t1`.
    u1: V,
    /// Output at `t1`.
    x1: V,
}

impl<V: Vector> SimpleTransition<V> {
    /// At rest on `x0`, easing every transition with `ease`.
    pub fn new(ease: Ease, x0: V) -> SimpleTransition<V> {
        SimpleTransition {
            ease,
            t1: f64::NEG_INFINITY,
            u1: x0,
            x1: x0,
        }
    }

    fn output(&self, t: f64) -> V {
        let s = self.ease.at(t - self.t1);
        self.x1.add_scaled(self.u1.sub(self.x1), s)
    }
}

impl<V: Vector> Transition<V> for SimpleTransition<V> {
    fn retarget(&mut self, t: f64, target: V) {
        self.x1 = self.output(t);
        self.t1 = t;
        self.u1 = target;
    }
    fn sample(&mut self, t: f64) -> V {
        self.output(t)
    }
    fn reset(&mut self, x: V) {
        *self = SimpleTransition::new(self.ease.clone(), x);
    }
}

/// The spline transition algorithm (paper sec. 3, Definition 3): each target change
/// starts a cubic Hermite segment from the current position *and velocity* to the new
/// target, reached with zero velocity after `duration` seconds:
///
/// `r(p₀, ṗ₀, p₁, τ) = (2τ³ − 3τ² + 1)p₀ + (τ³ − 2τ² + τ)·d·ṗ₀ + (−2τ³ + 3τ²)p₁`, `τ = (t − tᵢ)/d`.
///
/// Velocity stays continuous across interruptions, but the motion has no design freedom.
/// Under retargeting at every instant it tends to the system `ÿ = (6(u − y) − 4dẏ)/d²`
/// (sec. 3's limit `A' = [[0, 1], [−6, −4]]`, `B' = [0, 6]` for `d = 1`), available as
/// [`super::Lti::spline_limit`].
#[derive(Clone, Debug)]
pub struct SplineTransition<V> {
    duration: f64,
    t0: f64,
    p0: V,
    v0: V,
    p1: V,
}

impl<V: Vector> SplineTransition<V> {
    /// At rest on `x0`; segments last `duration` seconds (finite, `> 0`).
    pub fn new(duration: f64, x0: V) -> Result<SplineTransition<V>, SignalError> {
        positive("spline duration", duration)?;
        Ok(SplineTransition {
            duration,
            t0: f64::NEG_INFINITY,
            p0: x0,
            v0: V::zero(),
            p1: x0,
        })
    }

    /// Position and velocity (units per second) at `t`.
    pub fn state(&self, t: f64) -> (V, V) {
        let d = self.duration;
        let tau = (t - self.t0) / d;
        if tau >= 1.0 {
            return (self.p1, V::zero());
        }
        let tau = tau.max(0.0);
        let (t2, t3) = (tau * tau, tau * tau * tau);
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + tau;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let pos = self
            .p0
            .scale(h00)
            .add_scaled(self.v0, h10 * d)
            .add_scaled(self.p1, h01);
        let (d00, d10, d01) = (
            6.0 * t2 - 6.0 * tau,
            3.0 * t2 - 4.0 * tau + 1.0,
            -6.0 * t2 + 6.0 * tau,
        );
        let vel = self
            .p0
            .scale(d00 / d)
            .add_scaled(self.v0, d10)
            .add_scaled(self.p1, d01 / d);
        (pos, vel)
    }
}

impl<V: Vector> Transition<V> for SplineTransition<V> {
    fn retarget(&mut self, t: f64, target: V) {
        let (p, v) = self.state(t);
        *self = SplineTransition {
            duration: self.duration,
            t0: t,
            p0: p,
            v0: v,
            p1: target,
        };
    }
    fn sample(&mut self, t: f64) -> V {
        self.state(t).0
    }
    fn reset(&mut self, x: V) {
        *self = SplineTransition {
            duration: self.duration,
            t0: f64::NEG_INFINITY,
            p0: x,
            v0: V::zero(),
            p1: x,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signals::Easing;

    #[test]
    fn simple_transition_restarts_from_rest() {
        let ease = Ease::new(Easing::BSpline(3), 1.0).unwrap();
        let mut s = SimpleTransition::new(ease.clone(), 0.0);
        s.retarget(0.0, 1.0);
        let mid = s.sample(0.5);
        assert!((mid - 0.5).abs() < 1e-12);
        s.retarget(0.5, 2.0);
        // Just after the interruption the output has barely moved: velocity reset to 0.
        let h = 1e-4;
        assert!((s.sample(0.5 + h) - mid).abs() < 1e-6);
        assert_eq!(s.sample(1.5), 2.0);
    }

    #[test]
    fn spline_keeps_velocity_across_interruptions() {
        let mut s = SplineTransition::new(1.0, 0.0).unwrap();
        s.retarget(0.0, 1.0);
        let (_, v_before) = s.state(0.4);
        s.retarget(0.4, -1.0);
        let (_, v_after) = s.state(0.4);
        assert!((v_before - v_after).abs() < 1e-12);
        assert!(v_before > 1.0);
        assert!((s.sample(1.4) + 1.0).abs() < 1e-12);
        assert_eq!(s.sample(1.5), -1.0);
    }
}
