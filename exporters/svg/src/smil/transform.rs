//! A track's transform as nested SMIL groups.
//!
//! The model composes a shape's transform from windows (see [`gmotion::motion`]): segments
//! sharing a window nest with the earlier-listed one outside, and each later window sits
//! outside every earlier one, since it acts on the state they left. Every segment becomes one
//! group: `R(t) = T(pivot)·Πcᵢ(f(t))·Πcᵢ(f(t₀))⁻¹·T(−pivot)`, with the animated product as
//! additive `animateTransform`s on the group and the static factors folded into the
//! `transform` attributes of this group and the next inner one. Consecutive windows of one
//! motion are joined first. A segment with a non-cubic easing keeps its components and has
//! its progress sampled; one SMIL cannot say at all (Alexa interpolation, a blend of several
//! cells, a matrix or two-axis skew component) is sampled and written as
//! `translate·rotate·scale·skewX` keys. Sampled keys are reduced to a tolerance measured in
//! canvas units at the shape's corners.
//!
//! The segments' `start` transforms are checked against what the nesting produces; where
//! they differ (the state jumps), a group with discrete keys applies the difference. A track
//! with more than [`MAX_GROUPS`] windows is sampled as a whole into one group.

mod follow;

use kurbo::{Affine, Point};

use super::decompose::Decomposed;
use gmotion::keyframe::reduce::ramer_douglas_peucker;
use gmotion::keyframe::sample::{fraction, frame_times, sample_times, sampled_progress};
use gmotion::keyframe::{Format, Key, Piece, progress_keys};
use gmotion::motion::component::product_at;
use gmotion::motion::{Component, Interp, MotionKind, MotionSeg, Track};
use gmotion::tolerance::PROGRESS;

/// A SMIL `animateTransform` type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `translate`: two numbers.
    Translate,
    /// `rotate`: an angle in degrees.
    Rotate,
    /// `scale`: two factors.
    Scale,
    /// `skewX`: an angle in degrees.
    SkewX,
    /// `skewY`: an angle in degrees.
    SkewY,
    /// An `animateMotion` along [`TransformAnim::path`] (turning with its tangent when
    /// `auto`): the arc-length fraction travelled, in the first number.
    Motion {
        /// `rotate="auto"`.
        auto: bool,
    },
}

impl Kind {
    /// The SMIL `type` attribute value.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Translate => "translate",
            Kind::Rotate => "rotate",
            Kind::Scale => "scale",
            Kind::SkewX => "skewX",
            Kind::SkewY => "skewY",
            Kind::Motion { .. } => "motion",
        }
    }
}

/// One `animateTransform` (additive, post-multiplied onto its group's transform), or an
/// `animateMotion` (alone in its group, so its order among them never matters).
#[derive(Clone, Debug)]
pub struct TransformAnim {
    /// Which transform type.
    pub kind: Kind,
    /// Keys; one-number types use the first entry.
    pub keys: Vec<Key<[f64; 2]>>,
    /// Jump from key to key instead of interpolating.
    pub discrete: bool,
    /// The path data an `animateMotion` travels ([`Kind::Motion`] only).
    pub path: Option<String>,
}

/// One nested group: a static transform and the animations multiplied onto it.
#[derive(Clone, Debug)]
pub struct Nested {
    /// The group's `transform` attribute.
    pub base: Affine,
    /// Animations in application order (the first is outermost).
    pub anims: Vec<TransformAnim>,
}

/// The groups that wrap a unit node, outermost first, and the static transform of the
/// innermost group that holds the node itself.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Animated groups.
    pub layers: Vec<Nested>,
    /// The innermost group's transform.
    pub inner: Affine,
    /// Segments written exactly.
    pub exact: usize,
    /// Segments that were sampled and reduced.
    pub baked: usize,
}

/// Most window groups written as nested groups. Every group's static transform is rounded
/// (to 1e-6 and 1e-4 user units), and rounding errors add up with depth: a track with more
/// windows than this (data-driven transitions have one per frame) is sampled as a whole into
/// one group instead, which also keeps the document small.
pub const MAX_GROUPS: usize = 24;

/// Settings for planning.
#[derive(Clone, Copy, Debug)]
pub struct Ctx {
    /// The animation's duration; nothing after it is written.
    pub dur: f64,
    /// Largest allowed error of baked motion, in canvas units.
    pub tolerance: f64,
    /// Samples per second when baking.
    pub rate: f64,
    /// The animation's frame rate: every frame instant is sampled too, so that baked motion
    /// is within the tolerance where gmotion renders its frames (between uniform samples a
    /// fast curve can stray further).
    pub fps: f64,
}

