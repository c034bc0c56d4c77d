//! usvg tree → scene tree, choosing and tagging the animated units on the way.
//!
//! usvg adds groups of its own (for an element's transform or opacity) and drops ids inside
//! `use` instances; units and tags are therefore decided on source elements, found through
//! the ids [`Source`] guarantees, never on usvg's structure.

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use kurbo::{Affine, BezPath, Point, Rect};
use usvg::roxmltree::NodeId;
use usvg::tiny_skia_path::PathSegment;

use super::filters;
use super::source::{Scope, Source};
use super::{ImportOptions, Units};
use gmotion::color::Color;
use gmotion::scene::{
    ClipPath, Fill, FillRule, Group, ImageFormat, ImageNode, LineCap, LineJoin, LinearGradient,
    Mask, MaskKind, Node, Paint, PathNode, Pattern, RadialGradient, Spread, Stop, Stroke,
};

/// An animated unit found during conversion.
pub(super) struct Unit {
    pub tag: String,
    /// Ids it answers to besides its tag ([`Source::aliases`]).
    pub aliases: Vec<String>,
    pub node_path: Vec<usize>,
    pub parent_transform: Affine,
    /// A text unit's letters, words and lines.
    pub text: Option<Arc<gmotion::text::TextLayout>>,
}

/// The converted tree with its units (in paint order) and warnings.
pub(super) struct Converted {
    pub root: Group,
    pub units: Vec<Unit>,
    pub warnings: Vec<(String, String)>,
}

/// Converts a usvg tree parsed from `src.prepared`.
pub(super) fn convert<'s>(
    tree: &usvg::Tree,
    src: &'s Source,
    opts: &ImportOptions,
    fonts: &'s usvg::fontdb::Database,
    policy: &'s crate::Policy,
) -> Converted {
    let mut c = Converter {
        src,
        fonts,
        font_options: &policy.fonts,
        opts: opts.clone(),
        warnings: Vec::new(),
        warned: HashSet::new(),
        ids: HashSet::new(),
        linear: HashMap::new(),
        radial: HashMap::new(),
        gradients: HashMap::new(),
        patterns: HashMap::new(),
        clips: HashMap::new(),
        masks: HashMap::new(),
        units: Vec::new(),
        path: Vec::new(),
        zip: None,
        baked_pixels: 0.0,
        max_baked_pixels: policy.max_baked_pixels as f64,
        max_image_pixels: policy.max_image_pixels,
    };
    let root_elem = src.doc.root_element();
    let mut ctx = Ctx {
        scope: src.scope(root_elem, Scope::default(), opts.tag_from, None),
        abs: Affine::IDENTITY,
        units: true,
        near: None,
    };
    let mut root = Group::new();
    // The `<svg>` element's id (Illustrator's `Layer_1`) names the root group, as a `<g>`'s
    // id names its group: exporters keep it as the outermost group's name.
    if let Some(id) = root_elem.attribute("id") {
        root.id = c.keep_id(id);
    }
    let top = tree.root();
    // The viewBox mapping arrives as usvg's only top-level group; it becomes the root's
    // transform, as the scene model documents.
    match top.children() {
        [usvg::Node::Group(g)] if g.id().is_empty() && is_plain(g) => {
            root.transform = affine(g.transform());
            ctx.abs = root.transform;
            c.children(g, &mut root, ctx);
        }
        _ => c.children(top, &mut root, ctx),
    }
    // Sides as every output rounds them (`gmotion::canvas::pixels`).
    let (w, h) = (
        gmotion::canvas::pixels(f64::from(tree.size().width())),
        gmotion::canvas::pixels(f64::from(tree.size().height())),
    );
    let canvas_pixels = u64::from(w) * u64::from(h);
    if canvas_pixels > policy.max_canvas_pixels {
        c.warn(
            Some(root_elem.id()),
            &format!(
                "its canvas, {w} × {h} px, has {canvas_pixels} pixels, more than the limit of {}: a PNG, GIF, APNG or video at the canvas's size is refused (give --width or --height, or raise --limit pixels=N)",
                policy.max_canvas_pixels
            ),
        );
    }
    for e in filters::unread_css_filters(&src.doc) {
        c.warn(
            Some(e.id()),
            "CSS filter ignored (usvg cannot read a function inside one, such as rgba(…); write the colour as #RRGGBBAA)",
        );
    }
    Converted {
        root,
        units: c.units,
        warnings: c.warnings,
    }
}

/// A group that only transforms.
fn is_plain(g: &usvg::Group) -> bool {
    g.opacity() == usvg::Opacity::ONE
        && g.clip_path().is_none()
        && g.mask().is_none()
        && g.filters().is_empty()
        && g.blend_mode() == usvg::BlendMode::Normal
}

