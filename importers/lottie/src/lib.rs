//! Lottie import: a Bodymovin / After Effects JSON document as a gmotion [`Scene`] whose
//! animated units are the layers of its root composition, plus the document itself, kept
//! whole for verbatim pass-through ([`Source`]).
//!
//! **Units.** Every root layer that draws (shape, precomposition, solid, image, text) is a
//! unit; null layers are rigs (they move their children, but are not units); a track
//! matte's source layer (`td`) moves with the layer it mattes, as one unit; hidden layers
//! are not units. Units are in paint order (bottom layer first), and ids count within a
//! tag in that order. Tags come from layer names ([`tags`]). With [`Units::Groups`] the
//! top-level groups of shape layers are the units instead ([`UnitLayers::part`]).
//!
//! **Geometry.** The document is evaluated at a reference time (the first frame unless
//! [`ImportOptions::time`] says otherwise), and at any frame by [`Source::scene_at`], which
//! is how gmotion plays a Lottie file itself: parenting builds every layer's world
//! transform (3D layers projected as players without a camera show them, auto-oriented
//! layers turned along their path); shape layers' groups, paths (`sh`), rectangles,
//! ellipses, stars and polygons (built as lottie-web builds them, [`outline`]), fills,
//! strokes with dashes and gradients become painted paths, after trim paths, round corners
//! and repeaters; layer masks
//! in every mode and every kind of track matte become masks; precompositions are expanded
//! (start time, stretch, time remap, clipped to their size); solids are filled rectangles.
//! Keyframes are read in the time of the layer's composition, with per-component Bézier
//! easing, holds, legacy end values (`e`), split positions, and spatial tangents travelled
//! by arc length. Each unit is measured on that geometry (centroid, bounds, paint).
//!
//! Image layers draw their asset: embedded (`e: 1`: a PNG, JPEG, GIF or WebP data URL) or
//! linked (`u` + `p`, read from the file's folder by [`load`] under
//! [`gmotion::input::References`]). Text layers draw the glyphs the file embeds, laid out
//! and animated as lottie-web does ([`text`]); a file without glyphs has its text set in
//! the machine's fonts, as players set it ([`fonts`], given [`ImportOptions::fonts`]).
//! Gaussian Blur and Drop Shadow effects are
//! drawn as lottie-web draws them ([`effects`]).
//!
//! **Not drawn** (with a warning naming the first place and how many): images that cannot
//! be read (their rectangle is measured), text without embedded glyphs when no fonts are
//! given (measured as a point), merge paths and the other shape modifiers (offset paths, zig-zags, pucker and
//! bloat, twists), other effects, expressions (the property's own value is
//! used).
//!
//! **Errors.** Nothing in the input can make the import panic: every value is checked as it
//! is read, and every error names its JSON location (`$.layers[3].ks.p.k[1].s`). Parent
//! cycles, precomposition cycles, precompositions nested deeper than
//! [`build::MAX_PRECOMP_DEPTH`], more than [`build::MAX_DRAWN_LAYERS`] layers to draw, and
//! numbers beyond ±[`model::MAX_MAGNITUDE`] are errors; serde_json refuses documents
//! nested deeper than 128 levels.
#![forbid(unsafe_code)]

pub mod build;
pub mod effects;
pub mod eval;
pub mod fonts;
pub mod model;
pub mod offset;
pub mod outline;
pub mod tags;
pub mod text;

use std::path::{Path, PathBuf};

use kurbo::{Affine, Point, Rect};
use serde_json::Value;

use gmotion::Warning;
use gmotion::color::Color;
use gmotion::input::ReadError;
use gmotion::measure::measure;
use gmotion::scene::{Group, Node, Scene, Shape};

use model::{Document, Loc};

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

/// What a Lottie scene's units are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Units {
    /// Every root layer that draws (`--units auto`).
    #[default]
    Layers,
    /// Every top-level item of a shape layer that has outlines of its own (a group, or a
    /// path, rectangle, ellipse or star outside any group) is a unit, styled by the
    /// layer's fills and strokes as in the layer; other layers, and shape layers with a
    /// track matte, stay whole (`--units groups`).
    Groups,
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

