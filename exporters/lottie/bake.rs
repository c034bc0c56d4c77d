//! Baking: motion Lottie cannot say is sampled at every frame, then thinned greedily so
//! that what a player reconstructs (linear interpolation between the kept keyframes) stays
//! within the error bound, measured as the displacement of check points in canvas units.

use kurbo::{Affine, Point, Vec2};

use super::geometry::{Contour, svd};
use super::model::{Ease, Keyframe, N, Prop, Transform, Value};

/// Greedy keyframe reduction over `n` samples: keeps the first and last, and from each kept
/// sample jumps as far as `fits(i, j)` allows (`fits` says whether interpolating from `i`
/// to `j` reproduces every sample between them). Adjacent samples always fit.
pub fn reduce(n: usize, fits: impl Fn(usize, usize) -> bool) -> Vec<usize> {
    if n == 0 {
        return Vec::new();
    }
    let mut kept = vec![0];
    let mut i = 0;
    while i + 1 < n {
        let mut j = i + 1;
        while j + 1 < n && fits(i, j + 1) {
            j += 1;
        }
        kept.push(j);
        i = j;
    }
    kept
}

/// The parameters a skew-free two-level transform interpolates:
/// `T(p)·R(phi)·S(s)·R(theta)·T(-anchor)`, angles in radians.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Params {
    p: Vec2,
    phi: f64,
    s: Vec2,
    theta: f64,
}

impl Params {
    fn lerp(&self, o: &Params, f: f64) -> Params {
        let l = |a: f64, b: f64| a + (b - a) * f;
        Params {
            p: self.p.lerp(o.p, f),
            phi: l(self.phi, o.phi),
            s: self.s.lerp(o.s, f),
            theta: l(self.theta, o.theta),
        }
    }

    fn affine(&self, anchor: Point) -> Affine {
        Affine::translate(self.p)
            * Affine::rotate(self.phi)
            * Affine::scale_non_uniform(self.s.x, self.s.y)
            * Affine::rotate(self.theta)
            * Affine::translate(-anchor.to_vec2())
    }
}

fn unwrap(angle: f64, near: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    angle - ((angle - near) / tau).round() * tau
}

/// Decomposes `m` about `anchor`, choosing among the equivalent forms the one closest to
/// `prev` so that interpolated parameters move smoothly.
fn params(m: Affine, anchor: Point, prev: Option<&Params>) -> Params {
    let (phi, s, theta) = svd(m);
    let p = (m * anchor).to_vec2();
    let Some(prev) = prev else {
        return Params { p, phi, s, theta };
    };
    let uniform = (s.x - s.y).abs() <= 1e-9 * s.x.abs().max(1.0);
    if uniform {
        // The split between the two rotations is free: keep the inner one still.
        let total = phi + theta;
        return Params {
            p,
            phi: unwrap(total - prev.theta, prev.phi),
            s,
            theta: prev.theta,
        };
    }
    let quarter = std::f64::consts::FRAC_PI_2;
    let mut best: Option<(f64, Params)> = None;
    for k in 0..4 {
        for flip in [false, true] {
            let q = k as f64 * quarter;
            let mut c = Params {
                p,
                phi: phi + q,
                s,
                theta: theta - q,
            };
            if k % 2 == 1 {
                c.s = Vec2::new(s.y, s.x);
            }
            if flip {
                c.phi += std::f64::consts::PI;
                c.s = -c.s;
            }
            c.phi = unwrap(c.phi, prev.phi);
            c.theta = unwrap(c.theta, prev.theta);
            let d =
                (c.phi - prev.phi).abs() + (c.theta - prev.theta).abs() + (c.s - prev.s).hypot();
            if best.as_ref().is_none_or(|(bd, _)| d < *bd) {
                best = Some((d, c));
            }
        }
    }
    best.expect("eight candidates").1
}

/// One sample of a rigid motion to bake.
#[derive(Clone, Debug)]
pub struct RigidSample {
    /// Frame.
    pub frame: f64,
    /// The transform to reproduce.
    pub m: Affine,
    /// Points it is applied to (the shape's bounding-box corners where it is).
    pub points: Vec<Point>,
    /// How much whatever is applied after `m` magnifies an error.
    pub gain: f64,
}

