//! Shape morphing: two outlines brought to one structure (the same subpaths, each of the
//! same number of cubic segments), so that interpolating their control points linearly
//! draws the in-between. This is what `animate(morph, …)` plays, and what the Lottie (path
//! keyframes) and SMIL (`d` animation) exporters write: every player interpolates matched
//! control points linearly, so they all draw the same in-between.
//!
//! How points correspond (see [`correspond`]):
//! - **Subpaths** are paired by size and place: the largest (by absolute area) first, each
//!   with the unpaired subpath of the other outline nearest to it (centroid distance plus
//!   the difference of the square roots of the areas). A subpath left without a partner
//!   grows from (or shrinks to) a point at its own centroid.
//! - **Orientation**: when the largest pair winds in opposite directions, the start
//!   outline's subpaths are all reversed (which keeps its fill under either fill rule).
//! - **Start point**: for closed pairs the target is rotated along its length to the offset
//!   that minimises the summed squared distance between the two outlines sampled at equal
//!   fractions of their lengths; open pairs keep their ends, the target reversed when that
//!   is closer.
//! - **Resampling by arc length**: both outlines are cut at the union of their vertices'
//!   positions as fractions of their lengths, so every vertex of one meets the point at the
//!   same fraction of the other. The cuts split the original segments exactly (de
//!   Casteljau), so the start and end outlines are the original geometry, not an
//!   approximation.
//!
//! For two convex outlines, or two star-shaped ones about nearby centres, corresponding
//! points advance around both outlines together, so the in-between neither twists nor
//! folds. For other pairs (a spiral into a circle, outlines far apart) the in-between is
//! still continuous but may cross itself on the way.

use kurbo::{BezPath, CubicBez, ParamCurve, ParamCurveArclen, PathEl, PathSeg, Point, Rect, Vec2};

/// Arc-length accuracy, relative to the outline's size.
const ACCURACY: f64 = 1e-6;
/// Fractions closer than this (of a subpath's length) are one cut: a vertex of one outline
/// that nearly meets a vertex of the other gives no sliver of a segment between them
/// (whose stroke join would show).
const SAME: f64 = 1e-6;
/// Samples of the start outline when choosing the target's start point.
const SAMPLES: usize = 64;
/// Candidate start offsets along the target (a multiple of [`SAMPLES`]).
const OFFSETS: usize = 256;

/// One subpath as cubic segments.
#[derive(Clone, Debug)]
struct Contour {
    segs: Vec<CubicBez>,
    closed: bool,
}

/// A line as a cubic with its control points at the thirds (so it stays straight while it
/// is interpolated).
fn line(a: Point, b: Point) -> CubicBez {
    CubicBez::new(a, a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b)
}

fn reversed(c: CubicBez) -> CubicBez {
    CubicBez::new(c.p3, c.p2, c.p1, c.p0)
}

/// The subpaths of `path` (a lone `M` draws nothing and is dropped).
fn contours(path: &BezPath) -> Vec<Contour> {
    let mut out = Vec::new();
    let mut cur = Contour {
        segs: Vec::new(),
        closed: false,
    };
    let mut start = Point::ORIGIN;
    let mut last = Point::ORIGIN;
    let flush = |cur: &mut Contour, out: &mut Vec<Contour>| {
        if !cur.segs.is_empty() {
            out.push(std::mem::replace(
                cur,
                Contour {
                    segs: Vec::new(),
                    closed: false,
                },
            ));
        }
        cur.closed = false;
    };
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) => {
                flush(&mut cur, &mut out);
                start = p;
                last = p;
            }
            PathEl::LineTo(p) => {
                cur.segs.push(line(last, p));
                last = p;
            }
            PathEl::QuadTo(a, p) => {
                cur.segs.push(kurbo::QuadBez::new(last, a, p).raise());
                last = p;
            }
            PathEl::CurveTo(a, b, p) => {
                cur.segs.push(CubicBez::new(last, a, b, p));
                last = p;
            }
            PathEl::ClosePath => {
                if !cur.segs.is_empty() {
                    // A closing gap of float noise (an outline this module cut) is no
                    // segment: the structure must read back as it was written.
                    if (last - start).hypot() > 1e-9 {
                        cur.segs.push(line(last, start));
                    }
                    cur.closed = true;
                }
                flush(&mut cur, &mut out);
                last = start;
            }
        }
    }
    flush(&mut cur, &mut out);
    out
}

