//! Key shapes: elements kept out of the drawing (`display="none"`, or a shape in `<defs>`)
//! whose outlines a grammar names as morph targets (`shape(TAG)`). usvg drops both, so a
//! document that has any is parsed a second time with each key made drawable in place
//! (its `display` taken away, a `<defs>` shape drawn by a `<use>`) inside a group of its
//! own, and only the paths of those groups are kept, in canvas coordinates: what the
//! key would draw were it shown. A document without keys costs nothing more.

use kurbo::{Affine, BezPath};
use usvg::roxmltree::{Document, Node};

use gmotion::scene::KeyShape;
use gmotion::tagging::strip_counter;

use crate::ImportOptions;
use crate::source::Source;

/// Elements whose outline a key shape may be.
const SHAPES: &[&str] = &[
    "g", "path", "rect", "circle", "ellipse", "line", "polyline", "polygon",
];

/// Containers whose content draws only where it is referenced (a key inside one is not
/// looked for: only a shape directly in `<defs>` is a key of its own).
const REFERENCED: &[&str] = &[
    "defs",
    "clipPath",
    "mask",
    "pattern",
    "marker",
    "symbol",
    "linearGradient",
    "radialGradient",
    "filter",
];

/// Whether `node` is hidden by its own `display` (attribute or `style` declaration).
fn hidden(node: Node) -> bool {
    let none = |v: &str| v.trim() == "none";
    node.attribute("display").is_some_and(none)
        || node.attribute("style").is_some_and(|s| {
            s.split(';').any(|d| {
                d.split_once(':')
                    .is_some_and(|(k, v)| k.trim() == "display" && none(v))
            })
        })
}

/// How a key is kept out of the drawing.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Hidden,
    Defs,
}

/// The keys of `doc` in document order: outermost hidden shapes outside referenced
/// content, and shapes with an id directly in `<defs>`.
fn find<'a, 'i>(doc: &'a Document<'i>) -> Vec<(Node<'a, 'i>, Kind)> {
    let mut out = Vec::new();
    let mut stack = vec![doc.root_element()];
    while let Some(n) = stack.pop() {
        for c in n.children().filter(|c| c.is_element()).rev() {
            let name = c.tag_name().name();
            if name == "defs" {
                for d in c.children().filter(|d| d.is_element()) {
                    if SHAPES.contains(&d.tag_name().name()) && d.attribute("id").is_some() {
                        out.push((d, Kind::Defs));
                    }
                }
                continue;
            }
            if REFERENCED.contains(&name) {
                continue;
            }
            if SHAPES.contains(&name) && hidden(c) {
                out.push((c, Kind::Hidden));
                continue;
            }
            stack.push(c);
        }
    }
    out.sort_by_key(|(n, _)| n.range().start);
    out
}

/// The key shapes of a document (`src` as the importer parsed it, `opt` usvg's options).
pub fn key_shapes(src: &Source, opt: &usvg::Options, opts: &ImportOptions) -> Vec<KeyShape> {
    let keys = find(&src.doc);
    if keys.is_empty() {
        return Vec::new();
    }
    // The text usvg reads has ids inserted: find the same keys there to edit it.
    let Ok(prepared) = Document::parse_with_options(
        &src.prepared,
        usvg::roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    ) else {
        return Vec::new();
    };
    let there = find(&prepared);
    if there.len() != keys.len() {
        return Vec::new();
    }
    let text: &str = &src.prepared;
    // Edits as (range, replacement), applied from the end.
    let mut edits: Vec<(std::ops::Range<usize>, String)> = Vec::new();
    let mut uses = String::new();
    for (i, (node, kind)) in there.iter().enumerate() {
        let group = format!("__gm_key_{i}");
        match kind {
            Kind::Hidden => {
                for a in node.attributes() {
                    if a.name() == "display" {
                        edits.push((a.range(), " ".repeat(a.range().len())));
                    } else if a.name() == "style" {
                        let r = a.range_value();
                        let v = &text[r.clone()];
                        edits.push((r, v.replace("display", "       ")));
                    }
                }
                let r = node.range();
                edits.push((r.start..r.start, format!("<g id=\"{group}\">")));
                edits.push((r.end..r.end, "</g>".to_string()));
            }
            Kind::Defs => {
                let id = node.attribute("id").unwrap_or_default();
                uses.push_str(&format!(
                    "<g id=\"{group}\"><use href=\"#{}\"/></g>",
                    id.replace('&', "&amp;").replace('"', "&quot;")
                ));
            }
        }
    }
    let root = prepared.root_element().range();
    let close = text[..root.end].rfind("</").unwrap_or(root.end);
    edits.push((close..close, uses));
    edits.sort_by_key(|(r, _)| (r.start, r.end));
    let mut edited = text.to_string();
    for (r, with) in edits.into_iter().rev() {
        edited.replace_range(r, &with);
    }
    let Ok(tree) = usvg::Tree::from_str(&edited, opt) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (i, (node, _)) in keys.iter().enumerate() {
        let Some(group) = tree.node_by_id(&format!("__gm_key_{i}")) else {
            continue;
        };
        let mut paths = Vec::new();
        collect(group, &mut paths);
        let id = node.attribute("id").map(strip_counter);
        let Some(tag) = src
            .explicit_tag(*node, opts.tag_from)
            .or(id)
            .map(str::to_string)
        else {
            continue;
        };
        let aliases = src.aliases(*node, None, &tag);
        out.push(KeyShape {
            tag,
            aliases,
            paths,
        });
    }
    out
}

/// The paths under `node`, in canvas coordinates, in document order.
fn collect(node: &usvg::Node, out: &mut Vec<BezPath>) {
    match node {
        usvg::Node::Group(g) => {
            for c in g.children() {
                collect(c, out);
            }
        }
        usvg::Node::Path(p) => {
            let t = p.abs_transform();
            let abs = Affine::new([
                t.sx as f64,
                t.ky as f64,
                t.kx as f64,
                t.sy as f64,
                t.tx as f64,
                t.ty as f64,
            ]);
            out.push(abs * crate::convert::bez(p.data()));
        }
        usvg::Node::Image(_) | usvg::Node::Text(_) => {}
    }
}
