//! Paints as Lottie style items: solid and gradient fills and strokes, with a shape's
//! colour tints and stroke-width multiplier as keyframes.
//!
//! Gradients are written in the path's own coordinates. A linear gradient stays linear
//! under any affine map, so its transform is folded into its end points exactly; a radial
//! gradient under a map that is not a similarity becomes an ellipse, which Lottie can only
//! draw by putting the path into the gradient's space ([`Styled::InSpace`]). Reflected and
//! repeated spreads are unrolled into extra stops over the area the path covers.

use std::sync::Arc;

use kurbo::{Affine, Point, Rect, Vec2};

use super::keys::{to_keyframes, within_range};
use super::model::{
    Dash, Fill as LFill, Gradient, GradientFill, GradientStops, GradientStroke, N, Prop, Shape,
    Stroke as LStroke, StrokeStyle, Value,
};
use gmotion::color::Color;
use gmotion::keyframe::Key;
use gmotion::motion::Tint;
use gmotion::scene::{
    Fill, FillRule, LineCap, LineJoin, LinearGradient, Paint, Pattern, RadialGradient, Spread,
    Stop, Stroke,
};

/// The keyframed channels of the shape a paint belongs to.
#[derive(Clone, Copy, Debug, Default)]
pub struct PaintAnim<'a> {
    /// Fill tint keys (empty: untinted).
    pub fill: &'a [Key<Tint>],
    /// Stroke tint keys.
    pub stroke: &'a [Key<Tint>],
    /// Stroke width multiplier keys.
    pub stroke_width: &'a [Key<f64>],
}

/// A paint ready to place.
#[derive(Clone, Debug)]
pub enum Styled {
    /// A style item for the path's own group.
    Item(Shape),
    /// A style item that needs the path drawn in another space: the group gets transform
    /// `space` and the geometry `space⁻¹ · path`.
    InSpace(Shape, Affine),
    /// A pattern: Lottie has no such paint, so the caller tiles it under a matte.
    Pattern(Arc<Pattern>, f32),
}

/// Most periods a reflected or repeated gradient is unrolled into.
const MAX_PERIODS: f64 = 64.0;

fn rgb(c: Color) -> Value {
    Value::Vec(vec![
        N::fine(c.r as f64),
        N::fine(c.g as f64),
        N::fine(c.b as f64),
    ])
}

fn percent(x: f64) -> Prop {
    Prop::scalar(N::coord(x * 100.0))
}

/// A colour, keyframed by `tint` when it has keys.
fn color_prop(c: Color, tint: &[Key<Tint>]) -> Prop {
    if tint.is_empty() {
        return Prop::fixed(rgb(c));
    }
    // `apply` clamps, as the model does.
    let keys = within_range(
        tint,
        |a, b, lo, hi| tint_leaves_range(c, *a, *b, lo, hi),
        |a, b, p| a.lerp(*b, p as f32),
    );
    Prop::keyed(to_keyframes(&keys, |t| rgb(t.apply(c))))
}

/// Whether some channel of `c` tinted from `a` to `b` leaves `[0, 1]` at a progress in
/// `[lo, hi]` (see `within_range`).
fn tint_leaves_range(c: Color, a: Tint, b: Tint, lo: f64, hi: f64) -> bool {
    let shown = |t: Tint, k: usize| {
        let own = [c.r, c.g, c.b][k];
        (own * (1.0 - t.weight) + t.sum[k]) as f64
    };
    (0..3).any(|k| {
        let (x, y) = (shown(a, k), shown(b, k));
        [lo, hi]
            .iter()
            .any(|p| !(-1e-6..=1.0 + 1e-6).contains(&(x + (y - x) * p)))
    })
}

fn fill_rule(r: FillRule) -> u8 {
    match r {
        FillRule::NonZero => 1,
        FillRule::EvenOdd => 2,
    }
}

/// The fill's style item. `bbox` is the path's bounding box in its own coordinates.
pub fn fill(
    f: &Fill,
    bbox: Rect,
    anim: PaintAnim,
    element: &str,
    warn: &mut Vec<String>,
) -> Option<Styled> {
    let o = percent(f.opacity as f64);
    let r = fill_rule(f.rule);
    Some(
        match resolve(&f.paint, bbox, anim.fill, false, element, warn) {
            Resolved::Solid(c) => Styled::Item(Shape::Fill(LFill {
                o,
                c: color_prop(c, anim.fill),
                r,
                slot: None,
            })),
            Resolved::Pattern(p) => Styled::Pattern(p, f.opacity),
            Resolved::Grad(grad, None) => {
                Styled::Item(Shape::GradientFill(Box::new(GradientFill {
                    o,
                    r,
                    grad: *grad,
                })))
            }
            Resolved::Grad(grad, Some(space)) => Styled::InSpace(
                Shape::GradientFill(Box::new(GradientFill { o, r, grad: *grad })),
                space,
            ),
        },
    )
}

