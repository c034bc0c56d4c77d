//! Every output gmotion writes, chosen by file name: `.json` Lottie, `.lottie` dotLottie,
//! `.svg` SVG (SMIL when animated), `.png` one picture, `.gif` / `.apng` a preview of the
//! whole animation, `.mp4` / `.webm` / `.mov` video (through ffmpeg, [`video`]), and a path
//! without extension (or an existing folder) one PNG per frame.
//!
//! This is the layer the command line and embedders share, so that picking a format and
//! rendering frames is not something every caller re-implements. Files are written whole or
//! not at all ([`gmotion::atomic`]).
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! # let anim: gmotion::Animation = unimplemented!();
//! use gmotion_output::{Options, write};
//! for path in ["out.json", "out.svg", "out.gif"] {
//!     let warnings = write(&anim, path.as_ref(), &Options::default())?;
//!     for w in warnings {
//!         eprintln!("{path}: warning: {w}");
//!     }
//! }
//! # Ok(()) }
//! ```
#![forbid(unsafe_code)]

pub mod flipbook;
pub mod video;

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use gmotion::Warning;
use gmotion::canvas::{OutputSize, pixels};
use gmotion::engine::markers::Marker;
use gmotion::engine::slots::SlotKinds;
use gmotion::motion::{Animation, Sampler, ShapeState, Track};
use gmotion::scene::Scene;
use gmotion_export_lottie::{self as lottie, LottieOptions};
use gmotion_export_raster::{self as raster, Pixmap, RenderError};
use gmotion_export_svg::{frame, smil};
use kurbo::Affine;
use rayon::prelude::*;

/// The source document of a scene imported from Lottie: a `.json` output of such a scene
/// is that document written back, with the animation's motion layered on top
/// ([`gmotion_export_lottie::layered`]).
pub use gmotion_lottie::Source as LottieSource;
pub use gmotion_lottie::dotlottie;
use gmotion_lottie::dotlottie::{Package, Picked};

/// What an output path asks for, by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// One PNG.
    Png,
    /// Lottie JSON.
    Lottie,
    /// dotLottie: the Lottie JSON in a `.lottie` package ([`dotlottie`]), with the other
    /// animations and the themes of the package the scene was read from, if it was.
    DotLottie,
    /// SVG (animated SMIL, or a clean still).
    Svg,
    /// Animated GIF preview.
    Gif,
    /// Animated PNG preview.
    Apng,
    /// PNG frames: a folder of `frame_00000.png` on, or files named by a pattern such as
    /// `walk_%04d.png`.
    Frames,
    /// MP4 video (H.264), through ffmpeg ([`video`]).
    Mp4,
    /// WebM video (VP9), through ffmpeg.
    Webm,
    /// QuickTime video (ProRes 4444), through ffmpeg.
    Mov,
}

impl Format {
    /// The format of `path`: by extension, or frames when it has none (or is an existing
    /// folder, or a frame-name pattern such as `walk_%04d.png`).
    pub fn of(path: &Path) -> Result<Format, OutputError> {
        if path.is_dir() || raster::FrameNames::is_pattern(path) {
            return Ok(Format::Frames);
        }
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("png") => Ok(Format::Png),
            Some("json") => Ok(Format::Lottie),
            Some("lottie") => Ok(Format::DotLottie),
            Some("svg") => Ok(Format::Svg),
            Some("gif") => Ok(Format::Gif),
            Some("apng") => Ok(Format::Apng),
            Some("mp4") => Ok(Format::Mp4),
            Some("webm") => Ok(Format::Webm),
            Some("mov") => Ok(Format::Mov),
            None => Ok(Format::Frames),
            Some(other) => Err(OutputError::UnknownFormat {
                path: path.to_path_buf(),
                extension: other.to_string(),
            }),
        }
    }

    /// Whether the format holds one still picture (what `convert` writes).
    pub fn is_still(self) -> bool {
        matches!(
            self,
            Format::Png | Format::Lottie | Format::DotLottie | Format::Svg
        )
    }

    /// Whether the format is a video ffmpeg encodes.
    pub fn is_video(self) -> bool {
        matches!(self, Format::Mp4 | Format::Webm | Format::Mov)
    }

    /// Whether the format is a Lottie document, plain or packaged.
    pub fn is_lottie(self) -> bool {
        matches!(self, Format::Lottie | Format::DotLottie)
    }
}

