//! What every load, run and write is done under: the limits users can see and raise
//! (`--limit NAME=N`), the folders a scene may read from, the fonts, and where warnings go.

use std::fmt;
use std::path::{Path, PathBuf};

use gmotion_import_svg::fonts::FontOptions;

use crate::{Error, Result};

/// What the pipeline runs under.
#[derive(Clone, Debug)]
pub struct Env {
    /// The limits in force.
    pub limits: Limits,
    /// Folders whose files a scene may reference besides its own (`--allow-path`).
    pub allow: Vec<PathBuf>,
    /// Fonts for SVG text and Lottie text without glyphs (`--font-dir`, `--font-file`,
    /// `--font-family`).
    pub fonts: FontOptions,
    /// Told each warning as it arises (an import's, a run's), with the file it concerns,
    /// so a front end can print it before a later step fails.
    pub warn: fn(&Path, &dyn fmt::Display),
}

impl Default for Env {
    /// The default limits, no extra folder or font, warnings dropped.
    fn default() -> Env {
        Env {
            limits: Limits::default(),
            allow: Vec::new(),
            fonts: FontOptions::default(),
            warn: |_, _| {},
        }
    }
}

impl Env {
    /// The SVG importer's policy under these limits, folders and fonts.
    pub fn svg_policy(&self) -> gmotion_import_svg::Policy {
        self.limits.svg_policy(&self.allow, &self.fonts)
    }
}

/// Every limit, its name for `--limit`, its default and what it bounds (the README's
/// "Limits" section lists the same).
pub const LIMITS: &[(&str, u64, &str)] = &[
    (
        "input-bytes",
        gmotion::input::DEFAULT_MAX_INPUT_BYTES,
        "size of a scene, grammar, targets file or referenced image",
    ),
    (
        "svgz-bytes",
        64 << 20,
        "decompressed size of a .svgz (or gzip data URI)",
    ),
    (
        "xml-entity-bytes",
        1 << 20,
        "total text XML entities expand to",
    ),
    (
        "xml-nodes",
        gmotion_import_svg::MAX_XML_NODES as u64,
        "XML nodes of an SVG (elements, the text between them, comments)",
    ),
    (
        "css-rules",
        10_000,
        "CSS rules in an SVG's <style> elements",
    ),
    (
        "path-segments",
        gmotion_import_svg::MAX_PATH_SEGMENTS,
        "path segments of an SVG (commands of `d`, points of `points`)",
    ),
    (
        "text-chars",
        gmotion_import_svg::MAX_TEXT_CHARS,
        "characters of one SVG <text> element",
    ),
    (
        "text-spans",
        gmotion_import_svg::MAX_TEXT_SPANS,
        "elements (<tspan>, <a>, …) inside one SVG <text> element",
    ),
    (
        "filter-pixels",
        gmotion_import_svg::MAX_BAKED_PIXELS,
        "pixels of all SVG filters drawn as images (those no Lottie effect expresses)",
    ),
    (
        "image-pixels",
        gmotion::scene::DEFAULT_MAX_IMAGE_PIXELS,
        "pixels a raster image in an SVG or Lottie scene may declare (decoding allocates them)",
    ),
    ("frames", 10_000, "frames of an animation (duration × fps)"),
    (
        "pixels",
        gmotion_export_raster::DEFAULT_MAX_PIXELS,
        "pixels of one rendered image",
    ),
    (
        "animation-pixels",
        gmotion_output::DEFAULT_MAX_ANIMATION_PIXELS,
        "pixels of all frames of a GIF, APNG or frames folder",
    ),
    (
        "steps",
        100_000,
        "largest --max-steps or max_steps (expansion time grows with its square)",
    ),
    (
        "pieces",
        gmotion::tangle::DEFAULT_MAX_PIECES as u64,
        "shapes a group grammar may make (about 4 KB each; four times as many over all its steps), and pieces one `place` may scatter",
    ),
    (
        "spatial-seconds",
        60,
        "seconds a group grammar's expansion may run (a rule feeding itself on shapes costly to cut)",
    ),
    ("learn-units", 10_000, "units (layers) `gmotion learn` fits"),
    (
        "learn-samples",
        5_000_000,
        "samples `gmotion learn` takes (units × frames of the animation)",
    ),
];

