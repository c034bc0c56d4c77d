//! Files shaped like real Illustrator, Figma and Inkscape exports, through the real binary:
//! element ids as tags (a rule on one id moves that shape and nothing else), counters that
//! tell copies apart without merging layers, set differences on ids, tag maps with CSS-like
//! selectors (`--tags` and the grammar's `tags`), and the unit depth. The corpus of
//! tests/corpus/designer (Illustrator, CorelDRAW, Inkscape, Figma, Sketch, and real exports
//! from published packages in its `real/` folder) is checked against the tags its
//! expected-tags.txt writes down.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gmotion-designer-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs and returns (success, stdout, stderr).
fn run(cmd: &mut Command) -> (bool, String, String) {
    let out = cmd.output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// An Illustrator 27 export: generator comment, style classes, two layers, ids on some
/// shapes, copies of `eye` made unique with Illustrator's `_1_` suffix.
const ILLUSTRATOR: &str = r##"<?xml version="1.0" encoding="utf-8"?>
<!-- Generator: Adobe Illustrator 27.0.0, SVG Export Plug-In . SVG Version: 6.00 Build 0)  -->
<svg version="1.1" id="Layer_1" xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" x="0px" y="0px"
	 viewBox="0 0 200 120" style="enable-background:new 0 0 200 120;" xml:space="preserve">
<style type="text/css">
	.st0{fill:#E30613;}
	.st1{fill:#1D71B8;}
</style>
<g id="Layer_1_1_">
	<rect x="10" y="10" class="st0" width="30" height="30"/>
	<rect id="tile_1" x="50" y="10" class="st1" width="30" height="30"/>
</g>
<g id="Layer_2">
	<circle id="eye_1_" class="st0" cx="120" cy="25" r="10"/>
	<circle id="eye" class="st0" cx="160" cy="25" r="10"/>
</g>
</svg>
"##;

/// A Figma export: a frame whose children are icon groups of several paths, Figma's
/// `Vector` ids, and a frame id with a space.
const FIGMA: &str = r##"<svg width="200" height="120" viewBox="0 0 200 120" fill="none" xmlns="http://www.w3.org/2000/svg">
<g id="Frame 1">
<rect width="200" height="120" fill="white"/>
<g id="icon-home">
<path id="Vector" d="M20 60L40 40L60 60V90H20V60Z" fill="#333333"/>
<path id="Vector_2" d="M35 75H45V90H35V75Z" fill="#FFCC00"/>
</g>
<g id="icon-user">
<circle id="Ellipse 1" cx="140" cy="55" r="12" fill="#333333"/>
<path id="Vector_3" d="M120 90C120 78 160 78 160 90H120Z" fill="#333333"/>
</g>
</g>
</svg>
"##;

/// Writes `files` into a fresh folder and returns it.
fn files(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let d = dir(name);
    for (file, text) in files {
        std::fs::write(d.join(file), text).unwrap();
    }
    d
}

/// The units `check --shapes --json` lists: (tag, aliases) in scene order.
fn units(d: &Path, scene: &str, extra: &[&str]) -> Vec<(String, Vec<String>)> {
    let (ok, out, err) = run(bin()
        .current_dir(d)
        .args(["check", "--shapes", "--json", scene])
        .args(extra));
    assert!(ok, "{err}");
    let json: serde_json::Value = serde_json::from_str(&out).unwrap();
    json.as_array()
        .unwrap()
        .iter()
        .map(|u| {
            let aliases = u["aliases"].as_array().unwrap();
            (
                u["tag"].as_str().unwrap().to_string(),
                aliases
                    .iter()
                    .map(|a| a.as_str().unwrap().to_string())
                    .collect(),
            )
        })
        .collect()
}

/// The animation rendered by the binary at `time` (RGBA, width 200).
fn frame(d: &Path, scene: &str, grammar: &str, time: f64, extra: &[&str]) -> Vec<u8> {
    let out = d.join(format!("frame-{time}.png"));
    let (ok, _, err) = run(bin()
        .current_dir(d)
        .args(["animate", scene, grammar, "-q", "--width", "200", "--time"])
        .arg(time.to_string())
        .arg("-o")
        .arg(&out)
        .args(extra));
    assert!(ok, "{err}");
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&out).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.width, 200);
    buf.truncate(info.buffer_size());
    buf
}