/// The stroke's style item.
pub fn stroke(
    s: &Stroke,
    bbox: Rect,
    anim: PaintAnim,
    element: &str,
    warn: &mut Vec<String>,
) -> Option<Styled> {
    let o = percent(s.opacity as f64);
    let (w, style) = stroke_style(s, anim.stroke_width, element, warn);
    // The stroke covers half its width beyond the outline.
    let area = bbox.inflate(s.width / 2.0, s.width / 2.0);
    Some(
        match resolve(&s.paint, area, anim.stroke, true, element, warn) {
            Resolved::Solid(c) => Styled::Item(Shape::Stroke(LStroke {
                o,
                c: color_prop(c, anim.stroke),
                w,
                style,
                slot: None,
            })),
            Resolved::Pattern(p) => Styled::Pattern(p, s.opacity),
            Resolved::Grad(grad, _) => {
                Styled::Item(Shape::GradientStroke(Box::new(GradientStroke {
                    o,
                    grad: *grad,
                    w,
                    style,
                })))
            }
        },
    )
}

/// `paint` as Lottie takes it, a gradient laid over `area` (where the fill or stroke it
/// belongs to paints, in the path's coordinates) and tinted by `tint`.
fn resolve(
    paint: &Paint,
    area: Rect,
    tint: &[Key<Tint>],
    is_stroke: bool,
    element: &str,
    warn: &mut Vec<String>,
) -> Resolved {
    match paint {
        Paint::Solid(c) => Resolved::Solid(*c),
        Paint::Pattern(p) => Resolved::Pattern(p.clone()),
        Paint::Linear(g) => linear(g, area, tint, element, warn),
        Paint::Radial(g) => radial(g, area, tint, is_stroke, element, warn),
    }
}

fn stroke_style(
    s: &Stroke,
    width_keys: &[Key<f64>],
    element: &str,
    warn: &mut Vec<String>,
) -> (Prop, StrokeStyle) {
    let w = if width_keys.is_empty() {
        Prop::scalar(N::coord(s.width))
    } else {
        Prop::keyed(to_keyframes(width_keys, |m| {
            Value::Scalar(N::coord(s.width * m))
        }))
    };
    let lc = match s.cap {
        LineCap::Butt => 1,
        LineCap::Round => 2,
        LineCap::Square => 3,
    };
    let lj = match s.join {
        LineJoin::Miter => 1,
        LineJoin::MiterClip => {
            warn.push(format!("element `{element}`: stroke-linejoin miter-clip is written as miter (Lottie has no miter-clip)"));
            1
        }
        LineJoin::Round => 2,
        LineJoin::Bevel => 3,
    };
    let mut d = Vec::new();
    // Gaps of zero draw a solid line (dashing it would only break its joins).
    if let Some(dash) = &s.dash
        && dash.iter().skip(1).step_by(2).any(|v| *v > 0.0)
    {
        for (k, v) in dash.iter().enumerate() {
            let (n, kind) = if k % 2 == 0 {
                ("d", "dash")
            } else {
                ("g", "gap")
            };
            // lottie-web names each entry as a property: the names must be unique.
            d.push(Dash {
                n: n.to_string(),
                nm: format!("{kind}{}", k / 2),
                v: Prop::scalar(N::coord(*v)),
            });
        }
        d.push(Dash {
            n: "o".to_string(),
            nm: "offset".to_string(),
            v: Prop::scalar(N::coord(s.dash_offset)),
        });
    }
    let style = StrokeStyle {
        lc,
        lj,
        ml: (lj == 1).then(|| N::coord(s.miter_limit)),
        dashes: d,
    };
    (w, style)
}

/// A paint as Lottie takes it ([`resolve`]). A gradient comes to `Solid` or `Grad`.
enum Resolved {
    /// One colour: a solid paint, or a gradient that paints one colour everywhere.
    Solid(Color),
    /// A Lottie gradient, and the space the path must be drawn in when it is not the
    /// path's own.
    Grad(Box<Gradient>, Option<Affine>),
    /// A pattern, which the layers draw ([`Styled::Pattern`]).
    Pattern(Arc<Pattern>),
}

