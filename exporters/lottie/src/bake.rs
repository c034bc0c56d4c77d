//! Baking: motion Lottie cannot say is sampled at every frame, then thinned greedily so
//! that what a player reconstructs (linear interpolation between the kept keyframes) stays
//! within the error bound, measured as the displacement of check points in canvas units.

use gmotion::keyframe::reduce::greedy;
use gmotion::tolerance::UNIFORM;
use kurbo::{Affine, Point, Vec2};

use super::geometry::{Contour, svd};
use super::model::{Keyframe, LINEAR, N, Prop, Transform, Value, from_css};

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
    let uniform = UNIFORM.same(s.x, s.y);
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
    pub points: [Point; 4],
    /// How much whatever is applied after `m` magnifies an error.
    pub gain: f64,
}

/// The parameters as channels: x, y, phi, sx, sy, theta.
fn channels(p: &Params) -> [f64; 6] {
    [p.p.x, p.p.y, p.phi, p.s.x, p.s.y, p.theta]
}

fn from_channels(c: [f64; 6]) -> Params {
    Params {
        p: Vec2::new(c[0], c[1]),
        phi: c[2],
        s: Vec2::new(c[3], c[4]),
        theta: c[5],
    }
}

/// Channels that share one keyframe easing: position and scale are each one vector
/// property with one easing for both axes. Position is not written split (x and y as
/// separate properties, each eased on its own): lottie-web accepts a split position only in
/// a layer's transform and draws nothing at all when a shape group's transform holds one,
/// and baked levels are shape groups. The error check below sees the shared easing, so the
/// bound holds; smooth motion may just need a few more keys.
const GROUPS: [&[usize]; 4] = [&[0, 1], &[2], &[3, 4], &[5]];

/// The least-squares fit of the easing `y(u) = 3(1−u)²u·y1 + 3(1−u)u²·y2 + u³` (a CSS
/// curve with x handles at 1/3 and 2/3) to normalised samples `(u, y)`, accumulated one
/// sample at a time so that testing a span allocates nothing.
#[derive(Clone, Copy, Default)]
struct EaseFit {
    a11: f64,
    a12: f64,
    a22: f64,
    r1: f64,
    r2: f64,
    any: bool,
}

impl EaseFit {
    fn add(&mut self, u: f64, y: f64) {
        let b1 = 3.0 * (1.0 - u) * (1.0 - u) * u;
        let b2 = 3.0 * (1.0 - u) * u * u;
        let t = y - u * u * u;
        self.a11 += b1 * b1;
        self.a12 += b1 * b2;
        self.a22 += b2 * b2;
        self.r1 += b1 * t;
        self.r2 += b2 * t;
        self.any = true;
    }

    /// `(y1, y2)`; linear when there was nothing to fit or the system is singular.
    fn solve(&self) -> (f64, f64) {
        let linear = (1.0 / 3.0, 2.0 / 3.0);
        if !self.any {
            return linear;
        }
        let det = self.a11 * self.a22 - self.a12 * self.a12;
        if det.abs() < 1e-18 {
            return linear;
        }
        (
            (self.r1 * self.a22 - self.r2 * self.a12) / det,
            (self.a11 * self.r2 - self.a12 * self.r1) / det,
        )
    }
}

fn ease_at((y1, y2): (f64, f64), u: f64) -> f64 {
    3.0 * (1.0 - u) * (1.0 - u) * u * y1 + 3.0 * (1.0 - u) * u * u * y2 + u * u * u
}

/// Per-group easings from sample `i` to sample `j`, fitted to the samples between.
fn fit_eases(frames: &[f64], ps: &[[f64; 6]], i: usize, j: usize) -> [(f64, f64); 4] {
    let span = frames[j] - frames[i];
    GROUPS.map(|chans| {
        let mut fit = EaseFit::default();
        for &c in chans {
            let d = ps[j][c] - ps[i][c];
            if d.abs() > 1e-9 {
                for m in i + 1..j {
                    fit.add((frames[m] - frames[i]) / span, (ps[m][c] - ps[i][c]) / d);
                }
            }
        }
        fit.solve()
    })
}

/// The parameters a player draws at sample `m` between keys `i` and `j` eased by `eases`.
fn rebuilt(
    frames: &[f64],
    ps: &[[f64; 6]],
    eases: &[(f64, f64); 4],
    (i, j): (usize, usize),
    m: usize,
) -> [f64; 6] {
    let u = (frames[m] - frames[i]) / (frames[j] - frames[i]);
    let mut v = ps[i];
    for (g, chans) in GROUPS.iter().enumerate() {
        let y = ease_at(eases[g], u);
        for &c in *chans {
            v[c] = ps[i][c] + (ps[j][c] - ps[i][c]) * y;
        }
    }
    v
}

