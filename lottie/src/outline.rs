//! Outlines as the players build them, and the shape modifiers that change them.
//!
//! Where an outline starts and which way it runs is not cosmetic in Lottie: dashes start
//! at the outline's first point and trim paths cut it by length from there. Rectangles,
//! ellipses and stars are therefore built vertex for vertex as lottie-web builds them
//! (`ShapeProperty.js`), not with kurbo's shapes, which start elsewhere.

use kurbo::{
    BezPath, CubicBez, ParamCurve, ParamCurveArclen, ParamCurveDeriv, PathEl, PathSeg, Point, Vec2,
};

/// lottie-web's handle length for a quarter ellipse (`roundCorner`).
const ROUND: f64 = 0.5519;

/// Arc-length accuracy, in user units, for trim paths.
const ACCURACY: f64 = 1e-3;

/// A rectangle about `c` of size `s` with corner radius `r`: starting at the top-right
/// corner and running clockwise (down the right side), or counter-clockwise when
/// `reversed` (`d` 3).
pub fn rect(c: Point, s: Vec2, r: f64, reversed: bool) -> BezPath {
    let (hw, hh) = (s.x.abs() / 2.0, s.y.abs() / 2.0);
    let (l, t, rt, b) = (c.x - hw, c.y - hh, c.x + hw, c.y + hh);
    let r = r.max(0.0).min(hw).min(hh);
    let k = r * (1.0 - ROUND);
    let p = Point::new;
    let mut path = BezPath::new();
    if r == 0.0 {
        path.move_to(p(rt, t));
        path.line_to(p(rt, b));
        path.line_to(p(l, b));
        path.line_to(p(l, t));
    } else {
        path.move_to(p(rt, t + r));
        path.line_to(p(rt, b - r));
        path.curve_to(p(rt, b - k), p(rt - k, b), p(rt - r, b));
        path.line_to(p(l + r, b));
        path.curve_to(p(l + k, b), p(l, b - k), p(l, b - r));
        path.line_to(p(l, t + r));
        path.curve_to(p(l, t + k), p(l + k, t), p(l + r, t));
        path.line_to(p(rt - r, t));
        path.curve_to(p(rt - k, t), p(rt, t + k), p(rt, t + r));
    }
    path.close_path();
    if reversed {
        path.reverse_subpaths()
    } else {
        path
    }
}

/// An ellipse about `c` of size `s`: starting at the top and running clockwise, or
/// counter-clockwise when `reversed`.
pub fn ellipse(c: Point, s: Vec2, reversed: bool) -> BezPath {
    let (a, b) = (s.x.abs() / 2.0, s.y.abs() / 2.0);
    let dir = if reversed { -1.0 } else { 1.0 };
    // The four vertices in drawing order, each with its outgoing handle offset (the
    // incoming one is its negation).
    let vertices = [
        (Point::new(c.x, c.y - b), Vec2::new(dir * a * ROUND, 0.0)),
        (Point::new(c.x + dir * a, c.y), Vec2::new(0.0, b * ROUND)),
        (Point::new(c.x, c.y + b), Vec2::new(-dir * a * ROUND, 0.0)),
        (Point::new(c.x - dir * a, c.y), Vec2::new(0.0, -b * ROUND)),
    ];
    let mut path = BezPath::new();
    path.move_to(vertices[0].0);
    for i in 0..4 {
        let (v, out) = vertices[i];
        let (w, w_out) = vertices[(i + 1) % 4];
        path.curve_to(v + out, w - w_out, w);
    }
    path.close_path();
    path
}

/// Trim paths (`tm`): the part of each outline between `start` and `end` (fractions of its
/// length, clamped to 0..1), shifted by `offset` degrees (360° is the whole length).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trim {
    /// Start, as a fraction of the length.
    pub start: f64,
    /// End, as a fraction of the length.
    pub end: f64,
    /// Offset in degrees.
    pub offset: f64,
    /// `m` 2: the outlines are trimmed as one run, one after the other, rather than each
    /// on its own.
    pub individually: bool,
}

