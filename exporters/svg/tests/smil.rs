//! SMIL export: structure of every animation element, and exactness checked by playing the
//! document with a small SMIL evaluator (the subset the exporter writes: additive
//! `animateTransform` of the five types, `animate` of colours, numbers and path data, with
//! `keyTimes`, `keySplines` and discrete steps) against the animation model itself.

use std::collections::HashMap;
use std::sync::Arc;

use gmotion::color::Color;
use gmotion::motion::{
    Animation, AttrSeg, Blend, Component, Field, Grid, Interp, MotionKind, MotionSeg, Timing, Tint,
    Track,
};
use gmotion::scene::{
    Fill, Group, LinearGradient, Node, Paint, PathNode, Pattern, Scene, SceneBuilder, Shape,
    Spread, Stop, Stroke,
};
use gmotion::signals::Easing;
use gmotion_export_svg::smil::{SmilError, SmilOptions, smil_document, to_smil};
use kurbo::{Affine, BezPath, Point, Rect, Shape as _, Vec2};

use crate::support::{run_grammar, scene_of, vertices};

// ---------------------------------------------------------------------------------------
// Hand-built animations

/// One shape of a test scene.
pub struct Item {
    /// Node id.
    pub id: &'static str,
    /// Geometry in the parent's coordinates.
    pub path: BezPath,
    /// Fill paint.
    pub fill: Paint,
    /// Stroke colour and width.
    pub stroke: Option<(Color, f64)>,
    /// Transform of a group around the path (identity: no group).
    pub parent: Affine,
}

/// A path unit `rect` filled with `c`.
pub fn item(id: &'static str, rect: Rect, c: Color) -> Item {
    Item {
        id,
        path: rect.to_path(0.1),
        fill: Paint::Solid(c),
        stroke: None,
        parent: Affine::IDENTITY,
    }
}

/// A path node `r` filled with `c`, with an opaque stroke `stroke` (colour and width).
fn rect_node(id: &str, r: Rect, c: Color, stroke: Option<(Color, f64)>) -> PathNode {
    let stroke = stroke.map(|(c, w)| Stroke::solid(c, w));
    PathNode::new(id, r.to_path(0.1), Some(Fill::solid(c)), stroke)
}

/// A scene of path units (tag `s`), each optionally inside its own transformed group,
/// measured as the importer measures them.
pub fn scene(width: f64, height: f64, items: Vec<Item>) -> Scene {
    let mut b = SceneBuilder::new(width, height);
    for it in items {
        let fill = Fill {
            paint: it.fill,
            ..Fill::solid(Color::BLACK)
        };
        let stroke = it.stroke.map(|(c, w)| Stroke::solid(c, w));
        let node = Node::Path(PathNode::new(it.id, it.path, Some(fill), stroke));
        let parent = (it.parent != Affine::IDENTITY).then(|| {
            let mut g = Group::new();
            g.id = format!("{}-parent", it.id);
            g.transform = it.parent;
            g
        });
        b = b.unit_under("s", parent, node);
    }
    b.build()
}

/// A timing over `[start, end]`.
pub fn timing(start: f64, end: f64, ease: Easing) -> Timing {
    Timing {
        start,
        end,
        delay: 0.0,
        ease,
        reversed: false,
    }
}

/// A single-entry rigid motion about `pivot`.
pub fn rigid(pivot: Point, comps: &[Component], interp: Interp) -> MotionKind {
    MotionKind::Rigid {
        pivot,
        blend: Arc::from([(1.0, Arc::from(comps))]),
        interp,
    }
}

/// Appends one motion played in the windows between consecutive `cuts`, each window
/// starting from the state the model gives at its start.
pub fn windows(track: &mut Track, kind: &MotionKind, timing: &Timing, cuts: &[f64]) {
    for w in cuts.windows(2) {
        let start = track.transform_at(w[0]);
        track.motions.push(MotionSeg {
            t0: w[0],
            t1: w[1],
            timing: timing.clone(),
            kind: kind.clone(),
            start,
        });
    }
}

/// A track that plays one motion in the windows between consecutive `cuts` ([`windows`]).
fn moved(kind: &MotionKind, timing: &Timing, cuts: &[f64]) -> Track {
    let mut t = Track::default();
    windows(&mut t, kind, timing, cuts);
    t
}

fn anim(scene: Scene, duration: f64, looping: bool, tracks: Vec<Track>) -> Animation {
    Animation {
        scene,
        duration,
        fps: 30.0,
        looping,
        tracks,
    }
}

/// The shape `a` (the rectangle `r` filled with `c`) alone on a 200 × 200 canvas, played by
/// `track`.
fn lone(r: Rect, c: Color, duration: f64, looping: bool, track: Track) -> Animation {
    let items = vec![item("a", r, c)];
    anim(scene(200.0, 200.0, items), duration, looping, vec![track])
}

fn ease_in_out() -> Easing {
    Easing::CubicBezier([0.42, 0.0, 0.58, 1.0])
}

fn red() -> Color {
    Color::rgb8(220, 40, 40)
}

fn blue() -> Color {
    Color::rgb8(30, 80, 200)
}

fn square(x: f64, y: f64, s: f64) -> Rect {
    Rect::new(x, y, x + s, y + s)
}

