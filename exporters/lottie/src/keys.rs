//! Keyframes for values driven by a [`Timing`]'s progress: two keyframes per window (the
//! ends of its active interval) with the easing curve as Bézier handles, hold keyframes
//! where the value jumps.
//!
//! Every channel gmotion animates is an affine function of progress (component parameters,
//! tints, multipliers), and a player interpolates keyframe values affinely along the easing
//! curve, so two keyframes reproduce a window exactly whenever the easing is a cubic Bézier
//! — also over a partial window, whose piece of the curve is again a cubic Bézier.

use kurbo::{CubicBez, ParamCurve, Point};

use super::model::{Ease, Keyframe, N, Value};
use gmotion::motion::reduce::greedy;
use gmotion::motion::{Timing, Tint};
use gmotion::signals::Easing;
use gmotion::signals::easing::solve_bezier_x;

/// Values compared the way output is written: equal when no player could tell them apart.
pub trait Near {
    /// Whether `self` and `other` are the same value up to float noise.
    fn near(&self, other: &Self) -> bool;
}

fn near_f64(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0)
}

impl Near for f64 {
    fn near(&self, o: &f64) -> bool {
        near_f64(*self, *o)
    }
}

impl<const K: usize> Near for [f64; K] {
    fn near(&self, o: &Self) -> bool {
        self.iter().zip(o).all(|(a, b)| near_f64(*a, *b))
    }
}

impl Near for Tint {
    fn near(&self, o: &Tint) -> bool {
        near_f64(self.weight as f64, o.weight as f64)
            && self
                .sum
                .iter()
                .zip(&o.sum)
                .all(|(a, b)| near_f64(*a as f64, *b as f64))
    }
}

/// A keyframe with its value still in the caller's terms; `t` in frames.
#[derive(Clone, Debug, PartialEq)]
pub struct Key<V> {
    /// Frame.
    pub t: f64,
    /// Value.
    pub v: V,
    /// CSS-style Bézier easing to the next keyframe; `None` means linear.
    pub ease: Option<[f64; 4]>,
    /// Hold the value until the next keyframe.
    pub hold: bool,
}

/// One window a channel changes in.
#[derive(Clone, Copy, Debug)]
pub struct Piece<'a> {
    /// Window start (seconds).
    pub t0: f64,
    /// Window end (seconds), already cut where the next window begins.
    pub t1: f64,
    /// What drives the progress.
    pub timing: &'a Timing,
}

/// How far apart (in frames) a value jump is written when it happens right on a keyframe.
const JUMP: f64 = 1e-3;