#[derive(Clone, Copy)]
struct Ctx<'a> {
    /// Tags seen so far.
    scope: Scope<'a>,
    /// Transform from the current group's coordinates to the canvas.
    abs: Affine,
    /// Whether nodes here may become units (not inside a unit, a clip, a mask or a pattern).
    units: bool,
    /// The nearest source element, to name in warnings.
    near: Option<NodeId>,
}

impl Ctx<'_> {
    /// The context for clip, mask and pattern content: no units, no tags.
    fn plain(near: Option<NodeId>) -> Self {
        Ctx {
            scope: Scope::default(),
            abs: Affine::IDENTITY,
            units: false,
            near,
        }
    }
}

/// The shapes of a `use` instance whose paths usvg left without ids, in paint order, and
/// the referenced element their tag lookup stops at.
struct Zip {
    limit: NodeId,
    shapes: std::vec::IntoIter<NodeId>,
}

struct Converter<'s, 'a> {
    src: &'s Source<'a>,
    /// The fonts text is drawn with (to name missing ones), and the options they came from.
    fonts: &'s usvg::fontdb::Database,
    font_options: &'s crate::fonts::FontOptions,
    opts: ImportOptions,
    warnings: Vec<(String, String)>,
    warned: HashSet<String>,
    /// Real ids given to scene nodes so far (each is used once).
    ids: HashSet<String>,
    linear: HashMap<usize, Arc<LinearGradient>>,
    radial: HashMap<usize, Arc<RadialGradient>>,
    /// Gradients by value (see [`gradient_key`]).
    gradients: HashMap<Vec<u32>, Paint>,
    patterns: HashMap<usize, Arc<Pattern>>,
    clips: HashMap<usize, Arc<ClipPath>>,
    masks: HashMap<usize, Arc<Mask>>,
    units: Vec<Unit>,
    /// Child indices from the root to the group being filled.
    path: Vec<usize>,
    zip: Option<Zip>,
    /// Pixels drawn so far for filters drawn as images, and the most there may be.
    baked_pixels: f64,
    max_baked_pixels: f64,
    /// The largest raster image kept, in decoded pixels.
    max_image_pixels: u64,
}

/// Identity of a usvg paint server, clip or mask: they are shared through `Arc`s.
fn key<T>(arc: &T) -> usize {
    arc as *const T as usize
}

/// How far from the origin, in px, the raster exporter draws (`gmotion_export_raster`'s
/// `MAX_DRAWN_COORD`, which this crate does not depend on): tiny-skia's 32-bit fixed point
/// panics near 5·10⁸ px.
const MAX_DRAWN: f64 = 1e8;

pub(crate) fn affine(t: usvg::Transform) -> Affine {
    Affine::new([
        t.sx as f64,
        t.ky as f64,
        t.kx as f64,
        t.sy as f64,
        t.tx as f64,
        t.ty as f64,
    ])
}

fn rect(r: usvg::NonZeroRect) -> Rect {
    Rect::new(
        r.left() as f64,
        r.top() as f64,
        r.right() as f64,
        r.bottom() as f64,
    )
}

pub(crate) fn bez(path: &usvg::tiny_skia_path::Path) -> BezPath {
    let pt = |p: usvg::tiny_skia_path::Point| Point::new(p.x as f64, p.y as f64);
    // One element a verb, allocated once: grown a push at a time, a rectangle's five
    // elements took room for eight, 170 MB over 999 000 shapes held for the whole run.
    let mut out = BezPath::with_capacity(path.verbs().len());
    for seg in path.segments() {
        match seg {
            PathSegment::MoveTo(p) => out.move_to(pt(p)),
            PathSegment::LineTo(p) => out.line_to(pt(p)),
            PathSegment::QuadTo(a, p) => out.quad_to(pt(a), pt(p)),
            PathSegment::CubicTo(a, b, p) => out.curve_to(pt(a), pt(b), pt(p)),
            PathSegment::Close => out.close_path(),
        }
    }
    out
}

fn count_paths(g: &usvg::Group) -> usize {
    g.children()
        .iter()
        .map(|n| match n {
            usvg::Node::Path(_) => 1,
            usvg::Node::Group(g) => count_paths(g),
            _ => 0,
        })
        .sum()
}

/// Whether `g` draws anything (a path or an image somewhere inside).
fn draws(g: &Group) -> bool {
    g.children.iter().any(|n| match n {
        Node::Path(_) | Node::Image(_) => true,
        Node::Group(g) => draws(g),
    })
}

