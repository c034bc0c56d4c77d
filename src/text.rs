//! What a unit that came from text knows of its letters: the glyph outlines an importer
//! laid out, each with the letter (grapheme cluster), word and line it belongs to, so the
//! spatial operators `letters()`, `words()` and `lines()` can cut the unit into pieces that
//! keep their paint and their Bézier outlines (see `tangle::ops::text`).
//!
//! An importer fills a [`TextLayout`] for every text unit (SVG `<text>`, Lottie text
//! layers); the engine never lays text out itself.

use std::sync::Arc;

use crate::scene::PathNode;

/// One glyph outline of a text unit, with its place in the text.
#[derive(Clone, Debug)]
pub struct Glyph {
    /// The outline with its paint, in the unit node's inner coordinates (the coordinates
    /// of its children when the unit is a group, of its parent when it is a path).
    pub path: PathNode,
    /// Its letter: the grapheme cluster (what a reader counts as one letter; a ligature
    /// drawn as one glyph is one) it draws, counted over the whole text in reading order.
    pub letter: usize,
    /// Its word, counted over the whole text in reading order (words are separated by
    /// white space).
    pub word: usize,
    /// Its line, counted from 0 in document order.
    pub line: usize,
}

/// A text unit's glyphs in reading order (left to right on a left-to-right line, right to
/// left on a right-to-left one; lines in document order). White space draws no glyph, so
/// it has none here.
#[derive(Clone, Debug, Default)]
pub struct TextLayout {
    /// The glyphs, sorted by letter.
    pub glyphs: Vec<Glyph>,
}

impl TextLayout {
    /// How many letters the text has (visible grapheme clusters).
    pub fn letters(&self) -> usize {
        self.glyphs.last().map_or(0, |g| g.letter + 1)
    }
}

/// How a shape stands in a text: the layout of an imported text unit, and a piece's line
/// and word (the expression variables `line_id` and `word_id`).
#[derive(Clone, Debug, Default)]
pub struct TextPlace {
    /// The text's layout, for a unit that came from text and was not cut yet.
    pub layout: Option<Arc<TextLayout>>,
    /// The line the shape is on (`line_id`): 0 for shapes that did not come from text, and
    /// for a whole text; a word's or a letter's line for the pieces `words()` and
    /// `letters()` make.
    pub line: usize,
    /// The word the shape is in (`word_id`), counted over the whole text: 0 for shapes
    /// that did not come from text, and for a whole text; a line's first word for the
    /// pieces `lines()` makes.
    pub word: usize,
    /// Why a unit that came from text has no layout, when the importer knows (a Lottie
    /// text layer drawn without glyph outlines of its own): the text operators say it when
    /// they pass the unit through whole.
    pub uncut: Option<String>,
}
