//! Whether a looping animation ends where it starts: a shape whose last frame differs from
//! its first jumps ("pops") each time the animation starts over, which is almost always a
//! forgotten inverted twin.

use kurbo::Point;

use crate::motion::{ShapeState, Tint, Track};
use crate::scene::Shape;
use crate::warning::Warning;

/// How far (canvas pixels) a corner of a shape's box may be from where it started.
const MOVED: f64 = 0.5;

/// How much a colour channel, opacity or stroke width factor may differ (about 1/255).
const CHANGED: f64 = 0.004;

/// A warning naming the shapes whose `tracks` (one per shape, over `duration` seconds) do
/// not end as they start, or `None` when every shape closes its loop.
pub fn loop_warning(shapes: &[Shape], tracks: &[Track], duration: f64) -> Option<Warning> {
    let mut jumping = tracks.iter().zip(shapes).filter_map(|(track, shape)| {
        let (a, b) = (track.state_at(0.0), track.state_at(duration));
        jump(&a, &b, shape.bbox).map(|what| (shape, what))
    });
    let (first, what) = jumping.next()?;
    let name = format!("`{}` #{}", first.tag, first.id);
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

/// What differs between the first state `a` and the last `b` of a shape with box `bbox`.
fn jump(a: &ShapeState, b: &ShapeState, bbox: kurbo::Rect) -> Option<String> {
    let corners = [
        Point::new(bbox.x0, bbox.y0),
        Point::new(bbox.x1, bbox.y0),
        Point::new(bbox.x0, bbox.y1),
        Point::new(bbox.x1, bbox.y1),
    ];
    let moved = corners
        .iter()
        .map(|&p| (a.transform * p).distance(b.transform * p))
        .fold(0.0, f64::max);
    if moved > MOVED {
        return Some(format!("{moved:.1} px away"));
    }
    let tint = |x: &Tint, y: &Tint| {
        (f64::from(x.weight) - f64::from(y.weight)).abs() > CHANGED
            || x.sum
                .iter()
                .zip(y.sum)
                .any(|(p, q)| f64::from(p - q).abs() > CHANGED)
    };
    if tint(&a.fill, &b.fill) || tint(&a.stroke, &b.stroke) {
        return Some("another colour".into());
    }
    if (a.opacity - b.opacity).abs() > CHANGED {
        return Some(format!("opacity {:.2}, not {:.2}", b.opacity, a.opacity));
    }
    if (a.stroke_width - b.stroke_width).abs() > CHANGED {
        return Some("another stroke width".into());
    }
    None
}
