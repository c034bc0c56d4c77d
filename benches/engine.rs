//! Expansion + evaluation of every frame, at the scales of gMotion's Table 1 and beyond.
//!
//! The paper reports 0.04 s for "teaser" (208 shapes, 44 rules, 60 steps, 6 s) and 22 s for
//! "intersections" (8214 shapes, 105 rules, 161 steps, 8 s); the scaling group shows cost
//! per shape stays flat from 1k to 1M shapes. The grammars are generated so their sizes
//! meet or exceed the paper's; `cargo bench --bench engine` prints their statistics.

use std::hint::black_box;

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gmotion::engine::{RunOptions, run};
use gmotion::motion::Animation;
use gmotion::scene::Scene;
use rayon::prelude::*;

mod workload;
use workload::{grammar, scene};

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

fn table1(c: &mut Criterion) {
    let cases = [
        ("teaser", 208usize, 6usize, 6.0, 30.0),
        ("intersections", 8214, 16, 8.0, 60.0),
    ];
    let mut group = c.benchmark_group("table1");
    group.sample_size(10);
    for (name, n, tags, dur, fps) in cases {
        let s = scene(n, tags);
        let src = grammar(tags, dur, fps);
        let rules = gmotion::grammar::parse(&src).expect("parses").rules.len();
        let steps = full_run(s.clone(), &src);
        eprintln!(
            "{name}: {n} shapes, {rules} rules, {steps} expansion steps, {dur} s at {fps} fps"
        );
        group.bench_function(name, |b| {
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

/// The two halves of a table-1 run measured apart: parsing + expansion + compilation into
/// tracks, then evaluating every frame of the finished animation (which includes building
/// its sampler, also measured alone).
fn phases(c: &mut Criterion) {
    let mut group = c.benchmark_group("phases");
    group.sample_size(10);
    for (name, n, tags, dur, fps) in [
        ("teaser", 208usize, 6usize, 6.0, 30.0),
        ("intersections", 8214, 16, 8.0, 60.0),
    ] {
        let s = scene(n, tags);
        let src = grammar(tags, dur, fps);
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
