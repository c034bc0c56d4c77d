//! Direction fields inside a shape, interpolated from boundary vectors with mean value
//! coordinates, and evenly spaced streamlines traced through them with Euler steps
//! (gTangle sec. 4.2, "streamline split").
//!
//! Mean value coordinates (Floater 2003; Hormann & Floater 2006 for arbitrary polygons with
//! holes — the interpolation gTangle cites from Meyer et al. 2002) blend the boundary
//! values smoothly into the interior and reproduce them exactly on the boundary.
//!
//! The outline and strip fields are *line* fields: a streamline has no preferred sense, and
//! on a ring the outer boundary and a hole run in opposite senses, so oriented vectors would
//! cancel half-way. Each boundary direction θ is therefore interpolated as the doubled-angle
//! vector (cos 2θ, sin 2θ) and halved back, which needs none of the paper's sign fixing; the
//! strip streamlines then cross the outline streamlines at right angles.
//!
//! The circular field is the rotation about its centre itself. The paper's boundary vectors
//! for it are exactly that rotation's values on the boundary, but interpolating them puts
//! the centre of rotation wherever the interpolant happens to vanish (as doubled angles,
//! nowhere: the centre splits into two half-turn singularities), not at the point asked for;
//! the rotation field agrees with the boundary data and turns about the right point.

use kurbo::{Point, Vec2};

use super::polygon::{Region, ring_area};

/// Which boundary directions a field is built from (gTangle's three splits).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FieldKind {
    /// Boundary tangents: streamlines run parallel to the outline, as nested rings.
    Outline,
    /// Boundary normals: streamlines run across the shape, cutting it into strips that
    /// follow its bends (a band becomes a ladder of tiles).
    Strip,
    /// Perpendiculars to the direction towards a centre: streamlines are circles around it.
    Circular(Point),
}

/// A line field inside a region.
#[derive(Clone, Debug)]
pub struct Field {
    rings: Vec<Ring>,
    /// Values are doubled-angle vectors (a line field) rather than oriented directions.
    doubled: bool,
    /// The centre of a rotation field (no boundary data needed).
    center: Option<Point>,
}

#[derive(Clone, Debug)]
struct Ring {
    points: Vec<Point>,
    /// Doubled-angle unit vectors of the boundary directions.
    values: Vec<Vec2>,
}

/// The boundary is resampled so no edge is longer than the perimeter over this: enough for
/// smooth interpolation of varying data, bounded so one evaluation stays cheap.
const SAMPLES: f64 = 256.0;

fn doubled(v: Vec2) -> Vec2 {
    let a = 2.0 * v.y.atan2(v.x);
    Vec2::new(a.cos(), a.sin())
}

fn resample(ring: &[Point], max_len: f64) -> Vec<Point> {
    let mut out = Vec::with_capacity(ring.len());
    for i in 0..ring.len() {
        let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
        let n = ((b - a).hypot() / max_len).ceil().max(1.0) as usize;
        out.extend((0..n).map(|k| a.lerp(b, k as f64 / n as f64)));
    }
    out
}

impl Field {
    /// The field of `kind` inside `region`.
    pub fn new(region: &Region, kind: FieldKind) -> Field {
        let across = match kind {
            FieldKind::Circular(c) => {
                return Field {
                    rings: Vec::new(),
                    doubled: false,
                    center: Some(c),
                };
            }
            FieldKind::Outline => false,
            FieldKind::Strip => true,
        };
        let max_len = (region.perimeter() / SAMPLES).max(1e-9);
        let mut rings = Vec::new();
        for poly in &region.polygons {
            for r in poly.rings() {
                if r.len() < 3 || ring_area(r) == 0.0 {
                    continue;
                }
                let points = resample(r, max_len);
                let n = points.len();
                let values = (0..n)
                    .map(|i| {
                        // The tangent (central difference), or the normal for strips.
                        let t = points[(i + 1) % n] - points[(i + n - 1) % n];
                        let dir = if across { Vec2::new(-t.y, t.x) } else { t };
                        if dir.hypot2() > 0.0 {
                            doubled(dir)
                        } else {
                            Vec2::ZERO
                        }
                    })
                    .collect();
                rings.push(Ring { points, values });
            }
        }
        Field {
            rings,
            doubled: true,
            center: None,
        }
    }

