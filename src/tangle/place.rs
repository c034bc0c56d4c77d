//! Shape placement (gTangle sec. 4.2): Poisson dart throwing, Lloyd relaxation on a
//! geodesic centroidal Voronoi diagram computed on a raster, then shrinking the placed
//! shapes until they fit inside the parent and none overlap.
//!
//! The geodesic diagram (distances measured inside the shape, by Dijkstra on the raster's
//! 8-neighbour graph) keeps sites in concave shapes from being pulled across a gap towards
//! a Euclidean centroid that lies outside; a centroid that still falls outside its own cell
//! is snapped to the nearest cell that is its own.

use std::collections::HashMap;

use kurbo::{Affine, Point, Rect, Vec2};

use super::boolean::{difference, intersect, normalize, union_all};
use super::noise::Rng;
use super::polygon::{Grid, Polygon, Region, scanline_crossings};
use crate::scene::FillRule;

/// What is placed.
#[derive(Clone, Debug, PartialEq)]
pub enum PlaceShape {
    /// A disc of diameter `size`.
    Circle,
    /// A square of side `size`, turned to the parent's orientation.
    Square,
    /// Any outline, scaled so its bounding box's longer side is `size`, centred on the
    /// box's centre and turned to the parent's orientation.
    Path(Region),
}

/// Parameters of [`place`].
#[derive(Clone, Debug, PartialEq)]
pub struct PlaceParams {
    /// What is placed.
    pub shape: PlaceShape,
    /// The placed shapes' size (diameter, side, or longer bounding side).
    pub size: f64,
    /// The desired distance between placed shapes' centres.
    pub distance: f64,
}

impl PlaceParams {
    /// `shape`s of `size`, their centres `distance` apart.
    pub fn new(shape: PlaceShape, size: f64, distance: f64) -> PlaceParams {
        PlaceParams {
            shape,
            size,
            distance,
        }
    }
}

/// The result of [`place`]: the placed shapes and what is left of the parent.
#[derive(Clone, Debug, Default)]
pub struct Placement {
    /// The parent minus the placed shapes.
    pub remainder: Region,
    /// The placed shapes: inside the parent, pairwise disjoint.
    pub placed: Vec<Region>,
}

/// Raster cells kept below this count, coarsening the raster on huge shapes.
const MAX_CELLS: f64 = 160_000.0;
/// Lloyd iterations (the Poisson start is already well spread, so few are needed).
const LLOYD_ITERATIONS: usize = 8;
/// Placed shapes shrunk below this fraction of their size are dropped.
const MIN_SCALE: f64 = 0.2;

/// A raster of the region: which cells are inside, and each cell's (chamfer) distance to
/// the outside.
struct Raster {
    origin: Point,
    h: f64,
    cols: usize,
    rows: usize,
    inside: Vec<bool>,
}

impl Raster {
    fn new(region: &Region, h: f64) -> Raster {
        let bb = region.bbox();
        let cols = (bb.width() / h).ceil().max(1.0) as usize;
        let rows = (bb.height() / h).ceil().max(1.0) as usize;
        let mut inside = vec![false; cols * rows];
        let mut xs = Vec::new();
        for r in 0..rows {
            let y = bb.y0 + (r as f64 + 0.5) * h;
            scanline_crossings(region.edges(), y, &mut xs);
            for span in xs.chunks_exact(2) {
                // Cells whose centres lie within the span.
                let c0 = ((span[0] - bb.x0) / h - 0.5).ceil().max(0.0) as usize;
                let c1 = ((span[1] - bb.x0) / h - 0.5).floor();
                if c1 < 0.0 {
                    continue;
                }
                for c in c0..=(c1 as usize).min(cols - 1) {
                    inside[r * cols + c] = true;
                }
            }
        }
        Raster {
            origin: bb.origin(),
            h,
            cols,
            rows,
            inside,
        }
    }

    fn center(&self, i: usize) -> Point {
        let (r, c) = (i / self.cols, i % self.cols);
        Point::new(
            self.origin.x + (c as f64 + 0.5) * self.h,
            self.origin.y + (r as f64 + 0.5) * self.h,
        )
    }

