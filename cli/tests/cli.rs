//! The real binary on the bundled examples: every output format, determinism across runs
//! and thread counts, and the demo command.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

use crate::support::root;

fn examples() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(root().join("grammars"))
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "gm") && p.with_extension("svg").exists())
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gmotion-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run_ok(cmd: &mut Command) -> String {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{cmd:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn animate(name: &str, outputs: &[&Path], extra: &[&str], threads: Option<&str>) {
    let g = root().join("grammars");
    let mut cmd = bin();
    cmd.arg("animate")
        .arg(g.join(format!("{name}.svg")))
        .arg(g.join(format!("{name}.gm")));
    for o in outputs {
        cmd.arg("-o").arg(o);
    }
    cmd.args(extra);
    if let Some(t) = threads {
        cmd.env("RAYON_NUM_THREADS", t);
    }
    run_ok(&mut cmd);
}

#[test]
fn every_example_writes_every_format_identically_on_every_run() {
    let names = examples();
    assert!(names.len() >= 4, "examples: {names:?}");
    for name in names {
        let d = out_dir(&name);
        let files = ["a.json", "a.svg", "a.png", "a.gif", "a.apng"];
        let first: Vec<PathBuf> = files.iter().map(|f| d.join(format!("1-{f}"))).collect();
        let second: Vec<PathBuf> = files.iter().map(|f| d.join(format!("2-{f}"))).collect();
        let refs1: Vec<&Path> = first.iter().map(|p| p.as_path()).collect();
        let refs2: Vec<&Path> = second.iter().map(|p| p.as_path()).collect();
        let extra = [
            "--seed", "11", "--time", "1.3", "--width", "100", "--fps", "2",
        ];
        animate(&name, &refs1, &extra, None);
        animate(&name, &refs2, &extra, Some("1"));
        for (a, b) in first.iter().zip(&second) {
            let (x, y) = (std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
            assert!(!x.is_empty(), "{} is empty", a.display());
            assert!(
                x == y,
                "{name}: {} differs between runs (second run single-threaded)",
                a.display()
            );
        }
        // The frames directory: one PNG per frame, the same count the preview holds.
        let frames = d.join("frames");
        animate(
            &name,
            &[frames.as_path()],
            &["--width", "60", "--fps", "2"],
            None,
        );
        let n = std::fs::read_dir(&frames).unwrap().count();
        assert!(n >= 4, "{name}: only {n} frames");
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn looping_examples_end_where_they_begin() {
    // A rendered loop's last instant equals its first (inverted slices close every change).
    for name in examples() {
        let d = out_dir(&format!("loop-{name}"));
        let (a, b) = (d.join("start.png"), d.join("end.png"));
        animate(
            &name,
            &[a.as_path()],
            &["--time", "0", "--width", "200"],
            None,
        );
        let src =
            std::fs::read_to_string(root().join("grammars").join(format!("{name}.gm"))).unwrap();
        let g = gmotion::grammar::parse(&src).unwrap();
        let dur = gmotion::engine::settings::from_grammar(&g)
            .unwrap()
            .duration;
        animate(
            &name,
            &[b.as_path()],
            &["--time", &dur.to_string(), "--width", "200"],
            None,
        );
        let pa = resvg::tiny_skia::Pixmap::load_png(&a).unwrap();
        let pb = resvg::tiny_skia::Pixmap::load_png(&b).unwrap();
        let off = gmotion_export_raster::compare(&pa, &pb, 8);
        assert!(
            off < 0.001,
            "{name}: {:.3}% of pixels differ between the first and last instant",
            off * 100.0
        );
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn demo_writes_frames_preview_lottie_and_smil() {
    let d = out_dir("demo");
    let stdout = run_ok(bin().current_dir(root()).arg("demo").arg("-o").arg(&d));
    for f in [
        "abstract.gif",
        "abstract.json",
        "abstract.svg",
        "preview.html",
    ] {
        assert!(
            d.join(f).is_file(),
            "demo did not write {f}; said:\n{stdout}"
        );
    }
    assert!(std::fs::read_dir(d.join("frames")).unwrap().count() > 10);
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("abstract.json")).unwrap()).unwrap();
    assert!(json["layers"].as_array().is_some_and(|l| !l.is_empty()));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn demo_carries_every_example_inside_the_binary() {
    // Every example of grammars/, and every transitions example, is listed.
    let listed = run_ok(bin().args(["demo", "--list"]));
    let names: Vec<&str> = listed
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    let mut want = examples();
    for entry in std::fs::read_dir(root().join("grammars")).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if let Some(stem) = name.strip_suffix(".targets.json") {
            want.push(stem.to_string());
        }
    }
    for w in &want {
        assert!(
            names.contains(&w.as_str()),
            "`{w}` is not bundled:\n{listed}"
        );
    }
    assert_eq!(names.len(), want.len(), "{listed}");
    // A copy of the binary far from the source tree runs a transitions example.
    let d = out_dir("demo-copy");
    let copy = d.join("gmotion");
    std::fs::copy(env!("CARGO_BIN_EXE_gmotion"), &copy).unwrap();
    run_ok(
        Command::new(&copy)
            .current_dir(&d)
            .args(["-q", "demo", "--example", "permutation", "-o", "out"])
            .env_remove("CARGO_MANIFEST_DIR"),
    );
    for f in [
        "permutation.json",
        "permutation.svg",
        "preview.html",
        "source/permutation.targets.json",
    ] {
        assert!(d.join("out").join(f).is_file(), "{f}");
    }
}

#[test]
fn convert_writes_png_lottie_and_svg() {
    let d = out_dir("convert");
    let input = root().join("grammars/toy.svg");
    run_ok(
        bin()
            .arg("convert")
            .arg(&input)
            .arg("-o")
            .arg(d.join("t.png"))
            .arg("-o")
            .arg(d.join("t.json"))
            .arg("-o")
            .arg(d.join("t.svg"))
            .args(["--width", "130"]),
    );
    let png = resvg::tiny_skia::Pixmap::load_png(d.join("t.png")).unwrap();
    assert_eq!(png.width(), 130);
    // The PNG and the clean SVG both show what resvg draws from the original file (an
    // oracle outside gmotion's scene model: it reads the source directly).
    let render = |path: &Path| {
        gmotion_export_raster::render(&std::fs::read_to_string(path).unwrap(), 130).unwrap()
    };
    let original = render(&input);
    let compare = gmotion_export_raster::compare;
    assert!(compare(&png, &original, 8) < 0.001);
    assert!(compare(&render(&d.join("t.svg")), &original, 8) < 0.001);
    let lottie: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("t.json")).unwrap()).unwrap();
    assert_eq!(
        (lottie["w"].as_f64(), lottie["layers"].is_array()),
        (Some(130.0), true)
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn check_prints_statistics_and_writes_the_graph() {
    let d = out_dir("check");
    let g = root().join("grammars");
    let out = run_ok(
        bin()
            .arg("check")
            .arg(g.join("toy.gm"))
            .arg(g.join("toy.svg"))
            .arg("--graph")
            .arg(d.join("g.dot")),
    );
    assert!(out.contains("rules: 5"), "{out}");
    assert!(out.contains("expansion:"), "{out}");
    let dot = std::fs::read_to_string(d.join("g.dot")).unwrap();
    assert!(
        dot.starts_with("digraph") && dot.contains("\"a\" -> \"b\""),
        "{dot}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// On a group grammar, `check` runs the spatial rules and reports the pieces the
/// timeslice rules then see (the consumed tags gone, the produced ones there); it does not
/// call the consumed tags unused.
#[test]
fn check_expands_group_grammars() {
    let g = root().join("grammars");
    // `check` on an example's grammar and scene: its whole report and the pieces line.
    let check = |name: &str| {
        let out = run_ok(
            bin()
                .arg("check")
                .arg(g.join(format!("{name}.gm")))
                .arg(g.join(format!("{name}.svg"))),
        );
        let line = out
            .lines()
            .find(|l| l.starts_with("spatial expansion:"))
            .unwrap_or_else(|| panic!("no spatial expansion line in {out}"))
            .to_string();
        (out, line)
    };
    let (out, line) = check("growing_tangle");
    // `disc` is cut into rings and pieces (tagged `ink` and `piece`); `paper` is left alone.
    assert!(!line.contains("disc ×"), "{line}");
    for tag in ["ink ×", "piece ×", "paper ×1"] {
        assert!(line.contains(tag), "{line}");
    }
    assert!(out.contains("spatial rules applied: 3 of 3"), "{out}");
    assert!(out.contains("\nrules applied: 3 of 3"), "{out}");
    assert!(!out.contains("`disc` match no rule"), "{out}");
    let (out, line) = check("regroup");
    assert!(!line.contains("p0 ×") && line.contains("done ×"), "{line}");
    assert!(out.contains("spatial rules applied: 11 of 11"), "{out}");
    assert!(out.contains("the result stands still"), "{out}");
    assert!(!out.contains("match no rule"), "{out}");
}

#[test]
fn transitions_run_the_three_applications() {
    let g = root().join("grammars");
    for name in ["histogram", "permutation", "revisions"] {
        let d = out_dir(&format!("tr-{name}"));
        let (json, svg, png) = (d.join("a.json"), d.join("a.svg"), d.join("a.png"));
        run_ok(
            bin()
                .arg("transitions")
                .arg(g.join(format!("{name}.svg")))
                .arg(g.join(format!("{name}.targets.json")))
                .args(["--fps", "20", "--time", "0.5", "--width", "120"])
                .arg("-o")
                .arg(&json)
                .arg("-o")
                .arg(&svg)
                .arg("-o")
                .arg(&png),
        );
        let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        assert!(v["op"].as_f64().unwrap() > 20.0, "{name}: too short");
        assert!(
            std::fs::read_to_string(&svg).unwrap().contains("<animate"),
            "{name}: SMIL has no animation"
        );
        let _ = std::fs::remove_dir_all(&d);
    }
    // A bad system is reported, with no output.
    let d = out_dir("tr-bad");
    let out = bin()
        .arg("transitions")
        .arg(g.join("histogram.svg"))
        .arg(g.join("histogram.targets.json"))
        .args(["--system", "spring(-1, 0)"])
        .arg("-o")
        .arg(d.join("x.json"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--system"));
    assert!(!d.join("x.json").exists());
    // A target naming a tag the scene lacks: the file, the target and the tags it has.
    let targets = d.join("bad.targets.json");
    let mut doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(g.join("histogram.targets.json")).unwrap()).unwrap();
    doc["targets"][0]["tag"] = "nosuchtag".into();
    std::fs::write(&targets, doc.to_string()).unwrap();
    let out = bin()
        .arg("transitions")
        .arg(g.join("histogram.svg"))
        .arg(&targets)
        .arg("-o")
        .arg(d.join("y.json"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("bad.targets.json: targets[0]: no shape has the tag `nosuchtag`")
            && err.contains("bar"),
        "{err}"
    );
    assert!(!d.join("y.json").exists());
}

/// Runs `cmd`, which must fail with status 1; returns its error output.
fn run_err(cmd: &mut Command) -> String {
    let out = cmd.output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{cmd:?}: {err}");
    err
}

/// `grammars/toy.gm` without its `scene` line.
fn toy_rules() -> String {
    let src = std::fs::read_to_string(root().join("grammars/toy.gm")).unwrap();
    let kept: Vec<&str> = src.lines().filter(|l| !l.starts_with("scene ")).collect();
    assert!(kept.len() < src.lines().count(), "toy.gm names no scene");
    kept.join("\n") + "\n"
}

fn lottie(p: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(p).unwrap()).unwrap()
}

/// The names of a Lottie's root layers.
fn layer_names(p: &Path) -> Vec<String> {
    let mut v: Vec<String> = lottie(p)["layers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["nm"].as_str().unwrap().to_string())
        .collect();
    v.sort();
    v
}

/// The `width` and `height` attributes of an SVG's root.
fn svg_size(p: &Path) -> (String, String) {
    let text = std::fs::read_to_string(p).unwrap();
    let root_tag = &text[..text.find('>').unwrap()];
    let attr = |name: &str| {
        let at = root_tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        root_tag[at..at + root_tag[at..].find('"').unwrap()].to_string()
    };
    (attr("width"), attr("height"))
}

#[test]
fn the_scene_directive_names_the_scene_beside_the_grammar() {
    let d = out_dir("scene-directive");
    let g = root().join("grammars");
    // Run from another folder: the scene is found beside the grammar, not in the cwd.
    let named = d.join("named.json");
    run_ok(
        bin()
            .current_dir(&d)
            .arg("animate")
            .arg(g.join("toy.gm"))
            .arg("-o")
            .arg(&named),
    );
    let given = d.join("given.json");
    animate("toy", &[given.as_path()], &[], None);
    assert!(std::fs::read(&named).unwrap() == std::fs::read(&given).unwrap());
    // The grammar is told by its extension, so it may come first.
    let swapped = d.join("swapped.json");
    run_ok(
        bin()
            .arg("animate")
            .arg(g.join("toy.gm"))
            .arg(g.join("toy.svg"))
            .arg("-o")
            .arg(&swapped),
    );
    assert!(std::fs::read(&swapped).unwrap() == std::fs::read(&given).unwrap());

    // A grammar naming another scene, in a folder of its own: the directive is followed,
    // and a scene on the command line overrides it.
    std::fs::create_dir_all(d.join("art")).unwrap();
    std::fs::write(
        d.join("art/small.svg"),
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50">
  <rect data-tag="s" x="5" y="5" width="10" height="10"/>
  <circle data-tag="c" cx="40" cy="20" r="5"/>
</svg>"#,
    )
    .unwrap();
    let gm = d.join("small.gm");
    std::fs::write(&gm, format!("scene art/small.svg\n{}", toy_rules())).unwrap();
    let small = d.join("small.json");
    run_ok(bin().arg("animate").arg(&gm).arg("-o").arg(&small));
    assert_eq!(lottie(&small)["w"], 100);
    let over = d.join("over.json");
    run_ok(
        bin()
            .arg("animate")
            .arg(g.join("toy.svg"))
            .arg(&gm)
            .arg("-o")
            .arg(&over),
    );
    assert!(std::fs::read(&over).unwrap() == std::fs::read(&given).unwrap());
    // `check` expands on the named scene too.
    let out = run_ok(bin().arg("check").arg(&gm));
    assert!(out.contains("scene: 2 shapes"), "{out}");

    // Neither: a clear error, nothing written.
    let bare = d.join("bare.gm");
    std::fs::write(&bare, toy_rules()).unwrap();
    let x = d.join("x.json");
    let err = run_err(bin().arg("animate").arg(&bare).arg("-o").arg(&x));
    assert!(err.contains("bare.gm") && err.contains("no scene"), "{err}");
    assert!(!x.exists());
    // A named scene that is not there: the error points at the directive's value.
    let missing = d.join("missing.gm");
    std::fs::write(&missing, format!("seed 3\nscene nope.svg\n{}", toy_rules())).unwrap();
    let err = run_err(bin().arg("animate").arg(&missing).arg("-o").arg(&x));
    assert!(
        err.contains("missing.gm:2:7") && err.contains("nope.svg"),
        "{err}"
    );
    // Only a scene: the grammar is asked for.
    let err = run_err(
        bin()
            .arg("animate")
            .arg(g.join("toy.svg"))
            .arg("-o")
            .arg(&x),
    );
    assert!(err.contains("grammar"), "{err}");
    assert!(!x.exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn width_and_height_size_every_output() {
    let d = out_dir("size");
    let toy = root().join("grammars/toy.svg");
    let scene = lottie_size(&toy);
    assert_eq!(
        scene,
        (520, 320),
        "toy.svg changed; the expectations below use its size"
    );
    // (header, flags, size): one side sets the other by the aspect ratio (320·260/520 =
    // 160, 520·100/320 = 162.5 → 163), both are taken as given, and either flag replaces
    // both directives.
    let cases: [(&str, &[&str], (u32, u32)); 5] = [
        ("width 260", &[], (260, 160)),
        ("height 100", &[], (163, 100)),
        ("width 200\nheight 200", &[], (200, 200)),
        ("width 260", &["--width", "130"], (130, 80)),
        ("width 260\nheight 300", &["--height", "40"], (65, 40)),
    ];
    for (i, (header, flags, (w, h))) in cases.into_iter().enumerate() {
        let gm = d.join(format!("g{i}.gm"));
        let text = format!("scene \"{}\"\n{header}\n{}", toy.display(), toy_rules());
        std::fs::write(&gm, text).unwrap();
        let out = |f: &str| d.join(format!("{i}-{f}"));
        let mut cmd = bin();
        cmd.arg("animate").arg(&gm).args(["--fps", "2"]).args(flags);
        for f in ["a.json", "a.svg", "a.png", "a.gif", "a.apng", "frames"] {
            cmd.arg("-o").arg(out(f));
        }
        run_ok(&mut cmd);
        let what = format!("{header:?} {flags:?}");
        let json = lottie(&out("a.json"));
        assert_eq!(
            (json["w"].as_u64(), json["h"].as_u64()),
            (Some(w.into()), Some(h.into())),
            "{what}"
        );
        assert_eq!(
            svg_size(&out("a.svg")),
            (w.to_string(), h.to_string()),
            "{what}"
        );
        let png = resvg::tiny_skia::Pixmap::load_png(out("a.png")).unwrap();
        assert_eq!((png.width(), png.height()), (w, h), "{what}");
        let frame =
            resvg::tiny_skia::Pixmap::load_png(out("frames").join("frame_00000.png")).unwrap();
        assert_eq!((frame.width(), frame.height()), (w, h), "{what}");
        let gif = gif::DecodeOptions::new()
            .read_info(std::fs::File::open(out("a.gif")).unwrap())
            .unwrap();
        assert_eq!(
            (u32::from(gif.width()), u32::from(gif.height())),
            (w, h),
            "{what}"
        );
        let apng = png::Decoder::new(std::io::BufReader::new(
            std::fs::File::open(out("a.apng")).unwrap(),
        ))
        .read_info()
        .unwrap();
        assert_eq!((apng.info().width, apng.info().height), (w, h), "{what}");
    }
    // Both sides: the art is fitted and centred, not stretched. 520×320 in 200×200 is
    // scaled by 200/520 and fills rows 38.5 to 161.5; toy's background covers its canvas.
    let png = resvg::tiny_skia::Pixmap::load_png(d.join("2-a.png")).unwrap();
    let alpha = |x, y| png.pixel(x, y).unwrap().alpha();
    assert_eq!([alpha(100, 20), alpha(100, 180)], [0, 0]);
    assert_eq!(
        [
            alpha(1, 100),
            alpha(198, 100),
            alpha(100, 40),
            alpha(100, 160)
        ],
        [255; 4]
    );
    // The Lottie says the same through a null parent of every root layer.
    let json = lottie(&d.join("2-a.json"));
    let layers = json["layers"].as_array().unwrap();
    let output = layers.iter().find(|l| l["nm"] == "output").unwrap();
    let k = 200.0 / 520.0;
    let num = |v: &serde_json::Value| v.as_f64().unwrap();
    let (s, p) = (&output["ks"]["s"]["k"], &output["ks"]["p"]["k"]);
    assert!(
        (num(&s[0]) - 100.0 * k).abs() < 1e-3 && (num(&s[1]) - 100.0 * k).abs() < 1e-3,
        "{s}"
    );
    assert!(
        num(&p[0]).abs() < 1e-3 && (num(&p[1]) - (200.0 - 320.0 * k) / 2.0).abs() < 1e-3,
        "{p}"
    );
    for l in layers.iter().filter(|l| l["nm"] != "output") {
        assert_eq!(l["parent"], output["ind"], "{}", l["nm"]);
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// The size `convert` gives a scene's Lottie: its canvas.
fn lottie_size(svg: &Path) -> (u64, u64) {
    let d = out_dir("lottie-size");
    let out = d.join("s.json");
    run_ok(bin().arg("convert").arg(svg).arg("-o").arg(&out));
    let json = lottie(&out);
    let _ = std::fs::remove_dir_all(&d);
    (json["w"].as_u64().unwrap(), json["h"].as_u64().unwrap())
}

/// Writes `scene.svg` and `g.gm` (naming it) in a fresh folder and animates it to a
/// Lottie with `flags`; the Lottie's root layer names, or the error.
fn animate_with(
    name: &str,
    svg: &str,
    grammar: &str,
    flags: &[&str],
) -> std::result::Result<Vec<String>, String> {
    let d = out_dir(name);
    std::fs::write(d.join("scene.svg"), svg).unwrap();
    std::fs::write(d.join("g.gm"), format!("scene scene.svg\n{grammar}")).unwrap();
    let json = d.join("a.json");
    let out = bin()
        .arg("animate")
        .arg(d.join("g.gm"))
        .arg("-o")
        .arg(&json)
        .args(flags)
        .output()
        .unwrap();
    let result = if out.status.success() {
        Ok(layer_names(&json))
    } else {
        assert_eq!(out.status.code(), Some(1));
        Err(String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let _ = std::fs::remove_dir_all(&d);
    result
}

#[test]
fn tag_from_chooses_the_tags_the_scene_gets() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50">
  <rect data-tag="a" class="b" x="10" y="10" width="20" height="20" fill="red"/>
</svg>"#;
    let moves = |tag: &str| {
        format!("duration 1s\nanimate(affine, world, 0, translate(10, 0)) : [all, {tag}] -> [m]\n")
    };
    // By default the data-tag names the shape, so a rule for class `b` finds nothing.
    let err = animate_with("tag-default", svg, &moves("b"), &[]).unwrap_err();
    assert!(err.contains("`b`"), "{err}");
    assert_eq!(animate_with("tag-a", svg, &moves("a"), &[]).unwrap(), ["a"]);
    let by_class = format!("tag_from class\n{}", moves("b"));
    assert_eq!(
        animate_with("tag-class", svg, &by_class, &[]).unwrap(),
        ["b"]
    );
    // The flag overrides the directive.
    let all = format!("tag_from class\n{}", moves("all"));
    let flagged = animate_with("tag-flag", svg, &all, &["--tag-from", "data-tag"]).unwrap();
    assert_eq!(flagged, ["a"]);
    // An unknown source is an error at the value.
    let err = animate_with(
        "tag-bad",
        svg,
        &format!("tag_from klass\n{}", moves("all")),
        &[],
    )
    .unwrap_err();
    assert!(err.contains("g.gm:2:10") && err.contains("klass"), "{err}");
}

#[test]
fn units_choose_what_moves_as_one() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50">
  <g data-tag="pair"><rect x="10" y="10" width="10" height="10"/><rect x="40" y="10" width="10" height="10"/></g>
</svg>"#;
    let moves = "duration 1s\nanimate(affine, world, 0, translate(10, 0)) : [all, pair] -> [m]\n";
    // A tagged group is one unit; `units paths` makes each of its paths one.
    assert_eq!(
        animate_with("units-auto", svg, moves, &[]).unwrap(),
        ["pair"]
    );
    let paths = format!("units paths\n{moves}");
    assert_eq!(
        animate_with("units-paths", svg, &paths, &[]).unwrap(),
        ["pair 1", "pair 2"]
    );
    // The flag overrides the directive.
    assert_eq!(
        animate_with("units-flag", svg, &paths, &["--units", "auto"]).unwrap(),
        ["pair"]
    );
    let err = animate_with("units-bad", svg, &format!("units path\n{moves}"), &[]).unwrap_err();
    assert!(err.contains("g.gm:2:7") && err.contains("`paths`"), "{err}");
}

#[test]
fn transitions_run_at_the_targets_files_frame_rate() {
    let d = out_dir("tr-fps");
    let svg = d.join("scene.svg");
    std::fs::write(
        &svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50"><rect data-tag="bar" width="10" height="10"/></svg>"#,
    )
    .unwrap();
    let json = d.join("t.json");
    std::fs::write(
        &json,
        r#"{"fps": 20, "duration": 1, "targets": [{"time": 0, "tag": "bar", "id": 0, "attr": "dx", "value": 30}]}"#,
    )
    .unwrap();
    let csv = d.join("t.csv");
    std::fs::write(
        &csv,
        "# fps: 25\n# duration: 1\ntime,tag,id,attr,value\n0,bar,0,dx,30\n",
    )
    .unwrap();
    let rate = |targets: &Path, flags: &[&str]| {
        let out = d.join("a.json");
        run_ok(
            bin()
                .arg("transitions")
                .arg(&svg)
                .arg(targets)
                .arg("-o")
                .arg(&out)
                .args(flags),
        );
        let v = lottie(&out);
        (v["fr"].as_f64().unwrap(), v["op"].as_f64().unwrap())
    };
    // One second at the file's rate, unless --fps says otherwise.
    assert_eq!(rate(&json, &[]), (20.0, 20.0));
    assert_eq!(rate(&csv, &[]), (25.0, 25.0));
    assert_eq!(rate(&json, &["--fps", "40"]), (40.0, 40.0));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_frames_folder_holding_other_files_is_refused_before_any_output() {
    let d = out_dir("frames-refused");
    let frames = d.join("frames");
    std::fs::create_dir(&frames).unwrap();
    std::fs::write(frames.join("notes.txt"), "mine").unwrap();
    let json = d.join("a.json");
    let err = run_err(
        bin()
            .arg("animate")
            .arg(root().join("grammars/toy.gm"))
            .arg("-o")
            .arg(&json)
            .arg("-o")
            .arg(&frames),
    );
    assert!(err.contains("notes.txt"), "{err}");
    assert!(!json.exists());
    let left: Vec<_> = std::fs::read_dir(&frames).unwrap().collect();
    assert_eq!(left.len(), 1);
    let _ = std::fs::remove_dir_all(&d);
}

/// A write past the file-size limit (`ulimit -f`, SIGXFSZ) is an error like any failed
/// write: exit status 1, a message naming the output, no output and no temporary file
/// left beside it.
#[test]
fn a_file_size_limit_fails_cleanly() {
    let dir = out_dir("xfsz");
    let g = root().join("grammars/abstract.gm");
    let svg = root().join("grammars/abstract.svg");
    let out = dir.join("out.gif");
    let script = format!(
        "ulimit -f 20; exec '{}' animate '{}' '{}' -o '{}'",
        env!("CARGO_BIN_EXE_gmotion"),
        svg.display(),
        g.display(),
        out.display()
    );
    let o = Command::new("bash")
        .arg("-c")
        .arg(&script)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("out.gif") && err.contains("File too large"),
        "{err}"
    );
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(left.is_empty(), "{left:?}");
}

/// Runs `cmd` with `input` on its standard input; returns (status, stdout, stderr).
fn piped(cmd: &mut Command, input: &[u8]) -> (Option<i32>, Vec<u8>, String) {
    use std::io::Write;
    use std::process::Stdio;
    let mut child = cmd
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    stdin.write_all(input).unwrap();
    drop(stdin);
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code(), out.stdout, err)
}

#[test]
fn dash_is_standard_input_and_output() {
    let d = out_dir("stdio");
    let g = root().join("grammars");
    let svg = std::fs::read(g.join("toy.svg")).unwrap();
    // The same animation through files and through pipes: the same bytes.
    let file = d.join("toy.json");
    animate("toy", &[&file], &[], None);
    let (code, out, err) = piped(
        bin()
            .args(["animate", "-", "--format", "json", "-o", "-"])
            .arg(g.join("toy.gm")),
        &svg,
    );
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(out, std::fs::read(&file).unwrap());
    assert!(err.contains("wrote standard output"), "{err}");
    // A GIF to standard output is a GIF; the grammar may come on standard input too.
    let gm = std::fs::read(g.join("toy.gm")).unwrap();
    let (code, out, err) = piped(
        bin()
            .args(["-q", "animate"])
            .arg(g.join("toy.svg"))
            .args(["-", "-o", "-", "--format", "gif"]),
        &gm,
    );
    assert_eq!(code, Some(0), "{err}");
    assert!(out.starts_with(b"GIF89a"));
    assert!(err.is_empty(), "--quiet printed: {err}");
    // Without --format, `-o -` is refused before any work and prints nothing on stdout.
    let (code, out, err) = piped(
        bin()
            .arg("animate")
            .arg(g.join("toy.svg"))
            .arg(g.join("toy.gm"))
            .args(["-o", "-"]),
        b"",
    );
    assert_eq!(code, Some(1));
    assert!(out.is_empty() && err.contains("--format"), "{err}");
    // A failed run prints nothing on standard output either.
    let (code, out, _) = piped(
        bin()
            .args(["animate", "-", "-o", "-", "--format", "json"])
            .arg(g.join("toy.gm")),
        b"<svg xmlns='http://www.w3.org/2000/svg'><rect",
    );
    assert_eq!(code, Some(1));
    assert!(out.is_empty());
}

#[test]
fn a_summary_line_says_what_was_written_unless_quiet() {
    let d = out_dir("summary");
    let g = root().join("grammars");
    let (json, frames) = (d.join("a.json"), d.join("frames"));
    let out = bin()
        .arg("animate")
        .arg(g.join("toy.svg"))
        .arg(g.join("toy.gm"))
        .arg("-o")
        .arg(&json)
        .arg("-o")
        .arg(&frames)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(
        lines[0].starts_with("wrote ")
            && lines[0].contains("a.json (")
            && lines[0].contains("(180 frames)"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn completions_and_the_manual_come_from_the_argument_definitions() {
    for shell in ["bash", "zsh", "fish", "elvish", "powershell"] {
        let script = run_ok(bin().args(["completions", shell]));
        assert!(
            script.contains("animate") && script.contains("tolerance"),
            "{shell}"
        );
    }
    let man = run_ok(bin().arg("man"));
    assert!(
        man.contains(".TH gmotion") && man.contains("animate"),
        "{man}"
    );
    let bad = bin().args(["completions", "tcsh"]).output().unwrap();
    assert_eq!(bad.status.code(), Some(2), "usage errors exit with 2");
    // Every command's help shows examples.
    for cmd in [
        "animate",
        "convert",
        "check",
        "transitions",
        "variations",
        "studio",
        "demo",
    ] {
        let help = run_ok(bin().args([cmd, "--help"]));
        assert!(
            help.contains("Examples:\n  gmotion "),
            "{cmd} --help has no examples"
        );
    }
}

#[test]
fn check_without_a_scene_reports_every_error_of_meaning_at_once() {
    let d = out_dir("static-errors");
    let g = d.join("bad.gm");
    std::fs::write(
        &g,
        "duration 2s
timesplit(0.5, 0.6) : [all, s] -> [a, b]
animate(opacity, local, 0, 2) : [a, s] -> [m]
animate(afine, world, 0, translate(1, 0)) : [b, s] -> [n]
animate(affine, world, -1, translate(1, 0), ease=easeInOut) : [m, s] -> [o]
animate(affine, world, 0.1 * id, translate(cx, 0)) : [n, s] -> [p]
",
    )
    .unwrap();
    let err = run_err(bin().arg("check").arg(&g));
    for (at, says) in [
        ("bad.gm:2:1:", "sum to 1, they sum to 1.1"),
        ("bad.gm:3:28:", "opacity lies in [0, 1], found 2"),
        ("bad.gm:4:9:", "did you mean `affine`?"),
        ("bad.gm:5:24:", "cannot be negative"),
        ("bad.gm:5:50:", "did you mean `ease-in-out`?"),
    ] {
        let line = err
            .lines()
            .position(|l| l.contains(at))
            .unwrap_or_else(|| panic!("no {at} in\n{err}"));
        assert!(
            err.lines().skip(line).take(6).any(|l| l.contains(says)),
            "{at} {says}:\n{err}"
        );
    }
    assert!(err.contains("5 errors in"), "{err}");
    // Values that depend on the shape are left to the run on a scene: no error on line 6.
    assert!(!err.contains("bad.gm:6:"), "{err}");
}

#[test]
fn a_loop_that_jumps_is_warned_about_and_a_closed_one_is_not() {
    let d = out_dir("seam");
    let g = root().join("grammars");
    let open = d.join("open.gm");
    std::fs::write(
        &open,
        "duration 2s\ntimesplit(0.5, 0.5) : [all, s] -> [a, b]\nanimate(affine, world, 0, translate(100, 0)) : [a, s] -> [m]\n",
    )
    .unwrap();
    for cmd in ["check", "animate"] {
        let mut c = bin();
        c.arg(cmd);
        if cmd == "check" {
            c.arg(&open).arg(g.join("toy.svg"));
        } else {
            c.arg(g.join("toy.svg"))
                .arg(&open)
                .arg("-o")
                .arg(d.join("o.json"));
        }
        let out = c.output().unwrap();
        // Both print their warnings on standard error, naming the grammar file.
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{err}");
        assert!(
            err.contains("open.gm: warning: ")
                && err.contains("`s` #0 ends where it did not start (100.0 px away)"),
            "{cmd}: {err}"
        );
        assert!(
            !String::from_utf8_lossy(&out.stdout).contains("warning"),
            "{cmd}"
        );
    }
    // `loop false` says the jump is meant; the bundled toy closes its loop.
    let closed = std::fs::read_to_string(&open)
        .unwrap()
        .replace("duration 2s", "duration 2s\nloop false");
    std::fs::write(&open, closed).unwrap();
    let toy = g.join("toy.gm");
    for grammar in [open.as_path(), toy.as_path()] {
        let out = bin()
            .arg("check")
            .arg(grammar)
            .arg(g.join("toy.svg"))
            .output()
            .unwrap();
        let said = String::from_utf8_lossy(&out.stderr) + String::from_utf8_lossy(&out.stdout);
        assert!(!said.contains("jump"), "{}", grammar.display());
    }
}

#[test]
fn a_reader_that_stops_early_is_not_an_error() {
    use std::io::Read;
    use std::process::Stdio;
    let g = root().join("grammars");
    let mut child = bin()
        .args(["check", "--shapes"])
        .arg(g.join("cube.svg"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Close the pipe after one byte, as `| head -c 1` would.
    let mut one = [0u8; 1];
    child.stdout.take().unwrap().read_exact(&mut one).unwrap();
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_frame_name_pattern_names_the_frames() {
    let d = out_dir("pattern");
    let g = root().join("grammars");
    std::fs::write(d.join("notes.txt"), "mine").unwrap();
    let frames = |fps: &str, pattern: &str| {
        run_ok(
            bin()
                .arg("-q")
                .arg("animate")
                .arg(g.join("toy.svg"))
                .arg(g.join("toy.gm"))
                .arg("-o")
                .arg(d.join(pattern))
                .args(["--fps", fps]),
        );
        let mut names: Vec<String> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    };
    // 6 s at 2 fps: 12 frames beside the user's own file, which stays.
    let names = frames("2", "walk_%04d.png");
    assert_eq!(names.len(), 13, "{names:?}");
    assert_eq!(names[0], "notes.txt");
    assert_eq!(names[1], "walk_0000.png");
    assert_eq!(names[12], "walk_0011.png");
    // A shorter run replaces the frames and removes those it no longer has.
    let names = frames("1", "walk_%04d.png");
    assert_eq!(names.len(), 7, "{names:?}");
    assert_eq!(names[6], "walk_0005.png");
    // `%d` pads nothing.
    let names = frames("1", "f%d.png");
    assert!(
        names.contains(&"f0.png".to_string()) && names.contains(&"f5.png".to_string()),
        "{names:?}"
    );
}

#[test]
fn font_options_name_what_they_cannot_find() {
    let g = root().join("grammars");
    let err = run_err(
        bin()
            .args(["convert", "--font-file", "/no/such/font.ttf"])
            .arg(g.join("toy.svg"))
            .args(["-o", "/tmp/never-written.png"]),
    );
    assert!(
        err.contains("/no/such/font.ttf: no such font file or folder"),
        "{err}"
    );
    assert!(!Path::new("/tmp/never-written.png").exists());
}

#[test]
fn convert_takes_a_folder_or_several_files_into_one_folder() {
    let d = out_dir("batch");
    let (inputs, out) = (d.join("in"), d.join("out"));
    std::fs::create_dir_all(&inputs).unwrap();
    for name in ["toy", "cube", "leaf"] {
        let svg = root().join("grammars").join(format!("{name}.svg"));
        std::fs::copy(svg, inputs.join(format!("{name}.svg"))).unwrap();
    }
    std::fs::write(inputs.join("notes.txt"), "not a picture").unwrap();
    std::fs::write(inputs.join("broken.svg"), "<svg").unwrap();
    // Every file is tried; the broken one is named, and the run fails.
    let err = run_err(bin().arg("convert").arg(&inputs).arg("-o").arg(&out));
    assert!(err.contains("broken.svg:1:1"), "{err}");
    assert!(err.contains("converted 3 of 4 files"), "{err}");
    for name in ["toy", "cube", "leaf"] {
        let json = lottie(&out.join(format!("{name}.json")));
        assert!(
            json["layers"].as_array().is_some_and(|l| !l.is_empty()),
            "{name}"
        );
    }
    assert!(!out.join("broken.json").exists() && !out.join("notes.json").exists());
    // Several files, to PNG.
    let pngs = d.join("pngs");
    let said = bin()
        .arg("convert")
        .args([inputs.join("toy.svg"), inputs.join("cube.svg")])
        .arg("-o")
        .arg(&pngs)
        .args(["--format", "png", "--width", "64"])
        .output()
        .unwrap();
    assert!(said.status.success());
    assert!(String::from_utf8_lossy(&said.stderr).contains("converted 2 of 2 files"));
    assert!(pngs.join("toy.png").is_file() && pngs.join("cube.png").is_file());
}
