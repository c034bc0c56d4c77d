//! Scenes and animation frames as SVG text: the static SVG `convert` writes, and the frame
//! documents gmotion renders with resvg for PNG, GIF and APNG output.
//!
//! A frame is the scene with every shape's [`ShapeState`] applied to its unit node:
//!
//! - the node is wrapped in a `<g>` whose transform is `P⁻¹·S·P`, where `S` is the state's
//!   canvas-space transform and `P` the shape's `parent_transform`, so the unit lands where
//!   `S` puts it whatever groups it sits in; the wrapper's opacity is the state's opacity;
//! - fill and stroke tints apply to every colour the unit paints, gradient stops and
//!   pattern content included (tinted copies of those are written once per tint);
//! - stroke widths are multiplied by the state's stroke-width factor;
//! - a shape whose track deforms per vertex has every path point moved by
//!   [`Track::deform`] instead of a wrapper transform. Gradients, patterns, clip paths and
//!   masks inside such a unit keep their rest geometry.
//!
//! Units do not nest in imported scenes; if they do, tints and stroke factors compose
//! (inner first) and deformations apply inner first.
//!
//! Numbers are written at `f32` precision (what resvg computes in) in their shortest
//! form, so a frame is exact for the renderer and identical on every run.

mod defs;
mod number;

use foldhash::{HashMap, HashSet, HashSetExt};

use kurbo::{Affine, BezPath, PathEl, Point, Rect};

use gmotion::canvas::Fit;

use defs::{Def, Defs, Names};
use gmotion::motion::{Animation, Sampler, ShapeState, Tint, Track, Trim};
use gmotion::scene::{FillRule, Group, ImageNode, LineCap, LineJoin, Node, Paint, PathNode, Scene};
use number::{attr_num, attr_transform, escaped, hex, num, point};

/// How far (canvas units) a frame's outline bent by a per-vertex motion may stray from the
/// field: finer than the exports' default `--tolerance` (0.25), as frames are what the
/// players' drawings of those exports are compared with.
const BEND_TOLERANCE: f64 = 0.05;

/// The opening of every document this module writes, up to the canvas size.
const ROOT: &str = "<svg xmlns=\"http://www.w3.org/2000/svg\"";

/// `svg`, a document written by this module (or spliced from one, as the SMIL exporter
/// does), sized as `fit` says: its root's `width` and `height` the output's pixels, and its
/// `viewBox` the part of the canvas they show ([`Fit::view_box`]), so that every SVG viewer
/// draws the art at `fit`'s scale and place, as the PNG and Lottie outputs do. Where the
/// canvas's own `viewBox` already draws it so (SVG's default `xMidYMid meet`: always when
/// both sides are given), it is kept. Text that does not start as this module writes it is
/// returned unchanged.
pub fn with_output_size(svg: &str, fit: &Fit) -> String {
    match output_size_edit(svg, fit) {
        Some((range, text)) => {
            let mut out = String::with_capacity(svg.len() + 16);
            out.push_str(&svg[..range.start]);
            out.push_str(&text);
            out.push_str(&svg[range.end..]);
            out
        }
        None => svg.to_string(),
    }
}

/// What [`with_output_size`] changes: the range of `svg` holding the root's `width` and
/// `height` (and its `viewBox`, where that changes too) and the attributes that replace
/// it; `None` for text that does not start as this module writes it.
pub fn output_size_edit(svg: &str, fit: &Fit) -> Option<(std::ops::Range<usize>, String)> {
    const VIEW_BOX: &str = " viewBox=\"";
    let rest = svg.strip_prefix(ROOT)?;
    let view_box = rest.find(VIEW_BOX)?;
    let mut text = String::with_capacity(64);
    attr_num(&mut text, "width", f64::from(fit.width));
    attr_num(&mut text, "height", f64::from(fit.height));
    if fit.is_meet() {
        return Some((ROOT.len()..ROOT.len() + view_box, text));
    }
    let value = view_box + VIEW_BOX.len();
    let end = value + rest[value..].find('"')? + 1;
    let shown = fit.view_box();
    text.push_str(VIEW_BOX);
    point(&mut text, shown.origin());
    text.push(' ');
    point(&mut text, Point::new(shown.width(), shown.height()));
    text.push('"');
    Some((ROOT.len()..ROOT.len() + end, text))
}

