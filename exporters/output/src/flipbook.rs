//! A Lottie source played as animated SVG (`gmotion convert anim.json -o anim.svg`, and
//! `gmotion animate anim.json motion.gm -o out.svg` when the source moves by itself): every
//! frame drawn by gmotion's own renderer (the source evaluated at the frame, moved by the
//! animation's tracks), each frame that differs from the one before an `<image>` holding
//! its own SVG document (so the ids of its masks, gradients and clips stay its own), shown
//! in turn by a discrete SMIL `display` animation. Frame for frame what a GIF shows, but
//! in vectors, scalable and without a palette; the file grows with the frames that differ,
//! bounded by [`MAX_BYTES`]. A viewer without SMIL shows the first frame.
//!
//! Why frames rather than animated elements: a Lottie's own motion (path keyframes, trims,
//! mattes, repeaters, time remapping) has no general counterpart in SMIL's attribute
//! animation; frames are exact wherever gmotion's own render is.

use std::fmt::Write as _;
use std::path::Path;

use base64::Engine as _;
use gmotion_export_svg::frame;

use crate::{LottieSource, Options, OutputError, Stage};

/// The most bytes a played Lottie may take as SVG (256 MiB): past it, a GIF, APNG or
/// frames folder says the same in far less.
pub const MAX_BYTES: usize = 256 << 20;

/// Whether `src` moves by itself: its first frame and some later one differ.
pub(crate) fn moves(src: &LottieSource) -> bool {
    let frames = ((src.duration() * src.fps()).round() as usize).max(1);
    let at = |k: usize| {
        src.scene_at(src.frame_at(k as f64 / src.fps()))
            .map(|(scene, _)| frame::scene_svg(&scene))
            .ok()
    };
    let first = at(0);
    // Eight frames spread over the composition: a source that differs nowhere among them
    // but moves between them is rare, and still drawn (at its reference frame) with the
    // animation's motion.
    (1..=8).any(|i| at(i * (frames - 1) / 8) != first)
}

/// `stage` played from its first frame to its last as SMIL, for `path` (named in errors).
pub(crate) fn smil(stage: Stage, path: &Path, opts: &Options) -> Result<String, OutputError> {
    let anim = stage.anim;
    let frames = anim.frame_count();
    let sampler = anim.sampler();
    let mut shown: Vec<(usize, String)> = Vec::new();
    let mut bytes = 0usize;
    let (width, height) = (anim.scene.width, anim.scene.height);
    for k in 0..frames {
        let svg = stage.svg(Some(&sampler), path, (k, anim.frame_time(k)))?;
        if shown.last().is_some_and(|(_, last)| *last == svg) {
            continue;
        }
        bytes += svg.len().div_ceil(3) * 4 + 256;
        if bytes > MAX_BYTES {
            return Err(OutputError::TooLargeAsSvg {
                path: path.to_path_buf(),
                frames: k + 1,
                max: MAX_BYTES,
            });
        }
        shown.push((k, svg));
    }
    let mut out = String::with_capacity(bytes + 512);
    let _ = write!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}">"#
    );
    let dur = frames as f64 / anim.fps;
    for (i, (k, svg)) in shown.iter().enumerate() {
        let end = shown.get(i + 1).map_or(frames, |(next, _)| *next);
        let display = if i == 0 { "inline" } else { "none" };
        let _ = write!(
            out,
            "\n<image width=\"{width}\" height=\"{height}\" display=\"{display}\" href=\"data:image/svg+xml;base64,"
        );
        base64::engine::general_purpose::STANDARD.encode_string(svg.as_bytes(), &mut out);
        out.push('"');
        if shown.len() == 1 {
            out.push_str("/>");
            continue;
        }
        // Shown from frame `k` up to the next distinct frame, hidden otherwise.
        let (on, off) = (*k as f64 / frames as f64, end as f64 / frames as f64);
        let (values, times) = match (*k == 0, end == frames) {
            (true, _) => ("inline;none".to_string(), format!("0;{off}")),
            (false, true) => ("none;inline".to_string(), format!("0;{on}")),
            (false, false) => ("none;inline;none".to_string(), format!("0;{on};{off}")),
        };
        let _ = write!(
            out,
            "><animate attributeName=\"display\" values=\"{values}\" keyTimes=\"{times}\" dur=\"{dur}s\" calcMode=\"discrete\" repeatCount=\"indefinite\"/></image>"
        );
    }
    out.push_str("\n</svg>\n");
    let out = match opts.size.fit(width, height) {
        Some(fit) => frame::with_output_size(&out, &fit),
        None => out,
    };
    Ok(out)
}
