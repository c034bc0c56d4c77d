//! The engine's integration tests (the `gmotion` crate), in one binary: the grammar
//! language, timeslice expansion, the sampler, signals and filters, group grammar
//! operators, data-driven transitions, and the papers' grammars and gallery as printed.
//! SVG scenes come in through `gmotion-import-svg` (a dev-dependency); nothing here runs
//! the `gmotion` binary or a player.
//!
//! Run them with `cargo test --profile quick -p gmotion`, one module with `cargo test
//! --profile quick -p gmotion --test engine tangle::`.

// The shared helpers, under the name the modules use.
use gmotion_testkit as support;

mod bend;
mod engine;
mod follow;
mod gallery;
mod grammar_parse;
mod papers;
mod sampler;
mod signals;
mod tangle;
mod text;
mod transitions;