impl Trim {
    /// The outlines trimmed, as lottie-web's `TrimModifier` trims them: `paths` are the
    /// shapes the modifier applies to, topmost first.
    pub fn apply(&self, paths: &mut [BezPath]) {
        let o = (self.offset % 360.0) / 360.0;
        let o = if o < 0.0 { o + 1.0 } else { o };
        let mut s = self.start.clamp(0.0, 1.0) + o;
        let mut e = self.end.clamp(0.0, 1.0) + o;
        if s > e {
            std::mem::swap(&mut s, &mut e);
        }
        let (s, e) = ((s * 1e4).round() * 1e-4, (e * 1e4).round() * 1e-4);
        if e == s {
            paths.iter_mut().for_each(|p| *p = BezPath::new());
            return;
        }
        if (s == 0.0 && e == 1.0) || (s == 1.0 && e == 0.0) {
            return;
        }
        let lengths: Vec<f64> = paths.iter().map(length).collect();
        let total: f64 = lengths.iter().sum();
        let mut added = 0.0;
        let together = self.individually && paths.len() > 1;
        for (path, &len) in paths.iter_mut().zip(&lengths) {
            let edges = if together {
                let edges = shape_edges(s, e, len, added, total);
                added += len;
                edges
            } else {
                vec![(s, e)]
            };
            let mut out = BezPath::new();
            for (a, b) in edges {
                let spans: Vec<(f64, f64)> = if b <= 1.0 {
                    vec![(len * a, len * b)]
                } else if a >= 1.0 {
                    vec![(len * (a - 1.0), len * (b - 1.0))]
                } else {
                    vec![(len * a, len), (0.0, len * (b - 1.0))]
                };
                if spans[0].0 == spans[0].1 {
                    continue;
                }
                let mut first = piece(path, spans[0]);
                if let Some(&second) = spans.get(1) {
                    let wraps = path.elements().last() == Some(&PathEl::ClosePath);
                    let rest = piece(path, second);
                    if wraps {
                        // A closed outline cut across its start is one run.
                        first.extend(rest.elements().iter().skip(1).copied());
                    } else {
                        first.extend(rest);
                    }
                }
                out.extend(first);
            }
            *path = out;
        }
    }
}

/// lottie-web's `calculateShapeEdges`: the part of `[s, e]` (fractions of the modifier's
/// whole length `total`) that falls on a shape of length `len` starting `added` along.
fn shape_edges(s: f64, e: f64, len: f64, added: f64, total: f64) -> Vec<(f64, f64)> {
    let ranges: Vec<(f64, f64)> = if e <= 1.0 {
        vec![(s, e)]
    } else if s >= 1.0 {
        vec![(s - 1.0, e - 1.0)]
    } else {
        vec![(s, 1.0), (0.0, e - 1.0)]
    };
    let mut out = Vec::new();
    for (a, b) in ranges {
        if b * total < added || a * total > added + len {
            continue;
        }
        let from = if a * total <= added {
            0.0
        } else {
            (a * total - added) / len
        };
        let to = if b * total >= added + len {
            1.0
        } else {
            (b * total - added) / len
        };
        out.push((from, to));
    }
    if out.is_empty() {
        out.push((0.0, 0.0));
    }
    out
}

/// The length of every segment of `path`, closing segments included.
fn length(path: &BezPath) -> f64 {
    path.segments().map(|s| s.arclen(ACCURACY)).sum()
}

/// The part of `path` from length `from` to length `to`, as open subpaths (a closed
/// subpath that lies wholly within stays closed).
fn piece(path: &BezPath, (from, to): (f64, f64)) -> BezPath {
    let mut out = BezPath::new();
    let mut at = 0.0;
    for sub in subpaths(path) {
        let len: f64 = sub.segments().map(|s| s.arclen(ACCURACY)).sum();
        let (lo, hi) = (from.max(at), to.min(at + len));
        if hi > lo || (len == 0.0 && from <= at && at <= to) {
            if lo <= at && hi >= at + len {
                out.extend(sub.iter());
            } else {
                cut(&sub, lo - at, hi - at, &mut out);
            }
        }
        at += len;
    }
    out
}

/// Appends the part of subpath `sub` between lengths `lo` and `hi` to `out`.
fn cut(sub: &BezPath, lo: f64, hi: f64, out: &mut BezPath) {
    let mut at = 0.0;
    let mut started = false;
    for seg in sub.segments() {
        let len = seg.arclen(ACCURACY);
        let (a, b) = (lo.max(at), hi.min(at + len));
        if b >= a && len > 0.0 && !(b == a && (a == at + len || started)) {
            let t0 = seg.inv_arclen(a - at, ACCURACY);
            let t1 = seg.inv_arclen(b - at, ACCURACY);
            let part = seg.subsegment(t0..t1);
            if !started {
                out.move_to(part.eval(0.0));
                started = true;
            }
            push(out, part);
        }
        at += len;
        if at >= hi {
            break;
        }
    }
}