impl Contour {
    fn path(&self) -> BezPath {
        let mut p = BezPath::new();
        self.append_to(&mut p);
        p
    }

    fn append_to(&self, p: &mut BezPath) {
        let Some(first) = self.segs.first() else {
            return;
        };
        p.move_to(first.p0);
        for s in &self.segs {
            p.curve_to(s.p1, s.p2, s.p3);
        }
        if self.closed {
            p.close_path();
        }
    }

    fn reverse(&mut self) {
        self.segs.reverse();
        for s in &mut self.segs {
            *s = reversed(*s);
        }
    }

    /// Signed area (kurbo's sign convention).
    fn area(&self) -> f64 {
        kurbo::Shape::area(&self.path())
    }

    fn bbox(&self) -> Rect {
        kurbo::Shape::bounding_box(&self.path())
    }

    fn centroid(&self) -> Point {
        centroid(std::slice::from_ref(&self.path())).unwrap_or(self.bbox().center())
    }

    /// The contour's size, for arc-length accuracy.
    fn scale(&self) -> f64 {
        let b = self.bbox();
        b.width().max(b.height()).max(1e-9)
    }

    /// Each segment's length.
    fn lengths(&self) -> Vec<f64> {
        let acc = ACCURACY * self.scale();
        self.segs.iter().map(|s| s.arclen(acc)).collect()
    }
}

/// Where each segment starts, as a fraction of the contour's length (`[0, …]`, one per
/// segment), and the total length. A contour of no length spreads its segments evenly.
fn breakpoints(lengths: &[f64]) -> (Vec<f64>, f64) {
    let total: f64 = lengths.iter().sum();
    let n = lengths.len();
    let mut out = Vec::with_capacity(n);
    let mut acc = 0.0;
    for (i, l) in lengths.iter().enumerate() {
        out.push(if total > 0.0 {
            acc / total
        } else {
            i as f64 / n as f64
        });
        acc += l;
    }
    (out, total)
}

/// A contour measured for cutting by arc length.
struct Measured<'a> {
    c: &'a Contour,
    lengths: Vec<f64>,
    starts: Vec<f64>,
    total: f64,
    acc: f64,
}

