//! The group grammar operators, one module each, as plain functions on regions with typed
//! parameters; [`Op`] gathers them for the expansion.

pub mod grouping;
pub mod outline;
pub mod paint;
pub mod perturb;
pub mod regular_split;
pub mod stipple;
pub mod streamline;
pub mod text;

use kurbo::{Point, Vec2};

use super::field::FieldKind;
use super::noise::Rng;
use super::place::{PlaceParams, place};
use super::polygon::{Grid, Region};
use crate::color::Color;
use grouping::{RegroupMode, regroup_slot};
use paint::Paint;
use regular_split::SplitParams;
use stipple::StippleParams;
use text::TextSplit;

/// The operators' unit-test case: the grid of a 100 × 100 canvas and a square region of
/// side `side` in its top-left corner.
#[cfg(test)]
fn test_square(side: f64) -> (Grid, Region) {
    use kurbo::Rect;
    let grid = Grid::for_bounds(Rect::new(0.0, 0.0, 100.0, 100.0)).unwrap();
    (grid, Region::from_rect(Rect::new(0.0, 0.0, side, side)))
}

/// Which field a streamline split follows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StreamKind {
    /// Parallel to the outline (nested rings).
    Outline,
    /// Across the shape (strips following its bends).
    Strip,
    /// Circles about a point (the shape's centroid when not given, or its innermost point
    /// if the centroid lies outside).
    Circular(Option<Point>),
}

/// An operator with its parameters bound.
#[derive(Clone, Debug, PartialEq)]
pub enum Op {
    /// `ungroup()`.
    Ungroup,
    /// `regroup(k, mode)`.
    Regroup {
        /// Number of new groups.
        k: usize,
        /// How shapes are dealt.
        mode: RegroupMode,
    },
    /// `regularSplit(curve, offsets, dual, angle)`.
    RegularSplit {
        /// Curve, offsets, dual.
        params: SplitParams,
        /// Degrees to turn the shape's orientation by first (the pieces keep it).
        angle: f64,
    },
    /// `outline(d)`.
    Outline {
        /// Ring width.
        distance: f64,
    },
    /// `streamlineSplit(type, offset)`.
    StreamlineSplit {
        /// The field.
        kind: StreamKind,
        /// Spacing between streamlines.
        spacing: f64,
    },
    /// `place(shape, size, distance)`.
    Place(PlaceParams),
    /// `fill(colour)`.
    Fill(Color),
    /// `stipple(kind, density, size)`.
    Stipple(StippleParams),
    /// `invert()`.
    Invert,
    /// `perturb(amplitude, scale)`.
    Perturb {
        /// Largest displacement.
        amplitude: f64,
        /// Size of the wobbles.
        scale: f64,
    },
    /// `letters()`, `words()`, `lines()`.
    Text(TextSplit),
}

/// One shape handed to an operator.
#[derive(Clone, Copy, Debug)]
pub struct Input<'a> {
    /// Its boundary.
    pub region: &'a Region,
    /// Its orientation d (unit).
    pub dir: Vec2,
    /// Its paint.
    pub paint: &'a Paint,
    /// Its split cell (from the last regular split).
    pub cell: (i64, i64),
    /// Its id in its group.
    pub sid: usize,
    /// Key for this shape's random draws.
    pub key: u64,
    /// Key shared by the whole group (perturbation noise, so neighbours move alike).
    pub group_key: u64,
}

/// What every operator needs besides the shape.
#[derive(Clone, Copy, Debug)]
pub struct Context {
    /// The lattice all geometry lives on.
    pub grid: Grid,
    /// Working resolution: fields are traced in steps of it, placement rasters are twice
    /// as fine, placed circles and dots have edges about half as long.
    pub resolution: f64,
    /// The most pieces one `place` may scatter ([`super::TangleOptions::max_shapes`]).
    pub max_pieces: usize,
}

/// A shape produced by an operator. `slot` indexes the rule's outputs (the tag, and the
/// new group, it joins).
#[derive(Clone, Debug)]
pub struct Piece {
    /// Its boundary.
    pub region: Region,
    /// Which output it is.
    pub slot: usize,
    /// Its split cell.
    pub cell: (i64, i64),
    /// Its orientation.
    pub dir: Vec2,
    /// Its paint.
    pub paint: Paint,
}

