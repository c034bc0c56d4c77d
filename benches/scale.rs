//! A million shapes (issue 46): what `gmotion animate` does with 10 000, 100 000 and
//! 999 000 squares (`gmotion_benches::squares_svg`, one `<rect>` a line) and a grammar of
//! three slices (`squares_grammar`: a translation with its inverted twin, a rotation
//! staggered by id), in process, to Lottie and to SMIL: the SVG imported, the grammar
//! expanded, the animation written to a sink (the writers stream, so the text is never
//! held whole). The cost per shape should stay the same from size to size; peak memory,
//! which criterion does not measure, is measured on the binary (docs/performance.md).
//!
//! Each size's scene and grammar are also written to `target/bench-workload/` as
//! `squares-N.svg` and `squares.gm`, so the binary can be measured on the very same files:
//! `/usr/bin/time -v gmotion animate target/bench-workload/squares-999000.svg
//! target/bench-workload/squares.gm -o x.json`.
//!
//! Ten samples a size (criterion's least). The 999 000-shape size would take about twenty
//! minutes of two shared cores, so it is measured only when asked for: `SCALE_999K=1
//! cargo bench --profile quick --bench scale` adds it (`-- /999000` then runs it alone);
//! `cargo bench --profile quick --bench scale -- /100000` runs one of the others.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gmotion::engine::{RunOptions, run};
use gmotion::motion::Animation;
use gmotion_import_svg::ImportOptions;

use gmotion_benches as workload;

/// The allocator the `gmotion` binary uses, so the numbers are what the command gets.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The sizes measured, in shapes: the issue's.
const SIZES: [usize; 2] = [10_000, 100_000];

/// The largest size, just under usvg's element limit, measured when the environment sets
/// [`LARGEST_ASKED`].
const LARGEST: usize = 999_000;

/// The environment variable that adds [`LARGEST`] to the sizes measured.
const LARGEST_ASKED: &str = "SCALE_999K";

/// Imports `svg` with the default limits and runs `gm` on it.
fn animate(svg: &str, gm: &str) -> Animation {
    let scene = gmotion_import_svg::parse(svg, "squares.svg", &ImportOptions::default())
        .expect("the squares import")
        .scene;
    let g = gmotion::grammar::parse(gm).expect("the grammar parses");
    run(scene, &g, &RunOptions::default())
        .expect("the grammar runs")
        .0
}

/// Writes `anim` as Lottie to a sink, streamed as the command streams it to its file.
fn lottie(anim: &Animation) {
    let opts = gmotion_export_lottie::LottieOptions::default();
    let (text, _) = gmotion_export_lottie::to_lottie_text(anim, &opts).expect("it exports");
    text.write_to(&mut std::io::sink())
        .expect("a sink takes all");
}

/// Writes `anim` as SMIL to a sink, streamed as the command streams it to its file.
fn smil(anim: &Animation) {
    let opts = gmotion_export_svg::smil::SmilOptions::default();
    let writer = gmotion_export_svg::smil::SmilWriter::new(anim, &opts).expect("it exports");
    writer
        .write_to(&mut std::io::sink())
        .expect("a sink takes all");
}

fn scale(c: &mut Criterion) {
    let gm = workload::squares_grammar();
    let out = workload::repo_root().join("target/bench-workload");
    let mut group = c.benchmark_group("scale");
    group.sample_size(10);
    let largest = std::env::var_os(LARGEST_ASKED).is_some_and(|v| !v.is_empty() && v != "0");
    let sizes = SIZES.into_iter().chain(largest.then_some(LARGEST));
    for n in sizes {
        let svg = workload::squares_svg(n);
        let written = std::fs::create_dir_all(&out).and_then(|()| {
            std::fs::write(out.join(format!("squares-{n}.svg")), &svg)?;
            std::fs::write(out.join("squares.gm"), &gm)
        });
        if let Err(e) = written {
            eprintln!("{}: {e}", out.display());
        }
        group.throughput(Throughput::Elements(n as u64));
        group.bench_with_input(BenchmarkId::new("lottie", n), &svg, |b, svg| {
            b.iter(|| lottie(&black_box(animate(svg, &gm))))
        });
        group.bench_with_input(BenchmarkId::new("smil", n), &svg, |b, svg| {
            b.iter(|| smil(&black_box(animate(svg, &gm))))
        });
    }
    group.finish();
}

criterion_group!(benches, scale);
criterion_main!(benches);
