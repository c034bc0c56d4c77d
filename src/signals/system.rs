//! Discrete-time blocks and system diagrams (paper sec. 7).
//!
//! A [`System`] is a block with state that turns one input sample into one output sample
//! per frame. Blocks compose into diagrams: [`Series`] feeds one block's output into the
//! next (impulse responses convolve), [`Parallel`] mixes the outputs of two blocks fed the
//! same input (impulse responses add). Composites of linear time-invariant blocks are
//! linear time-invariant, and composites of affine blocks are affine when parallel weights
//! sum to one — which [`Parallel::new`] enforces.

use super::error::{SignalError, finite};
use super::transition::Transition;
use super::vector::Vector;

/// A discrete-time block: one output per input sample.
pub trait System<V: Vector> {
    /// Feeds the next input sample and returns the output for this frame.
    fn step(&mut self, x: V) -> V;

    /// Puts the block at rest on a constant input `x`: the state it would reach after
    /// `x` had been fed forever. For the affine blocks of this module the output at rest
    /// equals `x`.
    fn reset(&mut self, x: V);
}

impl<V: Vector, S: System<V> + ?Sized> System<V> for Box<S> {
    fn step(&mut self, x: V) -> V {
        (**self).step(x)
    }
    fn reset(&mut self, x: V) {
        (**self).reset(x)
    }
}

/// The block that passes its input through unchanged (`smoothing none`).
#[derive(Clone, Copy, Debug, Default)]
pub struct Identity;

impl<V: Vector> System<V> for Identity {
    fn step(&mut self, x: V) -> V {
        x
    }
    fn reset(&mut self, _: V) {}
}

/// Two blocks in series: `y = b(a(x))` (sec. 7: the impulse response is the convolution
/// of the two, so moderate smoothers in series smooth heavily).
#[derive(Clone, Debug)]
pub struct Series<A, B>(pub A, pub B);

impl<V: Vector, A: System<V>, B: System<V>> System<V> for Series<A, B> {
    fn step(&mut self, x: V) -> V {
        let y = self.0.step(x);
        self.1.step(y)
    }
    fn reset(&mut self, x: V) {
        // Affine blocks rest with output = input, so `b` rests on `x` as well.
        self.0.reset(x);
        self.1.reset(x);
    }
}

/// Two blocks in parallel, outputs mixed: `y = w_a·a(x) + w_b·b(x)` (sec. 7: the impulse
/// responses add with these weights).
#[derive(Clone, Debug)]
pub struct Parallel<A, B> {
    a: A,
    b: B,
    weights: [f64; 2],
}

impl<A, B> Parallel<A, B> {
    /// Mixes `a` and `b` with `weights = [w_a, w_b]`. The weights must be finite and sum
    /// to 1 (within 1e-9) so that the diagram stays affine: a constant input still gives
    /// the same constant output. Negative weights are allowed (affine, not convex).
    pub fn new(a: A, b: B, weights: [f64; 2]) -> Result<Parallel<A, B>, SignalError> {
        for w in weights {
            finite("parallel weight", w)?;
        }
        let sum = weights[0] + weights[1];
        if (sum - 1.0).abs() > 1e-9 {
            return Err(SignalError::Invalid(format!(
                "parallel weights must sum to 1 so the diagram stays affine, got {} + {} = {sum}",
                weights[0], weights[1]
            )));
        }
        Ok(Parallel { a, b, weights })
    }
}

impl<V: Vector, A: System<V>, B: System<V>> System<V> for Parallel<A, B> {
    fn step(&mut self, x: V) -> V {
        let ya = self.a.step(x);
        let yb = self.b.step(x);
        ya.scale(self.weights[0]).add_scaled(yb, self.weights[1])
    }
    fn reset(&mut self, x: V) {
        self.a.reset(x);
        self.b.reset(x);
    }
}

/// A continuous-time, event-driven [`Transition`] run as a discrete block at a fixed
/// frame rate: frame `n` happens at `t = n / fps`; whenever the input sample differs from
/// the previous one the transition is retargeted at that instant, then sampled.
#[derive(Clone, Debug)]
pub struct Sampled<T, V> {
    transition: T,
    fps: f64,
    frame: u64,
    last: Option<V>,
}

impl<T, V> Sampled<T, V> {
    /// Runs `transition` at `fps` frames per second (finite, `> 0`).
    pub fn new(transition: T, fps: f64) -> Result<Sampled<T, V>, SignalError> {
        super::error::positive("frame rate", fps)?;
        Ok(Sampled {
            transition,
            fps,
            frame: 0,
            last: None,
        })
    }

    /// The wrapped transition.
    pub fn inner(&self) -> &T {
        &self.transition
    }
}

impl<V: Vector, T: Transition<V>> System<V> for Sampled<T, V> {
    fn step(&mut self, x: V) -> V {
        let t = self.frame as f64 / self.fps;
        self.frame += 1;
        match self.last {
            Some(prev) if prev == x => {}
            Some(_) => {
                self.transition.retarget(t, x);
                self.last = Some(x);
            }
            None => {
                self.transition.reset(x);
                self.last = Some(x);
            }
        }
        self.transition.sample(t)
    }
    fn reset(&mut self, x: V) {
        self.transition.reset(x);
        self.frame = 0;
        self.last = Some(x);
    }
}