/// What a usvg group stands for.
#[derive(Clone, Copy, PartialEq, Eq)]
enum GroupKind {
    /// A group usvg made for an element (or for its own reasons).
    Element,
    /// The outlines of a `<text>` element.
    Text,
}

impl<'s, 'a> Converter<'s, 'a> {
    /// The named families of `t`'s runs none of whose families is installed (a run
    /// written `font-family="Montserrat-SemiBold, sans-serif"` falls back as asked).
    fn missing_fonts(&self, t: &usvg::Text) -> Vec<String> {
        let mut missing: Vec<String> = Vec::new();
        for span in t.chunks().iter().flat_map(|c| c.spans()) {
            let families = span.font().families();
            let mut named = families.iter().filter_map(|f| match f {
                usvg::FontFamily::Named(n) => Some(n.as_str()),
                _ => None,
            });
            let generic = families
                .iter()
                .any(|f| !matches!(f, usvg::FontFamily::Named(_)));
            let found = named
                .clone()
                .any(|n| crate::fonts::installed(self.fonts, n));
            if let Some(first) = named.next()
                && !found
                && !generic
                && !missing.iter().any(|m| m == first)
            {
                missing.push(first.to_string());
            }
        }
        missing
    }

    fn warn(&mut self, near: Option<NodeId>, what: &str) {
        let place = near
            .and_then(|id| self.src.node(id))
            .map_or_else(|| "<svg>".to_string(), |n| self.src.describe(n));
        if self.warned.insert(format!("{place}: {what}")) {
            self.warnings.push((place, what.to_string()));
        }
    }

    /// The scene id for a usvg id: real ids once each, synthetic ones dropped.
    fn keep_id(&mut self, id: &str) -> String {
        if id.is_empty() || self.src.is_synthetic(id) || !self.ids.insert(id.to_string()) {
            return String::new();
        }
        id.to_string()
    }

    /// Registers a unit tagged `tag` on source element `elem` (drawn under `scope`'s
    /// element), at child `index` of the current group.
    fn register(
        &mut self,
        tag: &str,
        elem: Option<usvg::roxmltree::Node<'s, 'a>>,
        scope: Scope<'s>,
        parent_transform: Affine,
        index: usize,
    ) -> usize {
        let mut node_path = self.path.clone();
        node_path.push(index);
        let aliases = elem.map_or_else(Vec::new, |e| self.src.aliases(e, scope.elem(), tag));
        self.units.push(Unit {
            tag: tag.to_string(),
            aliases,
            node_path,
            parent_transform,
            text: None,
        });
        self.units.len() - 1
    }

    fn children(&mut self, g: &usvg::Group, dst: &mut Group, ctx: Ctx<'s>) {
        for child in g.children() {
            self.child(child, dst, ctx);
        }
    }

    fn child(&mut self, child: &usvg::Node, dst: &mut Group, ctx: Ctx<'s>) {
        {
            match child {
                usvg::Node::Group(g) => self.group(g, GroupKind::Element, dst, ctx),
                usvg::Node::Path(p) => self.path(p, dst, ctx),
                usvg::Node::Text(t) => {
                    let near = self.src.element(t.id()).map(|e| e.id()).or(ctx.near);
                    for missing in self.missing_fonts(t) {
                        let instead =
                            crate::fonts::fallback_family(self.fonts, &missing, self.font_options);
                        self.warn(
                            near,
                            &format!("font `{missing}` is not installed: the text is drawn in `{instead}` (give the font with --font-file or --font-dir, or choose the family with --font-family)"),
                        );
                    }
                    if t.flattened().children().is_empty() {
                        self.warn(near, "text dropped: no font to draw it with (no font is installed; give one with --font-file or --font-dir)");
                    } else {
                        self.warn(near, "text converted to outlines with the system fonts");
                        let units = self.units.len();
                        self.group(t.flattened(), GroupKind::Text, dst, ctx);
                        // The text became a unit of its own: keep its letters apart too.
                        if matches!(dst.children.last(), Some(Node::Group(g)) if g.unit == Some(units))
                        {
                            let fonts = self.fonts;
                            let layout =
                                crate::text::layout(t, fonts, |span| self.span_paint(span, near));
                            self.units[units].text = layout.map(Arc::new);
                        }
                    }
                }
                usvg::Node::Image(i) => self.image(i, dst, ctx),
            }
        }
    }

    /// The first source element `g`'s content comes from, in document order.
    fn first_element(&self, g: &usvg::Group) -> Option<NodeId> {
        g.children().iter().find_map(|c| {
            self.src
                .element(c.id())
                .map(|e| e.id())
                .or_else(|| match c {
                    usvg::Node::Group(h) => self.first_element(h),
                    _ => None,
                })
        })
    }

