//! dotLottie (`.lottie`) out and in, through the real binary: what `animate`, `convert` and
//! `variations` write is a zip holding the manifest and the animations (read back here with
//! the zip crate, not gmotion's reader), reads back as the scene it was written from, keeps
//! the other animations and the themes of a package a grammar ran on one animation of, and
//! bad packages are refused with nothing written. With the players: LottieFiles'
//! dotlottie-web plays what gmotion wrote like gmotion's own render, and dotlottie-js opens
//! it.

use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

fn out_dir(name: &str) -> PathBuf {
    crate::support::case_dir("dotlottie", name)
}

fn root() -> &'static Path {
    crate::support::root()
}

/// Runs `cmd`; returns (success, stderr).
fn run(cmd: &mut Command) -> (bool, String) {
    let out = cmd.output().expect("run gmotion");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Every file of the zip at `path`, by name.
fn unzip(path: &Path) -> BTreeMap<String, Vec<u8>> {
    let bytes = std::fs::read(path).expect("read the package");
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).expect("a zip archive");
    (0..zip.len())
        .map(|i| {
            let mut f = zip.by_index(i).expect("a file of the zip");
            let mut data = Vec::new();
            f.read_to_end(&mut data).expect("read a file of the zip");
            (f.name().expect("a UTF-8 name").to_string(), data)
        })
        .collect()
}

/// A zip of `files` (name, bytes), as any zip writer makes it.
fn zip_of(files: &[(&str, &[u8])]) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    for (name, data) in files {
        zip.start_file(*name, opts).expect("start a file");
        zip.write_all(data).expect("write a file");
    }
    zip.finish().expect("finish the zip").into_inner()
}

fn json(bytes: &[u8]) -> Value {
    serde_json::from_slice(bytes).expect("JSON")
}

#[test]
fn animate_writes_a_version_2_package_holding_the_lottie() {
    let dir = out_dir("animate");
    let (gm, lottie, plain) = (
        root().join("grammars/toy.gm"),
        dir.join("toy.lottie"),
        dir.join("toy.json"),
    );
    for out in [&lottie, &plain] {
        let (ok, err) = run(bin().arg("animate").arg(&gm).arg("-o").arg(out));
        assert!(ok, "{err}");
    }
    let files = unzip(&lottie);
    assert_eq!(
        files.keys().collect::<Vec<_>>(),
        ["a/toy.json", "manifest.json"],
        "the package holds the manifest and the animation"
    );
    let manifest = json(&files["manifest.json"]);
    assert_eq!(manifest["version"], "2");
    assert_eq!(manifest["animations"][0]["id"], "toy");
    assert_eq!(manifest["initial"]["animation"], "toy");
    // The animation is the Lottie `-o toy.json` writes, byte for byte.
    assert_eq!(
        files["a/toy.json"],
        std::fs::read(&plain).expect("read toy.json")
    );
}

#[test]
fn a_package_reads_back_as_the_scene_it_was_written_from() {
    let dir = out_dir("read_back");
    let (gm, lottie, plain) = (
        root().join("grammars/toy.gm"),
        dir.join("toy.lottie"),
        dir.join("toy.json"),
    );
    for out in [&lottie, &plain] {
        let (ok, err) = run(bin().arg("animate").arg(&gm).arg("-o").arg(out));
        assert!(ok, "{err}");
    }
    for t in ["0", "2.5"] {
        let (from_package, from_json) =
            (dir.join(format!("p{t}.png")), dir.join(format!("j{t}.png")));
        for (src, out) in [(&lottie, &from_package), (&plain, &from_json)] {
            let (ok, err) = run(bin()
                .arg("convert")
                .arg(src)
                .arg("-o")
                .arg(out)
                .args(["--time", t]));
            assert!(ok, "{err}");
        }
        assert_eq!(
            std::fs::read(&from_package).unwrap(),
            std::fs::read(&from_json).unwrap(),
            "frame at {t}s of the package and of the JSON differ"
        );
    }
    // `check --shapes` names the package's animations.
    let out = bin()
        .args(["check", "--shapes"])
        .arg(&lottie)
        .output()
        .expect("run gmotion");
    let listed = String::from_utf8_lossy(&out.stdout);
    assert!(
        listed.contains("dotLottie package: animations `toy` (read)"),
        "{listed}"
    );
}

