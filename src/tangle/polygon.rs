//! Polygons with holes — the boundary Θ of a tangle shape — and their conversions from and
//! to kurbo paths.
//!
//! Every vertex lies on one global [`Grid`] (multiples of a power-of-two quantum), so the
//! integer boolean engine sees exactly the coordinates we hold: an edge shared by two
//! pieces is bit-identical in both, and converting to and from the engine loses nothing.

use i_overlay::i_float::int::point::IntPoint;
use i_overlay::i_shape::int::shape::{IntShape, IntShapes};
use kurbo::{Affine, BezPath, PathEl, Point, Rect, Vec2};

/// Coordinates handed to the integer engine stay below this magnitude, leaving headroom in
/// i_overlay's `i32` budget (2^29) for offsets and cut lines reaching past a shape.
const COORD_BUDGET: f64 = (1u64 << 27) as f64;

/// The finest quantum we ever use; finer buys nothing at drawing scales.
const MAX_SCALE: f64 = (1u64 << 20) as f64;

/// The common integer lattice all tangle geometry is snapped to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    scale: f64,
}

impl Grid {
    /// The finest power-of-two lattice on which everything within twice `bounds` (around the
    /// origin) fits the integer engine. `None` if `bounds` is not finite.
    pub fn for_bounds(bounds: Rect) -> Option<Grid> {
        let reach = [bounds.x0, bounds.x1, bounds.y0, bounds.y1]
            .iter()
            .map(|v| v.abs())
            .fold(0.0f64, f64::max);
        if !reach.is_finite() {
            return None;
        }
        let reach = 2.0 * reach + 1.0;
        let scale = (COORD_BUDGET / reach).log2().floor().exp2().min(MAX_SCALE);
        Some(Grid { scale })
    }

    /// The spacing of the lattice.
    pub fn quantum(&self) -> f64 {
        1.0 / self.scale
    }

    /// Whether a point is within the range the integer engine handles exactly.
    pub fn holds(&self, p: Point) -> bool {
        p.x.is_finite()
            && p.y.is_finite()
            && (p.x * self.scale).abs() < 2.0 * COORD_BUDGET
            && (p.y * self.scale).abs() < 2.0 * COORD_BUDGET
    }

    /// The nearest lattice point.
    pub fn snap(&self, p: Point) -> Point {
        self.to_point(self.to_int(p))
    }

    /// The lattice coordinates of a point (saturating far outside the engine's range).
    pub fn to_int(&self, p: Point) -> IntPoint<i32> {
        let q = |v: f64| {
            (v * self.scale)
                .round()
                .clamp(-4.0 * COORD_BUDGET, 4.0 * COORD_BUDGET)
        };
        IntPoint::new(q(p.x) as i32, q(p.y) as i32)
    }

    /// The point of lattice coordinates.
    pub fn to_point(&self, p: IntPoint<i32>) -> Point {
        Point::new(p.x as f64 / self.scale, p.y as f64 / self.scale)
    }

    /// A distance in lattice units, rounded.
    pub fn to_int_len(&self, d: f64) -> i32 {
        (d * self.scale)
            .round()
            .clamp(-2.0 * COORD_BUDGET, 2.0 * COORD_BUDGET) as i32
    }
}

/// A polygon with holes: one outer ring with positive signed area, then holes with negative
/// signed area (the orientation i_overlay produces). Rings are implicitly closed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polygon {
    /// The outer boundary.
    pub outer: Vec<Point>,
    /// The holes.
    pub holes: Vec<Vec<Point>>,
}

/// A region: zero or more disjoint polygons with holes. A tangle shape's boundary Θ.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Region {
    /// The polygons.
    pub polygons: Vec<Polygon>,
}

