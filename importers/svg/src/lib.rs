//! SVG import: usvg normalises the file (CSS, `use`, markers, units, shapes to paths), then
//! the usvg tree becomes a [`Scene`] and its animated units are chosen and tagged.
//!
//! What is kept: groups with transform, opacity, clip path and mask; paths with fill
//! (paint, opacity, rule) and stroke (paint, opacity, width, caps, joins, miter limit,
//! dashes) and paint order; linear and radial gradients, patterns, clip paths and masks,
//! each converted once and shared. Markers arrive as ordinary paths (usvg instantiates
//! them). Text is converted to outlines with the system fonts and those of
//! [`Policy::fonts`] ([`fonts`]): a text in a missing font is drawn in the default family,
//! with a warning naming the font and the element.
//!
//! Raster images (PNG, JPEG, GIF, WebP, embedded or linked under the file-access policy)
//! become [`gmotion::scene::ImageNode`]s, units like paths; an SVG image becomes the vector
//! content it holds, clipped to its viewport.
//!
//! What is not: filters, blend modes and `shape-rendering` hints are dropped with a warning
//! that names the element (see [`Imported::warnings`]).
//!
//! Tags are read from the source text (see [`TagFrom`]): usvg keeps only ids, so elements
//! without one get a synthetic id before usvg parses the text, and every usvg node is traced
//! back to its source element. Paths that usvg instantiates for a `use` lose their ids; they
//! are matched to the referenced element's shapes in order when the counts agree, and
//! otherwise take their tags from the `use` and its ancestors. The unit rules are in
//! [`Units`].

mod access;
mod convert;
mod filters;
mod keys;
pub use filters::MAX_BAKED_PIXELS;
pub mod fonts;
mod source;
pub mod tagmap;
pub mod tags;
mod text;

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use gmotion::Warning;
use gmotion::input::ReadError;
use gmotion::measure::{Measure, measure};
use gmotion::scene::{Scene, Shape};
pub use gmotion::tagging::{TagFrom, Units};

/// How to import.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportOptions {
    /// Where tags come from.
    pub tag_from: TagFrom,
    /// Which nodes are animated units.
    pub units: Units,
    /// How deep a group must sit to become a unit: 1 (the default) lets top-level groups
    /// be units, 2 only the groups inside them, and so on (`--unit-depth N`). Shallower
    /// groups are looked into; paths outside any unit are units of their own.
    pub unit_depth: usize,
    /// Tags and units given from outside the file (`--tags FILE`, see [`tagmap`]).
    pub tag_map: Option<std::sync::Arc<tagmap::TagMap>>,
}

impl Default for ImportOptions {
    fn default() -> ImportOptions {
        ImportOptions {
            tag_from: TagFrom::default(),
            units: Units::default(),
            unit_depth: 1,
            tag_map: None,
        }
    }
}