/// Sampled transforms thinned to the keys that reproduce them: see [`bake_rigid`].
#[derive(Clone, Debug)]
pub struct BakedRigid {
    anchor: Point,
    /// Frame of each kept key.
    frames: Vec<f64>,
    /// Channels at each kept key.
    ps: Vec<[f64; 6]>,
    /// Per-group easing from each kept key to the next.
    eases: Vec<[(f64, f64); 4]>,
}

/// Bakes sampled transforms into keys of at most two skew-free levels that reproduce
/// every sample within `tolerance`; the first sample's transform should be the identity
/// when the levels must be neutral before the samples begin. Between kept samples every
/// channel follows a fitted Bézier easing, so smooth motion needs few keys.
pub fn bake_rigid(samples: &[RigidSample], anchor: Point, tolerance: f64) -> BakedRigid {
    let mut params_list: Vec<Params> = Vec::with_capacity(samples.len());
    for s in samples {
        let p = params(s.m, anchor, params_list.last());
        params_list.push(p);
    }
    let ps: Vec<[f64; 6]> = params_list.iter().map(channels).collect();
    let frames: Vec<f64> = samples.iter().map(|s| s.frame).collect();
    let err = |m: usize, rec: &[f64; 6]| {
        let a = from_channels(*rec).affine(anchor);
        let s = &samples[m];
        s.points
            .iter()
            .map(|q| ((a * *q) - (s.m * *q)).hypot())
            .fold(0.0, f64::max)
            * s.gain
    };
    let kept = greedy(samples.len(), |i, j| {
        let eases = fit_eases(&frames, &ps, i, j);
        (i + 1..j).all(|m| err(m, &rebuilt(&frames, &ps, &eases, (i, j), m)) <= tolerance)
    });
    BakedRigid {
        anchor,
        eases: kept
            .windows(2)
            .map(|w| fit_eases(&frames, &ps, w[0], w[1]))
            .collect(),
        frames: kept.iter().map(|&i| frames[i]).collect(),
        ps: kept.iter().map(|&i| ps[i]).collect(),
    }
}

impl BakedRigid {
    /// The keys as transform levels, outermost first, for the samples moved by `shift`:
    /// the same motion about an anchor `shift` away (position and anchor move with it, the
    /// rest is the same).
    pub fn levels(&self, shift: Vec2) -> Vec<Transform> {
        let BakedRigid {
            anchor,
            frames,
            ps,
            eases,
        } = self;
        let anchor = *anchor + shift;
        let keys = |group: usize, f: &dyn Fn(&[f64; 6]) -> Value| -> Prop {
            Prop::keyed(
                (frames.iter().zip(ps))
                    .enumerate()
                    .map(|(n, (&t, p))| {
                        Keyframe::written(
                            N::coord(t),
                            f(p),
                            eases.get(n).map(|e| {
                                let (y1, y2) = e[group];
                                from_css([1.0 / 3.0, y1, 2.0 / 3.0, y2])
                            }),
                            false,
                        )
                    })
                    .collect(),
            )
        };
        let position = keys(0, &|c| {
            Value::Vec(vec![N::coord(c[0] + shift.x), N::coord(c[1] + shift.y)])
        });
        let scale = keys(2, &|c| {
            Value::Vec(vec![N::coord(c[3] * 100.0), N::coord(c[4] * 100.0)])
        });
        let phi = keys(1, &|c| Value::Scalar(N::coord(c[2].to_degrees())));
        let a = Prop::fixed(Value::Vec(vec![N::coord(anchor.x), N::coord(anchor.y)]));
        let needs_inner = ps.iter().any(|p| p[5].abs() > 1e-9);
        if !needs_inner {
            return vec![Transform {
                a: Some(a),
                p: Some(position),
                s: Some(scale),
                r: Some(phi),
                o: None,
                ..Transform::empty()
            }];
        }
        let theta = keys(3, &|c| Value::Scalar(N::coord(c[5].to_degrees())));
        vec![
            Transform {
                a: None,
                p: Some(position),
                s: Some(scale),
                r: Some(phi),
                o: None,
                ..Transform::empty()
            },
            Transform {
                a: Some(a),
                p: None,
                s: None,
                r: Some(theta),
                o: None,
                ..Transform::empty()
            },
        ]
    }
}

/// Bakes sampled outlines of one path (same topology at every sample; `frames[k]` with
/// `shapes[k]`) into keyframed Lottie paths, one property per contour, within `tolerance`
/// after scaling by `gain` (how much the path's placement magnifies lengths).
pub fn bake_paths(frames: &[f64], shapes: &[Vec<Contour>], gain: f64, tolerance: f64) -> Vec<Prop> {
    let kept = greedy(frames.len(), |i, j| {
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
                .map(|(n, &i)| {
                    Keyframe::written(
                        N::coord(frames[i]),
                        Value::Bezier(Box::new(shapes[i][c].to_bezier())),
                        (n + 1 < kept.len()).then_some(LINEAR),
                        false,
                    )
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