    /// The unit line direction at `p` (either sense), or `None` near a singularity where the
    /// boundary data cancel.
    pub fn at(&self, p: Point) -> Option<Vec2> {
        self.direction(self.value_at(p)?, false)
    }

    /// The unit direction an interpolated value stands for (turned a right angle for
    /// `across`); `None` when the value is too short to tell (near a singularity).
    fn direction(&self, u: Vec2, across: bool) -> Option<Vec2> {
        if u.hypot() < 1e-3 {
            return None;
        }
        if self.doubled {
            let a = 0.5 * u.y.atan2(u.x)
                + if across {
                    std::f64::consts::FRAC_PI_2
                } else {
                    0.0
                };
            Some(Vec2::new(a.cos(), a.sin()))
        } else {
            let v = u.normalize();
            Some(if across { Vec2::new(-v.y, v.x) } else { v })
        }
    }

    /// The interpolated boundary value at `p` (`None` only where the weights vanish).
    fn value_at(&self, p: Point) -> Option<Vec2> {
        if let Some(c) = self.center {
            let r = c - p;
            return (r.hypot() > 1e-9).then(|| Vec2::new(-r.y, r.x) / r.hypot());
        }
        let mut num = Vec2::ZERO;
        let mut den = 0.0;
        for ring in &self.rings {
            let (pts, vals) = (&ring.points, &ring.values);
            let n = pts.len();
            // tan(α/2) of the edge a → b, α the signed angle it subtends at p; or, when p
            // lies on the vertex a or on the edge, the value there.
            let tan = |i: usize, j: usize| -> Result<(f64, f64), Vec2> {
                let (di, dj) = (pts[i] - p, pts[j] - p);
                let (ri, rj) = (di.hypot(), dj.hypot());
                if ri < 1e-9 {
                    return Err(vals[i]);
                }
                let denom = ri * rj + di.dot(dj);
                if denom <= 1e-12 * ri * rj && rj >= 1e-9 {
                    return Err(vals[i].lerp(vals[j], ri / (ri + rj)));
                }
                Ok((di.cross(dj) / denom, ri))
            };
            let mut prev = match tan(n - 1, 0) {
                Ok((t, _)) => t,
                Err(v) => return Some(v),
            };
            for (i, &v) in vals.iter().enumerate() {
                let (t, r) = match tan(i, (i + 1) % n) {
                    Ok(x) => x,
                    Err(v) => return Some(v),
                };
                let w = (prev + t) / r;
                num += v * w;
                den += w;
                prev = t;
            }
        }
        (den.abs() > 1e-300).then(|| num / den)
    }
}

/// A field sampled lazily on a grid and interpolated bilinearly (in the space of its
/// values, where interpolation is meaningful): tracing asks for thousands of nearby
/// directions, and each exact evaluation costs a pass over the whole boundary.
struct Sampler<'a> {
    field: &'a Field,
    origin: Point,
    cell: f64,
    cols: usize,
    rows: usize,
    /// Field values at grid nodes; NaN until computed.
    cache: Vec<Vec2>,
    /// Sample the perpendicular field instead.
    across: bool,
    region: &'a Region,
    /// Per grid cell: whether the boundary passes near it.
    edgy: Vec<bool>,
    /// Per grid cell: 0 unknown, 1 inside, 2 outside (for cells the boundary misses).
    inside: Vec<u8>,
}

/// Grid nodes are capped per shape; beyond that the grid coarsens.
const MAX_NODES: f64 = 250_000.0;

