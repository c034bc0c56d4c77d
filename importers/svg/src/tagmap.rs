//! Tag maps: tags and units given to a designer's file from outside it, with CSS-like
//! selectors, so an exported SVG need not be edited (and re-edited after every export).
//!
//! A tag map is a text file (`--tags FILE`, or the grammar's `tags` directive), one line
//! per entry, `#` starting a comment:
//!
//! ```text
//! #letter_*       -> letter unit   # every element whose id starts with `letter_`
//! .st1            -> outline       # class st1 (Illustrator's style classes)
//! g#Layer_1 > *   -> foreground    # the children of the group with id Layer_1
//! Layer_2/eyes    -> eyes          # a layer path: ids or Inkscape labels, outermost first
//! path[fill="#E30613"], circle -> red
//! g.icon          -> unit          # a unit, keeping the tag it has
//! ```
//!
//! Selectors: element names and `*`; `#id` and `.class`, where `*` in the name stands for
//! any run of characters; attributes `[a]`, `[a=v]`, `[a^=v]`, `[a$=v]`, `[a*=v]` (a
//! prefixed name such as `inkscape:label` matches that local name in any namespace);
//! descendant (space) and child (`>`) combinators; lists with `,`. A selector with a `/`
//! is a layer path: each step names a group by id (or id without its counter) or by
//! Inkscape label, each inside the one before, the last naming the element itself.
//!
//! After `->`: the tag (quoted if it has spaces or is the word `unit`), `unit`, or both. A
//! tag is the element's explicit tag, over `data-tag`, class and label (so a group given a
//! tag becomes one unit under `--units auto`, as with `data-tag`); `unit` makes the
//! element one unit under any `--units`. Where several lines match one element, the last
//! one wins, as later rules do in CSS.

use std::fmt;

use usvg::roxmltree::Node;

/// A parsed tag map.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TagMap {
    /// What the map was read from, for messages.
    pub source_name: String,
    entries: Vec<Entry>,
}

/// One line: selectors and what they give.
#[derive(Clone, Debug, PartialEq)]
struct Entry {
    selectors: Vec<Selector>,
    tag: Option<String>,
    unit: bool,
    line: usize,
}

/// What a tag map gives an element: a tag, unit-ness, or both.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Given {
    /// The tag, if a line gave one.
    pub tag: Option<String>,
    /// Whether a line made the element a unit.
    pub unit: bool,
}

/// A tag map that does not parse: where and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TagMapError {
    /// What the map was read from.
    pub source_name: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column (in characters).
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for TagMapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}",
            self.source_name, self.line, self.column, self.message
        )
    }
}

impl std::error::Error for TagMapError {}

