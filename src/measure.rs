//! Measurements of scene geometry in canvas coordinates: bounds, the area centroid of the
//! filled geometry and the representative paint that [`Shape`](crate::scene::Shape) records.
//!
//! The centroid is the centroid of what is actually painted: each path's interior follows
//! its fill rule (an even-odd star has a hole, a non-zero one does not) and overlapping
//! paths of one unit count once. Curves are flattened only here, to a tolerance of 1/400
//! of each path's size (the centroid moves by far less), and resolved with `i_overlay`.
//!
//! Importers measure every unit they make with it, and so does [`SceneBuilder`](crate::scene::SceneBuilder),
//! so a scene built in code has exactly the shapes an imported one would.

use i_overlay::core::fill_rule::FillRule as OverlayRule;
use i_overlay::float::simplify::SimplifyShape;
use kurbo::{Affine, BezPath, PathEl, Point, Rect, Shape as _};

use crate::color::Color;
use crate::scene::{FillRule, Node, Paint};

/// What [`measure`] finds out about a node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measure {
    /// Area centroid of the filled geometry; the bounding-box centre when nothing is
    /// filled or the filled area is degenerate.
    pub centroid: Point,
    /// Bounding box of the geometry (without stroke widths).
    pub bbox: Rect,
    /// First solid fill colour, its alpha the fill opacity; black if none.
    pub fill: Color,
    /// First solid stroke colour, its alpha the stroke opacity; black if none.
    pub stroke: Color,
    /// Width of the first stroke in its path's own units; 1 if none.
    pub stroke_width: f64,
}

/// Measures a node placed by `parent_transform` (its parent's coordinates to the canvas).
/// Returns `None` when the node holds no path geometry.
pub fn measure(node: &Node, parent_transform: Affine) -> Option<Measure> {
    let mut acc = Accumulator::default();
    acc.visit(node, parent_transform);
    acc.finish()
}

#[derive(Default)]
struct Accumulator {
    bbox: Option<Rect>,
    /// Filled regions of every path, each already resolved by its own fill rule, so they
    /// are consistently oriented and a non-zero union merges them.
    filled: Vec<Vec<[f64; 2]>>,
    /// How many paths contributed to `filled` (one needs no union).
    filled_paths: usize,
    fill: Option<Color>,
    stroke: Option<Color>,
    stroke_width: Option<f64>,
}

impl Accumulator {
    fn visit(&mut self, node: &Node, ts: Affine) {
        match node {
            Node::Group(g) => {
                let ts = ts * g.transform;
                for child in &g.children {
                    self.visit(child, ts);
                }
            }
            Node::Path(p) => {
                let mut path = p.path.clone();
                path.apply_affine(ts);
                let Some(bounds) = path_bounds(&path) else {
                    return;
                };
                self.bbox = Some(self.bbox.map_or(bounds, |b| b.union(bounds)));
                if let Some(fill) = &p.fill {
                    if let Paint::Solid(c) = fill.paint {
                        self.fill.get_or_insert(Color {
                            a: fill.opacity,
                            ..c
                        });
                    }
                    self.add_filled(&path, bounds, fill.rule);
                }
                if let Some(stroke) = &p.stroke {
                    if let Paint::Solid(c) = stroke.paint {
                        self.stroke.get_or_insert(Color {
                            a: stroke.opacity,
                            ..c
                        });
                    }
                    self.stroke_width.get_or_insert(stroke.width);
                }
            }
            // An image counts as its rectangle, filled: it paints every pixel of it.
            Node::Image(i) => {
                let path = ts * i.rect().to_path(0.1);
                if let Some(bounds) = path_bounds(&path) {
                    self.bbox = Some(self.bbox.map_or(bounds, |b| b.union(bounds)));
                    self.add_filled(&path, bounds, FillRule::NonZero);
                }
            }
        }
    }

    fn add_filled(&mut self, path: &BezPath, bounds: Rect, rule: FillRule) {
        let tolerance = (bounds.width().max(bounds.height()) * 2.5e-3).max(1e-9);
        let mut contours: Vec<Vec<[f64; 2]>> = Vec::new();
        kurbo::flatten(path, tolerance, |el| match el {
            PathEl::MoveTo(p) => contours.push(vec![[p.x, p.y]]),
            PathEl::LineTo(p) => match contours.last_mut() {
                Some(c) => c.push([p.x, p.y]),
                None => contours.push(vec![[p.x, p.y]]),
            },
            // Flattening yields only moves, lines and closes.
            _ => {}
        });
        for c in &mut contours {
            thin_out(c);
        }
        contours.retain(|c| c.len() >= 3);
        if contours.is_empty() {
            return;
        }
        self.filled_paths += 1;
        if too_many_to_resolve(&contours) {
            // Taken as drawn, oriented as i_overlay orients what it resolves (outer
            // contours of positive area), so they add up with resolved paths' contours.
            if signed_area2(&contours) < 0.0 {
                contours.iter_mut().for_each(|c| c.reverse());
            }
            self.filled.extend(contours);
            return;
        }
        let rule = match rule {
            FillRule::NonZero => OverlayRule::NonZero,
            FillRule::EvenOdd => OverlayRule::EvenOdd,
        };
        for shape in contours.simplify_shape(rule) {
            self.filled.extend(shape.into_iter().filter(|c| !sliver(c)));
        }
    }

