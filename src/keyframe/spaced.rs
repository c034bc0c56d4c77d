//! [`Format::Spaced`](super::Format::Spaced): keys for Lottie players. Two keys per window
//! (the ends of its active interval) with the easing curve as Bézier handles, hold keys
//! where the value jumps, times in frames.
//!
//! A partial window's piece of the easing curve is again a cubic Bézier, so the keys are
//! exact whenever the easing is one; other easings are sampled at every frame
//! ([`frame_progress`]).

use kurbo::{CubicBez, ParamCurve, Point};

use super::sample::frame_progress;
use super::{Ease, Key, Piece, Same, steps};
use crate::signals::easing::solve_bezier_x;
use crate::tolerance::KEY_TIME;

/// How far apart (in frames) a value jump is written when it happens right on a keyframe.
pub const JUMP: f64 = 1e-3;

/// The keys of a channel that holds `default` before its first window and
/// `value(piece, progress)` within (and after) each window, at `fps`; `tolerance` is the
/// progress error allowed where an easing is not a Bézier and must be sampled.
pub fn keys<V: Clone + Same>(
    pieces: &[Piece],
    fps: f64,
    default: V,
    value: impl Fn(usize, f64) -> V,
    tolerance: f64,
) -> Vec<Key<V>> {
    let mut keys: Vec<Key<V>> = Vec::new();
    let mut current = default;
    for (k, piece) in pieces.iter().enumerate() {
        let timing = piece.timing;
        let p0 = timing.progress(piece.t0);
        let v0 = value(k, p0);
        if !v0.same(&current) {
            jump(&mut keys, piece.t0 * fps, current, v0.clone());
        }
        current = v0;
        let (act0, act1) = timing.active();
        let a = piece.t0.max(act0);
        let b = piece.t1.min(act1);
        let span = timing.end - timing.start - timing.delay;
        if b > a && span > 0.0 {
            let pb = timing.progress(b);
            let vb = value(k, pb);
            let pa = timing.progress(a);
            if !vb.same(&current) || pa != pb {
                let u = |t: f64| {
                    let local = if timing.reversed {
                        t - timing.start
                    } else {
                        t - timing.start - timing.delay
                    };
                    (local / span).clamp(0.0, 1.0)
                };
                match timing.ease.as_cubic_bezier() {
                    None if timing.ease.steps().is_some() => {
                        for j in steps::jumps(timing, a, b) {
                            jump(&mut keys, j.t * fps, value(k, j.before), value(k, j.after));
                        }
                    }
                    Some(css) => eased(
                        &mut keys,
                        Stretch {
                            times: (a, b),
                            linear: (u(a), u(b)),
                            fps,
                        },
                        curve(css, timing.reversed),
                        timing.reversed,
                        |p| value(k, p),
                    ),
                    None => {
                        for (t, p) in frame_progress((a, b), fps, tolerance, |t| timing.progress(t))
                        {
                            push_key(&mut keys, t * fps, value(k, p));
                        }
                    }
                }
                current = vb;
            }
        }
        // A zero-length or already finished change steps at its active instant.
        let p1 = timing.progress(piece.t1);
        let v1 = value(k, p1);
        if !v1.same(&current) {
            let at = if span <= 0.0 {
                act0.clamp(piece.t0, piece.t1)
            } else {
                piece.t1
            };
            jump(&mut keys, at * fps, current, v1.clone());
            current = v1;
        }
    }
    keys
}

/// Makes the value step from `before` to `after` at frame `t`: the key at `t` holds the
/// previous value until then.
fn jump<V: Clone>(keys: &mut Vec<Key<V>>, t: f64, before: V, after: V) {
    match keys.last_mut() {
        None => {
            if t > 0.0 {
                keys.push(Key::linear(0.0f64.min(t - JUMP), before));
            }
        }
        Some(last) if last.t < t - JUMP => {}
        Some(last) => {
            // The previous value is reached exactly here: arrive a hair earlier, then step.
            last.t = t - JUMP;
        }
    }
    keys.push(Key {
        t,
        v: after,
        ease: Ease::Hold,
    });
}

/// Appends a key at `t` reached linearly, unless the last key is already there with the
/// same value.
fn push_key<V: Clone + Same>(keys: &mut Vec<Key<V>>, t: f64, v: V) {
    if let Some(last) = keys.last()
        && KEY_TIME.same(last.t, t)
        && last.v.same(&v)
    {
        return;
    }
    keys.push(Key::linear(t, v));
}

/// An eased stretch: its times `[a, b]` (seconds), the linear progress `ua → ub` over them,
/// and the frame rate keys are written at.
struct Stretch {
    times: (f64, f64),
    linear: (f64, f64),
    fps: f64,
}

/// Progress as a function of linear time fraction `y(u)` (progress is `y`, or `1 − y`
/// reversed): the CSS curve, mirrored when reversed.
fn curve([x1, y1, x2, y2]: [f64; 4], reversed: bool) -> CubicBez {
    if reversed {
        CubicBez::new(
            (0.0, 0.0),
            (1.0 - x2, 1.0 - y2),
            (1.0 - x1, 1.0 - y1),
            (1.0, 1.0),
        )
    } else {
        CubicBez::new((0.0, 0.0), (x1, y1), (x2, y2), (1.0, 1.0))
    }
}

