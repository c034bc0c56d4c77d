//! Paths as Lottie shapes: outlines, fills and strokes in paint order, skewed strokes as
//! filled outlines, per-vertex deformation baked into path keyframes.

use super::*;

impl Builder<'_> {
    pub(super) fn path(&mut self, p: &PathNode, acc: Affine, env: Env, comp: &mut Comp) {
        let morph = env.unit.and_then(|u| self.morph_leaf(u, p));
        // An outline a per-vertex motion moves is cut where the field bends it, at any of
        // the frames its keyframes sample ([`gmotion::motion::bend`]); a morphing one is
        // baked from its in-betweens, which are not cut.
        let bent = env
            .unit
            .filter(|_| morph.is_none())
            .and_then(|u| self.motion(u).map(|m| (u, m)))
            .filter(|(_, m)| !m.deform_frames.is_empty())
            .map(|(u, m)| {
                let times: Vec<f64> = m.deform_frames.iter().map(|f| f / self.src.fps).collect();
                let tracks = [&self.src.tracks[u]];
                let abs = env.to_canvas * acc;
                gmotion::motion::bend::refine(&p.path, abs, &tracks, &times, self.tolerance)
            });
        let cs = contours(bent.as_deref().unwrap_or(&p.path));
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
        let motion = env.unit.and_then(|u| self.motion(u));
        let anim = match motion {
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
            .filter(|m| !m.deform_frames.is_empty())
            .map(|m| (env.unit.expect("unit"), m.deform_frames.as_slice()));
        // A stroke under uneven scaling is drawn as its filled outline: players other than
        // lottie-web widen strokes by one averaged factor (rlottie) or scale the pen along
        // the canvas axes by the matrix's column lengths (ThorVG; wrong once the scaling
        // is rotated, as a skew's is), while an outline transforms exactly. Not when its
        // width animates or its outline moves per vertex.
        // A trimmed stroke sits in a group of its own with the trim, the fill untouched.
        let trim = motion.and_then(|m| trim_paths(&m.trim));
        let uneven = !is_even(acc) || motion.is_some_and(|m| m.anisotropic);
        let outline = p
            .stroke
            .as_ref()
            .filter(|s| {
                uneven
                    && deform.is_none()
                    && trim.is_none()
                    && morph.is_none()
                    && matches!(s.paint, Paint::Solid(_) | Paint::Linear(_))
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
        if trim.is_some() && matches!(stroke, Some((Styled::Pattern(..), _))) {
            self.warnings.push(format!(
                "element `{id}`: a stroke painted with a pattern is drawn whole, not trimmed"
            ));
        }
        // Paint order, bottom first.
        let mut paints: Vec<(Styled, Role)> = Vec::new();
        let (first, second) = if p.stroke_first {
            (stroke, fill)
        } else {
            (fill, stroke)
        };
        paints.extend(first);
        paints.extend(second);
        if let Some(u) = env.unit {
            self.mark_slots(u, &mut paints);
        }
        let geometry = |b: &Self, space: Affine| -> Vec<Prop> {
            match (&deform, morph) {
                (Some((u, frames)), morph) => {
                    b.deformed(&cs, *u, frames, acc * space, env.to_canvas, morph)
                }
                (None, Some((track, leaf))) => {
                    b.morphed(track, leaf, space, max_stretch(env.to_canvas * acc * space))
                }
                (None, None) => {
                    let inv = space.inverse();
                    cs.iter()
                        .map(|c| {
                            Prop::fixed(Value::Bezier(Box::new(c.transformed(inv).to_bezier())))
                        })
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
                Styled::Item(s) if role == Role::Stroke && trim.is_some() => {
                    parts.push(Part::Trimmed(s))
                }
                Styled::Item(s) => match parts.last_mut() {
                    Some(Part::Plain(v)) => v.push(s),
                    _ => parts.push(Part::Plain(vec![s])),
                },
                Styled::InSpace(s, space) => {
                    let tm = trim.clone().filter(|_| role == Role::Stroke).map(Box::new);
                    parts.push(Part::Space(s, space, tm))
                }
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
                                ks: Prop::fixed(Value::Bezier(Box::new(c.to_bezier()))),
                            })
                        })
                        .collect();
                    it.push(style);
                    comp.items.push(Item::Shape(Box::new(wrap(it, true))));
                }
                Part::Trimmed(style) => {
                    let mut it = sh(geometry(self, Affine::IDENTITY));
                    it.push(trim.clone().expect("a trimmed part has a trim"));
                    it.push(style);
                    comp.items.push(Item::Shape(Box::new(wrap(it, true))));
                }
                Part::Space(style, space, tm) => {
                    let mut it = sh(geometry(self, space));
                    it.extend(tm.map(|b| *b));
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
    pub(super) fn deformed(
        &self,
        cs: &[Contour],
        u: usize,
        frames: &[f64],
        acc: Affine,
        to_canvas: Affine,
        morph: Option<(&Track, usize)>,
    ) -> Vec<Prop> {
        let to = to_canvas * acc;
        if !to.determinant().is_normal() {
            return cs
                .iter()
                .map(|c| Prop::fixed(Value::Bezier(Box::new(c.to_bezier()))))
                .collect();
        }
        let back = to.inverse();
        let track = &self.src.tracks[u];
        let shapes: Vec<Vec<Contour>> = frames
            .iter()
            .map(|f| {
                let t = f / self.src.fps;
                // A morphing path deforms its in-between: the outline at each frame, in
                // the one structure of its morphs, so consecutive frames interpolate.
                let own = morph.map(|(m, leaf)| {
                    let o = gmotion::motion::morph::leaf_at(&m.morphs, leaf, t);
                    super::morph::subpaths(&o.unwrap_or_default())
                });
                own.as_deref()
                    .unwrap_or(cs)
                    .iter()
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

    /// Marks the solid colours of unit `u`'s `paints` with their slot ids, `TAG.fill` or
    /// `TAG.stroke` (a stroke drawn as its outline's fill is still the stroke), where the
    /// `slots` directive asks. Gradients and patterns have no colour slot.
    fn mark_slots(&self, u: usize, paints: &mut [(Styled, Role)]) {
        let Some(tag) = self.src.scene.shapes.get(u).map(|s| &s.tag) else {
            return;
        };
        for (styled, role) in paints {
            let Styled::Item(item) = styled else {
                continue;
            };
            match (item, role) {
                (Shape::Fill(f), Role::Fill) if self.slots.fill => {
                    f.slot = Some(format!("{tag}.fill"));
                }
                (Shape::Fill(f), Role::Outline) if self.slots.stroke => {
                    f.slot = Some(format!("{tag}.stroke"));
                }
                (Shape::Stroke(s), Role::Stroke) if self.slots.stroke => {
                    s.slot = Some(format!("{tag}.stroke"));
                }
                _ => {}
            }
        }
    }
}

/// A pattern-painted outline.
pub(super) enum Outline {
    Fill(Fill),
    Stroke(Stroke),
}

/// What a paint of a path paints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Role {
    Fill,
    Stroke,
    /// A stroke drawn as the fill of its outline.
    Outline,
}

/// The outline of `path` stroked with `s` (in the path's coordinates).
pub(super) fn outline_path(path: &BezPath, s: &Stroke, tolerance: f64) -> BezPath {
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
pub(super) enum Part {
    /// Style items drawn on the path's own geometry.
    Plain(Vec<Shape>),
    /// A stroke drawn as the fill of its outline.
    Outline(Shape),
    /// A style item drawn on the geometry mapped into a space (a stroke with its trim).
    Space(Shape, Affine, Option<Box<Shape>>),
    /// A stroke drawn on the path's own geometry cut by the path's trim, in a group of its
    /// own so that the trim leaves the fill whole.
    Trimmed(Shape),
    /// A group standing for a pattern paint.
    Layered(Group),
}

/// The trim paths item (`tm`) for a unit's trim keys, `None` without keys. Each path
/// (contour) is trimmed on its own length (`m: 1`, "simultaneously"), as the model trims
/// each subpath; a property that does not change is written static.
pub(super) fn trim_paths(keys: &[Key<Trim>]) -> Option<Shape> {
    keys.first()?;
    let prop = |f: fn(&Trim) -> f64| {
        let first = f(&keys[0].v);
        if keys.iter().all(|k| (f(&k.v) - first).abs() <= 1e-9) {
            Prop::scalar(N::coord(first))
        } else {
            Prop::keyed(to_keyframes(keys, |t| Value::Scalar(N::coord(f(t)))))
        }
    };
    Some(Shape::Trim(TrimPaths {
        s: prop(|t| t.start * 100.0),
        e: prop(|t| t.end * 100.0),
        o: prop(|t| t.shift * 360.0),
        m: 1,
    }))
}

/// The stroke width factor that `keys` hold throughout (1 without keys), or `None` when
/// the width changes. Smoothing rebuilds every channel from filtered samples, and a
/// constant width comes back within float noise of itself as keys of one value: that is
/// no width animation.
pub(super) fn held_factor(keys: &[Key<f64>]) -> Option<f64> {
    let Some(first) = keys.first() else {
        return Some(1.0);
    };
    keys.iter()
        .all(|k| (k.v - first.v).abs() <= WIDTH_FACTOR_TOLERANCE)
        .then_some(first.v)
}
