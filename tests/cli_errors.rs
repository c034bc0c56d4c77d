//! Bad input, table-driven, through the real binary: every case exits with status 1 (not a
//! panic's 101), says what and where, and leaves no output file behind.

use std::path::{Path, PathBuf};
use std::process::Command;

const SCENE: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="80">
  <rect data-tag="s" x="10" y="10" width="20" height="20" fill="red"/>
  <circle data-tag="c" cx="60" cy="40" r="10" fill="blue"/>
</svg>
"#;

const GOOD: &str = "duration 1s\nanimate(affine, world, 0, translate(10, 0)) : [all, s] -> [m]\n";

struct Case {
    name: &'static str,
    /// Files to create: (name, contents).
    files: Vec<(&'static str, Vec<u8>)>,
    /// Arguments; `{d}` is replaced by the case directory.
    args: Vec<&'static str>,
    /// Substrings the error must contain.
    expect: Vec<&'static str>,
    /// Output that must not exist afterwards (relative to the case directory).
    output: &'static str,
}

fn case(name: &'static str, grammar: &str, expect: &[&'static str]) -> Case {
    Case {
        name,
        files: vec![
            ("scene.svg", SCENE.into()),
            ("g.gm", grammar.as_bytes().to_vec()),
        ],
        args: vec![
            "animate",
            "{d}/scene.svg",
            "{d}/g.gm",
            "-o",
            "{d}/out.json",
            "-o",
            "{d}/out.png",
        ],
        expect: expect.to_vec(),
        output: "out.png",
    }
}

fn scene_case(name: &'static str, svg: &[u8], expect: &[&'static str]) -> Case {
    Case {
        name,
        files: vec![("scene.svg", svg.to_vec()), ("g.gm", GOOD.into())],
        args: vec!["animate", "{d}/scene.svg", "{d}/g.gm", "-o", "{d}/out.png"],
        expect: expect.to_vec(),
        output: "out.png",
    }
}

