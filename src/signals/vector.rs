//! The values signals take: elements of a real vector space (scalars, points, colours).
//!
//! Every block in this module is linear (or, for simple and spline transitions, built
//! from linear combinations), so it only needs to add values and scale them. Scalar
//! blocks act on each component of a vector independently; the one exception is the
//! matrix easing of sec. 8.2 ([`crate::signals::ArcEasing`]), which mixes components.

use std::fmt::Debug;

/// A value a signal can take: a fixed-size vector of reals.
///
/// Implemented for `f64`, `[f64; N]` (positions, RGBA colours, transform parameters),
/// [`kurbo::Vec2`] and glam's `DVec2`, `DVec3` and `DVec4`.
pub trait Vector: Copy + Debug + PartialEq + 'static {
    /// Number of components.
    const DIM: usize;

    /// Component `i` (`i < DIM`).
    fn get(&self, i: usize) -> f64;

    /// The vector whose component `i` is `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> f64) -> Self;

    /// The zero vector.
    fn zero() -> Self {
        Self::from_fn(|_| 0.0)
    }

    /// `self + o`.
    fn add(self, o: Self) -> Self {
        Self::from_fn(|i| self.get(i) + o.get(i))
    }

    /// `self - o`.
    fn sub(self, o: Self) -> Self {
        Self::from_fn(|i| self.get(i) - o.get(i))
    }

    /// `k · self`.
    fn scale(self, k: f64) -> Self {
        Self::from_fn(|i| k * self.get(i))
    }

    /// `self + k · o`, the inner loop of every filter.
    fn add_scaled(self, o: Self, k: f64) -> Self {
        Self::from_fn(|i| self.get(i) + k * o.get(i))
    }

    /// Largest absolute component (the distance used for settling tests).
    fn max_abs(&self) -> f64 {
        (0..Self::DIM)
            .map(|i| self.get(i).abs())
            .fold(0.0, f64::max)
    }

    /// True when every component is finite.
    fn is_finite(&self) -> bool {
        (0..Self::DIM).all(|i| self.get(i).is_finite())
    }
}

impl Vector for f64 {
    const DIM: usize = 1;
    fn get(&self, _: usize) -> f64 {
        *self
    }
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> f64 {
        f(0)
    }
    // Scalars are the common case: skip the component loop.
    fn add(self, o: f64) -> f64 {
        self + o
    }
    fn sub(self, o: f64) -> f64 {
        self - o
    }
    fn scale(self, k: f64) -> f64 {
        k * self
    }
    fn add_scaled(self, o: f64, k: f64) -> f64 {
        self + k * o
    }
}

impl<const N: usize> Vector for [f64; N] {
    const DIM: usize = N;
    fn get(&self, i: usize) -> f64 {
        self[i]
    }
    fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
        std::array::from_fn(f)
    }
}

impl Vector for kurbo::Vec2 {
    const DIM: usize = 2;
    fn get(&self, i: usize) -> f64 {
        if i == 0 { self.x } else { self.y }
    }
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        kurbo::Vec2::new(f(0), f(1))
    }
}

macro_rules! glam_vector {
    ($t:ty, $n:expr) => {
        impl Vector for $t {
            const DIM: usize = $n;
            fn get(&self, i: usize) -> f64 {
                self[i]
            }
            fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
                <$t>::from_array(std::array::from_fn(f))
            }
        }
    };
}
glam_vector!(glam::DVec2, 2);
glam_vector!(glam::DVec3, 3);
glam_vector!(glam::DVec4, 4);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrays_and_glam_agree() {
        let a = [1.0, 2.0, 3.0].add_scaled([1.0, 1.0, 1.0], 2.0);
        let g = glam::DVec3::new(1.0, 2.0, 3.0).add_scaled(glam::DVec3::ONE, 2.0);
        assert_eq!(a, g.to_array());
        assert_eq!(kurbo::Vec2::new(3.0, -4.0).max_abs(), 4.0);
    }
}