/// What an SVG may make gmotion read, and how much: the file-access policy and the limits
/// of the SVG importer. [`Policy::default`] is what `gmotion` uses unless told otherwise.
///
/// Files an SVG references (`<image href>`, `<feImage href>`) are read only when they lie
/// inside the SVG's own folder or one of [`Policy::allowed_dirs`] (after resolving `..` and
/// symbolic links) and are regular files; data URIs are always allowed. Anything else
/// (absolute paths elsewhere, `..` escapes, devices, FIFOs) is refused with a warning naming
/// the element, and the element is dropped.
#[derive(Clone, Debug)]
pub struct Policy {
    /// Folders besides the SVG's own whose files it may reference (`--allow-path DIR`).
    pub allowed_dirs: Vec<PathBuf>,
    /// Largest SVG file read, and largest referenced file (default
    /// [`gmotion::input::DEFAULT_MAX_INPUT_BYTES`]; `--limit input-bytes=N`).
    pub max_file_bytes: u64,
    /// Largest decompressed size of a `.svgz` (default 64 MiB; `--limit svgz-bytes=N`).
    pub max_svgz_bytes: u64,
    /// Most text XML entities may expand to in total (default 1 MiB;
    /// `--limit xml-entity-bytes=N`): a pre-check, since the XML parser has no such limit.
    pub max_entity_bytes: u64,
    /// Most XML nodes (elements, the text between them, comments) a document may have
    /// (default [`MAX_XML_NODES`]; `--limit xml-nodes=N`).
    pub max_xml_nodes: u32,
    /// Most CSS rules the `<style>` elements of a document may hold together (default
    /// 10 000; `--limit css-rules=N`).
    pub max_css_rules: u32,
    /// Most path segments (commands of `d`, points of `points`) a document may hold
    /// together, counted before usvg builds them (default [`MAX_PATH_SEGMENTS`];
    /// `--limit path-segments=N`).
    pub max_path_segments: u64,
    /// Most characters one `<text>` element may hold, its spans' included (default
    /// [`MAX_TEXT_CHARS`]; `--limit text-chars=N`).
    pub max_text_chars: u64,
    /// Most elements (`<tspan>`, `<a>`, `<textPath>`, …) one `<text>` element may hold
    /// (default [`MAX_TEXT_SPANS`]; `--limit text-spans=N`).
    pub max_text_spans: u64,
    /// Most pixels drawn for filters that are drawn as images, over the whole document
    /// (default [`MAX_BAKED_PIXELS`]; `--limit filter-pixels=N`); past it, such filters
    /// are left out with a warning.
    pub max_baked_pixels: u64,
    /// Most pixels a raster image (`<image>`, `<feImage>`, a data URI or a file) may
    /// declare in its header (default [`gmotion::scene::DEFAULT_MAX_IMAGE_PIXELS`];
    /// `--limit image-pixels=N`): decoding allocates them all, so a few hundred bytes of
    /// PNG can ask for a hundred gigabytes. A larger image is dropped with a warning.
    pub max_image_pixels: u64,
    /// Most pixels a picture of the canvas at its own size may have (the `pixels` limit,
    /// `--limit pixels=N`): a larger canvas is warned about at its `<svg>` element, where
    /// the file sets the size, since a PNG, GIF or video at that size is refused later by
    /// the renderer, which knows the output but not the file.
    pub max_canvas_pixels: u64,
    /// Fonts besides the system's, and the family a text in a missing font is drawn in
    /// (`--font-dir`, `--font-file`, `--font-family`).
    pub fonts: fonts::FontOptions,
}

impl Default for Policy {
    fn default() -> Policy {
        Policy {
            allowed_dirs: Vec::new(),
            max_file_bytes: gmotion::input::DEFAULT_MAX_INPUT_BYTES,
            max_svgz_bytes: 64 << 20,
            max_entity_bytes: 1 << 20,
            max_xml_nodes: MAX_XML_NODES,
            max_css_rules: 10_000,
            max_path_segments: MAX_PATH_SEGMENTS,
            max_text_chars: MAX_TEXT_CHARS,
            max_text_spans: MAX_TEXT_SPANS,
            max_baked_pixels: MAX_BAKED_PIXELS,
            max_image_pixels: gmotion::scene::DEFAULT_MAX_IMAGE_PIXELS,
            max_canvas_pixels: gmotion::scene::DEFAULT_MAX_IMAGE_PIXELS,
            fonts: fonts::FontOptions::default(),
        }
    }
}

/// The default of [`Policy::max_xml_nodes`]: four million, room for every document usvg
/// accepts. usvg itself stops past a million elements (its fixed element limit), and a
/// document has several XML nodes an element: one written a line has the line break's
/// text after it, one indented beside a comment four nodes. At one million, a scene of
/// 999 000 shapes written one a line was refused for its line breaks.
pub const MAX_XML_NODES: u32 = 4_000_000;

/// The default of [`Policy::max_path_segments`]: ten million segments (a 2-million-segment
/// path, 17 MB of text, animates in under 3 s; each segment costs about 100 bytes through
/// usvg and the scene).
pub const MAX_PATH_SEGMENTS: u64 = 10_000_000;

/// The default of [`Policy::max_text_chars`]: usvg lays a span of 10 000 characters out in
/// about half a second, and its time grows faster than the characters.
pub const MAX_TEXT_CHARS: u64 = 10_000;

