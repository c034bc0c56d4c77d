//! SVG out: gmotion scenes and animations as SVG text.
//!
//! - [`frame`]: a still scene, or an animation's frame at one time, as a static SVG
//!   document — what `gmotion convert -o x.svg` writes and what the raster exporter renders
//!   with resvg;
//! - [`smil`]: a whole animation as one SVG document animated with SMIL, which browsers
//!   play with no script; its static part is the [`frame`] writer's, so every picture
//!   element is exactly what gmotion renders.
#![forbid(unsafe_code)]

pub mod frame;
pub mod smil;
