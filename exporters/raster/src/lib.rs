//! Pixels: SVG text rendered with resvg on a transparent background, and PNG, GIF and
//! APNG files of the results. Every file is written whole or not at all
//! (see [`atomic`]).

use std::io::{self, Write};
use std::path::{Path, PathBuf};

pub use resvg::tiny_skia::Pixmap;
use resvg::tiny_skia::Transform;

use gmotion::atomic;
use gmotion::canvas::{Fit, OutputSize};

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
    /// Something in the picture lies farther from the output's origin than the rasteriser's
    /// fixed-point arithmetic reaches ([`MAX_DRAWN_COORD`]): a huge stroke width, scale or
    /// coordinate. Nothing was drawn; drawing it would crash inside tiny-skia.
    #[error(
        "a {what} reaches {extent:.3e} px from the output's origin; the renderer draws within ±{:.0e} px (a stroke width, scale or coordinate too large to draw)",
        MAX_DRAWN_COORD
    )]
    OutOfRange {
        /// What reaches that far: `path`, `stroked path`, `clip path` ….
        what: &'static str,
        /// How far, in output pixels (infinite or NaN for non-finite geometry).
        extent: f64,
    },
    /// The image would hold more pixels than allowed (see [`check_pixels`]).
    #[error(
        "a {width}x{height} px image has {} pixels, more than the limit of {limit} (raise it with --limit pixels=N)",
        u64::from(*width) * u64::from(*height)
    )]
    TooManyPixels {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// The limit.
        limit: u64,
    },
    /// A raster image in the picture declares more pixels than one rendered image may
    /// hold; resvg would allocate them all to decode it. The importers drop such images
    /// (`--limit image-pixels`); this guards SVG text from elsewhere.
    #[error(
        "an embedded raster image declares {width}x{height} px, more than the limit of {limit} pixels (raise it with --limit pixels=N)"
    )]
    ImageTooLarge {
        /// Declared width in pixels.
        width: u64,
        /// Declared height in pixels.
        height: u64,
        /// The limit.
        limit: u64,
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
    /// A frames folder holds files that are not gmotion frames; nothing was written.
    #[error(
        "{}: the folder holds files that are not gmotion frames ({}); write frames to a new or empty folder, or to one holding only frame_NNNNN.png files",
        path.display(),
        others.join(", ")
    )]
    FolderInUse {
        /// The folder.
        path: PathBuf,
        /// Some of the other entries' names (at most three, then `…`).
        others: Vec<String>,
    },
    /// Encoding or writing the file failed; nothing was left at `path`.
    #[error("{}: {source}", path.display())]
    Write {
        /// The target file.
        path: PathBuf,
        /// What failed.
        #[source]
        source: io::Error,
    },
}

/// Renders SVG text `width` pixels wide, the height following the document's aspect ratio
/// (rounded, at least 1 px), on a transparent background. No fonts are loaded: gmotion's
/// documents hold no text (the importer turns text into outlines), and other text elements
/// are not drawn.
pub fn render(svg: &str, width: u32) -> Result<Pixmap, RenderError> {
    render_sized(
        svg,
        OutputSize {
            width: Some(width),
            height: None,
        },
    )
}

/// Renders SVG text at `size` (see [`OutputSize`]: one side keeps the aspect ratio, both
/// fit the art inside and centre it; neither is the document's own size, each side rounded
/// half up), on a transparent background, like [`render`].
pub fn render_sized(svg: &str, size: OutputSize) -> Result<Pixmap, RenderError> {
    render_limited(svg, size, DEFAULT_MAX_PIXELS)
}

/// [`render_sized`] refusing an image of more than `max_pixels` pixels
/// ([`RenderError::TooManyPixels`]) before allocating it.
pub fn render_limited(svg: &str, size: OutputSize, max_pixels: u64) -> Result<Pixmap, RenderError> {
    let tree = parse(svg)?;
    let fit = size
        .fit(
            f64::from(tree.size().width()),
            f64::from(tree.size().height()),
        )
        .ok_or(RenderError::Size {
            width: 0,
            height: 0,
        })?;
    draw(&tree, &fit, max_pixels)
}

