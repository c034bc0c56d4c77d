//! Group grammars (gTangle, Santoni & Pellacini 2016): spatial rules that split, outline,
//! place, fill and regroup shapes, so a few input shapes become thousands of pattern
//! pieces that timeslice rules can then animate.
//!
//! A tangle shape is ⟨t, g, s; Θ, d⟩: a tag, a group id, an id within the group, a boundary
//! of polygons with holes ([`polygon::Region`]) and an orientation vector. [`expand()`] runs
//! the rules on a [`Scene`](crate::scene::Scene); the operators themselves are plain
//! functions in [`ops`] (with [`place`] and [`field`] holding the placement and streamline
//! machinery), all built on i_overlay's integer booleans ([`boolean`]) over one common
//! lattice, so pieces that share an edge share it exactly. [`graph`] gives the grammar
//! graph of gTangle sec. 5.
//!
//! Supported: every operator of the paper (ungroup, regroup, regular split with any curve,
//! outline, streamline split with its three fields, placement, fill, stippling, invert,
//! perturbation) on arbitrary polygons with holes. Not supported: operators on open paths
//! (a shape must enclose area), and the paper's interactive editing.

pub mod bind;
pub mod boolean;
pub mod expand;
pub mod field;
pub mod graph;
pub mod noise;
pub mod ops;
pub mod place;
pub mod polygon;

pub use expand::expand;
pub use graph::{GraphStats, graph_dot, graph_stats, graph_svg};

use std::time::Duration;

use crate::grammar::ast::Span;
use crate::warning::Warning;

/// Settings of a spatial expansion.
#[derive(Clone, Debug)]
pub struct TangleOptions {
    /// Seed of every random choice.
    pub seed: u64,
    /// Expansion stops with an error after this many steps.
    pub max_steps: usize,
    /// Expansion stops with an error when there are more shapes than this, and a `place`
    /// that would scatter more is refused before it starts.
    pub max_shapes: usize,
    /// Flattening tolerance in user units: curves become polylines within this distance.
    pub tolerance: f64,
    /// Working resolution in user units (gTangle's "polyline sample resolution"):
    /// streamlines are traced in steps of it, placement rasters are twice as fine.
    pub resolution: f64,
    /// Expansion stops with an error once it has run this long (`None`: no bound). Pieces
    /// and steps bound the count of operations, not their cost: a rule feeding itself on
    /// shapes that are costly to cut stays under both for minutes.
    pub max_time: Option<Duration>,
}

impl TangleOptions {
    /// The most pieces expansion may make over all its steps: four times `max_shapes`, room
    /// for pieces that are split again (a shape split in two, then each half in two, makes
    /// six pieces for four alive) while a rule that rewrites its own output in place for ever
    /// ends within a second instead of running through every step.
    pub fn max_work(&self) -> usize {
        self.max_shapes.saturating_mul(4)
    }

    /// The default settings with `seed`.
    pub fn with_seed(seed: u64) -> TangleOptions {
        TangleOptions {
            seed,
            ..TangleOptions::default()
        }
    }
}

/// The most shapes a group grammar makes by default: each costs about 4 KB, so this
/// bounds a run near a gigabyte (`--limit pieces=N` raises it).
pub const DEFAULT_MAX_PIECES: usize = 250_000;

impl Default for TangleOptions {
    fn default() -> Self {
        TangleOptions {
            seed: 0,
            max_steps: 100_000,
            max_shapes: DEFAULT_MAX_PIECES,
            tolerance: 0.1,
            resolution: 1.0,
            max_time: None,
        }
    }
}

/// What a spatial expansion did.
#[derive(Clone, Debug, Default)]
pub struct TangleStats {
    /// Expansion steps (one rule applied to one group).
    pub steps: usize,
    /// Pieces in the result (final tangle shapes).
    pub shapes: usize,
    /// Group ids used (the next free id).
    pub groups: usize,
    /// How often each spatial rule was applied, in the order given.
    pub rule_uses: Vec<usize>,
    /// Warnings.
    pub warnings: Vec<Warning>,
}

/// Why a spatial expansion failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TangleError {
    /// A rule's argument is wrong for its operator.
    #[error("{}:{}: {message}", span.line, span.col)]
    Arg {
        /// Where.
        span: Span,
        /// What is wrong.
        message: String,
    },
    /// Expansion did not end within the step budget.
    #[error("spatial expansion did not end after {steps} steps; still rewriting: {}", rules.iter().map(|(op, s)| format!("`{op}` at {}:{}", s.line, s.col)).collect::<Vec<_>>().join(", "))]
    MaxSteps {
        /// Steps taken.
        steps: usize,
        /// The rules applied in the last steps, with their places.
        rules: Vec<(String, Span)>,
    },
    /// Expansion made too many pieces over all its steps: a rule that keeps rewriting its
    /// own output (`regularSplit(line, 2) : s -> [s]`) halves slivers until they cannot be
    /// split, then rewrites each in place at every step, so its cost is the pieces it makes,
    /// not the steps or the shapes alive.
    #[error("spatial expansion made {made} pieces in {steps} steps, more than the limit of {limit} (`--limit pieces=N` raises it); still rewriting: {}", rules.iter().map(|(op, s)| format!("`{op}` at {}:{}", s.line, s.col)).collect::<Vec<_>>().join(", "))]
    MaxWork {
        /// Pieces made, all steps together.
        made: usize,
        /// Steps taken.
        steps: usize,
        /// The limit.
        limit: usize,
        /// The rules applied in the last steps, with their places.
        rules: Vec<(String, Span)>,
    },
    /// Expansion ran past its time budget ([`TangleOptions::max_time`]): `outline(5) : s
    /// -> [s, s]` on a polygon of 20 000 vertices cuts ever more rings of that many vertices,
    /// under the pieces limit for minutes.
    #[error("spatial expansion ran past the limit of {seconds} s ({steps} steps, {made} pieces made; `--limit spatial-seconds=N` raises it); still rewriting: {}", rules.iter().map(|(op, s)| format!("`{op}` at {}:{}", s.line, s.col)).collect::<Vec<_>>().join(", "))]
    MaxTime {
        /// The limit, in seconds.
        seconds: u64,
        /// Steps taken.
        steps: usize,
        /// Pieces made, all steps together.
        made: usize,
        /// The rules applied in the last steps, with their places.
        rules: Vec<(String, Span)>,
    },
    /// Expansion produced too many shapes.
    #[error("spatial expansion produced {shapes} shapes, more than the limit of {limit}")]
    MaxShapes {
        /// Shapes alive.
        shapes: usize,
        /// The limit.
        limit: usize,
    },
    /// The input geometry cannot be handled.
    #[error("{0}")]
    Geometry(String),
}

impl TangleError {
    /// An argument error at `span`.
    pub fn arg(span: Span, message: impl Into<String>) -> TangleError {
        TangleError::Arg {
            span,
            message: message.into(),
        }
    }
}
