//! The scene tree as Lottie layers and shapes.
//!
//! Plain content (paths, and groups whose effect can be folded into their children) becomes
//! nested shape groups in one shape layer, each path in a group carrying its full transform
//! as at most two skew-free levels. Whatever needs compositing of its own becomes a layer:
//!
//! - a group with a clip path: layer masks (`masksProperties`, mode add) when the clip is
//!   a union of single-contour non-zero outlines, else an alpha track matte drawn from the
//!   clip content filled white;
//! - a group with a mask: a luma (or alpha) track matte drawn from the mask content, itself
//!   clipped to the mask rectangle (a layer mask) and by the group's clip when that needs
//!   a matte too (clip and mask multiply, so the clip can be carried by the mask);
//! - a group with opacity below 1 that paints more than once: a layer with that opacity
//!   (group opacity composites the whole group, unlike per-paint opacity);
//! - a pattern paint: its tiles as content under an alpha matte of the painted outline;
//! - an animated shape: its own layer named `tag:id` (see [`super::animate`]).
//!
//! A layer holding only shapes is a shape layer; one holding layers is a precomposition,
//! whose content is drawn offset by a margin because players clip a precomposition to
//! its rectangle, which starts at the origin.

use std::sync::Arc;

use kurbo::{Affine, BezPath, Point, Rect, Shape as _, Vec2};

use super::animate::{UnitMotion, WIDTH_FACTOR_TOLERANCE, is_even, static_level};
use super::bake::bake_paths;
use super::geometry::{Contour, contours, decompose, max_stretch};
use super::keys::{Key, to_keyframes, within_range};
use super::model::{
    Asset, Bezier, Group as LGroup, Layer, LayerType, Mask as LMask, N, PathShape, Prop, Shape,
    Transform, Value,
};
use super::paint::{self, PaintAnim, Styled};
use gmotion::color::Color;
use gmotion::motion::Track;
use gmotion::scene::{
    ClipPath, Fill, FillRule, Group, LineCap, LineJoin, Mask, MaskKind, Node, Paint, PathNode,
    Pattern, Scene, Stroke,
};

/// Most pattern tiles drawn for one paint before falling back to a plain colour.
const MAX_TILES: f64 = 2500.0;

/// What applies to the nodes being emitted.
#[derive(Clone, Copy, Debug)]
struct Env {
    /// Opacity folded down from groups that paint once.
    alpha: f64,
    /// The animated shape being emitted, if any.
    unit: Option<usize>,
    /// From the current composition's coordinates to the canvas.
    to_canvas: Affine,
    /// The current composition's size.
    size: (u32, u32),
}

/// An emitted piece, in paint order.
enum Item {
    /// A shape group for the current shape layer.
    Shape(Box<Shape>),
    /// Finished layers, bottom first.
    Layers(Vec<Layer>),
}

/// A composition being built.
struct Comp {
    items: Vec<Item>,
    next_ind: u32,
}

impl Comp {
    fn new(next_ind: u32) -> Comp {
        Comp {
            items: Vec::new(),
            next_ind,
        }
    }

    fn layer(&mut self, ty: LayerType, nm: String, op: f64) -> Layer {
        self.next_ind += 1;
        Layer::new(ty, nm, self.next_ind, 0.0, op)
    }

    fn only_shapes(&self) -> bool {
        self.items.iter().all(|i| matches!(i, Item::Shape(_)))
    }

    /// The shapes, topmost first (for a composition of shapes only).
    fn into_shapes(self) -> Vec<Shape> {
        let mut out: Vec<Shape> = Vec::with_capacity(self.items.len());
        for item in self.items.into_iter().rev() {
            if let Item::Shape(s) = item {
                out.push(*s);
            }
        }
        out
    }

    /// The layers, topmost first; runs of shapes become shape layers.
    fn into_layers(mut self, op: f64) -> Vec<Layer> {
        let mut bottom_up: Vec<Layer> = Vec::new();
        let mut run: Vec<Shape> = Vec::new();
        let items = std::mem::take(&mut self.items);
        for item in items {
            match item {
                Item::Shape(s) => run.push(*s),
                Item::Layers(ls) => {
                    self.flush(&mut run, &mut bottom_up, op);
                    bottom_up.extend(ls);
                }
            }
        }
        self.flush(&mut run, &mut bottom_up, op);
        bottom_up.reverse();
        bottom_up
    }

    fn flush(&mut self, run: &mut Vec<Shape>, out: &mut Vec<Layer>, op: f64) {
        if run.is_empty() {
            return;
        }
        let name = match run.as_slice() {
            [Shape::Group(g)] if !g.nm.is_empty() => g.nm.clone(),
            _ => "shapes".to_string(),
        };
        let mut l = self.layer(LayerType::Shape, name, op);
        l.shapes = Some(run.drain(..).rev().collect());
        out.push(l);
    }
}

/// How a clip path can be written.
enum ClipKind {
    /// It clips everything away.
    Empty,
    /// As layer masks: closed contours in the clipped group's coordinates.
    Masks(Vec<Contour>),
    /// Only as a track matte.
    Matte,
}

/// Builds the layers of a scene (or an animation's scene with its tracks).
pub struct Builder<'a> {
    scene: &'a Scene,
    tracks: &'a [Track],
    motions: Vec<UnitMotion>,
    fps: f64,
    op: f64,
    tolerance: f64,
    margin: f64,
    /// Warnings, one per dropped or approximated feature, naming the element.
    pub warnings: Vec<String>,
    /// Precompositions made so far.
    pub assets: Vec<Asset>,
}