/// Renders SVG text as `fit` places its canvas (`fit.canvas` the document's size, which
/// the caller knows more exactly than the document's `f32` numbers say), refusing an image
/// of more than `max_pixels` pixels: how every frame of an animation is drawn, sized by the
/// one rule of [`gmotion::canvas`] that its Lottie and SVG outputs follow too.
pub fn render_fit(svg: &str, fit: &Fit, max_pixels: u64) -> Result<Pixmap, RenderError> {
    draw(&parse(svg)?, fit, max_pixels)
}

fn parse(svg: &str) -> Result<usvg::Tree, RenderError> {
    usvg::Tree::from_str(svg, &usvg::Options::default())
        .map_err(|e| RenderError::Svg(e.to_string()))
}

fn draw(tree: &usvg::Tree, fit: &Fit, max_pixels: u64) -> Result<Pixmap, RenderError> {
    let (width, height) = (fit.width, fit.height);
    check_pixels(width, height, max_pixels)?;
    check_drawable(tree, fit.scale, fit.offset.x, fit.offset.y)?;
    check_images(tree.root(), max_pixels)?;
    let mut pixmap = Pixmap::new(width, height).ok_or(RenderError::Size { width, height })?;
    let scale = fit.scale as f32;
    resvg::render(
        tree,
        Transform::from_row(
            scale,
            0.0,
            0.0,
            scale,
            fit.offset.x as f32,
            fit.offset.y as f32,
        ),
        &mut pixmap.as_mut(),
    );
    Ok(pixmap)
}

/// The farthest, in output pixels, that anything drawn may reach from the output's origin.
///
/// tiny-skia supersamples anti-aliased paths in 32-bit fixed point and panics (or indexes
/// past its buffers) on a path whose bounds reach about 5·10⁸ px (`stroke-width="1e10"`,
/// `scale(1e10)` on a stroked shape). Every path of a picture, stroke included, clip paths
/// and masks too, is checked against this bound before anything is drawn.
pub const MAX_DRAWN_COORD: f64 = 1e8;

/// Checks that every path of `tree`, mapped to output pixels by `scale` and `(dx, dy)`,
/// lies within [`MAX_DRAWN_COORD`] of the origin (see [`RenderError::OutOfRange`]).
pub fn check_drawable(tree: &usvg::Tree, scale: f64, dx: f64, dy: f64) -> Result<(), RenderError> {
    fn reach(r: usvg::Rect, scale: f64, dx: f64, dy: f64) -> f64 {
        let xs = [f64::from(r.left()), f64::from(r.right())];
        let ys = [f64::from(r.top()), f64::from(r.bottom())];
        let x = xs
            .iter()
            .map(|x| (x * scale + dx).abs())
            .fold(0.0, f64::max);
        let y = ys
            .iter()
            .map(|y| (y * scale + dy).abs())
            .fold(0.0, f64::max);
        let all = xs.iter().chain(&ys);
        if all.clone().any(|v| !v.is_finite()) {
            return f64::INFINITY;
        }
        x.max(y)
    }
    fn group(g: &usvg::Group, scale: f64, dx: f64, dy: f64, sub: bool) -> Result<(), RenderError> {
        for node in g.children() {
            if let usvg::Node::Path(p) = node {
                let stroked = p.stroke().is_some();
                let extent = reach(p.abs_stroke_bounding_box(), scale, dx, dy);
                if extent.is_nan() || extent > MAX_DRAWN_COORD {
                    let what = match (sub, stroked) {
                        (true, _) => "path inside a clip path, mask or pattern",
                        (false, true) => "stroked path",
                        (false, false) => "path",
                    };
                    return Err(RenderError::OutOfRange { what, extent });
                }
            }
            if let usvg::Node::Group(h) = node {
                group(h, scale, dx, dy, sub)?;
            }
            let mut found = Ok(());
            node.subroots(|s| {
                if found.is_ok() {
                    found = group(s, scale, dx, dy, true);
                }
            });
            found?;
        }
        Ok(())
    }
    group(tree.root(), scale, dx, dy, false)
}

