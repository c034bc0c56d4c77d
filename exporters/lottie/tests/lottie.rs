//! Lottie export: structure of the JSON, and exactness checked by playing it back with a
//! small Lottie evaluator written here from the format (keyframes with Bézier easing and
//! holds, transform levels `T(p)·R(r)·S(s)·T(-a)`, layer parenting), compared with the
//! motion model's own `Track::state_at` and `Track::deform`.

use std::sync::Arc;

use gmotion::color::Color;
use gmotion::motion::{Animation, Blend, Component, Interp, MotionKind, MotionSeg, Timing, Track};
#[cfg(feature = "players")]
use gmotion::motion::{AttrSeg, Field, Grid, Tint};
#[cfg(feature = "players")]
use gmotion::scene::LineJoin;
use gmotion::scene::{
    ClipPath, Fill, FillRule, Group, Mask, MaskKind, Node, Paint, PathNode, RadialGradient, Scene,
    SceneBuilder, Spread, Stop, Stroke,
};
use gmotion::signals::Easing;
use gmotion_export_lottie::{LottieOptions, layer_names, still_to_lottie, to_lottie};
use kurbo::{Affine, BezPath, Point, Rect, Shape as _, Vec2};
use serde_json::Value;

#[cfg(feature = "players")]
use crate::support::players::{Player, assert_plays_like_model, frames_to_check};

/// Plays `json` (the export of `anim`) in every real player in `players` against the
/// model's own rendering, at twice the canvas width: the evaluator below checks geometry to
/// a hundredth of a pixel, the players decide whether the file draws what it should.
#[cfg(feature = "players")]
fn plays(case: &str, anim: &Animation, json: &str, players: &[Player]) {
    let width = (2.0 * anim.scene.width).round() as u32;
    assert_plays_like_model(case, anim, json, &frames_to_check(anim), width, players);
}

// ---- a Lottie evaluator for the subset gmotion writes -------------------------------------

fn num(v: &Value) -> f64 {
    v.as_f64()
        .unwrap_or_else(|| panic!("number expected, got {v}"))
}

/// A value as a vector (a number becomes a one-element vector).
fn vector(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().map(num).collect(),
        other => vec![num(other)],
    }
}

fn handle(h: &Value, axis: &str) -> f64 {
    match &h[axis] {
        Value::Array(a) => num(&a[0]),
        other => num(other),
    }
}