impl<'a> Sampler<'a> {
    fn new(field: &'a Field, region: &'a Region, cell: f64) -> Sampler<'a> {
        let bb = region.bbox().inflate(2.0 * cell, 2.0 * cell);
        let cell = cell.max((bb.area() / MAX_NODES).sqrt());
        let cols = (bb.width() / cell).ceil() as usize + 2;
        let rows = (bb.height() / cell).ceil() as usize + 2;
        let mut edgy = vec![false; cols * rows];
        for (a, b) in region.edges() {
            // Walk the edge in half cells, marking each cell met and its neighbours.
            let n = ((b - a).hypot() / (0.5 * cell)).ceil().max(1.0) as usize;
            for k in 0..=n {
                let q = a.lerp(b, k as f64 / n as f64);
                let c = ((q.x - bb.x0) / cell).floor() as isize;
                let r = ((q.y - bb.y0) / cell).floor() as isize;
                for (dc, dr) in (-1..=1).flat_map(|dc| (-1..=1).map(move |dr| (dc, dr))) {
                    let (cc, rr) = (c + dc, r + dr);
                    if cc >= 0 && rr >= 0 && (cc as usize) < cols && (rr as usize) < rows {
                        edgy[rr as usize * cols + cc as usize] = true;
                    }
                }
            }
        }
        Sampler {
            field,
            origin: bb.origin(),
            cell,
            cols,
            rows,
            cache: vec![Vec2::new(f64::NAN, f64::NAN); cols * rows],
            across: false,
            region,
            edgy,
            inside: vec![0; cols * rows],
        }
    }

    /// Whether `p` is inside the region: exact near the boundary, cached per cell elsewhere.
    fn contains(&mut self, p: Point) -> bool {
        let c = ((p.x - self.origin.x) / self.cell).floor();
        let r = ((p.y - self.origin.y) / self.cell).floor();
        if !(c >= 0.0 && r >= 0.0 && c < self.cols as f64 && r < self.rows as f64) {
            return false;
        }
        let i = r as usize * self.cols + c as usize;
        if self.edgy[i] {
            return self.region.contains(p);
        }
        if self.inside[i] == 0 {
            self.inside[i] = if self.region.contains(p) { 1 } else { 2 };
        }
        self.inside[i] == 1
    }

    fn node(&mut self, c: usize, r: usize) -> Vec2 {
        let i = r * self.cols + c;
        if self.cache[i].x.is_nan() {
            let p = self.origin + Vec2::new(c as f64, r as f64) * self.cell;
            self.cache[i] = self.field.value_at(p).unwrap_or(Vec2::ZERO);
        }
        self.cache[i]
    }

    fn at(&mut self, p: Point) -> Option<Vec2> {
        let x = (p.x - self.origin.x) / self.cell;
        let y = (p.y - self.origin.y) / self.cell;
        if !(x >= 0.0 && y >= 0.0 && x < (self.cols - 1) as f64 && y < (self.rows - 1) as f64) {
            let u = self.field.value_at(p)?;
            return self.field.direction(u, self.across);
        }
        let (c, r) = (x.floor() as usize, y.floor() as usize);
        let (fx, fy) = (x - c as f64, y - r as f64);
        let top = self.node(c, r).lerp(self.node(c + 1, r), fx);
        let bottom = self.node(c, r + 1).lerp(self.node(c + 1, r + 1), fx);
        self.field.direction(top.lerp(bottom, fy), self.across)
    }
}

/// How a traced streamline ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum End {
    /// It left the region; the last point is just outside.
    Exit,
    /// It came back to its seed; the last point is the seed.
    Closed,
    /// It hit a singularity or ran too long.
    Stalled,
}

/// Traces one streamline from `seed` with steps of `step`, starting in the sense of
/// `initial`, keeping each step's sense consistent with the previous one. With
/// `close = Some(snap)`, a streamline that comes back across the line through the seed
/// perpendicular to its start, within `snap` of the seed, is closed there.
fn trace(
    field: &mut Sampler,
    seed: Point,
    initial: Vec2,
    step: f64,
    max_len: f64,
    close: Option<f64>,
) -> (Vec<Point>, End) {
    let oriented = |v: Vec2, along: Vec2| if v.dot(along) < 0.0 { -v } else { v };
    let mut pts = vec![seed];
    let mut p = seed;
    let mut prev = initial;
    let normal = Vec2::new(-initial.y, initial.x);
    let mut travelled = 0.0;
    while travelled < max_len {
        // The improved Euler (midpoint) step: plain Euler drifts outwards by about πh per
        // turn of a circle, which keeps loops from closing.
        let Some(v0) = field.at(p) else {
            return (pts, End::Stalled);
        };
        let v0 = oriented(v0, prev);
        let Some(v) = field.at(p + v0 * (0.5 * step)) else {
            return (pts, End::Stalled);
        };
        let v = oriented(v, v0);
        let q = p + v * step;
        travelled += step;
        if !field.contains(q) {
            pts.push(q);
            return (pts, End::Exit);
        }
        if let Some(snap) = close
            && travelled > 4.0 * step
        {
            let (sp, sq) = ((p - seed).dot(initial), (q - seed).dot(initial));
            if sp < 0.0 && sq >= 0.0 {
                // Crossing the seed's line: where, along it?
                let x = p.lerp(q, sp / (sp - sq));
                if (x - seed).dot(normal).abs() <= snap {
                    pts.push(seed);
                    return (pts, End::Closed);
                }
            }
        }
        pts.push(q);
        p = q;
        prev = v;
    }
    (pts, End::Stalled)
}

