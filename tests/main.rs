//! gmotion's integration tests, in one binary (one link instead of one per file): the real
//! `gmotion` binary on files, the importers, the engine's properties from the papers, the
//! exporters played in real players (`support::players`), and the resvg corpus.
//!
//! The tests that play exports in the real players or read the fetched Lottie corpus
//! (what `tests/conformance/install.sh` installs) are compiled in only with the `players`
//! feature, which `scripts/test.sh` always turns on: there a missing player fails the run.
//! Without it, `cargo test` on a fresh clone runs everything else.
//!
//! Run them all with `bash scripts/test.sh`, or `cargo test --profile quick --workspace
//! --features gmotion-cli/players` once the players are installed; one module with `cargo
//! test --profile quick -p gmotion-cli --features players --test gmotion lottie::`.

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
// Every test here plays exports or reads the Lottie corpus.
#[cfg(feature = "players")]
mod hierarchy;
mod images;
mod import;
mod lottie;
mod lottie_import;
// Every test here plays exports or reads the Lottie corpus.
#[cfg(feature = "players")]
mod lottie_time;
mod papers;
// Every test here plays exports or reads the Lottie corpus.
#[cfg(feature = "players")]
mod rigs;
mod sampler;
mod signals;
mod smil;
mod studio;
mod tangle;
mod transitions;
