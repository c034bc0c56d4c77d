//! Tracks as Lottie transform levels and keyframes.
//!
//! A track's transform is, for `t` in window `k`, `R_i(t)·…·R_j(t)·start_k`, every `R`
//! being identity before its window and holding its end value after it. Written as nested
//! levels, outermost first — the last window's segments (earliest-listed outside), a hold
//! correction `J_k = start_k·(end of window k−1)⁻¹` where the chain jumps, then the earlier
//! windows — the player composes exactly this product.
//!
//! A segment is exact when it is a single-entry linear blend of translations, rotations and
//! scales with a Bézier easing: each component is then an affine function of progress, so
//! `F(p)` packs into levels `T(pos)·R(rot)·S(scale)·T(-anchor)` whose channels a player
//! interpolates along the same easing curve. Anything else (Alexa interpolation that
//! differs from the linear one, bilinear blends, skews, matrices) is sampled and reduced
//! ([`super::bake`]); per-vertex deformation bakes the outlines themselves.

use kurbo::{Affine, Point, Rect, Vec2};

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use super::bake::{BakedRigid, RigidSample, bake_rigid};
use super::fold::fold;
use super::geometry::{Trs, decompose, max_stretch, svd};
use super::keys::to_keyframes;
use super::model::{Keyframe, N, Prop, Transform, Value};
use gmotion::keyframe::{Format, Key, Piece, Same, progress_keys};
use gmotion::motion::grid::blend_at;
use gmotion::motion::{AttrSeg, Component, Interp, MotionKind, MotionSeg, Tint, Track, Trim};
use gmotion::scene::{Node, Paint};
use gmotion::signals::easing::Easing;
use gmotion::tolerance::COMPOSED;

/// What a shape's track becomes.
#[derive(Clone, Debug, Default)]
pub struct UnitMotion {
    /// Transform levels in canvas space, outermost first.
    pub levels: Vec<Transform>,
    /// Opacity multiplier keys.
    pub opacity: Vec<Key<f64>>,
    /// Fill tint keys.
    pub fill: Vec<Key<Tint>>,
    /// Stroke tint keys.
    pub stroke: Vec<Key<Tint>>,
    /// Stroke width multiplier keys.
    pub stroke_width: Vec<Key<f64>>,
    /// Keys of the strokes' visible part.
    pub trim: Vec<Key<Trim>>,
    /// Frames at which deformed outlines are sampled (per-vertex motion), else empty.
    pub deform_frames: Vec<f64>,
    /// Whether the transform ever scales unevenly (strokes then need outlining, since
    /// rlottie widens strokes evenly). Only looked for when [`UnitInfo::strokes`].
    pub anisotropic: bool,
}

impl UnitMotion {
    /// Whether anything changes over time.
    pub fn is_animated(&self) -> bool {
        !(self.levels.is_empty()
            && self.opacity.is_empty()
            && self.fill.is_empty()
            && self.stroke.is_empty()
            && self.stroke_width.is_empty()
            && self.trim.is_empty()
            && self.deform_frames.is_empty())
    }
}

/// Everything [`unit_motion`] needs about the shape besides its track.
#[derive(Clone, Copy, Debug)]
pub struct UnitInfo {
    /// Bounding box in canvas space (error check points).
    pub bbox: Rect,
    /// Centroid in canvas space (anchor of baked motion).
    pub centroid: Point,
    /// Whether the shape may draw a stroke, the only paint [`UnitMotion::anisotropic`]
    /// matters to. Finding it evaluates the transform frame by frame, which was the largest
    /// part of exporting thousands of filled shapes.
    pub strokes: bool,
}

/// How far apart two stroke width factors may be and still make one key value.
pub const WIDTH_FACTOR_TOLERANCE: f64 = 1e-3;

/// How far apart two trim fractions may be and still make one key value (a sampled
/// easing's keys stay this close to the trim).
pub const TRIM_TOLERANCE: f64 = 1e-4;

