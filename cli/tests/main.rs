//! The command line's integration tests, in one binary (one link instead of one per file):
//! the real `gmotion` binary on files, end to end through every layer — the bundled
//! examples in every format, bad and hostile input, designer files, filters, images,
//! Lottie in, rigs and composition time, the studio's API, mutation fuzzing — with the
//! exports played in the real players (`support::players`). The libraries' own tests live
//! in their crates (CONTRIBUTING.md lists them).
//!
//! The tests that play exports in the real players or read the fetched Lottie corpus
//! (what `tests/conformance/install.sh` installs) are compiled in only with the `players`
//! feature, which `scripts/test.sh` always turns on: there a missing player fails the run.
//! Without it, `cargo test` on a fresh clone runs everything else.
//!
//! Run them with `cargo test --profile quick -p gmotion-cli --features players` once the
//! players are installed; one module with `cargo test --profile quick -p gmotion-cli
//! --features players --test gmotion lottie_import::`.

mod support;

// Every test here plays exports.
#[cfg(feature = "players")]
mod bend;
mod cli;
mod cli_errors;
mod designer;
mod dotlottie;
mod filters;
mod fuzz;
// Every test here plays exports or reads the Lottie corpus.
#[cfg(feature = "players")]
mod hierarchy;
mod images;
mod learn;
mod lottie_import;
mod lottie_text;
mod markers;
mod scale;
// Every test here plays exports or reads the Lottie corpus.
#[cfg(feature = "players")]
mod pack;
mod slots;
// Every test here plays exports or reads the Lottie corpus.
#[cfg(feature = "players")]
mod lottie_time;
// Every test here plays exports or reads the Lottie corpus.
#[cfg(feature = "players")]
mod rigs;
mod size_and_length;
mod smil_follow;
mod studio;
mod studio_load;
// Every test here plays exports in the real players.
#[cfg(feature = "players")]
mod text;
// Every test here plays exports.
#[cfg(feature = "players")]
mod trim;
// Every test here runs ffmpeg and ffprobe, which tests/conformance/install.sh installs.
#[cfg(feature = "players")]
mod video;
