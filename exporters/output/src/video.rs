//! Video: MP4 (H.264), WebM (VP9) and MOV (ProRes 4444), encoded by ffmpeg.
//!
//! gmotion draws every frame itself (as for a GIF) and streams the pixels to an ffmpeg
//! process, a few frames ahead of it, so a long video is never held in memory whole. The
//! video has exactly the animation's frames at its frame rate, so its duration is the frame
//! count over the rate. ffmpeg writes a temporary file beside the output, renamed into place
//! only when it succeeds ([`gmotion::atomic::write_via`]): a failure half-way leaves
//! nothing behind.
//!
//! - **MP4**: H.264 in `yuv420p`, what every browser, phone and editor plays. It has no
//!   transparency: frames are drawn over [`Options::background`] (white by default), and an
//!   odd width or height gets one more column or row of that colour, since 4:2:0 chroma
//!   needs even sizes.
//! - **WebM**: VP9, also 4:2:0 (padded the same way); with [`Options::transparent`] it keeps
//!   the alpha channel (`yuva420p`), which Chromium and Firefox draw.
//! - **MOV**: ProRes 4444 (`yuv444p10le`, or `yuva444p10le` with transparency), the editing
//!   format After Effects, Premiere and Final Cut take with alpha.
//!
//! All three are tagged BT.709, which is what the encoders' colour conversion is set to
//! and what players assume of HD video.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use gmotion::atomic;
use gmotion_export_raster::Pixmap;
use rayon::prelude::*;

use crate::{Format, Options, OutputError, Stage, raster_size};

/// The environment variable naming the ffmpeg to run, when it is not `ffmpeg` on the PATH.
pub const FFMPEG_VAR: &str = "GMOTION_FFMPEG";

/// Frames drawn at a time, in parallel, before they are handed to ffmpeg: enough to keep
/// the cores busy, few enough that memory stays a few dozen frames whatever the length.
const BATCH: usize = 16;

/// How much of ffmpeg's error output an error quotes (its last bytes, where the cause is).
const STDERR_TAIL: usize = 2000;

/// The ffmpeg gmotion runs: the one [`FFMPEG_VAR`] names, else `ffmpeg` found on the
/// PATH. `None` when there is none.
pub fn ffmpeg() -> Option<PathBuf> {
    if let Some(named) = named() {
        return executable(&named).then_some(named);
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| {
            dir.join(if cfg!(windows) {
                "ffmpeg.exe"
            } else {
                "ffmpeg"
            })
        })
        .find(|p| executable(p))
}

/// What [`FFMPEG_VAR`] names, if anything.
pub fn named() -> Option<PathBuf> {
    std::env::var_os(FFMPEG_VAR)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
}

/// Whether `path` is a file this process may run.
fn executable(path: &Path) -> bool {
    let Ok(meta) = std::fs::metadata(path) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        meta.is_file() && meta.permissions().mode() & 0o111 != 0
    }
    #[cfg(not(unix))]
    {
        meta.is_file()
    }
}

/// Checks a video can be written to `path` as `format` before any work: ffmpeg is there,
/// and transparency is not asked of a format without it.
pub fn check(path: &Path, format: Format, opts: &Options) -> Result<PathBuf, OutputError> {
    if opts.transparent && format == Format::Mp4 {
        return Err(OutputError::Video {
            path: path.to_path_buf(),
            message: "MP4 (H.264) has no transparency; write .webm or .mov for --transparent"
                .into(),
        });
    }
    ffmpeg().ok_or_else(|| OutputError::NoFfmpeg {
        path: path.to_path_buf(),
        named: named(),
    })
}