/// The bounding box `[x0, y0, x1, y1)` of the pixels that differ between two frames.
fn changed(a: &[u8], b: &[u8]) -> Option<[usize; 4]> {
    let mut bbox: Option<[usize; 4]> = None;
    for (i, (pa, pb)) in a.chunks(4).zip(b.chunks(4)).enumerate() {
        if pa.iter().zip(pb).any(|(x, y)| x.abs_diff(*y) > 8) {
            let (x, y) = (i % 200, i / 200);
            let r = bbox.get_or_insert([x, y, x + 1, y + 1]);
            *r = [r[0].min(x), r[1].min(y), r[2].max(x + 1), r[3].max(y + 1)];
        }
    }
    bbox
}

/// Whether box `a` lies within `b` grown by a pixel (anti-aliasing).
fn within(a: [usize; 4], b: [f64; 4]) -> bool {
    a[0] as f64 >= b[0] - 1.0
        && a[1] as f64 >= b[1] - 1.0
        && a[2] as f64 <= b[2] + 1.0
        && a[3] as f64 <= b[3] + 1.0
}

#[test]
fn an_element_id_is_a_tag_and_a_rule_on_it_moves_that_shape_alone() {
    let d = files(
        "id",
        &[
            ("art.svg", ILLUSTRATOR),
            (
                "move.gm",
                "duration 1s\nloop false\nanimate(affine, world, 0, translate(0, 60)) : [all, tile_1] -> [down]\n",
            ),
        ],
    );
    let (a, b) = (
        frame(&d, "art.svg", "move.gm", 0.0, &[]),
        frame(&d, "art.svg", "move.gm", 1.0, &[]),
    );
    // The tile (50..80, 10..40) moved 60 px down; nothing else changed.
    let moved = changed(&a, &b).expect("the tile moved");
    assert!(within(moved, [50.0, 10.0, 80.0, 100.0]), "{moved:?}");
    assert!(moved[3] >= 99 && moved[1] <= 11, "{moved:?}");

    // The same through a Figma id, and a multi-word one as a string.
    let d = files(
        "figma-id",
        &[
            ("art.svg", FIGMA),
            (
                "move.gm",
                "duration 1s\nloop false\nanimate(affine, world, 0, translate(0, 20)) : [all, \"Ellipse 1\"] -> [down]\n",
            ),
        ],
    );
    let moved = changed(
        &frame(&d, "art.svg", "move.gm", 0.0, &[]),
        &frame(&d, "art.svg", "move.gm", 1.0, &[]),
    )
    .expect("the ellipse moved");
    assert!(within(moved, [128.0, 43.0, 152.0, 87.0]), "{moved:?}");
}

#[test]
fn a_layer_left_out_by_id_stays_still_while_the_rest_moves() {
    let d = files(
        "difference",
        &[
            ("art.svg", ILLUSTRATOR),
            (
                "move.gm",
                "duration 1s\nloop false\nanimate(affine, world, 0, translate(0, 60)) : [all, all - Layer_2] -> [down]\n",
            ),
        ],
    );
    let moved = changed(
        &frame(&d, "art.svg", "move.gm", 0.0, &[]),
        &frame(&d, "art.svg", "move.gm", 1.0, &[]),
    )
    .expect("Layer_1 moved");
    // Layer_1's two tiles span x 10..80; Layer_2's eyes (x 110..170) did not change.
    assert!(within(moved, [10.0, 10.0, 80.0, 100.0]), "{moved:?}");
}

