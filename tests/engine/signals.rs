//! Properties of the signals-and-systems blocks (Reach & North), tested on random inputs:
//! Claims 1 and 3, velocity continuity under interruptions, convexity, affinity, and the
//! accuracy of each discretisation against the closed-form spring.

use gmotion::signals::*;
use proptest::prelude::*;

const METHODS: [Discretization; 4] = [
    Discretization::ZeroOrderHold,
    Discretization::ImpulseInvariant,
    Discretization::Bilinear,
    Discretization::Matched,
];

/// Textbook closed form of the unit step response of `ÿ + 2ζωẏ + ω²y = ω²u` from rest
/// (phase form), written independently of `Spring::step_state`.
fn spring_reference(omega: f64, zeta: f64, t: f64) -> f64 {
    if t <= 0.0 {
        return 0.0;
    }
    if zeta < 1.0 {
        let root = (1.0 - zeta * zeta).sqrt();
        let phi = root.atan2(zeta);
        1.0 - (-zeta * omega * t).exp() * (omega * root * t + phi).sin() / root
    } else if zeta == 1.0 {
        1.0 - (-omega * t).exp() * (1.0 + omega * t)
    } else {
        let r = (zeta * zeta - 1.0).sqrt();
        let (s1, s2) = (-omega * (zeta - r), -omega * (zeta + r));
        1.0 - (s2 * (s1 * t).exp() - s1 * (s2 * t).exp()) / (s2 - s1)
    }
}

fn easing_strategy() -> impl Strategy<Value = Easing> {
    prop_oneof![
        Just(Easing::Linear),
        Just(Easing::CubicBezier([0.42, 0.0, 0.58, 1.0])),
        (2u32..8).prop_map(Easing::BSpline),
        (2u32..9).prop_map(|n| Easing::poles(n).unwrap()),
    ]
}