/// The default of [`Policy::max_text_spans`]: usvg's layout time grows with spans times
/// characters, so a text at both limits takes about 3 s (1 000 spans of 10 characters).
pub const MAX_TEXT_SPANS: u64 = 1_000;

/// An imported scene with what could not be kept.
///
/// Shapes are in paint order (`z` is their index). A shape's `fill` and `stroke` carry the
/// fill and stroke opacity as alpha. Scene node ids are the source's ids, each used once:
/// elements without one, and later elements repeating one, get an empty id.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The scene; it may have no shapes (an empty or invisible drawing).
    pub scene: Scene,
    /// One line per thing dropped or approximated, deduplicated, in the form
    /// `file: <element id="…"> (line N): what happened`.
    pub warnings: Vec<Warning>,
}

/// Why an SVG could not be imported.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// The file could not be read.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The text is not well-formed XML.
    #[error("{source_name}:{line}:{column}: malformed XML: {message}")]
    Xml {
        /// The file name (or what the caller named the text).
        source_name: String,
        /// 1-based line.
        line: u32,
        /// 1-based column.
        column: u32,
        /// What is wrong.
        message: String,
    },
    /// The bytes are not UTF-8 text, or a `.svgz` did not decompress.
    #[error("{source_name}: {message}")]
    Encoding {
        /// The file name.
        source_name: String,
        /// What is wrong.
        message: String,
    },
    /// The root element is not `<svg>`.
    #[error("{source_name}: not an SVG document: the root element is <{found}>, expected <svg>")]
    NotSvg {
        /// The file name.
        source_name: String,
        /// The root element's name.
        found: String,
    },
    /// Width or height is zero or negative, or missing with no `viewBox` to derive it from.
    #[error(
        "{source_name}: the SVG has no usable size: width and height must be positive (or a viewBox given)"
    )]
    Size {
        /// The file name.
        source_name: String,
    },
    /// usvg refused the document for another reason (e.g. too many elements).
    #[error("{source_name}: cannot convert the SVG: {message}")]
    Svg {
        /// The file name.
        source_name: String,
        /// usvg's reason.
        message: String,
    },
}

/// Imports an SVG (or gzip-compressed `.svgz`) file; external images resolve relative to it.
pub fn load(path: &Path, opts: &ImportOptions) -> Result<Imported, ImportError> {
    load_with(path, opts, &Policy::default())
}

/// A hint for a scene whose tags mostly name nothing a designer chose (generated style
/// classes such as `st0`, element names such as `path`; see
/// [`gmotion::tagging::looks_generated`]): the `--tag-from` source that names more of its
/// shapes, found by importing `path` again under each other source, with a few of the
/// names it gives. `None` when most tags are names already, or no other source does
/// better. `scene` is `path` imported under `opts`.
pub fn tag_hint(
    path: &Path,
    opts: &ImportOptions,
    policy: &Policy,
    scene: &Scene,
) -> Option<String> {
    let named = |scene: &Scene| {
        let names = scene.shapes.iter().map(|s| s.tag.as_str());
        names
            .filter(|t| !gmotion::tagging::looks_generated(t))
            .count()
    };
    let (have, total) = (named(scene), scene.shapes.len());
    if total == 0 || have * 2 >= total {
        return None;
    }
    // A source is better when it names a larger share of its units (each source may
    // choose different units) and more of them.
    let mut best: Option<(TagFrom, usize, Scene)> = None;
    for from in TagFrom::ALL.into_iter().filter(|f| *f != opts.tag_from) {
        let other = ImportOptions {
            tag_from: from,
            ..opts.clone()
        };
        let Ok(imported) = load_with(path, &other, policy) else {
            continue;
        };
        let n = named(&imported.scene);
        let better_than = |k: usize, of: usize| n * of > k * imported.scene.shapes.len() && n > k;
        let beats = match &best {
            None => better_than(have, total),
            Some((_, k, s)) => better_than(*k, s.shapes.len()),
        };
        if beats {
            best = Some((from, n, imported.scene));
        }
    }
    let (from, n, better) = best?;
    let mut examples: Vec<&str> = Vec::new();
    for tag in better.shapes.iter().map(|s| s.tag.as_str()) {
        if examples.len() < 3 && !gmotion::tagging::looks_generated(tag) && !examples.contains(&tag)
        {
            examples.push(tag);
        }
    }
    let mut generated: Vec<&str> = Vec::new();
    for tag in scene.shapes.iter().map(|s| s.tag.as_str()) {
        if generated.len() < 3
            && gmotion::tagging::looks_generated(tag)
            && !generated.contains(&tag)
        {
            generated.push(tag);
        }
    }
    Some(format!(
        "{} of {total} shapes have tags no designer chose ({}, …): `--tag-from {}` (or `tag_from {}` in the grammar) names {n} of {} ({}, …)",
        total - have,
        generated.join(", "),
        from.name(),
        from.name(),
        better.shapes.len(),
        examples.join(", ")
    ))
}