impl<'a> Builder<'a> {
    /// A builder for `scene`; `motions[i]` and `tracks[i]` belong to `scene.shapes[i]`
    /// (both empty for a still).
    pub fn new(
        scene: &'a Scene,
        tracks: &'a [Track],
        motions: Vec<UnitMotion>,
        fps: f64,
        op: f64,
        tolerance: f64,
    ) -> Builder<'a> {
        let margin = scene.width.max(scene.height).ceil().max(1.0);
        Builder {
            scene,
            tracks,
            motions,
            fps,
            op,
            tolerance,
            margin,
            warnings: Vec::new(),
            assets: Vec::new(),
        }
    }

    /// The root composition's layers, topmost first.
    pub fn layers(&mut self, size: (u32, u32)) -> Vec<Layer> {
        let env = Env {
            alpha: 1.0,
            unit: None,
            to_canvas: Affine::IDENTITY,
            size,
        };
        let mut comp = Comp::new(0);
        let root = self.scene.root.clone();
        self.node(&Node::Group(root), Affine::IDENTITY, env, &mut comp);
        let next = comp.next_ind;
        let mut layers = comp.into_layers(self.op);
        // Lottie sizes are whole pixels: stretch a fractional canvas onto them, through a
        // null parent (exact for every layer whatever its own transform).
        let scale = Vec2::new(
            size.0 as f64 / self.scene.width,
            size.1 as f64 / self.scene.height,
        );
        if (scale - Vec2::new(1.0, 1.0)).hypot() > 1e-9 {
            let ind = layers.iter().map(|l| l.ind).max().unwrap_or(next) + 1;
            for l in layers.iter_mut().filter(|l| l.parent.is_none()) {
                l.parent = Some(ind);
            }
            let mut null = Layer::new(LayerType::Null, "canvas".to_string(), ind, 0.0, self.op);
            null.ks.s = Some(Prop::vec(vec![
                N::fine(scale.x * 100.0),
                N::fine(scale.y * 100.0),
            ]));
            layers.push(null);
        }
        layers
    }

    fn motion(&self, unit: usize) -> Option<&UnitMotion> {
        self.motions.get(unit).filter(|m| m.is_animated())
    }

    fn node(&mut self, node: &Node, acc: Affine, env: Env, comp: &mut Comp) {
        if let Some(u) = node.unit()
            && env.unit != Some(u)
            && u < self.scene.shapes.len()
        {
            return self.unit(node, u, acc, env, comp);
        }
        match node {
            Node::Path(p) => self.path(p, acc, env, comp),
            Node::Group(g) => self.group(g, acc, env, comp),
        }
    }

    fn children(&mut self, g: &Group, acc: Affine, env: Env, comp: &mut Comp) {
        for child in &g.children {
            self.node(child, acc, env, comp);
        }
    }

    // ----- groups -----------------------------------------------------------------

    fn group(&mut self, g: &Group, acc: Affine, mut env: Env, comp: &mut Comp) {
        if g.opacity <= 0.0 || g.children.is_empty() {
            return;
        }
        let clip = g.clip_path.as_deref().map(|c| self.classify_clip(c));
        if matches!(clip, Some(ClipKind::Empty)) {
            return;
        }
        let isolate = clip.is_some() || g.mask.is_some() || (g.opacity < 1.0 && paints(g) > 1);
        if !isolate {
            env.alpha *= g.opacity as f64;
            return self.children(g, acc * g.transform, env, comp);
        }
        let layers = self.isolate(g, clip, acc, env, comp);
        comp.items.push(Item::Layers(layers));
    }

    /// Draws `g` as a layer of its own (plus its matte layer), bottom first.
    fn isolate(
        &mut self,
        g: &Group,
        clip: Option<ClipKind>,
        acc: Affine,
        env: Env,
        comp: &mut Comp,
    ) -> Vec<Layer> {
        let inner = acc * g.transform;
        let name = if g.id.is_empty() {
            "group".to_string()
        } else {
            g.id.clone()
        };
        let sub_env = Env { alpha: 1.0, ..env };
        let layered = self.children_need_layers(g, env.unit);
        let (mut content, local) =
            self.content_layer(&name, layered, sub_env, comp, |b, env, acc0, sub| {
                b.children(g, acc0 * inner, env, sub);
            });
        let opacity = g.opacity as f64 * env.alpha;
        if opacity < 1.0 {
            // On the layer, which every player but lottie-web's canvas renderer composites
            // whole; rlottie and ThorVG apply a shape group's opacity to each paint or path
            // in it (see `unit`).
            content.ks.o = Some(Prop::scalar(N::coord(opacity * 100.0)));
        }
        let mut matte_group: Option<(Group, u8)> = None;
        match clip {
            Some(ClipKind::Masks(cs)) => {
                content.masks = cs
                    .iter()
                    .map(|c| mask(&c.transformed(local * inner)))
                    .collect();
                content.has_mask = Some(true);
            }
            Some(ClipKind::Matte) => {
                let c = g.clip_path.as_ref().expect("a matte clip has a clip path");
                matte_group = Some((clip_group(c), 1));
            }
            Some(ClipKind::Empty) | None => {}
        }
        if let Some(m) = &g.mask {
            // A clip that needs a matte rides on the mask's matte (both multiply).
            let clip = matte_group
                .take()
                .map(|_| g.clip_path.clone().expect("clip"));
            let mode = if m.kind == MaskKind::Luminance { 3 } else { 1 };
            matte_group = Some((mask_group(m, clip), mode));
        }
        let mut out = vec![content];
        if let Some((mg, mode)) = matte_group {
            let matte_env = Env {
                alpha: 1.0,
                unit: None,
                ..env
            };
            let mut matte = self.one_layer(&mg, inner, matte_env, comp);
            matte.td = Some(1);
            let content = &mut out[0];
            content.tt = Some(mode);
            content.tp = Some(matte.ind);
            out.push(matte);
        }
        out
    }

    /// A layer holding what `draw` emits: a shape layer when `layered` is false (only
    /// shapes), else a precomposition drawn with the margin offset. `draw` gets the
    /// environment and the offset to prepend to transforms. Returns the layer and the map
    /// from the current composition's coordinates into the layer's own.
    fn content_layer(
        &mut self,
        name: &str,
        layered: bool,
        env: Env,
        comp: &mut Comp,
        draw: impl Fn(&mut Self, Env, Affine, &mut Comp),
    ) -> (Layer, Affine) {
        if !layered {
            let mut sub = Comp::new(comp.next_ind);
            draw(self, env, Affine::IDENTITY, &mut sub);
            comp.next_ind = sub.next_ind;
            let mut l = comp.layer(LayerType::Shape, name.to_string(), self.op);
            l.shapes = Some(sub.into_shapes());
            return (l, Affine::IDENTITY);
        }
        // Offset so that nothing falls left of or above the precomposition's clip rectangle.
        let m = self.margin;
        let offset = Affine::translate((m, m));
        let size = (env.size.0 + 2 * m as u32, env.size.1 + 2 * m as u32);
        let inner_env = Env {
            to_canvas: env.to_canvas * offset.inverse(),
            size,
            ..env
        };
        let mut sub = Comp::new(0);
        draw(self, inner_env, offset, &mut sub);
        let id = format!("comp_{}", self.assets.len());
        let layers = sub.into_layers(self.op);
        self.assets.push(Asset {
            id: id.clone(),
            layers,
        });
        let mut l = comp.layer(LayerType::Precomp, name.to_string(), self.op);
        l.ref_id = Some(id);
        l.w = Some(size.0);
        l.h = Some(size.1);
        l.ks.a = Some(Prop::vec(vec![N::coord(m), N::coord(m)]));
        (l, offset)
    }

    /// Whether drawing `node` makes layers (so its container must be a precomposition).
    fn needs_layers(&self, node: &Node, unit: Option<usize>) -> bool {
        if let Some(u) = node.unit()
            && unit != Some(u)
            && self.motion(u).is_some()
        {
            return true;
        }
        match node {
            Node::Path(p) => {
                let pattern = |paint: &Paint| matches!(paint, Paint::Pattern(_));
                p.fill.as_ref().is_some_and(|f| pattern(&f.paint))
                    || p.stroke.as_ref().is_some_and(|s| pattern(&s.paint))
            }
            Node::Group(g) => {
                g.clip_path.is_some()
                    || g.mask.is_some()
                    || (g.opacity < 1.0 && paints(g) > 1)
                    || g.children.iter().any(|c| self.needs_layers(c, unit))
            }
        }
    }

    fn children_need_layers(&self, g: &Group, unit: Option<usize>) -> bool {
        g.children.iter().any(|c| self.needs_layers(c, unit))
    }

    /// `g` as exactly one layer (a track matte source must be a single layer).
    fn one_layer(&mut self, g: &Group, acc: Affine, env: Env, comp: &mut Comp) -> Layer {
        let clip = g.clip_path.as_deref().map(|c| self.classify_clip(c));
        let needs_matte = g.mask.is_some() || matches!(clip, Some(ClipKind::Matte));
        if matches!(clip, Some(ClipKind::Empty)) {
            // Nothing shows: an empty shape layer.
            let mut l = comp.layer(LayerType::Shape, g.id.clone(), self.op);
            l.shapes = Some(Vec::new());
            return l;
        }
        if !needs_matte {
            let mut layers = self.isolate(g, clip, acc, env, comp);
            return layers.remove(0);
        }
        let name = if g.id.is_empty() {
            "matte".to_string()
        } else {
            g.id.clone()
        };
        let (l, _) = self.content_layer(&name, true, env, comp, |b, env, acc0, sub| {
            let clip = g.clip_path.as_deref().map(|c| b.classify_clip(c));
            let layers = b.isolate(g, clip, acc0 * acc, env, sub);
            sub.items.push(Item::Layers(layers));
        });
        l
    }

    fn classify_clip(&self, clip: &ClipPath) -> ClipKind {
        if clip.clip_path.is_some() {
            return ClipKind::Matte;
        }
        let mut out = Vec::new();
        if !collect_clip(&clip.root, clip.transform * clip.root.transform, &mut out) {
            return ClipKind::Matte;
        }
        if out.is_empty() {
            ClipKind::Empty
        } else {
            ClipKind::Masks(out)
        }
    }

    // ----- animated shapes -------------------------------------------------------------

    fn unit(&mut self, node: &Node, u: usize, acc: Affine, env: Env, comp: &mut Comp) {
        let shape = &self.scene.shapes[u];
        let name = format!("{}:{}", shape.tag, shape.id);
        let unit_env = Env {
            unit: Some(u),
            ..env
        };
        let Some(motion) = self.motion(u).cloned() else {
            // Still: a named group (or its layers, when it needs some).
            let mut sub = Comp::new(comp.next_ind);
            self.node(node, acc, unit_env, &mut sub);
            comp.next_ind = sub.next_ind;
            if sub.only_shapes() {
                let mut it = sub.into_shapes();
                if it.is_empty() {
                    return;
                }
                // A single path's group takes the shape's name; several get a named parent.
                if let [Shape::Group(g)] = it.as_mut_slice() {
                    g.nm = name;
                    comp.items.push(Item::Shape(Box::new(it.remove(0))));
                    return;
                }
                it.push(Shape::Transform(Transform::empty()));
                comp.items
                    .push(Item::Shape(Box::new(Shape::Group(LGroup { nm: name, it }))));
            } else {
                comp.items.extend(sub.items);
            }
            return;
        };
        let levels = conjugate(motion.levels.clone(), env.to_canvas);
        let opacity = |base: f64| -> Prop {
            if motion.opacity.is_empty() {
                Prop::scalar(N::coord(base * 100.0))
            } else {
                // The model clamps the factor to [0, 1] (frame_svg).
                let at = |a: &f64, b: &f64, p: f64| a + (b - a) * p;
                let keys = within_range(
                    &motion.opacity,
                    |a, b, lo, hi| {
                        [lo, hi]
                            .iter()
                            .any(|&p| !(0.0..=1.0).contains(&at(a, b, p)))
                    },
                    |a, b, p| at(a, b, p).clamp(0.0, 1.0),
                );
                Prop::keyed(to_keyframes(&keys, |m| {
                    Value::Scalar(N::coord(base * m * 100.0))
                }))
            }
        };
        let content_env = Env {
            alpha: 1.0,
            ..unit_env
        };
        let mut sub = Comp::new(comp.next_ind);
        self.node(node, acc, content_env, &mut sub);
        if sub.only_shapes() {
            comp.next_ind = sub.next_ind;
            // The content sits in the innermost level's group, the outermost is the
            // named group itself.
            let mut it = sub.into_shapes();
            if levels.is_empty() {
                it.push(Shape::Transform(Transform::empty()));
            }
            for (k, level) in levels.iter().enumerate().rev() {
                it.push(Shape::Transform(level.clone()));
                if k > 0 {
                    it = vec![Shape::Group(LGroup {
                        nm: String::new(),
                        it,
                    })];
                }
            }
            let mut l = comp.layer(LayerType::Shape, name.clone(), self.op);
            // Opacity on the layer, not the named group: rlottie applies a group's opacity
            // to each paint in it (a stroke over its own fill draws darker) and ThorVG to
            // each path (a path over another shows the one beneath, a stroke baked to an
            // outline shows the fill), while both composite a layer's whole without
            // dimming the layers beneath. lottie-web's svg renderer does too; its canvas
            // renderer applies either per paint (matrix.py, KNOWN).
            l.ks.o = Some(opacity(env.alpha));
            l.shapes = Some(vec![Shape::Group(LGroup { nm: name, it })]);
            comp.items.push(Item::Layers(vec![l]));
            return;
        }
        // Layers inside: the transform levels become a chain of null layers they parent to.
        let mut nulls = Vec::with_capacity(levels.len());
        for (k, level) in levels.iter().enumerate() {
            let nm = if k == 0 {
                name.clone()
            } else {
                format!("{name}/{k}")
            };
            let mut n = sub.layer(LayerType::Null, nm, self.op);
            n.ks = full_transform(level.clone());
            n.parent = nulls.last().map(|p: &Layer| p.ind);
            nulls.push(n);
        }
        let innermost = nulls.last().map(|n| n.ind);
        let mut layers = Vec::new();
        let mut run = Vec::new();
        let items = std::mem::take(&mut sub.items);
        for item in items {
            match item {
                Item::Shape(s) => run.push(*s),
                Item::Layers(ls) => {
                    sub.flush(&mut run, &mut layers, self.op);
                    layers.extend(ls);
                }
            }
        }
        sub.flush(&mut run, &mut layers, self.op);
        comp.next_ind = sub.next_ind;
        for l in &mut layers {
            if l.parent.is_none() {
                l.parent = innermost;
            }
            if l.td.is_none() {
                let base = match &l.ks.o {
                    Some(Prop::Fixed(Value::Scalar(x))) => x.0 / 100.0,
                    _ => 1.0,
                };
                l.ks.o = Some(opacity(base * env.alpha));
            }
        }
        if let Some(first) = layers.first_mut()
            && nulls.is_empty()
        {
            first.nm = name;
        }
        layers.extend(nulls);
        comp.items.push(Item::Layers(layers));
    }

    // ----- paths -------------------------------------------------------------------

    fn path(&mut self, p: &PathNode, acc: Affine, env: Env, comp: &mut Comp) {
        let cs = contours(&p.path);
        if cs.is_empty() || (p.fill.is_none() && p.stroke.is_none()) {
            return;
        }
        if cs
            .iter()
            .any(|c| c.points().any(|q| !q.x.is_finite() || !q.y.is_finite()))
        {
            self.warnings.push(format!(
                "element `{}`: the path has non-finite coordinates and is left out",
                p.id
            ));
            return;
        }
        let bbox = p.path.bounding_box();
        let motion = env.unit.and_then(|u| self.motion(u)).cloned();
        let anim = match &motion {
            Some(m) => PaintAnim {
                fill: &m.fill,
                stroke: &m.stroke,
                stroke_width: &m.stroke_width,
            },
            None => PaintAnim::default(),
        };
        let id = p.id.as_str();
        let fill = p
            .fill
            .as_ref()
            .and_then(|f| paint::fill(f, bbox, anim, id, &mut self.warnings));
        let deform = motion
            .as_ref()
            .filter(|m| !m.deform_frames.is_empty())
            .map(|m| (env.unit.expect("unit"), m.deform_frames.clone()));
        // A stroke under uneven scaling is drawn as its filled outline: players other than
        // lottie-web widen strokes by one averaged factor (rlottie) or scale the pen along
        // the canvas axes by the matrix's column lengths (ThorVG; wrong once the scaling
        // is rotated, as a skew's is), while an outline transforms exactly. Not when its
        // width animates or its outline moves per vertex.
        let uneven = !is_even(acc) || motion.as_ref().is_some_and(|m| m.anisotropic);
        let outline = p
            .stroke
            .as_ref()
            .filter(|s| {
                uneven && deform.is_none() && matches!(s.paint, Paint::Solid(_) | Paint::Linear(_))
            })
            .zip(held_factor(anim.stroke_width))
            .map(|(s, factor)| {
                let tolerance = 0.01 / max_stretch(acc).max(1e-9);
                let s = Stroke {
                    width: s.width * factor,
                    ..s.clone()
                };
                contours(&outline_path(&p.path, &s, tolerance))
            });
        let stroke = match (&p.stroke, &outline) {
            (Some(s), Some(o)) => {
                let area = o
                    .iter()
                    .flat_map(|c| c.points())
                    .fold(bbox, |r, q| r.union_pt(q));
                let as_fill = Fill {
                    paint: s.paint.clone(),
                    opacity: s.opacity,
                    rule: FillRule::NonZero,
                };
                let tinted = PaintAnim {
                    fill: anim.stroke,
                    ..PaintAnim::default()
                };
                paint::fill(&as_fill, area, tinted, id, &mut self.warnings)
                    .map(|st| (st, Role::Outline))
            }
            (Some(s), None) => {
                paint::stroke(s, bbox, anim, id, &mut self.warnings).map(|st| (st, Role::Stroke))
            }
            (None, _) => None,
        };
        let fill = fill.map(|f| (f, Role::Fill));
        // Paint order, bottom first.
        let mut paints: Vec<(Styled, Role)> = Vec::new();
        let (first, second) = if p.stroke_first {
            (stroke, fill)
        } else {
            (fill, stroke)
        };
        paints.extend(first);
        paints.extend(second);
        let geometry = |b: &Self, space: Affine| -> Vec<Prop> {
            match &deform {
                Some((u, frames)) => b.deformed(&cs, *u, frames, acc * space, env.to_canvas),
                None => {
                    let inv = space.inverse();
                    cs.iter()
                        .map(|c| Prop::fixed(Value::Bezier(c.transformed(inv).to_bezier())))
                        .collect()
                }
            }
        };
        let sh = |props: Vec<Prop>| {
            props
                .into_iter()
                .map(|ks| Shape::Path(PathShape { ks }))
                .collect::<Vec<_>>()
        };

        // Consecutive plain items share one group; the others need groups or layers.
        let mut parts: Vec<Part> = Vec::new();
        for (styled, role) in paints {
            let is_fill = role == Role::Fill;
            match styled {
                Styled::Item(s) if role == Role::Outline => parts.push(Part::Outline(s)),
                Styled::Item(s) => match parts.last_mut() {
                    Some(Part::Plain(v)) => v.push(s),
                    _ => parts.push(Part::Plain(vec![s])),
                },
                Styled::InSpace(s, space) => parts.push(Part::Space(s, space)),
                Styled::Pattern(pat, opacity) => {
                    let outline = if is_fill {
                        Outline::Fill(p.fill.clone().expect("fill"))
                    } else {
                        Outline::Stroke(p.stroke.clone().expect("stroke"))
                    };
                    match self.pattern_group(&pat, opacity, &p.path, outline, id) {
                        Some(g) => parts.push(Part::Layered(g)),
                        None => {
                            let c = paint::pattern_color(&pat);
                            let style = if is_fill {
                                let mut f = p.fill.clone().expect("fill");
                                f.paint = Paint::Solid(c);
                                paint::fill(&f, bbox, anim, id, &mut self.warnings)
                            } else {
                                let mut s = p.stroke.clone().expect("stroke");
                                s.paint = Paint::Solid(c);
                                paint::stroke(&s, bbox, anim, id, &mut self.warnings)
                            };
                            if let Some(Styled::Item(s)) = style {
                                match parts.last_mut() {
                                    Some(Part::Plain(v)) => v.push(s),
                                    _ => parts.push(Part::Plain(vec![s])),
                                }
                            }
                        }
                    }
                }
            }
        }

        let levels = decompose(acc, Point::ORIGIN);
        let alpha = env.alpha;
        let wrap = |mut it: Vec<Shape>, with_alpha: bool| -> Shape {
            // `it` holds the content; add the transform levels, outermost last added.
            let n = levels.len();
            for (k, level) in levels.iter().enumerate().rev() {
                let mut tr = static_level(level);
                if k == 0 && with_alpha && alpha < 1.0 {
                    tr.o = Some(Prop::scalar(N::coord(alpha * 100.0)));
                }
                it.push(Shape::Transform(tr));
                if k > 0 {
                    it = vec![Shape::Group(LGroup {
                        nm: String::new(),
                        it,
                    })];
                }
            }
            if n == 0 {
                it.push(Shape::Transform(Transform::empty()));
            }
            Shape::Group(LGroup {
                nm: id.to_string(),
                it,
            })
        };
        for part in parts {
            match part {
                Part::Plain(mut styles) => {
                    let mut it = sh(geometry(self, Affine::IDENTITY));
                    styles.reverse();
                    it.extend(styles);
                    comp.items.push(Item::Shape(Box::new(wrap(it, true))));
                }
                Part::Outline(style) => {
                    let o = outline.as_ref().expect("an outline part has an outline");
                    let mut it: Vec<Shape> = o
                        .iter()
                        .map(|c| {
                            Shape::Path(PathShape {
                                ks: Prop::fixed(Value::Bezier(c.to_bezier())),
                            })
                        })
                        .collect();
                    it.push(style);
                    comp.items.push(Item::Shape(Box::new(wrap(it, true))));
                }
                Part::Space(style, space) => {
                    let mut it = sh(geometry(self, space));
                    it.push(style);
                    let sub = decompose(space, Point::ORIGIN);
                    for (k, level) in sub.iter().enumerate().rev() {
                        it.push(Shape::Transform(static_level(level)));
                        if k > 0 {
                            it = vec![Shape::Group(LGroup {
                                nm: String::new(),
                                it,
                            })];
                        }
                    }
                    let inner = Shape::Group(LGroup {
                        nm: String::new(),
                        it,
                    });
                    comp.items
                        .push(Item::Shape(Box::new(wrap(vec![inner], true))));
                }
                Part::Layered(g) => {
                    let e = Env {
                        alpha: env.alpha,
                        unit: None,
                        ..env
                    };
                    self.group(&g, acc, e, comp);
                }
            }
        }
    }

    /// Outlines of `cs` (in coordinates mapped to the composition by `acc`) deformed at
    /// `frames` by unit `u`'s per-vertex motion, baked within the tolerance.
    fn deformed(
        &self,
        cs: &[Contour],
        u: usize,
        frames: &[f64],
        acc: Affine,
        to_canvas: Affine,
    ) -> Vec<Prop> {
        let to = to_canvas * acc;
        if !to.determinant().is_normal() {
            return cs
                .iter()
                .map(|c| Prop::fixed(Value::Bezier(c.to_bezier())))
                .collect();
        }
        let back = to.inverse();
        let track = &self.tracks[u];
        let shapes: Vec<Vec<Contour>> = frames
            .iter()
            .map(|f| {
                let t = f / self.fps;
                cs.iter()
                    .map(|c| {
                        let m = |p: &Point| back * track.deform(to * *p, t);
                        Contour {
                            closed: c.closed,
                            v: c.v.iter().map(m).collect(),
                            i: c.i.iter().map(m).collect(),
                            o: c.o.iter().map(m).collect(),
                        }
                    })
                    .collect()
            })
            .collect();
        bake_paths(frames, &shapes, max_stretch(to), self.tolerance)
    }

    /// A pattern paint as a group: the tiles, masked by the painted outline.
    fn pattern_group(
        &mut self,
        pat: &Pattern,
        opacity: f32,
        path: &BezPath,
        outline: Outline,
        element: &str,
    ) -> Option<Group> {
        let tile = pat.rect;
        if tile.width() <= 0.0 || tile.height() <= 0.0 || !pat.transform.determinant().is_normal() {
            return None;
        }
        let area = match &outline {
            Outline::Fill(_) => path.bounding_box(),
            Outline::Stroke(s) => path.bounding_box().inflate(s.width, s.width),
        };
        let inv = pat.transform.inverse();
        let corners = [
            area.origin(),
            Point::new(area.x1, area.y0),
            Point::new(area.x0, area.y1),
            Point::new(area.x1, area.y1),
        ];
        let local = corners.iter().map(|c| inv * *c).fold(
            Rect::from_points(inv * corners[0], inv * corners[0]),
            |r, p| r.union_pt(p),
        );
        let i0 = ((local.x0 - tile.x0) / tile.width()).floor();
        let i1 = ((local.x1 - tile.x0) / tile.width()).ceil();
        let j0 = ((local.y0 - tile.y0) / tile.height()).floor();
        let j1 = ((local.y1 - tile.y0) / tile.height()).ceil();
        let count = (i1 - i0) * (j1 - j0);
        if !(count.is_finite() && count <= MAX_TILES) {
            self.warnings.push(format!(
                "element `{element}`: pattern `{}` needs {count} tiles, more than Lottie output should hold; painted with its first colour",
                pat.id
            ));
            return None;
        }
        let content_bbox = bounds(&pat.root);
        let overflows = content_bbox.is_none_or(|b| {
            b.x0 < -1e-9
                || b.y0 < -1e-9
                || b.x1 > tile.width() + 1e-9
                || b.y1 > tile.height() + 1e-9
        });
        let tile_clip =
            overflows.then(|| rect_clip(Rect::new(0.0, 0.0, tile.width(), tile.height())));
        let mut tiles = Vec::with_capacity(count as usize);
        for j in j0 as i64..j1 as i64 {
            for i in i0 as i64..i1 as i64 {
                let at = Vec2::new(
                    tile.x0 + i as f64 * tile.width(),
                    tile.y0 + j as f64 * tile.height(),
                );
                tiles.push(Node::Group(Group {
                    transform: Affine::translate(at) * pat.root.transform,
                    clip_path: tile_clip.clone(),
                    children: strip_units(&pat.root.children),
                    ..Group::new()
                }));
            }
        }
        let outline_node = match outline {
            Outline::Fill(f) => PathNode {
                id: String::new(),
                path: path.clone(),
                fill: Some(Fill {
                    paint: Paint::Solid(Color::WHITE),
                    opacity: 1.0,
                    rule: f.rule,
                }),
                stroke: None,
                stroke_first: false,
                unit: None,
            },
            Outline::Stroke(s) => PathNode {
                id: String::new(),
                path: path.clone(),
                fill: None,
                stroke: Some(Stroke {
                    paint: Paint::Solid(Color::WHITE),
                    opacity: 1.0,
                    ..s
                }),
                stroke_first: false,
                unit: None,
            },
        };
        let mask = Mask {
            id: format!("{}-outline", pat.id),
            rect: area.inflate(1.0, 1.0),
            kind: MaskKind::Alpha,
            mask: None,
            root: Group {
                children: vec![Node::Path(outline_node)],
                ..Group::new()
            },
        };
        Some(Group {
            id: element.to_string(),
            opacity,
            mask: Some(Arc::new(mask)),
            children: vec![Node::Group(Group {
                transform: pat.transform,
                children: tiles,
                ..Group::new()
            })],
            ..Group::new()
        })
    }
}

