//! Spatial (group grammar) expansion at the scale of gTangle's Table 1, and its scaling.
//!
//! gTangle reports 190.5 s for "village" (101 rules, 907 steps, 18 396 shapes) on a
//! 3.1 GHz machine. `grammars/bench/village.gm` on `grammars/bench/village.svg` is at least that large;
//! `cargo bench --bench tangle` prints its statistics before timing it. The scaling group
//! expands a grid of tiles of growing size with the same grammar, so the cost per final
//! shape can be read off.

use std::fmt::Write as _;
use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gmotion::grammar::ast::Rule;
use gmotion::scene::Scene;
use gmotion::tangle::{TangleOptions, expand, graph_stats};
use gmotion_import_svg::{ImportOptions, load, parse as parse_svg};

fn village(c: &mut Criterion) {
    let dir = gmotion_benches::repo_root().join("grammars/bench");
    let scene = load(&dir.join("village.svg"), &ImportOptions::default())
        .expect("village.svg imports")
        .scene;
    let src = std::fs::read_to_string(dir.join("village.gm")).expect("village.gm reads");
    let grammar = gmotion::grammar::parse(&src).expect("village.gm parses");
    let rules: Vec<&Rule> = grammar.rules.iter().collect();
    let opts = TangleOptions::with_seed(1);
    let (out, stats) = expand(&scene, &rules, &opts).expect("village expands");
    let g = graph_stats(&rules);
    eprintln!(
        "village: {} rules (graph: {} nodes, {} edges, depth {}), {} steps, {} final shapes ({} in the scene)",
        rules.len(),
        g.nodes,
        g.edges,
        g.depth,
        stats.steps,
        stats.shapes,
        out.shapes.len()
    );
    let mut group = c.benchmark_group("table1");
    group.sample_size(10);
    group.bench_function("village", |b| {
        b.iter(|| black_box(expand(&scene, &rules, &opts).expect("expands")))
    });
    group.finish();
}

/// A row-major grid of `n` square tiles, each tagged `tile`.
fn tiles(n: usize) -> Scene {
    let side = (n as f64).sqrt().ceil() as usize;
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{0}" height="{0}">"#,
        side * 60
    );
    for i in 0..n {
        let (x, y) = ((i % side) * 60, (i / side) * 60);
        let _ = write!(
            svg,
            r#"<rect class="tile" x="{x}" y="{y}" width="56" height="56" fill="white" stroke="black"/>"#
        );
    }
    svg.push_str("</svg>");
    parse_svg(&svg, "tiles.svg", &ImportOptions::default())
        .expect("tiles import")
        .scene
}

/// Per tile: a 4 × 4 grid of cells, each cell decorated on its own.
const TILE_GRAMMAR: &str = "regularSplit(line, 14, 1) : tile -> [cell]
ungroup() : cell -> [one]
outline(2) : one -> [core, rim]
invert() : one -> [ink]
stipple(dots, 6, 0.8) : core -> [face, dots]
";

fn scaling(c: &mut Criterion) {
    let grammar = gmotion::grammar::parse(TILE_GRAMMAR).expect("tile grammar parses");
    let rules: Vec<&Rule> = grammar.rules.iter().collect();
    let opts = TangleOptions::with_seed(1);
    let mut group = c.benchmark_group("tangle_scaling");
    group.sample_size(10);
    for n in [16usize, 64, 256] {
        let scene = tiles(n);
        let (_, stats) = expand(&scene, &rules, &opts).expect("tiles expand");
        eprintln!(
            "tiles {n}: {} steps, {} final shapes",
            stats.steps, stats.shapes
        );
        group.throughput(Throughput::Elements(stats.shapes as u64));
        group.bench_with_input(BenchmarkId::from_parameter(n), &scene, |b, s| {
            b.iter(|| black_box(expand(s, &rules, &opts).expect("expands")))
        });
    }
    group.finish();
}

criterion_group!(benches, village, scaling);
criterion_main!(benches);