/// Decompresses gzip `bytes`, refusing more than `limit` bytes of output.
fn gunzip(bytes: &[u8], limit: u64) -> Result<Vec<u8>, String> {
    use std::io::Read;
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(bytes)
        .take(limit.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| format!("the .svgz does not decompress: {e}"))?;
    if out.len() as u64 > limit {
        return Err(format!(
            "the .svgz decompresses to more than the limit of {limit} bytes (raise it with --limit svgz-bytes=N)"
        ));
    }
    Ok(out)
}

/// [`load`] under `policy`: what the file may reference and how large it may be.
pub fn load_with(
    path: &Path,
    opts: &ImportOptions,
    policy: &Policy,
) -> Result<Imported, ImportError> {
    let name = path.display().to_string();
    let bytes =
        gmotion::input::read_regular(path, policy.max_file_bytes).map_err(ReadError::at(path))?;
    let bytes = if bytes.starts_with(&[0x1f, 0x8b]) {
        gunzip(&bytes, policy.max_svgz_bytes).map_err(|message| ImportError::Encoding {
            source_name: name.clone(),
            message,
        })?
    } else {
        bytes
    };
    let text = gmotion::input::utf8_str(&bytes).map_err(|message| ImportError::Encoding {
        source_name: name.clone(),
        message,
    })?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    parse_in(text, &name, Some(dir), opts, policy)
}

/// Imports SVG text; `source_name` names it in errors and warnings. It has no folder, so
/// it may reference no files (data URIs only).
pub fn parse(text: &str, source_name: &str, opts: &ImportOptions) -> Result<Imported, ImportError> {
    parse_in(text, source_name, None, opts, &Policy::default())
}

