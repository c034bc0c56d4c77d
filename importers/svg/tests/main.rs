//! The SVG importer's integration tests, in one binary: tags, units, geometry and errors
//! of the import, and the resvg corpus through gmotion's own path (import → scene → SVG
//! text → resvg) against each file's reference rendering.
//!
//! Run them with `cargo test --profile quick -p gmotion-import-svg`, one module with
//! `cargo test --profile quick -p gmotion-import-svg --test import_svg corpus::`.

// The shared helpers, under the name the modules use.
use gmotion_testkit as support;

mod corpus;
mod import;
