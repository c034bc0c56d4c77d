//! The source document as the designer wrote it: element lookup, synthetic ids and tags.
//!
//! usvg keeps only `id` attributes, so every element that can become a usvg node and has
//! no usable id gets a synthetic one before usvg sees the text. Afterwards any usvg node
//! leads back to its source element, where `data-tag`, `class` and `inkscape:label` are
//! still there to read.

use std::collections::{HashMap, HashSet};

use usvg::roxmltree::{self, Document, Node, NodeId};

use super::{ImportError, Policy};
use crate::tagmap::{Given, TagMap};
use crate::tags::{TagFrom, first_class, first_named_class, strip_counter_among};

const SVG_NS: &str = "http://www.w3.org/2000/svg";
const XLINK_NS: &str = "http://www.w3.org/1999/xlink";
const INKSCAPE_NS: &str = "http://www.inkscape.org/namespaces/inkscape";

/// The document [`Source::aside`] holds while the source's is set aside.
const PLACEHOLDER: &str = "<svg xmlns=\"http://www.w3.org/2000/svg\"/>";

/// Elements usvg turns into nodes that carry their id.
const MAPPED: &[&str] = &[
    "g", "a", "use", "svg", "switch", "path", "rect", "circle", "ellipse", "line", "polyline",
    "polygon", "text", "image",
];

/// Basic shapes: the elements a `use` instance's paths can come from.
const SHAPES: &[&str] = &[
    "path", "rect", "circle", "ellipse", "line", "polyline", "polygon",
];

/// Containers a shape inside a referenced element can sit in and still be drawn.
const TRANSPARENT_CONTAINERS: &[&str] = &["g", "a", "symbol", "svg"];

/// The parsed source plus the text prepared for usvg.
pub(super) struct Source<'a> {
    pub doc: Document<'a>,
    /// The source text with synthetic ids inserted (borrowed when none were needed).
    pub prepared: std::borrow::Cow<'a, str>,
    /// Whether the document has `<text>` (usvg then needs fonts).
    pub has_text: bool,
    /// References cut to break cycles ([`href_cycles`]), as `(place, message)` warnings.
    pub unlinked: Vec<(String, String)>,
    /// The source text and the node limit it was parsed under, to parse it again
    /// ([`Source::aside`]).
    text: &'a str,
    max_nodes: u32,
    prefix: String,
    synthetic: Vec<NodeId>,
    by_id: HashMap<String, NodeId>,
    /// The names the ids with Illustrator's or CorelDRAW's escapes spell
    /// ([`gmotion::tagging::unescape_id`]), by element.
    unescaped: HashMap<NodeId, String>,
    /// What a tag map gives elements ([`Source::apply`]).
    given: HashMap<NodeId, Given>,
    /// The ancestors of the elements a tag map made units ([`Source::holds_forced_unit`]).
    forced_within: HashSet<NodeId>,
}

/// The tag sources seen on the way from the root to a node (nearest wins).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Scope<'a> {
    /// Nearest explicit tag (`data-tag`, class or label, as `TagFrom` selects).
    explicit: Option<&'a str>,
    /// Nearest layer name (a `<g>` id without its counter).
    layer: Option<&'a str>,
    /// The source element this scope was last extended with.
    elem: Option<NodeId>,
}

impl<'a> Scope<'a> {
    /// The source element this scope was last extended with (for a `use` instance's
    /// shapes, the `use`).
    pub fn elem(&self) -> Option<NodeId> {
        self.elem
    }

    /// The tag: the explicit one, else the layer name, else `name`.
    pub fn tag<'b>(&self, name: &'b str) -> &'b str
    where
        'a: 'b,
    {
        self.explicit.or(self.layer).unwrap_or(name)
    }
}

fn is_svg(node: Node) -> bool {
    node.is_element() && matches!(node.tag_name().namespace(), None | Some(SVG_NS))
}

fn named(node: Node, names: &[&str]) -> bool {
    is_svg(node) && names.contains(&node.tag_name().name())
}

