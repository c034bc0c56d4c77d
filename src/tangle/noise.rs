//! Seeded randomness and coherent noise for the tangle operators.
//!
//! Every random decision is keyed by what it is for — the seed, the shape and its place in
//! its own derivation (see [`super::expand()`] and [`crate::engine::random`]) — rather than
//! drawn from one shared stream or keyed by a step counter, so expansion is deterministic
//! whatever the thread count, and editing the rules of one tag does not re-roll shapes of
//! another.

use std::f64::consts::TAU;

/// SplitMix64's finaliser: a strong 64-bit mix.
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

/// A uniform number in `[0, 1)` from a key.
pub fn unit(k: u64) -> f64 {
    (mix(k) >> 11) as f64 / (1u64 << 53) as f64
}

/// A small deterministic generator (SplitMix64) for the many draws one operator makes on
/// one shape; seed it with [`key`] of what the draws are for.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator for a key.
    pub fn new(key: u64) -> Rng {
        Rng(key)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        mix(self.0)
    }

    /// A uniform number in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform number in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }

    /// A uniform index in `0..n` (`n > 0`).
    pub fn index(&mut self, n: usize) -> usize {
        ((self.next_f64() * n as f64) as usize).min(n.saturating_sub(1))
    }
}

/// Seeded 2D gradient (Perlin) noise in `[-1, 1]`: continuous, zero on the integer lattice,
/// varying over about one unit.
pub fn perlin(seed: u64, x: f64, y: f64) -> f64 {
    // Rules ask again and again for the same point: one expression in each of a shape's
    // rules, and shapes of one cell alike (`noise(floor(cx / 64), …)`). The last answer is
    // kept per thread; eight sines and cosines are the cost it saves.
    thread_local! {
        static LAST: std::cell::Cell<Option<(u64, u64, u64, f64)>> =
            const { std::cell::Cell::new(None) };
    }
    let asked = (seed, x.to_bits(), y.to_bits());
    if let Some((s, xb, yb, v)) = LAST.get()
        && (s, xb, yb) == asked
    {
        return v;
    }
    let v = perlin_at(seed, x, y);
    LAST.set(Some((asked.0, asked.1, asked.2, v)));
    v
}

/// [`perlin`], computed.
fn perlin_at(seed: u64, x: f64, y: f64) -> f64 {
    let (xi, yi) = (x.floor(), y.floor());
    let (xf, yf) = (x - xi, y - yi);
    let grad = |ix: f64, iy: f64, dx: f64, dy: f64| {
        let a = unit(key(&[seed, ix as i64 as u64, iy as i64 as u64])) * TAU;
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
    // Unit gradients keep the value within ±√2/2; scale to ±1.
    ((nx0 + (nx1 - nx0) * v) * std::f64::consts::SQRT_2).clamp(-1.0, 1.0)
}

/// Two octaves of [`perlin`]: the coarse wobble of a hand-drawn line plus a little tremor.
pub fn fractal(seed: u64, x: f64, y: f64) -> f64 {
    (perlin(seed, x, y) + 0.35 * perlin(mix(seed), 2.0 * x + 17.3, 2.0 * y - 9.1)) / 1.35
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rng_is_uniform_and_keyed() {
        let mut r = Rng::new(key(&[1, 2]));
        let v: Vec<f64> = (0..20_000).map(|_| r.next_f64()).collect();
        assert!(v.iter().all(|x| (0.0..1.0).contains(x)));
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        assert!((mean - 0.5).abs() < 0.01, "mean {mean}");
        assert_ne!(
            Rng::new(key(&[1, 2])).next_u64(),
            Rng::new(key(&[1, 3])).next_u64()
        );
        assert!((0..1000).all(|_| r.index(7) < 7));
    }

    /// The kept last answer is only ever the answer for the same seed and point: asked in
    /// turn for points and seeds that repeat, alternate and differ in one bit.
    #[test]
    fn a_kept_answer_is_given_for_its_own_question_only() {
        let next = f64::from_bits(0.3f64.to_bits() + 1);
        let asks = [
            (5, 0.3, 0.6),
            (5, 0.3, 0.6),
            (6, 0.3, 0.6),
            (5, 0.3, 0.6),
            (5, next, 0.6),
        ];
        for (seed, x, y) in asks.into_iter().chain(asks.into_iter().rev()) {
            assert_eq!(
                perlin(seed, x, y).to_bits(),
                perlin_at(seed, x, y).to_bits()
            );
        }
        assert_ne!(perlin(5, 0.3, 0.6), perlin(5, 0.6, 0.3));
    }

    #[test]
    fn perlin_is_continuous_bounded_and_seeded() {
        assert_eq!(perlin(5, 3.0, -2.0), 0.0);
        let mut max_jump: f64 = 0.0;
        for i in 0..2000 {
            let x = i as f64 * 0.013;
            let a = perlin(5, x, 0.37 * x);
            let b = perlin(5, x + 1e-4, 0.37 * x);
            assert!((-1.0..=1.0).contains(&a));
            max_jump = max_jump.max((a - b).abs());
        }
        assert!(max_jump < 1e-3, "jump {max_jump}");
        assert_ne!(perlin(5, 0.3, 0.6), perlin(6, 0.3, 0.6));
        assert!((fractal(5, 0.3, 0.6)).abs() <= 1.0);
    }
}
