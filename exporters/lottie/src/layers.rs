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
//! - an animated shape: its own layer named after its tag (see [`units::layer_names`] and
//!   [`super::animate`]);
//! - a named group whose content makes layers: a null layer of its name, their parent
//!   (see [`Builder::named_group`]);
//! - an image: an image layer drawing an embedded image asset (see [`images`]).
//!
//! A layer holding only shapes is a shape layer; one holding layers is a precomposition,
//! whose content is drawn offset by a margin because players clip a precomposition to
//! its rectangle, which starts at the origin.
//!
//! This module walks the tree and decides what becomes a layer; the submodules hold the
//! rest, by concern: [`mattes`] (clip paths and masks), [`units`] (animated shapes),
//! [`paths`] (fills, strokes, outlines, deformation), [`patterns`] and [`images`].

mod effects;
mod images;
mod mattes;
mod morph;
mod paths;
mod patterns;
pub(crate) mod stream;
mod units;

use std::sync::Arc;

use kurbo::{Affine, BezPath, Point, Rect, Shape as _, Vec2};
use rayon::prelude::*;

use super::animate::{UnitMotion, WIDTH_FACTOR_TOLERANCE, is_even, static_level};
use super::bake::bake_paths;
use super::geometry::{Contour, contours, decompose, max_stretch};
use super::keys::{to_keyframes, within_range};
use super::model::{
    Asset, Bezier, Group as LGroup, Layer, LayerKind, Mask as LMask, N, PathShape, Prop, Shape,
    Transform, TrimPaths, Value, WriteLayer,
};
use super::paint::{self, PaintAnim, Styled};
use gmotion::color::Color;
use gmotion::engine::slots::SlotKinds;
use gmotion::keyframe::Key;
use gmotion::motion::{Track, Trim};
use gmotion::scene::{
    ClipPath, Fill, FillRule, Filter, Group, LineCap, LineJoin, Mask, MaskKind, Node, Paint,
    PathNode, Pattern, Scene, Stroke,
};
use mattes::{ClipKind, clip_group, mask, mask_group};
pub use units::layer_names;
pub(crate) use units::{conjugate, full_transform};

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

    fn layer(&mut self, ty: LayerKind, nm: String, op: f64) -> Layer {
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
        let mut bottom_up = self.take_layers(op);
        bottom_up.reverse();
        bottom_up
    }

    /// The layers made so far, bottom first, runs of shapes as shape layers; the
    /// composition keeps numbering after them.
    fn take_layers(&mut self, op: f64) -> Vec<Layer> {
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
        let mut l = self.layer(LayerKind::Shape, name, op);
        l.shapes = Some(run.drain(..).rev().collect());
        out.push(l);
    }
}

/// What a document's layers are built from: a scene and, for an animation, its shapes'
/// tracks and the motions baked from them (`tracks[i]` and `motions[i]` belong to
/// `scene.shapes[i]`; both are empty for a still).
#[derive(Clone, Copy)]
pub struct Source<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The shapes' tracks.
    pub tracks: &'a [Track],
    /// The shapes' motions, as the layers key them, from shape `first_motion` on (all of
    /// them, or those of the root's children being built: [`stream`]).
    pub motions: &'a [UnitMotion],
    /// The shape whose motion is `motions[0]`.
    pub first_motion: usize,
    /// The shapes' layer names ([`layer_names`]).
    pub names: &'a [String],
    /// Frames per second.
    pub fps: f64,
    /// The out point: the frame the document ends at.
    pub op: f64,
}

/// Builds the layers of a scene (or an animation's scene with its tracks).
pub struct Builder<'a> {
    src: Source<'a>,
    tolerance: f64,
    margin: f64,
    /// Warnings, one per dropped or approximated feature, naming the element.
    pub warnings: Vec<String>,
    /// Precompositions made so far.
    pub assets: Vec<Asset>,
    /// The properties given slots (marked for [`crate::slots`] to write).
    pub slots: SlotKinds,
}

