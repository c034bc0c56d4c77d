//! Real polynomials (coefficients in ascending powers) and their complex roots.

use super::complex::Complex;

/// The monic polynomial `Π (x − rᵢ)` of a conjugate-closed root set, ascending powers.
/// Imaginary round-off is dropped: the roots come in conjugate pairs.
pub(crate) fn from_roots(roots: &[Complex]) -> Vec<f64> {
    let mut c = vec![Complex::real(1.0)];
    for &r in roots {
        let mut next = vec![Complex::default(); c.len() + 1];
        for (i, &ci) in c.iter().enumerate() {
            next[i + 1] = next[i + 1] + ci;
            next[i] = next[i] - ci * r;
        }
        c = next;
    }
    c.into_iter().map(|z| z.re).collect()
}

/// Evaluates a real polynomial at a complex point (Horner).
pub(crate) fn eval(coeffs: &[f64], x: Complex) -> Complex {
    coeffs
        .iter()
        .rev()
        .fold(Complex::default(), |acc, &c| acc * x + Complex::real(c))
}

/// All complex roots of a real polynomial (ascending coefficients), by the Aberth–Ehrlich
/// iteration followed by Newton polishing. Leading coefficients that are negligible
/// relative to the largest one are dropped first, so the degree is the numerical one.
pub(crate) fn roots(coeffs: &[f64]) -> Vec<Complex> {
    let scale = coeffs.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if scale == 0.0 {
        return Vec::new();
    }
    let mut c: Vec<f64> = coeffs.iter().map(|v| v / scale).collect();
    while c.len() > 1 && c.last().is_some_and(|v| v.abs() < 1e-13) {
        c.pop();
    }
    let n = c.len() - 1;
    if n == 0 {
        return Vec::new();
    }
    let lead = c[n];
    let c: Vec<f64> = c.iter().map(|v| v / lead).collect();
    let dc: Vec<f64> = (1..=n).map(|k| c[k] * k as f64).collect();
    // Start on a circle whose radius bounds the roots (Cauchy), rotated off the axes so
    // that no start is a conjugate of another.
    let radius = 1.0 + c[..n].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut z: Vec<Complex> = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64 + 0.4;
            Complex::new(radius * 0.5 * a.cos(), radius * 0.5 * a.sin())
        })
        .collect();
    for _ in 0..500 {
        let mut moved = 0.0f64;
        for i in 0..n {
            let p = eval(&c, z[i]);
            let dp = eval(&dc, z[i]);
            if p.abs() == 0.0 {
                continue;
            }
            let ratio = p / dp;
            let mut sum = Complex::default();
            for j in 0..n {
                if j != i {
                    sum = sum + Complex::real(1.0) / (z[i] - z[j]);
                }
            }
            let step = ratio / (Complex::real(1.0) - ratio * sum);
            if step.is_finite() {
                z[i] = z[i] - step;
                moved = moved.max(step.abs() / (1.0 + z[i].abs()));
            }
        }
        if moved < 1e-15 {
            break;
        }
    }
    for zi in &mut z {
        for _ in 0..3 {
            let step = eval(&c, *zi) / eval(&dc, *zi);
            if step.is_finite() {
                *zi = *zi - step;
            }
        }
        if zi.im.abs() <= 1e-10 * (1.0 + zi.re.abs()) {
            zi.im = 0.0;
        }
    }
    z
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_of_known_polynomials() {
        // (x − 2)(x² + 2x + 5): roots 2, −1 ± 2i.
        let p = from_roots(&[
            Complex::real(2.0),
            Complex::new(-1.0, 2.0),
            Complex::new(-1.0, -2.0),
        ]);
        assert_eq!(p.len(), 4);
        let mut r = roots(&p);
        r.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
        let want = [
            Complex::new(-1.0, -2.0),
            Complex::new(-1.0, 2.0),
            Complex::real(2.0),
        ];
        for (a, b) in r.iter().zip(want) {
            assert!((*a - b).abs() < 1e-10, "{a} vs {b}");
        }
    }

    #[test]
    fn negligible_leading_terms_are_dropped() {
        let r = roots(&[-3.0, 1.0, 1e-17]);
        assert_eq!(r.len(), 1);
        assert!((r[0].re - 3.0).abs() < 1e-12);
    }
}
