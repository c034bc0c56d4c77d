//! Animated SVG (SMIL): an animation as one SVG document that browsers play with no script.
//!
//! The static scene is written by [`crate::frame::scene_svg`] (so every picture
//! element, paint server, clip path and mask is exactly what gmotion renders) and the
//! animation is spliced in:
//!
//! - each animated unit node is wrapped in nested `<g>`s, one per motion segment, carrying
//!   additive `animateTransform`s (`translate`, `rotate`, `scale`, `skewX`, `skewY`) whose
//!   `keyTimes`/`keySplines` reproduce the segment's timing and easing exactly, then merged
//!   wherever the product stays the same at every instant (groups whose static transforms
//!   commute with the animations outside them, animations of one type in turn: the
//!   `merge` module); the outermost group also carries the unit's opacity;
//! - paths inside animated units get `<animate>` children for fill and stroke colours (the
//!   tint applied to the path's own colour), stroke width, and, for per-vertex deformation,
//!   `d`; gradients and patterns under a tint are copied per path with animated
//!   `stop-color`s or content colours.
//!
//! What SMIL cannot say exactly — Alexa interpolation, blends of several grid cells, matrix
//! and two-axis skew components, easings that are not cubic Béziers, per-vertex deformation,
//! tints of nested units — is sampled and reduced to the fewest keys that keep every point
//! of the shape within [`SmilOptions::tolerance`] canvas units (colours within half an 8-bit
//! step). Gradients and patterns nested inside a tinted pattern keep their colours (a
//! [`Warning`] names the shape).
//!
//! Output is deterministic byte for byte; numbers are rounded to 1e-4 user units and
//! degrees, 1e-6 for scale factors, matrix entries and key times, 1e-5 for key splines.

mod attr;
mod decompose;
mod deform;
mod merge;
mod morph;
mod paint;
mod splice;
mod stream;
mod text;
mod transform;
mod xml;

use std::borrow::Cow;

use foldhash::{HashMap, HashSet};

use kurbo::Point;
use rayon::prelude::*;

use attr::Bake;
use gmotion::Warning;
use gmotion::canvas::OutputSize;
use gmotion::keyframe::Key;
use gmotion::motion::{Animation, Tint, Track, Trim};
use gmotion::scene::{Group, LineCap, Node, Paint, PathNode, Pattern, Stop};
use paint::{COLOR_TOL, Chain, OPACITY_TOL, TRIM_TOL, WIDTH_TOL, tint_dist};
use splice::{Edits, Element, MarkedPath, attr as tag_attr};
pub use text::SmilText;
use transform::{Kind, Plan, TransformAnim};
use xml::{COORD, Clock, FACTOR, num, push_num};

/// Settings for [`to_smil`].
#[derive(Clone, Debug, PartialEq)]
pub struct SmilOptions {
    /// Largest distance, in canvas units, between where baked motion puts any point of a
    /// shape and where gmotion puts it (at the sampled instants). Default 0.25.
    pub tolerance: f64,
    /// Samples per second taken when baking. Default 120.
    pub bake_rate: f64,
    /// The document's `width` and `height` (the `viewBox` keeps the canvas, so the art
    /// scales to fit). Default: the scene's size.
    pub size: OutputSize,
}

impl Default for SmilOptions {
    fn default() -> Self {
        SmilOptions {
            tolerance: 0.25,
            bake_rate: 120.0,
            size: OutputSize::default(),
        }
    }
}

/// Why an animation cannot be written.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SmilError {
    /// The duration is not a positive finite number.
    #[error("animation duration must be a positive number of seconds, got {0}")]
    Duration(f64),
    /// Tracks and shapes do not correspond.
    #[error("the animation has {tracks} tracks for {shapes} shapes")]
    TrackCount {
        /// Number of tracks.
        tracks: usize,
        /// Number of shapes.
        shapes: usize,
    },
    /// A track holds a non-finite number.
    #[error("shape {shape}: its track holds a non-finite number ({what})")]
    NonFinite {
        /// The shape, `tag:id`.
        shape: String,
        /// Which part.
        what: &'static str,
    },
    /// An option is out of range.
    #[error("SMIL option {name} must be a positive finite number, got {value}")]
    Option {
        /// The option.
        name: &'static str,
        /// Its value.
        value: f64,
    },
}