impl Op {
    /// The operator's grammar name.
    pub fn name(&self) -> &'static str {
        match self {
            Op::Ungroup => "ungroup",
            Op::Regroup { .. } => "regroup",
            Op::RegularSplit { .. } => "regularSplit",
            Op::Outline { .. } => "outline",
            Op::StreamlineSplit { .. } => "streamlineSplit",
            Op::Place(_) => "place",
            Op::Fill(_) => "fill",
            Op::Stipple(_) => "stipple",
            Op::Invert => "invert",
            Op::Perturb { .. } => "perturb",
            Op::Text(split) => split.name(),
        }
    }

    /// Applies the operator to one shape. Grouping operators return the shape unchanged
    /// (in the slot of its new group; `ungroup`'s one-group-per-shape is the caller's).
    ///
    /// # Errors
    /// A message when the parameters do not make sense for this shape; the caller keeps
    /// the shape whole and warns.
    pub fn apply(&self, input: Input<'_>, ctx: &Context) -> Result<Vec<Piece>, String> {
        let same = |region: Region, slot: usize, paint: Paint| Piece {
            region,
            slot,
            cell: input.cell,
            dir: input.dir,
            paint,
        };
        let keep = |slot: usize| vec![same(input.region.clone(), slot, input.paint.clone())];
        let grid = &ctx.grid;
        Ok(match self {
            Op::Ungroup => keep(0),
            Op::Regroup { k, mode } => {
                keep(regroup_slot(*mode, *k, input.cell, input.sid, input.key))
            }
            Op::RegularSplit { params, angle } => {
                let dir = kurbo::Affine::rotate(angle.to_radians()) * input.dir.to_point();
                let dir = dir.to_vec2();
                regular_split::regular_split(input.region, dir, params, grid)?
                    .into_iter()
                    .map(|p| Piece {
                        region: p.region,
                        slot: 0,
                        cell: p.cell,
                        dir,
                        paint: input.paint.clone(),
                    })
                    .collect()
            }
            Op::Outline { distance } => {
                // Slot 0 the inner pieces, slot 1 the ring: gTangle's Fig. 9 names them
                // `[in, out]` (its §4.2 text lists them the other way round). The ring
                // still comes first in drawing order.
                let (ring, inner) = outline::outline(input.region, *distance, grid)?;
                let each = |r: Region, slot: usize| {
                    r.polygons
                        .into_iter()
                        .map(move |p| (Region::from_polygon(p), slot))
                };
                each(ring, 1)
                    .chain(each(inner, 0))
                    .enumerate()
                    .map(|(n, (r, slot))| Piece {
                        cell: (n as i64, 0),
                        ..same(r, slot, input.paint.clone())
                    })
                    .collect()
            }
            Op::StreamlineSplit { kind, spacing } => {
                let field = match *kind {
                    StreamKind::Outline => FieldKind::Outline,
                    StreamKind::Strip => FieldKind::Strip,
                    StreamKind::Circular(Some(c)) => FieldKind::Circular(c),
                    StreamKind::Circular(None) => {
                        let c = input.region.centroid();
                        let c = if input.region.contains(c) {
                            c
                        } else {
                            super::field::pole(input.region).map_or(c, |(p, _)| p)
                        };
                        FieldKind::Circular(c)
                    }
                };
                streamline::streamline_split(
                    input.region,
                    field,
                    *spacing,
                    ctx.resolution,
                    input.dir,
                    grid,
                )?
                .into_iter()
                .enumerate()
                .map(|(n, r)| Piece {
                    cell: (n as i64, 0),
                    ..same(r, 0, input.paint.clone())
                })
                .collect()
            }
            Op::Place(params) => {
                let mut rng = Rng::new(input.key);
                let out = place(
                    input.region,
                    params,
                    input.dir,
                    &mut rng,
                    grid,
                    (ctx.resolution, ctx.max_pieces),
                )?;
                // Slot 0 the placed pieces, slot 1 the remainder: gTangle's Fig. 9 names
                // them `[blob, rem]` (its §4.2 text lists them the other way round). The
                // remainder still comes first in drawing order.
                let rem = out
                    .remainder
                    .polygons
                    .into_iter()
                    .map(|p| (Region::from_polygon(p), 1));
                rem.chain(out.placed.into_iter().map(|r| (r, 0)))
                    .enumerate()
                    .map(|(n, (r, slot))| Piece {
                        cell: (n as i64, 0),
                        ..same(r, slot, input.paint.clone())
                    })
                    .collect()
            }
            Op::Fill(c) => vec![same(input.region.clone(), 0, input.paint.filled(*c))],
            Op::Invert => vec![same(input.region.clone(), 0, input.paint.inverted())],
            Op::Stipple(params) => {
                let mut rng = Rng::new(input.key);
                let marks = stipple::stipple(input.region, params, &mut rng, grid, ctx.resolution)?;
                let mut out = keep(0);
                if !marks.is_empty() {
                    out.push(same(marks, 1, input.paint.ink()));
                }
                out
            }
            // The expansion cuts text with the layout it holds ([`text::cut`]); a shape
            // that reaches here did not come from text, and stays whole.
            Op::Text(split) => {
                return Err(format!(
                    "`{}()` cuts text; this shape did not come from text",
                    split.name()
                ));
            }
            Op::Perturb { amplitude, scale } => {
                let r = perturb::perturb(input.region, *amplitude, *scale, input.group_key, grid)?;
                vec![same(r, 0, input.paint.clone())]
            }
        })
    }
}
