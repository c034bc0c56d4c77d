//! How an importer names shapes and chooses the animated units: the options that the
//! grammar's `tag_from` and `units` directives (and the command line's `--tag-from` and
//! `--units`) set, and the name handling every importer shares ([`strip_counter`],
//! [`grammar_name`]). The importers implement the choice; the core only carries it.

/// Which source attribute names a shape's tag.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TagFrom {
    /// The nearest of `data-tag`, the first `class` that is not a generated style class
    /// ([`is_generated_class`]), `inkscape:label` on the element or an ancestor; else the
    /// id of the nearest ancestor `<g>` without its counter; else the element's name.
    #[default]
    Auto,
    /// Only `data-tag`, then the element's name.
    DataTag,
    /// Only the first class name, generated style classes included (asked for by name,
    /// `st0` groups shapes by their style), then the element's name.
    Class,
    /// Only `inkscape:label`, then the element's name.
    Label,
    /// Only the id of the nearest `<g>` without its counter, then the element's name.
    Layer,
}

impl TagFrom {
    /// Every source, in the order `--tag-from` lists them.
    pub const ALL: [TagFrom; 5] = [
        TagFrom::Auto,
        TagFrom::DataTag,
        TagFrom::Class,
        TagFrom::Label,
        TagFrom::Layer,
    ];

    /// The option's name as `--tag-from` and the grammar's `tag_from` spell it.
    pub fn name(self) -> &'static str {
        match self {
            TagFrom::Auto => "auto",
            TagFrom::DataTag => "data-tag",
            TagFrom::Class => "class",
            TagFrom::Label => "label",
            TagFrom::Layer => "layer",
        }
    }

    /// Whether this source reads layer (`<g>`) ids.
    pub fn reads_layers(self) -> bool {
        matches!(self, TagFrom::Auto | TagFrom::Layer)
    }
}

/// The style classes design tools generate, as `(prefix, tool)`: a class that is one of
/// these prefixes followed by a whole number (`st0`, `cls-12`) only carries a style, so it
/// never names a shape under [`TagFrom::Auto`].
///
/// Only these prefixes count: a class the designer chose may well end in a number
/// (`node3`, `vseg0`, `icon2`), so no looser rule (any short word and a number) is safe.
/// Tools not listed write no classes of their own: Figma, Sketch and Affinity Designer
/// write presentation attributes or `style` and name layers with ids, Inkscape writes
/// `style` and `inkscape:label`.
pub const GENERATED_CLASSES: &[(&str, &str)] = &[
    (
        "st",
        "Adobe Illustrator, Save As SVG with internal CSS (st0, st1, …)",
    ),
    (
        "cls-",
        "Adobe Illustrator's Export As SVG with internal CSS (cls-1, cls-2, …)",
    ),
    ("fil", "CorelDRAW fills (fil0, fil1, …)"),
    ("str", "CorelDRAW strokes (str0, str1, …)"),
    ("fnt", "CorelDRAW fonts (fnt0, fnt1, …)"),
];

/// Whether `class` is a generated style class ([`GENERATED_CLASSES`]): one of the listed
/// prefixes followed by ASCII digits and nothing else, possibly behind the `NAME__` an
/// optimiser puts before every class to keep files apart (svgo's `prefixIds`, which svgr
/// and React icon builds run: `prefix__cls-1`, `icon__st0`).
///
/// ```
/// use gmotion::tagging::is_generated_class;
/// assert!(is_generated_class("st12"));
/// assert!(is_generated_class("cls-3"));
/// assert!(is_generated_class("fil0"));
/// assert!(is_generated_class("prefix__cls-1"));
/// assert!(!is_generated_class("st"));
/// assert!(!is_generated_class("stem2"));
/// assert!(!is_generated_class("node3"));
/// assert!(!is_generated_class("hero__wing"));
/// ```
pub fn is_generated_class(class: &str) -> bool {
    let class = class.rsplit_once("__").map_or(class, |(_, rest)| rest);
    GENERATED_CLASSES.iter().any(|(prefix, _)| {
        class
            .strip_prefix(prefix)
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
    })
}

/// The names the SVG importer falls back to when nothing names a shape: the names of the
/// elements that draw (`path`, `rect`, …) or group.
const INVENTED: &[&str] = &[
    "path", "rect", "circle", "ellipse", "line", "polyline", "polygon", "text", "image", "g",
    "use", "svg",
];

