//! Text layers, drawn from the glyph outlines a file embeds (`chars`) and laid out and
//! animated as lottie-web lays them out (`TextProperty.completeTextData`,
//! `TextAnimatorProperty.getMeasures`): point text and box text (wrapped at spaces),
//! justification, tracking, line height, baseline shift, anchor grouping and alignment,
//! document keyframes, and text animators with range selectors (every shape, ease high and
//! low, smoothness, amount, units in percent or index, based on characters, words or lines)
//! moving, scaling, skewing, turning, fading, re-colouring and stroking letters.
//!
//! What players draw with the user's fonts (a file without `chars`) gets glyphs made from
//! the machine's fonts first ([`crate::fonts`]); without fonts it is measured as a point at
//! its anchor, with a warning. Text on a path is laid out on a straight line here; 3D letter
//! rotation and expression selectors are warned about.

use kurbo::{Affine, Vec2};
use serde_json::Value;

use crate::eval;
use crate::model::{
    Loc, Num, Result, ShapeItem, array, error, number, object, opt_number, opt_property,
    opt_string, shape_items,
};

/// Letters drawn in one document at most: a glyph's outline is copied for every letter,
/// so this bounds the scene a text of many megabytes could build.
pub const MAX_LETTERS: usize = 100_000;

/// A font the document names (`fonts.list[]`).
#[derive(Clone, Debug)]
pub struct Font {
    /// `fName`: the name text documents refer to.
    pub name: String,
    /// `fFamily`.
    pub family: String,
    /// `fStyle`.
    pub style: String,
    /// `ascent`, in hundredths of the font size.
    pub ascent: f64,
}

/// An embedded glyph (`chars[]`): its outline at size 100 and its advance.
#[derive(Clone, Debug)]
pub struct Glyph {
    /// The character (one or more code points).
    pub ch: String,
    /// `style`: the font style it belongs to.
    pub style: String,
    /// `fFamily`: the font family it belongs to.
    pub family: String,
    /// `w`: the advance at size 100.
    pub width: f64,
    /// The outline as shape items (`data.shapes`).
    pub shapes: Vec<ShapeItem>,
    /// The outline at size 100, y down from the baseline, of a glyph made from a system
    /// font ([`crate::fonts`]) rather than embedded; drawn instead of `shapes`.
    pub outline: Option<kurbo::BezPath>,
}

/// The fonts and glyphs of a document.
#[derive(Clone, Debug, Default)]
pub struct Fonts {
    /// `fonts.list`.
    pub fonts: Vec<Font>,
    /// `chars`.
    pub glyphs: Vec<Glyph>,
}

impl Fonts {
    /// Reads `fonts` and `chars` from the document's root object.
    pub(crate) fn read(root: &serde_json::Map<String, Value>, at: &Loc) -> Result<Fonts> {
        let mut out = Fonts::default();
        if let Some(list) = root
            .get("fonts")
            .and_then(|f| f.get("list"))
            .filter(|l| !l.is_null())
        {
            let l_at = at.key("fonts").key("list");
            for (i, f) in array(list, &l_at)?.iter().enumerate() {
                let f_at = l_at.idx(i);
                let o = object(f, &f_at)?;
                out.fonts.push(Font {
                    name: opt_string(o, "fName", &f_at)?.unwrap_or_default(),
                    family: opt_string(o, "fFamily", &f_at)?.unwrap_or_default(),
                    style: opt_string(o, "fStyle", &f_at)?.unwrap_or_default(),
                    ascent: opt_number(o, "ascent", &f_at)?.unwrap_or(0.0),
                });
            }
        }
        if let Some(chars) = root.get("chars").filter(|c| !c.is_null()) {
            let c_at = at.key("chars");
            for (i, c) in array(chars, &c_at)?.iter().enumerate() {
                let g_at = c_at.idx(i);
                let o = object(c, &g_at)?;
                // A glyph drawn by a precomposition (`t: 1`) has no outline of its own.
                let shapes = match o.get("data").and_then(|d| d.get("shapes")) {
                    Some(s) if !s.is_null() && o.get("t").and_then(Value::as_i64) != Some(1) => {
                        shape_items(s, &g_at.key("data").key("shapes"))?
                    }
                    _ => Vec::new(),
                };
                out.glyphs.push(Glyph {
                    ch: opt_string(o, "ch", &g_at)?.unwrap_or_default(),
                    style: opt_string(o, "style", &g_at)?.unwrap_or_default(),
                    family: opt_string(o, "fFamily", &g_at)?.unwrap_or_default(),
                    width: opt_number(o, "w", &g_at)?.unwrap_or(0.0),
                    shapes,
                    outline: None,
                });
            }
        }
        Ok(out)
    }

    /// The font named `name`, else the first (as lottie-web falls back).
    fn font(&self, name: &str) -> Option<&Font> {
        self.fonts
            .iter()
            .find(|f| f.name == name)
            .or(self.fonts.first())
    }