impl<'a> Builder<'a> {
    /// A builder for `src`, baking deformed paths within `tolerance`.
    pub fn new(src: Source<'a>, tolerance: f64) -> Builder<'a> {
        let margin = src.scene.width.max(src.scene.height).ceil().max(1.0);
        Builder {
            src,
            tolerance,
            margin,
            warnings: Vec::new(),
            assets: Vec::new(),
            slots: SlotKinds::default(),
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
        let root = &self.src.scene.root;
        if root.unit.is_some() {
            // The walk takes a unit as a node; wrapping the root in one copies the whole
            // tree, so only a root that is a unit itself is.
            self.node(&Node::Group(root.clone()), Affine::IDENTITY, env, &mut comp);
        } else {
            self.group(root, Affine::IDENTITY, env, &mut comp);
        }
        comp.into_layers(self.src.op)
    }

    /// The number of the next precomposition: one past the highest made so far (image
    /// assets, shared by content, take no number).
    fn next_comp(&self) -> usize {
        self.assets
            .iter()
            .filter_map(|a| asset_number(&a.id))
            .max()
            .map_or(0, |k| k + 1)
    }

    fn motion(&self, unit: usize) -> Option<&'a UnitMotion> {
        let k = unit.checked_sub(self.src.first_motion)?;
        self.src.motions.get(k).filter(|m| m.is_animated())
    }

    fn node(&mut self, node: &Node, acc: Affine, env: Env, comp: &mut Comp) {
        if let Some(u) = node.unit()
            && env.unit != Some(u)
            && u < self.src.scene.shapes.len()
        {
            return self.unit(node, u, acc, env, comp);
        }
        match node {
            Node::Path(p) => self.path(p, acc, env, comp),
            Node::Group(g) => self.group(g, acc, env, comp),
            Node::Image(i) => self.image(i, acc, env, comp),
        }
    }

    fn children(&mut self, g: &Group, acc: Affine, env: Env, comp: &mut Comp) {
        if g.children.len() >= PARALLEL_CHILDREN {
            return self.children_in_parallel(g, acc, env, comp);
        }
        for child in &g.children {
            self.node(child, acc, env, comp);
        }
    }

    /// [`Self::children`] for many children: each is built on its own, numbered from 0
    /// and naming its precompositions from `comp_0`, then the parts are taken in document
    /// order and renumbered to where the sequential walk would have put them. A part's
    /// layers refer (by `parent`, `tp`) only to layers of the same composition, all
    /// shifted alike, and to assets (by `refId`) of its own, all renamed alike; warnings
    /// keep their order. So the document is the same on any number of threads (tested).
    fn children_in_parallel(&mut self, g: &Group, acc: Affine, env: Env, comp: &mut Comp) {
        let seed = self.seed();
        let parts: Vec<Part> = g
            .children
            .par_iter()
            .map(|child| seed.part(child, acc, env, true))
            .collect();
        for mut part in parts {
            let ind = comp.next_ind;
            let asset = self.adopt(&mut part);
            renumber(&mut part.items, ind, asset);
            comp.next_ind += part.inds;
            comp.items.append(&mut part.items);
        }
    }

    /// What a part needs of this builder to be built on its own thread.
    fn seed(&self) -> Seed<'a> {
        Seed {
            src: self.src,
            tolerance: self.tolerance,
            margin: self.margin,
            slots: self.slots,
        }
    }

    /// Takes `part`'s warnings, and its precompositions renamed after those made so far:
    /// returns the shift its layers' references to them take ([`renumber`]).
    fn adopt(&mut self, part: &mut Part) -> usize {
        let asset = self.next_comp();
        if asset > 0 {
            for a in &mut part.assets {
                rename_asset_id(&mut a.id, asset);
                for l in &mut a.layers {
                    rename_asset(&mut l.ref_id, asset);
                }
            }
        }
        self.warnings.append(&mut part.warnings);
        for a in std::mem::take(&mut part.assets) {
            // Image assets are named by their content: one copy of each.
            if a.image.is_none() || !self.assets.iter().any(|b| b.id == a.id) {
                self.assets.push(a);
            }
        }
        asset
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
        let isolate = clip.is_some()
            || g.mask.is_some()
            || g.filter.is_some()
            || (g.opacity < 1.0 && paints(g) > 1);
        if !isolate {
            env.alpha *= g.opacity as f64;
            if g.id.is_empty() || env.unit.is_some() {
                return self.children(g, acc * g.transform, env, comp);
            }
            return self.named_group(g, acc * g.transform, env, comp);
        }
        let layers = self.isolate(g, clip, acc, env, comp);
        comp.items.push(Item::Layers(layers));
    }

