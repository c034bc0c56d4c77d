//! The linear combination of transformations (Alexa, SIGGRAPH 2002): `M^p = exp(p·log M)`
//! for 2D affine maps, computed on the 3×3 homogeneous matrix.
//!
//! `log` uses inverse scaling and squaring (Denman–Beavers square roots, then a series);
//! `exp` uses scaling and squaring with a Taylor series. A matrix without a real logarithm
//! (a reflection, or a half turn) falls back to entry-wise interpolation from the identity.

use kurbo::Affine;

type M3 = [[f64; 3]; 3];

const I3: M3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn from_affine(a: Affine) -> M3 {
    let [a0, b, c, d, e, f] = a.as_coeffs();
    [[a0, c, e], [b, d, f], [0.0, 0.0, 1.0]]
}

fn to_affine(m: &M3) -> Affine {
    Affine::new([m[0][0], m[1][0], m[0][1], m[1][1], m[0][2], m[1][2]])
}

fn mul(a: &M3, b: &M3) -> M3 {
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    r
}

fn add(a: &M3, b: &M3, k: f64) -> M3 {
    let mut r = *a;
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] += k * b[i][j];
        }
    }
    r
}

fn scale(a: &M3, k: f64) -> M3 {
    add(&[[0.0; 3]; 3], a, k)
}

fn norm(a: &M3) -> f64 {
    a.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max)
}

fn inverse(a: &M3) -> Option<M3> {
    let inv = to_affine(a).inverse();
    let m = from_affine(inv);
    m.iter().flatten().all(|v| v.is_finite()).then_some(m)
}

/// Matrix logarithm, or `None` when the matrix has no real one.
fn log(m: &M3) -> Option<M3> {
    let lin = to_affine(m);
    let [a, b, c, d, _, _] = lin.as_coeffs();
    let det = a * d - b * c;
    let tr = a + d;
    // A real log exists when no eigenvalue is real and non-positive.
    if det <= 0.0 || (tr * tr >= 4.0 * det && tr <= 0.0) {
        return None;
    }
    let mut y = *m;
    let mut k = 0;
    while norm(&add(&y, &I3, -1.0)) > 0.25 && k < 40 {
        // Denman–Beavers square root.
        let mut z = I3;
        for _ in 0..60 {
            let yi = inverse(&y)?;
            let zi = inverse(&z)?;
            let ny = scale(&add(&y, &zi, 1.0), 0.5);
            z = scale(&add(&z, &yi, 1.0), 0.5);
            let done = norm(&add(&ny, &y, -1.0)) < 1e-15;
            y = ny;
            if done {
                break;
            }
        }
        k += 1;
    }
    let x = add(&y, &I3, -1.0);
    let mut term = x;
    let mut sum = x;
    for n in 2..40 {
        term = mul(&term, &x);
        let sign = if n % 2 == 0 { -1.0 } else { 1.0 };
        sum = add(&sum, &term, sign / n as f64);
        if norm(&term) < 1e-18 {
            break;
        }
    }
    Some(scale(&sum, (1u64 << k) as f64))
}

fn exp(l: &M3) -> M3 {
    let n = norm(l);
    let k = if n > 0.5 {
        (n / 0.5).log2().ceil() as i32
    } else {
        0
    };
    let x = scale(l, 0.5f64.powi(k));
    let mut term = I3;
    let mut sum = I3;
    for i in 1..30 {
        term = scale(&mul(&term, &x), 1.0 / i as f64);
        sum = add(&sum, &term, 1.0);
        if norm(&term) < 1e-18 {
            break;
        }
    }
    for _ in 0..k {
        sum = mul(&sum, &sum);
    }
    sum
}

/// `m^p` by the linear combination of transformations; `p = 0` gives the identity and
/// `p = 1` gives `m`.
pub fn power(m: Affine, p: f64) -> Affine {
    if p == 0.0 {
        return Affine::IDENTITY;
    }
    if p == 1.0 {
        return m;
    }
    let h = from_affine(m);
    match log(&h) {
        Some(l) => to_affine(&exp(&scale(&l, p))),
        None => {
            let (a, i) = (m.as_coeffs(), Affine::IDENTITY.as_coeffs());
            Affine::new(std::array::from_fn(|k| i[k] + (a[k] - i[k]) * p))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tolerance::Tolerance;

    const ROUNDING: Tolerance = Tolerance::Below(1e-7);

    #[test]
    fn half_power_of_rotation_is_half_rotation() {
        let r = Affine::rotate(1.2);
        assert!(ROUNDING.same_affine(power(r, 0.5), Affine::rotate(0.6)));
    }

    #[test]
    fn powers_compose() {
        let m = Affine::translate((30.0, -4.0))
            * Affine::rotate(0.7)
            * Affine::scale_non_uniform(2.0, 0.5);
        assert!(ROUNDING.same_affine(power(m, 0.25) * power(m, 0.75), m));
        assert!(ROUNDING.same_affine(power(m, 1.0 - 1e-12), m));
    }

    #[test]
    fn reflection_falls_back() {
        let m = Affine::scale_non_uniform(-1.0, 1.0);
        let h = power(m, 0.5);
        assert!((h.as_coeffs()[0]).abs() < 1e-12);
    }
}