/// Writes `stage`'s frames to `path` as `format` (one of the video formats), calling
/// `tick` once per frame drawn.
pub(crate) fn write(
    stage: Stage,
    path: &Path,
    format: Format,
    opts: &Options,
    tick: &(dyn Fn() + Sync),
) -> Result<(), OutputError> {
    let ffmpeg = check(path, format, opts)?;
    let anim = stage.anim;
    let (width, height) = raster_size(anim.scene.width, anim.scene.height, opts.size);
    // 4:2:0 chroma covers 2×2 pixels: those formats need even sizes.
    let even = |v: u32| if format == Format::Mov { v } else { v + v % 2 };
    let canvas = Canvas {
        width,
        height,
        padded: (even(width), even(height)),
        background: (!opts.transparent).then_some(opts.background),
    };
    let io = |source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    };
    atomic::write_via(path, |tmp| {
        let mut child =
            spawn(&ffmpeg, tmp, format, &canvas, anim.fps, opts.transparent).map_err(|e| {
                Failed::Output(OutputError::Video {
                    path: path.to_path_buf(),
                    message: format!("cannot run {}: {e}", ffmpeg.display()),
                })
            })?;
        let stderr = child.stderr.take().map(|mut err| {
            std::thread::spawn(move || {
                let mut text = Vec::new();
                let _ = err.read_to_end(&mut text);
                text
            })
        });
        let fed = feed(stage, path, opts, &canvas, &mut child, tick);
        if fed.is_err() {
            // ffmpeg would otherwise wait for the frames that will not come.
            let _ = child.kill();
        }
        let status = child.wait();
        let said = stderr
            .and_then(|t| t.join().ok())
            .map(|t| tail(&String::from_utf8_lossy(&t)))
            .unwrap_or_default();
        match (fed, status) {
            (Err(Fed::Frame(e)), _) => Err(Failed::Output(e)),
            (Ok(()), Ok(s)) if s.success() => {
                std::fs::File::open(tmp)?.sync_all()?;
                Ok(())
            }
            // ffmpeg stopped reading before the last frame, or failed at the end.
            (_, status) => Err(Failed::Output(OutputError::Video {
                path: path.to_path_buf(),
                message: format!(
                    "{} failed ({}){}",
                    ffmpeg.display(),
                    status.map_or_else(|e| e.to_string(), |s| s.to_string()),
                    if said.is_empty() {
                        String::new()
                    } else {
                        format!(": {said}")
                    }
                ),
            })),
        }
    })
    .map_err(|f| match f {
        Failed::Output(e) => e,
        Failed::Io(e) => io(e),
    })
}

/// Why a video was not written: an output error, or the temporary file's handling failed.
enum Failed {
    Output(OutputError),
    Io(std::io::Error),
}

impl From<std::io::Error> for Failed {
    fn from(e: std::io::Error) -> Failed {
        Failed::Io(e)
    }
}

/// The pixels handed to ffmpeg: frames of `width` × `height` placed at the top left of a
/// `padded` picture, over `background` (an opaque colour) or kept translucent (`None`).
struct Canvas {
    width: u32,
    height: u32,
    padded: (u32, u32),
    background: Option<[u8; 3]>,
}

/// Runs ffmpeg reading raw RGBA frames of `canvas` from its standard input and writing
/// `tmp` as `format`.
fn spawn(
    ffmpeg: &Path,
    tmp: &Path,
    format: Format,
    canvas: &Canvas,
    fps: f64,
    transparent: bool,
) -> std::io::Result<Child> {
    let (w, h) = canvas.padded;
    let mut cmd = Command::new(ffmpeg);
    cmd.args(["-hide_banner", "-loglevel", "error", "-y"])
        .args(["-f", "rawvideo", "-pix_fmt", "rgba"])
        .args(["-video_size", &format!("{w}x{h}")])
        .args(["-framerate", &fps.to_string()])
        .args(["-i", "pipe:0"]);
    let (codec, pix_fmt, container): (&[&str], &str, &str) = match (format, transparent) {
        (Format::Mp4, _) => (
            &["-c:v", "libx264", "-preset", "medium", "-crf", "18"],
            "yuv420p",
            "mp4",
        ),
        (Format::Webm, t) => (
            &[
                "-c:v",
                "libvpx-vp9",
                "-crf",
                "24",
                "-b:v",
                "0",
                "-row-mt",
                "1",
                "-deadline",
                "good",
                "-cpu-used",
                "4",
            ],
            if t { "yuva420p" } else { "yuv420p" },
            "webm",
        ),
        (_, t) => (
            &["-c:v", "prores_ks", "-profile:v", "4444"],
            if t { "yuva444p10le" } else { "yuv444p10le" },
            "mov",
        ),
    };
    cmd.args(codec)
        .args([
            "-vf",
            &format!("scale=out_color_matrix=bt709,format={pix_fmt}"),
        ])
        .args(["-colorspace", "bt709", "-color_primaries", "bt709"])
        .args(["-color_trc", "bt709"]);
    if format == Format::Mp4 {
        // The index first, so a browser starts playing before the whole file is loaded.
        cmd.args(["-movflags", "+faststart"]);
    }
    cmd.args(["-f", container])
        .arg(tmp)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
}

