//! `streamlineSplit(type, offset)`: cuts a shape along evenly spaced streamlines of a field
//! interpolated from its boundary (gTangle sec. 4.2; the fields are in
//! [`crate::tangle::field`]).

use kurbo::Vec2;

use crate::tangle::boolean::slice;
use crate::tangle::field::{FieldKind, streamlines};
use crate::tangle::polygon::{Grid, Region};

/// Streamlines are capped so a tiny offset on a huge shape cannot run away.
const MAX_LINES: f64 = 2_000.0;

/// Cuts `region` along streamlines of `kind` spaced `spacing` apart, traced with steps of
/// `step`. The pieces partition the region; they come ordered along `dir`, then across.
///
/// # Errors
/// A message when `spacing` or `step` is not positive, or the spacing is so small the cut
/// count would explode.
pub fn streamline_split(
    region: &Region,
    kind: FieldKind,
    spacing: f64,
    step: f64,
    dir: Vec2,
    grid: &Grid,
) -> Result<Vec<Region>, String> {
    if !(spacing > 0.0 && spacing.is_finite() && step > 0.0) {
        return Err(format!(
            "streamlineSplit offset must be a positive number, not {spacing}"
        ));
    }
    let bb = region.bbox();
    if (bb.width() + bb.height()) / spacing > MAX_LINES {
        return Err(format!(
            "streamlineSplit offset {spacing} is too small for a shape this size"
        ));
    }
    let step = step.min(spacing / 4.0);
    let lines = streamlines(region, kind, spacing, step);
    let mut pieces: Vec<(Region, (f64, f64))> = slice(region, &lines, grid)
        .polygons
        .into_iter()
        .filter(|p| p.area() > 0.0)
        .map(|p| {
            let at = p.interior_point().unwrap_or_else(|| p.centroid()).to_vec2();
            let key = (at.dot(dir), at.dot(Vec2::new(-dir.y, dir.x)));
            (Region::from_polygon(p), key)
        })
        .collect();
    pieces.sort_by(|a, b| a.1.0.total_cmp(&b.1.0).then(a.1.1.total_cmp(&b.1.1)));
    Ok(pieces.into_iter().map(|(r, _)| r).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tangle::ops::test_square;
    use kurbo::Point;

    #[test]
    fn circular_split_makes_rings() {
        let (grid, r) = test_square(60.0);
        let c = FieldKind::Circular(Point::new(30.0, 30.0));
        let pieces = streamline_split(&r, c, 8.0, 1.0, Vec2::new(1.0, 0.0), &grid).unwrap();
        // Three full rings plus a disc, and the corners.
        assert!(pieces.len() >= 5, "{}", pieces.len());
        let total: f64 = pieces.iter().map(Region::area).sum();
        assert!((total - 3600.0).abs() < 1e-6);
        assert!(streamline_split(&r, c, 0.0, 1.0, Vec2::new(1.0, 0.0), &grid).is_err());
    }
}
