//! Whether a looping animation ends where it starts: a picture whose last frame differs from
//! its first jumps ("pops") each time the animation starts over, which is almost always a
//! forgotten inverted twin.
//!
//! The picture is compared, not each shape: shapes of one tag that trade places (a road's
//! dashes scrolling by exactly one period, a carousel turning by one step) end in a picture
//! equal to the first, and shapes entirely off the canvas at both ends are not seen.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};

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
///
/// A shape pops when its first look (with its tag) is among the changed shapes' first
/// looks more often than among their last looks. The looks are not held: each shape's two
/// are hashed, the hashes sorted, and only shapes whose hashes meet are looked at again
/// to tell equal looks from a collision. Holding them (with their pairs and a map of
/// them) took 600 MB at 999 000 shapes, at the expansion's peak.
pub fn loop_warning(
    shapes: &[Shape],
    tracks: &[Track],
    duration: f64,
    canvas: Rect,
) -> Option<Warning> {
    let n = shapes.len().min(tracks.len());
    let look = |i: usize, at: f64| Look::of(&shapes[i], &tracks[i].state_at(at), canvas);
    let hash = |i: usize, look: &Look| {
        let mut h = std::hash::DefaultHasher::new();
        (shapes[i].tag.as_str(), look).hash(&mut h);
        h.finish()
    };
    // Each shape's ends, on the thread pool for a large scene (on one thread this pass
    // took 6 ms of a 25 ms run on 8214 shapes).
    let ends = |i: usize| {
        let (first, last) = (look(i, 0.0), look(i, duration));
        (first != last).then(|| Ends {
            first: hash(i, &first),
            last: hash(i, &last),
            visible: first.visible,
        })
    };
    let ends: Vec<Option<Ends>> = if n >= super::expand::PARALLEL_SHAPES {
        (0..n).into_par_iter().map(ends).collect()
    } else {
        (0..n).map(ends).collect()
    };
    // The changed shapes' visible first looks, and all their last looks, by hash.
    let mut meets: Vec<Meet> = Vec::new();
    for (i, end) in ends.iter().enumerate() {
        if let Some(end) = end {
            if end.visible {
                meets.push(Meet {
                    hash: end.first,
                    shape: i,
                    last: false,
                });
            }
            meets.push(Meet {
                hash: end.last,
                shape: i,
                last: true,
            });
        }
    }
    if meets.len() >= super::expand::PARALLEL_SHAPES {
        meets.par_sort_unstable_by_key(|m| m.hash);
    } else {
        meets.sort_unstable_by_key(|m| m.hash);
    }
    // The first looks that more first looks than last looks share, less the last looks
    // that cover them: only hashes that both kinds have are looked at again.
    let mut popped = vec![false; n];
    for run in meets.chunk_by(|a, b| a.hash == b.hash) {
        if run.iter().all(|m| !m.last) {
            run.iter().for_each(|m| popped[m.shape] = true);
            continue;
        }
        if run.iter().all(|m| m.last) {
            continue;
        }
        let looks: Vec<Look> = run
            .iter()
            .map(|m| look(m.shape, if m.last { duration } else { 0.0 }))
            .collect();
        let mut unmatched: HashMap<(&str, &Look), usize> = HashMap::new();
        for (m, l) in run.iter().zip(&looks).filter(|(m, _)| !m.last) {
            *unmatched
                .entry((shapes[m.shape].tag.as_str(), l))
                .or_default() += 1;
        }
        for (m, l) in run.iter().zip(&looks).filter(|(m, _)| m.last) {
            if let Some(k) = unmatched.get_mut(&(shapes[m.shape].tag.as_str(), l)) {
                *k = k.saturating_sub(1);
            }
        }
        for (m, l) in run.iter().zip(&looks).filter(|(m, _)| !m.last) {
            popped[m.shape] = unmatched
                .get(&(shapes[m.shape].tag.as_str(), l))
                .is_some_and(|&k| k > 0);
        }
    }
    drop(meets);
    drop(ends);
    // Only a changed shape's visible first look can have popped.
    let mut jumping = (0..n).filter(|&i| popped[i]);
    let i = jumping.next()?;
    let shape = &shapes[i];
    let name = format!("`{}` #{}", shape.tag, shape.id);
    let what = look(i, 0.0).difference(&look(i, duration));
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

/// A changed shape's two looks, hashed with its tag.
struct Ends {
    first: u64,
    last: u64,
    /// Whether any of its first look lies on the canvas.
    visible: bool,
}

/// A changed shape's first or last look, by its hash.
struct Meet {
    hash: u64,
    shape: usize,
    last: bool,
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