fn parse_in(
    text: &str,
    source_name: &str,
    dir: Option<&Path>,
    opts: &ImportOptions,
    policy: &Policy,
) -> Result<Imported, ImportError> {
    source::check_entities(text, source_name, policy.max_entity_bytes)?;
    let mut src = source::Source::parse(text, source_name, policy)?;
    let unmatched = opts
        .tag_map
        .as_deref()
        .map_or_else(Vec::new, |map| src.apply(map));
    let refused = std::sync::Arc::new(std::sync::Mutex::new(Vec::<(String, String)>::new()));
    let mut uopt = usvg::Options {
        resources_dir: dir.map(Path::to_path_buf),
        image_href_resolver: access::resolver(dir, policy, refused.clone()),
        ..Default::default()
    };
    if src.has_text {
        uopt.fontdb = fonts::database(&policy.fonts);
        uopt.font_resolver = fonts::resolver(&policy.fonts);
    }
    let tree = src.aside(source_name, |prepared| {
        usvg::Tree::from_str(prepared, &uopt)
    })?;
    let tree = tree.map_err(|e| match e {
        usvg::Error::InvalidSize => ImportError::Size {
            source_name: source_name.to_string(),
        },
        // The document passed `xml-nodes`; usvg refuses elements nested past a fixed depth
        // (located by `too_deep`) and, with the same error, a tree of more than a fixed
        // million nodes: its elements, each `<use>` counted again with a copy of what it
        // references (ten `<use>`s of a group of ten `<use>`s …). The message says which
        // limit it is and what the document holds, since usvg says neither.
        usvg::Error::ElementsLimitReached
        | usvg::Error::ParsingFailed(usvg::roxmltree::Error::NodesLimitReached) => {
            if let Some(deep) = src.too_deep(source_name) {
                return deep;
            }
            ImportError::Svg {
                source_name: source_name.to_string(),
                message: src.past_element_limit(),
            }
        }
        e => ImportError::Svg {
            source_name: source_name.to_string(),
            message: e.to_string(),
        },
    })?;

    // The key shapes read the text prepared for usvg; it is freed once they are found.
    let keys = keys::key_shapes(&src, &uopt, opts);
    src.prepared = std::borrow::Cow::Borrowed("");
    let mut converted = convert::convert(&tree, &src, opts, &uopt.fontdb, policy);
    converted.warnings.extend(unmatched);
    converted.warnings.extend(src.unlinked.iter().cloned());
    let refused = std::mem::take(&mut *refused.lock().unwrap_or_else(|e| e.into_inner()));
    for (href, why) in refused {
        converted.warnings.push((
            src.place_of_href(&href),
            if href == "data:" {
                format!("image data not read: {why}")
            } else {
                format!("file `{href}` not read: {why}")
            },
        ));
    }
    let (width, height) = (tree.size().width() as f64, tree.size().height() as f64);
    // Nothing below reads usvg's tree or the source document: both are freed before the
    // units are measured, the import's last and largest step (at 999 000 shapes they
    // held about a gigabyte beside the scene).
    drop(tree);
    drop(src);
    let mut shapes = Vec::with_capacity(converted.units.len());
    let mut counts: std::collections::HashMap<String, usize> = Default::default();
    let mut scene = Scene {
        width,
        height,
        root: converted.root,
        shapes: Vec::new(),
        time: None,
        keys,
    };
    // The converter registers only units that hold a path, so a measure exists; the
    // fallback keeps `Node::unit` indices aligned should that ever change.
    let measure_unit = |unit: &convert::Unit| {
        scene
            .root
            .node_at(&unit.node_path)
            .and_then(|n| measure(n, unit.parent_transform))
            .unwrap_or(Measure {
                centroid: kurbo::Point::ORIGIN,
                bbox: kurbo::Rect::ZERO,
                fill: gmotion::color::Color::BLACK,
                stroke: gmotion::color::Color::BLACK,
                stroke_width: 1.0,
            })
    };
    // Units are measured independently (flattening and overlay work dominate a large
    // import); a small document is measured before the thread pool would have woken up.
    let measures: Vec<Measure> = if converted.units.len() < 32 {
        converted.units.iter().map(measure_unit).collect()
    } else {
        converted.units.par_iter().map(measure_unit).collect()
    };
    for (z, (unit, m)) in converted.units.into_iter().zip(measures).enumerate() {
        let count = counts.entry(unit.tag.clone()).or_default();
        shapes.push(Shape {
            id: *count,
            tag: unit.tag,
            aliases: unit.aliases,
            inherited: 0,
            rig: false,
            group: 0,
            z,
            node_path: unit.node_path,
            parent_transform: unit.parent_transform,
            centroid: m.centroid,
            bbox: m.bbox,
            fill: m.fill,
            stroke: m.stroke,
            stroke_width: m.stroke_width,
            text: gmotion::text::TextPlace {
                layout: unit.text,
                ..gmotion::text::TextPlace::default()
            },
        });
        *count += 1;
    }
    scene.shapes = shapes;
    // One element drawn several times (a marker at every vertex, a `<use>`d group) would
    // say the same thing once per copy: each warning is said once, in first-seen order.
    let mut seen = std::collections::HashSet::new();
    let warnings = converted
        .warnings
        .into_iter()
        .filter(|w| seen.insert(w.clone()))
        .map(|(place, what)| Warning::about(format!("{source_name}: {place}"), what))
        .collect();
    Ok(Imported { scene, warnings })
}
