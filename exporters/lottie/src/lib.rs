//! Lottie export: an [`Animation`] (or a still [`Scene`]) as Lottie JSON that validates
//! against the official schema and plays in lottie-web, rlottie and ThorVG.
//!
//! What is written:
//!
//! - one shape layer per animated shape, named after its tag: `letter_G` for a tag's only
//!   shape, `Wheel 1`, `Wheel 2`… for the shapes of a tag with several ([`layer_names`]; a
//!   still shape is a group of that name), in paint order;
//! - the source's named groups (`<g id>`, and the `<svg>`'s own id) whose content makes
//!   layers as null layers of that name, parents of those layers, so that the layer tree
//!   reads as the designer's groups (`Layer_1` › `Wheel` › `Wheel 1`, `Wheel 2`); the nulls
//!   are the identity, group transforms and opacity staying where they were;
//! - paths as Bézier outlines (quadratics raised to cubics, one `sh` per subpath); fills
//!   and strokes, solid or linear/radial gradient with colour and opacity stops, fill
//!   rule, opacity, caps, joins, miter limit and dashes, in SVG paint order; group
//!   transforms as skew-free levels (a skew is written as a rotation·scale·rotation pair,
//!   since rlottie cannot draw skew);
//! - clip paths as layer masks, or as alpha track mattes when they are more than a union
//!   of simple outlines; masks as luma or alpha track mattes; group opacity over several
//!   paints as layer opacity; patterns as tiles under an alpha matte of the outline;
//! - motion exactly where Lottie can say it (see the `animate` module): nested transform levels
//!   with keyframes at window boundaries and the ends of the active interval, eased by the
//!   motion's Bézier, holds where the motion jumps; colour tints, opacity and stroke-width
//!   multipliers as keyframes on `fl.c`/`st.c`/gradient stops, layer `o` and `st.w`;
//! - elsewhere (Alexa interpolation, bilinear blends, skew and matrix components,
//!   non-Bézier easing, per-vertex deformation) sampled per frame and reduced greedily
//!   within [`LottieOptions::tolerance`] canvas units (the `bake` module).
//!
//! A scene imported from Lottie is written back over its source instead ([`layered`]): the
//! document as it was read, with gmotion's motion layered on top.
//!
//! What is approximated, with a warning naming the element: focal radii of radial
//! gradients, radial gradients stretched on strokes, `miter-clip` joins, repeating
//! gradients with a focal point, patterns too fine to tile. Lottie players loop by
//! default and the format has no "play once" flag, so a non-looping animation is written
//! the same way (the player decides).

mod animate;
mod bake;
mod fold;
mod follow;
mod geometry;
mod keys;
pub mod layered;
mod layers;
mod model;
mod pack;
mod paint;
mod restyle;
pub mod slots;
mod text;

use rayon::prelude::*;

use animate::{Bakes, UnitInfo, UnitMotion, may_stroke, unit_motion};
use gmotion::Warning;
use gmotion::canvas::{Fit, OutputSize, pixels};
use gmotion::engine::markers::Marker;
use gmotion::engine::slots::SlotKinds;
use gmotion::motion::{Animation, Track};
use gmotion::scene::{Scene, Shape};
use layers::Source;
pub use layers::layer_names;
pub use text::LottieText;

/// Options of the Lottie export.
#[derive(Clone, Debug, PartialEq)]
pub struct LottieOptions {
    /// Error bound (canvas units) for motion that has to be sampled and reduced.
    pub tolerance: f64,
    /// The animation's name (`nm`).
    pub name: String,
    /// The composition's size `w` × `h`, the art scaled to fit (see [`OutputSize`]).
    /// Default: the scene's size.
    pub size: OutputSize,
    /// Named spans written as the document's `markers` (the grammar's `markers`).
    pub markers: Vec<Marker>,
    /// The properties given Lottie slots (the grammar's `slots`; see [`slots`]).
    pub slots: SlotKinds,
    /// Whether runs of plain shape layers are written as one layer of named groups
    /// (`--pack`): faster to play, one layer where After Effects saw many (see the `pack`
    /// module).
    pub pack: bool,
}

impl Default for LottieOptions {
    fn default() -> Self {
        LottieOptions {
            tolerance: 0.25,
            name: "gmotion".to_string(),
            size: OutputSize::default(),
            markers: Vec::new(),
            slots: SlotKinds::default(),
            pack: false,
        }
    }
}