/// The scene as a static SVG document, with its node ids.
pub fn scene_svg(scene: &Scene) -> String {
    scene_svg_with_ids(scene, None)
}

/// Ids that replace a scene's own, by node: the address of the node's [`Group`],
/// [`PathNode`] or [`ImageNode`] in the scene (the SMIL writer's marks, given this way
/// rather than on a copy of the whole tree).
pub(crate) type IdsByNode = HashMap<usize, String>;

/// The address [`IdsByNode`] knows a node by.
pub(crate) fn node_key<T>(node: &T) -> usize {
    std::ptr::from_ref(node) as usize
}

/// [`scene_svg`] with the nodes `ids` names written under those ids instead of their own
/// (what the scene with its ids so changed would write).
pub(crate) fn scene_svg_with_ids(scene: &Scene, ids: Option<&IdsByNode>) -> String {
    let mut names = HashSet::new();
    collect_ids(&scene.root, ids, &mut names);
    let writer = Writer {
        scene,
        frame: None,
        out: String::with_capacity(4096),
        defs: Defs::with_names(Names::new(names)),
        deform: Vec::new(),
        morph: None,
        written_ids: Some(HashSet::new()),
        ids,
    };
    writer.document()
}

/// The id `node` is written with: its own (`own`) unless `ids` names it.
fn id_of<'a, T>(ids: Option<&'a IdsByNode>, node: &T, own: &'a str) -> &'a str {
    ids.and_then(|m| m.get(&node_key(node)))
        .map_or(own, String::as_str)
}

/// The animation's frame at time `t` (seconds) as an SVG document.
pub fn frame_svg(anim: &Animation, t: f64) -> String {
    frame_with_states(&anim.scene, anim, t, anim.evaluate(t))
}

/// [`frame_svg`] with the states read from `sampler` (built once for many frames).
pub fn sampled_frame_svg(anim: &Animation, sampler: &Sampler, t: f64) -> String {
    frame_with_states(&anim.scene, anim, t, sampler.evaluate(t))
}

/// Frame `t` of `anim` with the shapes' `states` (as [`Animation::evaluate`] or a
/// [`Sampler`] gives them), drawing `scene` in place of the animation's own scene: for a
/// scene that moves by itself (a Lottie source evaluated at the frame). `scene` has the
/// animation's units, in the same order.
pub fn frame_with_states<'a>(
    scene: &'a Scene,
    anim: &'a Animation,
    t: f64,
    states: Vec<ShapeState>,
) -> String {
    frame_with_ids(scene, anim, t, states, "d")
}

/// [`frame_with_states`] with its `<defs>` entries (gradients, clip paths, masks…) named
/// `{ids}0`, `{ids}1`, … instead of `d0`, `d1`, …: frames that share one document (a
/// flipbook) need names of their own. A frame writes no other ids; `ids` must not end in
/// a digit (`f1` would name frame 1's tenth entry as frame 11's first).
pub fn frame_with_ids<'a>(
    scene: &'a Scene,
    anim: &'a Animation,
    t: f64,
    states: Vec<ShapeState>,
    ids: &str,
) -> String {
    let writer = Writer {
        scene,
        frame: Some(Frame {
            tracks: &anim.tracks,
            states,
            t,
        }),
        out: String::with_capacity(4096),
        defs: Defs::numbered(ids),
        deform: Vec::new(),
        morph: None,
        written_ids: None,
        ids: None,
    };
    writer.document()
}

fn collect_ids(g: &Group, by_node: Option<&IdsByNode>, ids: &mut HashSet<String>) {
    let add = |ids: &mut HashSet<String>, id: &str| {
        if !id.is_empty() {
            ids.insert(id.to_string());
        }
    };
    add(ids, id_of(by_node, g, &g.id));
    for child in &g.children {
        match child {
            Node::Group(h) => collect_ids(h, by_node, ids),
            Node::Path(p) => add(ids, id_of(by_node, p, &p.id)),
            Node::Image(i) => add(ids, id_of(by_node, i, &i.id)),
        }
    }
}

