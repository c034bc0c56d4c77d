//! Offset paths (`op`): every outline moved `amount` along its normals, as lottie-web's
//! `OffsetPathModifier` makes it, so that gmotion's own render draws what the players
//! draw. Each segment is cut at its inflections (so its control polygon is convex), each
//! piece offset by moving its control polygon's edges and intersecting them, the pieces
//! of neighbouring segments cut where they cross, and the gaps between them joined with
//! a miter (up to the miter limit, else a bevel), a round arc or a bevel. An open outline
//! is offset along both of its sides, there and back.

use kurbo::{BezPath, CubicBez, ParamCurve, ParamCurveDeriv, Point, Shape as _};

use crate::outline::{
    Vertex, linearized, polar, same, same_point, subpaths, vertices_of, vertices_path,
};

/// How the offset pieces of neighbouring segments are joined (`lj`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Join {
    /// `lj` 1 (and anything unknown, as lottie-web reads it): a miter up to the limit.
    Miter,
    /// `lj` 2: a round arc.
    Round,
    /// `lj` 3: a straight bevel.
    Bevel,
}

impl Join {
    /// The join of a Lottie `lj` code.
    pub fn from_code(lj: Option<i64>) -> Join {
        match lj {
            Some(2) => Join::Round,
            Some(3) => Join::Bevel,
            _ => Join::Miter,
        }
    }
}

/// An offset path modifier at one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Offset {
    /// How far, in the outline's units (positive outwards on a clockwise outline).
    pub amount: f64,
    /// How pieces are joined.
    pub join: Join,
    /// How far a miter may reach from its corner.
    pub miter_limit: f64,
}

/// The handle length of a quarter circle as a cubic, lottie-web's `roundCorner`.
const ROUND: f64 = 0.5519;

impl Offset {
    /// `path` offset.
    pub fn apply(&self, path: &BezPath) -> BezPath {
        let mut out = BezPath::new();
        if self.amount == 0.0 {
            out.extend(path.iter());
            return out;
        }
        for sub in subpaths(path) {
            let (vertices, closed) = vertices_of(&sub);
            out.extend(vertices_path(&self.vertices(&vertices, closed), closed).iter());
        }
        out
    }

    fn vertices(&self, vs: &[Vertex], closed: bool) -> Vec<Vertex> {
        let n = vs.len();
        let count = if closed { n } else { n.saturating_sub(1) };
        let mut pieces: Vec<Vec<CubicBez>> = Vec::with_capacity(2 * count);
        for i in 0..count {
            let (a, b) = (vs[i], vs[(i + 1) % n]);
            pieces.push(split_offset(linearized(a.p, a.o, b.i, b.p), self.amount));
        }
        if !closed {
            for i in (0..count).rev() {
                let (a, b) = (vs[i], vs[i + 1]);
                pieces.push(split_offset(linearized(b.p, b.i, a.o, a.p), self.amount));
            }
        }
        prune_intersections(&mut pieces);
        let mut out: Vec<Vertex> = Vec::new();
        let mut last_point: Option<Point> = None;
        let mut last_seg: Option<CubicBez> = None;
        for piece in &pieces {
            if let (Some(seg), Some(first)) = (last_seg, piece.first()) {
                last_point = Some(self.join(&mut out, seg, *first));
            }
            last_seg = piece.last().copied();
            for seg in piece {
                match (last_point, out.last_mut()) {
                    (Some(lp), Some(last)) if same_point(seg.p0, lp) => last.o = seg.p1,
                    _ => out.push(Vertex {
                        p: seg.p0,
                        i: seg.p0,
                        o: seg.p1,
                    }),
                }
                out.push(Vertex {
                    p: seg.p3,
                    i: seg.p2,
                    o: seg.p3,
                });
                last_point = Some(seg.p3);
            }
        }
        if let (Some(seg), Some(first)) = (last_seg, pieces.first().and_then(|p| p.first())) {
            self.join(&mut out, seg, *first);
        }
        out
    }