/// How to write.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Error bound, in canvas pixels, for motion an exporter has to bake (default 0.25).
    pub tolerance: f64,
    /// The output's pixel size (the `width`/`height` directives).
    pub size: OutputSize,
    /// The time, in seconds, of the frame a `.png` output shows.
    pub time: f64,
    /// Whether a Lottie source written to `.svg` plays (frame by frame, as SMIL) rather
    /// than showing the frame at [`time`](Self::time) still.
    pub play_svg: bool,
    /// The most pixels one rendered image may have (`--limit pixels=N`; default
    /// [`raster::DEFAULT_MAX_PIXELS`]).
    pub max_pixels: u64,
    /// The most pixels all the frames of a GIF, APNG or frames folder may have together,
    /// since they are held in memory until written (`--limit animation-pixels=N`; default
    /// [`DEFAULT_MAX_ANIMATION_PIXELS`]). A video streams its frames and is not bound by it.
    pub max_animation_pixels: u64,
    /// The colour a video is drawn over (8-bit RGB; default white): video has no
    /// transparency unless [`transparent`](Self::transparent) keeps it.
    pub background: [u8; 3],
    /// Whether a WebM or MOV video keeps the animation's transparency (`--transparent`).
    pub transparent: bool,
    /// The properties a Lottie output gives slots (the grammar's `slots`).
    pub slots: SlotKinds,
    /// Whether Lottie outputs pack runs of plain shape layers into one (`--pack`).
    pub pack: bool,
}

/// The default of [`Options::max_animation_pixels`]: 2²⁸ pixels, 1 GiB of RGBA frames.
pub const DEFAULT_MAX_ANIMATION_PIXELS: u64 = 1 << 28;

impl Default for Options {
    fn default() -> Options {
        Options {
            tolerance: 0.25,
            size: OutputSize::default(),
            time: 0.0,
            play_svg: false,
            max_pixels: raster::DEFAULT_MAX_PIXELS,
            max_animation_pixels: DEFAULT_MAX_ANIMATION_PIXELS,
            background: [255; 3],
            transparent: false,
            slots: SlotKinds::default(),
            pack: false,
        }
    }
}

/// Why an output could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The extension names no format gmotion writes.
    #[error(
        "{}: unknown output format `.{extension}`; use .png, .json (Lottie), .lottie (dotLottie), .svg, .gif, .apng, .mp4, .webm, .mov or a directory",
        path.display()
    )]
    UnknownFormat {
        /// The output.
        path: PathBuf,
        /// Its extension.
        extension: String,
    },
    /// A still scene cannot be written as an animation format.
    #[error("{}: a still picture is written as .png, .json, .lottie or .svg, not {format:?}", path.display())]
    NotStill {
        /// The output.
        path: PathBuf,
        /// What its name asked for.
        format: Format,
    },
    /// `time` lies outside the animation.
    #[error("--time must lie within the animation, 0..{duration}s, found {time}")]
    TimeOutside {
        /// The time asked for.
        time: f64,
        /// The animation's duration.
        duration: f64,
    },
    /// A frame cannot be drawn: something in it lies beyond what the renderer reaches
    /// (a huge stroke width, scale or coordinate), or it has too many pixels.
    #[error(
        "{}: frame {frame} (t = {time:.3}s){}: {source}",
        path.display(),
        shape.as_ref().map(|s| format!(", shape {s}")).unwrap_or_default()
    )]
    Frame {
        /// The output.
        path: PathBuf,
        /// The frame's index (0 for a still picture).
        frame: usize,
        /// The frame's time in seconds.
        time: f64,
        /// The shape (`tag:id`) reaching farthest, when the error is about reach.
        shape: Option<String>,
        /// What failed.
        #[source]
        source: RenderError,
    },
    /// A still picture cannot be drawn (see [`OutputError::Frame`]).
    #[error(
        "{}{}: {source}",
        path.display(),
        shape.as_ref().map(|s| format!(": shape {s}")).unwrap_or_default()
    )]
    Still {
        /// The output.
        path: PathBuf,
        /// The shape (`tag:id`) reaching farthest, when the error is about reach.
        shape: Option<String>,
        /// What failed.
        #[source]
        source: RenderError,
    },
    /// A frame of a Lottie source could not be evaluated.
    #[error("{}: frame {frame} of the Lottie source: {message}", path.display())]
    Source {
        /// The output.
        path: PathBuf,
        /// The frame's index.
        frame: usize,
        /// What failed.
        message: String,
    },
    /// A Lottie played as SVG would be larger than [`flipbook::MAX_BYTES`].
    #[error(
        "{}: the frames that differ up to frame {frames} already take more than {max} bytes as SVG; write a .gif, .apng or frames folder instead",
        path.display()
    )]
    TooLargeAsSvg {
        /// The output.
        path: PathBuf,
        /// Frames drawn when the bound was passed.
        frames: usize,
        /// The bound.
        max: usize,
    },
    /// A GIF, APNG or frames folder would hold more pixels than allowed.
    #[error(
        "{}: {frames} frames of {width}x{height} px are {} pixels, more than the limit of {limit} (raise it with --limit animation-pixels=N, or lower --fps, --width or --height)",
        path.display(),
        *frames as u64 * u64::from(*width) * u64::from(*height)
    )]
    AnimationPixels {
        /// The output.
        path: PathBuf,
        /// Frames.
        frames: usize,
        /// Frame width.
        width: u32,
        /// Frame height.
        height: u32,
        /// The limit.
        limit: u64,
    },
    /// Rendering or writing pixels failed.
    #[error("{}: {source}", path.display())]
    Raster {
        /// The output.
        path: PathBuf,
        /// What failed.
        #[source]
        source: RenderError,
    },
    /// The Lottie exporter refused the animation.
    #[error("{}: {source}", path.display())]
    Lottie {
        /// The output.
        path: PathBuf,
        /// Why.
        #[source]
        source: lottie::LottieError,
    },
    /// The dotLottie package could not be written.
    #[error("{}: {source}", path.display())]
    Package {
        /// The output.
        path: PathBuf,
        /// Why.
        #[source]
        source: dotlottie::PackageError,
    },
    /// The SMIL exporter refused the animation.
    #[error("{}: {source}", path.display())]
    Smil {
        /// The output.
        path: PathBuf,
        /// Why.
        #[source]
        source: smil::SmilError,
    },
    /// A folder of frames was asked for in memory ([`bytes_over_source`]): it is files.
    #[error("{}: a folder of frames is written to disk, not returned as bytes", path.display())]
    FramesInMemory {
        /// The output named.
        path: PathBuf,
    },
    /// A video was asked for and no ffmpeg is installed (or the one named is not there).
    #[error(
        "{}: writing video needs ffmpeg, {}: install it (Debian and Ubuntu: `apt install ffmpeg`; macOS: `brew install ffmpeg`; Windows: `winget install ffmpeg`) or name it with {}=PATH",
        path.display(),
        named.as_ref().map_or_else(
            || "which is not on the PATH".to_string(),
            |n| format!("and {} names {}, which is not a program", video::FFMPEG_VAR, n.display())
        ),
        video::FFMPEG_VAR
    )]
    NoFfmpeg {
        /// The output.
        path: PathBuf,
        /// What [`video::FFMPEG_VAR`] named, when it named something.
        named: Option<PathBuf>,
    },
    /// A video could not be written.
    #[error("{}: {message}", path.display())]
    Video {
        /// The output.
        path: PathBuf,
        /// Why (ffmpeg's own words when it failed).
        message: String,
    },
    /// Writing the file failed.
    #[error("{}: cannot write output: {source}", path.display())]
    Io {
        /// The output.
        path: PathBuf,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
}

