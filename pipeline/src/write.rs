//! One writer for every output: the animation (with the Lottie source it moves, when its
//! scene came from one) written by extension to a file, or to bytes.

use std::path::Path;
use std::sync::Arc;

use gmotion::Warning;
use gmotion::canvas::OutputSize;
use gmotion::engine::expand::Expansion;
use gmotion::engine::markers::Marker;
use gmotion::engine::slots::SlotKinds;
use gmotion::motion::Animation;
use gmotion_output::dotlottie::Picked;
use gmotion_output::{self as output, LottieSource};

use crate::Result;
use crate::env::Limits;
use crate::html;
use crate::scene::Imported;

/// A run's animation with what its outputs draw besides: the Lottie document its scene
/// came from, and the slices the HTML page's timeline shows.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The animation.
    pub anim: Animation,
    /// The Lottie document the scene came from, if it came from one.
    pub source: Option<Arc<LottieSource>>,
    /// The dotLottie package that document came from, if it did: a `.lottie` output is
    /// that package with the animation replaced.
    pub package: Option<Arc<Picked>>,
    /// The markers the grammar asks for (`markers`), written into Lottie outputs.
    pub markers: Vec<Marker>,
    /// The properties the grammar gives Lottie slots (`slots`).
    pub slots: SlotKinds,
    /// Every shape's final slices, when the run kept them ([`crate::Project::run`]).
    pub timelines: Option<Expansion>,
}

/// Writes by extension: `.json` Lottie, `.lottie` dotLottie, `.svg` SMIL, `.png` the frame at
/// [`output::Options::time`], `.gif`, `.apng`, `.html` (the page, [`html`]), and a path
/// without extension (or an existing folder, or a `%04d` pattern) a PNG per frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Writer {
    /// How to write.
    pub options: output::Options,
}

impl Writer {
    /// A writer of outputs of `size` under `limits` (`pixels`, `animation-pixels`), with
    /// the default tolerance, `.png` showing the first frame.
    pub fn new(size: OutputSize, limits: &Limits) -> Writer {
        Writer {
            options: output::Options {
                size,
                max_pixels: limits.get("pixels"),
                max_animation_pixels: limits.get("animation-pixels"),
                ..output::Options::default()
            },
        }
    }

    /// Whether `path` is written one frame at a time (GIF, APNG, video, a folder of
    /// frames): what a progress bar counts. A name no format is known by is an error.
    pub fn draws_every_frame(path: &Path) -> Result<bool> {
        if html::is_page(path) {
            return Ok(false);
        }
        let format = output::Format::of(path)?;
        Ok(format.is_video()
            || matches!(
                format,
                output::Format::Frames | output::Format::Gif | output::Format::Apng
            ))
    }

    /// Writes `r` to `path` whole or not at all, calling `tick` once per frame rendered;
    /// returns what the format could not show exactly.
    pub fn write(
        &self,
        r: &Rendered,
        path: &Path,
        tick: &(dyn Fn() + Sync),
    ) -> Result<Vec<Warning>> {
        let options = self.options_for(r);
        if html::is_page(path) {
            return html::write_page(r, path, &options);
        }
        Ok(output::write_over_source(
            &r.anim,
            r.source.as_deref(),
            r.package.as_deref(),
            &r.markers,
            path,
            &options,
            tick,
        )?)
    }

    /// The bytes [`Writer::write`] would write to `path` (which names the format and is
    /// named in errors; nothing is written), and its warnings. A folder of frames has no
    /// single bytes.
    pub fn bytes(&self, r: &Rendered, path: &Path) -> Result<(Vec<u8>, Vec<Warning>)> {
        let options = self.options_for(r);
        if html::is_page(path) {
            let (page, warnings) = html::page(r, path, &options)?;
            return Ok((page.into_bytes(), warnings));
        }
        Ok(output::bytes_over_source(
            &r.anim,
            r.source.as_deref(),
            r.package.as_deref(),
            &r.markers,
            path,
            &options,
        )?)
    }

    /// The options `r` is written with: this writer's, with the slots its grammar asks for.
    fn options_for(&self, r: &Rendered) -> output::Options {
        output::Options {
            slots: r.slots,
            ..self.options
        }
    }

    /// Writes a still scene to `path`: `.png` rendered, `.json` a still Lottie (a Lottie
    /// source written back as it was read), `.lottie` that packaged (in the package it
    /// came from, the other animations and themes kept), `.svg` a clean SVG; a Lottie source, which
    /// moves by itself, is also played to `.gif`, `.apng` or a folder of frames, and to
    /// `.svg` when [`output::Options::play_svg`].
    pub fn write_still(&self, still: &Imported, path: &Path) -> Result<Vec<Warning>> {
        Ok(output::write_still_over_source(
            &still.scene,
            still.source.as_deref(),
            still.package.as_deref(),
            path,
            &self.options,
        )?)
    }
}
