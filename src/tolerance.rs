//! "The same up to rounding": every comparison of two computed numbers (or affine maps)
//! that must not tell float noise from a real difference goes through [`Tolerance`].
//!
//! The comparisons differ on purpose, and the differences are named here rather than
//! spelled out where they are used:
//! - **[`Tolerance::Below`]** (`|a − b| < ε`) and **[`Tolerance::Within`]** (`|a − b| ≤ ε`)
//!   for values of a known scale: tests that compare a round trip with its source, numbers
//!   the output writes with a fixed number of decimals ([`WRITTEN`]), progress in `[0, 1]`
//!   ([`PROGRESS`]) and keyframe times ([`KEY_TIME`]). Which of the two a place uses is
//!   historical and kept: the edge case decides whether a key is written.
//! - **[`Tolerance::Relative`]** (`|a − b| ≤ ε·(1 + max(|a|, |b|))`) where sampled transforms
//!   are compared whatever their size ([`FRAME`], [`TELESCOPE`]): the `1 +` keeps the
//!   bound absolute near zero.
//! - **[`Tolerance::Scaled`]** (`|a − b| ≤ ε·max(|a|, |b|, 1)`) for keyframe values
//!   ([`KEY`]): equal when no player could tell them apart.
//! - **[`Tolerance::OfFirst`]** (`|a − b| ≤ ε·max(|a|, 1)`) where the first value is the
//!   reference the second was computed to match ([`COMPOSED`]).
//!
//! Changing a mode or a constant changes what gets written: the exporters' output is
//! checked byte for byte against these exact formulas.

use kurbo::Affine;

/// How far apart two numbers may be and still count as the same.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tolerance {
    /// `|a − b| < ε` (strictly): an absolute bound for values of a known scale.
    Below(f64),
    /// `|a − b| ≤ ε`: the same absolute bound, its edge included.
    Within(f64),
    /// `|a − b| ≤ ε·(1 + max(|a|, |b|))`: relative for large values, absolute near zero.
    Relative(f64),
    /// `|a − b| ≤ ε·max(|a|, |b|, 1)`: relative to the larger value, never below `ε`.
    Scaled(f64),
    /// `|a − b| ≤ ε·max(|a|, 1)`: relative to the first value, the reference.
    OfFirst(f64),
}

/// Keyframe values (Lottie keys, their holds and dedup): one part in 10⁹ of the value.
pub const KEY: Tolerance = Tolerance::Scaled(1e-9);

/// Progress values (in `[0, 1]`) of SMIL keys: a hold is not written twice, and a
/// window whose progress stays put is no animation.
pub const PROGRESS: Tolerance = Tolerance::Within(1e-12);

/// Keyframe times (Lottie frames): a key is not written twice at one time.
pub const KEY_TIME: Tolerance = Tolerance::Below(1e-9);

/// Consecutive sampled frames of a transition whose transforms do not move (no window
/// is made for them): rounding of the sampled affine only.
pub const FRAME: Tolerance = Tolerance::Relative(1e-12);

/// A transition window's full transform telescoped back onto the next sample: looser
/// than [`FRAME`], since the product goes through a power and an inverse.
pub const TELESCOPE: Tolerance = Tolerance::Relative(1e-9);

/// A transform composed from a motion's parts against the one it must reproduce (the
/// Lottie exporter's motion chains and identity checks).
pub const COMPOSED: Tolerance = Tolerance::OfFirst(1e-9);

/// The two scale factors of a Lottie transform level are one (a uniform scale, about which
/// the rotation may move between levels): relative to the first factor.
pub const UNIFORM: Tolerance = Tolerance::OfFirst(1e-9);

/// Coordinates the Lottie exporter writes with three decimals: closer than half the last
/// written digit is the same number in the file.
pub const WRITTEN: Tolerance = Tolerance::Below(5e-4);

impl Tolerance {
    /// Whether `a` and `b` are the same number under this tolerance.
    #[inline]
    pub fn same(self, a: f64, b: f64) -> bool {
        let d = (a - b).abs();
        match self {
            Tolerance::Below(eps) => d < eps,
            Tolerance::Within(eps) => d <= eps,
            Tolerance::Relative(eps) => d <= eps * (1.0 + a.abs().max(b.abs())),
            Tolerance::Scaled(eps) => d <= eps * a.abs().max(b.abs()).max(1.0),
            Tolerance::OfFirst(eps) => d <= eps * a.abs().max(1.0),
        }
    }

    /// Whether every pair of `a` and `b` is the same (`a` and `b` of equal length).
    pub fn same_all(self, a: &[f64], b: &[f64]) -> bool {
        a.iter().zip(b).all(|(x, y)| self.same(*x, *y))
    }

    /// Whether `a` and `b` agree in every coefficient: the same map up to rounding.
    pub fn same_affine(self, a: Affine, b: Affine) -> bool {
        self.same_all(&a.as_coeffs(), &b.as_coeffs())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_scale_as_documented() {
        // Below is strict, Within is not, and both ignore size.
        assert!(Tolerance::Within(1.0).same(0.0, 1.0));
        assert!(Tolerance::Below(1.0).same(0.0, 0.5));
        assert!(!Tolerance::Below(1.0).same(0.0, 1.0));
        assert!(!Tolerance::Below(1.0).same(1e6, 1e6 + 2.0));
        // Relative grows with the larger value and stays absolute near zero.
        assert!(Tolerance::Relative(1e-3).same(1e6, 1e6 + 1e3));
        assert!(Tolerance::Relative(1e-3).same(0.0, 1e-3));
        // Scaled never drops below ε, and is symmetric.
        assert!(Tolerance::Scaled(1e-3).same(0.0, 1e-3));
        assert!(Tolerance::Scaled(1e-3).same(1e3, 1e3 - 1.0));
        assert!(Tolerance::Scaled(1e-3).same(1e3 - 1.0, 1e3));
        // OfFirst measures against its first value only.
        assert!(Tolerance::OfFirst(1e-3).same(1e3, 1e3 + 1.0));
        assert!(!Tolerance::OfFirst(1e-3).same(0.0, 2e-3));
    }

    #[test]
    fn affines_compare_every_coefficient() {
        let a = Affine::rotate(0.3);
        assert!(FRAME.same_affine(a, a));
        assert!(!FRAME.same_affine(a, Affine::translate((1e-9, 0.0)) * a));
        assert!(COMPOSED.same_affine(a, Affine::translate((1e-10, 0.0)) * a));
    }
}