/// A written document with what went into it.
#[derive(Clone, Debug)]
pub struct SmilDocument {
    /// The SVG text.
    pub svg: SmilText,
    /// What the document does not show as gmotion renders it.
    pub warnings: Vec<Warning>,
    /// Motion segments written exactly.
    pub exact_segments: usize,
    /// Motion segments and attribute changes that were sampled and reduced.
    pub baked_segments: usize,
}

/// Writes `anim` as an animated SVG; returns the document and warnings about what it does
/// not show exactly as gmotion renders it.
pub fn to_smil(anim: &Animation, opts: &SmilOptions) -> Result<(String, Vec<Warning>), SmilError> {
    let doc = smil_document(anim, opts)?;
    Ok((doc.svg.into_string(), doc.warnings))
}

/// Like [`to_smil`], also counting what was written exactly and what was baked.
pub fn smil_document(anim: &Animation, opts: &SmilOptions) -> Result<SmilDocument, SmilError> {
    let writer = SmilWriter::new(anim, opts)?;
    let mut bytes = Vec::new();
    let report = writer
        .write_to(&mut bytes)
        .expect("writing to memory cannot fail");
    let text = String::from_utf8(bytes).expect("the document is written from strings");
    Ok(SmilDocument {
        svg: SmilText::from(text),
        warnings: report.warnings,
        exact_segments: report.exact_segments,
        baked_segments: report.baked_segments,
    })
}

/// What writing an animated SVG reports: [`SmilDocument`] without the text, which went to
/// the writer.
#[derive(Clone, Debug, Default)]
pub struct SmilReport {
    /// What the document does not show as gmotion renders it.
    pub warnings: Vec<Warning>,
    /// Motion segments written exactly.
    pub exact_segments: usize,
    /// Motion segments and attribute changes that were sampled and reduced.
    pub baked_segments: usize,
}

/// An animation checked and ready to be written as an animated SVG, streamed: the
/// document goes to its writer a run of elements at a time, each run's animation made
/// just before it is written and freed after, so a large export never holds its whole
/// text (nor every unit's animation) at once.
pub struct SmilWriter<'a> {
    anim: &'a Animation,
    opts: SmilOptions,
}

impl<'a> SmilWriter<'a> {
    /// Checks `anim` and `opts` (the errors [`smil_document`] gives) without writing
    /// anything, so that a caller can refuse before it creates a file.
    pub fn new(anim: &'a Animation, opts: &SmilOptions) -> Result<SmilWriter<'a>, SmilError> {
        validate(anim, opts)?;
        Ok(SmilWriter {
            anim,
            opts: opts.clone(),
        })
    }

    /// Writes the document to `out`, the same bytes [`smil_document`] holds.
    pub fn write_to(&self, out: &mut dyn std::io::Write) -> std::io::Result<SmilReport> {
        let w = Writer {
            anim: self.anim,
            // Every output lasts the duration rounded to whole frames (`gmotion::canvas`),
            // the SVG too: it loops when the Lottie and the GIF do.
            clock: Clock {
                dur: self.anim.length(),
                looping: self.anim.looping,
            },
            opts: &self.opts,
        };
        w.document(out)
    }
}

impl std::fmt::Debug for SmilWriter<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SmilWriter")
            .field("opts", &self.opts)
            .finish_non_exhaustive()
    }
}

fn validate(anim: &Animation, opts: &SmilOptions) -> Result<(), SmilError> {
    if !(anim.duration.is_finite() && anim.duration > 0.0) {
        return Err(SmilError::Duration(anim.duration));
    }
    for (name, value) in [("tolerance", opts.tolerance), ("bake_rate", opts.bake_rate)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(SmilError::Option { name, value });
        }
    }
    if anim.tracks.len() != anim.scene.shapes.len() {
        return Err(SmilError::TrackCount {
            tracks: anim.tracks.len(),
            shapes: anim.scene.shapes.len(),
        });
    }
    for (track, shape) in anim.tracks.iter().zip(&anim.scene.shapes) {
        if let Some(what) = non_finite(track) {
            return Err(SmilError::NonFinite {
                shape: format!("{}:{}", shape.tag, shape.id),
                what,
            });
        }
    }
    Ok(())
}