/// The hand-built animations, by name; `true` when SMIL should play them exactly.
pub fn cases() -> Vec<(&'static str, bool, Animation)> {
    let mut out = Vec::new();
    let c = |r: Rect| r.center();

    // A square turning half a turn about its centre, eased.
    let r = square(70.0, 70.0, 60.0);
    let turn = rigid(c(r), &[Component::Rotate(180.0)], Interp::Linear);
    let t = moved(&turn, &timing(0.5, 2.5, ease_in_out()), &[0.5, 2.5]);
    out.push(("rotate-pivot", true, lone(r, red(), 3.0, false, t)));

    // Scale and move a stroked rectangle.
    let r = Rect::new(40.0, 80.0, 100.0, 120.0);
    let mut it = item("a", r, blue());
    it.stroke = Some((Color::BLACK, 4.0));
    let comps = [
        Component::Translate(Vec2::new(30.0, 10.0)),
        Component::Scale(Vec2::new(2.0, 0.5)),
    ];
    let ease_out = Easing::CubicBezier([0.0, 0.0, 0.58, 1.0]);
    let kind = rigid(c(r), &comps, Interp::Linear);
    let t = moved(&kind, &timing(0.0, 2.0, ease_out), &[0.0, 2.0]);
    out.push((
        "scale",
        true,
        anim(scene(200.0, 200.0, vec![it]), 2.5, false, vec![t]),
    ));

    // One motion cut into two windows by a later timesplit, then another motion.
    let r = square(20.0, 20.0, 40.0);
    let comps = [
        Component::Translate(Vec2::new(80.0, 0.0)),
        Component::Rotate(90.0),
    ];
    let kind = rigid(c(r), &comps, Interp::Linear);
    let mut t = moved(&kind, &timing(0.0, 2.0, ease_in_out()), &[0.0, 0.8, 2.0]);
    let moved_centre = t.transform_at(2.0) * c(r);
    let shrink = [Component::Scale(Vec2::new(0.5, 0.5))];
    let kind = rigid(moved_centre, &shrink, Interp::Linear);
    windows(
        &mut t,
        &kind,
        &timing(2.0, 3.0, Easing::Linear),
        &[2.0, 3.0],
    );
    out.push(("chained", true, lone(r, red(), 3.0, false, t)));

    // A motion and its inverse slice, looping.
    let r = square(30.0, 60.0, 50.0);
    let kind = rigid(
        c(r),
        &[
            Component::Translate(Vec2::new(90.0, 30.0)),
            Component::Rotate(120.0),
        ],
        Interp::Linear,
    );
    let ease = Easing::CubicBezier([0.6, 0.0, 0.9, 0.4]);
    let mut t = moved(&kind, &timing(0.0, 1.5, ease.clone()), &[0.0, 1.5]);
    let back = Timing {
        reversed: true,
        ..timing(1.5, 3.0, ease)
    };
    windows(&mut t, &kind, &back, &[1.5, 2.2, 3.0]);
    out.push(("reversed", true, lone(r, blue(), 3.0, true, t)));

    // Tints: a solid fill, a stroke, and a gradient fill.
    let mut a = item("a", square(20.0, 20.0, 70.0), red());
    a.stroke = Some((Color::rgb8(20, 160, 60), 6.0));
    let grad = LinearGradient {
        id: "grad".into(),
        start: Point::new(110.0, 0.0),
        end: Point::new(190.0, 0.0),
        transform: Affine::IDENTITY,
        spread: Spread::Pad,
        stops: vec![
            Stop {
                offset: 0.0,
                color: Color::rgb8(250, 220, 40),
            },
            Stop {
                offset: 1.0,
                color: Color::rgb8(40, 200, 220),
            },
        ],
    };
    let mut b = item("b", square(110.0, 110.0, 80.0), Color::BLACK);
    b.fill = Paint::Linear(Arc::new(grad));
    let tint = |t0: f64, t1: f64, to: Color| AttrSeg {
        t0,
        t1,
        timing: timing(t0, t1, ease_in_out()),
        from: Tint::NONE,
        to: Tint::full(to),
    };
    let ta = Track {
        fill: vec![tint(0.5, 1.5, blue())],
        stroke: vec![tint(1.0, 2.5, Color::rgb8(250, 250, 0))],
        ..Track::default()
    };
    let tb = Track {
        fill: vec![tint(0.0, 2.0, red())],
        ..Track::default()
    };
    // A checker pattern: two coloured squares per 20 × 20 tile.
    let cell = |x: f64, y: f64, c: Color| Node::Path(rect_node("", square(x, y, 10.0), c, None));
    let mut tile = Group::new();
    tile.children = vec![
        cell(0.0, 0.0, Color::rgb8(240, 120, 0)),
        cell(10.0, 10.0, Color::rgb8(0, 90, 60)),
    ];
    let pattern = Pattern {
        id: "checker".into(),
        rect: Rect::new(0.0, 0.0, 20.0, 20.0),
        transform: Affine::IDENTITY,
        root: tile,
    };
    let mut p = item("p", Rect::new(110.0, 20.0, 190.0, 90.0), Color::BLACK);
    p.fill = Paint::Pattern(Arc::new(pattern));
    let tp = Track {
        fill: vec![tint(0.5, 2.5, Color::rgb8(60, 60, 255))],
        ..Track::default()
    };
    out.push((
        "tint",
        true,
        anim(
            scene(200.0, 200.0, vec![a, b, p]),
            3.0,
            false,
            vec![ta, tb, tp],
        ),
    ));

    // Opacity down and back up, stroke width growing.
    let mut a = item("a", square(50.0, 50.0, 100.0), blue());
    a.stroke = Some((Color::BLACK, 3.0));
    let num = |t0: f64, t1: f64, from: f64, to: f64| AttrSeg {
        t0,
        t1,
        timing: timing(t0, t1, ease_in_out()),
        from,
        to,
    };
    let t = Track {
        opacity: vec![num(0.0, 1.0, 1.0, 0.2), num(1.5, 2.5, 0.2, 1.0)],
        stroke_width: vec![num(0.0, 2.0, 1.0, 4.0)],
        ..Track::default()
    };
    out.push((
        "opacity",
        true,
        anim(scene(200.0, 200.0, vec![a]), 3.0, false, vec![t]),
    ));

    // A shape inside a rotated, squashed group.
    let r = square(-20.0, -20.0, 40.0);
    let mut a = item("a", r, red());
    a.parent = Affine::translate((100.0, 90.0))
        * Affine::rotate(0.5)
        * Affine::scale_non_uniform(1.5, 0.8);
    let centre = (a.parent * r.to_path(0.1)).bounding_box().center();
    let comps = [
        Component::Translate(Vec2::new(50.0, 30.0)),
        Component::Rotate(45.0),
    ];
    let kind = rigid(centre, &comps, Interp::Linear);
    let t = moved(&kind, &timing(0.0, 2.0, ease_in_out()), &[0.0, 2.0]);
    out.push((
        "parent",
        true,
        anim(scene(200.0, 200.0, vec![a]), 2.0, false, vec![t]),
    ));

    // Two motions sharing one window, the second with a delay and its own easing.
    let r = square(60.0, 60.0, 40.0);
    let mut t = Track::default();
    let first = MotionSeg {
        t0: 0.0,
        t1: 2.0,
        timing: timing(0.0, 2.0, ease_in_out()),
        kind: rigid(c(r), &[Component::Rotate(90.0)], Interp::Linear),
        start: Affine::IDENTITY,
    };
    let second = MotionSeg {
        timing: Timing {
            delay: 0.5,
            ..timing(0.0, 2.0, Easing::CubicBezier([0.2, 0.8, 0.4, 1.0]))
        },
        kind: rigid(
            Point::ORIGIN,
            &[Component::Translate(Vec2::new(60.0, 0.0))],
            Interp::Linear,
        ),
        ..first.clone()
    };
    t.motions = vec![first, second];
    out.push(("shared-window", true, lone(r, blue(), 2.0, false, t)));

    // An easing that overshoots, and skews on either axis.
    let r = square(20.0, 80.0, 40.0);
    let skews = [
        Component::Translate(Vec2::new(100.0, 0.0)),
        Component::Skew(20.0, 0.0),
        Component::Skew(0.0, -15.0),
    ];
    let overshoot = Easing::CubicBezier([0.3, -0.6, 0.4, 1.7]);
    let kind = rigid(c(r), &skews, Interp::Linear);
    let t = moved(&kind, &timing(0.0, 2.0, overshoot), &[0.0, 2.0]);
    out.push(("overshoot-skew", true, lone(r, red(), 2.0, false, t)));

    // A window whose start does not continue the previous one: the state jumps.
    let r = square(30.0, 30.0, 40.0);
    let turn = rigid(c(r), &[Component::Rotate(60.0)], Interp::Linear);
    let mut t = moved(&turn, &timing(0.0, 1.0, Easing::Linear), &[0.0, 1.0]);
    let start = Affine::translate((40.0, 50.0)) * t.transform_at(1.0);
    t.motions.push(MotionSeg {
        t0: 1.5,
        t1: 2.5,
        timing: timing(1.5, 2.5, Easing::Linear),
        kind: rigid(
            Point::ORIGIN,
            &[Component::Translate(Vec2::new(50.0, 0.0))],
            Interp::Linear,
        ),
        start,
    });
    out.push(("jump", true, lone(r, blue(), 3.0, false, t)));

    // Changes with no duration: a motion and an opacity that happen at one instant, and a
    // fill change that starts from another colour than the one held before it.
    let r = square(40.0, 40.0, 50.0);
    let slide = [Component::Translate(Vec2::new(60.0, 20.0))];
    let kind = rigid(c(r), &slide, Interp::Linear);
    let mut t = moved(&kind, &timing(1.0, 1.0, Easing::Linear), &[0.5, 1.5]);
    let step = |t0: f64, from: f64, to: f64| AttrSeg {
        t0,
        t1: t0 + 0.5,
        timing: timing(t0 + 0.25, t0 + 0.25, Easing::Linear),
        from,
        to,
    };
    t.opacity = vec![step(0.0, 1.0, 0.3), step(2.0, 0.6, 1.0)];
    let tint = |t0: f64, from: Color, to: Color| AttrSeg {
        t0,
        t1: t0 + 0.5,
        timing: timing(t0, t0 + 0.5, Easing::Linear),
        from: Tint::full(from),
        to: Tint::full(to),
    };
    t.fill = vec![tint(0.5, red(), blue()), tint(1.8, Color::WHITE, red())];
    out.push(("instant", true, lone(r, blue(), 3.0, false, t)));

    // What SMIL cannot say: Alexa interpolation, B-spline easing, a bilinear blend.
    let r = square(70.0, 70.0, 50.0);
    let comps = [
        Component::Rotate(200.0),
        Component::Scale(Vec2::new(1.6, 0.7)),
    ];
    let kind = rigid(c(r), &comps, Interp::Alexa);
    let t = moved(&kind, &timing(0.0, 2.0, Easing::Linear), &[0.0, 2.0]);
    out.push(("baked-alexa", false, lone(r, red(), 2.0, false, t)));

    let r = square(30.0, 70.0, 50.0);
    let comps = [
        Component::Translate(Vec2::new(100.0, 0.0)),
        Component::Rotate(90.0),
    ];
    let kind = rigid(c(r), &comps, Interp::Linear);
    let t = moved(&kind, &timing(0.0, 2.0, Easing::BSpline(4)), &[0.0, 2.0]);
    out.push(("baked-easing", false, lone(r, blue(), 2.0, false, t)));

    let r = square(70.0, 70.0, 50.0);
    let blend: Blend = Arc::from([
        (
            0.5,
            Arc::from([Component::Translate(Vec2::new(100.0, 0.0))]),
        ),
        (0.5, Arc::from([Component::Rotate(120.0)])),
    ]);
    let kind = MotionKind::Rigid {
        pivot: c(r),
        blend,
        interp: Interp::Linear,
    };
    let t = moved(&kind, &timing(0.0, 2.0, ease_in_out()), &[0.0, 2.0]);
    out.push(("baked-bilinear", false, lone(r, red(), 2.0, false, t)));

    // A group unit (two paths moving and tinted as one) inside a transformed group.
    let solid = |id: &str, r: Rect, c: Color, stroke: bool| {
        Node::Path(rect_node(id, r, c, stroke.then_some((Color::BLACK, 3.0))))
    };
    let mut unit = Group::new();
    unit.id = "pair".into();
    unit.transform = Affine::translate((10.0, 5.0));
    unit.opacity = 0.8;
    unit.unit = Some(0);
    unit.children = vec![
        solid("left", square(40.0, 60.0, 40.0), red(), true),
        solid(
            "right",
            square(90.0, 60.0, 40.0),
            Color::rgb8(240, 200, 30),
            false,
        ),
    ];
    let mut outer = Group::new();
    outer.id = "outer".into();
    outer.transform = Affine::translate((0.0, 20.0)) * Affine::scale(1.2);
    outer.children = vec![Node::Group(unit)];
    let parent = outer.transform;
    let bbox = (parent
        * Affine::translate((10.0, 5.0))
        * Rect::new(40.0, 60.0, 130.0, 100.0).to_path(0.1))
    .bounding_box();
    let mut root = Group::new();
    root.children = vec![Node::Group(outer)];
    let shape = Shape {
        aliases: Vec::new(),
        inherited: 0,
        rig: false,
        tag: "pair".into(),
        id: 0,
        group: 0,
        z: 0,
        node_path: vec![0, 0],
        parent_transform: parent,
        centroid: bbox.center(),
        bbox,
        fill: red(),
        stroke: Color::BLACK,
        stroke_width: 3.0,
        text: gmotion::text::TextPlace::default(),
    };
    let comps = [
        Component::Rotate(-70.0),
        Component::Translate(Vec2::new(20.0, 10.0)),
    ];
    let kind = rigid(bbox.center(), &comps, Interp::Linear);
    let mut t = moved(&kind, &timing(0.0, 2.0, ease_in_out()), &[0.0, 2.0]);
    t.fill.push(AttrSeg {
        t0: 0.5,
        t1: 2.5,
        timing: timing(0.5, 2.5, Easing::Linear),
        from: Tint::NONE,
        to: Tint::full(blue()),
    });
    t.opacity.push(AttrSeg {
        t0: 1.0,
        t1: 2.0,
        timing: timing(1.0, 2.0, Easing::Linear),
        from: 1.0,
        to: 0.5,
    });
    let pair = Scene {
        width: 200.0,
        height: 200.0,
        root,
        shapes: vec![shape],
        time: None,
        keys: Vec::new(),
    };
    out.push(("group-unit", true, anim(pair, 3.0, true, vec![t])));

    // Units inside units: the tints compose, so they are sampled.
    let mut inner = Group::new();
    inner.children = vec![solid("inner", square(100.0, 100.0, 60.0), blue(), true)];
    let Node::Path(ip) = &mut inner.children[0] else {
        unreachable!()
    };
    ip.unit = Some(1);
    let mut outer = Group::new();
    outer.id = "outer".into();
    outer.unit = Some(0);
    outer.children = vec![
        solid("plain", square(20.0, 20.0, 60.0), red(), false),
        Node::Group(inner),
    ];
    let mut root = Group::new();
    root.children = vec![Node::Group(outer)];
    let shape = |id: usize, node_path: Vec<usize>, bbox: Rect| Shape {
        aliases: Vec::new(),
        inherited: 0,
        rig: false,
        tag: "n".into(),
        id,
        group: 0,
        z: id,
        node_path,
        parent_transform: Affine::IDENTITY,
        centroid: bbox.center(),
        bbox,
        fill: red(),
        stroke: Color::BLACK,
        stroke_width: 3.0,
        text: gmotion::text::TextPlace::default(),
    };
    let shapes = vec![
        shape(0, vec![0], Rect::new(20.0, 20.0, 160.0, 160.0)),
        shape(1, vec![0, 1, 0], square(100.0, 100.0, 60.0)),
    ];
    let tint = |t0: f64, t1: f64, to: Color| AttrSeg {
        t0,
        t1,
        timing: timing(t0, t1, ease_in_out()),
        from: Tint::NONE,
        to: Tint {
            sum: [to.r * 0.7, to.g * 0.7, to.b * 0.7],
            weight: 0.7,
        },
    };
    let to = Track {
        fill: vec![tint(0.0, 2.0, Color::rgb8(250, 250, 0))],
        stroke: vec![tint(0.5, 1.5, red())],
        ..Track::default()
    };
    let ti = Track {
        fill: vec![tint(1.0, 3.0, Color::rgb8(0, 200, 0))],
        ..Track::default()
    };
    let nested = Scene {
        width: 200.0,
        height: 200.0,
        root,
        shapes,
        time: None,
        keys: Vec::new(),
    };
    out.push((
        "nested-units",
        false,
        anim(nested, 3.0, false, vec![to, ti]),
    ));

    // Per-vertex deformation towards the canvas centre.
    let r = Rect::new(20.0, 20.0, 180.0, 60.0);
    let grid = Grid::new(
        4,
        4,
        Rect::new(0.0, 0.0, 200.0, 200.0),
        Field::Towards(Point::new(100.0, 100.0)),
    );
    let kind = MotionKind::Vertex {
        grid: Arc::new(grid),
        pivot: None,
    };
    let t = moved(&kind, &timing(0.0, 2.0, ease_in_out()), &[0.0, 2.0]);
    out.push(("deform", false, lone(r, blue(), 2.0, false, t)));

    out
}

