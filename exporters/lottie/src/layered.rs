//! Motion layered onto a Lottie source: the document an animation's scene was imported
//! from ([`gmotion_lottie::Source`]) written back as it was read, with gmotion's
//! motion on top.
//!
//! This writer lives in the Lottie exporter, which depends on the Lottie importer for the
//! source model, rather than in the importer: it needs the exporter's keyframe and
//! transform-level writing (`unit_motion`, `to_keyframes`, the skew-free levels) — one
//! keyframe writer for both kinds of Lottie output — and an importer must know nothing of
//! animations. Dependencies stay one way: core ← importer ← exporter ← output.
//!
//! What it does to the source (nothing else is re-encoded: unknown keys, masks, effects,
//! expressions, text, legacy keyframes and `v` pass through as they were read):
//!
//! - a unit with affine motion gets a chain of new null layers (`ty` 3, `nm` "gmotion TAG
//!   ID", fresh `ind`s, `ip`/`op` covering the composition) holding its motion's transform
//!   levels — the ones the plain export writes — parented where the unit's layer was, and
//!   the layer is re-parented to the chain. The motion is conjugated by the parent's world
//!   transform at the reference frame, so it acts about the same pivot as in gmotion's
//!   model; when the parent itself animates, the motion rides along with it. A matte
//!   source moves with its target through a chain of its own.
//! - opacity motion is multiplied into the unit layer's `ks.o`: keyframes of the static
//!   value times the multiplier; where both animate, the product sampled at every frame.
//!   An opacity an expression drives is left alone, with a warning naming the layer.
//! - colour and stroke-width motion are written into the unit's own fills, strokes and
//!   gradients (the `restyle` module); per-vertex motion is not layered yet: a warning names
//!   the unit.
//! - a part of a shape layer (`--units groups`: one of its top-level groups) is wrapped in
//!   new groups (`nm` "gmotion TAG ID") whose transforms hold its motion, conjugated by the
//!   layer's world transform at the reference frame; its opacity motion goes into the
//!   outermost wrapper's opacity. The layer and its other items are not touched.
//!
//! Layers keep their names; null layers gmotion adds are appended after the existing
//! layers, where they cannot change which layer a track matte applies to.

use kurbo::{Affine, Point};
use serde_json::Value as Json;

use gmotion::Warning;
use gmotion::engine::markers::Marker;
use gmotion::motion::Animation;
use gmotion::tolerance::Tolerance;
use gmotion_lottie::Source;
use gmotion_lottie::eval;
use gmotion_lottie::model::{ShapeItem, ShapeKind};

use crate::animate::{Bakes, UnitInfo, static_level, unit_motion};
use crate::geometry::decompose;
use crate::keys::{to_keyframes, within_range};
use crate::layers::{conjugate, full_transform};
use crate::model::{Layer, LayerKind, N, Prop, Transform, Value, WriteLayer};
use crate::{LottieError, LottieOptions, LottieOutput};

/// The source document as it was read (JSON-equal to the file, apart from key order).
pub fn source_verbatim(source: &Source) -> String {
    source.json.to_string()
}