/// Bakes sampled transforms into at most two keyframed skew-free levels (outermost first)
/// that reproduce every sample within `tolerance`; the first sample's transform should be
/// the identity when the levels must be neutral before the samples begin.
pub fn bake_rigid(samples: &[RigidSample], anchor: Point, tolerance: f64) -> Vec<Transform> {
    let mut ps: Vec<Params> = Vec::with_capacity(samples.len());
    for s in samples {
        let p = params(s.m, anchor, ps.last());
        ps.push(p);
    }
    let err = |m: usize, rec: &Params| {
        let a = rec.affine(anchor);
        let s = &samples[m];
        s.points
            .iter()
            .map(|q| ((a * *q) - (s.m * *q)).hypot())
            .fold(0.0, f64::max)
            * s.gain
    };
    let kept = reduce(samples.len(), |i, j| {
        (i + 1..j).all(|m| {
            let f = (samples[m].frame - samples[i].frame) / (samples[j].frame - samples[i].frame);
            err(m, &ps[i].lerp(&ps[j], f)) <= tolerance
        })
    });
    let keys = |f: &dyn Fn(&Params) -> Value| -> Prop {
        Prop::keyed(
            kept.iter()
                .enumerate()
                .map(|(n, &i)| Keyframe {
                    t: N::coord(samples[i].frame),
                    s: f(&ps[i]),
                    ease: (n + 1 < kept.len()).then_some(Ease::LINEAR),
                    hold: false,
                })
                .collect(),
        )
    };
    let v2 = |v: Vec2| Value::Vec(vec![N::coord(v.x), N::coord(v.y)]);
    let scale = |s: Vec2| Value::Vec(vec![N::coord(s.x * 100.0), N::coord(s.y * 100.0)]);
    let deg = |r: f64| Value::Scalar(N::coord(r.to_degrees()));
    let needs_inner = kept.iter().any(|&i| ps[i].theta.abs() > 1e-9);
    let a = Prop::fixed(v2(anchor.to_vec2()));
    if !needs_inner {
        return vec![Transform {
            a: Some(a),
            p: Some(keys(&|q| v2(q.p))),
            s: Some(keys(&|q| scale(q.s))),
            r: Some(keys(&|q| deg(q.phi))),
            o: None,
        }];
    }
    vec![
        Transform {
            a: None,
            p: Some(keys(&|q| v2(q.p))),
            s: Some(keys(&|q| scale(q.s))),
            r: Some(keys(&|q| deg(q.phi))),
            o: None,
        },
        Transform {
            a: Some(a),
            p: None,
            s: None,
            r: Some(keys(&|q| deg(q.theta))),
            o: None,
        },
    ]
}

/// Bakes sampled outlines of one path (same topology at every sample; `frames[k]` with
/// `shapes[k]`) into keyframed Lottie paths, one property per contour, within `tolerance`
/// after scaling by `gain` (how much the path's placement magnifies lengths).
pub fn bake_paths(frames: &[f64], shapes: &[Vec<Contour>], gain: f64, tolerance: f64) -> Vec<Prop> {
    let kept = reduce(frames.len(), |i, j| {
        (i + 1..j).all(|m| {
            let f = (frames[m] - frames[i]) / (frames[j] - frames[i]);
            shapes[m]
                .iter()
                .zip(&shapes[i])
                .zip(&shapes[j])
                .all(|((cm, ci), cj)| {
                    cm.points()
                        .zip(ci.points().zip(cj.points()))
                        .all(|(pm, (pi, pj))| (pi.lerp(pj, f) - pm).hypot() * gain <= tolerance)
                })
        })
    });
    let contours = shapes.first().map_or(0, Vec::len);
    (0..contours)
        .map(|c| {
            let keys: Vec<Keyframe> = kept
                .iter()
                .enumerate()
                .map(|(n, &i)| Keyframe {
                    t: N::coord(frames[i]),
                    s: Value::Bezier(shapes[i][c].to_bezier()),
                    ease: (n + 1 < kept.len()).then_some(Ease::LINEAR),
                    hold: false,
                })
                .collect();
            Prop::keyed(keys)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reduce_keeps_ends_and_skips_fitting_runs() {
        let kept = reduce(10, |i, j| j - i <= 3);
        assert_eq!(kept, vec![0, 3, 6, 9]);
        assert_eq!(reduce(1, |_, _| true), vec![0]);
    }

    #[test]
    fn decomposition_is_continuous_through_a_turn() {
        let anchor = Point::new(5.0, 5.0);
        let mut prev: Option<Params> = None;
        for k in 0..=40 {
            let a = k as f64 * 0.2;
            let m = Affine::rotate_about(a, anchor) * Affine::scale_non_uniform(2.0, 1.0);
            let p = params(m, anchor, prev.as_ref());
            let back = p.affine(anchor);
            assert!(
                back.as_coeffs()
                    .iter()
                    .zip(m.as_coeffs())
                    .all(|(x, y)| (x - y).abs() < 1e-9)
            );
            if let Some(q) = prev {
                assert!(
                    (p.phi - q.phi).abs() < 0.3 && (p.theta - q.theta).abs() < 0.3,
                    "{q:?} -> {p:?}"
                );
            }
            prev = Some(p);
        }
    }
}
