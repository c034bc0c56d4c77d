//! Slots (`slots fill stroke opacity`): each tag's colours given a Lottie slot `TAG.fill`,
//! `TAG.stroke`, `TAG.opacity`. Setting a slot in the players recolours exactly that tag's
//! shapes, at every frame, its animated colour included; a tag whose shapes differ gets no
//! slot; the directive's words are checked where they are written.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

fn out_dir(name: &str) -> PathBuf {
    crate::support::case_dir("slots", name)
}

/// Two `leaf` rectangles (x 10–60 and 70–100, y 20–70: 4 000 pixels) whose fill a rule
/// turns from green to yellow and back, and a `stem` circle with a stroke that turns.
fn scene(dir: &Path, header: &str, second_leaf: &str) -> PathBuf {
    std::fs::write(
        dir.join("s.svg"),
        format!(
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100" viewBox="0 0 200 100">
<rect data-tag="leaf" x="10" y="20" width="50" height="50" fill="#30a040"/>
<rect data-tag="leaf" x="70" y="20" width="30" height="50" fill="{second_leaf}"/>
<circle data-tag="stem" cx="150" cy="45" r="25" fill="#2040e0" stroke="#101010" stroke-width="3"/>
</svg>"##
        ),
    )
    .unwrap();
    grammar(&dir.join("s.gm"), "s.svg", header)
}

fn animate(gm: &Path, out: &Path) -> String {
    let o = bin()
        .arg("animate")
        .arg(gm)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(o.status.success(), "{stderr}");
    stderr
}

fn doc(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// Every property carrying `sid` in `v`, with its id.
fn slotted(v: &Value, out: &mut Vec<(String, Value)>) {
    match v {
        Value::Object(o) => {
            if let Some(Value::String(id)) = o.get("sid") {
                let mut p = v.clone();
                p.as_object_mut().unwrap().remove("sid");
                out.push((id.clone(), p));
            }
            o.values().for_each(|x| slotted(x, out));
        }
        Value::Array(a) => a.iter().for_each(|x| slotted(x, out)),
        _ => {}
    }
}

#[test]
fn each_tag_gets_one_slot_per_kind_holding_its_property() {
    let dir = out_dir("kinds");
    let gm = scene(&dir, "slots fill stroke opacity", "#30a040");
    let json = dir.join("s.json");
    animate(&gm, &json);
    let d = doc(&json);
    let text = std::fs::read_to_string(&json).unwrap();
    assert!(!text.contains("gmotion_sid"), "a mark was left in");
    let slots = d["slots"].as_object().expect("slots");
    let mut ids: Vec<&str> = slots.keys().map(String::as_str).collect();
    ids.sort();
    assert_eq!(
        ids,
        [
            "leaf.fill",
            "leaf.opacity",
            "stem.fill",
            "stem.opacity",
            "stem.stroke"
        ]
    );
    // The animated fill and opacity are slotted whole: their keyframes are the slots'.
    assert_eq!(slots["leaf.fill"]["p"]["a"], 1);
    assert_eq!(slots["stem.opacity"]["p"]["a"], 1);
    assert_eq!(
        slots["leaf.opacity"]["p"],
        serde_json::json!({"a": 0, "k": 100})
    );
    let mut found = Vec::new();
    slotted(&d["layers"], &mut found);
    // Both leaves carry the slot, each property equal to the slot's value.
    assert_eq!(found.iter().filter(|(id, _)| id == "leaf.fill").count(), 2);
    for (id, p) in &found {
        assert_eq!(&slots[id]["p"], p, "{id}");
    }
}

#[test]
fn a_tag_whose_shapes_differ_gets_no_slot_and_a_warning() {
    let dir = out_dir("differ");
    let gm = scene(&dir, "slots fill", "#3050a0");
    let json = dir.join("s.json");
    let stderr = animate(&gm, &json);
    assert!(
        stderr.contains("slot `leaf.fill` is not written"),
        "{stderr}"
    );
    let d = doc(&json);
    assert!(d["slots"].get("leaf.fill").is_none());
    assert!(d["slots"].get("stem.fill").is_some());
    assert!(
        !std::fs::read_to_string(&json)
            .unwrap()
            .contains("\"sid\":\"leaf.fill\"")
    );
}

#[test]
fn an_unknown_or_repeated_kind_is_an_error_at_it() {
    let dir = out_dir("bad");
    for (header, col, says) in [
        ("slots fill colour", 12, "unknown `slots` value"),
        ("slots fill fill", 12, "`fill` is given twice"),
    ] {
        let gm = scene(&dir, header, "#30a040");
        let o = bin()
            .arg("animate")
            .arg(&gm)
            .arg("-o")
            .arg(dir.join("x.json"))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success());
        assert!(stderr.contains(says), "{stderr}");
        assert!(stderr.contains(&format!(":4:{col}")), "{stderr}");
    }
}