/// A pattern-painted outline.
enum Outline {
    Fill(Fill),
    Stroke(Stroke),
}

/// What a paint of a path paints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    Fill,
    Stroke,
    /// A stroke drawn as the fill of its outline.
    Outline,
}

/// The outline of `path` stroked with `s` (in the path's coordinates).
fn outline_path(path: &BezPath, s: &Stroke, tolerance: f64) -> BezPath {
    use kurbo::{Cap, Join};
    let cap = match s.cap {
        LineCap::Butt => Cap::Butt,
        LineCap::Round => Cap::Round,
        LineCap::Square => Cap::Square,
    };
    let join = match s.join {
        LineJoin::Miter | LineJoin::MiterClip => Join::Miter,
        LineJoin::Round => Join::Round,
        LineJoin::Bevel => Join::Bevel,
    };
    let mut style = kurbo::Stroke::new(s.width)
        .with_caps(cap)
        .with_join(join)
        .with_miter_limit(s.miter_limit);
    if let Some(d) = s
        .dash
        .as_ref()
        .filter(|d| d.iter().skip(1).step_by(2).any(|g| *g > 0.0))
    {
        style = style.with_dashes(s.dash_offset, d.iter().copied());
    }
    kurbo::stroke(
        path.elements().iter().copied(),
        &style,
        &kurbo::StrokeOpts::default(),
        tolerance,
    )
}