    /// The tag that makes a group a unit under the chosen unit rule, if it has one (text is
    /// a unit whatever its tag: it answers with its scope's).
    fn unit_tag(
        &self,
        elem: usvg::roxmltree::Node<'s, 'a>,
        kind: GroupKind,
        scope: Scope<'s>,
    ) -> Option<&'s str> {
        let from = self.opts.tag_from;
        if kind == GroupKind::Element && self.src.forced_unit(elem) {
            return Some(scope.tag(elem.tag_name().name()));
        }
        // A unit a tag map asks for inside this group outranks the group's own unit-ness
        // under the `--units` rules; the group's other content becomes units as usual.
        if kind == GroupKind::Element && self.src.holds_forced_unit(elem) {
            return None;
        }
        match (self.opts.units, kind) {
            (Units::Paths, _) => None,
            (_, GroupKind::Text) => Some(scope.tag("text")),
            (_, GroupKind::Element) if Source::depth(elem) < self.opts.unit_depth => None,
            (Units::Auto, GroupKind::Element) => self.src.own_tag(elem, from, false),
            (Units::Groups, GroupKind::Element) => self.src.own_tag(elem, from, true),
        }
    }

    fn group(&mut self, g: &usvg::Group, kind: GroupKind, dst: &mut Group, ctx: Ctx<'s>) {
        let elem = self.src.element(g.id());
        let near = elem.map(|e| e.id()).or(ctx.near);
        // usvg puts a filter or blend mode on a group of its own, without an id; the
        // element that asked for it is the one the group's content comes from. Looked for
        // only when there is one: most groups have neither.
        let has_effect = !g.filters().is_empty() || g.blend_mode() != usvg::BlendMode::Normal;
        let effect_of = match elem {
            Some(e) => Some(e.id()),
            None if has_effect => self.first_element(g).or(ctx.near),
            None => ctx.near,
        };
        let filter = if g.filters().is_empty() {
            None
        } else {
            match filters::recognise(g.filters()) {
                Some(f) => Some(f).filter(|f| !f.effects.is_empty()).map(Arc::new),
                // A filter that cannot be drawn as an image is left out (and said so):
                // the content is drawn without it.
                None if self.baked(g, kind, dst, ctx, effect_of) => return,
                None => None,
            }
        };
        if g.blend_mode() != usvg::BlendMode::Normal {
            self.warn(
                effect_of,
                &format!(
                    "mix-blend-mode {} ignored (blend modes are not supported)",
                    g.blend_mode()
                ),
            );
        }
        let from = self.opts.tag_from;
        let scope = match elem {
            Some(e) if ctx.units => self.src.scope(e, ctx.scope, from, None),
            _ => ctx.scope,
        };
        // A group unit is tagged with the tag that makes it one (for a `use`, possibly the
        // referenced group's), which is the nearest source anyway except for a layer name
        // under an explicit tag further up.
        let unit_tag = elem
            .filter(|_| ctx.units)
            .and_then(|e| self.unit_tag(e, kind, scope));
        let is_unit = unit_tag.is_some();
        let transform = affine(g.transform());
        let opacity = g.opacity().get();
        let clip_path = g.clip_path().map(|c| self.clip(c, near));
        let mask = g.mask().map(|m| self.mask(m, near));
        let id = self.keep_id(g.id());
        let inner = Ctx {
            scope,
            abs: ctx.abs * transform,
            units: ctx.units && !is_unit,
            near,
        };

        let zip = match elem {
            Some(e) if inner.units => self
                .src
                .use_shapes(e)
                .filter(|(_, shapes)| shapes.len() == count_paths(g))
                .map(|(limit, shapes)| Zip {
                    limit,
                    shapes: shapes.into_iter(),
                }),
            _ => None,
        };
        let outer_zip = zip.is_some().then(|| std::mem::replace(&mut self.zip, zip));

        // A group the designer named (an Inkscape label, an Illustrator `data-name`) is
        // kept even without an id of its own: its name is the layer tree's and a tag map's.
        let label = elem
            .and_then(|e| self.src.label_of(e))
            .unwrap_or_default()
            .to_string();
        let transparent = id.is_empty()
            && label.is_empty()
            && transform == Affine::IDENTITY
            && opacity == 1.0
            && clip_path.is_none()
            && mask.is_none()
            && filter.is_none()
            && !is_unit;
        if transparent {
            self.children(g, dst, inner);
        } else {
            let mut out = Group {
                id,
                label,
                transform,
                opacity,
                clip_path,
                mask,
                filter,
                children: Vec::new(),
                unit: None,
            };
            let index = dst.children.len();
            self.path.push(index);
            self.children(g, &mut out, inner);
            self.path.pop();
            if let Some(tag) = unit_tag.filter(|_| draws(&out)) {
                out.unit = Some(self.register(tag, elem, ctx.scope, ctx.abs, index));
            } else if out.filter.is_some() {
                self.hoist_unit(&mut out, ctx.abs);
            }
            if !out.children.is_empty() {
                dst.children.push(Node::Group(out));
            }
        }
        if let Some(z) = outer_zip {
            self.zip = z;
        }
    }

    /// Makes a filtered group whose one child is a unit the unit instead, so that the
    /// filter moves with it: a filtered shape is a group of its own in usvg, and a filter
    /// region left behind would cut off the shape once it moved out of it.
    fn hoist_unit(&mut self, g: &mut Group, parent_transform: Affine) {
        let [child] = g.children.as_mut_slice() else {
            return;
        };
        let unit = match child {
            Node::Group(c) => c.unit.take(),
            Node::Path(p) => p.unit.take(),
            Node::Image(i) => i.unit.take(),
        };
        if let Some(u) = unit {
            let shape = &mut self.units[u];
            shape.node_path.pop();
            shape.parent_transform = parent_transform;
            g.unit = Some(u);
        }
    }

    /// Draws group `g`, whose filter no scene effect expresses, as an image (with a
    /// warning naming the element that asked for the filter); the image is a unit where
    /// the group's content would have held units. False (with a warning) when it cannot.
    fn baked(
        &mut self,
        g: &usvg::Group,
        kind: GroupKind,
        dst: &mut Group,
        ctx: Ctx<'s>,
        effect_of: Option<NodeId>,
    ) -> bool {
        let parent_abs = g
            .transform()
            .invert()
            .map(|t| g.abs_transform().pre_concat(t));
        let budget = self.max_baked_pixels - self.baked_pixels;
        let baked = parent_abs.map_or(Err(filters::Unbaked::Nothing), |t| {
            filters::bake(g, t, budget, self.max_image_pixels)
        });
        let (image, place) = match baked {
            Ok(b) => b,
            Err(filters::Unbaked::Nothing) => {
                self.warn(effect_of, "filter ignored (it cannot be drawn as an image)");
                return false;
            }
            Err(filters::Unbaked::OverBudget) => {
                let why = format!(
                    "filter ignored (the filters drawn as images reached the limit of {} pixels; raise it with --limit filter-pixels=N)",
                    self.max_baked_pixels
                );
                self.warn(effect_of, &why);
                return false;
            }
        };
        self.baked_pixels += image.width * image.height;
        self.warn(
            effect_of,
            "filter drawn as an image (only blurs and drop shadows stay vector)",
        );
        let elem = self.src.element(g.id());
        let from = self.opts.tag_from;
        let index = dst.children.len();
        let unit = if let Some(e) = elem.filter(|_| ctx.units)
            && let Some(tag) = self.unit_tag(e, kind, self.src.scope(e, ctx.scope, from, None))
        {
            Some(self.register(tag, Some(e), ctx.scope, ctx.abs, index))
        } else if let Some(e) = effect_of
            .and_then(|id| self.src.node(id))
            .filter(|_| ctx.units)
        {
            let scope = self.src.scope(e, ctx.scope, from, None);
            let tag = scope.tag(e.tag_name().name());
            Some(self.register(tag, Some(e), ctx.scope, ctx.abs, index))
        } else {
            None
        };
        dst.children.push(Node::Group(Group {
            id: self.keep_id(g.id()),
            transform: place,
            children: vec![Node::Image(image)],
            unit,
            ..Group::new()
        }));
        true
    }

    fn path(&mut self, p: &usvg::Path, dst: &mut Group, ctx: Ctx<'s>) {
        let from = self.opts.tag_from;
        let mut elem = self.src.element(p.id());
        let mut limit = None;
        if elem.is_none()
            && ctx.units
            && let Some(zip) = &mut self.zip
        {
            // A path of a `use` instance: take the next shape of the referenced content.
            elem = zip.shapes.next().and_then(|id| self.src.node(id));
            limit = Some(zip.limit);
        }
        if !p.is_visible() {
            return;
        }
        let near = elem.map(|e| e.id()).or(ctx.near);
        if p.rendering_mode() != usvg::ShapeRendering::GeometricPrecision {
            self.warn(near, "shape-rendering ignored (always anti-aliased)");
        }
        let fill = p.fill().map(|f| Fill {
            paint: self.paint(f.paint(), near),
            opacity: f.opacity().get(),
            rule: match f.rule() {
                usvg::FillRule::NonZero => FillRule::NonZero,
                usvg::FillRule::EvenOdd => FillRule::EvenOdd,
            },
        });
        let stroke = p.stroke().map(|s| self.stroke(s, near));
        self.check_reach(p, stroke.as_ref().map_or(0.0, |s| s.width), near);
        let mut node = PathNode {
            id: self.keep_id(p.id()),
            path: bez(p.data()),
            fill,
            stroke,
            stroke_first: p.paint_order() == usvg::PaintOrder::StrokeAndFill,
            unit: None,
        };
        if ctx.units {
            let scope = elem.map_or(ctx.scope, |e| self.src.scope(e, ctx.scope, from, limit));
            let name = elem.map_or("path", |e| e.tag_name().name());
            let index = dst.children.len();
            // A path usvg made (a glyph run of a text under `--units paths`, a `use`
            // instance's path) has no element of its own: it answers to the names of the
            // element it was made from and of the groups around that.
            let named = elem.or_else(|| ctx.scope.elem().and_then(|id| self.src.node(id)));
            node.unit = Some(self.register(scope.tag(name), named, ctx.scope, ctx.abs, index));
        }
        dst.children.push(Node::Path(node));
    }

    /// A raster image as an image node (a unit, like a path, when units are being made);
    /// a nested SVG image as the vector content it holds, clipped to its viewport.
    fn image(&mut self, i: &usvg::Image, dst: &mut Group, ctx: Ctx<'s>) {
        if !i.is_visible() {
            return;
        }
        // usvg gives the `<image>` element's id to the groups it wraps the image in (which
        // place and clip it), so the element is the nearest one when the image has none.
        let elem = self.src.element(i.id()).or_else(|| {
            ctx.near
                .and_then(|id| self.src.node(id))
                .filter(|e| e.tag_name().name() == "image")
        });
        let near = elem.map(|e| e.id()).or(ctx.near);
        let (data, format) = match i.kind() {
            usvg::ImageKind::PNG(d) => (d, ImageFormat::Png),
            usvg::ImageKind::JPEG(d) => (d, ImageFormat::Jpeg),
            usvg::ImageKind::GIF(d) => (d, ImageFormat::Gif),
            usvg::ImageKind::WEBP(d) => (d, ImageFormat::Webp),
            usvg::ImageKind::SVG(tree) => {
                let size = i.size();
                let viewport = Rect::new(0.0, 0.0, size.width() as f64, size.height() as f64);
                let mut out = Group {
                    id: self.keep_id(i.id()),
                    clip_path: Some(Arc::new(ClipPath::rect(viewport))),
                    ..Group::new()
                };
                // The nested document's elements are not the source file's: no units or
                // tags come from them.
                let inner = Ctx {
                    units: false,
                    near,
                    ..ctx
                };
                self.children(tree.root(), &mut out, inner);
                if !out.children.is_empty() {
                    dst.children.push(Node::Group(out));
                }
                return;
            }
        };
        let size = i.size();
        let mut node = ImageNode {
            id: self.keep_id(i.id()),
            data: Arc::from(data.as_slice()),
            format,
            width: size.width() as f64,
            height: size.height() as f64,
            smooth: !matches!(
                i.rendering_mode(),
                usvg::ImageRendering::OptimizeSpeed
                    | usvg::ImageRendering::CrispEdges
                    | usvg::ImageRendering::Pixelated
            ),
            unit: None,
        };
        if let Some((w, h)) = node.pixel_size()
            && w.saturating_mul(h) > self.max_image_pixels
        {
            let why = format!(
                "image not drawn: it declares {w} × {h} pixels, more than the limit of {} (raise it with --limit image-pixels=N)",
                self.max_image_pixels
            );
            self.warn(near, &why);
            return;
        }
        if ctx.units {
            let from = self.opts.tag_from;
            let scope = elem.map_or(ctx.scope, |e| self.src.scope(e, ctx.scope, from, None));
            let index = dst.children.len();
            node.unit = Some(self.register(scope.tag("image"), elem, ctx.scope, ctx.abs, index));
        }
        dst.children.push(Node::Image(node));
    }

    /// The paint of a laid-out text span, as [`Converter::path`] converts a path's.
    fn span_paint(
        &mut self,
        span: &usvg::layout::Span,
        near: Option<NodeId>,
    ) -> crate::text::SpanPaint {
        let fill = span.fill.as_ref().map(|f| Fill {
            paint: self.paint(f.paint(), near),
            opacity: f.opacity().get(),
            rule: FillRule::NonZero,
        });
        let stroke = span.stroke.as_ref().map(|s| self.stroke(s, near));
        let stroke_first = span.paint_order == usvg::PaintOrder::StrokeAndFill;
        (fill, stroke, stroke_first)
    }

    /// Warns, at the element, about a path that reaches past what a picture of it can draw
    /// (its geometry, widened by half its stroke, farther than [`MAX_DRAWN`] canvas px from
    /// the origin: `stroke-width="1e10"`). The refusal of a PNG, GIF or video comes later
    /// from the renderer, which knows the output's scale but not the source: this says
    /// where in the file the shape is. Vector outputs are still written.
    fn check_reach(&mut self, p: &usvg::Path, stroke_width: f64, near: Option<NodeId>) {
        let ts = affine(p.abs_transform());
        let b = p.data().bounds();
        let half = 0.5 * stroke_width * ts.determinant().abs().sqrt();
        let reach = [
            (b.left(), b.top()),
            (b.right(), b.top()),
            (b.left(), b.bottom()),
            (b.right(), b.bottom()),
        ]
        .into_iter()
        .map(|(x, y)| {
            let q = ts * Point::new(f64::from(x), f64::from(y));
            q.x.abs().max(q.y.abs()) + half
        })
        .fold(0.0, f64::max);
        if reach > MAX_DRAWN {
            let what = if half > MAX_DRAWN / 2.0 {
                format!("its stroke, {stroke_width:.3e} wide,")
            } else {
                "its outline".to_string()
            };
            self.warn(
                near,
                &format!(
                    "{what} reaches {reach:.3e} px from the canvas's origin, past the ±{MAX_DRAWN:.0e} px a picture at the canvas's size can draw (a PNG, GIF, APNG or video of it is refused)"
                ),
            );
        }
    }

    fn stroke(&mut self, s: &usvg::Stroke, near: Option<NodeId>) -> Stroke {
        Stroke {
            paint: self.paint(s.paint(), near),
            opacity: s.opacity().get(),
            width: s.width().get() as f64,
            cap: match s.linecap() {
                usvg::LineCap::Butt => LineCap::Butt,
                usvg::LineCap::Round => LineCap::Round,
                usvg::LineCap::Square => LineCap::Square,
            },
            join: match s.linejoin() {
                usvg::LineJoin::Miter => LineJoin::Miter,
                usvg::LineJoin::MiterClip => LineJoin::MiterClip,
                usvg::LineJoin::Round => LineJoin::Round,
                usvg::LineJoin::Bevel => LineJoin::Bevel,
            },
            miter_limit: s.miterlimit().get() as f64,
            dash: s.dasharray().map(|d| d.iter().map(|&v| v as f64).collect()),
            dash_offset: s.dashoffset() as f64,
        }
    }

    fn paint(&mut self, p: &usvg::Paint, near: Option<NodeId>) -> Paint {
        match p {
            usvg::Paint::Color(c) => Paint::Solid(Color::rgb8(c.red, c.green, c.blue)),
            usvg::Paint::LinearGradient(lg) => {
                let lg: &usvg::LinearGradient = lg;
                if let Some(arc) = self.linear.get(&key(lg)) {
                    return Paint::Linear(arc.clone());
                }
                let value = [lg.x1(), lg.y1(), lg.x2(), lg.y2(), 0.0, 0.0];
                let same = gradient_key(0, value, lg);
                let arc = self.gradients.entry(same).or_insert_with(|| {
                    Paint::Linear(Arc::new(LinearGradient {
                        id: lg.id().to_string(),
                        start: Point::new(lg.x1() as f64, lg.y1() as f64),
                        end: Point::new(lg.x2() as f64, lg.y2() as f64),
                        transform: affine(lg.transform()),
                        spread: spread(lg.spread_method()),
                        stops: stops(lg.stops()),
                    }))
                });
                if let Paint::Linear(a) = arc {
                    self.linear.insert(key(lg), a.clone());
                }
                arc.clone()
            }
            usvg::Paint::RadialGradient(rg) => {
                let rg: &usvg::RadialGradient = rg;
                if let Some(arc) = self.radial.get(&key(rg)) {
                    return Paint::Radial(arc.clone());
                }
                let value = [
                    rg.cx(),
                    rg.cy(),
                    rg.r().get(),
                    rg.fx(),
                    rg.fy(),
                    rg.fr().get(),
                ];
                let same = gradient_key(1, value, rg);
                let arc = self.gradients.entry(same).or_insert_with(|| {
                    Paint::Radial(Arc::new(RadialGradient {
                        id: rg.id().to_string(),
                        center: Point::new(rg.cx() as f64, rg.cy() as f64),
                        radius: rg.r().get() as f64,
                        focal: Point::new(rg.fx() as f64, rg.fy() as f64),
                        focal_radius: rg.fr().get() as f64,
                        transform: affine(rg.transform()),
                        spread: spread(rg.spread_method()),
                        stops: stops(rg.stops()),
                    }))
                });
                if let Paint::Radial(a) = arc {
                    self.radial.insert(key(rg), a.clone());
                }
                arc.clone()
            }
            usvg::Paint::Pattern(pat) => Paint::Pattern(self.pattern(pat, near)),
        }
    }

    /// Converts clip, mask or pattern content: never units, and a `use` instance being
    /// matched must not lose shapes to it. A clip path's `use` of a `use` is left out, as
    /// browsers leave it out (usvg draws it).
    fn content(&mut self, g: &usvg::Group, near: Option<NodeId>) -> Group {
        let zip = self.zip.take();
        let mut root = Group::new();
        for child in g.children() {
            let elem = self.src.element(child.id());
            if let Some(e) = elem.filter(|e| self.src.is_indirect_clip_use(*e)) {
                self.warn(
                    Some(e.id()),
                    "ignored, as browsers do: a clip path's <use> must point at a shape or text, not at a <use> or group",
                );
                continue;
            }
            self.child(child, &mut root, Ctx::plain(near));
        }
        self.zip = zip;
        root
    }

    fn pattern(&mut self, p: &usvg::Pattern, near: Option<NodeId>) -> Arc<Pattern> {
        if let Some(a) = self.patterns.get(&key(p)) {
            return a.clone();
        }
        let root = self.content(p.root(), near);
        let arc = Arc::new(Pattern {
            id: p.id().to_string(),
            rect: rect(p.rect()),
            transform: affine(p.transform()),
            root,
        });
        self.patterns.insert(key(p), arc.clone());
        arc
    }

    fn clip(&mut self, c: &usvg::ClipPath, near: Option<NodeId>) -> Arc<ClipPath> {
        if let Some(a) = self.clips.get(&key(c)) {
            return a.clone();
        }
        let root = self.content(c.root(), near);
        let clip_path = c.clip_path().map(|n| self.clip(n, near));
        let arc = Arc::new(ClipPath {
            id: c.id().to_string(),
            transform: affine(c.transform()),
            clip_path,
            root,
        });
        self.clips.insert(key(c), arc.clone());
        arc
    }

    fn mask(&mut self, m: &usvg::Mask, near: Option<NodeId>) -> Arc<Mask> {
        if let Some(a) = self.masks.get(&key(m)) {
            return a.clone();
        }
        let root = self.content(m.root(), near);
        let mask = m.mask().map(|n| self.mask(n, near));
        let kind = match m.kind() {
            usvg::MaskType::Luminance => MaskKind::Luminance,
            usvg::MaskType::Alpha => MaskKind::Alpha,
        };
        let arc = Arc::new(Mask {
            id: m.id().to_string(),
            rect: rect(m.rect()),
            kind,
            mask,
            root,
        });
        self.masks.insert(key(m), arc.clone());
        arc
    }
}

