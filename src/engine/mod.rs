//! The engine: runs a grammar on a scene and produces an [`Animation`].
//!
//! Spatial (group grammar) rules run first and rewrite the scene; timeslice rules then
//! expand every shape's timeline breadth-first ([`expand`]); finally the timelines are
//! compiled into keyframed tracks ([`compile`]).

pub mod check;
pub mod compile;
pub mod expand;
pub mod follow;
pub mod markers;
pub mod morph;
mod plan;
pub mod random;
pub mod rules;
pub(crate) mod seam;
pub mod settings;
pub mod slots;
pub mod smooth;
pub mod target;

use crate::warning::Warning;
use std::fmt;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::grammar::ast::{Grammar, Span};
use crate::grammar::diagnostics::Diagnostic;
use crate::motion::Animation;
use crate::scene::Scene;

pub use settings::Settings;

/// An error from running a grammar, pointing into the grammar source where it can.
#[derive(Clone, Debug, PartialEq)]
pub struct EngineError {
    /// Where in the grammar, if the error has a place.
    pub span: Option<Span>,
    /// What went wrong.
    pub message: String,
    /// Further lines (e.g. the rules of a cycle).
    pub notes: Vec<String>,
}

impl EngineError {
    /// An error at a place in the grammar.
    pub fn at(span: Span, message: impl Into<String>) -> EngineError {
        EngineError {
            span: Some(span),
            message: message.into(),
            notes: Vec::new(),
        }
    }

    /// The same error with one more note.
    pub fn with_note(mut self, note: impl Into<String>) -> EngineError {
        self.notes.push(note.into());
        self
    }

    /// The same error with a "did you mean" note when one of `names` is close to `written`.
    pub fn suggesting<'a>(
        self,
        written: Option<&str>,
        names: impl IntoIterator<Item = &'a str>,
    ) -> EngineError {
        match written.and_then(|w| crate::grammar::diagnostics::did_you_mean(w, names)) {
            Some(close) => self.with_note(format!("did you mean `{close}`?")),
            None => self,
        }
    }

    /// An error with no place.
    pub fn general(message: impl Into<String>) -> EngineError {
        EngineError {
            span: None,
            message: message.into(),
            notes: Vec::new(),
        }
    }
}

impl fmt::Display for EngineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(s) = self.span {
            write!(f, "{}:{}: ", s.line, s.col)?;
        }
        f.write_str(&self.message)?;
        for n in &self.notes {
            write!(f, "\n  note: {n}")?;
        }
        Ok(())
    }
}

impl std::error::Error for EngineError {}

/// The error as a grammar diagnostic: at its place, or with none, its notes as the help
/// (one line each).
impl From<&EngineError> for Diagnostic {
    fn from(e: &EngineError) -> Diagnostic {
        let d = match e.span {
            Some(span) => Diagnostic::new(span, e.message.clone()),
            None => Diagnostic::general(e.message.clone()),
        };
        if e.notes.is_empty() {
            d
        } else {
            d.with_help(e.notes.join("\n"))
        }
    }
}

impl From<crate::grammar::value::EvalError> for EngineError {
    fn from(e: crate::grammar::value::EvalError) -> Self {
        EngineError::at(e.span, e.message)
    }
}

/// Options that override the grammar's header.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Overrides `seed`.
    pub seed: Option<u64>,
    /// Overrides `fps`.
    pub fps: Option<f64>,
    /// Overrides `max_steps`.
    pub max_steps: Option<usize>,
    /// Replaces the `markers` directive: the slice tags written as markers.
    pub markers: Option<Vec<String>>,
    /// The most shapes a group grammar may make (default
    /// [`crate::tangle::DEFAULT_MAX_PIECES`]).
    pub max_pieces: Option<usize>,
    /// The longest a group grammar's expansion may run (default: no bound).
    pub max_spatial_time: Option<std::time::Duration>,
}

/// Statistics of one run, for `gmotion check` and benchmarks.
#[derive(Clone, Debug, Default)]
pub struct RunStats {
    /// Timeslice expansion steps taken.
    pub steps: usize,
    /// Spatial (group grammar) expansion steps taken.
    pub spatial_steps: usize,
    /// Things the author should know (degenerate geometry, approximations).
    pub warnings: Vec<Warning>,
    /// How many times each rule (by index in the grammar) was applied.
    pub rule_uses: Vec<usize>,
    /// Total timeslices after expansion.
    pub slices: usize,
    /// Number of shapes animated.
    pub shapes: usize,
    /// The markers the grammar's `markers` directive asks for, in its order.
    pub markers: Vec<markers::Marker>,
    /// The properties the grammar's `slots` directive gives Lottie slots.
    pub slots: slots::SlotKinds,
}