/// A piece of a path's drawing.
enum Part {
    /// Style items drawn on the path's own geometry.
    Plain(Vec<Shape>),
    /// A stroke drawn as the fill of its outline.
    Outline(Shape),
    /// A style item drawn on the geometry mapped into a space.
    Space(Shape, Affine),
    /// A group standing for a pattern paint.
    Layered(Group),
}

/// The stroke width factor that `keys` hold throughout (1 without keys), or `None` when
/// the width changes. Smoothing rebuilds every channel from filtered samples, and a
/// constant width comes back within float noise of itself as keys of one value: that is
/// no width animation.
fn held_factor(keys: &[Key<f64>]) -> Option<f64> {
    let Some(first) = keys.first() else {
        return Some(1.0);
    };
    keys.iter()
        .all(|k| (k.v - first.v).abs() <= WIDTH_FACTOR_TOLERANCE)
        .then_some(first.v)
}

/// How many paints `g` draws, counting to two.
fn paints(g: &Group) -> usize {
    let mut n = 0;
    for c in &g.children {
        n += match c {
            Node::Path(p) => p.fill.is_some() as usize + p.stroke.is_some() as usize,
            Node::Group(h) => paints(h),
        };
        if n > 1 {
            break;
        }
    }
    n
}

/// Collects clip outlines as mask contours; false when they cannot all be layer masks.
fn collect_clip(g: &Group, ts: Affine, out: &mut Vec<Contour>) -> bool {
    for c in &g.children {
        match c {
            Node::Group(h) => {
                if h.clip_path.is_some() || h.mask.is_some() {
                    return false;
                }
                if !collect_clip(h, ts * h.transform, out) {
                    return false;
                }
            }
            Node::Path(p) => {
                let Some(f) = &p.fill else { continue };
                let cs = contours(&p.path);
                match cs.as_slice() {
                    [] => {}
                    [c] if f.rule == FillRule::NonZero => out.push(c.transformed(ts)),
                    _ => return false,
                }
            }
        }
    }
    true
}