    /// The glyphs of `font` by character, as indices into [`Fonts::glyphs`] (the first of
    /// a character's glyphs, as lottie-web finds it): built once a layout, not searched for
    /// every letter.
    fn glyphs_of(&self, font: Option<&Font>) -> std::collections::HashMap<&str, usize> {
        let (style, family) = font.map_or(("", ""), |f| (f.style.as_str(), f.family.as_str()));
        let mut out = std::collections::HashMap::new();
        for (i, g) in self.glyphs.iter().enumerate() {
            if g.style == style && g.family == family {
                out.entry(g.ch.as_str()).or_insert(i);
            }
        }
        out
    }
}

/// One text document (a keyframe's `s`): the text and how it is set.
#[derive(Clone, Debug, Default)]
pub struct TextDocument {
    /// `t`: the text; `\r` (or U+0003) breaks a line.
    pub text: String,
    /// `s`: font size.
    pub size: f64,
    /// `f`: the font's `fName`.
    pub font: String,
    /// `fc`: fill colour, components in `0..=1` (no fill when absent).
    pub fill: Option<Vec<f64>>,
    /// `sc`: stroke colour (no stroke when absent).
    pub stroke: Option<Vec<f64>>,
    /// `sw`: stroke width.
    pub stroke_width: f64,
    /// `j`: justification (0 left, 1 right, 2 centre, 3–6 full).
    pub justify: i64,
    /// `tr`: tracking, in thousandths of the font size.
    pub tracking: f64,
    /// `lh`: line height (the size × 1.2 when absent or zero).
    pub line_height: f64,
    /// `ls`: baseline shift.
    pub baseline_shift: f64,
    /// `ps`: box text's top-left corner.
    pub box_position: Option<Vec2>,
    /// `sz`: box text's size (lines wrap at its width).
    pub box_size: Option<Vec2>,
}

impl TextDocument {
    fn read(v: &Value, at: &Loc) -> Result<TextDocument> {
        let o = object(v, at)?;
        let vector = |key: &str| -> Result<Option<Vec<f64>>> {
            match o.get(key) {
                None | Some(Value::Null) => Ok(None),
                Some(v) => {
                    let k_at = at.key(key);
                    array(v, &k_at)?
                        .iter()
                        .enumerate()
                        .map(|(i, x)| number(x, &k_at.idx(i)))
                        .collect::<Result<Vec<f64>>>()
                        .map(Some)
                }
            }
        };
        let point = |key: &str| -> Result<Option<Vec2>> {
            Ok(vector(key)?.map(|v| {
                Vec2::new(
                    v.first().copied().unwrap_or(0.0),
                    v.get(1).copied().unwrap_or(0.0),
                )
            }))
        };
        Ok(TextDocument {
            text: opt_string(o, "t", at)?.unwrap_or_default(),
            size: opt_number(o, "s", at)?.unwrap_or(0.0),
            font: opt_string(o, "f", at)?.unwrap_or_default(),
            fill: vector("fc")?,
            stroke: vector("sc")?,
            stroke_width: opt_number(o, "sw", at)?.unwrap_or(0.0),
            justify: opt_number(o, "j", at)?.map_or(0, |j| j.round() as i64),
            tracking: opt_number(o, "tr", at)?.unwrap_or(0.0),
            line_height: opt_number(o, "lh", at)?.unwrap_or(0.0),
            baseline_shift: opt_number(o, "ls", at)?.unwrap_or(0.0),
            box_position: point("ps")?,
            box_size: point("sz")?,
        })
    }
}

/// A range selector (`a[].s`): which letters an animator acts on, and how much.
#[derive(Clone, Debug, Default)]
pub struct Selector {
    /// Start (`s`), end (`e`, 100 when absent) and offset (`o`), in percent or letters.
    pub start: Option<Num>,
    /// End.
    pub end: Option<Num>,
    /// Offset.
    pub offset: Option<Num>,
    /// `a`: amount, percent.
    pub amount: Option<Num>,
    /// `ne`: ease low, percent.
    pub ease_low: Option<Num>,
    /// `xe`: ease high, percent.
    pub ease_high: Option<Num>,
    /// `sm`: smoothness, percent (100 when absent).
    pub smoothness: Option<Num>,
    /// `b`: based on (1 characters, 2 characters without spaces, 3 words, 4 lines).
    pub based: i64,
    /// `r`: units (1 percent, 2 index).
    pub units: i64,
    /// `sh`: shape (1 square, 2 ramp up, 3 ramp down, 4 triangle, 5 round, 6 smooth).
    pub shape: i64,
    /// `rn`: random order (players shuffle at random; gmotion keeps the order).
    pub random: bool,
    /// An expression selector (not run).
    pub expression: bool,
}

