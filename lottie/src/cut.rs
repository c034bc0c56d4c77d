//! Text layers cut into letters, words or lines (`letters()`, `words()`, `lines()`).
//!
//! On import, a text layer drawn from the glyph outlines its file embeds (`chars`, After
//! Effects' "glyphs" export) gets the layout of its letters at the reference frame
//! ([`gmotion::text::TextLayout`]): each glyph's outline and paint, in the unit node's
//! inner coordinates, with its letter, word and line. A text layer set in fonts (no
//! `chars`: players set it in the user's fonts, gmotion in the machine's) has none, and
//! says why ([`gmotion::text::TextPlace::uncut`]).
//!
//! On export, a text layer the animation's scene has cut into pieces cannot stay a text
//! layer: a piece moves on its own, and a text layer has no per-letter place for gmotion's
//! motion. [`Source::cut`] writes such a layer as a shape layer instead — same place in the
//! layer stack, same `ind`, parent, in and out points, start time, transform, masks and
//! effects — whose top-level groups are the pieces (their glyph outlines and paint), and
//! splits it into one unit per group, as `--units groups` splits a shape layer. The motion
//! is then layered onto each group as onto any part, and gmotion's own render draws the
//! same document. The text's own animation (text animators, document keyframes) is kept
//! as it was at the reference frame, with a warning.

use std::sync::Arc;

use kurbo::{Affine, BezPath, PathEl, Point};
use serde_json::{Value, json};

use gmotion::color::Color;
use gmotion::measure::Measure;
use gmotion::scene::{Fill, FillRule, LineCap, LineJoin, Node, Paint, PathNode, Scene, Stroke};
use gmotion::text::{Glyph, TextLayout, TextPlace};

use crate::Source;
use crate::build::Builder;
use crate::model::{self, Document, Layer, LayerKind, Loc, Result};
use crate::units::{UnitLayers, scene_of};

/// The text place of text layer `l` drawn at frame `t` as a unit: its layout when it can
/// be cut, else why not. `matted`: the layer has a track matte (which moves with it as
/// one unit); `inner`: the unit node's inner coordinates to the canvas; `world`: the
/// layer's space to the canvas.
pub(crate) fn text_place(
    b: &mut Builder,
    doc: &Document,
    l: &Layer,
    matted: bool,
    t: f64,
    (inner, world): (Affine, Affine),
) -> Result<TextPlace> {
    let uncut = |why: String| TextPlace {
        uncut: Some(format!(
            "is the Lottie text layer `{}` ({}) {why}",
            l.nm, l.at
        )),
        ..TextPlace::default()
    };
    let Some(data) = &l.text else {
        return Ok(uncut("without text".into()));
    };
    let fonts = &doc.fonts;
    let placed = crate::text::letters(data, fonts, t);
    if fonts.glyphs.is_empty()
        || placed
            .iter()
            .any(|p| fonts.glyphs[p.glyph].outline.is_some())
    {
        return Ok(uncut(
            "without glyph outlines of its own (`chars`): players set it in the user's fonts, so it stays one text layer"
                .into(),
        ));
    }
    if matted {
        return Ok(uncut(
            "with a track matte, which moves with the whole text".into(),
        ));
    }
    if inner.determinant().abs() < 1e-12 {
        return Ok(uncut("scaled to nothing at the reference frame".into()));
    }
    let to_inner = inner.inverse() * world;
    let mut glyphs: Vec<Glyph> = Vec::new();
    // Each glyph's outline is built once, however many letters draw it.
    let mut outlines: std::collections::HashMap<usize, BezPath> = Default::default();
    // Words and lines counted over the glyphs drawn, from 0.
    let (mut words, mut lines): (Vec<usize>, Vec<usize>) = (Vec::new(), Vec::new());
    for p in placed {
        if fonts.glyphs[p.glyph].ch.chars().all(char::is_whitespace) {
            continue;
        }
        let outline = match outlines.get(&p.glyph) {
            Some(o) => o.clone(),
            None => {
                let o = b.glyph_outline(p.glyph)?;
                outlines.insert(p.glyph, o.clone());
                o
            }
        };
        if outline.elements().is_empty() {
            continue;
        }
        let color = |c: [f64; 3]| {
            let ch = |v: f64| v.clamp(0.0, 1.0) as f32;
            Color::rgb(ch(c[0]), ch(c[1]), ch(c[2]))
        };
        let opacity = p.opacity as f32;
        // As the text layer draws its letters: strokes with round joins.
        let stroke = p.stroke.map(|(c, w)| Stroke {
            join: LineJoin::Round,
            opacity,
            ..Stroke::solid(color(c), w * stretch(to_inner * p.transform))
        });
        let fill = p.fill.map(|c| Fill {
            opacity,
            ..Fill::solid(color(c))
        });
        if fill.is_none() && stroke.is_none() {
            continue;
        }
        let dense = |seen: &mut Vec<usize>, k: usize| {
            if seen.last() != Some(&k) {
                seen.push(k);
            }
            seen.len() - 1
        };
        let (word, line) = (dense(&mut words, p.word), dense(&mut lines, p.line));
        glyphs.push(Glyph {
            path: PathNode {
                id: String::new(),
                path: (to_inner * p.transform * Affine::scale(p.glyph_scale)) * outline,
                fill,
                stroke,
                stroke_first: false,
                unit: None,
            },
            letter: glyphs.len(),
            word,
            line,
        });
    }
    if glyphs.is_empty() {
        return Ok(uncut("showing no letter at the reference frame".into()));
    }
    Ok(TextPlace {
        layout: Some(Arc::new(TextLayout { glyphs })),
        ..TextPlace::default()
    })
}