impl<'a> Measured<'a> {
    fn new(c: &'a Contour) -> Measured<'a> {
        let lengths = c.lengths();
        let (starts, total) = breakpoints(&lengths);
        Measured {
            c,
            lengths,
            starts,
            total,
            acc: ACCURACY * c.scale(),
        }
    }

    /// The segment holding fraction `s` (in `[0, 1]`).
    fn segment(&self, s: f64) -> usize {
        self.starts.partition_point(|&x| x <= s).saturating_sub(1)
    }

    /// The parameter of fraction `s` within segment `i`.
    fn param(&self, i: usize, s: f64) -> f64 {
        let n = self.c.segs.len();
        let start = self.starts[i];
        let end = if i + 1 < n { self.starts[i + 1] } else { 1.0 };
        if s <= start + SAME {
            return 0.0;
        }
        if s >= end - SAME {
            return 1.0;
        }
        if self.total <= 0.0 {
            return ((s - start) / (end - start)).clamp(0.0, 1.0);
        }
        let local = (s - start) * self.total;
        if self.lengths[i] <= 0.0 {
            return 0.0;
        }
        self.c.segs[i].inv_arclen(local, self.acc).clamp(0.0, 1.0)
    }

    /// The point at fraction `s` (taken modulo 1).
    fn at(&self, s: f64) -> Point {
        let s = s.rem_euclid(1.0);
        let i = self.segment(s);
        self.c.segs[i].eval(self.param(i, s))
    }

    /// The pieces between consecutive `cuts` (fractions in `[0, 1)`, ascending, holding
    /// every segment start shifted by `-shift`), read from `shift` on: each lies within one
    /// segment, so it is an exact piece of it.
    fn cut(&self, cuts: &[f64], shift: f64) -> Vec<Piece> {
        let mut out = Vec::with_capacity(cuts.len());
        for (k, &u) in cuts.iter().enumerate() {
            let next = cuts.get(k + 1).copied().unwrap_or(1.0);
            let mut s0 = (u + shift).rem_euclid(1.0);
            if s0 >= 1.0 - SAME {
                s0 = 0.0;
            }
            let s1 = s0 + (next - u);
            let i = self.segment((s0 + s1) / 2.0);
            let (t0, t1) = (self.param(i, s0), self.param(i, s1.min(1.0)));
            out.push(Piece { seg: i, t0, t1 });
        }
        out
    }
}

/// A piece of a contour's segment `seg`, between parameters `t0` and `t1`.
#[derive(Clone, Copy, Debug)]
struct Piece {
    seg: usize,
    t0: f64,
    t1: f64,
}

fn pieces(c: &Contour, ps: &[Piece]) -> Vec<CubicBez> {
    ps.iter()
        .map(|p| c.segs[p.seg].subsegment(p.t0..p.t1))
        .collect()
}

/// A point drawn as `n` segments of no length (a subpath that grows from it).
fn point_contour(p: Point, n: usize, closed: bool) -> Contour {
    Contour {
        segs: vec![CubicBez::new(p, p, p, p); n],
        closed,
    }
}

/// `a` and `b` (one subpath each) cut to the same number of segments, `b`'s start moved
/// (closed pairs) or its direction chosen (open ones) to lie closest to `a`; also how `a`
/// was cut.
fn match_pair(a: &Contour, b: &Contour) -> (Contour, Contour, Vec<Piece>) {
    let closed = a.closed && b.closed;
    let ma = Measured::new(a);
    let mut b = b.clone();
    let samples: Vec<Point> = (0..SAMPLES)
        .map(|m| ma.at(m as f64 / SAMPLES as f64))
        .collect();
    let cost = |mb: &Measured, shift: f64| -> f64 {
        samples
            .iter()
            .enumerate()
            .map(|(m, p)| (*p - mb.at(m as f64 / SAMPLES as f64 + shift)).hypot2())
            .sum()
    };
    let shift = if closed {
        let mb = Measured::new(&b);
        let grid: Vec<Point> = (0..OFFSETS)
            .map(|k| mb.at(k as f64 / OFFSETS as f64))
            .collect();
        let step = OFFSETS / SAMPLES;
        let best = (0..OFFSETS)
            .min_by(|&x, &y| {
                let c = |d: usize| -> f64 {
                    samples
                        .iter()
                        .enumerate()
                        .map(|(m, p)| (*p - grid[(m * step + d) % OFFSETS]).hypot2())
                        .sum()
                };
                c(x).total_cmp(&c(y))
            })
            .unwrap_or(0);
        best as f64 / OFFSETS as f64
    } else {
        let forward = cost(&Measured::new(&b), 0.0);
        let mut back = b.clone();
        back.reverse();
        if cost(&Measured::new(&back), 0.0) < forward {
            b = back;
        }
        0.0
    };
    let mb = Measured::new(&b);
    let mut cuts: Vec<f64> = ma
        .starts
        .iter()
        .copied()
        .chain(mb.starts.iter().map(|s| (s - shift).rem_euclid(1.0)))
        .map(|s| if s >= 1.0 - SAME { 0.0 } else { s })
        .collect();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|x, y| (*x - *y).abs() <= SAME);
    if cuts.first() != Some(&0.0) {
        cuts.insert(0, 0.0);
    }
    let cut_a = ma.cut(&cuts, 0.0);
    let from = Contour {
        segs: pieces(a, &cut_a),
        closed,
    };
    let to = Contour {
        segs: pieces(&b, &mb.cut(&cuts, shift)),
        closed,
    };
    (from, to, cut_a)
}