/// Refuses a document whose XML entities would expand to more than `limit` bytes in
/// total (a "billion laughs" or a quadratic blow-up): the XML parser expands every
/// reference and has no such limit. Entities are read from the internal DTD subset;
/// each reference in the document counts its entity's full expansion.
pub(super) fn check_entities(text: &str, source_name: &str, limit: u64) -> Result<(), ImportError> {
    let Some(doctype) = text.find("<!DOCTYPE") else {
        return Ok(());
    };
    let (Some(open), Some(close)) = (
        text[doctype..].find('[').map(|i| doctype + i),
        text[doctype..].find("]>").map(|i| doctype + i),
    ) else {
        return Ok(());
    };
    if open > close {
        return Ok(());
    }
    let subset = &text[open + 1..close];
    let mut values: HashMap<&str, &str> = HashMap::new();
    let mut rest = subset;
    while let Some(i) = rest.find("<!ENTITY") {
        rest = &rest[i + 8..];
        let decl = rest.trim_start();
        if decl.starts_with('%') {
            continue;
        }
        let name_end = decl.find(|c: char| c.is_whitespace()).unwrap_or(decl.len());
        let name = &decl[..name_end];
        let after = decl[name_end..].trim_start();
        let Some(q) = after.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            continue;
        };
        let Some(end) = after[1..].find(q) else {
            continue;
        };
        values.entry(name).or_insert(&after[1..1 + end]);
    }
    if values.is_empty() {
        return Ok(());
    }
    // Expanded sizes, deepest first; a loop or a depth past roxmltree's ten levels is the
    // parser's error to report, so it counts as infinite here only past the limit.
    fn size<'t>(
        name: &str,
        values: &HashMap<&'t str, &'t str>,
        memo: &mut HashMap<String, u64>,
        depth: u32,
    ) -> u64 {
        if let Some(&n) = memo.get(name) {
            return n;
        }
        let Some(value) = values.get(name) else {
            return name.len() as u64 + 2;
        };
        if depth > 16 {
            return u64::MAX;
        }
        let mut total = 0u64;
        let mut rest = *value;
        while let Some(i) = rest.find('&') {
            total = total.saturating_add(i as u64);
            rest = &rest[i + 1..];
            match rest.find(';') {
                Some(j) if !rest[..j].starts_with('#') => {
                    total = total.saturating_add(size(&rest[..j], values, memo, depth + 1));
                    rest = &rest[j + 1..];
                }
                _ => total = total.saturating_add(1),
            }
        }
        total = total.saturating_add(rest.len() as u64);
        memo.insert(name.to_string(), total);
        total
    }
    let mut memo = HashMap::new();
    let body = &text[close + 2..];
    let mut total = 0u64;
    let mut rest = body;
    while let Some(i) = rest.find('&') {
        rest = &rest[i + 1..];
        if let Some(j) = rest.find(';')
            && values.contains_key(&rest[..j])
        {
            total = total.saturating_add(size(&rest[..j], &values, &mut memo, 0));
            if total > limit {
                let at = text.len() - rest.len() - 1;
                let pos = text[..at].matches('\n').count() + 1;
                let col = at - text[..at].rfind('\n').map_or(0, |k| k + 1) + 1;
                return Err(ImportError::Encoding {
                    source_name: source_name.to_string(),
                    message: format!(
                        "{pos}:{col}: XML entities expand to more than the limit of {limit} bytes here (`&{};`; raise it with --limit xml-entity-bytes=N)",
                        &rest[..j]
                    ),
                });
            }
            rest = &rest[j + 1..];
        }
    }
    Ok(())
}

/// Turns a roxmltree error into one that names the file, line and column.
fn xml_error(e: roxmltree::Error, source_name: &str) -> ImportError {
    let pos = e.pos();
    let message = e.to_string().replacen(&format!(" at {pos}"), "", 1);
    ImportError::Xml {
        source_name: source_name.to_string(),
        line: pos.row,
        column: pos.col,
        message,
    }
}

/// Parses the source text with the same options usvg uses, so both parses see the same
/// document, with a limit on the number of nodes.
fn parse_document<'a>(
    text: &'a str,
    source_name: &str,
    max_nodes: u32,
) -> Result<Document<'a>, ImportError> {
    let opt = roxmltree::ParsingOptions {
        allow_dtd: true,
        nodes_limit: max_nodes,
        ..Default::default()
    };
    Document::parse_with_options(text, opt).map_err(|e| match e {
        roxmltree::Error::NodesLimitReached => ImportError::Encoding {
            source_name: source_name.to_string(),
            message: format!(
                "the document has more than the limit of {max_nodes} XML nodes, counting its elements, the text between them (whitespace too) and its comments (raise it with --limit xml-nodes=N)"
            ),
        },
        e => xml_error(e, source_name),
    })
}

/// How deep usvg follows nested elements: it refuses an element below more than this many
/// (`usvg::parser::svgtree::parse`, a fixed bound against its recursion overflowing).
const USVG_MAX_DEPTH: usize = 1024;

/// usvg's element limit: it refuses a document whose own tree (every SVG element, each
/// `<use>` once more with a copy of what it references, the root) grows past this many
/// nodes (`usvg::parser::svgtree::parse`, a fixed bound no option raises).
pub(super) const USVG_MAX_ELEMENTS: usize = 1_000_000;

/// A document refused at `node`: `why`, after the node's line and column.
fn refused_at(doc: &Document, node: roxmltree::Node, source_name: &str, why: &str) -> ImportError {
    let pos = doc.text_pos_at(node.range().start);
    ImportError::Encoding {
        source_name: source_name.to_string(),
        message: format!("{}:{}: {why}", pos.row, pos.col),
    }
}

/// Refuses a `<text>` with more characters or more elements inside it than the policy
/// allows. usvg lays a text out in time that grows with its spans times its characters
/// (measured: 1 000 `<tspan>`s of 10 characters 3 s, 4 000 of them 42 s; one span of
/// 30 000 characters 2.3 s, 60 000 6.6 s), so both are counted before it sees them.
fn check_texts(doc: &Document, source_name: &str, policy: &Policy) -> Result<(), ImportError> {
    for text in doc
        .descendants()
        .filter(|n| n.has_tag_name((SVG_NS, "text")))
    {
        let mut chars = 0u64;
        let mut spans = 0u64;
        for n in text.descendants().skip(1) {
            if n.is_text() {
                chars += n.text().map_or(0, |t| t.chars().count()) as u64;
            } else if n.is_element() {
                spans += 1;
            }
        }
        let over = if chars > policy.max_text_chars {
            Some(format!(
                "the text has {chars} characters, more than the limit of {} (raise it with --limit text-chars=N)",
                policy.max_text_chars
            ))
        } else if spans > policy.max_text_spans {
            Some(format!(
                "the text has {spans} elements inside it (`<tspan>`, `<a>`, …), more than the limit of {} (raise it with --limit text-spans=N)",
                policy.max_text_spans
            ))
        } else {
            None
        };
        if let Some(why) = over {
            return Err(refused_at(doc, text, source_name, &why));
        }
    }
    Ok(())
}