/// Stops after unrolling `periods` (first, count) of a reflected or repeated spread.
fn unroll(stops: &[Stop], spread: Spread, first: i64, count: i64) -> Vec<Stop> {
    let mut out = Vec::with_capacity(stops.len() * count as usize);
    for j in first..first + count {
        let mirrored = spread == Spread::Reflect && j.rem_euclid(2) == 1;
        let period: Vec<Stop> = if mirrored {
            stops
                .iter()
                .rev()
                .map(|s| Stop {
                    offset: 1.0 - s.offset,
                    color: s.color,
                })
                .collect()
        } else {
            stops.to_vec()
        };
        for s in period {
            let offset = ((j - first) as f32 + s.offset) / count as f32;
            out.push(Stop {
                offset,
                color: s.color,
            });
        }
    }
    out
}

/// The flat Lottie stop list, colours tinted by `tint`.
fn stops_prop(stops: &[Stop], tint: &[Key<Tint>]) -> GradientStops {
    let flat = |t: Tint| {
        let mut v = Vec::with_capacity(stops.len() * 6);
        for s in stops {
            let c = t.apply(s.color);
            v.extend(
                [s.offset as f64, c.r as f64, c.g as f64, c.b as f64]
                    .map(|x| N::fine(x.clamp(0.0, 1.0))),
            );
        }
        if stops.iter().any(|s| s.color.a < 1.0) {
            for s in stops {
                v.extend([s.offset as f64, s.color.a as f64].map(|x| N::fine(x.clamp(0.0, 1.0))));
            }
        }
        Value::Vec(v)
    };
    let k = if tint.is_empty() {
        Prop::fixed(flat(Tint::NONE))
    } else {
        Prop::keyed(to_keyframes(tint, |t| flat(*t)))
    };
    GradientStops {
        p: stops.len(),
        k: Some(k),
    }
}

fn point(p: Point) -> Prop {
    Prop::vec(vec![N::coord(p.x), N::coord(p.y)])
}

/// A one-colour gradient (one stop, or nothing to interpolate over) as its colour.
fn single(stops: &[Stop]) -> Option<Color> {
    let last = stops.last()?;
    let c = last.color;
    (stops.len() == 1).then_some(c)
}

fn linear(
    g: &LinearGradient,
    bbox: Rect,
    tint: &[Key<Tint>],
    element: &str,
    warn: &mut Vec<String>,
) -> Resolved {
    let solid = |c: Color| Resolved::Solid(c);
    if let Some(c) = single(&g.stops) {
        return solid(c);
    }
    let d = g.end - g.start;
    let inv = g.transform.inverse();
    let len2 = d.hypot2();
    if len2 <= 0.0 || !g.transform.determinant().is_normal() {
        // SVG paints a zero-length gradient with its last stop.
        return solid(g.stops.last().map_or(Color::BLACK, |s| s.color));
    }
    // The gradient coordinate of a user-space point is affine: t(x) = n·x + c.
    let t_of = |x: Point| ((inv * x) - g.start).dot(d) / len2;
    let start = g.transform * g.start;
    let [a, b, c, dd, _, _] = inv.as_coeffs();
    // Gradient of t: Lᵀ·d / |d|² with L the linear part of the inverse transform.
    let n = Vec2::new(a * d.x + b * d.y, c * d.x + dd * d.y) / len2;
    let n2 = n.hypot2();
    let at = |t: f64| start + n * (t / n2);
    let mut stops = g.stops.clone();
    let (mut t0, mut t1) = (0.0, 1.0);
    if g.spread != Spread::Pad {
        let ts: Vec<f64> = [
            bbox.origin(),
            Point::new(bbox.x1, bbox.y0),
            Point::new(bbox.x0, bbox.y1),
            Point::new(bbox.x1, bbox.y1),
        ]
        .iter()
        .map(|p| t_of(*p))
        .collect();
        let lo = ts
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
            .floor()
            .min(0.0);
        let hi = ts
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil()
            .max(1.0);
        if hi - lo > MAX_PERIODS {
            warn.push(format!(
                "element `{element}`: gradient `{}` repeats {} times over the shape; written with pad spread",
                g.id,
                hi - lo
            ));
        } else if hi - lo > 1.0 {
            stops = unroll(&g.stops, g.spread, lo as i64, (hi - lo) as i64);
            (t0, t1) = (lo, hi);
        }
    }
    let grad = Gradient {
        t: 1,
        s: Some(point(at(t0))),
        e: Some(point(at(t1))),
        h: None,
        a: None,
        g: stops_prop(&stops, tint),
    };
    Resolved::Grad(Box::new(grad), None)
}