/// `ts⁻¹`, or the identity for a singular `ts` (which flattens its content to nothing, so
/// any inverse would do).
fn inverse(ts: Affine) -> Affine {
    if ts.determinant().abs() > 1e-12 {
        ts.inverse()
    } else {
        Affine::IDENTITY
    }
}

/// A tint applied after `inner`: `outer(inner(c))` for every colour `c`.
fn compose(outer: Tint, inner: Tint) -> Tint {
    if inner == Tint::NONE {
        return outer;
    }
    if outer == Tint::NONE {
        return inner;
    }
    let k = 1.0 - outer.weight;
    Tint {
        sum: std::array::from_fn(|i| inner.sum[i] * k + outer.sum[i]),
        weight: 1.0 - (1.0 - inner.weight) * k,
    }
}

struct Frame<'a> {
    tracks: &'a [Track],
    states: Vec<ShapeState>,
    t: f64,
}

/// What applies to the nodes being written.
#[derive(Clone, Copy)]
struct Ctx {
    /// Rest transform from the current coordinates to the canvas.
    abs: Affine,
    fill: Tint,
    stroke: Tint,
    /// Stroke width factor.
    width: f64,
    /// The strokes' visible part.
    trim: Trim,
}

impl Ctx {
    const REST: Ctx = Ctx {
        abs: Affine::IDENTITY,
        fill: Tint::NONE,
        stroke: Tint::NONE,
        width: 1.0,
        trim: Trim::REST,
    };
}

/// Which paints of a path an element draws: both, or one of a trimmed path's two.
#[derive(Clone, Copy, PartialEq)]
enum Paints {
    Both,
    Fill,
    Stroke,
}

struct Writer<'a> {
    scene: &'a Scene,
    frame: Option<Frame<'a>>,
    out: String,
    defs: Defs<'a>,
    /// Tracks deforming the unit being written, outermost first.
    deform: Vec<&'a Track>,
    /// The outlines of the morphing unit being written (one per path, in document order)
    /// and how many of its paths are written so far.
    morph: Option<(Vec<BezPath>, usize)>,
    /// Node ids written so far (`None` when ids are not written: frames and defs).
    written_ids: Option<HashSet<&'a str>>,
    /// Ids written in place of the nodes' own.
    ids: Option<&'a IdsByNode>,
}

impl<'a> Writer<'a> {
    fn document(mut self) -> String {
        let root = &self.scene.root;
        self.group(root, Ctx::REST);
        let mut body = std::mem::take(&mut self.out);
        self.written_ids = None;
        self.write_defs();
        let defs = std::mem::take(&mut self.out);

        let mut head = String::with_capacity(defs.len() + 160);
        head.push_str(ROOT);
        attr_num(&mut head, "width", self.scene.width);
        attr_num(&mut head, "height", self.scene.height);
        head.push_str(" viewBox=\"0 0 ");
        point(&mut head, Point::new(self.scene.width, self.scene.height));
        head.push_str("\">\n");
        if !defs.is_empty() {
            head.push_str("<defs>\n");
            head.push_str(&defs);
            head.push_str("</defs>\n");
        }
        // The head goes in front of the body in place: a copy of a large scene's body
        // would hold its text twice (the SMIL writer's peak at a million shapes).
        body.reserve_exact(head.len() + "</svg>\n".len());
        body.insert_str(0, &head);
        body.push_str("</svg>\n");
        body
    }

    fn id_attr(&mut self, id: &'a str) {
        if id.is_empty() {
            return;
        }
        if let Some(written) = &mut self.written_ids
            && written.insert(id)
        {
            self.out.push_str(" id=\"");
            escaped(&mut self.out, id);
            self.out.push('"');
        }
    }

    fn node(&mut self, node: &'a Node, ctx: Ctx) {
        if let Some(unit) = node.unit()
            && self.frame.is_some()
        {
            self.animated(node, unit, ctx);
            return;
        }
        self.plain(node, ctx);
    }

