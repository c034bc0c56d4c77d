//! Keyframe reduction: which of a run of samples to keep so that a player, interpolating
//! between the kept ones, stays within an error bound. Both exporters bake motion their
//! format cannot say into samples and thin them with one of these; each is named by its
//! algorithm, and the caller says what "fits" means for its interpolation.

/// Greedy forward reduction over `n` samples: keeps the first and last, and from each kept
/// sample `i` jumps to the farthest `j` that `fits(i, j)` allows (`fits` says whether
/// interpolating from `i` to `j` reproduces every sample between them). Adjacent samples
/// always fit and are never asked about. The Lottie exporter uses it where a fit is cheap to
/// test for a whole span.
///
/// The whole run is tried first (most baked windows fit in one span); failing that, the
/// farthest `j` is found by galloping, `i + 2, i + 4, i + 8, …` while they fit, then by
/// bisection between the last span that fitted and the first that did not. Testing a span
/// costs about its length, so a run that fits in one span costs n sample checks and any run
/// O(n log n); trying `i + 2, i + 3, …` in turn cost O(s²) per kept span of length `s`,
/// which was most of a large export (a 72-frame window that fits in one span took 2 600
/// sample checks instead of 72). When fitting is monotone (a span that fits implies its
/// shorter prefixes fit) the kept samples are those of trying every `j` in turn; when it is
/// not, a jump may land farther, and every kept span still satisfies `fits`.
///
/// ```
/// use gmotion::keyframe::reduce::greedy;
/// assert_eq!(greedy(10, |i, j| j - i <= 3), vec![0, 3, 6, 9]);
/// assert_eq!(greedy(1, |_, _| true), vec![0]);
/// ```
pub fn greedy(n: usize, fits: impl Fn(usize, usize) -> bool) -> Vec<usize> {
    if n == 0 {
        return Vec::new();
    }
    let last = n - 1;
    if last < 2 || fits(0, last) {
        return if last == 0 { vec![0] } else { vec![0, last] };
    }
    let mut kept = vec![0];
    let mut i = 0;
    while i < last {
        // `lo` fits (adjacent samples always do); `hi`, once found, does not.
        let mut lo = i + 1;
        let mut hi = None;
        let mut step = 2;
        while lo < last {
            let j = (i + step).min(last);
            if fits(i, j) {
                lo = j;
                step *= 2;
            } else {
                hi = Some(j);
                break;
            }
        }
        if let Some(mut hi) = hi {
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if fits(i, mid) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
        }
        kept.push(lo);
        i = lo;
    }
    kept
}

/// Ramer–Douglas–Peucker reduction: indices of the samples to keep (always the first and
/// the last) so that at every dropped sample `k`, interpolating between its kept
/// neighbours `i < k < j` errs by at most `tol` as `err(k, i, j)` measures it. Splits at
/// the worst sample until every span fits; the SMIL exporter uses it, since its error is
/// measured per sample.
pub fn ramer_douglas_peucker(
    n: usize,
    tol: f64,
    err: impl Fn(usize, usize, usize) -> f64,
) -> Vec<usize> {
    if n <= 2 {
        return (0..n).collect();
    }
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[n - 1] = true;
    let mut stack = vec![(0, n - 1)];
    while let Some((i, j)) = stack.pop() {
        let mut worst = (0.0, 0);
        for k in i + 1..j {
            let e = err(k, i, j);
            if e > worst.0 {
                worst = (e, k);
            }
        }
        if worst.0 > tol {
            let k = worst.1;
            keep[k] = true;
            stack.push((i, k));
            stack.push((k, j));
        }
    }
    (0..n).filter(|&k| keep[k]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    /// The reduction `greedy` replaced: every `j` tried in turn.
    fn one_step(n: usize, fits: impl Fn(usize, usize) -> bool) -> Vec<usize> {
        let mut kept = vec![0];
        let mut i = 0;
        while i + 1 < n {
            let mut j = i + 1;
            while j + 1 < n && fits(i, j + 1) {
                j += 1;
            }
            kept.push(j);
            i = j;
        }
        kept
    }

    /// A deterministic scramble of `(i, j, seed)` in `[0, 1)`.
    fn noise(i: usize, j: usize, seed: u64) -> f64 {
        let mut x = (i as u64) << 32 ^ j as u64 ^ seed.wrapping_mul(0x9e37_79b9_7f4a_7c15);
        x ^= x >> 33;
        x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
        x ^= x >> 33;
        (x >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn greedy_keeps_what_trying_every_span_keeps_when_fitting_is_monotone() {
        for seed in 0..200 {
            let n = 1 + (noise(0, 0, seed) * 300.0) as usize;
            // Each sample reaches a random distance; a span fits up to it.
            let reach = |i: usize| 1 + (noise(i, 0, seed) * 40.0) as usize;
            let fits = |i: usize, j: usize| j - i <= reach(i);
            assert_eq!(greedy(n, fits), one_step(n, fits), "seed {seed}");
        }
    }

    #[test]
    fn every_kept_span_fits_when_fitting_is_not_monotone() {
        for seed in 0..200 {
            let n = 2 + (noise(0, 0, seed) * 300.0) as usize;
            let fits = |i: usize, j: usize| noise(i, j, seed) < 0.7;
            let kept = greedy(n, fits);
            assert_eq!((kept[0], *kept.last().unwrap()), (0, n - 1));
            for w in kept.windows(2) {
                assert!(w[1] == w[0] + 1 || fits(w[0], w[1]), "seed {seed}: {w:?}");
            }
        }
    }

    /// What a caller pays: a fit test looks at every sample of its span.
    fn work(n: usize, fits: impl Fn(usize, usize) -> bool) -> usize {
        let cost = Cell::new(0);
        greedy(n, |i, j| {
            cost.set(cost.get() + (j - i));
            fits(i, j)
        });
        cost.get()
    }

    #[test]
    fn greedy_costs_about_n_log_n_sample_checks() {
        for n in [10, 100, 1000, 10_000] {
            // One span: linear.
            assert!(work(n, |_, _| true) <= n, "n = {n}");
            // Spans of every length: within a log factor.
            for reach in [2, 7, 60, n / 3 + 1] {
                let log = (usize::BITS - n.leading_zeros()) as usize;
                let w = work(n, |i, j| j - i <= reach);
                assert!(w <= 4 * n * log, "n = {n}, reach {reach}: {w}");
            }
        }
    }
}