    /// The content of a named group that needs no layer of its own. When it makes layers,
    /// they are parented to a null layer named after the group (its id, as the designer
    /// wrote it), so the document's layer tree reads as the SVG's groups: the `Layer_1`
    /// null holds `letter_G` and the `Wheel` null, which holds the wheel's units. Runs of
    /// still shapes among them become shape layers of their own so they are parented too.
    ///
    /// The null is the identity: the content keeps the group's transform as an unnamed
    /// group's does, which is exact whatever the transform (a rotation under a non-uniform
    /// scale, for one, is a skew, which a null could say only with the `sk` rlottie does
    /// not draw) and needs no motion conjugated by it; the group's opacity, which a null
    /// does not pass on in Lottie, stays folded into its paints. A group whose only layer is named after it (a unit tagged
    /// with the group's name) gets no null: it would only repeat the name. Content that
    /// makes no layers (still shapes) stays in the shape layers as it was.
    fn named_group(&mut self, g: &Group, acc: Affine, env: Env, comp: &mut Comp) {
        let mut sub = Comp::new(comp.next_ind);
        self.children(g, acc, env, &mut sub);
        if sub.only_shapes() {
            comp.next_ind = sub.next_ind;
            comp.items.append(&mut sub.items);
            return;
        }
        let mut layers = sub.take_layers(self.src.op);
        let repeats_name =
            matches!(layers.as_slice(), [l] if l.nm.split(' ').next() == Some(g.id.as_str()));
        if !repeats_name {
            let null = sub.layer(LayerKind::Null, g.id.clone(), self.src.op);
            for l in layers.iter_mut().filter(|l| l.parent.is_none()) {
                l.parent = Some(null.ind);
            }
            layers.push(null);
        }
        comp.next_ind = sub.next_ind;
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
        if let Some(f) = &g.filter {
            let canvas = Rect::new(0.0, 0.0, self.src.scene.width, self.src.scene.height);
            let region = g
                .filter_region(env.to_canvas * inner, canvas)
                .unwrap_or(f.region);
            self.add_effects(&mut content, f, region, local * inner);
        }
        let opacity = g.opacity as f64 * env.alpha;
        if opacity < 1.0 {
            let o = Prop::scalar(N::coord(opacity * 100.0));
            match content.shapes.as_mut() {
                // Shape layers carry opacity on a group (which lottie-web also draws as group
                // opacity): rlottie's translucent layer dims everything under it by about
                // 1/255, which adds up over many layers (see `unit`).
                Some(shapes) => {
                    let mut it = std::mem::take(shapes);
                    it.push(Shape::Transform(Transform {
                        o: Some(o),
                        ..Transform::empty()
                    }));
                    *shapes = vec![Shape::Group(LGroup {
                        nm: String::new(),
                        it,
                    })];
                }
                None => content.ks.o = Some(o),
            }
        }
        let mut matte_group: Option<(Group, u8)> = None;
        match clip {
            Some(ClipKind::Masks(cs)) => {
                content.masks = cs
                    .iter()
                    .map(|c| mask(&c.transformed(local * inner)))
                    .collect();
                content.written.has_mask = Some(true);
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
            matte.td = true;
            let content = &mut out[0];
            content.tt = Some(mode.into());
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
            let mut l = comp.layer(LayerKind::Shape, name.to_string(), self.src.op);
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
        let id = asset_id(self.next_comp());
        let layers = sub.into_layers(self.src.op);
        self.assets.push(Asset {
            id: id.clone(),
            layers,
            image: None,
        });
        let mut l = comp.layer(LayerKind::Precomp, name.to_string(), self.src.op);
        l.ref_id = Some(id);
        l.w = Some(size.0);
        l.h = Some(size.1);
        l.ks.a = Some(Prop::vec(vec![N::coord(m), N::coord(m)]));
        (l, offset)
    }

    /// Puts `f`'s effects on `layer`, which draws the filtered group's content through
    /// `to_layer`, with `region` (in the group's coordinates, see [`Group::filter_region`])
    /// as an invisible shape at its bottom (see [`effects`]).
    fn add_effects(&mut self, layer: &mut Layer, f: &Filter, region: Rect, to_layer: Affine) {
        layer.effects = effects::effects(f, to_layer);
        self.warnings.push(effects::PLAYERS.to_string());
        let extent = effects::extent(to_layer.transform_rect_bbox(region));
        if let Some(shapes) = layer.shapes.as_mut() {
            shapes.push(extent);
            return;
        }
        let asset = layer
            .ref_id
            .as_ref()
            .and_then(|id| self.assets.iter_mut().find(|a| &a.id == id));
        if let Some(asset) = asset {
            let ind = asset.layers.iter().map(|l| l.ind).max().unwrap_or(0) + 1;
            let mut l = Layer::new(
                LayerKind::Shape,
                "filter region".to_string(),
                ind,
                0.0,
                self.src.op,
            );
            l.shapes = Some(vec![extent]);
            asset.layers.push(l);
        }
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
            Node::Image(_) => true,
            Node::Path(p) => {
                let pattern = |paint: &Paint| matches!(paint, Paint::Pattern(_));
                p.fill.as_ref().is_some_and(|f| pattern(&f.paint))
                    || p.stroke.as_ref().is_some_and(|s| pattern(&s.paint))
            }
            Node::Group(g) => {
                g.clip_path.is_some()
                    || g.mask.is_some()
                    || g.filter.is_some()
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
            let mut l = comp.layer(LayerKind::Shape, g.id.clone(), self.src.op);
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

    // ----- animated shapes -------------------------------------------------------------

    // ----- paths -------------------------------------------------------------------
}

/// Children of one group from which the builder makes them in parallel: the root of a
/// large animation holds thousands of animated shapes, each its own layer and motion
/// keys, and a handful is not worth waking the thread pool for.
const PARALLEL_CHILDREN: usize = 64;

/// One child of [`Builder::children_in_parallel`], built on its own.
struct Part {
    /// What it emitted, numbered from 0.
    items: Vec<Item>,
    /// The layer indices it used (its composition's `next_ind`).
    inds: u32,
    warnings: Vec<String>,
    /// Its precompositions, named from `comp_0`.
    assets: Vec<Asset>,
}

/// What [`Builder::children_in_parallel`] hands each thread: a builder's settings.
#[derive(Clone, Copy)]
struct Seed<'a> {
    src: Source<'a>,
    tolerance: f64,
    margin: f64,
    slots: SlotKinds,
}

impl Seed<'_> {
    /// `child` built on its own, numbered from 0 and naming its precompositions from
    /// `comp_0`; its finished layers written (`seal`) when they will be.
    fn part(self, child: &Node, acc: Affine, env: Env, seal: bool) -> Part {
        let mut b = Builder {
            src: self.src,
            tolerance: self.tolerance,
            margin: self.margin,
            warnings: Vec::new(),
            assets: Vec::new(),
            slots: self.slots,
        };
        let mut sub = Comp::new(0);
        b.node(child, acc, env, &mut sub);
        if seal && env.unit.is_none() {
            // Outside an animated shape, a composition's finished layers change later
            // only in their numbering and parent (an animated shape's own layers get its
            // opacity), so they can be written now.
            for item in &mut sub.items {
                if let Item::Layers(ls) = item {
                    ls.iter_mut().for_each(Layer::seal);
                }
            }
        }
        Part {
            items: sub.items,
            inds: sub.next_ind,
            warnings: b.warnings,
            assets: b.assets,
        }
    }
}

/// Numbers a part's layers after the `ind` layers and `asset` precompositions made before
/// it: they refer (by `parent`, `tp`) only to layers of the same part, all shifted alike,
/// and to assets (by `refId`) of its own, all renamed alike.
fn renumber(items: &mut [Item], ind: u32, asset: usize) {
    for item in items {
        if let Item::Layers(ls) = item {
            for l in ls {
                l.ind += ind;
                l.parent = l.parent.map(|p| p + ind);
                l.tp = l.tp.map(|p| p + ind);
                rename_asset(&mut l.ref_id, asset);
            }
        }
    }
}

/// The `k`-th precomposition's id.
fn asset_id(k: usize) -> String {
    format!("comp_{k}")
}

/// `k` from an id made by [`asset_id`]; `None` for an image asset's id.
fn asset_number(id: &str) -> Option<usize> {
    id.strip_prefix("comp_").and_then(|k| k.parse().ok())
}

/// Shifts a part's precomposition id by the `by` assets made before it (image ids name
/// content, not a position, and stay).
fn rename_asset_id(id: &mut String, by: usize) {
    if let Some(k) = asset_number(id) {
        *id = asset_id(k + by);
    }
}

/// [`rename_asset_id`] for a layer's reference.
fn rename_asset(ref_id: &mut Option<String>, by: usize) {
    if by > 0
        && let Some(id) = ref_id
    {
        rename_asset_id(id, by);
    }
}

/// How many paints `g` draws, counting to two.
fn paints(g: &Group) -> usize {
    let mut n = 0;
    for c in &g.children {
        n += match c {
            Node::Path(p) => p.fill.is_some() as usize + p.stroke.is_some() as usize,
            Node::Image(_) => 1,
            Node::Group(h) => paints(h),
        };
        if n > 1 {
            break;
        }
    }
    n
}
