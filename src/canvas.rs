//! The size of what gmotion writes: the `width` and `height` directives (and the
//! command line's `--width`/`--height`) ask for an output size, and [`OutputSize::fit`]
//! says where the scene's canvas lands in it. Every exporter sizes its output this way.

use kurbo::Vec2;

/// The largest side, in pixels, of an output gmotion writes.
pub const MAX_OUTPUT_SIZE: u32 = 16_384;

/// The pixel size asked of an output (the `width` and `height` directives, `--width` and
/// `--height`): a width, a height, both or neither.
///
/// - Neither: the output has the scene's own size (see [`OutputSize::fit`]).
/// - One side: the output has that side, the other follows the scene's aspect ratio
///   (rounded, at least 1 px), and the art is scaled by the given side's ratio.
/// - Both: the output has exactly that size; the art is scaled uniformly to fit inside it
///   and centred (SVG's default `xMidYMid meet`), leaving transparent bands on two sides
///   when the aspect ratios differ.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OutputSize {
    /// Width in pixels.
    pub width: Option<u32>,
    /// Height in pixels.
    pub height: Option<u32>,
}

/// Where the scene's canvas lands in an output: output pixel `offset + scale · p` shows
/// canvas point `p`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// Output width in pixels.
    pub width: u32,
    /// Output height in pixels.
    pub height: u32,
    /// Output pixels per canvas unit (the same on both axes: art is never stretched).
    pub scale: f64,
    /// Where the canvas origin lands, in output pixels.
    pub offset: Vec2,
}

impl OutputSize {
    /// How a canvas of `width` × `height` units fits this size; `None` when no size is
    /// asked for or the canvas is empty or not finite (each exporter then writes the
    /// scene's own size, as it always has).
    pub fn fit(self, width: f64, height: f64) -> Option<Fit> {
        if !(width.is_finite() && height.is_finite() && width > 0.0 && height > 0.0) {
            return None;
        }
        let follow = |v: f64| v.round().clamp(1.0, f64::from(u32::MAX)) as u32;
        let (w, h, scale) = match (self.width, self.height) {
            (None, None) => return None,
            (Some(w), None) => {
                let k = f64::from(w) / width;
                (w, follow(height * k), k)
            }
            (None, Some(h)) => {
                let k = f64::from(h) / height;
                (follow(width * k), h, k)
            }
            (Some(w), Some(h)) => (w, h, (f64::from(w) / width).min(f64::from(h) / height)),
        };
        let offset = Vec2::new(
            (f64::from(w) - width * scale) / 2.0,
            (f64::from(h) - height * scale) / 2.0,
        );
        // With one side given the art fills the output exactly up to the rounding of the
        // other side: no centring, so that side's last row or column is not split.
        let offset = if self.width.is_some() && self.height.is_some() {
            offset
        } else {
            Vec2::ZERO
        };
        Some(Fit {
            width: w,
            height: h,
            scale,
            offset,
        })
    }
}