fn push(out: &mut BezPath, seg: PathSeg) {
    match seg {
        PathSeg::Line(l) => out.line_to(l.p1),
        PathSeg::Quad(q) => out.quad_to(q.p1, q.p2),
        PathSeg::Cubic(c) => out.curve_to(c.p1, c.p2, c.p3),
    }
}

/// Round corners (`rd`): every corner of `path` (a vertex whose tangents are both zero)
/// replaced by a curve starting and ending up to `radius` away along its two sides (at
/// most half of each), as lottie-web's `RoundCornersModifier` does; an open outline's
/// ends stay.
pub fn round_corners(path: &BezPath, radius: f64) -> BezPath {
    let mut out = BezPath::new();
    if radius <= 0.0 {
        out.extend(path.iter());
        return out;
    }
    for sub in subpaths(path) {
        let (vertices, closed) = vertices_of(&sub);
        let n = vertices.len();
        let mut rounded: Vec<Vertex> = Vec::with_capacity(n * 2);
        for (k, v) in vertices.iter().enumerate() {
            let corner = v.i == v.p && v.o == v.p;
            if !corner || (!closed && (k == 0 || k == n - 1)) {
                rounded.push(*v);
                continue;
            }
            let prev = vertices[(k + n - 1) % n].p;
            let next = vertices[(k + 1) % n].p;
            let towards = |other: Point| {
                let d = v.p.distance(other);
                let f = if d > 0.0 {
                    (d / 2.0).min(radius) / d
                } else {
                    0.0
                };
                v.p.lerp(other, f)
            };
            let a = towards(prev);
            let b = towards(next);
            rounded.push(Vertex {
                p: a,
                i: a,
                o: a.lerp(v.p, ROUND),
            });
            rounded.push(Vertex {
                p: b,
                i: b.lerp(v.p, ROUND),
                o: b,
            });
        }
        out.extend(vertices_path(&rounded, closed).iter());
    }
    out
}

/// Pucker and bloat (`pb`): each outline's vertices move `amount` percent of the way to
/// their mean and its control points as far away from it (a negative amount the other
/// way round), as lottie-web's `PuckerAndBloatModifier` does.
pub fn pucker_bloat(path: &BezPath, amount: f64) -> BezPath {
    let mut out = BezPath::new();
    if amount == 0.0 {
        out.extend(path.iter());
        return out;
    }
    let k = amount / 100.0;
    for sub in subpaths(path) {
        let (vertices, closed) = vertices_of(&sub);
        if vertices.is_empty() {
            continue;
        }
        let sum = vertices
            .iter()
            .fold(Vec2::ZERO, |acc, v| acc + v.p.to_vec2());
        let centre = (sum / vertices.len() as f64).to_point();
        let moved: Vec<Vertex> = vertices
            .iter()
            .map(|v| Vertex {
                p: v.p.lerp(centre, k),
                i: v.i.lerp(centre, -k),
                o: v.o.lerp(centre, -k),
            })
            .collect();
        out.extend(vertices_path(&moved, closed).iter());
    }
    out
}

/// The most points zig-zags add to one document: two million points already outline
/// more ridges than a frame has pixels; past it, outlines of many vertices with many ridges
/// each would grow without bound (a thousand segments of a million ridges).
pub const MAX_RIDGE_POINTS: usize = 2_000_000;

/// Zig-zags (`zz`): along every segment `ridges` points alternately `size` to one side
/// and to the other, and every vertex moved off its corner too; corners (`smooth` false)
/// or smooth points with tangents along the outline, as lottie-web's `ZigZagModifier`
/// makes them (its angles, its order of sides, its start on the first vertex).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZigZag {
    /// How far each point moves off the outline.
    pub size: f64,
    /// Points per segment (rounded, at least 0).
    pub ridges: f64,
    /// Smooth points instead of corners.
    pub smooth: bool,
}

impl ZigZag {
    /// `path` with its zig-zags, and whether `budget` (points the document may still add,
    /// counted down) left out some of them.
    pub fn apply(&self, path: &BezPath, budget: &mut usize) -> (BezPath, bool) {
        let mut out = BezPath::new();
        if self.size == 0.0 {
            out.extend(path.iter());
            return (out, false);
        }
        let mut cut = false;
        for sub in subpaths(path) {
            let (vertices, closed) = vertices_of(&sub);
            let (zigzagged, short) = self.vertices(&vertices, closed, budget);
            cut |= short;
            out.extend(vertices_path(&zigzagged, closed).iter());
        }
        (out, cut)
    }

