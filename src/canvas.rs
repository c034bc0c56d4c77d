//! The size and length of what gmotion writes: one rule every output follows, so that a
//! PNG, a GIF, a video, a Lottie, a dotLottie, an animated SVG and the HTML preview of the
//! same animation are the same number of pixels and end at the same instant.
//!
//! **Size.** The `width` and `height` directives (and `--width`/`--height`) ask for an
//! output size ([`OutputSize`]); [`OutputSize::fit`] says how many whole pixels the output
//! has and where the scene's canvas lands in it ([`Fit`]). A side the output takes from the
//! canvas is the canvas's side times the scale, rounded half up ([`pixels`]); the art is
//! scaled by exactly the asked side over the canvas's (1 when no side is asked), as
//! browsers and resvg draw an SVG at a given width, never fitted into a rounded side.
//!
//! **Length.** A duration that is not a whole number of frames is rounded to the nearest
//! whole number of frames, half up ([`frames`]), and every output lasts that many frames
//! ([`length`]): a Lottie's `op`, an SVG's `dur`, a GIF's delays, a video's frames. What
//! the animation does at each instant does not change; only where it ends.

use kurbo::{Rect, Size, Vec2};

/// The largest side, in pixels, of an output gmotion writes.
pub const MAX_OUTPUT_SIZE: u32 = 16_384;

/// The pixel size asked of an output (the `width` and `height` directives, `--width` and
/// `--height`): a width, a height, both or neither.
///
/// - Neither: the output has the scene's own size, each side rounded half up (at least
///   1 px), and the art its own size (scale 1).
/// - One side: the output has that side, the other is the canvas's other side times the
///   scale, rounded the same way, and the art is scaled by exactly the given side over the
///   canvas's.
/// - Both: the output has exactly that size; the art is scaled uniformly to fit inside it
///   and centred (SVG's default `xMidYMid meet`), leaving transparent bands on two sides
///   when the aspect ratios differ.
///
/// With neither or one side, the art starts at the output's top left corner: the last
/// row or column of pixels shows the rest of the canvas, cut or padded by less than half a
/// pixel.
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
    /// The canvas, in its own units.
    pub canvas: Size,
}

/// Whole output pixels for a side of `v` pixels: rounded half up, at least 1 (and at most
/// `u32::MAX`; the callers bound sizes far below it).
pub fn pixels(v: f64) -> u32 {
    // `round` takes halves away from zero, which is up for the positive sides measured
    // here; NaN saturates to 0 and is lifted to 1 like any side under half a pixel.
    (v.round().clamp(0.0, f64::from(u32::MAX)) as u32).max(1)
}

/// The number of frames an animation of `duration` seconds has at `fps` frames a second:
/// the nearest whole number, half up, at least 1. Frame `i` shows time `i / fps`.
///
/// The nearest (rather than the next) whole number keeps every output within half a frame
/// of the duration asked for, and keeps a Lottie's own length whole where After Effects
/// wrote it with float noise (`op` 177.0000072 at 29.97 fps is 177 frames, not 178).
pub fn frames(duration: f64, fps: f64) -> usize {
    // A millionth of a frame decides halves that decimal durations miss in binary
    // (0.35 s · 30 fps is 10.499999999999998): they round up, as written.
    let n = (duration * fps + 1e-6).round();
    if n >= 1.0 {
        n.min(usize::MAX as f64) as usize
    } else {
        1
    }
}

/// How long every output of an animation of `duration` seconds at `fps` lasts, in
/// seconds: its [`frames`] over the rate.
pub fn length(duration: f64, fps: f64) -> f64 {
    frames(duration, fps) as f64 / fps
}

impl OutputSize {
    /// Whether a side is asked for at all.
    pub fn is_given(self) -> bool {
        self.width.is_some() || self.height.is_some()
    }

    /// How a canvas of `width` × `height` units lands in an output of this size (the
    /// canvas's own, rounded, when no side is asked for); `None` when the canvas is empty or
    /// not finite.
    pub fn fit(self, width: f64, height: f64) -> Option<Fit> {
        if !(width.is_finite() && height.is_finite() && width > 0.0 && height > 0.0) {
            return None;
        }
        let (w, h, scale) = match (self.width, self.height) {
            (None, None) => (pixels(width), pixels(height), 1.0),
            (Some(w), None) => {
                let k = f64::from(w) / width;
                (w, pixels(height * k), k)
            }
            (None, Some(h)) => {
                let k = f64::from(h) / height;
                (pixels(width * k), h, k)
            }
            (Some(w), Some(h)) => (w, h, (f64::from(w) / width).min(f64::from(h) / height)),
        };
        // With both sides given the art is centred in them. Otherwise it fills the output
        // up to the rounding of a side: no centring, so that side's last row or column is
        // not split.
        let offset = if self.width.is_some() && self.height.is_some() {
            Vec2::new(
                (f64::from(w) - width * scale) / 2.0,
                (f64::from(h) - height * scale) / 2.0,
            )
        } else {
            Vec2::ZERO
        };
        Some(Fit {
            width: w,
            height: h,
            scale,
            offset,
            canvas: Size::new(width, height),
        })
    }
}