/// Builds the keyframes of a channel that holds `default` before its first window and
/// `value(piece, progress)` within (and after) each window. `tolerance(piece)` is the
/// progress error allowed where an easing is not a Bézier and must be sampled.
pub fn progress_keys<V: Clone + Near>(
    pieces: &[Piece],
    fps: f64,
    default: V,
    value: impl Fn(usize, f64) -> V,
    tolerance: impl Fn(usize) -> f64,
) -> Vec<Key<V>> {
    let mut keys: Vec<Key<V>> = Vec::new();
    let mut current = default;
    for (k, piece) in pieces.iter().enumerate() {
        let timing = piece.timing;
        let p0 = timing.progress(piece.t0);
        let v0 = value(k, p0);
        if !v0.near(&current) {
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
            if !vb.near(&current) || pa != pb {
                let u = |t: f64| {
                    let local = if timing.reversed {
                        t - timing.start
                    } else {
                        t - timing.start - timing.delay
                    };
                    (local / span).clamp(0.0, 1.0)
                };
                match timing.ease.as_cubic_bezier() {
                    Some(css) => eased(
                        &mut keys,
                        (a, b),
                        (u(a), u(b)),
                        css,
                        timing.reversed,
                        fps,
                        |p| value(k, p),
                    ),
                    None => sampled(
                        &mut keys,
                        (a, b),
                        fps,
                        tolerance(k),
                        |t| timing.progress(t),
                        |p| value(k, p),
                    ),
                }
                current = vb;
            }
        }
        // A zero-length or already finished change steps at its active instant.
        let p1 = timing.progress(piece.t1);
        let v1 = value(k, p1);
        if !v1.near(&current) {
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

/// Makes the value step from `before` to `after` at frame `t`.
fn jump<V: Clone>(keys: &mut Vec<Key<V>>, t: f64, before: V, after: V) {
    match keys.last_mut() {
        None => {
            if t > 0.0 {
                keys.push(Key {
                    t: 0.0f64.min(t - JUMP),
                    v: before,
                    ease: None,
                    hold: true,
                });
            }
        }
        Some(last) if last.t < t - JUMP => {
            last.hold = true;
        }
        Some(last) => {
            // The previous value is reached exactly here: arrive a hair earlier, then step.
            last.t = t - JUMP;
            last.hold = true;
        }
    }
    keys.push(Key {
        t,
        v: after,
        ease: None,
        hold: false,
    });
}

/// Appends a key at `t` unless the last key is already there with the same value.
fn push_key<V: Clone + Near>(keys: &mut Vec<Key<V>>, t: f64, v: V) {
    if let Some(last) = keys.last()
        && (last.t - t).abs() < 1e-9
        && last.v.near(&v)
    {
        return;
    }
    keys.push(Key {
        t,
        v,
        ease: None,
        hold: false,
    });
}

/// Keys for the eased stretch `[a, b]` (seconds) whose linear progress runs `ua → ub`.
#[allow(clippy::too_many_arguments)]
fn eased<V: Clone + Near>(
    keys: &mut Vec<Key<V>>,
    (a, b): (f64, f64),
    (ua, ub): (f64, f64),
    css: [f64; 4],
    reversed: bool,
    fps: f64,
    value: impl Fn(f64) -> V + Copy,
) {
    // Progress as a function of linear time fraction: `y(u)`, and progress = y or 1 − y.
    let [x1, y1, x2, y2] = css;
    let curve = if reversed {
        CubicBez::new(
            (0.0, 0.0),
            (1.0 - x2, 1.0 - y2),
            (1.0 - x1, 1.0 - y1),
            (1.0, 1.0),
        )
    } else {
        CubicBez::new((0.0, 0.0), (x1, y1), (x2, y2), (1.0, 1.0))
    };
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
            Some([ox.clamp(0.0, 1.0), oy, ix.clamp(0.0, 1.0), iy])
        } else {
            None
        };
        if let Some(last) = keys.last_mut() {
            last.ease = ease;
        }
        keys.push(Key {
            t: t_end * fps,
            v: value(progress(q3.y)),
            ease: None,
            hold: false,
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

/// Keys for `[a, b]` from progress sampled at every frame, thinned so that linear
/// interpolation stays within `tolerance` of the progress.
fn sampled<V: Clone + Near>(
    keys: &mut Vec<Key<V>>,
    (a, b): (f64, f64),
    fps: f64,
    tolerance: f64,
    progress: impl Fn(f64) -> f64,
    value: impl Fn(f64) -> V,
) {
    let mut times = vec![a];
    let first = (a * fps).floor() as i64 + 1;
    let last = (b * fps).ceil() as i64 - 1;
    times.extend(
        (first..=last)
            .map(|f| f as f64 / fps)
            .filter(|t| *t > a && *t < b),
    );
    times.push(b);
    let ps: Vec<f64> = times.iter().map(|t| progress(*t)).collect();
    let kept = greedy(times.len(), |i, j| {
        (i + 1..j).all(|m| {
            let f = (times[m] - times[i]) / (times[j] - times[i]);
            (ps[i] + (ps[j] - ps[i]) * f - ps[m]).abs() <= tolerance
        })
    });
    for i in kept {
        push_key(keys, times[i] * fps, value(ps[i]));
    }
}

/// Turns keys into Lottie keyframes with `to_value` mapping each value; a key whose next
/// key has the same value becomes a hold.
pub fn to_keyframes<V: Near>(keys: &[Key<V>], to_value: impl Fn(&V) -> Value) -> Vec<Keyframe> {
    let n = keys.len();
    keys.iter()
        .enumerate()
        .map(|(i, k)| {
            let last = i + 1 == n;
            let hold = !last && (k.hold || keys[i + 1].v.near(&k.v));
            Keyframe {
                t: N::coord(k.t),
                s: to_value(&k.v),
                ease: if last || hold {
                    None
                } else {
                    Some(k.ease.map_or(Ease::LINEAR, Ease::from_css))
                },
                hold,
            }
        })
        .collect()
}

/// `keys` with every eased stretch that carries the value out of its range sampled as one
/// linear key per frame. Players interpolate each channel along the keyframe's easing, and
/// an overshooting Bézier (`cubic(0.3, -0.3, 0.7, 1.3)`) passes the ends it eases between:
/// near a colour channel's 0 or 1, or full opacity, that leaves the range. The model clamps
/// there, and so do lottie-web and ThorVG, but rlottie wraps: a yellow whose red passes 1
/// drew green (matrix gm-0187), a layer faded from 100% drew at about 0% while its
/// opacity overshot (gm-0199). `leaves(a, b, lo, hi)` tells whether a stretch from `a` to
/// `b` leaves the range at some progress in `[lo, hi]`; `clamped(a, b, p)` is the model's
/// value at progress `p`.
pub fn within_range<V: Clone>(
    keys: &[Key<V>],
    leaves: impl Fn(&V, &V, f64, f64) -> bool,
    clamped: impl Fn(&V, &V, f64) -> V,
) -> Vec<Key<V>> {
    let mut out = Vec::with_capacity(keys.len());
    for (k, next) in keys.iter().zip(keys.iter().skip(1)) {
        out.push(k.clone());
        // A curve whose control points' y lie in [0, 1] stays there (it lies in their convex
        // hull): most easings, and no need to scan them (257 curve solves per key were a
        // tenth of a large export).
        let in_hull = |e: &[f64; 4]| (0.0..=1.0).contains(&e[1]) && (0.0..=1.0).contains(&e[3]);
        let Some(ease) = k.ease.filter(|e| !k.hold && !in_hull(e)) else {
            continue;
        };
        let curve = Easing::CubicBezier(ease);
        let (lo, hi) = (0..=256)
            .map(|i| curve.apply(i as f64 / 256.0))
            .fold((0.0_f64, 1.0_f64), |(lo, hi), p| (lo.min(p), hi.max(p)));
        if (lo, hi) == (0.0, 1.0) || !leaves(&k.v, &next.v, lo, hi) {
            continue;
        }
        out.last_mut().expect("just pushed").ease = None;
        let mut f = k.t.floor() + 1.0;
        while f < next.t {
            let p = curve.apply((f - k.t) / (next.t - k.t));
            out.push(Key {
                t: f,
                v: clamped(&k.v, &next.v, p),
                ease: None,
                hold: false,
            });
            f += 1.0;
        }
    }
    out.extend(keys.last().cloned());
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use gmotion::signals::Easing;

    /// Evaluates keys the way a player does (CSS cubic-bezier easing between keys).
    fn eval(keys: &[Key<f64>], frame: f64) -> f64 {
        if frame <= keys[0].t {
            return keys[0].v;
        }
        for w in keys.windows(2) {
            let (k0, k1) = (&w[0], &w[1]);
            if frame < k1.t {
                if k0.hold {
                    return k0.v;
                }
                let u = (frame - k0.t) / (k1.t - k0.t);
                let y = match k0.ease {
                    Some(c) => Easing::CubicBezier(c).apply(u),
                    None => u,
                };
                return k0.v + (k1.v - k0.v) * y;
            }
        }
        keys.last().unwrap().v
    }

    fn check(pieces: &[Piece], default: f64, values: &[(f64, f64)]) {
        let fps = 10.0;
        let keys = progress_keys(
            pieces,
            fps,
            default,
            |k, p| values[k].0 + (values[k].1 - values[k].0) * p,
            |_| 1e-4,
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
            let got = eval(&keys, f as f64);
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