/// One text animator (`t.a[]`): properties applied to the selected letters.
#[derive(Clone, Debug, Default)]
pub struct Animator {
    /// Where it is.
    pub at: Loc,
    /// The selector.
    pub selector: Selector,
    /// `a.p`: position offset.
    pub position: Option<Num>,
    /// `a.a`: anchor offset.
    pub anchor: Option<Num>,
    /// `a.s`: scale, percent.
    pub scale: Option<Num>,
    /// `a.sk`: skew, degrees.
    pub skew: Option<Num>,
    /// `a.sa`: skew axis, degrees.
    pub skew_axis: Option<Num>,
    /// `a.r`: rotation, degrees.
    pub rotation: Option<Num>,
    /// `a.o`: opacity, percent.
    pub opacity: Option<Num>,
    /// `a.t`: tracking, in pixels.
    pub tracking: Option<Num>,
    /// `a.fc`: fill colour.
    pub fill: Option<Num>,
    /// `a.sc`: stroke colour.
    pub stroke: Option<Num>,
    /// `a.sw`: stroke width.
    pub stroke_width: Option<Num>,
    /// `a.fh`: fill hue, degrees.
    pub hue: Option<Num>,
    /// `a.fs`: fill saturation, percent.
    pub saturation: Option<Num>,
    /// `a.fb`: fill brightness, percent.
    pub brightness: Option<Num>,
    /// `a.rx` or `a.ry`: 3D letter rotation (not drawn).
    pub turns_3d: bool,
}

impl Animator {
    fn read(v: &Value, at: &Loc) -> Result<Animator> {
        let o = object(v, at)?;
        let mut out = Animator {
            at: at.clone(),
            ..Animator::default()
        };
        if let Some(s) = o.get("s").filter(|s| !s.is_null()) {
            let s_at = at.key("s");
            let so = object(s, &s_at)?;
            let int = |key: &str, default: i64| -> Result<i64> {
                Ok(opt_number(so, key, &s_at)?.map_or(default, |x| x.round() as i64))
            };
            out.selector = Selector {
                start: opt_property(so, "s", &s_at)?,
                end: opt_property(so, "e", &s_at)?,
                offset: opt_property(so, "o", &s_at)?,
                amount: opt_property(so, "a", &s_at)?,
                ease_low: opt_property(so, "ne", &s_at)?,
                ease_high: opt_property(so, "xe", &s_at)?,
                smoothness: opt_property(so, "sm", &s_at)?,
                based: int("b", 1)?,
                units: int("r", 1)?,
                shape: int("sh", 1)?,
                random: int("rn", 0)? == 1,
                expression: so.get("x").is_some_and(|x| !x.is_null()),
            };
        }
        if let Some(a) = o.get("a").filter(|a| !a.is_null()) {
            let a_at = at.key("a");
            let ao = object(a, &a_at)?;
            let p = |key: &str| opt_property(ao, key, &a_at);
            out.position = p("p")?;
            out.anchor = p("a")?;
            out.scale = p("s")?;
            out.skew = p("sk")?;
            out.skew_axis = p("sa")?;
            out.rotation = p("r")?;
            out.opacity = p("o")?;
            out.tracking = p("t")?;
            out.fill = p("fc")?;
            out.stroke = p("sc")?;
            out.stroke_width = p("sw")?;
            out.hue = p("fh")?;
            out.saturation = p("fs")?;
            out.brightness = p("fb")?;
            out.turns_3d = ao.contains_key("rx") || ao.contains_key("ry");
        }
        Ok(out)
    }
}

/// A text layer's `t`.
#[derive(Clone, Debug, Default)]
pub struct TextData {
    /// Where it is.
    pub at: Loc,
    /// The document keyframes `(frame, document)`, in time order: each holds until the next.
    pub documents: Vec<(f64, TextDocument)>,
    /// `m.g`: anchor point grouping (1 characters, 2 words, 3 lines, 4 all).
    pub grouping: i64,
    /// `m.a`: grouping alignment, percent.
    pub alignment: Option<Num>,
    /// `a`: the animators.
    pub animators: Vec<Animator>,
    /// `p.m`: the text runs along a mask path.
    pub on_path: bool,
    /// An expression drives the document (`d.x`).
    pub expression: bool,
}

impl TextData {
    /// Reads a text layer's `t`.
    pub(crate) fn read(v: &Value, at: &Loc) -> Result<TextData> {
        let o = object(v, at)?;
        let mut out = TextData {
            at: at.clone(),
            grouping: 1,
            ..TextData::default()
        };
        if let Some(d) = o.get("d").filter(|d| !d.is_null()) {
            let d_at = at.key("d");
            let d_obj = object(d, &d_at)?;
            out.expression = d_obj.get("x").is_some_and(|x| !x.is_null());
            match d_obj.get("k") {
                // Since Bodymovin 4.4.14 the document is keyframed; before, `d` was it.
                Some(k) if k.is_array() => {
                    let k_at = d_at.key("k");
                    for (i, key) in array(k, &k_at)?.iter().enumerate() {
                        let key_at = k_at.idx(i);
                        let ko = object(key, &key_at)?;
                        let t = opt_number(ko, "t", &key_at)?.unwrap_or(0.0);
                        let Some(s) = ko.get("s") else {
                            return error(&key_at, "a text keyframe needs its document `s`");
                        };
                        out.documents
                            .push((t, TextDocument::read(s, &key_at.key("s"))?));
                    }
                }
                _ => out.documents.push((0.0, TextDocument::read(d, &d_at)?)),
            }
        }
        if let Some(m) = o.get("m").filter(|m| !m.is_null()) {
            let m_at = at.key("m");
            let mo = object(m, &m_at)?;
            out.grouping = opt_number(mo, "g", &m_at)?.map_or(1, |g| g.round() as i64);
            out.alignment = opt_property(mo, "a", &m_at)?;
        }
        if let Some(a) = o.get("a").filter(|a| !a.is_null()) {
            let a_at = at.key("a");
            out.animators = array(a, &a_at)?
                .iter()
                .enumerate()
                .map(|(i, v)| Animator::read(v, &a_at.idx(i)))
                .collect::<Result<_>>()?;
        }
        out.on_path = o
            .get("p")
            .and_then(|p| p.get("m"))
            .is_some_and(|m| !m.is_null());
        Ok(out)
    }

