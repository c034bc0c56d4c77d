//! Sampling TARGETS into per-frame input signals and smoothing them: the numbers an
//! animation is then built from.

use std::collections::{BTreeMap, HashMap};

use kurbo::{Affine, Point, Vec2};

use super::TransitionError;
use super::targets::{Attr, Channel, TargetValue, Targets};
use crate::scene::Scene;
use crate::signals::{SignalError, SmoothSpec, smooth_samples};

/// Scale factors are kept at least this far from zero (keeping their sign) when turned
/// into transforms, so that a shape shrunk to nothing can still grow back: the motion
/// model composes relative transforms, which needs them invertible. A 20 px glyph at
/// this scale is 0.002 px.
pub const MIN_SCALE: f64 = 1e-4;

/// Largest frame rate accepted.
pub const MAX_FPS: f64 = 1000.0;
/// Largest number of frames accepted.
pub const MAX_FRAMES: usize = 1_000_000;

/// One channel's smoothed values, one per frame.
#[derive(Clone, Debug, PartialEq)]
pub enum ChannelSamples {
    /// A scalar channel.
    Scalar(Vec<f64>),
    /// The position offset `(dx, dy)`.
    Vec2(Vec<[f64; 2]>),
    /// The fill tint `(r·w, g·w, b·w, w)`.
    Vec4(Vec<[f64; 4]>),
}

/// The smoothed channels of one shape.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeSamples {
    /// Index into `scene.shapes`.
    pub shape: usize,
    /// The canvas point scale and rotation act about (and that `x`, `y` place).
    pub anchor: Point,
    /// The channels that have targets.
    pub channels: BTreeMap<Channel, ChannelSamples>,
}

/// A shape's attributes at one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameState {
    /// Offset of the anchor from where the shape is drawn.
    pub offset: Vec2,
    /// Rotation in degrees about the anchor.
    pub rotate: f64,
    /// Total scale factors `(scale·sx·zx, scale·sy·zy)` about the anchor.
    pub scale: Vec2,
    /// Opacity multiplier (unclamped; tracks clamp it to `[0, 1]`).
    pub opacity: f64,
    /// Fill tint `(r·w, g·w, b·w, w)`, if the shape has fill targets.
    pub fill: Option<[f64; 4]>,
}

impl FrameState {
    /// The shape's canvas transform: `T(offset) · R(rotate) · S(scale)` about `anchor`,
    /// with each scale factor at least [`MIN_SCALE`] in magnitude.
    pub fn transform(&self, anchor: Point) -> Affine {
        let a = anchor.to_vec2();
        let s = self.clamped_scale();
        Affine::translate(self.offset + a)
            * Affine::rotate(self.rotate.to_radians())
            * Affine::scale_non_uniform(s.x, s.y)
            * Affine::translate(-a)
    }

    /// The scale factors with magnitudes raised to at least [`MIN_SCALE`] (sign kept;
    /// zero counts as positive).
    pub fn clamped_scale(&self) -> Vec2 {
        let c = |s: f64| {
            if s.abs() < MIN_SCALE {
                MIN_SCALE.copysign(if s == 0.0 { 1.0 } else { s })
            } else {
                s
            }
        };
        Vec2::new(c(self.scale.x), c(self.scale.y))
    }
}

impl ShapeSamples {
    fn scalar(&self, c: Channel, frame: usize, rest: f64) -> f64 {
        match self.channels.get(&c) {
            Some(ChannelSamples::Scalar(v)) => v[frame],
            _ => rest,
        }
    }

    /// The attributes at `frame`.
    pub fn state(&self, frame: usize) -> FrameState {
        let offset = match self.channels.get(&Channel::Position) {
            Some(ChannelSamples::Vec2(v)) => Vec2::new(v[frame][0], v[frame][1]),
            _ => Vec2::ZERO,
        };
        let fill = match self.channels.get(&Channel::Fill) {
            Some(ChannelSamples::Vec4(v)) => Some(v[frame]),
            _ => None,
        };
        let s = self.scalar(Channel::Scale, frame, 1.0);
        FrameState {
            offset,
            rotate: self.scalar(Channel::Rotate, frame, 0.0),
            scale: Vec2::new(
                s * self.scalar(Channel::Sx, frame, 1.0) * self.scalar(Channel::Zx, frame, 1.0),
                s * self.scalar(Channel::Sy, frame, 1.0) * self.scalar(Channel::Zy, frame, 1.0),
            ),
            opacity: self.scalar(Channel::Opacity, frame, 1.0),
            fill,
        }
    }