/// Runs `grammar` on `scene`: expansion, then compilation into tracks.
pub fn run(
    scene: Scene,
    grammar: &Grammar,
    opts: &RunOptions,
) -> Result<(Animation, RunStats), EngineError> {
    // A run large enough to go parallel happens on a worker of the thread pool: its
    // parallel parts (expansion, smoothing) are then queued where the other workers steal
    // them, instead of each being handed over from outside while the caller sleeps until
    // it is woken (measured 0.05 ms better on the 208-shape teaser). Small scenes run
    // serially on the caller.
    if scene.shapes.len() < expand::PARALLEL_SHAPES {
        run_here(scene, grammar, opts)
    } else {
        rayon::scope(|_| run_here(scene, grammar, opts))
    }
}

/// The group grammar stage: `None` when the grammar has no spatial rules, else the scene
/// with every shape the spatial rules consume replaced by its pieces. Either way the
/// timeslice rules' shape tags are checked against the scene they will animate.
pub(crate) fn spatial_stage(
    scene: &Scene,
    grammar: &Grammar,
    program: &rules::Program,
    settings: &settings::Settings,
    opts: &RunOptions,
) -> Result<Option<(Scene, crate::tangle::TangleStats)>, EngineError> {
    if program.spatial.is_empty() {
        rules::check_shape_tags(grammar, &scene_tags(scene), false)?;
        return Ok(None);
    }
    // Spatial rules may consume the scene's tags and the tags spatial rules produce.
    let mut known = scene_tags(scene);
    let spatial: Vec<&crate::grammar::ast::Rule> =
        program.spatial.iter().map(|&i| &grammar.rules[i]).collect();
    known.extend(
        spatial
            .iter()
            .flat_map(|r| r.outputs.iter().map(|t| t.name.as_str())),
    );
    rules::check_shape_tags(grammar, &known, true)?;
    let mut topts = crate::tangle::TangleOptions {
        seed: settings.seed,
        ..Default::default()
    };
    if let Some(m) = opts.max_steps {
        topts.max_steps = m;
    }
    if let Some(m) = opts.max_pieces {
        topts.max_shapes = m;
    }
    topts.max_time = opts.max_spatial_time;
    let (expanded, tstats) =
        crate::tangle::expand(scene, &spatial, &topts).map_err(|e| match &e {
            crate::tangle::TangleError::Arg { span, message } => {
                EngineError::at(*span, message.clone())
            }
            other => EngineError::general(other.to_string()),
        })?;
    if expanded.shapes.is_empty() {
        return Err(EngineError::general(
            "the spatial rules left no shapes to animate",
        ));
    }
    rules::check_shape_tags(grammar, &scene_tags(&expanded), false)?;
    Ok(Some((expanded, tstats)))
}

/// Every shape's final timeslices: what [`run`] compiles into tracks, for tools that show
/// a timeline (the studio). The timelines are in the order of the scene after the group
/// grammar's spatial rules, i.e. the order of `run`'s `Animation::scene.shapes`; `scene` is
/// the scene as given to `run`. Expands once more; `run` itself does not keep them.
pub fn timelines(
    scene: &Scene,
    grammar: &Grammar,
    opts: &RunOptions,
) -> Result<expand::Expansion, EngineError> {
    let settings = effective_settings(grammar, scene, opts)?;
    let program = rules::Program::new(grammar)?;
    let spatial = spatial_stage(scene, grammar, &program, &settings, opts)?;
    let scene = spatial.as_ref().map_or(scene, |(s, _)| s);
    expand::expand(scene, &program, &settings)
}

