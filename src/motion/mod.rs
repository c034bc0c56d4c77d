//! The animation model: a scene plus, for every shape, keyframed channels (transform, fill
//! and stroke tints, opacity, stroke width). This is what the engine produces, what
//! `evaluate(t)` samples and what exporters read; it knows nothing of grammars.
//!
//! A transform channel is a list of [`MotionSeg`]s in time order. Each segment plays a
//! window of one *motion* (an animation set by a rule): the motion's transform `F(p)`, a
//! product of components about a pivot, is driven by a progress `p = f(t)`; within its window
//! the segment contributes `F(f(t))·F(f(t₀))⁻¹` on top of the state the shape was in at `t₀`.
//! Consecutive windows of one motion therefore telescope back to the whole motion, and a
//! reversed motion (an `inv_` slice) runs `f` backwards so it undoes its forward twin.
//!
//! Several motions may share one window (a slice animated by two rules): such segments
//! are adjacent in the list and compose with the earlier-listed one outermost, so a shape's
//! transform is `X(t) = Rᵢ(t)·Rᵢ₊₁(t)·…·R_j(t)·start_i` for the window group `i..=j` holding
//! `t`, each `R` being identity before its window and holding its end value after it. In
//! exporter terms: one nested group per segment, earlier segments outside.

pub mod alexa;
pub mod bend;
pub mod component;
pub mod follow;
pub mod grid;
pub mod morph;
pub mod sampler;
pub mod trim;

use std::sync::Arc;

use kurbo::{Affine, Point};

use crate::color::Color;
use crate::scene::Scene;
use crate::signals::Easing;
pub use component::Component;
pub use grid::{Blend, Field, Grid, Lookup};
pub use morph::MorphSeg;
pub use sampler::{Playhead, Sampler};
pub use trim::Trim;

/// The six things a shape's track animates, each a list of its own in a [`Track`]: its
/// transform ([`Track::motions`]), fill and stroke tints, opacity, stroke width and trim. The
/// discriminants index per-channel arrays, in this order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    /// The shape's transform (motion windows).
    Transform = 0,
    /// The fill tint.
    Fill = 1,
    /// The stroke tint.
    Stroke = 2,
    /// The opacity factor.
    Opacity = 3,
    /// The stroke-width factor.
    StrokeWidth = 4,
    /// The visible part of the strokes ([`Trim`]).
    Trim = 5,
}

impl Channel {
    /// How many channels there are.
    pub const COUNT: usize = 6;
}

/// How a motion's transform is interpolated between its neutral and full value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Interp {
    /// Each component by its own parameters (angles, factors, offsets).
    #[default]
    Linear,
    /// The linear combination of transformations (Alexa 2002): `exp(p·log M)`.
    Alexa,
}

/// When a motion or attribute change runs and how its progress is shaped.
#[derive(Clone, Debug, PartialEq)]
pub struct Timing {
    /// Start of the slice the change was set on (seconds).
    pub start: f64,
    /// End of that slice.
    pub end: f64,
    /// Delay from the start before the change begins (seconds; at the end when reversed).
    pub delay: f64,
    /// Easing of the progress.
    pub ease: Easing,
    /// True for inverted slices: the change plays backwards in time.
    pub reversed: bool,
}

impl Timing {
    /// A change over `[start, end]` that begins `delay` seconds in (before the end when
    /// `reversed`), its progress shaped by `ease`.
    pub fn new(start: f64, end: f64, delay: f64, ease: Easing, reversed: bool) -> Timing {
        Timing {
            start,
            end,
            delay,
            ease,
            reversed,
        }
    }

    /// A change over all of `[start, end]`, linear, forward: what sampled tracks (smoothing,
    /// transitions) use between two samples.
    pub fn linear(start: f64, end: f64) -> Timing {
        Timing::new(start, end, 0.0, Easing::Linear, false)
    }

    /// The progress `f(t)` that drives the change's endpoints: 0 at the neutral end,
    /// 1 at the full end. Forward changes go 0→1, reversed ones 1→0.
    #[inline]
    pub fn progress(&self, t: f64) -> f64 {
        let span = (self.end - self.start - self.delay).max(0.0);
        let local = if self.reversed {
            t - self.start
        } else {
            t - self.start - self.delay
        };
        let u = if span <= 0.0 {
            if local >= 0.0 { 1.0 } else { 0.0 }
        } else {
            (local / span).clamp(0.0, 1.0)
        };
        if self.reversed {
            self.ease.apply(1.0 - u)
        } else {
            self.ease.apply(u)
        }
    }