/// The most element moves that splitting arcs into curves may cost a document (see
/// [`ArcCost`]): about a second of copying.
const MAX_ARC_MOVES: f64 = 3e8;

/// What the arcs of path data cost usvg's path parser (svgtypes' `SimplifyingPathParser`):
/// it cuts an arc into cubics, as many as kurbo's error bound asks of its radius
/// (`(11.2 · r)^⅙` a turn at a tolerance of 0.1), buffers them and takes them from the
/// front of a vector, so an arc cut into `n` curves costs `n²/2` moves. An arc of radius
/// 10³⁷ (or one whose end lies that far away) is two million curves: hours.
#[derive(Debug, Default)]
struct ArcCost {
    /// Element moves so far, all arcs together.
    moves: f64,
    /// The last arc's radius (its own, or half its chord when that is longer, as the arc is
    /// then widened to reach its end) and curve count.
    radius: f64,
    curves: f64,
}

impl ArcCost {
    /// Adds the arcs of path data `d`; answers its segment count, each arc counted as the
    /// curves it becomes.
    fn add(&mut self, d: &str) -> u64 {
        use svgtypes::PathSegment as S;
        let (mut at, mut start) = ((0.0f64, 0.0f64), (0.0f64, 0.0f64));
        let mut segments = 0u64;
        for seg in svgtypes::PathParser::from(d).flatten() {
            let to = |abs: bool, x: f64, y: f64| if abs { (x, y) } else { (at.0 + x, at.1 + y) };
            let end = match seg {
                S::MoveTo { abs, x, y } => {
                    start = to(abs, x, y);
                    start
                }
                S::LineTo { abs, x, y }
                | S::SmoothQuadratic { abs, x, y }
                | S::CurveTo { abs, x, y, .. }
                | S::SmoothCurveTo { abs, x, y, .. }
                | S::Quadratic { abs, x, y, .. } => to(abs, x, y),
                S::HorizontalLineTo { abs, x } => (if abs { x } else { at.0 + x }, at.1),
                S::VerticalLineTo { abs, y } => (at.0, if abs { y } else { at.1 + y }),
                S::ClosePath { .. } => start,
                S::EllipticalArc {
                    abs, rx, ry, x, y, ..
                } => {
                    let end = to(abs, x, y);
                    let chord = (end.0 - at.0).hypot(end.1 - at.1);
                    let r = rx.abs().max(ry.abs()).max(chord / 2.0);
                    let n = (11.163 * r).powf(1.0 / 6.0).max(4.0).ceil();
                    let n = if n.is_finite() { n } else { f64::MAX };
                    self.moves += n * n / 2.0;
                    self.radius = r;
                    self.curves = n;
                    segments = segments.saturating_add(n.min(u64::MAX as f64) as u64);
                    at = end;
                    continue;
                }
            };
            segments += 1;
            at = end;
        }
        segments
    }
}

/// The elements usvg's tree keeps (its `EId` names); it drops others with their ids.
const USVG_ELEMENTS: &[&str] = &[
    "a",
    "circle",
    "clipPath",
    "defs",
    "ellipse",
    "feBlend",
    "feColorMatrix",
    "feComponentTransfer",
    "feComposite",
    "feConvolveMatrix",
    "feDiffuseLighting",
    "feDisplacementMap",
    "feDistantLight",
    "feDropShadow",
    "feFlood",
    "feFuncA",
    "feFuncB",
    "feFuncG",
    "feFuncR",
    "feGaussianBlur",
    "feImage",
    "feMerge",
    "feMergeNode",
    "feMorphology",
    "feOffset",
    "fePointLight",
    "feSpecularLighting",
    "feSpotLight",
    "feTile",
    "feTurbulence",
    "filter",
    "g",
    "image",
    "line",
    "linearGradient",
    "marker",
    "mask",
    "path",
    "pattern",
    "polygon",
    "polyline",
    "radialGradient",
    "rect",
    "stop",
    "style",
    "svg",
    "switch",
    "symbol",
    "text",
    "textPath",
    "tref",
    "tspan",
    "use",
];

/// An edit of the text usvg reads.
enum Edit {
    /// Give the element an id of its own (a synthetic one, or one replacing a duplicate).
    Id(NodeId),
    /// Point the href whose value this is at nothing.
    Unlink,
}

