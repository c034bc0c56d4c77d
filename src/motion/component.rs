//! Transform components: the pieces an affine animation is a product of.
//!
//! An animation interpolates each component from neutral (progress 0) to its full value
//! (progress 1) by its own parameters — an angle for a rotation, factors for a scale — so a
//! rotation rotates rather than shrinking through a matrix blend, and each component maps
//! onto one Lottie or SMIL transform channel exactly.

use kurbo::{Affine, Vec2};

/// One factor of an affine animation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Component {
    /// Translation by `(dx, dy)`.
    Translate(Vec2),
    /// Rotation by an angle in degrees (clockwise on screen, as in SVG).
    Rotate(f64),
    /// Scale by `(sx, sy)`.
    Scale(Vec2),
    /// Skew by angles in degrees along x and y.
    Skew(f64, f64),
    /// A raw matrix, interpolated entry by entry from the identity.
    Matrix(Affine),
}

impl Component {
    /// The component at progress `s` (0 = identity, 1 = full value).
    #[inline]
    pub fn at(&self, s: f64) -> Affine {
        match *self {
            Component::Translate(d) => Affine::translate(d * s),
            Component::Rotate(deg) => Affine::rotate((deg * s).to_radians()),
            Component::Scale(k) => {
                Affine::scale_non_uniform(1.0 + (k.x - 1.0) * s, 1.0 + (k.y - 1.0) * s)
            }
            Component::Skew(ax, ay) => Affine::skew(tan_deg(ax * s), tan_deg(ay * s)),
            Component::Matrix(m) => {
                let a = m.as_coeffs();
                let i = Affine::IDENTITY.as_coeffs();
                let mut c = [0.0; 6];
                for k in 0..6 {
                    c[k] = i[k] + (a[k] - i[k]) * s;
                }
                Affine::new(c)
            }
        }
    }

    /// True when the component does nothing at any progress.
    pub fn is_identity(&self) -> bool {
        match *self {
            Component::Translate(d) => d == Vec2::ZERO,
            Component::Rotate(a) => a == 0.0,
            Component::Scale(k) => k == Vec2::new(1.0, 1.0),
            Component::Skew(x, y) => x == 0.0 && y == 0.0,
            Component::Matrix(m) => m == Affine::IDENTITY,
        }
    }

    /// True when every parameter is finite.
    pub fn is_finite(&self) -> bool {
        match *self {
            Component::Translate(d) | Component::Scale(d) => d.x.is_finite() && d.y.is_finite(),
            Component::Rotate(a) => a.is_finite(),
            Component::Skew(x, y) => x.is_finite() && y.is_finite(),
            Component::Matrix(m) => m.as_coeffs().iter().all(|v| v.is_finite()),
        }
    }
}

/// `tan` of an angle in degrees. Skews are usually along one axis; `tan(±0) = ±0`, so
/// skipping the call for a zero angle changes no bit and saves a libm call per frame.
#[inline]
fn tan_deg(deg: f64) -> f64 {
    let r = deg.to_radians();
    if r == 0.0 { r } else { r.tan() }
}

/// The product of a list of components at progress `s`, leftmost applied last (as in SVG's
/// `transform="translate(..) rotate(..)"`).
#[inline]
pub fn product_at(components: &[Component], s: f64) -> Affine {
    match components {
        [] => Affine::IDENTITY,
        [first, rest @ ..] => rest.iter().fold(first.at(s), |acc, c| acc * c.at(s)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_keeps_length_halfway() {
        let m = Component::Rotate(90.0).at(0.5);
        let p = m * kurbo::Point::new(10.0, 0.0);
        assert!((p.to_vec2().hypot() - 10.0).abs() < 1e-9);
        assert!((p.x - p.y).abs() < 1e-9);
    }

    #[test]
    fn endpoints_are_identity_and_full() {
        let cs = [
            Component::Translate(Vec2::new(3.0, 4.0)),
            Component::Scale(Vec2::new(2.0, 0.5)),
        ];
        assert_eq!(product_at(&cs, 0.0), Affine::IDENTITY);
        let full = product_at(&cs, 1.0);
        assert_eq!(
            full * kurbo::Point::new(1.0, 2.0),
            kurbo::Point::new(5.0, 5.0)
        );
    }
}
