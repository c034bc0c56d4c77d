//! Lottie import: a Bodymovin / After Effects JSON document as a gmotion [`Scene`] whose
//! animated units are the layers of its root composition, plus the document itself, kept
//! whole for verbatim pass-through ([`Source`]). The document's model, its evaluation and
//! the player that draws it at any frame are the `gmotion-lottie` crate's; this crate reads
//! the file, its linked images and the reference frame, and makes the scene.
//!
//! **Units.** Every root layer that draws (shape, precomposition, solid, image, text) is a
//! unit; null layers are rigs (they move their children, but are not units); a track
//! matte's source layer (`td`) moves with the layer it mattes, as one unit; hidden layers
//! are not units. Units are in paint order (bottom layer first), and ids count within a
//! tag in that order. Tags come from layer names ([`gmotion_lottie::tags`]). With
//! [`Units::Groups`] the top-level groups of shape layers are the units instead
//! ([`UnitLayers::part`]).
//!
//! **Geometry.** The document is evaluated at a reference time (the first frame where every
//! unit has area, [`reference_frame`], unless [`ImportOptions::time`] says otherwise) as
//! the player draws it at any frame ([`Source::scene_at`]), and each unit is measured on
//! that geometry (centroid, bounds, paint).
//!
//! Image layers draw their asset: embedded (`e: 1`: a PNG, JPEG, GIF or WebP data URL) or
//! linked (`u` + `p`, read from the file's folder by [`load`] under
//! [`gmotion::input::References`]). A file without glyphs has its text set in the
//! machine's fonts, as players set it ([`gmotion_lottie::fonts`], given
//! [`ImportOptions::fonts`]). A text layer drawn from the glyphs its file embeds (`chars`)
//! keeps the layout of its letters, words and lines ([`gmotion::text::TextLayout`]), so
//! the text operators can cut it; one set in fonts says why it cannot be cut.
//!
//! **Not drawn** (with a warning naming the first place and how many): images that cannot
//! be read (their rectangle is measured), text without embedded glyphs when no fonts are
//! given (measured as a point), merge paths and twists (lottie-web applies neither), effects
//! other than Gaussian Blur and Drop Shadow, expressions (the property's own value is used).
//! Offset paths, zig-zags, pucker and bloat, round corners and repeaters are drawn, as
//! lottie-web's modifiers make them.
//!
//! **Errors.** Nothing in the input can make the import panic: every value is checked as it
//! is read, and every error names its JSON location (`$.layers[3].ks.p.k[1].s`); the
//! limits are [`gmotion_lottie`]'s; serde_json refuses documents nested deeper than 128
//! levels.
#![forbid(unsafe_code)]

use std::path::{Path, PathBuf};

use kurbo::Affine;
use serde_json::Value;

use gmotion::Warning;
use gmotion::input::ReadError;
use gmotion::scene::{Node, Scene};

use gmotion_lottie::build;
use gmotion_lottie::model::{self, Document, Loc};
use gmotion_lottie::units::{Role, parent_indices, roles, scene_of, split_parts};

pub use gmotion_lottie::{Source, UnitLayers, Units, fonts};

/// How to import.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportOptions {
    /// The reference time, in seconds from the composition's in point, at which units are
    /// measured and the still scene drawn; `None`: the first frame where every unit draws
    /// something with area ([`reference_frame`]).
    pub time: Option<f64>,
    /// Most pixels an embedded image may declare in its header (default
    /// [`gmotion::scene::DEFAULT_MAX_IMAGE_PIXELS`]; `--limit image-pixels=N`): decoding
    /// allocates them all. A larger image is not drawn (its rectangle is measured), with a
    /// warning; the document written back keeps it.
    pub max_image_pixels: u64,
    /// Folders besides the file's own whose images it may link (`--allow-path DIR`).
    pub allowed_dirs: Vec<PathBuf>,
    /// Largest Lottie file, and largest linked image, read (default
    /// [`gmotion::input::DEFAULT_MAX_INPUT_BYTES`]; `--limit input-bytes=N`).
    pub max_file_bytes: u64,
    /// What the units are (`--units`).
    pub units: Units,
    /// The fonts text the file does not embed is drawn in ([`fonts`]); `None`: such text
    /// is measured as a point, with a warning.
    pub fonts: Option<fonts::SystemFonts>,
}

impl Default for ImportOptions {
    fn default() -> ImportOptions {
        ImportOptions {
            time: None,
            max_image_pixels: gmotion::scene::DEFAULT_MAX_IMAGE_PIXELS,
            allowed_dirs: Vec::new(),
            max_file_bytes: gmotion::input::DEFAULT_MAX_INPUT_BYTES,
            units: Units::Layers,
            fonts: None,
        }
    }
}

/// An imported scene, its source and what could not be kept.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The scene at the reference frame.
    pub scene: Scene,
    /// The document, for pass-through export.
    pub source: Source,
    /// What is not drawn, one per kind, about its first place (`$.layers[2]`): `what (N places)`.
    pub warnings: Vec<Warning>,
}

