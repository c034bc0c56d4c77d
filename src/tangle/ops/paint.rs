//! How a tangle shape is painted, and the decorative operators that change it: `fill(c)`
//! and `invert()` (gTangle sec. 4: decorative operators change only the appearance).

use crate::color::Color;
use crate::scene::{Fill, FillRule, LineCap, LineJoin, Paint as ScenePaint, PathNode, Stroke};

/// A tangle shape's paint: the parent path's fill and stroke, carried to every piece.
#[derive(Clone, Debug)]
pub struct Paint {
    /// Fill, if any.
    pub fill: Option<Fill>,
    /// Stroke, if any.
    pub stroke: Option<Stroke>,
    /// Whether the stroke is painted before the fill.
    pub stroke_first: bool,
}

/// Pen and paper: what gTangle draws with when a shape has no paint of its own.
const PAPER: Color = Color::WHITE;
const INK: Color = Color::BLACK;

fn solid(paint: &ScenePaint) -> Option<Color> {
    match paint {
        ScenePaint::Solid(c) => Some(*c),
        _ => None,
    }
}

fn plain_stroke(color: Color, width: f64) -> Stroke {
    Stroke {
        paint: ScenePaint::Solid(color),
        opacity: 1.0,
        width,
        cap: LineCap::Round,
        join: LineJoin::Round,
        miter_limit: 4.0,
        dash: None,
        dash_offset: 0.0,
    }
}

impl Paint {
    /// The paint of a path node.
    pub fn of(node: &PathNode) -> Paint {
        Paint {
            fill: node.fill.clone(),
            stroke: node.stroke.clone(),
            stroke_first: node.stroke_first,
        }
    }

    /// The fill colour (the first solid one; paper white when unfilled or not solid).
    pub fn fill_color(&self) -> Color {
        self.fill
            .as_ref()
            .and_then(|f| solid(&f.paint))
            .unwrap_or(PAPER)
    }

    /// The stroke colour (ink black when unstroked or not solid).
    pub fn stroke_color(&self) -> Color {
        self.stroke
            .as_ref()
            .and_then(|s| solid(&s.paint))
            .unwrap_or(INK)
    }

    /// The stroke width (1 when unstroked).
    pub fn stroke_width(&self) -> f64 {
        self.stroke.as_ref().map_or(1.0, |s| s.width)
    }

    /// `fill(c)`: the same paint with a solid fill of `color`.
    pub fn filled(&self, color: Color) -> Paint {
        let fill = Fill {
            paint: ScenePaint::Solid(color),
            opacity: self.fill.as_ref().map_or(1.0, |f| f.opacity),
            rule: FillRule::NonZero,
        };
        Paint {
            fill: Some(fill),
            ..self.clone()
        }
    }

    /// `invert()`: fill and stroke colours swapped (missing fill counts as white paper,
    /// missing stroke as black ink), so a white tile with black lines becomes a black tile
    /// with white lines.
    pub fn inverted(&self) -> Paint {
        let (fill, stroke) = (self.fill_color(), self.stroke_color());
        let mut out = self.filled(stroke);
        out.stroke = Some(match &self.stroke {
            Some(s) => Stroke {
                paint: ScenePaint::Solid(fill),
                ..s.clone()
            },
            None => plain_stroke(fill, 1.0),
        });
        out
    }

    /// Ink marks (stipples): filled with the stroke colour, not stroked.
    pub fn ink(&self) -> Paint {
        let fill = Fill {
            paint: ScenePaint::Solid(self.stroke_color()),
            opacity: 1.0,
            rule: FillRule::NonZero,
        };
        Paint {
            fill: Some(fill),
            stroke: None,
            stroke_first: false,
        }
    }

    /// A path node drawing `path` with this paint.
    pub fn node(&self, id: String, path: kurbo::BezPath, unit: usize) -> PathNode {
        PathNode {
            id,
            path,
            fill: self.fill.clone(),
            stroke: self.stroke.clone(),
            stroke_first: self.stroke_first,
            unit: Some(unit),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invert_swaps_and_twice_restores_colours() {
        let p = Paint {
            fill: None,
            stroke: Some(plain_stroke(Color::rgb(0.2, 0.3, 0.4), 2.0)),
            stroke_first: false,
        };
        let i = p.inverted();
        assert_eq!(i.fill_color(), Color::rgb(0.2, 0.3, 0.4));
        assert_eq!(i.stroke_color(), Color::WHITE);
        assert_eq!(i.stroke_width(), 2.0);
        let back = i.inverted();
        assert_eq!(back.fill_color(), Color::WHITE);
        assert_eq!(back.stroke_color(), Color::rgb(0.2, 0.3, 0.4));
        assert_eq!(p.filled(Color::BLACK).fill_color(), Color::BLACK);
        assert_eq!(p.ink().fill_color(), Color::rgb(0.2, 0.3, 0.4));
        assert!(p.ink().stroke.is_none());
    }
}
