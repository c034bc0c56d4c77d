//! Geometry for Lottie: Bézier paths as vertex/tangent lists, and affine maps as chains of
//! skew-free transforms (`T·R·S`, at most two levels) that every player draws the same.

use gmotion::tolerance::Tolerance;
use kurbo::{Affine, BezPath, PathEl, Point, Vec2};

use super::model::{Bezier, N};

/// One subpath: vertices with absolute in and out control points.
#[derive(Clone, Debug, PartialEq)]
pub struct Contour {
    /// Closed.
    pub closed: bool,
    /// On-curve points.
    pub v: Vec<Point>,
    /// Control point entering each vertex (absolute).
    pub i: Vec<Point>,
    /// Control point leaving each vertex (absolute).
    pub o: Vec<Point>,
}

impl Contour {
    /// Every point (vertices and control points), for error measures.
    pub fn points(&self) -> impl Iterator<Item = Point> + '_ {
        self.v.iter().chain(&self.i).chain(&self.o).copied()
    }

    /// The contour mapped by `m` (exact for Béziers).
    pub fn transformed(&self, m: Affine) -> Contour {
        let map = |ps: &[Point]| ps.iter().map(|p| m * *p).collect();
        Contour {
            closed: self.closed,
            v: map(&self.v),
            i: map(&self.i),
            o: map(&self.o),
        }
    }

    /// The Lottie form (tangents relative to their vertex).
    ///
    /// A straight segment is written with its control points at its thirds, not on its
    /// ends: lottie-web draws every segment as a cubic, and Chromium's Skia (both of
    /// lottie-web's renderers) steps a cubic whose controls sit on its ends in fixed point
    /// from a first piece only a sliver long, so in some convex outlines a nearly vertical or
    /// horizontal edge under a rotation or skew came out slanted, up to a quarter pixel off
    /// at its far end (gm-0075: skewed pieces' outlines, 0.56% of pixels). At the thirds the
    /// cubic is the same line, evenly parametrised, and every player draws it alike.
    pub fn to_bezier(&self) -> Bezier {
        let pt = |p: Point| [N::coord(p.x).0, N::coord(p.y).0];
        let rel = |c: Point, v: Point| [N::coord(c.x - v.x).0, N::coord(c.y - v.y).0];
        let n = self.v.len();
        let (mut i, mut o) = (self.i.clone(), self.o.clone());
        let segments = if self.closed { n } else { n.saturating_sub(1) };
        for (k, out) in o.iter_mut().enumerate().take(segments) {
            let next = (k + 1) % n;
            let (p0, p3) = (self.v[k], self.v[next]);
            if *out == p0 && self.i[next] == p3 && p0 != p3 {
                *out = p0.lerp(p3, 1.0 / 3.0);
                i[next] = p3.lerp(p0, 1.0 / 3.0);
            }
        }
        Bezier {
            closed: Some(self.closed),
            v: self.v.iter().map(|p| pt(*p)).collect(),
            i: i.iter().zip(&self.v).map(|(c, v)| rel(*c, *v)).collect(),
            o: o.iter().zip(&self.v).map(|(c, v)| rel(*c, *v)).collect(),
        }
    }
}

