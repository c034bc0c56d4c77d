//! Properties of [`progress_keys`] in both formats, checked with one player.

use super::*;
use crate::signals::Easing;

/// What a player computes from `keys` at time `t`: before the first key its value, after
/// the last the last value; between two keys the later key's easing from the earlier value
/// (at equal times, the later key wins).
pub(super) fn play(keys: &[Key<f64>], t: f64) -> f64 {
    let i = keys.partition_point(|k| k.t <= t);
    if i == 0 {
        return keys[0].v;
    }
    if i == keys.len() {
        return keys[i - 1].v;
    }
    let (a, b) = (&keys[i - 1], &keys[i]);
    let x = (t - a.t) / (b.t - a.t);
    let y = match b.ease {
        Ease::Linear => x,
        Ease::Bezier(s) => Easing::CubicBezier(s).apply(x),
        Ease::Hold => 0.0,
    };
    a.v + (b.v - a.v) * y
}

const FPS: f64 = 24.0;

fn formats() -> [Format; 2] {
    [
        Format::UnitBox,
        Format::Spaced {
            fps: FPS,
            tolerance: 1e-4,
        },
    ]
}

/// Seconds to the format's unit.
fn unit(format: Format) -> f64 {
    match format {
        Format::UnitBox => 1.0,
        Format::Spaced { fps, .. } => fps,
    }
}

/// Whether a key's Bézier has a time handle clamped onto the far box edge (an outgoing
/// handle at 1 or an incoming one at 0; none of [`timings`] has one of its own). Lottie players need a
/// keyframe's time handles in `[0, 1]`, and the piece of an S-curve cut inside a window can
/// have one outside: [`Format::Spaced`] clamps it onto the edge, which bends the curve
/// between the keys (by about 1 % of the change for `cubic(0.9, 0.1, 0.1, 0.9)` cut at a
/// third). The exporter has always written it so and its output must not change, so only
/// the keys themselves are checked there.
fn clamped(keys: &[Key<f64>]) -> bool {
    keys.iter().any(|k| match k.ease {
        Ease::Bezier([x1, _, x2, _]) => x1 == 1.0 || x2 == 0.0,
        _ => false,
    })
}

fn timings() -> Vec<Timing> {
    let eases = [
        Easing::Linear,
        Easing::CubicBezier([0.42, 0.0, 0.58, 1.0]),
        Easing::CubicBezier([0.3, -0.6, 0.4, 1.7]),
        Easing::CubicBezier([0.9, 0.1, 0.1, 0.9]),
    ];
    let mut out = Vec::new();
    for ease in eases {
        for reversed in [false, true] {
            for delay in [0.0, 0.5] {
                out.push(Timing::new(1.0, 3.0, delay, ease.clone(), reversed));
            }
        }
    }
    out
}

/// The keys of `value ∘ progress` over the pieces `[t0, t1]` of one timing, in `format`.
fn keys_of(timing: &Timing, cuts: &[(f64, f64)], format: Format) -> Vec<Key<f64>> {
    let pieces: Vec<Piece> = cuts
        .iter()
        .map(|&(t0, t1)| Piece { t0, t1, timing })
        .collect();
    let value = |_: usize, p: f64| 5.0 - 12.0 * p;
    let default = value(0, timing.progress(cuts[0].0));
    progress_keys(&pieces, default, value, format).expect("Bézier easings")
}

#[test]
fn keys_reproduce_progress_at_the_ends_and_between() {
    for format in formats() {
        let u = unit(format);
        for timing in timings() {
            for cuts in [
                vec![(0.0, 4.0)],
                vec![(1.0, 3.0)],
                vec![(1.3, 2.2)],
                vec![(0.5, 2.0), (2.0, 3.5)],
            ] {
                let keys = keys_of(&timing, &cuts, format);
                let (a, b) = (cuts[0].0, cuts[cuts.len() - 1].1);
                let exact = format == Format::UnitBox || !clamped(&keys);
                for i in (0..=800).filter(|_| exact) {
                    let t = a + (b - a) * i as f64 / 800.0;
                    let want = 5.0 - 12.0 * timing.progress(t);
                    let got = play(&keys, t * u);
                    assert!(
                        (got - want).abs() < 1e-6,
                        "{format:?} {timing:?} {cuts:?} at {t}: {got} vs {want}; {keys:?}"
                    );
                }
                // The window ends are keys of their own (or held up to them).
                for &(t0, t1) in &cuts {
                    for t in [t0, t1] {
                        let want = 5.0 - 12.0 * timing.progress(t);
                        assert!((play(&keys, t * u) - want).abs() < 1e-9, "{format:?} {t}");
                    }
                }
                assert!(keys.windows(2).all(|w| w[1].t >= w[0].t), "{keys:?}");
            }
        }
    }
}

