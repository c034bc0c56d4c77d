//! Deterministic randomness keyed by what it is for, not by a shared stream or a step
//! counter, so that editing the rules of one shape tag leaves every other shape as it was,
//! and thread count never matters. The generators are shared with the group grammar
//! ([`crate::tangle::noise`]).
//!
//! # What a draw is keyed on
//!
//! A random rule choice and a `rand()` draw happen at one *place*: a shape, rewritten by one
//! expansion step. The place is named by
//!
//! - the seed;
//! - the shape: its tag's name and (for `choice shape` and for `rand()`) its id within the
//!   tag;
//! - the step's place in that shape's own derivation: the **name** of the slice tag the step
//!   rewrites and how many steps rewrote that tag on the shape before (`visits`; 0 for the
//!   first time, 1 when a rule re-creates the tag and it is rewritten again, …);
//! - for `rand()`, the draw number within the slice (the first `rand()` the rule's
//!   arguments evaluate is 1, and so on, offset before easing before value).
//!
//! Everything here is decided by rules that match the shape's tag: which slice tags its
//! timeline gets and how often each is rewritten. A rule for another shape tag cannot
//! change any of it, so it cannot re-roll this shape. What is deliberately left out:
//!
//! - the global step number and slice tag ids, which count the steps and tags of every
//!   shape tag, so a rule for tag `a` inserted anywhere shifts them for tag `b` (the bug
//!   this replaces);
//! - line numbers and rule positions in the file, which shift when an unrelated rule is
//!   inserted above;
//! - the rule itself (its text or index). Which rule applies is already a function of the
//!   place, so the rule adds nothing to tell draws apart; leaving it out means that tuning
//!   a rule's numbers (`rotate(rand(0, 30))` to `rotate(rand(0, 40))`) keeps its random
//!   pattern, scaled, and adding or editing a *candidate* of the same match moves only the
//!   weight boundaries of the choice, not the number drawn for it.
//!
//! All slices one step rewrites on one shape — several slices with the same tag, and a
//! slice with its `inv_` twin — are at the same place and draw the same numbers: the twin
//! replays exactly the motion of its forward slice backwards.
//!
//! The part of a place shared by all shapes of a step is hashed once when the expansion is
//! planned ([`Place::draw_key`]); a draw only mixes in the shape id and the draw number
//! ([`draw`]), with no allocation and no string hashing.

pub use crate::tangle::noise::{key, perlin as noise2, unit};

/// FNV-1a of a string, for folding tags into keys.
pub fn hash_str(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Domain words, so a rule choice and a `rand()` draw at one place are independent.
const CHOICE: u64 = 0x5EED_C401_CE00_0001;
const DRAW: u64 = 0x5EED_D4A3_0000_0002;

/// Where a step rewrites a shape, as random keys see it (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Place {
    /// The seed.
    pub seed: u64,
    /// [`hash_str`] of the shape tag.
    pub shape_tag: u64,
    /// [`hash_str`] of the slice tag rewritten (its base name: a twin is at the same place).
    pub slice_tag: u64,
    /// How many steps rewrote this slice tag on the shape before.
    pub visits: u64,
}

impl Place {
    /// The uniform number in `[0, 1)` that chooses the rule: one per shape tag with
    /// `choice group` (`id` is `None`), one per shape with `choice shape`.
    pub fn choice(&self, id: Option<usize>) -> f64 {
        let k = key(&[
            CHOICE,
            self.seed,
            self.shape_tag,
            self.slice_tag,
            self.visits,
        ]);
        unit(match id {
            Some(id) => key(&[k, id as u64]),
            None => k,
        })
    }

    /// The key of the `rand()` draws at this place, before the shape id and draw number.
    pub fn draw_key(&self) -> u64 {
        key(&[DRAW, self.seed, self.shape_tag, self.slice_tag, self.visits])
    }
}

/// Draw number `n` of shape `id` at the place of `draw_key` ([`Place::draw_key`]).
pub fn draw(draw_key: u64, id: usize, n: u64) -> f64 {
    unit(key(&[draw_key, id as u64, n]))
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

    /// Every word of a place, the shape id and the draw number tell draws apart, and a
    /// choice is independent of the draws at its place.
    #[test]
    fn every_part_of_a_place_counts() {
        let p = Place {
            seed: 3,
            shape_tag: hash_str("a"),
            slice_tag: hash_str("all"),
            visits: 0,
        };
        let variants = [
            Place { seed: 4, ..p },
            Place {
                shape_tag: hash_str("b"),
                ..p
            },
            Place {
                slice_tag: hash_str("x"),
                ..p
            },
            Place { visits: 1, ..p },
        ];
        for q in variants {
            assert_ne!(p.draw_key(), q.draw_key(), "{q:?}");
            assert_ne!(p.choice(None), q.choice(None), "{q:?}");
            assert_ne!(p.choice(Some(2)), q.choice(Some(2)), "{q:?}");
        }
        let k = p.draw_key();
        assert_ne!(draw(k, 0, 1), draw(k, 1, 1));
        assert_ne!(draw(k, 0, 1), draw(k, 0, 2));
        assert_ne!(p.choice(Some(0)), p.choice(Some(1)));
        assert_ne!(p.choice(None), unit(k));
    }
}