/// Rings of `href` references between gradients, patterns and filters that another such
/// element links into, each as the element whose reference closes the ring (the one
/// pointing back at where the first outside link enters it) and the ids around it. usvg
/// follows a ring for ever when it enters from outside (found by the `svg` fuzz target:
/// `lg4 → lg1 → lg2 → lg1 …`), and stops when it comes back to where it started; cutting
/// that one reference keeps both walks as usvg and browsers make them (a ring nothing
/// enters is left as it is).
fn href_cycles(doc: &Document) -> Vec<(NodeId, Vec<String>)> {
    let linking = |n: &Node| {
        n.is_element()
            && is_svg(*n)
            && matches!(
                n.tag_name().name(),
                "linearGradient" | "radialGradient" | "pattern" | "filter"
            )
    };
    // An id names the last element of a kind usvg knows that has it, as in usvg's tree
    // (found by the `svg` fuzz target: an unknown `<radialGradientQ id="rg3">` first).
    let mut by_id: HashMap<&str, Node> = HashMap::new();
    for n in doc
        .descendants()
        .filter(|n| n.is_element() && is_svg(*n) && USVG_ELEMENTS.contains(&n.tag_name().name()))
    {
        if let Some(id) = n.attribute("id") {
            by_id.insert(id, n);
        }
    }
    let target = |n: &Node| -> Option<Node> {
        let href = n
            .attributes()
            .find(|a| a.name() == "href" && a.namespace().is_none_or(|ns| ns == XLINK_NS))?;
        let t = *by_id.get(href.value().trim().strip_prefix('#')?)?;
        linking(&t).then_some(t)
    };
    // Each element links at most one other: walk from each, marking the walk, until it
    // ends, meets an earlier walk, or meets itself (a ring).
    let mut state: HashMap<NodeId, u8> = HashMap::new(); // 1 on this walk, 2 done
    let mut rings: Vec<Vec<Node>> = Vec::new();
    for start in doc.descendants().filter(linking) {
        let mut walk = Vec::new();
        let mut at = Some(start);
        while let Some(n) = at {
            match state.get(&n.id()) {
                Some(2) => break,
                Some(_) => {
                    let from = walk
                        .iter()
                        .position(|w: &Node| w.id() == n.id())
                        .unwrap_or(0);
                    rings.push(walk[from..].to_vec());
                    break;
                }
                None => {
                    state.insert(n.id(), 1);
                    walk.push(n);
                    at = target(&n);
                }
            }
        }
        for w in walk {
            state.insert(w.id(), 2);
        }
    }
    let mut out = Vec::new();
    for ring in rings {
        let inside = |n: &Node| ring.iter().any(|r| r.id() == n.id());
        let entry = doc
            .descendants()
            .filter(|n| linking(n) && !inside(n))
            .find_map(|n| target(&n).filter(inside));
        let Some(entry) = entry else {
            continue;
        };
        let Some(at) = ring.iter().position(|r| r.id() == entry.id()) else {
            continue;
        };
        let closing = ring[(at + ring.len() - 1) % ring.len()];
        let ids = (0..=ring.len())
            .map(|k| {
                ring[(at + k) % ring.len()]
                    .attribute("id")
                    .unwrap_or_default()
                    .to_string()
            })
            .collect();
        out.push((closing.id(), ids));
    }
    out
}

impl<'a> Source<'a> {
    /// Parses `text` and prepares the copy usvg will read.
    pub fn parse(
        text: &'a str,
        source_name: &str,
        policy: &Policy,
    ) -> Result<Source<'a>, ImportError> {
        let (max_nodes, max_css_rules, max_segments) = (
            policy.max_xml_nodes,
            policy.max_css_rules,
            policy.max_path_segments,
        );
        let doc = parse_document(text, source_name, max_nodes)?;
        let root = doc.root_element();
        if !(is_svg(root) && root.tag_name().name() == "svg") {
            return Err(ImportError::NotSvg {
                source_name: source_name.to_string(),
                found: root.tag_name().name().to_string(),
            });
        }

        // usvg's style resolution is quadratic in the number of CSS rules (20 000 rules
        // take 1.7 s, 200 000 over a minute): counted before it sees them.
        let mut rules = 0usize;
        for style in doc
            .descendants()
            .filter(|n| n.has_tag_name((SVG_NS, "style")))
        {
            // Text nodes only: an element's `text()` is its first child's, which counted
            // each rule twice (the limit was reached at half its rules).
            rules += style
                .descendants()
                .filter(|t| t.is_text())
                .filter_map(|t| t.text())
                .map(|t| t.matches('{').count())
                .sum::<usize>();
            if rules > max_css_rules as usize {
                return Err(refused_at(
                    &doc,
                    style,
                    source_name,
                    &format!(
                        "the `<style>` elements so far hold {rules} CSS rules (counted by their `{{`), more than the limit of {max_css_rules} (raise it with --limit css-rules=N)"
                    ),
                ));
            }
        }

        // Path data: usvg builds every segment (and each `<use>` of it) in memory; counted
        // first, so a document of tens of millions is refused at the element that passes
        // the limit, not after seconds and gigabytes.
        let mut segments = 0u64;
        let mut arcs = ArcCost::default();
        for node in doc.descendants().filter(|n| n.is_element()) {
            if let Some(d) = node.attribute("d") {
                segments += arcs.add(d);
                if arcs.moves > MAX_ARC_MOVES {
                    return Err(refused_at(
                        &doc,
                        node,
                        source_name,
                        &format!(
                            "an arc of radius {:.3e} is too large to draw: it is cut into {} curves, and arcs that size make usvg's path parser take minutes",
                            arcs.radius, arcs.curves
                        ),
                    ));
                }
            }
            if let Some(p) = node.attribute("points") {
                segments += svgtypes::PointsParser::from(p).count() as u64;
            }
            if segments > max_segments {
                return Err(refused_at(
                    &doc,
                    node,
                    source_name,
                    &format!(
                        "the paths so far have {segments} segments (commands of `d`, points of `points`), more than the limit of {max_segments} (raise it with --limit path-segments=N)"
                    ),
                ));
            }
        }

        check_texts(&doc, source_name, policy)?;

        let cycles = href_cycles(&doc);

