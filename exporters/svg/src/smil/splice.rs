//! Reusing the static writer: the scene is written by [`scene_svg`] with every node the
//! animation touches findable by id, and the animation elements are spliced into that text.
//!
//! Nodes that have no id, or share one, get a marker id for the writing (markers are chosen
//! to collide with nothing, so the writer's def names avoid them too) which the splice
//! removes again. The writer's output is regular (one tag per line, escaped attribute
//! values), so a tag scanner is enough to find elements.

use foldhash::{HashMap, HashMapExt, HashSet, HashSetExt};

use kurbo::Affine;

use super::SmilText;
use crate::frame::{IdsByNode, node_key, scene_svg_with_ids};
use gmotion::scene::{Group, Node, PathNode, Scene};

/// A path inside one or more animated units, with what the splice needs to animate it.
pub struct MarkedPath<'a> {
    /// The path in the original scene.
    pub path: &'a PathNode,
    /// Its element (an index into [`Marked::elements`]).
    pub element: usize,
    /// Transform from the path's coordinates to the canvas at rest.
    pub abs: Affine,
    /// The units it lies in, outermost first.
    pub units: Vec<usize>,
}

/// The static document and where the animated nodes are in it.
pub struct Marked<'a> {
    /// `scene_svg`'s text of the marked scene.
    pub svg: String,
    /// The ids of the elements made findable, in document order, each with whether it is
    /// a marker (to remove when splicing).
    pub elements: Vec<(String, bool)>,
    /// Each animated unit with its element (an index into `elements`), in document order.
    pub units: Vec<(usize, usize)>,
    /// Paths inside units, in document order.
    pub paths: Vec<MarkedPath<'a>>,
    /// The scene's own node ids, with how many nodes carry each: with the markers (in
    /// `elements`), every node id in the document (to name new elements without
    /// collisions).
    pub node_ids: HashMap<&'a str, usize>,
}

/// Writes `scene` with ids on the unit nodes of `units` and on every path inside them
/// (given to the writer by node: the scene is not copied).
pub fn mark<'a>(scene: &'a Scene, units: &HashSet<usize>) -> Marked<'a> {
    let mut count: HashMap<&str, usize> = HashMap::new();
    count_ids(&scene.root, &mut count);
    let mut st = MarkState {
        units,
        count: &count,
        elements: Vec::new(),
        marked_units: Vec::new(),
        paths: Vec::new(),
        markers: HashSet::new(),
        ids: IdsByNode::default(),
    };
    st.group(&scene.root, scene.root.transform, &mut Vec::new());
    let svg = scene_svg_with_ids(scene, Some(&st.ids));
    let MarkState {
        elements,
        marked_units: units,
        paths,
        ..
    } = st;
    Marked {
        svg,
        elements,
        units,
        paths,
        node_ids: count,
    }
}

fn count_ids<'s>(g: &'s Group, count: &mut HashMap<&'s str, usize>) {
    if !g.id.is_empty() {
        *count.entry(&g.id).or_default() += 1;
    }
    for child in &g.children {
        match child {
            Node::Group(h) => count_ids(h, count),
            Node::Path(_) | Node::Image(_) if !child.id().is_empty() => {
                *count.entry(child.id()).or_default() += 1
            }
            Node::Path(_) | Node::Image(_) => {}
        }
    }
}

struct MarkState<'a, 'c> {
    units: &'c HashSet<usize>,
    count: &'c HashMap<&'a str, usize>,
    elements: Vec<(String, bool)>,
    marked_units: Vec<(usize, usize)>,
    paths: Vec<MarkedPath<'a>>,
    markers: HashSet<String>,
    /// The ids the document is written with, by node.
    ids: IdsByNode,
}

