//! gmotion's colour and stroke-width motion written into a Lottie source's own shape
//! items: every fill's and stroke's colour tinted as gmotion tints it, every stroke's
//! width multiplied, sampled frame by frame over the composition (where the source's own
//! value animates too, the product follows both) and reduced to the keyframes that
//! matter.

use serde_json::Value as Json;

use gmotion::Warning;
use gmotion::color::Color;
use gmotion::motion::{ShapeState, Tint, Track};
use gmotion_lottie::Source;
use gmotion_lottie::eval;
use gmotion_lottie::model::{Layer, LayerKind, Num, ShapeItem, ShapeKind};

use crate::model::{Keyframe, LINEAR, N, Prop, Value};

/// How far (in the property's own unit: 0–1 colour, pixels of width, percent of
/// opacity) a sample may stray from the line through its neighbours to be dropped.
const COLOR_EPS: f64 = 1.0 / 512.0;
const WIDTH_EPS: f64 = 0.01;

/// Writes `track`'s fill and stroke tints and stroke-width factor into root layer `li` of
/// `doc` (the document being written) and everything it draws: the fills, strokes and
/// gradients of a shape layer; for a precomposition, a copy of its asset (so that other
/// uses keep theirs) with the same done to every layer inside, on the precomposition's own
/// clock, the copies' layers counted against `budget`. With `part` (`--units groups`: the index of a top-level item, and the layer's
/// top-level items as `doc` holds them now), only that item is restyled. What cannot be
/// written is warned about under `name`, in `tally`.
pub(crate) fn restyle(
    doc: &mut Json,
    li: usize,
    part: Option<(usize, &[ShapeItem])>,
    source: &Source,
    track: &Track,
    name: &str,
    tally: &mut Tally,
) {
    let warnings = &mut *tally.warnings;
    let budget = &mut tally.budget;
    let d = &source.document;
    let Some(model) = d.layers.get(li) else {
        return;
    };
    let frames = sampled_frames(d, &format!("{name} (layer \"{}\")", model.nm), warnings);
    let clock: Vec<(f64, ShapeState)> = (0..=frames)
        .map(|f| (d.ip + f as f64, track.state_at(f as f64 / d.fr)))
        .collect();
    let mut walk = Walk {
        source,
        legacy: d.older_than((4, 1, 9)),
        label: format!("{name} (layer \"{}\")", model.nm),
        warnings,
        copies: Vec::new(),
        made: Default::default(),
        suffix: name.replace(':', " "),
        budget,
    };
    let Some(layer) = doc.get_mut("layers").and_then(|l| l.get_mut(li)) else {
        return;
    };
    match part {
        Some((k, items)) => walk.part(layer, items, k, &clock),
        None => walk.layer(layer, model, &clock, 0),
    }
    let copies = std::mem::take(&mut walk.copies);
    if copies.is_empty() {
        return;
    }
    if let Some(assets) = doc.get_mut("assets").and_then(Json::as_array_mut) {
        assets.extend(copies);
    }
}

/// What the restyles of one document add up as they go: the warnings, and how many more
/// layers their precomposition copies may hold.
pub(crate) struct Tally<'a> {
    /// The document's warnings.
    pub warnings: &'a mut Vec<Warning>,
    /// Layers the copies may still hold (from [`MAX_COPIED_LAYERS`]).
    pub budget: usize,
}

/// Most layers the precomposition copies that colour changes make may hold in all, over
/// a document's units (each clock an asset runs on in a unit needs one copy): bounds the
/// output of a precomposition used many times over at many levels.
pub(crate) const MAX_COPIED_LAYERS: usize = 20_000;

struct Walk<'a> {
    source: &'a Source,
    /// Files before 4.1.9 hold 0–255 fill and stroke colours (see [`Walk::scale`]).
    legacy: bool,
    label: String,
    warnings: &'a mut Vec<Warning>,
    /// Restyled copies of precomposition assets, to add to the document.
    copies: Vec<Json>,
    /// The copy made of each asset for each clock it runs on (its frames' times), so that
    /// a precomposition used many times over (at many levels) is copied once per clock,
    /// not once per use.
    made: std::collections::HashMap<(String, Vec<u64>), String>,
    /// What names the unit in a copied asset's id.
    suffix: String,
    /// Layers the document's copies may still hold ([`MAX_COPIED_LAYERS`]).
    budget: &'a mut usize,
}