    /// Joins the end of `seg1` to the start of `seg2` (lottie-web's `joinLines`): the
    /// point the next piece continues from.
    fn join(&self, out: &mut Vec<Vertex>, seg1: CubicBez, seg2: CubicBez) -> Point {
        let (p0, p1) = (seg1.p3, seg2.p0);
        if self.join == Join::Bevel || same_point(p0, p1) {
            return p0;
        }
        if self.join == Join::Round {
            let angle_out = -tangent_angle(&seg1, 1.0);
            let angle_in = -tangent_angle(&seg2, 0.0) + std::f64::consts::PI;
            let across = angle_out + std::f64::consts::FRAC_PI_2;
            let centre =
                line_intersection(p0, polar(p0, across, 100.0), p1, polar(p1, across, 100.0));
            let radius = match centre {
                Some(c) => c.distance(p0),
                None => p0.distance(p1) / 2.0,
            };
            if let Some(last) = out.last_mut() {
                last.o = polar(p0, angle_out, 2.0 * radius * ROUND);
            }
            out.push(Vertex {
                p: p1,
                i: polar(p1, angle_in, 2.0 * radius * ROUND),
                o: p1,
            });
            return p1;
        }
        let t0 = if same_point(p0, seg1.p2) {
            seg1.p0
        } else {
            seg1.p2
        };
        let t1 = if same_point(p1, seg2.p1) {
            seg2.p3
        } else {
            seg2.p1
        };
        match line_intersection(t0, p0, p1, t1) {
            Some(x) if x.distance(p0) < self.miter_limit => {
                out.push(Vertex { p: x, i: x, o: x });
                x
            }
            _ => p0,
        }
    }
}

fn tangent_angle(seg: &CubicBez, t: f64) -> f64 {
    let d = seg.deriv().eval(t);
    d.y.atan2(d.x)
}

/// Where the line through `a1`, `a2` meets the line through `b1`, `b2` (homogeneous
/// coordinates, as lottie-web computes it); `None` for parallel lines.
fn line_intersection(a1: Point, a2: Point, b1: Point, b2: Point) -> Option<Point> {
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let h = |p: Point| [p.x, p.y, 1.0];
    let r = cross(cross(h(a1), h(a2)), cross(h(b1), h(b2)));
    (r[2].abs() > 1e-5).then(|| Point::new(r[0] / r[2], r[1] / r[2]))
}

/// The edge `p1`→`p2` moved `amount` to its side.
fn edge_offset(p1: Point, p2: Point, amount: f64) -> (Point, Point) {
    let angle = (p2.x - p1.x).atan2(p2.y - p1.y);
    (polar(p1, angle, amount), polar(p2, angle, amount))
}

/// A convex segment offset: its control polygon's three edges moved and intersected.
fn offset_segment(seg: CubicBez, amount: f64) -> CubicBez {
    let (p0, p1a) = edge_offset(seg.p0, seg.p1, amount);
    let (p1b, p2b) = edge_offset(seg.p1, seg.p2, amount);
    let (p2a, p3) = edge_offset(seg.p2, seg.p3, amount);
    let p1 = line_intersection(p0, p1a, p1b, p2b).unwrap_or(p1a);
    let p2 = line_intersection(p2a, p3, p1b, p2b).unwrap_or(p2a);
    CubicBez::new(p0, p1, p2, p3)
}

/// Where a segment's curvature changes sign, in `(0, 1)` (lottie-web's
/// `inflectionPoints`, from the polynomial coefficients).
fn inflections(seg: &CubicBez) -> Vec<f64> {
    let (p0, p1, p2, p3) = (
        seg.p0.to_vec2(),
        seg.p1.to_vec2(),
        seg.p2.to_vec2(),
        seg.p3.to_vec2(),
    );
    let a = -p0 + 3.0 * p1 - 3.0 * p2 + p3;
    let b = 3.0 * p0 - 6.0 * p1 + 3.0 * p2;
    let c = -3.0 * p0 + 3.0 * p1;
    let denom = a.y * b.x - a.x * b.y;
    if denom.abs() <= 1e-5 {
        return Vec::new();
    }
    let cusp = -0.5 * (a.y * c.x - a.x * c.y) / denom;
    let square = cusp * cusp - (b.y * c.x - b.x * c.y) / (3.0 * denom);
    if square < 0.0 {
        return Vec::new();
    }
    let root = square.sqrt();
    if root.abs() <= 1e-5 {
        return if root > 0.0 && root < 1.0 {
            vec![cusp]
        } else {
            Vec::new()
        };
    }
    [cusp - root, cusp + root]
        .into_iter()
        .filter(|&r| r > 0.0 && r < 1.0)
        .collect()
}