/// Checks that every raster image in `g` (clip paths, masks, patterns, filters and nested
/// SVG images included) declares at most `limit` pixels ([`RenderError::ImageTooLarge`]).
fn check_images(g: &usvg::Group, limit: u64) -> Result<(), RenderError> {
    for node in g.children() {
        match node {
            usvg::Node::Group(h) => check_images(h, limit)?,
            usvg::Node::Image(i) => match i.kind() {
                usvg::ImageKind::PNG(d)
                | usvg::ImageKind::JPEG(d)
                | usvg::ImageKind::GIF(d)
                | usvg::ImageKind::WEBP(d) => {
                    if let Some((width, height)) = gmotion::scene::image_pixel_size(d)
                        && width.saturating_mul(height) > limit
                    {
                        return Err(RenderError::ImageTooLarge {
                            width,
                            height,
                            limit,
                        });
                    }
                }
                usvg::ImageKind::SVG(tree) => check_images(tree.root(), limit)?,
            },
            usvg::Node::Path(_) | usvg::Node::Text(_) => {}
        }
        let mut found = Ok(());
        node.subroots(|s| {
            if found.is_ok() {
                found = check_images(s, limit);
            }
        });
        found?;
    }
    Ok(())
}

/// The default largest number of pixels of one image: 2²⁶ (8192 × 8192, 256 MiB of RGBA).
pub const DEFAULT_MAX_PIXELS: u64 = 1 << 26;

/// Checks that a `width` × `height` image holds at most `limit` pixels.
pub fn check_pixels(width: u32, height: u32, limit: u64) -> Result<(), RenderError> {
    if u64::from(width) * u64::from(height) > limit {
        return Err(RenderError::TooManyPixels {
            width,
            height,
            limit,
        });
    }
    Ok(())
}

fn write_error(path: &Path, source: io::Error) -> RenderError {
    RenderError::Write {
        path: path.to_path_buf(),
        source,
    }
}

/// Writes a PNG (straight alpha, as PNG requires).
pub fn save_png(pixmap: &Pixmap, path: &Path) -> Result<(), RenderError> {
    let bytes = png_bytes(pixmap, path)?;
    atomic::write_bytes(path, &bytes).map_err(|e| write_error(path, e))
}

/// The PNG [`save_png`] writes, in memory (`path` is named in errors).
pub fn png_bytes(pixmap: &Pixmap, path: &Path) -> Result<Vec<u8>, RenderError> {
    pixmap
        .encode_png()
        .map_err(|e| write_error(path, io::Error::other(e)))
}

/// A rendered animation, as an animated GIF or PNG holds it: its frames, shown `fps` a
/// second, repeating forever when `looping`, else played once.
#[derive(Clone, Copy, Debug)]
pub struct Frames<'a> {
    /// The frames in order, all of one size.
    pub frames: &'a [Pixmap],
    /// Frames per second.
    pub fps: f64,
    /// Whether the animation repeats.
    pub looping: bool,
}

impl Frames<'_> {
    /// The frames' size, once checked that they are a non-empty run of equally sized
    /// images and `fps` is usable.
    fn size(&self) -> Result<(u32, u32), RenderError> {
        let fps = self.fps;
        if !(fps.is_finite() && fps > 0.0) {
            return Err(RenderError::Fps(fps));
        }
        let first = self.frames.first().ok_or(RenderError::NoFrames)?;
        let want = (first.width(), first.height());
        for (index, f) in self.frames.iter().enumerate() {
            let got = (f.width(), f.height());
            if got != want {
                return Err(RenderError::FrameSize { index, got, want });
            }
        }
        Ok(want)
    }
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

/// The shortest GIF delay browsers honour, in 1/100 s: Chromium and Firefox play 0 and
/// 1 as 1/10 s.
const GIF_MIN_DELAY: f64 = 2.0;

