//! How an importer names shapes and chooses the animated units: the options that the
//! grammar's `tag_from` and `units` directives (and the command line's `--tag-from` and
//! `--units`) set, and the name handling every importer shares ([`strip_counter`],
//! [`grammar_name`]). The importers implement the choice; the core only carries it.

/// Which source attribute names a shape's tag.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TagFrom {
    /// The nearest of `data-tag`, the first `class`, `inkscape:label` on the element or an
    /// ancestor; else the id of the nearest ancestor `<g>` without its counter; else the
    /// element's name.
    #[default]
    Auto,
    /// Only `data-tag`, then the element's name.
    DataTag,
    /// Only the first class name, then the element's name.
    Class,
    /// Only `inkscape:label`, then the element's name.
    Label,
    /// Only the id of the nearest `<g>` without its counter, then the element's name.
    Layer,
}

impl TagFrom {
    /// Whether this source reads layer (`<g>`) ids.
    pub fn reads_layers(self) -> bool {
        matches!(self, TagFrom::Auto | TagFrom::Layer)
    }
}

/// Which nodes become animated units (shapes). Units never nest: inside a unit nothing else
/// is one. Clip, mask and pattern content is never a unit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Units {
    /// A group (`<g>`, `<a>`, or a `use` of a group or symbol) that carries an explicit
    /// tag itself (`data-tag`, `class` or `inkscape:label`, as [`TagFrom`] selects) is one
    /// unit, so a character drawn with many paths moves as one piece; the outermost such
    /// group wins. An Inkscape layer's label names its paths but does not make the layer a
    /// unit, and neither does an Illustrator layer id. Each `<text>` is one unit. Every
    /// other visible path is its own unit.
    #[default]
    Auto,
    /// Every visible path (and every glyph run of a text) is a unit.
    Paths,
    /// Every outermost group that carries a tag itself, layer ids and Inkscape layer labels
    /// included, is a unit; visible paths outside such groups are units of their own.
    Groups,
}

/// Removes a trailing layer counter: `_12`, `-3`, or Illustrator's `_12_`. A name that is
/// only a counter is kept as it is, so a tag is never empty.
///
/// Design tools make layer names unique with a counter; the counter is noise to a grammar
/// author, so every `Wheel_2` is a `Wheel`.
///
/// ```
/// use gmotion::tagging::strip_counter;
/// assert_eq!(strip_counter("Wheel_2"), "Wheel");
/// assert_eq!(strip_counter("arm-13"), "arm");
/// assert_eq!(strip_counter("eye_1_"), "eye");
/// assert_eq!(strip_counter("layer"), "layer");
/// assert_eq!(strip_counter("_7"), "_7");
/// ```
pub fn strip_counter(name: &str) -> &str {
    let body = name.strip_suffix('_').unwrap_or(name);
    let digits = body.trim_end_matches(|c: char| c.is_ascii_digit());
    if digits.len() == body.len() {
        return name;
    }
    match digits.strip_suffix(['_', '-']) {
        Some(stem) if !stem.is_empty() => stem,
        _ => name,
    }
}

/// A layer id without the counter a design tool added to make it unique, keeping distinct
/// layers distinct: Illustrator's duplicate suffix `_12_` always goes (`eye_1_`, `eye_2_`
/// are copies of `eye`); a plain `_12` or `-3` goes only when the stem is itself a layer
/// (`exists`), as Figma numbers copies after the first (`Vector`, `Vector_2`). So
/// Illustrator's `Layer_1` and `Layer_2` stay two layers; a grammar takes both with the
/// pattern `Layer_*`.
///
/// ```
/// use gmotion::tagging::strip_counter_among;
/// let ids = ["Vector", "Vector_2", "Layer_1", "Layer_2", "eye_1_"];
/// let exists = |s: &str| ids.contains(&s);
/// assert_eq!(strip_counter_among("Vector_2", exists), "Vector");
/// assert_eq!(strip_counter_among("Layer_2", exists), "Layer_2");
/// assert_eq!(strip_counter_among("eye_1_", exists), "eye");
/// ```
pub fn strip_counter_among(name: &str, exists: impl Fn(&str) -> bool) -> &str {
    let stem = strip_counter(name);
    if stem.len() == name.len() || name.ends_with('_') || exists(stem) {
        stem
    } else {
        name
    }
}

/// A free-form layer name as a name a grammar can write without quotes: every run of
/// characters that cannot continue an identifier (spaces, punctuation) becomes one `_`,
/// leading and trailing ones are dropped, a name starting with a digit gets a leading `_`,
/// and a name that would read as an inverted tag (`inv_…`) too. `None` when nothing is left.
///
/// ```
/// use gmotion::tagging::grammar_name;
/// assert_eq!(grammar_name("Left arm 2").as_deref(), Some("Left_arm_2"));
/// assert_eq!(grammar_name("  wheel (front) ").as_deref(), Some("wheel_front"));
/// assert_eq!(grammar_name("3D box").as_deref(), Some("_3D_box"));
/// assert_eq!(grammar_name("inv_x").as_deref(), Some("_inv_x"));
/// assert_eq!(grammar_name("!!"), None);
/// ```
pub fn grammar_name(name: &str) -> Option<String> {
    let mut out = String::with_capacity(name.len());
    let mut gap = false;
    for c in name.chars() {
        if c.is_alphanumeric() || c == '_' {
            if gap && !out.is_empty() {
                out.push('_');
            }
            gap = false;
            out.push(c);
        } else {
            gap = true;
        }
    }
    if out.is_empty() {
        return None;
    }
    if out.starts_with(|c: char| c.is_ascii_digit()) || out.starts_with("inv_") {
        out.insert(0, '_');
    }
    Some(out)
}
