//! Keyframes: the one model both exporters write (a [`Key`] per instant, an [`Ease`] into
//! it), and the one routine that turns a motion's progress into keys, [`progress_keys`],
//! under the constraints of the format that will play them ([`Format`]).
//!
//! Every channel gmotion animates is an affine function of progress (component parameters,
//! tints, multipliers), and players interpolate keyframe values affinely along each key's
//! easing, so a window whose easing is a cubic Bézier is reproduced exactly by keys whose
//! easings are pieces of that Bézier. What differs between formats is which pieces they
//! accept and how they spell a jump:
//! - **SMIL** ([`Format::UnitBox`], [`unit_box`]): a `keySplines` entry must have its control
//!   points in `[0, 1]²`, so the curve is cut at the window's ends and its extrema in value
//!   and halved until each piece fits; a jump is two keys at one time.
//! - **Lottie** ([`Format::Spaced`], [`spaced`]): easing handles may leave the box, a
//!   value jump is a hold ([`Ease::Hold`]) arriving a thousandth of a frame before the next
//!   key, and times are frames.
//!
//! A stepped easing (`steps(n)`, `hold`) is written as its jumps alone ([`steps`]).
//!
//! Motion neither format can say (an easing that is not a cubic Bézier, a deformation) is
//! sampled and thinned: [`sample`] has the sample instants and the sampled progress,
//! [`reduce`] the reductions that keep as few samples as stay within an error bound.
//! The exporters keep only their encoding (Lottie keyframe JSON, SMIL attribute text).

pub mod reduce;
pub mod sample;
pub mod spaced;
pub mod steps;
pub mod unit_box;

use crate::motion::{Timing, Tint};
use crate::tolerance::KEY;

/// How a channel arrives at a key from the key before it (ignored on a channel's first key).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ease {
    /// Straight interpolation.
    Linear,
    /// Along a CSS-style cubic Bézier `[x1, y1, x2, y2]` from time fraction to value
    /// fraction. [`Format::UnitBox`] keeps every number in `[0, 1]`; [`Format::Spaced`]
    /// keeps `x1, x2` there.
    Bezier([f64; 4]),
    /// The previous key's value until this key's time, then this key's value at once.
    Hold,
}

/// A keyframe: at time `t` the channel has value `v`, reached from the previous key by
/// `ease`. Times are in the unit of the format ([`Format`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Key<V> {
    /// Seconds (SMIL) or frames (Lottie).
    pub t: f64,
    /// The value.
    pub v: V,
    /// How the channel gets here from the previous key.
    pub ease: Ease,
}

impl<V> Key<V> {
    /// A key reached by straight interpolation.
    pub fn linear(t: f64, v: V) -> Key<V> {
        Key {
            t,
            v,
            ease: Ease::Linear,
        }
    }
}

/// Values compared the way output is written: equal when no player could tell them apart
/// (within [`KEY`]).
pub trait Same {
    /// Whether `self` and `other` are the same value up to float noise.
    fn same(&self, other: &Self) -> bool;
}

impl Same for f64 {
    fn same(&self, o: &f64) -> bool {
        KEY.same(*self, *o)
    }
}

impl<const K: usize> Same for [f64; K] {
    fn same(&self, o: &Self) -> bool {
        KEY.same_all(self, o)
    }
}

impl Same for Tint {
    fn same(&self, o: &Tint) -> bool {
        KEY.same(self.weight as f64, o.weight as f64)
            && self
                .sum
                .iter()
                .zip(&o.sum)
                .all(|(a, b)| KEY.same(*a as f64, *b as f64))
    }
}

/// One window a channel changes in.
#[derive(Clone, Copy, Debug)]
pub struct Piece<'a> {
    /// Window start (seconds).
    pub t0: f64,
    /// Window end (seconds), already cut where the next window begins.
    pub t1: f64,
    /// What drives the progress.
    pub timing: &'a Timing,
}

/// The format the keys are for: what their times count and which easings and jumps it
/// can play.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Format {
    /// SMIL `keyTimes`/`keySplines`: times in seconds; every Bézier's control points in
    /// `[0, 1]²`; a jump is two keys at one time and a hold two keys of one value (no
    /// [`Ease::Hold`]). Easings that are not cubic Béziers with `x1, x2 ∈ [0, 1]` give no
    /// keys: the caller samples them against its own error ([`sample::sampled_progress`]).
    UnitBox,
    /// Lottie keyframes: times in frames at `fps`; a value jump is an [`Ease::Hold`] key,
    /// and one that happens right on a key arrives [`spaced::JUMP`] frames earlier; easings
    /// that are not cubic Béziers are sampled at every frame and thinned so that linear
    /// interpolation stays within `tolerance` of the progress.
    Spaced {
        /// Frames per second.
        fps: f64,
        /// Largest progress error of a sampled easing.
        tolerance: f64,
    },
}

/// The keys of a channel that holds `default` before its first piece and
/// `value(piece, progress)` within (and after) each piece, for `format`. `None` only for
/// [`Format::UnitBox`] when a piece's easing is not a Bézier SMIL can play.
pub fn progress_keys<V: Clone + Same>(
    pieces: &[Piece],
    default: V,
    value: impl Fn(usize, f64) -> V,
    format: Format,
) -> Option<Vec<Key<V>>> {
    match format {
        Format::Spaced { fps, tolerance } => {
            Some(spaced::keys(pieces, fps, default, value, tolerance))
        }
        Format::UnitBox => unit_box::keys(pieces, default, value),
    }
}

#[cfg(test)]
mod tests;
