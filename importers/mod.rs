//! Importers: files in, [`Scene`](crate::scene::Scene) out. They know nothing of grammars.

pub mod measure;
pub mod svg;
pub mod tags;