/// A package of two animations (an empty one, and the toy example as `animate` writes it
/// to Lottie), a theme and a state machine, as another tool would write it: `initial`
/// names the empty one.
fn two_animation_package(dir: &Path) -> PathBuf {
    let toy = dir.join("toy-anim.json");
    let (ok, err) = run(bin()
        .arg("animate")
        .arg(root().join("grammars/toy.gm"))
        .arg("-o")
        .arg(&toy));
    assert!(ok, "{err}");
    let toy = std::fs::read(&toy).unwrap();
    let other = br#"{"v":"5.7.0","fr":30,"ip":0,"op":30,"w":100,"h":100,"nm":"other","layers":[]}"#;
    let theme = br#"{"rules":[{"id":"bg.fill","type":"Color","value":[0,0,0,1]}]}"#;
    let manifest = br#"{"version":"2","generator":"another tool","animations":[{"id":"other"},{"id":"toy"}],"themes":[{"id":"dark"}],"initial":{"animation":"other"}}"#;
    let path = dir.join("two.lottie");
    std::fs::write(
        &path,
        zip_of(&[
            ("manifest.json", manifest),
            ("a/other.json", other),
            ("a/toy.json", &toy),
            ("t/dark.json", theme),
            ("s/machine.json", b"{}"),
        ]),
    )
    .unwrap();
    path
}

#[test]
fn a_grammar_on_one_animation_keeps_the_others_and_the_themes() {
    let dir = out_dir("keeps_others");
    let package = two_animation_package(&dir);
    let out = dir.join("moved.lottie");
    let plain = dir.join("moved.json");
    let gm = root().join("grammars/toy.gm");
    let (ok, err) = run(bin()
        .arg("animate")
        .arg(&package)
        .arg(&gm)
        .args(["--animation", "toy", "-o"])
        .arg(&out));
    assert!(ok, "{err}");
    // The same grammar on the animation given as plain JSON writes the same Lottie.
    let toy_json = dir.join("toy.json");
    std::fs::write(&toy_json, &unzip(&package)["a/toy.json"]).unwrap();
    let (ok, err) = run(bin()
        .arg("animate")
        .arg(&toy_json)
        .arg(&gm)
        .arg("-o")
        .arg(&plain));
    assert!(ok, "{err}");
    let before = unzip(&package);
    let after = unzip(&out);
    assert_eq!(after["a/toy.json"], std::fs::read(&plain).unwrap());
    for kept in ["a/other.json", "t/dark.json", "s/machine.json"] {
        assert_eq!(after[kept], before[kept], "{kept} is kept as it was");
    }
    let manifest = json(&after["manifest.json"]);
    assert_eq!(manifest["animations"][0]["id"], "other");
    assert_eq!(manifest["animations"][1]["id"], "toy");
    assert_eq!(manifest["themes"][0]["id"], "dark");
    assert_eq!(manifest["initial"]["animation"], "other");
    // Without --animation, the package's initial one is read: `other` has no shapes.
    let (ok, err) = run(bin()
        .arg("animate")
        .arg(&package)
        .arg(&gm)
        .arg("-o")
        .arg(dir.join("x.lottie")));
    assert!(!ok && err.contains("no visible shapes"), "{err}");
}

