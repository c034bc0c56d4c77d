//! Signals and systems for animation (Reach & North): easing, FIR and IIR transitions.

pub mod easing;

pub use easing::Easing;