    /// The instants where the change starts and stops moving, clamped to `[start, end]`.
    pub fn active(&self) -> (f64, f64) {
        if self.reversed {
            (self.start, (self.end - self.delay).max(self.start))
        } else {
            ((self.start + self.delay).min(self.end), self.end)
        }
    }
}

/// How the transform of a motion depends on its progress.
#[derive(Clone, Debug)]
pub enum MotionKind {
    /// A weighted blend of component products about `pivot` (one entry for nearest and
    /// exact lookups, up to four for bilinear).
    Rigid {
        /// Centre of local motions (the shape's centroid), or the origin for world ones.
        pivot: Point,
        /// The components with their weights.
        blend: Blend,
        /// How the components interpolate.
        interp: Interp,
    },
    /// Per-vertex deformation: every vertex reads the grid bilinearly.
    Vertex {
        /// The grid.
        grid: Arc<Grid>,
        /// Local motions pivot about this point, in the grid's frame ([`Grid::frame`]);
        /// `None` for world motions.
        pivot: Option<Point>,
    },
    /// Motion along a path by arc length (`animate(follow, …)`): the progress is the
    /// fraction of the path travelled.
    Follow(Arc<follow::Follow>),
}

impl MotionKind {
    /// `F(p)`: the motion's transform at progress `p` (identity for vertex motions, which
    /// act through [`Track::deform`]).
    #[inline]
    pub fn at(&self, p: f64) -> Affine {
        match self {
            MotionKind::Rigid {
                pivot,
                blend,
                interp,
            } => match interp {
                Interp::Linear => grid::blend_at(blend, *pivot, p),
                Interp::Alexa => alexa::power(grid::blend_at(blend, *pivot, 1.0), p),
            },
            MotionKind::Vertex { .. } => Affine::IDENTITY,
            MotionKind::Follow(f) => f.at(p),
        }
    }
}

/// One window of a motion on one shape.
#[derive(Clone, Debug)]
pub struct MotionSeg {
    /// Window start (a slice boundary).
    pub t0: f64,
    /// Window end.
    pub t1: f64,
    /// The motion's timing (its whole slice, not just this window).
    pub timing: Timing,
    /// What moves.
    pub kind: MotionKind,
    /// The shape's accumulated transform at `t0`, before every segment of this window.
    pub start: Affine,
}

impl MotionSeg {
    /// `F(p)` for a rigid motion.
    #[inline]
    pub fn full_at(&self, p: f64) -> Affine {
        self.kind.at(p)
    }

    /// The relative transform this window adds at time `t` (identity for vertex motions,
    /// which act through [`Track::deform`]).
    pub fn relative_at(&self, t: f64) -> Affine {
        let p0 = self.timing.progress(self.t0);
        let p = self.timing.progress(t.clamp(self.t0, self.t1));
        if p == p0 {
            return Affine::IDENTITY;
        }
        // F(0) is the identity: a window that starts where its motion starts (the common
        // case) needs one product, not two and an inverse.
        if p0 == 0.0 {
            return self.full_at(p);
        }
        self.full_at(p) * self.full_at(p0).inverse()
    }
}

/// A colour change, stored as a tint that mixes into every painted colour of the shape:
/// `shown = original·(1 − weight) + sum`, where `sum = weight·target`. Both parts blend
/// linearly, so a tint interpolates linearly per path whatever the path's own colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tint {
    /// `weight · target colour` (rgb; alpha stays the path's own).
    pub sum: [f32; 3],
    /// How much of the original colour is replaced, in `0..=1`.
    pub weight: f32,
}

impl Tint {
    /// No change.
    pub const NONE: Tint = Tint {
        sum: [0.0; 3],
        weight: 0.0,
    };

    /// Replace the colour fully by `c`.
    pub fn full(c: Color) -> Tint {
        Tint {
            sum: [c.r, c.g, c.b],
            weight: 1.0,
        }
    }

    /// Linear blend.
    pub fn lerp(self, o: Tint, t: f32) -> Tint {
        Tint {
            sum: std::array::from_fn(|i| self.sum[i] + (o.sum[i] - self.sum[i]) * t),
            weight: self.weight + (o.weight - self.weight) * t,
        }
    }

    /// The colour shown for a path whose own colour is `c`.
    pub fn apply(self, c: Color) -> Color {
        let k = 1.0 - self.weight;
        Color {
            r: (c.r * k + self.sum[0]).clamp(0.0, 1.0),
            g: (c.g * k + self.sum[1]).clamp(0.0, 1.0),
            b: (c.b * k + self.sum[2]).clamp(0.0, 1.0),
            a: c.a,
        }
    }
}