#[test]
fn ids_and_their_counters_are_aliases_that_keep_layers_apart() {
    let d = files("aliases", &[("art.svg", ILLUSTRATOR), ("figma.svg", FIGMA)]);
    let ai = units(&d, "art.svg", &[]);
    // Tags from the layers, never from Illustrator's style classes (`st0`, `st1`); ids
    // (and Illustrator's `_1_` copies without their suffix) and enclosing layers as
    // aliases.
    assert_eq!(ai.len(), 4);
    let tags: Vec<&str> = ai.iter().map(|u| u.0.as_str()).collect();
    assert_eq!(tags, ["Layer_1", "Layer_1", "Layer_2", "Layer_2"], "{ai:?}");
    assert!(ai[1].1.contains(&"tile_1".to_string()), "{ai:?}");
    assert!(ai[2].1.contains(&"eye_1_".to_string()) && ai[2].1.contains(&"eye".to_string()));
    assert!(ai[3].1.contains(&"eye".to_string()), "{ai:?}");
    // The layer is the eyes' tag, so it is no alias of theirs.
    assert!(!ai[2].1.contains(&"Layer_2".to_string()), "{ai:?}");
    assert!(!ai[0].1.contains(&"Layer_2".to_string()), "{ai:?}");
    // Layers stay distinct: no shape of Layer_2 answers to a Layer_1 name and vice versa.
    assert!(ai[0].1.iter().all(|a| a.starts_with("Layer_1")), "{ai:?}");

    let figma = units(&d, "figma.svg", &[]);
    let vectors: Vec<_> = figma
        .iter()
        .filter(|u| u.1.contains(&"Vector".to_string()))
        .collect();
    // `Vector_2` and `Vector_3` are Figma's copies of `Vector`: all three answer to it.
    assert_eq!(vectors.len(), 3, "{figma:?}");
    // A rule naming an alias that no shape has is still an error with a suggestion.
    std::fs::write(
        d.join("typo.gm"),
        "animate(affine, world, 0, translate(0, 20)) : [all, tile_2] -> [m]\n",
    )
    .unwrap();
    let (ok, _, err) = run(bin().current_dir(&d).args(["check", "typo.gm", "art.svg"]));
    assert!(!ok);
    assert!(err.contains("tile_1"), "{err}");
}

#[test]
fn a_tag_map_gives_tags_and_makes_units_from_the_command_line_or_the_grammar() {
    // A letter drawn as a stem and a dot must move as one: a map makes each letter group
    // one unit without editing the SVG.
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 120">
<!-- Generator: Adobe Illustrator 27.0.0 -->
<g id="Layer_1">
<g id="letter_i_1_"><rect x="20" y="40" width="10" height="50"/><circle cx="25" cy="25" r="6"/></g>
<g id="letter_j"><rect x="60" y="40" width="10" height="60"/><circle cx="65" cy="25" r="6"/></g>
<rect id="bar" class="st1" x="100" y="90" width="80" height="10" fill="#1D71B8"/>
</g>
</svg>"##;
    let map = "# which groups are letters\n#letter_*      -> letter\n.st1, #nothing -> underline   # Illustrator's style class\n";
    let d = files("map", &[("art.svg", svg), ("map.tags", map)]);
    let without = units(&d, "art.svg", &[]);
    assert_eq!(
        without.len(),
        5,
        "four letter parts and the bar: {without:?}"
    );
    let with = units(&d, "art.svg", &["--tags", "map.tags"]);
    let tags: Vec<&str> = with.iter().map(|u| u.0.as_str()).collect();
    assert_eq!(tags, ["letter", "letter", "underline"]);

    // A rule on the map's tag turns each letter as one piece: the dot turns around the
    // letter's centre, so it moves, which it would not as a unit of its own.
    std::fs::write(
        d.join("turn.gm"),
        "duration 1s\nloop false\ntags map.tags\nanimate(affine, local, 0, rotate(180)) : [all, letter] -> [t]\n",
    )
    .unwrap();
    let moved = changed(
        &frame(&d, "art.svg", "turn.gm", 0.0, &[]),
        &frame(&d, "art.svg", "turn.gm", 1.0, &[]),
    )
    .expect("the letters turned");
    // The i's dot (y 19..31) swings below the stem: changed pixels reach y > 90.
    assert!(moved[1] <= 20 && moved[3] >= 95, "{moved:?}");
    assert!(moved[2] <= 82, "the underline stayed: {moved:?}");

    // `unit` makes a group one unit keeping its tag.
    std::fs::write(d.join("unit.tags"), "g#Layer_1 > g -> unit\n").unwrap();
    let unit = units(&d, "art.svg", &["--tags", "unit.tags"]);
    assert_eq!(unit.len(), 3, "{unit:?}");

    // A line that matches nothing is a warning naming it; a bad selector an error that
    // says where.
    let (ok, _, err) = run(bin()
        .current_dir(&d)
        .args(["check", "--shapes", "art.svg", "--tags", "map.tags"]));
    assert!(ok);
    assert!(
        err.contains("map.tags:3") && err.contains("#nothing"),
        "{err}"
    );
    std::fs::write(
        d.join("bad.tags"),
        "#letter_*  -> letter\ng > > rect -> x\n",
    )
    .unwrap();
    let (ok, _, err) = run(bin()
        .current_dir(&d)
        .args(["check", "--shapes", "art.svg", "--tags", "bad.tags"]));
    assert!(!ok);
    assert!(err.contains("bad.tags:2:5:"), "{err}");
    // The grammar's map is looked for beside the grammar; a missing one is an error at
    // the directive.
    std::fs::write(
        d.join("lost.gm"),
        "tags lost.tags\nanimate(affine, local, 0, rotate(90)) : [all, all] -> [t]\n",
    )
    .unwrap();
    let (ok, _, err) = run(bin()
        .current_dir(&d)
        .args(["animate", "art.svg", "lost.gm", "-o", "out.json"]));
    assert!(!ok);
    assert!(
        err.contains("lost.gm:1:") && err.contains("lost.tags"),
        "{err}"
    );
    assert!(!d.join("out.json").exists());
}