    fn plain(&mut self, node: &'a Node, ctx: Ctx) {
        match node {
            Node::Group(g) => self.group(g, ctx),
            Node::Path(p) => self.path(p, ctx),
            Node::Image(i) => self.image(i),
        }
    }

    /// Writes a unit node in the state its shape is in.
    fn animated(&mut self, node: &'a Node, unit: usize, ctx: Ctx) {
        let Some(frame) = &self.frame else {
            return self.plain(node, ctx);
        };
        let (Some(&state), Some(track), Some(shape)) = (
            frame.states.get(unit),
            frame.tracks.get(unit),
            self.scene.shapes.get(unit),
        ) else {
            return self.plain(node, ctx);
        };
        let deforms = track.deforms();
        let outlines = track.outlines_at(frame.t);
        if state == ShapeState::REST && !deforms && outlines.is_none() {
            return self.plain(node, ctx);
        }
        let opacity = state.opacity.clamp(0.0, 1.0);
        if opacity == 0.0 {
            return;
        }
        let p = shape.parent_transform;
        let ts = if deforms {
            Affine::IDENTITY
        } else {
            inverse(p) * state.transform * p
        };
        let wrapped = ts != Affine::IDENTITY || opacity != 1.0;
        if wrapped {
            self.out.push_str("<g");
            attr_transform(&mut self.out, "transform", ts);
            if opacity != 1.0 {
                attr_num(&mut self.out, "opacity", opacity);
            }
            self.out.push_str(">\n");
        }
        let inner = Ctx {
            abs: ctx.abs,
            fill: compose(ctx.fill, state.fill),
            stroke: compose(ctx.stroke, state.stroke),
            width: ctx.width * state.stroke_width,
            // A unit that never trims keeps the trim of the unit around it.
            trim: if track.trim.is_empty() {
                ctx.trim
            } else {
                state.trim
            },
        };
        if deforms {
            self.deform.push(track);
        }
        let outer = match outlines {
            Some(o) => self.morph.replace((o, 0)),
            None => self.morph.take(),
        };
        self.plain(node, inner);
        self.morph = outer;
        if deforms {
            self.deform.pop();
        }
        if wrapped {
            self.out.push_str("</g>\n");
        }
    }

    fn group(&mut self, g: &'a Group, ctx: Ctx) {
        let id = id_of(self.ids, g, &g.id);
        let bare = g.transform == Affine::IDENTITY
            && g.opacity == 1.0
            && g.clip_path.is_none()
            && g.mask.is_none()
            && g.filter.is_none()
            && (id.is_empty() || self.written_ids.is_none());
        if bare {
            return self.group_content(g, ctx);
        }
        self.out.push_str("<g");
        self.id_attr(id);
        attr_transform(&mut self.out, "transform", g.transform);
        if g.opacity != 1.0 {
            attr_num(&mut self.out, "opacity", g.opacity as f64);
        }
        if let Some(f) = &g.filter {
            let canvas = Rect::new(0.0, 0.0, self.scene.width, self.scene.height);
            let region = g
                .filter_region(ctx.abs * g.transform, canvas)
                .unwrap_or(f.region);
            self.url("filter", Def::Filter(f, region));
        }
        if let Some(c) = &g.clip_path {
            self.url("clip-path", Def::Clip(c, Affine::IDENTITY));
        }
        if let Some(m) = &g.mask {
            self.url("mask", Def::Mask(m));
        }
        if g.children.is_empty() {
            self.out.push_str("/>\n");
            return;
        }
        self.out.push_str(">\n");
        self.group_content(g, ctx);
        self.out.push_str("</g>\n");
    }

    /// Writes a group's children (its own attributes are the caller's business).
    fn group_content(&mut self, g: &'a Group, ctx: Ctx) {
        let inner = Ctx {
            abs: ctx.abs * g.transform,
            ..ctx
        };
        for child in &g.children {
            self.node(child, inner);
        }
    }

