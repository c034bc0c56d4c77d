//! The text operators: `letters()`, `words()` and `lines()` cut a unit that came from text
//! into one piece per letter (grapheme cluster), word or line, numbered in reading order.
//!
//! Unlike the other operators they do not cut polygons: a piece keeps the glyph outlines
//! the importer laid out ([`crate::text::TextLayout`]), Bézier curves and paint as they
//! were, and the polygon it also gets (flattened like any unit's) only measures it (its
//! centroid, the pivot of a `local` motion, and its box) and serves the operators a later
//! rule may apply to it. A piece that another operator cuts again becomes polygons like
//! any shape.

use std::sync::Arc;

use kurbo::{Affine, Vec2};

use super::Piece;
use super::paint::Paint;
use crate::scene::FillRule;
use crate::tangle::boolean::normalize;
use crate::tangle::polygon::{Grid, flatten_rings};
use crate::text::TextLayout;

/// What a text operator cuts a text into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextSplit {
    /// `letters()`: one piece per grapheme cluster.
    Letters,
    /// `words()`: one piece per word.
    Words,
    /// `lines()`: one piece per line.
    Lines,
}

impl TextSplit {
    /// The operator's grammar name.
    pub fn name(self) -> &'static str {
        match self {
            TextSplit::Letters => "letters",
            TextSplit::Words => "words",
            TextSplit::Lines => "lines",
        }
    }
}

/// The drawing a piece keeps instead of its polygon, as long as no operator reshapes it.
#[derive(Clone, Debug)]
pub enum Drawing {
    /// Some glyphs of a text unit (indices into its layout's glyphs, in reading order),
    /// drawn in the unit node's inner coordinates, which `to_canvas` maps to the canvas.
    Glyphs {
        /// The text's layout.
        layout: Arc<TextLayout>,
        /// The glyphs the piece draws.
        glyphs: Vec<usize>,
        /// The unit node's inner coordinates to the canvas.
        to_canvas: Affine,
    },
    /// The imported unit as it was drawn (a text operator passed it through: it did not
    /// come from text).
    Whole,
}

impl Drawing {
    /// The line and word a piece drawing these glyphs stands for (its first glyph's).
    pub fn place(&self) -> Option<(usize, usize)> {
        match self {
            Drawing::Glyphs { layout, glyphs, .. } => {
                let g = &layout.glyphs[*glyphs.first()?];
                Some((g.line, g.word))
            }
            Drawing::Whole => None,
        }
    }
}

/// Cuts the glyphs `glyphs` of `layout` by `split`: one piece per letter, word or line in
/// reading order, each with the polygon of its outlines (flattened to `tolerance` on
/// `grid`), orientation `dir` and its first glyph's paint, and the drawing it keeps.
pub fn cut(
    split: TextSplit,
    layout: &Arc<TextLayout>,
    glyphs: &[usize],
    to_canvas: Affine,
    dir: Vec2,
    grid: &Grid,
    tolerance: f64,
) -> Vec<(Piece, Drawing)> {
    let key = |i: usize| {
        let g = &layout.glyphs[i];
        match split {
            TextSplit::Letters => g.letter,
            TextSplit::Words => g.word,
            TextSplit::Lines => g.line,
        }
    };
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for &i in glyphs {
        match groups.last_mut() {
            Some(last) if key(last[0]) == key(i) => last.push(i),
            _ => groups.push(vec![i]),
        }
    }
    groups
        .into_iter()
        .enumerate()
        .map(|(n, members)| {
            let rings: Vec<_> = members
                .iter()
                .flat_map(|&i| {
                    flatten_rings(&layout.glyphs[i].path.path, to_canvas, tolerance, grid)
                })
                .collect();
            let piece = Piece {
                region: normalize(&rings, FillRule::NonZero, grid),
                slot: 0,
                cell: (n as i64, 0),
                dir,
                paint: Paint::of(&layout.glyphs[members[0]].path),
            };
            let drawing = Drawing::Glyphs {
                layout: layout.clone(),
                glyphs: members,
                to_canvas,
            };
            (piece, drawing)
        })
        .collect()
}