impl Ctx {
    /// The frame instants inside `[a, b]`.
    fn frame_times(&self, a: f64, b: f64) -> Vec<f64> {
        frame_times(a, b, self.fps)
    }
}

/// A group before its static factors are folded into its neighbours.
struct RawLayer {
    prefix: Affine,
    anims: Vec<TransformAnim>,
    suffix: Affine,
}

/// How a segment turned out.
enum SegLayer {
    /// It never moves within the document.
    Identity,
    /// Written as its components; `true` when the progress was sampled.
    Exact(RawLayer, bool),
}

/// Plans the groups for a rigid track whose unit node sits under `parent` (its parent's
/// transform to the canvas); `corners` are the shape's rest bounding box corners on the
/// canvas. `None` when nothing moves; an error when `parent` cannot be inverted.
pub fn plan(
    track: &Track,
    parent: Affine,
    corners: &[Point; 4],
    ctx: &Ctx,
) -> Result<Option<Plan>, &'static str> {
    let n = track.motions.partition_point(|s| s.t0 < ctx.dur);
    let segs = &track.motions[..n];
    if segs.is_empty() {
        return Ok(None);
    }
    let parent_inv = invert(parent).ok_or("its parent transform is singular")?;
    let groups = merge_windows(segs, corners);
    if groups.len() > MAX_GROUPS {
        return Ok(Some(whole_track(track, parent, parent_inv, corners, ctx)));
    }
    let (mut exact, mut baked) = (0, 0);
    // The transform the nesting holds after the previous group, and from when.
    let mut acc = Affine::IDENTITY;
    let mut acc_from = f64::NEG_INFINITY;
    let mut nested: Vec<Vec<RawLayer>> = Vec::with_capacity(groups.len());
    for (gi, group) in groups.iter().enumerate() {
        // A group plays until the next begins or its last segment ends, whichever is
        // first; then the model holds the next group's start.
        let next_t0 = groups.get(gi + 1).map_or(ctx.dur, |g| g[0].t0.min(ctx.dur));
        let last_t1 = group[group.len() - 1].t1;
        let end = if gi + 1 < groups.len() {
            last_t1.min(next_t0)
        } else {
            next_t0
        };
        let ends: Vec<f64> = group.iter().map(|s| s.t1.min(end).max(s.t0)).collect();
        let mut layers = Vec::with_capacity(group.len() + 1);
        for (k, seg) in group.iter().enumerate() {
            let a = seg.t0.max(0.0);
            let b = ends[k].max(a);
            let w = Window {
                group,
                k,
                a,
                b,
                corners,
                ctx,
            };
            match exact_layer(&w) {
                Some(SegLayer::Identity) => {}
                Some(SegLayer::Exact(l, sampled)) => {
                    if sampled {
                        baked += 1;
                    } else {
                        exact += 1;
                    }
                    layers.push(l);
                }
                None => {
                    baked += 1;
                    layers.push(baked_layer(&w));
                }
            }
        }
        let start = group[0].start;
        if max_gap(start, acc, corners) > 1e-7 {
            let Some(c) = invert(acc).map(|inv| start * inv) else {
                return Ok(Some(whole_track(track, parent, parent_inv, corners, ctx)));
            };
            layers.push(jump_layer(c, group[0].t0.min(acc_from)));
        }
        acc = group
            .iter()
            .zip(&ends)
            .fold(Affine::IDENTITY, |m, (s, &e)| m * s.relative_at(e))
            * start;
        acc_from = last_t1;
        nested.push(layers);
    }
    let (layers, inner) = fold(nested.into_iter().rev().flatten(), parent_inv, parent);
    let (layers, inner) = super::merge::merge(layers, inner);
    Ok(Some(Plan {
        layers,
        inner,
        exact,
        baked,
    }))
}

/// The segments grouped by window, with consecutive windows of one motion (a motion cut by
/// later slices) joined into one segment: such windows telescope, so one group plays them.
fn merge_windows(segs: &[MotionSeg], corners: &[Point; 4]) -> Vec<Vec<MotionSeg>> {
    let mut groups: Vec<Vec<MotionSeg>> = Vec::new();
    for g in segs.chunk_by(|a, b| a.t0 == b.t0) {
        if let ([next], Some([prev])) = (g, groups.last_mut().map(Vec::as_mut_slice))
            && prev.t1 == next.t0
            && prev.timing == next.timing
            && same_motion(&prev.kind, &next.kind)
            && max_gap(next.start, prev.relative_at(prev.t1) * prev.start, corners) <= 1e-7
        {
            prev.t1 = next.t1;
            continue;
        }
        groups.push(g.to_vec());
    }
    groups
}