/// What each frame of an output draws: the animation's own scene, or the Lottie source the
/// scene was imported from evaluated at the frame (a scene that moves by itself); in both
/// cases moved by the animation's tracks.
#[derive(Clone, Copy)]
pub(crate) struct Stage<'a> {
    anim: &'a Animation,
    source: Option<&'a LottieSource>,
}

impl Stage<'_> {
    /// Frame `index` (at time `t`) of `path` rendered, its states read from `sampler` (or
    /// evaluated directly for a single picture).
    fn render(
        &self,
        sampler: Option<&Sampler>,
        path: &Path,
        (index, t): (usize, f64),
        opts: &Options,
    ) -> Result<Pixmap, OutputError> {
        let svg = self.svg(sampler, path, (index, t), "d")?;
        let scene = &self.anim.scene;
        render_sized(&svg, (scene.width, scene.height), opts)
            .map_err(|e| frame_error(path, self.anim, index, t, e))
    }

    /// Frame `index` (at time `t`) of `path` as an SVG document, its states read from
    /// `sampler` (or evaluated directly), its `<defs>` entries named `{ids}0`, `{ids}1`, …
    /// (see [`frame::frame_with_ids`]).
    pub(crate) fn svg(
        &self,
        sampler: Option<&Sampler>,
        path: &Path,
        (index, t): (usize, f64),
        ids: &str,
    ) -> Result<String, OutputError> {
        let anim = self.anim;
        let mut states = match sampler {
            Some(s) => s.evaluate(t),
            None => anim.evaluate(t),
        };
        Ok(match self.source {
            None => frame::frame_with_ids(&anim.scene, anim, t, states, ids),
            Some(src) => {
                let (scene, moved) =
                    src.scene_at(src.frame_at(t))
                        .map_err(|e| OutputError::Source {
                            path: path.to_path_buf(),
                            frame: index,
                            message: e.to_string(),
                        })?;
                riding(src, &mut states, &moved);
                frame::frame_with_ids(&scene, anim, t, states, ids)
            }
        })
    }

    /// Every frame of `path` rendered in parallel; `tick` is called once per frame. Order
    /// and bytes do not depend on the thread count, nor does which error is reported (the
    /// earliest frame's).
    fn render_all(
        &self,
        path: &Path,
        opts: &Options,
        tick: &(dyn Fn() + Sync),
    ) -> Result<Vec<Pixmap>, OutputError> {
        let anim = self.anim;
        let sampler = anim.sampler();
        (0..anim.frame_count())
            .into_par_iter()
            .map(|i| {
                let r = self.render(Some(&sampler), path, (i, anim.frame_time(i)), opts);
                tick();
                r
            })
            .collect::<Vec<_>>()
            .into_iter()
            .collect()
    }
}