/// A streamline through `seed` traced both ways: a closed loop, or a curve whose two ends
/// lie just outside the region. `None` when neither happens (it stalls inside).
fn full_streamline(
    field: &mut Sampler,
    seed: Point,
    step: f64,
    snap: f64,
    max_len: f64,
) -> Option<Vec<Point>> {
    let dir = field.at(seed)?;
    let (fwd, end) = trace(field, seed, dir, step, max_len, Some(snap));
    match end {
        End::Closed => Some(fwd),
        End::Stalled => None,
        End::Exit => {
            let (mut back, end) = trace(field, seed, -dir, step, max_len, None);
            if end != End::Exit {
                return None;
            }
            back.reverse();
            back.pop();
            back.extend(fwd);
            Some(back)
        }
    }
}

/// Points every `spacing` along a polyline, starting half a spacing in.
fn along(line: &[Point], spacing: f64) -> Vec<Point> {
    let mut out = Vec::new();
    let mut next = 0.5 * spacing;
    let mut at = 0.0;
    for w in line.windows(2) {
        let len = (w[1] - w[0]).hypot();
        while next <= at + len && len > 0.0 {
            out.push(w[0].lerp(w[1], (next - at) / len));
            next += spacing;
        }
        at += len;
    }
    out
}

/// The interior point farthest from the boundary (approximately): the centre of the
/// largest inscribed circle, by a coarse search refined locally.
pub fn pole(region: &Region) -> Option<(Point, f64)> {
    let bb = region.bbox();
    let mut best: Option<(Point, f64)> = region
        .interior_point()
        .map(|p| (p, region.boundary_distance(p)));
    let n = 16;
    for i in 0..n {
        for j in 0..n {
            let p = Point::new(
                bb.x0 + bb.width() * (i as f64 + 0.5) / n as f64,
                bb.y0 + bb.height() * (j as f64 + 0.5) / n as f64,
            );
            if region.contains(p) {
                let d = region.boundary_distance(p);
                if best.is_none_or(|(_, bd)| d > bd) {
                    best = Some((p, d));
                }
            }
        }
    }
    let (mut p, mut d) = best?;
    let mut h = bb.width().max(bb.height()) / n as f64;
    while h > 1e-3 * d.max(1e-9) {
        let mut moved = false;
        for off in [
            Vec2::new(h, 0.0),
            Vec2::new(-h, 0.0),
            Vec2::new(0.0, h),
            Vec2::new(0.0, -h),
        ] {
            let q = p + off;
            if region.contains(q) {
                let dq = region.boundary_distance(q);
                if dq > d {
                    (p, d, moved) = (q, dq, true);
                }
            }
        }
        if !moved {
            h *= 0.5;
        }
    }
    Some((p, d))
}

/// Eight directions around the compass.
fn compass() -> impl Iterator<Item = Vec2> {
    (0..8).map(|k| Vec2::from_angle(std::f64::consts::FRAC_PI_4 * k as f64))
}

/// Seeds for nested rings, keyed by ring number: along rays from `centre`, the points where
/// the distance to the boundary first falls to each multiple of `spacing`.
fn depth_seeds(region: &Region, centre: Point, spacing: f64) -> Vec<(usize, Point)> {
    let reach = region.bbox().width() + region.bbox().height();
    let walk = spacing / 8.0;
    let mut out = Vec::new();
    for dir in compass() {
        let mut level = (region.boundary_distance(centre) / spacing).floor() as usize;
        let mut t = walk;
        while t < reach {
            let p = centre + dir * t;
            if !region.contains(p) {
                break;
            }
            let l = (region.boundary_distance(p) / spacing).floor() as usize;
            if l < level {
                if l >= 1 {
                    out.push((l, p));
                }
                level = l;
            }
            t += walk;
        }
    }
    out
}

