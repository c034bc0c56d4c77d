//! Affine maps as the SMIL transform types: `translate · rotate · scale · skewX`.
//!
//! SMIL has no matrix animation, but every 2D affine map with a non-degenerate first column
//! is such a product (a QR factorisation of its linear part), so a sampled or jumping
//! transform can still be written as four `animateTransform`s on one group. Putting the skew
//! innermost keeps every parameter finite and continuous when the map passes through a
//! reflection (`sy` just changes sign), which a `skewX · scale` order would not.

use kurbo::Affine;

/// An affine map as `translate(tx, ty) · rotate(angle) · scale(sx, sy) · skewX(skew)`,
/// angles in degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decomposed {
    /// Translation.
    pub translate: [f64; 2],
    /// Rotation in degrees.
    pub rotate: f64,
    /// Skew along x in degrees.
    pub skew_x: f64,
    /// Scale factors (`sy < 0` for reflections).
    pub scale: [f64; 2],
}

impl Decomposed {
    /// The identity.
    pub const IDENTITY: Decomposed = Decomposed {
        translate: [0.0; 2],
        rotate: 0.0,
        skew_x: 0.0,
        scale: [1.0; 2],
    };

    /// Splits `m`; `None` when its first column vanishes (no unique rotation).
    pub fn of(m: Affine) -> Option<Decomposed> {
        let [a, b, c, d, e, f] = m.as_coeffs();
        let sx = a.hypot(b);
        if sx.is_nan() || sx <= 1e-12 || !m.as_coeffs().iter().all(|v| v.is_finite()) {
            return None;
        }
        let (cos, sin) = (a / sx, b / sx);
        // R⁻¹·(c, d) = (sx·tan(skew), sy).
        let sy = -sin * c + cos * d;
        let shear = (cos * c + sin * d) / sx;
        Some(Decomposed {
            translate: [e, f],
            rotate: b.atan2(a).to_degrees(),
            skew_x: shear.atan().to_degrees(),
            scale: [sx, sy],
        })
    }

    /// The map back.
    pub fn to_affine(self) -> Affine {
        Affine::translate((self.translate[0], self.translate[1]))
            * Affine::rotate(self.rotate.to_radians())
            * Affine::scale_non_uniform(self.scale[0], self.scale[1])
            * Affine::skew(self.skew_x.to_radians().tan(), 0.0)
    }

    /// Linear blend of the parameters (what a player does between two keys).
    pub fn lerp(self, o: Decomposed, s: f64) -> Decomposed {
        let l = |a: f64, b: f64| a + (b - a) * s;
        Decomposed {
            translate: [
                l(self.translate[0], o.translate[0]),
                l(self.translate[1], o.translate[1]),
            ],
            rotate: l(self.rotate, o.rotate),
            skew_x: l(self.skew_x, o.skew_x),
            scale: [l(self.scale[0], o.scale[0]), l(self.scale[1], o.scale[1])],
        }
    }

    /// `self` with its rotation moved by whole turns to lie within half a turn of `prev`,
    /// so that interpolating from `prev` takes the short way.
    pub fn unwrapped_after(mut self, prev: &Decomposed) -> Decomposed {
        self.rotate -= 360.0 * ((self.rotate - prev.rotate) / 360.0).round();
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gmotion::tolerance::Tolerance;

    #[test]
    fn round_trips_general_maps() {
        for m in [
            Affine::IDENTITY,
            Affine::new([0.3, -1.2, 2.5, 0.7, 11.0, -4.0]),
            Affine::scale_non_uniform(-2.0, 0.5) * Affine::rotate(2.9),
            Affine::skew(0.4, -0.3) * Affine::translate((3.0, 9.0)),
        ] {
            let d = Decomposed::of(m).unwrap();
            assert!(
                Tolerance::Below(1e-9).same_affine(d.to_affine(), m),
                "{m:?} -> {d:?}"
            );
        }
    }

    #[test]
    fn only_a_vanishing_first_column_has_no_decomposition() {
        assert!(Decomposed::of(Affine::scale_non_uniform(0.0, 1.0)).is_none());
        assert!(Decomposed::of(Affine::scale(0.0)).is_none());
        let flat = Decomposed::of(Affine::new([1.0, 0.0, 2.0, 0.0, 0.0, 0.0])).unwrap();
        assert!(flat.scale[1] == 0.0 && flat.skew_x.is_finite());
    }

    #[test]
    fn unwrapping_takes_the_short_way() {
        let a = Decomposed {
            rotate: 170.0,
            ..Decomposed::IDENTITY
        };
        let b = Decomposed {
            rotate: -170.0,
            ..Decomposed::IDENTITY
        }
        .unwrapped_after(&a);
        assert_eq!(b.rotate, 190.0);
    }
}