/// Why a document could not be imported.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// The file could not be read.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The text is not JSON.
    #[error("{source_name}:{line}:{column}: malformed JSON: {message}")]
    Json {
        /// The file name.
        source_name: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What serde_json said.
        message: String,
    },
    /// The reference time asked for lies outside the composition.
    #[error(
        "{source_name}: the reference time {time}s lies outside the composition (0 to {duration}s)"
    )]
    ReferenceTime {
        /// The file name.
        source_name: String,
        /// The reference time asked for, in seconds.
        time: f64,
        /// The composition's length in seconds.
        duration: f64,
    },
    /// The JSON is not a Lottie animation gmotion can read.
    #[error("{source_name}: {at}: {message}")]
    Lottie {
        /// The file name.
        source_name: String,
        /// Where in the document.
        at: Loc,
        /// What is wrong.
        message: String,
    },
}

/// Imports a Lottie file.
/// Images it links (an asset's folder `u` and file `p`, `e: 0`) are read from the file's
/// folder, as players read them, under [`gmotion::input::References`].
pub fn load(path: &Path, opts: &ImportOptions) -> Result<Imported, ImportError> {
    let text = gmotion::input::read_text(path, opts.max_file_bytes).map_err(ReadError::at(path))?;
    let dir = path.parent().map(|d| {
        if d.as_os_str().is_empty() {
            Path::new(".")
        } else {
            d
        }
    });
    let json = json_of(&text, &path.display().to_string())?;
    import(json, &path.display().to_string(), dir, opts)
}

/// Imports Lottie JSON text; `source_name` names it in errors and warnings. Linked images
/// are not read (there is no folder to read them from).
pub fn parse(text: &str, source_name: &str, opts: &ImportOptions) -> Result<Imported, ImportError> {
    import(json_of(text, source_name)?, source_name, None, opts)
}

fn json_of(text: &str, source_name: &str) -> Result<Value, ImportError> {
    serde_json::from_str(text.trim_start_matches('\u{feff}')).map_err(|e| {
        let message = e.to_string();
        let message = message
            .rsplit_once(" at line ")
            .map_or(message.as_str(), |(m, _)| m)
            .to_string();
        ImportError::Json {
            source_name: source_name.to_string(),
            line: e.line(),
            column: e.column(),
            message,
        }
    })
}

/// Imports a parsed document; linked images are not read.
pub fn from_json(
    json: Value,
    source_name: &str,
    opts: &ImportOptions,
) -> Result<Imported, ImportError> {
    import(json, source_name, None, opts)
}

fn import(
    json: Value,
    source_name: &str,
    dir: Option<&Path>,
    opts: &ImportOptions,
) -> Result<Imported, ImportError> {
    let located = |e: model::ModelError| ImportError::Lottie {
        source_name: source_name.to_string(),
        at: e.at,
        message: e.message,
    };
    let mut document = Document::read(&json).map_err(located)?;
    let font_warnings = match &opts.fonts {
        Some(f) => fonts::fill_in(&mut document, f),
        None => Vec::new(),
    };
    let refs = gmotion::input::References {
        owner: "Lottie file",
        dir,
        allowed: &opts.allowed_dirs,
        max_bytes: opts.max_file_bytes,
    };
    for a in &mut document.assets {
        a.image = picture(a, &refs);
        let declared = match &a.image {
            Ok(Some((data, _))) => gmotion::scene::image_pixel_size(data),
            _ => None,
        };
        // Too many pixels to decode, or so thin that usvg panics fitting it (see the SVG
        // importer's image screening).
        if let Some((w, h)) = declared
            && (w.saturating_mul(h) > opts.max_image_pixels
                || w == 0
                || h == 0
                || w.max(h) / w.min(h) > 65_536)
        {
            a.oversized = Some((w, h));
        }
    }
    let mut reference_warning = None;
    let frame = match opts.time {
        Some(time) => {
            let frame = document.ip + time * document.fr;
            if !(frame.is_finite() && document.ip <= frame && frame <= document.op) {
                return Err(ImportError::ReferenceTime {
                    source_name: source_name.to_string(),
                    time,
                    duration: (document.op - document.ip) / document.fr,
                });
            }
            frame
        }
        None => {
            let (frame, empty) = reference_frame(&document, opts.units).map_err(located)?;
            if empty > 0 {
                reference_warning = Some((
                    Loc::root().to_string(),
                    format!(
                        "no frame shows every unit: {empty} have no area at frame {frame}, where they are measured (their `local` motion pivots about a point; set `reference_time` to measure them elsewhere)"
                    ),
                ));
            }
            frame
        }
    };
    let (root, shapes, units, warnings) =
        scene_of(&document, frame, opts.units, None).map_err(located)?;
    let scene = Scene {
        width: document.w,
        height: document.h,
        root,
        shapes,
        time: Some(gmotion::scene::SceneTime {
            duration: (document.op - document.ip) / document.fr,
            fps: document.fr,
        }),
        keys: Vec::new(),
    };
    let warnings = font_warnings
        .into_iter()
        .map(|(at, what)| (at.to_string(), what))
        .chain(reference_warning)
        .chain(warnings)
        .map(|(at, what)| Warning::about(at, what))
        .collect();
    Ok(Imported {
        scene,
        source: Source {
            json,
            document,
            units,
            mode: opts.units,
            frame,
        },
        warnings,
    })
}