/// Seeds for circles about `centre`, keyed by ring number: `spacing` apart along rays.
fn radial_seeds(region: &Region, centre: Point, spacing: f64) -> Vec<(usize, Point)> {
    let reach = {
        let bb = region.bbox();
        [
            bb.origin(),
            Point::new(bb.x1, bb.y0),
            Point::new(bb.x0, bb.y1),
            Point::new(bb.x1, bb.y1),
        ]
        .iter()
        .map(|&q| (q - centre).hypot())
        .fold(0.0, f64::max)
    };
    // Rings before the shape's nearest point cannot meet it: a centre far outside (`center=
    // (1e300, 0)`) would otherwise count rings up to it without end.
    let near = {
        let bb = region.bbox();
        let dx = (bb.x0 - centre.x).max(centre.x - bb.x1).max(0.0);
        let dy = (bb.y0 - centre.y).max(centre.y - bb.y1).max(0.0);
        dx.hypot(dy)
    };
    let first = (near / spacing).floor().max(1.0);
    let last = (reach / spacing).floor();
    // More rings than that across one shape are refused before this (streamlineSplit caps
    // lines per shape size); here it only guards against what rounding does far away.
    if (last - first).is_nan() || last - first > MAX_RINGS {
        return Vec::new();
    }
    let mut out = Vec::new();
    for dir in compass() {
        let mut k = first;
        while k <= last {
            let p = centre + dir * (k * spacing);
            if region.contains(p) {
                out.push(((k - first) as usize, p));
            }
            k += 1.0;
        }
    }
    out
}

/// The most rings [`radial_seeds`] steps through.
const MAX_RINGS: f64 = 100_000.0;

/// Evenly spaced streamlines of a field of `kind` inside `region`, `spacing` apart along
/// a seed curve, traced with steps of `step`. Each is a closed loop or a curve whose ends
/// lie just outside the region, ready to cut it.
pub fn streamlines(region: &Region, kind: FieldKind, spacing: f64, step: f64) -> Vec<Vec<Point>> {
    if !(spacing > 0.0 && step > 0.0) || region.is_empty() {
        return Vec::new();
    }
    let field = Field::new(region, kind);
    // Grid nodes a third of the spacing apart resolve the field at the scale it is cut.
    let mut sampler = Sampler::new(&field, region, spacing / 3.0);
    // A loop is closed when it comes back within a third of the spacing of its seed.
    let snap = (spacing / 3.0).max(step);
    let max_len = 2.0 * region.perimeter() + region.bbox().width() + region.bbox().height();
    let seeds: Vec<Point> = match kind {
        FieldKind::Outline | FieldKind::Circular(_) => {
            let mut keyed = match kind {
                FieldKind::Circular(c) => radial_seeds(region, c, spacing),
                _ => {
                    let Some((c, _)) = pole(region) else {
                        return Vec::new();
                    };
                    depth_seeds(region, c, spacing)
                }
            };
            // Ring by ring, so a ring's seeds on other rays find it already traced.
            keyed.sort_by_key(|&(k, _)| k);
            keyed.into_iter().map(|(_, p)| p).collect()
        }
        FieldKind::Strip => {
            // The seed curve runs along the strips, across the streamlines: a streamline of
            // the perpendicular field through the shape's middle.
            let Some((c, _)) = pole(region) else {
                return Vec::new();
            };
            sampler.across = true;
            let Some(dir) = sampler.at(c) else {
                return Vec::new();
            };
            let (fwd, end) = trace(&mut sampler, c, dir, step, max_len, Some(snap));
            let curve = if end == End::Closed {
                fwd
            } else {
                let (mut back, _) = trace(&mut sampler, c, -dir, step, max_len, None);
                back.reverse();
                back.pop();
                back.extend(fwd);
                back
            };
            sampler.across = false;
            along(&curve, spacing)
                .into_iter()
                .filter(|&p| region.contains(p))
                .collect()
        }
    };
    let mut lines: Vec<Vec<Point>> = Vec::new();
    let mut traced = SegmentIndex::new(spacing);
    for seed in seeds {
        // A seed on (or next to) a streamline already traced would only trace it again.
        if traced.near(seed, 0.5 * spacing) {
            continue;
        }
        if let Some(l) = full_streamline(&mut sampler, seed, step, snap, max_len) {
            traced.add(&l);
            lines.push(l);
        }
    }
    lines
}

/// Polyline segments bucketed on a grid, to ask whether a point is near any of them.
struct SegmentIndex {
    cell: f64,
    buckets: std::collections::HashMap<(i64, i64), Vec<(Point, Point)>>,
}