/// A warning about the document written back: where, what.
pub type Note = (String, String);

impl Source {
    /// The source with every text layer that `scene` (an animation's scene, made from
    /// this source's by spatial rules) cut into pieces written as a shape layer of one
    /// group per piece, split into one unit per piece, so that its units are `scene`'s
    /// shapes; with warnings about what the pieces do not keep. `None` when `scene` has
    /// the source's own units, or cut something that is not a text layer.
    pub fn cut(&self, scene: &Scene) -> Option<(Source, Vec<Note>)> {
        if scene.shapes.len() == self.units.len() {
            return None;
        }
        let doc = &self.document;
        let worlds = Builder::new(doc).worlds(&doc.layers, self.frame).ok()?;
        let mut json = self.json.clone();
        let mut document = doc.clone();
        let mut notes = Vec::new();
        let mut measures: Vec<Option<Measure>> = Vec::with_capacity(scene.shapes.len());
        let mut shapes = scene.shapes.iter().peekable();
        for (r, unit) in self.units.iter().enumerate() {
            // The scene's shapes drawn in the unit's root node, in paint order.
            let mut members = Vec::new();
            while let Some(s) = shapes.next_if(|s| s.node_path.first() == Some(&r)) {
                members.push(s);
            }
            // One shape is the unit itself: left as it was, or passed through a text
            // operator whole (drawn one group deeper), or a text of one letter.
            if members.len() == 1 {
                measures.push(unit.measure);
                continue;
            }
            let (&[i], None) = (unit.layers.as_slice(), unit.part) else {
                return None;
            };
            let layer = &doc.layers[i];
            if layer.kind != LayerKind::Text || worlds[i].determinant().abs() < 1e-12 {
                return None;
            }
            let to_layer = worlds[i].inverse();
            let mut groups = Vec::with_capacity(members.len());
            for s in &members {
                let (node, at) = placed(&scene.root, &s.node_path)?;
                let mut paths = Vec::new();
                collect(node, to_layer * at, &mut paths);
                groups.push(piece_group(&format!("{} {}", s.tag, s.id), &paths));
                measures.push(Some(Measure {
                    centroid: s.centroid,
                    bbox: s.bbox,
                    fill: s.fill,
                    stroke: s.stroke,
                    stroke_width: s.stroke_width,
                }));
            }
            // Lottie draws its first item on top: the first piece is drawn first.
            groups.reverse();
            let l = json.get_mut("layers")?.get_mut(i)?.as_object_mut()?;
            l.remove("t");
            l.insert("ty".into(), json!(4));
            l.insert("shapes".into(), Value::Array(groups));
            let at = Loc::root().key("layers").idx(i);
            document.layers[i] = model::read_layer(&Value::Object(l.clone()), &at).ok()?;
            document.split.push(i);
            if let Some(t) = &layer.text
                && (!t.animators.is_empty() || t.documents.len() > 1)
            {
                notes.push((
                    at.to_string(),
                    format!(
                        "the text layer `{}` is written as shapes, one group per piece; its text animators and document keyframes are kept as they were at the reference frame",
                        layer.nm
                    ),
                ));
            }
        }
        if shapes.next().is_some() {
            return None;
        }
        let reference: Vec<UnitLayers> = measures
            .into_iter()
            .map(|measure| UnitLayers {
                layers: Vec::new(),
                parent_world: Vec::new(),
                part: None,
                measure,
            })
            .collect();
        let (_, built, units, _) =
            scene_of(&document, self.frame, self.mode, Some(&reference)).ok()?;
        if built.len() != scene.shapes.len() {
            return None;
        }
        Some((
            Source {
                json,
                document,
                units,
                mode: self.mode,
                frame: self.frame,
            },
            notes,
        ))
    }
}

