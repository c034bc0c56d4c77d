//! Group grammars (gTangle, Santoni & Pellacini): spatial rules that split, outline, place,
//! fill and regroup shapes, so a few input shapes become thousands of pattern pieces.
//!
//! A tangle shape is ⟨t, g, s; Θ, d⟩: a tag, a group id, an id within the group, a boundary
//! made of polygons with holes ([`polygon::Region`]) and an orientation vector.

pub mod boolean;
pub mod field;
pub mod noise;
pub mod ops;
pub mod place;
pub mod polygon;
