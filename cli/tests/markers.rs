//! Markers (`markers TAG …`): the grammar's phases written as named spans of the Lottie file,
//! as a web page plays them. The spans follow from the rules (a `timesplit` of 4 s into
//! 0.25, 0.5, 0.25 makes `in` 0–1 s, `hold` 1–3 s, `out` 3–4 s, whatever renames the pieces
//! later); lottie-web lands on them by name and dotlottie-web lists them.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

fn out_dir(name: &str) -> PathBuf {
    crate::support::case_dir("markers", name)
}

fn root() -> &'static Path {
    crate::support::root()
}

/// Phases `in`, `hold`, `out` over 4 s at 30 fps, each renamed or split further by later
/// rules (so the final slices carry none of the three names), and an inverted twin.
fn phases(dir: &Path, header: &str) -> PathBuf {
    let gm = dir.join("phases.gm");
    std::fs::write(
        &gm,
        format!(
            "scene {}\nduration 4s\nfps 30\n{header}\n\
             timesplit(0.25, 0.5, 0.25) : [all, (s, c)] -> [in, hold, out]\n\
             animate(affine, local, 0.1 * id, rotate(90)) : [in, (s, c)] -> [in_moving]\n\
             timesplit(0.5, 0.5) : [hold, (s, c)] -> [wave, inv_wave]\n\
             animate(affine, local, 0, translate(0, -20)) : [wave, (s, c)] -> [up]\n\
             animate(opacity, local, 0, 0.3) : [out, (s, c)] -> [gone]\n",
            root().join("grammars/toy.svg").display()
        ),
    )
    .unwrap();
    gm
}

fn run_ok(cmd: &mut Command) {
    let out = cmd.output().expect("run gmotion");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn markers_of(lottie: &Path) -> Vec<(String, f64, f64)> {
    let doc: Value = serde_json::from_slice(&std::fs::read(lottie).unwrap()).unwrap();
    doc["markers"]
        .as_array()
        .expect("a markers list")
        .iter()
        .map(|m| {
            (
                m["cm"].as_str().unwrap().to_string(),
                m["tm"].as_f64().unwrap(),
                m["dr"].as_f64().unwrap(),
            )
        })
        .collect()
}

#[test]
fn phases_become_markers_spanning_what_came_from_them() {
    let dir = out_dir("phases");
    let gm = phases(&dir, "markers in hold out wave inv_wave");
    let out = dir.join("p.json");
    run_ok(bin().arg("animate").arg(&gm).arg("-o").arg(&out));
    // In frames at 30 fps: in 0–1 s, hold 1–3 s (its halves `wave` 1–2 s and `inv_wave`
    // 2–3 s), out 3–4 s.
    assert_eq!(
        markers_of(&out),
        [
            ("in".to_string(), 0.0, 30.0),
            ("hold".to_string(), 30.0, 60.0),
            ("out".to_string(), 90.0, 30.0),
            ("wave".to_string(), 30.0, 30.0),
            ("inv_wave".to_string(), 60.0, 30.0),
        ]
    );
    // Without the directive, no markers are written.
    let plain = dir.join("plain.json");
    run_ok(
        bin()
            .arg("animate")
            .arg(phases(&dir, ""))
            .arg("-o")
            .arg(&plain),
    );
    let doc: Value = serde_json::from_slice(&std::fs::read(&plain).unwrap()).unwrap();
    assert!(doc.get("markers").is_none());
}

#[test]
fn the_markers_option_replaces_the_directive() {
    let dir = out_dir("option");
    let gm = phases(&dir, "markers in hold out");
    let out = dir.join("o.json");
    run_ok(
        bin()
            .arg("animate")
            .arg(&gm)
            .args(["--markers", "out,inv_wave"])
            .arg("-o")
            .arg(&out),
    );
    assert_eq!(
        markers_of(&out),
        [
            ("out".to_string(), 90.0, 30.0),
            ("inv_wave".to_string(), 60.0, 30.0),
        ]
    );
    // A tag no slice carries is refused naming the flag, and nothing is written.
    let bad = dir.join("bad.json");
    let res = bin()
        .arg("animate")
        .arg(&gm)
        .args(["--markers", "nowhere"])
        .arg("-o")
        .arg(&bad)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&res.stderr);
    assert!(
        !res.status.success() && err.contains("--markers: marker `nowhere`"),
        "{err}"
    );
    assert!(!bad.exists());
}

