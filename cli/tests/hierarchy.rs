//! Structure in, structure out, for SVG scenes: an Illustrator file's names and groups come
//! out of the Lottie export as layers named after the units, parented to null layers named
//! after the groups, and out of the SMIL export as the same `<g id>`s; both play as gmotion
//! draws the animation, and the Lottie read back by gmotion gives the SVG's tags.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use gmotion::motion::Animation;
use gmotion::tagging::TagFrom;
use gmotion_export_lottie::{LottieOptions, to_lottie};
use gmotion_export_raster::{compare, render};
use gmotion_export_svg::frame::frame_svg;
use gmotion_export_svg::smil::{SmilOptions, to_smil};
use gmotion_import_svg::ImportOptions;
use serde_json::{Value, json};

use crate::support::players::{Player, assert_plays_like_model, chromium, frames_to_check};
use crate::support::{root, run_grammar};

/// An Illustrator export with internal CSS: the `<svg>` is the layer `Layer_1`, sublayers
/// and groups are `<g id>`s, every shape is styled by a generated class. The groups carry
/// what a null could not: a rotation under a non-uniform scale (a skew, which rlottie
/// cannot draw as one) and an opacity (which a null does not pass on).
const ART: &str = r##"<?xml version="1.0" encoding="utf-8"?>
<!-- Generator: Adobe Illustrator 27.0.0, SVG Export Plug-In . SVG Version: 6.00 Build 0)  -->
<svg version="1.1" id="Layer_1" xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" x="0px" y="0px"
	 viewBox="0 0 200 120" style="enable-background:new 0 0 200 120;" xml:space="preserve">