impl SegmentIndex {
    fn new(cell: f64) -> SegmentIndex {
        SegmentIndex {
            cell,
            buckets: std::collections::HashMap::new(),
        }
    }

    fn key(&self, p: Point) -> (i64, i64) {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
        )
    }

    fn add(&mut self, line: &[Point]) {
        for w in line.windows(2) {
            // Segments are shorter than a cell (steps are), so both ends' cells suffice.
            for k in [self.key(w[0]), self.key(w[1])] {
                self.buckets.entry(k).or_default().push((w[0], w[1]));
            }
        }
    }

    /// Whether a segment lies within `d` (at most a cell) of `p`.
    fn near(&self, p: Point, d: f64) -> bool {
        let (x, y) = self.key(p);
        (x - 1..=x + 1)
            .flat_map(|i| (y - 1..=y + 1).map(move |j| (i, j)))
            .any(|k| {
                self.buckets.get(&k).is_some_and(|v| {
                    v.iter()
                        .any(|&(a, b)| super::polygon::segment_distance(p, a, b) < d)
                })
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Rect;

    fn rect(w: f64, h: f64) -> Region {
        Region::from_rect(Rect::new(0.0, 0.0, w, h))
    }

    #[test]
    fn mean_value_interpolation_is_exact_on_linear_data() {
        // Mean value coordinates reproduce linear functions, holes and concave corners
        // included: boundary values v(p) = (p.x, 2 p.y + 1) come back exactly inside.
        let points = |xy: &[(f64, f64)]| xy.iter().map(|&p| Point::from(p)).collect::<Vec<_>>();
        let outer = points(&[(0., 0.), (10., 0.), (10., 10.), (5., 4.), (0., 10.)]);
        // Clockwise, as holes are.
        let hole = points(&[(6., 3.), (8., 3.), (8., 1.), (6., 1.)]);
        let linear = |p: Point| Vec2::new(p.x, 2.0 * p.y + 1.0);
        let rings = [outer, hole]
            .into_iter()
            .map(|points| Ring {
                values: points.iter().map(|&p| linear(p)).collect(),
                points,
            })
            .collect();
        let field = Field {
            rings,
            doubled: true,
            center: None,
        };
        for p in [
            Point::new(2.0, 2.0),
            Point::new(9.0, 5.0),
            Point::new(5.0, 0.5),
            Point::new(7.0, 3.5),
        ] {
            let v = field.value_at(p).unwrap();
            assert!((v - linear(p)).hypot() < 1e-9, "{v:?} at {p:?}");
        }
        // On the boundary itself, the boundary value.
        let v = field.value_at(Point::new(10.0, 5.0)).unwrap();
        assert!((v - linear(Point::new(10.0, 5.0))).hypot() < 1e-9);
    }

    #[test]
    fn outline_field_is_tangent_near_the_boundary() {
        let region = rect(40.0, 20.0);
        let field = Field::new(&region, FieldKind::Outline);
        let v = field.at(Point::new(20.0, 0.5)).unwrap();
        assert!(v.x.abs() > 0.99, "{v:?}");
        let v = field.at(Point::new(0.5, 10.0)).unwrap();
        assert!(v.y.abs() > 0.99, "{v:?}");
    }

    #[test]
    fn circular_streamlines_close_around_the_centre() {
        let region = rect(100.0, 100.0);
        let lines = streamlines(
            &region,
            FieldKind::Circular(Point::new(50.0, 50.0)),
            10.0,
            1.0,
        );
        assert!(lines.len() >= 4, "{}", lines.len());
        let first = &lines[0];
        assert_eq!(first.first(), first.last());
        assert!(lines.len() >= 8, "{}", lines.len());
        for p in first {
            assert!(
                ((*p - Point::new(50.0, 50.0)).hypot() - 10.0).abs() < 2.0,
                "{p:?}"
            );
        }
    }

    #[test]
    fn strip_streamlines_cross_a_long_rectangle() {
        let region = rect(200.0, 20.0);
        let lines = streamlines(&region, FieldKind::Strip, 20.0, 1.0);
        assert!(lines.len() >= 8, "{}", lines.len());
        for l in &lines {
            let (a, b) = (l[0], *l.last().unwrap());
            assert!(!region.contains(a) && !region.contains(b));
        }
    }
}