/// A complex selector: compounds from the outermost, each with how it relates to the
/// one after it.
#[derive(Clone, Debug, PartialEq)]
struct Selector {
    /// `(compound, combinator to the next compound)`; the last one's combinator is unused.
    steps: Vec<(Compound, Combinator)>,
    /// As written, for messages.
    text: String,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Combinator {
    Descendant,
    Child,
}

/// A compound selector: all of its tests hold on one element.
#[derive(Clone, Debug, Default, PartialEq)]
struct Compound {
    /// Element name (`None` for `*` or none written).
    name: Option<String>,
    tests: Vec<Test>,
}

#[derive(Clone, Debug, PartialEq)]
enum Test {
    /// `#glob`: the id.
    Id(String),
    /// `.glob`: one of the classes.
    Class(String),
    /// `[prefix:name op value]`.
    Attr {
        prefixed: bool,
        name: String,
        op: AttrOp,
    },
    /// A layer path step: the id, the id without its counter, or the Inkscape label.
    Layer(String),
}

#[derive(Clone, Debug, PartialEq)]
enum AttrOp {
    Exists,
    Equals(String),
    Prefix(String),
    Suffix(String),
    Contains(String),
}

/// Whether `glob` (with `*` for any run of characters) matches `s` whole.
fn glob(glob: &str, s: &str) -> bool {
    gmotion::grammar::ast::tag_matches(glob, s)
}

impl TagMap {
    /// Parses a tag map; `source_name` names it in errors and warnings.
    ///
    /// ```
    /// use gmotion_import_svg::tagmap::TagMap;
    /// let map = TagMap::parse("#letter_* -> letter unit\n.st1 -> outline\n", "tags.txt").unwrap();
    /// assert_eq!(map.len(), 2);
    /// assert!(TagMap::parse("#a -> ", "tags.txt").is_err());
    /// ```
    pub fn parse(text: &str, source_name: &str) -> Result<TagMap, TagMapError> {
        let mut entries = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let err = |column: usize, message: String| TagMapError {
                source_name: source_name.to_string(),
                line,
                column,
                message,
            };
            let body = strip_comment(raw);
            if body.trim().is_empty() {
                continue;
            }
            let Some(arrow) = body.find("->") else {
                return Err(err(
                    body.len() - body.trim_start().len() + 1,
                    "expected `SELECTOR -> TAG` (a tag, `unit`, or both after the arrow)".into(),
                ));
            };
            let (sel_text, rest) = (&body[..arrow], &body[arrow + 2..]);
            let col_of = |sub: &str| {
                body[..sub.as_ptr() as usize - body.as_ptr() as usize]
                    .chars()
                    .count()
                    + 1
            };
            let mut selectors = Vec::new();
            for part in split_list(sel_text) {
                let trimmed = part.trim();
                let at = col_of(part) + (part.len() - part.trim_start().len());
                if trimmed.is_empty() {
                    return Err(err(at, "empty selector".into()));
                }
                let mut sel = if trimmed.contains('/') {
                    layer_path(trimmed).map_err(|(off, m)| err(at + off, m))?
                } else {
                    selector(trimmed).map_err(|(off, m)| err(at + off, m))?
                };
                sel.text = trimmed.to_string();
                selectors.push(sel);
            }
            let (tag, unit) = target(rest).map_err(|m| err(col_of(rest), m))?;
            entries.push(Entry {
                selectors,
                tag,
                unit,
                line,
            });
        }
        Ok(TagMap {
            source_name: source_name.to_string(),
            entries,
        })
    }

    /// Number of entries (lines with a selector).
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Number of selectors over all entries (a list counts each of its selectors): the
    /// size of the `matched` table [`TagMap::given`] fills.
    pub(crate) fn selectors(&self) -> usize {
        self.entries.iter().map(|e| e.selectors.len()).sum()
    }

    /// Whether the map has no entries.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// What the map gives `node` (the last matching line's tag, `unit` if any matching
    /// line says so), marking in `matched` which selectors matched (numbered over all
    /// entries, in order).
    pub(crate) fn given(&self, node: Node, matched: &mut [bool]) -> Option<Given> {
        let mut out: Option<Given> = None;
        let mut k = 0;
        for e in &self.entries {
            let mut hit = false;
            for s in &e.selectors {
                if s.matches(node) {
                    matched[k] = true;
                    hit = true;
                }
                k += 1;
            }
            if hit {
                let g = out.get_or_insert_with(Given::default);
                if e.tag.is_some() {
                    g.tag.clone_from(&e.tag);
                }
                g.unit |= e.unit;
            }
        }
        out
    }

    /// For selectors that matched nothing: a warning each, `(place, message)`.
    pub(crate) fn unmatched(&self, matched: &[bool]) -> Vec<(String, String)> {
        let all = (self.entries.iter()).flat_map(|e| e.selectors.iter().map(move |s| (e.line, s)));
        all.zip(matched)
            .filter(|(_, m)| !**m)
            .map(|((line, s), _)| {
                (
                    format!("{}:{line}", self.source_name),
                    format!("`{}` matches no element", s.text),
                )
            })
            .collect()
    }
}

/// The line without its comment. `#` also starts id selectors, so a comment is a `#`
/// followed by a space or ending the line (outside quotes and brackets), or any `#` after
/// the arrow.
fn strip_comment(line: &str) -> &str {
    for (i, c) in top_level(line) {
        if c == '#' {
            let next = line[i + 1..].chars().next();
            if next.is_none_or(char::is_whitespace) || line[..i].contains("->") {
                return &line[..i];
            }
        }
    }
    line
}

/// Splits a selector list at commas outside quotes and brackets.
fn split_list(text: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let mut start = 0;
    for (i, c) in top_level(text) {
        if c == ',' {
            parts.push(&text[start..i]);
            start = i + 1;
        }
    }
    parts.push(&text[start..]);
    parts
}