#[test]
fn variations_write_one_animation_per_seed() {
    let dir = out_dir("variations");
    let out = dir.join("set.lottie");
    let (ok, err) = run(bin()
        .arg("variations")
        .arg(root().join("grammars/variations.gm"))
        .args(["--count", "3", "--seed-start", "7", "-o"])
        .arg(&out));
    assert!(ok, "{err}");
    let files = unzip(&out);
    let manifest = json(&files["manifest.json"]);
    let ids: Vec<&str> = manifest["animations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, ["seed_7", "seed_8", "seed_9"]);
    // Different seeds, different animations (variations.gm chooses among rules at random).
    assert!(
        files["a/seed_7.json"] != files["a/seed_8.json"],
        "seeds 7 and 8 wrote the same animation"
    );
}

#[test]
fn bad_packages_are_refused_with_nothing_written() {
    let dir = out_dir("bad");
    let gm = root().join("grammars/toy.gm");
    let toy = std::fs::read(root().join("grammars/toy.svg")).unwrap();
    let bomb = {
        let big = format!(r#"{{"pad":"{}","layers":[]}}"#, "0".repeat(4 << 20));
        zip_of(&[
            (
                "manifest.json",
                br#"{"version":"2","animations":[{"id":"a"}]}"#,
            ),
            ("a/a.json", big.as_bytes()),
        ])
    };
    let cases: Vec<(&str, Vec<u8>, &[&str], &str)> = vec![
        ("not_zip", toy.clone(), &[], "not a dotLottie file (a .lottie is a zip archive)"),
        (
            "no_manifest",
            zip_of(&[("a/a.json", b"{}")]),
            &[],
            "manifest.json: missing",
        ),
        (
            "missing_animation",
            zip_of(&[("manifest.json", br#"{"version":"2","animations":[{"id":"gone"}]}"#)]),
            &[],
            "the manifest names animation `gone`, but the package has no `a/gone.json`",
        ),
        (
            "missing_image",
            zip_of(&[
                ("manifest.json", br#"{"version":"2","animations":[{"id":"a"}]}"#),
                (
                    "a/a.json",
                    br#"{"v":"5.7.0","fr":30,"ip":0,"op":30,"w":10,"h":10,"assets":[{"id":"i","w":1,"h":1,"u":"/i/","p":"x.png","e":0}],"layers":[]}"#,
                ),
            ]),
            &[],
            "animation `a` shows image `x.png`, which the package does not hold",
        ),
        (
            "bomb",
            bomb,
            &["--limit", "input-bytes=1000000"],
            "decompresses past the limit of 1000000 bytes",
        ),
        (
            "unknown_animation",
            zip_of(&[
                ("manifest.json", br#"{"version":"2","animations":[{"id":"a"}]}"#),
                ("a/a.json", br#"{"v":"5.7.0","fr":30,"ip":0,"op":30,"w":10,"h":10,"layers":[]}"#),
            ]),
            &["--animation", "b"],
            "no animation `b` in the package; it holds `a`",
        ),
    ];
    for (name, bytes, flags, expected) in cases {
        let input = dir.join(format!("{name}.lottie"));
        std::fs::write(&input, bytes).unwrap();
        let out = dir.join(format!("{name}-out.lottie"));
        let (ok, err) = run(bin()
            .arg("animate")
            .arg(&input)
            .arg(&gm)
            .args(flags)
            .arg("-o")
            .arg(&out));
        assert!(!ok, "{name}: accepted");
        assert!(
            err.contains(expected) && err.contains(&input.display().to_string()),
            "{name}: {err}"
        );
        assert!(!out.exists(), "{name}: an output was left");
    }
    // --animation on a scene that is not a package is an error too.
    let (ok, err) = run(bin()
        .arg("animate")
        .arg(&gm)
        .args(["--animation", "a", "-o"])
        .arg(dir.join("svg.lottie")));
    assert!(
        !ok && err.contains("--animation picks an animation of a dotLottie"),
        "{err}"
    );
}

/// dotlottie-web draws what `animate -o X.lottie` wrote like gmotion's own render of the
/// same frames, and plays the animation `--animation` would read from a package of several.
#[cfg(feature = "players")]
#[test]
fn dotlottie_web_plays_the_package_like_the_model() {
    use gmotion_export_raster::{Pixmap, compare};
    let dir = out_dir("dotlottie_web");
    let lottie = dir.join("toy.lottie");
    let gm = root().join("grammars/toy.gm");
    let (ok, err) = run(bin().arg("animate").arg(&gm).arg("-o").arg(&lottie));
    assert!(ok, "{err}");
    let frames = [0u32, 20, 45, 90, 135, 179];
    let (width, height) = (520u32, 320u32);
    let mut jobs = Vec::new();
    let player_frames: Vec<PathBuf> = frames
        .iter()
        .map(|f| dir.join(format!("dl-{f}.png")))
        .collect();
    jobs.push(serde_json::json!({
        "lottie": lottie, "width": width, "height": height, "frames": frames,
        "out": player_frames,
    }));
    // A package of several: the animation asked for is the one played.
    let package = two_animation_package(&dir);
    jobs.push(serde_json::json!({
        "lottie": package, "animation": "toy", "width": width, "height": height,
        "frames": [0], "out": [dir.join("two-toy.png")],
    }));
    let jobs_path = dir.join("jobs.json");
    std::fs::write(&jobs_path, serde_json::to_string(&jobs).unwrap()).unwrap();
    let out = Command::new("node")
        .arg(root().join("tests/conformance/dotlottie_web.mjs"))
        .arg(&jobs_path)
        .output()
        .expect("run node");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "dotlottie-web failed: {}{stdout}",
        String::from_utf8_lossy(&out.stderr)
    );
    let read: Vec<Value> = stdout.lines().map(|l| json(l.as_bytes())).collect();
    assert_eq!(read[0]["totalFrames"], 180);
    assert_eq!(read[1]["manifest"]["animations"][1]["id"], "toy");
    let mut failures = Vec::new();
    for (f, got) in frames.iter().zip(&player_frames) {
        let model = dir.join(format!("model-{f}.png"));
        let (ok, err) = run(bin()
            .arg("animate")
            .arg(&gm)
            .arg("-o")
            .arg(&model)
            .args(["--time", &format!("{}", f64::from(*f) / 30.0)]));
        assert!(ok, "{err}");
        let (model, got) = (
            Pixmap::load_png(&model).expect("the model frame"),
            Pixmap::load_png(got).expect("the player's frame"),
        );
        let off = compare(&model, &got, 32);
        if off > 0.005 {
            failures.push(format!("frame {f}: {:.2}% off", off * 100.0));
        }
    }
    // The toy animation, picked out of the package of two, is drawn too.
    let off = compare(
        &Pixmap::load_png(dir.join("model-0.png")).unwrap(),
        &Pixmap::load_png(dir.join("two-toy.png")).unwrap(),
        32,
    );
    if off > 0.005 {
        failures.push(format!(
            "`toy` of the package of two: {:.2}% off",
            off * 100.0
        ));
    }
    assert!(
        failures.is_empty(),
        "files in {}:\n{}",
        dir.display(),
        failures.join("\n")
    );
}

/// dotlottie-js, LottieFiles' library for reading and making packages, opens what
/// `variations -o X.lottie` wrote and finds every animation whole.
#[cfg(feature = "players")]
#[test]
fn dotlottie_js_opens_the_package() {
    let dir = out_dir("dotlottie_js");
    let out = dir.join("set.lottie");
    let (ok, err) = run(bin()
        .arg("variations")
        .arg(root().join("grammars/toy.gm"))
        .args(["--count", "4", "-o"])
        .arg(&out));
    assert!(ok, "{err}");
    let read = Command::new("node")
        .arg(root().join("tests/conformance/dotlottie_js.mjs"))
        .arg(&out)
        .output()
        .expect("run node");
    assert!(
        read.status.success(),
        "{}",
        String::from_utf8_lossy(&read.stderr)
    );
    let got = json(&read.stdout);
    assert_eq!(got["version"], "2");
    let animations = got["animations"].as_array().unwrap();
    assert_eq!(animations.len(), 4);
    for (i, a) in animations.iter().enumerate() {
        assert_eq!(a["id"], format!("seed_{i}"));
        assert_eq!(
            (a["w"].as_f64(), a["h"].as_f64(), a["op"].as_f64()),
            (Some(520.0), Some(320.0), Some(180.0))
        );
        assert_eq!(a["layers"], 6);
    }
}