/// The first part of a track holding a non-finite number.
fn non_finite(track: &Track) -> Option<&'static str> {
    use gmotion::motion::{MotionKind, Timing};
    let timing_ok = |t: &Timing| [t.start, t.end, t.delay].iter().all(|v| v.is_finite());
    for m in &track.motions {
        if ![m.t0, m.t1].iter().all(|v| v.is_finite()) || !timing_ok(&m.timing) {
            return Some("motion timing");
        }
        if !m.start.as_coeffs().iter().all(|v| v.is_finite()) {
            return Some("motion start transform");
        }
        if let MotionKind::Rigid { pivot, blend, .. } = &m.kind
            && (!pivot.is_finite()
                || blend
                    .iter()
                    .any(|(w, cs)| !w.is_finite() || cs.iter().any(|c| !c.is_finite())))
        {
            return Some("motion components");
        }
    }
    let tint_ok = |t: &Tint| t.weight.is_finite() && t.sum.iter().all(|v| v.is_finite());
    let segs_ok = |ok: &dyn Fn(&gmotion::motion::AttrSeg<Tint>) -> bool,
                   s: &[gmotion::motion::AttrSeg<Tint>]| s.iter().all(ok);
    let tint_seg = |s: &gmotion::motion::AttrSeg<Tint>| {
        timing_ok(&s.timing)
            && s.t0.is_finite()
            && s.t1.is_finite()
            && tint_ok(&s.from)
            && tint_ok(&s.to)
    };
    if !segs_ok(&tint_seg, &track.fill) || !segs_ok(&tint_seg, &track.stroke) {
        return Some("tint");
    }
    let num_ok = |s: &[gmotion::motion::AttrSeg<f64>]| {
        s.iter().all(|s| {
            timing_ok(&s.timing) && [s.t0, s.t1, s.from, s.to].iter().all(|v| v.is_finite())
        })
    };
    if !num_ok(&track.opacity) || !num_ok(&track.stroke_width) {
        return Some("opacity or stroke width");
    }
    None
}

/// True when some channel of the track changes before `dur`.
fn changes(track: &Track, dur: f64) -> bool {
    let starts = |t0: Option<f64>| t0.is_some_and(|t| t < dur);
    starts(track.motions.first().map(|s| s.t0))
        || starts(track.fill.first().map(|s| s.t0))
        || starts(track.stroke.first().map(|s| s.t0))
        || starts(track.opacity.first().map(|s| s.t0))
        || starts(track.stroke_width.first().map(|s| s.t0))
        || starts(track.trim.first().map(|s| s.t0))
        || starts(track.morphs.first().map(|s| s.t0))
}

/// Below this many items a document is written on the calling thread.
const PARALLEL_ITEMS: usize = 64;

/// `f` over `items`, in parallel when there are enough of them, results in order.
fn par_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    if items.len() >= PARALLEL_ITEMS {
        items.par_iter().map(f).collect()
    } else {
        items.iter().map(f).collect()
    }
}

/// Whether the path's fill or stroke is a gradient or a pattern (which a tint copies).
fn uses_paint_server(path: &PathNode) -> bool {
    let server = |p: Option<&Paint>| p.is_some_and(|p| !matches!(p, Paint::Solid(_)));
    server(path.fill.as_ref().map(|f| &f.paint)) || server(path.stroke.as_ref().map(|s| &s.paint))
}

/// What the animation of everything shares.
struct Writer<'a> {
    anim: &'a Animation,
    clock: Clock,
    opts: &'a SmilOptions,
}

/// What writing one unit or one path adds to the document: edits of the static text,
/// warnings (with their unit) and segment counts.
#[derive(Default)]
struct Part {
    edits: Vec<(std::ops::Range<usize>, String)>,
    warnings: Vec<(usize, String)>,
    exact: usize,
    baked: usize,
}