/// Whether some unit of a Lottie source moves another through parenting (its layer a
/// parent of the other's) in `anim`: SMIL has no parenting, so such a scene is drawn
/// frame by frame, as players draw it ([`riding`]).
fn rides(anim: &Animation, src: &LottieSource) -> bool {
    (0..src.units.len()).any(|u| {
        src.parent_unit(u)
            .and_then(|v| anim.tracks.get(v))
            .is_some_and(|t| !t.motions.is_empty())
    })
}

/// The canvas-space states of a Lottie source's units as players draw the exported
/// motion: each unit's motion rides on the layer it hangs from (conjugated by how that
/// layer has `moved` since the reference frame), and a unit that hangs from another unit
/// moves with that unit's motion too.
fn riding(src: &LottieSource, states: &mut [ShapeState], moved: &[Affine]) {
    let own: Vec<Affine> = states
        .iter()
        .zip(moved)
        .map(|(s, &c)| {
            if s.transform == Affine::IDENTITY || c == Affine::IDENTITY {
                s.transform
            } else {
                c * s.transform * c.inverse()
            }
        })
        .collect();
    let mut total: Vec<Option<Affine>> = vec![None; states.len()];
    for u in 0..states.len() {
        // Up the chain of units to one already known (units are few; chains short).
        let mut chain = vec![u];
        while let Some(v) = src.parent_unit(*chain.last().unwrap_or(&u)) {
            if total.get(v).is_none_or(Option::is_some) || chain.contains(&v) {
                break;
            }
            chain.push(v);
        }
        for &w in chain.iter().rev() {
            let above = src
                .parent_unit(w)
                .and_then(|v| total.get(v).copied().flatten())
                .unwrap_or(Affine::IDENTITY);
            total[w] = Some(above * own[w]);
        }
    }
    for (s, t) in states.iter_mut().zip(total) {
        s.transform = t.unwrap_or(s.transform);
    }
}

/// The pixel size a raster output of a `width` × `height` canvas has at `size`, as
/// [`OutputSize::fit`] decides it for every output.
fn raster_size(width: f64, height: f64, size: OutputSize) -> (u32, u32) {
    size.fit(width, height)
        .map_or((pixels(width), pixels(height)), |f| (f.width, f.height))
}

/// `svg`, a document of a `canvas` (width, height) scene, rendered at `opts.size` as
/// [`OutputSize::fit`] places the scene's canvas (the scene's own numbers, not the
/// document's `f32` ones, so the pixels match every other output's size exactly).
fn render_sized(svg: &str, canvas: (f64, f64), opts: &Options) -> Result<Pixmap, RenderError> {
    match opts.size.fit(canvas.0, canvas.1) {
        Some(fit) => raster::render_fit(svg, &fit, opts.max_pixels),
        // An empty or infinite canvas: the renderer says what is wrong with it.
        None => raster::render_limited(svg, opts.size, opts.max_pixels),
    }
}

/// The shape reaching farthest from the output's origin in `states` (rest geometry moved
/// by each state, its stroke widened by the state's factor), as `tag:id`: what a
/// [`RenderError::OutOfRange`] is most likely about.
fn farthest_shape(scene: &Scene, states: &[ShapeState]) -> Option<String> {
    let mut best: Option<(f64, String)> = None;
    for (i, shape) in scene.shapes.iter().enumerate() {
        let st = states.get(i).copied().unwrap_or(ShapeState::REST);
        let b = shape.bbox;
        let ts = st.transform;
        let half = 0.5 * shape.stroke_width * st.stroke_width.abs() * ts.determinant().abs().sqrt();
        let reach = [(b.x0, b.y0), (b.x1, b.y0), (b.x0, b.y1), (b.x1, b.y1)]
            .into_iter()
            .map(|(x, y)| {
                let p = ts * kurbo::Point::new(x, y);
                p.x.abs().max(p.y.abs()) + half
            })
            .fold(
                0.0,
                |a: f64, r| if r.is_nan() { f64::INFINITY } else { a.max(r) },
            );
        if best.as_ref().is_none_or(|(r, _)| reach > *r) {
            best = Some((reach, format!("{}:{}", shape.tag, shape.id)));
        }
    }
    best.map(|(_, name)| name)
}