/// An image asset's picture: embedded (`e: 1`, a data URL) or linked (the file `u` + `p`
/// next to the document, read under `refs`); `Ok(None)` for an asset that is not an
/// image, `Err` saying why a picture could not be had.
fn picture(
    a: &model::Asset,
    refs: &gmotion::input::References,
) -> Result<Option<build::Picture>, String> {
    let Some(p) = a.p.as_deref().filter(|_| a.layers.is_none()) else {
        return Ok(None);
    };
    if p.starts_with("data:") {
        return build::embedded_image(p)
            .map(Some)
            .ok_or_else(|| "only PNG, JPEG, GIF and WebP data URLs are read".into());
    }
    let href = format!("{}{p}", a.u.as_deref().unwrap_or(""));
    let real = refs
        .check(&href)
        .map_err(|why| format!("`{href}`: {why}"))?;
    let data = gmotion::input::read_regular(&real, refs.max_bytes)
        .map_err(|e| format!("`{href}`: {e}"))?;
    let format = gmotion::scene::ImageFormat::sniff(&data)
        .ok_or_else(|| format!("`{href}` is not a PNG, JPEG, GIF or WebP image"))?;
    Ok(Some((std::sync::Arc::from(data), format)))
}
/// Most frames [`reference_frame`] looks at, evenly spread from the first.
pub const REFERENCE_TRIES: usize = 240;

/// The frame a Lottie scene's units are measured at when no reference time is given: the
/// first where every unit draws something with area (a unit that scales in from nothing,
/// or is drawn on by a trim path, has none at frame 0, and `local` motion would pivot
/// about a point), trying each frame from the in point, at most [`REFERENCE_TRIES`]. When
/// none shows them all, the first that shows the most; with how many it misses.
pub fn reference_frame(doc: &Document, mode: Units) -> model::Result<(f64, usize)> {
    let (ip, op) = (doc.ip, doc.op);
    let span = (op - ip).max(0.0);
    let step = (span / REFERENCE_TRIES as f64).max(1.0);
    // What each layer is does not change with the frame: found once for every try.
    let parents = parent_indices(&doc.layers);
    let roles = roles(&doc.layers, mode, &|i: usize| parents[i]);
    let mut best: Option<(f64, usize)> = None;
    let mut k = 0;
    loop {
        // Whole frames from the in point, as players draw them.
        let frame = ip + (k as f64 * step).round();
        if k > 0 && frame >= op {
            break;
        }
        let empty = units_without_area(doc, frame, &roles)?;
        if best.is_none_or(|(_, e)| empty < e) {
            best = Some((frame, empty));
        }
        if empty == 0 {
            break;
        }
        k += 1;
    }
    Ok(best.unwrap_or((ip, 0)))
}

/// How many of the scene's units (by the layers' `roles`) draw nothing with area at
/// `frame`.
fn units_without_area(doc: &Document, frame: f64, roles: &[Role]) -> model::Result<usize> {
    let layers = &doc.layers;
    let mut b = build::Builder::new(doc);
    let worlds = b.worlds(layers, frame)?;
    let mut stack = Vec::new();
    let mut empty = 0;
    for (i, l) in layers.iter().enumerate() {
        let parts = match roles[i] {
            Role::Whole => vec![None],
            Role::Parts => split_parts(l),
            Role::Rig | Role::None => continue,
        };
        for part in parts {
            let node = b.drawn(layers, i, &worlds, frame, &mut stack, part)?;
            let on = l.ip <= frame && frame < l.op;
            if !(on && has_area(&Node::Group(node), Affine::IDENTITY)) {
                empty += 1;
            }
        }
    }
    Ok(empty)
}

/// Whether `node`, placed by `at`, draws something with width and height (a stroked
/// line has its stroke's width).
fn has_area(node: &Node, at: Affine) -> bool {
    use kurbo::Shape as _;
    match node {
        Node::Group(g) => {
            g.opacity > 0.0 && g.children.iter().any(|c| has_area(c, at * g.transform))
        }
        Node::Path(p) => {
            if p.fill.is_none() && p.stroke.is_none() {
                return false;
            }
            let half = p.stroke.as_ref().map_or(0.0, |s| s.width / 2.0);
            let b = p.path.bounding_box().inflate(half, half);
            let area = (at * b.to_path(0.1)).bounding_box();
            area.width() > 1e-9 && area.height() > 1e-9 && at.determinant().abs() > 1e-18
        }
        Node::Image(i) => i.width > 0.0 && i.height > 0.0 && at.determinant().abs() > 1e-18,
    }
}