    /// The document shown at frame `t` (lottie-web's `getKeyframeValue`).
    pub fn document(&self, t: f64) -> Option<&TextDocument> {
        let i = self
            .documents
            .iter()
            .skip(1)
            .take_while(|(kt, _)| *kt <= t)
            .count();
        self.documents.get(i).map(|(_, d)| d)
    }
}

/// One letter of a laid-out document.
#[derive(Clone, Debug, Default)]
struct Letter {
    /// The glyph (index into [`Fonts::glyphs`]), if the file has it.
    glyph: Option<usize>,
    /// A line break (draws nothing).
    newline: bool,
    /// The character is a space.
    space: bool,
    /// Advance.
    l: f64,
    /// Width of the letter's anchor group (lottie-web's `an`).
    an: f64,
    /// Advance of the group before this letter (`add`).
    add: f64,
    /// Line number.
    line: usize,
    /// Anchor group (`ind`).
    ind: usize,
    /// Each animator's index of the letter in its selector's units (`anIndexes`).
    indexes: Vec<usize>,
    /// Justification offset from tracking animators (`animatorJustifyOffset`).
    justify_extra: f64,
}

/// A document laid out: letters and the measures placing them.
struct Layout {
    letters: Vec<Letter>,
    line_widths: Vec<f64>,
    box_width: f64,
    justify_offset: f64,
    /// Each animator's count of letters in its selector's units (`totalChars`).
    totals: Vec<usize>,
    ascent: f64,
}

/// The characters of `text` as lottie-web splits them (`buildFinalText`): code points,
/// with combining marks, variation selectors, zero-width joiners, emoji modifiers and
/// regional indicators kept on the character before them.
pub(crate) fn characters(text: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut join_next = false;
    for c in text.chars() {
        let u = c as u32;
        let combining = matches!(u, 0x300..=0x36F | 0x1AB0..=0x1AFF | 0x1DC0..=0x1DFF | 0x20D0..=0x20FF | 0xFE20..=0xFE2F)
            || matches!(u, 0xFE00..=0xFE0F | 0x1F3FB..=0x1F3FF | 0xE0020..=0xE007F);
        let joiner = u == 0x200D;
        match out.last_mut() {
            Some(last) if combining || joiner || join_next => last.push(c),
            _ => out.push(c.to_string()),
        }
        join_next = joiner;
    }
    out
}

fn is_newline(ch: &str) -> bool {
    ch == "\r" || ch == "\u{3}"
}

/// Lays `doc` out (`completeTextData`), measuring letters by their glyphs' advances.
fn layout(doc: &TextDocument, data: &TextData, fonts: &Fonts) -> Layout {
    let font = fonts.font(&doc.font);
    let size = doc.size;
    let glyphs = fonts.glyphs_of(font);
    let advance = |ch: &str| -> f64 {
        glyphs
            .get(ch)
            .map_or(0.0, |&g| fonts.glyphs[g].width * size / 100.0)
    };
    let tracking = doc.tracking / 1000.0 * size;
    let mut text = characters(&doc.text);
    text.truncate(MAX_LETTERS);
    if let Some(sz) = doc.box_size {
        // Box text wraps at the last space before the box's width, or before the letter
        // that does not fit when a word is wider than the box.
        let mut line = 0.0;
        let mut last_space: Option<usize> = None;
        let mut i = 0;
        while i < text.len() {
            if text[i] == " " {
                last_space = Some(i);
            } else if is_newline(&text[i]) {
                line = 0.0;
            }
            let w = if is_newline(&text[i]) {
                0.0
            } else {
                advance(&text[i])
            };
            // lottie-web loops for ever on a letter wider than the box at a line's start.
            if line + w > sz.x && text[i] != " " && line > 0.0 && text.len() < MAX_LETTERS {
                match last_space.take() {
                    Some(s) => {
                        text[s] = "\r".into();
                        i = s;
                    }
                    None => text.insert(i, "\r".into()),
                }
                line = 0.0;
            } else {
                line += w + tracking;
            }
            i += 1;
        }
    }
    let mut letters = Vec::with_capacity(text.len());
    let mut line_widths = Vec::new();
    let mut line_width = -tracking;
    let mut max_width: f64 = 0.0;
    let mut spaces = 0.0;
    let mut line = 0;
    let (mut index, mut current_size, mut current_pos) = (0, 0.0, 0);
    let len = text.len();
    for (i, ch) in text.iter().enumerate() {
        let newline = is_newline(ch);
        if newline {
            spaces = 0.0;
            line_widths.push(line_width);
            max_width = max_width.max(line_width);
            line_width = -2.0 * tracking;
            line += 1;
        }
        let l = if newline { 0.0 } else { advance(ch) };
        if ch == " " {
            spaces += l + tracking;
        } else {
            line_width += l + tracking + spaces;
            spaces = 0.0;
        }
        letters.push(Letter {
            glyph: if newline {
                None
            } else {
                glyphs.get(ch.as_str()).copied()
            },
            newline,
            space: ch == " ",
            l,
            an: l,
            add: current_size,
            line,
            ..Letter::default()
        });
        // Anchor groups: words (2) or lines (3) share one anchor; else each letter.
        let ends_group = match data.grouping {
            2 => newline || ch == " " || i == len - 1,
            3 => newline || i == len - 1,
            _ => {
                letters[index].ind = index;
                index += 1;
                continue;
            }
        };
        current_size += l;
        if ends_group {
            if newline || (data.grouping == 2 && ch == " ") {
                current_size -= l;
            }
            while current_pos <= i {
                letters[current_pos].an = current_size;
                letters[current_pos].ind = index;
                current_pos += 1;
            }
            index += 1;
            current_size = 0.0;
        }
    }
    max_width = max_width.max(line_width);
    line_widths.push(line_width);
    let (box_width, justify_offset) = match doc.box_size {
        Some(sz) => (sz.x, 0.0),
        None => (
            max_width,
            match doc.justify {
                1 => -max_width,
                2 => -max_width / 2.0,
                _ => 0.0,
            },
        ),
    };
    // Each animator counts letters in its selector's units.
    let mut totals = Vec::with_capacity(data.animators.len());
    for a in &data.animators {
        let mut ind = 0;
        for (i, letter) in letters.iter_mut().enumerate() {
            letter.indexes.push(ind);
            let counts = match a.selector.based {
                2 => !letter.newline && !letter.space,
                3 => letter.newline || letter.space || i == len - 1,
                4 => letter.newline || i == len - 1,
                _ => !letter.newline,
            };
            if counts {
                ind += 1;
            }
        }
        totals.push(ind);
    }
    Layout {
        letters,
        line_widths,
        box_width,
        justify_offset,
        totals,
        ascent: font.map_or(0.0, |f| f.ascent) * size / 100.0,
    }
}

