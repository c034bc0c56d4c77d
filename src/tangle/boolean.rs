//! Polygon booleans, slicing and offsets, all done by i_overlay's integer engine on the
//! common [`Grid`]. Results are valid polygons with holes (no self-intersections, outer
//! rings positive, holes negative), which is what every operator builds on.

use i_overlay::core::fill_rule::FillRule as IFillRule;
use i_overlay::core::overlay::{Overlay, ShapeType};
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::i_float::int::angle::Angle;
use i_overlay::i_float::int::point::IntPoint;
use i_overlay::mesh::int::arc::ArcOptions;
use i_overlay::mesh::int::outline::offset::IntOutlineOffset;
use i_overlay::mesh::int::style::{IntLineJoin, IntOutlineStyle};
use i_overlay::string::slice::IntSlice;
use kurbo::Point;

use super::polygon::{Grid, Region};
use crate::scene::FillRule;

fn engine_rule(rule: FillRule) -> IFillRule {
    match rule {
        FillRule::NonZero => IFillRule::NonZero,
        FillRule::EvenOdd => IFillRule::EvenOdd,
    }
}

fn int_ring(ring: &[Point], grid: &Grid) -> Vec<IntPoint<i32>> {
    let mut r: Vec<IntPoint<i32>> = ring.iter().map(|&p| grid.to_int(p)).collect();
    r.dedup();
    r
}

/// The region filled by arbitrary (possibly self-intersecting) closed rings under a fill
/// rule, as valid polygons with holes.
pub fn normalize(rings: &[Vec<Point>], rule: FillRule, grid: &Grid) -> Region {
    let mut overlay = Overlay::<i32>::new(rings.iter().map(Vec::len).sum());
    for r in rings {
        overlay.add_contour(&int_ring(r, grid), ShapeType::Subject);
    }
    Region::from_int(
        &overlay.overlay(OverlayRule::Subject, engine_rule(rule)),
        grid,
    )
}

/// Re-validates a region whose vertices were moved (which may have made rings cross).
pub fn clean(region: &Region, grid: &Grid) -> Region {
    let rings: Vec<Vec<Point>> = region
        .polygons
        .iter()
        .flat_map(|p| p.rings().cloned())
        .collect::<Vec<_>>();
    normalize(&rings, FillRule::NonZero, grid)
}

fn binary(a: &Region, b: &Region, rule: OverlayRule, grid: &Grid) -> Region {
    let (sa, sb) = (a.to_int(grid), b.to_int(grid));
    let mut overlay = Overlay::<i32>::new(a.vertex_count() + b.vertex_count());
    overlay.add_source(&sa, ShapeType::Subject);
    overlay.add_source(&sb, ShapeType::Clip);
    Region::from_int(&overlay.overlay(rule, IFillRule::NonZero), grid)
}

/// `a ∩ b`.
pub fn intersect(a: &Region, b: &Region, grid: &Grid) -> Region {
    binary(a, b, OverlayRule::Intersect, grid)
}

/// `a − b`.
pub fn difference(a: &Region, b: &Region, grid: &Grid) -> Region {
    binary(a, b, OverlayRule::Difference, grid)
}

/// The union of many regions in one pass.
pub fn union_all<'a>(regions: impl IntoIterator<Item = &'a Region>, grid: &Grid) -> Region {
    let mut overlay = Overlay::<i32>::new(0);
    for r in regions {
        overlay.add_source(&r.to_int(grid), ShapeType::Subject);
    }
    Region::from_int(
        &overlay.overlay(OverlayRule::Subject, IFillRule::NonZero),
        grid,
    )
}

/// Cuts a region along open polylines. Cuts that end inside the region or miss it leave it
/// whole there; the pieces partition the region exactly (they share the cut edges).
pub fn slice(region: &Region, cuts: &[Vec<Point>], grid: &Grid) -> Region {
    let paths: Vec<Vec<IntPoint<i32>>> = cuts
        .iter()
        .map(|c| int_ring(c, grid))
        .filter(|c| c.len() >= 2)
        .collect();
    let shapes = region.to_int(grid);
    if paths.is_empty() {
        return region.clone();
    }
    Region::from_int(&shapes.slice_by_paths(&paths, IFillRule::NonZero), grid)
}