/// The limits in force.
#[derive(Clone, Debug)]
pub struct Limits {
    values: Vec<u64>,
}

impl Limits {
    /// The defaults, with each `NAME=N` of `--limit` applied.
    pub fn parse(args: &[String]) -> Result<Limits> {
        let mut values: Vec<u64> = LIMITS.iter().map(|l| l.1).collect();
        for a in args {
            let names = || LIMITS.iter().map(|l| l.0).collect::<Vec<_>>().join(", ");
            let Some((name, value)) = a.split_once('=') else {
                return Err(Error::msg(format!(
                    "--limit {a}: expected NAME=N, one of {}",
                    names()
                )));
            };
            let Some(i) = LIMITS.iter().position(|l| l.0 == name.trim()) else {
                return Err(Error::msg(format!(
                    "--limit {a}: unknown limit `{name}`; the limits are {}",
                    names()
                )));
            };
            let v = value.trim();
            let parsed = v.parse::<u64>().ok().or_else(|| {
                v.parse::<f64>()
                    .ok()
                    .filter(|f| f.is_finite() && *f >= 0.0 && *f < 1.8e19)
                    .map(|f| f as u64)
            });
            values[i] = parsed
                .ok_or_else(|| Error::msg(format!("--limit {a}: `{v}` is not a whole number")))?;
        }
        Ok(Limits { values })
    }

    /// The value of limit `name` (one of [`LIMITS`]).
    pub fn get(&self, name: &str) -> u64 {
        LIMITS
            .iter()
            .position(|l| l.0 == name)
            .map_or(u64::MAX, |i| self.values[i])
    }

    /// The SVG importer's policy under these limits, `--allow-path` and the font options.
    pub fn svg_policy(
        &self,
        allow: &[PathBuf],
        fonts: &gmotion_import_svg::fonts::FontOptions,
    ) -> gmotion_import_svg::Policy {
        gmotion_import_svg::Policy {
            fonts: fonts.clone(),
            allowed_dirs: allow.to_vec(),
            max_file_bytes: self.get("input-bytes"),
            max_svgz_bytes: self.get("svgz-bytes"),
            max_entity_bytes: self.get("xml-entity-bytes"),
            max_xml_nodes: u32::try_from(self.get("xml-nodes")).unwrap_or(u32::MAX),
            max_css_rules: u32::try_from(self.get("css-rules")).unwrap_or(u32::MAX),
            max_path_segments: self.get("path-segments"),
            max_text_chars: self.get("text-chars"),
            max_text_spans: self.get("text-spans"),
            max_baked_pixels: self.get("filter-pixels"),
            max_image_pixels: self.get("image-pixels"),
            max_canvas_pixels: self.get("pixels"),
        }
    }

    /// Refuses `frames` frames past the `frames` limit; `what` says where they come from.
    pub fn check_frames(&self, frames: f64, what: &str) -> Result<()> {
        let limit = self.get("frames");
        if frames.is_nan() || frames > limit as f64 {
            return Err(Error::msg(format!(
                "{what} make {} frames, more than the limit of {limit} (raise it with --limit frames=N)",
                short(frames)
            )));
        }
        Ok(())
    }
}

/// `x` as written by a person: plain below a million, else in exponent form.
pub fn short(x: f64) -> String {
    if x.abs() < 1e6 {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

impl Default for Limits {
    /// Every limit at its default.
    fn default() -> Limits {
        Limits {
            values: LIMITS.iter().map(|l| l.1).collect(),
        }
    }
}
