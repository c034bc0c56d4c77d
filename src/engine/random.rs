//! Deterministic randomness keyed by what it is for, not by a shared stream: a value for
//! (seed, shape, step, draw) is the same whatever else the grammar does, so editing one rule
//! does not re-roll unrelated shapes, and thread count never matters.

/// SplitMix64 finaliser: a strong 64-bit mix.
pub fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Hashes a sequence of words into one key.
pub fn key(parts: &[u64]) -> u64 {
    parts.iter().fold(0x243F_6A88_85A3_08D3, |h, &p| mix(h ^ p))
}

/// FNV-1a of a string, for folding tags into keys.
pub fn hash_str(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A uniform number in `[0, 1)` from a key.
pub fn unit(k: u64) -> f64 {
    (mix(k) >> 11) as f64 / (1u64 << 53) as f64
}

/// 2D gradient (Perlin) noise in `[-1, 1]`, seeded; continuous in position.
pub fn noise2(seed: u64, x: f64, y: f64) -> f64 {
    let (xi, yi) = (x.floor(), y.floor());
    let (xf, yf) = (x - xi, y - yi);
    let grad = |ix: f64, iy: f64, dx: f64, dy: f64| {
        let h = key(&[seed, ix as i64 as u64, iy as i64 as u64]);
        let a = unit(h) * std::f64::consts::TAU;
        a.cos() * dx + a.sin() * dy
    };
    let fade = |t: f64| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v) = (fade(xf), fade(yf));
    let n00 = grad(xi, yi, xf, yf);
    let n10 = grad(xi + 1.0, yi, xf - 1.0, yf);
    let n01 = grad(xi, yi + 1.0, xf, yf - 1.0);
    let n11 = grad(xi + 1.0, yi + 1.0, xf - 1.0, yf - 1.0);
    let nx0 = n00 + (n10 - n00) * u;
    let nx1 = n01 + (n11 - n01) * u;
    // Gradient noise with unit gradients stays within ±√2/2; scale to ±1.
    ((nx0 + (nx1 - nx0) * v) * std::f64::consts::SQRT_2).clamp(-1.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_is_in_range_and_spread() {
        let vals: Vec<f64> = (0..10_000).map(|i| unit(key(&[7, i]))).collect();
        assert!(vals.iter().all(|v| (0.0..1.0).contains(v)));
        let mean = vals.iter().sum::<f64>() / vals.len() as f64;
        assert!((mean - 0.5).abs() < 0.02, "mean {mean}");
    }

    #[test]
    fn noise_is_continuous_and_zero_on_lattice() {
        assert_eq!(noise2(3, 2.0, 5.0), 0.0);
        let a = noise2(3, 1.3, 0.7);
        let b = noise2(3, 1.3001, 0.7);
        assert!((a - b).abs() < 1e-2);
        assert_ne!(noise2(3, 1.3, 0.7), noise2(4, 1.3, 0.7));
    }
}