/// `from` and `to` brought to one structure: the same subpaths, each of the same number of
/// cubic segments, the first the geometry of `from` and the second that of `to`
/// (see the module documentation for how points correspond). An empty outline on either
/// side becomes a point at the other's centroid.
pub fn correspond(from: &BezPath, to: &BezPath) -> (BezPath, BezPath) {
    let mut a = contours(from);
    let mut b = contours(to);
    if a.is_empty() && b.is_empty() {
        return (BezPath::new(), BezPath::new());
    }
    let size = |c: &Contour| c.area().abs();
    a.sort_by(|x, y| size(y).total_cmp(&size(x)));
    b.sort_by(|x, y| size(y).total_cmp(&size(x)));
    // The largest pair decides the direction of the whole start outline.
    if let (Some(x), Some(y)) = (a.first(), b.first()) {
        let (sa, sb) = (x.area(), y.area());
        if x.closed && y.closed && sa * sb < 0.0 {
            for c in &mut a {
                c.reverse();
            }
        }
    }
    let cost = |x: &Contour, y: &Contour| {
        (x.centroid() - y.centroid()).hypot2() + (size(x).sqrt() - size(y).sqrt()).powi(2)
    };
    let mut free: Vec<Option<Contour>> = b.into_iter().map(Some).collect();
    let mut pairs: Vec<(Contour, Contour)> = Vec::new();
    for x in a {
        let best = free
            .iter()
            .enumerate()
            .filter_map(|(i, y)| y.as_ref().map(|y| (i, cost(&x, y))))
            .min_by(|p, q| p.1.total_cmp(&q.1))
            .map(|(i, _)| i);
        match best.and_then(|i| free[i].take()) {
            Some(y) => {
                let (f, t, _) = match_pair(&x, &y);
                pairs.push((f, t));
            }
            None => {
                let p = point_contour(x.centroid(), x.segs.len(), x.closed);
                pairs.push((x, p));
            }
        }
    }
    for y in free.into_iter().flatten() {
        let p = point_contour(y.centroid(), y.segs.len(), y.closed);
        pairs.push((p, y));
    }
    let mut pa = BezPath::new();
    let mut pb = BezPath::new();
    for (x, y) in &pairs {
        x.append_to(&mut pa);
        y.append_to(&mut pb);
    }
    (pa, pb)
}

/// How an outline of a morph chain is cut again when the next morph of the chain is
/// matched ([`correspond_from`]): each of its subpaths cut into pieces of its segments,
/// subpaths that grow from a point appended. Cutting a cubic is linear in its control
/// points, so cutting both outlines of an earlier morph the same way leaves its in-between
/// exactly as it was: every morph of a chain then has one structure, which Lottie and SMIL
/// players need to interpolate one path property through all of them.
#[derive(Clone, Debug)]
pub struct Refine {
    /// Per subpath: its pieces, and whether it is closed after.
    cut: Vec<(Vec<Piece>, bool)>,
    /// Subpaths appended: a point drawn as this many segments, closed or not.
    grown: Vec<(Point, usize, bool)>,
}

impl Refine {
    /// `path` (of the structure the chain had) cut to the new structure.
    pub fn apply(&self, path: &BezPath) -> BezPath {
        let cs = contours(path);
        let mut out = BezPath::new();
        for (c, (ps, closed)) in cs.iter().zip(&self.cut) {
            Contour {
                segs: pieces(c, ps),
                closed: *closed,
            }
            .append_to(&mut out);
        }
        for &(p, n, closed) in &self.grown {
            point_contour(p, n, closed).append_to(&mut out);
        }
        out
    }
}

