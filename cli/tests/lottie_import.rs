//! Lottie in: the real binary on Lottie scenes. The identity (`convert X.json -o Y.json`)
//! on the 111 real After Effects exports of the Lottie corpus, judged by Python's JSON
//! reader (not the one that wrote them); units, tags and parenting on small generated documents; a grammar on top
//! played in lottie-web and rlottie, judged by what the players draw; hostile documents.

use std::path::{Path, PathBuf};
use std::process::Command;

use gmotion_export_raster::Pixmap;
use serde_json::{Value, json};

use crate::support::files_with_extension;
#[cfg(feature = "players")]
use crate::support::players::{Player, frame_path, play, play_with_files};
#[cfg(feature = "players")]
use crate::support::root;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

fn out_dir(name: &str) -> PathBuf {
    crate::support::case_dir("lottie_import", name)
}

/// Runs `cmd`; returns (success, stdout, stderr).
fn run(cmd: &mut Command) -> (bool, String, String) {
    let out = cmd.output().expect("run gmotion");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A 200×200 composition of 60 frames at 30 fps. Layers say `ddd` first, as After
/// Effects writes them: rlottie reads a layer's transform as 3D (ignoring `r`) unless it
/// has seen `ddd: 0`.
fn doc(layers: Value, assets: Value) -> Value {
    json!({"v": "5.7.0", "fr": 30, "ip": 0, "op": 60, "w": 200, "h": 200, "nm": "test",
           "ddd": 0, "assets": assets, "layers": layers, "markers": [], "unknownKey": {"kept": [1, 2]}})
}

fn ks(p: [f64; 2], r: f64, s: f64) -> Value {
    json!({"o": {"a": 0, "k": 100}, "r": {"a": 0, "k": r}, "p": {"a": 0, "k": [p[0], p[1], 0]},
           "a": {"a": 0, "k": [0, 0, 0]}, "s": {"a": 0, "k": [s, s, 100]}})
}

/// A shape layer holding one `w`×`h` rectangle about its origin, filled with `rgb`.
fn rect_layer(
    nm: &str,
    ind: i64,
    parent: Option<i64>,
    p: [f64; 2],
    wh: [f64; 2],
    rgb: [f64; 3],
) -> Value {
    let mut l = json!({"ddd": 0, "ty": 4, "nm": nm, "ind": ind, "ip": 0, "op": 60, "st": 0, "sr": 1,
        "ks": ks(p, 0.0, 100.0), "ao": 0, "bm": 0, "mn": "ADBE Vector Layer",
        "shapes": [{"ty": "gr", "nm": "Group 1", "it": [
            {"ty": "rc", "d": 1, "p": {"a": 0, "k": [0, 0]}, "s": {"a": 0, "k": wh}, "r": {"a": 0, "k": 0}},
            {"ty": "fl", "c": {"a": 0, "k": [rgb[0], rgb[1], rgb[2], 1]}, "o": {"a": 0, "k": 100}, "r": 1},
            {"ty": "tr", "p": {"a": 0, "k": [0, 0]}, "a": {"a": 0, "k": [0, 0]}, "s": {"a": 0, "k": [100, 100]},
             "r": {"a": 0, "k": 0}, "o": {"a": 0, "k": 100}}]}]});
    if let Some(p) = parent {
        l["parent"] = json!(p);
    }
    l
}

#[cfg(feature = "players")]
fn null_layer(nm: &str, ind: i64, ks: Value) -> Value {
    json!({"ddd": 0, "ty": 3, "nm": nm, "ind": ind, "ip": 0, "op": 60, "st": 0, "sr": 1, "ks": ks, "ao": 0})
}

fn write_json(dir: &Path, name: &str, v: &Value) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(v).unwrap()).unwrap();
    p
}