/// GIF's schedule for `n` frames at `fps`: the frames written, each with its delay in
/// 1/100 s (GIF's unit), so that the running sum of delays tracks the exact time and the
/// whole run lasts `round(100·n/fps)`.
///
/// Up to 50 fps every frame is written and frame `k` starts at `round(100·k/fps)`: each
/// delay is a difference of rounded exact times, so no frame starts more than half a
/// hundredth off (30 fps: 3, 4, 3, 3, 4, 3, …). Faster rates would need delays of 1/100 s,
/// which browsers play as 1/10 s; there the file shows one frame every [`GIF_MIN_DELAY`]
/// hundredths, the frame whose exact time is nearest (60 fps: 100 of every 120 frames, 2
/// hundredths each, none more than 50/fps hundredths off).
fn gif_schedule(n: usize, fps: f64) -> Vec<(usize, u16)> {
    let end = (100.0 * n as f64 / fps).round();
    let starts: Vec<(usize, f64)> = if 100.0 / fps >= GIF_MIN_DELAY {
        (0..n)
            .map(|k| (k, (100.0 * k as f64 / fps).round()))
            .collect()
    } else {
        let slots = ((end / GIF_MIN_DELAY).floor() as usize).max(1);
        (0..slots)
            .map(|m| {
                let t = GIF_MIN_DELAY * m as f64;
                let k = ((t * fps / 100.0).round() as usize).min(n - 1);
                (k, t)
            })
            .collect()
    };
    (0..starts.len())
        .map(|i| {
            let (k, t) = starts[i];
            let next = starts.get(i + 1).map_or(end, |s| s.1);
            // Past 655 s a frame GIF cannot hold its delay; a zero delay means "none".
            (k, (next - t).clamp(1.0, f64::from(u16::MAX)) as u16)
        })
        .collect()
}

/// Writes an animated GIF: one palette of up to 256 colours per frame (NeuQuant when a
/// frame has more), alpha thresholded to fully transparent or opaque as GIF requires, and
/// frame delays in GIF's 1/100 s that add up to the exact time (see `gif_schedule`:
/// above 50 fps, 50 frames a second are shown).
pub fn write_gif(anim: Frames, path: &Path) -> Result<(), RenderError> {
    let encode = gif_encoder(anim)?;
    atomic::write_with(path, |out| encode(out)).map_err(|e| write_error(path, e))
}

/// The animated GIF [`write_gif`] writes, in memory (`path` is named in errors).
pub fn gif_bytes(anim: Frames, path: &Path) -> Result<Vec<u8>, RenderError> {
    let mut bytes = Vec::new();
    gif_encoder(anim)?(&mut bytes).map_err(|e| write_error(path, e))?;
    Ok(bytes)
}

/// Checks `anim` can be a GIF and returns what encodes it into a byte stream: a file and
/// memory get the same bytes.
fn gif_encoder(anim: Frames) -> Result<impl FnOnce(&mut dyn Write) -> io::Result<()>, RenderError> {
    let (w, h) = anim.size()?;
    let (w16, h16) = match (u16::try_from(w), u16::try_from(h)) {
        (Ok(w), Ok(h)) => (w, h),
        _ => {
            return Err(RenderError::Size {
                width: w,
                height: h,
            });
        }
    };
    let schedule = gif_schedule(anim.frames.len(), anim.fps);
    Ok(move |out: &mut dyn Write| -> io::Result<()> {
        let mut enc = gif::Encoder::new(out, w16, h16, &[]).map_err(io::Error::other)?;
        let repeat = if anim.looping {
            gif::Repeat::Infinite
        } else {
            gif::Repeat::Finite(0)
        };
        enc.set_repeat(repeat).map_err(io::Error::other)?;
        for &(k, delay) in &schedule {
            let mut rgba = straight_rgba(&anim.frames[k]);
            let mut frame = gif::Frame::from_rgba_speed(w16, h16, &mut rgba, 10);
            frame.delay = delay;
            // Frames are whole pictures with transparency: clear before drawing the next.
            frame.dispose = gif::DisposalMethod::Background;
            enc.write_frame(&frame).map_err(io::Error::other)?;
        }
        drop(enc);
        Ok(())
    })
}