// ---------------------------------------------------------------------------------------
// A small SVG DOM and SMIL player

#[derive(Debug)]
struct El {
    name: String,
    attrs: HashMap<String, String>,
    children: Vec<usize>,
    parent: Option<usize>,
}

struct Doc {
    els: Vec<El>,
}

impl Doc {
    fn parse(svg: &str) -> Doc {
        use svg::node::element::tag::Type;
        use svg::parser::Event;
        let mut els: Vec<El> = Vec::new();
        let mut stack: Vec<usize> = Vec::new();
        for ev in svg::read(svg).expect("parse") {
            match ev {
                Event::Tag(name, ty, attrs) => {
                    if ty == Type::End {
                        let open = stack.pop().expect("balanced");
                        assert_eq!(els[open].name, name);
                        continue;
                    }
                    let i = els.len();
                    let parent = stack.last().copied();
                    els.push(El {
                        name: name.to_string(),
                        attrs: attrs
                            .iter()
                            .map(|(k, v)| (k.clone(), v.to_string()))
                            .collect(),
                        children: Vec::new(),
                        parent,
                    });
                    if let Some(p) = parent {
                        els[p].children.push(i);
                    }
                    if ty == Type::Start {
                        stack.push(i);
                    }
                }
                Event::Error(e) => panic!("bad SVG: {e}"),
                _ => {}
            }
        }
        assert!(stack.is_empty(), "unclosed elements");
        Doc { els }
    }