/// A change of an attribute between two values over a [`Timing`]:
/// `value(t) = from + (to − from)·progress(t)`.
#[derive(Clone, Debug)]
pub struct AttrSeg<T> {
    /// Window start (a slice boundary).
    pub t0: f64,
    /// Window end.
    pub t1: f64,
    /// The change's timing.
    pub timing: Timing,
    /// Value at progress 0.
    pub from: T,
    /// Value at progress 1.
    pub to: T,
}

/// Values that attribute segments blend.
pub trait Blendable: Copy {
    /// Linear blend.
    fn blend(self, other: Self, t: f64) -> Self;
}

impl Blendable for f64 {
    fn blend(self, o: f64, t: f64) -> f64 {
        self + (o - self) * t
    }
}

impl Blendable for Tint {
    fn blend(self, o: Tint, t: f64) -> Tint {
        self.lerp(o, t as f32)
    }
}

impl MotionSeg {
    /// A window over `[t0, t1]`, linear in time, moving by `components` about the canvas
    /// origin from `start`: what sampled tracks and held pre-applied states use (no
    /// components holds `start`).
    pub fn linear(t0: f64, t1: f64, components: &[Component], start: Affine) -> MotionSeg {
        MotionSeg {
            t0,
            t1,
            timing: Timing::linear(t0, t1),
            kind: MotionKind::Rigid {
                pivot: Point::ORIGIN,
                blend: Arc::from([(1.0, Arc::from(components))]),
                interp: Interp::Linear,
            },
            start,
        }
    }
}

impl<T> AttrSeg<T> {
    /// A linear change from `from` at `t0` to `to` at `t1`.
    pub fn linear(t0: f64, t1: f64, from: T, to: T) -> AttrSeg<T> {
        AttrSeg {
            t0,
            t1,
            timing: Timing::linear(t0, t1),
            from,
            to,
        }
    }
}

impl<T: Blendable> AttrSeg<T> {
    /// The value at time `t` inside the window.
    #[inline]
    pub fn value_at(&self, t: f64) -> T {
        self.from
            .blend(self.to, self.timing.progress(t.clamp(self.t0, self.t1)))
    }
}

/// Samples a list of attribute segments (sorted by `t0`) at `t`, holding the last value
/// between segments and `default` before the first.
pub(crate) fn attr_at<T: Blendable>(segs: &[AttrSeg<T>], t: f64, default: T) -> T {
    let i = segs.partition_point(|s| s.t0 <= t);
    if i == 0 {
        return default;
    }
    segs[i - 1].value_at(t)
}

/// Every channel of one shape.
#[derive(Clone, Debug, Default)]
pub struct Track {
    /// Transform windows, sorted and non-overlapping.
    pub motions: Vec<MotionSeg>,
    /// Fill tint changes.
    pub fill: Vec<AttrSeg<Tint>>,
    /// Stroke tint changes.
    pub stroke: Vec<AttrSeg<Tint>>,
    /// Opacity multiplier changes (the shape's own opacity times this).
    pub opacity: Vec<AttrSeg<f64>>,
    /// Stroke width multiplier changes.
    pub stroke_width: Vec<AttrSeg<f64>>,
    /// Changes of the strokes' visible part.
    pub trim: Vec<AttrSeg<Trim>>,
    /// Outline changes (morphs), sorted and non-overlapping.
    pub morphs: Vec<MorphSeg>,
}

/// A shape's state at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeState {
    /// Canvas-space transform applied on top of the shape's placement.
    pub transform: Affine,
    /// Fill tint.
    pub fill: Tint,
    /// Stroke tint.
    pub stroke: Tint,
    /// Opacity multiplier.
    pub opacity: f64,
    /// Stroke width multiplier.
    pub stroke_width: f64,
    /// The strokes' visible part.
    pub trim: Trim,
}

impl ShapeState {
    /// The state of a shape nothing has touched.
    pub const REST: ShapeState = ShapeState {
        transform: Affine::IDENTITY,
        fill: Tint::NONE,
        stroke: Tint::NONE,
        opacity: 1.0,
        stroke_width: 1.0,
        trim: Trim::REST,
    };
}

impl Track {
    /// True when no channel ever changes.
    pub fn is_still(&self) -> bool {
        self.motions.is_empty()
            && self.fill.is_empty()
            && self.stroke.is_empty()
            && self.opacity.is_empty()
            && self.stroke_width.is_empty()
            && self.trim.is_empty()
            && self.morphs.is_empty()
    }

    /// The unit's paths at `t` (one per path, in document order, each in its own
    /// coordinates): `None` while they are as drawn.
    pub fn outlines_at(&self, t: f64) -> Option<Vec<kurbo::BezPath>> {
        morph::outlines_at(&self.morphs, t)
    }