/// Writes `source` with the motion of `anim` (whose scene was imported from it) layered on
/// top.
pub fn over_source(
    anim: &Animation,
    source: &Source,
    opts: &LottieOptions,
) -> Result<LottieOutput, LottieError> {
    if !(anim.fps.is_finite() && anim.fps > 0.0 && anim.duration.is_finite() && anim.duration > 0.0)
    {
        return Err(LottieError::Timing {
            fps: anim.fps,
            duration: anim.duration,
        });
    }
    let shapes = anim.scene.shapes.len();
    if anim.tracks.len() != shapes || source.units.len() != shapes {
        return Err(LottieError::Tracks {
            tracks: anim.tracks.len(),
            shapes: source.units.len(),
        });
    }
    let mut warnings = Vec::new();
    if opts.size.is_given() {
        warnings.push(Warning::new(
            "--width/--height do not resize a Lottie source; its composition size is kept",
        ));
    }
    let doc = &source.document;
    let fr = doc.fr;
    let (ip, op) = (doc.ip, doc.op);
    // The source's frames up to where every output ends (the duration rounded to whole
    // frames at the animation's own rate, `gmotion::canvas`).
    let frames = (anim.length() * fr).ceil().max(1.0) as usize;
    let mut json = source.json.clone();
    let Some(layers) = json.get_mut("layers").and_then(Json::as_array_mut) else {
        return Ok((json.to_string(), warnings));
    };
    let mut next_ind = layers
        .iter()
        .filter_map(|l| l.get("ind").and_then(Json::as_f64))
        .fold(0.0_f64, f64::max) as i64
        + 1;
    let mut nulls: Vec<Json> = Vec::new();
    let mut restyles: Vec<(usize, Option<usize>, usize, String)> = Vec::new();
    // Parts (`--units groups`) to wrap in groups holding their motion: layer, item, the
    // wrappers' transforms (outermost first).
    let mut wraps: Vec<(usize, usize, Vec<Transform>, String, String)> = Vec::new();
    // Layers with a part whose paint changes.
    let mut paint_parts = std::collections::BTreeSet::new();
    let bakes = Bakes::default();
    for (u, (track, shape)) in anim.tracks.iter().zip(&anim.scene.shapes).enumerate() {
        let info = UnitInfo {
            bbox: shape.bbox,
            centroid: shape.centroid,
            // The source's own paint is kept as it is: no stroke is outlined here.
            strokes: false,
        };
        let name = format!("{}:{}", shape.tag, shape.id);
        // A morph is not motion of the unit's layer: said here, whether or not it moves.
        if !track.morphs.is_empty() {
            warnings.push(Warning::about(
                name.clone(),
                "a morph is not yet layered onto a Lottie source; left out",
            ));
        }
        let motion = unit_motion(track, info, fr, frames, opts.tolerance, &bakes);
        if !motion.is_animated() {
            continue;
        }
        let unit = &source.units[u];
        if !motion.trim.is_empty() {
            warnings.push(Warning::about(
                name.clone(),
                "a trim is not yet layered onto a Lottie source; left out",
            ));
        }
        if !motion.deform_frames.is_empty() {
            warnings.push(Warning::about(
                name.clone(),
                "per-vertex motion is not yet layered onto a Lottie source; left out",
            ));
        }
        if !(motion.fill.is_empty() && motion.stroke.is_empty() && motion.stroke_width.is_empty())
            && let Some(&li) = unit.layers.first()
        {
            restyles.push((li, unit.part, u, name.clone()));
        }
        if let (Some(k), Some(&li)) = (unit.part, unit.layers.first()) {
            if !(motion.opacity.is_empty()
                && motion.fill.is_empty()
                && motion.stroke.is_empty()
                && motion.stroke_width.is_empty())
            {
                paint_parts.insert(li);
            }
            let world = unit
                .parent_world
                .first()
                .copied()
                .unwrap_or(Affine::IDENTITY);
            let levels = match motion.levels.is_empty() {
                true => Some(Vec::new()),
                false => in_parent_space(&motion.levels, world),
            };
            let Some(mut levels) = levels else {
                warnings.push(Warning::about(
                    name.clone(),
                    "its layer is scaled to nothing at the reference frame; the motion is left out",
                ));
                continue;
            };
            for level in &mut levels {
                retime(level, |t| ip + t);
            }
            if !motion.opacity.is_empty() {
                if levels.is_empty() {
                    levels.push(Transform::empty());
                }
                levels[0].o = Some(opacity_prop(&motion.opacity, 100.0, ip));
            }
            let nm = format!("gmotion {} {}", shape.tag, shape.id);
            wraps.push((li, k, levels, nm, name));
            continue;
        }
        if !motion.levels.is_empty() {
            for (k, (&li, &parent_world)) in unit.layers.iter().zip(&unit.parent_world).enumerate()
            {
                let Some(levels) = in_parent_space(&motion.levels, parent_world) else {
                    warnings.push(Warning::about(
                        name.clone(),
                        "its parent layer is scaled to nothing at the reference frame; the motion is left out",
                    ));
                    continue;
                };
                let Some(layer) = layers.get_mut(li).and_then(Json::as_object_mut) else {
                    continue;
                };
                let mut parent = layer.get("parent").cloned();
                let role = if k == 0 { "" } else { " matte" };
                for (n, level) in levels.into_iter().enumerate() {
                    let nm = match n {
                        0 => format!("gmotion {} {}{role}", shape.tag, shape.id),
                        n => format!("gmotion {} {}{role}/{n}", shape.tag, shape.id),
                    };
                    let mut null = Layer::new(LayerKind::Null, nm, 0, ip, op);
                    null.ks = full_transform(level);
                    retime(&mut null.ks, |t| ip + t);
                    nulls.push(null_json(&null, next_ind, parent.take()));
                    parent = Some(Json::from(next_ind));
                    next_ind += 1;
                }
                if let Some(p) = parent {
                    layer.insert("parent".into(), p);
                }
            }
        }
        if !motion.opacity.is_empty()
            && let Some(&li) = unit.layers.first()
            && let Some(layer) = layers.get_mut(li)
        {
            multiply_opacity(
                layer,
                li,
                source,
                track,
                &motion.opacity,
                &name,
                &mut warnings,
            );
        }
    }
    layers.extend(nulls);
    // Parts painted by their layer's own fills and strokes get copies of them, so that
    // their colour and opacity can change alone: the layer's new top-level items, and
    // where each old one went.
    let mut pushed: std::collections::HashMap<usize, (Vec<ShapeItem>, Vec<usize>)> =
        Default::default();
    for li in paint_parts {
        if let (Some(model), Some(layer)) = (doc.layers.get(li), layers.get_mut(li))
            && let Some(p) = styles_pushed_down(layer, &model.shapes)
        {
            pushed.insert(li, p);
        }
    }
    let moved = |li: usize, k: usize| pushed.get(&li).map_or(k, |(_, at)| at[k]);
    let items_of = |li: usize| match pushed.get(&li) {
        Some((items, _)) => items.as_slice(),
        None => doc.layers.get(li).map_or(&[][..], |l| l.shapes.as_slice()),
    };
    // Colour and stroke width go into the layers' own items (and copies of the assets
    // they draw), which needs the whole document.
    let mut tally = crate::restyle::Tally {
        warnings: &mut warnings,
        budget: crate::restyle::MAX_COPIED_LAYERS,
    };
    for (li, part, u, name) in restyles {
        crate::restyle::restyle(
            &mut json,
            li,
            part.map(|k| (moved(li, k), items_of(li))),
            source,
            &anim.tracks[u],
            &name,
            &mut tally,
        );
    }
    // Last: wrapping moves an item into a new group, where the restyling would not find it.
    for (li, k, levels, nm, name) in wraps {
        let k = moved(li, k);
        let fades = levels.first().is_some_and(|l| l.o.is_some());
        if fades
            && items_of(li).iter().skip(k + 1).any(|i| {
                matches!(
                    i.kind,
                    ShapeKind::Fill { .. } | ShapeKind::Stroke { .. } | ShapeKind::Gradient(_)
                )
            })
        {
            warnings.push(Warning::about(
                name,
                "fills or strokes of its layer outside its group paint it, with a modifier that takes the layer's outlines together; its opacity motion does not reach them",
            ));
        }
        if let Some(item) = json
            .get_mut("layers")
            .and_then(|l| l.get_mut(li))
            .and_then(|l| l.get_mut("shapes"))
            .and_then(|s| s.get_mut(k))
        {
            wrap(item, levels, &nm);
        }
    }
    with_markers(&mut json, &opts.markers, ip, fr);
    if opts.slots.any() {
        for (u, shape) in anim.scene.shapes.iter().enumerate() {
            let unit = &source.units[u];
            let part = unit
                .part
                .and_then(|k| unit.layers.first().map(|&li| moved(li, k)));
            mark_slots(
                &mut json,
                unit.layers.first().copied(),
                part,
                &shape.tag,
                opts.slots,
            );
        }
        warnings.extend(
            crate::slots::write(&mut json)
                .into_iter()
                .map(Warning::from),
        );
    }
    if opts.pack {
        crate::pack::pack(&mut json);
    }
    Ok((json.to_string(), warnings))
}