/// The grammar's header with `opts` applied.
fn effective_settings(
    grammar: &Grammar,
    scene: &Scene,
    opts: &RunOptions,
) -> Result<Settings, EngineError> {
    let mut settings = settings::from_grammar(grammar)?;
    // A scene with a time of its own (a Lottie composition) sets what the grammar does not.
    if let Some(time) = scene.time {
        if !settings.duration_given {
            settings.duration = time.duration;
        }
        if !settings.fps_given {
            settings.fps = time.fps;
        }
    }
    if let Some(s) = opts.seed {
        settings.seed = s;
    }
    if let Some(f) = opts.fps {
        if !(f.is_finite() && f > 0.0) {
            return Err(EngineError::general(format!(
                "the frame rate must be a positive number, found {f}"
            )));
        }
        settings.fps = f;
    }
    if let Some(m) = opts.max_steps {
        settings.max_steps = m;
    }
    Ok(settings)
}

fn run_here(
    scene: Scene,
    grammar: &Grammar,
    opts: &RunOptions,
) -> Result<(Animation, RunStats), EngineError> {
    let settings = effective_settings(grammar, &scene, opts)?;
    let program = rules::Program::new(grammar)?;
    if scene.shapes.is_empty() {
        return Err(EngineError::general(
            "the scene has no visible shapes to animate",
        ));
    }
    let mut warnings = Vec::new();
    let mut tangle_steps = 0;
    let scene = match spatial_stage(&scene, grammar, &program, &settings, opts)? {
        None => scene,
        Some((expanded, tstats)) => {
            warnings.extend(tstats.warnings.iter().cloned());
            tangle_steps = tstats.steps;
            expanded
        }
    };
    // Each timeline is compiled into its track as soon as it is expanded, by the thread
    // that expanded it (and freed there).
    let slices = AtomicUsize::new(0);
    let marker_names: Vec<(String, Option<Span>)> = match &opts.markers {
        Some(names) => names.iter().map(|n| (n.clone(), None)).collect(),
        None => (settings.markers.iter())
            .map(|(n, span)| (n.clone(), Some(*span)))
            .collect(),
    };
    let want_markers = !marker_names.is_empty();
    let (
        compiled,
        expand::ExpandStats {
            steps,
            rule_uses,
            slice_tags,
        },
    ) = expand::expand_each(&scene, &program, &settings, |si, timeline| {
        slices.fetch_add(timeline.len(), Ordering::Relaxed);
        // Each shape's slice spans by tag, only when markers are asked for.
        let spans = match want_markers {
            true => markers::spans_of(&timeline),
            false => Vec::new(),
        };
        (compile::track(&scene.shapes[si], &timeline), spans)
    })?;
    let slices = slices.into_inner();
    let (mut tracks, spans): (Vec<_>, Vec<_>) = compiled.into_iter().unzip();
    let markers = match want_markers {
        true => markers::collect(
            &marker_names,
            &slice_tags,
            &program,
            spans.into_iter().flatten(),
        )?,
        false => Vec::new(),
    };
    if let Some((value, span)) = &settings.smoothing {
        let spec = smooth::spec_from_value(value).map_err(|m| EngineError::at(*span, m))?;
        smooth::smooth_tracks(
            &mut tracks,
            &spec,
            settings.duration,
            settings.fps,
            settings.looping,
        )
        .map_err(|m| EngineError::at(*span, m))?;
    }
    let anim = Animation {
        scene,
        duration: settings.duration,
        fps: settings.fps,
        looping: settings.looping,
        tracks,
    };
    if anim.looping {
        warnings.extend(seam::loop_warning(
            &anim.scene.shapes,
            &anim.tracks,
            anim.duration,
            anim.scene.canvas(),
        ));
    }
    let stats = RunStats {
        steps,
        spatial_steps: tangle_steps,
        warnings,
        rule_uses,
        slices,
        shapes: anim.scene.shapes.len(),
        markers,
        slots: settings.slots,
    };
    Ok((anim, stats))
}

/// `v` as a finite number, or an error at `span`: `v`'s own when it is not a number,
/// `not_finite(x)` when it is infinite or NaN.
pub(crate) fn finite_number(
    v: &crate::grammar::value::Value,
    span: Span,
    not_finite: impl FnOnce(f64) -> String,
) -> Result<f64, EngineError> {
    let x = v
        .as_num()
        .map_err(|m| EngineError::at(span, m.to_string()))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(EngineError::at(span, not_finite(x)))
    }
}

/// Every tag some shape of `scene` answers to (aliases included), sorted.
fn scene_tags(scene: &Scene) -> Vec<&str> {
    let mut tags: Vec<&str> = scene.shapes.iter().flat_map(|s| s.tags()).collect();
    tags.sort_unstable();
    tags.dedup();
    tags
}
