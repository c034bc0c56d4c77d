//! `perturb(amplitude, scale)`: coherent Perlin noise displaces every boundary point, so a
//! tangle looks drawn by hand (gTangle sec. 4.3, Fig. 8).
//!
//! The displacement is a function of position alone (for one seed), so two shapes sharing
//! an edge move it identically and stay adjacent. Edges are first subdivided where they
//! cross a fixed lattice of lines, which also depends on position alone: an edge that is
//! whole in one shape and split by a T-junction in its neighbour gains the same new
//! vertices in both.

use kurbo::{Point, Vec2};

use crate::tangle::boolean::clean;
use crate::tangle::noise::{fractal, mix};
use crate::tangle::polygon::{Grid, Region};

/// The most points the noise lattice may add to one shape's outline.
const MAX_ADDED_POINTS: f64 = 200_000.0;

/// The displacement of `p`: two independent noise channels, `amplitude` at most,
/// varying over `scale` units.
pub fn displacement(seed: u64, amplitude: f64, scale: f64, p: Point) -> Vec2 {
    let (x, y) = (p.x / scale, p.y / scale);
    Vec2::new(
        fractal(seed, x, y),
        fractal(mix(seed ^ 0x5EED), x + 31.7, y - 12.9),
    ) * amplitude
}

/// Points where segment `ab` crosses the lattice lines `x = k·h` and `y = k·h`, in order
/// from `a` (excluding both ends).
fn lattice_crossings(a: Point, b: Point, h: f64) -> Vec<Point> {
    let mut ts: Vec<f64> = Vec::new();
    for (a0, b0) in [(a.x, b.x), (a.y, b.y)] {
        if a0 == b0 {
            continue;
        }
        let (lo, hi) = (a0.min(b0), a0.max(b0));
        let mut k = (lo / h).floor() + 1.0;
        while k * h < hi {
            ts.push((k * h - a0) / (b0 - a0));
            k += 1.0;
        }
    }
    ts.sort_by(f64::total_cmp);
    ts.into_iter()
        .filter(|&t| t > 0.0 && t < 1.0)
        .map(|t| a.lerp(b, t))
        .collect()
}

/// The region with every boundary point displaced by noise seeded with `seed`. Crossings
/// the displacement creates are resolved, so the result is valid polygons again.
///
/// # Errors
/// A message when `scale` is not positive or `amplitude` is negative.
pub fn perturb(
    region: &Region,
    amplitude: f64,
    scale: f64,
    seed: u64,
    grid: &Grid,
) -> Result<Region, String> {
    if !(scale > 0.0 && scale.is_finite() && amplitude >= 0.0 && amplitude.is_finite()) {
        return Err("perturb needs a non-negative amplitude and a positive scale".into());
    }
    if amplitude == 0.0 {
        return Ok(region.clone());
    }
    // Four samples per noise feature follow the wobble closely.
    let h = scale / 4.0;
    // The lattice adds a point per crossing: a scale far below the shape's size would add
    // them without end (`perturb(1, 1e-300)` ran for ever).
    let crossings: f64 = region
        .edges()
        .map(|(a, b)| ((b.x - a.x).abs() + (b.y - a.y).abs()) / h)
        .sum();
    if crossings.is_nan() || crossings > MAX_ADDED_POINTS {
        return Err(format!(
            "perturb's scale {} is too small for a shape this size: its outline would gain more than {MAX_ADDED_POINTS} points",
            if scale >= 1e-4 {
                format!("{scale}")
            } else {
                format!("{scale:e}")
            }
        ));
    }
    let moved = |ring: &Vec<Point>| -> Vec<Point> {
        let mut out = Vec::with_capacity(ring.len() * 2);
        for i in 0..ring.len() {
            let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
            out.push(a);
            out.extend(lattice_crossings(a, b, h).into_iter().map(|p| grid.snap(p)));
        }
        out.into_iter()
            .map(|p| grid.snap(p + displacement(seed, amplitude, scale, p)))
            .collect()
    };
    let moved = Region {
        polygons: region
            .polygons
            .iter()
            .map(|p| crate::tangle::polygon::Polygon {
                outer: moved(&p.outer),
                holes: p.holes.iter().map(moved).collect(),
            })
            .collect(),
    };
    Ok(clean(&moved, grid))
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Rect;

    fn rect(x0: f64, x1: f64) -> Region {
        Region::from_rect(Rect::new(x0, 0.0, x1, 40.0))
    }

    #[test]
    fn neighbours_keep_their_shared_edge() {
        let grid = Grid::for_bounds(Rect::new(0.0, 0.0, 100.0, 100.0)).unwrap();
        let (a, b) = (rect(0.0, 30.0), rect(30.0, 60.0));
        let (pa, pb) = (
            perturb(&a, 2.0, 10.0, 9, &grid).unwrap(),
            perturb(&b, 2.0, 10.0, 9, &grid).unwrap(),
        );
        // The two perturbed pieces neither overlap nor leave a gap: their union has the
        // area of the two together, and is one polygon.
        let u = crate::tangle::boolean::union_all([&pa, &pb], &grid);
        assert!((u.area() - pa.area() - pb.area()).abs() < 1e-6);
        assert_eq!(u.polygons.len(), 1);
        assert_eq!(u.polygons[0].holes.len(), 0);
        // The outline did move.
        assert!((pa.area() - a.area()).abs() > 1e-3);
        assert!(pa.edges().all(|(p, _)| (p.x - 0.0).abs() < 40.0));
        assert!(perturb(&a, 1.0, 0.0, 9, &grid).is_err());
        // A scale so small the lattice would never end is refused, not looped over.
        let e = perturb(&a, 1.0, 1e-300, 9, &grid).unwrap_err();
        assert!(e.contains("too small"), "{e}");
    }
}
