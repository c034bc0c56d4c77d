//! gmotion: procedural motion graphics from still vector art.
//!
//! This crate is the engine: the scene model, the grammar language, expansion into an
//! animation, the signal filters and the data-driven transitions. It knows no file format.
//! Data flows one way: an importer crate (`gmotion-import-svg`) builds a [`Scene`], the
//! engine expands a grammar on it into an [`Animation`], and an exporter crate writes it
//! out (`gmotion-export-lottie`, `gmotion-export-svg` for still SVG and SMIL,
//! `gmotion-export-raster` for PNG, GIF and APNG, or `gmotion-output` for all of them by
//! file name).
//!
//! An SVG and a grammar to Lottie:
//!
//! ```
//! use gmotion::engine::{RunOptions, run};
//! use gmotion_export_lottie::{LottieOptions, to_lottie};
//! use gmotion_import_svg::{ImportOptions, parse};
//!
//! let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">
//!     <rect class="box" x="10" y="40" width="20" height="20"/></svg>"#;
//! let scene = parse(svg, "scene.svg", &ImportOptions::default())?.scene;
//! let grammar = gmotion::grammar::parse(
//!     "duration 1s\n\
//!      timesplit(0.5, 0.5) : [all, box] -> [a, inv_a]\n\
//!      animate(affine, world, 0, translate(60, 0)) : [a, box] -> [move]\n",
//! )?;
//! let (animation, _stats) = run(scene, &grammar, &RunOptions::default())?;
//! let (json, _warnings) = to_lottie(&animation, &LottieOptions::default())?;
//! assert!(json.starts_with('{'));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The modules, in the order data flows: [`scene`] (the model an importer fills),
//! [`grammar`] (the language), [`tangle`] (group grammars: spatial rules), [`engine`]
//! (expansion and compilation), [`motion`] (the animation model and its sampling),
//! [`keyframe`] (the keys exporters write), [`signals`] (easings, FIR and spring filters),
//! [`transitions`] (data-driven motion); beside them [`color`], [`canvas`] (output sizes and lengths),
//! [`tagging`] (import options the grammar sets), [`tolerance`] ("the same up to rounding"),
//! [`warning`] and [`atomic`] (whole-or-nothing file writes).
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod atomic;
pub mod canvas;
pub mod color;
pub mod engine;
pub mod grammar;
pub mod input;
pub mod keyframe;
pub mod measure;
pub mod morph;
pub mod motion;
pub mod scene;
pub mod signals;
pub mod tagging;
pub mod tangle;
#[cfg(test)]
mod testing;
pub mod text;
pub mod tolerance;
pub mod transitions;
pub mod warning;

pub use motion::Animation;
pub use scene::Scene;
pub use tagging::{TagFrom, Units};
pub use warning::Warning;