/// True when two rigid motions are the same motion.
fn same_motion(a: &MotionKind, b: &MotionKind) -> bool {
    match (a, b) {
        (
            MotionKind::Rigid {
                pivot: p,
                blend: x,
                interp: i,
            },
            MotionKind::Rigid {
                pivot: q,
                blend: y,
                interp: j,
            },
        ) => {
            p == q
                && i == j
                && x.len() == y.len()
                && x.iter()
                    .zip(y.iter())
                    .all(|((w, c), (v, d))| w == v && c[..] == d[..])
        }
        _ => false,
    }
}

/// Folds each layer's static factors into its group and the next inner one.
fn fold(
    raw: impl Iterator<Item = RawLayer>,
    outer: Affine,
    parent: Affine,
) -> (Vec<Nested>, Affine) {
    let mut pre = outer;
    let mut layers = Vec::new();
    for l in raw {
        if l.anims.is_empty() {
            pre = pre * l.prefix * l.suffix;
            continue;
        }
        layers.push(Nested {
            base: pre * l.prefix,
            anims: l.anims,
        });
        pre = l.suffix;
    }
    (layers, pre * parent)
}

/// The inverse of `m`, unless it is (numerically) singular.
fn invert(m: Affine) -> Option<Affine> {
    let det = m.determinant();
    let scale = m.as_coeffs()[..4]
        .iter()
        .fold(0.0f64, |s, v| s.max(v.abs()));
    (det.is_finite() && det.abs() > 1e-12 * scale.max(1e-300) * scale.max(1e-300))
        .then(|| m.inverse())
}

/// Largest distance between where `a` and `b` put the corners.
fn max_gap(a: Affine, b: Affine, corners: &[Point; 4]) -> f64 {
    corners
        .iter()
        .map(|&q| (a * q - b * q).hypot())
        .fold(0.0, f64::max)
}

/// The SMIL type that animates the component exactly, if there is one.
fn smil_kind(c: &Component) -> Option<Kind> {
    match *c {
        Component::Translate(_) => Some(Kind::Translate),
        Component::Rotate(_) => Some(Kind::Rotate),
        Component::Scale(_) => Some(Kind::Scale),
        Component::Skew(_, 0.0) => Some(Kind::SkewX),
        Component::Skew(0.0, _) => Some(Kind::SkewY),
        Component::Skew(..) | Component::Matrix(_) => None,
    }
}

/// The component's SMIL value at progress `p` (linear in `p`, as the model interpolates).
fn smil_value(c: &Component, p: f64) -> [f64; 2] {
    match *c {
        Component::Translate(d) => [d.x * p, d.y * p],
        Component::Rotate(a) => [a * p, 0.0],
        Component::Scale(k) => [1.0 + (k.x - 1.0) * p, 1.0 + (k.y - 1.0) * p],
        Component::Skew(ax, ay) => [if ay == 0.0 { ax * p } else { ay * p }, 0.0],
        Component::Matrix(_) => [0.0, 0.0],
    }
}

/// One segment of a window group, over `[a, b]`, with what measuring its error needs.
struct Window<'g> {
    group: &'g [MotionSeg],
    k: usize,
    a: f64,
    b: f64,
    corners: &'g [Point; 4],
    ctx: &'g Ctx,
}

/// Sample instants of a window with, at each, the transform of the segments outside this
/// one and where the shape's corners are before this one acts.
struct Samples {
    ts: Vec<f64>,
    outer: Vec<Affine>,
    points: Vec<[Point; 4]>,
}

impl Window<'_> {
    fn seg(&self) -> &MotionSeg {
        &self.group[self.k]
    }

    fn samples(&self) -> Samples {
        let (act0, act1) = self.seg().timing.active();
        let mut extra = vec![act0, act1];
        extra.extend(self.ctx.frame_times(self.a, self.b));
        let ts = sample_times(self.a, self.b, self.ctx.rate, 8, &extra);
        let product = |segs: &[MotionSeg], t: f64| {
            segs.iter()
                .fold(Affine::IDENTITY, |m, s| m * s.relative_at(t))
        };
        let outer = ts
            .iter()
            .map(|&t| product(&self.group[..self.k], t))
            .collect();
        let points = ts
            .iter()
            .map(|&t| {
                let inner = product(&self.group[self.k + 1..], t) * self.group[0].start;
                self.corners.map(|q| inner * q)
            })
            .collect();
        Samples { ts, outer, points }
    }
}

