//! Helpers shared by the integration tests of gmotion's crates (a dev-dependency of each,
//! never published): scenes and grammars in a line, case folders, bounded child processes,
//! and with the `players` feature the real players as test oracles (the `players` module).
//!
//! The crates' test binaries name it `support` (`use gmotion_testkit as support;` in their
//! `main.rs`), as when these helpers were a module of one test binary.

use std::path::{Path, PathBuf};

use gmotion::color::Color;
use gmotion::engine::RunOptions;
use gmotion::motion::Animation;
use gmotion::scene::{Fill, Scene, SceneBuilder, Stroke};
use gmotion_import_svg::ImportOptions;
use kurbo::{BezPath, Point, Rect, Shape as _};

// The real players (node, Python, Chromium), compiled in by the `players` feature, which
// each crate whose tests use them forwards as its own `players` feature (see
// CONTRIBUTING.md), as is every test that uses them.
#[cfg(feature = "players")]
pub mod players;

/// The tests' temporary folder, `tmp/` in the target directory: where Cargo's
/// `CARGO_TARGET_TMPDIR` points, which it gives to test binaries only, not to a library
/// they use. A test binary runs as `TARGET/PROFILE/deps/NAME`.
pub fn tmp_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    exe.ancestors()
        .nth(3)
        .expect("a test binary sits in TARGET/PROFILE/deps")
        .join("tmp")
}

/// A fresh, empty folder `name` for the tests of `module` under the tests' temporary folder.
pub fn case_dir(module: &str, name: &str) -> PathBuf {
    let d = tmp_dir().join(module).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create the test's folder");
    d
}

/// Runs `cmd` (stdin empty, stdout dropped), killing it past `bound`: its exit code
/// (`None` when killed or ended by a signal), its stderr and the time it took.
pub fn run_bounded(
    cmd: &mut std::process::Command,
    bound: std::time::Duration,
) -> (Option<i32>, String, std::time::Duration) {
    use std::process::Stdio;
    let start = std::time::Instant::now();
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the command starts");
    let mut stderr = child.stderr.take().expect("piped stderr");
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut stderr, &mut s).ok();
        s
    });
    let status = loop {
        if let Some(st) = child.try_wait().expect("wait for the child") {
            break Some(st);
        }
        if start.elapsed() > bound {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    };
    let elapsed = start.elapsed();
    let text = reader.join().unwrap_or_default();
    (status.and_then(|s| s.code()), text, elapsed)
}

/// The repository's root (this crate is `testkit/`, one folder down).
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the testkit crate sits inside the repository")
}

/// A file of `grammars/`.
pub fn grammar_file(name: &str) -> PathBuf {
    root().join("grammars").join(name)
}

/// The files of `dir` ending in `.ext`, sorted; a folder that cannot be read fails the
/// test with `hint` (how to get it).
pub fn files_with_extension(dir: &Path, ext: &str, hint: &str) -> Vec<PathBuf> {
    let entries = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{} not readable ({e}); {hint}", dir.display()));
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        .collect();
    files.sort();
    files
}

/// A path's vertices: the end point of every element (a close adds none).
pub fn vertices(path: &BezPath) -> Vec<Point> {
    path.elements()
        .iter()
        .filter_map(|el| el.end_point())
        .collect()
}

/// The scene of the SVG text `svg`, imported with the default options.
pub fn scene_of(svg: &str) -> Scene {
    gmotion_import_svg::parse(svg, "t.svg", &ImportOptions::default())
        .unwrap()
        .scene
}

/// The fonts vendored for the tests (`tests/fonts`: Noto Sans, Noto Sans Hebrew), so that
/// what a text test counts does not depend on the machine's fonts.
pub fn test_fonts() -> Vec<PathBuf> {
    ["NotoSans-Regular.ttf", "NotoSansHebrew-Regular.ttf"]
        .iter()
        .map(|f| root().join("tests/fonts").join(f))
        .collect()
}

/// The scene of the SVG text `svg`, imported with the default options, its text drawn
/// with [`test_fonts`] (Noto Sans where a family is not found). `name` names the file
/// written in the tests' temporary folder.
pub fn text_scene_of(name: &str, svg: &str) -> Scene {
    let file = tmp_dir().join(format!("{name}.svg"));
    std::fs::create_dir_all(tmp_dir()).unwrap();
    std::fs::write(&file, svg).unwrap();
    let policy = gmotion_import_svg::Policy {
        fonts: gmotion_import_svg::fonts::FontOptions {
            dirs: Vec::new(),
            files: test_fonts(),
            default_family: Some("Noto Sans".into()),
        },
        ..gmotion_import_svg::Policy::default()
    };
    gmotion_import_svg::load_with(&file, &ImportOptions::default(), &policy)
        .unwrap()
        .scene
}

/// The animation `grammar` makes of `scene` with the default options; a grammar or run
/// error panics with its message.
pub fn run_grammar(scene: Scene, grammar: &str) -> Animation {
    let g = gmotion::grammar::parse(grammar)
        .unwrap_or_else(|d| panic!("{}", d.render("case.gm", grammar)));
    gmotion::engine::run(scene, &g, &RunOptions::default())
        .unwrap_or_else(|e| panic!("{e}\n{grammar}"))
        .0
}

/// Where shape `shape`'s centroid is at time `t`.
pub fn centre_at(a: &Animation, shape: usize, t: f64) -> Point {
    a.tracks[shape].transform_at(t) * a.scene.shapes[shape].centroid
}

/// Whether two points are the same up to rounding (1e-6 canvas units).
pub fn same_point(a: Point, b: Point) -> bool {
    (a - b).hypot() < 1e-6
}

/// A `width` × `height` scene of axis-aligned squares, (tag, centre, side) each, filled
/// blue-grey and, when `stroked`, outlined in black 2 px wide.
pub fn squares(
    (width, height): (f64, f64),
    items: &[(&str, (f64, f64), f64)],
    stroked: bool,
) -> Scene {
    let mut b = SceneBuilder::new(width, height);
    for (tag, (x, y), side) in items {
        let rect = Rect::from_center_size((*x, *y), (*side, *side));
        b = b.path(
            tag,
            rect.to_path(0.1),
            Some(Fill::solid(Color::rgb(0.2, 0.4, 0.6))),
            stroked.then(|| Stroke::solid(Color::BLACK, 2.0)),
        );
    }
    b.build()
}
