//! The studio's edit loop (issue 16): `PUT /api/grammar` → the new Lottie ready, in process
//! (`Live::set_text` then `Live::lottie`, what the two requests run), at the scales of
//! gMotion's Table 1: teaser (208 shapes) and intersections (8214 shapes). Targets: ≤ 30 ms
//! and ≤ 300 ms. Each iteration sends a grammar that differs from the last one, so every
//! edit rebuilds.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use gmotion::engine::RunOptions;
use gmotion_studio::{Config, Live};

#[path = "../../benches/workload/mod.rs"]
mod workload;

/// The allocator the `gmotion` binary uses, so the numbers are what the command gets.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn put_then_lottie(c: &mut Criterion) {
    let cases = [
        ("teaser", 208usize, 6usize, 6.0, 30.0),
        ("intersections", 8214, 16, 8.0, 60.0),
    ];
    let dir = std::env::temp_dir().join(format!("gmotion-studio-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let mut group = c.benchmark_group("studio_put");
    group.sample_size(10);
    for (name, n, tags, dur, fps) in cases {
        let src = workload::grammar(tags, dur, fps);
        let path = dir.join(format!("{name}.gm"));
        std::fs::write(&path, &src).expect("the grammar file");
        let live = Live::new(Config {
            grammar_path: path,
            scene: workload::scene(n, tags),
            source: None,
            loader: None,
            run: RunOptions::default(),
            port: 0,
        })
        .expect("the studio state");
        // Two edits of one number, sent in turn.
        let edits = [src.replace("rotate(30 + 0)", "rotate(31)"), src.clone()];
        // One edit timed by parts, for the printed breakdown.
        let start = std::time::Instant::now();
        live.set_text(edits[0].clone());
        let built = start.elapsed();
        let bytes = live.lottie().expect("a Lottie").len();
        eprintln!(
            "{name}: {n} shapes, PUT (parse, expand, compile) {built:.1?}, Lottie export {:.1?} ({bytes} bytes)",
            start.elapsed() - built
        );
        let mut i = 0;
        group.bench_function(name, |b| {
            b.iter(|| {
                i += 1;
                let (_, diagnostics) = live.set_text(edits[i % 2].clone());
                assert!(diagnostics.is_empty());
                black_box(live.lottie().expect("a Lottie"))
            })
        });
    }
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, put_then_lottie);
criterion_main!(benches);
