//! Attribute channels (tints, opacity, stroke width) as keys over the document.
//!
//! An [`AttrSeg`] list holds its last value between segments, so the channel is a chain of
//! holds, jumps (equal-time keys) and eased runs; every run is exact because the value is
//! linear in the progress. The progress of an easing SMIL cannot say is sampled and reduced.

use gmotion::keyframe::sample::{frame_times, sample_times, sampled_progress};
use gmotion::keyframe::{Format, Key, Piece, progress_keys};
use gmotion::motion::{AttrSeg, Blendable};

/// How baked attribute values are compared.
pub struct Bake<'a, T> {
    /// Samples per second.
    pub rate: f64,
    /// The animation's frame rate (every frame instant is sampled too).
    pub fps: f64,
    /// Largest allowed `dist` between the played and the true value.
    pub tolerance: f64,
    /// Distance between two values.
    pub dist: &'a dyn Fn(T, T) -> f64,
}

/// The channel's keys over `[0, dur]`, starting from `default`; `None` when it never
/// changes. The second value counts the segments that had to be baked.
pub fn attr_keys<T: Blendable + PartialEq>(
    segs: &[AttrSeg<T>],
    default: T,
    dur: f64,
    bake: &Bake<'_, T>,
) -> Option<(Vec<Key<T>>, usize)> {
    let n = segs.partition_point(|s| s.t0 < dur);
    if n == 0 {
        return None;
    }
    let mut keys = vec![Key::linear(0.0, default)];
    let mut baked = 0;
    for (i, seg) in segs[..n].iter().enumerate() {
        let next_t0 = segs.get(i + 1).map_or(dur, |s| s.t0.min(dur));
        // A segment the next one replaces at its start (an outer change cut away where an
        // inner one begins) is never shown: the model plays the last segment begun. Its
        // value written between the boundary's keys would play a hair before the boundary.
        if next_t0 <= seg.t0 {
            continue;
        }
        let a = seg.t0.max(0.0);
        let b = seg.t1.min(next_t0).max(a);
        let held = keys[keys.len() - 1].v;
        keys.push(Key::linear(a, held));
        let piece = Piece {
            t0: a,
            t1: b,
            timing: &seg.timing,
        };
        let progress = seg.timing.progress(a);
        match progress_keys(&[piece], progress, |_, p| p, Format::UnitBox) {
            Some(ps) => keys.extend(ps.iter().map(|k| Key {
                t: k.t,
                v: seg.from.blend(seg.to, k.v),
                ease: k.ease,
            })),
            None => {
                baked += 1;
                let (x, y) = seg.timing.active();
                let mut extra = vec![x, y];
                extra.extend(frame_times(a, b, bake.fps));
                let ts = sample_times(a, b, bake.rate, 8, &extra);
                let value = |p: f64| seg.from.blend(seg.to, p);
                let ps = sampled_progress(&seg.timing, &ts, bake.tolerance, |_, played, truth| {
                    (bake.dist)(value(played), value(truth))
                });
                keys.extend(ps.iter().map(|k| Key {
                    t: k.t,
                    v: value(k.v),
                    ease: k.ease,
                }));
            }
        }
    }
    keys.iter().any(|k| k.v != default).then_some((keys, baked))
}
