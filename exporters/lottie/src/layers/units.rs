//! Animated units: each animated shape as a layer of its own, named after its tag
//! ([`layer_names`]), with its motion as nested transform levels (see `crate::animate`).

use std::collections::HashMap;

use gmotion::scene::Shape as Unit;
use gmotion::tagging::strip_counter;

use super::*;

/// The names of the layers the scene's shapes are exported as, in shape order (see
/// [`crate::to_lottie`]): a tag's only shape is named by the tag, the shapes of a tag that
/// has several by the tag and their number from 1 after a space (`Wheel 1`, `Wheel 2`), as
/// After Effects numbers copies. So a group's null (named after the group, `Wheel`) never
/// shares its name with the shapes tagged after it. A tag ending in what reads as a
/// counter (`Layer_1`) always gets a number (`Layer_1 1`): a Lottie import drops one
/// trailing counter from a layer name, so the tag reads back whole. The names are unique
/// among the shapes whose tags are grammar names (no spaces).
///
/// ```
/// use gmotion::scene::SceneBuilder;
/// use gmotion_export_lottie::layer_names;
/// use kurbo::{Rect, Shape as _};
///
/// let square = || Rect::new(0.0, 0.0, 10.0, 10.0).to_path(0.1);
/// let scene = SceneBuilder::new(100.0, 100.0)
///     .path("Wheel", square(), None, None)
///     .path("letter_G", square(), None, None)
///     .path("Wheel", square(), None, None)
///     .path("Layer_1", square(), None, None)
///     .build();
/// assert_eq!(
///     layer_names(&scene),
///     ["Wheel 1", "letter_G", "Wheel 2", "Layer_1 1"]
/// );
/// ```
pub fn layer_names(scene: &Scene) -> Vec<String> {
    let mut counts: HashMap<&str, usize> = HashMap::new();
    for s in &scene.shapes {
        *counts.entry(s.tag.as_str()).or_default() += 1;
    }
    let name = |s: &Unit| {
        if counts.get(s.tag.as_str()) == Some(&1) && strip_counter(&s.tag) == s.tag {
            s.tag.clone()
        } else {
            format!("{} {}", s.tag, s.id + 1)
        }
    };
    scene.shapes.iter().map(name).collect()
}

impl Builder<'_> {
    pub(super) fn unit(&mut self, node: &Node, u: usize, acc: Affine, env: Env, comp: &mut Comp) {
        let name = self.src.names.get(u).cloned().unwrap_or_default();
        let unit_env = Env {
            unit: Some(u),
            ..env
        };
        let Some(motion) = self.motion(u) else {
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
            for (k, level) in levels.into_iter().enumerate().rev() {
                it.push(Shape::Transform(level));
                if k > 0 {
                    it = vec![Shape::Group(LGroup {
                        nm: String::new(),
                        it,
                    })];
                }
            }
            let mut l = comp.layer(LayerKind::Shape, name.clone(), self.src.op);
            let slot = self.opacity_slot(u);
            if painting_groups(&it) > 1 {
                // ThorVG applies a group's opacity to each path in it (so a path over
                // another shows the one beneath, and a stroke baked to an outline shows
                // the fill), but composites a layer's as a whole.
                l.ks.o = Some(opacity(env.alpha));
                l.written.slot = slot.map(|id| (id, false));
            } else if let Some(Shape::Transform(tr)) = it.last_mut() {
                // One path: opacity on the outermost group rather than the layer. rlottie
                // composites a translucent layer by dimming everything beneath it by about
                // 1/255, which adds up: the cube example's background fell to alpha 215
                // under its ~50 fading units (its frames 81 and 98, 96% of pixels off) when
                // every unit carried its opacity on its layer. A group's opacity every player
                // draws over the path; rlottie and lottie-web's canvas apply it to fill and
                // stroke separately (matrix.py, KNOWN).
                tr.o = Some(opacity(env.alpha));
                l.written.slot = slot.map(|id| (id, true));
            }
            l.shapes = Some(vec![Shape::Group(LGroup { nm: name, it })]);
            comp.items.push(Item::Layers(vec![l]));
            return;
        }
        // Layers inside: the transform levels become a chain of null layers they parent to.
        let mut nulls = Vec::with_capacity(levels.len());
        for (k, level) in levels.into_iter().enumerate() {
            let nm = if k == 0 {
                name.clone()
            } else {
                format!("{name}/{k}")
            };
            let mut n = sub.layer(LayerKind::Null, nm, self.src.op);
            n.ks = full_transform(level);
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
                    sub.flush(&mut run, &mut layers, self.src.op);
                    layers.extend(ls);
                }
            }
        }
        sub.flush(&mut run, &mut layers, self.src.op);
        comp.next_ind = sub.next_ind;
        for l in &mut layers {
            if l.parent.is_none() {
                l.parent = innermost;
            }
            if !l.td {
                let base = match &l.ks.o {
                    Some(Prop::Static(Value::Scalar(x))) => x.0 / 100.0,
                    _ => 1.0,
                };
                l.ks.o = Some(opacity(base * env.alpha));
                l.written.slot = self.opacity_slot(u).map(|id| (id, false));
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
}

impl Builder<'_> {
    /// Unit `u`'s opacity slot id, `TAG.opacity`, where the `slots` directive asks.
    fn opacity_slot(&self, u: usize) -> Option<String> {
        let tag = &self.src.scene.shapes.get(u)?.tag;
        self.slots.opacity.then(|| format!("{tag}.opacity"))
    }
}

/// Moves canvas-space levels into a composition whose map to the canvas is `to_canvas`
/// (a translation): `C⁻¹·L₁·…·Lₙ·C`.
pub(crate) fn conjugate(mut levels: Vec<Transform>, to_canvas: Affine) -> Vec<Transform> {
    let shift = -to_canvas.translation();
    if shift == Vec2::ZERO || levels.is_empty() {
        return levels;
    }
    let n = levels.len();
    shift_prop(&mut levels[0].p, shift);
    shift_prop(&mut levels[n - 1].a, shift);
    levels
}

pub(crate) fn shift_prop(p: &mut Option<Prop>, by: Vec2) {
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
        Some(Prop::Static(v)) => add(v),
        Some(Prop::Animated(keys)) => keys.iter_mut().filter_map(|k| k.s.as_mut()).for_each(add),
    }
}

/// A transform with every channel written (for layers).
pub(crate) fn full_transform(t: Transform) -> Transform {
    let d = crate::model::layer_identity();
    Transform {
        a: t.a.or(d.a),
        p: t.p.or(d.p),
        s: t.s.or(d.s),
        r: t.r.or(d.r),
        o: t.o.or(d.o),
        ..Transform::empty()
    }
}

/// How many of `items`' groups (counting `items` itself) draw a fill or stroke of their
/// own, counting to two.
fn painting_groups(items: &[Shape]) -> usize {
    let mut n = items.iter().any(|s| {
        matches!(
            s,
            Shape::Fill(_) | Shape::Stroke(_) | Shape::GradientFill(_) | Shape::GradientStroke(_)
        )
    }) as usize;
    for s in items {
        if n > 1 {
            break;
        }
        if let Shape::Group(g) = s {
            n += painting_groups(&g.it);
        }
    }
    n
}