impl<'a> MarkState<'a, '_> {
    /// Makes the node `key` findable by an id: its own when unique, else a fresh marker;
    /// returns its element's index.
    fn findable(&mut self, key: usize, own: &str, hint: &str) -> usize {
        let (id, marker) = if !own.is_empty() && self.count.get(own) == Some(&1) {
            (own.to_string(), false)
        } else {
            let mut name = format!("gmotion-{hint}");
            while self.count.contains_key(name.as_str()) || self.markers.contains(&name) {
                name.push('_');
            }
            self.markers.insert(name.clone());
            (name, true)
        };
        self.ids.insert(key, id.clone());
        self.elements.push((id, marker));
        self.elements.len() - 1
    }

    /// Walks `g`'s content; `abs` maps it to the canvas.
    fn group(&mut self, g: &'a Group, abs: Affine, inside: &mut Vec<usize>) {
        for node in &g.children {
            let unit = node.unit().filter(|u| self.units.contains(u));
            let mut element = None;
            if let Some(u) = unit {
                let e = self.findable(key_of(node), node.id(), &format!("u{u}"));
                self.marked_units.push((u, e));
                element = Some(e);
                inside.push(u);
            }
            match node {
                Node::Group(h) => self.group(h, abs * h.transform, inside),
                Node::Path(p) if !inside.is_empty() => {
                    let hint = format!("p{}", self.paths.len());
                    let element = match element {
                        Some(e) => e,
                        None => self.findable(node_key(p), &p.id, &hint),
                    };
                    self.paths.push(MarkedPath {
                        path: p,
                        element,
                        abs,
                        units: inside.clone(),
                    });
                }
                _ => {}
            }
            if unit.is_some() {
                inside.pop();
            }
        }
    }
}

/// The key [`IdsByNode`] knows `node` by: its group's, path's or image's address.
fn key_of(node: &Node) -> usize {
    match node {
        Node::Group(g) => node_key(g),
        Node::Path(p) => node_key(p),
        Node::Image(i) => node_key(i),
    }
}

/// A tag in the document: byte range and shape.
#[derive(Clone, Copy, Debug)]
pub struct Tag {
    /// Offset of `<`.
    pub start: usize,
    /// Offset just past `>`.
    pub end: usize,
    /// `</…>`.
    pub closing: bool,
    /// `<…/>`.
    pub empty: bool,
}

/// An element: its start tag and, for non-empty elements, the offset past its end tag.
#[derive(Clone, Copy, Debug)]
pub struct Element {
    /// The start tag.
    pub tag: Tag,
    /// Offset just past the element (its end tag, or the empty tag).
    pub end: usize,
}

/// Every tag of a document the static writer produced (no comments, CDATA or `>` in
/// attribute values).
pub fn tags(svg: &str) -> Vec<Tag> {
    let mut out = Vec::new();
    let mut i = 0;
    let b = svg.as_bytes();
    while let Some(off) = svg[i..].find('<') {
        let start = i + off;
        let Some(len) = svg[start..].find('>') else {
            break;
        };
        let end = start + len + 1;
        out.push(Tag {
            start,
            end,
            closing: b.get(start + 1) == Some(&b'/'),
            empty: b[end - 2] == b'/',
        });
        i = end;
    }
    out
}

/// The value of attribute `name` in a tag's text, with its byte range in that text.
pub fn attr<'s>(tag: &'s str, name: &str) -> Option<(std::ops::Range<usize>, &'s str)> {
    // The first ` name="`, found without building that pattern: this runs for every tag
    // of a large document, and the pattern's allocation was most of its time.
    let step = name.chars().next()?.len_utf8();
    let mut from = 0;
    while let Some(i) = tag[from..].find(name) {
        let at = from + i;
        let after = at + name.len();
        if tag[..at].ends_with(' ') && tag[after..].starts_with("=\"") {
            let start = after + 2;
            let len = tag[start..].find('"')?;
            return Some((start..start + len, &tag[start..start + len]));
        }
        from = at + step;
    }
    None
}

/// The elements that carry an id, by id (the first one when an id repeats).
pub fn elements_by_id<'s>(svg: &'s str) -> HashMap<&'s str, Element> {
    let mut found = HashMap::new();
    let mut open: Vec<Tag> = Vec::new();
    let finish = |t: Tag, end: usize, found: &mut HashMap<&'s str, Element>| {
        if let Some((_, id)) = attr(&svg[t.start..t.end], "id") {
            found.entry(id).or_insert(Element { tag: t, end });
        }
    };
    for t in tags(svg) {
        if t.closing {
            if let Some(o) = open.pop() {
                finish(o, t.end, &mut found);
            }
        } else if t.empty {
            finish(t, t.end, &mut found);
        } else if !svg[t.start..].starts_with("<?") {
            open.push(t);
        }
    }
    found
}

