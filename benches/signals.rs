//! Samples per second for each filter kind, and the cost of interruptions: the
//! continuous FIR queue (Alg. 2) pays per target in flight, IIR biquads (Alg. 4) do not.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gmotion::signals::{
    Discretization, Ease, Easing, FirTransition, Lti, SmoothSpec, Spring, StateSpace, System,
    Transition,
};

const FPS: f64 = 60.0;
const N: usize = 6000;

/// A step input that changes every 20 frames (100 s at 60 fps).
fn input() -> Vec<f64> {
    (0..N)
        .map(|i| ((i / 20) as f64 * 0.7).sin() * 100.0)
        .collect()
}

fn run<S: System<f64> + ?Sized>(sys: &mut S, x: &[f64]) -> f64 {
    sys.reset(x[0]);
    let mut acc = 0.0;
    for &v in x {
        acc += sys.step(v);
    }
    acc
}

fn filters(c: &mut Criterion) {
    let x = input();
    let mut g = c.benchmark_group("filter");
    g.throughput(Throughput::Elements(N as u64));
    g.sample_size(30);
    let specs = [
        ("simple_alg1", "simple(ease-in-out, 0.5)"),
        ("spline_sec3", "spline(0.5)"),
        ("fir_alg3_31taps", "fir(bspline(3), 0.5)"),
        ("fir_alg3_121taps", "fir(bspline(3), 2)"),
        ("spring_biquad_zoh", "spring(0.5, 0.2)"),
        ("spring_biquad_tustin", "tustin(spring(0.5, 0.2))"),
        ("lowpass4_biquads", "lowpass(4, 0.05)"),
        (
            "series_fir_spring",
            "series(fir(linear, 0.1), spring(0.5, 0))",
        ),
    ];
    for (name, text) in specs {
        let spec = SmoothSpec::parse(text).unwrap();
        let mut sys = spec.build::<f64>(FPS).unwrap();
        g.bench_function(name, |b| b.iter(|| run(sys.as_mut(), black_box(&x))));
    }
    let spring = Spring::from_duration_bounce(0.5, 0.2).unwrap();
    let mut ss = StateSpace::spring(&spring)
        .discretize_zoh::<f64>(FPS)
        .unwrap();
    g.bench_function("spring_state_space_zoh", |b| {
        b.iter(|| run(&mut ss, black_box(&x)))
    });
    let arc = SmoothSpec::parse("arc(0.6, 1)").unwrap();
    let mut arc_sys = arc.build::<[f64; 2]>(FPS).unwrap();
    let x2: Vec<[f64; 2]> = x.iter().map(|&v| [v, 0.0]).collect();
    g.bench_function("arc_fir_2d_61taps", |b| {
        b.iter(|| {
            arc_sys.reset(x2[0]);
            let mut acc = 0.0;
            for &v in black_box(&x2) {
                acc += arc_sys.step(v)[1];
            }
            acc
        })
    });
    g.finish();
}

/// Retargeting every `every` frames with a 100-frame FIR keeps about `100 / every`
/// targets in flight; the spring's biquads do the same work either way.
fn interruptions(c: &mut Criterion) {
    let mut g = c.benchmark_group("interruptions");
    g.throughput(Throughput::Elements(N as u64));
    g.sample_size(20);
    let d = 100.0 / FPS;
    let ease = Ease::new(Easing::BSpline(3), d).unwrap();
    let spring = Lti::spring(&Spring::from_duration_bounce(d, 0.0).unwrap());
    for every in [100usize, 1] {
        let in_flight = 100 / every;
        let x: Vec<f64> = (0..N)
            .map(|i| ((i / every) as f64 * 0.37).sin() * 100.0)
            .collect();
        g.bench_with_input(BenchmarkId::new("fir_alg2", in_flight), &x, |b, x| {
            b.iter(|| {
                let mut f = FirTransition::new(ease.clone(), x[0]);
                let mut acc = 0.0;
                for (i, &v) in x.iter().enumerate() {
                    let t = i as f64 / FPS;
                    if i % every == 0 {
                        f.retarget(t, v);
                    }
                    acc += f.sample(t);
                }
                acc
            })
        });
        let mut iir = spring
            .discretize::<f64>(Discretization::ZeroOrderHold, FPS)
            .unwrap();
        g.bench_with_input(BenchmarkId::new("iir_biquads", in_flight), &x, |b, x| {
            b.iter(|| run(&mut iir, x))
        });
    }
    g.finish();
}

criterion_group!(benches, filters, interruptions);
criterion_main!(benches);
