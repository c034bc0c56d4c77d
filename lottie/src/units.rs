//! The units a document's root layers make, and the scene they draw at a frame: which layer
//! is a unit, a part (`--units groups`), a rig or nothing ([`Role`]), each unit's tag and
//! aliases (from [`crate::tags`]), the world of the layer it hangs from, and its measure.
//! The importer builds them at the reference frame; [`crate::Source::scene_at`] builds the
//! same units again at any frame, which is why they live beside the player.

use kurbo::{Affine, Point, Rect};

use gmotion::color::Color;
use gmotion::measure::measure;
use gmotion::scene::{Group, Node, Shape};

use crate::model::{self, Document};
use crate::{build, eval, tags};

/// What a Lottie scene's units are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Units {
    /// Every root layer that draws (`--units auto`).
    #[default]
    Layers,
    /// Every top-level item of a shape layer that has outlines of its own (a group, or a
    /// path, rectangle, ellipse or star outside any group) is a unit, styled by the
    /// layer's fills and strokes as in the layer; other layers, and shape layers with a
    /// track matte, stay whole (`--units groups`).
    Groups,
}

/// The root layers one unit moves.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitLayers {
    /// Indices into the document's root `layers`: the unit's layer first, then its track
    /// matte's source when it has one.
    pub layers: Vec<usize>,
    /// For each of `layers`, its parent's world transform at the reference frame (the
    /// identity for a layer without a parent): where a motion in canvas space must be
    /// conjugated to act in the parent's space. For a part, the world transform of its
    /// layer, where it moves. Where that is scaled to nothing at the reference frame, the
    /// first later frame's where it is not.
    pub parent_world: Vec<Affine>,
    /// With `--units groups`, the index in the layer's `shapes` of the top-level item the
    /// unit is (the layer's other parts are other units); `None` for a whole layer.
    pub part: Option<usize>,
    /// What the unit measured at the reference frame (`None`: no geometry); a frame drawn
    /// later ([`crate::Source::scene_at`]) keeps it rather than measuring again.
    pub measure: Option<gmotion::measure::Measure>,
}

/// What [`scene_of`] makes: the root group, the units' shapes, their layers, and the
/// warnings (JSON location, what) of what was not drawn.
pub type Built = (Group, Vec<Shape>, Vec<UnitLayers>, Vec<(String, String)>);

/// For each unit, the layers whose worlds are its `parent_world` (`None`: the canvas).
type Anchors = Vec<Vec<Option<usize>>>;