/// Whether a shape tag names nothing a designer chose: a generated style class (`st0`), an
/// element name an importer fell back to (`path`), or an element name with a tool's
/// serial number (Inkscape's `path1234`, `g12`, `rect5`, or `layer1`). Used to tell a user
/// when another tag source would name a scene's shapes better.
///
/// ```
/// use gmotion::tagging::looks_generated;
/// assert!(looks_generated("st3"));
/// assert!(looks_generated("path"));
/// assert!(looks_generated("path1234"));
/// assert!(!looks_generated("letter_G"));
/// assert!(!looks_generated("Layer_1"));
/// ```
pub fn looks_generated(tag: &str) -> bool {
    let word = tag.trim_end_matches(|c: char| c.is_ascii_digit());
    is_generated_class(tag)
        || INVENTED.contains(&word)
        || (word == "layer" && word.len() < tag.len())
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

/// The name an id spells with the escapes Adobe Illustrator and CorelDRAW write for the
/// characters an XML id cannot hold (`_xHH_` or `_xHHHH_`, the character's code in hex:
/// `_x33_D_box` is the layer "3D box", `PL_x5F_Reset` is "PL_Reset", `Layer_x0020_1` is
/// "Layer 1"), as the designer wrote it (spaces kept, as an Inkscape label's are: a grammar
/// names it in quotes); `None` when it has no escape.
///
/// ```
/// use gmotion::tagging::unescape_id;
/// assert_eq!(unescape_id("PL_x5F_Reset_1_").as_deref(), Some("PL_Reset_1_"));
/// assert_eq!(unescape_id("_x33_D_box").as_deref(), Some("3D_box"));
/// assert_eq!(unescape_id("Layer_x0020_1").as_deref(), Some("Layer 1"));
/// assert_eq!(unescape_id("Wheel_2"), None);
/// assert_eq!(unescape_id("box_xyz_"), None);
/// ```
pub fn unescape_id(id: &str) -> Option<String> {
    let mut out = String::with_capacity(id.len());
    let mut rest = id;
    let mut found = false;
    while let Some(at) = rest.find("_x") {
        out.push_str(&rest[..at]);
        let after = &rest[at + 2..];
        let hex = after
            .find('_')
            .map(|end| &after[..end])
            .filter(|h| (2..=4).contains(&h.len()) && h.bytes().all(|b| b.is_ascii_hexdigit()));
        match hex.and_then(|h| u32::from_str_radix(h, 16).ok().and_then(char::from_u32)) {
            Some(c) => {
                out.push(c);
                rest = &after[hex.map_or(0, str::len) + 1..];
                found = true;
            }
            None => {
                out.push_str("_x");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    found.then_some(out).filter(|s| !s.trim().is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_generated_classes_of_each_tool_are_recognised() {
        for class in [
            "st0", "st1", "st12", "st123", "cls-1", "cls-12", "fil0", "fil3", "str1", "fnt0",
        ] {
            assert!(is_generated_class(class), "{class}");
        }
    }

    #[test]
    fn a_designers_class_is_not_generated_even_with_a_number() {
        for class in [
            "st", "cls-", "cls1", "st-1", "st1a", "stem", "stem2", "star3", "first", "node3",
            "vseg0", "hseg1", "block2", "icon2", "fill0", "stroke1", "font0", "ST0", "st０",
            "letter_G", "",
        ] {
            assert!(!is_generated_class(class), "{class}");
        }
    }

    #[test]
    fn invented_and_serial_names_look_generated_and_layer_names_do_not() {
        for tag in [
            "st0", "cls-2", "path", "rect", "text", "path1234", "g12", "layer1",
        ] {
            assert!(looks_generated(tag), "{tag}");
        }
        for tag in [
            "letter_G",
            "Wheel",
            "Layer_1",
            "layer",
            "Vector",
            "Ellipse 1",
            "icon-home",
            "node3",
            "a",
            "pathway",
        ] {
            assert!(!looks_generated(tag), "{tag}");
        }
    }

    #[test]
    fn every_tag_source_has_its_option_name() {
        let names: Vec<&str> = TagFrom::ALL.iter().map(|t| t.name()).collect();
        assert_eq!(names, ["auto", "data-tag", "class", "label", "layer"]);
    }
}