/// The characters of `text` outside quotes and attribute brackets, with their byte
/// offsets: where `#` and `,` mean something rather than being part of a value.
fn top_level(text: &str) -> impl Iterator<Item = (usize, char)> + '_ {
    let (mut quote, mut depth) = (None, 0usize);
    text.char_indices().filter(move |&(_, c)| {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '"' | '\'') => quote = Some(c),
            (None, '[') => depth += 1,
            (None, ']') => depth = depth.saturating_sub(1),
            (None, _) => return depth == 0,
        }
        false
    })
}

/// What follows the arrow: a tag, `unit`, or both.
fn target(text: &str) -> Result<(Option<String>, bool), String> {
    let mut tag = None;
    let mut unit = false;
    let mut rest = text.trim();
    while !rest.is_empty() {
        let (word, quoted, after) = if let Some(q) = rest.strip_prefix(['"', '\'']) {
            let close = rest.as_bytes()[0] as char;
            let end = q
                .find(close)
                .ok_or_else(|| format!("unclosed quote {close}"))?;
            (&q[..end], true, &q[end + 1..])
        } else {
            let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
            (&rest[..end], false, &rest[end..])
        };
        if word == "unit" && !quoted {
            unit = true;
        } else if tag.is_some() {
            return Err(format!(
                "`{word}`: one tag per line (write `unit` to make the element one unit)"
            ));
        } else if word.trim().is_empty() {
            return Err("empty tag".into());
        } else {
            tag = Some(word.to_string());
        }
        rest = after.trim_start();
    }
    if tag.is_none() && !unit {
        return Err("expected a tag, `unit`, or both after `->`".into());
    }
    Ok((tag, unit))
}

/// Parses a CSS-like complex selector; errors carry a byte offset into `text`.
fn selector(text: &str) -> Result<Selector, (usize, String)> {
    let mut steps: Vec<(Compound, Combinator)> = Vec::new();
    let b = text;
    let mut i = 0;
    let mut pending: Option<Combinator> = None;
    while i < b.len() {
        let c = b[i..].chars().next().expect("in bounds");
        if c.is_whitespace() {
            if !steps.is_empty() && pending.is_none() {
                pending = Some(Combinator::Descendant);
            }
            i += c.len_utf8();
            continue;
        }
        if c == '>' {
            if steps.is_empty() || pending == Some(Combinator::Child) {
                return Err((i, "`>` needs a selector on both sides".into()));
            }
            pending = Some(Combinator::Child);
            i += 1;
            continue;
        }
        if matches!(c, '+' | '~') {
            return Err((
                i,
                format!("the `{c}` combinator is not supported (use a space or `>`)"),
            ));
        }
        if !steps.is_empty() && pending.is_none() {
            return Err((i, format!("unexpected `{c}`")));
        }
        let (compound, used) = compound(&b[i..]).map_err(|(o, m)| (i + o, m))?;
        if let (Some(comb), Some(last)) = (pending.take(), steps.last_mut()) {
            last.1 = comb;
        }
        steps.push((compound, Combinator::Descendant));
        i += used;
    }
    if pending == Some(Combinator::Child) {
        return Err((b.len(), "`>` needs a selector on both sides".into()));
    }
    Ok(Selector {
        steps,
        text: String::new(),
    })
}

/// A name (`*` allowed as a glob) at the start of `s`: its length in bytes.
fn name_len(s: &str) -> usize {
    s.find(|c: char| !(c.is_alphanumeric() || matches!(c, '_' | '-' | '*')))
        .unwrap_or(s.len())
}

