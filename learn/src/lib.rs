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
//! says how well each unit is reproduced and what could not be explained.

#![forbid(unsafe_code)]

pub mod fit;
pub mod report;
pub mod rules;
pub mod sample;
pub mod share;

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
    let samples = sample::sample(src, &imported.scene, opts.max_samples).map_err(|e| match e {
        LearnError::Input(m) => LearnError::Input(format!("{name}: error: {m}")),
        LearnError::Limit(m) => LearnError::Limit(format!("{name}: error: {m}")),
    })?;
    if samples.iter().all(|s| {
        s.motion.windows(2).all(|w| w[0] == w[1])
            && s.opacity.windows(2).all(|w| w[0] == w[1])
            && s.fill.windows(2).all(|w| w[0] == w[1])
            && s.inner_px <= 1e-9
            && !s.stroke_changes
    }) {
        return Err(LearnError::Input(format!(
            "{name}: error: the animation is static: no layer moves, fades, changes colour or changes shape over its {} frames, so there is no motion to learn",
            samples.first().map_or(0, |s| s.motion.len())
        )));
    }
    let clock = fit::Clock {
        fps: src.fps(),
        duration: src.duration(),
    };
    let fitted: Vec<fit::Fitted> = samples
        .par_iter()
        .map(|s| {
            let mut f = fit::fit(s, clock, opts.tolerance, opts.opacity_tolerance);
            fit::twins(s, clock, opts.tolerance, &mut f);
            f
        })
        .collect();
    let unmodelled = report::unmodelled(src);
    let svg = still_name.to_ascii_lowercase().ends_with(".svg");
    let still = rules::still_scene(&imported.scene, &samples, svg);
    let (grammar, rules, played) =
        rules::write(&still, &samples, &fitted, clock, still_name, svg, opts);
    // The report says how each unit plays as written: a shared set's numbers, not its own.
    let mut fitted = fitted;
    for (u, px, op) in played {
        fitted[u].max_px = px;
        fitted[u].max_opacity = op;
    }
    let report = Report::new(&still, &fitted, rules, &unmodelled, &samples, opts, clock);
    Ok(Learned {
        grammar,
        still,
        report,
        duration: clock.duration,
        fps: clock.fps,
    })
}
