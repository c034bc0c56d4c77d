//! The document at the reference frame as a scene tree: every drawn layer a group with its
//! world transform (parenting resolved) and opacity, shape layers' items as painted paths,
//! precompositions expanded, track mattes as masks.

use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

use kurbo::{Affine, BezPath, Point, Rect, Shape as _, Vec2};

use gmotion::color::Color;
use gmotion::scene::{
    ClipPath, Fill, FillRule, Group, ImageFormat, ImageNode, LineCap, LineJoin, LinearGradient,
    Mask, MaskKind, Node, Paint, PathNode, RadialGradient, Spread, Stop, Stroke,
};

use crate::model::{
    Asset, Document, Gradient, Layer, LayerKind, LayerMask, Loc, Num, Result, ShapeItem, ShapeKind,
    StrokeStyle, error,
};
use crate::offset::{Join, Offset};
use crate::{effects, eval, outline, text};

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
    /// Items repeaters may still copy ([`MAX_REPEATED`]).
    repeat_budget: usize,
    /// Points zig-zags may still add ([`outline::MAX_RIDGE_POINTS`]).
    ridge_budget: usize,
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
            repeat_budget: MAX_REPEATED,
            ridge_budget: outline::MAX_RIDGE_POINTS,
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
                base *= eval::matrix(&l.ks, t);
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
    /// children in paint order. With `part`, a shape layer draws only that top-level item
    /// of its `shapes` among those with outlines of their own ([`ShapeKind::part_name`]),
    /// styled and modified by the layer's other items as in the whole layer.
    pub fn layer_node(
        &mut self,
        l: &Layer,
        world: Affine,
        t: f64,
        stack: &mut Vec<String>,
        part: Option<usize>,
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
        // Keyframe times are in the time of the composition the layer is in (lottie-web
        // subtracts the layer's start time from both the time and the keyframes'), so
        // properties are read at `t`; only a precomposition's content runs on its own
        // clock.
        let lt = t;
        if l.ks.has_expression() {
            self.warn(
                &l.at.key("ks"),
                "expressions are not run; their properties' own values are used",
            );
        }
        let mut children = Vec::new();
        match l.kind {
            LayerKind::Shape => {
                let mut outlines = Outlines::default();
                let scope = self.items(&l.shapes, lt, &mut outlines, part)?;
                let cut;
                (children, cut) = outlines.finish(scope.drawn, &mut self.ridge_budget);
                if cut {
                    self.warn(&l.at.key("shapes"), ridges_cut());
                }
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
                let asset = l
                    .ref_id
                    .as_deref()
                    .and_then(|id| self.assets.get(id))
                    .copied();
                let (w, h) = asset.map_or((0.0, 0.0), |a| (a.w.unwrap_or(0.0), a.h.unwrap_or(0.0)));
                let oversized = asset.and_then(|a| a.oversized);
                if let Some((pw, ph)) = oversized {
                    self.warn(
                        &l.at,
                        format!("image not drawn: it declares {pw} × {ph} pixels, more than the limit (raise it with --limit image-pixels=N) or proportions no renderer places; its rectangle is measured"),
                    );
                }
                let data = match asset.map(|a| &a.image) {
                    _ if oversized.is_some() => None,
                    Some(Ok(picture)) => picture.clone(),
                    Some(Err(why)) => {
                        self.warn(
                            &l.at,
                            format!("image not drawn: {why}; its rectangle is measured"),
                        );
                        None
                    }
                    None => {
                        self.warn(
                            &l.at.key("refId"),
                            "image not drawn: no image asset has this id; nothing is measured",
                        );
                        None
                    }
                };
                match data {
                    Some((data, format)) => children.push(Node::Image(ImageNode {
                        id: String::new(),
                        data,
                        format,
                        width: w,
                        height: h,
                        smooth: true,
                        unit: None,
                    })),
                    None => children.push(path_node(
                        Rect::new(0.0, 0.0, w, h).to_path(0.1),
                        None,
                        None,
                    )),
                }
            }
            LayerKind::Text => children = self.text(l, lt)?,
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
                    None => inner_time(l, t),
                };
                stack.push(id);
                let nodes = self.comp_nodes(layers, inner, stack);
                stack.pop();
                children = nodes?;
                // Players clip a precomposition to its own size.
                if let (Some(w), Some(h)) = (l.w, l.h) {
                    children = vec![Node::Group(Group {
                        clip_path: Some(Arc::new(ClipPath {
                            id: String::new(),
                            transform: Affine::IDENTITY,
                            clip_path: None,
                            root: Group {
                                children: vec![path_node(
                                    Rect::new(0.0, 0.0, w, h).to_path(0.1),
                                    Some(Fill::solid(Color::WHITE)),
                                    None,
                                )],
                                ..Group::new()
                            },
                        })),
                        children,
                        ..Group::new()
                    })];
                }
            }
            LayerKind::Null | LayerKind::Other(_) => {}
        }
        // Effects draw in the layer's coordinates, over the whole (wide) canvas.
        let filter = match world.determinant() {
            d if d != 0.0 && !l.effects.is_empty() => {
                let region = world
                    .inverse()
                    .transform_rect_bbox(Canvas::of(self.doc).area);
                let mut warnings = Vec::new();
                let f = effects::filter(&l.effects, lt, region, &mut |at, m| {
                    warnings.push((at.clone(), m));
                });
                for (at, m) in warnings {
                    self.warn(&at, m);
                }
                f.map(Arc::new)
            }
            _ => None,
        };
        let group = Group {
            transform: world,
            opacity: eval::opacity(&l.ks, lt) as f32,
            filter,
            children,
            ..Group::new()
        };
        Ok(match self.layer_masks(l, world, lt) {
            // The mask is in canvas space: it wraps the layer rather than moving with it.
            Some(mask) => Group {
                children: vec![Node::Group(group)],
                mask: Some(mask),
                ..Group::new()
            },
            None => group,
        })
    }

    /// A text layer's letters at frame `t`, drawn from the file's glyphs ([`text`]); a
    /// point at the anchor when there is nothing it can draw.
    fn text(&mut self, l: &Layer, t: f64) -> Result<Vec<Node>> {
        let fonts = &self.doc.fonts;
        let data = l.text.as_ref();
        let placed = data.map_or_else(Vec::new, |d| text::letters(d, fonts, t));
        if let Some(d) = data {
            if d.on_path {
                self.warn(&d.at.key("p"), "text on a path is set on a straight line");
            }
            if d.expression {
                self.warn(
                    &d.at.key("d"),
                    "expressions are not run; the text's own documents are used",
                );
            }
            for a in &d.animators {
                if a.turns_3d {
                    self.warn(
                        &a.at.key("a"),
                        "3D letter rotation (`rx`, `ry`) is not drawn",
                    );
                }
                if a.selector.random {
                    self.warn(&a.at.key("s"), "randomised text selectors are applied in order (players shuffle at random)");
                }
                if a.selector.expression {
                    self.warn(
                        &a.at.key("s"),
                        "expression text selectors are not run; applied as range selectors",
                    );
                }
            }
            let shown = d.document(t).is_some_and(|doc| !doc.text.trim().is_empty());
            if shown && fonts.glyphs.is_empty() {
                self.warn(&l.at, "text not drawn: the file embeds no glyph outlines (`chars`), and players draw it with the user's fonts; measured as a point at its anchor");
            }
        }
        if placed.is_empty() {
            let a = eval::vec2(l.ks.a.as_ref(), t, Vec2::ZERO);
            let r = Rect::from_center_size(a.to_point(), (1.0, 1.0));
            return Ok(vec![path_node(r.to_path(0.1), None, None)]);
        }
        let mut outlines: HashMap<usize, BezPath> = HashMap::new();
        let mut nodes = Vec::with_capacity(placed.len());
        for letter in placed {
            let outline = match outlines.get(&letter.glyph) {
                Some(o) => o.clone(),
                None => {
                    let o = self.glyph_outline(letter.glyph)?;
                    outlines.insert(letter.glyph, o.clone());
                    o
                }
            };
            let color = |c: [f64; 3]| {
                let ch = |v: f64| v.clamp(0.0, 1.0) as f32;
                Color::rgb(ch(c[0]), ch(c[1]), ch(c[2]))
            };
            // lottie-web strokes letters with butt caps, round joins and a miter limit of 4.
            let stroke = letter.stroke.map(|(c, w)| Stroke {
                join: LineJoin::Round,
                ..Stroke::solid(color(c), w)
            });
            let fill = letter.fill.map(|c| Fill::solid(color(c)));
            if fill.is_none() && stroke.is_none() {
                continue;
            }
            nodes.push(Node::Group(Group {
                transform: letter.transform,
                opacity: letter.opacity as f32,
                children: vec![path_node(
                    Affine::scale(letter.glyph_scale) * outline,
                    fill,
                    stroke,
                )],
                ..Group::new()
            }));
        }
        Ok(nodes)
    }

    /// The outline of glyph `glyph` (an index into the document's glyphs) at size 100: the
    /// one made from a system font, else its shape items at their first frame.
    pub(crate) fn glyph_outline(&mut self, glyph: usize) -> Result<BezPath> {
        let glyph = &self.doc.fonts.glyphs[glyph];
        match &glyph.outline {
            Some(o) => Ok(o.clone()),
            None => self.unstyled(&glyph.shapes),
        }
    }

    /// Every outline of `items` at their first frame, with no style of their own (a glyph,
    /// painted by its text layer).
    fn unstyled(&mut self, items: &[ShapeItem]) -> Result<BezPath> {
        let mut outlines = Outlines::default();
        let scope = self.items(items, 0.0, &mut outlines, None)?;
        // Glyphs are small and made once each; zig-zags in them count all the same.
        if outlines.modify(&mut self.ridge_budget) {
            self.warn(&Loc::root().key("chars"), ridges_cut());
        }
        let mut path = BezPath::new();
        for (id, m) in scope.visible {
            path.extend(outlines.paths[id].iter().map(|el| m * el));
        }
        Ok(path)
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
            let node = self.drawn(layers, i, &worlds, t, stack, None)?;
            out.push(Node::Group(node));
        }
        Ok(out)
    }

    /// Layer `i` drawn, with its track matte when it has one; with `part`, only that part
    /// of a shape layer ([`Builder::layer_node`]).
    pub fn drawn(
        &mut self,
        layers: &[Layer],
        i: usize,
        worlds: &[Affine],
        t: f64,
        stack: &mut Vec<String>,
        part: Option<usize>,
    ) -> Result<Group> {
        let l = &layers[i];
        let node = self.layer_node(l, worlds[i], t, stack, part)?;
        let Some(m) = Self::matte_source(layers, i) else {
            if l.tt.is_some_and(|tt| tt != 0) {
                self.warn(
                    &l.at.key("tt"),
                    "a track matte without its matte layer; drawn unmatted",
                );
            }
            return Ok(node);
        };
        let (kind, inverted) = match l.tt {
            Some(1) => (MaskKind::Alpha, false),
            Some(2) => (MaskKind::Alpha, true),
            Some(3) => (MaskKind::Luminance, false),
            Some(4) => (MaskKind::Luminance, true),
            _ => {
                self.warn(
                    &l.at.key("tt"),
                    "an unknown track matte mode; drawn unmatted",
                );
                return Ok(node);
            }
        };
        let source = self.layer_node(&layers[m], worlds[m], t, stack, None)?;
        let canvas = Canvas::of(self.doc);
        let mask = |kind, children| canvas.mask(kind, children);
        let everywhere = |color| canvas.everywhere(color);
        let mut matte = mask(kind, vec![Node::Group(source)]);
        if inverted {
            // 1 − coverage: black painted through the matte over white, read as luminance.
            let through = Group {
                children: vec![everywhere(Color::BLACK)],
                mask: Some(matte),
                ..Group::new()
            };
            matte = mask(
                MaskKind::Luminance,
                vec![everywhere(Color::WHITE), Node::Group(through)],
            );
        }
        Ok(Group {
            children: vec![Node::Group(node)],
            mask: Some(matte),
            ..Group::new()
        })
    }

    /// Shape items at layer frame `t`, read into `out`: what they paint (topmost first)
    /// and which outlines are visible to styles further down, with the group's transform
    /// and opacity. Painting waits until every modifier has changed the outlines
    /// ([`Outlines::finish`]): in Lottie a modifier below a style still changes what the
    /// style paints, and a modifier changes the outlines of nested groups too. With `part`,
    /// the items with outlines of their own other than item `part` are left out.
    fn items(
        &mut self,
        items: &[ShapeItem],
        t: f64,
        out: &mut Outlines,
        part: Option<usize>,
    ) -> Result<Scope> {
        let mut scope = Scope {
            drawn: Vec::new(),
            visible: Vec::new(),
            transform: Affine::IDENTITY,
            opacity: 1.0,
        };
        for (k, item) in items.iter().enumerate() {
            if item.hidden || part.is_some_and(|p| p != k && item.kind.part_name().is_some()) {
                continue;
            }
            let mut add = |path: BezPath, scope: &mut Scope| {
                scope.visible.push((out.paths.len(), Affine::IDENTITY));
                out.paths.push(path);
            };
            match &item.kind {
                ShapeKind::Group(sub) => {
                    let inner = self.items(sub, t, out, None)?;
                    let m = inner.transform;
                    scope
                        .visible
                        .extend(inner.visible.into_iter().map(|(id, a)| (id, m * a)));
                    if !inner.drawn.is_empty() && inner.opacity > 0.0 {
                        scope.drawn.push(Draw::Group {
                            id: item.nm.clone(),
                            transform: m,
                            opacity: inner.opacity as f32,
                            children: inner.drawn,
                        });
                    }
                }
                ShapeKind::Path { ks, closed } => {
                    let mut closed = *closed;
                    if closed.is_none() && self.doc.older_than((4, 4, 18)) {
                        closed = Some(false);
                    }
                    add(eval::outline(ks, t, closed), &mut scope);
                }
                ShapeKind::Rect { p, s, r, reversed } => {
                    let c = eval::vec2(p.as_ref(), t, Vec2::ZERO).to_point();
                    let s = eval::vec2(s.as_ref(), t, Vec2::ZERO);
                    let r = eval::scalar(r.as_ref(), t, 0.0);
                    add(outline::rect(c, s, r, *reversed), &mut scope);
                }
                ShapeKind::Ellipse { p, s, reversed } => {
                    let c = eval::vec2(p.as_ref(), t, Vec2::ZERO).to_point();
                    let s = eval::vec2(s.as_ref(), t, Vec2::ZERO);
                    add(outline::ellipse(c, s, *reversed), &mut scope);
                }
                ShapeKind::Star {
                    sy,
                    p,
                    or,
                    ir,
                    r,
                    pt,
                    reversed,
                } => {
                    let path = star(
                        *sy,
                        eval::vec2(p.as_ref(), t, Vec2::ZERO).to_point(),
                        eval::scalar(or.as_ref(), t, 0.0),
                        eval::scalar(ir.as_ref(), t, 0.0),
                        eval::scalar(r.as_ref(), t, 0.0),
                        eval::scalar(pt.as_ref(), t, 5.0),
                    );
                    add(
                        if *reversed {
                            path.reverse_subpaths()
                        } else {
                            path
                        },
                        &mut scope,
                    );
                }
                ShapeKind::Fill { c, o, rule } => {
                    let fill = Fill {
                        paint: Paint::Solid(self.color(c.as_ref(), t)),
                        opacity: percent(o.as_ref(), t),
                        rule: fill_rule(*rule),
                    };
                    scope.paint(Some(fill), None);
                }
                ShapeKind::Stroke { c, o, w, style } => {
                    let mut stroke = Stroke::solid(
                        self.color(c.as_ref(), t),
                        eval::scalar(w.as_ref(), t, 1.0).max(0.0),
                    );
                    stroke.opacity = percent(o.as_ref(), t);
                    styled(&mut stroke, style, t);
                    scope.paint(None, Some(stroke));
                }
                ShapeKind::Gradient(g) => {
                    let paint = gradient(&g.gradient, t);
                    let opacity = percent(g.o.as_ref(), t);
                    if g.stroke {
                        let width = eval::scalar(g.w.as_ref(), t, 1.0).max(0.0);
                        let mut s = Stroke::solid(Color::BLACK, width);
                        s.paint = paint;
                        s.opacity = opacity;
                        styled(&mut s, &g.style, t);
                        scope.paint(None, Some(s));
                    } else {
                        let f = Fill {
                            paint,
                            opacity,
                            rule: fill_rule(g.rule),
                        };
                        scope.paint(Some(f), None);
                    }
                }
                ShapeKind::Trim {
                    s,
                    e,
                    o,
                    individually,
                } => {
                    let trim = outline::Trim {
                        start: eval::scalar(s.as_ref(), t, 0.0) / 100.0,
                        end: eval::scalar(e.as_ref(), t, 100.0) / 100.0,
                        offset: eval::scalar(o.as_ref(), t, 0.0),
                        individually: *individually,
                    };
                    out.modifiers
                        .push((Modifier::Trim(trim), scope.outline_ids()));
                }
                ShapeKind::RoundCorners { r } => {
                    let radius = eval::scalar(r.as_ref(), t, 0.0);
                    out.modifiers
                        .push((Modifier::Round(radius), scope.outline_ids()));
                }
                ShapeKind::PuckerBloat { a } => {
                    let amount = eval::scalar(a.as_ref(), t, 0.0);
                    out.modifiers
                        .push((Modifier::PuckerBloat(amount), scope.outline_ids()));
                }
                ShapeKind::OffsetPath { a, lj, ml } => {
                    let offset = Offset {
                        amount: eval::scalar(a.as_ref(), t, 0.0),
                        join: Join::from_code(*lj),
                        miter_limit: eval::scalar(ml.as_ref(), t, 4.0),
                    };
                    out.modifiers
                        .push((Modifier::Offset(offset), scope.outline_ids()));
                }
                ShapeKind::ZigZag { s, r, pt } => {
                    let zz = outline::ZigZag {
                        size: eval::scalar(s.as_ref(), t, 0.0),
                        // lottie-web rounds the ridge count.
                        ridges: eval::scalar(r.as_ref(), t, 0.0).round().max(0.0),
                        smooth: eval::scalar(pt.as_ref(), t, 1.0) == 2.0,
                    };
                    out.modifiers
                        .push((Modifier::ZigZag(zz), scope.outline_ids()));
                }
                ShapeKind::Repeater {
                    c,
                    o,
                    above,
                    tr,
                    so,
                    eo,
                } => {
                    let mut copies = repeats(
                        c.as_ref(),
                        o.as_ref(),
                        *above,
                        tr,
                        so.as_ref(),
                        eo.as_ref(),
                        t,
                    );
                    // Repeaters in repeaters multiply: what they copy is bounded in all.
                    let weight = (weight(&scope.drawn) + scope.visible.len()).max(1);
                    let affordable = (self.repeat_budget / weight).max(1);
                    if copies.len() > affordable {
                        self.warn(
                            &item.at,
                            format!("repeater copies past {MAX_REPEATED} repeated items in all are left out"),
                        );
                        copies.truncate(affordable);
                    }
                    self.repeat_budget = self.repeat_budget.saturating_sub(copies.len() * weight);
                    let drawn = std::mem::take(&mut scope.drawn);
                    let visible = std::mem::take(&mut scope.visible);
                    for (m, opacity) in copies {
                        scope
                            .visible
                            .extend(visible.iter().map(|&(id, a)| (id, m * a)));
                        if !drawn.is_empty() && opacity > 0.0 {
                            // Built topmost first, like the items themselves.
                            let mut children = drawn.clone();
                            children.reverse();
                            scope.drawn.push(Draw::Group {
                                id: item.nm.clone(),
                                transform: m,
                                opacity: opacity as f32,
                                children,
                            });
                        }
                    }
                }
                ShapeKind::Transform(tr) => {
                    scope.transform = eval::matrix(tr, t);
                    scope.opacity = eval::opacity(tr, t);
                }
                ShapeKind::Other(ty) => {
                    let (what, note) = match ty.as_str() {
                        "mm" => ("merge paths are", "; lottie-web does not apply them either"),
                        "tw" => ("twists are", "; lottie-web does not apply them either"),
                        _ => ("unknown shape items are", ""),
                    };
                    self.warn(
                        &item.at,
                        format!("{what} not applied (`ty` \"{ty}\"{note})"),
                    );
                }
            }
        }
        scope.drawn.reverse();
        Ok(scope)
    }

    /// Layer masks (`masksProperties`) as one luminance mask over the layer drawn with
    /// world transform `world` at layer time `t`: white where the layer shows. Masks
    /// combine in order, as After Effects and lottie-web combine them: each adds to,
    /// subtracts from or intersects with what the ones before it let through, at its
    /// opacity; coverage starts empty, or full when the first mask subtracts or
    /// intersects.
    fn layer_masks(&mut self, l: &Layer, world: Affine, t: f64) -> Option<Arc<Mask>> {
        let canvas = Canvas::of(self.doc);
        let everywhere = |color| canvas.everywhere(color);
        let active: Vec<&LayerMask> = l.masks.iter().filter(|m| m.mode != "n").collect();
        let first = active.first()?;
        let mut children = Vec::new();
        if matches!(first.mode.as_str(), "s" | "i") {
            children.push(everywhere(Color::WHITE));
        }
        for m in active {
            let Some(pt) = &m.pt else { continue };
            let mut outline = eval::outline(pt, t, None);
            outline.apply_affine(world);
            let opacity = percent(m.o.as_ref(), t);
            // Expansion (`x`, in layer units) grows the mask by a band along its outline,
            // or shrinks it, as lottie-web draws it: a stroke twice as wide (SVG's miter
            // joins) for growth, an erosion by the same radius for shrinking.
            let x = eval::scalar(m.x.as_ref(), t, 0.0);
            let band = 2.0 * x.abs() * world.determinant().abs().sqrt();
            let fill = |color: Color| path_node(outline.clone(), Some(Fill::solid(color)), None);
            let stroke =
                |color: Color| path_node(outline.clone(), None, Some(Stroke::solid(color, band)));
            let group = |children: Vec<Node>, mask: Option<Arc<Mask>>| {
                Node::Group(Group {
                    children,
                    mask,
                    ..Group::new()
                })
            };
            // The mask's coverage painted in `color`: its outline, or for an inverted
            // mask everything outside it.
            let coverage = |color: Color| -> Node {
                let node = if m.inverted {
                    // Painted through the hole the outline makes: it shrinks as the
                    // coverage grows and grows as the coverage shrinks.
                    let hole = match x {
                        0.0 => fill(Color::BLACK),
                        x if x > 0.0 => group(vec![fill(Color::BLACK), stroke(Color::WHITE)], None),
                        _ => group(vec![fill(Color::BLACK), stroke(Color::BLACK)], None),
                    };
                    group(
                        vec![everywhere(color)],
                        Some(
                            canvas.mask(MaskKind::Luminance, vec![everywhere(Color::WHITE), hole]),
                        ),
                    )
                } else {
                    match x {
                        0.0 => fill(color),
                        x if x > 0.0 => group(vec![fill(color), stroke(color)], None),
                        _ => group(
                            vec![fill(color)],
                            Some(canvas.mask(
                                MaskKind::Luminance,
                                vec![everywhere(Color::WHITE), stroke(Color::BLACK)],
                            )),
                        ),
                    }
                };
                Node::Group(Group {
                    opacity,
                    children: vec![node],
                    ..Group::new()
                })
            };
            match m.mode.as_str() {
                "a" | "l" => children.push(coverage(Color::WHITE)),
                "s" => children.push(coverage(Color::BLACK)),
                "i" | "d" => {
                    let so_far = std::mem::take(&mut children);
                    children.push(Node::Group(Group {
                        children: so_far,
                        mask: Some(canvas.mask(MaskKind::Luminance, vec![coverage(Color::WHITE)])),
                        ..Group::new()
                    }));
                }
                other => {
                    self.warn(
                        &m.at.key("mode"),
                        format!("mask mode `{other}` is drawn as add"),
                    );
                    children.push(coverage(Color::WHITE));
                }
            }
            if m.mode == "l" || m.mode == "d" {
                self.warn(
                    &m.at.key("mode"),
                    "lighten and darken masks are drawn as add and intersect",
                );
            }
        }
        Some(canvas.mask(MaskKind::Luminance, children))
    }

    /// A fill's or stroke's colour: 0–255 components in files before 4.1.9, which lottie-web
    /// (Bodymovin's own player, the only one that upgrades such files) divides by 255
    /// whatever their values, so that `[1, 1, 1]` there is near black, not white.
    fn color(&self, c: Option<&Num>, t: f64) -> Color {
        let v = eval::num(c, t, &[0.0, 0.0, 0.0]);
        let scale = if self.legacy_colors { 255.0 } else { 1.0 };
        let ch = |k: usize| (v.get(k).copied().unwrap_or(0.0) / scale).clamp(0.0, 1.0) as f32;
        Color::rgb(ch(0), ch(1), ch(2))
    }
}

