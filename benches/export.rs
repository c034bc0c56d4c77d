//! End to end export (issue 17): what `gmotion animate SCENE.svg GRAMMAR.gm -o OUT` does
//! between reading its two files and writing the output's bytes, in process: the SVG
//! imported, the grammar parsed and expanded, the animation written as Lottie JSON
//! (`.json`) or animated SVG (`.svg`, SMIL) text. Targets at the intersections scale
//! (8214 shapes, 8 s at 60 fps): ≤ 0.2 s to Lottie, ≤ 0.15 s to SMIL, whole process.
//!
//! The input is `grammars/intersections.svg` with `grammars/intersections.gm` when both
//! exist, else the generated intersections workload of the engine benchmark (its grid of
//! squares, each filled, written as SVG). Either way the pair is also written to
//! `target/bench-workload/`, so the binary can be timed on the very same files:
//! `gmotion animate target/bench-workload/intersections.svg
//! target/bench-workload/intersections.gm -o x.json`.
//!
//! The `phases` group splits a run: import, expansion, and each export from a built
//! animation. The `process` group is the targets' own measure: the `gmotion` binary run on
//! those files, start to exit, writing its output into a temporary folder (the release
//! build at `target/release/gmotion`, or the one `GMOTION_BIN` names; skipped, saying so,
//! when there is none: `cargo build --release` first).

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use gmotion::engine::{RunOptions, run};
use gmotion::motion::Animation;
use gmotion_import_svg::ImportOptions;
use gmotion_output::Options;

use gmotion_benches as workload;

/// The allocator the `gmotion` binary uses, so the numbers are what the command gets.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The intersections scene as SVG text, and its grammar.
fn input() -> (String, String) {
    let root = workload::repo_root();
    let real = (
        root.join("grammars/intersections.svg"),
        root.join("grammars/intersections.gm"),
    );
    let (svg, gm) = match (
        std::fs::read_to_string(&real.0),
        std::fs::read_to_string(&real.1),
    ) {
        (Ok(svg), Ok(gm)) => {
            eprintln!("input: {} and {}", real.0.display(), real.1.display());
            (svg, gm)
        }
        _ => {
            eprintln!(
                "input: the generated intersections workload ({} not found)",
                real.0.display()
            );
            (generated_svg(), workload::grammar(16, 8.0, 60.0))
        }
    };
    let out = root.join("target/bench-workload");
    let written = std::fs::create_dir_all(&out).and_then(|()| {
        std::fs::write(out.join("intersections.svg"), &svg)?;
        std::fs::write(out.join("intersections.gm"), &gm)
    });
    match written {
        Ok(()) => eprintln!("written to {}", out.display()),
        Err(e) => eprintln!("{}: {e}", out.display()),
    }
    (svg, gm)
}

/// The engine benchmark's grid of 8214 squares over 16 tags, each square filled (the
/// generated scene has no paint, and an SVG importer drops what draws nothing).
fn generated_svg() -> String {
    use std::fmt::Write as _;
    let scene = workload::scene(8214, 16);
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#,
        w = scene.width,
        h = scene.height
    );
    for s in &scene.shapes {
        let b = s.bbox;
        let _ = write!(
            svg,
            "\n<rect data-tag=\"{}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#333\"/>",
            s.tag,
            b.x0,
            b.y0,
            b.width(),
            b.height()
        );
    }
    svg.push_str("\n</svg>\n");
    svg
}

fn import(svg: &str) -> gmotion::scene::Scene {
    gmotion_import_svg::parse(svg, "intersections.svg", &ImportOptions::default())
        .expect("the scene imports")
        .scene
}

fn expand(scene: gmotion::scene::Scene, gm: &str) -> Animation {
    let g = gmotion::grammar::parse(gm).expect("the grammar parses");
    run(scene, &g, &RunOptions::default())
        .expect("the grammar runs")
        .0
}

/// The output's text, as the command makes it for `path` (its extension picks the format).
fn export(anim: &Animation, path: &str) -> String {
    let path = PathBuf::from(path);
    let opts = Options::default();
    let text = if path.extension().is_some_and(|e| e == "json") {
        gmotion_output::lottie_text(anim, None, &[], &path, &opts)
    } else {
        gmotion_output::smil_text(anim, None, &path, &opts)
    };
    text.expect("the animation exports").0
}

fn end_to_end(c: &mut Criterion) {
    let (svg, gm) = input();
    let anim = expand(import(&svg), &gm);
    eprintln!(
        "intersections: {} shapes, {} frames; Lottie {} bytes, SMIL {} bytes",
        anim.scene.shapes.len(),
        anim.frame_count(),
        export(&anim, "x.json").len(),
        export(&anim, "x.svg").len()
    );
    let mut group = c.benchmark_group("export");
    group.sample_size(10);
    for out in ["x.json", "x.svg"] {
        let name = if out.ends_with(".json") {
            "intersections/lottie"
        } else {
            "intersections/smil"
        };
        group.bench_function(name, |b| {
            b.iter(|| black_box(export(&expand(import(&svg), &gm), out).len()))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("phases");
    group.sample_size(10);
    group.bench_function("intersections/import", |b| {
        b.iter(|| black_box(import(&svg)))
    });
    let scene = import(&svg);
    group.bench_function("intersections/expand", |b| {
        b.iter_batched(
            || scene.clone(),
            |s| black_box(expand(s, &gm)),
            criterion::BatchSize::LargeInput,
        )
    });
    group.bench_function("intersections/lottie", |b| {
        b.iter(|| black_box(export(&anim, "x.json").len()))
    });
    group.bench_function("intersections/smil", |b| {
        b.iter(|| black_box(export(&anim, "x.svg").len()))
    });
    group.finish();
}

/// The whole command, as a user runs it: start, import, expansion, export, the atomic
/// write and the exit.
fn process(c: &mut Criterion) {
    let root = workload::repo_root();
    let bin = std::env::var_os("GMOTION_BIN")
        .map_or_else(|| root.join("target/release/gmotion"), PathBuf::from);
    if !bin.is_file() {
        eprintln!(
            "process: skipped, no binary at {} (cargo build --release, or set GMOTION_BIN)",
            bin.display()
        );
        return;
    }
    // The files `input` wrote, which are what the export group measured.
    let _ = input();
    let inputs = root.join("target/bench-workload");
    let out = inputs.join("process");
    if let Err(e) = std::fs::create_dir_all(&out) {
        eprintln!("process: skipped, {}: {e}", out.display());
        return;
    }
    let mut group = c.benchmark_group("process");
    group.sample_size(20);
    for (name, file) in [
        ("intersections/lottie", "x.json"),
        ("intersections/smil", "x.svg"),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let status = std::process::Command::new(&bin)
                    .arg("--quiet")
                    .arg("animate")
                    .arg(inputs.join("intersections.svg"))
                    .arg(inputs.join("intersections.gm"))
                    .arg("-o")
                    .arg(out.join(file))
                    .status()
                    .expect("the binary starts");
                assert!(status.success(), "{} failed: {status}", bin.display());
            })
        });
    }
    group.finish();
}

criterion_group!(benches, end_to_end, process);
criterion_main!(benches);
