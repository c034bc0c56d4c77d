//! Glyphs from the user's fonts for text a file does not embed.
//!
//! A Bodymovin export keeps the glyph outlines of its text (`chars`) only when asked to;
//! otherwise players set the text in the named font if the machine has it, measuring each
//! letter's advance (lottie-web asks the browser). gmotion does the same before laying
//! text out: in a file without glyphs (a file with some is drawn from them alone, as
//! players do), every letter a text layer shows gets a glyph made from the font database — the font's family and style (`fFamily`, `fStyle`), else
//! the database's sans-serif family — with its outline and advance at size 100, as
//! embedded glyphs are. The layout ([`crate::text`]) then cannot tell them apart.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

use kurbo::{BezPath, Point};
use skrifa::MetadataProvider;
use skrifa::instance::{LocationRef, Size};
use skrifa::outline::{DrawSettings, OutlinePen};
use usvg::fontdb::{Database, Family, Query, Style, Weight};

use crate::model::{Document, Layer, LayerKind, Loc};
use crate::text::{Font, Glyph, characters};

/// A font database, loaded the first time a document needs it (loading the system's fonts
/// takes a good part of a second, which most Lottie files, with their glyphs embedded or
/// no text at all, need not pay).
#[derive(Clone)]
pub struct SystemFonts(Arc<dyn Fn() -> Arc<Database> + Send + Sync>);

impl SystemFonts {
    /// Fonts from `load`, called when a document first needs them.
    pub fn new(load: impl Fn() -> Arc<Database> + Send + Sync + 'static) -> SystemFonts {
        SystemFonts(Arc::new(load))
    }
}

impl std::fmt::Debug for SystemFonts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SystemFonts")
    }
}