/// The x coordinates where the horizontal line at height `y` crosses `edges`, sorted, into
/// `xs` (cleared first, so one buffer serves every scanline). Consecutive pairs bound the
/// spans inside; an edge counts when exactly one end lies above `y`.
pub(crate) fn scanline_crossings(
    edges: impl Iterator<Item = (Point, Point)>,
    y: f64,
    xs: &mut Vec<f64>,
) {
    xs.clear();
    for (a, b) in edges {
        if (a.y > y) != (b.y > y) {
            xs.push(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
        }
    }
    xs.sort_by(f64::total_cmp);
}

/// Signed area of a closed ring (positive when counter-clockwise with y up).
pub fn ring_area(ring: &[Point]) -> f64 {
    let n = ring.len();
    if n < 3 {
        return 0.0;
    }
    let mut a = 0.0;
    for i in 0..n {
        let (p, q) = (ring[i], ring[(i + 1) % n]);
        a += p.x * q.y - q.x * p.y;
    }
    0.5 * a
}

/// Whether `p` is inside a ring by the even-odd crossing rule.
fn ring_crossings(ring: &[Point], p: Point) -> bool {
    let mut inside = false;
    let n = ring.len();
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (ring[i], ring[j]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Distance from `p` to segment `ab`.
pub fn segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let len2 = ab.hypot2();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).hypot()
}

impl Polygon {
    /// All rings, outer first.
    pub fn rings(&self) -> impl Iterator<Item = &Vec<Point>> {
        std::iter::once(&self.outer).chain(self.holes.iter())
    }

    /// Area (outer minus holes), as signed ring areas sum.
    pub fn area(&self) -> f64 {
        self.rings().map(|r| ring_area(r)).sum()
    }

    /// Area centroid; the vertex mean for degenerate (zero-area) polygons.
    pub fn centroid(&self) -> Point {
        let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
        for r in self.rings() {
            let n = r.len();
            for i in 0..n {
                let (p, q) = (r[i], r[(i + 1) % n]);
                let c = p.x * q.y - q.x * p.y;
                a += c;
                cx += (p.x + q.x) * c;
                cy += (p.y + q.y) * c;
            }
        }
        if a.abs() > 1e-12 {
            Point::new(cx / (3.0 * a), cy / (3.0 * a))
        } else {
            let n = self.outer.len().max(1) as f64;
            let s = self.outer.iter().fold(Vec2::ZERO, |s, p| s + p.to_vec2());
            (s / n).to_point()
        }
    }

    /// Bounding box of the outer ring.
    pub fn bbox(&self) -> Rect {
        bbox_of(self.outer.iter().copied())
    }

    /// Whether `p` is inside (even-odd over all rings, which for a valid polygon is the
    /// interior minus the holes).
    pub fn contains(&self, p: Point) -> bool {
        self.rings().filter(|r| ring_crossings(r, p)).count() % 2 == 1
    }

    /// Total boundary length.
    pub fn perimeter(&self) -> f64 {
        self.edges().map(|(a, b)| (b - a).hypot()).sum()
    }

    /// Every boundary edge as a pair of points.
    pub fn edges(&self) -> impl Iterator<Item = (Point, Point)> + '_ {
        self.rings()
            .flat_map(|r| (0..r.len()).map(move |i| (r[i], r[(i + 1) % r.len()])))
    }

    /// Distance from `p` to the boundary.
    pub fn boundary_distance(&self, p: Point) -> f64 {
        self.edges()
            .map(|(a, b)| segment_distance(p, a, b))
            .fold(f64::INFINITY, f64::min)
    }

    /// A point strictly inside: the middle of the widest interior interval on a few
    /// horizontal scanlines (the centroid of a concave polygon can lie outside it).
    pub fn interior_point(&self) -> Option<Point> {
        let bb = self.bbox();
        if !(bb.height() > 0.0 && bb.width() > 0.0) {
            return None;
        }
        let c = self.centroid();
        let mut lines = vec![c.y];
        lines.extend((0..9).map(|k| bb.y0 + bb.height() * (k as f64 + 0.5) / 9.0));
        let mut best: Option<(f64, Point)> = None;
        let mut xs = Vec::new();
        for y in lines {
            // Nudge off vertices so every crossing is a proper one.
            let y = if self.edges().any(|(a, _)| a.y == y) {
                y + bb.height() * 1.37e-7
            } else {
                y
            };
            scanline_crossings(self.edges(), y, &mut xs);
            for pair in xs.chunks_exact(2) {
                let w = pair[1] - pair[0];
                if best.is_none_or(|(bw, _)| w > bw) {
                    best = Some((w, Point::new(0.5 * (pair[0] + pair[1]), y)));
                }
            }
        }
        best.filter(|(w, _)| *w > 0.0).map(|(_, p)| p)
    }

    /// The polygon with every vertex mapped by `f`.
    pub fn map_points(&self, mut f: impl FnMut(Point) -> Point) -> Polygon {
        Polygon {
            outer: self.outer.iter().map(|&p| f(p)).collect(),
            holes: self
                .holes
                .iter()
                .map(|h| h.iter().map(|&p| f(p)).collect())
                .collect(),
        }
    }

    /// The polygon as a closed kurbo path (one subpath per ring).
    pub fn to_bezpath(&self) -> BezPath {
        let mut path = BezPath::new();
        for r in self.rings() {
            push_ring(&mut path, r);
        }
        path
    }
}