impl Samples {
    /// How far the corners land from the truth at sample `i` when this segment plays `m`.
    fn error(&self, i: usize, m: Affine, truth: Affine) -> f64 {
        let o = self.outer[i];
        self.points[i]
            .iter()
            .map(|&q| (o * (m * q) - o * (truth * q)).hypot())
            .fold(0.0, f64::max)
    }

    /// Keeps the samples (of values `vs`, played by `play`) that the tolerance needs.
    fn reduce<V: Copy>(
        &self,
        tolerance: f64,
        vs: &[V],
        lerp: impl Fn(V, V, f64) -> V,
        play: impl Fn(V) -> Affine,
    ) -> Vec<usize> {
        let truth: Vec<Affine> = vs.iter().map(|&v| play(v)).collect();
        ramer_douglas_peucker(self.ts.len(), tolerance, |i, lo, hi| {
            let v = lerp(vs[lo], vs[hi], fraction(&self.ts, i, lo, hi));
            self.error(i, play(v), truth[i])
        })
    }
}

/// The layer of a single-entry linear rigid segment, whose components SMIL animates
/// exactly; the progress is exact for cubic easings and sampled for others. `None` when
/// the segment needs baking as a whole.
fn exact_layer(w: &Window<'_>) -> Option<SegLayer> {
    let seg = w.seg();
    if let MotionKind::Follow(f) = &seg.kind {
        return follow::layer(w, f);
    }
    let MotionKind::Rigid {
        pivot,
        blend,
        interp: Interp::Linear,
    } = &seg.kind
    else {
        return None;
    };
    let [(_, comps)] = &blend[..] else {
        return None;
    };
    let comps: Vec<Component> = comps.iter().filter(|c| !c.is_identity()).copied().collect();
    let kinds: Vec<Kind> = comps.iter().map(smil_kind).collect::<Option<_>>()?;
    let p_ref = seg.timing.progress(seg.t0);
    let held = invert(product_at(&comps, p_ref))?;
    let piece = Piece {
        t0: w.a,
        t1: w.b,
        timing: &seg.timing,
    };
    let start = seg.timing.progress(w.a);
    let (keys, sampled) = match progress_keys(&[piece], start, |_, p| p, Format::UnitBox) {
        Some(keys) => (keys, false),
        None => {
            let s = w.samples();
            let about = |m: Affine| {
                Affine::translate(pivot.to_vec2()) * m * Affine::translate(-pivot.to_vec2())
            };
            let play = |p: f64| about(product_at(&comps, p) * held);
            let keys = sampled_progress(&seg.timing, &s.ts, w.ctx.tolerance, |i, played, truth| {
                s.error(i, play(played), play(truth))
            });
            (keys, true)
        }
    };
    if comps.is_empty() || keys.iter().all(|k| PROGRESS.same(k.v, p_ref)) {
        return Some(SegLayer::Identity);
    }
    let anims = comps
        .iter()
        .zip(kinds)
        .map(|(c, kind)| TransformAnim {
            kind,
            keys: keys
                .iter()
                .map(|k| Key {
                    t: k.t,
                    v: smil_value(c, k.v),
                    ease: k.ease,
                })
                .collect(),
            discrete: false,
            path: None,
        })
        .collect();
    let to_pivot = Affine::translate(pivot.to_vec2());
    let layer = RawLayer {
        prefix: to_pivot,
        anims,
        suffix: held * to_pivot.inverse(),
    };
    Some(SegLayer::Exact(layer, sampled))
}

/// Samples a segment as `translate·rotate·scale·skewX` and keeps what the tolerance needs.
fn baked_layer(w: &Window<'_>) -> RawLayer {
    let seg = w.seg();
    let s = w.samples();
    let truth: Vec<Affine> = s.ts.iter().map(|&t| seg.relative_at(t)).collect();
    let dec = decompose_all(&truth);
    let keep = s.reduce(
        w.ctx.tolerance,
        &dec,
        |x, y, f| x.lerp(y, f),
        |d| d.to_affine(),
    );
    let keys: Vec<(f64, Decomposed)> = keep.iter().map(|&i| (s.ts[i], dec[i])).collect();
    RawLayer {
        prefix: Affine::IDENTITY,
        anims: decomposed_anims(&keys, false),
        suffix: Affine::IDENTITY,
    }
}