/// Whether two JSON files hold equal documents, read by Python (correctly rounded floats,
/// key order ignored), so the check does not share a parser with what wrote them.
/// Which of the pairs of files read back unequal in Python's JSON reader (one process
/// for all of them).
#[cfg(feature = "players")]
fn json_unequal(pairs: &[(PathBuf, PathBuf)]) -> Vec<PathBuf> {
    let list: Vec<String> = pairs
        .iter()
        .flat_map(|(a, b)| [a.display().to_string(), b.display().to_string()])
        .collect();
    let out = Command::new("python3")
        .arg("-c")
        .arg("import json, sys\nr = lambda p: json.load(open(p, encoding='utf-8-sig'))\na = sys.argv[1:]\nfor i in range(0, len(a), 2):\n    if r(a[i]) != r(a[i + 1]): print(a[i])")
        .args(&list)
        .output()
        .expect("python3 runs (tests/conformance/install.sh)");
    assert!(
        out.status.success(),
        "python3 failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(PathBuf::from)
        .collect()
}

/// The identity on every file of the Lottie corpus (lottie-web's test animations and
/// rlottie's examples, fetched by `tests/conformance/install.sh`): what `convert` writes
/// reads back equal to what it read.
#[cfg(feature = "players")]
#[test]
fn convert_is_the_identity_on_the_lottie_corpus() {
    let folder = root().join("tests/conformance/lottie-corpus");
    let files = files_with_extension(&folder, "json", "run tests/conformance/install.sh");
    assert!(
        files.len() >= 100,
        "the Lottie corpus: {} files",
        files.len()
    );
    let dir = out_dir("identity");
    let mut pairs = Vec::new();
    for f in &files {
        let out = dir.join(f.file_name().unwrap());
        let (ok, _, err) = run(bin().arg("convert").arg(f).arg("-o").arg(&out));
        assert!(ok, "{}: {err}", f.display());
        pairs.push((f.clone(), out));
    }
    let different = json_unequal(&pairs);
    assert!(different.is_empty(), "not the identity: {different:?}");
}

/// The units `check --shapes` lists: (tag:id, box, layer names).
fn units(path: &Path) -> Vec<(String, [f64; 4], String)> {
    let (ok, out, err) = run(bin().arg("check").arg("--shapes").arg(path));
    assert!(ok, "{err}");
    out.lines()
        .skip(1)
        .filter(|l| !l.trim_start().starts_with("measured at frame"))
        .map(|l| {
            let l = l.trim();
            let (name, rest) = l.split_once("  box [").expect("a unit line");
            let (b, rest) = rest.split_once(']').unwrap();
            let b: Vec<f64> = b.split(',').map(|x| x.trim().parse().unwrap()).collect();
            let layers = rest.split_once("layer ").map_or("", |x| x.1).to_string();
            (name.to_string(), [b[0], b[1], b[2], b[3]], layers)
        })
        .collect()
}

#[cfg(feature = "players")]
#[test]
fn layers_are_units_tagged_from_their_names() {
    let dir = out_dir("units");
    let mut hidden = rect_layer("hidden", 9, None, [10.0, 10.0], [4.0, 4.0], [0.0, 0.0, 0.0]);
    hidden["hd"] = json!(true);
    let mut matte = rect_layer("cutout", 7, None, [100.0, 150.0], [20.0, 20.0], [1.0; 3]);
    matte["td"] = json!(1);
    let blue = [0.0, 0.0, 1.0];
    let mut body = rect_layer("Body", 8, None, [100.0, 150.0], [40.0, 10.0], blue);
    body["tt"] = json!(1);
    let layers = json!([
        null_layer("Null 1", 1, ks([50.0, 0.0], 0.0, 100.0)),
        rect_layer("Wheel 2 Outlines", 2, Some(1), [20.0, 30.0], [10.0, 10.0], [1.0, 0.0, 0.0]),
        rect_layer("Wheel 1", 3, None, [20.0, 30.0], [10.0, 10.0], [1.0, 0.0, 0.0]),
        rect_layer("Shape Layer 3", 4, Some(1), [0.0, 100.0], [20.0, 40.0], [0.0, 1.0, 0.0]),
        hidden,
        matte,
        body,
        {"ty": 1, "nm": "Dark Gray Solid 1", "ind": 10, "ip": 0, "op": 60, "st": 0, "sr": 1,
         "ks": ks([0.0, 0.0], 0.0, 100.0), "sc": "#333333", "sw": 200, "sh": 200},
    ]);
    let path = write_json(&dir, "units.json", &doc(layers, json!([])));
    let got = units(&path);
    let names: Vec<&str> = got.iter().map(|u| u.0.as_str()).collect();
    // Paint order, bottom first: ids count within a tag in that order; the hidden layer and
    // the matte source are no units; the null, parent of two, is a rig, after the units.
    assert_eq!(
        names,
        [
            "solid:0",
            "Body:0",
            "shape:0",
            "Wheel:0",
            "Wheel:1",
            "rig null:0"
        ]
    );
    let by = |n: &str| got.iter().find(|u| u.0 == n).unwrap();
    // Parenting: the null moves its children by (50, 0).
    assert_eq!(by("Wheel:1").1, [65.0, 25.0, 75.0, 35.0]);
    assert_eq!(by("Wheel:0").1, [15.0, 25.0, 25.0, 35.0]);
    assert_eq!(by("shape:0").1, [40.0, 80.0, 60.0, 120.0]);
    assert_eq!(by("solid:0").1, [0.0, 0.0, 200.0, 200.0]);
    // The matte moves with its target, and names come back as they were.
    assert_eq!(
        by("Body:0").2,
        "\"Body\" (ind 8) + matte \"cutout\" (ind 7)"
    );
    assert_eq!(by("Wheel:1").2, "\"Wheel 2 Outlines\" (ind 2)");

    // Nothing moves: the output is the input, unknown keys included.
    let g = dir.join("still.gm");
    std::fs::write(&g, "duration 2s\nfps 30\n").unwrap();
    let out = dir.join("out.json");
    let (ok, _, err) = run(bin().arg("animate").arg(&path).arg(&g).arg("-o").arg(&out));
    assert!(ok, "{err}");
    assert!(json_unequal(&[(path.clone(), out.clone())]).is_empty());
}

/// Red pixels' count, centroid and second moments (`xx`, `yy`, `xy`) in a player's frame.
#[cfg(feature = "players")]
fn moments(png: &Path, pick: impl Fn(u8, u8, u8, u8) -> bool) -> (f64, [f64; 2], [f64; 3]) {
    let pm = Pixmap::load_png(png).unwrap_or_else(|e| panic!("{}: {e}", png.display()));
    let w = pm.width() as usize;
    let mut pts = Vec::new();
    for (i, p) in pm.pixels().iter().enumerate() {
        if pick(p.red(), p.green(), p.blue(), p.alpha()) {
            pts.push(((i % w) as f64 + 0.5, (i / w) as f64 + 0.5));
        }
    }
    let n = pts.len() as f64;
    assert!(n > 20.0, "{}: too few pixels ({n})", png.display());
    let c = pts
        .iter()
        .fold([0.0, 0.0], |a, p| [a[0] + p.0 / n, a[1] + p.1 / n]);
    let m = pts.iter().fold([0.0; 3], |a, p| {
        let (dx, dy) = (p.0 - c[0], p.1 - c[1]);
        [a[0] + dx * dx / n, a[1] + dy * dy / n, a[2] + dx * dy / n]
    });
    (n, c, m)
}

/// Runs `gmotion animate SRC GRAMMAR -o out.json` in `dir` with `grammar` as the grammar
/// file's text; returns the Lottie written and what the command said on stderr.
fn animate_lottie(dir: &Path, src: &Path, grammar: &str) -> (String, String) {
    let g = dir.join("grammar.gm");
    std::fs::write(&g, grammar).unwrap();
    let out = dir.join("out.json");
    let (ok, _, err) = run(bin().arg("animate").arg(src).arg(&g).arg("-o").arg(&out));
    assert!(ok, "{err}");
    (std::fs::read_to_string(&out).unwrap(), err)
}

/// Asserts that what `pick` selects in `before` turns a quarter about its centroid by
/// `after`: the centroid stays, the second moments swap their axes and the cross moment
/// changes sign; the area is kept. Returns the starting moments.
#[cfg(feature = "players")]
fn assert_quarter_turn(
    who: &str,
    before: &Path,
    after: &Path,
    pick: impl Fn(u8, u8, u8, u8) -> bool + Copy,
) -> [f64; 3] {
    let (n0, c0, m0) = moments(before, pick);
    let (n1, c1, m1) = moments(after, pick);
    let msg = format!("{who}: before {n0} px at {c0:?} {m0:?}, after {n1} px at {c1:?} {m1:?}");
    assert!(
        (c0[0] - c1[0]).abs() < 1.0 && (c0[1] - c1[1]).abs() < 1.0,
        "{msg}"
    );
    assert!((n0 - n1).abs() < 0.03 * n0, "{msg}");
    let scale = m0[0].max(m0[1]);
    assert!((m1[0] - m0[1]).abs() < 0.05 * scale, "{msg}");
    assert!((m1[1] - m0[0]).abs() < 0.05 * scale, "{msg}");
    assert!((m1[2] + m0[2]).abs() < 0.05 * scale, "{msg}");
    m0
}

/// The opacity (0–1) of pixel `(x, y)` of a player's frame.
#[cfg(feature = "players")]
fn alpha_at(png: &Path, x: usize, y: usize) -> f64 {
    let pm = Pixmap::load_png(png).unwrap();
    pm.pixels()[y * pm.width() as usize + x].alpha() as f64 / 255.0
}

#[cfg(feature = "players")]
#[test]
fn a_turn_and_a_fade_on_top_play_in_lottie_web_and_rlottie() {
    let dir = out_dir("turn");
    // A bar under a rotated, scaled null, and a square under nothing; the bar's own layer
    // carries an AE name and an unknown key, which must come back.
    let mut bar = rect_layer(
        "Bar Outlines",
        2,
        Some(1),
        [10.0, 5.0],
        [60.0, 16.0],
        [1.0, 0.0, 0.0],
    );
    bar["mn"] = json!("ADBE Vector Layer");
    let layers = json!([
        null_layer("Rig", 1, ks([90.0, 80.0], 30.0, 150.0)),
        bar,
        rect_layer(
            "dot",
            3,
            None,
            [160.0, 160.0],
            [24.0, 24.0],
            [0.0, 0.0, 1.0]
        ),
    ]);
    let src = write_json(&dir, "scene.json", &doc(layers, json!([])));
    // The changes last the first 1 s of the 2 s composition: from frame 30 on their end
    // state holds.
    let (text, _) = animate_lottie(
        &dir,
        &src,
        "fps 30\ntimesplit(0.5, 0.5) : [all, all] -> [change, hold]\n\
         animate(affine, local, 0, rotate(90)) : [change, Bar] -> [turned]\n\
         animate(opacity, local, 0, 0.5) : [change, dot] -> [faded]\n",
    );
    let v: Value = serde_json::from_str(&text).unwrap();
    let layers = v["layers"].as_array().unwrap();
    assert_eq!(layers[1]["nm"], "Bar Outlines");
    assert_eq!(layers[1]["mn"], "ADBE Vector Layer");
    assert_eq!(v["unknownKey"], json!({"kept": [1, 2]}));
    let null = layers
        .iter()
        .find(|l| l["nm"] == "gmotion Bar 0")
        .expect("a null layer for the bar's motion");
    assert_eq!(null["ty"], 3);
    assert_eq!(null["parent"], 1, "gmotion's nulls hang where the bar did");
    // The bar hangs from a chain of gmotion's nulls that starts at that one.
    let mut at = layers[1]["parent"].clone();
    let mut chain = 0;
    while at != null["ind"] {
        let l = layers.iter().find(|l| l["ind"] == at).expect("a parent");
        let nm = l["nm"].as_str().unwrap();
        assert!(nm.starts_with("gmotion Bar 0/"), "{nm}");
        at = l["parent"].clone();
        chain += 1;
        assert!(chain < 10);
    }

    let players = [Player::LottieWebSvg, Player::Rlottie];
    let frames = [0.0, 45.0];
    let played = play("lottie_import-turn", &text, &frames, 200, &players);
    let red = |r: u8, g: u8, b: u8, a: u8| a > 128 && r > 128 && g < 64 && b < 64;
    let blue = |r: u8, g: u8, b: u8, a: u8| a > 0 && b > 16 && r < 16 && g < 16;
    for p in players {
        let m0 = assert_quarter_turn(
            &format!("{p:?}"),
            &frame_path(&played, p, 0.0),
            &frame_path(&played, p, 45.0),
            red,
        );
        assert!(
            m0[2].abs() > 0.2 * m0[0].max(m0[1]),
            "{p:?}: the bar starts at an angle: {m0:?}"
        );
        // The square fades to half its opacity and stays where it was.
        let alpha = |f: f64| alpha_at(&frame_path(&played, p, f), 160, 160);
        assert!((alpha(0.0) - 1.0).abs() < 0.02, "{p:?}: {}", alpha(0.0));
        assert!((alpha(45.0) - 0.5).abs() < 0.03, "{p:?}: {}", alpha(45.0));
        let (_, d0, _) = moments(&frame_path(&played, p, 0.0), blue);
        let (_, d1, _) = moments(&frame_path(&played, p, 45.0), blue);
        assert!(
            (d0[0] - d1[0]).abs() < 1.0 && (d0[1] - d1[1]).abs() < 1.0,
            "{p:?}: {d0:?} {d1:?}"
        );
    }
}

#[cfg(feature = "players")]
#[test]
fn top_level_groups_as_units_move_inside_their_layer_in_lottie_web_and_rlottie() {
    let dir = out_dir("groups");
    // One shape layer, turned and under a rotated, scaled null, drawing two top-level
    // groups: a red bar and a blue square. With `units groups` each is a unit.
    let red = [1.0, 0.0, 0.0];
    let blue = [0.0, 0.0, 1.0];
    let rect = |x: f64, w: f64, h: f64| json!({"ty": "rc", "d": 1, "p": fixed(json!([x, 0])), "s": fixed(json!([w, h])), "r": fixed(json!(0))});
    let car = json!({"ddd": 0, "ty": 4, "nm": "Car", "ind": 2, "parent": 1, "ip": 0, "op": 60,
    "st": 0, "sr": 1, "ks": ks([10.0, 5.0], 20.0, 100.0), "ao": 0, "bm": 0,
    "shapes": [
        {"ty": "gr", "nm": "Bar 2", "it": [rect(20.0, 40.0, 10.0), solid_fill(red), group_tr()]},
        {"ty": "gr", "nm": "Group 7", "it": [rect(-25.0, 16.0, 16.0), solid_fill(blue), group_tr()]},
    ]});
    let layers = json!([null_layer("Rig", 1, ks([90.0, 80.0], 30.0, 150.0)), car]);
    let src = write_json(&dir, "scene.json", &doc(layers, json!([])));
    let (ok, listing, err) = run(bin()
        .args(["check", "--shapes", "--units", "groups"])
        .arg(&src));
    assert!(ok, "{err}");
    let tags: Vec<&str> = listing
        .lines()
        .skip(2)
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    // Bottom first; a default group name gives the item's kind; the null is a rig.
    assert_eq!(tags, ["group:0", "Bar:0", "rig"], "{listing}");
    assert!(
        listing.contains("group \"Bar 2\" ($.layers[1].shapes[0])"),
        "{listing}"
    );
    // The layer's parts answer to its name by themselves; the null moves them, once.
    assert!(
        listing.contains("also Bar_2, Car  follows Rig"),
        "{listing}"
    );
    let (ok, _, err) = run(bin()
        .args(["check", "--shapes", "--units", "paths"])
        .arg(&src));
    assert!(!ok && err.contains("--units paths"), "{err}");

    let (text, _) = animate_lottie(
        &dir,
        &src,
        "units groups\nfps 30\ntimesplit(0.5, 0.5) : [all, all] -> [change, hold]\n\
         animate(affine, local, 0, rotate(90)) : [change, Bar] -> [turned]\n\
         animate(opacity, local, 0, 0.5) : [change, group] -> [faded]\n",
    );
    let v: Value = serde_json::from_str(&text).unwrap();
    let source: Value = serde_json::from_str(&std::fs::read_to_string(&src).unwrap()).unwrap();
    let layers = v["layers"].as_array().unwrap();
    assert_eq!(
        layers.len(),
        2,
        "a part moves inside its layer: no null layers"
    );
    assert_eq!(layers[1]["ks"], source["layers"][1]["ks"]);
    assert_eq!(layers[1]["parent"], 1);
    // Each group is wrapped, unchanged, in groups named after its unit.
    for (k, nm) in [(0, "gmotion Bar 0"), (1, "gmotion group 0")] {
        let mut item = &layers[1]["shapes"][k];
        assert_eq!(item["nm"], nm);
        while item["nm"]
            .as_str()
            .is_some_and(|n| n.starts_with("gmotion "))
        {
            assert_eq!(item["it"][1]["ty"], "tr");
            item = &item["it"][0];
        }
        assert_eq!(item, &source["layers"][1]["shapes"][k]);
    }

    let players = [
        Player::LottieWebSvg,
        Player::LottieWebCanvas,
        Player::Rlottie,
        Player::Thorvg,
    ];
    let frames = [0.0, 45.0];
    let played = play("lottie_import-groups", &text, &frames, 200, &players);
    let is_red = |r: u8, g: u8, b: u8, a: u8| a > 128 && r > 128 && g < 64 && b < 64;
    let is_blue = |r: u8, g: u8, b: u8, a: u8| a > 0 && b > 16 && r < 16 && g < 16;
    for p in players {
        // A quarter turn about the bar's centroid, whatever the layer and rig do.
        assert_quarter_turn(
            &format!("{p:?}"),
            &frame_path(&played, p, 0.0),
            &frame_path(&played, p, 45.0),
            is_red,
        );
        // The square stays, fading to half.
        let (b0, d0, _) = moments(&frame_path(&played, p, 0.0), is_blue);
        let (b1, d1, _) = moments(&frame_path(&played, p, 45.0), is_blue);
        assert!(
            (d0[0] - d1[0]).abs() < 1.0
                && (d0[1] - d1[1]).abs() < 1.0
                && (b0 - b1).abs() < 0.03 * b0,
            "{p:?}: {b0} px at {d0:?}, then {b1} px at {d1:?}"
        );
        let alpha = |f: f64| alpha_at(&frame_path(&played, p, f), d0[0] as usize, d0[1] as usize);
        assert!((alpha(0.0) - 1.0).abs() < 0.02, "{p:?}: {}", alpha(0.0));
        assert!((alpha(45.0) - 0.5).abs() < 0.03, "{p:?}: {}", alpha(45.0));
    }
}

#[cfg(feature = "players")]
#[test]
fn parts_painted_by_their_layers_fill_change_colour_and_fade_alone() {
    let dir = out_dir("painted-parts");
    // Two rectangles straight in a shape layer (no groups), painted by one fill of the
    // layer below them and rounded by its round corners: the left one fades to half, the
    // right one turns blue; each must change alone.
    let rect = |nm: &str, x: f64| json!({"ty": "rc", "d": 1, "nm": nm, "p": fixed(json!([x, 0])), "s": fixed(json!([60, 60])), "r": fixed(json!(0))});
    let mut layer = shape_layer("Tiles", 1, ks([100.0, 100.0], 0.0, 100.0), json!([]));
    layer["shapes"] = json!([
        rect("Left", -45.0),
        rect("Right", 45.0),
        {"ty": "rd", "nm": "Round Corners 1", "r": fixed(json!(8))},
        solid_fill([1.0, 0.0, 0.0]),
    ]);
    let src = write_json(&dir, "scene.json", &doc(json!([layer]), json!([])));
    let (text, _) = animate_lottie(
        &dir,
        &src,
        "units groups\nfps 30\ntimesplit(0.5, 0.5) : [all, all] -> [change, hold]\n\
         animate(opacity, local, 0, 0.5) : [change, Right] -> [faded]\n\
         animate(fill, local, 0, #0000ff) : [change, Left] -> [blue]\n",
    );
    let players = Player::ALL;
    let played = play(
        "lottie_import-painted-parts",
        &text,
        &[0.0, 45.0],
        200,
        &players,
    );
    for p in players {
        let pixel = |f: f64, x: usize, y: usize| {
            rgba_at(&Pixmap::load_png(frame_path(&played, p, f)).unwrap(), x, y)
        };
        let at = |f: f64, x: usize| pixel(f, x, 100);
        for x in [55, 145] {
            let (r, g, b, a) = at(0.0, x);
            assert!(
                r > 240 && g < 16 && b < 16 && a > 240,
                "{p:?} frame 0 at x {x}: {:?}",
                (r, g, b, a)
            );
        }
        let (r, g, b, a) = at(45.0, 145);
        assert!(
            r > 240 && g < 16 && b < 16 && a.abs_diff(128) < 8,
            "{p:?} faded: {:?}",
            (r, g, b, a)
        );
        let (r, g, b, a) = at(45.0, 55);
        assert!(
            r < 16 && g < 16 && b > 240 && a > 240,
            "{p:?} blue: {:?}",
            (r, g, b, a)
        );
        // The corners stay rounded: the left rectangle (x 25–85, y 70–130) has its edges
        // but not its corners.
        for f in [0.0, 45.0] {
            assert!(
                pixel(f, 26, 100).3 > 240 && pixel(f, 55, 71).3 > 240,
                "{p:?}"
            );
            assert!(pixel(f, 26, 71).3 < 8 && pixel(f, 84, 129).3 < 8, "{p:?}");
        }
    }
}

/// A file from before Bodymovin 4.1.9 holds fill and stroke colours in 0–255, which
/// lottie-web (Bodymovin's own player, the only one that upgrades such files) divides by 255
/// whatever they are. A black fill tinted blue by a grammar must be written in that scale
/// too (it was written `[0.125, 0.5, 1]`, which lottie-web drew black), and gmotion reads
/// the file as lottie-web does: `[1, 1, 1]` there is near black, not white. A solid layer
/// whose colour changes becomes a shape layer there too, its fill in that scale. rlottie and
/// ThorVG read legacy colours as they are (a 0–255 red is white to them), so lottie-web's
/// two renderers judge.
#[cfg(feature = "players")]
#[test]
fn a_legacy_files_colours_are_read_and_tinted_in_its_scale() {
    let dir = out_dir("legacy-colour");
    let square = |nm: &str, ind: i64, x: f64, rgb: [f64; 3]| {
        shape_layer(
            nm,
            ind,
            ks([x, 100.0], 0.0, 100.0),
            json!([{"ty": "rc", "d": 1, "p": fixed(json!([0, 0])), "s": fixed(json!([50, 50])), "r": fixed(json!(0))},
                   {"ty": "fl", "c": fixed(json!([rgb[0], rgb[1], rgb[2], 255])), "o": fixed(json!(100))},
                   group_tr()]),
        )
    };
    // A red solid along the bottom, whose colour changes too (written as a shape layer).
    let mut plate = json!({"ddd": 0, "ty": 1, "nm": "plate", "ind": 4, "ip": 0, "op": 60,
        "st": 0, "sr": 1, "ao": 0, "sw": 200, "sh": 40, "sc": "#e02020",
        "ks": ks([100.0, 170.0], 0.0, 100.0)});
    plate["ks"]["a"] = fixed(json!([100, 20, 0]));
    let mut d = doc(
        json!([
            square("black", 1, 40.0, [0.0, 0.0, 0.0]),
            square("red", 2, 100.0, [200.0, 40.0, 40.0]),
            square("dim", 3, 160.0, [1.0, 1.0, 1.0]),
            plate
        ]),
        json!([]),
    );
    d["v"] = json!("4.0.0");
    let src = write_json(&dir, "scene.json", &d);
    let (text, err) = animate_lottie(
        &dir,
        &src,
        "loop false\ntimesplit(0.5, 0.5) : [all, (black, plate)] -> [change, hold]\nanimate(fill, local, 0, #2040e0) : [change, (black, plate)] -> [blue]\n",
    );
    assert!(!err.contains("warning"), "{err}");
    let players = [Player::LottieWebSvg, Player::LottieWebCanvas];
    let frames = [0.0, 45.0];
    let played = play("lottie_import-legacy-colour", &text, &frames, 200, &players);
    let out = played.join("anim.json");
    let mut failures = Vec::new();
    for f in frames {
        let ours = own_frame(&out, &dir.join(format!("own-{f}.png")), f);
        let drawn = |pm: &Pixmap, x: usize| {
            let (r, g, b, _) = rgba_at(pm, x, 100);
            (r, g, b)
        };
        let want_blue = f > 0.0;
        for (who, pm) in players
            .iter()
            .map(|p| {
                (
                    format!("{p:?}"),
                    Pixmap::load_png(frame_path(&played, *p, f)).unwrap(),
                )
            })
            .chain([("gmotion".to_string(), ours.clone())])
        {
            let (r, g, b) = drawn(&pm, 40);
            let ok = if want_blue {
                r < 60 && b > 200
            } else {
                r < 20 && g < 20 && b < 20
            };
            if !ok {
                failures.push(format!(
                    "{who} frame {f}: the tinted square is {:?}",
                    (r, g, b)
                ));
            }
            let (r, g, b) = drawn(&pm, 100);
            if !(r > 180 && g < 60 && b < 60) {
                failures.push(format!(
                    "{who} frame {f}: the red square is {:?}",
                    (r, g, b)
                ));
            }
            let (r, g, b) = drawn(&pm, 160);
            if r.max(g).max(b) > 20 {
                failures.push(format!(
                    "{who} frame {f}: the [1, 1, 1] square is {:?}",
                    (r, g, b)
                ));
            }
            let (r, g, b, _) = rgba_at(&pm, 100, 170);
            let ok = if want_blue {
                r < 60 && b > 200
            } else {
                r > 200 && g < 60 && b < 60
            };
            if !ok {
                failures.push(format!("{who} frame {f}: the solid is {:?}", (r, g, b)));
            }
        }
        for p in players {
            let theirs = Pixmap::load_png(frame_path(&played, p, f)).unwrap();
            failures.extend(unlike_own(&ours, &theirs, p, f));
        }
    }
    assert_no_failures(&failures, &played);
}

/// A solid layer's colour changes although Lottie cannot animate a solid's `sc`: the solid
/// (turned, anchored off its corner, half of it masked away) is written as a shape layer
/// drawing its rectangle, whose fill is keyed, and every player draws it as before at the
/// first frame and in the grammar's colour once it is done, as gmotion's own render of the
/// file does; the layer keeps its mask, transform and name, and the shape layer on top
/// keeps its colour.
#[cfg(feature = "players")]
#[test]
fn a_solid_layers_colour_changes_in_every_player() {
    let dir = out_dir("solid-colour");
    let dot = shape_layer(
        "Dot",
        1,
        ks([150.0, 150.0], 0.0, 100.0),
        json!([{"ty": "el", "d": 1, "p": fixed(json!([0, 0])), "s": fixed(json!([30, 30]))},
               solid_fill([0.0, 1.0, 0.0]), group_tr()]),
    );
    let corner = json!([0, 0]);
    let mut solid = json!({"ddd": 0, "ty": 1, "nm": "Red Solid 1", "ind": 2, "ip": 0, "op": 60,
        "st": 0, "sr": 1, "ao": 0, "bm": 0, "sw": 120, "sh": 80, "sc": "#e02020",
        "ks": ks([100.0, 90.0], 20.0, 100.0), "hasMask": true,
        "masksProperties": [{"inv": false, "mode": "a", "nm": "Mask 1", "o": fixed(json!(100)),
            "x": fixed(json!(0)), "pt": fixed(json!({"c": true,
                "v": [[0, 0], [60, 0], [60, 80], [0, 80]],
                "i": [corner, corner, corner, corner], "o": [corner, corner, corner, corner]}))}]});
    solid["ks"]["a"] = fixed(json!([60, 40, 0]));
    let src = write_json(&dir, "scene.json", &doc(json!([dot, solid]), json!([])));
    // The change lasts the first 1 s of the 2 s composition: from frame 30 on its end
    // state holds.
    let (text, err) = animate_lottie(
        &dir,
        &src,
        "loop false\ntimesplit(0.5, 0.5) : [all, solid] -> [change, hold]\nanimate(fill, local, 0, #2040e0) : [change, solid] -> [blue]\n",
    );
    assert!(!err.contains("warning"), "{err}");
    let v: Value = serde_json::from_str(&text).unwrap();
    let layer = &v["layers"][1];
    assert_eq!(
        (
            &layer["nm"],
            &layer["ty"],
            &layer["masksProperties"][0]["nm"]
        ),
        (&json!("Red Solid 1"), &json!(4), &json!("Mask 1"))
    );
    let players = Player::ALL;
    let frames = [0.0, 45.0];
    let played = play("lottie_import-solid-colour", &text, &frames, 200, &players);
    let out = played.join("anim.json");
    let mut failures = Vec::new();
    for f in frames {
        let ours = own_frame(&out, &dir.join(format!("own-{f}.png")), f);
        for p in players {
            let theirs = Pixmap::load_png(frame_path(&played, p, f)).unwrap();
            let px = |x: usize, y: usize| rgba_at(&theirs, x, y);
            // The unmasked half's middle (layer point (30, 40)), the masked half's (90, 40)
            // and the dot on top.
            let (r, g, b, a) = px(72, 80);
            let want_red = f == 0.0;
            let coloured = a > 240
                && if want_red {
                    r > 200 && g < 50 && b < 50
                } else {
                    r < 50 && g < 80 && b > 200
                };
            if !coloured {
                failures.push(format!("{p:?} frame {f}: solid drawn {:?}", (r, g, b, a)));
            }
            if px(128, 100).3 > 8 {
                failures.push(format!("{p:?} frame {f}: the masked half is drawn"));
            }
            let (r, g, b, _) = px(150, 150);
            if !(r < 50 && g > 200 && b < 50) {
                failures.push(format!("{p:?} frame {f}: the dot is {:?}", (r, g, b)));
            }
            failures.extend(unlike_own(&ours, &theirs, p, f));
        }
    }
    assert_no_failures(&failures, &played);
}

/// The colour at `(x, y)` of a rendered frame, straight (not premultiplied).
#[cfg(feature = "players")]
fn rgba_at(pm: &Pixmap, x: usize, y: usize) -> (u8, u8, u8, u8) {
    let c = pm.pixels()[y * pm.width() as usize + x].demultiply();
    (c.red(), c.green(), c.blue(), c.alpha())
}

/// Fails with every collected failure, naming where the played files are.
#[cfg(feature = "players")]
fn assert_no_failures(failures: &[String], files: &Path) {
    assert!(
        failures.is_empty(),
        "{}\n(files in {})",
        failures.join("\n"),
        files.display()
    );
}

/// Says how `theirs`, player `p`'s frame `f`, differs from gmotion's own render `ours`,
/// when more than 1% of its pixels do.
#[cfg(feature = "players")]
fn unlike_own(ours: &Pixmap, theirs: &Pixmap, p: Player, f: f64) -> Option<String> {
    let off = gmotion_export_raster::compare(ours, theirs, 32);
    (off > 0.01).then(|| {
        format!(
            "{p:?} frame {f}: {:.2}% of pixels differ from gmotion's own render",
            off * 100.0
        )
    })
}

/// Runs `check --shapes` on `text` and returns the error message (the command must fail,
/// without panicking).
fn refused(name: &str, text: &str) -> String {
    let dir = out_dir("hostile");
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, text).unwrap();
    let start = std::time::Instant::now();
    let (ok, _, err) = run(bin().arg("check").arg("--shapes").arg(&path));
    assert!(!ok, "{name}: accepted");
    assert!(!err.contains("panicked"), "{name}: {err}");
    assert!(
        start.elapsed().as_secs() < 20,
        "{name}: took {:?}",
        start.elapsed()
    );
    err
}

