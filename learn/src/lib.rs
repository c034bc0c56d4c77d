//! `gmotion learn`: a timeslice grammar and a still scene fitted to a keyframed Lottie
//! animation (After Effects' through Bodymovin, or gmotion's own export), such that
//! `gmotion animate` on the grammar plays the animation again within a tolerance.
//!
//! The steps, one module each: [`sample`] plays the file and records every unit's world
//! motion, opacity and fill at every frame; [`fit`] cuts each unit's timeline at its
//! change points and fits each piece as one `animate` with an easing of the language;
//! [`share`] fits one rule set to units whose pieces say the same kinds of change, each
//! number an expression of the shape (`id`, `k`, `cx`, `cy`, distance); [`rules`] groups
//! the units (tuples of tags, a tag, most of a tag) and writes the grammar; [`report`]
//! says how well each unit is reproduced and what could not be explained. What changes
//! besides motion and fill has a module each: [`trim`] (trim paths, read from the
//! document), [`outline`] (a one-path unit's outline, as morphs) and [`stroke`] (stroke
//! colour and width), the last two nested in the leaves of a unit's slices; [`clip`]
//! keeps a precomposition's clip from moving with its content.

#![forbid(unsafe_code)]

pub mod clip;
pub mod fit;
pub mod outline;
pub mod report;
pub mod rules;
pub mod sample;
pub mod share;
pub mod stroke;
pub mod trim;

use std::path::Path;

use gmotion::motion::{Animation, AttrSeg, Track};
use gmotion::scene::Scene;
use gmotion_pipeline::{Env, ImportChoices, Imported, SceneOptions};
use rayon::prelude::*;

pub use report::Report;

/// Why an animation could not be learned.
#[derive(Debug, thiserror::Error)]
pub enum LearnError {
    /// The input is not a Lottie animation, or cannot be read or played.
    #[error("{0}")]
    Input(String),
    /// A bound on the work was reached (raisable with `--limit`).
    #[error("{0}")]
    Limit(String),
}

/// How closely to fit, and how much work to accept.
#[derive(Clone, Debug)]
pub struct Options {
    /// The largest error accepted, in pixels (as `animate`'s tolerance).
    pub tolerance: f64,
    /// The largest opacity error accepted (0 … 1).
    pub opacity_tolerance: f64,
    /// The most units (layers) learned.
    pub max_units: u64,
    /// The most samples (units × frames) taken.
    pub max_samples: u64,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            tolerance: 0.25,
            opacity_tolerance: 0.01,
            max_units: DEFAULT_MAX_UNITS,
            max_samples: DEFAULT_MAX_SAMPLES,
        }
    }
}

/// Default of `--limit learn-units`.
pub const DEFAULT_MAX_UNITS: u64 = 10_000;

/// Default of `--limit learn-samples`.
pub const DEFAULT_MAX_SAMPLES: u64 = 5_000_000;

/// What `learn` found: the grammar, the still scene it animates and the report.
#[derive(Debug)]
pub struct Learned {
    /// The grammar's text; its `scene` directive names the still scene.
    pub grammar: String,
    /// The still scene: the art at the reference frame, each unit tagged, no motion.
    pub still: Scene,
    /// Whether the grammar names the still as SVG (`units groups`), else as Lottie.
    pub still_svg: bool,
    /// Per unit errors, the rules and what could not be explained.
    pub report: Report,
    /// The animation's length in seconds.
    pub duration: f64,
    /// Its frame rate.
    pub fps: f64,
}

impl Learned {
    /// The still scene as an animation of its full length in which nothing changes, each
    /// unit given a track of its own: the Lottie writer then writes every unit as a layer
    /// of its own, named after its tag (the importer reads the names back as the same tags
    /// and ids), with no keyframe (a change from 1 to 1 is written static).
    pub fn still_animation(&self, duration: f64, fps: f64) -> Animation {
        let track = Track {
            opacity: vec![AttrSeg::linear(0.0, duration, 1.0, 1.0)],
            ..Track::default()
        };
        Animation {
            scene: self.still.clone(),
            duration,
            fps,
            looping: true,
            tracks: vec![track; self.still.shapes.len()],
        }
    }
}

/// Learns the animation at `path`; the grammar's `scene` directive will say `still_name`
/// (the still scene's path relative to the grammar's folder).
pub fn learn(
    path: &Path,
    still_name: &str,
    env: &Env,
    opts: &Options,
) -> Result<Learned, LearnError> {
    learn_still(path, still_name, None, env, opts)
}

