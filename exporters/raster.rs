//! Pixels: SVG text rendered with resvg on a transparent background, and PNG, GIF and
//! APNG files of the results. Every file is written whole or not at all
//! (see [`atomic`]).

use std::io::{self, Write};
use std::path::{Path, PathBuf};

pub use resvg::tiny_skia::Pixmap;
use resvg::tiny_skia::Transform;

use super::atomic;

/// Why rendering or writing pixels failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The SVG text could not be parsed (gmotion's own documents always parse; this
    /// guards text from elsewhere).
    #[error("cannot render the SVG: {0}")]
    Svg(String),
    /// The requested size is empty or too large for one image.
    #[error("cannot render a {width}x{height} px image")]
    Size {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// An animation needs at least one frame.
    #[error("no frames to write")]
    NoFrames,
    /// Animation frames must all have the first frame's size.
    #[error("frame {index} is {got:?} px, the first frame is {want:?} px")]
    FrameSize {
        /// The offending frame.
        index: usize,
        /// Its size.
        got: (u32, u32),
        /// The first frame's size.
        want: (u32, u32),
    },
    /// The frame rate is not a positive number.
    #[error("frame rate must be positive, got {0}")]
    Fps(f64),
    /// Encoding or writing the file failed; nothing was left at `path`.
    #[error("{}: {message}", path.display())]
    Write {
        /// The target file.
        path: PathBuf,
        /// What failed.
        message: String,
    },
}

/// Renders SVG text `width` pixels wide, the height following the document's aspect ratio
/// (rounded, at least 1 px), on a transparent background. No fonts are loaded: gmotion's
/// documents hold no text (the importer turns text into outlines), and other text elements
/// are not drawn.
pub fn render(svg: &str, width: u32) -> Result<Pixmap, RenderError> {
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default())
        .map_err(|e| RenderError::Svg(e.to_string()))?;
    let size = tree.size();
    let scale = width as f32 / size.width();
    let height = (size.height() * scale).round().max(1.0) as u32;
    let mut pixmap = Pixmap::new(width, height).ok_or(RenderError::Size { width, height })?;
    resvg::render(
        &tree,
        Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    Ok(pixmap)
}