fn args_case(
    name: &'static str,
    args: &[&'static str],
    expect: &[&'static str],
    output: &'static str,
) -> Case {
    Case {
        name,
        files: vec![("scene.svg", SCENE.into()), ("g.gm", GOOD.into())],
        args: args.to_vec(),
        expect: expect.to_vec(),
        output,
    }
}

fn cases() -> Vec<Case> {
    vec![
        scene_case("malformed svg", b"<svg xmlns='http://www.w3.org/2000/svg'>\n  <rect width='10'\n</svg>", &["scene.svg", "3:"]),
        scene_case("empty svg file", b"", &["scene.svg"]),
        scene_case("not an svg", b"hello, I am text", &["scene.svg"]),
        scene_case("svg without shapes", b"<svg xmlns='http://www.w3.org/2000/svg' width='10' height='10'/>", &["no visible shapes"]),
        scene_case("zero-size svg", b"<svg xmlns='http://www.w3.org/2000/svg' width='0' height='10'><rect width='5' height='5'/></svg>", &["scene.svg"]),
        case("syntax error", "duration 1s\nanimate(affine, world, 0, translate(1, 0)) : [all, s] [m]\n", &["g.gm:2:", "^", "->"]),
        case("unknown operator", "duration 1s\nwiggle(3) : [all, s] -> [m]\n", &["g.gm:2:1", "unknown", "wiggle"]),
        case("unknown shape tag", "duration 1s\nanimate(affine, world, 0, translate(1, 0)) : [all, square] -> [m]\n", &["g.gm:2:", "square"]),
        case("unknown slice tag", "duration 1s\nanimate(affine, world, 0, translate(1, 0)) : [a1l, s] -> [m]\n", &["g.gm:2:", "a1l"]),
        case("fractions do not sum to 1", "duration 1s\ntimesplit(0.5, 0.6) : [all, s] -> [a, b]\n", &["g.gm:2:", "sum to 1"]),
        case("zero fraction", "duration 1s\ntimesplit(0, 1) : [all, s] -> [a, b]\n", &["g.gm:2:", "greater than zero"]),
        case("zero duration", "duration 0s\nanimate(affine, world, 0, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:1:", "duration"]),
        case("negative duration", "duration -2s\nanimate(affine, world, 0, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:1:", "duration"]),
        case("nan value", "duration 1s\nanimate(affine, world, 0, translate(sqrt(-1), 0)) : [all, s] -> [m]\n", &["g.gm:2:37", "square root"]),
        case("infinite value", "duration 1s\nanimate(affine, world, 0, translate(1 / 0, 0)) : [all, s] -> [m]\n", &["g.gm:2:"]),
        case("overflowing literal", "duration 1s\nanimate(affine, world, 0, translate(1e999, 0)) : [all, s] -> [m]\n", &["g.gm:2:"]),
        case(
            "never terminates",
            "duration 1s\nmax_steps 40\ntimesplit(0.5, 0.5) : [all, s] -> [x, z]\nanimate(opacity, local, 0, 0.5) : [x, s] -> [y]\nanimate(opacity, local, 0, 1) : [y, s] -> [x]\n",
            &["did not terminate within 40", "line 4", "line 5"],
        ),
        case(
            "splits its own output forever",
            "duration 1s\ntimesplit(0.5, 0.5) : [all, s] -> [x, x]\ntimesplit(0.5, 0.5) : [x, s] -> [x, x]\n",
            &["g.gm:3:1", "slices (at most 10000)", "line 3"],
        ),
        case(
            "bad value before a cycle",
            "duration 1s\nanimate(opacity, local, 0, 2) : [all, s] -> [x]\nanimate(opacity, local, 0, 0.5) : [x, s] -> [x]\n",
            &["g.gm:2:", "[0, 1]"],
        ),
        case("negative offset", "duration 1s\nanimate(affine, world, -1, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:2:", "negative"]),
        case("opacity out of range", "duration 1s\nanimate(opacity, local, 0, 3) : [all, s] -> [m]\n", &["g.gm:2:", "[0, 1]"]),
        case("bad colour", "duration 1s\nanimate(fill, local, 0, 12) : [all, s] -> [m]\n", &["g.gm:2:", "colour"]),
        case("bad path data", "duration 1s\nanimate(path, world, 0, \"M 0 0 Q\") : [all, s] -> [m]\n", &["g.gm:2:", "path"]),
        case("wrong argument count", "duration 1s\nanimate(affine, world, translate(1, 0)) : [all, s] -> [m]\n", &["g.gm:2:", "4 arguments"]),
        case("split outputs mismatch", "duration 1s\ntimesplit(0.5, 0.5) : [all, s] -> [a, b, c]\n", &["g.gm:2:", "output"]),
        case("unknown directive", "durration 1s\n", &["g.gm:1:1", "durration"]),
        case("unknown easing", "duration 1s\nanimate(affine, world, 0, translate(1, 0), ease=wobbly) : [all, s] -> [m]\n", &["g.gm:2:", "wobbly"]),
        case("unknown animation type", "duration 1s\nanimate(spin, world, 0, 1) : [all, s] -> [m]\n", &["g.gm:2:", "animation type"]),
        Case {
            name: "grammar not utf-8",
            files: vec![("scene.svg", SCENE.into()), ("g.gm", vec![b'd', 0xff, 0xfe, b'\n'])],
            args: vec!["animate", "{d}/scene.svg", "{d}/g.gm", "-o", "{d}/out.png"],
            expect: vec!["g.gm", "UTF-8"],
            output: "out.png",
        },
        args_case("missing grammar", &["animate", "{d}/scene.svg", "{d}/nope.gm", "-o", "{d}/out.png"], &["nope.gm"], "out.png"),
        args_case("missing scene", &["animate", "{d}/nope.svg", "{d}/g.gm", "-o", "{d}/out.png"], &["nope.svg"], "out.png"),
        args_case("scene is a directory", &["animate", "{d}", "{d}/g.gm", "-o", "{d}/out.png"], &["{d}"], "out.png"),
        args_case("unwritable output", &["animate", "{d}/scene.svg", "{d}/g.gm", "-o", "{d}/no/such/dir/out.png"], &["out.png", "does not exist"], "no"),
        args_case("unknown output format", &["animate", "{d}/scene.svg", "{d}/g.gm", "-o", "{d}/out.xyz"], &["out.xyz", ".xyz"], "out.xyz"),
        args_case("zero width", &["animate", "{d}/scene.svg", "{d}/g.gm", "-o", "{d}/out.png", "--width", "0"], &["width"], "out.png"),
        args_case("time outside animation", &["animate", "{d}/scene.svg", "{d}/g.gm", "-o", "{d}/out.png", "--time", "7"], &["--time"], "out.png"),
        args_case("zero fps", &["animate", "{d}/scene.svg", "{d}/g.gm", "-o", "{d}/out.gif", "--fps", "0"], &["fps"], "out.gif"),
        args_case("bad tolerance", &["animate", "{d}/scene.svg", "{d}/g.gm", "-o", "{d}/out.json", "--tolerance", "0"], &["tolerance"], "out.json"),
        args_case("convert missing file", &["convert", "{d}/nope.svg", "-o", "{d}/out.png"], &["nope.svg"], "out.png"),
        args_case("convert to a frames directory", &["convert", "{d}/scene.svg", "-o", "{d}/frames"], &["still"], "frames"),
        args_case("check missing grammar", &["check", "{d}/nope.gm"], &["nope.gm"], "nope.gm"),
    ]
}

fn case_dir(i: usize) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gmotion-cli-errors-{}-{i}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn bad_input_is_reported_cleanly() {
    let bin = env!("CARGO_BIN_EXE_gmotion");
    let all = cases();
    assert!(all.len() >= 25);
    let mut failures = Vec::new();
    for (i, c) in all.iter().enumerate() {
        let dir = case_dir(i);
        for (name, bytes) in &c.files {
            std::fs::write(dir.join(name), bytes).unwrap();
        }
        let d = dir.display().to_string();
        let args: Vec<String> = c.args.iter().map(|a| a.replace("{d}", &d)).collect();
        let out = Command::new(bin).args(&args).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        let code = out.status.code();
        let mut problems = Vec::new();
        if code != Some(1) && code != Some(2) {
            problems.push(format!(
                "exit status {code:?} (1 = error, 2 = usage; anything else is a crash)"
            ));
        }
        for e in &c.expect {
            let e = e.replace("{d}", &d);
            if !stderr.contains(&e) {
                problems.push(format!("message lacks `{e}`"));
            }
        }
        if stderr.contains("panicked") {
            problems.push("panicked".into());
        }
        let leftover = Path::new(&dir).join(c.output);
        let expected_files: Vec<_> = c.files.iter().map(|f| f.0).collect();
        if leftover.exists() && !expected_files.contains(&c.output) {
            problems.push(format!("left {} behind", leftover.display()));
        }
        let stray: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| !expected_files.contains(&n.as_str()))
            .collect();
        if !stray.is_empty() {
            problems.push(format!("stray files {stray:?}"));
        }
        if !problems.is_empty() {
            failures.push(format!(
                "{}: {}\n--- stderr ---\n{stderr}",
                c.name,
                problems.join("; ")
            ));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n\n{}",
        failures.len(),
        all.len(),
        failures.join("\n\n")
    );
}