/// `seg` cut at `t` into two, each linearized as lottie-web's `split` makes them.
fn split(seg: &CubicBez, t: f64) -> (CubicBez, CubicBez) {
    if t <= 0.0 {
        return (CubicBez::new(seg.p0, seg.p0, seg.p0, seg.p0), *seg);
    }
    if t >= 1.0 {
        return (*seg, CubicBez::new(seg.p3, seg.p3, seg.p3, seg.p3));
    }
    let p10 = seg.p0.lerp(seg.p1, t);
    let p11 = seg.p1.lerp(seg.p2, t);
    let p12 = seg.p2.lerp(seg.p3, t);
    let p20 = p10.lerp(p11, t);
    let p21 = p11.lerp(p12, t);
    let p3 = p20.lerp(p21, t);
    (
        linearized(seg.p0, p10, p20, p3),
        linearized(p3, p21, p12, seg.p3),
    )
}

/// `seg` offset in convex pieces, cut at its inflections.
fn split_offset(seg: CubicBez, amount: f64) -> Vec<CubicBez> {
    let flex = inflections(&seg);
    if flex.is_empty() {
        return vec![offset_segment(seg, amount)];
    }
    if flex.len() == 1 || same(flex[1], 1.0) {
        let (l, r) = split(&seg, flex[0]);
        return vec![offset_segment(l, amount), offset_segment(r, amount)];
    }
    let (l, rest) = split(&seg, flex[0]);
    let (m, r) = split(&rest, (flex[1] - flex[0]) / (1.0 - flex[0]));
    vec![
        offset_segment(l, amount),
        offset_segment(m, amount),
        offset_segment(r, amount),
    ]
}

/// A piece of a segment in a crossing search: the piece, its box and its parameters.
struct Part {
    seg: CubicBez,
    bbox: kurbo::Rect,
    t: f64,
    t1: f64,
    t2: f64,
}

impl Part {
    fn new(seg: CubicBez, t1: f64, t2: f64) -> Part {
        Part {
            seg,
            bbox: seg.bounding_box(),
            t: (t1 + t2) / 2.0,
            t1,
            t2,
        }
    }

    fn halves(&self) -> [Part; 2] {
        let (l, r) = split(&self.seg, 0.5);
        [Part::new(l, self.t1, self.t), Part::new(r, self.t, self.t2)]
    }

    fn overlaps(&self, other: &Part) -> bool {
        let (a, b) = (self.bbox, other.bbox);
        (a.center().x - b.center().x).abs() * 2.0 < a.width() + b.width()
            && (a.center().y - b.center().y).abs() * 2.0 < a.height() + b.height()
    }
}

/// Where two segments cross, as lottie-web's `intersections` finds them: boxes halved
/// together seven times or down to 2 units, in its order.
fn crossings(a: &CubicBez, b: &CubicBez) -> Vec<(f64, f64)> {
    fn search(d1: &Part, d2: &Part, depth: u32, out: &mut Vec<(f64, f64)>) {
        if !d1.overlaps(d2) {
            return;
        }
        let small = |p: &Part| p.bbox.width() <= 2.0 && p.bbox.height() <= 2.0;
        if depth >= 7 || (small(d1) && small(d2)) {
            out.push((d1.t, d2.t));
            return;
        }
        let h1 = d1.halves();
        let h2 = d2.halves();
        for x in &h1 {
            for y in &h2 {
                search(x, y, depth + 1, out);
            }
        }
    }
    let mut out = Vec::new();
    search(
        &Part::new(*a, 0.0, 1.0),
        &Part::new(*b, 0.0, 1.0),
        0,
        &mut out,
    );
    out
}

/// The first crossing of `a` and `b`, but one at the very end of `a`.
fn first_crossing(a: &CubicBez, b: &CubicBez) -> Option<(f64, f64)> {
    let mut found = crossings(a, b);
    if found.first().is_some_and(|x| same(x.0, 1.0)) {
        found.remove(0);
    }
    found.first().copied()
}

