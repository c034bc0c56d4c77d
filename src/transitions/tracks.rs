//! Smoothed samples into the animation model: per frame, a rigid motion window whose
//! components carry the shape from its transform at one frame to the next, and
//! attribute windows for opacity and fill.
//!
//! A window from frame `k` to `k+1` starts from the accumulated transform `A_k` and adds
//! `R = A_{k+1}·A_k⁻¹`, written as components about the anchor's current position
//! `p = anchor + offset_k`: `R = T(Δoffset) · About(p, Rot(Δθ) · Scale(s_{k+1}/s_k))`. That
//! product is exact whenever the scale change is uniform or the shape is not rotated
//! at frame `k`; otherwise the rotation and scale part is one `Matrix` component. Frames
//! where nothing changes get no window (the track holds).

use std::sync::Arc;

use kurbo::{Affine, Point, Vec2};

use super::samples::{FrameState, Samples, ShapeSamples};
use crate::motion::{
    Animation, AttrSeg, Component, Interp, MotionKind, MotionSeg, Timing, Tint, Track,
};
use crate::scene::Scene;
use crate::tolerance::{FRAME, TELESCOPE};

/// The animation for `samples` on `scene` (shapes without samples get empty tracks).
pub fn animation(scene: &Scene, samples: &Samples) -> Animation {
    let mut tracks = vec![Track::default(); scene.shapes.len()];
    for s in &samples.shapes {
        tracks[s.shape] = track(s, samples);
    }
    Animation {
        scene: scene.clone(),
        duration: samples.duration(),
        fps: samples.fps,
        looping: false,
        tracks,
    }
}

/// The track of one shape.
pub fn track(s: &ShapeSamples, samples: &Samples) -> Track {
    let states: Vec<FrameState> = (0..samples.frames).map(|k| s.state(k)).collect();
    let mut track = Track::default();
    if s.has_transform() {
        let mats: Vec<Affine> = states.iter().map(|st| st.transform(s.anchor)).collect();
        for k in 0..samples.frames - 1 {
            let first = k == 0 && !FRAME.same_affine(mats[0], Affine::IDENTITY);
            if !first && FRAME.same_affine(mats[k], mats[k + 1]) {
                continue;
            }
            let (pivot, comps) = window(s.anchor, &states[k], &states[k + 1], mats[k], mats[k + 1]);
            track.motions.push(MotionSeg {
                t0: samples.time(k),
                t1: samples.time(k + 1),
                timing: Timing::linear(samples.time(k), samples.time(k + 1)),
                kind: MotionKind::Rigid {
                    pivot,
                    blend: Arc::from([(1.0, Arc::from(comps))]),
                    interp: Interp::Linear,
                },
                start: mats[k],
            });
        }
    }
    let opacity: Vec<f64> = states.iter().map(|st| st.opacity.clamp(0.0, 1.0)).collect();
    track.opacity = attr_windows(&opacity, 1.0, samples, |a, b| a == b);
    if states.first().is_some_and(|st| st.fill.is_some()) {
        let tints: Vec<Tint> = states
            .iter()
            .map(|st| tint(st.fill.unwrap_or_default()))
            .collect();
        track.fill = attr_windows(&tints, Tint::NONE, samples, |a, b| a == b);
    }
    track
}

/// A smoothed `(r·w, g·w, b·w, w)` as a tint, clamped into the tint's valid range
/// (springs may overshoot it slightly).
fn tint(v: [f64; 4]) -> Tint {
    let c = |x: f64| x.clamp(0.0, 1.0) as f32;
    Tint {
        sum: [c(v[0]), c(v[1]), c(v[2])],
        weight: c(v[3]),
    }
}

/// One attribute window per frame whose value changes, plus one at frame 0 when the
/// starting value is not the channel's rest value.
fn attr_windows<T: Copy>(
    values: &[T],
    rest: T,
    samples: &Samples,
    same: impl Fn(&T, &T) -> bool,
) -> Vec<AttrSeg<T>> {
    let mut out = Vec::new();
    for k in 0..values.len().saturating_sub(1) {
        let first = k == 0 && !same(&values[0], &rest);
        if !first && same(&values[k], &values[k + 1]) {
            continue;
        }
        let (t0, t1) = (samples.time(k), samples.time(k + 1));
        out.push(AttrSeg::linear(t0, t1, values[k], values[k + 1]));
    }
    out
}

/// The pivot and components of the window from `a` (transform `ma`) to `b` (`mb`).
fn window(
    anchor: Point,
    a: &FrameState,
    b: &FrameState,
    ma: Affine,
    mb: Affine,
) -> (Point, Vec<Component>) {
    let pivot = anchor + a.offset;
    let about =
        |m: Affine| Affine::translate(pivot.to_vec2()) * m * Affine::translate(-pivot.to_vec2());
    let d = b.offset - a.offset;
    let (sa, sb) = (a.clamped_scale(), b.clamped_scale());
    let ratio = Vec2::new(sb.x / sa.x, sb.y / sa.y);
    let uniform = (ratio.x - ratio.y).abs() <= 1e-12 * ratio.x.abs().max(1.0);
    let mut comps = Vec::new();
    if d != Vec2::ZERO {
        comps.push(Component::Translate(d));
    }
    if uniform || a.rotate.rem_euclid(360.0) == 0.0 {
        if b.rotate != a.rotate {
            comps.push(Component::Rotate(b.rotate - a.rotate));
        }
        if ratio != Vec2::new(1.0, 1.0) {
            comps.push(Component::Scale(ratio));
        }
    } else {
        let rot = |deg: f64| Affine::rotate(deg.to_radians());
        let m = rot(b.rotate) * Affine::scale_non_uniform(ratio.x, ratio.y) * rot(-a.rotate);
        comps.push(Component::Matrix(m));
    }
    if comps.is_empty() {
        // The first window of a shape that starts displaced and holds: it only carries
        // the starting transform.
        comps.push(Component::Translate(Vec2::ZERO));
    }
    let full = about(crate::motion::component::product_at(&comps, 1.0));
    if TELESCOPE.same_affine(full * ma, mb) {
        (pivot, comps)
    } else {
        // Rounding in the decomposition: fall back to the exact relative matrix.
        (Point::ORIGIN, vec![Component::Matrix(mb * ma.inverse())])
    }
}
