//! Outlines cut where a per-vertex motion bends them (`lookup=vertex`).
//!
//! A vertex motion moves each point of an outline by the grid read at that point
//! ([`Track::deform`]). Writers move the outline's vertices and control points and let the
//! curve between them follow, which is exact only where the field is affine along the
//! segment: a rectangle's edge under a 12×1 grid would stay straight while the band should
//! wave. [`refine`] cuts each segment in halves (the same curve at rest, so nothing moves
//! until the field does) until the segment drawn through its moved points stays within
//! the tolerance of the exact field at every instant asked for, measured at every sixteenth
//! of each piece.

use kurbo::{Affine, BezPath, CubicBez, Line, ParamCurve, PathEl, PathSeg, Point, QuadBez};

use super::Track;

/// How many times a segment may be halved (a piece is then 1/256 of it).
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
    let bends = |seg: &PathSeg| {
        times.iter().any(|&t| {
            let drawn = map_seg(seg, |q| moved(q, t));
            (1..PROBES).any(|k| {
                let s = f64::from(k) / f64::from(PROBES);
                (drawn.eval(s) - moved(seg.eval(s), t)).hypot() > tolerance
            })
        })
    };
    if !path.segments().any(|s| bends(&s)) {
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

/// `seg` cut in halves while `bends` says so.
fn cut(seg: PathSeg, bends: &dyn Fn(&PathSeg) -> bool, depth: u32, out: &mut Vec<PathSeg>) {
    if depth < MAX_DEPTH && bends(&seg) {
        cut(seg.subsegment(0.0..0.5), bends, depth + 1, out);
        cut(seg.subsegment(0.5..1.0), bends, depth + 1, out);
    } else {
        out.push(seg);
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
