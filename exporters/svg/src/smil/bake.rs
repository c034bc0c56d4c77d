//! Baking: sampling what SMIL cannot say exactly and keeping only the samples that linear
//! interpolation needs to stay within an error bound.

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

#[cfg(test)]
mod tests {
    use super::*;
    use gmotion::motion::reduce::ramer_douglas_peucker;

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
}
