//! gmotion: procedural motion graphics from still vector art.
//!
//! Data flows one way: [`importers`] build a [`scene::Scene`], the engine expands grammars
//! into a [`motion::Animation`], and [`exporters`] write it out.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod color;
pub mod grammar;
pub mod motion;
pub mod scene;
pub mod signals;
pub mod tangle;