/// Baked windows of one export, by everything their keys depend on. A window is baked
/// about its anchor, in a frame where the anchor is the origin, so the shapes of a tag that
/// one rule moves alike, wherever they are, share one bake (the generated intersections
/// workload: 16 428 skewing windows, 959 bakes; the rest differ in the last bits of a
/// pivot or a start transform).
#[derive(Debug, Default)]
pub struct Bakes(Mutex<HashMap<Vec<u64>, Arc<BakedRigid>>>);

impl Bakes {
    /// The bake under `key`, made by `bake` the first time. Two threads may both make it;
    /// both get the same keys, as `bake` depends on nothing but `key`.
    fn get(&self, key: Vec<u64>, bake: impl FnOnce() -> BakedRigid) -> Arc<BakedRigid> {
        let lock = || self.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(b) = lock().get(&key) {
            return b.clone();
        }
        let made = Arc::new(bake());
        lock().entry(key).or_insert(made).clone()
    }
}

/// Converts a track. `frames` is the animation's frame count, `tolerance` the baking
/// error bound in canvas units; `bakes` is shared by the tracks of one export.
pub fn unit_motion(
    track: &Track,
    info: UnitInfo,
    fps: f64,
    frames: usize,
    tolerance: f64,
    bakes: &Bakes,
) -> UnitMotion {
    let mut out = UnitMotion {
        opacity: attr_keys(&track.opacity, fps, 1.0, |v| v, 1e-3),
        fill: attr_keys(&track.fill, fps, Tint::NONE, |t| t, 0.5 / 255.0),
        stroke: attr_keys(&track.stroke, fps, Tint::NONE, |t| t, 0.5 / 255.0),
        stroke_width: attr_keys(&track.stroke_width, fps, 1.0, |v| v, WIDTH_FACTOR_TOLERANCE),
        trim: attr_keys(&track.trim, fps, Trim::REST, |v| v, TRIM_TOLERANCE),
        ..UnitMotion::default()
    };
    if track.motions.is_empty() {
        return out;
    }
    if track.deforms() {
        out.deform_frames = (0..=frames).map(|f| f as f64).collect();
        return out;
    }
    out.anisotropic = info.strokes
        && !always_even(track)
        && (0..=frames).any(|f| !is_even(track.transform_at(f as f64 / fps)));
    let windows = windows(&track.motions);
    // Many windows (smoothed or data-driven motion has one per frame) would nest one group
    // level each; bake the whole track instead, into at most two levels.
    if windows.len() > MAX_WINDOW_LEVELS {
        out.levels = fold(whole_track_levels(track, info, fps, frames, tolerance));
        return out;
    }
    let mut prev_end = Affine::IDENTITY;
    let mut per_window: Vec<Vec<Transform>> = Vec::with_capacity(windows.len());
    for (k, w) in windows.iter().enumerate() {
        let mut levels = Vec::new();
        let t1 = windows.get(k + 1).map_or(f64::INFINITY, |n| n.t0);
        for (s, seg) in w.segs.iter().enumerate() {
            let end = seg.t1.min(t1);
            let exact = exact_levels(seg, end, fps)
                .or_else(|| follow_levels(seg, end, fps, info, tolerance));
            match exact {
                Some(mut l) => levels.append(&mut l),
                None => levels.extend(baked_levels(w, s, end, info, fps, tolerance, bakes)),
            }
        }
        // The correction is applied inside this window's own segments.
        let jump = w.start * prev_end.inverse();
        levels.extend(hold_levels(jump, w.t0 * fps));
        prev_end = w.segs.iter().fold(Affine::IDENTITY, |acc, seg| {
            acc * seg.relative_at(seg.t1.min(t1))
        }) * w.start;
        per_window.push(levels);
    }
    out.levels = fold(per_window.into_iter().rev().flatten().collect());
    out
}

/// Above this many motion windows a track is baked as a whole rather than one group level
/// per window, which keeps the layer tree shallow for players.
const MAX_WINDOW_LEVELS: usize = 8;

