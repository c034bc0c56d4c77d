//! `animate(trim, …)` and the stepped easings (`steps(n)`, `hold`), from their definitions:
//! a `(0, 0)` trim draws nothing of the stroke and `(0, 1)` all of it while the fill stays
//! whole (pixels of gmotion's own frames); an inverted trim slice is the time reverse of
//! its twin; the keyframes are native and few (a trim at most 4 per property for one
//! change, a hold 2); and every player (lottie-web svg and canvas, rlottie, ThorVG,
//! Chromium SMIL) draws what the model draws.

use std::path::PathBuf;

use gmotion::motion::{Animation, Trim};
use gmotion_export_lottie::{LottieOptions, to_lottie};
use gmotion_export_raster::{Pixmap, compare, render};
use gmotion_export_svg::frame::frame_svg;
use gmotion_export_svg::smil::{SmilOptions, to_smil};
use gmotion_import_svg::ImportOptions;
use serde_json::Value;

use crate::support::players::{Player, assert_plays_like_model, chromium, frames_to_check};
use crate::support::run_grammar;

/// A filled, stroked ring and an open tick with round caps (a check-mark icon).
const ICON: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="120" height="120" viewBox="0 0 120 120">
<rect data-tag="background" width="120" height="120" fill="#ffffff"/>
<circle data-tag="ring" cx="60" cy="60" r="42" fill="#dff3e4" stroke="#2a9d5c" stroke-width="6"/>
<path data-tag="tick" d="M 39 62 L 53 75 L 82 46" fill="none" stroke="#1d6e40" stroke-width="7" stroke-linecap="round" stroke-linejoin="round"/>
</svg>"##;

fn animation(grammar: &str) -> Animation {
    let scene = gmotion_import_svg::parse(ICON, "icon.svg", &ImportOptions::default())
        .unwrap()
        .scene;
    run_grammar(scene, grammar)
}

