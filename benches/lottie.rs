//! A Lottie file in and out: what `gmotion convert X.json -o Y.json` does between reading
//! and writing bytes (JSON parse, the typed model, the scene at the first frame, the
//! document written back), over the Lottie corpus that `tests/conformance/install.sh`
//! fetches (lottie-web's test animations and rlottie's examples). The same work by
//! python-lottie (load, then export) is timed by `tests/conformance/python_lottie_bench.py`
//! on the same files, for the README's comparison.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use gmotion_export_lottie::layered::source_verbatim;
use gmotion_import_lottie::{ImportOptions, parse};

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn corpus() -> Vec<(String, String)> {
    let dir = gmotion_benches::repo_root().join("tests/conformance/lottie-corpus");
    let mut files: Vec<(String, String)> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}; run tests/conformance/install.sh", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .map(|p| {
            let text = std::fs::read_to_string(&p).expect("a corpus file reads");
            (p.display().to_string(), text)
        })
        .collect();
    files.sort();
    files
}

fn round_trip(c: &mut Criterion) {
    let files = corpus();
    let bytes: usize = files.iter().map(|f| f.1.len()).sum();
    let mut g = c.benchmark_group("lottie");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(bytes as u64));
    g.bench_function(
        format!("import_and_identity_export/{}_files", files.len()),
        |b| {
            b.iter(|| {
                for (name, text) in &files {
                    let imported = parse(text, name, &ImportOptions::default()).expect("imports");
                    black_box(source_verbatim(&imported.source));
                }
            })
        },
    );
    g.finish();
}

criterion_group!(benches, round_trip);
criterion_main!(benches);