    /// True when some channel moves the shape (position, scale or rotation).
    pub fn has_transform(&self) -> bool {
        self.channels
            .keys()
            .any(|c| !matches!(c, Channel::Opacity | Channel::Fill))
    }
}

/// Every targeted shape's smoothed channels, at frames `0..frames` (time `k / fps`).
#[derive(Clone, Debug, PartialEq)]
pub struct Samples {
    /// Frames per second.
    pub fps: f64,
    /// Number of frames, the first at time 0 and the last at the duration.
    pub frames: usize,
    /// The targeted shapes, by scene index.
    pub shapes: Vec<ShapeSamples>,
}

impl Samples {
    /// The time of frame `k`.
    pub fn time(&self, k: usize) -> f64 {
        k as f64 / self.fps
    }

    /// The duration covered (time of the last frame).
    pub fn duration(&self) -> f64 {
        self.time(self.frames.saturating_sub(1))
    }
}

/// The value a channel rests at when nothing targets it.
fn rest(channel: Channel) -> [f64; 4] {
    match channel {
        Channel::Position | Channel::Rotate | Channel::Fill => [0.0; 4],
        _ => [1.0, 0.0, 0.0, 0.0],
    }
}

/// A target for one shape's channel: when, which attribute, what value.
type Event = (f64, Attr, TargetValue);

