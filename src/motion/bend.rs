//! Outlines cut where a per-vertex motion bends them (`lookup=vertex`).
//!
//! A vertex motion moves each point of an outline by the grid read at that point
//! ([`Track::deform`]). Writers move the outline's vertices and control points and let the
//! curve between them follow, which is exact only where the field is affine along the
//! segment: a rectangle's edge under a 12×1 grid would stay straight while the band should
//! wave. [`refine`] cuts each segment where it strays most (the same curve at rest, so
//! nothing moves until the field does) until the segment drawn through its moved points
//! stays within the tolerance of the exact field at every instant asked for, measured at
//! every sixteenth of each piece.

use kurbo::{Affine, BezPath, CubicBez, Line, ParamCurve, PathEl, PathSeg, Point, QuadBez};

use super::Track;

/// How many levels deep a segment may be cut (at most 256 pieces).
const MAX_DEPTH: u32 = 8;

/// A piece is measured at its `k / PROBES` points, `0 < k < PROBES`: sixteenths, as the
/// bilinear field has a kink on every line through the cells' centres, and a kink near a
/// piece's end strays most between the end and the first probe (with quarters, a leaf
/// under a 6×6 `path` grid was drawn 0.31 px off at a 0.25 tolerance).
const PROBES: u32 = 16;

/// `path` (in coordinates that `abs` maps onto the canvas) with its segments cut where the
/// deforming `tracks` (outermost first, applied innermost first) bend them more than
/// `tolerance` canvas units at any of `times`; `path` itself when no segment needs it (so
/// outlines that the field does not bend are written as they were).
pub fn refine<'p>(
    path: &'p BezPath,
    abs: Affine,
    tracks: &[&Track],
    times: &[f64],
    tolerance: f64,
) -> std::borrow::Cow<'p, BezPath> {
    use std::borrow::Cow;
    let moved = |q: Point, t: f64| tracks.iter().rev().fold(abs * q, |c, tr| tr.deform(c, t));
    // Where (the parameter of the probe) the piece strays most past the tolerance, at
    // any of the times; `None` when it stays within.
    let bends = |seg: &PathSeg| -> Option<f64> {
        let mut worst = (tolerance, None);
        for &t in times {
            let drawn = map_seg(seg, |q| moved(q, t));
            for k in 1..PROBES {
                let s = f64::from(k) / f64::from(PROBES);
                let off = (drawn.eval(s) - moved(seg.eval(s), t)).hypot();
                if off > worst.0 {
                    worst = (off, Some(s));
                }
            }
        }
        worst.1
    };
    if path.segments().all(|s| bends(&s).is_none()) {
        return Cow::Borrowed(path);
    }
    let mut out = BezPath::new();
    let mut start = Point::ORIGIN;
    let mut at = Point::ORIGIN;
    for el in path.elements() {
        let seg = match *el {
            PathEl::MoveTo(p) => {
                out.move_to(p);
                (start, at) = (p, p);
                continue;
            }
            PathEl::LineTo(p) => PathSeg::Line(Line::new(at, p)),
            PathEl::QuadTo(a, p) => PathSeg::Quad(QuadBez::new(at, a, p)),
            PathEl::CurveTo(a, b, p) => PathSeg::Cubic(CubicBez::new(at, a, b, p)),
            PathEl::ClosePath => {
                // The closing line bends too: its pieces but the last, then the close.
                if at != start {
                    let mut pieces = Vec::new();
                    cut(PathSeg::Line(Line::new(at, start)), &bends, 0, &mut pieces);
                    pieces.pop();
                    for s in pieces {
                        push(&mut out, s);
                    }
                }
                out.close_path();
                at = start;
                continue;
            }
        };
        let mut pieces = Vec::new();
        cut(seg, &bends, 0, &mut pieces);
        for s in pieces {
            push(&mut out, s);
        }
        at = seg.end();
    }
    Cow::Owned(out)
}

/// `seg` cut where it strays most (at a probe) while `bends` finds it straying: a kink of
/// the field (on a line through the cells' centres) is closed in on by up to a sixteenth
/// per cut rather than a half, which cuts the band of the docs into 32 points rather than
/// the 70 that halving made.
fn cut(seg: PathSeg, bends: &dyn Fn(&PathSeg) -> Option<f64>, depth: u32, out: &mut Vec<PathSeg>) {
    match (depth < MAX_DEPTH).then(|| bends(&seg)).flatten() {
        Some(s) => {
            cut(seg.subsegment(0.0..s), bends, depth + 1, out);
            cut(seg.subsegment(s..1.0), bends, depth + 1, out);
        }
        None => out.push(seg),
    }
}

fn push(out: &mut BezPath, seg: PathSeg) {
    match seg {
        PathSeg::Line(l) => out.line_to(l.p1),
        PathSeg::Quad(q) => out.quad_to(q.p1, q.p2),
        PathSeg::Cubic(c) => out.curve_to(c.p1, c.p2, c.p3),
    }
}

/// `seg` with every point (ends and handles) mapped by `f`.
fn map_seg(seg: &PathSeg, f: impl Fn(Point) -> Point) -> PathSeg {
    match *seg {
        PathSeg::Line(l) => PathSeg::Line(Line::new(f(l.p0), f(l.p1))),
        PathSeg::Quad(q) => PathSeg::Quad(QuadBez::new(f(q.p0), f(q.p1), f(q.p2))),
        PathSeg::Cubic(c) => PathSeg::Cubic(CubicBez::new(f(c.p0), f(c.p1), f(c.p2), f(c.p3))),
    }
}