/// Marks the paints of one unit of a Lottie source for [`crate::slots::write`]: the solid
/// fills and strokes of its layer `li` (of its top-level item `part` alone for a part),
/// however deep in groups, and its layer's opacity (a whole layer only: a part's opacity
/// is no property of its own). A precomposition's content is shared by every layer that
/// shows it, so only its layer's opacity is marked. Tags whose units' properties differ
/// are then refused by `slots::write`, with a warning, as for an SVG scene.
fn mark_slots(
    json: &mut Json,
    li: Option<usize>,
    part: Option<usize>,
    tag: &str,
    kinds: gmotion::engine::slots::SlotKinds,
) {
    let Some(layer) = li
        .and_then(|li| json.get_mut("layers")?.get_mut(li))
        .and_then(Json::as_object_mut)
    else {
        return;
    };
    if kinds.opacity && part.is_none() {
        layer.insert(
            crate::slots::MARK.into(),
            serde_json::json!([format!("{tag}.opacity"), false]),
        );
    }
    let Some(shapes) = layer.get_mut("shapes").and_then(Json::as_array_mut) else {
        return;
    };
    let items: &mut [Json] = match part {
        Some(k) => shapes.get_mut(k..=k).unwrap_or_default(),
        None => shapes,
    };
    fn paint(item: &mut Json, tag: &str, kinds: gmotion::engine::slots::SlotKinds) {
        let Some(o) = item.as_object_mut() else {
            return;
        };
        let kind = match o.get("ty").and_then(Json::as_str) {
            Some("fl") if kinds.fill => Some("fill"),
            Some("st") if kinds.stroke => Some("stroke"),
            _ => None,
        };
        if let Some(kind) = kind
            && o.contains_key("c")
        {
            o.insert(
                crate::slots::MARK.into(),
                Json::String(format!("{tag}.{kind}")),
            );
        }
        if let Some(it) = o.get_mut("it").and_then(Json::as_array_mut) {
            it.iter_mut().for_each(|i| paint(i, tag, kinds));
        }
    }
    items.iter_mut().for_each(|i| paint(i, tag, kinds));
}