        let mut by_id = HashMap::new();
        let mut ids: HashSet<&str> = HashSet::new();
        for node in doc.descendants().filter(|n| n.is_element()) {
            if let Some(id) = node.attribute("id") {
                ids.insert(id);
            }
        }
        let mut prefix = String::from("__gm");
        while ids.iter().any(|id| id.starts_with(prefix.as_str())) {
            prefix.push('_');
        }

        // (byte range to replace, node): an empty range inserts a new attribute.
        let mut edits: Vec<(std::ops::Range<usize>, Edit)> = Vec::new();
        for (node, _) in &cycles {
            if let Some(href) = doc.get_node(*node).and_then(|n| {
                n.attributes()
                    .find(|a| a.name() == "href" && a.namespace().is_none_or(|ns| ns == XLINK_NS))
            }) {
                edits.push((href.range_value(), Edit::Unlink));
            }
        }
        let mut has_text = false;
        for node in doc.descendants().filter(|n| named(*n, MAPPED)) {
            has_text |= node.tag_name().name() == "text";
            if node == root {
                continue;
            }
            let own = node
                .attributes()
                .find(|a| a.name() == "id" && a.namespace().is_none());
            match own {
                Some(a) if !by_id.contains_key(a.value()) => {
                    by_id.insert(a.value().to_string(), node.id());
                }
                // usvg resolves a duplicated id to its first element, so renaming a later
                // one changes no reference and lets it be told apart.
                Some(a) => edits.push((a.range_value(), Edit::Id(node.id()))),
                None => {
                    let start = node.range().start + 1;
                    let name_len = text[start..]
                        .find(|c: char| c.is_ascii_whitespace() || c == '/' || c == '>')
                        .unwrap_or(0);
                    let at = start + name_len;
                    edits.push((at..at, Edit::Id(node.id())));
                }
            }
        }

