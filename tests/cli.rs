//! The real binary on the bundled examples: every output format, determinism across runs
//! and thread counts, and the demo command.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

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
        let off = gmotion::exporters::raster::compare(&pa, &pb, 8);
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
    for f in ["abstract.gif", "abstract.json", "abstract.svg", "view.html"] {
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
    // The clean SVG renders like the original.
    let again =
        gmotion::exporters::raster::render(&std::fs::read_to_string(d.join("t.svg")).unwrap(), 130)
            .unwrap();
    assert!(gmotion::exporters::raster::compare(&png, &again, 8) < 0.001);
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
    let pieces_line = |out: &str| {
        out.lines()
            .find(|l| l.starts_with("spatial expansion:"))
            .unwrap_or_else(|| panic!("no spatial expansion line in {out}"))
            .to_string()
    };
    let out = run_ok(
        bin()
            .arg("check")
            .arg(g.join("growing_tangle.gm"))
            .arg(g.join("growing_tangle.svg")),
    );
    let line = pieces_line(&out);
    // `disc` is cut into rings and pieces (tagged `ink` and `piece`); `paper` is left alone.
    assert!(!line.contains("disc ×"), "{line}");
    for tag in ["ink ×", "piece ×", "paper ×1"] {
        assert!(line.contains(tag), "{line}");
    }
    assert!(out.contains("spatial rules applied: 3 of 3"), "{out}");
    assert!(out.contains("\nrules applied: 3 of 3"), "{out}");
    assert!(!out.contains("`disc` match no rule"), "{out}");
    let out = run_ok(
        bin()
            .arg("check")
            .arg(g.join("regroup.gm"))
            .arg(g.join("regroup.svg")),
    );
    let line = pieces_line(&out);
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