/// Splits a path into contours; quadratic segments become cubics, a closing segment that
/// returns to the start point merges with it. Contours with no segment are dropped.
pub fn contours(path: &BezPath) -> Vec<Contour> {
    let mut out = Vec::new();
    let mut cur: Option<Contour> = None;
    let finish = |c: Option<Contour>, closed: bool, out: &mut Vec<Contour>| {
        if let Some(mut c) = c {
            if c.v.len() < 2 {
                return;
            }
            c.closed = closed;
            if closed {
                let n = c.v.len();
                // An explicit segment back to the start duplicates vertex 0.
                if (c.v[n - 1] - c.v[0]).hypot() < 1e-9 {
                    c.i[0] = c.i[n - 1];
                    c.v.pop();
                    c.i.pop();
                    c.o.pop();
                }
            }
            out.push(c);
        }
    };
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) => {
                finish(cur.take(), false, &mut out);
                cur = Some(Contour {
                    closed: false,
                    v: vec![p],
                    i: vec![p],
                    o: vec![p],
                });
            }
            PathEl::LineTo(p) => {
                if let Some(c) = cur.as_mut() {
                    c.v.push(p);
                    c.i.push(p);
                    c.o.push(p);
                }
            }
            PathEl::QuadTo(q, p) => {
                if let Some(c) = cur.as_mut() {
                    let p0 = *c.v.last().expect("contour has a start point");
                    let c1 = p0 + (q - p0) * (2.0 / 3.0);
                    let c2 = p + (q - p) * (2.0 / 3.0);
                    *c.o.last_mut().expect("contour has a start point") = c1;
                    c.v.push(p);
                    c.i.push(c2);
                    c.o.push(p);
                }
            }
            PathEl::CurveTo(c1, c2, p) => {
                if let Some(c) = cur.as_mut() {
                    *c.o.last_mut().expect("contour has a start point") = c1;
                    c.v.push(p);
                    c.i.push(c2);
                    c.o.push(p);
                }
            }
            PathEl::ClosePath => {
                let start = cur.as_ref().map(|c| c.v[0]);
                finish(cur.take(), true, &mut out);
                // Drawing may continue from the start point without a new move.
                cur = start.map(|p| Contour {
                    closed: false,
                    v: vec![p],
                    i: vec![p],
                    o: vec![p],
                });
            }
        }
    }
    finish(cur, false, &mut out);
    out
}

/// A transform level Lottie can say without skew: `T(p)·R(r)·S(s)·T(-a)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trs {
    /// Anchor.
    pub a: Vec2,
    /// Position.
    pub p: Vec2,
    /// Rotation in degrees.
    pub r: f64,
    /// Scale factors (not percent).
    pub s: Vec2,
}

impl Trs {
    /// The matrix.
    pub fn affine(&self) -> Affine {
        Affine::translate(self.p)
            * Affine::rotate(self.r.to_radians())
            * Affine::scale_non_uniform(self.s.x, self.s.y)
            * Affine::translate(-self.a)
    }

    /// True when the level does nothing (within the rounding of the output).
    pub fn is_identity(&self) -> bool {
        let [a, b, c, d, e, f] = self.affine().as_coeffs();
        (a - 1.0).abs() < 1e-7
            && b.abs() < 1e-7
            && c.abs() < 1e-7
            && (d - 1.0).abs() < 1e-7
            && e.abs() < 1e-4
            && f.abs() < 1e-4
    }
}

/// `M = R(phi)·diag(sx, sy)·R(theta)` for the linear part of `m` (angles in radians; `sy`
/// is negative for reflections). Closed form for 2×2 matrices.
pub fn svd(m: Affine) -> (f64, Vec2, f64) {
    let [a, b, c, d, _, _] = m.as_coeffs();
    // Rows are (a c) and (b d) in kurbo's column-major coefficients.
    let e = (a + d) / 2.0;
    let f = (a - d) / 2.0;
    let g = (b + c) / 2.0;
    let h = (b - c) / 2.0;
    let q = e.hypot(h);
    let r = f.hypot(g);
    let a1 = g.atan2(f);
    let a2 = h.atan2(e);
    let theta = (a2 - a1) / 2.0;
    let phi = (a2 + a1) / 2.0;
    (phi, Vec2::new(q + r, q - r), theta)
}