/// The time inside a precomposition layer's composition at frame `t` of the composition
/// the layer is in: shifted by its start time, slowed by its stretch.
pub fn inner_time(l: &Layer, t: f64) -> f64 {
    (t - l.st) / l.sr
}

fn percent(o: Option<&Num>, t: f64) -> f32 {
    (eval::scalar(o, t, 100.0) / 100.0).clamp(0.0, 1.0) as f32
}

/// `stroke` with the caps, joins and dashes of `style` at time `t`.
fn styled(stroke: &mut Stroke, style: &StrokeStyle, t: f64) {
    stroke.cap = match style.lc {
        1 => LineCap::Butt,
        3 => LineCap::Square,
        _ => LineCap::Round,
    };
    stroke.join = match style.lj {
        1 => LineJoin::Miter,
        3 => LineJoin::Bevel,
        _ => LineJoin::Round,
    };
    // 4 is the format's default miter limit.
    stroke.miter_limit = style.ml.unwrap_or(4.0).max(1.0);
    let mut dash = Vec::new();
    for d in &style.dashes {
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
}

/// The composition's canvas with a wide margin: the region of the masks built for layer
/// masks and track mattes, which must not clip what moves beyond the canvas.
struct Canvas {
    area: Rect,
}

impl Canvas {
    fn of(doc: &Document) -> Canvas {
        let margin = 10.0 * doc.w.max(doc.h);
        Canvas {
            area: Rect::new(-margin, -margin, doc.w + margin, doc.h + margin),
        }
    }

    /// A mask of `kind` drawing `children`.
    fn mask(&self, kind: MaskKind, children: Vec<Node>) -> Arc<Mask> {
        Arc::new(Mask {
            id: String::new(),
            rect: self.area,
            kind,
            mask: None,
            root: Group {
                children,
                ..Group::new()
            },
        })
    }

    /// The whole area painted `color`.
    fn everywhere(&self, color: Color) -> Node {
        path_node(self.area.to_path(0.1), Some(Fill::solid(color)), None)
    }
}

fn fill_rule(rule: i64) -> FillRule {
    if rule == 2 {
        FillRule::EvenOdd
    } else {
        FillRule::NonZero
    }
}

/// What one group of shape items holds once read: what it paints (topmost first until
/// [`Builder::items`] returns, then in paint order), the outlines styles below it in its
/// parent see (ids into [`Outlines::paths`], each with its transform into this group's
/// space), and the group's own transform and opacity.
struct Scope {
    drawn: Vec<Draw>,
    visible: Vec<(usize, Affine)>,
    transform: Affine,
    opacity: f64,
}

impl Scope {
    /// The outlines visible so far, each once (a repeater shows one several times).
    fn outline_ids(&self) -> Vec<usize> {
        let mut seen = std::collections::HashSet::new();
        self.visible
            .iter()
            .map(|v| v.0)
            .filter(|id| seen.insert(*id))
            .collect()
    }

    /// A style painting every outline visible so far.
    fn paint(&mut self, fill: Option<Fill>, stroke: Option<Stroke>) {
        self.drawn.push(Draw::Paint {
            fill,
            stroke,
            outlines: self.visible.clone(),
        });
    }
}

/// Painting that waits for the outlines' final geometry.
#[derive(Clone)]
enum Draw {
    /// A fill or stroke of outlines (ids into [`Outlines::paths`], with transforms).
    Paint {
        fill: Option<Fill>,
        stroke: Option<Stroke>,
        outlines: Vec<(usize, Affine)>,
    },
    /// A nested group of shape items.
    Group {
        id: String,
        transform: Affine,
        opacity: f32,
        children: Vec<Draw>,
    },
}

/// Every outline of a shape layer, and the modifiers that change them (in the order
/// they apply: nested groups' before their parents', each with the outlines it takes).
#[derive(Default)]
pub(crate) struct Outlines {
    paths: Vec<BezPath>,
    modifiers: Vec<(Modifier, Vec<usize>)>,
}

/// The warning for zig-zags cut short by [`outline::MAX_RIDGE_POINTS`].
fn ridges_cut() -> String {
    format!(
        "zig-zags past {} added points in all are drawn with fewer ridges",
        outline::MAX_RIDGE_POINTS
    )
}

/// A shape modifier, with what it needs to change outlines.
enum Modifier {
    /// Trim paths (`tm`).
    Trim(outline::Trim),
    /// Round corners (`rd`) of this radius.
    Round(f64),
    /// Pucker and bloat (`pb`) by this percentage.
    PuckerBloat(f64),
    /// Zig-zags (`zz`).
    ZigZag(outline::ZigZag),
    /// Offset paths (`op`).
    Offset(Offset),
}

/// A repeater's copies at layer time `t`, topmost first: each one's transform and opacity,
/// as lottie-web's `RepeaterModifier` makes them. Copy `k` (counted from the offset) is
/// turned `k` times about the anchor, then scaled `k` times about it, then moved `k`
/// times (each step a fraction of a whole one for a fractional offset); opacity runs from
/// the start opacity to the end opacity over the copies.
fn repeats(
    c: Option<&Num>,
    o: Option<&Num>,
    above: bool,
    tr: &crate::model::Transform,
    so: Option<&Num>,
    eo: Option<&Num>,
    t: f64,
) -> Vec<(Affine, f64)> {
    let copies = eval::scalar(c, t, 1.0)
        .ceil()
        .clamp(0.0, MAX_REPEATS as f64) as usize;
    let offset = eval::scalar(o, t, 0.0);
    let a = eval::vec2(tr.a.as_ref(), t, Vec2::ZERO);
    let p = eval::position(tr.p.as_ref(), t);
    let s = eval::vec2(tr.s.as_ref(), t, Vec2::new(100.0, 100.0)) / 100.0;
    let r = eval::scalar(tr.r.as_ref(), t, 0.0).to_radians();
    let (so, eo) = (
        eval::scalar(so, t, 100.0) / 100.0,
        eval::scalar(eo, t, 100.0) / 100.0,
    );
    // One step (or a fraction `f` of one, backwards when `f` is negative) on each matrix.
    let (mut pm, mut rm, mut sm) = (Affine::IDENTITY, Affine::IDENTITY, Affine::IDENTITY);
    let step = |f: f64, pm: &mut Affine, rm: &mut Affine, sm: &mut Affine| {
        let inv = f < 0.0;
        let f = f.abs();
        let dir = if inv { -1.0 } else { 1.0 };
        let sx = s.x + (1.0 - s.x) * (1.0 - f);
        let sy = s.y + (1.0 - s.y) * (1.0 - f);
        let (sx, sy) = if inv { (1.0 / sx, 1.0 / sy) } else { (sx, sy) };
        *pm = Affine::translate(p * dir * f) * *pm;
        *rm = Affine::translate(a) * Affine::rotate(r * dir * f) * Affine::translate(-a) * *rm;
        *sm =
            Affine::translate(a) * Affine::scale_non_uniform(sx, sy) * Affine::translate(-a) * *sm;
    };
    let whole = offset.trunc();
    let part = offset - whole;
    for _ in 0..(whole.abs().min(MAX_REPEATS as f64) as usize) {
        step(offset.signum(), &mut pm, &mut rm, &mut sm);
    }
    if part != 0.0 {
        step(part, &mut pm, &mut rm, &mut sm);
    }
    let mut out = vec![(Affine::IDENTITY, 1.0); copies];
    let order: Vec<usize> = if above {
        (0..copies).collect()
    } else {
        (0..copies).rev().collect()
    };
    let mut iteration = offset;
    for (n, &i) in order.iter().enumerate() {
        let opacity = if copies == 1 {
            so
        } else {
            so + (eo - so) * (i as f64 / (copies - 1) as f64)
        };
        let m = if iteration != 0.0 {
            if n > 0 {
                step(1.0, &mut pm, &mut rm, &mut sm);
            }
            pm * sm * rm
        } else {
            Affine::IDENTITY
        };
        out[i] = (m, opacity.clamp(0.0, 1.0));
        iteration += 1.0;
    }
    out
}

/// Most copies one repeater draws.
pub const MAX_REPEATS: usize = 1000;

/// Most items (paints, groups, outlines) repeaters copy in one drawing: each copies
/// everything above it, so repeaters nested in repeaters multiply.
pub const MAX_REPEATED: usize = 50_000;

/// How many items `drawn` holds, nested ones and outline references included.
fn weight(drawn: &[Draw]) -> usize {
    drawn
        .iter()
        .map(|d| match d {
            Draw::Paint { outlines, .. } => 1 + outlines.len(),
            Draw::Group { children, .. } => 1 + weight(children),
        })
        .sum()
}

impl Outlines {
    /// Applies the modifiers, then turns `drawn` into scene nodes; also whether zig-zags
    /// were cut short by `ridge_budget`.
    fn finish(mut self, drawn: Vec<Draw>, ridge_budget: &mut usize) -> (Vec<Node>, bool) {
        let cut = self.modify(ridge_budget);
        (self.nodes(drawn), cut)
    }

    /// Applies the modifiers to the outlines they take; whether zig-zags were cut short.
    fn modify(&mut self, ridge_budget: &mut usize) -> bool {
        let mut cut = false;
        for (modifier, ids) in std::mem::take(&mut self.modifiers) {
            let mut taken: Vec<BezPath> = ids
                .iter()
                .map(|&i| std::mem::take(&mut self.paths[i]))
                .collect();
            match modifier {
                Modifier::Trim(trim) => trim.apply(&mut taken),
                Modifier::Round(radius) => {
                    for p in &mut taken {
                        *p = outline::round_corners(p, radius);
                    }
                }
                Modifier::PuckerBloat(amount) => {
                    for p in &mut taken {
                        *p = outline::pucker_bloat(p, amount);
                    }
                }
                Modifier::Offset(offset) => {
                    for p in &mut taken {
                        *p = offset.apply(p);
                    }
                }
                Modifier::ZigZag(zz) => {
                    for p in &mut taken {
                        let short;
                        (*p, short) = zz.apply(p, ridge_budget);
                        cut |= short;
                    }
                }
            }
            for (&i, p) in ids.iter().zip(taken) {
                self.paths[i] = p;
            }
        }
        cut
    }

    fn nodes(&self, drawn: Vec<Draw>) -> Vec<Node> {
        drawn
            .into_iter()
            .filter_map(|d| match d {
                Draw::Paint {
                    fill,
                    stroke,
                    outlines,
                } => {
                    let mut path = BezPath::new();
                    for (id, m) in outlines {
                        path.extend(self.paths[id].iter().map(|el| m * el));
                    }
                    (!path.elements().is_empty()).then(|| path_node(path, fill, stroke))
                }
                Draw::Group {
                    id,
                    transform,
                    opacity,
                    children,
                } => {
                    let children = self.nodes(children);
                    (!children.is_empty()).then(|| {
                        Node::Group(Group {
                            id,
                            transform,
                            opacity,
                            children,
                            ..Group::new()
                        })
                    })
                }
            })
            .collect()
    }
}

/// A gradient fill's or stroke's paint at layer time `t`: colour stops with the opacity
/// stops merged in (each offset of either gets both), in the item's own space; a radial
/// gradient's focus placed by its highlight as lottie-web places it.
fn gradient(g: &Gradient, t: f64) -> Paint {
    let Gradient {
        s: start,
        e: end,
        h: highlight,
        a: angle,
        g: stops,
        ..
    } = g;
    let v = eval::num(stops.k.as_ref(), t, &[]);
    let n = stops.p.min(v.len() / 4);
    let colors: Vec<(f64, Color)> = (0..n)
        .map(|i| {
            let c = |k: usize| v[4 * i + k].clamp(0.0, 1.0) as f32;
            (v[4 * i], Color::rgb(c(1), c(2), c(3)))
        })
        .collect();
    let alphas: Vec<(f64, f64)> = v[4 * n..]
        .chunks_exact(2)
        .map(|p| (p[0], p[1].clamp(0.0, 1.0)))
        .collect();
    let mut offsets: Vec<f64> = colors
        .iter()
        .map(|c| c.0)
        .chain(alphas.iter().map(|a| a.0))
        .collect();
    offsets.sort_by(f64::total_cmp);
    offsets.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
    let stops: Vec<Stop> = if colors.is_empty() {
        vec![Stop {
            offset: 0.0,
            color: Color::BLACK,
        }]
    } else {
        offsets
            .iter()
            .map(|&x| {
                let mut color = at_offset(&colors, x, Color::BLACK, |a, b, u| a.lerp(b, u as f32));
                color.a = at_offset(&alphas, x, 1.0, |a, b, u| a + (b - a) * u) as f32;
                Stop {
                    offset: x.clamp(0.0, 1.0) as f32,
                    color,
                }
            })
            .collect()
    };
    let s = eval::vec2(start.as_ref(), t, Vec2::ZERO).to_point();
    let e = eval::vec2(end.as_ref(), t, Vec2::ZERO).to_point();
    if g.radial() {
        let radius = (e - s).hypot();
        let h = (eval::scalar(highlight.as_ref(), t, 0.0) / 100.0).clamp(-0.99, 0.99);
        let a = (e - s).atan2() + eval::scalar(angle.as_ref(), t, 0.0).to_radians();
        Paint::Radial(Arc::new(RadialGradient {
            id: String::new(),
            center: s,
            radius,
            focal: s + Vec2::from_angle(a) * radius * h,
            focal_radius: 0.0,
            transform: Affine::IDENTITY,
            spread: Spread::Pad,
            stops,
        }))
    } else {
        Paint::Linear(Arc::new(LinearGradient {
            id: String::new(),
            start: s,
            end: e,
            transform: Affine::IDENTITY,
            spread: Spread::Pad,
            stops,
        }))
    }
}

/// The value of piecewise-linear `stops` (sorted by offset) at `x`, held past the ends;
/// `none` when there are no stops.
fn at_offset<T: Copy>(stops: &[(f64, T)], x: f64, none: T, lerp: impl Fn(T, T, f64) -> T) -> T {
    let i = stops.partition_point(|s| s.0 <= x);
    match (i.checked_sub(1).map(|j| stops[j]), stops.get(i)) {
        (Some(a), Some(b)) if b.0 > a.0 => lerp(a.1, b.1, (x - a.0) / (b.0 - a.0)),
        (Some(a), _) => a.1,
        (None, Some(b)) => b.1,
        (None, None) => none,
    }
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

/// An image asset's picture when it is embedded: a `data:` URL holding base64 of a PNG,
/// JPEG, GIF or WebP file (told apart by its first bytes, as players do, not by the URL's
/// type, which exporters spell variously: `image/jpg`, `image/png`, none).
/// An image's bytes and format.
pub type Picture = (Arc<[u8]>, ImageFormat);

/// The picture of a `data:` URL (base64), if it is a PNG, JPEG, GIF or WebP image.
pub fn embedded_image(p: &str) -> Option<Picture> {
    use base64::Engine as _;
    let rest = p.strip_prefix("data:")?;
    let (head, body) = rest.split_once(',')?;
    if !head.ends_with(";base64") {
        return None;
    }
    let data = base64::engine::general_purpose::STANDARD
        .decode(body.trim())
        .ok()?;
    let format = ImageFormat::sniff(&data)?;
    Some((Arc::from(data), format))
}