/// CSS cubic-bezier timing function, solved by bisection.
fn ease(x1: f64, y1: f64, x2: f64, y2: f64, x: f64) -> f64 {
    let b = |a: f64, c: f64, s: f64| {
        let m = 1.0 - s;
        3.0 * m * m * s * a + 3.0 * m * s * s * c + s * s * s
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if b(x1, x2, mid) < x {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    b(y1, y2, 0.5 * (lo + hi))
}

/// A property's value at `frame`; `lerp` interpolates two keyframe values.
fn prop_at<T>(
    prop: &Value,
    frame: f64,
    fixed: impl Fn(&Value) -> T,
    lerp: impl Fn(&T, &T, f64) -> T,
) -> T {
    if prop["a"] == 0 {
        return fixed(&prop["k"]);
    }
    let keys = prop["k"].as_array().expect("keyframes");
    assert!(
        keys.len() >= 2,
        "an animated property has at least two keyframes"
    );
    let kv = |k: &Value| fixed(&k["s"]);
    if frame <= num(&keys[0]["t"]) {
        return kv(&keys[0]);
    }
    for w in keys.windows(2) {
        let (t0, t1) = (num(&w[0]["t"]), num(&w[1]["t"]));
        assert!(t1 >= t0, "keyframes in time order");
        if frame < t1 {
            if w[0]["h"] == 1 {
                return kv(&w[0]);
            }
            let u = (frame - t0) / (t1 - t0);
            let (o, i) = (&w[0]["o"], &w[0]["i"]);
            let y = ease(
                handle(o, "x"),
                handle(o, "y"),
                handle(i, "x"),
                handle(i, "y"),
                u,
            );
            return lerp(&kv(&w[0]), &kv(&w[1]), y);
        }
    }
    kv(keys.last().unwrap())
}

fn vec_at(prop: &Value, frame: f64) -> Vec<f64> {
    // Keyframe values of scalars are one-element arrays; fixed ones are bare numbers.
    prop_at(prop, frame, vector, |a, b, y| {
        a.iter().zip(b).map(|(p, q)| p + (q - p) * y).collect()
    })
}

/// A transform object at `frame` (defaults as the format defines them).
fn transform_at(tr: &Value, frame: f64) -> Affine {
    assert!(
        tr.get("sk").is_none_or(|sk| vec_at(sk, frame)[0] == 0.0),
        "no skew is ever written: {tr}"
    );
    let v2 = |key: &str, default: [f64; 2]| {
        tr.get(key).map_or(Vec2::new(default[0], default[1]), |p| {
            // lottie-web draws nothing when a shape group holds a split position, and
            // layers never need one: gmotion writes none (see `lottie_web_problems`).
            assert!(p.get("s").is_none(), "a split position: {tr}");
            let v = vec_at(p, frame);
            Vec2::new(v[0], v[1])
        })
    };
    let a = v2("a", [0.0, 0.0]);
    let p = v2("p", [0.0, 0.0]);
    let s = v2("s", [100.0, 100.0]) / 100.0;
    let r = tr.get("r").map_or(0.0, |p| vec_at(p, frame)[0]);
    Affine::translate(p)
        * Affine::rotate(r.to_radians())
        * Affine::scale_non_uniform(s.x, s.y)
        * Affine::translate(-a)
}

fn opacity_at(tr: &Value, frame: f64) -> f64 {
    tr.get("o").map_or(1.0, |p| vec_at(p, frame)[0] / 100.0)
}

/// A drawn path: its outline at `frame` in canvas space, with the colour and opacity
/// it is drawn with (the colours and opacity are read by the player tests only).
#[derive(Debug)]
#[cfg_attr(not(feature = "players"), allow(dead_code))]
struct Drawn {
    points: Vec<Point>,
    fill: Option<[f64; 3]>,
    stroke_width: Option<f64>,
    opacity: f64,
}

fn bezier_points(b: &Value) -> Vec<Point> {
    b["v"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| Point::new(num(&p[0]), num(&p[1])))
        .collect()
}

fn shape_points(ks: &Value, frame: f64) -> Vec<Point> {
    prop_at(
        ks,
        frame,
        |v| {
            let b = if v.is_array() { &v[0] } else { v };
            bezier_points(b)
        },
        |a, b, y| a.iter().zip(b).map(|(p, q)| p.lerp(*q, y)).collect(),
    )
}

/// Walks a group's items (topmost first), applying its transform to the paths in it.
fn walk(items: &[Value], m: Affine, opacity: f64, frame: f64, out: &mut Vec<Drawn>) {
    let tr = items.iter().find(|it| it["ty"] == "tr");
    let (m, opacity) = match tr {
        Some(tr) => (m * transform_at(tr, frame), opacity * opacity_at(tr, frame)),
        None => (m, opacity),
    };
    let fill = items.iter().find(|it| it["ty"] == "fl").map(|f| {
        let c = vec_at(&f["c"], frame);
        [c[0], c[1], c[2]]
    });
    let stroke_width = items
        .iter()
        .find(|it| it["ty"] == "st")
        .map(|s| vec_at(&s["w"], frame)[0]);
    for it in items {
        match it["ty"].as_str().unwrap() {
            "gr" => walk(it["it"].as_array().unwrap(), m, opacity, frame, out),
            "sh" => out.push(Drawn {
                points: shape_points(&it["ks"], frame)
                    .into_iter()
                    .map(|p| m * p)
                    .collect(),
                fill,
                stroke_width,
                opacity,
            }),
            _ => {}
        }
    }
}

/// A layer's transform at `frame`, following its parents.
fn layer_matrix(layers: &[Value], layer: &Value, frame: f64) -> Affine {
    let own = transform_at(&layer["ks"], frame);
    match layer.get("parent") {
        Some(p) => {
            let parent = layers
                .iter()
                .find(|l| l["ind"] == *p)
                .expect("parent layer exists");
            layer_matrix(layers, parent, frame) * own
        }
        None => own,
    }
}

/// Everything the layer named `name` draws at `frame`.
fn drawn(doc: &Value, name: &str, frame: f64) -> Vec<Drawn> {
    let layers = doc["layers"].as_array().unwrap();
    let layer = layers
        .iter()
        .find(|l| l["nm"] == name)
        .unwrap_or_else(|| panic!("no layer named {name}"));
    let m = layer_matrix(layers, layer, frame);
    let mut out = Vec::new();
    walk(
        layer["shapes"].as_array().unwrap(),
        m,
        opacity_at(&layer["ks"], frame),
        frame,
        &mut out,
    );
    out
}

fn parse(json: &str) -> Value {
    serde_json::from_str(json).expect("valid JSON")
}

/// Every object in the document with its key, for "never written" checks.
#[cfg(feature = "players")]
fn keys_anywhere(v: &Value, key: &str) -> usize {
    match v {
        Value::Object(m) => {
            m.get(key).is_some() as usize + m.values().map(|x| keys_anywhere(x, key)).sum::<usize>()
        }
        Value::Array(a) => a.iter().map(|x| keys_anywhere(x, key)).sum(),
        _ => 0,
    }
}

// ---- scenes and motions ------------------------------------------------------------------

fn rect_path(r: Rect) -> BezPath {
    r.to_path(0.1)
}

fn solid(c: Color) -> Option<Fill> {
    Some(Fill::solid(c))
}

#[cfg(feature = "players")]
fn stroke(width: f64) -> Option<Stroke> {
    Some(Stroke::solid(Color::BLACK, width))
}

/// A scene whose shapes are the given paths (tag `t`, ids `p0`, `p1`, …), each directly
/// under the root, measured as the importer measures them.
fn scene(paths: Vec<(BezPath, Option<Fill>, Option<Stroke>)>) -> Scene {
    let mut b = SceneBuilder::new(400.0, 300.0);
    for (i, (path, fill, stroke)) in paths.into_iter().enumerate() {
        b = b.unit(
            "t",
            Node::Path(PathNode::new(format!("p{i}"), path, fill, stroke)),
        );
    }
    b.build()
}

/// A scene of one black rectangle (`p0`, tag `t`).
fn black_rect(r: Rect) -> Scene {
    scene(vec![(rect_path(r), solid(Color::BLACK), None)])
}

fn rigid(pivot: Point, comps: &[Component], interp: Interp) -> MotionKind {
    let blend: Blend = Arc::from([(1.0, Arc::from(comps))]);
    MotionKind::Rigid {
        pivot,
        blend,
        interp,
    }
}

/// Appends a window of `kind` over `[t0, t1]` of a motion timed by `timing`, starting
/// from where the track is at `t0`.
fn push(track: &mut Track, t0: f64, t1: f64, timing: &Timing, kind: &MotionKind) {
    let start = track.transform_at(t0);
    track.motions.push(MotionSeg {
        t0,
        t1,
        timing: timing.clone(),
        kind: kind.clone(),
        start,
    });
}

/// An opacity change from `from` to `to` over its timing's window.
#[cfg(feature = "players")]
fn fade(track: &mut Track, timing: Timing, from: f64, to: f64) {
    track.opacity.push(AttrSeg {
        t0: timing.start,
        t1: timing.end,
        timing,
        from,
        to,
    });
}

fn animation(scene: Scene, tracks: Vec<Track>, duration: f64) -> Animation {
    Animation {
        scene,
        duration,
        fps: 30.0,
        looping: true,
        tracks,
    }
}

/// A looping animation of `s`'s one shape, moved by `kind` over the whole window of its
/// timing.
fn one_motion(s: Scene, tm: &Timing, kind: &MotionKind, duration: f64) -> Animation {
    let mut track = Track::default();
    push(&mut track, tm.start, tm.end, tm, kind);
    animation(s, vec![track], duration)
}

/// `anim` exported with the default options, and its parsed document.
fn export(anim: &Animation) -> (String, Value) {
    let (json, _) = to_lottie(anim, &LottieOptions::default()).unwrap();
    let doc = parse(&json);
    (json, doc)
}

const EASE_IN_OUT: Easing = Easing::CubicBezier([0.42, 0.0, 0.58, 1.0]);

/// The largest distance between the exported outline and the model's, over `samples`
/// instants per frame, for every path unit of `anim`.
fn max_error(anim: &Animation, doc: &Value, samples: usize) -> f64 {
    let frames = anim.frame_count();
    let names = layer_names(&anim.scene);
    let mut worst: f64 = 0.0;
    for (i, name) in names.iter().enumerate() {
        let Some(Node::Path(p)) = anim.scene.unit_node(i) else {
            panic!("path units")
        };
        let rest: Vec<Point> = p
            .path
            .elements()
            .iter()
            .filter_map(|e| e.end_point())
            .collect();
        for k in 0..=frames * samples {
            let frame = k as f64 / samples as f64;
            let t = frame / anim.fps;
            let got = drawn(doc, name, frame);
            let track = &anim.tracks[i];
            let want: Vec<Point> = if track.deforms() {
                rest.iter().map(|q| track.deform(*q, t)).collect()
            } else {
                let m = track.state_at(t).transform * anim.scene.shapes[i].parent_transform;
                rest.iter().map(|q| m * *q).collect()
            };
            let pts = &got[0].points;
            // The exported outline drops the duplicate closing vertex; match by nearest.
            for w in &want {
                let d = pts
                    .iter()
                    .map(|g| (*g - *w).hypot())
                    .fold(f64::INFINITY, f64::min);
                worst = worst.max(d);
            }
        }
    }
    worst
}

#[cfg(feature = "players")]
fn animated_keys(doc: &Value) -> usize {
    fn count(v: &Value) -> usize {
        match v {
            Value::Object(m) => {
                let own = if m.get("a") == Some(&Value::from(1)) {
                    m["k"].as_array().map_or(0, Vec::len)
                } else {
                    0
                };
                own + m.values().map(count).sum::<usize>()
            }
            Value::Array(a) => a.iter().map(count).sum(),
            _ => 0,
        }
    }
    count(doc)
}

// ---- structure ---------------------------------------------------------------------------

#[cfg(feature = "players")]
#[test]
fn layers_are_named_after_tags_and_carry_no_skew() {
    let s = scene(vec![
        (
            rect_path(Rect::new(10.0, 10.0, 50.0, 50.0)),
            solid(Color::rgb(1.0, 0.0, 0.0)),
            None,
        ),
        (
            rect_path(Rect::new(100.0, 10.0, 150.0, 60.0)),
            solid(Color::rgb(0.0, 0.0, 1.0)),
            None,
        ),
    ]);
    let mut tracks = vec![Track::default(), Track::default()];
    let tm = Timing::new(0.0, 2.0, 0.0, Easing::Linear, false);
    let kind = rigid(
        Point::new(125.0, 35.0),
        &[Component::Skew(30.0, 0.0), Component::Rotate(45.0)],
        Interp::Linear,
    );
    push(&mut tracks[1], 0.0, 2.0, &tm, &kind);
    let anim = animation(s, tracks, 2.0);
    let (json, doc) = export(&anim);
    assert_eq!(doc["w"], 400);
    assert_eq!(doc["h"], 300);
    assert_eq!(doc["fr"], 30);
    assert_eq!(doc["op"], 60);
    let names: Vec<&str> = doc["layers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["nm"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"t 2"), "{names:?}");
    assert_eq!(keys_anywhere(&doc, "sk"), 0);
    // The skewing motion is sampled, and still lands within the tolerance.
    assert!(max_error(&anim, &doc, 1) <= 0.25);
    plays("skew-sampled", &anim, &json, &Player::ALL);
}

/// Shapes moved alike, wherever they are, share one bake of a skewing window (it is baked
/// about each shape's anchor, in a frame where the anchor is the origin): every shape must
/// still land within the bound where it is, and shapes moved differently (another
/// rotation before the skew, another size) must not take each other's keys.
#[test]
fn shapes_skewed_alike_share_bakes_each_where_it_is() {
    let mut paths = Vec::new();
    for i in 0..12 {
        let (x, y) = (20.0 + 31.3 * (i % 4) as f64, 30.0 + 70.1 * (i / 4) as f64);
        let side = if i % 3 == 0 { 12.0 } else { 20.0 };
        paths.push((
            rect_path(Rect::new(x, y, x + side, y + side * 0.5)),
            solid(Color::BLACK),
            None,
        ));
    }
    let s = scene(paths);
    let first = Timing::new(0.0, 1.0, 0.0, Easing::Linear, false);
    let second = Timing::new(1.0, 2.0, 0.0, EASE_IN_OUT, false);
    let tracks = (s.shapes.iter().enumerate())
        .map(|(i, shape)| {
            let mut track = Track::default();
            let turn = if i % 2 == 0 { 35.0 } else { 80.0 };
            let c = shape.centroid;
            push(
                &mut track,
                0.0,
                1.0,
                &first,
                &rigid(c, &[Component::Rotate(turn)], Interp::Linear),
            );
            let skew = [
                Component::Skew(25.0, 0.0),
                Component::Scale(Vec2::new(0.8, 0.8)),
            ];
            push(
                &mut track,
                1.0,
                2.0,
                &second,
                &rigid(c, &skew, Interp::Linear),
            );
            track
        })
        .collect();
    let anim = animation(s, tracks, 2.0);
    let (_, doc) = export(&anim);
    let err = max_error(&anim, &doc, 2);
    // The baking bound, plus the written precision.
    assert!(err <= 0.25 + 0.02, "error {err} px");
}

#[cfg(feature = "players")]
#[test]
fn one_window_has_keyframes_at_the_active_ends_only() {
    let s = black_rect(Rect::new(10.0, 10.0, 50.0, 50.0));
    let tm = Timing::new(0.5, 2.5, 0.5, EASE_IN_OUT, false);
    let kind = rigid(
        Point::new(30.0, 30.0),
        &[
            Component::Translate(Vec2::new(200.0, 40.0)),
            Component::Rotate(270.0),
            Component::Scale(Vec2::new(2.0, 0.5)),
        ],
        Interp::Linear,
    );
    let anim = one_motion(s, &tm, &kind, 3.0);
    let (json, warnings) = to_lottie(&anim, &LottieOptions::default()).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let doc = parse(&json);
    let mut times = Vec::new();
    fn collect(v: &Value, times: &mut Vec<Vec<f64>>) {
        match v {
            Value::Object(m) => {
                if m.get("a") == Some(&Value::from(1)) {
                    times.push(
                        m["k"]
                            .as_array()
                            .unwrap()
                            .iter()
                            .map(|k| num(&k["t"]))
                            .collect(),
                    );
                }
                m.values().for_each(|x| collect(x, times));
            }
            Value::Array(a) => a.iter().for_each(|x| collect(x, times)),
            _ => {}
        }
    }
    collect(&doc, &mut times);
    // Position, rotation and scale: two keyframes each, at (start + delay)·fps and end·fps.
    assert_eq!(times.len(), 3, "{times:?}");
    for t in &times {
        assert_eq!(t, &vec![30.0, 75.0]);
    }
    // The easing handles are the motion's own curve.
    let eased = json.contains(r#""o":{"x":0.42,"y":0},"i":{"x":0.58,"y":1}"#);
    assert!(eased, "{json}");
    assert!(max_error(&anim, &doc, 4) < 0.01, "exact motion");
    plays("one-window", &anim, &json, &Player::ALL);
}

#[cfg(feature = "players")]
#[test]
fn split_reversed_and_shared_windows_are_exact() {
    let s = scene(vec![
        (
            rect_path(Rect::new(20.0, 20.0, 60.0, 80.0)),
            solid(Color::BLACK),
            None,
        ),
        (
            rect_path(Rect::new(200.0, 100.0, 260.0, 140.0)),
            solid(Color::BLACK),
            None,
        ),
    ]);
    let mut a = Track::default();
    // A slice [0, 2] animated, split at 0.8 (two windows of one motion), then its inverted
    // twin over [2, 4] (reversed timing), as `[a, inv_a]` does.
    let fwd = Timing::new(0.0, 2.0, 0.3, EASE_IN_OUT, false);
    let back = Timing::new(2.0, 4.0, 0.3, EASE_IN_OUT, true);
    let kind = rigid(
        Point::new(40.0, 50.0),
        &[
            Component::Rotate(120.0),
            Component::Scale(Vec2::new(1.5, 0.7)),
        ],
        Interp::Linear,
    );
    push(&mut a, 0.0, 0.8, &fwd, &kind);
    push(&mut a, 0.8, 2.0, &fwd, &kind);
    push(&mut a, 2.0, 4.0, &back, &kind);
    // Two motions sharing a window, then one that starts elsewhere (a jump).
    let mut b = Track::default();
    let ease = Easing::CubicBezier([0.3, -0.3, 0.6, 1.4]);
    let t1 = Timing::new(0.5, 3.0, 0.0, ease, false);
    let k1 = rigid(
        Point::ORIGIN,
        &[Component::Translate(Vec2::new(-80.0, 60.0))],
        Interp::Linear,
    );
    let k2 = rigid(
        Point::new(230.0, 120.0),
        &[
            Component::Scale(Vec2::new(0.5, 0.5)),
            Component::Rotate(-90.0),
        ],
        Interp::Linear,
    );
    let start = Affine::IDENTITY;
    b.motions.push(MotionSeg {
        t0: 0.5,
        t1: 3.0,
        timing: t1.clone(),
        kind: k1,
        start,
    });
    b.motions.push(MotionSeg {
        t0: 0.5,
        t1: 3.0,
        timing: t1,
        kind: k2,
        start,
    });
    let t2 = Timing::new(3.0, 4.0, 0.0, Easing::Linear, false);
    let k3 = rigid(
        Point::ORIGIN,
        &[Component::Translate(Vec2::new(0.0, -50.0))],
        Interp::Linear,
    );
    b.motions.push(MotionSeg {
        t0: 3.0,
        t1: 4.0,
        timing: t2,
        kind: k3,
        start: Affine::translate((30.0, 0.0)),
    });
    let anim = animation(s, vec![a, b], 4.0);
    let (json, warnings) = to_lottie(&anim, &LottieOptions::default()).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let doc = parse(&json);
    let err = max_error(&anim, &doc, 3);
    // Exact up to the written precision (and the jump landing a thousandth of a frame early).
    assert!(err < 0.01, "error {err}");
    // Nothing was sampled: every animated property has few keyframes.
    assert!(
        animated_keys(&doc) < 40,
        "{} keyframes",
        animated_keys(&doc)
    );
    plays("split-reversed-shared", &anim, &json, &Player::ALL);
}

/// The spiral is the hardest case for the position track: x and y follow different
/// profiles, yet share one easing (lottie-web cannot draw the split position that gave
/// each its own inside a shape group), so it needs about three times the keys straight
/// motion does; the reduction must still cut the per-frame keys threefold.
#[cfg(feature = "players")]
#[test]
fn smooth_baked_motion_is_three_times_smaller_than_per_frame() {
    let s = black_rect(Rect::new(50.0, 50.0, 110.0, 90.0));
    // Alexa interpolation of a rotation with a translation is a spiral, not what Lottie's
    // component-wise interpolation draws: it must be sampled and reduced.
    let tm = Timing::new(0.0, 4.0, 0.0, EASE_IN_OUT, false);
    let kind = rigid(
        Point::new(80.0, 70.0),
        &[
            Component::Translate(Vec2::new(220.0, 120.0)),
            Component::Rotate(150.0),
            Component::Scale(Vec2::new(1.6, 1.6)),
        ],
        Interp::Alexa,
    );
    let anim = one_motion(s, &tm, &kind, 4.0);
    let tolerance = 0.25;
    let (json, _) = to_lottie(
        &anim,
        &LottieOptions {
            tolerance,
            ..Default::default()
        },
    )
    .unwrap();
    let doc = parse(&json);
    let err = max_error(&anim, &doc, 1);
    assert!(err <= tolerance, "error {err}");
    let frames = anim.frame_count() + 1;
    let keys = animated_keys(&doc);
    let props = {
        fn animated(v: &Value) -> usize {
            match v {
                Value::Object(m) => {
                    (m.get("a") == Some(&Value::from(1))) as usize
                        + m.values().map(animated).sum::<usize>()
                }
                Value::Array(a) => a.iter().map(animated).sum(),
                _ => 0,
            }
        }
        animated(&doc)
    };
    assert!(props > 0);
    assert!(
        keys * 3 <= props * frames,
        "{keys} keyframes on {props} properties over {frames} frames"
    );
    plays("smooth-baked", &anim, &json, &Player::ALL);
}

#[cfg(feature = "players")]
#[test]
fn bilinear_blend_is_sampled_within_tolerance() {
    let s = black_rect(Rect::new(150.0, 120.0, 190.0, 160.0));
    let tm = Timing::new(0.0, 2.0, 0.0, Easing::Linear, false);
    let blend: Blend = Arc::from([
        (0.6, Arc::from([Component::Rotate(90.0)].as_slice())),
        (
            0.4,
            Arc::from([Component::Translate(Vec2::new(100.0, 0.0))].as_slice()),
        ),
    ]);
    let kind = MotionKind::Rigid {
        pivot: Point::new(170.0, 140.0),
        blend,
        interp: Interp::Linear,
    };
    let anim = one_motion(s, &tm, &kind, 2.0);
    let (json, doc) = export(&anim);
    assert!(max_error(&anim, &doc, 1) <= 0.25);
    plays("bilinear-blend", &anim, &json, &Player::ALL);
}

#[cfg(feature = "players")]
#[test]
fn vertex_deformation_becomes_path_keyframes() {
    let mut p = BezPath::new();
    p.move_to((100.0, 100.0));
    p.curve_to((150.0, 60.0), (250.0, 60.0), (300.0, 100.0));
    p.line_to((300.0, 200.0));
    p.close_path();
    let s = scene(vec![(p, solid(Color::BLACK), None)]);
    let grid = Arc::new(Grid::new(
        3,
        3,
        Rect::new(0.0, 0.0, 400.0, 300.0),
        Field::Towards(Point::new(200.0, 150.0)),
    ));
    let tm = Timing::new(0.0, 2.0, 0.0, EASE_IN_OUT, false);
    let anim = one_motion(s, &tm, &MotionKind::Vertex { grid, pivot: None }, 2.0);
    let (json, doc) = export(&anim);
    assert!(max_error(&anim, &doc, 1) <= 0.25);
    // The outline is keyframed, not the transform.
    let sh = json.find(r#""ty":"sh","ks":{"a":1"#);
    assert!(sh.is_some(), "animated path expected");
    plays("vertex-deformation", &anim, &json, &Player::ALL);
}

#[cfg(feature = "players")]
#[test]
fn tints_opacity_and_stroke_width_follow_the_model() {
    let s = scene(vec![(
        rect_path(Rect::new(10.0, 10.0, 90.0, 90.0)),
        solid(Color::rgb(0.2, 0.4, 0.8)),
        stroke(3.0),
    )]);
    let mut track = Track::default();
    let red = Tint::full(Color::rgb(1.0, 0.0, 0.0));
    let tm = Timing::new(0.0, 1.0, 0.2, EASE_IN_OUT, false);
    let back = Timing::new(1.0, 2.0, 0.0, EASE_IN_OUT, true);
    track.fill.push(AttrSeg {
        t0: 0.0,
        t1: 1.0,
        timing: tm.clone(),
        from: Tint::NONE,
        to: red,
    });
    track.fill.push(AttrSeg {
        t0: 1.0,
        t1: 2.0,
        timing: back.clone(),
        from: Tint::NONE,
        to: red,
    });
    fade(&mut track, tm.clone(), 1.0, 0.3);
    track.stroke_width.push(AttrSeg {
        t0: 0.5,
        t1: 2.0,
        timing: Timing::new(0.5, 2.0, 0.0, Easing::Linear, false),
        from: 1.0,
        to: 4.0,
    });
    let anim = animation(s, vec![track], 2.0);
    let (json, doc) = export(&anim);
    for k in 0..=120 {
        let frame = k as f64 / 2.0;
        let t = frame / 30.0;
        let state = anim.tracks[0].state_at(t);
        let d = drawn(&doc, "t", frame);
        let want = state.fill.apply(Color::rgb(0.2, 0.4, 0.8));
        let fill = d.iter().find_map(|x| x.fill).expect("a fill");
        for (g, w) in fill.iter().zip([want.r, want.g, want.b]) {
            assert!(
                (g - w as f64).abs() < 1e-3,
                "frame {frame}: fill {fill:?} vs {want:?}"
            );
        }
        let width = d.iter().find_map(|x| x.stroke_width).expect("a stroke");
        assert!(
            (width - 3.0 * state.stroke_width).abs() < 1e-3,
            "frame {frame}: width {width}"
        );
        assert!(
            (d[0].opacity - state.opacity).abs() < 1e-3,
            "frame {frame}: opacity {}",
            d[0].opacity
        );
    }
    // A translucent filled and stroked square: see `Player::WHOLE_GROUP_OPACITY`.
    plays(
        "tints-opacity-width",
        &anim,
        &json,
        &Player::WHOLE_GROUP_OPACITY,
    );
}

/// A translucent animated shape of two paths, a circle over a square: the circle must show
/// the background beneath it, not the square (group opacity composites the whole group).
/// ThorVG applies a shape group's opacity to each path in it, so this is layer opacity.
#[cfg(feature = "players")]
#[test]
fn translucent_shape_of_two_paths_composites_as_a_whole() {
    let square = PathNode {
        id: "square".into(),
        path: rect_path(Rect::new(100.0, 100.0, 300.0, 250.0)),
        fill: solid(Color::rgb(0.9, 0.5, 0.4)),
        stroke: None,
        stroke_first: false,
        unit: None,
    };
    let circle = PathNode {
        id: "circle".into(),
        path: kurbo::Circle::new((200.0, 175.0), 50.0).to_path(0.1),
        fill: solid(Color::rgb(1.0, 0.9, 0.4)),
        ..square.clone()
    };
    let mut g = Group::new();
    g.id = "pair".into();
    g.children = vec![Node::Path(square), Node::Path(circle)];
    let s = SceneBuilder::new(400.0, 300.0)
        .unit("t", Node::Group(g))
        .build();
    let mut track = Track::default();
    fade(
        &mut track,
        Timing::new(0.0, 1.0, 0.0, Easing::Linear, false),
        1.0,
        0.3,
    );
    let anim = animation(s, vec![track], 1.0);
    let (json, _) = to_lottie(&anim, &LottieOptions::default()).unwrap();
    plays(
        "translucent-two-paths",
        &anim,
        &json,
        &Player::WHOLE_GROUP_OPACITY,
    );
}

/// A stroke under a skewing motion whose width keys hold one value (smoothing rebuilds a
/// constant width as keys within float noise of each other, matrix gm-0171) is still drawn
/// as its filled outline. ThorVG widens a stroke along the canvas axes by the matrix's
/// column lengths, which is wrong once the scaling is rotated, as the skew's is: the 6 px
/// stroke came out about 8 px wide at 2x (0.94% of the case's pixels off).
#[cfg(feature = "players")]
#[test]
fn stroke_with_held_width_under_skew_is_an_outline() {
    let mut zigzag = BezPath::new();
    zigzag.move_to((60.0, 60.0));
    for k in 1..=6 {
        zigzag.line_to((
            60.0 + 45.0 * k as f64,
            if k % 2 == 1 { 160.0 } else { 60.0 },
        ));
    }
    let mut s = scene(vec![(zigzag, None, stroke(4.0))]);
    if let Node::Path(p) = &mut s.root.children[0] {
        p.stroke.as_mut().unwrap().join = LineJoin::Round;
    }
    let tm = Timing::new(0.0, 1.0, 0.0, EASE_IN_OUT, false);
    let kind = rigid(
        Point::new(200.0, 110.0),
        &[Component::Skew(40.0, 0.0)],
        Interp::Linear,
    );
    let mut anim = one_motion(s, &tm, &kind, 1.0);
    anim.tracks[0].stroke_width.push(AttrSeg {
        t0: 0.0,
        t1: 1.0,
        timing: tm,
        from: 1.0,
        to: 1.0 - 1e-12,
    });
    let (json, _) = to_lottie(&anim, &LottieOptions::default()).unwrap();
    plays("held-width-under-skew", &anim, &json, &Player::ALL);
}

/// Colour and opacity changes eased by an overshooting Bézier, from a yellow (red at 1) and
/// from full opacity: the eased value passes the range at the start. The model clamps;
/// rlottie wraps a keyframed channel past its end (the yellow drew green, matrix gm-0187;
/// the opacity drew about 0%, gm-0199), so those stretches are written as clamped keys.
#[cfg(feature = "players")]
#[test]
fn overshooting_colour_and_opacity_stay_in_range() {
    let s = scene(vec![
        (
            rect_path(Rect::new(40.0, 40.0, 180.0, 160.0)),
            solid(Color::rgb(1.0, 0.79, 0.08)),
            None,
        ),
        (
            rect_path(Rect::new(220.0, 40.0, 360.0, 160.0)),
            solid(Color::rgb(0.2, 0.4, 0.8)),
            None,
        ),
    ]);
    let overshoot = Easing::CubicBezier([0.3, -0.3, 0.7, 1.3]);
    let tm = Timing::new(0.0, 1.0, 0.0, overshoot, false);
    let mut tint = Track::default();
    tint.fill.push(AttrSeg {
        t0: 0.0,
        t1: 1.0,
        timing: tm.clone(),
        from: Tint::NONE,
        to: Tint::full(Color::rgb(0.82, 0.29, 0.36)),
    });
    let mut fading = Track::default();
    fade(&mut fading, tm, 1.0, 0.3);
    let anim = animation(s, vec![tint, fading], 1.0);
    let (json, _) = to_lottie(&anim, &LottieOptions::default()).unwrap();
    plays("overshoot-in-range", &anim, &json, &Player::ALL);
}

#[test]
fn output_is_deterministic() {
    let s = black_rect(Rect::new(10.0, 10.0, 50.0, 50.0));
    let tm = Timing::new(0.0, 2.0, 0.0, EASE_IN_OUT, false);
    let turn = rigid(
        Point::new(30.0, 30.0),
        &[Component::Rotate(33.0)],
        Interp::Alexa,
    );
    let anim = one_motion(s, &tm, &turn, 2.0);
    let a = to_lottie(&anim, &LottieOptions::default()).unwrap().0;
    let b = to_lottie(&anim, &LottieOptions::default()).unwrap().0;
    assert_eq!(a, b);
}

/// Builds `f`'s result on a thread pool of `threads` threads.
fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// Checks that every layer's `parent` and `tp` name a layer of its own composition and
/// every `refId` an asset, and that indices are unique within a composition and asset
/// ids in the document.
fn assert_references_resolve(doc: &Value) {
    let assets: Vec<&str> = doc["assets"]
        .as_array()
        .map(|a| a.iter().map(|a| a["id"].as_str().unwrap()).collect())
        .unwrap_or_default();
    let mut unique_assets = assets.clone();
    unique_assets.sort();
    unique_assets.dedup();
    assert_eq!(unique_assets.len(), assets.len(), "duplicate asset ids");
    let comps = std::iter::once(&doc["layers"]).chain(
        doc["assets"]
            .as_array()
            .into_iter()
            .flatten()
            .map(|a| &a["layers"]),
    );
    for layers in comps {
        let layers = layers.as_array().unwrap();
        let inds: Vec<u64> = layers.iter().map(|l| l["ind"].as_u64().unwrap()).collect();
        let mut unique = inds.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), inds.len(), "duplicate layer indices");
        for (k, l) in layers.iter().enumerate() {
            if let Some(tp) = l["tp"].as_u64() {
                // A track matte is the layer right above the one it mattes.
                assert_eq!(
                    layers[k - 1]["ind"].as_u64(),
                    Some(tp),
                    "tp names another layer"
                );
                assert_eq!(layers[k - 1]["td"], 1);
            }
            for key in ["parent", "tp"] {
                if let Some(p) = l[key].as_u64() {
                    assert!(inds.contains(&p), "{key} {p} names no layer");
                }
            }
            if let Some(r) = l["refId"].as_str() {
                assert!(assets.contains(&r), "refId {r} names no asset");
            }
        }
    }
}

#[test]
fn many_children_are_built_in_parallel_into_the_same_document() {
    // A root of 150 children (the builder goes parallel from 64): animated rectangles,
    // groups that need a precomposition (translucent over a masked group: a matte inside,
    // so an asset), clipped groups (layer masks), masked groups (a matte in the root
    // composition) and paths with an approximated gradient
    // (a warning each), so that layer indices, parents, matte references, asset names and
    // warnings all have to be renumbered in document order.
    let focal = |id: &str| {
        let grad = Arc::new(RadialGradient {
            id: format!("g{id}"),
            center: Point::new(100.0, 100.0),
            radius: 80.0,
            focal: Point::new(110.0, 100.0),
            focal_radius: 20.0,
            transform: Affine::IDENTITY,
            spread: Spread::Pad,
            stops: vec![
                Stop {
                    offset: 0.0,
                    color: Color::WHITE,
                },
                Stop {
                    offset: 1.0,
                    color: Color::BLACK,
                },
            ],
        });
        Some(Fill {
            paint: Paint::Radial(grad),
            opacity: 1.0,
            rule: FillRule::NonZero,
        })
    };
    let mask = Arc::new(Mask {
        id: "m".into(),
        rect: Rect::new(0.0, 0.0, 200.0, 200.0),
        kind: MaskKind::Luminance,
        mask: None,
        root: group_with(vec![path_node(
            "mc",
            rect_path(Rect::new(50.0, 0.0, 150.0, 200.0)),
            solid(Color::WHITE),
        )]),
    });
    let clip = Arc::new(ClipPath {
        id: "clip".into(),
        transform: Affine::IDENTITY,
        clip_path: None,
        root: group_with(vec![path_node(
            "c",
            kurbo::Circle::new((100.0, 100.0), 50.0).to_path(0.1),
            solid(Color::BLACK),
        )]),
    });
    let mut b = SceneBuilder::new(400.0, 300.0);
    for i in 0..150 {
        let r = Rect::from_origin_size(
            (i as f64 % 20.0 * 20.0, i as f64 / 20.0 * 30.0),
            (15.0, 15.0),
        );
        let node = match i % 5 {
            0 => Node::Path(PathNode::new(
                format!("p{i}"),
                rect_path(r),
                solid(Color::BLACK),
                None,
            )),
            1 => Node::Group(Group {
                id: format!("translucent{i}"),
                opacity: 0.5,
                children: vec![
                    Node::Group(Group {
                        id: format!("masked{i}"),
                        mask: Some(mask.clone()),
                        ..black_canvas()
                    }),
                    path_node(&format!("q{i}"), rect_path(r), solid(Color::BLACK)),
                ],
                ..Group::new()
            }),
            2 => Node::Group(Group {
                id: format!("clipped{i}"),
                clip_path: Some(clip.clone()),
                ..black_canvas()
            }),
            3 => path_node(&format!("f{i}"), rect_path(r), focal(&i.to_string())),
            _ => Node::Group(Group {
                id: format!("masked{i}"),
                mask: Some(mask.clone()),
                ..black_canvas()
            }),
        };
        b = b.unit("t", node);
    }
    let scene = b.build();
    let tm = Timing::new(0.0, 1.0, 0.0, EASE_IN_OUT, false);
    let turn = rigid(
        Point::new(30.0, 30.0),
        &[Component::Rotate(33.0)],
        Interp::Alexa,
    );
    let tracks = (0..scene.shapes.len())
        .map(|i| {
            let mut track = Track::default();
            if i % 2 == 0 {
                push(&mut track, tm.start, tm.end, &tm, &turn);
            }
            track
        })
        .collect();
    let anim = animation(scene, tracks, 1.0);
    let export = |threads| {
        on_threads(threads, || {
            let (json, warnings) = to_lottie(&anim, &LottieOptions::default()).unwrap();
            (
                json,
                warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>(),
            )
        })
    };
    let (one, warned_one) = export(1);
    let (two, warned_two) = export(2);
    assert!(one == two, "the document depends on the number of threads");
    assert_eq!(warned_one, warned_two);
    assert!(warned_one.len() >= 30, "{warned_one:?}");
    let doc = parse(&one);
    assert!(doc["assets"].as_array().is_some_and(|a| a.len() >= 30));
    assert_references_resolve(&doc);
    // The still scene goes through the same builder.
    let still = |threads| {
        on_threads(threads, || {
            still_to_lottie(&anim.scene, &LottieOptions::default())
                .unwrap()
                .0
        })
    };
    let (one, two) = (still(1), still(2));
    assert!(one == two, "the still depends on the number of threads");
    assert_references_resolve(&parse(&one));
}

// ---- stills --------------------------------------------------------------------------------

fn group_with(children: Vec<Node>) -> Group {
    Group {
        children,
        ..Group::new()
    }
}

fn still(root: Group) -> Scene {
    Scene {
        width: 200.0,
        height: 200.0,
        root,
        shapes: Vec::new(),
        time: None,
        keys: Vec::new(),
    }
}

fn path_node(id: &str, path: BezPath, fill: Option<Fill>) -> Node {
    Node::Path(PathNode::new(id, path, fill, None))
}

/// A group painting the whole 200 × 200 canvas black (one path, `r`).
fn black_canvas() -> Group {
    group_with(vec![path_node(
        "r",
        rect_path(Rect::new(0.0, 0.0, 200.0, 200.0)),
        solid(Color::BLACK),
    )])
}

/// The Lottie document of the still scene holding `g` alone.
fn still_doc(g: Group) -> Value {
    let root = group_with(vec![Node::Group(g)]);
    let (json, _) = still_to_lottie(&still(root), &LottieOptions::default()).unwrap();
    parse(&json)
}

#[test]
fn clip_paths_become_layer_masks_and_masks_luma_mattes() {
    let clip = Arc::new(ClipPath {
        id: "clip".into(),
        transform: Affine::IDENTITY,
        clip_path: None,
        root: group_with(vec![path_node(
            "c",
            kurbo::Circle::new((100.0, 100.0), 50.0).to_path(0.1),
            solid(Color::BLACK),
        )]),
    });
    let clipped = Group {
        id: "clipped".into(),
        clip_path: Some(clip),
        ..black_canvas()
    };
    let doc = still_doc(clipped);
    let layer = &doc["layers"][0];
    assert_eq!(layer["hasMask"], true);
    assert_eq!(layer["masksProperties"].as_array().unwrap().len(), 1);
    assert_eq!(layer["masksProperties"][0]["mode"], "a");

    let mask = Arc::new(Mask {
        id: "m".into(),
        rect: Rect::new(0.0, 0.0, 200.0, 200.0),
        kind: MaskKind::Luminance,
        mask: None,
        root: group_with(vec![path_node(
            "mc",
            rect_path(Rect::new(50.0, 0.0, 150.0, 200.0)),
            solid(Color::WHITE),
        )]),
    });
    let masked = Group {
        id: "masked".into(),
        mask: Some(mask),
        ..black_canvas()
    };
    let doc = still_doc(masked);
    let layers = doc["layers"].as_array().unwrap();
    // Topmost first: the matte, then the layer it mattes.
    assert_eq!(layers[0]["td"], 1);
    assert_eq!(layers[1]["tt"], 3);
    assert_eq!(layers[1]["tp"], layers[0]["ind"]);
}

#[test]
fn unsupported_paint_features_warn_naming_the_element() {
    let grad = Arc::new(RadialGradient {
        id: "rg".into(),
        center: Point::new(100.0, 100.0),
        radius: 80.0,
        focal: Point::new(110.0, 100.0),
        focal_radius: 20.0,
        transform: Affine::IDENTITY,
        spread: Spread::Pad,
        stops: vec![
            Stop {
                offset: 0.0,
                color: Color::WHITE,
            },
            Stop {
                offset: 1.0,
                color: Color::BLACK,
            },
        ],
    });
    let fill = Some(Fill {
        paint: Paint::Radial(grad),
        opacity: 1.0,
        rule: FillRule::EvenOdd,
    });
    let root = group_with(vec![path_node(
        "shape7",
        rect_path(Rect::new(20.0, 20.0, 180.0, 180.0)),
        fill,
    )]);
    let (json, warnings) = still_to_lottie(&still(root), &LottieOptions::default()).unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.to_string().contains("shape7") && w.to_string().contains("focal radius")),
        "{warnings:?}"
    );
    let doc = parse(&json);
    let gf = &doc["layers"][0]["shapes"][0]["it"][1];
    assert_eq!(gf["ty"], "gf");
    assert_eq!(gf["t"], 2);
    assert_eq!(gf["r"], 2, "even-odd fill rule");
}

#[test]
fn bad_animations_are_errors_not_panics() {
    let s = black_rect(Rect::new(10.0, 10.0, 50.0, 50.0));
    let anim = animation(s.clone(), vec![Track::default()], 0.0);
    assert!(to_lottie(&anim, &LottieOptions::default()).is_err());
    let anim = animation(s.clone(), vec![], 1.0);
    assert!(to_lottie(&anim, &LottieOptions::default()).is_err());
    let mut empty = s;
    empty.width = 0.0;
    assert!(still_to_lottie(&empty, &LottieOptions::default()).is_err());
}

// ---- the corpus, in process ----------------------------------------------------------------

/// Every corpus file that imports converts to a Lottie document with its canvas size, and
/// the time per file (import plus export, as `gmotion convert` spends it) is reported: the
/// conformance run prints it beside python-lottie's in-process conversion time.
#[test]
fn corpus_converts_in_process() {
    use gmotion_import_svg::{ImportOptions, load};
    let dir = match std::env::var_os("GMOTION_CORPUS") {
        Some(d) => std::path::PathBuf::from(d),
        None => crate::support::root().join("tests/corpus/resvg"),
    };
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("corpus at {}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "svg"))
        .collect();
    files.sort();
    assert!(files.len() >= 500, "{} files", files.len());
    // Three passes over the corpus: the first loads the system fonts (once per process)
    // and the files into the page cache and is reported apart; each file's time is the
    // faster of the other two, which keeps a busy machine's hiccups out of the figures.
    let mut times = vec![f64::INFINITY; files.len()];
    let mut export_times = vec![f64::INFINITY; files.len()];
    let mut cold = 0.0;
    let mut unreadable = Vec::new();
    for pass in 0..3 {
        for (i, f) in files.iter().enumerate() {
            let start = std::time::Instant::now();
            let imported = match load(f, &ImportOptions::default()) {
                Ok(i) => i,
                Err(e) => {
                    if pass == 0 {
                        unreadable.push(e.to_string());
                    }
                    continue;
                }
            };
            let exporting = std::time::Instant::now();
            let (json, _) = still_to_lottie(&imported.scene, &LottieOptions::default())
                .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            let (total, export) = (
                start.elapsed().as_secs_f64(),
                exporting.elapsed().as_secs_f64(),
            );
            if pass == 0 {
                cold += total;
                let doc = parse(&json);
                assert_eq!(
                    doc["w"],
                    imported.scene.width.round().max(1.0) as u64,
                    "{}",
                    f.display()
                );
                assert!(doc["layers"].is_array());
            } else {
                times[i] = times[i].min(total);
                export_times[i] = export_times[i].min(export);
            }
        }
    }
    // The slowest files, which make the mean.
    let mut slowest: Vec<(f64, &std::path::PathBuf)> = times
        .iter()
        .zip(&files)
        .filter(|(t, _)| t.is_finite())
        .map(|(t, f)| (*t, f))
        .collect();
    slowest.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (t, f) in slowest.iter().take(5) {
        eprintln!(
            "  slow: {:.2} ms {}",
            t * 1e3,
            f.file_name().unwrap().to_string_lossy()
        );
    }
    times.retain(|t| t.is_finite());
    export_times.retain(|t| t.is_finite());
    // Only files the importer rejects with a message (a non-UTF-8 one) are left out.
    assert!(unreadable.len() <= 2, "{unreadable:?}");
    let stats = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        (
            v[v.len() / 2] * 1e3,
            v.iter().sum::<f64>() / v.len() as f64 * 1e3,
        )
    };
    let (median, mean) = stats(&mut times);
    let (export_median, export_mean) = stats(&mut export_times);
    eprintln!(
        "lottie corpus conversion in process: {} files, median {median:.3} ms, mean {mean:.3} ms \
         (Lottie export alone: median {export_median:.3} ms, mean {export_mean:.3} ms; \
         first pass, with the one-time font scan: {:.1} ms in all)",
        times.len(),
        cold * 1e3,
    );
}

// ---- what lottie-web can draw --------------------------------------------------------------

/// Constructs in a shape group's transform (`ty: "tr"`) that lottie-web does not draw, as
/// `where: what` lines. lottie-web reads a group transform's `a`, `p`, `s`, `r`, `o`, `sk`
/// and `sa`, each `{"a":0,"k":value}` or `{"a":1,"k":[keyframes]}`; a split position
/// (`{"s":true,"x":…,"y":…}`, legal only in a layer's `ks`) makes it draw nothing at all,
/// background included, and so would any other key the format keeps for layers.
fn lottie_web_problems(doc: &Value) -> Vec<String> {
    fn property(prop: &Value, vector: bool, at: &str, out: &mut Vec<String>) {
        let Some(m) = prop.as_object() else {
            out.push(format!("{at}: not an object: {prop}"));
            return;
        };
        if let Some(k) = m.keys().find(|k| !["a", "k"].contains(&k.as_str())) {
            out.push(format!(
                "{at}: key {k:?} (split or layer-only form): {prop}"
            ));
            return;
        }
        let is_vector = |v: &Value| {
            v.as_array()
                .is_some_and(|a| a.len() >= 2 && a.iter().all(Value::is_number))
        };
        let is_scalar = |v: &Value| {
            v.is_number()
                || v.as_array()
                    .is_some_and(|a| a.len() == 1 && a[0].is_number())
        };
        let value_ok = |v: &Value| if vector { is_vector(v) } else { is_scalar(v) };
        match prop.get("a").and_then(Value::as_u64) {
            Some(0) if value_ok(&prop["k"]) => {}
            Some(1) => match prop["k"].as_array() {
                Some(keys) if keys.len() >= 2 => {
                    for (n, key) in keys.iter().enumerate() {
                        if !key["t"].is_number() || !value_ok(&key["s"]) {
                            out.push(format!("{at}: keyframe {n} unreadable: {key}"));
                        }
                    }
                }
                _ => out.push(format!("{at}: animated without two keyframes: {prop}")),
            },
            _ => out.push(format!("{at}: unreadable value: {prop}")),
        }
    }
    fn items(list: &Value, at: &str, out: &mut Vec<String>) {
        for (i, it) in list.as_array().into_iter().flatten().enumerate() {
            let at = format!("{at}/{i}");
            match it["ty"].as_str() {
                Some("gr") => items(&it["it"], &at, out),
                Some("tr") => {
                    for (key, v) in it.as_object().expect("an item is an object") {
                        let vector = match key.as_str() {
                            "ty" | "nm" => continue,
                            "a" | "p" | "s" => true,
                            "r" | "o" | "sk" | "sa" => false,
                            other => {
                                out.push(format!("{at}: transform key {other:?}: {it}"));
                                continue;
                            }
                        };
                        property(v, vector, &format!("{at}.{key}"), out);
                    }
                }
                _ => {}
            }
        }
    }
    let mut out = Vec::new();
    let assets = doc["assets"].as_array().into_iter().flatten();
    let lists = std::iter::once(&doc["layers"]).chain(assets.map(|a| &a["layers"]));
    for layers in lists {
        for l in layers.as_array().into_iter().flatten() {
            items(&l["shapes"], &format!("layer {}", l["nm"]), &mut out);
        }
    }
    out
}

fn repo_file(rel: &str) -> std::path::PathBuf {
    crate::support::root().join(rel)
}

fn import(path: &std::path::Path) -> Scene {
    use gmotion_import_svg::{ImportOptions, load};
    load(path, &ImportOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
        .scene
}

fn run_grammar(scene: &Scene, src: &str) -> Animation {
    let g = gmotion::grammar::parse(src).unwrap_or_else(|d| panic!("{}", d.render("case.gm", src)));
    gmotion::engine::run(scene.clone(), &g, &gmotion::engine::RunOptions::default())
        .unwrap_or_else(|e| panic!("{e}\n{src}"))
        .0
}

/// Small grammars on the toy scene (a square `s`, four circles `c`) over every motion that
/// is baked or keyed specially — `smoothing`, `ease=bspline(…)` / `poles(…)`, skews, Alexa
/// interpolation (of skews too), delays inside the slice (0.3 and 0.9 of it, and per id) —
/// for both references, with and without a split that cuts a delayed window short. Every
/// ease, value and offset meets every other; the rest vary with the case number.
fn baked_motion_grammars() -> Vec<String> {
    let eases = [
        "",
        ", ease=ease-in-out",
        ", ease=bspline(3)",
        ", ease=poles(2)",
        ", ease=poles(3, 0.2)",
    ];
    let values = [
        "translate(120, 20)",
        "rotate(90) scale(1.5)",
        "skewX(30) translate(40, 0)",
        "skew(20, 10) scale(1.3)",
        "rotate(200) scale(0.6, 1.4)",
    ];
    // The slice `a` lasts 1 s.
    let offsets = ["0", "0.3", "0.9", "0.12 * id"];
    let mut out = Vec::new();
    for ease in eases {
        for value in values {
            for offset in offsets {
                let n = out.len();
                let (r1, r2) = if n % 2 == 0 {
                    ("local", "world")
                } else {
                    ("world", "local")
                };
                let interp = if n % 3 == 0 { "interp alexa\n" } else { "" };
                let smoothing = if n % 4 == 1 {
                    "smoothing spring(0.3, 0.1)\n"
                } else {
                    ""
                };
                // A split of the moving slice at 0.3 s ends the delayed window before its
                // change begins (offsets 0.3 and 0.9).
                let nested = if n % 5 >= 2 {
                    "timesplit(0.3, 0.7) : [m, s] -> [m1, m2]\n\
                     animate(affine, local, 0, scale(1.2)) : [m2, s] -> [k]\n"
                } else {
                    ""
                };
                out.push(format!(
                    "duration 2s\nfps 30\n{interp}{smoothing}\
                     timesplit(0.5, 0.5) : [all, (s, c)] -> [a, inv_a]\n\
                     animate(affine, {r1}, {offset}, {value}{ease}) : [a, s] -> [m]\n\
                     {nested}\
                     animate(affine, {r2}, {offset}, {value}{ease}) : [a, c] -> [mc]\n"
                ));
            }
        }
    }
    out
}

/// lottie-web drew every frame of these blank (split positions in baked shape groups):
/// no export holds anything in a shape group's transform that lottie-web cannot draw —
/// over the generated baked-motion grammars, every example grammar, and the three
/// `transitions` examples.
#[test]
fn no_shape_group_holds_what_lottie_web_cannot_draw() {
    let toy = import(&repo_file("grammars/toy.svg"));
    let mut docs: Vec<(String, String)> = baked_motion_grammars()
        .into_iter()
        .map(|src| {
            let (json, _) = to_lottie(&run_grammar(&toy, &src), &LottieOptions::default())
                .unwrap_or_else(|e| panic!("{e}\n{src}"));
            (src, json)
        })
        .collect();
    let mut examples: Vec<_> = std::fs::read_dir(repo_file("grammars"))
        .expect("grammars/")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "gm"))
        .collect();
    examples.sort();
    assert!(examples.len() >= 7, "{examples:?}");
    for gm in examples {
        let src = std::fs::read_to_string(&gm).expect("read the grammar");
        let scene = import(&gm.with_extension("svg"));
        let (json, _) = to_lottie(&run_grammar(&scene, &src), &LottieOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", gm.display()));
        docs.push((gm.display().to_string(), json));
    }
    for name in ["histogram", "permutation", "revisions"] {
        let scene = import(&repo_file(&format!("grammars/{name}.svg")));
        let targets = gmotion::transitions::Targets::load(&repo_file(&format!(
            "grammars/{name}.targets.json"
        )))
        .unwrap_or_else(|e| panic!("{e}"));
        let system = targets.default_system(None);
        let anim = gmotion::transitions::run(&scene, &targets, &system, 60.0, None)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let (json, _) = to_lottie(&anim, &LottieOptions::default()).unwrap();
        docs.push((format!("transitions {name}"), json));
    }
    let mut baked = 0;
    for (what, json) in &docs {
        let doc = parse(json);
        let problems = lottie_web_problems(&doc);
        assert!(
            problems.is_empty(),
            "{what}:\n{}",
            problems[..problems.len().min(5)].join("\n")
        );
        // The check saw baked motion: an animated position in a shape group.
        baked += usize::from(json.contains(r#""ty":"tr","p":{"a":1"#));
    }
    assert!(
        baked * 2 >= docs.len(),
        "{baked} of {} exports bake motion",
        docs.len()
    );
}

/// The checker itself rejects what lottie-web cannot draw (a split position, a layer-only
/// key) and accepts the forms it can.
#[test]
fn lottie_web_checker_rejects_split_positions_in_shape_groups() {
    let doc = |tr: Value| serde_json::json!({"layers": [{"nm": "x", "shapes": [{"ty": "gr", "it": [tr]}]}]});
    let fixed =
        doc(serde_json::json!({"ty": "tr", "p": {"a": 0, "k": [1, 2]}, "r": {"a": 0, "k": 5}}));
    assert_eq!(lottie_web_problems(&fixed), Vec::<String>::new());
    let keyed = doc(serde_json::json!({"ty": "tr", "p": {"a": 1, "k": [
        {"t": 0, "s": [0, 0], "o": {"x": 0, "y": 0}, "i": {"x": 1, "y": 1}}, {"t": 5, "s": [3, 4]}
    ]}}));
    assert_eq!(lottie_web_problems(&keyed), Vec::<String>::new());
    let split = doc(serde_json::json!({"ty": "tr", "p": {"s": true,
        "x": {"a": 0, "k": 1}, "y": {"a": 0, "k": 2}}}));
    assert_eq!(lottie_web_problems(&split).len(), 1);
    let three_d = doc(serde_json::json!({"ty": "tr", "rx": {"a": 0, "k": 1}}));
    assert_eq!(lottie_web_problems(&three_d).len(), 1);
}

/// A delayed window (an `animate` offset inside its slice) is written with its anchor and
/// its position together, also when a later split ends the window before the change
/// begins: the export follows the model at every frame within the tolerance. Before, such a
/// window wrote the anchor alone and every player drew the square 100 px up and left.
#[cfg(feature = "players")]
#[test]
fn delayed_windows_follow_the_model() {
    let toy = import(&repo_file("grammars/toy.svg"));
    let mut cases = 0;
    for src in baked_motion_grammars() {
        let anim = run_grammar(&toy, &src);
        let (json, _) = to_lottie(&anim, &LottieOptions::default()).unwrap();
        let err = max_error(&anim, &parse(&json), 1);
        // The baking bound, plus the written precision.
        assert!(err <= 0.25 + 0.02, "error {err} px\n{src}");
        // Every tenth case also in the real players (each launch costs a second or two).
        if cases % 10 == 0 {
            plays(&format!("baked-{cases}"), &anim, &json, &Player::ALL);
        }
        cases += 1;
    }
    assert_eq!(cases, 100);
}

/// Many translucent shapes over an opaque background: every player must leave the
/// background opaque. Each translucent rlottie layer dims everything beneath it by about
/// 1/255, which adds up, so the exporter keeps a single-path shape's opacity on its group
/// (the cube example's background fell to alpha 215 when 50-odd fading units carried their
/// opacity on their layers).
#[cfg(feature = "players")]
#[test]
fn many_translucent_shapes_leave_the_background_opaque() {
    let mut paths = vec![(
        rect_path(Rect::new(0.0, 0.0, 400.0, 300.0)),
        solid(Color::rgb(0.95, 0.93, 0.9)),
        None,
    )];
    for k in 0..60 {
        let (x, y) = (
            20.0 + 60.0 * (k % 6) as f64,
            20.0 + 45.0 * (k / 6) as f64 * 0.6,
        );
        paths.push((
            rect_path(Rect::new(x, y, x + 30.0, y + 20.0)),
            solid(Color::rgb(0.2, 0.3, 0.7)),
            None,
        ));
    }
    let s = scene(paths);
    let mut tracks = vec![Track::default(); s.shapes.len()];
    for track in tracks.iter_mut().skip(1) {
        fade(
            track,
            Timing::new(0.0, 1.0, 0.0, Easing::Linear, false),
            1.0,
            0.4,
        );
    }
    let anim = animation(s, tracks, 1.0);
    let (json, _) = to_lottie(&anim, &LottieOptions::default()).unwrap();
    plays("many-translucent", &anim, &json, &Player::ALL);
}