    fn cell_of(&self, p: Point) -> Option<usize> {
        let c = ((p.x - self.origin.x) / self.h).floor();
        let r = ((p.y - self.origin.y) / self.h).floor();
        if c < 0.0 || r < 0.0 || c >= self.cols as f64 || r >= self.rows as f64 {
            return None;
        }
        Some(r as usize * self.cols + c as usize)
    }

    /// Inside neighbours of cell `i` with their step cost in fifths of a cell (5 across, 7
    /// diagonally: the 5-7 chamfer, within 1% of √2).
    fn neighbours(&self, i: usize) -> impl Iterator<Item = (usize, u32)> + '_ {
        let (r, c) = ((i / self.cols) as isize, (i % self.cols) as isize);
        const D: [(isize, isize, u32); 8] = [
            (-1, 0, 5),
            (1, 0, 5),
            (0, -1, 5),
            (0, 1, 5),
            (-1, -1, 7),
            (-1, 1, 7),
            (1, -1, 7),
            (1, 1, 7),
        ];
        D.iter().filter_map(move |&(dr, dc, w)| {
            let (rr, cc) = (r + dr, c + dc);
            if rr < 0 || cc < 0 || rr >= self.rows as isize || cc >= self.cols as isize {
                return None;
            }
            let j = rr as usize * self.cols + cc as usize;
            self.inside[j].then_some((j, w))
        })
    }

    /// Distance of every inside cell to the nearest outside cell (or raster edge), along
    /// the 8-neighbour graph (within ~8% of Euclidean).
    fn depth(&self) -> Vec<f64> {
        let border: Vec<(usize, u32)> = (0..self.inside.len())
            .filter(|&i| {
                let (r, c) = (i / self.cols, i % self.cols);
                let on_edge = r == 0 || c == 0 || r + 1 == self.rows || c + 1 == self.cols;
                self.inside[i] && (on_edge || self.neighbours(i).count() < 8)
            })
            .map(|i| (i, 0))
            .collect();
        let (dist, _) = propagate(self, &border);
        dist.iter()
            .map(|&d| {
                if d == u32::MAX {
                    f64::INFINITY
                } else {
                    (d as f64 / 5.0 + 0.5) * self.h
                }
            })
            .collect()
    }
}

/// Multi-source shortest paths over the raster's inside cells from `(cell, label)` seeds:
/// each cell's distance (in fifths of a cell) and the label of its nearest seed — a
/// geodesic Voronoi diagram. Dial's bucket queue makes it linear in the cells.
fn propagate(raster: &Raster, seeds: &[(usize, u32)]) -> (Vec<u32>, Vec<u32>) {
    let n = raster.inside.len();
    let mut dist = vec![u32::MAX; n];
    let mut label = vec![u32::MAX; n];
    // Steps cost at most 7, so pending distances span at most 8 consecutive values.
    let mut buckets: [Vec<usize>; 8] = Default::default();
    for &(c, l) in seeds {
        if dist[c] != 0 {
            dist[c] = 0;
            label[c] = l;
            buckets[0].push(c);
        }
    }
    let mut pending: usize = buckets[0].len();
    let mut d: u32 = 0;
    while pending > 0 {
        let slot = (d % 8) as usize;
        let cells = std::mem::take(&mut buckets[slot]);
        pending -= cells.len();
        for &c in &cells {
            if dist[c] != d {
                continue;
            }
            for (j, w) in raster.neighbours(c) {
                let nd = d + w;
                if nd < dist[j] {
                    dist[j] = nd;
                    label[j] = label[c];
                    buckets[(nd % 8) as usize].push(j);
                    pending += 1;
                }
            }
        }
        // Keep the emptied bucket's allocation for reuse.
        let mut cells = cells;
        cells.clear();
        if buckets[slot].is_empty() {
            buckets[slot] = cells;
        }
        d += 1;
    }
    (dist, label)
}

/// Points kept at least a minimum distance apart, with a bucket grid for the test.
pub(crate) struct DiskSet {
    min: f64,
    buckets: HashMap<(i64, i64), Vec<Point>>,
}