    fn by_id(&self, id: &str) -> usize {
        self.els
            .iter()
            .position(|e| e.attrs.get("id").is_some_and(|v| v == id))
            .unwrap_or_else(|| panic!("no #{id}"))
    }

    fn anims(&self) -> impl Iterator<Item = &El> {
        self.els.iter().filter(|e| e.name.starts_with("animate"))
    }

    /// The animation children of `e` animating `attr`.
    fn anims_of(&self, e: usize, attr: &str) -> Vec<&El> {
        self.els[e]
            .children
            .iter()
            .map(|&c| &self.els[c])
            .filter(|c| c.name.starts_with("animate") && c.attrs["attributeName"] == attr)
            .collect()
    }

    /// The element's own transform at `t`: its attribute, then its animations in order.
    fn local(&self, e: usize, t: f64) -> Affine {
        let mut m = self.els[e]
            .attrs
            .get("transform")
            .map_or(Affine::IDENTITY, |v| {
                let ts: svgtypes::Transform = v.parse().expect("transform");
                Affine::new([ts.a, ts.b, ts.c, ts.d, ts.e, ts.f])
            });
        for a in self.anims_of(e, "transform") {
            let v = play(a, t);
            let value = match a.attrs["type"].as_str() {
                "translate" => Affine::translate((v[0], v.get(1).copied().unwrap_or(0.0))),
                "rotate" => Affine::rotate(v[0].to_radians()),
                "scale" => Affine::scale_non_uniform(v[0], v.get(1).copied().unwrap_or(v[0])),
                "skewX" => Affine::skew(v[0].to_radians().tan(), 0.0),
                "skewY" => Affine::skew(0.0, v[0].to_radians().tan()),
                other => panic!("unexpected type {other}"),
            };
            m = if a.attrs.get("additive").is_some_and(|v| v == "sum") {
                m * value
            } else {
                value
            };
        }
        m
    }

    /// The transform from `e`'s content to the canvas at `t`.
    fn total(&self, e: usize, t: f64) -> Affine {
        let mut m = self.local(e, t);
        let mut at = self.els[e].parent;
        while let Some(p) = at {
            m = self.local(p, t) * m;
            at = self.els[p].parent;
        }
        m
    }

    /// The opacity `e` is drawn with at `t`: the product of its own and its ancestors'.
    fn opacity(&self, e: usize, t: f64) -> f64 {
        let mut opacity = 1.0;
        let mut at = Some(e);
        while let Some(i) = at {
            opacity *= self.value(i, "opacity", t).map_or(1.0, |v| v[0]);
            at = self.els[i].parent;
        }
        opacity
    }

    /// The value of `attr` on `e` at `t`: the played animation, else the attribute.
    fn value(&self, e: usize, attr: &str, t: f64) -> Option<Vec<f64>> {
        match self.anims_of(e, attr).last() {
            Some(a) => Some(play(a, t)),
            None => self.els[e].attrs.get(attr).map(|v| numbers(v)),
        }
    }
}

/// The id in `url(#id)`.
fn def_id(url: &str) -> &str {
    url.trim_start_matches("url(#").trim_end_matches(')')
}

/// Numbers in a value: a `#rrggbb` colour as three 0..255 channels, else every number.
fn numbers(v: &str) -> Vec<f64> {
    let v = v.trim();
    if let Some(h) = v.strip_prefix('#') {
        return (0..3)
            .map(|i| u8::from_str_radix(&h[2 * i..2 * i + 2], 16).unwrap() as f64)
            .collect();
    }
    v.split(|c: char| c.is_whitespace() || c == ',' || c.is_ascii_alphabetic())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap_or_else(|_| panic!("number {s:?}")))
        .collect()
}

fn list(v: &str) -> Vec<&str> {
    v.split(';').map(str::trim).collect()
}

/// The CSS/SMIL cubic timing function, by bisection.
fn spline(s: [f64; 4], x: f64) -> f64 {
    let bez = |a: f64, b: f64, u: f64| {
        3.0 * (1.0 - u) * (1.0 - u) * u * a + 3.0 * (1.0 - u) * u * u * b + u * u * u
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if bez(s[0], s[2], mid) < x {
            lo = mid
        } else {
            hi = mid
        }
    }
    bez(s[1], s[3], 0.5 * (lo + hi))
}

