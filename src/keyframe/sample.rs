//! Baking: sampling what a format cannot say exactly (an easing that is not a cubic
//! Bézier) and keeping only the samples that interpolation needs to stay within an error
//! bound. [`sampled_progress`] is SMIL's ([`Format::UnitBox`]: the caller measures the
//! error, pieces are unit-box splines), [`frame_progress`] Lottie's ([`Format::Spaced`]:
//! one sample per frame, straight pieces, the error in progress).

#[cfg(doc)]
use super::Format;
use super::reduce::{greedy, ramer_douglas_peucker};
use super::unit_box::TIME_EPS;
use super::{Ease, Key};
use crate::motion::Timing;
use crate::tolerance::PROGRESS;

/// Sample times over `[a, b]`: uniform at `rate` per second (at least `min` intervals),
/// plus `extra` instants that fall inside (where the motion changes character).
pub fn sample_times(a: f64, b: f64, rate: f64, min: usize, extra: &[f64]) -> Vec<f64> {
    if b <= a {
        return vec![a];
    }
    let n = (((b - a) * rate).ceil() as usize).max(min).min(1 << 16);
    let mut ts: Vec<f64> = (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect();
    ts.extend(extra.iter().copied().filter(|t| *t > a && *t < b));
    ts.sort_by(f64::total_cmp);
    ts.dedup_by(|x, y| (*x - *y).abs() < 1e-9);
    ts
}

/// The frame instants `k / fps` inside `[a, b]` (none when `fps` is not positive): baked
/// values are reduced against these too, so that they are within the tolerance where gmotion
/// renders its frames (between uniform samples a fast curve can stray further).
pub fn frame_times(a: f64, b: f64, fps: f64) -> Vec<f64> {
    if !(fps.is_finite() && fps > 0.0) || b < a {
        return Vec::new();
    }
    let first = (a * fps - 1e-9).ceil().max(0.0);
    let last = (b * fps + 1e-9).floor();
    let n = ((last - first + 1.0).max(0.0) as usize).min(1 << 16);
    (0..n).map(|i| (first + i as f64) / fps).collect()
}

/// Where sample `k` falls between samples `i` and `j`, as a fraction.
pub fn fraction(ts: &[f64], k: usize, i: usize, j: usize) -> f64 {
    let span = ts[j] - ts[i];
    if span <= 0.0 {
        0.0
    } else {
        (ts[k] - ts[i]) / span
    }
}

/// The progress of `timing` at the sample instants `ts` as few keys as keep
/// `err(i, played, true)` within `tolerance` at every sample `i` (`err` measures what a
/// progress error costs, e.g. on the canvas). For easings that are not cubic Béziers: each
/// run between kept samples is a cubic Hermite piece with the curve's own slopes at its ends
/// (a key spline with `x1 = 1/3, x2 = 2/3`) where that fits the spline box, else straight.
pub fn sampled_progress(
    timing: &Timing,
    ts: &[f64],
    tolerance: f64,
    err: impl Fn(usize, f64, f64) -> f64,
) -> Vec<Key<f64>> {
    let ps: Vec<f64> = ts.iter().map(|&t| timing.progress(t)).collect();
    // One-sided slopes: the curve may kink where the change starts and stops.
    let h = 1e-6 * (timing.end - timing.start).abs().max(1e-3);
    let slopes: Vec<(f64, f64)> = ts
        .iter()
        .zip(&ps)
        .map(|(&t, &p)| {
            (
                (p - timing.progress(t - h)) / h,
                (timing.progress(t + h) - p) / h,
            )
        })
        .collect();
    // The Hermite piece's `(y1, y2)`, or `None` for a straight one.
    let piece = |i: usize, j: usize| -> Option<(f64, f64)> {
        let (dt, dp) = (ts[j] - ts[i], ps[j] - ps[i]);
        if dt <= TIME_EPS || PROGRESS.same(dp, 0.0) {
            return None;
        }
        let y1 = slopes[i].1 * dt / (3.0 * dp);
        let y2 = 1.0 - slopes[j].0 * dt / (3.0 * dp);
        ((0.0..=1.0).contains(&y1) && (0.0..=1.0).contains(&y2)).then_some((y1, y2))
    };
    let keep = ramer_douglas_peucker(ts.len(), tolerance, |k, i, j| {
        let x = fraction(ts, k, i, j);
        let y = match piece(i, j) {
            // With x1 = 1/3 and x2 = 2/3 the spline's x is its parameter.
            Some((y1, y2)) => 3.0 * (1.0 - x) * x * ((1.0 - x) * y1 + x * y2) + x * x * x,
            None => x,
        };
        err(k, ps[i] + (ps[j] - ps[i]) * y, ps[k])
    });
    let mut keys = vec![Key::linear(ts[keep[0]], ps[keep[0]])];
    for w in keep.windows(2) {
        keys.push(Key {
            t: ts[w[1]],
            v: ps[w[1]],
            ease: piece(w[0], w[1]).map_or(Ease::Linear, |(y1, y2)| {
                Ease::Bezier([1.0 / 3.0, y1, 2.0 / 3.0, y2])
            }),
        });
    }
    keys
}

/// The progress over `[a, b]` (seconds) sampled at `a`, at every frame inside and at `b`,
/// as the `(time, progress)` samples to keep so that linear interpolation between them
/// stays within `tolerance` of the progress at every sample.
pub fn frame_progress(
    (a, b): (f64, f64),
    fps: f64,
    tolerance: f64,
    progress: impl Fn(f64) -> f64,
) -> Vec<(f64, f64)> {
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
    kept.into_iter().map(|i| (times[i], ps[i])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::keyframe::tests::play;
    use crate::signals::Easing;

    #[test]
    fn straight_lines_keep_their_ends() {
        let ts = sample_times(0.0, 1.0, 100.0, 4, &[]);
        let v: Vec<f64> = ts.iter().map(|t| 3.0 * t).collect();
        let keep = ramer_douglas_peucker(ts.len(), 1e-9, |k, i, j| {
            let s = fraction(&ts, k, i, j);
            (v[i] + (v[j] - v[i]) * s - v[k]).abs()
        });
        assert_eq!(keep, vec![0, ts.len() - 1]);
    }

    #[test]
    fn curves_stay_within_tolerance() {
        let ts = sample_times(0.0, 1.0, 200.0, 4, &[0.123]);
        assert!(ts.contains(&0.123));
        let v: Vec<f64> = ts.iter().map(|t| (6.0 * t).sin() * 100.0).collect();
        let err = |k: usize, i: usize, j: usize| {
            let s = fraction(&ts, k, i, j);
            (v[i] + (v[j] - v[i]) * s - v[k]).abs()
        };
        let keep = ramer_douglas_peucker(ts.len(), 0.25, err);
        assert!(
            keep.len() > 2 && keep.len() < ts.len() / 3,
            "{} of {}",
            keep.len(),
            ts.len()
        );
        for w in keep.windows(2) {
            for k in w[0] + 1..w[1] {
                assert!(err(k, w[0], w[1]) <= 0.25);
            }
        }
    }

    #[test]
    fn sampled_easings_stay_within_tolerance_with_few_keys() {
        for ease in [Easing::BSpline(4), Easing::poles(3).unwrap()] {
            for reversed in [false, true] {
                let tm = Timing {
                    start: 1.0,
                    end: 3.0,
                    delay: 0.3,
                    ease: ease.clone(),
                    reversed,
                };
                let ts = sample_times(0.5, 3.5, 240.0, 8, &[1.3, 3.0]);
                // An error of one progress unit costs 100 canvas units.
                let keys = sampled_progress(&tm, &ts, 0.05, |_, a, b| 100.0 * (a - b).abs());
                assert!(keys.len() < 16, "{ease:?}: {} keys", keys.len());
                for i in 0..=2000 {
                    let t = 0.5 + 3.0 * i as f64 / 2000.0;
                    let err = 100.0 * (play(&keys, t) - tm.progress(t)).abs();
                    assert!(err < 0.1, "{ease:?} reversed {reversed} at {t}: {err}");
                }
            }
        }
    }
}