    /// The rigid transform at `t`.
    pub fn transform_at(&self, t: f64) -> Affine {
        let end = self.motions.partition_point(|s| s.t0 <= t);
        if end == 0 {
            return Affine::IDENTITY;
        }
        let t0 = self.motions[end - 1].t0;
        // Past the window: the next window's start already holds the result.
        if let Some(next) = self.motions.get(end)
            && self.motions[end - 1].t1 <= t
        {
            return next.start;
        }
        let first = self.motions[..end].partition_point(|s| s.t0 < t0);
        let group = &self.motions[first..end];
        group
            .iter()
            .fold(Affine::IDENTITY, |acc, seg| acc * seg.relative_at(t))
            * group[0].start
    }

    /// Every channel at `t`.
    pub fn state_at(&self, t: f64) -> ShapeState {
        ShapeState {
            transform: self.transform_at(t),
            fill: attr_at(&self.fill, t, Tint::NONE),
            stroke: attr_at(&self.stroke, t, Tint::NONE),
            opacity: attr_at(&self.opacity, t, 1.0),
            stroke_width: attr_at(&self.stroke_width, t, 1.0),
            trim: attr_at(&self.trim, t, Trim::REST),
        }
    }

    /// True when some motion deforms the shape per vertex.
    pub fn deforms(&self) -> bool {
        self.motions
            .iter()
            .any(|m| matches!(m.kind, MotionKind::Vertex { .. }))
    }

    /// Where a canvas-space point of the shape is at time `t`, following every motion
    /// (rigid ones as a whole, vertex ones reading the grid at the point's own position).
    ///
    /// Segments sharing a window compose as in [`Track::transform_at`], the earlier-listed
    /// outermost, so a point goes through them last-listed first, on top of the first
    /// window's start (a pre-applied rigid state).
    ///
    /// A vertex motion reads the grid where the point was when the motion began (as a rigid
    /// motion reads it at the centroid where it began): its later windows and its inverted
    /// twin (a reversed segment on the same grid after a forward one) read the same cells,
    /// so a split motion telescopes and a twin undoes it exactly. A reversed vertex motion
    /// with no forward one on its grid before it is pre-applied (an entrance): it deforms
    /// the drawn points innermost from time 0 at its progress then, `ease(1)` before its
    /// slice, and plays back to the drawn shape.
    pub fn deform(&self, p: Point, t: f64) -> Point {
        let mut q = p;
        // Where each vertex motion (keyed by its grid) began reading the grid, in its frame.
        let mut anchors: Vec<(*const (), Point)> = Vec::new();
        let mut forward: Vec<*const ()> = Vec::new();
        let mut pre: Vec<*const ()> = Vec::new();
        for seg in &self.motions {
            if let MotionKind::Vertex { grid, pivot } = &seg.kind {
                let g = grid.key();
                if !seg.timing.reversed {
                    forward.push(g);
                } else if !forward.contains(&g) && !pre.contains(&g) {
                    // Pre-applied: in the art's frame (compile never carries it).
                    pre.push(g);
                    let pv = pivot.unwrap_or(Point::ORIGIN);
                    let blend = grid.lookup(p, Lookup::Vertex);
                    q = grid::blend_at(&blend, pv, seg.timing.progress(t)) * q;
                }
            }
        }
        match self.motions.first() {
            Some(first) if first.t0 <= t => q = first.start * q,
            _ => {}
        }
        let upto = self.motions.partition_point(|s| s.t0 <= t);
        // Grids of the forward vertex motions met so far, in time order.
        let mut seen: Vec<*const ()> = Vec::new();
        for window in self.motions[..upto].chunk_by(|a, b| a.t0 == b.t0) {
            for seg in window.iter().rev() {
                let te = t.min(seg.t1);
                let MotionKind::Vertex { grid, pivot } = &seg.kind else {
                    q = seg.relative_at(te) * q;
                    continue;
                };
                let g = grid.key();
                if !seg.timing.reversed {
                    seen.push(g);
                } else if !seen.contains(&g) {
                    // Pre-applied, above.
                    continue;
                }
                let frame = grid.frame();
                let local = frame.inverse() * q;
                // A forward motion that begins here takes the point's place as its anchor.
                let begins = !seg.timing.reversed && seg.t0 <= seg.timing.start + 1e-9;
                let at = match anchors.iter_mut().find(|(k, _)| *k == g) {
                    Some(e) if !begins => e.1,
                    Some(e) => {
                        e.1 = local;
                        local
                    }
                    None => {
                        anchors.push((g, local));
                        local
                    }
                };
                let pv = pivot.unwrap_or(Point::ORIGIN);
                let blend = grid.lookup(at, Lookup::Vertex);
                let p0 = seg.timing.progress(seg.t0);
                let p1 = seg.timing.progress(te);
                let m = grid::blend_at(&blend, pv, p1) * grid::blend_at(&blend, pv, p0).inverse();
                q = frame * (m * local);
            }
        }
        q
    }
}