/// A selector's range at `t`, in its units: `(start, end)`, ordered.
fn range(s: &Selector, t: f64, total: usize) -> (f64, f64) {
    let divisor = if s.units == 2 {
        1.0
    } else {
        100.0 / total.max(1) as f64
    };
    let o = eval::scalar(s.offset.as_ref(), t, 0.0) / divisor;
    let start = eval::scalar(s.start.as_ref(), t, 0.0) / divisor + o;
    let end = match &s.end {
        Some(e) => eval::scalar(Some(e), t, 100.0) / divisor + o,
        None => 100.0 / divisor + o,
    };
    if start > end {
        (end, start)
    } else {
        (start, end)
    }
}

/// How much a selector selects the letter at index `ind` (`getMult`), amount included.
fn weight(s: &Selector, t: f64, (start, end): (f64, f64), ind: f64) -> f64 {
    let ne = eval::scalar(s.ease_low.as_ref(), t, 0.0);
    let xe = eval::scalar(s.ease_high.as_ref(), t, 0.0);
    let (mut x1, mut y1, mut x2, mut y2) = (0.0, 0.0, 1.0, 1.0);
    if ne > 0.0 {
        x1 = ne / 100.0;
    } else {
        y1 = -ne / 100.0;
    }
    if xe > 0.0 {
        x2 = 1.0 - xe / 100.0;
    } else {
        y2 = 1.0 + xe / 100.0;
    }
    let ease = |x: f64| -> f64 {
        if (x1, y1, x2, y2) == (0.0, 0.0, 1.0, 1.0) {
            return x;
        }
        let c = kurbo::CubicBez::new((0.0, 0.0), (x1, y1), (x2, y2), (1.0, 1.0));
        use kurbo::ParamCurve;
        c.eval(gmotion::signals::easing::solve_bezier_x(
            &c,
            x.clamp(0.0, 1.0),
        ))
        .y
    };
    let (s_, e) = (start, end);
    let ramp = || (0.5 / (e - s_) + (ind - s_) / (e - s_)).clamp(0.0, 1.0);
    let mult = match s.shape {
        2 => ease(if e == s_ {
            f64::from(u8::from(ind >= e))
        } else {
            ramp()
        }),
        3 => ease(if e == s_ {
            f64::from(u8::from(ind < e))
        } else {
            1.0 - ramp()
        }),
        4 => ease(if e == s_ {
            0.0
        } else {
            let m = ramp();
            if m < 0.5 {
                m * 2.0
            } else {
                1.0 - 2.0 * (m - 0.5)
            }
        }),
        5 => ease(if e == s_ {
            0.0
        } else {
            let tot = e - s_;
            let i = (ind + 0.5 - s_).clamp(0.0, tot);
            let x = -tot / 2.0 + i;
            let a = tot / 2.0;
            (1.0 - x * x / (a * a)).max(0.0).sqrt()
        }),
        6 => ease(if e == s_ {
            0.0
        } else {
            let i = (ind + 0.5 - s_).clamp(0.0, e - s_);
            (1.0 + (std::f64::consts::PI + std::f64::consts::TAU * i / (e - s_)).cos()) / 2.0
        }),
        _ => {
            let mut m = 0.0;
            if ind >= s_.floor() {
                m = if ind - s_ < 0.0 {
                    (e.min(1.0) - (s_ - ind)).clamp(0.0, 1.0)
                } else {
                    (e - ind).clamp(0.0, 1.0)
                };
            }
            ease(m)
        }
    };
    let sm = eval::scalar(s.smoothness.as_ref(), t, 100.0);
    let mult = if sm == 100.0 {
        mult
    } else {
        let smooth = if sm == 0.0 { 1e-8 } else { sm / 100.0 };
        let threshold = 0.5 - smooth * 0.5;
        if mult < threshold {
            0.0
        } else {
            ((mult - threshold) / smooth).min(1.0)
        }
    };
    mult * eval::scalar(s.amount.as_ref(), t, 100.0) / 100.0
}

