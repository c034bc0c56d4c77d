//! The document at the reference frame as a scene tree: every drawn layer a group with its
//! world transform (parenting resolved) and opacity, shape layers' items as painted paths,
//! precompositions expanded, track mattes as masks.

use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

use kurbo::{Affine, BezPath, Ellipse, Point, Rect, RoundedRect, Shape as _, Vec2};

use gmotion::color::Color;
use gmotion::scene::{
    Fill, FillRule, Group, LineCap, LineJoin, Mask, MaskKind, Node, Paint, PathNode, Stroke,
};

use crate::eval;
use crate::model::{
    Asset, Document, Layer, LayerKind, Loc, Num, Result, ShapeItem, ShapeKind, error,
};

/// Precompositions may nest this deep.
pub const MAX_PRECOMP_DEPTH: usize = 32;
/// At most this many layers are drawn in all (a precomposition used many times at many
/// levels multiplies its layers).
pub const MAX_DRAWN_LAYERS: usize = 200_000;

/// Builds scene nodes from a document.
#[derive(Debug)]
pub struct Builder<'a> {
    doc: &'a Document,
    assets: HashMap<&'a str, &'a Asset>,
    budget: usize,
    legacy_colors: bool,
    /// Warnings by kind: the message, how often, and the first place.
    warnings: BTreeMap<String, (usize, Loc)>,
}

