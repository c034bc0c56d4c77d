//! The letters, words and lines of a `<text>`: usvg lays the text out (spans of positioned
//! glyphs, in visual order, chunk by chunk) and draws it as one path per span; this keeps
//! every glyph's outline apart, with the grapheme cluster, word and line it belongs to,
//! so the spatial operators `letters()`, `words()` and `lines()` can cut the text unit
//! into pieces ([`gmotion::text::TextLayout`]).
//!
//! Reading order is recovered from usvg's layout: a span's glyphs are in visual order, and
//! each carries the text of its cluster (empty for the further glyphs of a cluster drawn
//! with several). Running the Unicode bidirectional algorithm on the chunk's text as usvg
//! does gives its visual runs; walking a span's glyphs along them (forwards on a
//! left-to-right run, backwards on a right-to-left one) gives each glyph the byte offset of
//! its cluster in the chunk. Glyphs of one cluster share that offset, so a ligature (one
//! glyph for "fi") and a base letter with its marks are each one letter.

use gmotion::scene::{Fill, PathNode, Stroke};
use gmotion::text::{Glyph, TextLayout};
use kurbo::{BezPath, Point};
use skrifa::MetadataProvider;
use skrifa::outline::{DrawSettings, OutlinePen};
use usvg::fontdb::Database;

use crate::convert::affine;

/// The paint of a span, converted by the importer: fill, stroke, stroke painted first.
pub(crate) type SpanPaint = (Option<Fill>, Option<Stroke>, bool);

/// One glyph before it is numbered: chunk, byte offset of its cluster in the chunk, the
/// cluster's text, outline and paint.
struct Placed {
    chunk: usize,
    offset: usize,
    text: String,
    path: PathNode,
    /// The glyph's origin on the baseline (where a line starts or ends).
    origin: Point,
    font_size: f64,
}

/// The layout of `text`, its glyphs drawn from `fonts` and painted by `paint`; `None` when
/// usvg's layout cannot be matched to the text's chunks (then the text stays one unit that
/// the text operators cannot cut).
pub(crate) fn layout(
    text: &usvg::Text,
    fonts: &Database,
    mut paint: impl FnMut(&usvg::layout::Span) -> SpanPaint,
) -> Option<TextLayout> {
    let mut spans = text.layouted().iter();
    let mut placed: Vec<Placed> = Vec::new();
    for (c, chunk) in text.chunks().iter().enumerate() {
        let runs = visual_runs(chunk.text());
        for s in chunk.spans() {
            if s.end() <= s.start() {
                continue;
            }
            // A span usvg laid out has glyphs whose texts cover its range; one with no
            // glyph (no font) was left out of the layout.
            let mut ahead = spans.clone();
            let Some(span) = ahead.next() else { break };
            let covered: usize = span.positioned_glyphs.iter().map(|g| g.text.len()).sum();
            if covered != s.end() - s.start() {
                continue;
            }
            spans = ahead;
            if !span.visible {
                continue;
            }
            let offsets = offsets(&span.positioned_glyphs, &runs, s.start()..s.end())?;
            let (fill, stroke, stroke_first) = paint(span);
            for (g, offset) in span.positioned_glyphs.iter().zip(offsets) {
                let Some(path) = outline(fonts, span, g) else {
                    continue;
                };
                let origin = affine(g.transform()) * Point::ORIGIN;
                placed.push(Placed {
                    chunk: c,
                    offset,
                    text: g.text.clone(),
                    path: PathNode {
                        id: String::new(),
                        path,
                        fill: fill.clone(),
                        stroke: stroke.clone(),
                        stroke_first,
                        unit: None,
                    },
                    origin,
                    font_size: f64::from(span.font_size.get()),
                });
            }
        }
    }
    if spans.next().is_some() {
        return None;
    }
    // Reading order: chunks in document order, clusters by their offset (a stable sort
    // keeps a cluster's glyphs in drawing order).
    placed.sort_by_key(|p| (p.chunk, p.offset));
    // A cluster is all white space only when its text-bearing glyph says so.
    let blank: std::collections::HashSet<(usize, usize)> = placed
        .iter()
        .filter(|p| !p.text.is_empty() && p.text.chars().all(char::is_whitespace))
        .map(|p| (p.chunk, p.offset))
        .collect();
    placed.retain(|p| !blank.contains(&(p.chunk, p.offset)));

    let lines = lines(text, &placed);
    let words = words(text, &lines);
    let mut glyphs = Vec::with_capacity(placed.len());
    let mut letter = 0;
    let mut last = None;
    for p in placed {
        let key = (p.chunk, p.offset);
        if last.is_some_and(|k| k != key) {
            letter += 1;
        }
        last = Some(key);
        let word = words[p.chunk]
            .iter()
            .rev()
            .find(|(start, _)| *start <= p.offset)
            .map_or(0, |&(_, w)| w);
        glyphs.push(Glyph {
            path: p.path,
            letter,
            word,
            line: lines[p.chunk],
        });
    }
    Some(TextLayout { glyphs })
}

