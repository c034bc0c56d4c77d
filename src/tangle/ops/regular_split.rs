//! `regularSplit(curve, offsets, dual)`: cuts a shape along copies of a curve placed along
//! its orientation d at fixed or cycling offsets; a dual split cuts a second time along the
//! perpendicular, giving grids.
//!
//! The curve is one period of a pattern running across the shape: its chord (start to end)
//! is laid along d⊥ and the curve is repeated end to end to span the shape, so a straight
//! line gives stripes, a zigzag gives chevrons and an arc gives scales. All copies are cut
//! in one slicing pass, so neighbouring pieces share their cut edges exactly.

use kurbo::{Point, Vec2};

use crate::tangle::boolean::slice;
use crate::tangle::polygon::{Grid, Region};

/// The cutting curve of a regular split.
#[derive(Clone, Debug, PartialEq)]
pub enum Curve {
    /// A straight line.
    Line,
    /// One period of a polyline, in user units; its chord sets the repeat.
    Polyline(Vec<Point>),
}

/// Parameters of [`regular_split`].
#[derive(Clone, Debug, PartialEq)]
pub struct SplitParams {
    /// The cutting curve.
    pub curve: Curve,
    /// Distances between consecutive copies, cycled through.
    pub offsets: Vec<f64>,
    /// Cut a second time across.
    pub dual: bool,
}

/// A piece of a regular split and its cell: the number of copies before it along d and,
/// for dual splits, along d⊥.
#[derive(Clone, Debug, PartialEq)]
pub struct SplitPiece {
    /// The piece (one polygon with holes).
    pub region: Region,
    /// `(i, j)`: strip index along d, strip index along d⊥ (0 unless dual).
    pub cell: (i64, i64),
}

/// Copies, and cells of a dual split, are capped so a tiny offset on a huge shape cannot
/// exhaust memory.
const MAX_CUTS: usize = 20_000;
const MAX_CELLS: usize = 250_000;
/// Points all copies of a curve may hold together (16 bytes each, before the cut): room for
/// a fine pattern over a large shape, while a microscopic one is refused before allocating.
const MAX_CUT_POINTS: usize = 1_000_000;

/// One family of parallel copies: the curve period in its frame (u along the chord, v
/// across it), and the copies' positions along the family's axis.
struct Family {
    along: Vec2,
    across: Vec2,
    /// The period's points as (u, v), u from 0 to `period`.
    period_pts: Vec<(f64, f64)>,
    period: f64,
    positions: Vec<f64>,
}