/// Step inputs: `(time, value)` changes in increasing time order.
fn steps(min_gap: f64, max_gap: f64, count: usize) -> impl Strategy<Value = Vec<(f64, f64)>> {
    prop::collection::vec((min_gap..max_gap, -100.0..100.0f64), 1..count).prop_map(|v| {
        let mut t = 0.0;
        v.into_iter()
            .map(|(gap, x)| {
                t += gap;
                (t, x)
            })
            .collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Claim 3: when each transition finishes before the next begins, FIR transitions
    /// (Alg. 2) and simple transitions (Alg. 1) produce the same output.
    #[test]
    fn claim3_fir_equals_simple_when_uninterrupted(
        easing in easing_strategy(),
        d in 0.05..2.0f64,
        x0 in -100.0..100.0f64,
        changes in prop::collection::vec((0.0..1.0f64, -100.0..100.0f64), 1..8),
        probes in prop::collection::vec(0.0..1.0f64, 20),
    ) {
        let ease = Ease::new(easing, d).unwrap();
        let mut t = 0.0;
        let changes: Vec<(f64, f64)> = changes.into_iter().map(|(gap, x)| { t += d * (1.0 + gap); (t, x) }).collect();
        let end = t + 2.0 * d;
        let mut times: Vec<f64> = probes.iter().map(|p| p * end).chain(changes.iter().map(|c| c.0)).collect();
        times.sort_by(f64::total_cmp);
        let mut fir = FirTransition::new(ease.clone(), x0);
        let mut simple = SimpleTransition::new(ease, x0);
        let mut next = 0;
        for &t in &times {
            while next < changes.len() && changes[next].0 <= t {
                fir.retarget(changes[next].0, changes[next].1);
                simple.retarget(changes[next].0, changes[next].1);
                next += 1;
            }
            let (a, b) = (fir.sample(t), simple.sample(t));
            prop_assert!((a - b).abs() < 1e-9, "t={t}: fir {a} simple {b}");
        }
    }

    /// Alg. 3 with taps h[k] = s(kT) − s((k−1)T) gives exactly the samples of Alg. 2 when
    /// the targets change on frames, interrupted or not (both evaluate Claim 2's sum).
    #[test]
    fn discrete_fir_equals_continuous_fir_on_frames(
        easing in easing_strategy(),
        d in 0.05..1.0f64,
        fps in 10.0..120.0f64,
        x0 in -100.0..100.0f64,
        inputs in prop::collection::vec((0usize..20, -100.0..100.0f64), 1..12),
    ) {
        let ease = Ease::new(easing, d).unwrap();
        let mut fir: Fir<f64> = Fir::from_response(&ease, fps).unwrap();
        fir.reset(x0);
        let mut cont = FirTransition::new(ease, x0);
        let mut frame = 0usize;
        let mut current = x0;
        for (hold, x) in inputs.into_iter().chain([(0usize, x0)]) {
            for _ in 0..=hold {
                let t = frame as f64 / fps;
                let y = fir.step(current);
                let want = cont.sample(t);
                prop_assert!((y - want).abs() < 1e-9 * (1.0 + want.abs()), "frame {frame}: {y} vs {want}");
                frame += 1;
            }
            current = x;
            cont.retarget(frame as f64 / fps, x);
        }
    }

    /// FIR, spline, spring and low-pass (order ≥ 2) keep velocity continuous under
    /// interruptions: the largest jump of the finite-difference velocity between
    /// consecutive samples halves when the sampling step halves (O(h)). A velocity
    /// discontinuity would keep the jump the same size (O(1)).
    #[test]
    fn velocity_stays_continuous_under_interruptions(
        changes in steps(0.02, 0.2, 10),
    ) {
        let specs = [
            "fir(bspline(3), 0.5)",
            "fir(poles(4), 0.5)",
            "spline(0.5)",
            "spring(0.5, 0.3)",
            "spring(0.4, -0.3)",
            "lowpass(3, 0.08)",
            "series(fir(bspline(2), 0.2), spring(0.5, 0))",
        ];
        let total: f64 = changes.iter().map(|c| c.1.abs()).sum::<f64>() + 1.0;
        for text in specs {
            let spec = SmoothSpec::parse(text).unwrap();
            let j1 = max_velocity_jump(&spec, &changes, 1000.0);
            let j2 = max_velocity_jump(&spec, &changes, 2000.0);
            prop_assert!(j2 < 0.6 * j1 + 1e-9 * total, "{text}: jump {j1} at 1 kHz, {j2} at 2 kHz");
        }
    }

    /// A FIR transition's velocity jump per sample is bounded by h·max|s''|·Σ|Δx|.
    #[test]
    fn fir_velocity_jump_is_bounded(changes in steps(0.01, 0.3, 12), k in 2u32..6) {
        let d = 0.5;
        let ease = Ease::new(Easing::BSpline(k), d).unwrap();
        // max |s''| from second differences of the easing on a fine grid.
        let g = 20_000;
        let hh = d / g as f64;
        let curv = (1..g)
            .map(|i| {
                let t = i as f64 * hh;
                (ease.at(t + hh) - 2.0 * ease.at(t) + ease.at(t - hh)).abs() / (hh * hh)
            })
            .fold(0.0, f64::max);
        let mut total = 0.0;
        let mut prev = 0.0;
        for c in &changes {
            total += (c.1 - prev).abs();
            prev = c.1;
        }
        let h = 1e-3;
        let jump = max_velocity_jump(&SmoothSpec::Fir(ease), &changes, 1.0 / h);
        prop_assert!(jump <= 1.01 * h * curv * total + 1e-9, "jump {jump} > bound {}", h * curv * total);
    }

    /// Convex filters (non-negative impulse response summing to 1) never leave the range
    /// of their input: FIR filters with monotone easings, low-pass cascades and
    /// critically or over-damped springs (discretised by zero-order hold, which keeps the
    /// step response monotone), and series/parallel diagrams of them with weights ≥ 0.
    #[test]
    fn convex_filters_never_overshoot(
        samples in prop::collection::vec(-50.0..50.0f64, 2..200),
        hold in 1usize..6,
    ) {
        let input: Vec<f64> = samples.iter().flat_map(|&x| std::iter::repeat_n(x, hold)).collect();
        let (lo, hi) = input.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| (l.min(x), h.max(x)));
        for text in [
            "fir(bspline(4), 0.3)",
            "fir(poles(4), 0.4)",
            "fir(ease-in-out, 0.3)",
            "fir(linear, 0.1)",
            "lowpass(4, 0.05)",
            "spring(0.5, 0)",
            "spring(0.6, -0.5)",
            "msd(1, 100, 30)",
            "series(lowpass(1, 0.02), fir(bspline(3), 0.2))",
            "parallel(0.3, spring(0.3, 0), 0.7, fir(poles(3), 0.5))",
        ] {
            let spec = SmoothSpec::parse(text).unwrap();
            for y in smooth_samples(&spec, &input, 60.0).unwrap() {
                prop_assert!(y >= lo - 1e-9 && y <= hi + 1e-9, "{text}: {y} outside [{lo}, {hi}]");
            }
        }
    }

    /// Affine filters (impulse response summing to 1, convex or not) converge to a
    /// constant input whatever came before.
    #[test]
    fn affine_filters_converge_to_a_constant_input(
        history in prop::collection::vec(-50.0..50.0f64, 1..100),
        c in -50.0..50.0f64,
    ) {
        for text in [
            "fir(cubic(0.3, -0.6, 0.6, 1.6), 0.3)",
            "spring(0.5, 0.7)",
            "tustin(spring(0.4, 0.5))",
            "impulse(lowpass(3, 0.05))",
            "matched(msd(2, 300, 5))",
            "spline(0.4)",
            "simple(ease, 0.3)",
            "parallel(1.5, fir(linear, 0.2), -0.5, spring(0.3, 0))",
            "arc(0.7, 0.5)",
        ] {
            let spec = SmoothSpec::parse(text).unwrap();
            let settle = 50.0 * spec.time_scale().unwrap() + 1.0;
            let n = (settle * 60.0) as usize;
            let input: Vec<[f64; 2]> = history
                .iter()
                .map(|&x| [x, -x])
                .chain(std::iter::repeat_n([c, 2.0 * c], n))
                .collect();
            let out = smooth_samples(&spec, &input, 60.0).unwrap();
            let last = out[out.len() - 1];
            prop_assert!((last[0] - c).abs() < 1e-6 && (last[1] - 2.0 * c).abs() < 1e-6, "{text}: {last:?} vs {c}");
        }
    }

    /// Each discretisation of the spring agrees with the closed-form solution at 60 fps
    /// within the bound documented on `Discretization` (T = 1/60 s, d = duration):
    /// ZOH 1e-9; impulse invariance and bilinear 3·T/d; matched 3·(T/d)².
    #[test]
    fn discretisations_agree_with_the_continuous_spring(d in 0.2..2.0f64, b in -0.5..0.9f64) {
        let fps = 60.0;
        let r = 1.0 / fps / d;
        let spring = Spring::from_duration_bounce(d, b).unwrap();
        let (w, z) = (spring.natural_frequency(), spring.damping_ratio());
        for m in METHODS {
            let bound = match m {
                Discretization::ZeroOrderHold => 1e-9,
                Discretization::ImpulseInvariant | Discretization::Bilinear => 3.0 * r,
                Discretization::Matched => 3.0 * r * r,
            };
            let mut sys: BiquadCascade<f64> = Lti::spring(&spring).discretize(m, fps).unwrap();
            sys.reset(0.0);
            for n in 0..(5.0 * d * fps) as usize {
                let err = (sys.step(1.0) - spring_reference(w, z, n as f64 / fps)).abs();
                prop_assert!(err <= bound, "{m:?} d={d} b={b} frame {n}: error {err} > {bound}");
            }
        }
    }

    /// Invalid parameters give errors, never panics.
    #[test]
    fn bad_parameters_are_errors(x in prop::num::f64::ANY, y in prop::num::f64::ANY, z in prop::num::f64::ANY) {
        let ok_spring = x > 0.0 && y > 0.0 && z > 0.0 && x.is_finite() && y.is_finite() && z.is_finite();
        prop_assert_eq!(Spring::new(x, y, z).is_ok(), ok_spring);
        // Durations so extreme that the stiffness overflows or underflows are rejected too.
        let ok_perceptual = x > 1e-100 && x < 1e100 && y > -1.0 && y < 1.0;
        let good_perceptual = x > 0.0 && x.is_finite() && y > -1.0 && y < 1.0;
        match Spring::from_duration_bounce(x, y) {
            Ok(s) => {
                prop_assert!(good_perceptual);
                prop_assert!(s.stiffness().is_finite() && s.damping().is_finite());
            }
            Err(_) => prop_assert!(!ok_perceptual),
        }
        prop_assert_eq!(Ease::new(Easing::Linear, x).is_ok(), x > 0.0 && x.is_finite());
        let _ = Lti::lowpass(3, x).and_then(|l| l.discretize::<f64>(Discretization::Bilinear, y.abs()));
        let _ = ArcEasing::new(x, Easing::Linear, y);
        let _ = Easing::from_call("cubic", &[x, y, z, x]);
        let _ = SmoothSpec::parse(&format!("parallel({x}, spring({y}, {z}), {}, none)", 1.0 - x));
    }

    /// Random text never panics the parser.
    #[test]
    fn parser_never_panics(text in "[a-z(),.0-9 \\-]{0,40}") {
        let _ = SmoothSpec::parse(&text);
    }
}

/// The largest change of the finite-difference velocity between consecutive samples at
/// `rate` samples per second, for the step input `changes` (starting at 0).
fn max_velocity_jump(spec: &SmoothSpec, changes: &[(f64, f64)], rate: f64) -> f64 {
    let end = changes.last().map_or(0.0, |c| c.0) + 1.5;
    let n = (end * rate) as usize;
    let input: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 / rate;
            // Changes take effect on the first sample at or after their time, rounded to
            // the millisecond so that both rates see the same instants.
            changes
                .iter()
                .rev()
                .find(|c| (c.0 * 1000.0).round() / 1000.0 <= t + 1e-12)
                .map_or(0.0, |c| c.1)
        })
        .collect();
    let y = smooth_samples(spec, &input, rate).unwrap();
    let v: Vec<f64> = y.windows(2).map(|w| (w[1] - w[0]) * rate).collect();
    v.windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f64::max)
}