/// A chunk's text split into runs of one direction, in visual order: (byte range,
/// right to left). The paragraph level is left to right, as usvg shapes it.
fn visual_runs(text: &str) -> Vec<(std::ops::Range<usize>, bool)> {
    let info = unicode_bidi::BidiInfo::new(text, Some(unicode_bidi::Level::ltr()));
    let mut out = Vec::new();
    for para in &info.paragraphs {
        let (levels, runs) = info.visual_runs(para, para.range.clone());
        out.extend(runs.into_iter().map(|r| {
            let rtl = levels[r.start].is_rtl();
            (r, rtl)
        }));
    }
    out
}

/// The byte offset of each glyph's cluster in its chunk, for a span's glyphs (visual
/// order) covering `range` of the chunk's text; `None` when they do not walk the runs.
fn offsets(
    glyphs: &[usvg::layout::PositionedGlyph],
    runs: &[(std::ops::Range<usize>, bool)],
    range: std::ops::Range<usize>,
) -> Option<Vec<usize>> {
    // The parts of the visual runs inside the span, in visual order.
    let mut parts = runs
        .iter()
        .map(|(r, rtl)| (r.start.max(range.start)..r.end.min(range.end), *rtl))
        .filter(|(r, _)| r.start < r.end);
    let mut part = parts.next()?;
    let mut cursor = if part.1 { part.0.end } else { part.0.start };
    let mut last = cursor;
    let mut out = Vec::with_capacity(glyphs.len());
    for g in glyphs {
        let len = g.text.len();
        // A further glyph of a right-to-left cluster follows the one with its text.
        if len == 0 && part.1 {
            out.push(last);
            continue;
        }
        let spent = if part.1 {
            cursor == part.0.start
        } else {
            cursor == part.0.end
        };
        if spent {
            part = parts.next()?;
            cursor = if part.1 { part.0.end } else { part.0.start };
        }
        let at = if part.1 {
            cursor = cursor.checked_sub(len).filter(|&c| c >= part.0.start)?;
            cursor
        } else {
            let at = cursor;
            cursor += len;
            if cursor > part.0.end {
                return None;
            }
            at
        };
        last = at;
        out.push(at);
    }
    Some(out)
}