/// An animation element's value at document time `t` (SMIL 3 simple-time semantics).
fn play(a: &El, t: f64) -> Vec<f64> {
    let dur: f64 = a.attrs["dur"].trim_end_matches('s').parse().unwrap();
    let looping = a
        .attrs
        .get("repeatCount")
        .is_some_and(|v| v == "indefinite");
    let values: Vec<Vec<f64>> = list(&a.attrs["values"]).into_iter().map(numbers).collect();
    let times: Vec<f64> = list(&a.attrs["keyTimes"])
        .into_iter()
        .map(|v| v.parse().unwrap())
        .collect();
    let tau = if looping {
        (t / dur).fract()
    } else {
        (t / dur).min(1.0)
    };
    let mode = a.attrs.get("calcMode").map_or("linear", String::as_str);
    let i = times.partition_point(|&k| k <= tau).saturating_sub(1);
    if mode == "discrete" {
        return values[i].clone();
    }
    if i + 1 >= values.len() {
        return values[values.len() - 1].clone();
    }
    let span = times[i + 1] - times[i];
    let x = if span > 0.0 {
        ((tau - times[i]) / span).clamp(0.0, 1.0)
    } else {
        1.0
    };
    let y = if mode == "spline" {
        let s = numbers(list(&a.attrs["keySplines"])[i]);
        spline([s[0], s[1], s[2], s[3]], x)
    } else {
        x
    };
    values[i]
        .iter()
        .zip(&values[i + 1])
        .map(|(p, q)| p + (q - p) * y)
        .collect()
}

/// Instants to compare at: a fine grid plus just before and after every key boundary.
fn instants(a: &Animation) -> Vec<f64> {
    let d = a.duration;
    let mut ts: Vec<f64> = (0..=200).map(|i| d * i as f64 / 200.0 * 0.9999).collect();
    for tr in &a.tracks {
        for s in &tr.motions {
            for b in [s.t0, s.t1, s.timing.start + s.timing.delay] {
                ts.extend([b - 1e-3, b + 1e-3]);
            }
        }
    }
    ts.retain(|t| (0.0..d).contains(t));
    ts
}

// ---------------------------------------------------------------------------------------
// Tests

