//! Paint channels of the paths inside animated units: fill and stroke tints (on solid
//! colours and on gradient stops) and stroke width, with the semantics of
//! [`crate::frame`]: a tint `shown = original·(1 − w) + sum` applies to every
//! colour the unit paints; tints of nested units compose, the inner one first.

use gmotion::motion::{AttrSeg, Blendable, Tint, Track};

use super::attr::{Bake, attr_keys};
use gmotion::keyframe::Key;
use gmotion::keyframe::reduce::ramer_douglas_peucker;
use gmotion::keyframe::sample::{fraction, frame_times, sample_times};

/// Largest error of a baked colour or tint component (half an 8-bit step).
pub const COLOR_TOL: f64 = 0.5 / 255.0;
/// Largest error of a baked opacity.
pub const OPACITY_TOL: f64 = 0.5 / 255.0;
/// Largest relative error of a baked stroke width factor.
pub const WIDTH_TOL: f64 = 2e-3;
/// Largest error of a baked trim fraction (or shift, in turns).
pub const TRIM_TOL: f64 = 1e-4;

/// `outer(inner(c))` for every colour `c`, as one tint.
pub fn compose(outer: Tint, inner: Tint) -> Tint {
    let k = 1.0 - outer.weight;
    Tint {
        sum: std::array::from_fn(|i| inner.sum[i] * k + outer.sum[i]),
        weight: 1.0 - (1.0 - inner.weight) * k,
    }
}

/// Largest component difference of two tints.
pub fn tint_dist(a: Tint, b: Tint) -> f64 {
    let d = (0..3)
        .map(|i| (a.sum[i] - b.sum[i]).abs())
        .fold((a.weight - b.weight).abs(), f32::max);
    d as f64
}

/// A channel that several nested units may drive, combined by `combine` (outer first).
pub struct Chain<'a, T> {
    /// Segment lists of the units, outermost first; units that never change it are left out.
    pub segs: Vec<&'a [AttrSeg<T>]>,
    /// The value of a unit that has not changed it.
    pub rest: T,
}

impl<'a, T: Blendable + PartialEq> Chain<'a, T> {
    /// The channel from each of `tracks` (outermost first) via `get`.
    pub fn new(
        tracks: impl Iterator<Item = &'a Track>,
        get: impl Fn(&'a Track) -> &'a [AttrSeg<T>],
        rest: T,
        dur: f64,
    ) -> Self {
        let segs = tracks
            .map(get)
            .filter(|s| s.first().is_some_and(|f| f.t0 < dur))
            .collect();
        Chain { segs, rest }
    }

    /// Keys over `[0, dur]`: exact for a single unit, sampled and reduced within
    /// `bake.tolerance` when nested units both drive the channel. `None` when nothing changes.
    pub fn keys(
        &self,
        dur: f64,
        bake: &Bake<'_, T>,
        combine: impl Fn(T, T) -> T,
    ) -> Option<(Vec<Key<T>>, usize)> {
        match self.segs.as_slice() {
            [] => None,
            [one] => attr_keys(one, self.rest, dur, bake),
            many => {
                let mut extra = Vec::new();
                for s in many.iter().flat_map(|l| l.iter()) {
                    let (x, y) = s.timing.active();
                    extra.extend([s.t0, s.t1, x, y]);
                }
                extra.extend(frame_times(0.0, dur, bake.fps));
                let ts = sample_times(0.0, dur, bake.rate, 8, &extra);
                let value = |t: f64| {
                    many.iter()
                        .map(|l| value_at(l, t, self.rest))
                        .reduce(&combine)
                        .unwrap_or(self.rest)
                };
                let vs: Vec<T> = ts.iter().map(|&t| value(t)).collect();
                let keep = ramer_douglas_peucker(ts.len(), bake.tolerance, |k, lo, hi| {
                    (bake.dist)(vs[lo].blend(vs[hi], fraction(&ts, k, lo, hi)), vs[k])
                });
                Some((keep.iter().map(|&k| Key::linear(ts[k], vs[k])).collect(), 1))
            }
        }
    }
}

/// A segment list's value at `t` (the model's `attr_at`: the last segment begun holds).
fn value_at<T: Blendable>(segs: &[AttrSeg<T>], t: f64, rest: T) -> T {
    let i = segs.partition_point(|s| s.t0 <= t);
    if i == 0 {
        rest
    } else {
        segs[i - 1].value_at(t)
    }
}