/// `x` as a fraction `num/den` with both terms at most `u16::MAX`, if one equals it (to
/// within floating-point rounding): the continued fraction's convergents, in order.
fn small_fraction(x: f64) -> Option<(u16, u16)> {
    let max = f64::from(u16::MAX);
    // Convergents h/k from the recurrence h(i) = a(i)·h(i-1) + h(i-2), likewise k.
    let (mut h0, mut h1, mut k0, mut k1) = (0.0, 1.0, 1.0, 0.0);
    let mut r = x;
    for _ in 0..40 {
        let a = r.floor();
        let (h2, k2) = (a * h1 + h0, a * k1 + k0);
        if h2 > max || k2 > max {
            return None;
        }
        if h2 >= 1.0 && (h2 / k2 - x).abs() <= 1e-12 * x {
            return Some((h2 as u16, k2 as u16));
        }
        let frac = r - a;
        if frac <= 0.0 {
            return None;
        }
        (h0, h1, k0, k1, r) = (h1, h2, k1, k2, 1.0 / frac);
    }
    None
}

/// APNG delays of `n` frames at `fps`, as (numerator, denominator) seconds. When `1/fps`
/// is a fraction of 16-bit terms (every whole rate; 29.97 = 30000/1001 …) every frame
/// gets it, exactly. Otherwise frame `k` starts at `round(den·k/fps)/den` with `den` =
/// 10000 (coarser only for rates so slow that a delay would not fit 16 bits), so the
/// running sum stays within half a `1/den` of the exact time.
fn apng_delays(n: usize, fps: f64) -> Vec<(u16, u16)> {
    if let Some(d) = small_fraction(1.0 / fps) {
        return vec![d; n];
    }
    let max = f64::from(u16::MAX);
    let den = [10_000u16, 1000, 100, 10, 1]
        .into_iter()
        .find(|&d| (f64::from(d) / fps).ceil() <= max)
        .unwrap_or(1);
    let start = |k: usize| (f64::from(den) * k as f64 / fps).round();
    (0..n)
        .map(|k| ((start(k + 1) - start(k)).clamp(1.0, max) as u16, den))
        .collect()
}

/// Writes an animated PNG with full alpha and exact frame delays (see `apng_delays`).
pub fn write_apng(anim: Frames, path: &Path) -> Result<(), RenderError> {
    let encode = apng_encoder(anim)?;
    atomic::write_with(path, |out| encode(out)).map_err(|e| write_error(path, e))
}

/// The animated PNG [`write_apng`] writes, in memory (`path` is named in errors).
pub fn apng_bytes(anim: Frames, path: &Path) -> Result<Vec<u8>, RenderError> {
    let mut bytes = Vec::new();
    apng_encoder(anim)?(&mut bytes).map_err(|e| write_error(path, e))?;
    Ok(bytes)
}

/// Checks `anim` can be an APNG and returns what encodes it into a byte stream.
fn apng_encoder(
    anim: Frames,
) -> Result<impl FnOnce(&mut dyn Write) -> io::Result<()>, RenderError> {
    let (w, h) = anim.size()?;
    let delays = apng_delays(anim.frames.len(), anim.fps);
    Ok(move |out: &mut dyn Write| -> io::Result<()> {
        let mut enc = png::Encoder::new(&mut *out, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_animated(anim.frames.len() as u32, if anim.looping { 0 } else { 1 })
            .map_err(io::Error::other)?;
        let mut writer = enc.write_header().map_err(io::Error::other)?;
        for (f, &(num, den)) in anim.frames.iter().zip(&delays) {
            writer.set_frame_delay(num, den).map_err(io::Error::other)?;
            writer
                .write_image_data(&straight_rgba(f))
                .map_err(io::Error::other)?;
        }
        writer.finish().map_err(io::Error::other)?;
        out.flush()
    })
}

/// The name of frame `i` in a frames folder: `frame_00000.png`, `frame_00001.png`, …
/// (more digits past 99999).
pub fn frame_file_name(i: usize) -> String {
    FrameNames::folder().name(i)
}

/// Whether `name` is one of the names [`frame_file_name`] gives: `frame_`, five or more
/// digits, `.png`.
pub fn is_frame_file_name(name: &str) -> bool {
    FrameNames::folder().is_ours(name)
}

/// How the frames of an output are named: a folder of `frame_00000.png`, … of its own, or a
/// printf-style pattern such as `shots/walk_%04d.png` (`%d` or `%0Nd`, as ffmpeg and
/// Blender take them) naming files in a folder that may hold other things.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameNames {
    prefix: String,
    width: usize,
    suffix: String,
    /// Whether the folder belongs to the frames (it then holds nothing else).
    own_folder: bool,
}