/// The elements whose ids are `ids`, listed in the order they are written (each id
/// once), found in one pass over the document instead of through a map of every element
/// (whose look-ups, a cache miss each, made a large export slower per shape than a small
/// one). An id not met in that order is looked for by [`elements_by_id`], as before.
pub fn locate(svg: &str, ids: &[&str]) -> Vec<Option<Element>> {
    let mut found: Vec<Option<Element>> = vec![None; ids.len()];
    let mut next = 0;
    let mut open: Vec<(Tag, Option<usize>)> = Vec::new();
    let mut finish = |t: Tag, end: usize, at: Option<usize>| {
        if let Some(i) = at {
            found[i] = Some(Element { tag: t, end });
        }
    };
    for t in tags(svg) {
        if t.closing {
            if let Some((o, at)) = open.pop() {
                finish(o, t.end, at);
            }
            continue;
        }
        if svg[t.start..].starts_with("<?") {
            continue;
        }
        let at = ids
            .get(next)
            .filter(|&&id| attr(&svg[t.start..t.end], "id").is_some_and(|(_, v)| v == id))
            .map(|_| {
                next += 1;
                next - 1
            });
        if t.empty {
            finish(t, t.end, at);
        } else {
            open.push((t, at));
        }
    }
    if next < ids.len() {
        let els = elements_by_id(svg);
        for (slot, id) in found.iter_mut().zip(ids).skip(next) {
            *slot = els.get(id).copied();
        }
    }
    found
}

/// Text edits on a document: insertions and replacements at byte offsets.
#[derive(Default)]
pub struct Edits {
    list: Vec<(usize, usize, u32, String)>,
    seq: u32,
}

impl Edits {
    /// Replaces `range` by `text` (an empty range inserts it; insertions at one offset keep
    /// the order they were made in).
    pub fn replace(&mut self, range: std::ops::Range<usize>, text: String) {
        self.list.push((range.start, range.end, self.seq, text));
        self.seq += 1;
    }

    /// The edited document. Replaced ranges must not overlap.
    pub fn apply(mut self, doc: String) -> SmilText {
        self.list.sort_by_key(|e| (e.0, e.1 != e.0, e.2));
        let edits = self
            .list
            .into_iter()
            .map(|(s, e, _, t)| (s, e, t))
            .collect();
        SmilText::new(doc, edits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_elements_and_attributes() {
        let doc = "<svg a=\"1\">\n<g id=\"x\">\n<path id=\"y\" d=\"M0 0\"/>\n</g>\n</svg>\n";
        let els = elements_by_id(doc);
        let x = els["x"];
        assert_eq!(
            &doc[x.tag.start..x.end],
            "<g id=\"x\">\n<path id=\"y\" d=\"M0 0\"/>\n</g>"
        );
        let y = els["y"];
        assert_eq!(attr(&doc[y.tag.start..y.tag.end], "d").unwrap().1, "M0 0");
    }

    #[test]
    fn elements_are_located_in_one_pass_or_by_id() {
        let doc = "<svg>\n<defs>\n<g id=\"b\"/>\n</defs>\n<g id=\"a\">\n<path id=\"b\"/>\n</g>\n<path id=\"c\"/>\n</svg>\n";
        let text = |e: Option<Element>| e.map(|e| &doc[e.tag.start..e.end]);
        // In the order written: each found after the one before.
        let found = locate(doc, &["a", "b", "c"]);
        let texts: Vec<_> = found.into_iter().map(text).collect();
        assert_eq!(
            texts,
            [
                Some("<g id=\"a\">\n<path id=\"b\"/>\n</g>"),
                Some("<path id=\"b\"/>"),
                Some("<path id=\"c\"/>")
            ]
        );
        // Out of order, or missing: by id, the first element that has it.
        let found = locate(doc, &["c", "a", "x"]);
        let texts: Vec<_> = found.into_iter().map(text).collect();
        assert_eq!(
            texts,
            [
                Some("<path id=\"c\"/>"),
                Some("<g id=\"a\">\n<path id=\"b\"/>\n</g>"),
                None
            ]
        );
    }

    #[test]
    fn an_attribute_is_found_by_its_whole_name() {
        let tag = "<path data-id=\"a\" xid=\"b\" title=\"id=c\" id=\"d\" idx=\"e\"/>";
        let (range, value) = attr(tag, "id").unwrap();
        assert_eq!((value, &tag[range]), ("d", "d"));
        assert_eq!(attr(tag, "idx").unwrap().1, "e");
        assert_eq!(attr(tag, "x"), None);
        assert_eq!(attr(tag, ""), None);
    }

    #[test]
    fn edits_apply_in_order() {
        let mut e = Edits::default();
        e.replace(3..3, "b".into());
        e.replace(1..2, "X".into());
        e.replace(3..3, "c".into());
        e.replace(0..0, "<".into());
        assert_eq!(e.apply("0123".into()).into_string(), "<0X2bc3");
    }
}
