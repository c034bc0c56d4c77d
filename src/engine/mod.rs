//! The engine: runs a grammar on a scene and produces an [`Animation`].
//!
//! Spatial (group grammar) rules run first and rewrite the scene; timeslice rules then
//! expand every shape's timeline breadth-first ([`expand`]); finally the timelines are
//! compiled into keyframed tracks ([`compile`]).

pub mod check;
pub mod compile;
pub mod expand;
pub mod random;
pub mod rules;
pub mod settings;

use std::fmt;

use crate::grammar::ast::{Grammar, Span};
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
        EngineError { span: Some(span), message: message.into(), notes: Vec::new() }
    }

    /// An error with no place.
    pub fn general(message: impl Into<String>) -> EngineError {
        EngineError { span: None, message: message.into(), notes: Vec::new() }
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
}

/// Statistics of one run, for `gmotion check` and benchmarks.
#[derive(Clone, Debug, Default)]
pub struct RunStats {
    /// Expansion steps taken.
    pub steps: usize,
    /// How many times each rule (by index in the grammar) was applied.
    pub rule_uses: Vec<usize>,
    /// Total timeslices after expansion.
    pub slices: usize,
    /// Number of shapes animated.
    pub shapes: usize,
}

/// Runs `grammar` on `scene`: expansion, then compilation into tracks.
pub fn run(scene: Scene, grammar: &Grammar, opts: &RunOptions) -> Result<(Animation, RunStats), EngineError> {
    let mut settings = settings::from_grammar(grammar)?;
    if let Some(s) = opts.seed {
        settings.seed = s;
    }
    if let Some(f) = opts.fps {
        if !(f.is_finite() && f > 0.0) {
            return Err(EngineError::general(format!("--fps must be a positive number, found {f}")));
        }
        settings.fps = f;
    }
    if let Some(m) = opts.max_steps {
        settings.max_steps = m;
    }
    let program = rules::Program::new(grammar)?;
    if scene.shapes.is_empty() {
        return Err(EngineError::general("the scene has no visible shapes to animate"));
    }
    let tags: Vec<&str> = scene.shapes.iter().map(|s| s.tag.as_str()).collect();
    rules::check_shape_tags(grammar, &tags)?;
    let expansion = expand::expand(&scene, &program, &settings)?;
    let tracks = compile::compile(&scene, &expansion, &settings);
    let stats = RunStats {
        steps: expansion.steps,
        rule_uses: expansion.rule_uses.clone(),
        slices: expansion.timelines.iter().map(Vec::len).sum(),
        shapes: scene.shapes.len(),
    };
    let anim = Animation {
        scene,
        duration: settings.duration,
        fps: settings.fps,
        looping: settings.looping,
        tracks,
    };
    Ok((anim, stats))
}