impl Family {
    fn new(region: &Region, curve: &Curve, along: Vec2, offsets: &[f64]) -> Result<Family, String> {
        let across = Vec2::new(-along.y, along.x);
        let (period_pts, period) = match curve {
            Curve::Line => (vec![(0.0, 0.0), (1.0, 0.0)], 1.0),
            Curve::Polyline(pts) => {
                let (Some(&a), Some(&b)) = (pts.first(), pts.last()) else {
                    return Err("the split curve is empty".into());
                };
                let chord = b - a;
                let len = chord.hypot();
                if len.is_nan() || len <= 1e-9 {
                    return Err("the split curve must be open: its ends coincide".into());
                }
                let (cu, cv) = (chord / len, Vec2::new(-chord.y, chord.x) / len);
                let uv = pts
                    .iter()
                    .map(|&p| ((p - a).dot(cu), (p - a).dot(cv)))
                    .collect();
                (uv, len)
            }
        };
        let proj = |axis: Vec2| {
            region
                .edges()
                .map(|(p, _)| p.to_vec2().dot(axis))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                })
        };
        let (a0, a1) = proj(along);
        let (vmin, vmax) = period_pts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(_, v)| {
                (lo.min(v), hi.max(v))
            });
        let mut positions = Vec::new();
        // Anchored so a copy's highest point would touch the shape's start; copies continue
        // while any part of them can still reach the shape.
        let mut t = a0 - vmax;
        for k in 0.. {
            t += offsets[k % offsets.len()];
            if t + vmin >= a1 {
                break;
            }
            positions.push(t);
            if positions.len() > MAX_CUTS {
                return Err(format!(
                    "more than {MAX_CUTS} cuts: the offsets are too small for the shape"
                ));
            }
        }
        Ok(Family {
            along,
            across,
            period_pts,
            period,
            positions,
        })
    }

    /// The copies as polylines crossing the whole shape; an error when they would hold more
    /// than [`MAX_CUT_POINTS`] points (a microscopic period repeated across a large shape
    /// asked for gigabytes at once).
    fn cuts(&self, region: &Region) -> Result<Vec<Vec<Point>>, String> {
        let (c0, c1) = region
            .edges()
            .map(|(p, _)| p.to_vec2().dot(self.across))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        let margin = 0.01 * (c1 - c0) + 1e-6;
        if self.period_pts.iter().all(|&(_, v)| v == 0.0) {
            // A straight period needs no repeats: one segment across the shape.
            let at = |c: f64, t: f64| (self.across * c + self.along * t).to_point();
            return Ok(self
                .positions
                .iter()
                .map(|&t| vec![at(c0 - margin, t), at(c1 + margin, t)])
                .collect());
        }
        let repeats = ((c1 - c0 + 2.0 * margin) / self.period).ceil() + 2.0;
        let points = repeats * (self.period_pts.len() - 1) as f64 * self.positions.len() as f64;
        // NaN (a degenerate period) counts as too many.
        if points.is_nan() || points > MAX_CUT_POINTS as f64 {
            return Err(format!(
                "the split curve, {} long, repeats {repeats:.0} times across the shape: its {} copies would hold {points:.0} points, more than {MAX_CUT_POINTS}; use a longer curve or larger offsets",
                self.period,
                self.positions.len()
            ));
        }
        let first = ((c0 - margin) / self.period).floor() as i64 - 1;
        let last = ((c1 + margin) / self.period).ceil() as i64 + 1;
        Ok(self
            .positions
            .iter()
            .map(|&t| {
                let mut line = Vec::new();
                for k in first..last {
                    let base = k as f64 * self.period;
                    let pts = if k == first {
                        &self.period_pts[..]
                    } else {
                        &self.period_pts[1..]
                    };
                    for &(u, v) in pts {
                        line.push((self.across * (base + u) + self.along * (t + v)).to_point());
                    }
                }
                line
            })
            .collect())
    }

    /// The curve's offset along the axis at across-coordinate `c` (first crossing).
    fn height(&self, c: f64) -> f64 {
        let u = c.rem_euclid(self.period);
        self.period_pts
            .windows(2)
            .find_map(|w| {
                let ((u0, v0), (u1, v1)) = (w[0], w[1]);
                let (lo, hi) = (u0.min(u1), u0.max(u1));
                (u >= lo && u <= hi).then(|| {
                    if hi > lo {
                        v0 + (v1 - v0) * (u - u0) / (u1 - u0)
                    } else {
                        v0
                    }
                })
            })
            .unwrap_or(0.0)
    }

    /// How many copies lie before `p` along the axis.
    fn index_of(&self, p: Point) -> i64 {
        let h = p.to_vec2().dot(self.along) - self.height(p.to_vec2().dot(self.across));
        self.positions.partition_point(|&t| t <= h) as i64
    }
}