/// A shape layer's top-level styles (fills, strokes, gradients) moved into copies inside
/// each of its parts (`--units groups`), so that a part painted by them can be restyled and
/// faded alone: each part becomes a group of the part and the styles below it, in their
/// order, with the modifiers among them that change each outline alone (round corners,
/// trim paths trimming each outline), and the layer's own styles and modifiers go. Every
/// outline is then modified and painted as before. Done only for layers that need it (a
/// part with paint motion, and a style below a part) and can take it: no modifier that
/// treats the outlines above it together (a repeater, merge paths, trim paths as one run,
/// an unknown item) at the top level. Returns the layer's new top-level items and the new
/// index of each old one (a removed item's: the next item's), or `None` when the layer
/// is left as it was.
fn styles_pushed_down(
    layer: &mut Json,
    model: &[ShapeItem],
) -> Option<(Vec<ShapeItem>, Vec<usize>)> {
    let is_style = |k: &ShapeKind| {
        matches!(
            k,
            ShapeKind::Fill { .. } | ShapeKind::Stroke { .. } | ShapeKind::Gradient(_)
        )
    };
    let copied = |k: &ShapeKind| {
        is_style(k)
            || matches!(
                k,
                ShapeKind::RoundCorners { .. }
                    | ShapeKind::PuckerBloat { .. }
                    | ShapeKind::ZigZag { .. }
                    | ShapeKind::OffsetPath { .. }
                    | ShapeKind::Trim {
                        individually: false,
                        ..
                    }
            )
    };
    let first_part = model.iter().position(|i| i.kind.part_name().is_some())?;
    if !model[first_part..].iter().any(|i| is_style(&i.kind))
        || model
            .iter()
            .any(|i| !i.hidden && i.kind.part_name().is_none() && !copied(&i.kind))
    {
        return None;
    }
    let shapes = layer.get_mut("shapes").and_then(Json::as_array_mut)?;
    if shapes.len() != model.len() {
        return None;
    }
    let mut json_out = Vec::new();
    let mut model_out = Vec::new();
    let mut at = Vec::with_capacity(model.len());
    for (k, (j, m)) in shapes.iter().zip(model).enumerate() {
        at.push(json_out.len());
        if copied(&m.kind) {
            continue;
        }
        if m.kind.part_name().is_none() {
            json_out.push(j.clone());
            model_out.push(m.clone());
            continue;
        }
        let below = (k + 1..model.len()).filter(|&b| copied(&model[b].kind));
        let mut it: Vec<Json> = vec![j.clone()];
        let mut sub = vec![m.clone()];
        for b in below {
            it.push(shapes[b].clone());
            sub.push(model[b].clone());
        }
        it.push(
            serde_json::to_value(crate::model::Shape::Transform(Transform::empty()))
                .unwrap_or(Json::Null),
        );
        let mut g = serde_json::Map::new();
        g.insert("ty".into(), Json::from("gr"));
        g.insert("nm".into(), Json::from(format!("gmotion paint {}", m.nm)));
        g.insert("it".into(), Json::Array(it));
        json_out.push(Json::Object(g));
        model_out.push(ShapeItem {
            at: m.at.clone(),
            nm: m.nm.clone(),
            hidden: m.hidden,
            kind: ShapeKind::Group(sub),
        });
    }
    *shapes = json_out;
    Some((model_out, at))
}