/// A layer mask (mode add) of a contour.
fn mask(c: &Contour) -> LMask {
    let mut b: Bezier = c.to_bezier();
    b.c = true;
    LMask {
        mode: "a",
        pt: Prop::fixed(Value::Bezier(b)),
        o: Prop::scalar(N(100.0)),
        x: Prop::scalar(N(0.0)),
        inv: false,
    }
}

/// Clip content as an ordinary group: every outline filled opaque white with its clip rule,
/// under the clip's transform; a clip on the clip becomes the group's clip.
fn clip_group(clip: &ClipPath) -> Group {
    Group {
        id: clip.id.clone(),
        clip_path: clip.clip_path.clone(),
        children: vec![Node::Group(Group {
            transform: clip.transform * clip.root.transform,
            clip_path: clip.root.clip_path.clone(),
            children: whiten(&clip.root.children),
            ..Group::new()
        })],
        ..Group::new()
    }
}

fn whiten(nodes: &[Node]) -> Vec<Node> {
    nodes
        .iter()
        .filter_map(|n| match n {
            Node::Group(g) => Some(Node::Group(Group {
                id: g.id.clone(),
                transform: g.transform,
                opacity: 1.0,
                clip_path: g.clip_path.clone(),
                mask: None,
                children: whiten(&g.children),
                unit: None,
            })),
            Node::Path(p) => {
                let f = p.fill.as_ref()?;
                Some(Node::Path(PathNode {
                    id: p.id.clone(),
                    path: p.path.clone(),
                    fill: Some(Fill {
                        paint: Paint::Solid(Color::WHITE),
                        opacity: 1.0,
                        rule: f.rule,
                    }),
                    stroke: None,
                    stroke_first: false,
                    unit: None,
                }))
            }
        })
        .collect()
}