/// The theme file becomes `t/ID.json` in the package, listed in the manifest: a colour
/// string a Color rule, an opacity a Scalar one in Lottie's percent; a slot the animation
/// lacks is a warning naming it, and left out.
#[test]
fn a_theme_becomes_the_packages_rules() {
    let dir = out_dir("theme");
    let gm = scene(&dir, "slots fill stroke opacity", "#30a040");
    let theme = dir.join("Dark Mode.json");
    std::fs::write(
        &theme,
        r##"{"leaf.fill": "#ff0000", "stem.opacity": 0.25, "twig.fill": "#000"}"##,
    )
    .unwrap();
    let lottie = dir.join("s.lottie");
    let o = bin()
        .arg("animate")
        .arg(&gm)
        .arg("-o")
        .arg(&lottie)
        .arg("--theme")
        .arg(&theme)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(stderr.contains("no slot `twig.fill`"), "{stderr}");
    let bytes = std::fs::read(&lottie).unwrap();
    let package = gmotion_pipeline::dotlottie::Package::read(&bytes, "s.lottie", 1 << 30).unwrap();
    assert_eq!(package.themes.len(), 1);
    let t: Value = serde_json::from_str(&package.themes[0].text).unwrap();
    assert_eq!(
        t,
        serde_json::json!({"rules": [
            {"id": "leaf.fill", "type": "Color", "value": [1.0, 0.0, 0.0]},
            {"id": "stem.opacity", "type": "Scalar", "value": 25.0},
        ]})
    );
}