/// Claim 1: with an easing whose derivative vanishes at 0, simple transitions
/// retargeted at every frame stall — their progress goes to 0 as the frame rate grows —
/// while FIR transitions with the same easing track the target.
#[test]
fn claim1_simple_transitions_stall_under_frequent_interruptions() {
    let ease = Ease::new(Easing::BSpline(3), 0.5).unwrap();
    let mut last_simple = f64::INFINITY;
    for fps in [30.0, 120.0, 480.0, 1920.0] {
        let mut simple = SimpleTransition::new(ease.clone(), 0.0);
        let mut fir = FirTransition::new(ease.clone(), 0.0);
        let frames = fps as usize;
        let (mut ys, mut yf) = (0.0, 0.0);
        for i in 1..=frames {
            // The target ramps: a new value every frame.
            let t = i as f64 / fps;
            simple.retarget(t, t);
            fir.retarget(t, t);
            ys = simple.sample(t);
            yf = fir.sample(t);
        }
        // The FIR output lags the ramp by the easing's mean delay (d/2 for a symmetric
        // easing): 1 − 0.25 = 0.75 at t = 1.
        assert!((yf - 0.75).abs() < 0.05, "fps {fps}: FIR at {yf}");
        assert!(
            ys < last_simple,
            "fps {fps}: simple progress {ys} did not shrink"
        );
        last_simple = ys;
    }
    assert!(
        last_simple < 0.01,
        "simple transitions still moved to {last_simple}"
    );
}