/// Keys for an eased stretch along `curve`.
fn eased<V: Clone + Same>(
    keys: &mut Vec<Key<V>>,
    Stretch {
        times: (a, b),
        linear: (ua, ub),
        fps,
    }: Stretch,
    curve: CubicBez,
    reversed: bool,
    value: impl Fn(f64) -> V + Copy,
) {
    let progress = |y: f64| if reversed { 1.0 - y } else { y };
    let sa = solve_bezier_x(&curve, ua);
    let sb = solve_bezier_x(&curve, ub);
    let pieces = split_monotone(&curve, sa, sb);
    let mut t = a;
    push_key(keys, a * fps, value(progress(curve.eval(sa).y)));
    for (s0, s1) in pieces {
        let sub = curve.subsegment(s0..s1);
        let (q0, q3) = (sub.p0, sub.p3);
        let dx = q3.x - q0.x;
        let dy = q3.y - q0.y;
        let t_end = if ub > ua {
            a + (q3.x - ua) / (ub - ua) * (b - a)
        } else {
            b
        };
        let ease = if dx.abs() > 1e-12 && dy.abs() > 1e-12 {
            let n = |p: Point| ((p.x - q0.x) / dx, (p.y - q0.y) / dy);
            let (ox, oy) = n(sub.p1);
            let (ix, iy) = n(sub.p2);
            Ease::Bezier([ox.clamp(0.0, 1.0), oy, ix.clamp(0.0, 1.0), iy])
        } else {
            Ease::Linear
        };
        keys.push(Key {
            t: t_end * fps,
            v: value(progress(q3.y)),
            ease,
        });
        t = t_end;
    }
    debug_assert!((t - b).abs() < 1e-6 * b.abs().max(1.0));
}

/// Splits `[s0, s1]` where the curve's `y` turns, so that each part's ends differ in value
/// whenever the part moves at all (a keyframe pair cannot rise and return to its start).
fn split_monotone(curve: &CubicBez, s0: f64, s1: f64) -> Vec<(f64, f64)> {
    let (a, b) = (curve.eval(s0).y, curve.eval(s1).y);
    if (b - a).abs() > 1e-9 || s1 - s0 < 1e-6 {
        return vec![(s0, s1)];
    }
    let mid = 0.5 * (s0 + s1);
    let moves = (0..=8).any(|k| (curve.eval(s0 + (s1 - s0) * k as f64 / 8.0).y - a).abs() > 1e-9);
    if !moves {
        return vec![(s0, s1)];
    }
    vec![(s0, mid), (mid, s1)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::keyframe::tests::play;
    use crate::motion::Timing;
    use crate::signals::Easing;

    fn check(pieces: &[Piece], default: f64, values: &[(f64, f64)]) {
        let fps = 10.0;
        let keys = keys(
            pieces,
            fps,
            default,
            |k, p| values[k].0 + (values[k].1 - values[k].0) * p,
            1e-4,
        );
        for f in 0..=80 {
            let t = f as f64 / fps;
            // The reference: the last piece that started, else the default.
            let want = match pieces.iter().rposition(|p| p.t0 <= t) {
                None => default,
                Some(k) => {
                    let p = pieces[k]
                        .timing
                        .progress(t.clamp(pieces[k].t0, pieces[k].t1));
                    values[k].0 + (values[k].1 - values[k].0) * p
                }
            };
            let got = play(&keys, f as f64);
            // A jump onto a keyframe arrives a thousandth of a frame early (`JUMP`).
            assert!(
                (got - want).abs() < 1e-4,
                "frame {f}: got {got}, want {want}; keys {keys:?}"
            );
        }
    }

    #[test]
    fn eased_window_is_exact() {
        let ease = Easing::CubicBezier([0.42, 0.0, 0.58, 1.0]);
        let t = Timing::new(1.0, 5.0, 0.5, ease, false);
        check(
            &[Piece {
                t0: 1.0,
                t1: 5.0,
                timing: &t,
            }],
            0.0,
            &[(0.0, 10.0)],
        );
    }

    #[test]
    fn reversed_and_partial_windows_are_exact() {
        let ease = Easing::CubicBezier([0.3, -0.4, 0.7, 1.6]);
        let t = Timing::new(0.0, 6.0, 1.0, ease, true);
        check(
            &[
                Piece {
                    t0: 0.0,
                    t1: 2.5,
                    timing: &t,
                },
                Piece {
                    t0: 2.5,
                    t1: 6.0,
                    timing: &t,
                },
            ],
            3.0,
            &[(3.0, -7.0), (3.0, -7.0)],
        );
    }

    #[test]
    fn jumps_are_held() {
        let a = Timing::new(0.0, 3.0, 0.0, Easing::Linear, false);
        let ease = Easing::CubicBezier([0.25, 0.1, 0.25, 1.0]);
        let b = Timing::new(3.0, 6.0, 0.0, ease, false);
        check(
            &[
                Piece {
                    t0: 0.0,
                    t1: 3.0,
                    timing: &a,
                },
                Piece {
                    t0: 3.0,
                    t1: 6.0,
                    timing: &b,
                },
            ],
            1.0,
            &[(1.0, 2.0), (5.0, 0.0)],
        );
        check(
            &[Piece {
                t0: 2.0,
                t1: 3.0,
                timing: &a,
            }],
            1.0,
            &[(4.0, 4.0)],
        );
    }
}