/// The JSON text and the warnings: features dropped or approximated, each naming the
/// element.
pub type LottieOutput = (String, Vec<Warning>);

/// Why an export failed.
#[derive(Debug, thiserror::Error)]
pub enum LottieError {
    /// The canvas is empty or not finite.
    #[error("the canvas is {width}×{height}; Lottie needs a positive, finite size")]
    Size {
        /// Width.
        width: f64,
        /// Height.
        height: f64,
    },
    /// Frame rate or duration unusable.
    #[error(
        "the animation's frame rate ({fps}) and duration ({duration} s) must be positive and finite"
    )]
    Timing {
        /// Frames per second.
        fps: f64,
        /// Seconds.
        duration: f64,
    },
    /// The animation has a different number of tracks than shapes.
    #[error("the animation has {tracks} tracks for {shapes} shapes")]
    Tracks {
        /// Tracks.
        tracks: usize,
        /// Shapes.
        shapes: usize,
    },
}

/// Shapes from which an export bakes their motions in parallel.
const PARALLEL_UNITS: usize = 64;

/// Writes an animation as Lottie JSON.
pub fn to_lottie(anim: &Animation, opts: &LottieOptions) -> Result<LottieOutput, LottieError> {
    to_lottie_text(anim, opts).map(|(text, warnings)| (text.into_string(), warnings))
}

/// [`to_lottie`] with the text not yet written: [`LottieText::write_to`] writes it to a
/// file a run of layers at a time, never holding the whole text.
pub fn to_lottie_text(
    anim: &Animation,
    opts: &LottieOptions,
) -> Result<(LottieText, Vec<Warning>), LottieError> {
    if !(anim.fps.is_finite() && anim.fps > 0.0 && anim.duration.is_finite() && anim.duration > 0.0)
    {
        return Err(LottieError::Timing {
            fps: anim.fps,
            duration: anim.duration,
        });
    }
    if anim.tracks.len() != anim.scene.shapes.len() {
        return Err(LottieError::Tracks {
            tracks: anim.tracks.len(),
            shapes: anim.scene.shapes.len(),
        });
    }
    let frames = anim.frame_count();
    let bakes = Bakes::default();
    let motion = |(u, (track, shape)): (usize, (&Track, &Shape))| {
        let info = UnitInfo {
            bbox: shape.bbox,
            centroid: shape.centroid,
            strokes: anim.scene.unit_node(u).is_none_or(may_stroke),
        };
        unit_motion(track, info, anim.fps, frames, opts.tolerance, &bakes)
    };
    // Shapes are independent, and baking what Lottie cannot say (skews, blends) samples and
    // fits every frame of a moving window: most of an export's time on large scenes. A
    // handful of shapes is not worth waking the thread pool for.
    let motions: Vec<UnitMotion> = if anim.tracks.len() >= PARALLEL_UNITS {
        (anim.tracks.par_iter().zip(&anim.scene.shapes))
            .enumerate()
            .map(motion)
            .collect()
    } else {
        anim.tracks
            .iter()
            .zip(&anim.scene.shapes)
            .enumerate()
            .map(motion)
            .collect()
    };
    let names = layer_names(&anim.scene);
    let src = Source {
        scene: &anim.scene,
        tracks: &anim.tracks,
        motions: &motions,
        names: &names,
        fps: anim.fps,
        op: frames as f64,
    };
    let written = write(src, opts);
    // The layers hold what they need of the motions: freeing many (every shape's keys,
    // 7 ms at the intersections scale) is left to the thread pool, while the caller
    // writes the text.
    if motions.len() >= PARALLEL_UNITS {
        rayon::spawn(move || drop(motions));
    }
    written
}

/// Writes a still scene as a one-frame Lottie.
pub fn still_to_lottie(scene: &Scene, opts: &LottieOptions) -> Result<LottieOutput, LottieError> {
    let names = layer_names(scene);
    let src = Source {
        scene,
        tracks: &[],
        motions: &[],
        names: &names,
        fps: 30.0,
        op: 1.0,
    };
    write(src, opts).map(|(text, warnings)| (text.into_string(), warnings))
}