/// The document drawn at `frame`; its units measured, or given the measures of
/// `reference` (the same units, at the reference frame).
pub fn scene_of(
    doc: &Document,
    frame: f64,
    mode: Units,
    reference: Option<&[UnitLayers]>,
) -> model::Result<Built> {
    let mut b = build::Builder::new(doc);
    let layers = &doc.layers;
    let worlds = b.worlds(layers, frame)?;
    let parents = parent_indices(layers);
    let parent_of = |i: usize| parents[i];
    let mut roles = roles(layers, mode, &parent_of);
    for &i in &doc.split {
        roles[i] = Role::Parts;
    }
    let mut anchors: Anchors = Vec::new();
    let mut root = Group::new();
    let mut shapes = Vec::new();
    let mut units = Vec::new();
    let mut counts: std::collections::HashMap<String, usize> = Default::default();
    let mut stack = Vec::new();
    for i in (0..layers.len()).rev() {
        let l = &layers[i];
        let matte = build::Builder::matte_source(layers, i);
        let parts: Vec<Option<usize>> = match roles[i] {
            Role::Whole => vec![None],
            Role::Parts => split_parts(l),
            Role::Rig | Role::None => continue,
        };
        for part in parts {
            let mut node = b.drawn(layers, i, &worlds, frame, &mut stack, part)?;
            if !(l.ip <= frame && frame < l.op) {
                // Not on screen at the reference frame: measured, but not drawn in the still.
                node.opacity = 0.0;
            }
            let index = shapes.len();
            let mut node_path = vec![root.children.len()];
            match (part, &node.mask, node.children.as_mut_slice()) {
                // A part moves inside its layer, under the layer's masks (they wrap the
                // layer, [`build::Builder::layer_node`]), which stay where they are.
                (Some(_), Some(_), [Node::Group(layer)]) => {
                    layer.unit = Some(index);
                    node_path.push(0);
                }
                _ => node.unit = Some(index),
            }
            // A text layer's letters, laid out when it is imported.
            let text = match (reference, part, l.kind) {
                (None, None, model::LayerKind::Text) => crate::cut::text_place(
                    &mut b,
                    doc,
                    l,
                    matte.is_some(),
                    frame,
                    (node.transform, worlds[i]),
                )?,
                _ => gmotion::text::TextPlace::default(),
            };
            let node = Node::Group(node);
            // Measuring resolves every overlap of the unit's outlines, which takes seconds
            // for a rich precomposition: done once, at the reference frame.
            let m = match reference {
                Some(units) => units.get(index).and_then(|u| u.measure),
                None => measure(&node, Affine::IDENTITY),
            };
            let at = worlds[i] * Point::ORIGIN;
            let layer_tag = tags::layer_tag(&l.nm, l.kind);
            let item = part.and_then(|k| l.shapes.get(k));
            let tag = match item {
                Some(item) => tags::part_tag(&item.nm, &item.kind),
                None => layer_tag.clone(),
            };
            let own = item.and_then(|item| gmotion::tagging::grammar_name(item.nm.trim()));
            let (aliases, inherited) = names_of(layers, &roles, &parent_of, i, &tag, own);
            let id = counts.entry(tag.clone()).or_default();
            shapes.push(Shape {
                tag,
                aliases,
                inherited,
                rig: false,
                id: *id,
                group: 0,
                z: index,
                node_path,
                parent_transform: Affine::IDENTITY,
                centroid: m.map_or(at, |m| m.centroid),
                bbox: m.map_or(Rect::from_points(at, at), |m| m.bbox),
                fill: m.map_or(Color::BLACK, |m| m.fill),
                stroke: m.map_or(Color::BLACK, |m| m.stroke),
                stroke_width: m.map_or(1.0, |m| m.stroke_width),
                text,
            });
            *id += 1;
            let mut members = vec![i];
            members.extend(matte);
            // A part moves inside its layer: in the layer's own space.
            let anchor: Vec<Option<usize>> = match part {
                Some(_) => vec![Some(i)],
                None => members.iter().map(|&j| parent_of(j)).collect(),
            };
            units.push(UnitLayers {
                parent_world: anchor
                    .iter()
                    .map(|a| a.map_or(Affine::IDENTITY, |j| worlds[j]))
                    .collect(),
                layers: members,
                part,
                measure: m,
            });
            anchors.push(anchor);
            root.children.push(node);
        }
    }
    rigs(
        doc,
        &worlds,
        (&roles, &parent_of),
        frame,
        &mut counts,
        (&mut root, &mut shapes, &mut units, &mut anchors),
    );
    if reference.is_none() {
        first_invertible_worlds(&mut b, layers, frame, doc.op, &mut units, &anchors)?;
    }
    Ok((root, shapes, units, b.warnings()))
}

/// Each layer's parent, as an index into `layers` (the first layer with the `ind` its
/// `parent` names; `None` without a parent, or when none has that `ind`).
pub fn parent_indices(layers: &[model::Layer]) -> Vec<Option<usize>> {
    let mut by_ind = std::collections::HashMap::new();
    for (i, l) in layers.iter().enumerate() {
        if let Some(ind) = l.ind {
            by_ind.entry(ind).or_insert(i);
        }
    }
    layers
        .iter()
        .map(|l| l.parent.and_then(|p| by_ind.get(&p)).copied())
        .collect()
}

