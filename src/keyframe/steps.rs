//! Stepped easings ([`Easing::Steps`](crate::signals::Easing::Steps), `hold`) as keys: the
//! progress holds between jumps, so both formats write only the jumps — Lottie as hold keys,
//! SMIL as two keys per jump — and never sample.
//!
//! A forward change jumps right-continuously (at a jump instant the value is already the new
//! one); its reversed twin, the exact time reverse, jumps left-continuously (the old value
//! still shows at the instant). Keys say a jump happens *at* a key, which is
//! right-continuous, so a reversed jump is written [`LATE`] seconds after its instant: a
//! frame falling right on it shows the value before, as the model does.

use crate::motion::Timing;

/// How late (seconds) a reversed change's jump is written: far below any frame period and
/// above the rounding of written key times (SMIL writes `keyTimes` to 1e-6 of the duration).
pub const LATE: f64 = 1e-4;

/// One jump of a stepped progress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jump {
    /// When it is written (seconds): its instant, [`LATE`] after it for a reversed change
    /// (at most the window's end).
    pub t: f64,
    /// The progress before.
    pub before: f64,
    /// The progress after.
    pub after: f64,
}

/// The jumps of `timing`'s progress inside the window `[a, b]` whose value at `a` is
/// already settled (a jump at `a` of a forward change belongs to the window before, one at
/// `b` of a reversed change to the window after), in time order. Empty when the easing is
/// not stepped.
pub fn jumps(timing: &Timing, a: f64, b: f64) -> Vec<Jump> {
    let Some(n) = timing.ease.steps() else {
        return Vec::new();
    };
    let span = timing.end - timing.start - timing.delay;
    if span <= 0.0 {
        return Vec::new();
    }
    let base = if timing.reversed {
        timing.start
    } else {
        timing.start + timing.delay
    };
    let nf = f64::from(n);
    (0..=n)
        .filter_map(|k| {
            let at = base + f64::from(k) / nf * span;
            let inside = if timing.reversed {
                a <= at && at < b
            } else {
                a < at && at <= b
            };
            if !inside {
                return None;
            }
            // The progress just before and just after the instant, from the curve itself.
            let before = timing.progress(at - 1e-6 * span);
            let after = timing.progress(at + 1e-6 * span);
            (before != after).then_some(Jump {
                t: if timing.reversed {
                    (at + LATE).min(b)
                } else {
                    at
                },
                before,
                after,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signals::Easing;

    #[test]
    fn forward_steps_jump_on_their_instants_and_reversed_ones_mirror_them() {
        let fwd = Timing::new(1.0, 3.0, 0.0, Easing::Steps(4), false);
        let js = jumps(&fwd, 1.0, 3.0);
        let ts: Vec<f64> = js.iter().map(|j| j.t).collect();
        assert_eq!(ts, [1.5, 2.0, 2.5, 3.0]);
        assert_eq!((js[0].before, js[0].after), (0.0, 0.25));
        assert_eq!((js[3].before, js[3].after), (0.75, 1.0));
        let rev = Timing::new(1.0, 3.0, 0.0, Easing::Steps(4), true);
        let js = jumps(&rev, 1.0, 3.0);
        assert_eq!(js.len(), 4);
        for (j, t) in js.iter().zip([1.0, 1.5, 2.0, 2.5]) {
            assert!((j.t - t - LATE).abs() < 1e-12);
            // The time reverse: the value at each instant is the forward value there.
            assert_eq!(rev.progress(t), fwd.progress(4.0 - t));
        }
        assert_eq!((js[0].before, js[0].after), (1.0, 0.75));
        // A hold: one jump, at the end forward and at the start reversed.
        let hold = Timing::new(0.0, 2.0, 0.5, Easing::Steps(1), false);
        assert_eq!(jumps(&hold, 0.0, 2.0).len(), 1);
        assert_eq!(jumps(&hold, 0.0, 2.0)[0].t, 2.0);
        assert!(jumps(&hold, 0.0, 1.0).is_empty());
    }
}
