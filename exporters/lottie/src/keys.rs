//! The core's keys ([`gmotion::keyframe`], made in `Format::Spaced`) as Lottie keyframes:
//! each key's easing and hold written on the keyframe before it, and eased stretches that
//! would carry a value out of its range sampled for rlottie.

use super::model::{Keyframe, LINEAR, N, Value, from_css};
use gmotion::keyframe::{Ease, Key, Same};
use gmotion::signals::Easing;

/// Turns keys into Lottie keyframes with `to_value` mapping each value. Lottie writes how a
/// channel leaves a keyframe: a key's easing goes on the keyframe before it, and a key
/// reached by a hold, or whose value the next key repeats, makes that keyframe a hold.
pub fn to_keyframes<V: Same>(keys: &[Key<V>], to_value: impl Fn(&V) -> Value) -> Vec<Keyframe> {
    keys.iter()
        .enumerate()
        .map(|(i, k)| {
            let next = keys.get(i + 1);
            let hold = next.is_some_and(|n| n.ease == Ease::Hold || n.v.same(&k.v));
            Keyframe::written(
                N::coord(k.t),
                to_value(&k.v),
                next.filter(|_| !hold).map(|n| match n.ease {
                    Ease::Bezier(css) => from_css(css),
                    Ease::Linear | Ease::Hold => LINEAR,
                }),
                hold,
            )
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
    // Whether the stretch into the next key was sampled: it is then reached linearly.
    let mut sampled = false;
    let reached = |k: &Key<V>, sampled: bool| Key {
        ease: if sampled { Ease::Linear } else { k.ease },
        ..k.clone()
    };
    for (k, next) in keys.iter().zip(keys.iter().skip(1)) {
        out.push(reached(k, sampled));
        sampled = false;
        // A curve whose control points' y lie in [0, 1] stays there (it lies in their convex
        // hull): most easings, and no need to scan them (257 curve solves per key were a
        // tenth of a large export).
        let in_hull = |e: &[f64; 4]| (0.0..=1.0).contains(&e[1]) && (0.0..=1.0).contains(&e[3]);
        let Ease::Bezier(ease) = next.ease else {
            continue;
        };
        if in_hull(&ease) {
            continue;
        }
        let curve = Easing::CubicBezier(ease);
        let (lo, hi) = (0..=256)
            .map(|i| curve.apply(i as f64 / 256.0))
            .fold((0.0_f64, 1.0_f64), |(lo, hi), p| (lo.min(p), hi.max(p)));
        if (lo, hi) == (0.0, 1.0) || !leaves(&k.v, &next.v, lo, hi) {
            continue;
        }
        sampled = true;
        let mut f = k.t.floor() + 1.0;
        while f < next.t {
            let p = curve.apply((f - k.t) / (next.t - k.t));
            out.push(Key::linear(f, clamped(&k.v, &next.v, p)));
            f += 1.0;
        }
    }
    out.extend(keys.last().map(|k| reached(k, sampled)));
    out
}