/// The whole track's transform sampled at every frame and at every window boundary, baked
/// and reduced within `tolerance`.
fn whole_track_levels(
    track: &Track,
    info: UnitInfo,
    fps: f64,
    frames: usize,
    tolerance: f64,
) -> Vec<Transform> {
    let corners = [
        info.bbox.origin(),
        Point::new(info.bbox.x1, info.bbox.y0),
        Point::new(info.bbox.x0, info.bbox.y1),
        Point::new(info.bbox.x1, info.bbox.y1),
    ];
    let mut times: Vec<f64> = (0..=frames).map(|f| f as f64 / fps).collect();
    times.extend(track.motions.iter().flat_map(|m| [m.t0, m.t1]));
    times.retain(|t| t.is_finite() && *t >= 0.0 && *t <= frames as f64 / fps);
    times.sort_by(f64::total_cmp);
    times.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let samples: Vec<RigidSample> = times
        .iter()
        .map(|&t| RigidSample {
            frame: t * fps,
            m: track.transform_at(t),
            points: corners,
            gain: 1.0,
        })
        .collect();
    bake_rigid(&samples, info.centroid, tolerance).levels(Vec2::ZERO)
}

/// Whether anything in `node` may draw a stroke: a stroked path, or content the export
/// draws through other paths (a pattern paint's tile, a clip path, a mask).
pub fn may_stroke(node: &Node) -> bool {
    match node {
        Node::Path(p) => {
            p.stroke.is_some()
                || p.fill
                    .as_ref()
                    .is_some_and(|f| matches!(f.paint, Paint::Pattern(_)))
        }
        Node::Group(g) => {
            g.clip_path.is_some() || g.mask.is_some() || g.children.iter().any(may_stroke)
        }
        Node::Image(_) => false,
    }
}

/// Whether every transform of `track` is a similarity, known from its motions without
/// sampling it frame by frame (that scan was the largest cost of a large export's strokes):
/// each start is one, and every component translates, rotates or scales evenly. Such
/// matrices (`[a −b; b a]`) stay such under products, weighted blends and Alexa's powers.
fn always_even(track: &Track) -> bool {
    track.motions.iter().all(|m| {
        is_even(m.start)
            && match &m.kind {
                MotionKind::Rigid { blend, .. } => blend.iter().all(|(_, comps)| {
                    comps.iter().all(|c| match c {
                        Component::Translate(_) | Component::Rotate(_) => true,
                        Component::Scale(k) => k.x == k.y,
                        Component::Skew(..) | Component::Matrix(_) => false,
                    })
                }),
                MotionKind::Vertex { .. } => false,
                // A turn and a move, carried by its frame.
                MotionKind::Follow(f) => is_even(f.frame),
            }
    })
}

/// Whether `m` scales every direction by the same factor (a similarity).
pub fn is_even(m: Affine) -> bool {
    let (_, s, _) = svd(m);
    (s.x.abs() - s.y.abs()).abs() <= 1e-6 * s.x.abs().max(s.y.abs()).max(1e-12)
}

/// A transform window: segments sharing a start, possibly several windows of one motion
/// merged back together.
struct Window {
    t0: f64,
    start: Affine,
    segs: Vec<MotionSeg>,
}

fn same_motion(a: &MotionSeg, b: &MotionSeg) -> bool {
    let kind = match (&a.kind, &b.kind) {
        (
            MotionKind::Rigid {
                pivot: pa,
                blend: ba,
                interp: ia,
            },
            MotionKind::Rigid {
                pivot: pb,
                blend: bb,
                interp: ib,
            },
        ) => {
            pa == pb
                && ia == ib
                && ba.len() == bb.len()
                && ba
                    .iter()
                    .zip(bb.iter())
                    .all(|(x, y)| x.0 == y.0 && x.1 == y.1)
        }
        _ => false,
    };
    kind && a.timing == b.timing
}