impl DiskSet {
    /// An empty set whose points stay `min` apart.
    pub(crate) fn new(min: f64) -> DiskSet {
        DiskSet {
            min,
            buckets: HashMap::new(),
        }
    }

    fn bucket(&self, p: Point) -> (i64, i64) {
        (
            (p.x / self.min).floor() as i64,
            (p.y / self.min).floor() as i64,
        )
    }

    /// Adds `p` if no point in the set is closer than the minimum; says whether it did.
    pub(crate) fn try_insert(&mut self, p: Point) -> bool {
        let (bx, by) = self.bucket(p);
        for y in by - 1..=by + 1 {
            for x in bx - 1..=bx + 1 {
                if self
                    .buckets
                    .get(&(x, y))
                    .is_some_and(|v| v.iter().any(|q| (*q - p).hypot() < self.min))
                {
                    return false;
                }
            }
        }
        self.buckets.entry((bx, by)).or_default().push(p);
        true
    }
}

/// Poisson dart throwing: random points in cells among `eligible`, kept when no earlier
/// site is closer than `distance`.
fn dart_throw(raster: &Raster, eligible: &[usize], distance: f64, rng: &mut Rng) -> Vec<Point> {
    let expected = eligible.len() as f64 * raster.h * raster.h / (0.7 * distance * distance);
    let attempts = ((30.0 * expected) as usize).clamp(60, 400_000);
    let mut set = DiskSet::new(distance);
    let mut sites = Vec::new();
    for _ in 0..attempts {
        let c = raster.center(eligible[rng.index(eligible.len())]);
        let p = Point::new(
            c.x + (rng.next_f64() - 0.5) * raster.h,
            c.y + (rng.next_f64() - 0.5) * raster.h,
        );
        if set.try_insert(p) {
            sites.push(p);
        }
    }
    sites
}

/// Lloyd relaxation of `sites` on the geodesic Voronoi diagram of the raster.
fn lloyd(raster: &Raster, sites: &mut [Point]) {
    for _ in 0..LLOYD_ITERATIONS {
        let seeds: Vec<(usize, u32)> = sites
            .iter()
            .enumerate()
            .filter_map(|(s, &p)| {
                let i = raster.cell_of(p).filter(|&i| raster.inside[i])?;
                Some((i, s as u32))
            })
            .collect();
        let (_, label) = propagate(raster, &seeds);
        let mut sum = vec![(Vec2::ZERO, 0usize); sites.len()];
        for (i, &l) in label.iter().enumerate() {
            if l != u32::MAX {
                sum[l as usize].0 += raster.center(i).to_vec2();
                sum[l as usize].1 += 1;
            }
        }
        let mut targets: Vec<Option<Point>> = sum
            .iter()
            .map(|&(s, k)| (k > 0).then(|| (s / k as f64).to_point()))
            .collect();
        // A centroid outside its own cell is snapped to the cell's nearest raster cell.
        let mut snap: Vec<(f64, Option<usize>)> = vec![(f64::INFINITY, None); sites.len()];
        let stray: Vec<bool> = targets
            .iter()
            .enumerate()
            .map(|(s, t)| {
                t.is_some_and(|t| {
                    raster
                        .cell_of(t)
                        .is_none_or(|i| !raster.inside[i] || label[i] != s as u32)
                })
            })
            .collect();
        if stray.iter().any(|&b| b) {
            for (i, &l) in label.iter().enumerate() {
                let s = l as usize;
                if l != u32::MAX && stray[s] {
                    let d = (raster.center(i) - targets[s].unwrap_or_default()).hypot2();
                    if d < snap[s].0 {
                        snap[s] = (d, Some(i));
                    }
                }
            }
            for (s, t) in targets.iter_mut().enumerate() {
                if stray[s] {
                    *t = snap[s].1.map(|i| raster.center(i));
                }
            }
        }
        let mut moved: f64 = 0.0;
        for (p, t) in sites.iter_mut().zip(targets) {
            if let Some(t) = t {
                moved = moved.max((t - *p).hypot());
                *p = t;
            }
        }
        if moved < 0.5 * raster.h {
            break;
        }
    }
}