    fn vertices(&self, vs: &[Vertex], closed: bool, budget: &mut usize) -> (Vec<Vertex>, bool) {
        let n = vs.len();
        let count = if closed { n } else { n.saturating_sub(1) };
        if count == 0 {
            return (Vec::new(), false);
        }
        // `as` saturates: a ridge count past usize (or infinite) is cut by the budget.
        let wanted = self.ridges.max(0.0) as usize;
        let affordable = (*budget / count).saturating_sub(1);
        let ridges = wanted.min(affordable);
        *budget = budget.saturating_sub(count * (ridges + 1));
        let mut out = Vec::with_capacity((count + 1) * (ridges + 1));
        let mut side = -1.0;
        self.corner(vs, 0, side, ridges, &mut out);
        for i in 0..count {
            side = self.segment(vs, i, -side, ridges, &mut out);
            self.corner(vs, i + 1, side, ridges, &mut out);
        }
        (out, ridges < wanted)
    }

    /// The point of vertex `cur`, moved off along the perpendicular of the line joining its
    /// neighbours (the previous one of the first vertex is the last, open or not).
    fn corner(&self, vs: &[Vertex], cur: usize, side: f64, ridges: usize, out: &mut Vec<Vertex>) {
        let n = vs.len();
        let point = vs[cur % n].p;
        let prev = vs[if cur == 0 { n - 1 } else { cur - 1 }].p;
        let next = vs[(cur + 1) % n].p;
        let v = next - prev;
        let rot = -std::f64::consts::FRAC_PI_2;
        let perpendicular = Vec2::new(
            rot.cos() * v.x - rot.sin() * v.y,
            rot.sin() * v.x + rot.cos() * v.y,
        );
        let angle = 0f64.atan2(1.0) - perpendicular.y.atan2(perpendicular.x);
        let (to_prev, to_next) = if self.smooth {
            (point.distance(prev), point.distance(next))
        } else {
            (0.0, 0.0)
        };
        let share = ((ridges + 1) * 2) as f64;
        out.push(self.point(point, angle, side, to_next / share, to_prev / share));
    }

    /// The ridges of segment `i`; returns the side the next point goes to.
    fn segment(
        &self,
        vs: &[Vertex],
        i: usize,
        mut side: f64,
        ridges: usize,
        out: &mut Vec<Vertex>,
    ) -> f64 {
        let seg = segment(vs, i);
        let dist = if self.smooth {
            seg.p0.distance(seg.p3)
        } else {
            0.0
        };
        let share = ((ridges + 1) * 2) as f64;
        for k in 0..ridges {
            let t = (k + 1) as f64 / (ridges + 1) as f64;
            let d = seg.deriv().eval(t);
            let angle = d.x.atan2(d.y);
            out.push(self.point(seg.eval(t), angle, side, dist / share, dist / share));
            side = -side;
        }
        side
    }

    /// A point `size` off `p` in the direction `angle` (lottie-web's: y down, measured the
    /// other way), with tangents across it.
    fn point(&self, p: Point, angle: f64, side: f64, out_len: f64, in_len: f64) -> Vertex {
        let p = polar(p, angle, side * self.size);
        let quarter = std::f64::consts::FRAC_PI_2;
        Vertex {
            p,
            o: polar(p, angle - quarter, out_len),
            i: polar(p, angle + quarter, in_len),
        }
    }
}

/// lottie-web's `floatEqual`: `a` and `b` within a 100 000th of the smaller.
pub(crate) fn same(a: f64, b: f64) -> bool {
    (a - b).abs() * 100_000.0 <= a.abs().min(b.abs())
}

/// lottie-web's `pointEqual`: each coordinate [`same`].
pub(crate) fn same_point(a: Point, b: Point) -> bool {
    same(a.x, b.x) && same(a.y, b.y)
}

/// `p` moved `length` in the direction `angle` (y down, angles the other way round, as
/// lottie-web's `polarOffset` measures them).
pub(crate) fn polar(p: Point, angle: f64, length: f64) -> Point {
    Point::new(p.x + angle.cos() * length, p.y - angle.sin() * length)
}