fn push_ring(path: &mut BezPath, ring: &[Point]) {
    let Some((first, rest)) = ring.split_first() else {
        return;
    };
    path.move_to(*first);
    for p in rest {
        path.line_to(*p);
    }
    path.close_path();
}

/// Bounding box of points (`Rect::ZERO` if there are none).
pub fn bbox_of(points: impl Iterator<Item = Point>) -> Rect {
    let mut r: Option<Rect> = None;
    for p in points {
        r = Some(match r {
            None => Rect::from_points(p, p),
            Some(r) => r.union_pt(p),
        });
    }
    r.unwrap_or(Rect::ZERO)
}

impl Region {
    /// A region of one polygon.
    pub fn from_polygon(p: Polygon) -> Region {
        Region { polygons: vec![p] }
    }

    /// The rectangle `r` as a region of one polygon without holes, its outer ring starting
    /// at `(x0, y0)` with positive signed area as outer rings have.
    pub fn from_rect(r: Rect) -> Region {
        Region::from_polygon(Polygon {
            outer: vec![
                Point::new(r.x0, r.y0),
                Point::new(r.x1, r.y0),
                Point::new(r.x1, r.y1),
                Point::new(r.x0, r.y1),
            ],
            holes: vec![],
        })
    }

    /// Whether the region has no polygons.
    pub fn is_empty(&self) -> bool {
        self.polygons.is_empty()
    }

    /// Total area.
    pub fn area(&self) -> f64 {
        self.polygons.iter().map(Polygon::area).sum()
    }

    /// Area centroid (vertex mean when the area is zero).
    pub fn centroid(&self) -> Point {
        let total = self.area();
        if total.abs() <= 1e-12 {
            return self.polygons.first().map_or(Point::ZERO, Polygon::centroid);
        }
        let s = self
            .polygons
            .iter()
            .fold(Vec2::ZERO, |s, p| s + p.centroid().to_vec2() * p.area());
        (s / total).to_point()
    }

    /// Bounding box.
    pub fn bbox(&self) -> Rect {
        bbox_of(self.polygons.iter().flat_map(|p| p.outer.iter().copied()))
    }

    /// Whether `p` is inside.
    pub fn contains(&self, p: Point) -> bool {
        self.polygons.iter().any(|poly| poly.contains(p))
    }

    /// Every boundary edge.
    pub fn edges(&self) -> impl Iterator<Item = (Point, Point)> + '_ {
        self.polygons.iter().flat_map(Polygon::edges)
    }

    /// Total boundary length.
    pub fn perimeter(&self) -> f64 {
        self.polygons.iter().map(Polygon::perimeter).sum()
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.polygons
            .iter()
            .flat_map(|p| p.rings())
            .map(Vec::len)
            .sum()
    }

    /// Distance from `p` to the boundary.
    pub fn boundary_distance(&self, p: Point) -> f64 {
        self.polygons
            .iter()
            .map(|poly| poly.boundary_distance(p))
            .fold(f64::INFINITY, f64::min)
    }

    /// A point strictly inside the largest polygon.
    pub fn interior_point(&self) -> Option<Point> {
        self.polygons
            .iter()
            .max_by(|a, b| a.area().total_cmp(&b.area()))?
            .interior_point()
    }

    /// The region with every vertex mapped by `f`.
    pub fn map_points(&self, mut f: impl FnMut(Point) -> Point) -> Region {
        Region {
            polygons: self.polygons.iter().map(|p| p.map_points(&mut f)).collect(),
        }
    }

    /// The region as a kurbo path (one closed subpath per ring; fill with either rule).
    pub fn to_bezpath(&self) -> BezPath {
        let mut path = BezPath::new();
        for p in &self.polygons {
            for r in p.rings() {
                push_ring(&mut path, r);
            }
        }
        path
    }

    /// The region in the engine's integer form.
    pub fn to_int(&self, grid: &Grid) -> IntShapes<i32> {
        self.polygons
            .iter()
            .map(|p| {
                p.rings()
                    .map(|r| r.iter().map(|&q| grid.to_int(q)).collect())
                    .collect()
            })
            .collect()
    }

    /// A region from the engine's integer shapes (outer ring first in each).
    pub fn from_int(shapes: &[IntShape<i32>], grid: &Grid) -> Region {
        let ring = |c: &Vec<IntPoint<i32>>| c.iter().map(|&q| grid.to_point(q)).collect();
        Region {
            polygons: shapes
                .iter()
                .filter_map(|s| {
                    let (outer, holes) = s.split_first()?;
                    Some(Polygon {
                        outer: ring(outer),
                        holes: holes.iter().map(ring).collect(),
                    })
                })
                .collect(),
        }
    }
}

