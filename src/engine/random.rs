//! Deterministic randomness keyed by what it is for, not by a shared stream: a value for
//! (seed, shape, step, draw) is the same whatever else the grammar does, so editing one rule
//! does not re-roll unrelated shapes, and thread count never matters. The generators are
//! shared with the group grammar ([`crate::tangle::noise`]).

pub use crate::tangle::noise::{key, perlin as noise2, unit};

/// FNV-1a of a string, for folding tags into keys.
pub fn hash_str(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tags_hash_apart() {
        assert_ne!(hash_str("a"), hash_str("b"));
        assert_eq!(hash_str("petal"), hash_str("petal"));
    }

    #[test]
    fn draws_are_uniform_in_the_unit_interval() {
        let vals: Vec<f64> = (0..10_000).map(|i| unit(key(&[7, i]))).collect();
        assert!(vals.iter().all(|v| (0.0..1.0).contains(v)));
        let mean = vals.iter().sum::<f64>() / vals.len() as f64;
        assert!((mean - 0.5).abs() < 0.02, "mean {mean}");
    }
}