/// Segment `i` of an outline (to the next vertex, the first after the last), as
/// lottie-web's `PolynomialBezier.shapeSegment` takes it.
fn segment(vs: &[Vertex], i: usize) -> CubicBez {
    let (a, b) = (vs[i], vs[(i + 1) % vs.len()]);
    linearized(a.p, a.o, b.i, b.p)
}

/// A cubic whose control point that sits on its end is moved to a third of the chord, as
/// lottie-web's `PolynomialBezier` makes its segments (a straight segment then moves
/// evenly, and has a tangent).
pub(crate) fn linearized(p0: Point, p1: Point, p2: Point, p3: Point) -> CubicBez {
    let p1 = if same_point(p0, p1) {
        p0.lerp(p3, 1.0 / 3.0)
    } else {
        p1
    };
    let p2 = if same_point(p2, p3) {
        p0.lerp(p3, 2.0 / 3.0)
    } else {
        p2
    };
    CubicBez::new(p0, p1, p2, p3)
}

/// A vertex of an outline with its in and out control points (absolute).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Vertex {
    /// The vertex.
    pub(crate) p: Point,
    /// Its in control point.
    pub(crate) i: Point,
    /// Its out control point.
    pub(crate) o: Point,
}

/// A subpath's vertices and whether it is closed (a closing segment back to the start is
/// folded into the first vertex).
pub(crate) fn vertices_of(sub: &BezPath) -> (Vec<Vertex>, bool) {
    let mut vs: Vec<Vertex> = Vec::new();
    let mut closed = false;
    let at = |p: Point| Vertex { p, i: p, o: p };
    for el in sub.elements() {
        match *el {
            PathEl::MoveTo(p) => vs.push(at(p)),
            PathEl::LineTo(p) => vs.push(at(p)),
            PathEl::QuadTo(c, p) => {
                if let Some(last) = vs.last_mut() {
                    last.o = last.p.lerp(c, 2.0 / 3.0);
                }
                vs.push(Vertex {
                    p,
                    i: p.lerp(c, 2.0 / 3.0),
                    o: p,
                });
            }
            PathEl::CurveTo(c1, c2, p) => {
                if let Some(last) = vs.last_mut() {
                    last.o = c1;
                }
                vs.push(Vertex { p, i: c2, o: p });
            }
            PathEl::ClosePath => closed = true,
        }
    }
    if closed
        && vs.len() > 1
        && vs.first().map(|v| v.p) == vs.last().map(|v| v.p)
        && let Some(last) = vs.pop()
    {
        vs[0].i = last.i;
    }
    (vs, closed)
}

/// The outline through `vs` (closed back to the first when `closed`).
pub(crate) fn vertices_path(vs: &[Vertex], closed: bool) -> BezPath {
    let mut path = BezPath::new();
    let Some(first) = vs.first() else {
        return path;
    };
    path.move_to(first.p);
    let n = vs.len();
    let segments = if closed { n } else { n - 1 };
    for k in 0..segments {
        let (a, b) = (vs[k], vs[(k + 1) % n]);
        if a.o == a.p && b.i == b.p {
            path.line_to(b.p);
        } else {
            path.curve_to(a.o, b.i, b.p);
        }
    }
    if closed {
        path.close_path();
    }
    path
}

