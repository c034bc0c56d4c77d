//! The player: a Lottie document kept whole beside its model and units ([`Source`]), drawn
//! as a gmotion scene at any frame ([`Source::scene_at`]). This is how gmotion plays a
//! Lottie file itself, and what the Lottie exporter writes back with gmotion's motion on
//! top.

use kurbo::Affine;
use serde_json::Value;

use gmotion::scene::Scene;

use crate::model::{self, Document, Loc};
use crate::units::{UnitLayers, Units, scene_of};

/// The source document of an imported scene, for the exporter that writes it back with
/// gmotion's motion layered on top.
#[derive(Clone, Debug)]
pub struct Source {
    /// The document as read (every key, known or not).
    pub json: Value,
    /// The typed model of what gmotion reads.
    pub document: Document,
    /// For each unit of the scene (`scene.shapes[i]`), its layers.
    pub units: Vec<UnitLayers>,
    /// What the units are.
    pub mode: Units,
    /// The reference frame the scene was measured at.
    pub frame: f64,
}

/// A frame the document cannot be drawn at ([`Source::scene_at`]), and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("frame {frame}: {at}: {message}")]
pub struct FrameError {
    /// The composition frame.
    pub frame: f64,
    /// Where in the document.
    pub at: Loc,
    /// What is wrong.
    pub message: String,
}

impl Source {
    /// The composition frame a time in seconds from the animation's start is.
    pub fn frame_at(&self, seconds: f64) -> f64 {
        self.document.ip + seconds * self.document.fr
    }

    /// The nearest unit that unit `u` hangs from through its layer's parents, if any. The
    /// exported motion of that unit moves `u` too (its layer is re-parented under the
    /// unit's motion), as After Effects' parenting moves children.
    pub fn parent_unit(&self, u: usize) -> Option<usize> {
        let layers = &self.document.layers;
        let first = |u: &UnitLayers| u.layers.first().copied();
        let mut at = first(self.units.get(u)?)?;
        // Parents cannot cycle in an imported document; the bound only keeps this finite.
        for _ in 0..layers.len() {
            let parent = layers.get(at)?.parent?;
            at = layers.iter().position(|l| l.ind == Some(parent))?;
            // A part's motion moves only the part, not the layers parented to its layer.
            if let Some(v) = self
                .units
                .iter()
                .position(|w| w.part.is_none() && first(w) == Some(at))
            {
                return Some(v);
            }
        }
        None
    }

    /// The source made to last `duration` seconds, when that is not the composition's own
    /// length, and what that did: a longer animation holds the composition's last frame
    /// (every root layer on screen at its end stays on, its properties held after their
    /// last keyframes, and a precomposition's content held at its last frame by a time
    /// remap), a shorter one cuts it. The document written back and gmotion's own render
    /// both use the new source, so they agree on every frame.
    pub fn lasting(&self, duration: f64) -> Option<(Source, String)> {
        let doc = &self.document;
        let (ip, op, fr) = (doc.ip, doc.op, doc.fr);
        let new_op = ip + duration * fr;
        // Within a thousandth of a frame is the same length: After Effects writes whole
        // lengths with float noise (`op` 177.0000072 at 29.97 fps, 124.000126 at 30.00003).
        if !(new_op.is_finite() && new_op > ip) || (new_op - op).abs() < 1e-3 {
            return None;
        }
        let mut src = self.clone();
        let json = src.json.as_object_mut()?;
        json.insert("op".into(), new_op.into());
        src.document.op = new_op;
        let said = if new_op < op {
            format!(
                "the grammar's duration ({}s) is shorter than the composition ({}s): the composition is cut at {}s",
                seconds(duration),
                seconds((op - ip) / fr),
                seconds(duration)
            )
        } else {
            let last = op - 1.0;
            let layers = json.get_mut("layers").and_then(Value::as_array_mut)?;
            for (l, model) in layers.iter_mut().zip(src.document.layers.iter_mut()) {
                let Some(o) = l.as_object_mut() else {
                    continue;
                };
                // A layer that is on screen until the end stays on.
                if model.op < op - 1e-9 || model.ip > last {
                    continue;
                }
                o.insert("op".into(), new_op.into());
                model.op = new_op;
                if model.kind == model::LayerKind::Precomp && model.tm.is_none() && model.ip < last
                {
                    // Its content runs as it did up to the last frame, then holds there:
                    // precomposition time (seconds) = (t − st) / sr / fr, until `last`.
                    let at = |t: f64| (t - model.st) / model.sr / fr;
                    let tm = serde_json::json!({
                        "a": 1,
                        "k": [
                            {"t": model.ip, "s": [at(model.ip)], "i": {"x": [1], "y": [1]}, "o": {"x": [0], "y": [0]}},
                            {"t": last, "s": [at(last)]}
                        ]
                    });
                    o.insert("tm".into(), tm);
                    model.tm = model::opt_property(o, "tm", &model.at).ok().flatten();
                }
            }
            format!(
                "the grammar's duration ({}s) is longer than the composition ({}s): its last frame is held from {}s",
                seconds(duration),
                seconds((op - ip) / fr),
                seconds((last - ip) / fr)
            )
        };
        Some((src, said))
    }

    /// The composition's length in seconds, from its in point to its out point.
    pub fn duration(&self) -> f64 {
        (self.document.op - self.document.ip) / self.document.fr
    }

    /// The composition's frame rate.
    pub fn fps(&self) -> f64 {
        self.document.fr
    }

    /// The scene as the document draws it at composition `frame`: the same units in the
    /// same order as the imported scene (so an animation's tracks apply to it unchanged),
    /// each where its layers put it then; a unit whose layer is not on screen at `frame`
    /// is drawn at zero opacity. This is how gmotion plays a Lottie file itself. The units
    /// keep the measures (centroid, box, paint) of the reference frame.
    ///
    /// With it, each unit's motion: how the world of the layer the unit hangs from has
    /// moved since the reference frame (`parent(frame) · parent(reference)⁻¹`). gmotion's
    /// motion on a Lottie source is exported in that parent's space, so that it follows
    /// the rig it is added to; a renderer conjugates a canvas-space state by it to draw
    /// what players draw.
    pub fn scene_at(&self, frame: f64) -> Result<(Scene, Vec<Affine>), FrameError> {
        let (root, shapes, units, _) =
            scene_of(&self.document, frame, self.mode, Some(&self.units)).map_err(|e| {
                FrameError {
                    frame,
                    at: e.at,
                    message: e.message,
                }
            })?;
        let moved = units
            .iter()
            .zip(&self.units)
            .map(|(now, then)| {
                let at =
                    |u: &UnitLayers| u.parent_world.first().copied().unwrap_or(Affine::IDENTITY);
                let then = at(then);
                if then.determinant().abs() < 1e-12 {
                    Affine::IDENTITY
                } else {
                    at(now) * then.inverse()
                }
            })
            .collect();
        let scene = Scene {
            width: self.document.w,
            height: self.document.h,
            root,
            shapes,
            time: Some(gmotion::scene::SceneTime {
                duration: self.duration(),
                fps: self.fps(),
            }),
            keys: Vec::new(),
        };
        Ok((scene, moved))
    }
}

/// `x` seconds as people write them: at most three decimals, no trailing zeros.
fn seconds(x: f64) -> String {
    let s = format!("{x:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