fn strip_units(nodes: &[Node]) -> Vec<Node> {
    nodes
        .iter()
        .map(|n| match n {
            Node::Group(g) => Node::Group(Group {
                children: strip_units(&g.children),
                unit: None,
                ..g.clone()
            }),
            Node::Path(p) => Node::Path(PathNode {
                unit: None,
                ..p.clone()
            }),
        })
        .collect()
}

/// Mask content as a group: clipped to the mask rectangle (and by `clip`), masked by the
/// mask's own mask.
fn mask_group(m: &Mask, clip: Option<Arc<ClipPath>>) -> Group {
    Group {
        id: m.id.clone(),
        clip_path: Some(rect_clip(m.rect)),
        children: vec![Node::Group(Group {
            clip_path: clip,
            mask: m.mask.clone(),
            children: vec![Node::Group(Group {
                children: strip_units(&m.root.children),
                ..m.root.clone()
            })],
            ..Group::new()
        })],
        ..Group::new()
    }
}

fn rect_clip(r: Rect) -> Arc<ClipPath> {
    let path = r.to_path(0.1);
    Arc::new(ClipPath {
        id: String::new(),
        transform: Affine::IDENTITY,
        clip_path: None,
        root: Group {
            children: vec![Node::Path(PathNode {
                id: String::new(),
                path,
                fill: Some(Fill {
                    paint: Paint::Solid(Color::WHITE),
                    opacity: 1.0,
                    rule: FillRule::NonZero,
                }),
                stroke: None,
                stroke_first: false,
                unit: None,
            })],
            ..Group::new()
        },
    })
}