impl FrameNames {
    /// A folder of its own, `frame_00000.png` on.
    fn folder() -> FrameNames {
        FrameNames {
            prefix: "frame_".into(),
            width: 5,
            suffix: ".png".into(),
            own_folder: true,
        }
    }

    /// The naming `path` asks for, with the folder the frames go in: the pattern in its
    /// file name, or the path itself as a folder of `frame_NNNNN.png`.
    pub fn of(path: &Path) -> (PathBuf, FrameNames) {
        if let Some(names) = path
            .file_name()
            .and_then(|n| n.to_str())
            .and_then(Self::pattern)
        {
            let dir = match path.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => PathBuf::from("."),
            };
            return (dir, names);
        }
        (path.to_path_buf(), FrameNames::folder())
    }

    /// Whether `path`'s file name is a frame-name pattern (`…%04d….png`).
    pub fn is_pattern(path: &Path) -> bool {
        path.file_name()
            .and_then(|n| n.to_str())
            .is_some_and(|n| Self::pattern(n).is_some())
    }

    /// `prefix%0Nd suffix.png` or `prefix%dsuffix.png`, with one `%`.
    fn pattern(name: &str) -> Option<FrameNames> {
        let (prefix, rest) = name.split_once('%')?;
        let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
        let suffix = rest[digits..].strip_prefix('d')?;
        let lower = suffix.to_ascii_lowercase();
        if !lower.ends_with(".png") || suffix.contains('%') || digits > 2 {
            return None;
        }
        let width = if digits == 0 {
            1
        } else {
            rest[..digits].parse().ok()?
        };
        Some(FrameNames {
            prefix: prefix.to_string(),
            width,
            suffix: suffix.to_string(),
            own_folder: false,
        })
    }

    /// The name of frame `i`.
    pub fn name(&self, i: usize) -> String {
        let (prefix, suffix, width) = (&self.prefix, &self.suffix, self.width);
        format!("{prefix}{i:0width$}{suffix}")
    }

    /// Whether `name` is a name this naming gives (at least `width` digits).
    fn is_ours(&self, name: &str) -> bool {
        name.strip_prefix(self.prefix.as_str())
            .and_then(|r| r.strip_suffix(self.suffix.as_str()))
            .is_some_and(|d| d.len() >= self.width && d.bytes().all(|b| b.is_ascii_digit()))
    }
}