#[test]
fn the_unit_depth_takes_the_groups_inside_a_frame() {
    let d = files(
        "depth",
        &[
            ("art.svg", FIGMA),
            (
                "g.gm",
                "units groups\nunit_depth 2\nanimate(affine, local, 0, rotate(90)) : [all, all] -> [t]\n",
            ),
        ],
    );
    let outer = units(&d, "art.svg", &["--units", "groups"]);
    assert_eq!(
        outer.len(),
        1,
        "the frame is the one outermost group: {outer:?}"
    );
    let inner = units(&d, "art.svg", &["--units", "groups", "--unit-depth", "2"]);
    let tags: Vec<&str> = inner.iter().map(|u| u.0.as_str()).collect();
    // The frame's background is a path outside any group at that depth: its own unit.
    assert_eq!(tags, ["Frame 1", "icon-home", "icon-user"], "{inner:?}");
    // The grammar's directives say the same.
    let (ok, out, err) = run(bin().current_dir(&d).args(["check", "g.gm", "art.svg"]));
    assert!(ok, "{err}");
    assert!(out.contains("scene: 3 shapes"), "{out}");
    // A Lottie scene has layers, not SVG groups: the SVG-only options say so.
    let lottie = d.join("anim.json");
    std::fs::write(
        &lottie,
        r#"{"v":"5.7.0","fr":30,"ip":0,"op":30,"w":100,"h":100,"layers":[]}"#,
    )
    .unwrap();
    let (ok, _, err) = run(bin()
        .current_dir(&d)
        .args(["check", "--shapes", "--unit-depth", "2"])
        .arg(lottie));
    assert!(!ok);
    assert!(err.contains("--unit-depth"), "{err}");
}