/// What a root layer is to the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// One unit.
    Whole,
    /// Split into units, one per top-level item (`--units groups`).
    Parts,
    /// A rig: a layer that draws no unit of its own (a null, a hidden layer) but moves the
    /// units parented to it.
    Rig,
    /// Neither.
    None,
}

/// Each root layer's [`Role`].
pub fn roles(
    layers: &[model::Layer],
    mode: Units,
    parent_of: &dyn Fn(usize) -> Option<usize>,
) -> Vec<Role> {
    let mut roles: Vec<Role> = layers
        .iter()
        .enumerate()
        .map(|(i, l)| {
            if !l.kind.draws() || l.hidden || l.td {
                Role::None
            } else if mode == Units::Groups
                && l.kind == model::LayerKind::Shape
                // A matted layer stays whole, as its matte moves with it.
                && build::Builder::matte_source(layers, i).is_none()
            {
                Role::Parts
            } else {
                Role::Whole
            }
        })
        .collect();
    // Every layer up a unit's chain of parents that is no unit itself moves it: a rig.
    for i in 0..layers.len() {
        if !matches!(roles[i], Role::Whole | Role::Parts) {
            continue;
        }
        let mut at = parent_of(i);
        let mut hops = 0;
        while let Some(j) = at.filter(|_| hops <= layers.len()) {
            if roles[j] == Role::None {
                roles[j] = Role::Rig;
            }
            at = parent_of(j);
            hops += 1;
        }
    }
    roles
}

/// A shape layer's parts (`--units groups`): its top-level items with outlines of their
/// own, bottom first.
pub fn split_parts(l: &model::Layer) -> Vec<Option<usize>> {
    l.shapes
        .iter()
        .enumerate()
        .rev()
        .filter(|(_, item)| !item.hidden && item.kind.part_name().is_some())
        .map(|(k, _)| Some(k))
        .collect()
}

/// The aliases of a unit on layer `i` whose tag is `tag` (its `own` name as written first,
/// e.g. a part's, counter kept), and how many of them are inherited: its layer's names,
/// then its parents', nearest first, so a rule can name one layer of several, a rig that
/// moves several, or every part of a layer. A parent that moves the unit through
/// parenting (a unit or a rig) is inherited: a rule naming it moves the unit once, through
/// the parent. A layer split into parts moves none of its children, so its name stays the
/// children's own.
fn names_of(
    layers: &[model::Layer],
    roles: &[Role],
    parent_of: &dyn Fn(usize) -> Option<usize>,
    i: usize,
    tag: &str,
    own: Option<String>,
) -> (Vec<String>, usize) {
    let names = |l: &model::Layer| {
        [
            gmotion::tagging::grammar_name(l.nm.trim()),
            Some(tags::layer_tag(&l.nm, l.kind)),
        ]
        .into_iter()
        .flatten()
    };
    let mut mine: Vec<String> = Vec::new();
    let mut theirs: Vec<String> = Vec::new();
    for name in own.into_iter().chain(names(&layers[i])) {
        if name != tag && !mine.contains(&name) {
            mine.push(name);
        }
    }
    let mut at = parent_of(i);
    let mut hops = 0;
    while let Some(j) = at.filter(|_| hops <= layers.len()) {
        let carries = matches!(roles[j], Role::Whole | Role::Rig);
        for name in names(&layers[j]) {
            if name == tag || mine.contains(&name) || theirs.contains(&name) {
                continue;
            }
            match carries {
                true => theirs.push(name),
                false => mine.push(name),
            }
        }
        at = parent_of(j);
        hops += 1;
    }
    let inherited = theirs.len();
    mine.extend(theirs);
    (mine, inherited)
}