/// Wraps shape item `item` in nested groups named `nm` whose transforms are `levels`
/// (outermost first), so that it moves by them inside its layer.
fn wrap(item: &mut Json, levels: Vec<Transform>, nm: &str) {
    for (n, level) in levels.into_iter().enumerate().rev() {
        let nm = match n {
            0 => nm.to_string(),
            n => format!("{nm}/{n}"),
        };
        let tr = serde_json::to_value(crate::model::Shape::Transform(level)).unwrap_or(Json::Null);
        let inner = std::mem::take(item);
        let mut g = serde_json::Map::new();
        g.insert("ty".into(), Json::from("gr"));
        g.insert("nm".into(), Json::from(nm));
        g.insert("it".into(), Json::Array(vec![inner, tr]));
        *item = Json::Object(g);
    }
}

/// A null layer as After Effects writes one, keys in its order: `ddd` first, since
/// rlottie reads a layer's transform as 3D (ignoring `r`) unless it has seen `ddd: 0`.
fn null_json(null: &Layer, ind: i64, parent: Option<Json>) -> Json {
    let mut o = serde_json::Map::new();
    o.insert("ddd".into(), Json::from(0));
    o.insert("ind".into(), Json::from(ind));
    o.insert("ty".into(), Json::from(3));
    o.insert("nm".into(), Json::from(null.nm.clone()));
    if let Some(p) = parent {
        o.insert("parent".into(), p);
    }
    o.insert("sr".into(), Json::from(1));
    o.insert(
        "ks".into(),
        serde_json::to_value(&null.ks).unwrap_or(Json::Null),
    );
    o.insert("ao".into(), Json::from(0));
    o.insert(
        "ip".into(),
        serde_json::to_value(null.ip).unwrap_or(Json::Null),
    );
    o.insert(
        "op".into(),
        serde_json::to_value(null.op).unwrap_or(Json::Null),
    );
    o.insert("st".into(), Json::from(0));
    o.insert("bm".into(), Json::from(0));
    Json::Object(o)
}

/// Canvas-space levels acting in the space of a parent whose world transform at the
/// reference frame is `a`: `A⁻¹·L₁·…·Lₙ·A` as levels. `None` when `a` is singular.
fn in_parent_space(levels: &[Transform], a: Affine) -> Option<Vec<Transform>> {
    let [m11, m12, m21, m22, _, _] = a.as_coeffs();
    if Tolerance::Below(1e-12).same_all(&[m11, m12, m21, m22], &[1.0, 0.0, 0.0, 1.0]) {
        // A translation (or nothing): shift the pivot and the position.
        return Some(conjugate(levels.to_vec(), a));
    }
    if a.determinant().abs() < 1e-12 {
        return None;
    }
    let mut out: Vec<Transform> = decompose(a.inverse(), Point::ORIGIN)
        .iter()
        .map(static_level)
        .collect();
    out.extend(levels.iter().cloned());
    out.extend(decompose(a, Point::ORIGIN).iter().map(static_level));
    Some(out)
}

