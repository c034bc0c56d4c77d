//! The Lottie exporter's integration tests, in one binary: the JSON's structure, its
//! exactness against a small Lottie evaluator, and (with the `players` feature, which
//! `scripts/test.sh` always turns on) the exports played in lottie-web, rlottie and ThorVG.
//!
//! Run them with `cargo test --profile quick -p gmotion-export-lottie --features players`;
//! without the feature the player tests are compiled out.

// The shared helpers, under the name the modules use.
use gmotion_testkit as support;

mod follow;
mod lottie;
mod morph;