/// Whether `m` maps circles to circles (rotation, uniform scale, reflection, translation).
fn is_similarity(m: Affine) -> bool {
    let [a, b, c, d, _, _] = m.as_coeffs();
    let tol = 1e-9 * (a.abs() + b.abs() + c.abs() + d.abs()).max(1e-300);
    ((a - d).abs() <= tol && (b + c).abs() <= tol) || ((a + d).abs() <= tol && (b - c).abs() <= tol)
}

fn radial(
    g: &RadialGradient,
    bbox: Rect,
    tint: &[Key<Tint>],
    is_stroke: bool,
    element: &str,
    warn: &mut Vec<String>,
) -> Resolved {
    if let Some(c) = single(&g.stops) {
        return Resolved::Solid(c);
    }
    if g.radius <= 0.0 || !g.transform.determinant().is_normal() {
        return Resolved::Solid(g.stops.last().map_or(Color::BLACK, |s| s.color));
    }
    let concentric = (g.focal - g.center).hypot() <= 1e-9 * g.radius;
    let fr = g.focal_radius.clamp(0.0, g.radius * 0.999);
    if fr > 0.0 && !(concentric && g.spread == Spread::Pad) {
        warn.push(format!(
            "element `{element}`: gradient `{}` has a focal radius (fr) off its centre or with a repeating spread, which Lottie cannot say; its stops are squeezed as if concentric",
            g.id
        ));
    }
    // Where the gradient is drawn: its own space when the transform distorts circles.
    let similar = is_similarity(g.transform);
    let (space, to_user) = if similar || is_stroke {
        if !similar {
            warn.push(format!(
                "element `{element}`: gradient `{}` is stretched on a stroke, which Lottie cannot draw; approximated by a circular gradient",
                g.id
            ));
        }
        (None, g.transform)
    } else {
        (Some(g.transform), Affine::IDENTITY)
    };
    // A focal circle of radius fr around the centre starts the stops at fr/r.
    let k = fr / g.radius;
    let mut stops: Vec<Stop> = g
        .stops
        .iter()
        .map(|s| Stop {
            offset: k as f32 + s.offset * (1.0 - k) as f32,
            color: s.color,
        })
        .collect();
    let mut radius = g.radius;
    let mut center = g.center;
    if g.spread != Spread::Pad && fr == 0.0 {
        let inv = g.transform.inverse();
        let far = [
            bbox.origin(),
            Point::new(bbox.x1, bbox.y0),
            Point::new(bbox.x0, bbox.y1),
            Point::new(bbox.x1, bbox.y1),
        ]
        .iter()
        .map(|p| cone_t(inv * *p, g.focal, g.center, g.radius))
        .fold(0.0, f64::max)
        .ceil();
        if far > MAX_PERIODS || !far.is_finite() {
            warn.push(format!(
                "element `{element}`: gradient `{}` repeats {far} times over the shape; written with pad spread",
                g.id
            ));
        } else if far > 1.0 {
            // Period k of the gradient is the circle of radius k·r centred at f + k·(c − f).
            stops = unroll(&g.stops, g.spread, 0, far as i64);
            radius *= far;
            center = g.focal + (g.center - g.focal) * far;
        }
    }
    let mut s = to_user * center;
    let mut e = to_user * (center + Vec2::new(radius, 0.0));
    if !similar && is_stroke {
        // Approximate the ellipse by the circle of the same area.
        let r = radius * g.transform.determinant().abs().sqrt();
        s = g.transform * center;
        e = s + Vec2::new(r, 0.0);
    }
    let f = to_user * g.focal;
    let r_out = (e - s).hypot();
    let fv = f - s;
    let (h, a) = if fv.hypot() > 1e-9 * r_out.max(1.0) {
        let h = fv.hypot() / r_out * 100.0;
        let ang = fv.y.atan2(fv.x) - (e - s).y.atan2((e - s).x);
        (
            Some(Prop::scalar(N::coord(h.min(99.0)))),
            Some(Prop::scalar(N::coord(ang.to_degrees()))),
        )
    } else {
        (None, None)
    };
    let grad = Gradient {
        t: 2,
        s: Some(point(s)),
        e: Some(point(e)),
        h,
        a,
        g: stops_prop(&stops, tint),
    };
    Resolved::Grad(Box::new(grad), space)
}

