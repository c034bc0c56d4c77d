//! SVG import: usvg normalises the file (CSS, `use`, markers, units, shapes to paths), then
//! the usvg tree becomes a [`Scene`] and its animated units are chosen and tagged.
//!
//! What is kept: groups with transform, opacity, clip path and mask; paths with fill
//! (paint, opacity, rule) and stroke (paint, opacity, width, caps, joins, miter limit,
//! dashes) and paint order; linear and radial gradients, patterns, clip paths and masks,
//! each converted once and shared. Markers arrive as ordinary paths (usvg instantiates
//! them). Text is converted to outlines with the system fonts.
//!
//! What is not: filters, blend modes, raster and nested SVG images and `shape-rendering`
//! hints are dropped with a warning that names the element (see [`Imported::warnings`]).
//!
//! Tags are read from the source text (see [`TagFrom`]): usvg keeps only ids, so elements
//! without one get a synthetic id before usvg parses the text, and every usvg node is traced
//! back to its source element. Paths that usvg instantiates for a `use` lose their ids; they
//! are matched to the referenced element's shapes in order when the counts agree, and
//! otherwise take their tags from the `use` and its ancestors. The unit rules are in
//! [`Units`].

mod convert;
mod source;
pub mod tags;

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use gmotion::Warning;
use gmotion::measure::{Measure, measure};
use gmotion::scene::{Scene, Shape};
pub use gmotion::tagging::{TagFrom, Units};

/// How to import.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ImportOptions {
    /// Where tags come from.
    pub tag_from: TagFrom,
    /// Which nodes are animated units.
    pub units: Units,
}

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
    #[error("{}: cannot read the file: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
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
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| ImportError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let bytes = if bytes.starts_with(&[0x1f, 0x8b]) {
        usvg::decompress_svgz(&bytes).map_err(|e| ImportError::Encoding {
            source_name: name.clone(),
            message: e.to_string(),
        })?
    } else {
        bytes
    };
    let text = std::str::from_utf8(&bytes).map_err(|e| ImportError::Encoding {
        source_name: name.clone(),
        message: format!(
            "not UTF-8 text (byte {}); only UTF-8 SVG is supported",
            e.valid_up_to()
        ),
    })?;
    parse_in(text, &name, path.parent(), opts)
}

/// Imports SVG text; `source_name` names it in errors and warnings.
pub fn parse(text: &str, source_name: &str, opts: &ImportOptions) -> Result<Imported, ImportError> {
    parse_in(text, source_name, None, opts)
}

fn parse_in(
    text: &str,
    source_name: &str,
    dir: Option<&Path>,
    opts: &ImportOptions,
) -> Result<Imported, ImportError> {
    let src = source::Source::parse(text, source_name)?;
    let mut uopt = usvg::Options {
        resources_dir: dir.map(Path::to_path_buf),
        ..Default::default()
    };
    if src.has_text {
        uopt.fontdb = system_fonts();
    }
    let tree = usvg::Tree::from_str(&src.prepared, &uopt).map_err(|e| match e {
        usvg::Error::InvalidSize => ImportError::Size {
            source_name: source_name.to_string(),
        },
        e => ImportError::Svg {
            source_name: source_name.to_string(),
            message: e.to_string(),
        },
    })?;

    let converted = convert::convert(&tree, &src, opts);
    let mut shapes = Vec::with_capacity(converted.units.len());
    let mut counts: std::collections::HashMap<String, usize> = Default::default();
    let mut scene = Scene {
        width: tree.size().width() as f64,
        height: tree.size().height() as f64,
        root: converted.root,
        shapes: Vec::new(),
    };
    // The converter registers only units that hold a path, so a measure exists; the
    // fallback keeps `Node::unit` indices aligned should that ever change.
    let measure_unit = |unit: &convert::Unit| {
        unit_node(&scene, &unit.node_path)
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
            group: 0,
            z,
            node_path: unit.node_path,
            parent_transform: unit.parent_transform,
            centroid: m.centroid,
            bbox: m.bbox,
            fill: m.fill,
            stroke: m.stroke,
            stroke_width: m.stroke_width,
        });
        *count += 1;
    }
    scene.shapes = shapes;
    let warnings = converted
        .warnings
        .into_iter()
        .map(|(place, what)| Warning::about(format!("{source_name}: {place}"), what))
        .collect();
    Ok(Imported { scene, warnings })
}

/// The system fonts, scanned once per process (a scan reads every font file's tables).
fn system_fonts() -> std::sync::Arc<usvg::fontdb::Database> {
    static FONTS: std::sync::OnceLock<std::sync::Arc<usvg::fontdb::Database>> =
        std::sync::OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = usvg::fontdb::Database::new();
            db.load_system_fonts();
            std::sync::Arc::new(db)
        })
        .clone()
}

fn unit_node<'s>(scene: &'s Scene, path: &[usize]) -> Option<&'s gmotion::scene::Node> {
    let (last, parents) = path.split_last()?;
    let mut group = &scene.root;
    for &i in parents {
        match group.children.get(i)? {
            gmotion::scene::Node::Group(g) => group = g,
            gmotion::scene::Node::Path(_) => return None,
        }
    }
    group.children.get(*last)
}