/// The region grown (`distance > 0`) or shrunk (`distance < 0`) by `|distance|`, with
/// round joins — the exact Minkowski offset up to the arc tessellation.
pub fn offset(region: &Region, distance: f64, grid: &Grid) -> Region {
    let d = grid.to_int_len(distance);
    if d == 0 {
        return region.clone();
    }
    // 1/64 turn per arc step: smooth at drawing scales without exploding vertex counts.
    let arc = ArcOptions {
        max_step: Angle::from_bits(1 << 26),
        rotation_precision: 8,
    };
    let style = IntOutlineStyle::new(d).line_join(IntLineJoin::Round(arc));
    let shapes = region.to_int(grid);
    match shapes.outline(&style) {
        Ok(s) => Region::from_int(&s, grid),
        // Construction itself never fails; only the optional range check can.
        Err(_) => Region::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Rect;

    fn grid() -> Grid {
        Grid::for_bounds(Rect::new(0.0, 0.0, 100.0, 100.0)).unwrap()
    }

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Region {
        Region::from_rect(Rect::new(x0, y0, x1, y1))
    }

    #[test]
    fn orientation_is_outer_positive() {
        let g = grid();
        // Given clockwise (negative) input, the engine still yields a positive outer ring.
        let mut ring = rect(0.0, 0.0, 10.0, 10.0).polygons[0].outer.clone();
        ring.reverse();
        let r = normalize(&[ring], FillRule::NonZero, &g);
        assert_eq!(r.polygons.len(), 1);
        assert!(crate::tangle::polygon::ring_area(&r.polygons[0].outer) > 0.0);
        let holed = difference(&rect(0.0, 0.0, 10.0, 10.0), &rect(3.0, 3.0, 6.0, 6.0), &g);
        assert_eq!(holed.polygons[0].holes.len(), 1);
        assert!(crate::tangle::polygon::ring_area(&holed.polygons[0].holes[0]) < 0.0);
        assert!((holed.area() - 91.0).abs() < 1e-6);
    }

    #[test]
    fn bowtie_is_resolved() {
        let g = grid();
        let bow = [(0., 0.), (10., 10.), (10., 0.), (0., 10.)].map(Point::from);
        let r = normalize(&[bow.to_vec()], FillRule::EvenOdd, &g);
        assert_eq!(r.polygons.len(), 2);
        assert!((r.area() - 50.0).abs() < 1e-6);
    }

    #[test]
    fn slicing_partitions() {
        let g = grid();
        let r = rect(0.0, 0.0, 10.0, 10.0);
        let cuts = vec![
            vec![Point::new(-1.0, 5.0), Point::new(11.0, 5.0)],
            vec![Point::new(5.0, -1.0), Point::new(5.0, 11.0)],
            // A cut ending inside leaves the region whole.
            vec![Point::new(2.0, 2.0), Point::new(3.0, 3.0)],
        ];
        let s = slice(&r, &cuts, &g);
        assert_eq!(s.polygons.len(), 4);
        assert!((s.area() - 100.0).abs() < 1e-6);
    }

    #[test]
    fn offsets_shrink_and_vanish() {
        let g = grid();
        let r = rect(0.0, 0.0, 10.0, 10.0);
        let inner = offset(&r, -2.0, &g);
        assert!((inner.area() - 36.0).abs() < 1e-3, "{}", inner.area());
        assert!(offset(&r, -6.0, &g).is_empty());
        let u = union_all([&rect(0.0, 0.0, 2.0, 2.0), &rect(1.0, 0.0, 3.0, 2.0)], &g);
        assert!((u.area() - 6.0).abs() < 1e-6);
        assert!((intersect(&r, &rect(5.0, 5.0, 20.0, 20.0), &g).area() - 25.0).abs() < 1e-6);
    }
}