/// Groups segments into windows and merges consecutive single-segment windows of one
/// motion (they telescope: `F(f(t))·F(f(t₀))⁻¹` over the union).
fn windows(segs: &[MotionSeg]) -> Vec<Window> {
    let mut out: Vec<Window> = Vec::new();
    for (i, seg) in segs.iter().enumerate() {
        if let Some(w) = out.last_mut()
            && w.segs.last().is_some_and(|last| last.t0 == seg.t0)
        {
            w.segs.push(seg.clone());
            continue;
        }
        let alone = segs.get(i + 1).is_none_or(|next| next.t0 != seg.t0);
        if let Some(w) = out.last_mut()
            && alone
            && let [prev] = w.segs.as_mut_slice()
            && same_motion(prev, seg)
            && (prev.t1 - seg.t0).abs() < 1e-12
            && COMPOSED.same_affine(seg.start, prev.relative_at(prev.t1) * prev.start)
        {
            prev.t1 = seg.t1;
            continue;
        }
        out.push(Window {
            t0: seg.t0,
            start: seg.start,
            segs: vec![seg.clone()],
        });
    }
    out
}

/// A channel that is an affine function of progress: `base + slope·p`.
#[derive(Clone, Copy, Debug, Default)]
struct Lin {
    base: Vec2,
    slope: Vec2,
}

impl Lin {
    fn at(&self, p: f64) -> [f64; 2] {
        let v = self.base + self.slope * p;
        [v.x, v.y]
    }
}

/// One packed level `T(pos)·R(rot·p)·S(1 + (k−1)·p)·T(-anchor)`.
#[derive(Clone, Copy, Debug)]
struct LinLevel {
    anchor: Vec2,
    pos: Lin,
    rot: Option<f64>,
    scale: Option<Vec2>,
}

impl LinLevel {
    fn new() -> LinLevel {
        LinLevel {
            anchor: Vec2::ZERO,
            pos: Lin::default(),
            rot: None,
            scale: None,
        }
    }
}

/// Packs components into levels; `None` when a component is not a translation, rotation
/// or scale.
fn pack(components: &[Component], pivot: Point) -> Option<Vec<LinLevel>> {
    let mut levels = vec![LinLevel::new()];
    for c in components.iter().filter(|c| !c.is_identity()) {
        let cur = levels.last_mut().expect("at least one level");
        match *c {
            Component::Translate(d) => {
                if cur.rot.is_none() && cur.scale.is_none() {
                    cur.pos.slope += d;
                } else {
                    let mut l = LinLevel::new();
                    l.pos.slope = d;
                    levels.push(l);
                }
            }
            Component::Rotate(a) => {
                let uniform_scale = cur.scale.is_none_or(|k| k.x == k.y);
                if uniform_scale {
                    cur.rot = Some(cur.rot.unwrap_or(0.0) + a);
                } else {
                    levels.push(LinLevel {
                        rot: Some(a),
                        ..LinLevel::new()
                    });
                }
            }
            Component::Scale(k) => {
                if cur.scale.is_none() {
                    cur.scale = Some(k);
                } else {
                    levels.push(LinLevel {
                        scale: Some(k),
                        ..LinLevel::new()
                    });
                }
            }
            Component::Skew(..) | Component::Matrix(_) => return None,
        }
    }
    levels[0].pos.base = pivot.to_vec2();
    levels.last_mut().expect("at least one level").anchor = pivot.to_vec2();
    Some(levels)
}

/// The components of a segment that can be written exactly, if it can.
fn exact_components(seg: &MotionSeg) -> Option<(&[Component], Point)> {
    let MotionKind::Rigid {
        pivot,
        blend,
        interp,
    } = &seg.kind
    else {
        return None;
    };
    let [(_, comps)] = &blend[..] else {
        return None;
    };
    if seg.timing.ease.as_cubic_bezier().is_none() && seg.timing.ease.steps().is_none() {
        return None;
    }
    if *interp == Interp::Alexa {
        // Alexa's power equals the component-wise blend for single translations,
        // rotations below a half turn and scales; check rather than enumerate.
        let linear = |p: f64| blend_at(blend, *pivot, p);
        let same = [0.25, 0.5, 0.75]
            .iter()
            .all(|&p| COMPOSED.same_affine(seg.full_at(p), linear(p)));
        if !same {
            return None;
        }
    }
    Some((comps, *pivot))
}