#[test]
fn markers_join_a_lottie_scenes_own() {
    let dir = out_dir("over_source");
    // A Lottie scene (the toy example as gmotion writes it) with a marker of its own.
    let scene = dir.join("scene.json");
    run_ok(
        bin()
            .arg("animate")
            .arg(root().join("grammars/toy.gm"))
            .arg("-o")
            .arg(&scene),
    );
    let mut doc: Value = serde_json::from_slice(&std::fs::read(&scene).unwrap()).unwrap();
    doc["markers"] = serde_json::json!([{"tm": 12, "cm": "designer", "dr": 6}]);
    std::fs::write(&scene, doc.to_string()).unwrap();
    let gm = dir.join("on_top.gm");
    std::fs::write(
        &gm,
        "markers a\ntimesplit(0.5, 0.5) : [all, s] -> [a, b]\nanimate(affine, local, 0, scale(1.2)) : [a, s] -> [big]\n",
    )
    .unwrap();
    let out = dir.join("out.json");
    run_ok(
        bin()
            .arg("animate")
            .arg(&scene)
            .arg(&gm)
            .arg("-o")
            .arg(&out),
    );
    // The scene lasts 6 s at 30 fps: `a` is its first half.
    assert_eq!(
        markers_of(&out),
        [
            ("designer".to_string(), 12.0, 6.0),
            ("a".to_string(), 0.0, 90.0)
        ]
    );
}

#[test]
fn a_marker_naming_no_slice_is_an_error_at_the_directive() {
    let dir = out_dir("errors");
    for (header, expected) in [
        (
            "markers in nowhere",
            "phases.gm:4:12: error: marker `nowhere`: no slice carries this tag or comes from one that does",
        ),
        (
            "markers 3",
            "phases.gm:4:9: error: `markers` takes slice tags",
        ),
    ] {
        let gm = phases(&dir, header);
        let out = dir.join("x.json");
        let res = bin()
            .arg("animate")
            .arg(&gm)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&res.stderr);
        assert!(!res.status.success() && err.contains(expected), "{err}");
        assert!(!out.exists());
    }
}

/// lottie-web's `goToAndStop(name, true)` lands on each marker's first frame; dotlottie-web
/// reads the same markers from the `.lottie`.
#[cfg(feature = "players")]
#[test]
fn players_land_on_the_markers() {
    let dir = out_dir("players");
    let gm = phases(&dir, "markers in hold out");
    let (json, lottie) = (dir.join("p.json"), dir.join("p.lottie"));
    run_ok(
        bin()
            .arg("animate")
            .arg(&gm)
            .arg("-o")
            .arg(&json)
            .arg("-o")
            .arg(&lottie),
    );
    let out = Command::new("node")
        .arg(root().join("tests/conformance/lottie_markers.mjs"))
        .arg(&json)
        .args(["in", "hold", "out"])
        .output()
        .expect("run node");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let landed: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(landed, serde_json::json!({"in": 0, "hold": 30, "out": 90}));
    let jobs = dir.join("jobs.json");
    std::fs::write(
        &jobs,
        serde_json::json!([{"lottie": lottie, "width": 104, "height": 64, "frames": [30],
            "out": [dir.join("dl-30.png")]}])
        .to_string(),
    )
    .unwrap();
    let out = Command::new("node")
        .arg(root().join("tests/conformance/dotlottie_web.mjs"))
        .arg(&jobs)
        .output()
        .expect("run node");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let read: Value = serde_json::from_slice(&out.stdout).unwrap();
    let names: Vec<&str> = read["markers"]
        .as_array()
        .expect("dotlottie-web's markers")
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["in", "hold", "out"], "{read}");
}