impl Walk<'_> {
    /// Restyles layer `json` (read as `model`); `clock` pairs each frame of the layer's
    /// composition with gmotion's state then.
    fn layer(&mut self, json: &mut Json, model: &Layer, clock: &[(f64, ShapeState)], depth: usize) {
        match model.kind {
            LayerKind::Shape => {
                if let Some(items) = json.get_mut("shapes").and_then(Json::as_array_mut) {
                    self.items(items, &model.shapes, clock);
                }
            }
            LayerKind::Precomp if model.tm.is_some() => {
                self.warn(
                    "colour and stroke width are not written into time-remapped precompositions",
                );
            }
            LayerKind::Precomp => {
                let assets = self.source.document.assets.iter();
                let found = model
                    .ref_id
                    .as_deref()
                    .and_then(|id| assets.clone().find(|a| a.id == id))
                    .and_then(|a| Some((a, a.layers.as_ref()?)));
                let original = self
                    .source
                    .json
                    .get("assets")
                    .and_then(Json::as_array)
                    .and_then(|list| {
                        list.iter()
                            .find(|a| a.get("id").and_then(Json::as_str) == model.ref_id.as_deref())
                    });
                let (Some((asset, inner)), Some(original)) = (found, original) else {
                    return;
                };
                if depth >= gmotion_lottie::build::MAX_PRECOMP_DEPTH {
                    return;
                }
                let inner_clock: Vec<(f64, ShapeState)> = clock
                    .iter()
                    .map(|(f, s)| (gmotion_lottie::build::inner_time(model, *f), *s))
                    .collect();
                let key = (
                    asset.id.clone(),
                    inner_clock.iter().map(|(t, _)| t.to_bits()).collect(),
                );
                if let Some(id) = self.made.get(&key) {
                    json["refId"] = Json::from(id.clone());
                    return;
                }
                if inner.len() > *self.budget {
                    return self.warn(&format!("more than {MAX_COPIED_LAYERS} layers of precompositions to copy with colour changes; the rest keep their colours"));
                }
                *self.budget -= inner.len();
                let mut copy = original.clone();
                let id = format!("{} gmotion {} {}", asset.id, self.suffix, self.copies.len());
                copy["id"] = Json::from(id.clone());
                self.made.insert(key, id.clone());
                if let Some(layers) = copy.get_mut("layers").and_then(Json::as_array_mut) {
                    for (lj, lm) in layers.iter_mut().zip(inner) {
                        self.layer(lj, lm, &inner_clock, depth + 1);
                    }
                }
                json["refId"] = Json::from(id);
                self.copies.push(copy);
            }
            LayerKind::Solid => self.solid(json, model, clock),
            LayerKind::Null => {}
            _ => self.warn(
                "colour and stroke width are written into shape layers and precompositions only",
            ),
        }
    }

    /// Restyles top-level item `k` of shape layer `json` (whose top-level items are
    /// `model`), one part of it.
    fn part(
        &mut self,
        json: &mut Json,
        model: &[ShapeItem],
        k: usize,
        clock: &[(f64, ShapeState)],
    ) {
        let styles_below = model.iter().skip(k + 1).any(|item| {
            matches!(
                item.kind,
                ShapeKind::Fill { .. } | ShapeKind::Stroke { .. } | ShapeKind::Gradient(_)
            )
        });
        if styles_below {
            self.warn("fills or strokes of its layer outside its group paint it too (and the layer's other groups); their colour and width are left as they are");
        }
        if let (Some(item), Some(m)) = (
            json.get_mut("shapes").and_then(|s| s.get_mut(k)),
            model.get(k),
        ) {
            self.items(std::slice::from_mut(item), std::slice::from_ref(m), clock);
        }
    }

    fn items(&mut self, json: &mut [Json], model: &[ShapeItem], clock: &[(f64, ShapeState)]) {
        for (j, m) in json.iter_mut().zip(model) {
            match &m.kind {
                ShapeKind::Group(sub) => {
                    if let Some(it) = j.get_mut("it").and_then(Json::as_array_mut) {
                        self.items(it, sub, clock);
                    }
                }
                ShapeKind::Fill { c, .. } => self.color(j, c.as_ref(), clock, |s| s.fill),
                ShapeKind::Stroke { c, w, .. } => {
                    self.color(j, c.as_ref(), clock, |s| s.stroke);
                    self.width(j, w.as_ref(), clock);
                }
                ShapeKind::Gradient(g) => {
                    let tint = |s: &ShapeState| if g.stroke { s.stroke } else { s.fill };
                    self.stops(j, g, clock, tint);
                    if g.stroke {
                        self.width(j, g.w.as_ref(), clock);
                    }
                }
                _ => {}
            }
        }
    }

    fn warn(&mut self, what: &str) {
        let w = Warning::about(self.label.clone(), what);
        if !self.warnings.contains(&w) {
            self.warnings.push(w);
        }
    }

    /// A solid layer whose fill changes becomes a shape layer drawing what the solid
    /// drew, a `sw` × `sh` rectangle of its colour from the layer's origin, whose fill is
    /// then tinted: Lottie cannot animate a solid's colour (`sc`), and a shape layer keeps
    /// everything else a layer has (transform, parent, masks, mattes, effects, timing). A
    /// solid draws no stroke, so only the fill's tint is written.
    fn solid(&mut self, json: &mut Json, model: &Layer, clock: &[(f64, ShapeState)]) {
        if clock.iter().all(|(_, s)| s.fill == Tint::NONE) {
            return;
        }
        // The colour and size gmotion's own render draws the solid with.
        let c = model
            .solid_color
            .as_deref()
            .and_then(Color::parse)
            .unwrap_or(Color::BLACK);
        let rgb = [c.r, c.g, c.b].map(f64::from);
        let (w, h) = (model.sw.unwrap_or(0.0), model.sh.unwrap_or(0.0));
        let corner = serde_json::json!([0, 0]);
        let rect = serde_json::json!({
            "ty": "sh",
            "nm": "gmotion solid",
            "ks": {"a": 0, "k": {
                "c": true,
                "v": [[0, 0], [w, 0], [w, h], [0, h]],
                "i": [corner, corner, corner, corner],
                "o": [corner, corner, corner, corner],
            }},
        });
        let mut fill = serde_json::json!({
            "ty": "fl",
            "nm": "gmotion solid colour",
            "o": {"a": 0, "k": 100},
            "r": 1,
        });
        // In the document's own scale (0–255 in a legacy one, see [`Walk::scale`]).
        let scale = self.scale();
        self.tinted_color(
            &mut fill,
            |_| vec![rgb[0] * scale, rgb[1] * scale, rgb[2] * scale, scale],
            clock,
            |s| s.fill,
        );
        let Some(layer) = json.as_object_mut() else {
            return;
        };
        for key in ["sc", "sw", "sh"] {
            layer.remove(key);
        }
        layer.insert("ty".into(), Json::from(4));
        layer.insert("shapes".into(), Json::Array(vec![rect, fill]));
    }

    /// The item's colour `c` tinted by `tint` of each state.
    fn color(
        &mut self,
        item: &mut Json,
        c: Option<&Num>,
        clock: &[(f64, ShapeState)],
        tint: impl Fn(&ShapeState) -> Tint,
    ) {
        if clock.iter().all(|(_, s)| tint(s) == Tint::NONE) {
            return;
        }
        if c.is_some_and(|c| c.expression) {
            return self
                .warn("an expression drives a colour; gmotion's colour motion is left out there");
        }
        self.tinted_color(
            item,
            |f| eval::num(c, f, &[0.0, 0.0, 0.0, 1.0]),
            clock,
            tint,
        );
    }

    /// Writes `item`'s colour `c`: its own colour at each frame (`own`) tinted by `tint`
    /// of the state then, reduced to the keyframes that matter.
    fn tinted_color(
        &mut self,
        item: &mut Json,
        own: impl Fn(f64) -> Vec<f64>,
        clock: &[(f64, ShapeState)],
        tint: impl Fn(&ShapeState) -> Tint,
    ) {
        let scale = self.scale();
        let samples = clock
            .iter()
            .map(|(f, s)| {
                let mut v = own(*f);
                v.resize(4, 1.0);
                let [r, g, b] = tinted(tint(s), [v[0], v[1], v[2]], scale);
                (*f, vec![r, g, b, v[3]])
            })
            .collect();
        item["c"] = to_json(&resampled(samples, COLOR_EPS * scale));
    }

    /// A gradient's colour stops tinted by `tint` of each state (its opacity stops kept).
    fn stops(
        &mut self,
        item: &mut Json,
        g: &gmotion_lottie::model::GradientItem,
        clock: &[(f64, ShapeState)],
        tint: impl Fn(&ShapeState) -> Tint,
    ) {
        if clock.iter().all(|(_, s)| tint(s) == Tint::NONE) {
            return;
        }
        let stops = &g.gradient.g;
        if stops.k.as_ref().is_some_and(|c| c.expression) {
            return self.warn(
                "an expression drives gradient colours; gmotion's colour motion is left out there",
            );
        }
        let own = |f: f64| eval::num(stops.k.as_ref(), f, &[]);
        let samples: Vec<(f64, Vec<f64>)> = clock
            .iter()
            .map(|(f, s)| {
                let mut v = own(*f);
                for k in 0..stops.p.min(v.len() / 4) {
                    let rgb = [v[4 * k + 1], v[4 * k + 2], v[4 * k + 3]];
                    let [r, gg, b] = tinted(tint(s), rgb, 1.0);
                    v[4 * k + 1..4 * k + 4].copy_from_slice(&[r, gg, b]);
                }
                (*f, v)
            })
            .collect();
        if let Some(gj) = item.get_mut("g").and_then(Json::as_object_mut) {
            gj.insert("k".into(), to_json(&resampled(samples, COLOR_EPS)));
        }
    }

    /// What a colour component of 1 is written as: 255 in a legacy document, whose fill and
    /// stroke colours lottie-web divides by 255 whatever they hold (a black fill tinted
    /// blue was written `[0.125, 0.5, 1]` and drawn black), else 1.
    fn scale(&self) -> f64 {
        if self.legacy { 255.0 } else { 1.0 }
    }

    /// The stroke's width `w` multiplied by each state's stroke-width factor.
    fn width(&mut self, item: &mut Json, w: Option<&Num>, clock: &[(f64, ShapeState)]) {
        if clock.iter().all(|(_, s)| s.stroke_width == 1.0) {
            return;
        }
        if w.is_some_and(|w| w.expression) {
            return self.warn("an expression drives a stroke width; gmotion's stroke-width motion is left out there");
        }
        let samples = clock
            .iter()
            .map(|(f, s)| (*f, vec![eval::scalar(w, *f, 1.0) * s.stroke_width.max(0.0)]))
            .collect();
        item["w"] = to_json(&resampled(samples, WIDTH_EPS));
    }
}