// Levels are made at full precision and rounded once folded (`fold`), so that composing
// them does not compound the rounding: the anchors of two levels about one point would
// then differ in the last written digit and no longer fold.
fn v2(v: [f64; 2]) -> Value {
    Value::Vec(vec![N(v[0]), N(v[1])])
}

fn scalar(x: f64) -> Value {
    Value::Scalar(N(x))
}

/// Levels writing a follow's `F(f(t))·F(f(t₀))⁻¹` for `t` in `[seg.t0, end]`: position
/// keyframes with spatial tangents ([`super::follow`]), if exact.
fn follow_levels(
    seg: &MotionSeg,
    end: f64,
    fps: f64,
    info: UnitInfo,
    tolerance: f64,
) -> Option<Vec<Transform>> {
    let b = info.bbox;
    let radius = [(b.x0, b.y0), (b.x1, b.y0), (b.x0, b.y1), (b.x1, b.y1)]
        .iter()
        .map(|&q| (Point::from(q) - info.centroid).hypot())
        .fold(0.0, f64::max)
        * max_stretch(seg.start);
    let mut out = vec![super::follow::level(seg, end, fps, radius, tolerance)?];
    let p0 = seg.timing.progress(seg.t0);
    if p0 != 0.0 {
        // Undo F(p0), innermost, so the window starts from where the shape is.
        out.extend(
            decompose(seg.full_at(p0).inverse(), Point::ORIGIN)
                .iter()
                .filter(|l| !l.is_identity())
                .map(exact_static_level),
        );
    }
    Some(out)
}

/// Levels writing `F(f(t))·F(f(t₀))⁻¹` for `t` in `[seg.t0, end]`, if exact.
fn exact_levels(seg: &MotionSeg, end: f64, fps: f64) -> Option<Vec<Transform>> {
    let (comps, pivot) = exact_components(seg)?;
    let levels = pack(comps, pivot)?;
    let piece = [Piece {
        t0: seg.t0,
        t1: end,
        timing: &seg.timing,
    }];
    let p0 = seg.timing.progress(seg.t0);
    let track = |f: &dyn Fn(f64) -> [f64; 2]| {
        let spaced = Format::Spaced {
            fps,
            tolerance: 1e-4,
        };
        progress_keys(&piece, f(p0), |_, p| f(p), spaced).expect(SAMPLED)
    };
    let mut out = Vec::with_capacity(levels.len() + 2);
    // A channel whose window ends before its change begins (a delay longer than the part
    // of the slice this window covers) has no keys and stays at its start value `f(p0)`,
    // which is not the neutral value: the position is the pivot the anchor is taken from.
    let channel =
        |f: &dyn Fn(f64) -> [f64; 2], neutral: [f64; 2], to: &dyn Fn(&[f64; 2]) -> Value| {
            prop_or_default(&track(f), f(p0), neutral, to)
        };
    for l in &levels {
        let scale = |k: Vec2| {
            move |p: f64| {
                [
                    100.0 * (1.0 + (k.x - 1.0) * p),
                    100.0 * (1.0 + (k.y - 1.0) * p),
                ]
            }
        };
        out.push(Transform {
            a: (l.anchor != Vec2::ZERO).then(|| Prop::fixed(v2([l.anchor.x, l.anchor.y]))),
            p: channel(&|p| l.pos.at(p), [0.0, 0.0], &|v| v2(*v)),
            s: l.scale
                .and_then(|k| channel(&scale(k), [100.0, 100.0], &|v| v2(*v))),
            r: l.rot
                .and_then(|a| channel(&|p| [a * p, 0.0], [0.0, 0.0], &|v| scalar(v[0]))),
            o: None,
            ..Transform::empty()
        });
    }
    if p0 != 0.0 {
        // Undo F(p0), innermost, so the window starts from where the shape is.
        let undo = seg.full_at(p0).inverse();
        out.extend(
            decompose(undo, Point::ORIGIN)
                .iter()
                .filter(|l| !l.is_identity())
                .map(exact_static_level),
        );
    }
    Some(out)
}