/// The gradient coordinate of `x` for a radial gradient with focal point `f`, centre `c`
/// and radius `r` (focal radius 0): the `t` whose circle, centred at `f + t·(c − f)` with
/// radius `t·r`, passes through `x`.
fn cone_t(x: Point, f: Point, c: Point, r: f64) -> f64 {
    let q = x - f;
    let d = c - f;
    // |q − t·d| = t·r  ⇔  (d² − r²)·t² − 2(q·d)·t + q² = 0, with d² < r² (focal inside).
    let a = d.hypot2() - r * r;
    let b = q.dot(d);
    let disc = (b * b - a * q.hypot2()).max(0.0);
    if a.abs() < 1e-12 {
        return if b > 0.0 {
            q.hypot2() / (2.0 * b)
        } else {
            f64::INFINITY
        };
    }
    ((b - disc.sqrt()) / a).max((b + disc.sqrt()) / a)
}

/// A pattern's stand-in colour: the first solid paint of its content (black if none).
pub fn pattern_color(p: &Pattern) -> Color {
    fn first(g: &gmotion::scene::Group) -> Option<Color> {
        g.children.iter().find_map(|n| match n {
            gmotion::scene::Node::Group(g) => first(g),
            gmotion::scene::Node::Image(_) => None,
            gmotion::scene::Node::Path(p) => {
                let solid = |paint: &Paint| {
                    if let Paint::Solid(c) = paint {
                        Some(*c)
                    } else {
                        None
                    }
                };
                p.fill
                    .as_ref()
                    .and_then(|f| solid(&f.paint))
                    .or_else(|| p.stroke.as_ref().and_then(|s| solid(&s.paint)))
            }
        })
    }
    first(&p.root).unwrap_or(Color::BLACK)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stop(offset: f32, c: Color) -> Stop {
        Stop { offset, color: c }
    }

    #[test]
    fn cone_coordinate_is_one_on_the_circle() {
        let (f, c, r) = (Point::new(12.0, 0.0), Point::new(0.0, 0.0), 40.0);
        for a in [0.0f64, 1.0, 2.5, 4.0] {
            let x = c + Vec2::new(a.cos(), a.sin()) * r;
            assert!((cone_t(x, f, c, r) - 1.0).abs() < 1e-9);
            // Twice as far from the focal point along the same ray: the next period.
            let y = f + (x - f) * 2.0;
            assert!((cone_t(y, f, c, r) - 2.0).abs() < 1e-9);
        }
    }

    #[test]
    fn reflect_mirrors_every_other_period() {
        let s = [stop(0.0, Color::BLACK), stop(0.25, Color::WHITE)];
        let u = unroll(&s, Spread::Reflect, -1, 2);
        let offsets: Vec<f32> = u.iter().map(|s| s.offset).collect();
        // Period -1 is mirrored: its stops run from 1 − 0.25 back to 1, halved into [0, 0.5].
        assert_eq!(offsets, vec![0.375, 0.5, 0.5, 0.625]);
        assert_eq!(u[0].color, Color::WHITE);
    }

    #[test]
    fn skewed_linear_gradient_keeps_its_isolines() {
        let g = LinearGradient {
            id: "g".into(),
            start: Point::new(0.0, 0.0),
            end: Point::new(10.0, 0.0),
            transform: Affine::skew(0.5, 0.0) * Affine::scale_non_uniform(2.0, 1.0),
            spread: Spread::Pad,
            stops: vec![stop(0.0, Color::BLACK), stop(1.0, Color::WHITE)],
        };
        let Resolved::Grad(grad, None) = linear(
            &g,
            Rect::new(0.0, 0.0, 10.0, 10.0),
            &[],
            "p",
            &mut Vec::new(),
        ) else {
            panic!()
        };
        let pt = |p: &Option<Prop>| match p {
            Some(Prop::Static(Value::Vec(v))) => Point::new(v[0].0, v[1].0),
            _ => panic!(),
        };
        let (s, e) = (pt(&grad.s), pt(&grad.e));
        // The SVG gradient coordinate of a user point, against the Lottie one.
        for q in [Point::new(3.0, 7.0), Point::new(15.0, -2.0)] {
            let want = ((g.transform.inverse() * q) - g.start).dot(g.end - g.start) / 100.0;
            let got = (q - s).dot(e - s) / (e - s).hypot2();
            assert!((want - got).abs() < 1e-3, "{want} vs {got}");
        }
    }
}