impl<'a> Builder<'a> {
    /// A builder for `doc`.
    pub fn new(doc: &'a Document) -> Builder<'a> {
        Builder {
            doc,
            assets: doc.assets.iter().map(|a| (a.id.as_str(), a)).collect(),
            budget: MAX_DRAWN_LAYERS,
            legacy_colors: doc.older_than((4, 1, 9)),
            warnings: BTreeMap::new(),
        }
    }

    /// Records a warning of kind `message` at `at` (one line per kind, counted).
    pub fn warn(&mut self, at: &Loc, message: impl Into<String>) {
        self.warnings
            .entry(message.into())
            .or_insert((0, at.clone()))
            .0 += 1;
    }

    /// The warnings, one per kind: `(first place, message with count)`.
    pub fn warnings(&self) -> Vec<(String, String)> {
        self.warnings
            .iter()
            .map(|(m, (n, at))| {
                let more = if *n > 1 {
                    format!(" ({n} places)")
                } else {
                    String::new()
                };
                (at.to_string(), format!("{m}{more}"))
            })
            .collect()
    }

    /// World transforms of `layers` at composition frame `t`, parenting resolved.
    pub fn worlds(&mut self, layers: &[Layer], t: f64) -> Result<Vec<Affine>> {
        let mut by_ind: HashMap<i64, usize> = HashMap::new();
        for (i, l) in layers.iter().enumerate() {
            if let Some(ind) = l.ind {
                by_ind.entry(ind).or_insert(i);
            }
        }
        let mut parents = Vec::with_capacity(layers.len());
        for l in layers {
            let p = match l.parent {
                Some(p) => match by_ind.get(&p) {
                    Some(&j) => Some(j),
                    None => {
                        self.warn(
                            &l.at.key("parent"),
                            "a parent index names no layer of its composition; ignored",
                        );
                        None
                    }
                },
                None => None,
            };
            parents.push(p);
        }
        let mut memo: Vec<Option<Affine>> = vec![None; layers.len()];
        let mut on_chain = vec![false; layers.len()];
        for i in 0..layers.len() {
            let mut chain = Vec::new();
            let mut base = Affine::IDENTITY;
            let mut cur = Some(i);
            while let Some(j) = cur {
                if let Some(m) = memo[j] {
                    base = m;
                    break;
                }
                if on_chain[j] {
                    return error(
                        &layers[i].at.key("parent"),
                        format!(
                            "the layers' parents form a cycle (through layer {} \"{}\")",
                            layers[j].ind.unwrap_or(-1),
                            layers[j].nm
                        ),
                    );
                }
                on_chain[j] = true;
                chain.push(j);
                cur = parents[j];
            }
            for &j in chain.iter().rev() {
                let l = &layers[j];
                base *= eval::matrix(&l.ks, local_time(l, t));
                memo[j] = Some(base);
            }
            for j in chain {
                on_chain[j] = false;
            }
        }
        Ok(memo
            .into_iter()
            .map(|m| m.unwrap_or(Affine::IDENTITY))
            .collect())
    }

    /// The matte source of layer `i` (by `tp`, else the layer above it with `td`).
    pub fn matte_source(layers: &[Layer], i: usize) -> Option<usize> {
        let l = &layers[i];
        if l.tt.is_none_or(|tt| tt == 0) {
            return None;
        }
        if let Some(tp) = l.tp {
            return layers.iter().position(|m| m.ind == Some(tp));
        }
        let above = i.checked_sub(1)?;
        layers[above].td.then_some(above)
    }

    /// A layer drawn at composition frame `t` with world transform `world`: a group, its
    /// children in paint order.
    pub fn layer_node(
        &mut self,
        l: &Layer,
        world: Affine,
        t: f64,
        stack: &mut Vec<String>,
    ) -> Result<Group> {
        if self.budget == 0 {
            return error(
                &l.at,
                format!(
                    "more than {MAX_DRAWN_LAYERS} layers to draw (precompositions used many times over)"
                ),
            );
        }
        self.budget -= 1;
        let lt = local_time(l, t);
        if l.has_masks {
            self.warn(&l.at.key("masksProperties"), "layer masks are not applied");
        }
        if l.ks.has_expression() {
            self.warn(
                &l.at.key("ks"),
                "expressions are not run; their properties' own values are used",
            );
        }
        let mut children = Vec::new();
        match l.kind {
            LayerKind::Shape => {
                let (nodes, _, _, _) = self.items(&l.shapes, lt)?;
                children = nodes;
            }
            LayerKind::Solid => {
                let (w, h) = (l.sw.unwrap_or(0.0), l.sh.unwrap_or(0.0));
                let color = l
                    .solid_color
                    .as_deref()
                    .and_then(Color::parse)
                    .unwrap_or(Color::BLACK);
                children.push(path_node(
                    Rect::new(0.0, 0.0, w, h).to_path(0.1),
                    Some(Fill::solid(color)),
                    None,
                ));
            }
            LayerKind::Image => {
                let asset = l.ref_id.as_deref().and_then(|id| self.assets.get(id));
                let (w, h) = asset.map_or((0.0, 0.0), |a| (a.w.unwrap_or(0.0), a.h.unwrap_or(0.0)));
                self.warn(&l.at, "images are not drawn (their rectangle is measured)");
                children.push(path_node(
                    Rect::new(0.0, 0.0, w, h).to_path(0.1),
                    None,
                    None,
                ));
            }
            LayerKind::Text => {
                self.warn(
                    &l.at,
                    "text is not drawn (measured as a point at its anchor)",
                );
                let a = eval::vec2(l.ks.a.as_ref(), lt, Vec2::ZERO);
                let r = Rect::from_center_size(a.to_point(), (1.0, 1.0));
                children.push(path_node(r.to_path(0.1), None, None));
            }
            LayerKind::Precomp => {
                let Some(id) = l.ref_id.clone() else {
                    return error(&l.at, "a precomposition layer needs its `refId`");
                };
                let Some(asset) = self.assets.get(id.as_str()).copied() else {
                    return error(&l.at.key("refId"), format!("no asset has the id \"{id}\""));
                };
                let Some(layers) = &asset.layers else {
                    return error(
                        &l.at.key("refId"),
                        format!("the asset \"{id}\" is not a precomposition"),
                    );
                };
                if stack.contains(&id) {
                    return error(
                        &l.at.key("refId"),
                        format!("precompositions form a cycle: {} → {id}", stack.join(" → ")),
                    );
                }
                if stack.len() >= MAX_PRECOMP_DEPTH {
                    return error(
                        &l.at.key("refId"),
                        format!("precompositions nest deeper than {MAX_PRECOMP_DEPTH} levels"),
                    );
                }
                // Time remap is in seconds of the precomposition.
                let inner = match &l.tm {
                    Some(tm) => eval::scalar(Some(tm), lt, 0.0) * self.doc.fr,
                    None => lt,
                };
                stack.push(id);
                let nodes = self.comp_nodes(layers, inner, stack);
                stack.pop();
                children = nodes?;
            }
            LayerKind::Null | LayerKind::Other(_) => {}
        }
        Ok(Group {
            transform: world,
            opacity: eval::opacity(&l.ks, lt) as f32,
            children,
            ..Group::new()
        })
    }

    /// The layers of a composition drawn at its frame `t`, in paint order.
    pub fn comp_nodes(
        &mut self,
        layers: &[Layer],
        t: f64,
        stack: &mut Vec<String>,
    ) -> Result<Vec<Node>> {
        let worlds = self.worlds(layers, t)?;
        let mut out = Vec::new();
        for i in (0..layers.len()).rev() {
            let l = &layers[i];
            if !l.kind.draws() || l.hidden || l.td || !(l.ip <= t && t < l.op) {
                continue;
            }
            let node = self.drawn(layers, i, &worlds, t, stack)?;
            out.push(Node::Group(node));
        }
        Ok(out)
    }

    /// Layer `i` drawn, with its track matte when it has one.
    pub fn drawn(
        &mut self,
        layers: &[Layer],
        i: usize,
        worlds: &[Affine],
        t: f64,
        stack: &mut Vec<String>,
    ) -> Result<Group> {
        let l = &layers[i];
        let node = self.layer_node(l, worlds[i], t, stack)?;
        let Some(m) = Self::matte_source(layers, i) else {
            if l.tt.is_some_and(|tt| tt != 0) {
                self.warn(
                    &l.at.key("tt"),
                    "a track matte without its matte layer; drawn unmatted",
                );
            }
            return Ok(node);
        };
        let kind = match l.tt {
            Some(1) => MaskKind::Alpha,
            Some(3) => MaskKind::Luminance,
            _ => {
                self.warn(
                    &l.at.key("tt"),
                    "inverted track mattes are not drawn by gmotion's own renderer (the matte is left out)",
                );
                return Ok(node);
            }
        };
        let source = self.layer_node(&layers[m], worlds[m], t, stack)?;
        let (w, h) = (self.doc.w, self.doc.h);
        let margin = 10.0 * w.max(h);
        Ok(Group {
            children: vec![Node::Group(node)],
            mask: Some(Arc::new(Mask {
                id: String::new(),
                rect: Rect::new(-margin, -margin, w + margin, h + margin),
                kind,
                mask: None,
                root: Group {
                    children: vec![Node::Group(source)],
                    ..Group::new()
                },
            })),
            ..Group::new()
        })
    }

    /// Shape items at layer frame `t`: the nodes they draw (paint order), the outlines not
    /// yet painted (which styles further down the list paint), the group transform and
    /// opacity.
    fn items(
        &mut self,
        items: &[ShapeItem],
        t: f64,
    ) -> Result<(Vec<Node>, Vec<BezPath>, Affine, f64)> {
        let mut pending: Vec<BezPath> = Vec::new();
        let mut drawn: Vec<Node> = Vec::new(); // topmost first
        let mut transform = Affine::IDENTITY;
        let mut opacity = 1.0;
        for item in items {
            if item.hidden {
                continue;
            }
            match &item.kind {
                ShapeKind::Group(sub) => {
                    let (nodes, outlines, m, o) = self.items(sub, t)?;
                    pending.extend(outlines.into_iter().map(|mut p| {
                        p.apply_affine(m);
                        p
                    }));
                    if !nodes.is_empty() && o > 0.0 {
                        drawn.push(Node::Group(Group {
                            id: item.nm.clone(),
                            transform: m,
                            opacity: o as f32,
                            children: nodes,
                            ..Group::new()
                        }));
                    }
                }
                ShapeKind::Path { ks, closed } => {
                    let mut closed = *closed;
                    if closed.is_none() && self.doc.older_than((4, 4, 18)) {
                        closed = Some(false);
                    }
                    pending.push(eval::outline(ks, t, closed));
                }
                ShapeKind::Rect { p, s, r } => {
                    let c = eval::vec2(p.as_ref(), t, Vec2::ZERO).to_point();
                    let s = eval::vec2(s.as_ref(), t, Vec2::ZERO);
                    let rect = Rect::from_center_size(c, (s.x.abs(), s.y.abs()));
                    let r = eval::scalar(r.as_ref(), t, 0.0)
                        .max(0.0)
                        .min(rect.width().min(rect.height()) / 2.0);
                    pending.push(if r > 0.0 {
                        RoundedRect::from_rect(rect, r).to_path(0.1)
                    } else {
                        rect.to_path(0.1)
                    });
                }
                ShapeKind::Ellipse { p, s } => {
                    let c = eval::vec2(p.as_ref(), t, Vec2::ZERO).to_point();
                    let s = eval::vec2(s.as_ref(), t, Vec2::ZERO);
                    pending.push(
                        Ellipse::new(c, (s.x.abs() / 2.0, s.y.abs() / 2.0), 0.0).to_path(0.1),
                    );
                }
                ShapeKind::Star {
                    sy,
                    p,
                    or,
                    ir,
                    r,
                    pt,
                } => {
                    pending.push(star(
                        *sy,
                        eval::vec2(p.as_ref(), t, Vec2::ZERO).to_point(),
                        eval::scalar(or.as_ref(), t, 0.0),
                        eval::scalar(ir.as_ref(), t, 0.0),
                        eval::scalar(r.as_ref(), t, 0.0),
                        eval::scalar(pt.as_ref(), t, 5.0),
                    ));
                }
                ShapeKind::Fill { c, o, rule } => {
                    if let Some(path) = joined(&pending) {
                        let fill = Fill {
                            paint: Paint::Solid(self.color(c.as_ref(), t)),
                            opacity: percent(o.as_ref(), t),
                            rule: if *rule == 2 {
                                FillRule::EvenOdd
                            } else {
                                FillRule::NonZero
                            },
                        };
                        drawn.push(path_node(path, Some(fill), None));
                    }
                }
                ShapeKind::Stroke {
                    c,
                    o,
                    w,
                    lc,
                    lj,
                    ml,
                    dashes,
                } => {
                    if let Some(path) = joined(&pending) {
                        let mut stroke = Stroke::solid(
                            self.color(c.as_ref(), t),
                            eval::scalar(w.as_ref(), t, 1.0).max(0.0),
                        );
                        stroke.opacity = percent(o.as_ref(), t);
                        stroke.cap = match lc {
                            1 => LineCap::Butt,
                            3 => LineCap::Square,
                            _ => LineCap::Round,
                        };
                        stroke.join = match lj {
                            1 => LineJoin::Miter,
                            3 => LineJoin::Bevel,
                            _ => LineJoin::Round,
                        };
                        stroke.miter_limit = ml.max(1.0);
                        let mut dash = Vec::new();
                        for d in dashes {
                            let v = eval::scalar(Some(&d.v), t, 0.0).max(0.0);
                            match d.n.as_str() {
                                "o" => stroke.dash_offset = v,
                                _ => dash.push(v),
                            }
                        }
                        if dash.len() % 2 == 1 {
                            dash.extend(dash.clone());
                        }
                        if dash.iter().any(|d| *d > 0.0) {
                            stroke.dash = Some(dash);
                        }
                        drawn.push(path_node(path, None, Some(stroke)));
                    }
                }
                ShapeKind::Gradient {
                    stroke,
                    o,
                    stops,
                    w,
                    rule,
                } => {
                    self.warn(&item.at, "gradients are drawn in their first stop's colour");
                    if let Some(path) = joined(&pending) {
                        let v = eval::num(stops.as_ref(), t, &[0.0, 0.0, 0.0, 0.0]);
                        let c = |k: usize| v.get(k).copied().unwrap_or(0.0).clamp(0.0, 1.0) as f32;
                        let color = Color::rgb(c(1), c(2), c(3));
                        let alpha = percent(o.as_ref(), t);
                        if *stroke {
                            let mut s =
                                Stroke::solid(color, eval::scalar(w.as_ref(), t, 1.0).max(0.0));
                            s.opacity = alpha;
                            drawn.push(path_node(path, None, Some(s)));
                        } else {
                            let f = Fill {
                                paint: Paint::Solid(color),
                                opacity: alpha,
                                rule: if *rule == 2 {
                                    FillRule::EvenOdd
                                } else {
                                    FillRule::NonZero
                                },
                            };
                            drawn.push(path_node(path, Some(f), None));
                        }
                    }
                }
                ShapeKind::Transform(tr) => {
                    transform = eval::matrix(tr, t);
                    opacity = eval::opacity(tr, t);
                }
                ShapeKind::Other(ty) => {
                    let what = match ty.as_str() {
                        "tm" => "trim paths are",
                        "rd" => "round corners are",
                        "rp" => "repeaters are",
                        "mm" => "merge paths are",
                        "op" => "offset paths are",
                        "pb" => "pucker and bloat are",
                        "tw" => "twists are",
                        "zz" => "zig-zags are",
                        _ => "unknown shape items are",
                    };
                    self.warn(&item.at, format!("{what} not applied (`ty` \"{ty}\")"));
                }
            }
        }
        drawn.reverse();
        Ok((drawn, pending, transform, opacity))
    }

    /// A colour property (0–255 components in files before 4.1.9, as players upgrade them).
    fn color(&self, c: Option<&Num>, t: f64) -> Color {
        let v = eval::num(c, t, &[0.0, 0.0, 0.0]);
        let scale = if self.legacy_colors && v.iter().take(3).any(|x| *x > 1.0) {
            255.0
        } else {
            1.0
        };
        let ch = |k: usize| (v.get(k).copied().unwrap_or(0.0) / scale).clamp(0.0, 1.0) as f32;
        Color::rgb(ch(0), ch(1), ch(2))
    }
}

/// A layer's own time at composition frame `t`.
pub fn local_time(l: &Layer, t: f64) -> f64 {
    (t - l.st) / l.sr
}

fn percent(o: Option<&Num>, t: f64) -> f32 {
    (eval::scalar(o, t, 100.0) / 100.0).clamp(0.0, 1.0) as f32
}

fn joined(paths: &[BezPath]) -> Option<BezPath> {
    let mut out = BezPath::new();
    for p in paths {
        out.extend(p.iter());
    }
    (!out.elements().is_empty()).then_some(out)
}

fn path_node(path: BezPath, fill: Option<Fill>, stroke: Option<Stroke>) -> Node {
    Node::Path(PathNode {
        id: String::new(),
        path,
        fill,
        stroke,
        stroke_first: false,
        unit: None,
    })
}

/// A star (`sy` 1) or polygon (`sy` 2) with `points` points, the first straight up (turned
/// by `rotation` degrees clockwise).
fn star(sy: i64, c: Point, outer: f64, inner: f64, rotation: f64, points: f64) -> BezPath {
    let n = (points.round() as i64).clamp(2, 1000) as usize;
    let polygon = sy == 2;
    let count = if polygon { n } else { 2 * n };
    let mut path = BezPath::new();
    for k in 0..count {
        let angle =
            (rotation - 90.0).to_radians() + std::f64::consts::TAU * k as f64 / count as f64;
        let r = if polygon || k % 2 == 0 { outer } else { inner };
        let p = c + Vec2::new(angle.cos(), angle.sin()) * r;
        if k == 0 {
            path.move_to(p);
        } else {
            path.line_to(p);
        }
    }
    path.close_path();
    path
}
