//! The path every frame takes: SVG import, the frame writer, and resvg rendering, on a
//! drawing of `n` two-path characters (a curved body and a gradient-filled eye), each
//! tagged as one unit and animated (rotation about its centroid plus a tint).

use std::hint::black_box;
use std::sync::Arc;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gmotion::color::Color;
use gmotion::motion::{
    Animation, AttrSeg, Component, Interp, MotionKind, MotionSeg, Timing, Tint, Track,
};
use gmotion_export_raster::render;
use gmotion_export_svg::frame::{frame_svg, scene_svg};
use gmotion_import_svg::{ImportOptions, parse};
use kurbo::{Affine, Vec2};

fn drawing(n: usize) -> String {
    let mut body = String::new();
    for i in 0..n {
        let (x, y) = ((i % 50) as f64 * 20.0, (i / 50) as f64 * 20.0);
        body.push_str(&format!(
            r##"<g class="c{}" transform="translate({x} {y})"><path d="M0 0 C5 -5 10 5 15 0 S15 10 10 15 Q5 20 0 15 Z" fill="#3a7" stroke="#123" stroke-width="0.5"/><circle cx="7" cy="7" r="3" fill="url(#g)"/></g>"##,
            i % 7
        ));
    }
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="{}"><defs><radialGradient id="g"><stop offset="0" stop-color="#fff"/><stop offset="1" stop-color="#f00"/></radialGradient></defs>{body}</svg>"##,
        (n / 50 + 1) * 20
    )
}

fn animation(text: &str) -> Animation {
    let scene = parse(text, "bench.svg", &ImportOptions::default())
        .unwrap()
        .scene;
    let timing = Timing::linear(0.0, 1.0);
    let red = Tint::full(Color::rgb(1.0, 0.0, 0.0));
    let tracks = scene
        .shapes
        .iter()
        .map(|s| {
            let blend = vec![(
                1.0,
                Arc::from([
                    Component::Rotate(90.0),
                    Component::Translate(Vec2::new(5.0, 0.0)),
                ]),
            )];
            let kind = MotionKind::Rigid {
                pivot: s.centroid,
                blend: blend.into(),
                interp: Interp::Linear,
            };
            Track {
                motions: vec![MotionSeg {
                    t0: 0.0,
                    t1: 1.0,
                    timing: timing.clone(),
                    kind,
                    start: Affine::IDENTITY,
                }],
                fill: vec![AttrSeg {
                    t0: 0.0,
                    t1: 1.0,
                    timing: timing.clone(),
                    from: Tint::NONE,
                    to: red,
                }],
                ..Track::default()
            }
        })
        .collect();
    Animation {
        scene,
        duration: 1.0,
        fps: 30.0,
        looping: true,
        tracks,
    }
}

fn frame_path(c: &mut Criterion) {
    let mut g = c.benchmark_group("frame");
    g.sample_size(10);
    for n in [100, 1000] {
        let text = drawing(n);
        let anim = animation(&text);
        let frame = frame_svg(&anim, 0.5);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("import", n), &text, |b, t| {
            b.iter(|| parse(black_box(t), "bench.svg", &ImportOptions::default()).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("scene_svg", n), &anim, |b, a| {
            b.iter(|| scene_svg(black_box(&a.scene)))
        });
        g.bench_with_input(BenchmarkId::new("frame_svg", n), &anim, |b, a| {
            b.iter(|| frame_svg(black_box(a), 0.5))
        });
        g.bench_with_input(BenchmarkId::new("render_500px", n), &frame, |b, f| {
            b.iter(|| render(black_box(f), 500).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, frame_path);
criterion_main!(benches);