/// Learns the animation at `path` with no still scene named: the grammar's `scene`
/// directive says `json_name` (a Lottie still), or `svg_name` when the grammar animates
/// what the Lottie writer cannot layer onto a Lottie still (trim paths, morphs); then
/// [`Learned::still_svg`] is set.
pub fn learn_default(
    path: &Path,
    json_name: &str,
    svg_name: &str,
    env: &Env,
    opts: &Options,
) -> Result<Learned, LearnError> {
    learn_still(path, json_name, Some(svg_name), env, opts)
}

/// [`learn`], with the SVG still's name to take instead when trims or morphs are learned.
fn learn_still(
    path: &Path,
    still_name: &str,
    svg_name: Option<&str>,
    env: &Env,
    opts: &Options,
) -> Result<Learned, LearnError> {
    let name = path.display().to_string();
    if !gmotion_pipeline::scene::is_lottie(path) {
        return Err(LearnError::Input(format!(
            "{name}: error: not a Lottie animation (.json or .lottie); `learn` reads a keyframed animation, and an SVG is a still scene"
        )));
    }
    let options = SceneOptions::new(&ImportChoices::default(), None, env)
        .map_err(|e| LearnError::Input(e.to_string()))?;
    let imported =
        Imported::load(path, &options, env).map_err(|e| LearnError::Input(e.to_string()))?;
    let Some(src) = imported.source.as_deref() else {
        return Err(LearnError::Input(format!(
            "{name}: error: not a Lottie animation"
        )));
    };
    let units = imported.scene.shapes.len() as u64;
    if units == 0 {
        return Err(LearnError::Input(format!(
            "{name}: error: the animation draws nothing: no layer is a unit to learn"
        )));
    }
    if units > opts.max_units {
        return Err(LearnError::Limit(format!(
            "{name}: error: {units} units (layers), more than the limit of {} (raise it with --limit learn-units=N)",
            opts.max_units
        )));
    }
    // Trimmed strokes are learned from the trims' own values; the motion is sampled on
    // the document without them, and the still draws the whole strokes.
    let (trims, untrimmed) = trim::find(src);
    let mut reference = imported.scene.clone();
    if let Some(whole) = &untrimmed {
        reference.root = whole
            .scene_at(src.frame)
            .map_err(|e| LearnError::Input(format!("{name}: error: {}", e.message)))?
            .0
            .root;
    }
    let played = untrimmed.as_ref().unwrap_or(src);
    let samples = sample::sample(played, &reference, opts.max_samples).map_err(|e| match e {
        LearnError::Input(m) => LearnError::Input(format!("{name}: error: {m}")),
        LearnError::Limit(m) => LearnError::Limit(format!("{name}: error: {m}")),
    })?;
    if samples.iter().all(|s| {
        s.motion.windows(2).all(|w| w[0] == w[1])
            && s.opacity.windows(2).all(|w| w[0] == w[1])
            && s.fill.windows(2).all(|w| w[0] == w[1])
            && s.inner_px <= 1e-9
            && !s.stroke_changes
    }) && trims.iter().flatten().all(|t| !t.changes())
    {
        return Err(LearnError::Input(format!(
            "{name}: error: the animation is static: no layer moves, fades, changes colour or changes shape over its {} frames, so there is no motion to learn",
            samples.first().map_or(0, |s| s.motion.len())
        )));
    }
    let clock = fit::Clock {
        fps: src.fps(),
        duration: src.duration(),
    };
    // Morphs and stroke changes are nested in the leaves of a unit's slices, which a twin
    // would play backwards: such a unit is fitted without twins.
    let morphing =
        |s: &sample::UnitSamples| s.outline.as_ref().is_some_and(|o| !o.frames.is_empty());
    let stroking = |s: &sample::UnitSamples| stroke::values(&s.stroke).is_some();
    let mut fitted: Vec<fit::Fitted> = samples
        .par_iter()
        .map(|s| {
            if morphing(s) || stroking(s) {
                return fit::fit_with(s, clock, opts.tolerance, opts.opacity_tolerance, false);
            }
            let mut f = fit::fit(s, clock, opts.tolerance, opts.opacity_tolerance);
            fit::twins(s, clock, opts.tolerance, &mut f);
            f
        })
        .collect();
    // Outlines that change: morphs nested in the slices' leaves; what is left of the change
    // inside the unit is then the morphs' error.
    let morphs: Vec<Option<outline::Fitted>> = samples
        .par_iter()
        .zip(&fitted)
        .map(|(s, f)| {
            let o = s.outline.as_ref().filter(|_| morphing(s))?;
            outline::fit(o, &outline::leaves(&f.slices, clock), clock, opts.tolerance)
        })
        .collect();
    // Strokes that change, nested likewise (a unit with morphs keeps its stroke as drawn).
    let strokes: Vec<Option<stroke::Fitted>> = samples
        .par_iter()
        .zip(&fitted)
        .zip(&morphs)
        .map(|((s, f), m)| {
            let v = stroke::values(&s.stroke).filter(|_| m.is_none())?;
            let leaves = outline::leaves(&f.slices, clock);
            stroke::fit(&v, &leaves, clock, opts.opacity_tolerance, opts.tolerance)
        })
        .collect();
    let mut samples = samples;
    // A stroke learned within the tolerances is explained: the report names the others.
    for (u, st) in strokes.iter().enumerate() {
        if let Some(st) = st
            && st.max_colour <= opts.opacity_tolerance
            && st.max_width <= opts.tolerance
        {
            samples[u].stroke_changes = false;
        }
    }
    for (u, m) in morphs.iter().enumerate() {
        if let Some(m) = m {
            samples[u].inner_px = m.max_px;
            let pts = fit::points_of(&samples[u]);
            let (px, op) = fit::errors(&samples[u], &pts, clock, &fitted[u].slices);
            fitted[u].max_px = px;
            fitted[u].max_opacity = op;
        }
    }
    let unmodelled = report::unmodelled(src);
    // Each changing trim fitted within the tolerance as a fraction of its stroke's length.
    let lengths: Vec<f64> = reference
        .shapes
        .iter()
        .map(|s| {
            reference
                .root
                .node_at(&s.node_path)
                .map_or(0.0, |n| trim::stroke_length(n, s.parent_transform))
        })
        .collect();
    let trim_fits: Vec<Option<trim::Fitted>> = trims
        .iter()
        .zip(&lengths)
        .map(|(t, &len)| {
            let t = t.as_ref().filter(|t| t.problem.is_none() && t.changes())?;
            trim::fit(t, clock, opts.tolerance / len.max(1e-9))
        })
        .collect();
    // The Lottie writer layers no trim and no morph onto a Lottie still: a grammar with
    // either takes the SVG still when none was named.
    let needs_svg =
        trim_fits.iter().flatten().next().is_some() || morphs.iter().flatten().next().is_some();
    let (still_name, svg) = match svg_name {
        Some(n) if needs_svg => (n, true),
        _ => (
            still_name,
            still_name.to_ascii_lowercase().ends_with(".svg"),
        ),
    };
    let mut still = rules::still_scene(&reference, &samples, svg);
    // A morphing unit's still draws its frame-0 outline, where its morphs start.
    for (u, m) in morphs.iter().enumerate() {
        let first = samples[u].outline.as_ref().and_then(|o| o.frames.first());
        if let (Some(_), Some(first)) = (m, first) {
            let path = still.shapes[u].node_path.clone();
            if let Some(node) = still.root.node_at_mut(&path) {
                outline::set_path(node, first);
            }
        }
    }
    // A unit whose stroke changes draws frame 0's stroke in the still.
    for (u, st) in strokes.iter().enumerate() {
        if let Some(st) = st {
            let path = still.shapes[u].node_path.clone();
            if let Some(node) = still.root.node_at_mut(&path) {
                stroke::restroke(node, &st.first);
            }
        }
    }
    let (grammar, rules, played) = rules::write(
        &still, &samples, &fitted, &trim_fits, &morphs, &strokes, clock, still_name, svg, opts,
    );
    // The report says how each unit plays as written: a shared set's numbers, not its own.
    for (u, px, op) in played {
        fitted[u].max_px = px;
        fitted[u].max_opacity = op;
    }
    let mut report = Report::new(&still, &fitted, rules, &unmodelled, &samples, opts, clock);
    for (u, st) in strokes.iter().enumerate() {
        if let Some(st) = st {
            report.units[u].max_opacity = report.units[u].max_opacity.max(st.max_colour);
            report.units[u].max_px = report.units[u].max_px.max(st.max_width);
        }
    }
    for (u, t) in trims.iter().enumerate() {
        let Some(t) = t.as_ref().filter(|t| t.changes()) else {
            continue;
        };
        let why = match (&t.problem, &trim_fits[u]) {
            (Some(p), _) => Some(p.clone()),
            (None, None) => Some("its stroke starts trimmed and is not drawn back to the whole stroke by one eased change, which the still (whole strokes) cannot start from".to_string()),
            (None, Some(_)) if !fitted[u].slices.is_empty() => Some("its trim paths change while it also moves or changes paint, which `learn` does not combine yet".to_string()),
            (None, Some(f)) => {
                let px = f.max_off * lengths[u];
                report.units[u].max_px = report.units[u].max_px.max(px);
                (px > opts.tolerance).then(|| format!("its trim is off by up to {px:.2} px"))
            }
        };
        if let Some(why) = why {
            report.explain(u, why);
        }
    }
    Ok(Learned {
        grammar,
        still,
        still_svg: svg,
        report,
        duration: clock.duration,
        fps: clock.fps,
    })
}