/// Parses one compound selector at the start of `s`: it and the bytes it used.
fn compound(s: &str) -> Result<(Compound, usize), (usize, String)> {
    let mut out = Compound::default();
    let mut i = 0;
    let n = name_len(s);
    if n > 0 {
        if s[..n] != *"*" {
            if s[..n].contains('*') {
                return Err((0, "element names take no `*` pattern".into()));
            }
            out.name = Some(s[..n].to_string());
        }
        i = n;
    }
    while let Some(c) = s[i..].chars().next() {
        match c {
            '#' | '.' => {
                let n = name_len(&s[i + 1..]);
                if n == 0 {
                    return Err((i, format!("expected a name after `{c}`")));
                }
                let name = s[i + 1..i + 1 + n].to_string();
                out.tests.push(if c == '#' {
                    Test::Id(name)
                } else {
                    Test::Class(name)
                });
                i += 1 + n;
            }
            '[' => {
                let close = s[i..]
                    .find(']')
                    .ok_or_else(|| (i, "unclosed `[`".to_string()))?;
                out.tests
                    .push(attribute(&s[i + 1..i + close]).map_err(|m| (i, m))?);
                i += close + 1;
            }
            ':' => {
                return Err((
                    i,
                    "pseudo-classes are not supported (use ids, classes, attributes, `>` and spaces)"
                        .into(),
                ));
            }
            c if c.is_whitespace() || c == '>' || c == '+' || c == '~' => break,
            c => return Err((i, format!("unexpected `{c}` in a selector"))),
        }
    }
    if i == 0 {
        return Err((0, "expected a selector".into()));
    }
    Ok((out, i))
}

/// Parses the inside of `[...]`.
fn attribute(inner: &str) -> Result<Test, String> {
    let ops = ["^=", "$=", "*=", "="];
    let (name, op) = match ops.iter().find_map(|op| inner.find(op).map(|at| (at, *op))) {
        None => (inner.trim(), AttrOp::Exists),
        Some((at, op)) => {
            let value = inner[at + op.len()..].trim();
            let value = value
                .strip_prefix('"')
                .and_then(|v| v.strip_suffix('"'))
                .or_else(|| value.strip_prefix('\'').and_then(|v| v.strip_suffix('\'')))
                .unwrap_or(value)
                .to_string();
            let name = inner[..at].trim();
            (
                name,
                match op {
                    "^=" => AttrOp::Prefix(value),
                    "$=" => AttrOp::Suffix(value),
                    "*=" => AttrOp::Contains(value),
                    _ => AttrOp::Equals(value),
                },
            )
        }
    };
    let (prefixed, local) = match name.rsplit_once([':', '|']) {
        Some((_, local)) => (true, local),
        None => (false, name),
    };
    if local.is_empty()
        || !local
            .chars()
            .all(|c| c.is_alphanumeric() || c == '-' || c == '_')
    {
        return Err(format!("`[{inner}]`: expected an attribute name"));
    }
    Ok(Test::Attr {
        prefixed,
        name: local.to_string(),
        op,
    })
}

/// Parses a layer path `Layer_1/eyes/left`.
fn layer_path(text: &str) -> Result<Selector, (usize, String)> {
    let mut steps = Vec::new();
    let mut at = 0;
    for part in text.split('/') {
        let name = part.trim();
        if name.is_empty() {
            return Err((at, "empty step in a layer path".into()));
        }
        // `*` alone is any element (`Layer_1/*`: everything in the layer).
        let tests = if name == "*" {
            Vec::new()
        } else {
            vec![Test::Layer(name.to_string())]
        };
        steps.push((Compound { name: None, tests }, Combinator::Descendant));
        at += part.len() + 1;
    }
    Ok(Selector {
        steps,
        text: String::new(),
    })
}

impl Selector {
    fn matches(&self, node: Node) -> bool {
        match self.steps.split_last() {
            Some(((last, _), rest)) => last.matches(node) && matches_up(rest, node),
            None => false,
        }
    }
}

/// Whether the compounds `outer` (outermost first) match above `node`.
fn matches_up(outer: &[(Compound, Combinator)], node: Node) -> bool {
    let Some(((compound, comb), rest)) = outer.split_last() else {
        return true;
    };
    let mut up = node.parent_element();
    while let Some(a) = up {
        if compound.matches(a) && matches_up(rest, a) {
            return true;
        }
        if *comb == Combinator::Child {
            return false;
        }
        up = a.parent_element();
    }
    false
}

impl Compound {
    fn matches(&self, node: Node) -> bool {
        if !node.is_element() {
            return false;
        }
        if let Some(name) = &self.name
            && node.tag_name().name() != name
        {
            return false;
        }
        self.tests.iter().all(|t| t.matches(node))
    }
}