/// The node at `path` under `root`, and its parent's coordinates to the canvas.
fn placed<'a>(root: &'a gmotion::scene::Group, path: &[usize]) -> Option<(&'a Node, Affine)> {
    let (&last, above) = path.split_last()?;
    let mut at = root.transform;
    let mut group = root;
    for &k in above {
        match group.children.get(k)? {
            Node::Group(g) => {
                at *= g.transform;
                group = g;
            }
            _ => return None,
        }
    }
    Some((group.children.get(last)?, at))
}

/// Every path under `node` (placed by `at`), with its outline placed.
fn collect(node: &Node, at: Affine, out: &mut Vec<PathNode>) {
    match node {
        Node::Path(p) => out.push(PathNode {
            path: at * p.path.clone(),
            stroke: p.stroke.clone().map(|s| Stroke {
                width: s.width * stretch(at),
                ..s
            }),
            ..p.clone()
        }),
        Node::Group(g) => {
            for c in &g.children {
                collect(c, at * g.transform, out);
            }
        }
        Node::Image(_) => {}
    }
}

/// How much `a` stretches a stroke's width (the square root of its area scale).
fn stretch(a: Affine) -> f64 {
    a.determinant().abs().sqrt()
}

/// A piece as a Lottie group named `nm`: one group per glyph (outline, paint), the first
/// drawn first.
fn piece_group(nm: &str, paths: &[PathNode]) -> Value {
    let mut items: Vec<Value> = paths.iter().rev().map(glyph_group).collect();
    items.push(identity());
    json!({"ty": "gr", "nm": nm, "it": items})
}