fn dir(name: &str) -> PathBuf {
    let d = crate::support::tmp_dir().join("trim").join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn frame(anim: &Animation, t: f64) -> Pixmap {
    render(&frame_svg(anim, t), 120).unwrap()
}

/// The RGBA of pixel `(x, y)`.
fn pixel(p: &Pixmap, x: u32, y: u32) -> [u8; 4] {
    let i = (y * p.width() + x) as usize * 4;
    let d = p.data();
    [d[i], d[i + 1], d[i + 2], d[i + 3]]
}

/// Holds both shapes at a trim for the whole second: `timesplit` makes one slice, and an
/// inverted slice pre-applies the trim from time 0.
fn held(trim: &str) -> Animation {
    animation(&format!(
        "scene icon.svg\nduration 1s\nfps 30\n\
         animate(trim, local, 0, {trim}) : [all, (ring, tick)] -> [inv_held]\n"
    ))
}

#[test]
fn an_empty_trim_draws_no_stroke_and_a_whole_one_all_of_it_the_fill_untouched() {
    let none = held("(0, 0)");
    let all = held("(0, 1)");
    let plain = animation("scene icon.svg\nduration 1s\nfps 30\n");
    // At t = 0 the inverted slice shows its trim in full.
    let (none, all, plain) = (frame(&none, 0.0), frame(&all, 0.0), frame(&plain, 0.0));
    // (0, 1) is the drawing itself.
    assert_eq!(compare(&all, &plain, 0), 0.0);
    // (0, 0): the ring's stroke (at radius 42, 6 wide) is background or fill, never green;
    // the ring's inside keeps its fill; the tick is gone.
    let fill = [0xdf, 0xf3, 0xe4, 0xff];
    let white = [0xff; 4];
    for k in 0..72 {
        let a = k as f64 * std::f64::consts::TAU / 72.0;
        let (x, y) = (60.0 + 42.0 * a.cos(), 60.0 + 42.0 * a.sin());
        let p = pixel(&none, x.round() as u32, y.round() as u32);
        assert!(p[1] >= 0xe0, "stroke left at ({x:.0}, {y:.0}): {p:?}");
        let inside = pixel(
            &none,
            (60.0 + 30.0 * a.cos()) as u32,
            (60.0 + 30.0 * a.sin()) as u32,
        );
        assert!(inside == fill || inside == white, "{inside:?}");
    }
    assert_eq!(pixel(&none, 53, 75), fill, "the tick's corner");
    assert_eq!(pixel(&plain, 53, 75), [0x1d, 0x6e, 0x40, 0xff]);
}

#[test]
fn an_inverted_trim_slice_is_the_time_reverse_of_its_twin() {
    let anim = animation(
        "scene icon.svg\nduration 2s\nfps 30\n\
         timesplit(0.5, 0.5) : [all, (ring, tick)] -> [a, inv_a]\n\
         animate(trim, local, 0.1, (0.2, 0.7, 0.4), ease=ease-in) : [a, (ring, tick)] -> [cut]\n",
    );
    for k in 0..=20 {
        let t = k as f64 * 0.05;
        for (i, track) in anim.tracks.iter().enumerate() {
            let (x, y) = (track.state_at(t).trim, track.state_at(2.0 - t).trim);
            let same = (x.start - y.start).abs() < 1e-12
                && (x.end - y.end).abs() < 1e-12
                && (x.shift - y.shift).abs() < 1e-12;
            assert!(same, "shape {i} at {t}: {x:?} then {y:?}");
        }
    }
    let tick = &anim.tracks[2];
    assert_eq!(tick.state_at(0.0).trim, Trim::REST);
    assert_eq!(tick.state_at(2.0).trim, Trim::REST);
}

/// Every keyframed property of `json`'s `tm` items, with its keyframe count.
fn trim_keys(json: &str) -> Vec<(String, usize)> {
    fn walk(v: &Value, out: &mut Vec<(String, usize)>) {
        match v {
            Value::Object(o) => {
                if o.get("ty").and_then(Value::as_str) == Some("tm") {
                    assert_eq!(o["m"], 1, "each path trimmed on its own");
                    for p in ["s", "e", "o"] {
                        let n = o[p]["k"]
                            .as_array()
                            .filter(|_| o[p]["a"] == 1)
                            .map_or(0, Vec::len);
                        out.push((p.to_string(), n));
                    }
                }
                o.values().for_each(|x| walk(x, out));
            }
            Value::Array(a) => a.iter().for_each(|x| walk(x, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(&serde_json::from_str(json).unwrap(), &mut out);
    out
}

#[test]
fn one_trim_change_writes_at_most_four_keys_per_property_and_a_hold_two() {
    for ease in [
        "linear",
        "ease-in-out",
        "cubic(0.3, -0.4, 0.7, 1.4)",
        "steps(3)",
    ] {
        let anim = animation(&format!(
            "scene icon.svg\nduration 2s\nfps 30\n\
             animate(trim, local, 0, (0.1, 0.6, 0.5), ease={ease}) : [all, tick] -> [cut]\n"
        ));
        let (json, _) = to_lottie(&anim, &LottieOptions::default()).unwrap();
        let keys = trim_keys(&json);
        assert_eq!(keys.len(), 3, "{ease}: one tm");
        assert!(
            keys.iter().all(|(_, n)| (2..=4).contains(n)),
            "{ease}: {keys:?}"
        );
    }
    let anim = animation(
        "scene icon.svg\nduration 2s\nfps 30\n\
         animate(opacity, local, 0, 0.2, ease=hold) : [all, tick] -> [cut]\n",
    );
    let (json, _) = to_lottie(&anim, &LottieOptions::default()).unwrap();
    let v: Value = serde_json::from_str(&json).unwrap();
    let mut found = Vec::new();
    fn opacities(v: &Value, out: &mut Vec<Value>) {
        match v {
            Value::Object(o) => {
                if let Some(op) = o.get("o").filter(|p| p["a"] == 1) {
                    out.push(op["k"].clone());
                }
                o.values().for_each(|x| opacities(x, out));
            }
            Value::Array(a) => a.iter().for_each(|x| opacities(x, out)),
            _ => {}
        }
    }
    opacities(&v, &mut found);
    assert_eq!(found.len(), 1, "{found:?}");
    let k = found[0].as_array().unwrap();
    assert_eq!(k.len(), 2, "a hold is two keyframes: {k:?}");
    assert_eq!(k[0]["h"], 1);
}

/// The grammars every player plays: a draw-on and off with its inverted twin and an
/// offset, a spinner (a shifted part), steps and holds, and smoothing.
const PLAYED: [(&str, &str); 4] = [
    (
        "draw_on_off",
        "timesplit(0.4, 0.2, 0.4) : [all, (ring, tick)] -> [on, rest, off]\n\
         animate(trim, local, 0, (0, 0), ease=ease-out) : [on, ring] -> [inv_drawn]\n\
         animate(trim, local, 0.3, (0, 0), ease=ease-out) : [on, tick] -> [inv_drawn]\n\
         animate(trim, local, 0, (1, 1), ease=ease-in) : [off, (ring, tick)] -> [gone]\n",
    ),
    (
        "spinner",
        "timesplit(0.5, 0.5) : [all, ring] -> [a, inv_a]\n\
         animate(trim, local, 0, (0.1, 0.35, 1.5)) : [a, ring] -> [spun]\n",
    ),
    (
        "steps_and_hold",
        "timesplit(0.5, 0.5) : [all, (ring, tick)] -> [a, inv_a]\n\
         animate(trim, local, 0, (0, 0.2), ease=steps(4)) : [a, ring] -> [stepped]\n\
         animate(affine, local, 0.2, translate(10, 0), ease=hold) : [a, tick] -> [held]\n",
    ),
    (
        "smoothed",
        "smoothing spring(0.3, 0.2)\n\
         timesplit(0.5, 0.5) : [all, tick] -> [a, inv_a]\n\
         animate(trim, local, 0, (0, 0.3)) : [a, tick] -> [cut]\n",
    ),
];

fn played(rules: &str) -> Animation {
    animation(&format!("scene icon.svg\nduration 2s\nfps 30\n{rules}"))
}

#[test]
fn every_lottie_player_draws_trims_and_holds_as_the_model() {
    for (name, rules) in PLAYED {
        let anim = played(rules);
        let (json, _) = to_lottie(&anim, &LottieOptions::default()).unwrap();
        std::fs::write(dir(name).join("out.json"), &json).unwrap();
        assert_plays_like_model(
            &format!("trim_{name}"),
            &anim,
            &json,
            &frames_to_check(&anim),
            240,
            &Player::ALL,
        );
    }
}

#[test]
fn chromium_plays_the_smil_trims_and_holds_as_the_model() {
    for (name, rules) in PLAYED {
        let anim = played(rules);
        let (svg, _) = to_smil(&anim, &SmilOptions::default()).unwrap();
        let d = dir(name);
        let file = d.join("out.svg");
        std::fs::write(&file, &svg).unwrap();
        let times: Vec<f64> = frames_to_check(&anim)
            .iter()
            .map(|f| f / anim.fps)
            .collect();
        let shots = chromium(&file, 240, &times);
        let mut bad = Vec::new();
        for (&t, got) in times.iter().zip(&shots) {
            let model = render(&frame_svg(&anim, t), 240).unwrap();
            let off = compare(&model, got, 32);
            // Stricter than the players' usual 0.5 %: a stray round cap (a dot where an
            // empty stroke starts or ends) covers about 0.3 % of these frames.
            if off >= 0.001 {
                bad.push(format!("t = {t:.3}: {:.2}% off", off * 100.0));
            }
        }
        assert!(
            bad.is_empty(),
            "{name} ({}):\n{}",
            d.display(),
            bad.join("\n")
        );
    }
}

#[test]
fn bad_trims_and_steps_are_errors_at_the_number() {
    let d = dir("errors");
    std::fs::write(d.join("icon.svg"), ICON).unwrap();
    let dashed = ICON.replace(
        r#"stroke-linejoin="round"/>"#,
        r#"stroke-linejoin="round" stroke-dasharray="4 2" id="tick_path"/>"#,
    );
    std::fs::write(d.join("dashed.svg"), dashed).unwrap();
    for (scene, rule, at, says) in [
        (
            "icon.svg",
            "animate(trim, local, 0, (0.2, 1.5)) : [all, tick] -> [t]",
            ":3:31:",
            "the trim's end is a fraction of the path's length in [0, 1], found 1.5",
        ),
        (
            "icon.svg",
            "animate(trim, local, 0, (-0.1, 0.5)) : [all, tick] -> [t]",
            ":3:26:",
            "the trim's start is a fraction",
        ),
        (
            "icon.svg",
            "animate(trim, local, 0, (0.7, 0.2)) : [all, tick] -> [t]",
            ":3:26:",
            "the trim's start 0.7 is past its end 0.2",
        ),
        (
            "icon.svg",
            "animate(trim, local, 0, 0.5) : [all, tick] -> [t]",
            ":3:25:",
            "a trim is `(start, end)`",
        ),
        (
            "icon.svg",
            "animate(opacity, local, 0, 0.5, ease=steps(0)) : [all, tick] -> [t]",
            ":3:44:",
            "number of steps",
        ),
        (
            "icon.svg",
            "animate(opacity, local, 0, 0.5, ease=steps(2.5)) : [all, tick] -> [t]",
            ":3:44:",
            "number of steps",
        ),
        (
            "dashed.svg",
            "animate(trim, local, 0, (0, 0.5)) : [all, tick] -> [t]",
            ":3:25:",
            "element `tick_path` of shape `tick` #0 has a dashed stroke",
        ),
    ] {
        let g = d.join("bad.gm");
        std::fs::write(&g, format!("scene {scene}\nduration 1s\n{rule}\n")).unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_gmotion"))
            .arg("check")
            .arg(&g)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{rule}: {err}");
        let line = err
            .lines()
            .position(|l| l.contains(&format!("bad.gm{at}")))
            .unwrap_or_else(|| panic!("{rule}: no {at} in\n{err}"));
        assert!(
            err.lines().skip(line).take(6).any(|l| l.contains(says)),
            "{rule}: {says}\n{err}"
        );
    }
}
