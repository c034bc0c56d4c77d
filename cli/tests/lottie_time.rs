//! A Lottie scene's time is its composition's: a grammar without `duration` lasts the
//! composition at its frame rate, a longer one holds the last frame (precompositions
//! included), a shorter one cuts it; units are measured where they are visible; `k` and
//! `count` stagger over what a rule matched. Each played in lottie-web (svg and canvas),
//! rlottie and ThorVG against gmotion's own render.

use std::path::{Path, PathBuf};
use std::process::Command;

use gmotion_export_raster::Pixmap;
use serde_json::{Value, json};

use crate::support::pictures::load;
use crate::support::players::{Player, frame_path, play};

fn out_dir(name: &str) -> PathBuf {
    crate::support::case_dir("lottie_time", name)
}

/// Runs gmotion in `dir`; returns its standard output and error, failing the test when it
/// fails.
fn gmotion(dir: &Path, args: &[&str]) -> (String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_gmotion"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run gmotion");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "gmotion {args:?}: {err}");
    (String::from_utf8_lossy(&out.stdout).into_owned(), err)
}

/// A square `side` wide centred `(dx, 0)` from a shape layer's anchor, filled `rgb`.
fn square_layer(nm: &str, ind: i64, ks: Value, rgb: [f64; 3], dx: f64, side: f64) -> Value {
    json!({
        "ddd": 0, "ind": ind, "ty": 4, "nm": nm, "sr": 1, "ks": ks, "ao": 0,
        "ip": 0, "op": 45, "st": 0, "bm": 0,
        "shapes": [{
            "ty": "gr", "nm": "square", "it": [
                {"ty": "rc", "d": 1, "s": {"a": 0, "k": [side, side]}, "p": {"a": 0, "k": [dx, 0]}, "r": {"a": 0, "k": 0}},
                {"ty": "fl", "c": {"a": 0, "k": [rgb[0], rgb[1], rgb[2], 1]}, "o": {"a": 0, "k": 100}, "r": 1},
                {"ty": "tr", "p": {"a": 0, "k": [0, 0]}, "a": {"a": 0, "k": [0, 0]}, "s": {"a": 0, "k": [100, 100]}, "r": {"a": 0, "k": 0}, "o": {"a": 0, "k": 100}}
            ]
        }]
    })
}

/// A static transform at `p`.
fn at(p: [f64; 2]) -> Value {
    json!({"p": {"a": 0, "k": [p[0], p[1], 0]}, "a": {"a": 0, "k": [0, 0, 0]}, "s": {"a": 0, "k": [100, 100, 100]}, "r": {"a": 0, "k": 0}, "o": {"a": 0, "k": 100}})
}

/// A transform moving linearly from `a` (frame 0) to `b` (frame 44).
fn moving(a: [f64; 2], b: [f64; 2]) -> Value {
    let mut ks = at(a);
    ks["p"] = json!({"a": 1, "k": [
        {"t": 0, "s": [a[0], a[1], 0], "i": {"x": [1], "y": [1]}, "o": {"x": [0], "y": [0]}},
        {"t": 44, "s": [b[0], b[1], 0]}
    ]});
    ks
}

/// A 200×200 composition of 45 frames at 30 fps (1.5 s).
fn composition(layers: Vec<Value>, assets: Vec<Value>) -> Value {
    json!({"v": "5.7.4", "fr": 30, "ip": 0, "op": 45, "w": 200, "h": 200, "nm": "t", "ddd": 0,
           "assets": assets, "layers": layers})
}

/// The document drawn over the composition, the grammar and its outputs in a folder.
fn animate(dir: &Path, doc: &Value, grammar: &str) -> (Value, String) {
    std::fs::write(dir.join("scene.json"), doc.to_string()).unwrap();
    std::fs::write(dir.join("g.gm"), grammar).unwrap();
    let (_, err) = gmotion(
        dir,
        &[
            "animate",
            "scene.json",
            "g.gm",
            "-o",
            "out.json",
            "-o",
            "frames/",
        ],
    );
    let out = std::fs::read_to_string(dir.join("out.json")).unwrap();
    (serde_json::from_str(&out).unwrap(), err)
}

/// Plays `out` in every player at `frames` and says where one differs from gmotion's own
/// frames (`dir/frames/`) on more than 1% of its pixels.
fn unlike_own(case: &str, dir: &Path, out: &Value, frames: &[f64]) -> Vec<String> {
    let played = play(case, &out.to_string(), frames, 200, &Player::ALL);
    let mut failures = Vec::new();
    for &f in frames {
        let ours = own(dir, f);
        for p in Player::ALL {
            let theirs = load(&frame_path(&played, p, f));
            let off = gmotion_export_raster::compare(&ours, &theirs, 32);
            if off > 0.01 {
                failures.push(format!(
                    "{case}: {p:?} frame {f}: {:.2}% of pixels differ from gmotion's own render (files in {})",
                    off * 100.0,
                    played.display()
                ));
            }
        }
    }
    failures
}