/// A keyed channel as a property, or `None` when it stays at `neutral`. No keys means the
/// channel holds `start` throughout.
fn prop_or_default<V: Same + Clone>(
    keys: &[Key<V>],
    start: V,
    neutral: V,
    to: impl Fn(&V) -> Value,
) -> Option<Prop> {
    let fixed = |v: &V| (!v.same(&neutral)).then(|| Prop::fixed(to(v)));
    match keys {
        [] => fixed(&start),
        [k] => fixed(&k.v),
        _ => Some(Prop::keyed(to_keyframes(keys, to))),
    }
}

/// A fixed level, rounded as written.
pub fn static_level(l: &Trs) -> Transform {
    crate::model::rounded(exact_static_level(l))
}

/// A fixed level at full precision.
fn exact_static_level(l: &Trs) -> Transform {
    Transform {
        a: (l.a != Vec2::ZERO).then(|| Prop::fixed(v2([l.a.x, l.a.y]))),
        p: (l.p != Vec2::ZERO).then(|| Prop::fixed(v2([l.p.x, l.p.y]))),
        s: (l.s != Vec2::new(1.0, 1.0)).then(|| Prop::fixed(v2([l.s.x * 100.0, l.s.y * 100.0]))),
        r: (l.r != 0.0).then(|| Prop::scalar(N(l.r))),
        o: None,
        ..Transform::empty()
    }
}

/// Levels that are the identity before `frame` and `m` from then on.
fn hold_levels(m: Affine, frame: f64) -> Vec<Transform> {
    if COMPOSED.same_affine(m, Affine::IDENTITY) {
        return Vec::new();
    }
    let levels = decompose(m, Point::ORIGIN);
    if frame <= 0.0 {
        return levels.iter().map(exact_static_level).collect();
    }
    let held = |from: Value, to: Value| {
        Prop::Animated(vec![
            Keyframe::written(N(0.0), from, None, true),
            Keyframe::written(N::coord(frame), to, None, false),
        ])
    };
    levels
        .iter()
        .map(|l| Transform {
            a: None,
            p: Some(held(v2([0.0, 0.0]), v2([l.p.x, l.p.y]))),
            s: Some(held(v2([100.0, 100.0]), v2([l.s.x * 100.0, l.s.y * 100.0]))),
            r: Some(held(scalar(0.0), scalar(l.r))),
            o: None,
            ..Transform::empty()
        })
        .collect()
}

/// Sampled levels for segment `s` of window `w` over `[seg.t0, end]`.
///
/// The levels are anchored at the shape's centroid where the window starts, and baked in
/// a frame where that anchor is the origin: every pivot taken relative to it, the window's
/// start transform reduced to its linear part (it maps the centroid to the anchor), the
/// check points relative to the centroid. The keys then depend only on what [`bake_key`]
/// lists, and shapes that move alike share them through `bakes`.
fn baked_levels(
    w: &Window,
    s: usize,
    end: f64,
    info: UnitInfo,
    fps: f64,
    tolerance: f64,
    bakes: &Bakes,
) -> Vec<Transform> {
    let anchor = w.start * info.centroid;
    let shift = anchor.to_vec2();
    let bake = || {
        let segs: Vec<MotionSeg> = w.segs.iter().map(|seg| shifted(seg, -shift)).collect();
        let seg = &segs[s];
        let start = {
            let [a, b, c, d, _, _] = w.start.as_coeffs();
            Affine::new([a, b, c, d, 0.0, 0.0])
        };
        let bbox = info.bbox - info.centroid.to_vec2();
        let corners = [
            bbox.origin(),
            Point::new(bbox.x1, bbox.y0),
            Point::new(bbox.x0, bbox.y1),
            Point::new(bbox.x1, bbox.y1),
        ];
        let sample = |t: f64| {
            // Usually no segment is outside: no product, and a gain of exactly 1.
            let gain = match &segs[..s] {
                [] => 1.0,
                outer => max_stretch(
                    outer
                        .iter()
                        .fold(Affine::IDENTITY, |acc, o| acc * o.relative_at(t)),
                ),
            };
            let inner = segs[s + 1..]
                .iter()
                .fold(Affine::IDENTITY, |acc, o| acc * o.relative_at(t))
                * start;
            RigidSample {
                frame: t * fps,
                m: seg.relative_at(t),
                points: corners.map(|c| inner * c),
                gain,
            }
        };
        let mut times = vec![seg.t0];
        let first = (seg.t0 * fps).floor() as i64 + 1;
        let last = (end * fps).ceil() as i64 - 1;
        times.extend(
            (first..=last)
                .map(|f| f as f64 / fps)
                .filter(|t| *t > seg.t0 && *t < end),
        );
        if end > seg.t0 {
            times.push(end);
        }
        let samples: Vec<RigidSample> = times.iter().map(|t| sample(*t)).collect();
        bake_rigid(&samples, Point::ORIGIN, tolerance)
    };
    match bake_key(w, s, end, info, shift, fps, tolerance) {
        Some(key) => bakes.get(key, bake).levels(shift),
        None => bake().levels(shift),
    }
}