fn write_error(path: &Path, e: impl std::fmt::Display) -> RenderError {
    RenderError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Writes a PNG (straight alpha, as PNG requires).
pub fn save_png(pixmap: &Pixmap, path: &Path) -> Result<(), RenderError> {
    let bytes = pixmap.encode_png().map_err(|e| write_error(path, e))?;
    atomic::write_bytes(path, &bytes).map_err(|e| write_error(path, e))
}

/// Checks that `frames` is a non-empty run of equally sized images and `fps` is usable.
fn check_frames(frames: &[Pixmap], fps: f64) -> Result<(u32, u32), RenderError> {
    if !(fps.is_finite() && fps > 0.0) {
        return Err(RenderError::Fps(fps));
    }
    let first = frames.first().ok_or(RenderError::NoFrames)?;
    let want = (first.width(), first.height());
    for (index, f) in frames.iter().enumerate() {
        let got = (f.width(), f.height());
        if got != want {
            return Err(RenderError::FrameSize { index, got, want });
        }
    }
    Ok(want)
}

/// The frame's pixels with straight alpha, as image formats store them.
fn straight_rgba(pixmap: &Pixmap) -> Vec<u8> {
    let mut out = Vec::with_capacity(pixmap.data().len());
    for p in pixmap.pixels() {
        let c = p.demultiply();
        out.extend_from_slice(&[c.red(), c.green(), c.blue(), c.alpha()]);
    }
    out
}

/// Writes an animated GIF: one palette of up to 256 colours per frame (NeuQuant when a
/// frame has more), alpha thresholded to fully transparent or opaque as GIF requires, and
/// a frame delay of `1/fps` rounded to GIF's 1/100 s (browsers slow delays under 2/100 s).
/// `looping` repeats forever, otherwise it plays once.
pub fn write_gif(
    frames: &[Pixmap],
    fps: f64,
    looping: bool,
    path: &Path,
) -> Result<(), RenderError> {
    let (w, h) = check_frames(frames, fps)?;
    let (w16, h16) = match (u16::try_from(w), u16::try_from(h)) {
        (Ok(w), Ok(h)) => (w, h),
        _ => {
            return Err(RenderError::Size {
                width: w,
                height: h,
            });
        }
    };
    let delay = (100.0 / fps).round().clamp(1.0, u16::MAX as f64) as u16;
    atomic::write_with(path, |out| -> io::Result<()> {
        let mut enc = gif::Encoder::new(out, w16, h16, &[]).map_err(io::Error::other)?;
        let repeat = if looping {
            gif::Repeat::Infinite
        } else {
            gif::Repeat::Finite(0)
        };
        enc.set_repeat(repeat).map_err(io::Error::other)?;
        for f in frames {
            let mut rgba = straight_rgba(f);
            let mut frame = gif::Frame::from_rgba_speed(w16, h16, &mut rgba, 10);
            frame.delay = delay;
            // Frames are whole pictures with transparency: clear before drawing the next.
            frame.dispose = gif::DisposalMethod::Background;
            enc.write_frame(&frame).map_err(io::Error::other)?;
        }
        drop(enc);
        Ok(())
    })
    .map_err(|e| write_error(path, e))
}

/// `1/fps` as the numerator and denominator APNG stores (exact for whole frame rates).
fn apng_delay(fps: f64) -> (u16, u16) {
    if fps.fract() == 0.0 && fps <= u16::MAX as f64 {
        (1, fps as u16)
    } else {
        (
            (1000.0 / fps).round().clamp(1.0, u16::MAX as f64) as u16,
            1000,
        )
    }
}

/// Writes an animated PNG with full alpha. `looping` repeats forever, otherwise it plays
/// once.
pub fn write_apng(
    frames: &[Pixmap],
    fps: f64,
    looping: bool,
    path: &Path,
) -> Result<(), RenderError> {
    let (w, h) = check_frames(frames, fps)?;
    let (num, den) = apng_delay(fps);
    atomic::write_with(path, |out| -> io::Result<()> {
        let mut enc = png::Encoder::new(&mut *out, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_animated(frames.len() as u32, if looping { 0 } else { 1 })
            .map_err(io::Error::other)?;
        enc.set_frame_delay(num, den).map_err(io::Error::other)?;
        let mut writer = enc.write_header().map_err(io::Error::other)?;
        for f in frames {
            writer
                .write_image_data(&straight_rgba(f))
                .map_err(io::Error::other)?;
        }
        writer.finish().map_err(io::Error::other)?;
        out.flush()
    })
    .map_err(|e| write_error(path, e))
}

/// The fraction of pixels (of the area both images cover) where some channel differs by
/// more than `tol`. Channels are compared premultiplied, as stored: that is the difference
/// a viewer sees over a black background, and it does not count colour noise in pixels
/// that are (nearly) transparent in both. Callers decide whether differing sizes matter.
pub fn compare(a: &Pixmap, b: &Pixmap, tol: u8) -> f64 {
    let (w, h) = (
        a.width().min(b.width()) as usize,
        a.height().min(b.height()) as usize,
    );
    if w == 0 || h == 0 {
        return 0.0;
    }
    let (aw, bw) = (a.width() as usize * 4, b.width() as usize * 4);
    let mut differing = 0usize;
    for y in 0..h {
        let ra = &a.data()[y * aw..y * aw + w * 4];
        let rb = &b.data()[y * bw..y * bw + w * 4];
        for (pa, pb) in ra.chunks_exact(4).zip(rb.chunks_exact(4)) {
            if pa.iter().zip(pb).any(|(x, y)| x.abs_diff(*y) > tol) {
                differing += 1;
            }
        }
    }
    differing as f64 / (w * h) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="20" height="10"><rect width="10" height="10" fill="#f00"/></svg>"##;

    #[test]
    fn render_scales_to_width_and_keeps_aspect() {
        let p = render(SQUARE, 40).unwrap();
        assert_eq!((p.width(), p.height()), (40, 20));
        let left = p.pixel(5, 10).unwrap();
        let right = p.pixel(35, 10).unwrap();
        assert_eq!((left.red(), left.alpha()), (255, 255));
        assert_eq!(right.alpha(), 0);
    }

    #[test]
    fn compare_counts_pixels_over_tolerance() {
        let a = render(SQUARE, 40).unwrap();
        let mut b = a.clone();
        assert_eq!(compare(&a, &b, 0), 0.0);
        // Repaint 8 of the 800 pixels slightly and 8 more strongly.
        for (i, px) in b.data_mut().chunks_exact_mut(4).take(16).enumerate() {
            let d = if i < 8 { 10 } else { 100 };
            px[3] = if px[3] >= 128 { px[3] - d } else { px[3] + d };
        }
        assert_eq!(compare(&a, &b, 0), 16.0 / 800.0);
        assert_eq!(compare(&a, &b, 32), 8.0 / 800.0);
    }

    fn frames() -> Vec<Pixmap> {
        ["#f00", "#0f0", "#00f"]
            .iter()
            .map(|c| {
                let svg = SQUARE.replace("#f00", c);
                render(&svg, 20).unwrap()
            })
            .collect()
    }

    fn temp(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("gmotion-raster-{}-{name}", std::process::id()))
    }

    #[test]
    fn apng_holds_every_frame_with_its_delay() {
        let path = temp("anim.png");
        write_apng(&frames(), 25.0, false, &path).unwrap();
        let mut dec =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()))
                .read_info()
                .unwrap();
        let actl = dec.info().animation_control().copied().unwrap();
        assert_eq!((actl.num_frames, actl.num_plays), (3, 1));
        let mut buf = vec![0; dec.output_buffer_size().unwrap()];
        for want in [[255, 0, 0], [0, 255, 0], [0, 0, 255]] {
            dec.next_frame(&mut buf).unwrap();
            let fctl = dec.info().frame_control().copied().unwrap();
            assert_eq!((fctl.delay_num, fctl.delay_den), (1, 25));
            // Pixel (2, 2) lies in the square: opaque and of the frame's colour.
            let px = &buf[(2 * 20 + 2) * 4..][..4];
            assert_eq!(px, [want[0], want[1], want[2], 255]);
        }
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn gif_holds_every_frame_with_transparency() {
        let path = temp("anim.gif");
        write_gif(&frames(), 20.0, true, &path).unwrap();
        let mut opts = gif::DecodeOptions::new();
        opts.set_color_output(gif::ColorOutput::RGBA);
        let mut dec = opts.read_info(std::fs::File::open(&path).unwrap()).unwrap();
        assert_eq!(dec.repeat(), gif::Repeat::Infinite);
        let mut seen = 0;
        while let Some(f) = dec.read_next_frame().unwrap() {
            assert_eq!(f.delay, 5);
            let inside = &f.buffer[(2 * 20 + 2) * 4..][..4];
            let outside = &f.buffer[(2 * 20 + 15) * 4..][..4];
            assert_eq!(inside[3], 255);
            assert_eq!(outside[3], 0);
            seen += 1;
        }
        assert_eq!(seen, 3);
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(matches!(render("<svg", 10), Err(RenderError::Svg(_))));
        let dir = std::env::temp_dir();
        assert!(matches!(
            write_gif(&[], 10.0, true, &dir.join("x.gif")),
            Err(RenderError::NoFrames)
        ));
        let frames = [Pixmap::new(2, 2).unwrap(), Pixmap::new(3, 2).unwrap()];
        assert!(matches!(
            write_apng(&frames, 10.0, true, &dir.join("x.png")),
            Err(RenderError::FrameSize { index: 1, .. })
        ));
    }
}
