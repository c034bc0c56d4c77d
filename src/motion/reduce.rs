//! Keyframe reduction: which of a run of samples to keep so that a player, interpolating
//! between the kept ones, stays within an error bound. Both exporters bake motion their
//! format cannot say into samples and thin them with one of these; each is named by its
//! algorithm, and the caller says what "fits" means for its interpolation.

/// Greedy forward reduction over `n` samples: keeps the first and last, and from each kept
/// sample jumps as far as `fits(i, j)` allows (`fits` says whether interpolating from `i`
/// to `j` reproduces every sample between them). Adjacent samples always fit. One pass;
/// the Lottie exporter uses it where a fit is cheap to test for a whole span.
///
/// ```
/// use gmotion::motion::reduce::greedy;
/// assert_eq!(greedy(10, |i, j| j - i <= 3), vec![0, 3, 6, 9]);
/// assert_eq!(greedy(1, |_, _| true), vec![0]);
/// ```
pub fn greedy(n: usize, fits: impl Fn(usize, usize) -> bool) -> Vec<usize> {
    if n == 0 {
        return Vec::new();
    }
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