/// An error drawing frame `frame` of `anim` as an [`OutputError`] naming the frame, and the
/// shape when the error is about reach.
fn frame_error(
    path: &Path,
    anim: &Animation,
    frame: usize,
    time: f64,
    e: RenderError,
) -> OutputError {
    let shape = match e {
        RenderError::OutOfRange { .. } => farthest_shape(&anim.scene, &anim.evaluate(time)),
        _ => None,
    };
    match e {
        RenderError::OutOfRange { .. } | RenderError::TooManyPixels { .. } => OutputError::Frame {
            path: path.to_path_buf(),
            frame,
            time,
            shape,
            source: e,
        },
        source => OutputError::Raster {
            path: path.to_path_buf(),
            source,
        },
    }
}

/// Writes `anim` to `path` in the format its name asks for and returns what the format
/// could not show exactly.
pub fn write(anim: &Animation, path: &Path, opts: &Options) -> Result<Vec<Warning>, OutputError> {
    write_with_progress(anim, path, opts, &|| {})
}

/// [`write()`], calling `tick` once per frame rendered.
pub fn write_with_progress(
    anim: &Animation,
    path: &Path,
    opts: &Options,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<Warning>, OutputError> {
    let stage = Stage { anim, source: None };
    write_staged(stage, &[], path, opts, tick, Target::File)
}

/// Where an output goes: its file, written whole or not at all, or memory (the bytes the
/// file would hold).
enum Target<'b> {
    File,
    Memory(&'b mut Vec<u8>),
}

fn write_staged(
    stage: Stage,
    markers: &[Marker],
    path: &Path,
    opts: &Options,
    tick: &(dyn Fn() + Sync),
    target: Target,
) -> Result<Vec<Warning>, OutputError> {
    let anim = stage.anim;
    let raster_err = |source| OutputError::Raster {
        path: path.to_path_buf(),
        source,
    };
    let format = Format::of(path)?;
    if format.is_video() {
        let (width, height) = raster_size(anim.scene.width, anim.scene.height, opts.size);
        raster::check_pixels(width, height, opts.max_pixels)
            .map_err(|e| frame_error(path, anim, 0, 0.0, e))?;
    }
    if matches!(format, Format::Frames | Format::Gif | Format::Apng) {
        let (width, height) = raster_size(anim.scene.width, anim.scene.height, opts.size);
        let frames = anim.frame_count();
        let total = frames as u64 * u64::from(width) * u64::from(height);
        if total > opts.max_animation_pixels {
            return Err(OutputError::AnimationPixels {
                path: path.to_path_buf(),
                frames,
                width,
                height,
                limit: opts.max_animation_pixels,
            });
        }
        raster::check_pixels(width, height, opts.max_pixels)
            .map_err(|e| frame_error(path, anim, 0, 0.0, e))?;
    }
    let written = match format {
        Format::Png => {
            let t = opts.time;
            if !t.is_finite() || t < 0.0 || t > anim.duration {
                return Err(OutputError::TimeOutside {
                    time: t,
                    duration: anim.duration,
                });
            }
            let index = (t * anim.fps).round() as usize;
            let pm = stage.render(None, path, (index, t), opts)?;
            match target {
                Target::File => raster::save_png(&pm, path),
                Target::Memory(bytes) => raster::png_bytes(&pm, path).map(|b| *bytes = b),
            }
            .map_err(raster_err)?;
            return Ok(Vec::new());
        }
        format @ (Format::Mp4 | Format::Webm | Format::Mov) => {
            return match target {
                Target::File => video::write(stage, path, format, opts, tick).map(|()| Vec::new()),
                Target::Memory(_) => Err(OutputError::Video {
                    path: path.to_path_buf(),
                    message: "a video is written to a file, not returned as bytes".into(),
                }),
            };
        }
        Format::Frames => match target {
            Target::File => raster::write_frames(&stage.render_all(path, opts, tick)?, path),
            Target::Memory(_) => {
                return Err(OutputError::FramesInMemory {
                    path: path.to_path_buf(),
                });
            }
        },
        format @ (Format::Gif | Format::Apng) => {
            let frames = stage.render_all(path, opts, tick)?;
            let played = raster::Frames {
                frames: &frames,
                fps: anim.fps,
                looping: anim.looping,
            };
            match (format == Format::Gif, target) {
                (true, Target::File) => raster::write_gif(played, path),
                (false, Target::File) => raster::write_apng(played, path),
                (true, Target::Memory(bytes)) => {
                    raster::gif_bytes(played, path).map(|b| *bytes = b)
                }
                (false, Target::Memory(bytes)) => {
                    raster::apng_bytes(played, path).map(|b| *bytes = b)
                }
            }
        }
        Format::Lottie | Format::DotLottie => {
            return write_lottie(
                path,
                lottie::to_lottie_text(anim, &lottie_options(opts, markers)),
                target,
                None,
            );
        }
        Format::Svg => {
            let svg = smil_out(anim, stage.source, path, opts)?;
            return write_smil(path, &svg, target);
        }
    };
    written.map_err(raster_err)?;
    Ok(Vec::new())
}

/// [`write_with_progress`] for a scene imported from `source`: a `.json` or `.lottie`
/// output is the source document with the motion layered on top; other formats render the
/// scene. A `.lottie` output over the `package` the source was read from is that package
/// with the animation replaced (the others, the themes and the images kept).
pub fn write_over_source(
    anim: &Animation,
    source: Option<&LottieSource>,
    package: Option<&Picked>,
    markers: &[Marker],
    path: &Path,
    opts: &Options,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<Warning>, OutputError> {
    staged_over_source(
        Stage { anim, source },
        package,
        markers,
        path,
        opts,
        tick,
        Target::File,
    )
}

/// The bytes [`write_over_source`] would write to `path` (which names the format and is
/// named in errors; nothing is written), and its warnings: a file format's bytes straight
/// from its writer, with no file between. A folder of frames has no single bytes
/// ([`OutputError::FramesInMemory`]).
pub fn bytes_over_source(
    anim: &Animation,
    source: Option<&LottieSource>,
    package: Option<&Picked>,
    markers: &[Marker],
    path: &Path,
    opts: &Options,
) -> Result<(Vec<u8>, Vec<Warning>), OutputError> {
    let mut bytes = Vec::new();
    let stage = Stage { anim, source };
    let target = Target::Memory(&mut bytes);
    let warnings = staged_over_source(stage, package, markers, path, opts, &|| {}, target)?;
    Ok((bytes, warnings))
}

/// [`write_over_source`] to `target`.
fn staged_over_source(
    stage: Stage,
    package: Option<&Picked>,
    markers: &[Marker],
    path: &Path,
    opts: &Options,
    tick: &(dyn Fn() + Sync),
    target: Target,
) -> Result<Vec<Warning>, OutputError> {
    let anim = stage.anim;
    let (source, said) = lasting(anim, stage.source);
    let source = source.as_deref();
    let mut warnings = match source {
        Some(src) if Format::of(path)?.is_lottie() => write_lottie(
            path,
            lottie::layered::over_source(anim, src, &lottie_options(opts, markers)),
            target,
            package,
        ),
        _ => write_staged(Stage { anim, source }, markers, path, opts, tick, target),
    }?;
    warnings.extend(said);
    Ok(warnings)
}

/// `source` made to fit `anim`: its text layers that `anim`'s scene cut into pieces written
/// as shapes ([`LottieSource::cut`]), and made to last as long as `anim`
/// ([`LottieSource::lasting`]: its last frame held, or cut); with warnings saying so.
/// `source` itself when it fits already.
fn lasting<'s>(
    anim: &Animation,
    source: Option<&'s LottieSource>,
) -> (Option<Cow<'s, LottieSource>>, Vec<Warning>) {
    let mut said = Vec::new();
    let source = source.map(|s| match s.cut(&anim.scene) {
        None => Cow::Borrowed(s),
        Some((cut, notes)) => {
            said.extend(notes.into_iter().map(|(at, what)| Warning::about(at, what)));
            Cow::Owned(cut)
        }
    });
    let Some(source) = source else {
        return (None, said);
    };
    // As long as every other output: the duration rounded to whole frames.
    match source.lasting(anim.length()) {
        None => (Some(source), said),
        Some((fitted, what)) => {
            said.push(Warning::new(what));
            (Some(Cow::Owned(fitted)), said)
        }
    }
}

/// The Lottie JSON [`write_over_source`] writes to a `.json` `path` (named in errors), in
/// memory.
pub fn lottie_text(
    anim: &Animation,
    source: Option<&LottieSource>,
    markers: &[Marker],
    path: &Path,
    opts: &Options,
) -> Result<(String, Vec<Warning>), OutputError> {
    let (source, said) = lasting(anim, source);
    let (text, mut warnings) = match source.as_deref() {
        Some(src) => lottie::layered::over_source(anim, src, &lottie_options(opts, markers)),
        None => lottie::to_lottie(anim, &lottie_options(opts, markers)),
    }
    .map_err(|source| OutputError::Lottie {
        path: path.to_path_buf(),
        source,
    })?;
    warnings.extend(said);
    Ok((text, warnings))
}

/// The animated SVG (SMIL) [`write_over_source`] writes to an `.svg` `path` (named in
/// errors), in memory. A scene imported from a Lottie source that moves by itself is
/// played frame by frame ([`flipbook`]): SMIL's attribute animation has no counterpart for
/// a Lottie's own animation, and the frames carry it with the animation's motion.
pub fn smil_text(
    anim: &Animation,
    source: Option<&LottieSource>,
    path: &Path,
    opts: &Options,
) -> Result<(String, Vec<Warning>), OutputError> {
    let (source, said) = lasting(anim, source);
    let svg = smil_out(anim, source.as_deref(), path, opts)?;
    let mut bytes = Vec::new();
    let mut warnings = write_smil(path, &svg, Target::Memory(&mut bytes))?;
    warnings.extend(said);
    // Written from strings: always UTF-8.
    let text = String::from_utf8(bytes)
        .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned());
    Ok((text, warnings))
}