    fn finish(self) -> Option<Measure> {
        let bbox = self.bbox?;
        let centroid = match self.filled_paths {
            0 => None,
            1 => area_centroid(std::slice::from_ref(&self.filled), bbox),
            _ if too_many_to_resolve(&self.filled) => {
                area_centroid(std::slice::from_ref(&self.filled), bbox)
            }
            _ => area_centroid(&self.filled.simplify_shape(OverlayRule::NonZero), bbox),
        };
        Some(Measure {
            centroid: centroid.unwrap_or_else(|| bbox.center()),
            bbox,
            fill: self.fill.unwrap_or(Color::BLACK),
            stroke: self.stroke.unwrap_or(Color::BLACK),
            stroke_width: self.stroke_width.unwrap_or(1.0),
        })
    }
}

/// The most points of one flattened contour the measure resolves: past it, every k-th
/// point is kept. Resolving a contour's fill costs with its self-crossings, which grow
/// with the square of its points on a spiky outline (a circle of 5000 vertices with
/// zig-zags of 40 ridges, 200 000 points, took 10 s); the centroid of a contour that
/// detailed moves by next to nothing when it is thinned out evenly.
const MAX_CONTOUR_POINTS: usize = 4096;

/// The most contours, and the most points in all, that the measure resolves together.
/// Resolving them costs with their crossings, which grow with the square of the contours
/// where they overlap: text set along a `<textPath>` folded back and forth on itself (300
/// glyphs turned every way, on top of one another) took 44 s, found probing text after
/// the `svg` fuzz target's slow texts. Past either bound the contours are taken as drawn,
/// their signed areas summed: exact where they do not overlap, as a text's glyphs usually
/// do not, and overlaps counted once per contour where they do.
const MAX_RESOLVED_CONTOURS: usize = 128;
const MAX_RESOLVED_POINTS: usize = 4 * MAX_CONTOUR_POINTS;

fn too_many_to_resolve(contours: &[Vec<[f64; 2]>]) -> bool {
    contours.len() > MAX_RESOLVED_CONTOURS
        || contours.iter().map(Vec::len).sum::<usize>() > MAX_RESOLVED_POINTS
}

/// Twice the signed area of `contours` (positive counter-clockwise in y-up axes).
fn signed_area2(contours: &[Vec<[f64; 2]>]) -> f64 {
    contours.iter().map(|c| contour_area2(c)).sum()
}