/// Simple transitions, by contrast, jump in velocity at every interruption, and so does
/// a first-order low-pass: the jump does not shrink with the sampling step.
#[test]
fn simple_transitions_jump_in_velocity() {
    let changes = [(0.1, 10.0), (0.35, -10.0), (0.5, 30.0), (0.6, 0.0)];
    for text in ["simple(bspline(3), 0.5)", "lowpass(1, 0.1)"] {
        let spec = SmoothSpec::parse(text).unwrap();
        let j1 = max_velocity_jump(&spec, &changes, 1000.0);
        let j2 = max_velocity_jump(&spec, &changes, 2000.0);
        assert!(j2 > 0.9 * j1 && j1 > 1.0, "{text}: {j1} then {j2}");
    }
}

/// A spring that bounces overshoots a step: the convexity test above can fail.
#[test]
fn bouncy_springs_overshoot() {
    let spec = SmoothSpec::parse("spring(0.5, 0.3)").unwrap();
    let mut input = vec![0.0];
    input.extend(std::iter::repeat_n(1.0, 120));
    let peak = smooth_samples(&spec, &input, 60.0)
        .unwrap()
        .into_iter()
        .fold(0.0, f64::max);
    // Overshoot e^(−πζ/√(1−ζ²)) = 4.6 % for ζ = 0.7.
    assert!(peak > 1.04, "peak {peak}");
}