/// A letter to draw: its glyph, where (in the layer's space), how opaque, and its paint.
#[derive(Clone, Debug)]
pub struct PlacedLetter {
    /// Index into [`Fonts::glyphs`].
    pub glyph: usize,
    /// The letter's space to the layer's.
    pub transform: Affine,
    /// Glyph space (size 100) to the letter's space: the font size over 100.
    pub glyph_scale: f64,
    /// Opacity in `0..=1`.
    pub opacity: f64,
    /// Fill colour, components in `0..=1`.
    pub fill: Option<[f64; 3]>,
    /// Stroke colour and width, in the letter's space.
    pub stroke: Option<([f64; 3], f64)>,
    /// The line it is on, from 0.
    pub line: usize,
    /// The word it is in (a run of letters between spaces and line breaks), counted over
    /// the whole text from 0.
    pub word: usize,
}

/// The letters of `data` at frame `t`, placed (`getMeasures` without a path).
pub fn letters(data: &TextData, fonts: &Fonts, t: f64) -> Vec<PlacedLetter> {
    let Some(doc) = data.document(t) else {
        return Vec::new();
    };
    let mut lay = layout(doc, data, fonts);
    let size = doc.size;
    let align = eval::vec2(data.alignment.as_ref(), t, Vec2::ZERO);
    let y_off = size * 1.2 * 0.714;
    let tracking = doc.tracking * 0.001 * size;
    let line_height = if doc.line_height != 0.0 {
        doc.line_height
    } else {
        size * 1.2
    };
    let ranges: Vec<(f64, f64)> = data
        .animators
        .iter()
        .zip(&lay.totals)
        .map(|(a, &n)| range(&a.selector, t, n))
        .collect();
    let weights = |letter: &Letter| -> Vec<f64> {
        data.animators
            .iter()
            .zip(&ranges)
            .zip(&letter.indexes)
            .map(|((a, &r), &ind)| weight(&a.selector, t, r, ind as f64))
            .collect()
    };
    // Tracking animators move a right- or centre-justified line's start.
    if doc.justify == 1 || doc.justify == 2 {
        let mult = if doc.justify == 2 { -0.5 } else { -1.0 };
        let (mut offset, mut first_offset, mut last, mut new_line) = (0.0, 0.0, 0, true);
        let n = lay.letters.len();
        for i in 0..=n {
            if i == n || lay.letters[i].newline {
                if offset != 0.0 {
                    offset += first_offset;
                }
                while last < i {
                    lay.letters[last].justify_extra = offset;
                    last += 1;
                }
                offset = 0.0;
                new_line = true;
                continue;
            }
            let w = weights(&lay.letters[i]);
            for (a, m) in data.animators.iter().zip(&w) {
                if let Some(tr) = &a.tracking {
                    let v = eval::scalar(Some(tr), t, 0.0);
                    if new_line && doc.justify == 2 {
                        first_offset += v * mult;
                    }
                    offset += v * m * mult;
                }
            }
            new_line = false;
        }
    }
    let channel = |c: &Option<Vec<f64>>| -> Option<[f64; 3]> {
        c.as_ref().map(|c| {
            let k = |i: usize| c.get(i).copied().unwrap_or(0.0);
            [k(0), k(1), k(2)]
        })
    };
    let (mut x, mut y, mut first_line) = (0.0, 0.0, true);
    let mut out = Vec::new();
    // Words: a letter after a space or a line break starts one.
    let (mut words, mut in_word) = (0, false);
    for letter in &lay.letters {
        let starts_word = !(letter.newline || letter.space || in_word);
        in_word = !(letter.newline || letter.space);
        words += usize::from(starts_word);
        if letter.newline {
            x = 0.0;
            y += line_height + if first_line { 1.0 } else { 0.0 };
            first_line = false;
            continue;
        }
        let w = weights(letter);
        let offf = letter.an / 2.0 - letter.add;
        let grouping = Vec2::new(align.x * letter.an * 0.005, align.y * y_off * 0.01);
        let mut m = Affine::translate(-grouping) * Affine::translate((-offf, 0.0));
        for (a, &mult) in data.animators.iter().zip(&w) {
            if let Some(tr) = &a.tracking
                && (x != 0.0 || doc.justify != 0)
            {
                x += eval::scalar(Some(tr), t, 0.0) * mult;
            }
        }
        let mut fill = channel(&doc.fill);
        let mut stroke = channel(&doc.stroke);
        let mut stroke_width = doc.stroke_width;
        let mut opacity = 1.0;
        for (a, &mult) in data.animators.iter().zip(&w) {
            if let Some(an) = &a.anchor {
                m = Affine::translate(-eval::vec2(Some(an), t, Vec2::ZERO) * mult) * m;
            }
        }
        for (a, &mult) in data.animators.iter().zip(&w) {
            if let Some(s) = &a.scale {
                let s = eval::vec2(Some(s), t, Vec2::new(100.0, 100.0)) / 100.0;
                m = Affine::scale_non_uniform(1.0 + (s.x - 1.0) * mult, 1.0 + (s.y - 1.0) * mult)
                    * m;
            }
        }
        for (a, &mult) in data.animators.iter().zip(&w) {
            if let Some(sk) = &a.skew {
                let sk = eval::scalar(Some(sk), t, 0.0).to_radians() * mult;
                let sa = eval::scalar(a.skew_axis.as_ref(), t, 0.0).to_radians() * mult;
                m = eval::skew(sk, sa) * m;
            }
            if let Some(r) = &a.rotation {
                m = Affine::rotate(eval::scalar(Some(r), t, 0.0).to_radians() * mult) * m;
            }
            if let Some(o) = &a.opacity {
                let o = eval::scalar(Some(o), t, 100.0) / 100.0;
                opacity += (o * mult - opacity) * mult;
            }
            if let Some(sw) = &a.stroke_width {
                stroke_width += eval::scalar(Some(sw), t, 0.0) * mult;
            }
            if let Some(sc) = &a.stroke {
                let target = eval::num(Some(sc), t, &[0.0, 0.0, 0.0]);
                let c = stroke.get_or_insert([0.0; 3]);
                for (k, v) in c.iter_mut().enumerate() {
                    *v += (target.get(k).copied().unwrap_or(0.0) - *v) * mult;
                }
            }
            if let Some(f) = fill.as_mut() {
                if let Some(fc) = &a.fill {
                    let target = eval::num(Some(fc), t, &[0.0, 0.0, 0.0]);
                    for (k, v) in f.iter_mut().enumerate() {
                        *v += (target.get(k).copied().unwrap_or(0.0) - *v) * mult;
                    }
                }
                if let Some(h) = &a.hue {
                    *f = hsv_shift(*f, eval::scalar(Some(h), t, 0.0) * mult / 360.0, 0.0, 0.0);
                }
                if let Some(s) = &a.saturation {
                    *f = hsv_shift(*f, 0.0, eval::scalar(Some(s), t, 0.0) / 100.0 * mult, 0.0);
                }
                if let Some(b) = &a.brightness {
                    *f = hsv_shift(*f, 0.0, 0.0, eval::scalar(Some(b), t, 0.0) / 100.0 * mult);
                }
            }
        }
        for (a, &mult) in data.animators.iter().zip(&w) {
            if let Some(p) = &a.position {
                m = Affine::translate(eval::vec2(Some(p), t, Vec2::ZERO) * mult) * m;
            }
        }
        m = Affine::translate((x, y)) * m;
        if let Some(ps) = doc.box_position {
            m = Affine::translate((ps.x, ps.y + lay.ascent)) * m;
        }
        let line_width = lay.line_widths.get(letter.line).copied().unwrap_or(0.0);
        let justify = match doc.justify {
            1 => letter.justify_extra + lay.justify_offset + (lay.box_width - line_width),
            2 => letter.justify_extra + lay.justify_offset + (lay.box_width - line_width) / 2.0,
            _ => 0.0,
        };
        m = Affine::translate((justify, -doc.baseline_shift)) * m;
        m = Affine::translate(grouping) * Affine::translate((offf, 0.0)) * m;
        x += letter.l + tracking;
        if let Some(glyph) = letter.glyph {
            out.push(PlacedLetter {
                glyph,
                transform: m,
                glyph_scale: size / 100.0,
                opacity: opacity.clamp(0.0, 1.0),
                fill,
                stroke: stroke.map(|c| (c, stroke_width.max(0.0))),
                line: letter.line,
                word: words.saturating_sub(1),
            });
        }
    }
    out
}