fn write(src: Source, opts: &LottieOptions) -> Result<(LottieText, Vec<Warning>), LottieError> {
    let (w, h) = (src.scene.width, src.scene.height);
    let (fps, op) = (src.fps, src.op);
    if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
        return Err(LottieError::Size {
            width: w,
            height: h,
        });
    }
    // The one rule every output follows (`gmotion::canvas`): whole pixels, rounded half
    // up, and the art at exactly the asked scale, never stretched onto the rounded sides.
    let Some(fit) = opts.size.fit(w, h) else {
        return Err(LottieError::Size {
            width: w,
            height: h,
        });
    };
    let tolerance = if opts.tolerance.is_finite() && opts.tolerance > 0.0 {
        opts.tolerance
    } else {
        0.25
    };
    let mut builder = layers::Builder::new(src, tolerance);
    builder.slots = opts.slots;
    // Precompositions are as large as the canvas in whole pixels (and a margin): drawn at
    // the canvas's own scale, inside the null that `fit_layers` adds.
    let mut layers = builder.layers((pixels(w), pixels(h)));
    if fit.scale != 1.0 || fit.offset != kurbo::Vec2::ZERO {
        fit_layers(&mut layers, &fit, op);
    }
    let size = (fit.width, fit.height);
    let doc = model::Animation {
        v: "5.7.0",
        fr: model::N::coord(fps),
        ip: model::N(0.0),
        op: model::N::coord(op),
        w: size.0,
        h: size.1,
        nm: opts.name.clone(),
        markers: opts
            .markers
            .iter()
            .map(|m| model::MarkerOut::of(m, 0.0, fps))
            .collect(),
        assets: std::mem::take(&mut builder.assets),
        layers,
    };
    let mut json = LottieText::document(doc);
    if opts.slots.any() {
        json = with_slots(json, &mut builder.warnings);
    }
    if opts.pack {
        json = packed(json);
    }
    // Some warnings are about the document rather than one element (effects, for one):
    // each is said once.
    let mut seen = std::collections::HashSet::new();
    builder.warnings.retain(|w| seen.insert(w.clone()));
    Ok((
        json,
        builder.warnings.into_iter().map(Warning::from).collect(),
    ))
}

/// `json` with its slot marks written as slots ([`slots::write`]), what that leaves out
/// added to `warnings`.
fn with_slots(json: LottieText, warnings: &mut Vec<String>) -> LottieText {
    let text = json.into_string();
    // The builder writes JSON, so this parses; were it not to, the document is kept as
    // written (its marks unknown keys players skip) and the slots are said to be missing.
    match serde_json::from_str::<serde_json::Value>(&text) {
        Ok(mut doc) => {
            warnings.extend(slots::write(&mut doc));
            LottieText::from(doc.to_string())
        }
        Err(e) => {
            warnings.push(format!("slots are not written: {e}"));
            LottieText::from(text)
        }
    }
}

/// `json` with runs of plain layers packed into one ([`pack_json`]).
fn packed(json: LottieText) -> LottieText {
    LottieText::from(pack_json(json.into_string()))
}

/// A Lottie document's text with runs of plain shape layers packed into one layer of
/// named groups, in its own layer list and every precomposition's: what
/// [`LottieOptions::pack`] asks of an export, for a document written elsewhere (an After
/// Effects export converted with `--pack`). Text that is not JSON is returned as it is
/// (a document that does not parse has no layers to pack).
pub fn pack_json(text: String) -> String {
    match serde_json::from_str::<serde_json::Value>(&text) {
        Ok(mut doc) => {
            pack::pack(&mut doc);
            doc.to_string()
        }
        Err(_) => text,
    }
}

/// Places the root layers, drawn at the canvas's own scale, where `fit` puts the canvas:
/// through a null parent that scales and moves them (exact for every layer whatever its
/// own transform).
fn fit_layers(layers: &mut Vec<model::Layer>, fit: &Fit, op: f64) {
    use model::{Layer, LayerKind, N, Prop, WriteLayer};
    let ind = layers.iter().map(|l| l.ind).max().unwrap_or(0) + 1;
    for l in layers.iter_mut().filter(|l| l.parent.is_none()) {
        l.parent = Some(ind);
    }
    let mut null = Layer::new(LayerKind::Null, "output".to_string(), ind, 0.0, op);
    null.ks.s = Some(Prop::vec(vec![
        N::fine(fit.scale * 100.0),
        N::fine(fit.scale * 100.0),
    ]));
    null.ks.p = Some(Prop::vec(vec![
        N::coord(fit.offset.x),
        N::coord(fit.offset.y),
    ]));
    layers.push(null);
}
