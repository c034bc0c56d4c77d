//! `gmotion learn` (issue 45) on the paper's largest example: the intersections export
//! (8 217 layers, 240 frames, 16.2 MB of Lottie), kept as a fixture in
//! `benches/data/intersections.json.gz` as `gmotion animate grammars/intersections.gm`
//! wrote it when the issue was filed, so that the learner's speed is measured on the same
//! input as it changes. The target is 10 s on the test machine.
//!
//! The fixture is unpacked to `target/bench-workload/intersections-export.json` (the
//! learner reads a file, as the command does), so the binary can be timed on it too:
//! `/usr/bin/time gmotion learn target/bench-workload/intersections-export.json -o x.gm`.
//! One learn takes tens of seconds: ten samples (criterion's least) take minutes. Run it
//! with `cargo bench --profile quick --bench learn`.

use std::hint::black_box;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use gmotion_learn::{Options, learn};
use gmotion_pipeline::Env;

/// The allocator the `gmotion` binary uses, so the numbers are what the command gets.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Unpacks the fixture beside the other workloads and returns its path.
fn fixture() -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    let packed = std::fs::read(here.join("data/intersections.json.gz")).expect("the fixture");
    let mut text = Vec::new();
    flate2::read::GzDecoder::new(&packed[..])
        .read_to_end(&mut text)
        .expect("the fixture unpacks");
    let dir = here.join("../target/bench-workload");
    std::fs::create_dir_all(&dir).expect("the workload folder");
    let path = dir.join("intersections-export.json");
    std::fs::write(&path, text).expect("the fixture written out");
    path
}

fn bench(c: &mut Criterion) {
    let path = fixture();
    let env = Env::default();
    let opts = Options::default();
    let mut group = c.benchmark_group("learn");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(60));
    group.bench_function("intersections", |b| {
        b.iter(|| {
            let learned = learn(&path, "intersections-still.json", &env, &opts)
                .expect("the fixture is learned");
            black_box(learned.grammar.len())
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