/// Spline transitions retargeted at every sample tend to the system of sec. 3,
/// `ÿ = (6(u − y) − 4dẏ)/d²`; the gap shrinks with the sampling step.
#[test]
fn spline_transitions_tend_to_their_limit_system() {
    let d = 0.5;
    let gap = |rate: f64| {
        let mut spline = SplineTransition::new(d, 0.0).unwrap();
        let mut limit: BiquadCascade<f64> = Lti::spline_limit(d)
            .unwrap()
            .discretize(Discretization::ZeroOrderHold, rate)
            .unwrap();
        limit.reset(0.0);
        let mut worst: f64 = 0.0;
        for i in 0..(2.0 * rate) as usize {
            let t = i as f64 / rate;
            let u = (3.0 * t).sin() + 1.0;
            let y_limit = limit.step(u);
            spline.retarget(t, u);
            let y = spline.sample(t + 1.0 / rate);
            worst = worst.max((y - y_limit).abs());
        }
        worst
    };
    let (g1, g2) = (gap(500.0), gap(4000.0));
    assert!(
        g2 < 0.01 && g2 < 0.3 * g1,
        "gap {g1} at 500 Hz, {g2} at 4 kHz"
    );
}

/// Vector signals are smoothed component by component by scalar systems.
#[test]
fn vectors_smooth_per_component() {
    let spec = SmoothSpec::parse("series(fir(bspline(3), 0.2), spring(0.4, 0.2))").unwrap();
    let xs: Vec<f64> = (0..90).map(|i| ((i / 7) as f64).sin() * 10.0).collect();
    let ys: Vec<f64> = (0..90).map(|i| ((i / 11) as f64).cos() * 3.0).collect();
    let v: Vec<[f64; 2]> = xs.iter().zip(&ys).map(|(&x, &y)| [x, y]).collect();
    let sx = smooth_samples(&spec, &xs, 60.0).unwrap();
    let sy = smooth_samples(&spec, &ys, 60.0).unwrap();
    for (i, o) in smooth_samples(&spec, &v, 60.0)
        .unwrap()
        .into_iter()
        .enumerate()
    {
        assert!((o[0] - sx[i]).abs() < 1e-12 && (o[1] - sy[i]).abs() < 1e-12);
    }
}

/// Series composition convolves impulse responses; parallel composition adds them.
#[test]
fn diagrams_compose_impulse_responses() {
    let a = Ease::new(Easing::Linear, 0.05).unwrap();
    let b = Ease::new(Easing::BSpline(2), 0.1).unwrap();
    let fa: Fir<f64> = Fir::from_response(&a, 60.0).unwrap();
    let fb: Fir<f64> = Fir::from_response(&b, 60.0).unwrap();
    let (ha, hb) = (
        fa.scalar_taps().unwrap().to_vec(),
        fb.scalar_taps().unwrap().to_vec(),
    );
    let mut conv = vec![0.0; ha.len() + hb.len() - 1];
    for (i, x) in ha.iter().enumerate() {
        for (j, y) in hb.iter().enumerate() {
            conv[i + j] += x * y;
        }
    }
    let mut series = Series(fa.clone(), fb.clone());
    let mut parallel = Parallel::new(fa, fb, [0.25, 0.75]).unwrap();
    series.reset(0.0);
    parallel.reset(0.0);
    for n in 0..conv.len() + 3 {
        let x = if n == 0 { 1.0 } else { 0.0 };
        let ys = series.step(x);
        let yp = parallel.step(x);
        assert!((ys - conv.get(n).copied().unwrap_or(0.0)).abs() < 1e-12);
        let want =
            0.25 * ha.get(n).copied().unwrap_or(0.0) + 0.75 * hb.get(n).copied().unwrap_or(0.0);
        assert!((yp - want).abs() < 1e-12);
    }
    assert!(Parallel::new(Identity, Identity, [0.5, 0.6]).is_err());
}