/// `variations --theme` puts the theme in the set's package, once, for every seed's
/// animation (each has the grammar's slots); without a `.lottie` output it is an error.
#[test]
fn a_variations_set_carries_the_theme() {
    let dir = out_dir("variations-theme");
    let gm = scene(&dir, "slots fill stroke opacity", "#30a040");
    let theme = dir.join("autumn.json");
    std::fs::write(&theme, r##"{"leaf.fill": "#c0392b"}"##).unwrap();
    let set = dir.join("set.lottie");
    let run = |out: &Path| {
        bin()
            .arg("variations")
            .arg(&gm)
            .args(["--count", "3", "-o"])
            .arg(out)
            .arg("--theme")
            .arg(&theme)
            .output()
            .unwrap()
    };
    let o = run(&set);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&set).unwrap();
    let package =
        gmotion_pipeline::dotlottie::Package::read(&bytes, "set.lottie", 1 << 30).unwrap();
    assert_eq!(package.animations.len(), 3);
    for a in &package.animations {
        let doc: Value = serde_json::from_str(&a.text).unwrap();
        assert!(
            doc["slots"]["leaf.fill"].is_object(),
            "{} has the slot",
            a.id
        );
    }
    assert_eq!(package.themes.len(), 1);
    assert_eq!(package.themes[0].id, "autumn");
    let t: Value = serde_json::from_str(&package.themes[0].text).unwrap();
    let red = [
        0xc0 as f64 / 255.0,
        0x39 as f64 / 255.0,
        0x2b as f64 / 255.0,
    ];
    let got: Vec<f64> = t["rules"][0]["value"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(t["rules"][0]["id"], "leaf.fill");
    assert!(
        got.iter().zip(red).all(|(a, b)| (a - b).abs() < 1e-4),
        "{got:?}"
    );
    let sheet = dir.join("sheet.png");
    let o = run(&sheet);
    assert!(!o.status.success() && !sheet.exists());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("--theme is written into a .lottie output"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A theme that is no JSON is an error at its line and column, one with a value of the
/// wrong kind an error naming the slot; neither leaves an output behind.
#[test]
fn a_bad_theme_is_an_error_and_writes_nothing() {
    let dir = out_dir("bad-theme");
    let gm = scene(&dir, "slots fill", "#30a040");
    for (text, says) in [
        (
            "{\"leaf.fill\": \"#ff0000\",\n  \"x\": }",
            "t.json:2:8: error",
        ),
        (
            "{\"leaf.fill\": 3}",
            "slot `leaf.fill`: a colour slot takes",
        ),
        ("{\"leaf.opacity\": 2}", "opacity 2 is not between 0 and 1"),
    ] {
        let theme = dir.join("t.json");
        std::fs::write(&theme, text).unwrap();
        let lottie = dir.join("s.lottie");
        let o = bin()
            .arg("animate")
            .arg(&gm)
            .arg("-o")
            .arg(&lottie)
            .arg("--theme")
            .arg(&theme)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success());
        assert!(stderr.contains(says), "{stderr}");
        assert!(!lottie.exists());
    }
}

/// Without the directive, no slot and no mark: the document is as before.
#[test]
fn no_directive_no_slots() {
    let dir = out_dir("none");
    let gm = scene(&dir, "", "#30a040");
    let json = dir.join("s.json");
    animate(&gm, &json);
    let text = std::fs::read_to_string(&json).unwrap();
    assert!(!text.contains("sid") && !text.contains("\"slots\""));
}

/// Runs `lottie_slots.mjs` on `json` setting `leaf.fill` to magenta (`extra`: a package
/// and its theme for dotlottie-web) and checks what both players changed: at every frame
/// the leaves' 4 000 pixels, all in their rectangles and all magenta, nothing else.
#[cfg(feature = "players")]
fn assert_only_the_leaves_change(json: &Path, extra: &[&std::ffi::OsStr]) {
    assert_only_changes(
        json,
        ("leaf.fill", "1,0,1"),
        3900..=4100,
        [9, 19, 100, 70],
        extra,
        &[],
    );
}

/// Runs `lottie_slots.mjs` on `json` setting `slot` to `value` and checks, in lottie-web
/// and dotlottie-web, that at every frame the pixels it changed number `count` and lie in
/// `within` (x0, y0, x1, y1), nothing else; for a colour, that they took the colour.
/// `stale_first`: players known to draw the frame shown when the slot was set (frame 0)
/// without it, which must then change nothing there.
#[cfg(feature = "players")]
fn assert_only_changes(
    json: &Path,
    (slot, value): (&str, &str),
    count: std::ops::RangeInclusive<u64>,
    within: [u64; 4],
    extra: &[&std::ffi::OsStr],
    stale_first: &[&str],
) {
    let out = Command::new("node")
        .arg(crate::support::root().join("tests/conformance/lottie_slots.mjs"))
        .arg(json)
        .args([slot, value])
        .args(extra)
        .output()
        .expect("run node");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let result: Value = serde_json::from_slice(&out.stdout).unwrap();
    for player in ["lottie-web", "dotlottie-web"] {
        let frames = result[player].as_array().expect(player);
        assert_eq!(frames.len(), 60, "{player}");
        for (f, r) in frames.iter().enumerate() {
            let changed = r["changed"].as_u64().unwrap();
            if f == 0 && stale_first.contains(&player) {
                assert_eq!(
                    changed, 0,
                    "{player} frame 0 is no longer stale: drop the exception"
                );
                continue;
            }
            assert!(
                count.contains(&changed),
                "{player} frame {f}: {changed} pixels changed"
            );
            let b: Vec<u64> = r["box"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_u64().unwrap())
                .collect();
            assert!(
                b[0] >= within[0] && b[1] >= within[1] && b[2] <= within[2] && b[3] <= within[3],
                "{player} frame {f}: changed pixels in {b:?}, outside {within:?}"
            );
            assert!(r["off"].as_u64().unwrap() <= 100, "{player} frame {f}: {r}");
        }
    }
}

/// An opacity slot: `stem.opacity` set to 0 in lottie-web and (`setScalarSlot`) in
/// dotlottie-web hides exactly the stem at every frame, through its fading animation (the
/// circle, 26.5 px in radius with its stroke: about 2 200 pixels), and nothing of the leaves.
#[cfg(feature = "players")]
#[test]
fn setting_an_opacity_slot_fades_exactly_that_tag_at_every_frame() {
    let dir = out_dir("opacity-players");
    let gm = scene(&dir, "slots fill stroke opacity", "#30a040");
    let json = dir.join("s.json");
    animate(&gm, &json);
    assert_only_changes(
        &json,
        ("stem.opacity", "0"),
        2100..=2400,
        [121, 16, 179, 74],
        &[],
        &[],
    );
}

/// lottie-web (the document's slot replaced before loading) and dotlottie-web
/// (`setColorSlot`) recolour exactly the two leaves, through the fill's animation; the
/// stem, which has slots of its own, is untouched. The file validates against the
/// official schema, `sid` and `slots` included.
#[cfg(feature = "players")]
#[test]
fn setting_a_slot_recolours_exactly_that_tag_at_every_frame() {
    let dir = out_dir("players");
    let gm = scene(&dir, "slots fill stroke opacity", "#30a040");
    let json = dir.join("s.json");
    animate(&gm, &json);
    let out = Command::new("python3")
        .arg(crate::support::root().join("tests/conformance/schema_check.py"))
        .arg(&json)
        .output()
        .expect("python3 runs (tests/conformance/install.sh)");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert_only_the_leaves_change(&json, &[]);
}

/// `--theme` writes a dotLottie theme into the `.lottie`: dotlottie-web's `setTheme`
/// recolours exactly the leaves, as setting the slot does.
#[cfg(feature = "players")]
#[test]
fn a_theme_in_the_package_recolours_exactly_that_tag() {
    let dir = out_dir("theme-players");
    let gm = scene(&dir, "slots fill stroke opacity", "#30a040");
    let theme = dir.join("magenta.json");
    std::fs::write(&theme, r##"{"leaf.fill": "#ff00ff"}"##).unwrap();
    let (json, lottie) = (dir.join("s.json"), dir.join("s.lottie"));
    let o = bin()
        .arg("animate")
        .arg(&gm)
        .arg("-o")
        .arg(&json)
        .arg("-o")
        .arg(&lottie)
        .arg("--theme")
        .arg(&theme)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_only_the_leaves_change(&json, &[lottie.as_os_str(), "magenta".as_ref()]);
}

/// rlottie and ThorVG draw a slotted file exactly as the same grammar without `slots`
/// (the slots hold the values in place), frame for frame.
#[cfg(feature = "players")]
#[test]
fn players_draw_a_slotted_file_as_the_plain_one() {
    let dir = out_dir("same");
    let (slotted, plain) = (dir.join("slotted.json"), dir.join("plain.json"));
    animate(
        &scene(&dir, "slots fill stroke opacity", "#30a040"),
        &slotted,
    );
    animate(&scene(&dir, "", "#30a040"), &plain);
    let frames = [0, 15, 40];
    let png = |name: &str, player: &str, f: u32| dir.join(format!("{name}-{player}-{f}.png"));
    for player in ["rlottie", "thorvg"] {
        let jobs: Vec<Value> = [("slotted", &slotted), ("plain", &plain)]
            .iter()
            .map(|(name, json)| {
                serde_json::json!({"json": json, "width": 200, "frames": frames,
                    "out": frames.map(|f| png(name, player, f))})
            })
            .collect();
        let list = dir.join(format!("jobs-{player}.json"));
        std::fs::write(&list, Value::Array(jobs).to_string()).unwrap();
        let out = Command::new("python3")
            .arg(crate::support::root().join(format!("tests/conformance/{player}_render.py")))
            .arg(&list)
            .output()
            .expect("python3 runs (tests/conformance/install.sh)");
        assert!(
            out.status.success(),
            "{player}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        for f in frames {
            let (a, b) = (
                std::fs::read(png("slotted", player, f)).unwrap(),
                std::fs::read(png("plain", player, f)).unwrap(),
            );
            let decode = |bytes: &[u8]| {
                let d = png::Decoder::new(std::io::Cursor::new(bytes));
                let mut r = d.read_info().unwrap();
                let mut buf = vec![0; r.output_buffer_size().unwrap()];
                r.next_frame(&mut buf).unwrap();
                buf
            };
            assert_eq!(decode(&a), decode(&b), "{player} frame {f}");
        }
    }
}

/// The scene of [`scene`] as an After Effects-style Lottie: one shape layer per shape,
/// named by its tag (two `leaf` layers and a `stem`), with the same grammar on it.
fn lottie_scene(dir: &Path, header: &str) -> PathBuf {
    let ks = serde_json::json!({"a": {"a": 0, "k": [0, 0]}, "p": {"a": 0, "k": [0, 0]},
        "s": {"a": 0, "k": [100, 100]}, "r": {"a": 0, "k": 0}, "o": {"a": 0, "k": 100}});
    let tr = serde_json::json!({"ty": "tr", "a": {"a": 0, "k": [0, 0]}, "p": {"a": 0, "k": [0, 0]},
        "s": {"a": 0, "k": [100, 100]}, "r": {"a": 0, "k": 0}, "o": {"a": 0, "k": 100}});
    let green = serde_json::json!({"ty": "fl", "c": {"a": 0, "k": [0.188, 0.627, 0.251, 1]}, "o": {"a": 0, "k": 100}, "r": 1});
    let layer = |ind: u32, nm: &str, items: Value| {
        serde_json::json!({"ddd": 0, "ind": ind, "ty": 4, "nm": nm, "ks": ks, "ip": 0, "op": 60, "st": 0,
            "shapes": [{"ty": "gr", "nm": nm, "it": items}]})
    };
    let rect = |x: f64, w: f64| serde_json::json!([{"ty": "rc", "d": 1, "p": {"a": 0, "k": [x + w / 2.0, 45]}, "s": {"a": 0, "k": [w, 50]}, "r": {"a": 0, "k": 0}}, green, tr]);
    let stem = serde_json::json!([
        {"ty": "el", "d": 1, "p": {"a": 0, "k": [150, 45]}, "s": {"a": 0, "k": [50, 50]}},
        {"ty": "st", "c": {"a": 0, "k": [0.0627, 0.0627, 0.0627, 1]}, "o": {"a": 0, "k": 100}, "w": {"a": 0, "k": 3}, "lc": 2, "lj": 2},
        {"ty": "fl", "c": {"a": 0, "k": [0.125, 0.251, 0.878, 1]}, "o": {"a": 0, "k": 100}, "r": 1},
        tr]);
    let doc = serde_json::json!({"v": "5.7.4", "fr": 30, "ip": 0, "op": 60, "w": 200, "h": 100,
        "nm": "slots", "ddd": 0, "assets": [],
        "layers": [layer(1, "stem", stem), layer(2, "leaf", rect(70.0, 30.0)), layer(3, "leaf", rect(10.0, 50.0))]});
    std::fs::write(dir.join("scene.json"), doc.to_string()).unwrap();
    grammar(&dir.join("l.gm"), "scene.json", header)
}

/// Writes the grammar both scenes run at `gm`, on `scene`, `header` after its directives:
/// the leaves' fill turns yellow and back, the stem turns and fades.
fn grammar(gm: &Path, scene: &str, header: &str) -> PathBuf {
    std::fs::write(
        gm,
        format!(
            "scene {scene}\nduration 2s\nfps 30\n{header}\n\
             timesplit(0.5, 0.5) : [all, (leaf, stem)] -> [a, inv_a]\n\
             animate(fill, local, 0, #f0c040) : [a, leaf] -> [ripen]\n\
             animate(affine, local, 0, rotate(30)) : [a, stem] -> [turn]\n\
             animate(opacity, local, 0, 0.5) : [turn, stem] -> [fade]\n"
        ),
    )
    .unwrap();
    gm.to_path_buf()
}

/// On a Lottie scene (After Effects' layers, tagged by their names) the slots go on the
/// source's own paints: every fill and stroke of a tag's layers and their opacity.
#[test]
fn a_lottie_scene_gets_slots_on_its_layers_paints() {
    let dir = out_dir("lottie-scene");
    let gm = lottie_scene(&dir, "slots fill stroke opacity");
    let json = dir.join("s.json");
    let stderr = animate(&gm, &json);
    assert!(!stderr.contains("warning"), "{stderr}");
    let d = doc(&json);
    let mut ids: Vec<&str> = d["slots"]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    ids.sort_unstable();
    assert_eq!(
        ids,
        [
            "leaf.fill",
            "leaf.opacity",
            "stem.fill",
            "stem.opacity",
            "stem.stroke"
        ]
    );
    let mut found = Vec::new();
    slotted(&d, &mut found);
    // Both leaves' fills carry the one slot, holding the colour's animation.
    let leaves: Vec<&Value> = found
        .iter()
        .filter(|(id, _)| id == "leaf.fill")
        .map(|(_, p)| p)
        .collect();
    assert_eq!(leaves.len(), 2);
    assert_eq!(leaves[0]["a"], 1, "the fill's keyframes: {}", leaves[0]);
    assert_eq!(leaves[0], &d["slots"]["leaf.fill"]["p"]);
    // Different fills under one tag: no slot, said.
    let two = std::fs::read_to_string(dir.join("scene.json"))
        .unwrap()
        .replacen("0.188", "0.5", 1);
    std::fs::write(dir.join("scene.json"), two).unwrap();
    let stderr = animate(&gm, &json);
    assert!(
        stderr.contains("slot `leaf.fill` is not written"),
        "{stderr}"
    );
    assert!(doc(&json)["slots"].get("leaf.fill").is_none());
}

/// The players recolour exactly the leaves of the Lottie scene, and fade exactly its stem.
#[cfg(feature = "players")]
#[test]
fn a_lottie_scenes_slots_recolour_exactly_that_tag() {
    let dir = out_dir("lottie-scene-players");
    let gm = lottie_scene(&dir, "slots fill stroke opacity");
    let json = dir.join("s.json");
    animate(&gm, &json);
    assert_only_the_leaves_change(&json, &[]);
    // The stem's opacity slot is its layer's: dotlottie-web 0.80 (ThorVG) applies a slot
    // on a layer's transform only from the next frame it draws, so the frame shown when
    // it was set stays as it was (a slot on a group's transform, as an SVG scene's, is
    // drawn at once).
    assert_only_changes(
        &json,
        ("stem.opacity", "0"),
        2100..=2400,
        [121, 16, 179, 74],
        &[],
        &["dotlottie-web"],
    );
}