/// The outline of glyph `g` of `span`, in the text's coordinates (as usvg draws it:
/// unhinted, at the span's variations); `None` for a glyph without one (a space).
fn outline(
    fonts: &Database,
    span: &usvg::layout::Span,
    g: &usvg::layout::PositionedGlyph,
) -> Option<BezPath> {
    let path = fonts.with_face_data(g.font, |data, index| {
        let font = skrifa::FontRef::from_index(data, index).ok()?;
        let glyph = font.outline_glyphs().get(skrifa::GlyphId::new(g.id.0))?;
        let mut variations: Vec<(skrifa::Tag, f32)> = span
            .variations
            .iter()
            .map(|v| (skrifa::Tag::new(&v.tag), v.value))
            .collect();
        // `font-optical-sizing: auto` sets the optical size to the font size, as usvg does.
        let opsz = skrifa::Tag::new(b"opsz");
        if span.font_optical_sizing == usvg::FontOpticalSizing::Auto
            && !variations.iter().any(|(t, _)| *t == opsz)
            && font.axes().get_by_tag(opsz).is_some()
        {
            variations.push((opsz, g.font_size()));
        }
        let location = font.axes().location(variations);
        let mut pen = Pen(BezPath::new());
        glyph
            .draw(
                DrawSettings::unhinted(skrifa::prelude::Size::unscaled(), &location),
                &mut pen,
            )
            .ok()?;
        Some(pen.0)
    })??;
    if path.elements().is_empty() {
        return None;
    }
    Some(affine(g.outline_transform()) * path)
}

/// Draws a glyph in font units (y up, as the outline transform expects).
struct Pen(BezPath);

impl OutlinePen for Pen {
    fn move_to(&mut self, x: f32, y: f32) {
        self.0.move_to(p(x, y));
    }
    fn line_to(&mut self, x: f32, y: f32) {
        self.0.line_to(p(x, y));
    }
    fn quad_to(&mut self, cx0: f32, cy0: f32, x: f32, y: f32) {
        self.0.quad_to(p(cx0, cy0), p(x, y));
    }
    fn curve_to(&mut self, cx0: f32, cy0: f32, cx1: f32, cy1: f32, x: f32, y: f32) {
        self.0.curve_to(p(cx0, cy0), p(cx1, cy1), p(x, y));
    }
    fn close(&mut self) {
        self.0.close_path();
    }
}

fn p(x: f32, y: f32) -> Point {
    Point::new(f64::from(x), f64::from(y))
}

/// The line of each chunk: a chunk starts a new line when it is laid on a path, or when
/// its first glyph's baseline is more than half the font size away (across the writing
/// direction) from the previous chunk's last glyph. `placed` is in reading order.
fn lines(text: &usvg::Text, placed: &[Placed]) -> Vec<usize> {
    let chunks = text.chunks();
    let vertical = text.writing_mode() == usvg::WritingMode::TopToBottom;
    let across = |a: Point, b: Point| if vertical { a.x - b.x } else { a.y - b.y };
    let mut out = vec![0; chunks.len()];
    let mut line = 0;
    let mut prev: Option<(usize, Point)> = None;
    for (c, chunk) in chunks.iter().enumerate() {
        let mut mine = placed.iter().filter(|p| p.chunk == c);
        if let (Some(first), Some((pc, end))) = (mine.clone().next(), prev) {
            let on_path = matches!(chunk.text_flow(), usvg::TextFlow::Path(_))
                || matches!(chunks[pc].text_flow(), usvg::TextFlow::Path(_));
            if on_path || across(first.origin, end).abs() > first.font_size / 2.0 {
                line += 1;
            }
        }
        out[c] = line;
        if let Some(last) = mine.next_back() {
            prev = Some((c, last.origin));
        }
    }
    out
}

/// Where each word starts in each chunk: (byte offset, word number), words counted over
/// the whole text; a word goes on across chunks of one line (letters placed one by one)
/// and ends at white space or a line's end.
fn words(text: &usvg::Text, lines: &[usize]) -> Vec<Vec<(usize, usize)>> {
    let mut out = Vec::with_capacity(lines.len());
    let mut next = 0;
    let mut in_word = false;
    let mut line = usize::MAX;
    for (c, chunk) in text.chunks().iter().enumerate() {
        if lines[c] != line {
            line = lines[c];
            in_word = false;
        }
        let mut starts = Vec::new();
        for (i, ch) in chunk.text().char_indices() {
            if ch.is_whitespace() {
                in_word = false;
            } else if !in_word {
                in_word = true;
                starts.push((i, next));
                next += 1;
            } else if starts.is_empty() {
                // A word that began in the previous chunk.
                starts.push((i, next - 1));
            }
        }
        out.push(starts);
    }
    out
}
