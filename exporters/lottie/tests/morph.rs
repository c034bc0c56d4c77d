//! `animate(morph, …)` exported natively: Lottie path keyframes (counted) and SMIL `d`
//! animations, played in lottie-web (svg and canvas), rlottie, ThorVG and Chromium's SMIL
//! against gmotion's own render of the model.

use gmotion::motion::Animation;
use gmotion_export_lottie::{LottieOptions, to_lottie};
use serde_json::Value;

use crate::support::{run_grammar, scene_of};

/// A circle, a square of two paths, a hidden star and a heart in `<defs>`.
pub const SCENE: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="120" viewBox="0 0 200 120">
  <defs>
    <path id="heart" d="M60 100 C 10 65 10 20 40 20 C 52 20 60 32 60 38 C 60 32 68 20 80 20 C 110 20 110 65 60 100 Z"/>
  </defs>
  <circle id="logo" cx="60" cy="60" r="40" fill="#d1495b"/>
  <g id="pair" class="pair"><rect x="125" y="20" width="30" height="30" fill="#00798c"/><rect x="155" y="60" width="30" height="40" fill="#edae49" stroke="#222" stroke-width="3"/></g>
  <path id="star" display="none" d="M60 10 L72 45 L108 45 L79 66 L90 100 L60 79 L30 100 L41 66 L12 45 L48 45 Z"/>
  <g class="twin" style="display:none"><circle cx="140" cy="40" r="14"/><path d="M150 70 L190 80 L160 105 Z"/></g>
</svg>"##;

/// The grammars the cases run: a morph with its inverted twin, chained morphs, one under
/// motion, colour and an offset, path data of another point count, smoothing, and a unit
/// of two paths into a key of two paths, per-vertex motion (`lookup vertex`, where the
/// exporters bake the deformed in-between) around a delayed morph with its twin, a morph
/// held between its twin, and an easing no player can say (sampled).
pub const CASES: &[(&str, &str)] = &[
    (
        "twin",
        "duration 2s\nfps 30\ntimesplit(0.5, 0.5) : [all, logo] -> [a, inv_a]\nanimate(morph, local, 0, shape(star), ease=ease-in-out) : [a, logo] -> [m]\n",
    ),
    (
        "chain",
        "duration 3s\nfps 30\ntimesplit(0.34, 0.33, 0.33) : [all, logo] -> [a, b, inv_a]\nanimate(morph, local, 0, shape(star)) : [a, logo] -> [m]\nanimate(morph, world, 0, shape(heart), ease=ease-out) : [b, logo] -> [h]\n",
    ),
    (
        "moving",
        "duration 2s\nfps 30\nanimate(morph, local, 0.3, shape(heart), ease=ease-in) : [all, logo] -> [m]\nanimate(affine, world, 0, translate(40, 0) rotate(20)) : [m, logo] -> [mv]\nanimate(fill, local, 0, #00798c) : [mv, logo] -> [c]\n",
    ),
    (
        "path_data",
        "duration 2s\nfps 30\ntimesplit(0.6, 0.4) : [all, logo] -> [a, inv_a]\nanimate(morph, local, 0, \"M 0 0 L 50 10 L 40 60 L 10 50 Z M 20 20 L 30 20 L 30 30 Z\") : [a, logo] -> [m]\n",
    ),
    (
        "smoothed",
        "duration 2s\nfps 30\nsmoothing spring(0.4, 0)\ntimesplit(0.5, 0.5) : [all, logo] -> [a, inv_a]\nanimate(morph, local, 0, shape(star)) : [a, logo] -> [m]\nanimate(fill, local, 0, #00798c) : [m, logo] -> [s]\n",
    ),
    (
        "unit",
        "duration 2s\nfps 30\ntimesplit(0.5, 0.5) : [all, pair] -> [a, inv_a]\nanimate(morph, world, 0, shape(twin)) : [a, pair] -> [m]\n",
    ),
    (
        "held",
        "duration 2.4s\nfps 25\ntimesplit(0.3, 0.4, 0.3) : [all, logo] -> [a, hold, inv_a]\nanimate(morph, world, 0.1, shape(star), ease=ease-in) : [a, logo] -> [m]\n",
    ),
    (
        "sampled",
        "duration 2s\nfps 30\ntimesplit(0.5, 0.5) : [all, logo] -> [a, inv_a]\nanimate(morph, local, 0.2, shape(heart), ease=poles(4)) : [a, logo] -> [m]\n",
    ),
    (
        "vertex",
        "duration 2.4s\nfps 25\ngrid 3x2\nlookup vertex\nanimate(affine, world, 0, translate(25, 10)) : [all, logo] -> [mv]\ntimesplit(0.5, 0.5) : [mv, logo] -> [a, inv_a]\nanimate(morph, local, 0.2, shape(star), ease=bspline(3)) : [a, logo] -> [m]\nanimate(affine, world, 0, translate(-20, 15)) : [m, logo] -> [m2]\n",
    ),
];

/// The animation of case `name`.
pub fn case(name: &str) -> Animation {
    let (_, g) = CASES.iter().find(|(n, _)| *n == name).expect("case");
    run_grammar(scene_of(SCENE), g)
}