        // Elements an entity expands to have their source range in the DTD (once for all
        // their copies): only edits inside the root element's own text are made, each
        // range once (found by the `svg` fuzz target: an entity of two elements, used
        // twice, made overlapping edits).
        let body = root.range();
        edits.retain(|(range, _)| body.start <= range.start && range.end <= body.end);
        edits.sort_by_key(|(range, _)| range.start);
        let (mut free_from, mut last_insert) = (0, None);
        edits.retain(|(range, _)| {
            let fresh = range.start >= free_from && last_insert != Some(range.start);
            if fresh {
                free_from = range.end;
                if range.is_empty() {
                    last_insert = Some(range.start);
                }
            }
            fresh
        });
        let mut synthetic = Vec::with_capacity(edits.len());
        let prepared = if edits.is_empty() {
            std::borrow::Cow::Borrowed(text)
        } else {
            let mut out = String::with_capacity(text.len() + edits.len() * 16);
            let mut last = 0;
            for (range, edit) in edits {
                out.push_str(&text[last..range.start]);
                let node = match edit {
                    Edit::Id(node) => node,
                    Edit::Unlink => {
                        // A reference to an id nothing has: usvg stops following there.
                        out.push_str(&format!("#{prefix}unlinked"));
                        last = range.end;
                        continue;
                    }
                };
                let n = synthetic.len();
                synthetic.push(node);
                if range.is_empty() {
                    out.push_str(&format!(" id=\"{prefix}{n}\""));
                } else {
                    out.push_str(&format!("{prefix}{n}"));
                }
                last = range.end;
            }
            out.push_str(&text[last..]);
            std::borrow::Cow::Owned(out)
        };
        let unlinked = cycles
            .iter()
            .filter_map(|(node, ring)| {
                let n = doc.get_node(*node)?;
                let line = doc.text_pos_at(n.range().start).row;
                let name = n.tag_name().name();
                let id = n.attribute("id").unwrap_or_default();
                Some((
                    format!("<{name} id=\"{id}\"> (line {line})"),
                    format!(
                        "its href closes a cycle of references ({}); not followed",
                        ring.join(" → ")
                    ),
                ))
            })
            .collect();
        Ok(Source {
            doc,
            text,
            max_nodes,
            prepared,
            unlinked,
            has_text,
            prefix,
            synthetic,
            unescaped: by_id
                .iter()
                .filter_map(|(id, &node)| Some((node, gmotion::tagging::unescape_id(id)?)))
                .collect(),
            by_id,
            given: HashMap::new(),
            forced_within: HashSet::new(),
        })
    }

    /// Runs `f` (usvg's parse) on the prepared text with the source document set aside,
    /// then parses the source again. usvg parses the text into a document of its own and
    /// builds its own tree from that before its tree; this document beside them all was
    /// the import's peak (each document about 600 bytes a shape: 1.2 GB of the 2.2 GB at
    /// 999 000 shapes). The same text under the same options parses to the same nodes, so
    /// every [`NodeId`] held stays valid.
    pub fn aside<T>(
        &mut self,
        source_name: &str,
        f: impl FnOnce(&str) -> T,
    ) -> Result<T, ImportError> {
        let placeholder = Document::parse(PLACEHOLDER).map_err(|e| xml_error(e, source_name))?;
        drop(std::mem::replace(&mut self.doc, placeholder));
        let out = f(&self.prepared);
        self.doc = parse_document(self.text, source_name, self.max_nodes)?;
        Ok(out)
    }

    /// Gives elements the tags and units `map` assigns; returns a warning for each of its
    /// lines that matched nothing, as `(place, message)`.
    pub fn apply(&mut self, map: &TagMap) -> Vec<(String, String)> {
        let mut matched = vec![false; map.selectors()];
        for node in self.doc.descendants().filter(|n| is_svg(*n)) {
            if let Some(given) = map.given(node, &mut matched) {
                if given.unit {
                    let above = node.ancestors().skip(1).filter(|n| n.is_element());
                    self.forced_within.extend(above.map(|n| n.id()));
                }
                self.given.insert(node.id(), given);
            }
        }
        map.unmatched(&matched)
    }

    /// Whether a tag map made an element inside `node` a unit: then `node` is no unit by
    /// the `--units` rules, so that the element inside can be one (units never nest, and
    /// the map's `unit` holds whatever `--units` says).
    pub fn holds_forced_unit(&self, node: Node) -> bool {
        self.forced_within.contains(&node.id())
    }

    /// Whether a tag map made `node` a unit.
    pub fn forced_unit(&self, node: Node) -> bool {
        self.given.get(&node.id()).is_some_and(|g| g.unit)
    }

    /// How deep `node` sits: 1 for a child of the root `<svg>`, 2 inside that, and so on.
    pub fn depth(node: Node) -> usize {
        node.ancestors().skip(1).filter(|n| n.is_element()).count()
    }

    /// The refusal of a document whose elements nest deeper than usvg follows, located at
    /// the first element past that depth, or `None` when none does. usvg refuses such a
    /// document with the same error as one past its million elements, naming no place, so
    /// this is asked only after usvg refused one: 100 000 nested `<g>`s are then reported
    /// at the group where usvg stopped, not as a million elements the file does not hold.
    pub fn too_deep(&self, source_name: &str) -> Option<ImportError> {
        // The `<svg>` sits at depth 0 (usvg starts below the document's root node), here
        // counted 1. Each element's depth is its parent's plus one, in document order:
        // linear, where `ancestors()` for every element would be quadratic in the depth.
        let mut depths = vec![0usize; self.doc.descendants().len()];
        let deep = self.doc.descendants().find(|n| {
            let depth = n.parent().map_or(0, |p| depths[p.id().get() as usize])
                + usize::from(n.is_element());
            depths[n.id().get() as usize] = depth;
            depth > USVG_MAX_DEPTH + 1
        })?;
        Some(refused_at(
            &self.doc,
            deep,
            source_name,
            &format!(
                "elements nest more than {USVG_MAX_DEPTH} deep here (`<{}>`): usvg's fixed limit, which no `--limit` raises",
                deep.tag_name().name()
            ),
        ))
    }

    /// Why usvg refused the document past [`USVG_MAX_ELEMENTS`]: its elements and `<use>`s
    /// counted here, since usvg's error counts nothing and names no limit.
    pub fn past_element_limit(&self) -> String {
        let (mut elements, mut uses) = (0usize, 0usize);
        for n in self.doc.descendants().filter(|n| n.is_element()) {
            elements += 1;
            uses += usize::from(n.has_tag_name((SVG_NS, "use")));
        }
        let counted = if uses > 0 {
            format!(
                "the document has {} elements, {} of them `<use>`, which usvg counts again with a copy of what each references",
                spaced(elements),
                spaced(uses)
            )
        } else {
            format!("the document has {} elements", spaced(elements))
        };
        format!(
            "{counted}: past usvg's element limit of {} elements, a fixed limit which no `--limit` raises",
            spaced(USVG_MAX_ELEMENTS)
        )
    }

    /// Whether a usvg id is one this module invented.
    pub fn is_synthetic(&self, id: &str) -> bool {
        self.synthetic_index(id).is_some()
    }

    fn synthetic_index(&self, id: &str) -> Option<usize> {
        let n: usize = id.strip_prefix(self.prefix.as_str())?.parse().ok()?;
        (n < self.synthetic.len()).then_some(n)
    }

    /// The source element of a usvg node id.
    pub fn element(&self, id: &str) -> Option<Node<'_, 'a>> {
        if id.is_empty() {
            return None;
        }
        let node = match self.synthetic_index(id) {
            Some(n) => self.synthetic[n],
            None => *self.by_id.get(id)?,
        };
        self.doc.get_node(node)
    }

    /// A short description of an element for messages: `<rect id="a"> (line 4)`; ids the
    /// element does not own (duplicates) are left out.
    pub fn describe(&self, node: Node) -> String {
        let line = self.doc.text_pos_at(node.range().start).row;
        let name = node.tag_name().name();
        match node
            .attribute("id")
            .filter(|id| self.by_id.get(*id) == Some(&node.id()))
        {
            Some(id) => format!("<{name} id=\"{id}\"> (line {line})"),
            None => format!("<{name}> (line {line})"),
        }
    }

    /// The `<image>` or `<feImage>` elements referencing `href`, described for a warning.
    pub fn place_of_href(&self, href: &str) -> String {
        let places: Vec<String> = self
            .doc
            .descendants()
            .filter(|n| n.is_element() && matches!(n.tag_name().name(), "image" | "feImage"))
            .filter(|n| {
                n.attributes()
                    .any(|a| a.name() == "href" && a.value().trim() == href.trim())
            })
            .map(|n| self.describe(n))
            .collect();
        if places.is_empty() {
            "<image>".to_string()
        } else {
            places.join(", ")
        }
    }

    /// The explicit tag written on `node` itself.
    pub fn explicit_tag<'s>(&'s self, node: Node<'s, 'a>, from: TagFrom) -> Option<&'s str> {
        self.explicit(node, from, true)
    }

    /// The name the designer gave `node` besides its id: its `inkscape:label`, else its
    /// `data-name` (Illustrator's, when the id had to escape the name).
    pub fn label_of<'s>(&'s self, node: Node<'s, 'a>) -> Option<&'s str> {
        let nonempty = |v: Option<&'s str>| v.map(str::trim).filter(|v| !v.is_empty());
        nonempty(node.attribute((INKSCAPE_NS, "label")))
            .or_else(|| nonempty(node.attribute("data-name")))
    }

    /// The explicit tag on `node`, reading `inkscape:label` only with `labels`.
    fn explicit<'s>(&'s self, node: Node<'s, 'a>, from: TagFrom, labels: bool) -> Option<&'s str> {
        if let Some(tag) = self.given.get(&node.id()).and_then(|g| g.tag.as_deref()) {
            return Some(tag);
        }
        let nonempty = |v: Option<&'s str>| v.map(str::trim).filter(|v| !v.is_empty());
        let data = || nonempty(node.attribute("data-tag"));
        let class = || node.attribute("class").and_then(first_class);
        // Generated style classes (`st0`) name no shape by default; asked for by
        // `--tag-from class`, every class counts.
        let named_class = || node.attribute("class").and_then(first_named_class);
        let label = || nonempty(node.attribute((INKSCAPE_NS, "label"))).filter(|_| labels);
        match from {
            TagFrom::Auto => data().or_else(named_class).or_else(label),
            TagFrom::DataTag => data(),
            TagFrom::Class => class(),
            TagFrom::Label => label(),
            TagFrom::Layer => None,
        }
    }

    /// The layer name `node` gives, if it is a `<g>` with an id of its own.
    fn layer_name<'s>(&'s self, node: Node<'s, 'a>) -> Option<&'s str> {
        if !named(node, &["g"]) {
            return None;
        }
        let id = node.attribute("id")?;
        // The name an escaped id spells (`PL_x5F_Reset` is "PL_Reset").
        let name = self.unescaped.get(&node.id()).map_or(id, String::as_str);
        (self.by_id.get(id) == Some(&node.id()))
            .then(|| strip_counter_among(name, |stem| self.by_id.contains_key(stem)))
    }

    /// The tag a container element carries itself (for units): its explicit tag, with
    /// `layers` its layer name too; a `use` also carries its referenced container's tag.
    /// The label of an Inkscape layer (`inkscape:groupmode="layer"`) names a layer, like an
    /// Illustrator layer id, so it counts only with `layers`.
    pub fn own_tag<'s>(
        &'s self,
        node: Node<'s, 'a>,
        from: TagFrom,
        layers: bool,
    ) -> Option<&'s str> {
        let here = |n: Node<'s, 'a>| {
            let layer_group = n.attribute((INKSCAPE_NS, "groupmode")) == Some("layer");
            let explicit = self.explicit(n, from, layers || !layer_group);
            explicit.or_else(|| {
                if layers && from.reads_layers() {
                    self.layer_name(n)
                } else {
                    None
                }
            })
        };
        here(node).or_else(|| {
            let target = self.use_target(node)?;
            named(target, TRANSPARENT_CONTAINERS)
                .then(|| here(target))
                .flatten()
        })
    }

    /// Extends `parent` with the tag sources from `elem` up to where `parent` was taken,
    /// or up to and including `limit`.
    pub fn scope<'s>(
        &'s self,
        elem: Node<'s, 'a>,
        parent: Scope<'s>,
        from: TagFrom,
        limit: Option<NodeId>,
    ) -> Scope<'s> {
        let outer = parent.elem.and_then(|id| self.doc.get_node(id));
        let mut scope = Scope {
            elem: Some(elem.id()),
            ..parent
        };
        let (mut explicit, mut layer) = (None, None);
        for node in elem.ancestors().filter(|n| n.is_element()) {
            if outer.is_some_and(|o| o.ancestors().any(|a| a == node)) {
                break;
            }
            // A tag map's tags count whatever `from` says (`explicit` knows).
            if explicit.is_none() {
                explicit = self.explicit_tag(node, from);
            }
            if layer.is_none() && from.reads_layers() {
                layer = self.layer_name(node);
            }
            if limit == Some(node.id()) {
                break;
            }
        }
        scope.explicit = explicit.or(parent.explicit);
        scope.layer = layer.or(parent.layer);
        scope
    }

    /// The ids a unit on `elem` answers to besides its tag ([`gmotion::scene::Shape::aliases`]):
    /// the element's own id and those of the elements around it, nearest first, each also
    /// without its counter where that merges no distinct layers (`eye_1_` is also `eye`,
    /// `Layer_1` stays `Layer_1`). A `use` instance's shapes sit in the referenced content,
    /// so `outer` (the `use`, or any element the unit is drawn under) adds its ids and its
    /// ancestors'. Invented ids are never aliases; `tag` itself is left out.
    pub fn aliases(&self, elem: Node<'_, 'a>, outer: Option<NodeId>, tag: &str) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        let outer = outer.and_then(|id| self.doc.get_node(id));
        let chain = elem
            .ancestors()
            .chain(outer.into_iter().flat_map(|o| o.ancestors()));
        for node in chain.filter(|n| n.is_element()) {
            let Some(id) = node.attribute("id") else {
                continue;
            };
            if self.by_id.get(id) != Some(&node.id()) {
                continue;
            }
            let stem = strip_counter_among(id, |stem| self.by_id.contains_key(stem));
            // An escaped id also answers to the name it spells, with and without counter.
            let spelt = self.unescaped.get(&node.id()).map(String::as_str);
            let spelt_stem =
                spelt.map(|s| strip_counter_among(s, |stem| self.by_id.contains_key(stem)));
            for name in [Some(id), Some(stem), spelt, spelt_stem]
                .into_iter()
                .flatten()
            {
                if name != tag && !out.iter().any(|a| a == name) {
                    out.push(name.to_string());
                }
            }
        }
        out
    }

    /// The element a `use` references.
    pub fn use_target<'s>(&'s self, node: Node<'s, 'a>) -> Option<Node<'s, 'a>> {
        if !named(node, &["use"]) {
            return None;
        }
        let href = node
            .attribute((XLINK_NS, "href"))
            .or_else(|| node.attribute("href"))?;
        let id = href.trim().strip_prefix('#')?;
        self.doc.get_node(*self.by_id.get(id)?)
    }

    /// Whether `node` is a clip path's `use` that points at something other than a shape
    /// or text (another `use`, a group). SVG lets a clip path's `use` reference only those
    /// directly; browsers ignore any other such child (so a clip made only of them clips
    /// everything away), where usvg follows a `use` of a `use`.
    pub fn is_indirect_clip_use(&self, node: Node<'_, 'a>) -> bool {
        node.parent_element()
            .is_some_and(|p| is_svg(p) && p.tag_name().name() == "clipPath")
            && self
                .use_target(node)
                .is_some_and(|t| !named(t, SHAPES) && !named(t, &["text"]))
    }

    /// The shapes a `use` instance draws, in paint order, when that can be told from the
    /// source alone: `None` when the referenced content holds anything usvg may expand
    /// differently (nested `use`, text, images, switches).
    pub fn use_shapes<'s>(&'s self, node: Node<'s, 'a>) -> Option<(NodeId, Vec<NodeId>)> {
        let target = self.use_target(node)?;
        if named(target, SHAPES) {
            return Some((target.id(), vec![target.id()]));
        }
        if !named(target, TRANSPARENT_CONTAINERS) {
            return None;
        }
        let mut shapes = Vec::new();
        let mut stack: Vec<Node> = target.children().rev().collect();
        while let Some(n) = stack.pop() {
            if !is_svg(n) {
                continue;
            }
            let name = n.tag_name().name();
            if SHAPES.contains(&name) {
                shapes.push(n.id());
            } else if TRANSPARENT_CONTAINERS.contains(&name) {
                stack.extend(n.children().rev());
            } else if matches!(name, "use" | "text" | "image" | "switch" | "foreignObject") {
                return None;
            }
        }
        Some((target.id(), shapes))
    }

    /// A node by its roxmltree id.
    pub fn node(&self, id: NodeId) -> Option<Node<'_, 'a>> {
        self.doc.get_node(id)
    }
}