/// gmotion's own frame `f` of the animation written to `dir/frames/`.
fn own(dir: &Path, f: f64) -> Pixmap {
    load(&dir.join(format!("frames/frame_{:05}.png", f as usize)))
}

/// The centre of the pixels of `pm` whose straight colour is close to `rgb` (0–255).
fn centre_of(pm: &Pixmap, rgb: [u8; 3]) -> Option<(f64, f64)> {
    let (mut n, mut sx, mut sy) = (0.0, 0.0, 0.0);
    let w = pm.width() as usize;
    for (i, px) in pm.pixels().iter().enumerate() {
        let c = px.demultiply();
        let near = |a: u8, b: u8| a.abs_diff(b) < 40;
        if c.alpha() > 200
            && near(c.red(), rgb[0])
            && near(c.green(), rgb[1])
            && near(c.blue(), rgb[2])
        {
            n += 1.0;
            sx += (i % w) as f64 + 0.5;
            sy += (i / w) as f64 + 0.5;
        }
    }
    (n > 0.0).then(|| (sx / n, sy / n))
}

/// Without `duration` and `fps` a grammar lasts the composition (1.5 s, not the 5 s
/// default) at its frame rate (24, not 30): the export keeps the composition's length, and
/// own render and players agree on every frame, the last included.
#[test]
fn a_grammar_without_duration_lasts_the_composition() {
    let dir = out_dir("composition");
    let mut doc = composition(
        vec![square_layer(
            "box",
            1,
            moving([50.0, 100.0], [150.0, 100.0]),
            [1.0, 0.0, 0.0],
            0.0,
            40.0,
        )],
        vec![],
    );
    doc["fr"] = json!(24);
    let (out, _) = animate(
        &dir,
        &doc,
        "animate(affine, local, 0, rotate(90)) : [all, all] -> [turned]\n",
    );
    assert_eq!(out["op"].as_f64(), Some(45.0), "op of {out}");
    assert_eq!(out["fr"].as_f64(), Some(24.0));
    let frames = std::fs::read_dir(dir.join("frames")).unwrap().count();
    assert_eq!(frames, 45, "own render frames");
    let failures = unlike_own("composition", &dir, &out, &[0.0, 22.0, 44.0]);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A `duration` longer than the composition holds its last frame: a layer's keyframes and
/// a precomposition's content stay where they were at its last frame (the content's layers
/// end with the composition, and would vanish without the hold), in every player as in
/// gmotion's own render, and a warning says so. A shorter one cuts the composition.
#[test]
fn a_longer_duration_holds_the_last_frame_and_a_shorter_one_cuts() {
    let dir = out_dir("held");
    let inner = square_layer(
        "inner",
        1,
        moving([40.0, 40.0], [160.0, 40.0]),
        [0.0, 0.0, 1.0],
        0.0,
        30.0,
    );
    let precomp = json!({
        "ddd": 0, "ind": 2, "ty": 0, "nm": "clip", "refId": "comp_0", "sr": 1, "ks": at([0.0, 0.0]),
        "ao": 0, "w": 200, "h": 200, "ip": 0, "op": 45, "st": 0, "bm": 0
    });
    let doc = composition(
        vec![
            square_layer(
                "box",
                1,
                moving([50.0, 120.0], [150.0, 120.0]),
                [1.0, 0.0, 0.0],
                0.0,
                40.0,
            ),
            precomp,
        ],
        vec![json!({"id": "comp_0", "layers": [inner]})],
    );
    // No motion: what plays is the composition itself, made to last 3 s.
    let (out, err) = animate(
        &dir,
        &doc,
        "duration 3s\ntimesplit(0.5, 0.5) : [all, all] -> [a, b]\n",
    );
    assert!(err.contains("last frame is held"), "{err}");
    assert_eq!(out["op"].as_f64(), Some(90.0), "op of {out}");
    let frames = [44.0, 60.0, 89.0];
    let mut failures = unlike_own("held", &dir, &out, &frames);
    let played = play("held-again", &out.to_string(), &frames, 200, &Player::ALL);
    for p in Player::ALL {
        let last = load(&frame_path(&played, p, 44.0));
        for f in [60.0, 89.0] {
            let later = load(&frame_path(&played, p, f));
            let off = gmotion_export_raster::compare(&last, &later, 32);
            if off > 0.001 {
                failures.push(format!(
                    "{p:?}: frame {f} is not frame 44 ({:.2}% off)",
                    off * 100.0
                ));
            }
        }
        // Both squares are there: the held content did not vanish.
        if centre_of(&load(&frame_path(&played, p, 89.0)), [0, 0, 255]).is_none() {
            failures.push(format!(
                "{p:?}: the precomposition's square is gone at frame 89"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));

    let dir = out_dir("cut");
    let (out, err) = animate(
        &dir,
        &doc,
        "duration 1s\ntimesplit(0.5, 0.5) : [all, all] -> [a, b]\n",
    );
    assert!(err.contains("composition is cut at 1s"), "{err}");
    assert_eq!(out["op"].as_f64(), Some(30.0), "op of {out}");
    let failures = unlike_own("cut", &dir, &out, &[0.0, 15.0, 29.0]);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A layer that pops in at frame 5 (scale held at 0 before) is measured there, not at
/// frame 0 where it is a point: a `local` turn pivots about its own centre, so its centre
/// stays put, in every player. `check --shapes` says which frame.
#[test]
fn units_are_measured_where_they_are_visible() {
    let dir = out_dir("reference");
    let mut ks = at([100.0, 100.0]);
    ks["s"] = json!({"a": 1, "k": [
        {"t": 0, "s": [0, 0, 100], "h": 1},
        {"t": 5, "s": [100, 100, 100]}
    ]});
    // The square sits 40 px right of the anchor: at scale 0 its centroid is the anchor.
    let doc = composition(
        vec![square_layer("pop", 1, ks, [1.0, 0.0, 0.0], 40.0, 30.0)],
        vec![],
    );
    std::fs::write(dir.join("scene.json"), doc.to_string()).unwrap();
    let (listing, _) = gmotion(&dir, &["check", "--shapes", "scene.json"]);
    assert!(listing.contains("measured at frame 5 "), "{listing}");
    assert!(listing.contains("centroid (140.0, 100.0)"), "{listing}");
    let (out, _) = animate(
        &dir,
        &doc,
        "loop false\nanimate(affine, local, 0, rotate(90)) : [all, all] -> [turned]\n",
    );
    let frames = [10.0, 30.0, 44.0];
    let mut failures = unlike_own("reference", &dir, &out, &frames);
    let played = play(
        "reference-again",
        &out.to_string(),
        &frames,
        200,
        &Player::ALL,
    );
    for p in Player::ALL {
        for f in frames {
            match centre_of(&load(&frame_path(&played, p, f)), [255, 0, 0]) {
                Some((x, y)) if (x - 140.0).abs() < 1.5 && (y - 100.0).abs() < 1.5 => {}
                c => failures.push(format!(
                    "{p:?} frame {f}: the square's centre is {c:?}, not (140, 100)"
                )),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // `reference_time` in the grammar measures it where it says (frame 0: a point).
    std::fs::write(
        dir.join("at0.gm"),
        "reference_time 0\nanimate(affine, local, 0, rotate(90)) : [all, all] -> [turned]\n",
    )
    .unwrap();
    let (listing, _) = gmotion(&dir, &["check", "--shapes", "scene.json", "at0.gm"]);
    assert!(listing.contains("measured at frame 0 "), "{listing}");
}

/// `k` numbers the shapes a rule matched in paint order and `count` says how many, across
/// tags: three layers with names of their own, each its own tag with `id` 0, start one
/// after the other, the bottom one first, and all travel `20 * count` px.
#[test]
fn k_and_count_stagger_over_what_a_rule_matched() {
    let dir = out_dir("stagger");
    let colours = [[1.0, 0.0, 0.0], [0.0, 0.7, 0.0], [0.0, 0.0, 1.0]];
    // Layers are listed topmost first: the blue one is at the bottom, drawn first.
    let layers = (0..3)
        .map(|i| {
            let name = ["red", "green", "blue"][i];
            square_layer(
                name,
                i as i64 + 1,
                at([40.0, 40.0 + 55.0 * i as f64]),
                colours[i],
                0.0,
                30.0,
            )
        })
        .collect();
    let doc = composition(layers, vec![]);
    let (out, _) = animate(
        &dir,
        &doc,
        "loop false\ntimesplit(0.8, 0.2) : [all, all] -> [go, stay]\n\
         animate(affine, world, 0.3 * k, translate(20 * count, 0)) : [go, all] -> [moved]\n",
    );
    let frames = [0.0, 8.0, 26.0, 44.0];
    let failures = unlike_own("stagger", &dir, &out, &frames);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let x = |f: f64, rgb: [u8; 3]| {
        centre_of(&own(&dir, f), rgb)
            .expect("the square is drawn")
            .0
    };
    let (red, green, blue) = ([255, 0, 0], [0, 178, 0], [0, 0, 255]);
    // At 0.27 s only the bottom (blue, k = 0) has started; at 0.87 s the green (k = 1, from
    // 0.3 s) and the red (k = 2, from 0.6 s) have too, each behind the one before.
    assert!(
        x(8.0, blue) > 45.0 && (x(8.0, green) - 40.0).abs() < 0.5,
        "{} {}",
        x(8.0, blue),
        x(8.0, green)
    );
    assert!(
        x(26.0, green) > 45.0 && x(26.0, blue) > x(26.0, green) && x(26.0, green) > x(26.0, red)
    );
    // Every square ends 60 px (20 × 3) to the right, by 1.2 s.
    for c in [red, green, blue] {
        assert!(
            (x(44.0, c) - 100.0).abs() < 0.5,
            "{c:?} ends at {}",
            x(44.0, c)
        );
    }
}