impl Part {
    fn warn(&mut self, unit: usize, message: String) {
        self.warnings.push((unit, message));
    }

    fn insert(&mut self, at: usize, text: String) {
        self.edits.push((at..at, text));
    }

    fn replace(&mut self, range: std::ops::Range<usize>, text: String) {
        self.edits.push((range, text));
    }
}

/// The groups [`Writer::unit`] wraps a unit's element in.
struct UnitGroups {
    /// The opening tags with their animations, written before the element.
    open: String,
    /// How many groups to close after it.
    depth: usize,
}

/// Definitions added to the document (tinted copies of gradients and patterns).
struct Defs<'m> {
    /// Their text.
    text: String,
    /// The scene's node ids, which the marked document may use.
    node_ids: &'m HashMap<&'m str, usize>,
    /// The markers, which it may use too.
    markers: &'m HashSet<&'m str>,
    /// The marked document's elements, by id.
    els: &'m HashMap<&'m str, Element>,
    /// The ids given to copies so far.
    given: HashSet<String>,
}

impl Defs<'_> {
    /// Whether `id` is in use (looked up where it is kept: copying every id of a large
    /// document into one set took milliseconds on the export's one serial thread).
    fn taken(&self, id: &str) -> bool {
        self.node_ids.contains_key(id)
            || self.markers.contains(id)
            || self.els.contains_key(id)
            || self.given.contains(id)
    }
}

