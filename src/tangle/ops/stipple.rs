//! `stipple(kind, density)`: scatters small ink marks — dots, dashes or little curves —
//! inside a shape (gTangle sec. 4, after Secord 2002's stippling). The marks are laid out
//! by Poisson dart throwing, so they never clump, and each lies wholly inside the shape.

use std::f64::consts::{PI, TAU};

use kurbo::{Point, Vec2};

use crate::tangle::noise::Rng;
use crate::tangle::place::DiskSet;
use crate::tangle::polygon::{Grid, Polygon, Region};

/// The mark drawn by [`stipple`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StippleKind {
    /// Round dots of diameter `size`.
    Dots,
    /// Short strokes `3 × size` long, in random directions.
    Dashes,
    /// Small arcs (a third of a circle of radius `1.5 × size`).
    Curves,
}

/// Parameters of [`stipple`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StippleParams {
    /// The mark.
    pub kind: StippleKind,
    /// Marks per 100 square units (one per 10 × 10 square at density 1).
    pub density: f64,
    /// Mark size (dot diameter; dash and curve lengths scale with it).
    pub size: f64,
}

/// Marks per shape are capped; past that a stipple is a fill.
const MAX_MARKS: f64 = 50_000.0;

/// A mark's outline centred at the origin, pointing along +x.
fn mark(kind: StippleKind, size: f64, resolution: f64) -> Vec<Point> {
    let arc = |r: f64, a0: f64, a1: f64, n: usize| -> Vec<Point> {
        (0..=n)
            .map(|k| {
                Point::new(0.0, 0.0) + Vec2::from_angle(a0 + (a1 - a0) * k as f64 / n as f64) * r
            })
            .collect()
    };
    match kind {
        StippleKind::Dots => {
            let n = ((PI * size / (0.5 * resolution).max(1e-6)).ceil() as usize).clamp(6, 16);
            let mut pts = arc(0.5 * size, 0.0, TAU, n);
            pts.pop();
            pts
        }
        StippleKind::Dashes => {
            let (l, w) = (1.5 * size, 0.2 * size);
            vec![
                Point::new(-l, -w),
                Point::new(l, -w),
                Point::new(l, w),
                Point::new(-l, w),
            ]
        }
        StippleKind::Curves => {
            // A band between two concentric arcs, its middle at the origin.
            let (r, w) = (1.5 * size, 0.2 * size);
            let (a0, a1) = (-PI / 3.0, PI / 3.0);
            let mut outer = arc(r + w, a0, a1, 8);
            let mut inner = arc(r - w, a0, a1, 8);
            inner.reverse();
            outer.extend(inner);
            outer.into_iter().map(|p| p - Vec2::new(r, 0.0)).collect()
        }
    }
}

/// Ink marks inside `region`: each a small polygon wholly inside it.
///
/// # Errors
/// A message when the density or size is not positive, or the mark count would be absurd.
pub fn stipple(
    region: &Region,
    params: &StippleParams,
    rng: &mut Rng,
    grid: &Grid,
    resolution: f64,
) -> Result<Region, String> {
    if !(params.density > 0.0
        && params.size > 0.0
        && params.density.is_finite()
        && params.size.is_finite())
    {
        return Err("stipple density and size must be positive numbers".into());
    }
    let area = region.area();
    let expected = area * params.density / 100.0;
    if expected > MAX_MARKS {
        return Err(format!(
            "stipple density {} would draw {expected:.0} marks",
            params.density
        ));
    }
    let spacing = 10.0 / params.density.sqrt();
    let template = mark(params.kind, params.size, resolution);
    let reach = template
        .iter()
        .map(|p| p.to_vec2().hypot())
        .fold(0.0, f64::max);
    let bb = region.bbox();
    let attempts = ((8.0 * expected).ceil() as usize).max(16);
    let mut centres = DiskSet::new(0.7 * spacing);
    let mut marks = Region::default();
    for _ in 0..attempts {
        let p = Point::new(rng.range(bb.x0, bb.x1), rng.range(bb.y0, bb.y1));
        let angle = rng.range(0.0, TAU);
        // Inside with a quantum to spare, so snapping keeps it inside.
        if !region.contains(p) || region.boundary_distance(p) <= reach + 2.0 * grid.quantum() {
            continue;
        }
        if !centres.try_insert(p) {
            continue;
        }
        let (s, c) = angle.sin_cos();
        let outer = template
            .iter()
            .map(|q| grid.snap(Point::new(p.x + q.x * c - q.y * s, p.y + q.x * s + q.y * c)))
            .collect();
        marks.polygons.push(Polygon {
            outer,
            holes: vec![],
        });
    }
    // Outer rings are positive, as everywhere in the tangle.
    for m in &mut marks.polygons {
        if crate::tangle::polygon::ring_area(&m.outer) < 0.0 {
            m.outer.reverse();
        }
    }
    Ok(marks)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tangle::noise::key;
    use crate::tangle::ops::test_square;

    #[test]
    fn marks_lie_inside_at_the_asked_density() {
        let (grid, r) = test_square(100.0);
        for kind in [StippleKind::Dots, StippleKind::Dashes, StippleKind::Curves] {
            let p = StippleParams {
                kind,
                density: 1.0,
                size: 1.0,
            };
            let marks = stipple(&r, &p, &mut Rng::new(key(&[3])), &grid, 0.25).unwrap();
            // 100 expected at density 1 on 100 × 100; Poisson spacing packs at least half.
            assert!(
                marks.polygons.len() >= 50 && marks.polygons.len() <= 140,
                "{}",
                marks.polygons.len()
            );
            assert!(marks.polygons.iter().all(|m| m.area() > 0.0));
            assert!(
                marks
                    .polygons
                    .iter()
                    .flat_map(|m| m.outer.iter())
                    .all(|&q| r.contains(q))
            );
        }
        let bad = StippleParams {
            kind: StippleKind::Dots,
            density: 0.0,
            size: 1.0,
        };
        assert!(stipple(&r, &bad, &mut Rng::new(1), &grid, 0.25).is_err());
    }
}