/// Cuts `region` along copies of the curve at `offsets` along `dir` (and across it when
/// dual). The pieces partition the region and come in cell order. A curve that misses the
/// shape leaves it whole, as one piece.
///
/// # Errors
/// A message (the shape is then left whole) when the offsets are not positive, the curve
/// is closed, or the cuts would exceed a sane count.
pub fn regular_split(
    region: &Region,
    dir: Vec2,
    params: &SplitParams,
    grid: &Grid,
) -> Result<Vec<SplitPiece>, String> {
    if params.offsets.is_empty() || params.offsets.iter().any(|&o| !(o > 0.0 && o.is_finite())) {
        return Err("regularSplit offsets must be positive numbers".into());
    }
    let along = dir.normalize();
    if !along.is_finite() {
        return Err("the shape's orientation is not a direction".into());
    }
    let first = Family::new(region, &params.curve, along, &params.offsets)?;
    let mut cuts = first.cuts(region)?;
    let second = if params.dual {
        let f = Family::new(
            region,
            &params.curve,
            Vec2::new(-along.y, along.x),
            &params.offsets,
        )?;
        if (first.positions.len() + 1) * (f.positions.len() + 1) > MAX_CELLS {
            return Err(format!(
                "more than {MAX_CELLS} cells: the offsets are too small for the shape"
            ));
        }
        cuts.extend(f.cuts(region)?);
        Some(f)
    } else {
        None
    };
    let pieces = slice(region, &cuts, grid);
    let mut out: Vec<(SplitPiece, f64)> = pieces
        .polygons
        .into_iter()
        .filter(|p| p.area() > 0.0)
        .map(|p| {
            let at = p.interior_point().unwrap_or_else(|| p.centroid());
            let cell = (
                first.index_of(at),
                second.as_ref().map_or(0, |f| f.index_of(at)),
            );
            let key = at.to_vec2().dot(Vec2::new(-along.y, along.x));
            (
                SplitPiece {
                    region: Region::from_polygon(p),
                    cell,
                },
                key,
            )
        })
        .collect();
    out.sort_by(|(a, ka), (b, kb)| a.cell.cmp(&b.cell).then(ka.total_cmp(kb)));
    Ok(out.into_iter().map(|(p, _)| p).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Rect;

    fn rect(w: f64, h: f64) -> Region {
        Region::from_rect(Rect::new(0.0, 0.0, w, h))
    }

    /// Parameters for parallel copies of `curve` only (no dual cuts).
    fn stripes(curve: Curve, offsets: &[f64]) -> SplitParams {
        SplitParams {
            curve,
            offsets: offsets.to_vec(),
            dual: false,
        }
    }

    fn grid() -> Grid {
        Grid::for_bounds(Rect::new(0.0, 0.0, 200.0, 200.0)).unwrap()
    }

    #[test]
    fn stripes_and_grids() {
        let r = rect(100.0, 50.0);
        let p = stripes(Curve::Line, &[10.0]);
        let pieces = regular_split(&r, Vec2::new(1.0, 0.0), &p, &grid()).unwrap();
        assert_eq!(pieces.len(), 10);
        assert!(
            pieces
                .iter()
                .all(|p| (p.region.area() - 500.0).abs() < 1e-6)
        );
        let cells: Vec<i64> = pieces.iter().map(|p| p.cell.0).collect();
        assert_eq!(cells, (0..10).collect::<Vec<_>>());
        let dual = SplitParams { dual: true, ..p };
        let pieces = regular_split(&r, Vec2::new(1.0, 0.0), &dual, &grid()).unwrap();
        assert_eq!(pieces.len(), 50);
        assert_eq!(pieces[7].cell, (1, 2));
    }

    #[test]
    fn cycling_offsets_and_zigzags() {
        let r = rect(100.0, 50.0);
        let p = stripes(Curve::Line, &[10.0, 30.0]);
        let pieces = regular_split(&r, Vec2::new(1.0, 0.0), &p, &grid()).unwrap();
        let areas: Vec<f64> = pieces.iter().map(|p| p.region.area().round()).collect();
        // Cuts at 10, 40, 50, 80, 90.
        assert_eq!(areas, vec![500.0, 1500.0, 500.0, 1500.0, 500.0, 500.0]);
        let zig = Curve::Polyline(vec![
            Point::new(0.0, 0.0),
            Point::new(5.0, 4.0),
            Point::new(10.0, 0.0),
        ]);
        let p = stripes(zig, &[12.0]);
        let pieces = regular_split(&r, Vec2::new(0.0, 1.0), &p, &grid()).unwrap();
        let total: f64 = pieces.iter().map(|p| p.region.area()).sum();
        assert!((total - 5000.0).abs() < 1e-6);
        assert!(pieces.len() >= 4);
    }

    #[test]
    fn degenerate_parameters_are_errors() {
        let r = rect(10.0, 10.0);
        let bad = stripes(Curve::Line, &[0.0]);
        assert!(regular_split(&r, Vec2::new(1.0, 0.0), &bad, &grid()).is_err());
        let closed = Curve::Polyline(vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 0.0),
        ]);
        let p = stripes(closed, &[1.0]);
        assert!(regular_split(&r, Vec2::new(1.0, 0.0), &p, &grid()).is_err());
        let p = stripes(Curve::Line, &[1e-6]);
        assert!(regular_split(&r, Vec2::new(1.0, 0.0), &p, &grid()).is_err());
        // A period so short that its copies would hold millions of points is refused
        // before they are made.
        let tiny = Curve::Polyline(vec![
            Point::new(0.0, 0.0),
            Point::new(1e-4, 1e-4),
            Point::new(2e-4, 0.0),
        ]);
        let p = stripes(tiny, &[1.0]);
        let err = regular_split(&r, Vec2::new(1.0, 0.0), &p, &grid()).unwrap_err();
        assert!(err.contains("more than 1000000"), "{err}");
        // An offset larger than the shape misses it: the shape comes back whole.
        let p = stripes(Curve::Line, &[50.0]);
        let pieces = regular_split(&r, Vec2::new(1.0, 0.0), &p, &grid()).unwrap();
        assert_eq!(pieces.len(), 1);
    }
}