impl Writer<'_> {
    fn bake<T>(&self, tolerance: f64, dist: &'static dyn Fn(T, T) -> f64) -> Bake<'static, T> {
        Bake {
            rate: self.opts.bake_rate,
            fps: self.anim.fps,
            tolerance,
            dist,
        }
    }

    /// The transform groups and opacity that wrap unit `u`'s element, if it needs any;
    /// its warnings and counts go to `part`.
    fn unit(&self, u: usize, part: &mut Part) -> Option<UnitGroups> {
        let (track, shape) = (&self.anim.tracks[u], &self.anim.scene.shapes[u]);
        let dur = self.clock.dur;
        let mut plan: Option<Plan> = None;
        if !track.deforms() {
            let b = shape.bbox;
            let corners = [
                Point::new(b.x0, b.y0),
                Point::new(b.x1, b.y0),
                Point::new(b.x1, b.y1),
                Point::new(b.x0, b.y1),
            ];
            let ctx = transform::Ctx {
                dur,
                tolerance: self.opts.tolerance,
                rate: self.opts.bake_rate,
                fps: self.anim.fps,
            };
            match transform::plan(track, shape.parent_transform, &corners, &ctx) {
                Ok(p) => plan = p,
                Err(why) => part.warn(u, format!("motion not exported: {why}")),
            }
        }
        let bake = self.bake(OPACITY_TOL, &|a: f64, b: f64| (a - b).abs());
        let mut opacity = String::new();
        if let Some((keys, baked)) = Chain::new(std::iter::once(track), |t| &t.opacity, 1.0, dur)
            .keys(dur, &bake, |a, b| a * b)
        {
            part.baked += baked;
            let keys = strings(&keys, |v| num(*v, 4));
            if xml::animation(
                &mut opacity,
                "animate",
                "attributeName=\"opacity\"",
                &keys,
                false,
                self.clock,
            ) {
                opacity.push('\n');
            }
        }
        let mut open = String::new();
        let mut depth = 0;
        let layers = plan.as_ref().map_or(&[][..], |p| &p.layers);
        if layers.is_empty() && !opacity.is_empty() {
            open.push_str("<g>\n");
            open.push_str(&opacity);
            depth += 1;
        }
        for (i, layer) in layers.iter().enumerate() {
            open.push_str("<g");
            if let Some(v) = xml::transform_value(layer.base) {
                open.push_str(&format!(" transform=\"{v}\""));
                // An `animateMotion` goes on a group of its own without a `transform`:
                // Chromium applies the motion outside the group's transform, the SVG 1.1
                // text inside it, and with none there is no order to disagree on.
                if layer
                    .anims
                    .iter()
                    .any(|a| matches!(a.kind, Kind::Motion { .. }))
                {
                    open.push_str(">\n<g");
                    depth += 1;
                }
            }
            open.push_str(">\n");
            if i == 0 {
                open.push_str(&opacity);
            }
            for a in &layer.anims {
                self.transform_anim(&mut open, a);
            }
            depth += 1;
        }
        if let Some(p) = &plan {
            part.exact += p.exact;
            part.baked += p.baked;
            if let Some(v) = xml::transform_value(p.inner) {
                open.push_str(&format!("<g transform=\"{v}\">\n"));
                depth += 1;
            }
        }
        (depth > 0).then_some(UnitGroups { open, depth })
    }

    fn transform_anim(&self, out: &mut String, a: &TransformAnim) {
        if let (Kind::Motion { auto }, Some(path)) = (a.kind, &a.path) {
            let head = format!(
                "path=\"{path}\"{}",
                if auto { " rotate=\"auto\"" } else { "" }
            );
            let keys = strings(&a.keys, |v| num(v[0], FACTOR));
            if xml::motion(out, &head, &keys, self.clock) {
                out.push('\n');
            }
            return;
        }
        let head = format!(
            "attributeName=\"transform\" type=\"{}\" additive=\"sum\"",
            a.kind.name()
        );
        let pair = |v: &[f64], decimals: usize| {
            let mut s = num(v[0], decimals);
            s.push(' ');
            push_num(&mut s, v[1], decimals);
            s
        };
        let keys = strings(&a.keys, |v| match a.kind {
            Kind::Translate => pair(v, COORD),
            Kind::Scale => pair(v, FACTOR),
            Kind::Rotate | Kind::SkewX | Kind::SkewY | Kind::Motion { .. } => num(v[0], COORD),
        });
        if xml::animation(
            out,
            "animateTransform",
            &head,
            &keys,
            a.discrete,
            self.clock,
        ) {
            out.push('\n');
        }
    }

    /// Adds the paint, width and geometry animations of a path inside animated units.
    /// `defs` takes the tinted copies of its gradients and patterns: needed only when it
    /// is painted with one ([`uses_paint_server`]).
    fn path(
        &self,
        mp: &MarkedPath<'_>,
        el: &Element,
        svg: &str,
        els: &HashMap<&str, Element>,
        part: &mut Part,
        mut defs: Option<&mut Defs>,
    ) {
        let anim = self.anim;
        let dur = self.clock.dur;
        let tracks: Vec<&Track> = mp.units.iter().map(|&u| &anim.tracks[u]).collect();
        let tag = &svg[el.tag.start..el.tag.end];
        let unit = *mp.units.last().unwrap_or(&0);
        let mut children = String::new();
        let tint_bake = self.bake(COLOR_TOL, &|a: Tint, b: Tint| tint_dist(a, b));
        let paints = [
            (
                "fill",
                mp.path.fill.as_ref().map(|f| &f.paint),
                Chain::new(tracks.iter().copied(), |t| &t.fill, Tint::NONE, dur),
            ),
            (
                "stroke",
                mp.path.stroke.as_ref().map(|s| &s.paint),
                Chain::new(tracks.iter().copied(), |t| &t.stroke, Tint::NONE, dur),
            ),
        ];
        let at = |attr| PaintRef {
            el,
            tag,
            attr,
            svg,
            els,
        };
        for (name, paint, chain) in paints {
            let Some(paint) = paint else { continue };
            let Some((keys, baked)) = chain.keys(dur, &tint_bake, paint::compose) else {
                continue;
            };
            part.baked += baked;
            const GIVEN: &str = "paths painted with a paint server are given the definitions";
            match paint {
                Paint::Solid(c) => {
                    let values = strings(&keys, |t| t.apply(*c).to_hex());
                    if xml::animation(
                        &mut children,
                        "animate",
                        &format!("attributeName=\"{name}\""),
                        &values,
                        false,
                        self.clock,
                    ) {
                        children.push('\n');
                    }
                }
                Paint::Linear(_) | Paint::Radial(_) => {
                    let stops = paint.gradient_stops().unwrap_or_default();
                    let defs = defs.as_deref_mut().expect(GIVEN);
                    self.tinted_gradient(&at(name), stops, &keys, part, defs);
                }
                Paint::Pattern(p) => {
                    self.tinted_pattern(
                        unit,
                        &at(name),
                        p,
                        &keys,
                        part,
                        defs.as_deref_mut().expect(GIVEN),
                    );
                }
            }
        }
        if let Some(stroke) = &mp.path.stroke {
            let bake = self.bake(WIDTH_TOL, &|a: f64, b: f64| (a - b).abs());
            let chain = Chain::new(tracks.iter().copied(), |t| &t.stroke_width, 1.0, dur);
            if let Some((keys, baked)) = chain.keys(dur, &bake, |a, b| a * b) {
                part.baked += baked;
                let values = strings(&keys, |m| num(stroke.width * m, COORD));
                if xml::animation(
                    &mut children,
                    "animate",
                    "attributeName=\"stroke-width\"",
                    &values,
                    false,
                    self.clock,
                ) {
                    children.push('\n');
                }
            }
        }
        let mut trimmed = false;
        if mp.path.stroke.is_some() {
            trimmed = self.trim(mp, &tracks, unit, part, &mut children);
        }
        let morphing = mp
            .units
            .iter()
            .rev()
            .find_map(|&u| morph::leaf(anim, u, mp.path));
        let deforming: Vec<&Track> = tracks.iter().copied().filter(|t| t.deforms()).collect();
        if !deforming.is_empty() {
            // A morphing path deforms its in-between (then its morph is in these keys).
            let outline = |t: f64| match morphing {
                Some((segs, leaf)) => {
                    Cow::Owned(gmotion::motion::morph::leaf_at(segs, leaf, t).unwrap_or_default())
                }
                None => Cow::Borrowed(&mp.path.path),
            };
            match deform::d_keys(
                outline,
                mp.abs,
                &deforming,
                dur,
                self.opts.bake_rate,
                self.anim.fps,
                self.opts.tolerance,
            ) {
                Some(keys) => {
                    part.baked += 1;
                    if xml::animation(
                        &mut children,
                        "animate",
                        "attributeName=\"d\"",
                        &keys,
                        false,
                        self.clock,
                    ) {
                        children.push('\n');
                    }
                }
                None => part.warn(
                    unit,
                    "a path under a singular transform is not deformed".into(),
                ),
            }
        }
        // Under per-vertex motion the deformed keys above carry the morph.
        if let Some((segs, leaf)) = morphing.filter(|_| deforming.is_empty()) {
            let (rate, tol) = (self.opts.bake_rate, self.opts.tolerance);
            let keys = morph::d_keys(segs, leaf, mp.abs, rate, self.anim.fps, tol);
            part.exact += 1;
            if xml::animation(
                &mut children,
                "animate",
                "attributeName=\"d\"",
                &keys,
                false,
                self.clock,
            ) {
                children.push('\n');
            }
        }
        if !children.is_empty() {
            // A trim is a dash pattern on a path whose length counts as 1.
            let length = if trimmed { " pathLength=\"1\"" } else { "" };
            part.replace(
                el.tag.end - 2..el.tag.end,
                format!("{length}>\n{children}</path>"),
            );
        }
    }

    /// Writes the trim of the units `tracks` (outermost first) as `stroke-dasharray` and
    /// `stroke-dashoffset` animations on a path whose `pathLength` is 1: the dash is the
    /// visible part's length `L` followed by a gap `P − L` (the period `P` is 1 when a part
    /// moves past the end and must wrap to the start, else 2), and the offset `−(start +
    /// shift)` puts the dash where the visible part starts. Both are affine in the trim,
    /// so the keys are the trim's own. True when written.
    fn trim(
        &self,
        mp: &MarkedPath<'_>,
        tracks: &[&Track],
        unit: usize,
        part: &mut Part,
        children: &mut String,
    ) -> bool {
        let dur = self.clock.dur;
        let chain = Chain::new(tracks.iter().copied(), |t| &t.trim, Trim::REST, dur);
        let bake = self.bake(TRIM_TOL, &|a: Trim, b: Trim| {
            (a.start - b.start)
                .abs()
                .max((a.end - b.end).abs())
                .max((a.shift - b.shift).abs())
        });
        // The innermost unit that trims decides, as in the frame writer.
        let inner = |a: Trim, b: Trim| if b == Trim::REST { a } else { b };
        let Some((keys, baked)) = chain.keys(dur, &bake, inner) else {
            return false;
        };
        part.baked += baked;
        let subpaths = mp
            .path
            .path
            .elements()
            .iter()
            .filter(|e| matches!(e, kurbo::PathEl::MoveTo(_)))
            .count();
        if subpaths > 1 {
            part.warn(
                unit,
                format!(
                    "a trimmed path of {subpaths} subpaths is dashed along its whole length in SMIL (each subpath is trimmed on its own in the model and Lottie)"
                ),
            );
        }
        // A pattern repeating once per length wraps a part moved past the end to the
        // start, but its copies touch the ends of an open path (where round caps then draw
        // dots); when no part wraps, the pattern repeats every two lengths instead.
        let wraps = keys
            .iter()
            .any(|k| k.v.start + k.v.shift < -1e-12 || k.v.end + k.v.shift > 1.0 + 1e-12);
        let period = if wraps { 1.0 } else { 2.0 };
        let dashes = strings(&keys, |t| {
            let l = t.end - t.start;
            format!("{} {}", num(l, FACTOR), num(period - l, FACTOR))
        });
        let offsets = strings(&keys, |t| num(-(t.start + t.shift), FACTOR));
        for (attr, values) in [
            ("stroke-dasharray", &dashes),
            ("stroke-dashoffset", &offsets),
        ] {
            if xml::animation(
                children,
                "animate",
                &format!("attributeName=\"{attr}\""),
                values,
                false,
                self.clock,
            ) {
                children.push('\n');
            }
        }
        // A zero-length dash still draws its caps (a dot where the empty stroke would
        // start), so while the trim is empty the caps are butt ones, which draw nothing.
        let cap = match mp.path.stroke.as_ref().map(|s| s.cap) {
            Some(LineCap::Round) => "round",
            Some(LineCap::Square) => "square",
            Some(LineCap::Butt) | None => return true,
        };
        let empty = |t: &Trim| t.is_empty();
        if keys.iter().any(|k| empty(&k.v)) {
            let mut caps: Vec<Key<String>> = Vec::new();
            let mut put = |t: f64, v: &str| match caps.last() {
                Some(k) if k.v == v => {}
                _ => caps.push(Key::linear(t, v.to_string())),
            };
            for (i, k) in keys.iter().enumerate() {
                if !empty(&k.v) {
                    put(k.t, cap);
                    continue;
                }
                put(k.t, "butt");
                // Drawing on from empty: the caps come back right after the instant.
                if keys.get(i + 1).is_some_and(|n| !empty(&n.v) && n.t > k.t) {
                    put(k.t + gmotion::keyframe::steps::LATE, cap);
                }
            }
            if xml::animation(
                children,
                "animate",
                "attributeName=\"stroke-linecap\"",
                &caps,
                true,
                self.clock,
            ) {
                children.push('\n');
            }
        }
        true
    }

    /// Points the path's `attr` paint at a copy of its gradient whose stops animate `keys`.
    fn tinted_gradient(
        &self,
        at: &PaintRef<'_>,
        stops: &[Stop],
        keys: &[Key<Tint>],
        part: &mut Part,
        defs: &mut Defs,
    ) {
        let clock = self.clock;
        tinted_def(at, part, defs, |text, edits| {
            let stop_tags = splice::tags(text)
                .into_iter()
                .filter(|t| text[t.start..].starts_with("<stop"));
            for (t, stop) in stop_tags.zip(stops) {
                let values = strings(keys, |k| k.apply(stop.color).to_hex());
                let mut anim = String::new();
                xml::animation(
                    &mut anim,
                    "animate",
                    "attributeName=\"stop-color\"",
                    &values,
                    false,
                    clock,
                );
                edits.replace(t.end - 2..t.end, format!(">{anim}</stop>"));
            }
        });
    }

    /// Points the path's `attr` paint at a copy of its pattern whose content animates its
    /// solid colours by `keys` (content painted with paint servers keeps its colours).
    fn tinted_pattern(
        &self,
        unit: usize,
        at: &PaintRef<'_>,
        pattern: &Pattern,
        keys: &[Key<Tint>],
        part: &mut Part,
        defs: &mut Defs,
    ) {
        let clock = self.clock;
        let mut content = Vec::new();
        content_paths(&pattern.root, &mut content);
        let mut servers = false;
        tinted_def(at, part, defs, |text, edits| {
            let path_tags = splice::tags(text)
                .into_iter()
                .filter(|t| text[t.start..].starts_with("<path"));
            for (t, p) in path_tags.zip(&content) {
                let mut anims = String::new();
                let paints = [
                    ("fill", p.fill.as_ref().map(|f| &f.paint)),
                    ("stroke", p.stroke.as_ref().map(|s| &s.paint)),
                ];
                for (name, paint) in paints {
                    match paint {
                        Some(Paint::Solid(c)) => {
                            let values = strings(keys, |k| k.apply(*c).to_hex());
                            xml::animation(
                                &mut anims,
                                "animate",
                                &format!("attributeName=\"{name}\""),
                                &values,
                                false,
                                clock,
                            );
                        }
                        Some(_) => servers = true,
                        None => {}
                    }
                }
                if !anims.is_empty() {
                    edits.replace(t.end - 2..t.end, format!(">{anims}</path>"));
                }
            }
        });
        if servers {
            part.warn(
                unit,
                "gradients and patterns inside a tinted pattern keep their colours".into(),
            );
        }
    }
}