/// `path` split at its move-tos.
pub(crate) fn subpaths(path: &BezPath) -> Vec<BezPath> {
    let mut out: Vec<BezPath> = Vec::new();
    for el in path.elements() {
        if matches!(el, PathEl::MoveTo(_)) || out.is_empty() {
            out.push(BezPath::new());
        }
        if let Some(last) = out.last_mut() {
            last.push(*el);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Shape as _;

    #[test]
    fn round_corners_cut_each_corner_by_the_radius_and_keep_curves() {
        let square = kurbo::Rect::new(0.0, 0.0, 100.0, 100.0).to_path(0.1);
        let r = round_corners(&square, 10.0);
        let (vs, closed) = vertices_of(&r);
        assert!(closed);
        assert_eq!(vs.len(), 8, "two vertices a corner");
        // The corner at the origin becomes a curve from (0, 10) to (10, 0) (or back).
        assert!(vs.iter().any(|v| v.p == Point::new(10.0, 0.0)));
        assert!(vs.iter().any(|v| v.p == Point::new(0.0, 10.0)));
        // A radius past half a side stops at half of it.
        let (big, _) = vertices_of(&round_corners(&square, 80.0));
        assert!(big.iter().all(|v| v.p.x == 50.0 || v.p.y == 50.0));
        // An ellipse has no corners.
        let e = kurbo::Ellipse::new((0.0, 0.0), (30.0, 20.0), 0.0).to_path(0.1);
        assert_eq!(round_corners(&e, 10.0).elements().len(), e.elements().len());
    }

    fn len(p: &BezPath) -> f64 {
        length(p)
    }

    #[test]
    fn primitives_start_where_lottie_web_starts() {
        let r = rect(Point::new(0.0, 0.0), Vec2::new(20.0, 10.0), 0.0, false);
        let first = r.segments().next().unwrap();
        assert_eq!(first.eval(0.0), Point::new(10.0, -5.0), "top right");
        assert_eq!(first.eval(1.0), Point::new(10.0, 5.0), "then down");
        let e = ellipse(Point::new(0.0, 0.0), Vec2::new(20.0, 10.0), false);
        let first = e.segments().next().unwrap();
        assert_eq!(first.eval(0.0), Point::new(0.0, -5.0), "top");
        assert_eq!(first.eval(1.0), Point::new(10.0, 0.0), "clockwise");
        assert!((e.area().abs() - std::f64::consts::PI * 50.0).abs() < 0.5);
        let back = ellipse(Point::new(0.0, 0.0), Vec2::new(20.0, 10.0), true);
        assert_eq!(
            back.segments().next().unwrap().eval(1.0),
            Point::new(-10.0, 0.0)
        );
        let rounded = rect(Point::new(0.0, 0.0), Vec2::new(20.0, 10.0), 2.0, false);
        assert!((rounded.area().abs() - (200.0 - (4.0 - std::f64::consts::PI) * 4.0)).abs() < 0.2);
    }

    #[test]
    fn trim_keeps_the_fraction_of_the_length() {
        let square = rect(Point::new(5.0, 5.0), Vec2::new(10.0, 10.0), 0.0, false);
        for (s, e, o, want) in [
            (0.0, 0.5, 0.0, 20.0),
            (0.25, 1.0, 0.0, 30.0),
            (0.6, 0.2, 0.0, 16.0),
            (0.0, 0.5, 270.0, 20.0),
            (0.0, 1.0, 90.0, 40.0),
            (0.3, 0.3, 0.0, 0.0),
        ] {
            let mut paths = [square.clone()];
            Trim {
                start: s,
                end: e,
                offset: o,
                individually: false,
            }
            .apply(&mut paths);
            assert!(
                (len(&paths[0]) - want).abs() < 1e-6,
                "{s} {e} {o}: {}",
                len(&paths[0])
            );
        }
        // Half of the square starting at its top-right corner runs down and along the bottom.
        let mut paths = [square.clone()];
        Trim {
            start: 0.0,
            end: 0.5,
            offset: 0.0,
            individually: false,
        }
        .apply(&mut paths);
        let pts: Vec<Point> = paths[0].segments().map(|s| s.eval(1.0)).collect();
        assert_eq!(pts, [Point::new(10.0, 10.0), Point::new(0.0, 10.0)]);
        // Offset past the start: one run across the corner where the outline closes.
        let mut paths = [square];
        Trim {
            start: 0.0,
            end: 0.5,
            offset: 270.0,
            individually: false,
        }
        .apply(&mut paths);
        let moves = paths[0]
            .elements()
            .iter()
            .filter(|e| matches!(e, PathEl::MoveTo(_)))
            .count();
        assert_eq!(moves, 1);
    }

    #[test]
    fn individually_trims_the_outlines_as_one_run() {
        let line = |y: f64| {
            let mut p = BezPath::new();
            p.move_to((0.0, y));
            p.line_to((10.0, y));
            p
        };
        let mut paths = [line(0.0), line(1.0)];
        Trim {
            start: 0.0,
            end: 0.75,
            offset: 0.0,
            individually: true,
        }
        .apply(&mut paths);
        assert!((len(&paths[0]) - 10.0).abs() < 1e-9);
        assert!((len(&paths[1]) - 5.0).abs() < 1e-9);
        let mut paths = [line(0.0), line(1.0)];
        Trim {
            start: 0.0,
            end: 0.75,
            offset: 0.0,
            individually: false,
        }
        .apply(&mut paths);
        assert!((len(&paths[0]) - 7.5).abs() < 1e-9 && (len(&paths[1]) - 7.5).abs() < 1e-9);
    }
}