/// Appends the rigs (layers of [`Role::Rig`], top layer last) as units after the drawn
/// ones, so that the drawn units keep their places and ids: each draws nothing, pivots
/// about its anchor point at `frame`, and spans the units it moves.
fn rigs(
    doc: &Document,
    worlds: &[Affine],
    (roles, parent_of): (&[Role], &dyn Fn(usize) -> Option<usize>),
    frame: f64,
    counts: &mut std::collections::HashMap<String, usize>,
    (root, shapes, units, anchors): (
        &mut Group,
        &mut Vec<Shape>,
        &mut Vec<UnitLayers>,
        &mut Anchors,
    ),
) {
    let layers = &doc.layers;
    let drawn = shapes.len();
    for r in (0..layers.len()).rev().filter(|&r| roles[r] == Role::Rig) {
        let l = &layers[r];
        let pivot = worlds[r] * eval::vec2(l.ks.a.as_ref(), frame, kurbo::Vec2::ZERO).to_point();
        // The box of every drawn unit it moves.
        let moves = |u: &UnitLayers| {
            let mut at = u.layers.first().copied();
            let mut hops = 0;
            while let Some(j) = at.filter(|_| hops <= layers.len()) {
                if j == r {
                    return true;
                }
                at = parent_of(j);
                hops += 1;
            }
            false
        };
        let bbox = units[..drawn]
            .iter()
            .zip(&shapes[..drawn])
            .filter(|(u, _)| moves(u))
            .map(|(_, s)| s.bbox)
            .reduce(|a, b| a.union(b))
            .unwrap_or(Rect::from_points(pivot, pivot));
        let tag = tags::layer_tag(&l.nm, l.kind);
        let (aliases, inherited) = names_of(layers, roles, parent_of, r, &tag, None);
        let index = shapes.len();
        let id = counts.entry(tag.clone()).or_default();
        shapes.push(Shape {
            tag,
            aliases,
            inherited,
            rig: true,
            id: *id,
            group: 0,
            z: index,
            node_path: vec![root.children.len()],
            parent_transform: Affine::IDENTITY,
            centroid: pivot,
            bbox,
            fill: Color::BLACK,
            stroke: Color::BLACK,
            stroke_width: 1.0,
            text: gmotion::text::TextPlace::default(),
        });
        *id += 1;
        let anchor = vec![parent_of(r)];
        units.push(UnitLayers {
            parent_world: anchor
                .iter()
                .map(|a| a.map_or(Affine::IDENTITY, |j| worlds[j]))
                .collect(),
            layers: vec![r],
            part: None,
            measure: None,
        });
        anchors.push(anchor);
        let mut node = Group::new();
        node.unit = Some(index);
        root.children.push(Node::Group(node));
    }
}

/// Gives each unit whose anchor layer is scaled to nothing at the reference `frame` (a
/// layer that pops in from zero scale) the anchor's world at the first later frame where
/// it is invertible (sampled at up to [`INVERTIBLE_SEARCH`] frames before `op`): motion in
/// canvas space is carried into that layer's space through it, on export and in
/// [`crate::Source::scene_at`] alike. One that never becomes invertible keeps its singular world
/// (its motion is left out, with a warning, on export).
fn first_invertible_worlds(
    b: &mut build::Builder,
    layers: &[model::Layer],
    frame: f64,
    op: f64,
    units: &mut [UnitLayers],
    anchors: &Anchors,
) -> model::Result<()> {
    let singular = |a: &Affine| a.determinant().abs() < 1e-12;
    if !units.iter().any(|u| u.parent_world.iter().any(singular)) {
        return Ok(());
    }
    let step = ((op - frame) / INVERTIBLE_SEARCH as f64).max(1.0);
    let mut at = frame + step;
    while at < op && units.iter().any(|u| u.parent_world.iter().any(singular)) {
        let worlds = b.worlds(layers, at)?;
        for (u, anchor) in units.iter_mut().zip(anchors) {
            for (w, a) in u.parent_world.iter_mut().zip(anchor) {
                if let Some(j) = *a
                    && singular(w)
                    && !singular(&worlds[j])
                {
                    *w = worlds[j];
                }
            }
        }
        at += step;
    }
    Ok(())
}

/// At most this many frames are tried by [`first_invertible_worlds`].
const INVERTIBLE_SEARCH: usize = 2000;