/// Copies the definition `at` refers to under a fresh id, lets `body` edit the copy's
/// text, and points the reference at the copy.
fn tinted_def(
    at: &PaintRef<'_>,
    part: &mut Part,
    defs: &mut Defs,
    body: impl FnOnce(&str, &mut Edits),
) {
    let Some((range, value)) = tag_attr(at.tag, at.attr) else {
        return;
    };
    let Some((name, def)) = value
        .strip_prefix("url(#")
        .and_then(|v| v.strip_suffix(')'))
        .and_then(|n| at.els.get(n).map(|d| (n, d)))
    else {
        return;
    };
    let mut copy_name = format!("{name}-{}", at.attr);
    while defs.taken(&copy_name) {
        copy_name.push('_');
    }
    let text = &at.svg[def.tag.start..def.end];
    let mut edits = Edits::default();
    if let Some((r, _)) = tag_attr(text, "id") {
        edits.replace(r, copy_name.clone());
    }
    body(text, &mut edits);
    defs.given.insert(copy_name.clone());
    edits.apply(text.to_string()).push_to(&mut defs.text);
    defs.text.push('\n');
    let start = at.el.tag.start;
    part.replace(
        start + range.start..start + range.end,
        format!("url(#{copy_name})"),
    );
}

/// A paint attribute of a path element in the static document.
struct PaintRef<'s> {
    /// The path element.
    el: &'s Element,
    /// Its start tag's text.
    tag: &'s str,
    /// `fill` or `stroke`.
    attr: &'s str,
    /// The static document.
    svg: &'s str,
    /// Its elements by id.
    els: &'s HashMap<&'s str, Element>,
}

/// The paths of a group's content in document order (the order the writer writes them).
fn content_paths<'g>(g: &'g Group, out: &mut Vec<&'g PathNode>) {
    for child in &g.children {
        match child {
            Node::Group(h) => content_paths(h, out),
            Node::Path(p) => out.push(p),
            Node::Image(_) => {}
        }
    }
}

/// Keys with their values written out.
fn strings<T>(keys: &[Key<T>], f: impl Fn(&T) -> String) -> Vec<Key<String>> {
    keys.iter()
        .map(|k| Key {
            t: k.t,
            v: f(&k.v),
            ease: k.ease,
        })
        .collect()
}