/// One glyph's outline with its fill and stroke, in SVG's paint order (the stroke over the
/// fill unless it is painted first).
fn glyph_group(p: &PathNode) -> Value {
    let mut items = shapes(&p.path);
    let color = |paint: &Paint| match paint {
        Paint::Solid(c) => {
            Some(json!({"a": 0, "k": [r3(c.r.into()), r3(c.g.into()), r3(c.b.into()), 1]}))
        }
        _ => None,
    };
    let fill = p.fill.as_ref().and_then(|f| {
        let rule = if f.rule == FillRule::EvenOdd { 2 } else { 1 };
        Some(json!({"ty": "fl", "c": color(&f.paint)?, "o": {"a": 0, "k": r3(f64::from(f.opacity) * 100.0)}, "r": rule}))
    });
    let stroke = p.stroke.as_ref().and_then(|s| {
        Some(json!({
            "ty": "st", "c": color(&s.paint)?,
            "o": {"a": 0, "k": r3(f64::from(s.opacity) * 100.0)},
            "w": {"a": 0, "k": r3(s.width)},
            "lc": match s.cap { LineCap::Butt => 1, LineCap::Round => 2, LineCap::Square => 3 },
            "lj": match s.join { LineJoin::Miter | LineJoin::MiterClip => 1, LineJoin::Round => 2, LineJoin::Bevel => 3 },
            "ml": r3(s.miter_limit)
        }))
    });
    let (top, under) = if p.stroke_first {
        (fill, stroke)
    } else {
        (stroke, fill)
    };
    items.extend(top);
    items.extend(under);
    items.push(identity());
    json!({"ty": "gr", "it": items})
}

/// A group's identity transform.
fn identity() -> Value {
    json!({
        "ty": "tr",
        "p": {"a": 0, "k": [0, 0]}, "a": {"a": 0, "k": [0, 0]},
        "s": {"a": 0, "k": [100, 100]}, "r": {"a": 0, "k": 0},
        "o": {"a": 0, "k": 100}, "sk": {"a": 0, "k": 0}, "sa": {"a": 0, "k": 0}
    })
}

/// `x` to three decimals (a thousandth of a pixel), as the file needs it.
fn r3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// The subpaths of `path` as Lottie paths (`sh`): vertices with in and out tangents
/// relative to them, quadratics raised to cubics.
fn shapes(path: &BezPath) -> Vec<Value> {
    // Vertex, in tangent, out tangent (absolute points).
    let mut subpaths: Vec<(Vec<[Point; 3]>, bool)> = Vec::new();
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) => subpaths.push((vec![[p, p, p]], false)),
            PathEl::LineTo(p) => {
                if let Some((v, _)) = subpaths.last_mut() {
                    v.push([p, p, p]);
                }
            }
            PathEl::QuadTo(q, p) => {
                if let Some((v, _)) = subpaths.last_mut()
                    && let Some(last) = v.last_mut()
                {
                    let a = last[0];
                    last[2] = a + (q - a) * (2.0 / 3.0);
                    v.push([p, p + (q - p) * (2.0 / 3.0), p]);
                }
            }
            PathEl::CurveTo(c1, c2, p) => {
                if let Some((v, _)) = subpaths.last_mut()
                    && let Some(last) = v.last_mut()
                {
                    last[2] = c1;
                    v.push([p, c2, p]);
                }
            }
            PathEl::ClosePath => {
                if let Some((v, closed)) = subpaths.last_mut() {
                    *closed = true;
                    // A last vertex on the first is the first (its in tangent kept).
                    if v.len() > 1
                        && let (Some(first), Some(last)) = (v.first(), v.last())
                        && (first[0] - last[0]).hypot() < 1e-9
                    {
                        let inward = last[1];
                        v.pop();
                        v[0][1] = inward;
                    }
                }
            }
        }
    }
    subpaths
        .into_iter()
        .filter(|(v, _)| v.len() > 1)
        .map(|(v, closed)| {
            let pt = |p: Point| json!([r3(p.x), r3(p.y)]);
            let rel = |p: Point, o: Point| json!([r3(p.x - o.x), r3(p.y - o.y)]);
            json!({"ty": "sh", "ks": {"a": 0, "k": {
                "c": closed,
                "v": v.iter().map(|k| pt(k[0])).collect::<Vec<_>>(),
                "i": v.iter().map(|k| rel(k[1], k[0])).collect::<Vec<_>>(),
                "o": v.iter().map(|k| rel(k[2], k[0])).collect::<Vec<_>>(),
            }}})
        })
        .collect()
}