impl Fit {
    /// Whether the output is the canvas itself: its own whole size, at scale 1, from the
    /// origin (an output of it needs no resizing).
    pub fn is_canvas(&self) -> bool {
        self.scale == 1.0
            && self.offset == Vec2::ZERO
            && f64::from(self.width) == self.canvas.width
            && f64::from(self.height) == self.canvas.height
    }

    /// The output's pixels in canvas units: what an SVG's `viewBox` says to show this fit
    /// at the output's `width` × `height`.
    pub fn view_box(&self) -> Rect {
        let k = self.scale;
        Rect::new(
            -self.offset.x / k,
            -self.offset.y / k,
            (f64::from(self.width) - self.offset.x) / k,
            (f64::from(self.height) - self.offset.y) / k,
        )
    }

    /// Whether an SVG viewer showing the canvas's own `viewBox` at the output's size (by
    /// SVG's default `xMidYMid meet`) draws it as this fit does: always with both sides
    /// given, and otherwise when a rounded side is exact.
    pub fn is_meet(&self) -> bool {
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let (cw, ch) = (self.canvas.width, self.canvas.height);
        let k = (w / cw).min(h / ch);
        let at = Vec2::new((w - cw * k) / 2.0, (h - ch * k) / 2.0);
        let near = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0);
        near(k, self.scale) && near(at.x, self.offset.x) && near(at.y, self.offset.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NONE: OutputSize = OutputSize {
        width: None,
        height: None,
    };

    #[test]
    fn a_fractional_canvas_rounds_each_side_half_up_at_its_own_scale() {
        let fit = NONE.fit(567.4, 283.6).unwrap();
        assert_eq!((fit.width, fit.height, fit.scale), (567, 284, 1.0));
        assert_eq!(fit.offset, Vec2::ZERO);
        assert!(!fit.is_canvas() && !fit.is_meet());
        assert_eq!(fit.view_box(), Rect::new(0.0, 0.0, 567.0, 284.0));
        let half = NONE.fit(10.5, 0.2).unwrap();
        assert_eq!((half.width, half.height), (11, 1));
        let whole = NONE.fit(480.0, 220.0).unwrap();
        assert!(whole.is_canvas() && whole.is_meet());
    }

    #[test]
    fn one_side_scales_by_exactly_its_ratio() {
        // A wide logo: 100.9 · 0.5 = 50.45 rounds down, and the art keeps the scale 0.5
        // rather than shrinking into 50 rows (0.4955).
        let fit = OutputSize {
            width: Some(500),
            height: None,
        }
        .fit(1000.0, 100.9)
        .unwrap();
        assert_eq!((fit.width, fit.height, fit.scale), (500, 50, 0.5));
        assert!(!fit.is_meet());
        let vb = fit.view_box();
        assert_eq!((vb.x0, vb.y0, vb.x1, vb.y1), (0.0, 0.0, 1000.0, 100.0));
        let tall = OutputSize {
            width: None,
            height: Some(300),
        }
        .fit(200.0, 100.0)
        .unwrap();
        assert_eq!((tall.width, tall.height, tall.scale), (600, 300, 3.0));
        assert!(tall.is_meet());
    }

    #[test]
    fn both_sides_centre_the_art_as_svg_does() {
        let fit = OutputSize {
            width: Some(200),
            height: Some(200),
        }
        .fit(400.0, 100.0)
        .unwrap();
        assert_eq!((fit.scale, fit.offset), (0.5, Vec2::new(0.0, 75.0)));
        assert!(fit.is_meet());
        assert_eq!(fit.view_box(), Rect::new(0.0, -150.0, 400.0, 250.0));
    }

    #[test]
    fn frames_are_the_nearest_whole_number_half_up() {
        assert_eq!(frames(1.05, 30.0), 32);
        assert_eq!(frames(0.35, 30.0), 11);
        assert_eq!(frames(1.01, 30.0), 30);
        assert_eq!(frames(2.0, 30.0), 60);
        assert_eq!(frames(2.4, 25.0), 60);
        assert_eq!(
            frames(
                177.000_007_209_358 / 29.970_001_220_703_1,
                29.970_001_220_703_1
            ),
            177
        );
        assert_eq!(frames(0.001, 30.0), 1);
        assert_eq!(frames(f64::NAN, 30.0), 1);
        assert_eq!(length(1.05, 30.0), 32.0 / 30.0);
    }
}