/// Twice the signed area of one closed contour (the shoelace sum).
fn contour_area2(contour: &[[f64; 2]]) -> f64 {
    let n = contour.len();
    (0..n)
        .map(|i| {
            let (p, q) = (contour[i], contour[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum()
}

/// Keeps every k-th point of `contour` so that at most [`MAX_CONTOUR_POINTS`] remain.
fn thin_out(contour: &mut Vec<[f64; 2]>) {
    if contour.len() <= MAX_CONTOUR_POINTS {
        return;
    }
    let stride = contour.len().div_ceil(MAX_CONTOUR_POINTS);
    let mut k = 0;
    contour.retain(|_| {
        k += 1;
        (k - 1) % stride == 0
    });
}

/// Whether a simple contour encloses next to nothing for its length (area below 10⁻⁷ of
/// its perimeter squared: thinner than 1 : 10⁷). Such slivers move no centroid, and
/// i_overlay's union of a few of them can shatter into tens of thousands of pieces and
/// take seconds (found by the `lottie` fuzz target: thin rotated fills of a precomposition).
fn sliver(contour: &[[f64; 2]]) -> bool {
    let n = contour.len();
    let perimeter: f64 = (0..n)
        .map(|i| {
            let (p, q) = (contour[i], contour[(i + 1) % n]);
            (q[0] - p[0]).hypot(q[1] - p[1])
        })
        .sum();
    (contour_area2(contour) / 2.0).abs() <= 1e-7 * perimeter * perimeter
}

/// The exact bounds of a path, `None` for a path with no points.
fn path_bounds(path: &BezPath) -> Option<Rect> {
    if path.elements().is_empty() {
        return None;
    }
    let b = path.bounding_box();
    b.is_finite().then_some(b)
}

/// Centroid of oriented polygons (holes run opposite to outlines); `None` when the area is
/// negligible against the bounding box, where the division would only amplify noise.
fn area_centroid(shapes: &[Vec<Vec<[f64; 2]>>], bbox: Rect) -> Option<Point> {
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    // Coordinates relative to the box centre keep the cross products well conditioned.
    let o = bbox.center();
    for contour in shapes.iter().flatten() {
        for (i, p) in contour.iter().enumerate() {
            let q = contour[(i + 1) % contour.len()];
            let (x0, y0, x1, y1) = (p[0] - o.x, p[1] - o.y, q[0] - o.x, q[1] - o.y);
            let cross = x0 * y1 - x1 * y0;
            a2 += cross;
            cx += (x0 + x1) * cross;
            cy += (y0 + y1) * cross;
        }
    }
    let scale = bbox.area().abs().max(f64::MIN_POSITIVE);
    if (a2 * 0.5).abs() <= scale * 1e-9 {
        return None;
    }
    Some(Point::new(o.x + cx / (3.0 * a2), o.y + cy / (3.0 * a2)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Fill, Group, PathNode};
    use kurbo::{Circle, Shape, Vec2};

    fn filled(path: BezPath, rule: FillRule) -> Node {
        Node::Path(PathNode {
            id: String::new(),
            path,
            fill: Some(Fill {
                paint: Paint::Solid(Color::rgb(1.0, 0.0, 0.0)),
                opacity: 0.5,
                rule,
            }),
            stroke: None,
            stroke_first: false,
            unit: None,
        })
    }

    fn close(a: Point, b: Point) -> bool {
        a.distance(b) < 1e-3
    }

    #[test]
    fn rectangle_centroid_follows_transform() {
        let node = filled(
            Rect::new(0.0, 0.0, 10.0, 20.0).to_path(0.1),
            FillRule::NonZero,
        );
        let m = measure(&node, Affine::translate((100.0, 0.0)) * Affine::scale(2.0)).unwrap();
        assert!(
            close(m.centroid, Point::new(110.0, 20.0)),
            "{:?}",
            m.centroid
        );
        assert_eq!(m.bbox, Rect::new(100.0, 0.0, 120.0, 40.0));
        assert_eq!(m.fill.a, 0.5);
    }

    #[test]
    fn even_odd_hole_shifts_the_centroid() {
        // A 10x10 square with a 4x4 hole on its right half, both drawn the same direction.
        let mut p = Rect::new(0.0, 0.0, 10.0, 10.0).to_path(0.1);
        p.extend(Rect::new(5.0, 3.0, 9.0, 7.0).path_elements(0.1));
        let even = measure(&filled(p.clone(), FillRule::EvenOdd), Affine::IDENTITY).unwrap();
        let nonzero = measure(&filled(p, FillRule::NonZero), Affine::IDENTITY).unwrap();
        // Area 100 at x=5 minus area 16 at x=7: (500-112)/84.
        assert!(
            (even.centroid.x - 388.0 / 84.0).abs() < 1e-6,
            "{:?}",
            even.centroid
        );
        assert!(close(nonzero.centroid, Point::new(5.0, 5.0)));
    }

    #[test]
    fn overlapping_paths_count_once() {
        let big = filled(
            Rect::new(0.0, 0.0, 10.0, 10.0).to_path(0.1),
            FillRule::NonZero,
        );
        let inside = filled(
            Rect::new(6.0, 0.0, 10.0, 10.0).to_path(0.1),
            FillRule::NonZero,
        );
        let mut g = Group::new();
        g.children = vec![big, inside];
        let m = measure(&Node::Group(g), Affine::IDENTITY).unwrap();
        assert!(close(m.centroid, Point::new(5.0, 5.0)), "{:?}", m.centroid);
    }

    /// Many contours (past what is resolved together) that do not overlap, clockwise in
    /// y-up axes (the sign i_overlay's own contours do not have), each a square with an
    /// off-centre hole drawn the other way round, beside a path resolved as usual: the
    /// centroid is still the exact one of what is painted.
    #[test]
    fn many_disjoint_contours_measure_exactly() {
        let square = |x: f64, y: f64, side: f64, clockwise: bool| {
            let mut pts = [(x, y), (x, y + side), (x + side, y + side), (x + side, y)];
            if !clockwise {
                pts.reverse();
            }
            pts
        };
        let mut glyphs = BezPath::new();
        let (mut area, mut moment) = (0.0, Vec2::ZERO);
        for k in 0..150 {
            let (x, y) = (
                f64::from(k % 15) * 6.0,
                f64::from(k / 15) * 6.0 + f64::from(k % 4),
            );
            for (pts, sign) in [
                (square(x, y, 4.0, true), 1.0),
                (square(x + 2.0, y + 1.0, 1.5, false), -1.0),
            ] {
                glyphs.move_to(pts[0]);
                pts[1..].iter().for_each(|&p| glyphs.line_to(p));
                glyphs.close_path();
                let (side, corner) = (
                    (pts[0].0 - pts[2].0).abs(),
                    Vec2::new(pts[0].0.min(pts[2].0), pts[0].1.min(pts[2].1)),
                );
                area += sign * side * side;
                moment += sign * side * side * (corner + Vec2::new(side, side) / 2.0);
            }
        }
        let bar = Rect::new(-40.0, 0.0, -30.0, 100.0);
        area += bar.area();
        moment += bar.area() * bar.center().to_vec2();
        let mut g = Group::new();
        g.children = vec![
            filled(glyphs, FillRule::NonZero),
            filled(bar.to_path(0.1), FillRule::NonZero),
        ];
        let m = measure(&Node::Group(g), Affine::IDENTITY).unwrap();
        let expected = (moment / area).to_point();
        assert!(
            close(m.centroid, expected),
            "{:?} vs {expected:?}",
            m.centroid
        );
    }

    #[test]
    fn circle_centroid_is_its_centre() {
        let node = filled(
            Circle::new((30.0, 40.0), 7.0).to_path(0.01),
            FillRule::NonZero,
        );
        let m = measure(&node, Affine::IDENTITY).unwrap();
        assert!(close(m.centroid, Point::new(30.0, 40.0)));
    }

    #[test]
    fn stroke_only_uses_the_box_centre() {
        let mut line = BezPath::new();
        line.move_to((0.0, 0.0));
        line.line_to((10.0, 4.0));
        let node = Node::Path(PathNode {
            id: String::new(),
            path: line,
            fill: None,
            stroke: None,
            stroke_first: false,
            unit: None,
        });
        let m = measure(&node, Affine::IDENTITY).unwrap();
        assert_eq!(m.centroid, Point::new(5.0, 2.0));
        assert_eq!(m.stroke_width, 1.0);
    }

    #[test]
    fn slivers_count_for_nothing() {
        // Two slivers next to flat (from the lottie fuzz target's find, whose union of
        // such pieces shattered) beside a square: the centroid is the square's.
        let sliver = |pts: &[(f64, f64)]| {
            let mut p = BezPath::new();
            p.move_to(pts[0]);
            for &q in &pts[1..] {
                p.line_to(q);
            }
            p.close_path();
            filled(p, FillRule::NonZero)
        };
        let g = Node::Group(Group {
            children: vec![
                sliver(&[
                    (652.354982150232, 837.0916515159727),
                    (431.64681030574957, 454.8138833809018),
                    (524.2398193008057, 615.1896787452818),
                    (677.9532487517945, 881.4291492271543),
                ]),
                sliver(&[
                    (-142.39550630390227, -539.4565746867574),
                    (-160.46805421649992, -570.7591488444723),
                    (51.82750089824617, -203.0524609172262),
                    (1945.9889922922891, 3077.731478444346),
                    (1946.5423827952188, 3078.689985982188),
                    (263.61524351299227, 163.77467226148474),
                ]),
                filled(
                    Rect::new(0.0, 0.0, 100.0, 100.0).to_path(0.1),
                    FillRule::NonZero,
                ),
            ],
            ..Group::new()
        });
        let m = measure(&g, Affine::IDENTITY).unwrap();
        assert!(
            close(m.centroid, Point::new(50.0, 50.0)),
            "{:?}",
            m.centroid
        );
    }

    #[test]
    fn contours_of_many_points_are_thinned_out_and_keep_their_centroid() {
        // A half disc of 60 000 vertices (its centroid 4r/3π below the flat side), and
        // the thinning keeps every k-th point of a contour, in order.
        let (r, n) = (50.0, 60_000);
        let mut p = BezPath::new();
        p.move_to((100.0 - r, 100.0));
        for k in 1..n {
            let a = std::f64::consts::PI * k as f64 / n as f64;
            p.line_to((100.0 - r * a.cos(), 100.0 + r * a.sin()));
        }
        p.close_path();
        let m = measure(&filled(p, FillRule::NonZero), Affine::IDENTITY).unwrap();
        let expected = Point::new(100.0, 100.0 + 4.0 * r / (3.0 * std::f64::consts::PI));
        assert!(
            (m.centroid - expected).hypot() < 1e-3 * r,
            "{:?}",
            m.centroid
        );
        let mut c: Vec<[f64; 2]> = (0..10_000).map(|i| [i as f64, 0.0]).collect();
        thin_out(&mut c);
        assert_eq!(c.len(), 3334);
        assert!(c.iter().enumerate().all(|(i, q)| q[0] == (3 * i) as f64));
    }

    #[test]
    fn empty_group_has_no_measure() {
        assert!(measure(&Node::Group(Group::new()), Affine::IDENTITY).is_none());
    }
}
