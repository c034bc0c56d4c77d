//! gmotion: procedural motion graphics from still vector art.
//!
//! Data flows one way: [`importers`] build a [`scene::Scene`], the engine expands grammars
//! into a [`motion::Animation`], and [`exporters`] write it out.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod color;
pub mod engine;
/// Exporters: scenes and animations out as SVG text, pixels, PNG, GIF and APNG.
#[path = "../exporters/mod.rs"]
pub mod exporters;
pub mod grammar;
/// Importers: SVG files in, scenes out.
#[path = "../importers/mod.rs"]
pub mod importers;
pub mod motion;
pub mod plot;
pub mod scene;
pub mod signals;
pub mod tangle;
pub mod transitions;