/// `seg` with its pivot moved by `by` (the same motion in a frame moved by `by`).
fn shifted(seg: &MotionSeg, by: Vec2) -> MotionSeg {
    let mut seg = seg.clone();
    match &mut seg.kind {
        MotionKind::Rigid { pivot, .. } => *pivot += by,
        MotionKind::Follow(f) => *f = Arc::new(f.carried(Affine::translate(by))),
        MotionKind::Vertex { .. } => {}
    }
    seg
}

/// Everything [`baked_levels`] computes its keys from, as bits: the frame rate, the bound,
/// which segment is baked and to when, every segment of the window (times, timing, pivot
/// relative to the anchor at `shift`, blended components), the linear part of the
/// window's start and the box around the centroid. `None` for a window with per-vertex
/// motion, which is not baked here.
fn bake_key(
    w: &Window,
    s: usize,
    end: f64,
    info: UnitInfo,
    shift: Vec2,
    fps: f64,
    tolerance: f64,
) -> Option<Vec<u64>> {
    let mut key: Vec<u64> = Vec::with_capacity(32 + 24 * w.segs.len());
    let mut put = |xs: &[f64]| key.extend(xs.iter().map(|x| x.to_bits()));
    put(&[fps, tolerance, s as f64, end]);
    let [a, b, c, d, _, _] = w.start.as_coeffs();
    put(&[a, b, c, d]);
    let bbox = info.bbox - info.centroid.to_vec2();
    put(&[bbox.x0, bbox.y0, bbox.x1, bbox.y1]);
    for seg in &w.segs {
        let MotionKind::Rigid {
            pivot,
            blend,
            interp,
        } = &seg.kind
        else {
            return None;
        };
        let t = &seg.timing;
        put(&[seg.t0, seg.t1, t.start, t.end, t.delay]);
        put(&[f64::from(u8::from(t.reversed))]);
        match &t.ease {
            Easing::Linear => put(&[0.0]),
            Easing::CubicBezier(p) => put(&[1.0, p[0], p[1], p[2], p[3]]),
            Easing::BSpline(k) => put(&[2.0, f64::from(*k)]),
            Easing::Poles { n, tau } => put(&[3.0, f64::from(*n), *tau]),
            Easing::Steps(n) => put(&[4.0, f64::from(*n)]),
        }
        let p = *pivot - shift;
        put(&[p.x, p.y, f64::from(u8::from(*interp == Interp::Alexa))]);
        put(&[blend.len() as f64]);
        for (weight, comps) in blend.iter() {
            put(&[*weight, comps.len() as f64]);
            for c in comps.iter() {
                match *c {
                    Component::Translate(v) => put(&[0.0, v.x, v.y]),
                    Component::Rotate(a) => put(&[1.0, a]),
                    Component::Scale(v) => put(&[2.0, v.x, v.y]),
                    Component::Skew(x, y) => put(&[3.0, x, y]),
                    Component::Matrix(m) => {
                        put(&[4.0]);
                        put(&m.as_coeffs());
                    }
                }
            }
        }
    }
    Some(key)
}

