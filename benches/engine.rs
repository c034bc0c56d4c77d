//! Expansion + evaluation of every frame of gMotion's Table 1 animations, and beyond.
//!
//! The `table1` group runs the eight example files that re-create the paper's Table 1
//! (`grammars/teaser.gm` … `grammars/intersections.gm`, listed in `workload/table1.rs`)
//! and prints each one's counts next to the paper's before timing it; `phases` splits the
//! teaser and intersections runs into parse, expansion and evaluation; the scaling group,
//! on a generated grammar and grid, shows the cost per shape from 1k to 1M shapes.

use std::hint::black_box;

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gmotion::engine::{RunOptions, run};
use gmotion::motion::Animation;
use gmotion::scene::Scene;
use rayon::prelude::*;

use gmotion_benches::table1::TABLE1;
use gmotion_benches::{grammar, repo_root, scene};

/// The allocator the `gmotion` binary uses, so the numbers are what the command gets.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Evaluates every frame: the frames split into a few runs per thread (so a thread slowed
/// by the host can hand runs over), each played forward by its own playhead, the way a
/// renderer or exporter walks them.
fn evaluate_all(anim: &Animation) {
    let sampler = anim.sampler();
    let frames = anim.frame_count();
    let runs = (4 * rayon::current_num_threads()).min(frames);
    (0..runs).into_par_iter().for_each(|r| {
        let mut head = sampler.playhead();
        for i in r * frames / runs..(r + 1) * frames / runs {
            black_box(head.seek(anim.frame_time(i)));
        }
    });
}

/// Parses, expands and evaluates every frame; returns steps for the printed statistics.
/// Takes the scene as the engine does (the command moves the imported scene in); the
/// benchmarks clone it outside the timed part.
fn full_run(scene: Scene, src: &str) -> usize {
    let g = gmotion::grammar::parse(src).expect("bench grammar parses");
    let (anim, stats) = run(scene, &g, &RunOptions::default()).expect("bench grammar runs");
    evaluate_all(&anim);
    stats.steps
}

/// An example of `grammars/`: its scene (imported, as the command does) and its grammar's
/// text.
fn example(file: &str) -> (Scene, String) {
    let dir = repo_root().join("grammars");
    let scene = gmotion_import_svg::load(
        &dir.join(format!("{file}.svg")),
        &gmotion_import_svg::ImportOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{file}.svg: {e}"))
    .scene;
    let src = std::fs::read_to_string(dir.join(format!("{file}.gm")))
        .unwrap_or_else(|e| panic!("{file}.gm: {e}"));
    (scene, src)
}

fn table1(c: &mut Criterion) {
    let mut group = c.benchmark_group("table1");
    group.sample_size(10);
    for row in &TABLE1 {
        let (s, src) = example(row.file);
        let g = gmotion::grammar::parse(&src).expect("parses");
        let settings = gmotion::engine::settings::from_grammar(&g).expect("settings");
        let steps = full_run(s.clone(), &src);
        eprintln!(
            "{}: {} rules, {} shapes besides the background, {} s at {} fps, {steps} steps \
             (paper's {}: {} rules, {} shapes, {} s, {} steps, {} s to expand and evaluate)",
            row.file,
            g.rules.len(),
            s.shapes.len() - 1,
            settings.duration,
            settings.fps,
            row.paper_name,
            row.rules,
            row.shapes,
            row.duration,
            row.steps,
            row.seconds,
        );
        group.bench_function(row.file, |b| {
            b.iter_batched(|| s.clone(), |s| full_run(s, &src), BatchSize::LargeInput)
        });
    }
    group.finish();
}

fn scaling(c: &mut Criterion) {
    let mut group = c.benchmark_group("scaling");
    group.sample_size(10);
    let src = grammar(10, 2.0, 30.0);
    for n in [1_000usize, 10_000, 100_000, 1_000_000] {
        // Built on first use, so a filtered run (`cargo bench -- phases`) does not spend
        // seconds and gigabytes making the large scenes (nor profiles of it show them).
        let mut s = None;
        group.throughput(Throughput::Elements(n as u64));
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            let s = s.get_or_insert_with(|| scene(n, 10));
            b.iter_batched(|| s.clone(), |s| full_run(s, &src), BatchSize::LargeInput)
        });
    }
    group.finish();
}

/// The two halves of a table-1 run (teaser and intersections) measured apart: parsing + expansion + compilation into
/// tracks, then evaluating every frame of the finished animation (which includes building
/// its sampler, also measured alone).
fn phases(c: &mut Criterion) {
    let mut group = c.benchmark_group("phases");
    group.sample_size(10);
    for name in ["teaser", "intersections"] {
        let (s, src) = example(name);
        let g = gmotion::grammar::parse(&src).expect("parses");
        group.bench_function(format!("{name}/parse"), |b| {
            b.iter(|| gmotion::grammar::parse(black_box(&src)).expect("parses"))
        });
        group.bench_function(format!("{name}/expand"), |b| {
            b.iter_batched(
                || s.clone(),
                |s| run(s, &g, &RunOptions::default()).expect("runs"),
                BatchSize::LargeInput,
            )
        });
        let (anim, _) = run(s.clone(), &g, &RunOptions::default()).expect("runs");
        group.bench_function(format!("{name}/evaluate"), |b| {
            b.iter(|| evaluate_all(&anim))
        });
        group.bench_function(format!("{name}/sampler"), |b| {
            b.iter(|| black_box(anim.sampler()))
        });
    }
    group.finish();
}

criterion_group!(benches, table1, phases, scaling);
criterion_main!(benches);