/// The pieces of two neighbouring segments cut where they cross.
fn prune_pair(a: &[CubicBez], b: &[CubicBez]) -> (Vec<CubicBez>, Vec<CubicBez>) {
    let (mut outa, mut outb) = (a.to_vec(), b.to_vec());
    if let (Some(la), Some(fb)) = (a.last(), b.first())
        && let Some((ta, tb)) = first_crossing(la, fb)
    {
        *outa.last_mut().expect("a piece") = split(la, ta).0;
        outb[0] = split(fb, tb).1;
    }
    if a.len() > 1
        && b.len() > 1
        && let Some((ta, tb)) = first_crossing(&a[0], &b[b.len() - 1])
    {
        return (vec![split(&a[0], ta).0], vec![split(&b[b.len() - 1], tb).1]);
    }
    (outa, outb)
}

fn prune_intersections(pieces: &mut [Vec<CubicBez>]) {
    for i in 1..pieces.len() {
        let (a, b) = prune_pair(&pieces[i - 1], &pieces[i]);
        pieces[i - 1] = a;
        pieces[i] = b;
    }
    let n = pieces.len();
    if n > 1 {
        let (a, b) = prune_pair(&pieces[n - 1], &pieces[0]);
        pieces[n - 1] = a;
        pieces[0] = b;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Rect;

    #[test]
    fn a_square_offset_outwards_with_miters_is_a_larger_square() {
        // A clockwise square (y down), as After Effects draws a rectangle.
        let sq = Rect::new(0.0, 0.0, 100.0, 100.0).to_path(0.1);
        for (amount, grown) in [
            (10.0, Rect::new(-10.0, -10.0, 110.0, 110.0)),
            (-10.0, Rect::new(10.0, 10.0, 90.0, 90.0)),
        ] {
            let o = Offset {
                amount,
                join: Join::Miter,
                miter_limit: 100.0,
            }
            .apply(&sq);
            let b = o.bounding_box();
            assert!(
                (b.x0 - grown.x0).abs() < 1e-9 && (b.y1 - grown.y1).abs() < 1e-9,
                "{amount}: {b:?}"
            );
            assert!(
                (o.area().abs() - grown.area()).abs() < 1e-6,
                "{amount}: {}",
                o.area()
            );
        }
    }

    #[test]
    fn bevels_cut_the_corners_and_a_low_miter_limit_bevels_too() {
        let sq = Rect::new(0.0, 0.0, 100.0, 100.0).to_path(0.1);
        let bevel = Offset {
            amount: 10.0,
            join: Join::Bevel,
            miter_limit: 100.0,
        }
        .apply(&sq);
        // 120 x 120 less four corner triangles of 10 x 10 / 2.
        assert!(
            (bevel.area().abs() - (14_400.0 - 200.0)).abs() < 1e-6,
            "{}",
            bevel.area()
        );
        let limited = Offset {
            amount: 10.0,
            join: Join::Miter,
            miter_limit: 5.0,
        }
        .apply(&sq);
        assert!((limited.area().abs() - bevel.area().abs()).abs() < 1e-6);
    }

    #[test]
    fn inflections_agree_with_kurbo() {
        let curves = [
            CubicBez::new((0.0, 0.0), (100.0, 20.0), (-20.0, 80.0), (100.0, 100.0)),
            CubicBez::new((0.0, 0.0), (30.0, 90.0), (60.0, -90.0), (100.0, 10.0)),
            CubicBez::new((0.0, 0.0), (0.0, 50.0), (50.0, 100.0), (100.0, 100.0)),
        ];
        for c in curves {
            let ours = inflections(&c);
            let theirs = c.inflections();
            assert_eq!(ours.len(), theirs.len(), "{c:?}: {ours:?} {theirs:?}");
            for (a, b) in ours.iter().zip(&theirs) {
                assert!((a - b).abs() < 1e-9, "{c:?}: {ours:?} {theirs:?}");
            }
        }
        // lottie-web's formula divides by a term that vanishes on a point-symmetric S, so
        // it (and gmotion after it) does not cut one.
        let symmetric = CubicBez::new((0.0, 0.0), (30.0, 90.0), (70.0, -90.0), (100.0, 0.0));
        assert!(inflections(&symmetric).is_empty());
    }
}