/// Why Lottie keys always exist: `Format::Spaced` samples the easings it cannot say.
const SAMPLED: &str = "spaced keys sample what is not a Bézier";

/// Keys of an attribute channel.
fn attr_keys<T: Copy + gmotion::motion::Blendable, V: Clone + Same>(
    segs: &[AttrSeg<T>],
    fps: f64,
    default: V,
    map: impl Fn(T) -> V,
    value_tolerance: f64,
) -> Vec<Key<V>> {
    if segs.is_empty() {
        return Vec::new();
    }
    let pieces: Vec<Piece> = segs
        .iter()
        .enumerate()
        .map(|(k, s)| Piece {
            t0: s.t0,
            t1: s.t1.min(segs.get(k + 1).map_or(f64::INFINITY, |n| n.t0)),
            timing: &s.timing,
        })
        .collect();
    let spaced = Format::Spaced {
        fps,
        tolerance: value_tolerance,
    };
    progress_keys(
        &pieces,
        default,
        |k, p| map(segs[k].from.blend(segs[k].to, p)),
        spaced,
    )
    .expect(SAMPLED)
}

#[cfg(test)]
mod tests {
    use super::*;
    use gmotion::motion::Blend;

    /// A track of two overlapping windows of `comps`, a bilinear-style blend of two
    /// weighted entries in the second, starting from `start`.
    fn track(comps: &[Component], other: &[Component], start: Affine, interp: Interp) -> Track {
        let mut t = Track::default();
        t.motions.push(MotionSeg::linear(0.0, 1.0, comps, start));
        let blend: Blend = Arc::from([
            (0.3, Arc::<[Component]>::from(comps)),
            (0.7, Arc::<[Component]>::from(other)),
        ]);
        t.motions.push(MotionSeg {
            t0: 1.0,
            t1: 2.0,
            timing: gmotion::motion::Timing::linear(1.0, 2.0),
            kind: MotionKind::Rigid {
                pivot: Point::new(3.0, -2.0),
                blend,
                interp,
            },
            start: t.transform_at(1.0),
        });
        t
    }

    /// What the shortcut claims the frame-by-frame scan finds: similarities throughout for
    /// even components (from a mirrored start too, blended, under Alexa's interpolation);
    /// and it makes no claim once a component is uneven.
    #[test]
    fn even_components_keep_every_frame_even() {
        use Component::{Rotate, Scale, Skew, Translate};
        let even = [
            Translate(Vec2::new(4.0, -7.0)),
            Rotate(130.0),
            Scale(Vec2::new(-1.5, -1.5)),
        ];
        let other = [
            Rotate(-40.0),
            Scale(Vec2::new(0.25, 0.25)),
            Translate(Vec2::new(1.0, 2.0)),
        ];
        let mirrored = Affine::new([-2.0, 0.0, 0.0, 2.0, 10.0, 5.0]);
        for interp in [Interp::Linear, Interp::Alexa] {
            for start in [Affine::IDENTITY, mirrored] {
                let t = track(&even, &other, start, interp);
                assert!(always_even(&t));
                assert!((0..=60).all(|f| is_even(t.transform_at(f as f64 / 30.0))));
            }
            for uneven in [Scale(Vec2::new(1.0, 0.5)), Skew(10.0, 0.0)] {
                let t = track(&even, &[uneven], Affine::IDENTITY, interp);
                assert!(!always_even(&t));
                assert!(!(0..=60).all(|f| is_even(t.transform_at(f as f64 / 30.0))));
            }
        }
        let stretched = track(
            &even,
            &other,
            Affine::scale_non_uniform(1.0, 2.0),
            Interp::Linear,
        );
        assert!(!always_even(&stretched));
    }
}