fn precomp(ref_id: &str, ind: i64) -> Value {
    json!({"ddd": 0, "ty": 0, "nm": "pc", "ind": ind, "refId": ref_id, "ip": 0, "op": 60, "st": 0, "sr": 1,
           "w": 200, "h": 200, "ks": ks([0.0, 0.0], 0.0, 100.0)})
}

#[test]
fn hostile_documents_get_located_errors() {
    let bar = |p: Value| {
        let mut l = rect_layer("a", 1, None, [0.0, 0.0], [4.0, 4.0], [1.0, 0.0, 0.0]);
        l["ks"]["p"]["k"] = p;
        l
    };
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "syntax",
            "{\"v\": \"5.7.0\",\n \"fr\": }".into(),
            ":2:8: malformed JSON",
        ),
        (
            "not_object",
            "[1, 2]".into(),
            "$: expected an object, found an array",
        ),
        (
            "no_rate",
            json!({"ip": 0, "op": 1, "w": 1, "h": 1, "layers": []}).to_string(),
            "$: a Lottie animation needs `fr`",
        ),
        (
            "nan_string",
            doc(json!([]), json!([]))
                .to_string()
                .replace("\"fr\":30", "\"fr\":\"NaN\""),
            "$.fr: expected a number, found a string",
        ),
        (
            "overflow",
            doc(json!([]), json!([]))
                .to_string()
                .replace("\"fr\":30", "\"fr\":1e400"),
            "malformed JSON",
        ),
        (
            "huge",
            doc(json!([bar(json!([1e300, 0]))]), json!([])).to_string(),
            "$.layers[0].ks.p.k[0]: the number is out of range",
        ),
        (
            "wrong_type",
            doc(json!({"a": 1}), json!([])).to_string(),
            "$.layers: expected an array, found an object",
        ),
        (
            "bad_keyframe",
            doc(
                json!([bar(json!([{"t": 0, "s": [0, "x"]}, {"t": 5}]))]),
                json!([]),
            )
            .to_string(),
            "$.layers[0].ks.p.k[0].s[1]: expected a number",
        ),
        (
            "parent_cycle",
            {
                let mut a = rect_layer("a", 1, Some(2), [0.0, 0.0], [4.0, 4.0], [1.0, 0.0, 0.0]);
                let b = rect_layer("b", 2, Some(3), [0.0, 0.0], [4.0, 4.0], [1.0, 0.0, 0.0]);
                let c = rect_layer("c", 3, Some(1), [0.0, 0.0], [4.0, 4.0], [1.0, 0.0, 0.0]);
                a["nm"] = json!("a");
                doc(json!([a, b, c]), json!([])).to_string()
            },
            "$.layers[0].parent: the layers' parents form a cycle",
        ),
        (
            "precomp_cycle",
            doc(
                json!([precomp("x", 1)]),
                json!([
            {"id": "x", "layers": [precomp("y", 1)]}, {"id": "y", "layers": [precomp("x", 1)]}]),
            )
            .to_string(),
            "$.assets[1].layers[0].refId: precompositions form a cycle: x → y → x",
        ),
        (
            "precomp_deep",
            {
                let assets: Vec<Value> = (0..40).map(|i| json!({"id": format!("c{i}"), "layers": [precomp(&format!("c{}", i + 1), 1)]})).collect();
                doc(json!([precomp("c0", 1)]), Value::Array(assets)).to_string()
            },
            "precompositions nest deeper than 32 levels",
        ),
        (
            "precomp_fan_out",
            {
                // Ten uses of the next precomposition at each of nine levels: 10⁹ layers.
                let assets: Vec<Value> = (0..9)
                    .map(|i| {
                        json!({"id": format!("f{i}"),
                "layers": (0..10).map(|k| precomp(&format!("f{}", i + 1), k)).collect::<Vec<_>>()})
                    })
                    .collect();
                let mut assets = assets;
                assets.push(json!({"id": "f9", "layers": [rect_layer("leaf", 1, None, [0.0, 0.0], [2.0, 2.0], [1.0, 0.0, 0.0])]}));
                doc(json!([precomp("f0", 1)]), Value::Array(assets)).to_string()
            },
            "layers to draw",
        ),
        (
            "deep_groups",
            {
                let mut g =
                    json!({"ty": "fl", "c": {"a": 0, "k": [1, 0, 0]}, "o": {"a": 0, "k": 100}});
                for _ in 0..100 {
                    g = json!({"ty": "gr", "it": [g]});
                }
                let mut l = rect_layer("a", 1, None, [0.0, 0.0], [4.0, 4.0], [1.0, 0.0, 0.0]);
                l["shapes"] = json!([g]);
                doc(json!([l]), json!([])).to_string()
            },
            "malformed JSON: recursion limit exceeded",
        ),
        (
            "deep_json",
            format!("{}{}", "[".repeat(5000), "]".repeat(5000)),
            "recursion limit exceeded",
        ),
        (
            "shape_type",
            {
                let mut l = rect_layer("a", 1, None, [0.0, 0.0], [4.0, 4.0], [1.0, 0.0, 0.0]);
                l["shapes"][0]["it"][0]["ty"] = json!(5);
                doc(json!([l]), json!([])).to_string()
            },
            "$.layers[0].shapes[0].it[0].ty: expected a shape type string, found a number",
        ),
    ];
    let mut wrong = Vec::new();
    for (name, text, expected) in &cases {
        let err = refused(name, text);
        if !err.contains(expected) {
            wrong.push(format!("{name}: expected {expected:?} in {err:?}"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn huge_keyframe_arrays_import_in_bounded_time() {
    let dir = out_dir("huge_keys");
    let keys: Vec<Value> = (0..200_000)
        .map(|t| json!({"t": t, "s": [t % 200, 50], "o": {"x": [0.3], "y": [0]}, "i": {"x": [0.7], "y": [1]}}))
        .collect();
    let mut l = rect_layer("runner", 1, None, [0.0, 0.0], [4.0, 4.0], [1.0, 0.0, 0.0]);
    l["ks"]["p"] = json!({"a": 1, "k": keys});
    let path = write_json(&dir, "huge.json", &doc(json!([l]), json!([])));
    let start = std::time::Instant::now();
    let got = units(&path);
    assert!(start.elapsed().as_secs() < 30, "took {:?}", start.elapsed());
    assert_eq!(got.len(), 1);
    assert_eq!(got[0].1, [-2.0, 48.0, 2.0, 52.0]);
}

/// A composition a billion frames long: a grammar without `duration` would last as long,
/// and is refused at once for its frame count, naming the file; one with a duration cuts
/// the composition, and paint over more frames than are sampled is written for the first
/// of them, with a warning, in bounded time.
#[test]
fn paint_on_a_composition_a_billion_frames_long_is_written_in_bounded_time() {
    let dir = out_dir("long_comp");
    let mut l = rect_layer("tile", 1, None, [50.0, 50.0], [20.0, 20.0], [1.0, 0.0, 0.0]);
    l["op"] = json!(1e9);
    l["ks"]["o"] = anim(json!([100]), json!([20]));
    let mut d = doc(json!([l]), json!([]));
    d["op"] = json!(1e9);
    let src = write_json(&dir, "long.json", &d);
    let rules = "loop false\n\
         animate(fill, local, 0, #0000ff) : [all, tile] -> [blue]\n\
         animate(opacity, local, 0, 0.5) : [blue, tile] -> [faded]\n";
    let start = std::time::Instant::now();
    let g = dir.join("grammar.gm");
    std::fs::write(&g, rules).unwrap();
    let (ok, _, err) = run(bin()
        .arg("animate")
        .arg(&src)
        .arg(&g)
        .arg("-o")
        .arg(dir.join("no.json")));
    assert!(
        !ok && err.contains("long.json") && err.contains("more than the limit"),
        "{err}"
    );
    assert!(!dir.join("no.json").exists());
    // 700 s at the grammar's 1 fps, 21 000 frames of the 30 fps composition.
    let (text, err) = animate_lottie(&dir, &src, &format!("duration 700s\nfps 1\n{rules}"));
    assert!(start.elapsed().as_secs() < 30, "took {:?}", start.elapsed());
    assert!(err.contains("the composition is cut at 700s"), "{err}");
    assert!(
        err.contains("paint and opacity are written for its first"),
        "{err}"
    );
    let v: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["op"].as_f64(), Some(21_000.0));
}

/// A shape layer (`ty` 4) named `nm` holding `items` (a group's contents), 60 frames long.
fn shape_layer(nm: &str, ind: i64, ks: Value, items: Value) -> Value {
    json!({"ddd": 0, "ty": 4, "nm": nm, "ind": ind, "ip": 0, "op": 60, "st": 0, "sr": 1,
        "ks": ks, "ao": 0, "bm": 0,
        "shapes": [{"ty": "gr", "nm": "Group 1", "it": items}]})
}

/// An animated property from `a` at frame 0 to `b` at frame 60, linear.
fn anim(a: Value, b: Value) -> Value {
    json!({"a": 1, "k": [
        {"t": 0, "s": a, "i": {"x": [1], "y": [1]}, "o": {"x": [0], "y": [0]}},
        {"t": 60, "s": b}]})
}

fn fixed(v: Value) -> Value {
    json!({"a": 0, "k": v})
}

fn group_tr() -> Value {
    json!({"ty": "tr", "p": fixed(json!([0, 0])), "a": fixed(json!([0, 0])),
        "s": fixed(json!([100, 100])), "r": fixed(json!(0)), "o": fixed(json!(100))})
}

fn solid_fill(rgb: [f64; 3]) -> Value {
    json!({"ty": "fl", "c": fixed(json!([rgb[0], rgb[1], rgb[2], 1])), "o": fixed(json!(100)), "r": 1})
}

#[cfg(feature = "players")]
fn stroke(rgb: [f64; 3], w: f64) -> Value {
    json!({"ty": "st", "c": fixed(json!([rgb[0], rgb[1], rgb[2], 1])), "o": fixed(json!(100)),
        "w": fixed(json!(w)), "lc": 1, "lj": 1, "ml": 4})
}

/// A closed outline through `points`, straight edges.
#[cfg(feature = "players")]
fn polygon(points: &[[f64; 2]]) -> Value {
    let zero = vec![[0.0, 0.0]; points.len()];
    json!({"c": true, "v": points, "i": zero, "o": zero})
}

/// One document per feature of gmotion's own Lottie renderer, each made of large, plain
/// shapes so that the players agree on it: trim paths (simultaneous with an offset,
/// individual), dashes on an ellipse, layer masks in each mode, inverted and luma track
/// mattes, linear and radial gradients with opacity stops, a 3D turn, an auto-oriented
/// layer on a curved path, a precomposition with a start time, stretch and clip, a
/// rounded rectangle drawn counter-clockwise.
#[cfg(feature = "players")]
fn own_render_cases() -> Vec<(&'static str, Value)> {
    let red = [0.9, 0.1, 0.1];
    let blue = [0.1, 0.2, 0.9];
    let centre = ks([100.0, 100.0], 0.0, 100.0);
    let ellipse = json!({"ty": "el", "p": fixed(json!([0, 0])), "s": fixed(json!([120, 120]))});
    let rect = |w: f64, h: f64| json!({"ty": "rc", "d": 1, "p": fixed(json!([0, 0])), "s": fixed(json!([w, h])), "r": fixed(json!(0))});
    let square = polygon(&[[-70.0, -70.0], [70.0, -70.0], [70.0, 70.0], [-70.0, 70.0]]);
    let mask = |mode: &str, pt: Value, inv: bool| json!({"mode": mode, "inv": inv, "pt": fixed(pt), "o": fixed(json!(100)), "x": fixed(json!(0))});
    let mut cases = Vec::new();

    // Trim paths from `s` to `e` (animated over the composition), offset `o` degrees.
    let trim_item = |s: Value, e: Value, o: f64, m: i64| json!({"ty": "tm", "s": s, "e": e, "o": fixed(json!(o)), "m": m});
    let trim = trim_item(
        anim(json!([0]), json!([40])),
        anim(json!([30]), json!([100])),
        45.0,
        1,
    );
    cases.push((
        "trim",
        json!([shape_layer(
            "trim",
            1,
            centre.clone(),
            json!([
                ellipse,
                rect(60.0, 160.0),
                stroke(red, 14.0),
                trim,
                group_tr()
            ])
        )]),
    ));

    let together = trim_item(fixed(json!(0)), anim(json!([20]), json!([90])), 0.0, 2);
    cases.push((
        "trim-individually",
        json!([shape_layer(
            "trim2",
            1,
            centre.clone(),
            json!([
                rect(150.0, 40.0),
                rect(40.0, 150.0),
                together,
                stroke(blue, 10.0),
                group_tr()
            ])
        )]),
    ));

    let mut dashed = stroke(red, 10.0);
    // With their names, as After Effects writes them: lottie-web's svg renderer draws
    // nothing for dashes without.
    dashed["d"] = json!([{"n": "d", "nm": "dash", "v": fixed(json!(30))},
        {"n": "g", "nm": "gap", "v": fixed(json!(15))}, {"n": "o", "nm": "offset", "v": fixed(json!(20))}]);
    cases.push((
        "dashes",
        json!([shape_layer(
            "dashes",
            1,
            centre.clone(),
            json!([ellipse, dashed, group_tr()])
        )]),
    ));

    let outline =
        |x0: f64, y0: f64, x1: f64, y1: f64| polygon(&[[x0, y0], [x1, y0], [x1, y1], [x0, y1]]);
    let expanded = |mut m: Value, x: f64| {
        m["x"] = fixed(json!(x));
        m
    };
    let (tall, inner, corner) = (
        outline(-30.0, -90.0, 30.0, 90.0),
        outline(-40.0, -40.0, 40.0, 40.0),
        outline(-50.0, -50.0, 0.0, 0.0),
    );
    #[rustfmt::skip]
    let mask_cases = [
        ("mask-add", json!([mask("a", square.clone(), false)])),
        ("mask-subtract", json!([mask("a", square.clone(), false), mask("s", tall, false)])),
        ("mask-intersect-inverted", json!([mask("a", square.clone(), false), mask("i", inner.clone(), true)])),
        ("mask-subtract-first", json!([mask("s", corner, false)])),
        ("mask-expanded", json!([expanded(mask("a", inner.clone(), false), 15.0)])),
        ("mask-eroded", json!([expanded(mask("a", square.clone(), false), -15.0)])),
    ];
    for (name, masks) in mask_cases {
        let mut l = shape_layer(
            name,
            1,
            centre.clone(),
            json!([rect(180.0, 180.0), solid_fill(blue), group_tr()]),
        );
        l["hasMask"] = json!(true);
        l["masksProperties"] = masks;
        cases.push((name, json!([l])));
    }

    for (name, tt) in [
        ("matte-inverted-alpha", 2),
        ("matte-luma", 3),
        ("matte-inverted-luma", 4),
    ] {
        let mut matte = shape_layer(
            "matte",
            1,
            ks([100.0, 100.0], 45.0, 100.0),
            json!([rect(110.0, 110.0), solid_fill([0.8, 0.8, 0.8]), group_tr()]),
        );
        matte["td"] = json!(1);
        let mut body = shape_layer(
            "body",
            2,
            centre.clone(),
            json!([rect(170.0, 80.0), solid_fill(red), group_tr()]),
        );
        body["tt"] = json!(tt);
        cases.push((name, json!([matte, body])));
    }

    // Three colour stops, two opacity stops (opaque to a quarter).
    let stops = json!({"p": 3, "k": fixed(json!([0, 0.9, 0.1, 0.1, 0.5, 0.1, 0.8, 0.2, 1, 0.1, 0.2, 0.9, 0, 1, 1, 0.25]))});
    cases.push((
        "gradient-linear",
        json!([shape_layer(
            "gl",
            1,
            centre.clone(),
            json!([rect(180.0, 120.0),
        {"ty": "gf", "o": fixed(json!(100)), "r": 1, "t": 1, "g": stops,
         "s": fixed(json!([-90, 0])), "e": anim(json!([90, 0]), json!([0, 60]))}, group_tr()])
        )]),
    ));
    cases.push((
        "gradient-radial",
        json!([shape_layer(
            "gr",
            1,
            centre.clone(),
            json!([ellipse,
        {"ty": "gf", "o": fixed(json!(100)), "r": 1, "t": 2, "g": stops,
         "s": fixed(json!([0, 0])), "e": fixed(json!([60, 0])), "h": anim(json!([0]), json!([60])),
         "a": fixed(json!(30))}, group_tr()])
        )]),
    ));

    let mut turned = shape_layer(
        "turned",
        1,
        centre.clone(),
        json!([rect(120.0, 80.0), solid_fill(red), group_tr()]),
    );
    turned["ddd"] = json!(1);
    turned["ks"] = json!({"o": fixed(json!(100)), "rx": anim(json!([0]), json!([70])), "ry": fixed(json!(30)),
        "rz": fixed(json!(10)), "or": fixed(json!([0, 0, 0])), "p": fixed(json!([100, 100, 0])),
        "a": fixed(json!([0, 0, 0])), "s": fixed(json!([100, 100, 100]))});
    cases.push(("3d", json!([turned])));

    let mut oriented = shape_layer(
        "arrow",
        1,
        centre.clone(),
        json!([rect(60.0, 20.0), solid_fill(blue), group_tr()]),
    );
    oriented["ao"] = json!(1);
    oriented["ks"]["p"] = json!({"a": 1, "k": [
        {"t": 0, "s": [40, 160, 0], "to": [40, -120, 0], "ti": [-40, -120, 0],
         "i": {"x": 1, "y": 1}, "o": {"x": 0, "y": 0}},
        {"t": 60, "s": [160, 160, 0]}]});
    cases.push(("auto-orient", json!([oriented])));

    let inner = shape_layer(
        "inner",
        1,
        ks([20.0, 20.0], 0.0, 100.0),
        json!([{"ty": "rc", "p": anim(json!([0, 0]), json!([100, 100])), "s": fixed(json!([50, 50])),
                "r": fixed(json!(0))}, solid_fill(red), group_tr()]),
    );
    let mut pre = json!({"ddd": 0, "ty": 0, "nm": "pre", "refId": "comp_1", "ind": 1, "ip": 0, "op": 60,
        "st": 10, "sr": 2, "w": 120, "h": 120, "ks": ks([40.0, 40.0], 0.0, 100.0), "ao": 0, "bm": 0});
    pre["tm"] = Value::Null;
    if let Some(o) = pre.as_object_mut() {
        o.remove("tm");
    }
    cases.push((
        "precomp",
        json!({"layers": [pre], "assets": [{"id": "comp_1", "layers": [inner]}]}),
    ));

    let rounded = json!({"ty": "rc", "d": 3, "p": fixed(json!([0, 0])), "s": fixed(json!([160, 100])),
        "r": fixed(json!(25))});
    let trim_back = trim_item(fixed(json!(0)), anim(json!([10]), json!([70])), 0.0, 1);
    cases.push((
        "rounded-reversed",
        json!([shape_layer(
            "rounded",
            1,
            centre.clone(),
            json!([rounded, trim_back, stroke(blue, 12.0), group_tr()])
        )]),
    ));
    // A repeater: five copies of a bar (with its fill), each turned 30° about the anchor,
    // moved and shrunk, fading from full to a fifth; offset by half a copy, and the same
    // drawn with the first copy at the bottom.
    let repeater = |offset: f64, m: i64| {
        json!({"ty": "rp", "c": fixed(json!(5)), "o": fixed(json!(offset)), "m": m,
            "tr": {"ty": "tr", "a": fixed(json!([0, 0])), "p": fixed(json!([12, 6])), "s": fixed(json!([90, 90])),
                   "r": fixed(json!(30)), "so": fixed(json!(100)), "eo": fixed(json!(20))}})
    };
    let bar = polygon(&[[0.0, -10.0], [70.0, -10.0], [70.0, 10.0], [0.0, 10.0]]);
    for (name, offset, m) in [("repeater", 0.0, 1), ("repeater-offset-below", 0.5, 2)] {
        cases.push((
            name,
            json!([shape_layer(
                name,
                1,
                ks([70.0, 70.0], 0.0, 100.0),
                json!([
                    {"ty": "sh", "ks": fixed(bar.clone())},
                    solid_fill(red),
                    stroke(blue, 3.0),
                    repeater(offset, m),
                    group_tr()
                ])
            )]),
        ));
    }
    // Round corners on a square and a triangle (radius animated), and on an ellipse,
    // which has no corners.
    cases.push((
        "round-corners",
        json!([shape_layer(
            "rounded",
            1,
            centre.clone(),
            json!([
                rect(120.0, 120.0),
                {"ty": "sh", "ks": fixed(polygon(&[[-90.0, 90.0], [0.0, -95.0], [90.0, 90.0]]))},
                {"ty": "rd", "r": anim(json!([0]), json!([40]))},
                solid_fill(red),
                stroke(blue, 4.0),
                group_tr()
            ])
        )]),
    ));
    // Pucker and bloat: a square puckered into a star while a triangle bloats (amounts
    // animated through zero), and an ellipse bloated.
    let triangle = polygon(&[[-60.0, 50.0], [0.0, -60.0], [60.0, 50.0]]);
    cases.push((
        "pucker-bloat",
        json!([
            shape_layer(
                "puckered",
                1,
                ks([70.0, 70.0], 0.0, 100.0),
                json!([
                    {"ty": "sh", "ks": fixed(polygon(&[[-50.0, -50.0], [50.0, -50.0], [50.0, 50.0], [-50.0, 50.0]]))},
                    {"ty": "pb", "a": anim(json!([-60]), json!([40]))},
                    solid_fill(red),
                    group_tr()
                ])
            ),
            shape_layer(
                "bloated",
                2,
                ks([130.0, 130.0], 0.0, 100.0),
                json!([
                    {"ty": "sh", "ks": fixed(triangle.clone())},
                    ellipse.clone(),
                    {"ty": "pb", "a": anim(json!([50]), json!([-30]))},
                    stroke(blue, 4.0),
                    group_tr()
                ])
            )
        ]),
    ));
    // Zig-zags: corners on a rectangle and a triangle (size and ridges animated), smooth
    // points on an ellipse and an open line.
    let zigzag = |size: Value, ridges: Value, points: f64| json!({"ty": "zz", "s": size, "r": ridges, "pt": fixed(json!(points))});
    cases.push((
        "zig-zag-corners",
        json!([shape_layer(
            "zz",
            1,
            centre.clone(),
            json!([
                rect(140.0, 90.0),
                {"ty": "sh", "ks": fixed(triangle)},
                zigzag(anim(json!([4]), json!([12])), anim(json!([2]), json!([6])), 1.0),
                solid_fill(red),
                stroke(blue, 2.0),
                group_tr()
            ])
        )]),
    ));
    cases.push((
        "zig-zag-smooth",
        json!([shape_layer(
            "zz",
            1,
            centre.clone(),
            json!([
                ellipse.clone(),
                {"ty": "sh", "ks": fixed(json!({"c": false, "v": [[-80.0, 80.0], [80.0, 80.0]], "i": [[0, 0], [0, 0]], "o": [[0, 0], [0, 0]]}))},
                zigzag(fixed(json!(9)), fixed(json!(5)), 2.0),
                stroke(blue, 3.0),
                group_tr()
            ])
        )]),
    ));
    // Offset paths: grown with miters (animated from nothing), shrunk with round joins,
    // and an open zig-zag line thickened with bevels.
    let offset = |a: Value, lj: i64| json!({"ty": "op", "a": a, "lj": lj, "ml": fixed(json!(4))});
    let wedge = polygon(&[[-50.0, 40.0], [0.0, -60.0], [50.0, 40.0], [0.0, 15.0]]);
    cases.push((
        "offset-miter",
        json!([shape_layer(
            "grown",
            1,
            centre.clone(),
            json!([
                rect(90.0, 60.0),
                {"ty": "sh", "ks": fixed(wedge.clone())},
                offset(anim(json!([0]), json!([14])), 1),
                solid_fill(red),
                stroke(blue, 2.0),
                group_tr()
            ])
        )]),
    ));
    cases.push((
        "offset-round",
        json!([shape_layer(
            "shrunk",
            1,
            centre.clone(),
            json!([
                ellipse.clone(),
                {"ty": "sh", "ks": fixed(wedge)},
                offset(fixed(json!(-8)), 2),
                stroke(blue, 3.0),
                group_tr()
            ])
        )]),
    ));
    cases.push((
        "offset-open-bevel",
        json!([shape_layer(
            "thick",
            1,
            centre,
            json!([
                {"ty": "sh", "ks": fixed(json!({"c": false, "v": [[-80.0, 40.0], [-30.0, -40.0], [20.0, 40.0], [80.0, -30.0]], "i": [[0, 0], [0, 0], [0, 0], [-20, -20]], "o": [[0, 0], [0, 0], [20, 20], [0, 0]]}))},
                offset(fixed(json!(9)), 3),
                solid_fill(red),
                group_tr()
            ])
        )]),
    ));
    cases.extend(text_cases());
    cases
}

/// A glyph of the test font (size 100, baseline at y = 0): `outlines` (each a closed
/// polygon; a hole runs the other way) and an advance `w`.
#[cfg(feature = "players")]
fn glyph(ch: &str, w: f64, outlines: &[&[[f64; 2]]]) -> Value {
    let items: Vec<Value> = outlines
        .iter()
        .map(|o| json!({"ty": "sh", "ks": fixed(polygon(o))}))
        .collect();
    json!({"ch": ch, "size": 100, "style": "Regular", "fFamily": "Test", "w": w,
        "data": {"shapes": [{"ty": "gr", "nm": ch, "it": items}]}})
}

/// A text layer of `documents` (`(frame, document)`), animators `a` and more options `m`.
#[cfg(feature = "players")]
fn text_layer(
    nm: &str,
    ind: i64,
    p: [f64; 2],
    documents: &[(f64, Value)],
    a: Value,
    m: Value,
) -> Value {
    let k: Vec<Value> = documents
        .iter()
        .map(|(t, d)| {
            let mut d = d.clone();
            d["f"] = json!("Test-Regular");
            json!({"t": t, "s": d})
        })
        .collect();
    json!({"ddd": 0, "ty": 5, "nm": nm, "ind": ind, "ip": 0, "op": 60, "st": 0, "sr": 1,
        "ks": ks(p, 0.0, 100.0), "ao": 0, "bm": 0,
        "t": {"d": {"k": k}, "p": {}, "m": m, "a": a}})
}

#[cfg(feature = "players")]
#[test]
fn text_without_embedded_glyphs_is_set_in_the_installed_font_as_lottie_web_sets_it() {
    let dir = out_dir("system-font-text");
    // "Arial" is what After Effects files name most; Chromium and gmotion both find a
    // face for it through the machine's fonts (Liberation Sans, metric-compatible, where
    // Arial itself is missing: tests/conformance/install.sh installs it).
    let mut d = doc(
        json!([text_layer(
            "Title",
            1,
            [100.0, 110.0],
            &[(
                0.0,
                json!({"t": "Hello, World\rAgain", "s": 36, "j": 2, "tr": 0, "lh": 44, "ls": 0, "fc": [0.9, 0.1, 0.1]})
            )],
            json!([]),
            json!({"g": 1, "a": fixed(json!([0, 0]))}),
        )]),
        json!([]),
    );
    d["fonts"] = json!({"list": [{"fName": "Test-Regular", "fFamily": "Arial", "fStyle": "Regular", "ascent": 71.6, "fOrigin": "n"}]});
    let text = serde_json::to_string(&d).unwrap();
    let src = write_json(&dir, "text.json", &d);
    let ours = dir.join("ours.png");
    let (ok, _, err) = run(bin()
        .arg("convert")
        .arg(&src)
        .args(["-o"])
        .arg(&ours)
        .args(["--time", "0", "--width", "200"]));
    assert!(ok, "{err}");
    assert!(!err.contains("text not drawn"), "{err}");
    let red = |r: u8, g: u8, b: u8, a: u8| a > 128 && r > 128 && g < 100 && b < 100;
    let (n, c, m) = moments(&ours, red);
    // lottie-web's canvas renderer draws nothing of this text in our harness (as of
    // multi-line glyph text), rlottie draws no text, ThorVG only embedded glyphs: the svg
    // renderer is the one player that sets text in the machine's fonts.
    let players = [Player::LottieWebSvg];
    let played = play(
        "lottie_import-system-font-text",
        &text,
        &[0.0],
        200,
        &players,
    );
    for p in players {
        let (pn, pc, pm) = moments(&frame_path(&played, p, 0.0), red);
        let msg = format!("{p:?}: {pn} px at {pc:?} {pm:?}; gmotion {n} px at {c:?} {m:?}");
        // The same letters in the same place: centre within 2 px, spread (the lines'
        // length and spacing) within 10%; ink within 25% (Chromium rasterises text
        // heavier than outlines are filled).
        assert!((pn - n).abs() < 0.25 * pn, "{msg}");
        assert!(
            (pc[0] - c[0]).abs() < 2.0 && (pc[1] - c[1]).abs() < 2.0,
            "{msg}"
        );
        assert!(
            (pm[0] - m[0]).abs() < 0.1 * pm[0] && (pm[1] - m[1]).abs() < 0.1 * pm[1],
            "{msg}"
        );
    }
}

/// Text layers drawn from embedded glyphs (`chars`), one feature each: point text on two
/// lines with tracking, fill and stroke; right and centre justification; box text wrapping
/// at spaces; an animator whose range selector sweeps over the letters moving, scaling,
/// turning, fading and re-colouring them; a document keyframe; anchor grouping by words.
#[cfg(feature = "players")]
fn text_cases() -> Vec<(&'static str, Value)> {
    let square = |x0: f64, x1: f64, y0: f64, y1: f64| vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
    let hole = |x0: f64, x1: f64, y0: f64, y1: f64| vec![[x0, y0], [x0, y1], [x1, y1], [x1, y0]];
    let (i_bar, l_down, l_foot) = (
        square(10.0, 30.0, -70.0, 0.0),
        square(8.0, 26.0, -70.0, 0.0),
        square(8.0, 50.0, -18.0, 0.0),
    );
    let (o_out, o_in) = (
        square(6.0, 60.0, -70.0, 0.0),
        hole(22.0, 44.0, -52.0, -18.0),
    );
    let chars = json!([
        glyph("I", 40.0, &[&i_bar]),
        glyph("L", 56.0, &[&l_down, &l_foot]),
        glyph("O", 66.0, &[&o_out, &o_in]),
        glyph(" ", 30.0, &[]),
    ]);
    let fonts = json!({"list": [{"fName": "Test-Regular", "fFamily": "Test", "fStyle": "Regular", "ascent": 70}]});
    let text = |t: &str, size: f64, j: i64, tr: f64| json!({"t": t, "s": size, "j": j, "tr": tr, "lh": size * 1.3, "ls": 0, "fc": [0.9, 0.1, 0.1]});
    let plain = json!({"g": 1, "a": fixed(json!([0, 0]))});
    let with = |layers: Value| json!({"layers": layers, "assets": [], "fonts": fonts.clone(), "chars": chars.clone()});
    let mut cases = Vec::new();

    let mut stroked = text("LIO OIL\rOLI", 40.0, 0, 60.0);
    stroked["sc"] = json!([0.1, 0.2, 0.9]);
    stroked["sw"] = json!(4);
    cases.push((
        "text-point",
        with(json!([text_layer(
            "lines",
            1,
            [20.0, 80.0],
            &[(0.0, stroked)],
            json!([]),
            plain.clone()
        )])),
    ));
    cases.push((
        "text-justified",
        with(json!([
            text_layer(
                "right",
                1,
                [190.0, 60.0],
                &[(0.0, text("OIL\rLO", 36.0, 1, 0.0))],
                json!([]),
                plain.clone()
            ),
            text_layer(
                "centre",
                2,
                [100.0, 170.0],
                &[(0.0, text("LOL\rI", 36.0, 2, 0.0))],
                json!([]),
                plain.clone()
            ),
        ])),
    ));
    let mut boxed = text("LO IL OI LIO", 30.0, 2, 0.0);
    boxed["ps"] = json!([-80, -60]);
    boxed["sz"] = json!([160, 150]);
    cases.push((
        "text-box",
        with(json!([text_layer(
            "box",
            1,
            [100.0, 100.0],
            &[(0.0, boxed)],
            json!([]),
            plain.clone()
        )])),
    ));
    // A range over the letters sweeping from before the first to past the last: letters
    // it has reached are moved up, enlarged, turned, faded to half and turned blue.
    let animator = json!([{
        "nm": "Animator 1",
        "s": {"t": 0, "r": 1, "b": 1, "sh": 2, "rn": 0, "a": fixed(json!(100)),
              "s": fixed(json!(0)), "e": fixed(json!(40)), "o": anim(json!([-40]), json!([100])),
              "ne": fixed(json!(0)), "xe": fixed(json!(0))},
        "a": {"p": fixed(json!([0, -40, 0])), "s": fixed(json!([150, 150, 100])), "r": fixed(json!(20)),
              "o": fixed(json!(50)), "fc": fixed(json!([0.1, 0.2, 0.9, 1]))}
    }]);
    cases.push((
        "text-animator",
        with(json!([text_layer(
            "swept",
            1,
            [20.0, 130.0],
            &[(0.0, text("LOLIO", 44.0, 0, 20.0))],
            animator,
            plain.clone()
        )])),
    ));
    cases.push((
        "text-keyframes",
        with(json!([text_layer(
            "changing",
            1,
            [30.0, 110.0],
            &[
                (0.0, text("IO", 50.0, 0, 0.0)),
                (20.0, text("LOL", 60.0, 0, 0.0))
            ],
            json!([]),
            plain.clone()
        )])),
    ));
    // Words turn about their own centres (anchor grouping 2, alignment up by half a line).
    let words = json!([{
        "nm": "Animator 1",
        "s": {"t": 0, "r": 1, "b": 3, "sh": 1, "rn": 0, "a": fixed(json!(100)),
              "s": fixed(json!(0)), "e": fixed(json!(100)), "o": fixed(json!(0))},
        "a": {"r": anim(json!([0]), json!([90]))}
    }]);
    cases.push((
        "text-words",
        with(json!([text_layer(
            "words",
            1,
            [20.0, 110.0],
            &[(0.0, text("LOL IO", 40.0, 0, 0.0))],
            words,
            json!({"g": 2, "a": fixed(json!([0, -50]))})
        )])),
    ));
    cases
}

/// Where a player draws a feature otherwise than After Effects and the other players (and
/// gmotion) do: (case, player, what it does).
#[cfg(feature = "players")]
const OWN_RENDER_KNOWN: &[(&str, Player, &str)] = &[
    (
        "mask-expanded",
        Player::LottieWebCanvas,
        "does not expand masks",
    ),
    ("mask-expanded", Player::Rlottie, "does not expand masks"),
    (
        "mask-eroded",
        Player::LottieWebSvg,
        "erodes the rasterised mask by whole pixels (feMorphology): its edge lies a pixel inside",
    ),
    (
        "mask-eroded",
        Player::LottieWebCanvas,
        "does not expand masks",
    ),
    ("mask-eroded", Player::Rlottie, "does not expand masks"),
    (
        "dashes",
        Player::Rlottie,
        "starts the dash pattern elsewhere on an ellipse",
    ),
    (
        "mask-subtract",
        Player::LottieWebCanvas,
        "draws subtract masks as add",
    ),
    (
        "mask-subtract-first",
        Player::LottieWebCanvas,
        "starts from no coverage when the first mask subtracts",
    ),
    (
        "mask-intersect-inverted",
        Player::LottieWebSvg,
        "inverts the intersected mask's outline, not its coverage",
    ),
    (
        "mask-intersect-inverted",
        Player::LottieWebCanvas,
        "ignores the intersecting mask",
    ),
    (
        "mask-intersect-inverted",
        Player::Thorvg,
        "ignores `inv` on an intersecting mask",
    ),
    (
        "matte-luma",
        Player::LottieWebCanvas,
        "draws luma mattes as alpha mattes",
    ),
    (
        "matte-inverted-luma",
        Player::LottieWebSvg,
        "does not draw inverted luma mattes (shows the layer unmatted)",
    ),
    (
        "matte-inverted-luma",
        Player::LottieWebCanvas,
        "draws nothing for inverted luma mattes",
    ),
    (
        "gradient-linear",
        Player::LottieWebCanvas,
        "ignores gradient opacity stops",
    ),
    (
        "gradient-radial",
        Player::LottieWebCanvas,
        "ignores gradient opacity stops",
    ),
    ("3d", Player::Rlottie, "turns 3D layers in another order"),
    (
        "repeater",
        Player::Rlottie,
        "stacks the copies the other way (the first at the bottom)",
    ),
    (
        "repeater",
        Player::Thorvg,
        "stacks the copies the other way (the first at the bottom)",
    ),
    (
        "repeater-offset-below",
        Player::Rlottie,
        "stacks the copies the other way (the first on top)",
    ),
    (
        "repeater-offset-below",
        Player::Thorvg,
        "stacks the copies the other way and fades them in the other order",
    ),
    (
        "round-corners",
        Player::Rlottie,
        "rounds a rectangle's corners but not a path's",
    ),
    (
        "pucker-bloat",
        Player::Rlottie,
        "does not apply pucker and bloat",
    ),
    (
        "zig-zag-corners",
        Player::Rlottie,
        "does not apply zig-zags",
    ),
    ("zig-zag-corners", Player::Thorvg, "does not apply zig-zags"),
    ("zig-zag-smooth", Player::Rlottie, "does not apply zig-zags"),
    ("zig-zag-smooth", Player::Thorvg, "does not apply zig-zags"),
    (
        "offset-miter",
        Player::Rlottie,
        "does not apply offset paths",
    ),
    (
        "offset-miter",
        Player::Thorvg,
        "draws miters past the miter limit (lottie-web bevels them)",
    ),
    (
        "offset-round",
        Player::Rlottie,
        "does not apply offset paths",
    ),
    (
        "offset-round",
        Player::Thorvg,
        "rounds a shrunk outline's corners otherwise",
    ),
    (
        "offset-open-bevel",
        Player::Rlottie,
        "does not apply offset paths",
    ),
    (
        "offset-open-bevel",
        Player::Thorvg,
        "offsets an open outline otherwise (not there and back along both sides)",
    ),
    ("text-point", Player::Rlottie, "draws no text layers"),
    ("text-justified", Player::Rlottie, "draws no text layers"),
    ("text-box", Player::Rlottie, "draws no text layers"),
    ("text-animator", Player::Rlottie, "draws no text layers"),
    ("text-keyframes", Player::Rlottie, "draws no text layers"),
    ("text-words", Player::Rlottie, "draws no text layers"),
    (
        "text-point",
        Player::LottieWebCanvas,
        "throws on a character without a glyph, the line break too, and draws no text",
    ),
    (
        "text-justified",
        Player::LottieWebCanvas,
        "throws on a character without a glyph, the line break too, and draws no text",
    ),
    (
        "text-box",
        Player::LottieWebCanvas,
        "throws on a character without a glyph, the line break too, and draws no text",
    ),
    (
        "text-animator",
        Player::Thorvg,
        "scales and turns selected letters about another point than their centre",
    ),
    (
        "text-words",
        Player::Thorvg,
        "turns word groups about another point than their centre",
    ),
    (
        "auto-orient",
        Player::Rlottie,
        "faces an auto-oriented layer elsewhere at the first frame",
    ),
];

/// gmotion's own render of Lottie (`convert X.json -o f.png --time T`) draws each feature
/// as every player does: lottie-web (both renderers), rlottie and ThorVG, at three frames,
/// each within 1% of pixels, but for the named differences of one player from the others
/// (each checked to still differ, so that a list entry cannot outlive its reason).
#[cfg(feature = "players")]
#[test]
fn own_render_draws_each_feature_as_the_players_do() {
    let dir = out_dir("own_render");
    let frames = [0.0, 24.0, 47.0];
    let mut failures = Vec::new();
    let mut differing = std::collections::HashSet::new();
    for (name, content) in own_render_cases() {
        let d = match content.get("layers") {
            Some(layers) => {
                let mut d = doc(layers.clone(), content["assets"].clone());
                for key in ["fonts", "chars"] {
                    if let Some(v) = content.get(key) {
                        d[key] = v.clone();
                    }
                }
                d
            }
            None => doc(content, json!([])),
        };
        let text = d.to_string();
        let src = write_json(&dir, &format!("{name}.json"), &d);
        // gmotion draws its frames while the players draw theirs.
        let (played, own) = std::thread::scope(|scope| {
            let own = scope
                .spawn(|| frames.map(|f| own_frame(&src, &dir.join(format!("{name}-{f}.png")), f)));
            let played = play(&format!("own-{name}"), &text, &frames, 200, &Player::ALL);
            (
                played,
                own.join().unwrap_or_else(|e| std::panic::resume_unwind(e)),
            )
        });
        for (f, ours) in frames.into_iter().zip(own) {
            for p in Player::ALL {
                let theirs = Pixmap::load_png(frame_path(&played, p, f)).unwrap();
                let off = gmotion_export_raster::compare(&ours, &theirs, 32);
                let known = OWN_RENDER_KNOWN.iter().any(|k| k.0 == name && k.1 == p);
                if off > 0.01 && !known {
                    failures.push(format!(
                        "{name} frame {f}: {p:?} differs on {:.2}% of pixels",
                        off * 100.0
                    ));
                }
                if off > 0.01 && known {
                    differing.insert((name, p));
                }
            }
        }
    }
    for (name, p, why) in OWN_RENDER_KNOWN {
        if !differing.contains(&(*name, *p)) {
            failures.push(format!(
                "{name}: {p:?} now draws it as gmotion does (listed: {why})"
            ));
        }
    }
    assert_no_failures(&failures, &dir);
}

/// gmotion's own render of frame `f` (at 30 fps) of the Lottie file `src`, 200 px wide,
/// written to `png`.
#[cfg(feature = "players")]
fn own_frame(src: &Path, png: &Path, f: f64) -> Pixmap {
    let t = format!("{}", f / 30.0);
    let (ok, _, err) = run(bin()
        .arg("convert")
        .arg(src)
        .args(["--time", &t, "--width", "200", "-o"])
        .arg(png));
    assert!(ok, "{}: {err}", src.display());
    Pixmap::load_png(png).unwrap()
}

/// `convert anim.json -o anim.svg` (no `--time`) plays the whole composition as SMIL, each
/// frame as gmotion's own render draws it: Chromium's drawing of the SVG at a frame is
/// gmotion's PNG of that frame, for features that move by themselves (trims, auto-orient,
/// the shape modifiers), and so is `animate`'s SMIL of the same file with a grammar turning
/// every unit; with `--time` the `.svg` is that frame, still.
#[cfg(feature = "players")]
#[test]
fn a_lottie_converted_to_svg_plays_frame_by_frame_in_chromium() {
    let dir = out_dir("played_svg");
    let names = [
        "trim",
        "auto-orient",
        "round-corners",
        "pucker-bloat",
        "zig-zag-corners",
        "offset-miter",
    ];
    let frames = [0.0, 24.0, 47.0];
    let mut failures = Vec::new();
    for (name, content) in own_render_cases() {
        if !names.contains(&name) {
            continue;
        }
        let src = write_json(&dir, &format!("{name}.json"), &doc(content, json!([])));
        let svg = dir.join(format!("{name}.svg"));
        let (ok, _, err) = run(bin().arg("convert").arg(&src).arg("-o").arg(&svg));
        assert!(ok, "{name}: {err}");
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(
            text.matches("<animate ").count() > 1,
            "{name}: no frames animated"
        );
        // Midway through each frame: a discrete switch lands on the frame's start.
        let times: Vec<f64> = frames.iter().map(|f| (f + 0.5) / 30.0).collect();
        let shots = crate::support::players::chromium(&svg, 200, &times);
        for (f, theirs) in frames.iter().zip(shots) {
            let ours = own_frame(&src, &dir.join(format!("{name}-{f}.png")), *f);
            let off = gmotion_export_raster::compare(&ours, &theirs, 32);
            if off > 0.01 {
                failures.push(format!(
                    "{name} frame {f}: {:.2}% of pixels off",
                    off * 100.0
                ));
            }
        }
        // A grammar on top: the SMIL plays the source's own animation with the motion.
        let gm = dir.join(format!("{name}.gm"));
        std::fs::write(
            &gm,
            "duration 2s\nfps 30\nloop false\nanimate(affine, local, 0, rotate(90)) : [all, all] -> [turned]\n",
        )
        .unwrap();
        let moved = dir.join(format!("{name}-turned.svg"));
        let (ok, _, err) = run(bin()
            .arg("animate")
            .arg(&src)
            .arg(&gm)
            .arg("-o")
            .arg(&moved));
        assert!(ok, "{name}: {err}");
        let played = std::fs::read_to_string(&moved).unwrap();
        assert!(
            played.contains("attributeName=\"display\""),
            "{name}: animate's SMIL is not played frame by frame"
        );
        let shots = crate::support::players::chromium(&moved, 200, &times);
        for (f, theirs) in frames.iter().zip(shots) {
            let png = dir.join(format!("{name}-turned-{f}.png"));
            let t = format!("{}", f / 30.0);
            let (ok, _, err) = run(bin()
                .arg("animate")
                .arg(&src)
                .arg(&gm)
                .args(["--time", &t, "--width", "200", "-o"])
                .arg(&png));
            assert!(ok, "{name}: {err}");
            let ours = Pixmap::load_png(&png).unwrap();
            let off = gmotion_export_raster::compare(&ours, &theirs, 32);
            if off > 0.01 {
                failures.push(format!(
                    "{name} turned, frame {f}: {:.2}% of pixels off",
                    off * 100.0
                ));
            }
        }
        let still = dir.join(format!("{name}-still.svg"));
        let (ok, _, err) = run(bin()
            .arg("convert")
            .arg(&src)
            .args(["--time", "0.5", "-o"])
            .arg(&still));
        assert!(ok, "{name}: {err}");
        assert!(
            !std::fs::read_to_string(&still)
                .unwrap()
                .contains("<animate")
        );
    }
    assert_no_failures(&failures, &dir);
}

/// A played Lottie writes what its frames draw alike once: real files whose frames move a
/// few parts over a still backdrop (an embedded image, a banner, a map, masks whose
/// content stands still) play in Chromium
/// frame for frame as Chromium draws each frame written alone (`--time`), in a file
/// several times smaller than its distinct frames written whole (the parts that stand
/// still are `<use>`d). Chromium judges both sides: where it draws a frame unlike
/// gmotion's own render (the banner's edges, by a pixel), the played file must still
/// show that frame, not another.
#[cfg(feature = "players")]
#[test]
fn a_played_lottie_shares_what_its_frames_draw_alike() {
    let dir = out_dir("shared_frames");
    let folder = root().join("tests/conformance/lottie-corpus");
    let mut judge = crate::support::pictures::Judge::new(0.002);
    for name in [
        "rlottie-python__image_embedded",
        "lottie-web__banner",
        "rlottie-python__world_locations",
        "rlottie-python__1643-exploding-star",
    ] {
        let src = folder.join(format!("{name}.json"));
        let doc: Value = serde_json::from_slice(&std::fs::read(&src).unwrap()).unwrap();
        let (fps, ip, op) = (
            doc["fr"].as_f64().unwrap(),
            doc["ip"].as_f64().unwrap(),
            doc["op"].as_f64().unwrap(),
        );
        let svg = dir.join(format!("{name}.svg"));
        let (ok, _, err) = run(bin().arg("convert").arg(&src).arg("-o").arg(&svg));
        assert!(ok, "{name}: {err}");
        let played = std::fs::read_to_string(&svg).unwrap();
        // Frames spread over the composition.
        let frames: Vec<f64> = [0.0, 0.37, 0.81]
            .iter()
            .map(|x| (x * (op - ip - 1.0)).round())
            .collect();
        let mut whole = 0;
        let mut alone = Vec::new();
        for f in &frames {
            let still = dir.join(format!("{name}-{f}.svg"));
            let t = format!("{}", f / fps);
            let (ok, _, err) = run(bin()
                .arg("convert")
                .arg(&src)
                .args(["--time", &t, "-o"])
                .arg(&still));
            assert!(ok, "{name}: {err}");
            whole = whole.max(std::fs::metadata(&still).unwrap().len() as usize);
            alone.extend(crate::support::players::chromium(&still, 200, &[0.0]));
        }
        let distinct = played.matches("<animate ").count();
        assert!(
            played.contains("<use ") && played.len() * 4 < distinct * whole,
            "{name}: {} bytes for {distinct} frames of up to {whole} bytes each",
            played.len()
        );
        // Shot midway through each frame: a discrete switch lands on the frame's start.
        let times: Vec<f64> = frames.iter().map(|f| (f + 0.5) / fps).collect();
        let shots = crate::support::players::chromium(&svg, 200, &times);
        for ((f, theirs), ours) in frames.iter().zip(shots).zip(alone) {
            judge.close(&format!("{name} frame {f}"), &ours, &theirs);
        }
    }
    judge.assert_all_close(&dir);
}

/// An image layer whose picture is linked (`u` + `p`, `e: 0`, as Bodymovin exports it
/// with an `images/` folder) is drawn from the file beside the document, as rlottie and
/// ThorVG, which read a file's linked pictures, draw it; turned by its layer. (The picture
/// is a soft gradient: players resample pictures each their own way, which a sharp edge
/// inside the picture would show.)
#[cfg(feature = "players")]
#[test]
fn linked_images_are_drawn_from_the_files_folder() {
    let pic = gmotion_export_raster::render(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="60" height="90"><linearGradient id="g" x2="0.6" y2="1"><stop offset="0" stop-color="#1e78c8"/><stop offset="1" stop-color="#f0c814"/></linearGradient><rect width="60" height="90" fill="url(#g)"/></svg>"##,
        60,
    )
    .unwrap();
    let png = pic.encode_png().unwrap();
    let mut layer = json!({"ddd": 0, "ty": 2, "nm": "photo", "refId": "image_0", "ind": 1, "ip": 0, "op": 60, "st": 0, "sr": 1,
        "ks": ks([100.0, 100.0], 0.0, 100.0), "ao": 0});
    layer["ks"]["a"] = fixed(json!([30, 45, 0]));
    layer["ks"]["r"] = anim(json!([0]), json!([90]));
    let d = doc(
        json!([layer]),
        json!([{"id": "image_0", "w": 60, "h": 90, "u": "images/", "p": "photo.png", "e": 0}]),
    );
    let frames = [0.0, 30.0];
    let players = [Player::Rlottie, Player::Thorvg];
    let played = play_with_files(
        "linked-image",
        &d.to_string(),
        &[("images/photo.png", &png)],
        &frames,
        200,
        &players,
    );
    let src = played.join("anim.json");
    let mut failures = Vec::new();
    for f in frames {
        let ours = played.join(format!("gmotion-{f}.png"));
        let t = format!("{}", f / 30.0);
        let (ok, _, err) = run(bin()
            .arg("convert")
            .arg(&src)
            .args(["--time", &t, "--width", "200", "-o"])
            .arg(&ours));
        assert!(ok && !err.contains("image not drawn"), "{err}");
        let ours = Pixmap::load_png(&ours).unwrap();
        for p in players {
            let theirs = Pixmap::load_png(frame_path(&played, p, f)).unwrap();
            let off = gmotion_export_raster::compare(&ours, &theirs, 32);
            // ThorVG draws a turned picture's edges without anti-aliasing (1% of the
            // pixels here, where rlottie and gmotion agree to the pixel).
            let known = p == Player::Thorvg && f > 0.0;
            if off > 0.01 && !known {
                failures.push(format!(
                    "frame {f}: {p:?} differs on {:.2}% of pixels",
                    off * 100.0
                ));
            }
            if known && off <= 0.01 {
                failures.push(format!(
                    "frame {f}: ThorVG now anti-aliases a turned picture's edges; drop the exception"
                ));
            }
        }
    }
    assert_no_failures(&failures, &played);
}

/// `convert anim.json` plays the composition: a GIF of every frame (60 at 30 fps), a
/// folder of the same frames, and a PNG at `--time`; in each, a square that travels from
/// x = 40 to x = 160 is where the keyframes put it.
#[test]
fn a_lottie_file_plays_to_gif_frames_and_png() {
    let dir = out_dir("plays");
    let mut square = shape_layer(
        "square",
        1,
        ks([0.0, 0.0], 0.0, 100.0),
        json!([{"ty": "rc", "d": 1, "s": fixed(json!([20, 20])), "r": fixed(json!(0)),
                "p": anim(json!([40, 100]), json!([160, 100]))}, solid_fill([1.0, 0.0, 0.0]), group_tr()]),
    );
    square["ks"]["o"] = fixed(json!(100));
    let src = write_json(&dir, "anim.json", &doc(json!([square]), json!([])));
    let (gif, frames, png) = (dir.join("a.gif"), dir.join("frames"), dir.join("a.png"));
    let (ok, _, err) = run(bin()
        .arg("convert")
        .arg(&src)
        .args(["--time", "1", "-o"])
        .arg(&gif)
        .arg("-o")
        .arg(&frames)
        .arg("-o")
        .arg(&png));
    assert!(ok, "{err}");
    let red_x = |pm: &Pixmap| {
        let (mut sum, mut n) = (0.0, 0.0);
        for (i, p) in pm.pixels().iter().enumerate() {
            if p.alpha() > 128 && p.red() > 128 {
                sum += (i % pm.width() as usize) as f64 + 0.5;
                n += 1.0;
            }
        }
        sum / n
    };
    // Frame f shows the square at 40 + 120·f/60.
    let listed = files_with_extension(&frames, "png", "the frames folder");
    assert_eq!(listed.len(), 60, "{listed:?}");
    for f in [0, 15, 59] {
        let x = red_x(&Pixmap::load_png(&listed[f]).unwrap());
        assert!((x - (40.0 + 2.0 * f as f64)).abs() < 0.5, "frame {f}: {x}");
    }
    let x = red_x(&Pixmap::load_png(&png).unwrap());
    assert!((x - 100.0).abs() < 0.5, "--time 1: {x}");
    let mut decoder = gif::DecodeOptions::new()
        .read_info(std::fs::File::open(&gif).unwrap())
        .unwrap();
    let mut count = 0;
    while decoder.read_next_frame().unwrap().is_some() {
        count += 1;
    }
    assert_eq!(count, 60);
}

/// What the Lottie writer cannot yet lay onto a Lottie source's layers (a morph of a
/// layer's outline, a trim) is left out with a warning naming the unit, never silently.
#[test]
fn morphs_and_trims_onto_a_lottie_source_are_warned_of() {
    let dir = out_dir("left-out");
    let layers = json!([rect_layer(
        "box",
        1,
        None,
        [100.0, 100.0],
        [40.0, 40.0],
        [0.2, 0.4, 0.8]
    )]);
    write_json(&dir, "scene.json", &doc(layers, json!([])));
    for (name, rule, said) in [
        (
            "morph",
            r#"animate(morph, local, 0, "M80 80 L120 80 L100 120 Z") : [a, box] -> [m]"#,
            "box:0: a morph is not yet layered onto a Lottie source; left out",
        ),
        (
            "trim",
            "animate(trim, local, 0, (0, 0.5)) : [a, box] -> [m]",
            "box:0: a trim is not yet layered onto a Lottie source; left out",
        ),
    ] {
        let grammar = format!(
            "scene \"scene.json\"\nduration 2s\nfps 30\nloop false\ntimesplit(0.5, 0.5) : [all, box] -> [a, b]\n{rule}\n"
        );
        std::fs::write(dir.join(format!("{name}.gm")), grammar).unwrap();
        let (ok, _, err) = run(bin().current_dir(&dir).args([
            "animate",
            &format!("{name}.gm"),
            "-o",
            &format!("{name}.json"),
        ]));
        assert!(ok, "{err}");
        assert!(err.contains(said), "{name}: {err}");
        assert!(dir.join(format!("{name}.json")).is_file());
    }
}