/// The keyframe counts of every animated path shape (`ty: "sh"` with `ks.a == 1`).
fn path_key_counts(doc: &Value, out: &mut Vec<usize>) {
    match doc {
        Value::Object(m) => {
            if m.get("ty").and_then(Value::as_str) == Some("sh") && m["ks"]["a"].as_i64() == Some(1)
            {
                out.push(m["ks"]["k"].as_array().map_or(0, Vec::len));
            }
            m.values().for_each(|v| path_key_counts(v, out));
        }
        Value::Array(a) => a.iter().for_each(|v| path_key_counts(v, out)),
        _ => {}
    }
}

fn lottie(anim: &Animation) -> (String, Value) {
    let (json, _) = to_lottie(anim, &LottieOptions::default()).unwrap();
    let doc = serde_json::from_str(&json).unwrap();
    (json, doc)
}

/// A 2 s morph of one shape on one slice writes at most 4 path keyframes (2 here: its
/// ends), not one per frame; with its inverted twin, 3 (no jump where the twin begins).
#[test]
fn a_morph_writes_few_path_keyframes() {
    let one = run_grammar(
        scene_of(SCENE),
        "duration 2s\nfps 30\nanimate(morph, local, 0, shape(star), ease=ease-in-out) : [all, logo] -> [m]\n",
    );
    let (_, doc) = lottie(&one);
    let mut counts = Vec::new();
    path_key_counts(&doc, &mut counts);
    assert_eq!(
        counts,
        vec![2],
        "one path of one subpath, keyed at the morph's ends"
    );
    let (_, doc) = lottie(&case("twin"));
    let mut counts = Vec::new();
    path_key_counts(&doc, &mut counts);
    assert_eq!(counts, vec![3]);
    // Every keyframe of a path has the same vertex count.
    let (_, doc) = lottie(&case("chain"));
    let mut counts = Vec::new();
    path_key_counts(&doc, &mut counts);
    assert_eq!(
        counts,
        vec![4],
        "a, b (ease-out), then inv_a back: one key at each end"
    );
}

/// Under per-vertex motion a morphing path is baked once, its in-between deformed: one
/// animated path whose keys have the morph's structure (the star's ten corners cut into
/// the circle's outline, not the circle's four vertices), and one SMIL `d` animation, not
/// a deformed rest outline beside a morph that would override it.
#[test]
fn a_morph_under_vertex_motion_is_baked_with_its_in_between() {
    let anim = case("vertex");
    let (_, doc) = lottie(&anim);
    let mut counts = Vec::new();
    path_key_counts(&doc, &mut counts);
    assert_eq!(counts.len(), 1, "one animated path: {counts:?}");
    let vertices = |key: &Value| key["s"][0]["v"].as_array().map_or(0, Vec::len);
    let mut keys = Vec::new();
    collect_path_keys(&doc, &mut keys);
    assert!(
        keys.iter().all(|k| vertices(k) >= 10),
        "every key in the morph's structure: {:?}",
        keys.iter().map(vertices).collect::<Vec<_>>()
    );
    let (svg, _) = gmotion_export_svg::smil::to_smil(&anim, &Default::default()).unwrap();
    assert_eq!(svg.matches("attributeName=\"d\"").count(), 1);
}

/// The keyframes of every animated path shape.
fn collect_path_keys(doc: &Value, out: &mut Vec<Value>) {
    match doc {
        Value::Object(m) => {
            if m.get("ty").and_then(Value::as_str) == Some("sh") && m["ks"]["a"].as_i64() == Some(1)
            {
                out.extend(m["ks"]["k"].as_array().into_iter().flatten().cloned());
            }
            m.values().for_each(|v| collect_path_keys(v, out));
        }
        Value::Array(a) => a.iter().for_each(|v| collect_path_keys(v, out)),
        _ => {}
    }
}

#[cfg(feature = "players")]
mod players {
    use super::*;
    use crate::support::players::{Player, assert_plays_like_model, chromium, frames_to_check};
    use gmotion_export_raster::{compare, render};
    use gmotion_export_svg::frame::frame_svg;
    use gmotion_export_svg::smil::{SmilOptions, to_smil};

    /// Every case plays frame-exact in the four Lottie players.
    #[test]
    fn morphs_play_in_every_lottie_player() {
        for (name, _) in CASES {
            let anim = case(name);
            let (json, _) = lottie(&anim);
            let width = (2.0 * anim.scene.width).round() as u32;
            assert_plays_like_model(
                &format!("morph-{name}"),
                &anim,
                &json,
                &frames_to_check(&anim),
                width,
                &Player::ALL,
            );
        }
    }

    /// Every case plays frame-exact in Chromium's SMIL.
    #[test]
    fn morphs_play_in_chromium_smil() {
        for (name, _) in CASES {
            let anim = case(name);
            let (svg, _) = to_smil(&anim, &SmilOptions::default()).unwrap();
            let dir = crate::support::case_dir("morph", name);
            let path = dir.join("smil.svg");
            std::fs::write(&path, &svg).unwrap();
            let width = (2.0 * anim.scene.width).round() as u32;
            let times: Vec<f64> = frames_to_check(&anim)
                .iter()
                .map(|f| f / anim.fps)
                .collect();
            let got = chromium(&path, width, &times);
            for (t, g) in times.iter().zip(got) {
                let model = render(&frame_svg(&anim, *t), width).unwrap();
                let off = compare(&model, &g, 32);
                assert!(off <= 0.005, "{name} at {t} s: {:.2}% off", off * 100.0);
            }
        }
    }
}