    fn path(&mut self, p: &'a PathNode, ctx: Ctx) {
        let deform = (!self.deform.is_empty()).then_some(ctx.abs);
        // A morph's in-between replaces the outline (one per path of the unit, in turn).
        let morphed = self.morph.as_mut().and_then(|(o, k)| {
            *k += 1;
            o.get(*k - 1).cloned()
        });
        let outline = morphed.as_ref().unwrap_or(&p.path);
        if p.stroke.is_none() || ctx.trim.is_whole() {
            return self.painted(p, outline, deform, ctx, Paints::Both);
        }
        // A trimmed stroke: the fill whole, the stroke a second element drawn along the
        // visible part of the (deformed) outline, in the path's paint order.
        let cut = ctx.trim.apply(&self.deformed(outline, deform));
        let fill = |w: &mut Self| {
            if p.fill.is_some() {
                w.painted(p, outline, deform, ctx, Paints::Fill);
            }
        };
        if !p.stroke_first {
            fill(self);
        }
        if !cut.is_empty() {
            self.painted(p, &cut, None, ctx, Paints::Stroke);
        }
        if p.stroke_first {
            fill(self);
        }
    }

    /// `path` mapped by the running per-vertex motions (`deform` is the path's rest
    /// transform to the canvas), or as it is.
    fn deformed(&self, path: &BezPath, deform: Option<Affine>) -> BezPath {
        let Some(abs) = deform else {
            return path.clone();
        };
        let t = self.frame.as_ref().map_or(0.0, |f| f.t);
        let back = inverse(abs);
        let mut out = path.clone();
        let map = |q: Point| {
            let mut c = abs * q;
            for track in self.deform.iter().rev() {
                c = track.deform(c, t);
            }
            back * c
        };
        for el in out.elements_mut() {
            *el = match *el {
                PathEl::MoveTo(a) => PathEl::MoveTo(map(a)),
                PathEl::LineTo(a) => PathEl::LineTo(map(a)),
                PathEl::QuadTo(a, b) => PathEl::QuadTo(map(a), map(b)),
                PathEl::CurveTo(a, b, c) => PathEl::CurveTo(map(a), map(b), map(c)),
                PathEl::ClosePath => PathEl::ClosePath,
            };
        }
        out
    }

    /// One `<path>` element of `p` drawn along `path`, with the paints `which` says.
    fn painted(
        &mut self,
        p: &'a PathNode,
        path: &BezPath,
        deform: Option<Affine>,
        ctx: Ctx,
        which: Paints,
    ) {
        self.out.push_str("<path");
        // A split path keeps its id on the fill (ids are unique).
        if which != Paints::Stroke || p.fill.is_none() {
            self.id_attr(id_of(self.ids, p, &p.id));
        }
        self.out.push_str(" d=\"");
        self.path_data(path, deform);
        self.out.push('"');
        match p.fill.as_ref().filter(|_| which != Paints::Stroke) {
            None => self.out.push_str(" fill=\"none\""),
            Some(f) => {
                self.paint("fill", &f.paint, ctx.fill);
                if f.opacity != 1.0 {
                    attr_num(&mut self.out, "fill-opacity", f.opacity as f64);
                }
                if f.rule == FillRule::EvenOdd {
                    self.out.push_str(" fill-rule=\"evenodd\"");
                }
            }
        }
        if let Some(s) = p.stroke.as_ref().filter(|_| which != Paints::Fill) {
            self.paint("stroke", &s.paint, ctx.stroke);
            if s.opacity != 1.0 {
                attr_num(&mut self.out, "stroke-opacity", s.opacity as f64);
            }
            let width = s.width * ctx.width;
            if width != 1.0 {
                attr_num(&mut self.out, "stroke-width", width);
            }
            match s.cap {
                LineCap::Butt => {}
                LineCap::Round => self.out.push_str(" stroke-linecap=\"round\""),
                LineCap::Square => self.out.push_str(" stroke-linecap=\"square\""),
            }
            match s.join {
                LineJoin::Miter => {}
                LineJoin::MiterClip => self.out.push_str(" stroke-linejoin=\"miter-clip\""),
                LineJoin::Round => self.out.push_str(" stroke-linejoin=\"round\""),
                LineJoin::Bevel => self.out.push_str(" stroke-linejoin=\"bevel\""),
            }
            if s.miter_limit != 4.0 {
                attr_num(&mut self.out, "stroke-miterlimit", s.miter_limit);
            }
            if let Some(dash) = s.dash.as_deref().filter(|d| !d.is_empty()) {
                self.out.push_str(" stroke-dasharray=\"");
                for (i, v) in dash.iter().enumerate() {
                    if i > 0 {
                        self.out.push(' ');
                    }
                    num(&mut self.out, *v);
                }
                self.out.push('"');
                if s.dash_offset != 0.0 {
                    attr_num(&mut self.out, "stroke-dashoffset", s.dash_offset);
                }
            }
            if p.stroke_first {
                self.out.push_str(" paint-order=\"stroke\"");
            }
        }
        self.out.push_str("/>\n");
    }