/// The animated SVG an `.svg` output holds, checked and not yet written.
enum SmilOut<'a> {
    /// A flipbook's text, written whole.
    Text(String),
    /// The animation, written as it is made.
    Stream(smil::SmilWriter<'a>),
}

/// [`smil_text`]'s document, ready to be written to `path` (named in errors).
fn smil_out<'a>(
    anim: &'a Animation,
    source: Option<&LottieSource>,
    path: &Path,
    opts: &Options,
) -> Result<SmilOut<'a>, OutputError> {
    if let Some(src) = source
        && (rides(anim, src) || flipbook::moves(src))
    {
        let stage = Stage {
            anim,
            source: Some(src),
        };
        return Ok(SmilOut::Text(flipbook::smil(stage, path, opts)?));
    }
    let sopts = smil::SmilOptions {
        tolerance: opts.tolerance,
        size: opts.size,
        ..Default::default()
    };
    let writer = smil::SmilWriter::new(anim, &sopts).map_err(|source| OutputError::Smil {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(SmilOut::Stream(writer))
}

/// Writes `svg` to `path` (or `target`'s memory); returns its warnings. The animation is
/// streamed to the (temporary, then renamed) file as it is made.
fn write_smil(path: &Path, svg: &SmilOut<'_>, target: Target) -> Result<Vec<Warning>, OutputError> {
    let mut warnings = Vec::new();
    let mut write = |out: &mut dyn std::io::Write| match svg {
        SmilOut::Text(text) => out.write_all(text.as_bytes()),
        SmilOut::Stream(writer) => {
            warnings = writer.write_to(out)?.warnings;
            Ok(())
        }
    };
    let written = match target {
        Target::Memory(bytes) => write(bytes),
        Target::File => gmotion::atomic::write_with(path, |out| write(out)),
    };
    written.map_err(|source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(warnings)
}

/// [`write_still`] for a scene imported from `source`: a `.json` output is the source
/// document as it was read (the identity), a `.lottie` output that document packaged (in
/// the `package` it came from, if it came from one); other formats render the scene.
pub fn write_still_over_source(
    scene: &Scene,
    source: Option<&LottieSource>,
    package: Option<&Picked>,
    path: &Path,
    opts: &Options,
) -> Result<Vec<Warning>, OutputError> {
    match source {
        Some(src) if Format::of(path)?.is_lottie() => {
            let mut warnings = Vec::new();
            if opts.size.is_given() {
                warnings.push(Warning::new(
                    "--width/--height do not resize a Lottie source; its composition size is kept",
                ));
            }
            let mut text = lottie::layered::source_verbatim(src);
            if opts.pack {
                text = lottie::pack_json(text);
            }
            match Format::of(path)? {
                Format::DotLottie => write_file(path, &packaged(path, &text, package)?)?,
                _ => write_file(path, text.as_bytes())?,
            }
            Ok(warnings)
        }
        // A Lottie source moves by itself: it is played, each frame evaluated from the
        // document; a `.png` shows the frame at `opts.time`, an `.svg` that frame still.
        Some(src) => {
            let duration = src.duration();
            if !(0.0..=duration).contains(&opts.time) {
                return Err(OutputError::TimeOutside {
                    time: opts.time,
                    duration,
                });
            }
            let played = Animation {
                scene: scene.clone(),
                duration,
                fps: src.fps(),
                looping: true,
                tracks: vec![Track::default(); scene.shapes.len()],
            };
            if Format::of(path)? == Format::Svg && opts.play_svg {
                let stage = Stage {
                    anim: &played,
                    source: Some(src),
                };
                let svg = flipbook::smil(stage, path, opts)?;
                write_file(path, svg.as_bytes())?;
                return Ok(Vec::new());
            }
            if Format::of(path)? == Format::Svg {
                let frame = src.frame_at(opts.time);
                let (at, _) = src.scene_at(frame).map_err(|e| OutputError::Source {
                    path: path.to_path_buf(),
                    frame: (opts.time * src.fps()).round() as usize,
                    message: e.to_string(),
                })?;
                return write_still(&at, path, opts);
            }
            write_staged(
                Stage {
                    anim: &played,
                    source: Some(src),
                },
                &[],
                path,
                opts,
                &|| {},
                Target::File,
            )
        }
        None => write_still(scene, path, opts),
    }
}

/// Writes a still `scene` to `path`: `.png` rendered, `.json` a still Lottie, `.svg` a clean
/// SVG through gmotion's scene model.
pub fn write_still(
    scene: &Scene,
    path: &Path,
    opts: &Options,
) -> Result<Vec<Warning>, OutputError> {
    match Format::of(path)? {
        Format::Png => {
            let pm = render_sized(&frame::scene_svg(scene), (scene.width, scene.height), opts)
                .map_err(|e| {
                    let shape = matches!(e, RenderError::OutOfRange { .. })
                        .then(|| farthest_shape(scene, &[]))
                        .flatten();
                    match e {
                        RenderError::OutOfRange { .. } | RenderError::TooManyPixels { .. } => {
                            OutputError::Still {
                                path: path.to_path_buf(),
                                shape,
                                source: e,
                            }
                        }
                        source => OutputError::Raster {
                            path: path.to_path_buf(),
                            source,
                        },
                    }
                })?;
            raster::save_png(&pm, path).map_err(|source| OutputError::Raster {
                path: path.to_path_buf(),
                source,
            })?;
            Ok(Vec::new())
        }
        Format::Lottie | Format::DotLottie => write_lottie(
            path,
            lottie::still_to_lottie(scene, &lottie_options(opts, &[])),
            Target::File,
            None,
        ),
        Format::Svg => {
            let svg = frame::scene_svg(scene);
            let svg = match opts.size.fit(scene.width, scene.height) {
                Some(fit) if !fit.is_canvas() => frame::with_output_size(&svg, &fit),
                _ => svg,
            };
            write_file(path, svg.as_bytes())?;
            Ok(Vec::new())
        }
        format => Err(OutputError::NotStill {
            path: path.to_path_buf(),
            format,
        }),
    }
}

fn lottie_options(opts: &Options, markers: &[Marker]) -> LottieOptions {
    LottieOptions {
        tolerance: opts.tolerance,
        size: opts.size,
        markers: markers.to_vec(),
        slots: opts.slots,
        pack: opts.pack,
        ..Default::default()
    }
}

/// Writes an exporter's Lottie (or says why it refused) and passes its warnings on: the
/// JSON itself, or for a `.lottie` path the JSON packaged ([`packaged`], over `package`).
fn write_lottie<'a, T: Into<lottie::LottieText<'a>>>(
    path: &Path,
    exported: Result<(T, Vec<Warning>), lottie::LottieError>,
    target: Target,
    package: Option<&Picked>,
) -> Result<Vec<Warning>, OutputError> {
    let (json, warnings) = exported.map_err(|source| OutputError::Lottie {
        path: path.to_path_buf(),
        source,
    })?;
    let json: lottie::LottieText<'a> = json.into();
    let io_error = |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    };
    if Format::of(path)? == Format::DotLottie {
        let bytes = packaged(path, &json.into_string(), package)?;
        match target {
            Target::File => write_file(path, &bytes)?,
            Target::Memory(out) => *out = bytes,
        }
        return Ok(warnings);
    }
    // Streamed: the document goes to the file (or the bytes) a run of layers at a time.
    match target {
        Target::Memory(bytes) => json.write_to(bytes).map_err(io_error)?,
        Target::File => {
            gmotion::atomic::write_with(path, |out| json.write_to(out)).map_err(io_error)?;
        }
    }
    Ok(warnings)
}

/// The dotLottie package a `.lottie` output at `path` holds: the Lottie `text` put into
/// `package` in place of the animation the scene was read from, or alone in a new package
/// under an id made from the file name.
fn packaged(path: &Path, text: &str, package: Option<&Picked>) -> Result<Vec<u8>, OutputError> {
    let (mut pkg, id) = match package {
        Some(p) => (p.package.clone(), p.id.clone()),
        None => {
            let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
            (Package::new(), dotlottie::id_for(stem))
        }
    };
    let error = |source| OutputError::Package {
        path: path.to_path_buf(),
        source,
    };
    pkg.put_animation(&id, text).map_err(error)?;
    pkg.to_bytes().map_err(error)
}

fn write_file(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    gmotion::atomic::write_bytes(path, bytes).map_err(|source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    })
}