/// Like [`correspond`], for the next morph of a chain: `from` is the outline the chain
/// has reached (of the chain's structure), kept in its order and direction, so that the
/// chain's earlier outlines can be cut the same way ([`Refine`]).
pub fn correspond_from(from: &BezPath, to: &BezPath) -> (BezPath, BezPath, Refine) {
    let a = contours(from);
    let mut b = contours(to);
    let size = |c: &Contour| c.area().abs();
    b.sort_by(|x, y| size(y).total_cmp(&size(x)));
    let cost = |x: &Contour, y: &Contour| {
        (x.centroid() - y.centroid()).hypot2() + (size(x).sqrt() - size(y).sqrt()).powi(2)
    };
    // The larger subpaths of `from` choose first; the output keeps `from`'s order.
    let mut order: Vec<usize> = (0..a.len()).collect();
    order.sort_by(|&i, &j| size(&a[j]).total_cmp(&size(&a[i])));
    let mut free: Vec<Option<Contour>> = b.into_iter().map(Some).collect();
    let mut partner: Vec<Option<Contour>> = vec![None; a.len()];
    for &i in &order {
        let best = free
            .iter()
            .enumerate()
            .filter_map(|(k, y)| y.as_ref().map(|y| (k, cost(&a[i], y))))
            .min_by(|p, q| p.1.total_cmp(&q.1))
            .map(|(k, _)| k);
        partner[i] = best.and_then(|k| free[k].take());
    }
    let mut pa = BezPath::new();
    let mut pb = BezPath::new();
    let mut refine = Refine {
        cut: Vec::with_capacity(a.len()),
        grown: Vec::new(),
    };
    for (x, y) in a.iter().zip(partner) {
        match y {
            Some(mut y) => {
                if x.closed && y.closed && x.area() * y.area() < 0.0 {
                    y.reverse();
                }
                let (f, t, cut) = match_pair(x, &y);
                f.append_to(&mut pa);
                t.append_to(&mut pb);
                refine.cut.push((cut, f.closed));
            }
            None => {
                x.append_to(&mut pa);
                point_contour(x.centroid(), x.segs.len(), x.closed).append_to(&mut pb);
                let whole = (0..x.segs.len())
                    .map(|seg| Piece {
                        seg,
                        t0: 0.0,
                        t1: 1.0,
                    })
                    .collect();
                refine.cut.push((whole, x.closed));
            }
        }
    }
    for y in free.into_iter().flatten() {
        let p = y.centroid();
        point_contour(p, y.segs.len(), y.closed).append_to(&mut pa);
        y.append_to(&mut pb);
        refine.grown.push((p, y.segs.len(), y.closed));
    }
    (pa, pb, refine)
}

/// The outline between `a` and `b` (of one structure, from [`correspond`]) at `p`: every
/// point interpolated linearly.
pub fn lerp(a: &BezPath, b: &BezPath, p: f64) -> BezPath {
    let mix = |x: Point, y: Point| x.lerp(y, p);
    let els = a
        .elements()
        .iter()
        .zip(b.elements())
        .map(|(x, y)| match (*x, *y) {
            (PathEl::MoveTo(x), PathEl::MoveTo(y)) => PathEl::MoveTo(mix(x, y)),
            (PathEl::LineTo(x), PathEl::LineTo(y)) => PathEl::LineTo(mix(x, y)),
            (PathEl::QuadTo(x0, x1), PathEl::QuadTo(y0, y1)) => {
                PathEl::QuadTo(mix(x0, y0), mix(x1, y1))
            }
            (PathEl::CurveTo(x0, x1, x2), PathEl::CurveTo(y0, y1, y2)) => {
                PathEl::CurveTo(mix(x0, y0), mix(x1, y1), mix(x2, y2))
            }
            (x, _) => x,
        });
    BezPath::from_vec(els.collect())
}

/// An outline as a keyframe value: two are the same when every point agrees up to
/// rounding ([`crate::tolerance::KEY`]), so where one morph of a chain ends and the next
/// begins (the same outline, of one structure) is no jump.
#[derive(Clone, Debug, PartialEq)]
pub struct Outline(pub BezPath);

impl crate::keyframe::Same for Outline {
    fn same(&self, other: &Outline) -> bool {
        let (a, b) = (self.0.elements(), other.0.elements());
        a.len() == b.len()
            && a.iter().zip(b).all(|(x, y)| {
                let (px, py) = (points_of(*x), points_of(*y));
                px.len() == py.len()
                    && px.iter().zip(&py).all(|(p, q)| {
                        crate::tolerance::KEY.same(p.x, q.x) && crate::tolerance::KEY.same(p.y, q.y)
                    })
            })
    }
}

fn points_of(el: PathEl) -> Vec<Point> {
    match el {
        PathEl::MoveTo(p) | PathEl::LineTo(p) => vec![p],
        PathEl::QuadTo(a, p) => vec![a, p],
        PathEl::CurveTo(a, b, p) => vec![a, b, p],
        PathEl::ClosePath => Vec::new(),
    }
}