/// `rgb` (components in `0..=1`) with hue turned by `dh` turns and saturation and value
/// moved by `ds` and `dv`, clamped (lottie-web's `addHueToRGB` and its siblings).
fn hsv_shift(rgb: [f64; 3], dh: f64, ds: f64, dv: f64) -> [f64; 3] {
    let [r, g, b] = rgb;
    let max = r.max(g).max(b);
    let min = r.min(g).min(b);
    let d = max - min;
    let mut h = if d == 0.0 {
        0.0
    } else if max == r {
        ((g - b) + d * if g < b { 6.0 } else { 0.0 }) / (6.0 * d)
    } else if max == g {
        ((b - r) + d * 2.0) / (6.0 * d)
    } else {
        ((r - g) + d * 4.0) / (6.0 * d)
    };
    let s = if max == 0.0 { 0.0 } else { d / max };
    h = (h + dh).rem_euclid(1.0);
    let s = (s + ds).clamp(0.0, 1.0);
    let v = (max + dv).clamp(0.0, 1.0);
    let i = (h * 6.0).floor();
    let f = h * 6.0 - i;
    let (p, q, u) = (v * (1.0 - s), v * (1.0 - f * s), v * (1.0 - (1.0 - f) * s));
    match i as i64 % 6 {
        0 => [v, u, p],
        1 => [q, v, p],
        2 => [p, v, u],
        3 => [p, q, v],
        4 => [u, p, v],
        _ => [v, p, q],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glyph(ch: &str, width: f64) -> Glyph {
        Glyph {
            ch: ch.into(),
            style: "Regular".into(),
            family: "F".into(),
            width,
            shapes: Vec::new(),
            outline: None,
        }
    }

    fn fonts() -> Fonts {
        Fonts {
            fonts: vec![Font {
                name: "F-Regular".into(),
                family: "F".into(),
                style: "Regular".into(),
                ascent: 70.0,
            }],
            glyphs: vec![glyph("a", 50.0), glyph(" ", 25.0), glyph("b", 60.0)],
        }
    }

    fn data(text: &str, justify: i64) -> TextData {
        TextData {
            documents: vec![(
                0.0,
                TextDocument {
                    text: text.into(),
                    size: 20.0,
                    font: "F-Regular".into(),
                    fill: Some(vec![1.0, 0.0, 0.0]),
                    justify,
                    ..TextDocument::default()
                },
            )],
            grouping: 1,
            ..TextData::default()
        }
    }

    fn origins(d: &TextData) -> Vec<(f64, f64)> {
        letters(d, &fonts(), 0.0)
            .iter()
            .map(|l| {
                let c = l.transform.as_coeffs();
                (c[4], c[5])
            })
            .collect()
    }

    #[test]
    fn letters_advance_by_their_glyphs_widths_at_the_size() {
        // a: 50 → 10 px at size 20, space 5 px, b 12 px.
        assert_eq!(
            origins(&data("ab a", 0)),
            vec![(0.0, 0.0), (10.0, 0.0), (22.0, 0.0), (27.0, 0.0)]
        );
    }

    #[test]
    fn right_and_centre_justification_end_and_centre_each_line_on_the_anchor() {
        // "ab" is 22 px wide: right-justified it ends at 0, centred it spans ±11.
        assert_eq!(origins(&data("ab", 1))[0], (-22.0, 0.0));
        assert_eq!(origins(&data("ab", 2))[0], (-11.0, 0.0));
        // A second line, shorter, is justified on its own width, a line height below.
        let lines = origins(&data("ab\ra", 1));
        assert_eq!(lines[2], (-10.0, 24.0 + 1.0));
    }

    #[test]
    fn box_text_wraps_at_the_last_space_that_fits() {
        let mut d = data("ab ab ab", 0);
        d.documents[0].1.box_size = Some(Vec2::new(50.0, 100.0));
        d.documents[0].1.box_position = Some(Vec2::new(0.0, 0.0));
        let o = origins(&d);
        // "ab ab" fits in 49 px; the third word starts a line, at the box's left.
        let ascent = 70.0 * 20.0 / 100.0;
        assert_eq!(o.len(), 7, "the space that wrapped became the line break");
        assert_eq!(o[5], (0.0, ascent + 25.0));
    }

    #[test]
    fn a_full_square_selector_applies_all_of_an_animator_to_every_letter() {
        let mut d = data("aa", 0);
        let num = |v: Vec<f64>| crate::model::Property {
            value: crate::model::Prop::Static(v),
            expression: false,
            at: Loc::root(),
        };
        d.animators.push(Animator {
            position: Some(num(vec![0.0, -30.0])),
            opacity: Some(num(vec![0.0])),
            ..Animator::default()
        });
        d.animators[0].selector.based = 1;
        d.animators[0].selector.units = 1;
        d.animators[0].selector.shape = 1;
        let placed = letters(&d, &fonts(), 0.0);
        assert!(placed.iter().all(|l| l.opacity == 0.0));
        assert_eq!(origins(&d), vec![(0.0, -30.0), (10.0, -30.0)]);
        // A range over the first half selects the first letter only.
        d.animators[0].selector.end = Some(num(vec![50.0]));
        assert_eq!(origins(&d), vec![(0.0, -30.0), (10.0, 0.0)]);
    }

    #[test]
    fn hue_turns_and_brightness_clamps() {
        let turned = hsv_shift([1.0, 0.0, 0.0], 1.0 / 3.0, 0.0, 0.0);
        assert!((turned[1] - 1.0).abs() < 1e-9 && turned[0].abs() < 1e-9);
        assert_eq!(hsv_shift([0.5, 0.5, 0.5], 0.0, 0.0, 1.0), [1.0, 1.0, 1.0]);
    }

    #[test]
    fn combining_marks_stay_on_their_letter() {
        assert_eq!(characters("e\u{301}a"), vec!["e\u{301}", "a"]);
        assert_eq!(characters("👍🏽!"), vec!["👍🏽", "!"]);
    }
}
