//! Signals and systems for animation, after Reach & North, "The Signals and Systems
//! Approach to Animation" (the paper): motion is a signal passed through filters, so that
//! targets that change mid-flight stay smooth in position *and* velocity.
//!
//! | block | paper | here |
//! |---|---|---|
//! | easing functions of any duration | Def. 1, sec. 9 | [`Easing`], [`Ease`] |
//! | simple transitions (the baseline) | Alg. 1, eq. 1, Claim 1 | [`SimpleTransition`] |
//! | spline transitions | sec. 3, Def. 3 | [`SplineTransition`], [`Lti::spline_limit`] |
//! | FIR transitions, continuous time | Def. 4, Claim 2, Alg. 2 | [`FirTransition`] |
//! | FIR filter, discrete time | Alg. 3 | [`Fir`] |
//! | state-space systems | Def. 5 | [`StateSpace`], [`DiscreteStateSpace`] |
//! | spring–mass–damper | sec. 6, Fig. 1 | [`Spring`] |
//! | discretisation | sec. 6, 9 | [`Lti::discretize`], [`Discretization`] |
//! | biquads in transposed direct form II | Alg. 4, Fig. 2 | [`Biquad`], [`BiquadCascade`] |
//! | system diagrams | sec. 7 | [`System`], [`Series`], [`Parallel`] |
//! | elliptical arcs at constant speed | sec. 8.2 | [`ArcEasing`] |
//! | smoothing sampled channels | — | [`SmoothSpec`], [`smooth_samples`] |
//!
//! Signals take values in any [`Vector`] type (`f64`, `[f64; N]`, kurbo and glam
//! vectors). Every constructor validates its parameters and returns a [`SignalError`]
//! rather than panicking.

pub mod arc;
pub mod biquad;
pub mod complex;
pub mod easing;
pub mod error;
pub mod fir;
pub mod lti;
mod matrix;
mod poly;
pub mod smooth;
pub mod spring;
pub mod statespace;
pub mod system;
pub mod transition;
pub mod vector;

pub use arc::ArcEasing;
pub use biquad::{Biquad, BiquadCascade};
pub use complex::Complex;
pub use easing::{Ease, Easing};
pub use error::SignalError;
pub use fir::{Fir, FirTransition, Response};
pub use lti::{Discretization, Lti};
pub use smooth::{CallArg, SmoothSpec, smooth_samples};
pub use spring::Spring;
pub use statespace::{DiscreteStateSpace, StateSpace};
pub use system::{Identity, Parallel, Sampled, Series, System};
pub use transition::{SimpleTransition, SplineTransition, Transition};
pub use vector::Vector;