/// Most frames of a composition sampled to multiply gmotion's paint and opacity into the
/// source's own animated values (ten minutes at 30 fps).
pub(crate) const MAX_SAMPLED_FRAMES: usize = 18_000;

/// How many frames after its first the composition of `doc` is sampled over: all of them,
/// or [`MAX_SAMPLED_FRAMES`], with a warning under `label` (after them the last sampled
/// value holds).
pub(crate) fn sampled_frames(
    doc: &gmotion_lottie::model::Document,
    label: &str,
    warnings: &mut Vec<Warning>,
) -> usize {
    let span = (doc.op - doc.ip).ceil().max(1.0);
    if span > MAX_SAMPLED_FRAMES as f64 {
        let w = Warning::about(
            label.to_string(),
            format!(
                "the composition is {span} frames long; paint and opacity are written for its first {MAX_SAMPLED_FRAMES} frames, after which they hold"
            ),
        );
        if !warnings.contains(&w) {
            warnings.push(w);
        }
        return MAX_SAMPLED_FRAMES;
    }
    span as usize
}

/// `rgb` (in 0..`scale`) as `tint` shows it.
fn tinted(tint: Tint, rgb: [f64; 3], scale: f64) -> [f64; 3] {
    let c = |x: f64| (x / scale) as f32;
    let shown = tint.apply(Color {
        r: c(rgb[0]),
        g: c(rgb[1]),
        b: c(rgb[2]),
        a: 1.0,
    });
    [shown.r, shown.g, shown.b].map(|x| f64::from(x) * scale)
}