/// Decompositions of consecutive samples, with rotations unwrapped to be continuous.
fn decompose_all(ms: &[Affine]) -> Vec<Decomposed> {
    let mut prev = Decomposed::IDENTITY;
    ms.iter()
        .map(|&m| {
            let d = lossy(m).unwrapped_after(&prev);
            prev = d;
            d
        })
        .collect()
}

/// The decomposition of `m`, nudging a singular map (which paints nothing visible) to the
/// nearest one that has one.
fn lossy(m: Affine) -> Decomposed {
    Decomposed::of(m).unwrap_or_else(|| {
        let [a, b, c, d, e, f] = m.as_coeffs();
        Decomposed::of(Affine::new([a + 1e-6, b, c, d + 1e-6, e, f])).unwrap_or(Decomposed {
            translate: [e, f],
            scale: [1e-6, 1e-6],
            ..Decomposed::IDENTITY
        })
    })
}

/// `translate`, `rotate`, `scale` and `skewX` animations through the given keys.
fn decomposed_anims(keys: &[(f64, Decomposed)], discrete: bool) -> Vec<TransformAnim> {
    let channel = |kind: Kind, get: &dyn Fn(&Decomposed) -> [f64; 2]| TransformAnim {
        kind,
        keys: keys.iter().map(|(t, d)| Key::linear(*t, get(d))).collect(),
        discrete,
        path: None,
    };
    [
        channel(Kind::Translate, &|d| d.translate),
        channel(Kind::Rotate, &|d| [d.rotate, 0.0]),
        channel(Kind::Scale, &|d| d.scale),
        channel(Kind::SkewX, &|d| [d.skew_x, 0.0]),
    ]
    .into_iter()
    .filter(|a| {
        let neutral = if a.kind == Kind::Scale {
            [1.0, 1.0]
        } else {
            [0.0, 0.0]
        };
        a.keys
            .iter()
            .any(|k| (k.v[0] - neutral[0]).abs() > 1e-12 || (k.v[1] - neutral[1]).abs() > 1e-12)
    })
    .collect()
}

/// A jump by `c` at `t0` (static when the jump is at or before the document start).
fn jump_layer(c: Affine, t0: f64) -> RawLayer {
    if t0 <= 0.0 {
        return RawLayer {
            prefix: c,
            anims: Vec::new(),
            suffix: Affine::IDENTITY,
        };
    }
    let keys = [(0.0, Decomposed::IDENTITY), (t0, lossy(c))];
    RawLayer {
        prefix: Affine::IDENTITY,
        anims: decomposed_anims(&keys, true),
        suffix: Affine::IDENTITY,
    }
}

/// The whole track's transform sampled into one group: for tracks with very many windows,
/// and for a state that jumps from a singular transform (no correction group can say that).
fn whole_track(
    track: &Track,
    parent: Affine,
    parent_inv: Affine,
    corners: &[Point; 4],
    ctx: &Ctx,
) -> Plan {
    let mut extra: Vec<f64> = Vec::new();
    for s in &track.motions {
        let (x, y) = s.timing.active();
        // Just before each boundary too, so that a jump there stays a jump.
        extra.extend([s.t0, s.t1, x, y, s.t0 - 1e-6, s.t1 - 1e-6]);
    }
    extra.extend(ctx.frame_times(0.0, ctx.dur));
    let ts = sample_times(0.0, ctx.dur, ctx.rate, 8, &extra);
    let truth: Vec<Affine> = ts.iter().map(|&t| track.transform_at(t)).collect();
    let dec = decompose_all(&truth);
    let keep = ramer_douglas_peucker(ts.len(), ctx.tolerance, |i, lo, hi| {
        let m = dec[lo].lerp(dec[hi], fraction(&ts, i, lo, hi)).to_affine();
        max_gap(m, truth[i], corners)
    });
    let keys: Vec<(f64, Decomposed)> = keep.iter().map(|&i| (ts[i], dec[i])).collect();
    let raw = RawLayer {
        prefix: Affine::IDENTITY,
        anims: decomposed_anims(&keys, false),
        suffix: Affine::IDENTITY,
    };
    let (layers, inner) = fold(std::iter::once(raw), parent_inv, parent);
    Plan {
        layers,
        inner,
        exact: 0,
        baked: track.motions.len(),
    }
}