#[test]
fn unit_box_splines_stay_in_the_unit_box() {
    // Overshooting curves cut anywhere: their pieces leave the box until halved.
    for y in [-2.0, -0.6, 0.3, 1.7, 3.0] {
        for ease in [
            Easing::CubicBezier([0.2, y, 0.8, 1.0 - y]),
            Easing::CubicBezier([0.0, y, 1.0, y]),
            Easing::CubicBezier([1.0, 0.0, 0.0, y]),
        ] {
            for reversed in [false, true] {
                let timing = Timing::new(0.0, 2.0, 0.25, ease.clone(), reversed);
                for cuts in [(0.0, 2.0), (0.4, 1.1), (1.7, 2.0)] {
                    let keys = keys_of(&timing, &[cuts], Format::UnitBox);
                    for k in &keys {
                        match k.ease {
                            Ease::Bezier(s) => assert!(
                                s.iter().all(|v| (0.0..=1.0).contains(v)),
                                "{ease:?} {cuts:?}: {s:?}"
                            ),
                            Ease::Linear => {}
                            Ease::Hold => panic!("SMIL holds are equal values: {keys:?}"),
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn jumps_are_held_as_each_format_expects() {
    // A change with no duration steps at 1 s; a second piece starts elsewhere.
    let step = Timing::new(1.0, 1.0, 0.0, Easing::Linear, false);
    let run = Timing::new(3.0, 4.0, 0.0, Easing::Linear, false);
    let pieces = [
        Piece {
            t0: 0.0,
            t1: 2.0,
            timing: &step,
        },
        Piece {
            t0: 3.0,
            t1: 4.0,
            timing: &run,
        },
    ];
    let value = |k: usize, p: f64| if k == 0 { 2.0 * p } else { 7.0 + p };
    let at = |keys: &[Key<f64>]| keys.iter().map(|k| (k.t, k.v)).collect::<Vec<_>>();

    // SMIL: a jump is two keys at one time, a hold two keys of one value.
    let smil = progress_keys(&pieces, 0.0, value, Format::UnitBox).unwrap();
    assert_eq!(
        at(&smil),
        vec![
            (0.0, 0.0),
            (1.0, 0.0),
            (1.0, 2.0),
            (2.0, 2.0),
            (3.0, 2.0),
            (3.0, 7.0),
            (4.0, 8.0)
        ]
    );
    assert!(smil.iter().all(|k| k.ease == Ease::Linear));

    // Lottie: a jump is a hold into the new value, spaced a hair after a key it lands on.
    let format = Format::Spaced {
        fps: 10.0,
        tolerance: 1e-4,
    };
    let lottie = progress_keys(&pieces, 0.0, value, format).unwrap();
    let holds: Vec<(f64, f64)> = lottie
        .iter()
        .filter(|k| k.ease == Ease::Hold)
        .map(|k| (k.t, k.v))
        .collect();
    assert_eq!(holds, vec![(10.0, 2.0), (30.0, 7.0)]);
    for (i, k) in lottie.iter().enumerate().skip(1) {
        if k.ease == Ease::Hold {
            let before = &lottie[i - 1];
            assert!(k.t - before.t >= spaced::JUMP * (1.0 - 1e-9), "{lottie:?}");
        }
    }
    for t in [0.5, 0.99, 1.0, 1.5, 2.5, 2.99, 3.0, 3.5, 4.0, 5.0] {
        let want = match t {
            t if t < 1.0 => 0.0,
            t if t < 3.0 => 2.0,
            t => 7.0 + run.progress(t),
        };
        assert!(
            (play(&lottie, t * 10.0) - want).abs() < 1e-9,
            "{t}: {lottie:?}"
        );
    }
}

/// A piece that begins, after a gap, at the value the previous one ended in (a morph held
/// until its inverted twin plays it back) holds through the gap, then runs its own easing.
#[test]
fn a_run_after_a_gap_from_the_same_value_holds_through_the_gap() {
    let there = Timing::new(
        0.0,
        1.0,
        0.0,
        Easing::CubicBezier([0.42, 0.0, 1.0, 1.0]),
        false,
    );
    let back = Timing::new(
        3.0,
        4.0,
        0.0,
        Easing::CubicBezier([0.0, 0.0, 0.58, 1.0]),
        true,
    );
    let pieces = [
        Piece {
            t0: 0.0,
            t1: 1.0,
            timing: &there,
        },
        Piece {
            t0: 3.0,
            t1: 4.0,
            timing: &back,
        },
    ];
    let timings = [&there, &back];
    let model = |t: f64| {
        let k = usize::from(t >= 3.0);
        timings[k].progress(t.clamp(pieces[k].t0, pieces[k].t1))
    };
    assert_eq!(
        back.progress(3.0),
        1.0,
        "the twin starts where the run ended"
    );
    let keys = progress_keys(&pieces, 0.0, |_, p| p, Format::UnitBox).unwrap();
    for i in 0..=400 {
        let t = i as f64 * 0.01;
        let (got, want) = (play(&keys, t), model(t));
        assert!(
            (got - want).abs() < 1e-6,
            "at {t}: {got} for {want} ({keys:?})"
        );
    }
}