/// Splits an affine map into at most two skew-free levels, outermost first, such that
/// their product is `m`. `anchor` becomes the innermost level's anchor (the point the map
/// is written about: rotations and scales animate around it).
pub fn decompose(m: Affine, anchor: Point) -> Vec<Trs> {
    let (mut phi, mut s, mut theta) = svd(m);
    // Fold quarter turns of the inner rotation into the outer one so that axis-aligned
    // scales and plain rotations need a single level.
    let quarter = std::f64::consts::FRAC_PI_2;
    let k = (theta / quarter).round();
    theta -= k * quarter;
    phi += k * quarter;
    if (k as i64).rem_euclid(2) == 1 {
        s = Vec2::new(s.y, s.x);
    }
    let p = (m * anchor).to_vec2();
    // Uniform measured against the larger factor (not the first, as `UNIFORM` does):
    // written so before the tolerances had names, and kept for identical output.
    let uniform = Tolerance::Scaled(1e-9).same(s.x, s.y);
    if theta.abs() < 1e-9 || uniform {
        let r = if uniform { phi + theta } else { phi };
        return vec![Trs {
            a: anchor.to_vec2(),
            p,
            r: r.to_degrees(),
            s,
        }];
    }
    vec![
        Trs {
            a: Vec2::ZERO,
            p,
            r: phi.to_degrees(),
            s,
        },
        Trs {
            a: anchor.to_vec2(),
            p: Vec2::ZERO,
            r: theta.to_degrees(),
            s: Vec2::new(1.0, 1.0),
        },
    ]
}

/// The largest factor by which `m` stretches a length.
pub fn max_stretch(m: Affine) -> f64 {
    let (_, s, _) = svd(m);
    s.x.abs().max(s.y.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn product(levels: &[Trs]) -> Affine {
        levels
            .iter()
            .fold(Affine::IDENTITY, |acc, l| acc * l.affine())
    }

    #[test]
    fn decomposition_reproduces_matrices() {
        let cases = [
            Affine::IDENTITY,
            Affine::rotate(0.7) * Affine::scale_non_uniform(2.0, 0.5),
            Affine::skew(0.4, 0.0),
            Affine::new([1.0, 0.2, -0.7, 1.3, 5.0, -3.0]),
            Affine::scale_non_uniform(-1.0, 1.0) * Affine::rotate(2.0),
            Affine::scale_non_uniform(3.0, 0.2) * Affine::rotate(std::f64::consts::FRAC_PI_2),
        ];
        for m in cases {
            let levels = decompose(m, Point::new(10.0, 20.0));
            assert!(
                Tolerance::Below(1e-9).same_affine(product(&levels), m),
                "{m:?} -> {levels:?}"
            );
        }
    }

    #[test]
    fn similarities_need_one_level() {
        let m = Affine::translate((4.0, 5.0)) * Affine::rotate(1.1) * Affine::scale(3.0);
        assert_eq!(decompose(m, Point::ORIGIN).len(), 1);
        let m = Affine::rotate(0.3) * Affine::scale_non_uniform(1.0, 2.0);
        assert_eq!(decompose(m, Point::ORIGIN).len(), 1);
        assert_eq!(decompose(Affine::skew(0.5, 0.0), Point::ORIGIN).len(), 2);
    }

    #[test]
    fn closing_segment_merges_with_start() {
        let mut p = BezPath::new();
        p.move_to((0.0, 0.0));
        p.line_to((10.0, 0.0));
        p.curve_to((10.0, 5.0), (5.0, 10.0), (0.0, 0.0));
        p.close_path();
        let c = contours(&p);
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].v.len(), 2);
        assert!(c[0].closed);
        assert_eq!(c[0].i[0], Point::new(5.0, 10.0));
    }

    #[test]
    fn quadratics_become_exact_cubics() {
        let mut p = BezPath::new();
        p.move_to((0.0, 0.0));
        p.quad_to((10.0, 20.0), (20.0, 0.0));
        let c = &contours(&p)[0];
        let cubic = kurbo::CubicBez::new(c.v[0], c.o[0], c.i[1], c.v[1]);
        let quad = kurbo::QuadBez::new((0.0, 0.0), (10.0, 20.0), (20.0, 0.0));
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            use kurbo::ParamCurve;
            assert!((cubic.eval(t) - quad.eval(t)).hypot() < 1e-9);
        }
    }
}