/// Why the frames stopped before the last.
enum Fed {
    /// A frame could not be drawn.
    Frame(OutputError),
    /// ffmpeg stopped reading (it failed; its status and message say why).
    Closed,
}

/// Draws every frame and writes it to `child`'s standard input, then closes it.
fn feed(
    stage: Stage,
    path: &Path,
    opts: &Options,
    canvas: &Canvas,
    child: &mut Child,
    tick: &(dyn Fn() + Sync),
) -> Result<(), Fed> {
    let anim = stage.anim;
    let sampler = anim.sampler();
    let mut input = child.stdin.take().ok_or(Fed::Closed)?;
    let count = anim.frame_count();
    for first in (0..count).step_by(BATCH) {
        let frames: Vec<Result<Vec<u8>, OutputError>> = (first..(first + BATCH).min(count))
            .into_par_iter()
            .map(|i| {
                let pm = stage.render(Some(&sampler), path, (i, anim.frame_time(i)), opts)?;
                tick();
                Ok(canvas.pixels(&pm))
            })
            .collect();
        for frame in frames {
            let bytes = frame.map_err(Fed::Frame)?;
            input.write_all(&bytes).map_err(|_| Fed::Closed)?;
        }
    }
    // Closing the input ends the video.
    drop(input);
    Ok(())
}

impl Canvas {
    /// `pm` (premultiplied RGBA) as straight RGBA rows of the padded size: composited over
    /// the background, or unpremultiplied when translucency is kept.
    fn pixels(&self, pm: &Pixmap) -> Vec<u8> {
        let (pw, ph) = self.padded;
        let fill = match self.background {
            Some([r, g, b]) => [r, g, b, 255],
            None => [0; 4],
        };
        let mut out: Vec<u8> = fill.repeat(pw as usize * ph as usize);
        // The renderer rounds the size the same way; a frame of another size (never
        // expected) is cropped or padded rather than sheared.
        let (w, h) = (
            self.width.min(pm.width()) as usize,
            self.height.min(pm.height()) as usize,
        );
        let src = pm.data();
        let stride = pm.width() as usize * 4;
        for y in 0..h {
            let row = &src[y * stride..y * stride + w * 4];
            let dst = &mut out[y * pw as usize * 4..][..w * 4];
            for (d, s) in dst.chunks_exact_mut(4).zip(row.chunks_exact(4)) {
                let a = u32::from(s[3]);
                match self.background {
                    Some(bg) => {
                        for c in 0..3 {
                            let over = u32::from(bg[c]) * (255 - a);
                            d[c] = (u32::from(s[c]) + (over + 127) / 255).min(255) as u8;
                        }
                        d[3] = 255;
                    }
                    None if a == 0 => d.copy_from_slice(&[0; 4]),
                    None => {
                        for c in 0..3 {
                            d[c] = ((u32::from(s[c]) * 255 + a / 2) / a).min(255) as u8;
                        }
                        d[3] = s[3];
                    }
                }
            }
        }
        out
    }
}

/// The last [`STDERR_TAIL`] bytes of `text`, on one line.
fn tail(text: &str) -> String {
    let text = text.trim();
    let mut start = text.len().saturating_sub(STDERR_TAIL);
    while !text.is_char_boundary(start) {
        start += 1;
    }
    text[start..]
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}