impl PartialEq for SystemFonts {
    fn eq(&self, other: &SystemFonts) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// Most letters made from system fonts for one document (each distinct letter of each
/// font once): bounds the work a document of many scripts can ask for.
pub const MAX_MADE_GLYPHS: usize = 4096;

/// Adds to `doc.fonts.glyphs`, when the file embeds none, a glyph for every letter its
/// text layers show, made from `fonts`. Returns warnings `(place, message)`: a family
/// that is not installed (drawn in another), letters no font has.
pub fn fill_in(doc: &mut Document, fonts: &SystemFonts) -> Vec<(Loc, String)> {
    let wanted = wanted(doc);
    if wanted.is_empty() {
        return Vec::new();
    }
    let db = (fonts.0)();
    let mut warnings = Vec::new();
    let mut made = 0;
    for (font_index, (at, letters)) in wanted {
        let Some(font) = doc.fonts.fonts.get(font_index).cloned() else {
            continue;
        };
        let Some((id, family)) = face(&db, &font) else {
            warnings.push((at, "text not drawn: no font is installed".to_string()));
            continue;
        };
        if !family.eq_ignore_ascii_case(&font.family) {
            warnings.push((
                at.clone(),
                format!(
                    "the font \"{}\" is not embedded nor installed; its text is drawn in \"{family}\" (players use the fonts of the machine they run on)",
                    font.family
                ),
            ));
        }
        let mut missing = 0;
        let glyphs = db
            .with_face_data(id, |data, index| {
                let face = skrifa::FontRef::from_index(data, index).ok()?;
                let mut out = Vec::new();
                for ch in &letters {
                    if made >= MAX_MADE_GLYPHS {
                        break;
                    }
                    match glyph(&face, ch, &font) {
                        Some(g) => out.push(g),
                        None => missing += 1,
                    }
                    made += 1;
                }
                let ascent = face
                    .metrics(Size::new(100.0), LocationRef::default())
                    .ascent;
                Some((out, f64::from(ascent)))
            })
            .flatten();
        let Some((glyphs, ascent)) = glyphs else {
            warnings.push((
                at,
                format!("text not drawn: the font \"{family}\" cannot be read"),
            ));
            continue;
        };
        if missing > 0 {
            warnings.push((
                at.clone(),
                format!("{missing} letters have no glyph in \"{family}\"; they are left out"),
            ));
        }
        if let Some(f) = doc.fonts.fonts.get_mut(font_index)
            && f.ascent == 0.0
        {
            f.ascent = ascent;
        }
        doc.fonts.glyphs.extend(glyphs);
    }
    if made >= MAX_MADE_GLYPHS {
        warnings.push((
            Loc::root(),
            format!("more than {MAX_MADE_GLYPHS} different letters to draw from system fonts; the rest are left out"),
        ));
    }
    warnings
}

/// For each font (index into the fonts list) that some text layer shows letters in without
/// a glyph for them: the first such layer's place and the letters.
fn wanted(doc: &Document) -> BTreeMap<usize, (Loc, BTreeSet<String>)> {
    let mut out: BTreeMap<usize, (Loc, BTreeSet<String>)> = BTreeMap::new();
    // A file with glyphs is drawn from them alone: players draw a letter it lacks as
    // nothing, with no advance.
    if !doc.fonts.glyphs.is_empty() {
        return out;
    }
    let comps =
        std::iter::once(&doc.layers).chain(doc.assets.iter().filter_map(|a| a.layers.as_ref()));
    let fonts = &doc.fonts;
    for layer in comps.flat_map(|layers| layers.iter()) {
        let Some(data) = text_of(layer) else {
            continue;
        };
        for (_, d) in &data.documents {
            let Some(i) = fonts
                .fonts
                .iter()
                .position(|f| f.name == d.font)
                .or((!fonts.fonts.is_empty()).then_some(0))
            else {
                continue;
            };
            for ch in characters(&d.text) {
                if ch == "\r" || ch == "\u{3}" {
                    continue;
                }
                out.entry(i)
                    .or_insert_with(|| (layer.at.clone(), BTreeSet::new()))
                    .1
                    .insert(ch);
            }
        }
    }
    out
}

fn text_of(layer: &Layer) -> Option<&crate::text::TextData> {
    (layer.kind == LayerKind::Text && !layer.hidden)
        .then_some(layer.text.as_ref())
        .flatten()
}

/// The face `font` is drawn in, and its family's name: the font's own family at its
/// weight and slant, else the database's sans-serif family.
fn face(db: &Database, font: &Font) -> Option<(usvg::fontdb::ID, String)> {
    let style = font.style.to_ascii_lowercase();
    let weight = [
        ("thin", 100),
        ("extralight", 200),
        ("ultralight", 200),
        ("light", 300),
        ("medium", 500),
        ("semibold", 600),
        ("demibold", 600),
        ("extrabold", 800),
        ("ultrabold", 800),
        ("black", 900),
        ("heavy", 900),
        ("bold", 700),
    ]
    .iter()
    .find(|(w, _)| style.replace([' ', '-'], "").contains(w))
    .map_or(400, |&(_, w)| w);
    let slant = if style.contains("italic") {
        Style::Italic
    } else if style.contains("oblique") {
        Style::Oblique
    } else {
        Style::Normal
    };
    let query = |families: &[Family]| {
        db.query(&Query {
            families,
            weight: Weight(weight),
            style: slant,
            ..Query::default()
        })
    };
    let own = [Family::Name(&font.family)];
    if !font.family.is_empty()
        && let Some(id) = query(&own)
    {
        let name = db.face(id)?.families.first()?.0.clone();
        if name.eq_ignore_ascii_case(&font.family) {
            return Some((id, name));
        }
    }
    let id = query(&[Family::SansSerif])?;
    let name = db.face(id)?.families.first()?.0.clone();
    Some((id, name))
}

/// The glyph of letter `ch` (its first code point) in `face`, at size 100, as a glyph of
/// `font`; `None` when the face has none.
fn glyph(face: &skrifa::FontRef, ch: &str, font: &Font) -> Option<Glyph> {
    let c = ch.chars().next()?;
    let id = face.charmap().map(c)?;
    if id.to_u32() == 0 && !c.is_whitespace() {
        return None;
    }
    let size = Size::new(100.0);
    let width = face
        .glyph_metrics(size, LocationRef::default())
        .advance_width(id)?;
    let mut pen = Pen(BezPath::new());
    if let Some(outline) = face.outline_glyphs().get(id) {
        outline
            .draw(
                DrawSettings::unhinted(size, LocationRef::default()),
                &mut pen,
            )
            .ok()?;
    }
    Some(Glyph {
        ch: ch.to_string(),
        style: font.style.clone(),
        family: font.family.clone(),
        width: f64::from(width),
        shapes: Vec::new(),
        outline: Some(pen.0),
    })
}

/// Draws a glyph into a path, y down (a font's y goes up from the baseline).
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
    Point::new(f64::from(x), -f64::from(y))
}