/// A scene with a keyframed track per shape: the result of running a grammar.
#[derive(Clone, Debug)]
pub struct Animation {
    /// The scene (possibly rewritten by spatial rules).
    pub scene: Scene,
    /// Length in seconds.
    pub duration: f64,
    /// Frames per second for sampled output.
    pub fps: f64,
    /// Whether players should loop it.
    pub looping: bool,
    /// One track per `scene.shapes` entry.
    pub tracks: Vec<Track>,
}

impl Animation {
    /// Every shape's state at time `t` (the paper's `evaluate(t)`).
    pub fn evaluate(&self, t: f64) -> Vec<ShapeState> {
        self.tracks.iter().map(|tr| tr.state_at(t)).collect()
    }

    /// The tracks compiled for sampling many frames: use this rather than
    /// [`Animation::evaluate`] when evaluating more than a few instants.
    pub fn sampler(&self) -> Sampler<'_> {
        Sampler::new(self)
    }

    /// Like [`Animation::evaluate`], writing into `out` to avoid allocating per frame.
    pub fn evaluate_into(&self, t: f64, out: &mut Vec<ShapeState>) {
        out.clear();
        out.extend(self.tracks.iter().map(|tr| tr.state_at(t)));
    }

    /// Number of frames of every output (at least one): the duration in frames, rounded
    /// to the nearest whole number ([`crate::canvas::frames`]).
    pub fn frame_count(&self) -> usize {
        crate::canvas::frames(self.duration, self.fps)
    }

    /// How long every output lasts, in seconds: [`Animation::frame_count`] frames, which is
    /// the duration rounded to a whole frame ([`crate::canvas::length`]).
    pub fn length(&self) -> f64 {
        crate::canvas::length(self.duration, self.fps)
    }

    /// The time of frame `i`.
    pub fn frame_time(&self, i: usize) -> f64 {
        i as f64 / self.fps
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Vec2;

    fn timing(start: f64, end: f64, reversed: bool) -> Timing {
        Timing::new(start, end, 0.0, Easing::Linear, reversed)
    }

    #[test]
    fn reversed_timing_runs_backwards() {
        let t = timing(1.0, 3.0, true);
        assert_eq!(t.progress(1.0), 1.0);
        assert_eq!(t.progress(2.0), 0.5);
        assert_eq!(t.progress(3.0), 0.0);
    }

    #[test]
    fn delay_holds_then_moves() {
        let t = Timing {
            delay: 1.0,
            ..timing(0.0, 2.0, false)
        };
        assert_eq!(t.progress(0.5), 0.0);
        assert_eq!(t.progress(1.5), 0.5);
        assert_eq!(t.active(), (1.0, 2.0));
    }

    #[test]
    fn tint_is_linear_per_path() {
        let red = Tint::full(Color::rgb(1.0, 0.0, 0.0));
        let half = Tint::NONE.lerp(red, 0.5);
        let c = half.apply(Color::rgb(0.0, 0.0, 1.0));
        assert!((c.r - 0.5).abs() < 1e-6 && (c.b - 0.5).abs() < 1e-6);
    }

    #[test]
    fn split_windows_telescope() {
        let blend: Blend = Arc::from([(
            1.0,
            Arc::from([
                Component::Rotate(90.0),
                Component::Translate(Vec2::new(5.0, 0.0)),
            ]),
        )]);
        let kind = MotionKind::Rigid {
            pivot: Point::new(10.0, 10.0),
            blend,
            interp: Interp::Linear,
        };
        let whole = MotionSeg {
            t0: 0.0,
            t1: 2.0,
            timing: timing(0.0, 2.0, false),
            kind: kind.clone(),
            start: Affine::IDENTITY,
        };
        let a = MotionSeg {
            t1: 0.7,
            ..whole.clone()
        };
        let b = MotionSeg {
            t0: 0.7,
            start: a.relative_at(0.7),
            ..whole.clone()
        };
        let got = b.relative_at(2.0) * b.start;
        let want = whole.relative_at(2.0);
        for (x, y) in got.as_coeffs().iter().zip(want.as_coeffs()) {
            assert!((x - y).abs() < 1e-9);
        }
    }
}
