//! `--pack`: runs of plain shape layers written as one layer of named groups. The packed
//! file must draw what gmotion draws in every player (lottie-web svg and canvas, rlottie,
//! ThorVG), keep every unit's name (as a group) and the group hierarchy (null layers and
//! the layers parented to them), and a packed After Effects file must draw, in each player,
//! what that player drew of the file as it was.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::support::pictures::{Judge, gmotion, load};
use crate::support::players::{Player, frame_path, play};
use crate::support::root;

fn dir(name: &str) -> PathBuf {
    let d = crate::support::tmp_dir().join("pack").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The document's root layers.
fn layers(doc: &Value) -> &Vec<Value> {
    doc["layers"].as_array().expect("a layer list")
}

/// The names a document gives its units: the shape layers' names, and inside a packed
/// layer (named `first … last`) its groups' names.
fn unit_names(doc: &Value) -> Vec<String> {
    let mut names = Vec::new();
    for l in layers(doc).iter().filter(|l| l["ty"] == 4) {
        let nm = l["nm"].as_str().unwrap();
        if nm.contains(" … ") {
            for g in l["shapes"].as_array().unwrap() {
                names.push(g["nm"].as_str().unwrap().to_string());
            }
        } else {
            names.push(nm.to_string());
        }
    }
    names
}

/// Frame numbers spread over a document of `op` frames, both ends included.
fn spread(op: f64, count: usize) -> Vec<f64> {
    (0..count)
        .map(|k| (k as f64 * (op - 1.0) / (count - 1) as f64).floor())
        .collect()
}

/// Plays `packed.json` of `dir` in every player at `frames`, `width` px wide, and judges each
/// frame against gmotion's own (`frames/` of `dir`, written at that width).
fn plays_like_our_frames(case: &str, d: &Path, frames: &[f64], width: u32) {
    let text = std::fs::read_to_string(d.join("packed.json")).unwrap();
    let played = play(case, &text, frames, width, &Player::ALL);
    let mut judge = Judge::new(0.005);
    for f in frames {
        let ours = load(&d.join(format!("frames/frame_{:05}.png", *f as usize)));
        for p in Player::ALL {
            judge.close(
                &format!("{p:?} frame {f}"),
                &ours,
                &load(&frame_path(&played, p, *f)),
            );
        }
    }
    judge.assert_all_close(&played);
}

#[test]
fn a_packed_gallery_example_keeps_every_name_and_plays_as_gmotion_draws_it() {
    let d = dir("teaser");
    let grammars = root().join("grammars");
    for f in ["teaser.gm", "teaser.svg"] {
        std::fs::copy(grammars.join(f), d.join(f)).unwrap();
    }
    let width = "300";
    gmotion(
        &d,
        &["animate", "teaser.gm", "-o", "plain.json", "--width", width],
    );
    gmotion(
        &d,
        &[
            "animate",
            "teaser.gm",
            "-o",
            "packed.json",
            "-o",
            "frames/",
            "--width",
            width,
            "--pack",
        ],
    );
    let (plain, packed) = (
        read_json(&d.join("plain.json")),
        read_json(&d.join("packed.json")),
    );
    // 209 shapes, each a layer, under the null that scales the canvas to 300 px: packed,
    // four shape layers (of at most 64 groups) under that null.
    assert!(
        layers(&plain).len() > 200,
        "{} layers",
        layers(&plain).len()
    );
    assert_eq!(layers(&packed).len(), 5, "the null and four shape layers");
    assert_eq!(unit_names(&plain), unit_names(&packed));
    let op = packed["op"].as_f64().unwrap();
    let frames = spread(op, 9);
    plays_like_our_frames("pack-teaser", &d, &frames, 300);
}

/// An Illustrator file's groups: `Layer_1` › `Bike` › `letter_G`, `Wheel`; `Ground`.
const ART: &str = r##"<svg id="Layer_1" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 120">
<g id="Ground"><rect y="100" fill="#3AAA35" width="200" height="20"/></g>
<g id="Bike">
  <path id="letter_G" fill="#E94E1B" d="M20,20h40v20H40v40h20V60h10v30H20V20z"/>
  <g id="Wheel"><circle fill="#1D71B8" cx="140" cy="60" r="30"/><rect x="136" y="32" fill="#FFFFFF" width="8" height="56"/></g>
  <circle id="bell" fill="#FFD166" cx="100" cy="30" r="6"/>
</g>
</svg>"##;

#[test]
fn packing_keeps_the_group_hierarchy_and_packs_only_siblings() {
    let d = dir("hierarchy");
    std::fs::write(d.join("art.svg"), ART).unwrap();
    std::fs::write(
        d.join("art.gm"),
        "scene art.svg\nduration 1s\nfps 30\n\
         animate(affine, local, 0, rotate(120)) : [all, Wheel] -> [spun]\n",
    )
    .unwrap();
    gmotion(&d, &["animate", "art.gm", "-o", "plain.json"]);
    gmotion(
        &d,
        &[
            "animate",
            "art.gm",
            "-o",
            "packed.json",
            "-o",
            "frames/",
            "--pack",
        ],
    );
    let (plain, packed) = (
        read_json(&d.join("plain.json")),
        read_json(&d.join("packed.json")),
    );
    let nulls = |doc: &Value| -> Vec<String> {
        layers(doc)
            .iter()
            .filter(|l| l["ty"] == 3)
            .map(|l| l["nm"].as_str().unwrap().to_string())
            .collect()
    };
    // The groups' nulls stay, named; the units under `Bike` (a still letter, the turning
    // wheel, the bell) are siblings and become one layer parented to `Bike`'s null.
    assert!(!nulls(&plain).is_empty());
    assert_eq!(nulls(&plain), nulls(&packed));
    assert_eq!(unit_names(&plain), unit_names(&packed));
    assert!(layers(&packed).len() < layers(&plain).len());
    let parent_of = |doc: &Value, unit: &str| -> Option<String> {
        let l = layers(doc).iter().find(|l| {
            l["nm"] == unit
                || l["shapes"].as_array().is_some_and(|s| {
                    l["nm"].as_str().unwrap().contains(" … ") && s.iter().any(|g| g["nm"] == unit)
                })
        })?;
        let p = l["parent"].as_f64()?;
        let null = layers(doc).iter().find(|n| n["ind"].as_f64() == Some(p))?;
        Some(null["nm"].as_str()?.to_string())
    };
    for unit in unit_names(&plain) {
        assert_eq!(
            parent_of(&plain, &unit),
            parent_of(&packed, &unit),
            "{unit}"
        );
    }
    let frames = [0.0, 10.0, 20.0, 29.0];
    plays_like_our_frames("pack-hierarchy", &d, &frames, 200);
}

#[test]
fn a_packed_after_effects_file_draws_what_each_player_drew_of_it() {
    // Bodymovin exports whose plain layers (static, position on anchor) sit side by side.
    let corpus = root().join("tests/conformance/lottie-corpus");
    for name in [
        "rlottie-python__27746-joypixels-partying-face-emoji-animation",
        "rlottie-python__party_penguin",
    ] {
        let d = dir(name);
        let source = corpus.join(format!("{name}.json"));
        std::fs::copy(&source, d.join("source.json")).unwrap();
        gmotion(
            &d,
            &[
                "convert",
                "source.json",
                "-o",
                "packed.json",
                "--pack",
                "-q",
            ],
        );
        let (plain, packed) = (read_json(&source), read_json(&d.join("packed.json")));
        // Counted over the root and the precompositions (where these files' plain layers are).
        let all = |doc: &Value| {
            layers(doc).len()
                + doc["assets"].as_array().map_or(0, |a| {
                    a.iter()
                        .filter_map(|x| x["layers"].as_array())
                        .map(Vec::len)
                        .sum()
                })
        };
        assert!(all(&packed) < all(&plain), "{name}: nothing packed");
        let op = plain["op"].as_f64().unwrap() - plain["ip"].as_f64().unwrap();
        let frames: Vec<f64> = spread(op, 6)
            .into_iter()
            .map(|f| f + plain["ip"].as_f64().unwrap())
            .collect();
        let width = 256;
        let before = play(
            &format!("pack-{name}-source"),
            &std::fs::read_to_string(&source).unwrap(),
            &frames,
            width,
            &Player::ALL,
        );
        let after = play(
            &format!("pack-{name}-packed"),
            &std::fs::read_to_string(d.join("packed.json")).unwrap(),
            &frames,
            width,
            &Player::ALL,
        );
        let mut judge = Judge::new(0.001);
        for f in &frames {
            for p in Player::ALL {
                judge.close(
                    &format!("{name}: {p:?} frame {f}"),
                    &load(&frame_path(&before, p, *f)),
                    &load(&frame_path(&after, p, *f)),
                );
            }
        }
        judge.assert_all_close(&after);
    }
}