<style type="text/css">
	.st0{fill:#E94E1B;}
	.st1{fill:#1D71B8;}
	.st2{fill:#FFFFFF;}
	.st3{fill:#3AAA35;}
</style>
<g id="Ground">
	<rect y="100" class="st3" width="200" height="20"/>
</g>
<g id="Bike" transform="translate(0 6) scale(1 0.9)">
	<g id="letter_G" opacity="0.8">
		<path class="st0" d="M20,20h40v20H40v40h20V60h10v30H20V20z"/>
	</g>
	<g id="Wheel" transform="rotate(20 140 60)">
		<circle class="st1" cx="140" cy="60" r="30"/>
		<rect x="136" y="32" class="st2" width="8" height="56"/>
	</g>
</g>
</svg>
"##;

/// The wheel turns about its own centre while the letter slides; the ground stays.
const GRAMMAR: &str = "duration 2s\nloop false\n\
animate(affine, local, 0, rotate(120)) : [all, Wheel] -> [spun]\n\
animate(affine, world, 0, translate(30, -10)) : [all, letter_G] -> [slid]\n";

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

fn dir(name: &str) -> PathBuf {
    crate::support::case_dir("hierarchy", name)
}

/// The animation of [`ART`] by [`GRAMMAR`], the tags taken from the layer ids (what
/// `--tag-from layer` does), so that the units are the designer's `letter_G` and `Wheel`.
fn animation() -> Animation {
    let opts = ImportOptions {
        tag_from: TagFrom::Layer,
        ..ImportOptions::default()
    };
    let scene = gmotion_import_svg::parse(ART, "art.svg", &opts)
        .unwrap()
        .scene;
    run_grammar(scene, GRAMMAR)
}

/// Each layer of `layers` as its path of names from the root (`Layer_1/Bike/Wheel 2`) and
/// its type, sorted.
fn layer_tree(layers: &[Value]) -> Vec<(String, u64)> {
    let by_ind: HashMap<u64, &Value> = layers
        .iter()
        .map(|l| (l["ind"].as_u64().unwrap(), l))
        .collect();
    let mut out: Vec<(String, u64)> = layers
        .iter()
        .map(|l| {
            let mut names = vec![l["nm"].as_str().unwrap()];
            let mut at = l;
            while let Some(p) = at["parent"].as_u64() {
                at = by_ind[&p];
                names.push(at["nm"].as_str().unwrap());
                assert!(names.len() <= layers.len(), "a parenting cycle");
            }
            names.reverse();
            (names.join("/"), l["ty"].as_u64().unwrap())
        })
        .collect();
    out.sort();
    out
}

/// The tags `check --shapes --json` lists for `file`, in the scene's order: the units'
/// (`rig` false) or the rigs' (true).
fn tags_of(d: &Path, file: &str, extra: &[&str], rig: bool) -> Vec<String> {
    let out = bin()
        .current_dir(d)
        .args(["check", "--shapes", "--json", file])
        .args(extra)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    json.as_array()
        .unwrap()
        .iter()
        .filter(|u| u["rig"].as_bool() == Some(rig))
        .map(|u| u["tag"].as_str().unwrap().to_string())
        .collect()
}

/// The units' tags [`tags_of`] lists.
fn tags(d: &Path, file: &str, extra: &[&str]) -> Vec<String> {
    tags_of(d, file, extra, false)
}

/// Validates `file` against the official Lottie schema (`tests/conformance/install.sh`
/// installs it).
fn assert_schema_valid(file: &Path) {
    let out = Command::new("python3")
        .arg(root().join("tests/conformance/schema_check.py"))
        .arg(file)
        .output()
        .expect("python3 runs (tests/conformance/install.sh)");
    assert!(
        out.status.success(),
        "{} does not validate:\n{}{}",
        file.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn an_illustrator_files_groups_come_out_as_named_lottie_layers_and_nulls() {
    let anim = animation();
    let (json, _) = to_lottie(&anim, &LottieOptions::default()).unwrap();
    let doc: Value = serde_json::from_str(&json).unwrap();
    let (null, shape) = (3, 4);
    let expected: Vec<(String, u64)> = [
        ("Layer_1", null),
        ("Layer_1/Bike", null),
        // A group whose only layer is named after it gets no null of its own.
        ("Layer_1/Bike/Wheel", null),
        ("Layer_1/Bike/Wheel/Wheel 1", shape),
        ("Layer_1/Bike/Wheel/Wheel 2", shape),
        ("Layer_1/Bike/letter_G", shape),
        // Still art stays a shape layer, in its place among the group's layers.
        ("Layer_1/Ground", shape),
    ]
    .into_iter()
    .map(|(p, ty)| (p.to_string(), ty))
    .collect();
    let layers = doc["layers"].as_array().unwrap();
    assert_eq!(layer_tree(layers), expected);
    // The nulls only name and parent: the group transforms stay in the layers' content.
    for null in layers.iter().filter(|l| l["ty"] == 3) {
        let ks = &null["ks"];
        assert_eq!(
            [&ks["p"]["k"], &ks["a"]["k"], &ks["s"]["k"], &ks["r"]["k"]],
            [
                &json!([0, 0]),
                &json!([0, 0]),
                &json!([100, 100]),
                &json!(0)
            ],
            "{}",
            null["nm"]
        );
    }

    let d = dir("lottie");
    std::fs::write(d.join("art.svg"), ART).unwrap();
    std::fs::write(d.join("out.json"), &json).unwrap();
    assert_schema_valid(&d.join("out.json"));
    // Read back by gmotion, the layers give the tags the SVG gave.
    let svg_tags = tags(&d, "art.svg", &["--tag-from", "layer"]);
    assert_eq!(svg_tags, ["Ground", "letter_G", "Wheel", "Wheel"]);
    assert_eq!(tags(&d, "out.json", &[]), svg_tags);
    // The groups come back as the rigs that move them (top layer last).
    assert_eq!(
        tags_of(&d, "out.json", &[], true),
        ["Wheel", "Bike", "Layer"]
    );

    let width = (2.0 * anim.scene.width).round() as u32;
    assert_plays_like_model(
        "hierarchy",
        &anim,
        &json,
        &frames_to_check(&anim),
        width,
        &Player::ALL,
    );
}

#[test]
fn an_illustrator_files_group_ids_stay_in_smil() {
    let anim = animation();
    let (svg, _) = to_smil(&anim, &SmilOptions::default()).unwrap();
    let doc = usvg::roxmltree::Document::parse(&svg).unwrap();
    // Every id once, and the designer's groups nested as they were.
    let mut seen = HashMap::new();
    for n in doc.descendants() {
        if let Some(id) = n.attribute("id") {
            *seen.entry(id).or_insert(0) += 1;
        }
    }
    assert!(seen.values().all(|&k| k == 1), "{seen:?}");
    let group = |id: &str| {
        doc.descendants()
            .find(|n| n.has_tag_name("g") && n.attribute("id") == Some(id))
            .unwrap_or_else(|| panic!("no <g id=\"{id}\"> in\n{svg}"))
    };
    let named_ancestors = |id: &str| -> Vec<&str> {
        let mut names: Vec<&str> = group(id)
            .ancestors()
            .skip(1)
            .filter(|n| n.has_tag_name("g"))
            .filter_map(|n| n.attribute("id"))
            .collect();
        names.reverse();
        names
    };
    assert_eq!(named_ancestors("Layer_1"), Vec::<&str>::new());
    assert_eq!(named_ancestors("Bike"), ["Layer_1"]);
    assert_eq!(named_ancestors("Ground"), ["Layer_1"]);
    assert_eq!(named_ancestors("letter_G"), ["Layer_1", "Bike"]);
    assert_eq!(named_ancestors("Wheel"), ["Layer_1", "Bike"]);

    let d = dir("smil");
    let file = d.join("out.svg");
    std::fs::write(&file, &svg).unwrap();
    let width = (2.0 * anim.scene.width).round() as u32;
    let times = [0.0, 0.5, 1.0, 1.5, 1.95];
    let played = chromium(&file, width, &times);
    for (&t, got) in times.iter().zip(&played) {
        let model = render(&frame_svg(&anim, t), width).unwrap();
        let off = compare(&model, got, 32);
        assert!(
            off < 0.005,
            "t = {t}: {:.2}% of pixels off the model ({})",
            off * 100.0,
            d.display()
        );
    }
}
