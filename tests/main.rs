//! gmotion's integration tests, in one binary (one link instead of one per file): the real
//! `gmotion` binary on files, the importers, the engine's properties from the papers, the
//! exporters played in real players (`support::players`), and the resvg corpus.
//!
//! Run them all with `cargo test --release`; one module with `cargo test --release --test
//! gmotion lottie::`.

mod support;

mod cli;
mod cli_errors;
mod corpus;
mod designer;
mod engine;
mod filters;
mod frame;
mod fuzz;
mod gallery;
mod grammar_parse;
mod hierarchy;
mod images;
mod import;
mod lottie;
mod lottie_import;
mod lottie_time;
mod papers;
mod rigs;
mod sampler;
mod signals;
mod smil;
mod studio;
mod tangle;
mod transitions;