/// Everything that makes two usvg gradients paint the same: usvg copies a gradient for
/// each element it fills in `objectBoundingBox` units, and copies on equal boxes (repeated
/// elements, `use` instances) are merged back into one.
fn gradient_key(kind: u32, geometry: [f32; 6], g: &usvg::BaseGradient) -> Vec<u32> {
    let t = g.transform();
    let mut k = vec![kind, g.spread_method() as u32];
    k.extend(
        geometry
            .iter()
            .chain(&[t.sx, t.ky, t.kx, t.sy, t.tx, t.ty])
            .map(|v| v.to_bits()),
    );
    for s in g.stops() {
        let c = s.color();
        k.extend([s.offset().get().to_bits(), s.opacity().get().to_bits()]);
        k.push(u32::from_be_bytes([0, c.red, c.green, c.blue]));
    }
    k
}

fn spread(s: usvg::SpreadMethod) -> Spread {
    match s {
        usvg::SpreadMethod::Pad => Spread::Pad,
        usvg::SpreadMethod::Reflect => Spread::Reflect,
        usvg::SpreadMethod::Repeat => Spread::Repeat,
    }
}

fn stops(stops: &[usvg::Stop]) -> Vec<Stop> {
    stops
        .iter()
        .map(|s| {
            let c = s.color();
            let mut color = Color::rgb8(c.red, c.green, c.blue);
            color.a = s.opacity().get();
            Stop {
                offset: s.offset().get(),
                color,
            }
        })
        .collect()
}