/// `n` with its digits in groups of three, as the documentation writes counts
/// (`1 000 000`).
fn spaced(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn synthetic_ids_are_inserted_and_resolved() {
        let text = r#"<svg xmlns="http://www.w3.org/2000/svg"><g><rect/><circle id="c"/><path id="c"/></g></svg>"#;
        let src = Source::parse(text, "t.svg", &Policy::default()).unwrap();
        let prepared = Document::parse(&src.prepared).unwrap();
        let ids: Vec<_> = prepared
            .descendants()
            .filter_map(|n| n.attribute("id"))
            .collect();
        assert_eq!(ids, ["__gm0", "__gm1", "c", "__gm2"]);
        assert_eq!(src.element("__gm1").unwrap().tag_name().name(), "rect");
        assert_eq!(src.element("__gm2").unwrap().tag_name().name(), "path");
        assert_eq!(src.element("c").unwrap().tag_name().name(), "circle");
        assert!(src.element("__gm3").is_none());
    }

    #[test]
    fn prefix_avoids_existing_ids() {
        let text = r#"<svg xmlns="http://www.w3.org/2000/svg"><rect id="__gm0"/><rect/></svg>"#;
        let src = Source::parse(text, "t.svg", &Policy::default()).unwrap();
        assert!(src.prepared.contains("id=\"__gm_0\""));
        assert!(!src.is_synthetic("__gm0"));
    }

    #[test]
    fn counts_are_written_in_groups_of_three() {
        let written: Vec<_> = [0, 7, 999, 1000, 12_345, 999_000, 1_000_000]
            .into_iter()
            .map(spaced)
            .collect();
        assert_eq!(
            written,
            ["0", "7", "999", "1 000", "12 345", "999 000", "1 000 000"]
        );
    }

    /// Each CSS rule counts once against `css-rules` (an element's text was counted with
    /// its text node's, so a style reached the limit at half its rules).
    #[test]
    fn css_rules_are_counted_once() {
        let style = |n: usize| {
            let rules: String = (0..n).map(|i| format!(".c{i}{{fill:red}}")).collect();
            format!(r#"<svg xmlns="http://www.w3.org/2000/svg"><style>{rules}</style></svg>"#)
        };
        let policy = Policy {
            max_css_rules: 3,
            ..Policy::default()
        };
        assert!(Source::parse(&style(3), "t.svg", &policy).is_ok());
        let Err(e) = Source::parse(&style(4), "t.svg", &policy) else {
            panic!("four rules pass a limit of three");
        };
        assert!(e.to_string().contains("hold 4 CSS rules"), "{e}");
    }
}