/// The gmotion frames at `path` (a frames folder or a frame-name pattern), if they can be
/// written fresh by [`write_frames`]. A folder of its own must not exist or hold nothing
/// but files named like frames (which an earlier run wrote, and which a new run replaces);
/// anything else is [`RenderError::FolderInUse`]. A pattern's folder may hold other files;
/// only those its pattern names are the run's. Call this before rendering so a refused
/// folder costs nothing.
pub fn check_frame_folder(path: &Path) -> Result<Vec<PathBuf>, RenderError> {
    let (dir, names) = FrameNames::of(path);
    let entries = match std::fs::read_dir(&dir) {
        Ok(e) => e,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(write_error(&dir, e)),
    };
    let (mut frames, mut others) = (Vec::new(), Vec::new());
    for entry in entries {
        let entry = entry.map_err(|e| write_error(&dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_file = entry.file_type().is_ok_and(|t| t.is_file());
        if is_file && names.is_ours(&name) {
            frames.push(entry.path());
        } else {
            others.push(name);
        }
    }
    if others.is_empty() || !names.own_folder {
        return Ok(frames);
    }
    others.sort();
    if others.len() > 3 {
        others.truncate(3);
        others.push("…".into());
    }
    Err(RenderError::FolderInUse { path: dir, others })
}

/// Writes one PNG per frame at `path` (a folder of `frame_00000.png`, …, or a frame-name
/// pattern such as `walk_%04d.png`), all or nothing: the frames are written into a hidden
/// temporary folder and moved in at once (or when the open [`atomic::Staging`] commits),
/// and the frames an earlier, longer run left are removed.
pub fn write_frames(frames: &[Pixmap], path: &Path) -> Result<(), RenderError> {
    use rayon::prelude::*;
    let (dir, names) = FrameNames::of(path);
    let old = check_frame_folder(path)?;
    let encoded: Vec<Vec<u8>> = frames
        .par_iter()
        .map(|f| {
            f.encode_png()
                .map_err(|e| write_error(path, io::Error::other(e)))
        })
        .collect::<Result<_, _>>()?;
    // Beside a folder of its own; inside a pattern's folder, which may be `.`.
    let tmp = if names.own_folder {
        atomic::temp_path(&dir)
    } else {
        atomic::temp_path(&dir.join("frames"))
    };
    atomic::register(&tmp);
    let written = (|| -> io::Result<()> {
        if !names.own_folder {
            std::fs::create_dir_all(&dir)?;
        }
        std::fs::create_dir(&tmp)?;
        for (i, bytes) in encoded.iter().enumerate() {
            std::fs::write(tmp.join(names.name(i)), bytes)?;
        }
        Ok(())
    })();
    if let Err(e) = written {
        // The hidden folder is ours and holds nothing the user needs.
        let _ = std::fs::remove_dir_all(&tmp);
        atomic::forget(&tmp);
        return Err(write_error(path, e));
    }
    let n = encoded.len();
    let (from, to) = (tmp.clone(), dir);
    // Moving the frames in (now, or when the open staging commits), then removing the
    // frames of an earlier, longer run.
    let commit = move || -> io::Result<()> {
        let moved = (|| -> io::Result<()> {
            std::fs::create_dir_all(&to)?;
            for i in 0..n {
                let name = names.name(i);
                std::fs::rename(from.join(&name), to.join(&name))?;
            }
            Ok(())
        })();
        let _ = std::fs::remove_dir_all(&from);
        atomic::forget(&from);
        moved?;
        let fresh: std::collections::HashSet<String> = (0..n).map(|i| names.name(i)).collect();
        for path in old {
            let stale = path
                .file_name()
                .is_some_and(|n| !fresh.contains(&*n.to_string_lossy()));
            if stale {
                std::fs::remove_file(&path)?;
            }
        }
        Ok(())
    };
    atomic::finish(&tmp, Box::new(commit)).map_err(|e| write_error(path, e))
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

    /// `frames` at `fps`, looping or played once.
    fn played(frames: &[Pixmap], fps: f64, looping: bool) -> Frames<'_> {
        Frames {
            frames,
            fps,
            looping,
        }
    }

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
        write_apng(played(&frames(), 25.0, false), &path).unwrap();
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
        write_gif(played(&frames(), 20.0, true), &path).unwrap();
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

    /// `n` 2×2 frames whose red channel is their index, so a decoder can tell which
    /// frames a file holds.
    fn numbered(n: usize) -> Vec<Pixmap> {
        (0..n)
            .map(|k| {
                let mut p = Pixmap::new(2, 2).unwrap();
                p.fill(resvg::tiny_skia::Color::from_rgba8(k as u8, 0, 0, 255));
                p
            })
            .collect()
    }

    /// The rates of the tempo tests: film, PAL, NTSC-ish, and above GIF's 50 fps limit.
    const RATES: [f64; 5] = [24.0, 25.0, 30.0, 50.0, 60.0];

    #[test]
    fn gif_delays_add_up_to_the_exact_time() {
        for fps in RATES {
            // Two seconds; 2·fps frames is a whole number for every rate here.
            let n = (2.0 * fps) as usize;
            let path = temp(&format!("tempo-{fps}.gif"));
            write_gif(played(&numbered(n), fps, true), &path).unwrap();
            let mut opts = gif::DecodeOptions::new();
            opts.set_color_output(gif::ColorOutput::RGBA);
            let mut dec = opts.read_info(std::fs::File::open(&path).unwrap()).unwrap();
            let (mut elapsed, mut shown) = (0u32, Vec::new());
            while let Some(f) = dec.read_next_frame().unwrap() {
                let k = usize::from(f.buffer[0]);
                let exact = 100.0 * k as f64 / fps;
                assert!(
                    (f64::from(elapsed) - exact).abs() <= 1.0,
                    "{fps} fps: frame {k} starts at {elapsed} cs, exactly {exact:.2}"
                );
                // Browsers play shorter delays as 1/10 s.
                assert!(f.delay >= 2, "{fps} fps: frame {k} has delay {}", f.delay);
                elapsed += u32::from(f.delay);
                shown.push(k);
            }
            let total = 100.0 * n as f64 / fps;
            assert!(
                (f64::from(elapsed) - total).abs() <= 1.0,
                "{fps} fps: {elapsed} cs in all, exactly {total}"
            );
            assert!(
                shown.windows(2).all(|w| w[0] < w[1]),
                "{fps} fps: {shown:?}"
            );
            assert_eq!(shown[0], 0);
            if fps <= 50.0 {
                assert_eq!(shown.len(), n, "{fps} fps: every frame is written");
            } else {
                // GIF cannot hold more than 50 frames a second that browsers honour.
                assert!(
                    shown.len() as f64 >= 2.0 * 50.0 - 1.0,
                    "{fps} fps: {shown:?}"
                );
            }
            std::fs::remove_file(&path).unwrap();
        }
    }

    #[test]
    fn apng_delays_are_exact() {
        // 29.97 is 30000/1001; 10π has no fraction of 16-bit terms and takes the running sum.
        let rates = RATES
            .into_iter()
            .chain([30000.0 / 1001.0, 10.0 * std::f64::consts::PI]);
        for fps in rates {
            let n = (2.0 * fps).round() as usize;
            let path = temp(&format!("tempo-{fps}.png"));
            write_apng(played(&numbered(n), fps, true), &path).unwrap();
            let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
            let mut dec = png::Decoder::new(file).read_info().unwrap();
            let mut buf = vec![0; dec.output_buffer_size().unwrap()];
            let mut elapsed = 0.0;
            for k in 0..n {
                dec.next_frame(&mut buf).unwrap();
                assert_eq!(usize::from(buf[0]), k, "{fps} fps: frame order");
                let exact = k as f64 / fps;
                assert!(
                    (elapsed - exact).abs() < 1e-4,
                    "{fps} fps: frame {k} starts at {elapsed} s, exactly {exact}"
                );
                let fctl = dec.info().frame_control().copied().unwrap();
                elapsed += f64::from(fctl.delay_num) / f64::from(fctl.delay_den);
            }
            let total = n as f64 / fps;
            assert!(
                (elapsed - total).abs() < 1e-4,
                "{fps} fps: {elapsed} s, exactly {total}"
            );
            std::fs::remove_file(&path).unwrap();
        }
    }

    #[test]
    fn sizes_fit_the_art() {
        // One side: the other follows the aspect ratio; both: fitted and centred.
        let p = render_sized(
            SQUARE,
            OutputSize {
                width: None,
                height: Some(30),
            },
        )
        .unwrap();
        assert_eq!((p.width(), p.height()), (60, 30));
        let p = render_sized(
            SQUARE,
            OutputSize {
                width: Some(40),
                height: Some(40),
            },
        )
        .unwrap();
        assert_eq!((p.width(), p.height()), (40, 40));
        // The 20×10 canvas becomes 40×20 in rows 10..30; the red square its left half.
        let alpha = |x, y| p.pixel(x, y).unwrap().alpha();
        assert_eq!((alpha(5, 5), alpha(5, 34)), (0, 0));
        assert_eq!((alpha(5, 11), alpha(5, 28)), (255, 255));
        assert_eq!(alpha(30, 20), 0);
        let own = render_sized(SQUARE, OutputSize::default()).unwrap();
        assert_eq!((own.width(), own.height()), (20, 10));
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(matches!(render("<svg", 10), Err(RenderError::Svg(_))));
        let dir = std::env::temp_dir();
        assert!(matches!(
            write_gif(played(&[], 10.0, true), &dir.join("x.gif")),
            Err(RenderError::NoFrames)
        ));
        let frames = [Pixmap::new(2, 2).unwrap(), Pixmap::new(3, 2).unwrap()];
        assert!(matches!(
            write_apng(played(&frames, 10.0, true), &dir.join("x.png")),
            Err(RenderError::FrameSize { index: 1, .. })
        ));
    }
}