/// The discrete arc filter is the continuous matrix easing sampled on frames.
#[test]
fn arc_fir_matches_its_continuous_form() {
    let arc = ArcEasing::new(0.6, Easing::poles(4).unwrap(), 0.8).unwrap();
    let mut fir: Fir<[f64; 2]> = Fir::from_response(&arc, 60.0).unwrap();
    fir.reset([0.0, 0.0]);
    let mut cont = FirTransition::new(arc, [0.0, 0.0]);
    let targets = [(3, [100.0, 0.0]), (20, [40.0, 10.0]), (25, [-50.0, 0.0])];
    let mut current = [0.0, 0.0];
    for frame in 0..120 {
        if let Some(&(_, x)) = targets.iter().find(|t| t.0 == frame) {
            current = x;
            cont.retarget(frame as f64 / 60.0, x);
        }
        let y = fir.step(current);
        let want = cont.sample(frame as f64 / 60.0);
        assert!(
            (y[0] - want[0]).abs() < 1e-9 && (y[1] - want[1]).abs() < 1e-9,
            "frame {frame}"
        );
    }
}

/// `smoothing` starts at rest in the animation's own state at t = 0 (Reach & North: the
/// filter is at rest before its input changes). With `loop false` an inverted slice with no
/// twin before it is pre-applied, so the state at t = 0 is already the twin's end state;
/// the smoothed animation must show that state at t = 0 (and hold it while the input does),
/// not the drawn art until its first change.
#[test]
fn smoothing_starts_in_the_state_at_time_zero() {
    use gmotion_import_svg::{ImportOptions, parse};
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="150">
<rect data-tag="s" x="30" y="40" width="40" height="30" fill="#e4572e" stroke="#1d3557" stroke-width="2"/>
<rect data-tag="s" x="110" y="80" width="36" height="36" fill="#17bebb" stroke="#1d3557" stroke-width="2"/>
</svg>"##;
    let scene = parse(svg, "t.svg", &ImportOptions::default())
        .unwrap()
        .scene;
    let changes = [
        "animate(border, local, 0, #edae49)",
        "animate(fill, local, 0, #5d2e8c)",
        "animate(opacity, local, 0, 0.3)",
        "animate(stroke-width, local, 0, 3)",
        "animate(affine, world, 0, translate(25, 10))",
    ];
    let systems = ["lowpass(2, 0.06)", "spring(0.3, 0.1)", "fir(linear, 0.2)"];
    for (i, change) in changes.iter().enumerate() {
        let system = systems[i % systems.len()];
        // A hold first, so the input stays put for a while after t = 0.
        let rules = format!(
            "timesplit(0.3, 0.4, 0.3) : [all, s] -> [inv_a, hold, a]\n{change} : [a, s] -> [m]\n"
        );
        let head = "duration 2s\nfps 30\nloop false\n";
        let run = |src: &str| {
            let g = gmotion::grammar::parse(src)
                .unwrap_or_else(|d| panic!("{}", d.render("t.gm", src)));
            gmotion::engine::run(scene.clone(), &g, &gmotion::engine::RunOptions::default())
                .unwrap_or_else(|e| panic!("{e}"))
                .0
        };
        let raw = run(&format!("{head}{rules}"));
        let smooth = run(&format!("{head}smoothing {system}\n{rules}"));
        for (u, (r, s)) in raw.tracks.iter().zip(&smooth.tracks).enumerate() {
            let want = r.state_at(0.0);
            // The input holds its t = 0 state through the first slice's start (frames 0–2
            // at least: `inv_a` lasts 0.6 s and plays from the pre-applied state).
            for k in 0..3 {
                let t = k as f64 / 30.0;
                let (got, input) = (s.state_at(t), r.state_at(t));
                if input != want {
                    continue;
                }
                let m = (got.transform.as_coeffs(), want.transform.as_coeffs());
                let close = (0..6).all(|j| (m.0[j] - m.1[j]).abs() < 1e-6)
                    && (got.opacity - want.opacity).abs() < 1e-6
                    && (got.stroke_width - want.stroke_width).abs() < 1e-6
                    && (0..3).all(|j| (got.fill.sum[j] - want.fill.sum[j]).abs() < 1e-5)
                    && (got.fill.weight - want.fill.weight).abs() < 1e-5
                    && (0..3).all(|j| (got.stroke.sum[j] - want.stroke.sum[j]).abs() < 1e-5)
                    && (got.stroke.weight - want.stroke.weight).abs() < 1e-5;
                assert!(
                    close,
                    "{change} smoothed by {system}, shape {u}, frame {k}: {got:?} vs {want:?}"
                );
            }
        }
    }
}
