//! Per-vertex deformation as `<animate attributeName="d">`: the path, cut where the field
//! bends it ([`gmotion::motion::bend`]), is sampled (every point through
//! [`Track::deform`], as the frame writer does), and samples are kept where
//! linear interpolation of the points would stray more than the tolerance on the canvas.
//! Every value has the same commands, so browsers interpolate it point by point.

use std::borrow::Cow;
use std::fmt::Write;

use kurbo::{Affine, BezPath, PathEl, Point};

use super::xml::{COORD, num};
use gmotion::keyframe::Key;
use gmotion::keyframe::reduce::ramer_douglas_peucker;
use gmotion::keyframe::sample::{fraction, frame_times, sample_times};
use gmotion::motion::Track;

/// The keys of the path's `d` over `[0, dur]`, the path (`outline`, at each instant: a
/// morph's in-between changes, in one structure) in its own coordinates `abs` away from
/// the canvas and deformed by `tracks` (outermost first, applied innermost first). `None`
/// when `abs` is singular.
pub fn d_keys<'p>(
    outline: impl Fn(f64) -> Cow<'p, BezPath>,
    abs: Affine,
    tracks: &[&Track],
    dur: f64,
    rate: f64,
    fps: f64,
    tolerance: f64,
) -> Option<Vec<Key<String>>> {
    if abs.determinant().abs() <= 1e-12 {
        return None;
    }
    let back = abs.inverse();
    let mut extra = Vec::new();
    for s in tracks.iter().flat_map(|t| &t.motions) {
        let (x, y) = s.timing.active();
        extra.extend([s.t0, s.t1, x, y]);
    }
    let at_frames = frame_times(0.0, dur, fps);
    extra.extend(&at_frames);
    let ts = sample_times(0.0, dur, rate, 8, &extra);
    // The outline at every sample: a morph's in-between changes, a plain path does not.
    let outlines: Vec<Cow<'p, BezPath>> = ts.iter().map(|&t| outline(t)).collect();
    let first = outlines.first().cloned().unwrap_or_else(|| outline(0.0));
    let morphing = outlines.iter().any(|o| o.as_ref() != first.as_ref());
    // A plain path is cut where the field bends it at any frame (what players are judged
    // at; the samples between are several times as many, and the field moves little
    // between two frames): every value then has the same commands. A morphing outline is
    // not cut, as its cuts would differ from one in-between to the next.
    let path: Cow<BezPath> = match morphing {
        true => first,
        false => Cow::Owned(
            gmotion::motion::bend::refine(&first, abs, tracks, &at_frames, tolerance).into_owned(),
        ),
    };
    let frames: Vec<Vec<Point>> = ts
        .iter()
        .zip(&outlines)
        .map(|(&t, o)| {
            let drawn = if morphing { o.as_ref() } else { path.as_ref() };
            points(drawn)
                .into_iter()
                .map(|q| tracks.iter().rev().fold(abs * q, |c, tr| tr.deform(c, t)))
                .collect()
        })
        .collect();
    let keep = ramer_douglas_peucker(ts.len(), tolerance, |k, lo, hi| {
        let s = fraction(&ts, k, lo, hi);
        frames[k]
            .iter()
            .zip(frames[lo].iter().zip(&frames[hi]))
            .map(|(q, (a, b))| (a.lerp(*b, s) - *q).hypot())
            .fold(0.0, f64::max)
    });
    Some(
        keep.iter()
            .map(|&k| Key::linear(ts[k], path_data(&path, frames[k].iter().map(|&q| back * q))))
            .collect(),
    )
}

/// Every point of a path in order (control points included).
pub(super) fn points(path: &BezPath) -> Vec<Point> {
    let mut out = Vec::with_capacity(path.elements().len() * 3);
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) | PathEl::LineTo(p) => out.push(p),
            PathEl::QuadTo(a, b) => out.extend([a, b]),
            PathEl::CurveTo(a, b, c) => out.extend([a, b, c]),
            PathEl::ClosePath => {}
        }
    }
    out
}

/// The path's commands with its points replaced, in order, by `pts`.
pub(super) fn path_data(path: &BezPath, mut pts: impl Iterator<Item = Point>) -> String {
    let mut out = String::new();
    let mut pt = |out: &mut String| {
        let q = pts.next().unwrap_or_default();
        let _ = write!(out, "{} {}", num(q.x, COORD), num(q.y, COORD));
    };
    for (i, el) in path.elements().iter().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        match el {
            PathEl::MoveTo(_) => {
                out.push('M');
                pt(&mut out);
            }
            PathEl::LineTo(_) => {
                out.push('L');
                pt(&mut out);
            }
            PathEl::QuadTo(..) => {
                out.push('Q');
                pt(&mut out);
                out.push(' ');
                pt(&mut out);
            }
            PathEl::CurveTo(..) => {
                out.push('C');
                pt(&mut out);
                out.push(' ');
                pt(&mut out);
                out.push(' ');
                pt(&mut out);
            }
            PathEl::ClosePath => out.push('Z'),
        }
    }
    out
}