/// The bounds of a group's drawing (strokes included) in its own coordinates.
fn bounds(g: &Group) -> Option<Rect> {
    let mut out: Option<Rect> = None;
    for c in &g.children {
        let b = match c {
            Node::Group(h) => bounds(h).map(|b| h.transform.transform_rect_bbox(b)),
            Node::Path(p) => {
                let w = p.stroke.as_ref().map_or(0.0, |s| s.width / 2.0 * 1.5);
                Some(p.path.bounding_box().inflate(w, w))
            }
        };
        if let Some(b) = b {
            out = Some(out.map_or(b, |o| o.union(b)));
        }
    }
    out
}

/// Moves canvas-space levels into a composition whose map to the canvas is `to_canvas`
/// (a translation): `C⁻¹·L₁·…·Lₙ·C`.
fn conjugate(mut levels: Vec<Transform>, to_canvas: Affine) -> Vec<Transform> {
    let shift = -to_canvas.translation();
    if shift == Vec2::ZERO || levels.is_empty() {
        return levels;
    }
    let n = levels.len();
    shift_prop(&mut levels[0].p, shift);
    shift_prop(&mut levels[n - 1].a, shift);
    levels
}

fn shift_prop(p: &mut Option<Prop>, by: Vec2) {
    let add = |v: &mut Value| {
        if let Value::Vec(xs) = v
            && xs.len() >= 2
        {
            xs[0] = N::coord(xs[0].0 + by.x);
            xs[1] = N::coord(xs[1].0 + by.y);
        }
    };
    match p {
        None => *p = Some(Prop::vec(vec![N::coord(by.x), N::coord(by.y)])),
        Some(Prop::Fixed(v)) => add(v),
        Some(Prop::Animated(keys)) => keys.iter_mut().for_each(|k| add(&mut k.s)),
    }
}

/// A transform with every channel written (for layers).
fn full_transform(t: Transform) -> Transform {
    let d = Transform::layer_identity();
    Transform {
        a: t.a.or(d.a),
        p: t.p.or(d.p),
        s: t.s.or(d.s),
        r: t.r.or(d.r),
        o: t.o.or(d.o),
    }
}