    /// An image, embedded as a `data:` URL. It keeps its pixels under colour motion (a tint
    /// recolours paints, and an image has none) and its rectangle under per-vertex motion.
    fn image(&mut self, i: &'a ImageNode) {
        self.out.push_str("<image");
        self.id_attr(id_of(self.ids, i, &i.id));
        attr_num(&mut self.out, "width", i.width);
        attr_num(&mut self.out, "height", i.height);
        // The groups around the image already fit it to its viewport.
        self.out.push_str(" preserveAspectRatio=\"none\"");
        if !i.smooth {
            self.out.push_str(" image-rendering=\"pixelated\"");
        }
        self.out.push_str(" href=\"");
        self.out.push_str(&i.data_url());
        self.out.push_str("\"/>\n");
    }

    fn paint(&mut self, attr: &str, paint: &'a Paint, tint: Tint) {
        match paint {
            Paint::Solid(c) => {
                self.out.push(' ');
                self.out.push_str(attr);
                self.out.push_str("=\"");
                hex(&mut self.out, tint.apply(*c));
                self.out.push('"');
            }
            Paint::Linear(g) => self.url(attr, Def::Linear(g, tint)),
            Paint::Radial(g) => self.url(attr, Def::Radial(g, tint)),
            Paint::Pattern(p) => self.url(attr, Def::Pattern(p, tint)),
        }
    }

    /// Writes path data; with `deform` (the path's rest transform to the canvas) every
    /// point goes through the deforming tracks, innermost first, the outline cut first
    /// where they bend it ([`gmotion::motion::bend`]).
    fn path_data(&mut self, path: &BezPath, deform: Option<Affine>) {
        let t = self.frame.as_ref().map_or(0.0, |f| f.t);
        // Cut where the field bends the outline, so the frame draws the field itself.
        let path = match deform {
            Some(abs) => {
                gmotion::motion::bend::refine(path, abs, &self.deform, &[t], BEND_TOLERANCE)
            }
            None => std::borrow::Cow::Borrowed(path),
        };
        let back = deform.map(inverse);
        let map = |q: Point| -> Point {
            match (deform, back) {
                (Some(abs), Some(back)) => {
                    let mut c = abs * q;
                    for track in self.deform.iter().rev() {
                        c = track.deform(c, t);
                    }
                    back * c
                }
                _ => q,
            }
        };
        let mut buf = std::mem::take(&mut self.out);
        for (i, el) in path.elements().iter().enumerate() {
            if i > 0 {
                buf.push(' ');
            }
            match *el {
                PathEl::MoveTo(p) => {
                    buf.push('M');
                    point(&mut buf, map(p));
                }
                PathEl::LineTo(p) => {
                    buf.push('L');
                    point(&mut buf, map(p));
                }
                PathEl::QuadTo(a, p) => {
                    buf.push('Q');
                    point(&mut buf, map(a));
                    buf.push(' ');
                    point(&mut buf, map(p));
                }
                PathEl::CurveTo(a, b, p) => {
                    buf.push('C');
                    point(&mut buf, map(a));
                    buf.push(' ');
                    point(&mut buf, map(b));
                    buf.push(' ');
                    point(&mut buf, map(p));
                }
                PathEl::ClosePath => buf.push('Z'),
            }
        }
        self.out = buf;
    }
}
