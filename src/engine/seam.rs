//! Whether a looping animation ends where it starts: a picture whose last frame differs from
//! its first jumps ("pops") each time the animation starts over, which is almost always a
//! forgotten inverted twin.
//!
//! The picture is compared, not each shape: shapes of one tag that trade places (a road's
//! dashes scrolling by exactly one period, a carousel turning by one step) end in a picture
//! equal to the first, and shapes entirely off the canvas at both ends are not seen.

use std::collections::HashMap;

use kurbo::{Point, Rect};
use rayon::prelude::*;

use crate::motion::{ShapeState, Track, Trim};
use crate::scene::Shape;
use crate::warning::Warning;

/// The grid (canvas pixels) corners are compared on: much finer than a visible jump,
/// much coarser than rounding noise.
const GRID: f64 = 0.05;

/// The grid colour channels, opacity and stroke-width factors are compared on (1/255).
const LEVEL: f64 = 1.0 / 255.0;

/// A warning naming a shape of the looping animation `tracks` (one per shape of `shapes`,
/// over `duration` seconds, on a canvas `canvas`) whose first frame is not in the last
/// frame's picture, or `None` when the loop closes.
pub fn loop_warning(
    shapes: &[Shape],
    tracks: &[Track],
    duration: f64,
    canvas: Rect,
) -> Option<Warning> {
    // What each shape looks like at both ends, when it changed at all: on the thread pool
    // for a large scene (on one thread this pass took 6 ms of a 25 ms run on 8214 shapes).
    let ends = |(i, (track, shape)): (usize, (&Track, &Shape))| {
        let (a, b) = (track.state_at(0.0), track.state_at(duration));
        let (first, last) = (Look::of(shape, &a, canvas), Look::of(shape, &b, canvas));
        (first != last).then_some((i, first, last))
    };
    let changed: Vec<(usize, Look, Look)> = if shapes.len() >= super::expand::PARALLEL_SHAPES {
        tracks
            .par_iter()
            .zip(shapes)
            .enumerate()
            .filter_map(ends)
            .collect()
    } else {
        tracks
            .iter()
            .zip(shapes)
            .enumerate()
            .filter_map(ends)
            .collect()
    };
    // The changed shapes' first looks, less the last looks that cover them.
    let mut unmatched: HashMap<(&str, &Look), usize> = HashMap::new();
    for (i, first, _) in &changed {
        if first.visible {
            *unmatched
                .entry((shapes[*i].tag.as_str(), first))
                .or_default() += 1;
        }
    }
    for (i, _, last) in &changed {
        if let Some(n) = unmatched.get_mut(&(shapes[*i].tag.as_str(), last)) {
            *n = n.saturating_sub(1);
        }
    }
    let popped = |first: &Look, i: usize| {
        unmatched
            .get(&(shapes[i].tag.as_str(), first))
            .is_some_and(|&n| n > 0)
    };
    let mut jumping = changed
        .iter()
        .filter(|(i, first, _)| first.visible && popped(first, *i));
    let &(i, ref first, ref last) = jumping.next()?;
    let shape = &shapes[i];
    let name = format!("`{}` #{}", shape.tag, shape.id);
    let what = first.difference(last);
    let shapes = match jumping.count() {
        0 => format!("{name} ends where it did not start ({what}), so it jumps"),
        n => format!(
            "{name} and {n} other shape{} end where they did not start ({name}: {what}), so they jump",
            if n == 1 { "" } else { "s" }
        ),
    };
    Some(Warning::new(format!(
        "the animation loops, but {shapes} when the animation starts over; end each change with its inverted twin (`[a, inv_a]`) or write `loop false`"
    )))
}

/// A shape's look at one instant, on grids: its box's corners, colours, opacity, width,
/// trim.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct Look {
    corners: [(i64, i64); 4],
    paint: [i64; 13],
    /// Whether any of it lies on the canvas.
    visible: bool,
}

impl Look {
    fn of(shape: &Shape, state: &ShapeState, canvas: Rect) -> Look {
        let b = shape.bbox;
        let points = [(b.x0, b.y0), (b.x1, b.y0), (b.x0, b.y1), (b.x1, b.y1)]
            .map(|(x, y)| state.transform * Point::new(x, y));
        let on = |v: f64| (v / GRID).round() as i64;
        let level = |v: f64| (v / LEVEL).round() as i64;
        let (f, s) = (&state.fill, &state.stroke);
        // A whole stroke looks the same however far it is shifted, and an empty one
        // wherever it is empty.
        let trim = if state.trim.is_whole() {
            Trim::REST
        } else if state.trim.is_empty() {
            Trim {
                start: 0.0,
                end: 0.0,
                shift: 0.0,
            }
        } else {
            state.trim
        };
        let seen = points
            .iter()
            .fold(Rect::from_points(points[0], points[0]), |r, p| {
                r.union_pt(*p)
            });
        Look {
            corners: points.map(|p| (on(p.x), on(p.y))),
            paint: [
                level(f64::from(f.weight)),
                level(f64::from(f.sum[0])),
                level(f64::from(f.sum[1])),
                level(f64::from(f.sum[2])),
                level(f64::from(s.weight)),
                level(f64::from(s.sum[0])),
                level(f64::from(s.sum[1])),
                level(f64::from(s.sum[2])),
                level(state.opacity),
                level(state.stroke_width),
                level(trim.start),
                level(trim.end),
                level(trim.shift.rem_euclid(1.0)),
            ],
            visible: state.opacity > 0.0 && seen.overlaps(canvas),
        }
    }

    /// How `last` differs from `self`, in words.
    fn difference(&self, last: &Look) -> String {
        if self.corners != last.corners {
            let moved = (self.corners.iter().zip(&last.corners))
                .map(|(a, b)| ((a.0 - b.0) as f64 * GRID).hypot((a.1 - b.1) as f64 * GRID))
                .fold(0.0, f64::max);
            return format!("{moved:.1} px away");
        }
        if self.paint[..8] != last.paint[..8] {
            return "another colour".into();
        }
        if self.paint[8] != last.paint[8] {
            return format!(
                "opacity {:.2}, not {:.2}",
                last.paint[8] as f64 * LEVEL,
                self.paint[8] as f64 * LEVEL
            );
        }
        if self.paint[9] != last.paint[9] {
            return "another stroke width".into();
        }
        "another visible part of the stroke (trim)".into()
    }
}