/// An emoji-shaped clip (Noto and Twemoji export such files): a clip path whose `use`
/// points at another `use`, or at a group, is ignored by browsers, so what it clips is not
/// drawn; a `use` of a shape clips as usual. Judged against Chromium's drawing.
#[cfg(feature = "players")]
#[test]
fn a_clip_paths_use_of_a_use_clips_everything_away_as_in_browsers() {
    use crate::support::players::chromium;
    use gmotion_export_raster::{Pixmap, compare};
    let d = files(
        "clip-use",
        &[(
            "emoji.svg",
            r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="120" height="120">
<defs>
<circle id="face" cx="60" cy="60" r="40"/>
<use id="face_ref" xlink:href="#face"/>
<g id="group"><circle cx="60" cy="60" r="30"/></g>
<clipPath id="via_use"><use xlink:href="#face_ref"/></clipPath>
<clipPath id="via_group"><use xlink:href="#group"/></clipPath>
<clipPath id="direct"><use xlink:href="#face"/></clipPath>
</defs>
<rect width="40" height="120" fill="#3a3" clip-path="url(#via_use)"/>
<rect x="40" width="40" height="120" fill="#a33" clip-path="url(#via_group)"/>
<rect x="80" width="40" height="120" fill="#33a" clip-path="url(#direct)"/>
</svg>"##,
        )],
    );
    let (ok, _, err) = run(bin()
        .current_dir(&d)
        .args(["convert", "emoji.svg", "-o", "emoji.png"]));
    assert!(ok, "{err}");
    assert_eq!(
        err.matches("a clip path's <use> must point at a shape or text")
            .count(),
        2,
        "one warning per ignored child:\n{err}"
    );
    let ours = Pixmap::load_png(d.join("emoji.png")).unwrap();
    let chrome = chromium(&d.join("emoji.svg"), 120, &[0.0]).remove(0);
    let off = compare(&chrome, &ours, 32);
    assert!(off < 0.005, "{:.2}% of pixels off Chromium", off * 100.0);
    // The direct clip still draws: the blue band's disc part is there.
    let blue = ours.pixel(90, 60).unwrap();
    assert!(
        blue.blue() > 100 && blue.alpha() == 255,
        "the direct clip draws"
    );
}

/// A filter drawn as an image or a blend mode that is dropped is warned about with the
/// element that asked for it (usvg moves it onto an anonymous group, which used to be
/// named `<svg>`).
#[test]
fn dropped_effects_are_warned_about_by_the_element_that_has_them() {
    let d = files(
        "effects",
        &[(
            "fx.svg",
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">
<defs><filter id="b"><feMorphology operator="dilate" radius="3"/></filter></defs>
<circle id="glow" cx="50" cy="50" r="20" filter="url(#b)"/>
<rect x="10" y="10" width="20" height="20" style="mix-blend-mode:multiply"/>
</svg>"##,
        )],
    );
    let (ok, _, err) = run(bin()
        .current_dir(&d)
        .args(["convert", "fx.svg", "-o", "fx.json"]));
    assert!(ok, "{err}");
    assert!(
        err.contains("<circle id=\"glow\"> (line 3): filter drawn as an image"),
        "{err}"
    );
    assert!(
        err.contains("<rect> (line 4): mix-blend-mode multiply ignored"),
        "{err}"
    );
    assert!(!err.contains("<svg>"), "{err}");
}

/// The designer-export corpus, by name: `expected-tags.txt` as `(file, tags)`.
fn expected_corpus_tags(dir: &Path) -> Vec<(String, Vec<String>)> {
    let text = std::fs::read_to_string(dir.join("expected-tags.txt")).unwrap();
    let mut files: Vec<(String, Vec<String>)> = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        match line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            Some(file) => files.push((file.to_string(), Vec::new())),
            None => files
                .last_mut()
                .expect("a tag before any [file] header")
                .1
                .push(line.to_string()),
        }
    }
    files
}

fn corpus_dir() -> PathBuf {
    crate::support::root().join("tests/corpus/designer")
}

/// Every SVG under `dir` (the hand-written files and the real exports in `real/` and its
/// package folders), as paths relative to the corpus written with `/`, sorted.
fn corpus_svgs(dir: &Path, prefix: &str) -> Vec<String> {
    let mut out: Vec<String> =
        crate::support::files_with_extension(dir, "svg", "in the repository")
            .iter()
            .map(|p| format!("{prefix}{}", p.file_name().unwrap().to_string_lossy()))
            .collect();
    let mut subdirs: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    subdirs.sort();
    for sub in subdirs {
        let name = sub.file_name().unwrap().to_string_lossy().into_owned();
        out.extend(corpus_svgs(&sub, &format!("{prefix}{name}/")));
    }
    out.sort();
    out
}