/// The area centroid of `paths` taken together (each subpath's signed area counted, so a
/// hole counts against its outline), or `None` when they enclose no area.
pub fn centroid(paths: &[BezPath]) -> Option<Point> {
    let mut area = 0.0;
    let mut moment = Vec2::ZERO;
    for path in paths {
        let mut first = None;
        let mut last = Point::ORIGIN;
        let mut edge = |a: Point, b: Point| {
            let cross = a.to_vec2().cross(b.to_vec2());
            area += cross;
            moment += (a.to_vec2() + b.to_vec2()) * cross;
        };
        kurbo::flatten(path.iter(), 1e-3 * scale(path), |el| match el {
            PathEl::MoveTo(p) => {
                if let Some(f) = first {
                    edge(last, f);
                }
                first = Some(p);
                last = p;
            }
            PathEl::LineTo(p) => {
                edge(last, p);
                last = p;
            }
            PathEl::ClosePath => {
                if let Some(f) = first {
                    edge(last, f);
                    last = f;
                }
                first = None;
            }
            _ => {}
        });
        if let Some(f) = first {
            edge(last, f);
        }
    }
    if area.abs() <= 1e-12 {
        return None;
    }
    let c = moment / (3.0 * area);
    Some(c.to_point())
}

fn scale(path: &BezPath) -> f64 {
    let b = kurbo::Shape::bounding_box(path);
    b.width().max(b.height()).max(1e-9)
}

/// The segments of a path as cubics, for checks that walk an outline (a test of the
/// in-between, the exporters' vertex counts).
pub fn cubics(path: &BezPath) -> Vec<CubicBez> {
    path.segments()
        .map(|s| match s {
            PathSeg::Line(l) => line(l.p0, l.p1),
            PathSeg::Quad(q) => q.raise(),
            PathSeg::Cubic(c) => c,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::{Circle, Shape as _};

    fn star(c: Point, r0: f64, r1: f64, n: usize) -> BezPath {
        let mut p = BezPath::new();
        for k in 0..2 * n {
            let a = std::f64::consts::PI * k as f64 / n as f64;
            let r = if k % 2 == 0 { r0 } else { r1 };
            let q = c + Vec2::new(a.sin(), -a.cos()) * r;
            if k == 0 { p.move_to(q) } else { p.line_to(q) }
        }
        p.close_path();
        p
    }

    #[test]
    fn ends_keep_their_geometry() {
        let a = Circle::new((50.0, 50.0), 30.0).to_path(1e-3);
        let b = star(Point::new(60.0, 40.0), 40.0, 15.0, 5);
        let (x, y) = correspond(&a, &b);
        assert_eq!(x.elements().len(), y.elements().len());
        assert!((x.area().abs() - a.area().abs()).abs() < 1e-6 * a.area().abs());
        assert!((y.area().abs() - b.area().abs()).abs() < 1e-6 * b.area().abs());
        assert_eq!(lerp(&x, &y, 1.0), y);
    }

    #[test]
    fn unpaired_subpaths_grow_from_a_point() {
        let a = Circle::new((50.0, 50.0), 30.0).to_path(1e-3);
        let mut b = star(Point::new(50.0, 50.0), 40.0, 15.0, 5);
        b.extend(Circle::new((150.0, 50.0), 10.0).to_path(1e-3));
        let (x, y) = correspond(&a, &b);
        let subpaths = |p: &BezPath| {
            p.elements()
                .iter()
                .filter(|e| matches!(e, PathEl::MoveTo(_)))
                .count()
        };
        assert_eq!((subpaths(&x), subpaths(&y)), (2, 2));
        assert!((y.area().abs() - b.area().abs()).abs() < 1e-6 * b.area().abs());
    }

    #[test]
    fn centroid_of_a_square() {
        let r = Rect::new(10.0, 20.0, 30.0, 60.0).to_path(0.1);
        let c = centroid(&[r]).unwrap();
        assert!((c - Point::new(20.0, 40.0)).hypot() < 1e-9);
    }
}