#[test]
fn every_animation_element_is_well_formed() {
    for (name, _, a) in cases() {
        let (svg, warnings) = to_smil(&a, &SmilOptions::default()).unwrap();
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        let doc = Doc::parse(&svg);
        let mut count = 0;
        for el in doc.anims() {
            count += 1;
            let at = &el.attrs;
            let n = list(&at["values"]).len();
            let times: Vec<f64> = list(&at["keyTimes"])
                .iter()
                .map(|v| v.parse().unwrap())
                .collect();
            assert_eq!(
                times.len(),
                n,
                "{name}: keyTimes and values differ in count"
            );
            assert!(n >= 2, "{name}: an animation needs two values");
            assert_eq!(times[0], 0.0, "{name}: keyTimes must start at 0");
            assert!(
                times.windows(2).all(|w| w[0] <= w[1]),
                "{name}: keyTimes must not decrease: {times:?}"
            );
            let discrete = at.get("calcMode").is_some_and(|m| m == "discrete");
            if !discrete {
                assert_eq!(times[n - 1], 1.0, "{name}: keyTimes must end at 1");
            }
            if at.get("calcMode").is_some_and(|m| m == "spline") {
                let splines = list(&at["keySplines"]);
                assert_eq!(splines.len(), n - 1, "{name}: one keySpline per interval");
                for s in splines {
                    let v = numbers(s);
                    assert_eq!(v.len(), 4);
                    assert!(
                        v.iter().all(|x| (0.0..=1.0).contains(x)),
                        "{name}: keySplines {s} outside [0, 1]"
                    );
                }
            } else {
                assert!(
                    !at.contains_key("keySplines"),
                    "{name}: keySplines without calcMode spline"
                );
            }
            assert_eq!(at["begin"], "0s");
            assert_eq!(
                at["dur"].trim_end_matches('s').parse::<f64>().unwrap(),
                a.duration
            );
            assert_eq!(
                at.get("repeatCount").map(String::as_str),
                a.looping.then_some("indefinite"),
                "{name}"
            );
            assert_eq!(
                at.get("fill").map(String::as_str),
                (!a.looping).then_some("freeze"),
                "{name}"
            );
            if el.name == "animateTransform" {
                assert_eq!(at["attributeName"], "transform");
                assert_eq!(at["additive"], "sum");
            }
        }
        assert!(count > 0, "{name}: nothing animated");
        // The document still renders as a still picture.
        usvg::Tree::from_str(&svg, &usvg::Options::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

/// How far unit `u`'s played transform is from the model's at a time: the largest distance
/// between where the two put a corner of the unit's box.
fn transform_error<'a>(doc: &'a Doc, a: &'a Animation, u: usize) -> impl Fn(f64) -> f64 + 'a {
    let shape = &a.scene.shapes[u];
    let node = a.scene.unit_node(u).unwrap();
    let e = doc.by_id(node.id());
    let own = match node {
        Node::Group(g) => g.transform,
        Node::Path(_) | Node::Image(_) => Affine::IDENTITY,
    };
    let b = shape.bbox;
    let back = (shape.parent_transform * own).inverse();
    let corners =
        [(b.x0, b.y0), (b.x1, b.y0), (b.x1, b.y1), (b.x0, b.y1)].map(|c| back * Point::from(c));
    move |t| {
        let got = doc.total(e, t);
        let want = a.tracks[u].transform_at(t) * shape.parent_transform * own;
        corners
            .iter()
            .map(|&q| (got * q - want * q).hypot())
            .fold(0.0, f64::max)
    }
}

#[test]
fn transforms_play_as_the_model_moves() {
    for (name, exact, a) in cases() {
        if a.tracks.iter().any(Track::deforms) {
            continue;
        }
        let tol = if exact {
            2e-3
        } else {
            SmilOptions::default().tolerance + 0.02
        };
        let (svg, _) = to_smil(&a, &SmilOptions::default()).unwrap();
        let doc = Doc::parse(&svg);
        for u in 0..a.scene.shapes.len() {
            if a.tracks[u].motions.is_empty() {
                continue;
            }
            let off = transform_error(&doc, &a, u);
            let worst = instants(&a).into_iter().map(off).fold(0.0, f64::max);
            assert!(
                worst <= tol,
                "{name}: shape {u} off by {worst} (allowed {tol})"
            );
        }
    }
}

/// Every path of the scene with the units it lies in, outermost first.
fn paths_in_units(g: &Group, inside: &mut Vec<usize>, out: &mut Vec<(PathNode, Vec<usize>)>) {
    for child in &g.children {
        if let Some(u) = child.unit() {
            inside.push(u);
        }
        match child {
            Node::Group(h) => paths_in_units(h, inside, out),
            Node::Path(p) => out.push((p.clone(), inside.clone())),
            Node::Image(_) => {}
        }
        if child.unit().is_some() {
            inside.pop();
        }
    }
}

/// `outer(inner(c))` as one tint (the frame writer's composition of nested units).
fn compose(outer: Tint, inner: Tint) -> Tint {
    let k = 1.0 - outer.weight;
    Tint {
        sum: std::array::from_fn(|i| inner.sum[i] * k + outer.sum[i]),
        weight: 1.0 - (1.0 - inner.weight) * k,
    }
}

#[test]
fn colours_opacity_and_widths_play_as_the_model_changes() {
    for (name, _, a) in cases() {
        let (svg, _) = to_smil(&a, &SmilOptions::default()).unwrap();
        let doc = Doc::parse(&svg);
        let mut paths = Vec::new();
        paths_in_units(&a.scene.root, &mut Vec::new(), &mut paths);
        for (p, units) in paths.iter().filter(|(_, u)| !u.is_empty()) {
            let e = doc.by_id(&p.id);
            for t in instants(&a) {
                let states: Vec<_> = units.iter().map(|&u| a.tracks[u].state_at(t)).collect();
                let fill = states.iter().map(|s| s.fill).reduce(compose).unwrap();
                let stroke = states.iter().map(|s| s.stroke).reduce(compose).unwrap();
                let close = |got: Vec<f64>, want: Color, what: &str| {
                    let w = want.to_rgba8();
                    for i in 0..3 {
                        assert!(
                            (got[i] - w[i] as f64).abs() <= 1.5,
                            "{name}: {what} of {} at {t}: {got:?} vs {w:?}",
                            p.id
                        );
                    }
                };
                match &p.fill.as_ref().unwrap().paint {
                    Paint::Solid(c) => {
                        close(doc.value(e, "fill", t).unwrap(), fill.apply(*c), "fill")
                    }
                    Paint::Linear(g) => {
                        let def = doc.by_id(def_id(&doc.els[e].attrs["fill"]));
                        assert_eq!(doc.els[def].children.len(), g.stops.len());
                        for (&s, stop) in doc.els[def].children.iter().zip(&g.stops) {
                            close(
                                doc.value(s, "stop-color", t).unwrap(),
                                fill.apply(stop.color),
                                "stop",
                            );
                        }
                    }
                    Paint::Pattern(pat) => {
                        let def = doc.by_id(def_id(&doc.els[e].attrs["fill"]));
                        assert_eq!(doc.els[def].children.len(), pat.root.children.len());
                        for (&c, node) in doc.els[def].children.iter().zip(&pat.root.children) {
                            let Node::Path(cp) = node else { unreachable!() };
                            let Paint::Solid(own) = cp.fill.as_ref().unwrap().paint else {
                                unreachable!()
                            };
                            close(doc.value(c, "fill", t).unwrap(), fill.apply(own), "pattern");
                        }
                    }
                    Paint::Radial(_) => unreachable!(),
                }
                if let Some(s) = &p.stroke {
                    let Paint::Solid(c) = s.paint else {
                        unreachable!()
                    };
                    close(
                        doc.value(e, "stroke", t).unwrap(),
                        stroke.apply(c),
                        "stroke",
                    );
                    let factor: f64 = states.iter().map(|s| s.stroke_width).product();
                    let w = doc.value(e, "stroke-width", t).map_or(1.0, |v| v[0]);
                    assert!((w - s.width * factor).abs() < 1e-3, "{name}: width at {t}");
                }
                // Opacity sits on the units' wrappers: the product along the ancestors,
                // over the nodes' own opacities.
                let opacity = doc.opacity(e, t);
                let own: f64 = own_opacity(&a.scene.root, &p.id).unwrap();
                let want = own * states.iter().map(|s| s.opacity).product::<f64>();
                assert!(
                    (opacity - want).abs() < 1e-3,
                    "{name}: opacity at {t}: {opacity} vs {want}"
                );
            }
        }
    }
}

/// The product of the group opacities above the path with id `id`.
fn own_opacity(g: &Group, id: &str) -> Option<f64> {
    for child in &g.children {
        match child {
            Node::Path(p) if p.id == id => return Some(g.opacity as f64),
            Node::Group(h) => {
                if let Some(o) = own_opacity(h, id) {
                    return Some(o * g.opacity as f64);
                }
            }
            Node::Path(_) | Node::Image(_) => {}
        }
    }
    None
}

#[test]
fn deformation_plays_within_tolerance() {
    let (name, _, a) = cases().into_iter().find(|c| c.0 == "deform").unwrap();
    let tol = SmilOptions::default().tolerance;
    let (svg, _) = to_smil(&a, &SmilOptions::default()).unwrap();
    let doc = Doc::parse(&svg);
    let Node::Path(p) = a.scene.unit_node(0).unwrap() else {
        unreachable!()
    };
    let e = doc.by_id(&p.id);
    // The outline is cut where the grid's clamped border bends it (`lookup=vertex`): the
    // points played at the start (at rest) are the cut rectangle's, on its edges.
    let start = doc.value(e, "d", 0.0).unwrap();
    let rest: Vec<Point> = start.chunks(2).map(|c| Point::new(c[0], c[1])).collect();
    let rect = p.path.bounding_box();
    for q in &rest {
        let on_edge = [q.x - rect.x0, rect.x1 - q.x, q.y - rect.y0, rect.y1 - q.y]
            .iter()
            .any(|d| d.abs() < 0.01);
        assert!(
            on_edge && rect.inflate(0.01, 0.01).contains(*q),
            "{name}: {q:?}"
        );
    }
    assert!(rest.len() > vertices(&p.path).len(), "{name}: not cut");
    for t in instants(&a)
        .into_iter()
        .chain((0..40).map(|i| i as f64 * 0.0497))
    {
        let got = doc.value(e, "d", t).unwrap();
        let want: Vec<Point> = rest.iter().map(|&q| a.tracks[0].deform(q, t)).collect();
        // The rectangle's path is all moves and lines: two numbers per point.
        assert_eq!(got.len(), 2 * want.len(), "{name}");
        for (i, w) in want.iter().enumerate() {
            let d = (Point::new(got[2 * i], got[2 * i + 1]) - *w).hypot();
            assert!(d <= tol + 0.02, "{name}: point {i} at {t} off by {d}");
        }
    }
}

#[test]
fn exact_motion_is_written_exactly_and_baked_motion_is_reduced() {
    for (name, exact, a) in cases() {
        let doc = smil_document(&a, &SmilOptions::default()).unwrap();
        let svg = doc.svg.into_string();
        if exact {
            assert_eq!(doc.baked_segments, 0, "{name}");
        } else {
            assert!(doc.baked_segments > 0, "{name}");
            // Far fewer keys than samples: at most one per 4 samples at 120 per second.
            let keys = svg.matches("keyTimes=\"").count().max(1);
            let max_values = Doc::parse(&svg)
                .anims()
                .map(|e| list(&e.attrs["values"]).len())
                .max()
                .unwrap();
            assert!(
                max_values < (a.duration * 120.0 / 4.0) as usize,
                "{name}: {max_values} keys in {keys} animations"
            );
        }
    }
}

#[test]
fn looser_tolerance_writes_fewer_keys() {
    let (_, _, a) = cases().into_iter().find(|c| c.0 == "baked-alexa").unwrap();
    let keys = |tolerance: f64| {
        let (svg, _) = to_smil(
            &a,
            &SmilOptions {
                tolerance,
                ..SmilOptions::default()
            },
        )
        .unwrap();
        Doc::parse(&svg)
            .anims()
            .map(|e| list(&e.attrs["values"]).len())
            .sum::<usize>()
    };
    assert!(keys(2.0) < keys(0.05));
}

#[test]
fn bad_input_is_an_error() {
    let (_, _, a) = cases().into_iter().next().unwrap();
    let opts = SmilOptions::default();
    let zero = Animation {
        duration: 0.0,
        ..a.clone()
    };
    assert!(matches!(to_smil(&zero, &opts), Err(SmilError::Duration(_))));
    let missing = Animation {
        tracks: Vec::new(),
        ..a.clone()
    };
    assert!(matches!(
        to_smil(&missing, &opts),
        Err(SmilError::TrackCount { .. })
    ));
    let mut nan = a.clone();
    nan.tracks[0].motions[0].kind = rigid(
        Point::ORIGIN,
        &[Component::Rotate(f64::NAN)],
        Interp::Linear,
    );
    let err = to_smil(&nan, &opts).unwrap_err();
    assert!(err.to_string().contains("s:0"), "{err}");
    let bad_opts = SmilOptions {
        tolerance: -1.0,
        ..opts
    };
    assert!(matches!(
        to_smil(&a, &bad_opts),
        Err(SmilError::Option { .. })
    ));
}

#[test]
fn ids_of_unnamed_nodes_do_not_leak() {
    let (_, _, mut a) = cases().into_iter().next().unwrap();
    let Node::Path(p) = &mut a.scene.root.children[0] else {
        unreachable!()
    };
    p.id.clear();
    let (svg, _) = to_smil(&a, &SmilOptions::default()).unwrap();
    assert!(!svg.contains("id=\""), "{svg}");
    assert!(svg.contains("<animateTransform"));
}

/// A jump (a step change, or a window starting from a state other than the one the window
/// before ended in) exactly at a frame time: a player sampling that frame must show the
/// value after the jump, as the model does. Written with keyTimes rounded to nearest, a jump
/// at 1/30 s of a 2 s document lands at 0.016667, after the frame, and the player shows the
/// value before it.
#[test]
fn jumps_at_frame_times_play_the_side_the_model_shows() {
    for (dur, fps) in [
        (2.0_f64, 30.0_f64),
        (1.5, 24.0),
        (2.4, 25.0),
        (1.0, 60.0),
        (3.0, 7.0),
    ] {
        let frames = (dur * fps).round() as usize;
        let at = |k: usize| k as f64 / fps;
        // Jumps at the first frame after 0, one in the middle, and the last frame before
        // the end; the attribute ones are steps, the motion one restarts a window.
        let (j1, j2, j3) = (at(1), at(frames / 3), at(frames - 1));
        let mut it = item("u0", square(20.0, 20.0, 30.0), red());
        it.stroke = Some((blue(), 2.0));
        let sc = scene(100.0, 100.0, vec![it]);
        let mut tr = Track::default();
        fn seg<T>(t: f64, from: T, to: T) -> AttrSeg<T> {
            AttrSeg {
                t0: t,
                t1: t,
                timing: timing(t, t, Easing::Linear),
                from,
                to,
            }
        }
        tr.fill.push(seg(j1, Tint::NONE, Tint::full(blue())));
        tr.fill.push(seg(j3, Tint::full(blue()), Tint::NONE));
        tr.stroke.push(seg(j2, Tint::NONE, Tint::full(red())));
        tr.opacity.push(AttrSeg::linear(j1, j2, 1.0, 0.5));
        tr.opacity.push(seg(j3, 0.5, 0.2));
        tr.stroke_width.push(seg(j2, 1.0, 3.0));
        let slide = rigid(
            Point::ORIGIN,
            &[Component::Translate(Vec2::new(30.0, 0.0))],
            Interp::Linear,
        );
        windows(
            &mut tr,
            &slide,
            &timing(0.0, j2, Easing::Linear),
            &[0.0, j2],
        );
        tr.motions.push(MotionSeg {
            t0: j2,
            t1: dur,
            timing: timing(j2, dur, Easing::Linear),
            kind: slide.clone(),
            start: Affine::translate((-25.0, 10.0)),
        });
        let a = Animation {
            fps,
            ..anim(sc, dur, false, vec![tr])
        };
        let (svg, _) = to_smil(&a, &SmilOptions::default()).unwrap();
        let doc = Doc::parse(&svg);
        let e = doc.by_id("u0");
        let node = a.scene.unit_node(0).unwrap();
        let wrapper = doc.by_id(node.id());
        for k in 0..=frames {
            let t = at(k);
            let s = a.tracks[0].state_at(t);
            let ctx = format!("{dur} s at {fps} fps, frame {k}");
            let rgb = |v: Vec<f64>, c: Color| {
                let w = c.to_rgba8();
                (0..3).all(|i| (v[i] - w[i] as f64).abs() <= 1.5)
            };
            let fill = doc.value(e, "fill", t).unwrap();
            assert!(
                rgb(fill.clone(), s.fill.apply(red())),
                "{ctx}: fill {fill:?}"
            );
            let stroke = doc.value(e, "stroke", t).unwrap();
            assert!(
                rgb(stroke.clone(), s.stroke.apply(blue())),
                "{ctx}: stroke {stroke:?}"
            );
            let w = doc.value(e, "stroke-width", t).map_or(2.0, |v| v[0]);
            assert!((w - 2.0 * s.stroke_width).abs() < 1e-3, "{ctx}: width {w}");
            let opacity = doc.opacity(e, t);
            assert!(
                (opacity - s.opacity).abs() < 1e-3,
                "{ctx}: opacity {opacity}"
            );
            let got = doc.total(wrapper, t);
            let want = s.transform;
            let q = Point::new(35.0, 35.0);
            assert!(
                (got * q - want * q).hypot() < 1e-2,
                "{ctx}: transform {got:?} vs {want:?}"
            );
        }
    }
}

/// An inner fill change inherited through an inverted twin: the slice that drives the
/// outer change is cut to nothing where the inner one begins, so the engine never shows
/// the outer value there. Written as a key between the two keys of the boundary, it made
/// Chromium show it a hair before the boundary (gm-0173 frame 45, gm-0060 frame 51,
/// gm-0155 frame 12 of the conformance matrix). Within a key unit of every frame time the
/// played colour must lie between the colours the engine shows on either side.
#[test]
fn a_cut_away_fill_change_is_never_played() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="150">
      <circle id="s0" data-tag="s" cx="50" cy="50" r="18" fill="#e4572e"/>
      <rect id="c0" data-tag="c" x="70" y="100" width="60" height="30" fill="#ffc914"/>
    </svg>"##;
    let grammar = "duration 2.4s\nfps 25\n\
        animate(fill, local, 0, #5d2e8c) : [all, (s, c)] -> [moving]\n\
        timesplit(0.5, 0.5) : [moving, (s, c)] -> [a, inv_a]\n\
        timesplit(0.5, 0.5) : [a, (s, c)] -> [m, inv_m]\n\
        animate(affine, world, 0, translate(12, 4)) : [m, (s, c)] -> [m1]\n\
        animate(fill, local, 0, #00798c) : [m1, (s, c)] -> [m2]\n";
    let a = run_grammar(scene_of(svg), grammar);
    let (svg, _) = to_smil(&a, &SmilOptions::default()).unwrap();
    let doc = Doc::parse(&svg);
    let mut paths = Vec::new();
    paths_in_units(&a.scene.root, &mut Vec::new(), &mut paths);
    let unit = a.duration * 1e-6;
    for (p, units) in paths.iter().filter(|(_, u)| !u.is_empty()) {
        let Paint::Solid(own) = p.fill.as_ref().unwrap().paint else {
            unreachable!()
        };
        let e = doc.by_id(&p.id);
        let shown = |t: f64| {
            let tint = units
                .iter()
                .map(|&u| a.tracks[u].state_at(t).fill)
                .reduce(compose)
                .unwrap();
            tint.apply(own).to_rgba8()
        };
        for k in 0..a.frame_count() {
            let t = a.frame_time(k);
            let (before, after) = (shown(t - unit), shown(t + unit));
            for dt in [-0.4 * unit, 0.0, 0.4 * unit] {
                let got = doc.value(e, "fill", t + dt).unwrap();
                for i in 0..3 {
                    let (lo, hi) = (before[i].min(after[i]), before[i].max(after[i]));
                    assert!(
                        got[i] >= lo as f64 - 1.5 && got[i] <= hi as f64 + 1.5,
                        "{} at frame {k} {dt:+e} s: {got:?}, engine {before:?} .. {after:?}",
                        p.id
                    );
                }
            }
        }
    }
}

/// The conformance matrix's bake tolerance (`matrix.py`, TOLERANCE), in canvas units.
const MATRIX_TOLERANCE: f64 = 0.05;

/// `grammar` run on the SVG text `svg`, and its SMIL at [`MATRIX_TOLERANCE`].
fn baked_at_matrix_tolerance(svg: &str, grammar: &str) -> (Animation, String) {
    let a = run_grammar(scene_of(svg), grammar);
    let opts = SmilOptions {
        tolerance: MATRIX_TOLERANCE,
        ..SmilOptions::default()
    };
    let (svg, _) = to_smil(&a, &opts).unwrap();
    (a, svg)
}

/// Baked motion was reduced against a uniform grid of samples only, so between two samples
/// a fast curve could stray well past the tolerance, and frame instants fall between them:
/// gm-0146 of the conformance matrix (a 0.12 s B-spline ease, Alexa interpolation) put
/// every rectangle ~0.4 units off at frame 1 in Chromium (0.92% of pixels at 2x). At every
/// frame instant baked motion must be within the tolerance.
#[test]
fn baked_motion_is_within_tolerance_at_every_frame() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="150">
      <rect id="s0" data-tag="s" x="30" y="40" width="40" height="30" fill="#e4572e"/>
      <rect id="s1" data-tag="s" x="110" y="80" width="36" height="36" fill="#17bebb"/>
      <rect id="c0" data-tag="c" x="150" y="20" width="30" height="20" fill="#ffc914"/>
    </svg>"##;
    let grammar = "duration 1.5s\nfps 24\nseed 3\n\
        timesplit(0.4, 0.6) : [all, (s, c)] -> [a, rest]\n\
        timesplit(0.4, 0.6) : [a, (s, c)] -> [b, e]\n\
        timesplit(0.5, 0.5) : [b, (s, c)] -> [m, f]\n\
        animate(affine, world, 0.3 * d * id / n, translate(40, -20), ease=bspline(3), \
        grid=3x2, lookup=exact, interp=alexa) : [m, (s, c)] -> [m1]\n";
    let (a, svg) = baked_at_matrix_tolerance(svg, grammar);
    let doc = Doc::parse(&svg);
    let mut moved = 0;
    for u in 0..a.scene.shapes.len() {
        if a.tracks[u].motions.is_empty() {
            continue;
        }
        moved += 1;
        let error = transform_error(&doc, &a, u);
        for k in 0..a.frame_count() {
            let off = error(a.frame_time(k));
            assert!(
                off <= MATRIX_TOLERANCE + 1e-3,
                "shape {u} at frame {k}: off by {off} (tolerance {})",
                MATRIX_TOLERANCE
            );
        }
    }
    assert!(moved > 0, "the grammar moves some shapes");
}

/// Baked deformation (`d` keys) was reduced against a uniform grid of samples only, so a
/// frame instant between two samples could be off by more than the tolerance: gm-0180 of
/// the conformance matrix (an ease-in rotation by vertex lookup, Alexa interpolation) at
/// frame 13, 0.73% of pixels off in Chromium at 2x. At every frame instant the played
/// points must be within the tolerance.
#[test]
fn baked_deformation_is_within_tolerance_at_every_frame() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="150">
      <rect id="s0" data-tag="s" x="32" y="32" width="36" height="36" fill="#e4572e"/>
      <rect id="s1" data-tag="s" x="86" y="76" width="28" height="28" fill="#76b041"/>
      <rect id="c0" data-tag="c" x="60" y="113" width="80" height="24" fill="#ffc914"/>
    </svg>"##;
    let grammar = "duration 2.4s\nfps 25\nseed 3\n\
        timesplit(0.4, 0.6) : [all, (s, c)] -> [a, rest]\n\
        timesplit(0.5, 0.5) : [a, (s, c)] -> [m, inv_m]\n\
        animate(affine, local, 0.9 * d, rotate(60, 10, 5), ease=ease-in, grid=1x1, \
        lookup=vertex, interp=alexa) : [m, (s, c)] -> [m1]\n";
    let (a, svg) = baked_at_matrix_tolerance(svg, grammar);
    let doc = Doc::parse(&svg);
    let mut paths = Vec::new();
    paths_in_units(&a.scene.root, &mut Vec::new(), &mut paths);
    let mut deformed = 0;
    for (p, units) in &paths {
        let tracks: Vec<&Track> = units.iter().map(|&u| &a.tracks[u]).collect();
        if !tracks.iter().any(|t| t.deforms()) {
            continue;
        }
        deformed += 1;
        let e = doc.by_id(&p.id);
        let rest = vertices(&p.path);
        for k in 0..a.frame_count() {
            let t = a.frame_time(k);
            let got = doc.value(e, "d", t).unwrap();
            let want: Vec<Point> = rest
                .iter()
                .map(|&q| tracks.iter().rev().fold(q, |c, tr| tr.deform(c, t)))
                .collect();
            // Rectangles are all moves and lines: two numbers per point.
            assert_eq!(got.len(), 2 * want.len(), "{}", p.id);
            for (i, w) in want.iter().enumerate() {
                let d = (Point::new(got[2 * i], got[2 * i + 1]) - *w).hypot();
                assert!(
                    d <= MATRIX_TOLERANCE + 1e-3,
                    "{} point {i} at frame {k}: off by {d} (tolerance {})",
                    p.id,
                    MATRIX_TOLERANCE
                );
            }
        }
    }
    assert!(deformed > 0, "the grammar deforms some paths");
}