/// An opacity of `base` percent times the multiplier `keys` (frames from the animation's
/// start), keyed in the composition's frames (which start at `ip`).
fn opacity_prop(keys: &[gmotion::keyframe::Key<f64>], base: f64, ip: f64) -> Prop {
    let at = |a: &f64, b: &f64, p: f64| a + (b - a) * p;
    let keys = within_range(
        keys,
        |a, b, lo, hi| {
            [lo, hi]
                .iter()
                .any(|&p| !(0.0..=1.0).contains(&at(a, b, p)))
        },
        |a, b, p| at(a, b, p).clamp(0.0, 1.0),
    );
    let mut kfs = to_keyframes(&keys, |m| Value::Scalar(N::coord(base * m)));
    for k in &mut kfs {
        k.t = N::coord(ip + k.t.0);
    }
    Prop::keyed(kfs)
}

/// Moves every keyframe time of `tr` through `f`.
fn retime(tr: &mut Transform, f: impl Fn(f64) -> f64) {
    for p in [&mut tr.a, &mut tr.p, &mut tr.s, &mut tr.r, &mut tr.o]
        .into_iter()
        .flatten()
    {
        if let Prop::Animated(keys) = p {
            for k in keys {
                k.t = N::coord(f(k.t.0));
            }
        }
    }
}

/// How far, in percent, a resampled opacity may stray from its keyframes' line.
const OPACITY_EPS: f64 = 0.05;

/// Multiplies the opacity multiplier `keys` (frames from the animation's start at the
/// source's frame rate) into layer `li`'s `ks.o`.
fn multiply_opacity(
    layer: &mut Json,
    li: usize,
    source: &Source,
    track: &gmotion::motion::Track,
    keys: &[gmotion::keyframe::Key<f64>],
    name: &str,
    warnings: &mut Vec<Warning>,
) {
    let doc = &source.document;
    let Some(model) = doc.layers.get(li) else {
        return;
    };
    let label = format!("{name} (layer \"{}\")", model.nm);
    if model.ks.o.as_ref().is_some_and(|o| o.expression) {
        warnings.push(Warning::about(
            label,
            "an expression drives its opacity; gmotion's opacity motion is left out",
        ));
        return;
    }
    // Keyframe times of a layer's properties are in the time of its composition (players
    // subtract the start time from both the time and the keyframes).
    let animated = matches!(
        model.ks.o.as_ref().map(|o| &o.value),
        Some(gmotion_lottie::model::Prop::Animated(_))
    );
    let prop = if animated {
        // Both animate: the product at every frame of the composition.
        let frames = crate::restyle::sampled_frames(doc, &label, warnings);
        let samples: Vec<(f64, Vec<f64>)> = (0..=frames)
            .map(|f| {
                let comp = doc.ip + f as f64;
                let own = eval::scalar(model.ks.o.as_ref(), comp, 100.0);
                let m = track.state_at(f as f64 / doc.fr).opacity.clamp(0.0, 1.0);
                (comp, vec![own * m])
            })
            .collect();
        crate::restyle::resampled(samples, OPACITY_EPS)
    } else {
        opacity_prop(keys, eval::scalar(model.ks.o.as_ref(), 0.0, 100.0), doc.ip)
    };
    let Some(ks) = layer.get_mut("ks").and_then(Json::as_object_mut) else {
        if let Some(l) = layer.as_object_mut() {
            let mut ks = serde_json::Map::new();
            ks.insert(
                "o".into(),
                serde_json::to_value(&prop).unwrap_or(Json::Null),
            );
            l.insert("ks".into(), Json::Object(ks));
        }
        return;
    };
    ks.insert(
        "o".into(),
        serde_json::to_value(&prop).unwrap_or(Json::Null),
    );
}

/// Adds `markers` to the document's own (`ip`, `fr` its first frame and rate): one of the
/// same name is replaced, the others are kept.
fn with_markers(json: &mut Json, markers: &[Marker], ip: f64, fr: f64) {
    if markers.is_empty() {
        return;
    }
    let Some(doc) = json.as_object_mut() else {
        return;
    };
    let list = doc
        .entry("markers")
        .or_insert_with(|| Json::Array(Vec::new()));
    if !list.is_array() {
        *list = Json::Array(Vec::new());
    }
    let Some(list) = list.as_array_mut() else {
        return;
    };
    for m in markers {
        list.retain(|old| old.get("cm").and_then(Json::as_str) != Some(m.name.as_str()));
        list.push(serde_json::to_value(crate::model::MarkerOut::of(m, ip, fr)).unwrap_or_default());
    }
}
