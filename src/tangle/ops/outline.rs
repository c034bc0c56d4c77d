//! `outline(d)` → [out, in]: the outer ring of width `d` and the inner shapes left by an
//! inward offset of `d` (gTangle sec. 4.2, "geometric outline").

use crate::tangle::boolean::{difference, offset};
use crate::tangle::polygon::{Grid, Region};

/// Splits `region` into its outer ring (`region` minus the inner shapes) and the inner
/// shapes (the region shrunk by `distance`, round at reflex corners). An offset larger
/// than the shape leaves no inner shapes and the whole shape as the ring.
///
/// # Errors
/// A message when `distance` is not a positive number.
pub fn outline(region: &Region, distance: f64, grid: &Grid) -> Result<(Region, Region), String> {
    if !(distance > 0.0 && distance.is_finite()) {
        return Err(format!(
            "outline distance must be a positive number, not {distance}"
        ));
    }
    let inner = offset(region, -distance, grid);
    if inner.is_empty() {
        return Ok((region.clone(), inner));
    }
    Ok((difference(region, &inner, grid), inner))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tangle::ops::test_square;

    #[test]
    fn ring_and_core_partition_a_square() {
        let (grid, r) = test_square(50.0);
        let (out, inner) = outline(&r, 5.0, &grid).unwrap();
        assert!((inner.area() - 1600.0).abs() < 0.5, "{}", inner.area());
        assert!((out.area() + inner.area() - 2500.0).abs() < 1e-6);
        assert_eq!(out.polygons.len(), 1);
        assert_eq!(out.polygons[0].holes.len(), 1);
        let (out, inner) = outline(&r, 40.0, &grid).unwrap();
        assert!(inner.is_empty());
        assert_eq!(out, r);
        assert!(outline(&r, -1.0, &grid).is_err());
    }
}