fn to_json(p: &Prop) -> Json {
    serde_json::to_value(p).unwrap_or(Json::Null)
}

/// A property from per-frame `samples` (composition frame, value): static when every
/// sample is equal, else linear keyframes at as few samples as keep every sample within
/// `eps` (in every component) of the line between the keyframes around it.
pub(crate) fn resampled(samples: Vec<(f64, Vec<f64>)>, eps: f64) -> Prop {
    let value = |v: &[f64]| match v {
        [x] => Value::Scalar(N::coord(*x)),
        v => Value::Vec(v.iter().map(|x| N::coord(*x)).collect()),
    };
    let first = samples.first().map(|s| s.1.clone()).unwrap_or_default();
    if samples.iter().all(|s| s.1 == first) {
        return Prop::fixed(value(&first));
    }
    // Greedy: from keyframe a, the farthest b whose line from a passes within eps of
    // every sample between them. A line from a is fixed by its slope, so each sample
    // between narrows the open interval of slopes that pass it (per component); b fits
    // while its own slope lies in the interval of the samples before it. Linear in the
    // sample count.
    let dims = first.len();
    let mut keep = vec![0];
    let mut a = 0;
    while a + 1 < samples.len() {
        let (ta, va) = &samples[a];
        let mut lo = vec![f64::NEG_INFINITY; dims];
        let mut hi = vec![f64::INFINITY; dims];
        let mut b = a + 1;
        while b + 1 < samples.len() {
            // Sample b becomes one between a and the candidate b + 1.
            let (tb, vb) = &samples[b];
            let dt = tb - ta;
            for d in 0..dims {
                let (x, p) = (
                    vb.get(d).copied().unwrap_or(0.0),
                    va.get(d).copied().unwrap_or(0.0),
                );
                lo[d] = lo[d].max((x - p - eps) / dt);
                hi[d] = hi[d].min((x - p + eps) / dt);
            }
            let (tc, vc) = &samples[b + 1];
            let fits = (0..dims).all(|d| {
                let slope = (vc.get(d).copied().unwrap_or(0.0) - va.get(d).copied().unwrap_or(0.0))
                    / (tc - ta);
                lo[d] < slope && slope < hi[d]
            });
            if !fits {
                break;
            }
            b += 1;
        }
        keep.push(b);
        a = b;
    }
    let mut kept: Vec<Keyframe> = keep
        .into_iter()
        .map(|i| {
            Keyframe::written(
                N::coord(samples[i].0),
                value(&samples[i].1),
                Some(LINEAR),
                false,
            )
        })
        .collect();
    if let Some(last) = kept.last_mut() {
        last.set_easing(None);
    }
    Prop::keyed(kept)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The keyframes' values at their times, for the first `dims` components.
    fn keys(p: &Prop) -> Vec<(f64, Vec<f64>)> {
        let Prop::Animated(ks) = p else {
            panic!("animated");
        };
        ks.iter()
            .map(|k| match k.value() {
                Value::Scalar(x) => (k.t.0, vec![x.0]),
                Value::Vec(v) => (k.t.0, v.iter().map(|x| x.0).collect()),
                _ => panic!("a number or a vector"),
            })
            .collect()
    }

    #[test]
    fn resampling_keeps_every_sample_within_eps_of_its_keyframes_line() {
        let eps = 0.01;
        let samples: Vec<(f64, Vec<f64>)> = (0..=300)
            .map(|f| {
                let t = f as f64;
                (
                    t,
                    vec![(t / 20.0).sin(), 0.002 * t, if f < 150 { 0.0 } else { 1.0 }],
                )
            })
            .collect();
        let kept = keys(&resampled(samples.clone(), eps));
        assert!(kept.len() < samples.len() / 3, "{} keyframes", kept.len());
        assert_eq!(kept.first().map(|k| k.0), Some(0.0));
        assert_eq!(kept.last().map(|k| k.0), Some(300.0));
        for (t, v) in &samples {
            let i = kept.iter().rposition(|k| k.0 <= *t).unwrap();
            let j = (i + 1).min(kept.len() - 1);
            let ((ta, va), (tb, vb)) = (&kept[i], &kept[j]);
            let u = if tb > ta { (t - ta) / (tb - ta) } else { 0.0 };
            for d in 0..3 {
                let line = va[d] + (vb[d] - va[d]) * u;
                // Keyframe values are rounded to what Lottie writes.
                assert!(
                    (line - v[d]).abs() < eps + 1e-3,
                    "frame {t}, component {d}: {line} for {}",
                    v[d]
                );
            }
        }
        // A straight line is its two ends.
        let line: Vec<(f64, Vec<f64>)> = (0..=100)
            .map(|f| (f as f64, vec![f as f64 * 0.5]))
            .collect();
        assert_eq!(keys(&resampled(line, eps)).len(), 2);
    }
}
