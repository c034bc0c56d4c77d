//! The Lottie document for gmotion, in the shape schema → evaluation → player, shared by
//! the importer (`gmotion-import-lottie`: file → scene) and the exporter
//! (`gmotion-export-lottie`: animation → document), so that a Lottie feature is taught
//! once.
//!
//! - [`model`]: the typed document, read from serde_json's tree with the JSON location of
//!   every error (`$.layers[3].ks.p.k[1].s`); what it does not know stays in the tree,
//!   which the [`Source`] keeps whole for verbatim pass-through.
//! - [`number`]: a number as gmotion writes it into a document; [`written`]: properties
//!   and keyframes as the exporter writes them (the model's, holding written values).
//! - [`eval`]: a property's value at a frame (per-component Bézier easing, holds, legacy
//!   end values, split positions, spatial tangents travelled by arc length) and a
//!   transform's matrix.
//! - The player, [`Source::scene_at`]: the document drawn as a gmotion scene at any frame,
//!   which is how gmotion plays a Lottie file itself. Parenting builds every layer's world
//!   transform (3D layers projected as players without a camera show them, auto-oriented
//!   layers turned along their path); shape layers' groups, paths (`sh`), rectangles,
//!   ellipses, stars and polygons (built as lottie-web builds them, [`outline`]), fills,
//!   strokes with dashes and gradients become painted paths, after trim paths, round
//!   corners, offset paths ([`offset`]) and repeaters; layer masks in every mode and every
//!   kind of track matte become masks; precompositions are expanded (start time, stretch,
//!   time remap, clipped to their size); solids are filled rectangles ([`build`]). Image
//!   layers draw their asset's picture; text layers draw the glyphs the file embeds, laid
//!   out and animated as lottie-web does ([`text`]), or glyphs set in the machine's fonts
//!   ([`fonts`]); Gaussian Blur and Drop Shadow are drawn as lottie-web draws them
//!   ([`effects`]). The units of the scene (which layer is a unit, a part or a rig, their
//!   tags and measures) are built the same way at every frame ([`units`], [`tags`]).
//! - Kinetic type: a text layer drawn from embedded glyphs is imported with the layout of
//!   its letters, words and lines, which `letters()`, `words()` and `lines()` cut; a text
//!   layer cut so is written back as a shape layer of one group per piece
//!   ([`Source::cut`]).
//!
//! **Errors.** Nothing in the input can make reading or playing panic: every value is
//! checked as it is read. Parent cycles, precomposition cycles, precompositions nested
//! deeper than [`build::MAX_PRECOMP_DEPTH`], more than [`build::MAX_DRAWN_LAYERS`] layers
//! to draw, and numbers beyond ±[`model::MAX_MAGNITUDE`] are errors.
#![forbid(unsafe_code)]

pub mod build;
mod cut;
pub mod dotlottie;
pub mod effects;
pub mod eval;
pub mod fonts;
pub mod model;
pub mod number;
pub mod offset;
pub mod outline;
mod player;
pub mod tags;
pub mod text;
pub mod units;
pub mod written;

pub use cut::Note;
pub use player::{FrameError, Source};
pub use units::{UnitLayers, Units};