/// The root layers one unit moves.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitLayers {
    /// Indices into the document's root `layers`: the unit's layer first, then its track
    /// matte's source when it has one.
    pub layers: Vec<usize>,
    /// For each of `layers`, its parent's world transform at the reference frame (the
    /// identity for a layer without a parent): where a motion in canvas space must be
    /// conjugated to act in the parent's space. For a part, the world transform of its
    /// layer, where it moves. Where that is scaled to nothing at the reference frame, the
    /// first later frame's where it is not.
    pub parent_world: Vec<Affine>,
    /// With `--units groups`, the index in the layer's `shapes` of the top-level item the
    /// unit is (the layer's other parts are other units); `None` for a whole layer.
    pub part: Option<usize>,
    /// What the unit measured at the reference frame (`None`: no geometry); a frame drawn
    /// later ([`Source::scene_at`]) keeps it rather than measuring again.
    pub measure: Option<gmotion::measure::Measure>,
}

/// The source document of an imported scene, for the exporter that writes it back with
/// gmotion's motion layered on top.
#[derive(Clone, Debug)]
pub struct Source {
    /// The document as read (every key, known or not).
    pub json: Value,
    /// The typed model of what gmotion reads.
    pub document: Document,
    /// For each unit of the scene (`scene.shapes[i]`), its layers.
    pub units: Vec<UnitLayers>,
    /// What the units are.
    pub mode: Units,
    /// The reference frame the scene was measured at.
    pub frame: f64,
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

type Built = (Group, Vec<Shape>, Vec<UnitLayers>, Vec<(String, String)>);

/// For each unit, the layers whose worlds are its `parent_world` (`None`: the canvas).
type Anchors = Vec<Vec<Option<usize>>>;

/// The document drawn at `frame`; its units measured, or given the measures of
/// `reference` (the same units, at the reference frame).
fn scene_of(
    doc: &Document,
    frame: f64,
    mode: Units,
    reference: Option<&[UnitLayers]>,
) -> model::Result<Built> {
    let mut b = build::Builder::new(doc);
    let layers = &doc.layers;
    let worlds = b.worlds(layers, frame)?;
    let parents = parent_indices(layers);
    let parent_of = |i: usize| parents[i];
    let roles = roles(layers, mode, &parent_of);
    let mut anchors: Anchors = Vec::new();
    let mut root = Group::new();
    let mut shapes = Vec::new();
    let mut units = Vec::new();
    let mut counts: std::collections::HashMap<String, usize> = Default::default();
    let mut stack = Vec::new();
    for i in (0..layers.len()).rev() {
        let l = &layers[i];
        let matte = build::Builder::matte_source(layers, i);
        let parts: Vec<Option<usize>> = match roles[i] {
            Role::Whole => vec![None],
            Role::Parts => split_parts(l),
            Role::Rig | Role::None => continue,
        };
        for part in parts {
            let mut node = b.drawn(layers, i, &worlds, frame, &mut stack, part)?;
            if !(l.ip <= frame && frame < l.op) {
                // Not on screen at the reference frame: measured, but not drawn in the still.
                node.opacity = 0.0;
            }
            let index = shapes.len();
            let mut node_path = vec![root.children.len()];
            match (part, &node.mask, node.children.as_mut_slice()) {
                // A part moves inside its layer, under the layer's masks (they wrap the
                // layer, [`build::Builder::layer_node`]), which stay where they are.
                (Some(_), Some(_), [Node::Group(layer)]) => {
                    layer.unit = Some(index);
                    node_path.push(0);
                }
                _ => node.unit = Some(index),
            }
            let node = Node::Group(node);
            // Measuring resolves every overlap of the unit's outlines, which takes seconds
            // for a rich precomposition: done once, at the reference frame.
            let m = match reference {
                Some(units) => units.get(index).and_then(|u| u.measure),
                None => measure(&node, Affine::IDENTITY),
            };
            let at = worlds[i] * Point::ORIGIN;
            let layer_tag = tags::layer_tag(&l.nm, l.kind);
            let item = part.and_then(|k| l.shapes.get(k));
            let tag = match item {
                Some(item) => tags::part_tag(&item.nm, &item.kind),
                None => layer_tag.clone(),
            };
            let own = item.and_then(|item| gmotion::tagging::grammar_name(item.nm.trim()));
            let (aliases, inherited) = names_of(layers, &roles, &parent_of, i, &tag, own);
            let id = counts.entry(tag.clone()).or_default();
            shapes.push(Shape {
                tag,
                aliases,
                inherited,
                rig: false,
                id: *id,
                group: 0,
                z: index,
                node_path,
                parent_transform: Affine::IDENTITY,
                centroid: m.map_or(at, |m| m.centroid),
                bbox: m.map_or(Rect::from_points(at, at), |m| m.bbox),
                fill: m.map_or(Color::BLACK, |m| m.fill),
                stroke: m.map_or(Color::BLACK, |m| m.stroke),
                stroke_width: m.map_or(1.0, |m| m.stroke_width),
            });
            *id += 1;
            let mut members = vec![i];
            members.extend(matte);
            // A part moves inside its layer: in the layer's own space.
            let anchor: Vec<Option<usize>> = match part {
                Some(_) => vec![Some(i)],
                None => members.iter().map(|&j| parent_of(j)).collect(),
            };
            units.push(UnitLayers {
                parent_world: anchor
                    .iter()
                    .map(|a| a.map_or(Affine::IDENTITY, |j| worlds[j]))
                    .collect(),
                layers: members,
                part,
                measure: m,
            });
            anchors.push(anchor);
            root.children.push(node);
        }
    }
    rigs(
        doc,
        &worlds,
        (&roles, &parent_of),
        frame,
        &mut counts,
        (&mut root, &mut shapes, &mut units, &mut anchors),
    );
    if reference.is_none() {
        first_invertible_worlds(&mut b, layers, frame, doc.op, &mut units, &anchors)?;
    }
    Ok((root, shapes, units, b.warnings()))
}

/// Each layer's parent, as an index into `layers` (the first layer with the `ind` its
/// `parent` names; `None` without a parent, or when none has that `ind`).
fn parent_indices(layers: &[model::Layer]) -> Vec<Option<usize>> {
    let mut by_ind = std::collections::HashMap::new();
    for (i, l) in layers.iter().enumerate() {
        if let Some(ind) = l.ind {
            by_ind.entry(ind).or_insert(i);
        }
    }
    layers
        .iter()
        .map(|l| l.parent.and_then(|p| by_ind.get(&p)).copied())
        .collect()
}

/// `x` seconds as people write them: at most three decimals, no trailing zeros.
fn seconds(x: f64) -> String {
    let s = format!("{x:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
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

/// What a root layer is to the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    /// One unit.
    Whole,
    /// Split into units, one per top-level item (`--units groups`).
    Parts,
    /// A rig: a layer that draws no unit of its own (a null, a hidden layer) but moves the
    /// units parented to it.
    Rig,
    /// Neither.
    None,
}

/// Each root layer's [`Role`].
fn roles(
    layers: &[model::Layer],
    mode: Units,
    parent_of: &dyn Fn(usize) -> Option<usize>,
) -> Vec<Role> {
    let mut roles: Vec<Role> = layers
        .iter()
        .enumerate()
        .map(|(i, l)| {
            if !l.kind.draws() || l.hidden || l.td {
                Role::None
            } else if mode == Units::Groups
                && l.kind == model::LayerKind::Shape
                // A matted layer stays whole, as its matte moves with it.
                && build::Builder::matte_source(layers, i).is_none()
            {
                Role::Parts
            } else {
                Role::Whole
            }
        })
        .collect();
    // Every layer up a unit's chain of parents that is no unit itself moves it: a rig.
    for i in 0..layers.len() {
        if !matches!(roles[i], Role::Whole | Role::Parts) {
            continue;
        }
        let mut at = parent_of(i);
        let mut hops = 0;
        while let Some(j) = at.filter(|_| hops <= layers.len()) {
            if roles[j] == Role::None {
                roles[j] = Role::Rig;
            }
            at = parent_of(j);
            hops += 1;
        }
    }
    roles
}

/// A shape layer's parts (`--units groups`): its top-level items with outlines of their
/// own, bottom first.
fn split_parts(l: &model::Layer) -> Vec<Option<usize>> {
    l.shapes
        .iter()
        .enumerate()
        .rev()
        .filter(|(_, item)| !item.hidden && item.kind.part_name().is_some())
        .map(|(k, _)| Some(k))
        .collect()
}

/// The aliases of a unit on layer `i` whose tag is `tag` (its `own` name as written first,
/// e.g. a part's, counter kept), and how many of them are inherited: its layer's names,
/// then its parents', nearest first, so a rule can name one layer of several, a rig that
/// moves several, or every part of a layer. A parent that moves the unit through
/// parenting (a unit or a rig) is inherited: a rule naming it moves the unit once, through
/// the parent. A layer split into parts moves none of its children, so its name stays the
/// children's own.
fn names_of(
    layers: &[model::Layer],
    roles: &[Role],
    parent_of: &dyn Fn(usize) -> Option<usize>,
    i: usize,
    tag: &str,
    own: Option<String>,
) -> (Vec<String>, usize) {
    let names = |l: &model::Layer| {
        [
            gmotion::tagging::grammar_name(l.nm.trim()),
            Some(tags::layer_tag(&l.nm, l.kind)),
        ]
        .into_iter()
        .flatten()
    };
    let mut mine: Vec<String> = Vec::new();
    let mut theirs: Vec<String> = Vec::new();
    for name in own.into_iter().chain(names(&layers[i])) {
        if name != tag && !mine.contains(&name) {
            mine.push(name);
        }
    }
    let mut at = parent_of(i);
    let mut hops = 0;
    while let Some(j) = at.filter(|_| hops <= layers.len()) {
        let carries = matches!(roles[j], Role::Whole | Role::Rig);
        for name in names(&layers[j]) {
            if name == tag || mine.contains(&name) || theirs.contains(&name) {
                continue;
            }
            match carries {
                true => theirs.push(name),
                false => mine.push(name),
            }
        }
        at = parent_of(j);
        hops += 1;
    }
    let inherited = theirs.len();
    mine.extend(theirs);
    (mine, inherited)
}

/// Appends the rigs (layers of [`Role::Rig`], top layer last) as units after the drawn
/// ones, so that the drawn units keep their places and ids: each draws nothing, pivots
/// about its anchor point at `frame`, and spans the units it moves.
fn rigs(
    doc: &Document,
    worlds: &[Affine],
    (roles, parent_of): (&[Role], &dyn Fn(usize) -> Option<usize>),
    frame: f64,
    counts: &mut std::collections::HashMap<String, usize>,
    (root, shapes, units, anchors): (
        &mut Group,
        &mut Vec<Shape>,
        &mut Vec<UnitLayers>,
        &mut Anchors,
    ),
) {
    let layers = &doc.layers;
    let drawn = shapes.len();
    for r in (0..layers.len()).rev().filter(|&r| roles[r] == Role::Rig) {
        let l = &layers[r];
        let pivot = worlds[r] * eval::vec2(l.ks.a.as_ref(), frame, kurbo::Vec2::ZERO).to_point();
        // The box of every drawn unit it moves.
        let moves = |u: &UnitLayers| {
            let mut at = u.layers.first().copied();
            let mut hops = 0;
            while let Some(j) = at.filter(|_| hops <= layers.len()) {
                if j == r {
                    return true;
                }
                at = parent_of(j);
                hops += 1;
            }
            false
        };
        let bbox = units[..drawn]
            .iter()
            .zip(&shapes[..drawn])
            .filter(|(u, _)| moves(u))
            .map(|(_, s)| s.bbox)
            .reduce(|a, b| a.union(b))
            .unwrap_or(Rect::from_points(pivot, pivot));
        let tag = tags::layer_tag(&l.nm, l.kind);
        let (aliases, inherited) = names_of(layers, roles, parent_of, r, &tag, None);
        let index = shapes.len();
        let id = counts.entry(tag.clone()).or_default();
        shapes.push(Shape {
            tag,
            aliases,
            inherited,
            rig: true,
            id: *id,
            group: 0,
            z: index,
            node_path: vec![root.children.len()],
            parent_transform: Affine::IDENTITY,
            centroid: pivot,
            bbox,
            fill: Color::BLACK,
            stroke: Color::BLACK,
            stroke_width: 1.0,
        });
        *id += 1;
        let anchor = vec![parent_of(r)];
        units.push(UnitLayers {
            parent_world: anchor
                .iter()
                .map(|a| a.map_or(Affine::IDENTITY, |j| worlds[j]))
                .collect(),
            layers: vec![r],
            part: None,
            measure: None,
        });
        anchors.push(anchor);
        let mut node = Group::new();
        node.unit = Some(index);
        root.children.push(Node::Group(node));
    }
}

/// Gives each unit whose anchor layer is scaled to nothing at the reference `frame` (a
/// layer that pops in from zero scale) the anchor's world at the first later frame where
/// it is invertible (sampled at up to [`INVERTIBLE_SEARCH`] frames before `op`): motion in
/// canvas space is carried into that layer's space through it, on export and in
/// [`Source::scene_at`] alike. One that never becomes invertible keeps its singular world
/// (its motion is left out, with a warning, on export).
fn first_invertible_worlds(
    b: &mut build::Builder,
    layers: &[model::Layer],
    frame: f64,
    op: f64,
    units: &mut [UnitLayers],
    anchors: &Anchors,
) -> model::Result<()> {
    let singular = |a: &Affine| a.determinant().abs() < 1e-12;
    if !units.iter().any(|u| u.parent_world.iter().any(singular)) {
        return Ok(());
    }
    let step = ((op - frame) / INVERTIBLE_SEARCH as f64).max(1.0);
    let mut at = frame + step;
    while at < op && units.iter().any(|u| u.parent_world.iter().any(singular)) {
        let worlds = b.worlds(layers, at)?;
        for (u, anchor) in units.iter_mut().zip(anchors) {
            for (w, a) in u.parent_world.iter_mut().zip(anchor) {
                if let Some(j) = *a
                    && singular(w)
                    && !singular(&worlds[j])
                {
                    *w = worlds[j];
                }
            }
        }
        at += step;
    }
    Ok(())
}

/// At most this many frames are tried by [`first_invertible_worlds`].
const INVERTIBLE_SEARCH: usize = 2000;

impl Source {
    /// The composition frame a time in seconds from the animation's start is.
    pub fn frame_at(&self, seconds: f64) -> f64 {
        self.document.ip + seconds * self.document.fr
    }

    /// The nearest unit that unit `u` hangs from through its layer's parents, if any. The
    /// exported motion of that unit moves `u` too (its layer is re-parented under the
    /// unit's motion), as After Effects' parenting moves children.
    pub fn parent_unit(&self, u: usize) -> Option<usize> {
        let layers = &self.document.layers;
        let first = |u: &UnitLayers| u.layers.first().copied();
        let mut at = first(self.units.get(u)?)?;
        // Parents cannot cycle in an imported document; the bound only keeps this finite.
        for _ in 0..layers.len() {
            let parent = layers.get(at)?.parent?;
            at = layers.iter().position(|l| l.ind == Some(parent))?;
            // A part's motion moves only the part, not the layers parented to its layer.
            if let Some(v) = self
                .units
                .iter()
                .position(|w| w.part.is_none() && first(w) == Some(at))
            {
                return Some(v);
            }
        }
        None
    }

    /// The source made to last `duration` seconds, when that is not the composition's own
    /// length, and what that did: a longer animation holds the composition's last frame
    /// (every root layer on screen at its end stays on, its properties held after their
    /// last keyframes, and a precomposition's content held at its last frame by a time
    /// remap), a shorter one cuts it. The document written back and gmotion's own render
    /// both use the new source, so they agree on every frame.
    pub fn lasting(&self, duration: f64) -> Option<(Source, String)> {
        let doc = &self.document;
        let (ip, op, fr) = (doc.ip, doc.op, doc.fr);
        let new_op = ip + duration * fr;
        if !(new_op.is_finite() && new_op > ip) || (new_op - op).abs() < 1e-6 {
            return None;
        }
        let mut src = self.clone();
        let json = src.json.as_object_mut()?;
        json.insert("op".into(), new_op.into());
        src.document.op = new_op;
        let said = if new_op < op {
            format!(
                "the grammar's duration ({}s) is shorter than the composition ({}s): the composition is cut at {}s",
                seconds(duration),
                seconds((op - ip) / fr),
                seconds(duration)
            )
        } else {
            let last = op - 1.0;
            let layers = json.get_mut("layers").and_then(Value::as_array_mut)?;
            for (l, model) in layers.iter_mut().zip(src.document.layers.iter_mut()) {
                let Some(o) = l.as_object_mut() else {
                    continue;
                };
                // A layer that is on screen until the end stays on.
                if model.op < op - 1e-9 || model.ip > last {
                    continue;
                }
                o.insert("op".into(), new_op.into());
                model.op = new_op;
                if model.kind == model::LayerKind::Precomp && model.tm.is_none() && model.ip < last
                {
                    // Its content runs as it did up to the last frame, then holds there:
                    // precomposition time (seconds) = (t − st) / sr / fr, until `last`.
                    let at = |t: f64| (t - model.st) / model.sr / fr;
                    let tm = serde_json::json!({
                        "a": 1,
                        "k": [
                            {"t": model.ip, "s": [at(model.ip)], "i": {"x": [1], "y": [1]}, "o": {"x": [0], "y": [0]}},
                            {"t": last, "s": [at(last)]}
                        ]
                    });
                    o.insert("tm".into(), tm);
                    model.tm = model::opt_property(o, "tm", &model.at).ok().flatten();
                }
            }
            format!(
                "the grammar's duration ({}s) is longer than the composition ({}s): its last frame is held from {}s",
                seconds(duration),
                seconds((op - ip) / fr),
                seconds((last - ip) / fr)
            )
        };
        Some((src, said))
    }

    /// The composition's length in seconds, from its in point to its out point.
    pub fn duration(&self) -> f64 {
        (self.document.op - self.document.ip) / self.document.fr
    }

    /// The composition's frame rate.
    pub fn fps(&self) -> f64 {
        self.document.fr
    }

    /// The scene as the document draws it at composition `frame`: the same units in the
    /// same order as the imported scene (so an animation's tracks apply to it unchanged),
    /// each where its layers put it then; a unit whose layer is not on screen at `frame`
    /// is drawn at zero opacity. This is how gmotion plays a Lottie file itself. The units
    /// keep the measures (centroid, box, paint) of the reference frame.
    ///
    /// With it, each unit's motion: how the world of the layer the unit hangs from has
    /// moved since the reference frame (`parent(frame) · parent(reference)⁻¹`). gmotion's
    /// motion on a Lottie source is exported in that parent's space, so that it follows
    /// the rig it is added to; a renderer conjugates a canvas-space state by it to draw
    /// what players draw.
    pub fn scene_at(&self, frame: f64) -> Result<(Scene, Vec<Affine>), ImportError> {
        let (root, shapes, units, _) =
            scene_of(&self.document, frame, self.mode, Some(&self.units)).map_err(|e| {
                ImportError::Lottie {
                    source_name: format!("frame {frame}"),
                    at: e.at,
                    message: e.message,
                }
            })?;
        let moved = units
            .iter()
            .zip(&self.units)
            .map(|(now, then)| {
                let at =
                    |u: &UnitLayers| u.parent_world.first().copied().unwrap_or(Affine::IDENTITY);
                let then = at(then);
                if then.determinant().abs() < 1e-12 {
                    Affine::IDENTITY
                } else {
                    at(now) * then.inverse()
                }
            })
            .collect();
        let scene = Scene {
            width: self.document.w,
            height: self.document.h,
            root,
            shapes,
            time: Some(gmotion::scene::SceneTime {
                duration: self.duration(),
                fps: self.fps(),
            }),
        };
        Ok((scene, moved))
    }
}
