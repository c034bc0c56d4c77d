//! The studio's edit loop (issue 16): `PUT /api/grammar` → the new Lottie ready, in process
//! (`Live::set_text` then `Live::lottie`, what the two requests run), at the scales of
//! gMotion's Table 1: teaser (208 shapes) and intersections (8214 shapes), generated grids,
//! then the gallery's real `grammars/intersections.{svg,gm}` (8216 shapes, 105 rules).
//! Targets: ≤ 30 ms and ≤ 300 ms. Each iteration sends a grammar that differs from the last
//! one, so every edit rebuilds.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use gmotion::engine::RunOptions;
use gmotion::scene::Scene;
use gmotion_import_svg::ImportOptions;
use gmotion_pipeline::Imported;
use gmotion_studio::{Config, Live};

use gmotion_benches as workload;

/// The allocator the `gmotion` binary uses, so the numbers are what the command gets.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn put_then_lottie(c: &mut Criterion) {
    let generated = [
        ("teaser", 208usize, 6usize, 6.0, 30.0),
        ("intersections", 8214, 16, 8.0, 60.0),
    ];
    let mut cases: Vec<(&str, Scene, String, [&str; 2])> = generated
        .into_iter()
        .map(|(name, n, tags, dur, fps)| {
            let src = workload::grammar(tags, dur, fps);
            (
                name,
                workload::scene(n, tags),
                src,
                ["rotate(30 + 0)", "rotate(31)"],
            )
        })
        .collect();
    if let Some((scene, src)) = gallery_intersections() {
        cases.push((
            "gallery_intersections",
            scene,
            src,
            ["scale(0.85)", "scale(0.86)"],
        ));
    }
    let dir = std::env::temp_dir().join(format!("gmotion-studio-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let mut group = c.benchmark_group("studio_put");
    group.sample_size(10);
    for (name, scene, src, [old, new]) in cases {
        let n = scene.shapes.len();
        let path = dir.join(format!("{name}.gm"));
        std::fs::write(&path, &src).expect("the grammar file");
        let live = Live::new(Config {
            grammar_path: path,
            imported: Imported {
                scene,
                source: None,
                package: None,
            },
            rescene: None,
            run: RunOptions::default(),
            port: 0,
        })
        .expect("the studio state");
        // Two edits of one number, sent in turn.
        let edits = [src.replace(old, new), src.clone()];
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

/// The gallery's intersections scene and grammar, when the checkout has them; the grammar's
/// `scene` line is left out because the bench hands the studio the scene itself.
fn gallery_intersections() -> Option<(Scene, String)> {
    let root = workload::repo_root().join("grammars");
    let svg = std::fs::read_to_string(root.join("intersections.svg")).ok()?;
    let gm = std::fs::read_to_string(root.join("intersections.gm")).ok()?;
    let scene = gmotion_import_svg::parse(&svg, "intersections.svg", &ImportOptions::default())
        .expect("the gallery scene imports")
        .scene;
    let gm = gm
        .lines()
        .filter(|l| !l.starts_with("scene "))
        .collect::<Vec<_>>()
        .join("\n");
    Some((scene, gm))
}

criterion_group!(benches, put_then_lottie);
criterion_main!(benches);
