//! Exporters: an animation (or a still scene) out to files and pixels. They see only the
//! animation model, never the grammar that produced it.

pub mod atomic;
pub mod frame;
pub mod lottie;
pub mod raster;
pub mod smil;