/// The closed rings of a path after `transform`, flattened to within `tolerance` and snapped
/// to `grid`. Open subpaths are closed, as a fill would close them.
pub fn flatten_rings(
    path: &BezPath,
    transform: Affine,
    tolerance: f64,
    grid: &Grid,
) -> Vec<Vec<Point>> {
    let mut rings: Vec<Vec<Point>> = Vec::new();
    let mut current: Vec<Point> = Vec::new();
    let finish = |current: &mut Vec<Point>, rings: &mut Vec<Vec<Point>>| {
        current.dedup();
        if current.len() > 1 && current.first() == current.last() {
            current.pop();
        }
        if current.len() >= 3 {
            rings.push(std::mem::take(current));
        }
        current.clear();
    };
    kurbo::flatten(
        transform * path.clone(),
        tolerance.max(1e-6),
        |el| match el {
            PathEl::MoveTo(p) => {
                finish(&mut current, &mut rings);
                current.push(grid.snap(p));
            }
            PathEl::LineTo(p) => current.push(grid.snap(p)),
            PathEl::ClosePath => finish(&mut current, &mut rings),
            // `flatten` only emits lines.
            PathEl::QuadTo(..) | PathEl::CurveTo(..) => {}
        },
    );
    finish(&mut current, &mut rings);
    rings
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, s: f64) -> Vec<Point> {
        vec![
            Point::new(x, y),
            Point::new(x + s, y),
            Point::new(x + s, y + s),
            Point::new(x, y + s),
        ]
    }

    #[test]
    fn grid_round_trips_and_fits_budget() {
        let g = Grid::for_bounds(Rect::new(0.0, 0.0, 1000.0, 800.0)).unwrap();
        let p = g.snap(Point::new(123.456789, -7.25));
        assert_eq!(g.snap(p), p);
        assert_eq!(g.to_point(g.to_int(p)), p);
        assert!((p.x - 123.456789).abs() <= g.quantum());
        assert!(g.holds(Point::new(2000.0, 2000.0)));
        assert!(Grid::for_bounds(Rect::new(0.0, 0.0, f64::INFINITY, 1.0)).is_none());
    }

    #[test]
    fn polygon_measures() {
        let mut hole = square(2.0, 2.0, 2.0);
        hole.reverse();
        let p = Polygon {
            outer: square(0.0, 0.0, 6.0),
            holes: vec![hole],
        };
        assert!((p.area() - 32.0).abs() < 1e-12);
        assert!((p.perimeter() - 32.0).abs() < 1e-12);
        assert!(p.contains(Point::new(1.0, 1.0)));
        assert!(!p.contains(Point::new(3.0, 3.0)));
        let c = p.centroid();
        assert!((c - Point::new(3.0, 3.0)).hypot() < 1e-9);
        let ip = p.interior_point().unwrap();
        assert!(p.contains(ip), "{ip:?}");
        assert!((p.boundary_distance(Point::new(1.0, 3.0)) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn interior_point_of_concave_polygon_is_inside() {
        // A C shape whose centroid lies in the notch.
        let outer = vec![
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 2.0),
            Point::new(2.0, 2.0),
            Point::new(2.0, 8.0),
            Point::new(10.0, 8.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
        ];
        let p = Polygon {
            outer,
            holes: vec![],
        };
        assert!(!p.contains(p.centroid()));
        assert!(p.contains(p.interior_point().unwrap()));
    }

    #[test]
    fn flattening_closes_and_transforms() {
        let g = Grid::for_bounds(Rect::new(0.0, 0.0, 100.0, 100.0)).unwrap();
        let path = BezPath::from_svg("M0 0 L10 0 L10 10 M20 20 Q 30 20 30 30 Z").unwrap();
        let rings = flatten_rings(&path, Affine::translate((5.0, 0.0)), 0.1, &g);
        assert_eq!(rings.len(), 2);
        assert_eq!(rings[0][0], Point::new(5.0, 0.0));
        assert!(rings[1].len() > 3);
    }
}