/// Samples and smooths `targets` on `scene` (see [`super::run`] for the rules).
pub fn sample(
    scene: &Scene,
    targets: &Targets,
    system: &SmoothSpec,
    fps: f64,
    duration: Option<f64>,
) -> Result<Samples, TransitionError> {
    let signal = |context: &str| {
        let context = context.to_string();
        move |source: SignalError| TransitionError::Signal {
            context: context.clone(),
            source,
        }
    };
    if !(fps.is_finite() && fps > 0.0 && fps <= MAX_FPS) {
        return Err(signal("frame rate")(SignalError::OutOfRange {
            what: "fps",
            range: "(0, 1000]",
            value: fps,
        }));
    }

    // Resolve targets to (shape, channel) event lists, in time order.
    let mut by_tag: HashMap<&str, Vec<usize>> = HashMap::new();
    for (i, s) in scene.shapes.iter().enumerate() {
        by_tag.entry(s.tag.as_str()).or_default().push(i);
    }
    for list in by_tag.values_mut() {
        list.sort_by_key(|&i| scene.shapes[i].id);
    }
    // An alias (an element id, a tag map's tag) names its shapes in document order, where
    // no shape has it as its tag.
    let mut by_alias: HashMap<&str, Vec<usize>> = HashMap::new();
    for (i, s) in scene.shapes.iter().enumerate() {
        for a in s
            .aliases
            .iter()
            .filter(|a| !by_tag.contains_key(a.as_str()))
        {
            by_alias.entry(a.as_str()).or_default().push(i);
        }
    }
    by_tag.extend(by_alias);
    let all: Vec<usize> = (0..scene.shapes.len()).collect();
    let anchor = |i: usize| {
        let s = &scene.shapes[i];
        match targets.anchor_for(&s.tag) {
            Some([fx, fy]) => Point::new(
                s.bbox.x0 + fx * s.bbox.width(),
                s.bbox.y0 + fy * s.bbox.height(),
            ),
            None => s.centroid,
        }
    };
    let mut events: BTreeMap<(usize, Channel), Vec<Event>> = BTreeMap::new();
    for t in &targets.targets {
        let shapes: &[usize] = if t.tag == "all" {
            &all
        } else {
            by_tag.get(t.tag.as_str()).ok_or_else(|| {
                let mut tags: Vec<&str> = by_tag.keys().copied().collect();
                tags.sort_unstable();
                tags.truncate(20);
                TransitionError::Shape {
                    location: t.location.clone(),
                    message: format!(
                        "no shape has the tag `{}`; the scene's tags are: {}",
                        t.tag,
                        tags.join(", ")
                    ),
                }
            })?
        };
        let chosen: Vec<usize> = match t.id {
            None => shapes.to_vec(),
            Some(id) => {
                let hit = shapes
                    .iter()
                    .copied()
                    .find(|&i| scene.shapes[i].id == id)
                    .ok_or_else(|| TransitionError::Shape {
                        location: t.location.clone(),
                        message: format!(
                            "shape `{}` #{id} does not exist (the tag has {} shapes, ids 0 to {})",
                            t.tag,
                            shapes.len(),
                            shapes.len().saturating_sub(1)
                        ),
                    })?;
                vec![hit]
            }
        };
        for i in chosen {
            events
                .entry((i, t.attr.channel()))
                .or_default()
                .push((t.time, t.attr, t.value));
        }
    }

    // The time span: explicit, from the file, or until the slowest system settles.
    let system_of = |i: usize, c: Channel| targets.system_for(&scene.shapes[i].tag, c, system);
    let duration = match duration.or(targets.duration) {
        Some(d) => d,
        None => {
            let last = targets.targets.iter().map(|t| t.time).fold(0.0, f64::max);
            let mut settle: f64 = 0.0;
            let mut seen: Vec<&SmoothSpec> = Vec::new();
            for &(i, c) in events.keys() {
                let spec = system_of(i, c);
                if !seen.contains(&spec) {
                    settle = settle.max(
                        spec.settle_time(1e-3)
                            .map_err(signal(&format!("system `{spec}`")))?,
                    );
                    seen.push(spec);
                }
            }
            last + settle + 1.0 / fps
        }
    };
    if !(duration.is_finite() && duration > 0.0) {
        return Err(signal("duration")(SignalError::NotPositive {
            what: "duration",
            value: duration,
        }));
    }
    let last_frame = (duration * fps - 1e-9).ceil().max(1.0);
    if last_frame >= MAX_FRAMES as f64 {
        return Err(signal("duration")(SignalError::Invalid(format!(
            "{duration} s at {fps} fps is more than {MAX_FRAMES} frames"
        ))));
    }
    let frames = last_frame as usize + 1;

    let mut shapes: BTreeMap<usize, ShapeSamples> = BTreeMap::new();
    for ((i, channel), list) in &events {
        let a = anchor(*i);
        // Sample and hold: each frame sees every target set at or before it.
        let mut value = rest(*channel);
        let mut next = 0;
        let input: Vec<[f64; 4]> = (0..frames)
            .map(|k| {
                let t = k as f64 / fps;
                while next < list.len() && list[next].0 <= t + 1e-9 {
                    let (_, attr, v) = list[next];
                    match (attr, v) {
                        (Attr::X, TargetValue::Number(x)) => value[0] = x - a.x,
                        (Attr::Y, TargetValue::Number(y)) => value[1] = y - a.y,
                        (Attr::Dy, TargetValue::Number(y)) => value[1] = y,
                        (_, TargetValue::Number(x)) => value[0] = x,
                        (_, TargetValue::Color(c)) => {
                            value = [f64::from(c.r), f64::from(c.g), f64::from(c.b), 1.0];
                        }
                    }
                    next += 1;
                }
                value
            })
            .collect();
        let spec = system_of(*i, *channel);
        let shape = &scene.shapes[*i];
        let context = format!(
            "channel `{}` of `{}` #{} (system `{spec}`)",
            channel.name(),
            shape.tag,
            shape.id
        );
        let out = match channel {
            Channel::Position => {
                let v: Vec<[f64; 2]> = input.iter().map(|x| [x[0], x[1]]).collect();
                ChannelSamples::Vec2(smooth_samples(spec, &v, fps).map_err(signal(&context))?)
            }
            Channel::Fill => {
                ChannelSamples::Vec4(smooth_samples(spec, &input, fps).map_err(signal(&context))?)
            }
            _ => {
                let v: Vec<f64> = input.iter().map(|x| x[0]).collect();
                ChannelSamples::Scalar(smooth_samples(spec, &v, fps).map_err(signal(&context))?)
            }
        };
        shapes
            .entry(*i)
            .or_insert_with(|| ShapeSamples {
                shape: *i,
                anchor: a,
                channels: BTreeMap::new(),
            })
            .channels
            .insert(*channel, out);
    }
    Ok(Samples {
        fps,
        frames,
        shapes: shapes.into_values().collect(),
    })
}
