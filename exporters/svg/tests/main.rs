//! The SVG exporter's integration tests, in one binary: frame documents against SVG
//! written by hand and drawn by resvg, and the SMIL export played by a small evaluator
//! against the animation model.
//!
//! Run them with `cargo test --profile quick -p gmotion-export-svg`, one module with
//! `cargo test --profile quick -p gmotion-export-svg --test export_svg smil::`.

// The shared helpers, under the name the modules use.
use gmotion_testkit as support;

mod frame;
mod morph;
mod smil;