/// Every designer export is named by its layers (and labels, and the classes a designer
/// chose), never by the style classes its tool generated (`st0`, `cls-1`, `fil0`, `str0`).
#[test]
fn designer_exports_are_tagged_by_their_layer_names_not_their_style_classes() {
    let dir = corpus_dir();
    let files = expected_corpus_tags(&dir);
    let on_disk = corpus_svgs(&dir, "");
    let mut listed: Vec<String> = files.iter().map(|f| f.0.clone()).collect();
    listed.sort();
    assert_eq!(
        listed, on_disk,
        "expected-tags.txt lists every file of the corpus"
    );
    let mut failures = Vec::new();
    for (file, want) in &files {
        let got: Vec<String> = units(&dir, file, &[]).into_iter().map(|u| u.0).collect();
        if &got != want {
            failures.push(format!("{file}: tags {got:?}, expected {want:?}"));
        }
        // The names are the designer's: `check` has nothing better to suggest.
        let (ok, _, err) = run(bin().current_dir(&dir).args(["check", "--shapes", file]));
        assert!(ok, "{err}");
        if err.contains("hint:") {
            failures.push(format!("{file}: unexpected hint: {err}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Asked for classes, Illustrator's `st0`… are what a scene gets; `check` says that the
/// default source names the shapes, from the command line and from the grammar.
#[test]
fn check_says_which_tag_source_names_generated_tags_better() {
    let dir = corpus_dir();
    let (ok, _, err) = run(bin().current_dir(&dir).args([
        "check",
        "--shapes",
        "--tag-from",
        "class",
        "illustrator-internal-css.svg",
    ]));
    assert!(ok, "{err}");
    let hint = err
        .lines()
        .find(|l| l.contains("hint:"))
        .unwrap_or_else(|| panic!("no hint: {err}"));
    assert!(
        hint.contains("`--tag-from auto`") && hint.contains("st0") && hint.contains("letter_G"),
        "{hint}"
    );
    let d = files(
        "hint",
        &[(
            "class.gm",
            "tag_from class\nanimate(affine, local, 0, rotate(90)) : [all, all] -> [t]\n",
        )],
    );
    let (ok, _, err) = run(bin()
        .current_dir(&d)
        .arg("check")
        .arg("class.gm")
        .arg(dir.join("coreldraw.svg")));
    assert!(ok, "{err}");
    assert!(
        err.contains("hint:") && err.contains("tag_from auto") && err.contains("fil1"),
        "{err}"
    );
}

/// A tag map's `unit` holds whatever `--units` says, also for an element inside a group
/// that would otherwise move as one: the group's other content then moves as usual.
#[test]
fn a_tag_map_unit_inside_a_group_that_moves_as_one_is_a_unit() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 120">
<g data-tag="face">
<g id="eyes"><circle cx="80" cy="40" r="6"/><circle cx="120" cy="40" r="6"/></g>
<path id="mouth" d="M70 80 Q100 100 130 80" stroke="black" fill="none"/>
</g>
</svg>"##;
    let d = files(
        "map-unit",
        &[("face.svg", svg), ("eyes.tags", "#eyes -> unit\n")],
    );
    assert_eq!(units(&d, "face.svg", &[]).len(), 1, "the face moves as one");
    for extra in [
        &["--tags", "eyes.tags"][..],
        &["--tags", "eyes.tags", "--units", "groups"],
    ] {
        let got = units(&d, "face.svg", extra);
        assert_eq!(
            got.len(),
            2,
            "{extra:?}: the eyes as one, the mouth: {got:?}"
        );
        assert!(got.iter().all(|u| u.0 == "face"), "{got:?}");
        assert!(got[0].1.contains(&"eyes".to_string()), "{got:?}");
        assert!(got[1].1.contains(&"mouth".to_string()), "{got:?}");
    }
}