/// The unit template of a placed shape, centred at the origin.
fn template(shape: &PlaceShape, size: f64, resolution: f64) -> Vec<Vec<Point>> {
    match shape {
        PlaceShape::Circle => {
            let n = ((std::f64::consts::PI * size / (0.5 * resolution).max(1e-6)).ceil() as usize)
                .clamp(12, 48);
            vec![
                (0..n)
                    .map(|k| {
                        let a = std::f64::consts::TAU * k as f64 / n as f64;
                        Point::new(0.5 * a.cos(), 0.5 * a.sin())
                    })
                    .collect(),
            ]
        }
        PlaceShape::Square => vec![vec![
            Point::new(-0.5, -0.5),
            Point::new(0.5, -0.5),
            Point::new(0.5, 0.5),
            Point::new(-0.5, 0.5),
        ]],
        PlaceShape::Path(region) => {
            let bb = region.bbox();
            let s = bb.width().max(bb.height());
            if s <= 0.0 {
                return Vec::new();
            }
            let c = bb.center();
            region
                .polygons
                .iter()
                .flat_map(|p| p.rings())
                .map(|r| r.iter().map(|&q| ((q - c) / s).to_point()).collect())
                .collect()
        }
    }
}

/// Whether two segments cross or touch.
fn segments_meet(a: Point, b: Point, c: Point, d: Point) -> bool {
    let o = |p: Point, q: Point, r: Point| (q - p).cross(r - p);
    let (d1, d2, d3, d4) = (o(c, d, a), o(c, d, b), o(a, b, c), o(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: Point, q: Point, r: Point, v: f64| {
        v == 0.0
            && r.x >= p.x.min(q.x)
            && r.x <= p.x.max(q.x)
            && r.y >= p.y.min(q.y)
            && r.y <= p.y.max(q.y)
    };
    on(c, d, a, d1) || on(c, d, b, d2) || on(a, b, c, d3) || on(a, b, d, d4)
}

fn rings_edges(rings: &[Vec<Point>]) -> impl Iterator<Item = (Point, Point)> + '_ {
    rings
        .iter()
        .flat_map(|r| (0..r.len()).map(move |i| (r[i], r[(i + 1) % r.len()])))
}

fn rings_contain(rings: &[Vec<Point>], p: Point) -> bool {
    let poly = |r: &Vec<Point>| {
        Polygon {
            outer: r.clone(),
            holes: vec![],
        }
        .contains(p)
    };
    rings.iter().filter(|r| poly(r)).count() % 2 == 1
}

/// Whether two small outlines overlap (edges meet, or one lies in the other).
fn outlines_overlap(a: &[Vec<Point>], b: &[Vec<Point>]) -> bool {
    for (p, q) in rings_edges(a) {
        for (r, s) in rings_edges(b) {
            if segments_meet(p, q, r, s) {
                return true;
            }
        }
    }
    a.first()
        .and_then(|r| r.first())
        .is_some_and(|&p| rings_contain(b, p))
        || b.first()
            .and_then(|r| r.first())
            .is_some_and(|&p| rings_contain(a, p))
}

/// A uniform grid of the parent's edges, to test placed outlines against nearby edges only.
struct EdgeIndex {
    origin: Point,
    cell: f64,
    cols: usize,
    rows: usize,
    buckets: Vec<Vec<(Point, Point)>>,
}

impl EdgeIndex {
    fn new(region: &Region, cell: f64) -> EdgeIndex {
        let bb = region.bbox();
        let cols = ((bb.width() / cell).ceil() as usize).max(1);
        let rows = ((bb.height() / cell).ceil() as usize).max(1);
        let mut idx = EdgeIndex {
            origin: bb.origin(),
            cell,
            cols,
            rows,
            buckets: vec![Vec::new(); cols * rows],
        };
        for (a, b) in region.edges() {
            let r = Rect::from_points(a, b);
            for i in idx.cells(r) {
                idx.buckets[i].push((a, b));
            }
        }
        idx
    }

    fn cells(&self, r: Rect) -> Vec<usize> {
        let q =
            |v: f64, o: f64, n: usize| (((v - o) / self.cell).floor().max(0.0) as usize).min(n - 1);
        let (c0, c1) = (
            q(r.x0, self.origin.x, self.cols),
            q(r.x1, self.origin.x, self.cols),
        );
        let (r0, r1) = (
            q(r.y0, self.origin.y, self.rows),
            q(r.y1, self.origin.y, self.rows),
        );
        (r0..=r1)
            .flat_map(|y| (c0..=c1).map(move |x| y * self.cols + x))
            .collect()
    }

    fn crosses(&self, rings: &[Vec<Point>]) -> bool {
        rings_edges(rings).any(|(p, q)| {
            self.cells(Rect::from_points(p, q)).into_iter().any(|i| {
                self.buckets[i]
                    .iter()
                    .any(|&(a, b)| segments_meet(p, q, a, b))
            })
        })
    }
}

/// At most this many pairs of sites close enough to overlap are tested: shapes much
/// larger than their distance (`place(20, 0.5)`) would otherwise test every site against
/// thousands of neighbours for minutes.
pub const MAX_NEAR_PAIRS: usize = 2_000_000;

/// Places copies of `params.shape` inside `region`, turned to `dir`, with randomness from
/// `rng`. The raster is twice as fine as `resolution` (or finer, for close placements).
/// An error when the shapes are so much larger than their distance that resolving their
/// overlaps would pass [`MAX_NEAR_PAIRS`], or when the region holds room for more than
/// `max_pieces` of them at their distance (checked before any is placed).
pub fn place(
    region: &Region,
    params: &PlaceParams,
    dir: Vec2,
    rng: &mut Rng,
    grid: &Grid,
    (resolution, max_pieces): (f64, usize),
) -> Result<Placement, String> {
    let whole = Placement {
        remainder: region.clone(),
        placed: Vec::new(),
    };
    let area = region.area();
    if !(params.size > 0.0 && params.distance > 0.0 && area > 0.0) {
        return Ok(whole);
    }
    // Sites at least `distance` apart pack at most as densely as a hexagonal lattice,
    // one per √3/2·distance² of area.
    let room = area / (0.75f64.sqrt() * params.distance * params.distance);
    if room > max_pieces as f64 {
        return Err(format!(
            "place would scatter up to {} shapes {} apart in an area of {}, more than the limit of {max_pieces} (a larger distance, or --limit pieces=N)",
            room.round(),
            params.distance,
            area.round()
        ));
    }
    let unit = template(&params.shape, params.size, resolution);
    if unit.is_empty() {
        return Ok(whole);
    }
    let bb = region.bbox();
    let h = (params.distance / 8.0)
        .min(0.5 * resolution.max(1e-6))
        .max((bb.area() / MAX_CELLS).sqrt());
    let raster = Raster::new(region, h);
    let depth = raster.depth();
    // Darts only where a full-size shape's inscribed disc fits, or the deepest cells.
    let deepest = depth
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .fold(0.0, f64::max);
    let need = (0.5 * params.size).min(deepest);
    let eligible: Vec<usize> = (0..raster.inside.len())
        .filter(|&i| raster.inside[i] && depth[i] >= need)
        .collect();
    if eligible.is_empty() {
        return Ok(whole);
    }
    let mut sites = dart_throw(&raster, &eligible, params.distance, rng);
    lloyd(&raster, &mut sites);

    let turn = Affine::rotate(dir.y.atan2(dir.x));
    let radius = unit
        .iter()
        .flatten()
        .map(|p| p.to_vec2().hypot())
        .fold(0.0, f64::max)
        * params.size;
    let clearance: Vec<f64> = sites
        .iter()
        .map(|&s| {
            if region.contains(s) {
                region.boundary_distance(s)
            } else {
                0.0
            }
        })
        .collect();
    let edges = EdgeIndex::new(region, params.size.max(h));
    let outline = |s: Point, k: f64| -> Vec<Vec<Point>> {
        let m = Affine::translate(s.to_vec2()) * turn * Affine::scale(params.size * k);
        unit.iter()
            .map(|r| r.iter().map(|&p| m * p).collect())
            .collect()
    };
    let mut scale = vec![1.0f64; sites.len()];
    let mut alive: Vec<bool> = clearance.iter().map(|&c| c > 0.0).collect();
    // Neighbours whose discs can touch, found once with the full-size radius.
    let mut near: Vec<Vec<usize>> = vec![Vec::new(); sites.len()];
    let mut by_x: Vec<usize> = (0..sites.len()).collect();
    by_x.sort_by(|&a, &b| sites[a].x.total_cmp(&sites[b].x));
    let mut pairs = 0usize;
    for (k, &i) in by_x.iter().enumerate() {
        for &j in by_x[k + 1..]
            .iter()
            .take_while(|&&j| sites[j].x - sites[i].x < 2.0 * radius)
        {
            if (sites[i] - sites[j]).hypot() < 2.0 * radius {
                near[i].push(j);
                pairs += 1;
            }
        }
        if pairs > MAX_NEAR_PAIRS {
            return Err(format!(
                "shapes of size {} placed {} apart overlap too many neighbours to resolve (more than {MAX_NEAR_PAIRS} pairs); use a distance nearer the size",
                params.size, params.distance
            ));
        }
    }
    loop {
        let mut shrink = vec![false; sites.len()];
        for i in 0..sites.len() {
            if !alive[i] {
                continue;
            }
            if clearance[i] <= radius * scale[i] {
                let o = outline(sites[i], scale[i]);
                let inside = o.iter().flatten().all(|&p| region.contains(p)) && !edges.crosses(&o);
                if !inside {
                    shrink[i] = true;
                }
            }
            for &j in &near[i] {
                if alive[j]
                    && (sites[i] - sites[j]).hypot() < radius * (scale[i] + scale[j])
                    && outlines_overlap(&outline(sites[i], scale[i]), &outline(sites[j], scale[j]))
                {
                    shrink[i] = true;
                    shrink[j] = true;
                }
            }
        }
        if !shrink.iter().any(|&s| s) {
            break;
        }
        for i in 0..sites.len() {
            if shrink[i] {
                scale[i] *= 0.85;
                if scale[i] < MIN_SCALE {
                    alive[i] = false;
                }
            }
        }
    }
    let placed: Vec<Region> = (0..sites.len())
        .filter(|&i| alive[i])
        .map(|i| {
            let r = normalize(&outline(sites[i], scale[i]), FillRule::NonZero, grid);
            // Snapping can nudge a vertex touching the boundary a quantum outside.
            if clearance[i] <= radius * scale[i] + 2.0 * grid.quantum() {
                intersect(&r, region, grid)
            } else {
                r
            }
        })
        .filter(|r| !r.is_empty())
        .collect();
    if placed.is_empty() {
        return Ok(whole);
    }
    let remainder = difference(region, &union_all(placed.iter(), grid), grid);
    Ok(Placement { remainder, placed })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tangle::noise::key;

    fn square_region(s: f64) -> Region {
        Region::from_rect(Rect::new(0.0, 0.0, s, s))
    }

    #[test]
    fn raster_and_depth() {
        let r = Raster::new(&square_region(10.0), 1.0);
        assert_eq!((r.cols, r.rows), (10, 10));
        assert!(r.inside.iter().all(|&b| b));
        let d = r.depth();
        assert!(
            d[0] < 1.0 && d[5 * 10 + 5] > 4.0 && d[5 * 10 + 5] < 5.5,
            "{}",
            d[55]
        );
    }

    #[test]
    fn places_disjoint_discs_inside() {
        let region = square_region(100.0);
        let grid = Grid::for_bounds(region.bbox()).unwrap();
        let params = PlaceParams::new(PlaceShape::Circle, 12.0, 16.0);
        let mut rng = Rng::new(key(&[1]));
        let out = place(
            &region,
            &params,
            Vec2::new(1.0, 0.0),
            &mut rng,
            &grid,
            (0.5, usize::MAX),
        )
        .unwrap();
        assert!(out.placed.len() > 15, "{}", out.placed.len());
        let total: f64 = out.placed.iter().map(Region::area).sum::<f64>() + out.remainder.area();
        assert!((total - 10_000.0).abs() < 1.0, "{total}");
    }
}