impl Test {
    fn matches(&self, node: Node) -> bool {
        match self {
            Test::Id(g) => node.attribute("id").is_some_and(|id| glob(g, id)),
            Test::Class(g) => node
                .attribute("class")
                .is_some_and(|c| c.split_ascii_whitespace().any(|c| glob(g, c))),
            Test::Attr { prefixed, name, op } => node
                .attributes()
                .filter(|a| a.name() == name && a.namespace().is_some() == *prefixed)
                .any(|a| {
                    let v = a.value();
                    match op {
                        AttrOp::Exists => true,
                        AttrOp::Equals(x) => v == x,
                        AttrOp::Prefix(x) => v.starts_with(x.as_str()),
                        AttrOp::Suffix(x) => v.ends_with(x.as_str()),
                        AttrOp::Contains(x) => v.contains(x.as_str()),
                    }
                }),
            Test::Layer(g) => {
                let id = node.attribute("id");
                let label = node
                    .attributes()
                    .find(|a| a.name() == "label" && a.namespace().is_some())
                    .map(|a| a.value());
                id.is_some_and(|id| glob(g, id) || glob(g, gmotion::tagging::strip_counter(id)))
                    || label.is_some_and(|l| glob(g, l.trim()))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use usvg::roxmltree::Document;

    const SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape">
<g id="Layer_1"><rect id="letter_a" class="st0 big"/><g id="eyes_2_"><circle id="left"/></g></g>
<g inkscape:label="Top layer" inkscape:groupmode="layer"><path fill="#E30613" class="st1"/></g>
</svg>"##;

    /// The ids (or element names) of the elements `selector` matches.
    fn matching(selector: &str) -> Vec<String> {
        let map = TagMap::parse(&format!("{selector} -> x"), "t").unwrap();
        let doc = Document::parse(SVG).unwrap();
        let mut seen = vec![false; map.selectors()];
        doc.descendants()
            .filter(|n| map.given(*n, &mut seen).is_some())
            .map(|n| n.attribute("id").unwrap_or(n.tag_name().name()).to_string())
            .collect()
    }

    #[test]
    fn selectors_match_as_css_does() {
        assert_eq!(matching("#letter_*"), ["letter_a"]);
        assert_eq!(matching(".big"), ["letter_a"]);
        assert_eq!(matching(".st*"), ["letter_a", "path"]);
        assert_eq!(matching("g#Layer_1 > *"), ["letter_a", "eyes_2_"]);
        assert_eq!(matching("#Layer_1 circle"), ["left"]);
        assert_eq!(matching("#Layer_1 > circle"), Vec::<String>::new());
        assert_eq!(matching(r##"path[fill="#E30613"]"##), ["path"]);
        assert_eq!(matching("[inkscape:groupmode=layer] > *"), ["path"]);
        assert_eq!(matching("rect, circle"), ["letter_a", "left"]);
    }

    #[test]
    fn layer_paths_use_ids_counters_and_labels() {
        assert_eq!(matching("Layer_1/eyes/left"), ["left"]);
        assert_eq!(matching("Layer_1/eyes"), ["eyes_2_"]);
        assert_eq!(matching("Top layer/*"), ["path"]);
    }

    #[test]
    fn the_last_line_wins_and_unit_adds_up() {
        let map = TagMap::parse("rect -> a unit\n.st0 -> b\n#nothing -> c\n", "t").unwrap();
        let doc = Document::parse(SVG).unwrap();
        let rect = doc.descendants().find(|n| n.has_tag_name("rect")).unwrap();
        let mut seen = vec![false; 3];
        let given = map.given(rect, &mut seen).unwrap();
        assert_eq!(given.tag.as_deref(), Some("b"));
        assert!(given.unit);
        assert_eq!(map.unmatched(&seen).len(), 1);
    }

    #[test]
    fn errors_say_where() {
        let e = TagMap::parse("# tags\n\n#a > > b -> x\n", "t.txt").unwrap_err();
        assert_eq!((e.line, e.column), (3, 6), "{e}");
        let e = TagMap::parse(".a:hover -> x", "t.txt").unwrap_err();
        assert_eq!((e.line, e.column), (1, 3), "{e}");
        let e = TagMap::parse("#a b", "t.txt").unwrap_err();
        assert!(e.message.contains("->"), "{e}");
        let e = TagMap::parse("#a -> one two", "t.txt").unwrap_err();
        assert!(e.message.contains("one tag"), "{e}");
        assert!(TagMap::parse("#a -> \"unit\"  # a tag named unit", "t").is_ok());
        assert!(TagMap::parse("a + b -> x", "t").is_err());
    }
}
