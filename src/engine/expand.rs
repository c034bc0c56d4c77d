//! Timeslice expansion (gMotion sec. 3.4/3.6): every shape starts with one slice tagged
//! `all` covering the whole duration; each step picks the non-terminal slices with the
//! lowest slice tag (tags numbered by first creation, so expansion is breadth-first) on the
//! shapes with the lowest shape tag (lexicographic), together with their `inv_` twins,
//! chooses one rule among the highest-priority matches and applies it to all of them.
//!
//! That order is worked out on tags alone first (in the `plan` module); then every shape runs
//! through its own list of steps, evaluating its values, shapes in parallel. The result is
//! the same as applying the steps one after the other to all shapes.

use std::sync::{Arc, Mutex};

use kurbo::{BezPath, Point, Vec2};
use rayon::prelude::*;

use crate::color::Color;
use crate::grammar::ast::{Expr, ExprKind};
use crate::grammar::value::{Env, Value, arithmetic, eval, geometry_var};
use crate::motion::{Component, Field, Grid, Interp, Lookup, Trim};
use crate::scene::{Node, Scene, Shape};
use crate::signals::Easing;

use super::EngineError;
use super::plan::Plan;
use super::random::{draw, noise2};
use super::rules::{AnimType, CRule, Op, Program};
use super::settings::{MAX_KEYS, NoShape, Settings};

/// What an `animate` rule set on a slice, resolved for one shape.
#[derive(Clone, Debug)]
pub enum AnimSpec {
    /// A motion read from a grid.
    Motion {
        /// The grid of transforms.
        grid: Arc<Grid>,
        /// `world` (true) or `local`.
        world: bool,
        /// Where the motion pivots relative to the origin (world) or the centroid (local),
        /// from a transform written about a point, e.g. `rotate(a, cx, cy)`.
        pivot_offset: Vec2,
        /// Grid lookup.
        lookup: Lookup,
        /// Temporal interpolation.
        interp: Interp,
    },
    /// Fill colour target.
    Fill(Color),
    /// Stroke colour target.
    Border(Color),
    /// Opacity target.
    Opacity(f64),
    /// Stroke width target (user units).
    StrokeWidth(f64),
    /// The strokes' visible part to reach.
    Trim(Trim),
    /// Travel along a path (`animate(follow, …)`).
    Follow {
        /// The path, measured.
        route: Arc<crate::motion::follow::Route>,
        /// `world`: the path where it is written; `local`: its start on the centroid.
        world: bool,
        /// Whether the shape turns with the path's tangent.
        orient: bool,
    },
    /// An outline target (resolved for one shape: a morph's spec is never shared).
    Morph(Arc<super::morph::MorphSpec>),
}

/// One application of `animate` to one slice of one shape (or one keyframe interval of
/// it, for a grid with more than two keyframes in time).
#[derive(Clone, Debug)]
pub struct AnimInst {
    /// Expansion step that set it times [`MAX_KEYS`], plus the keyframe interval it
    /// plays: shared by a slice and its `inv_` twin, and ordered as the rules were applied.
    pub step: usize,
    /// What changes.
    pub spec: AnimSpec,
    /// The slice it was set on: start time.
    pub start: f64,
    /// The slice it was set on: end time.
    pub end: f64,
    /// Delay before it starts.
    pub delay: f64,
    /// Easing.
    pub ease: Easing,
    /// True on inverted slices.
    pub reversed: bool,
    /// The part of the change window it plays, as fractions `(from, to)` of it: `(0, 1)`
    /// but for the keyframe intervals of an n×m×p grid.
    pub part: (f64, f64),
}

impl AnimInst {
    /// When the change plays: its slice, delay, easing and direction, narrowed to its
    /// [`part`](AnimInst::part) of the window (mirrored on an inverted slice).
    pub fn timing(&self) -> crate::motion::Timing {
        use crate::motion::Timing;
        let (from, to) = self.part;
        if (from, to) == (0.0, 1.0) {
            return Timing::new(
                self.start,
                self.end,
                self.delay,
                self.ease.clone(),
                self.reversed,
            );
        }
        let len = self.end - self.start - self.delay;
        let (a, b) = if self.reversed {
            (
                self.start + (1.0 - to) * len,
                self.start + (1.0 - from) * len,
            )
        } else {
            let begin = self.start + self.delay;
            (begin + from * len, begin + to * len)
        };
        Timing::new(a, b, 0.0, self.ease.clone(), self.reversed)
    }
}

/// A timeslice.
#[derive(Clone, Debug)]
pub struct Slice {
    /// Slice tag id (into [`Expansion::slice_tags`]).
    pub tag: u32,
    /// Inverted (`inv_`) version of the tag.
    pub inverted: bool,
    /// Start time.
    pub t0: f64,
    /// Duration.
    pub dur: f64,
    /// Animations on this slice (or on the slice it was split from), in the order set.
    /// Shared: the pieces of a split point at their parent's list.
    pub anims: Arc<[Arc<AnimInst>]>,
}

/// The result of expansion.
#[derive(Clone, Debug)]
pub struct Expansion {
    /// One timeline per shape, slices in time order.
    pub timelines: Vec<Vec<Slice>>,
    /// Slice tag names by id (creation order; `all` is 0).
    pub slice_tags: Vec<String>,
    /// Steps taken.
    pub steps: usize,
    /// Uses per grammar rule index.
    pub rule_uses: Vec<usize>,
}

/// The variables [`ShapeEnv`] defines: an expression naming none of them (and not calling
/// `rand`) has one value for every shape of a step.
const SHAPE_VARS: &[&str] = &[
    "id", "n", "k", "count", "cx", "cy", "w", "h", "x0", "y0", "z", "group", "t0", "d", "step",
    "W", "H", "line_id", "word_id",
];

/// True when `e` evaluates the same for every shape and slice of a step.
fn shape_independent(e: &Expr) -> bool {
    match &e.kind {
        // `w-h` lexes as one name and is an error per shape: leave it to the shape.
        ExprKind::Ident(name) => !name.split('-').any(|p| SHAPE_VARS.contains(&p)),
        ExprKind::Call { name, args } => {
            name != "rand" && args.iter().all(|a| shape_independent(&a.value))
        }
        ExprKind::Tuple(items) => items.iter().all(shape_independent),
        ExprKind::Neg(x) => shape_independent(x),
        ExprKind::Binary { lhs, rhs, .. } => shape_independent(lhs) && shape_independent(rhs),
        ExprKind::Num(_) | ExprKind::Str(_) | ExprKind::Color(_) | ExprKind::Size(..) => true,
    }
}

/// Per-shape expression environment.
struct ShapeEnv<'a> {
    shape: &'a Shape,
    n: usize,
    /// The shape's index among those the rule takes, and how many those are (`k`,
    /// `count`), when the rule's values name them.
    rank: Option<(usize, usize)>,
    canvas: (f64, f64),
    t0: f64,
    d: f64,
    /// The shape's own step count ([`super::plan::Applied::depth`]).
    step: usize,
    seed: u64,
    /// Key of this step's draws on the shape's place ([`super::plan::Applied::rand_key`]).
    rand_key: u64,
    draws: u64,
    /// The keyframe an n×m×p motion's value is evaluated at (`u`, 0 to 1), if any.
    u: Option<f64>,
}

impl Env for ShapeEnv<'_> {
    fn var(&self, name: &str) -> Option<f64> {
        let s = self.shape;
        Some(match name {
            "id" => s.id as f64,
            "n" => self.n as f64,
            "k" => self.rank?.0 as f64,
            "count" => self.rank?.1 as f64,
            "z" => s.z as f64,
            "group" => s.group as f64,
            "t0" => self.t0,
            "d" => self.d,
            "step" => self.step as f64,
            "line_id" => s.text.line as f64,
            "word_id" => s.text.word as f64,
            "u" => return self.u,
            _ => return geometry_var(name, s.centroid, s.bbox, self.canvas),
        })
    }

    fn rand(&mut self) -> f64 {
        self.draws += 1;
        draw(self.rand_key, self.shape.id, self.draws)
    }

    fn noise(&self, x: f64, y: f64) -> f64 {
        noise2(self.seed, x, y)
    }
}

/// The grids built during one step: shapes that evaluate the same motion share one grid
/// instead of sampling n×m cells each.
#[derive(Default)]
struct GridCache {
    recent: Vec<Arc<Grid>>,
}

impl GridCache {
    fn get(&mut self, cols: usize, rows: usize, area: kurbo::Rect, field: Field) -> Arc<Grid> {
        let same = |g: &Grid| {
            g.cols == cols
                && g.rows == rows
                && g.area == area
                && match (&g.field, &field) {
                    (Field::Constant(a), Field::Constant(b)) => a == b,
                    (Field::Towards(a), Field::Towards(b)) => a == b,
                    (Field::Path(a), Field::Path(b)) => {
                        Arc::ptr_eq(a, b) || a.elements() == b.elements()
                    }
                    _ => false,
                }
        };
        if let Some(g) = self.recent.iter().find(|g| same(g)) {
            return g.clone();
        }
        let g = Arc::new(Grid::new(cols, rows, area, field));
        if self.recent.len() == 4 {
            self.recent.remove(0);
        }
        self.recent.push(g.clone());
        g
    }
}

/// Shapes from which expansion runs in parallel; below, handing work to other threads
/// costs more than it saves.
pub const PARALLEL_SHAPES: usize = 64;

/// Expands every timeline.
pub fn expand(
    scene: &Scene,
    program: &Program,
    settings: &Settings,
) -> Result<Expansion, EngineError> {
    let (timelines, stats) = expand_each(scene, program, settings, |_, timeline| timeline)?;
    Ok(Expansion {
        timelines,
        slice_tags: stats.slice_tags,
        steps: stats.steps,
        rule_uses: stats.rule_uses,
    })
}

/// What [`expand_each`] reports besides its results.
#[derive(Clone, Debug)]
pub struct ExpandStats {
    /// Slice tag names by id (creation order; `all` is 0).
    pub slice_tags: Vec<String>,
    /// Steps taken.
    pub steps: usize,
    /// Uses per grammar rule index.
    pub rule_uses: Vec<usize>,
}

/// Expands every shape's timeline and hands it to `finish(shape index, timeline)` on the
/// thread that built it, while it is still in that core's cache; returns what `finish`
/// made, in shape order.
///
/// The steps are planned first on tags alone; then each shape runs through its
/// whole history at once, shapes in parallel. The result and, on failure, the error are
/// those of expanding step after step: the error reported is the one of the earliest step,
/// on the first shape in scene order that meets it.
pub fn expand_each<T, F>(
    scene: &Scene,
    program: &Program,
    settings: &Settings,
    finish: F,
) -> Result<(Vec<T>, ExpandStats), EngineError>
where
    T: Send + Default,
    F: Fn(usize, Vec<Slice>) -> T + Sync,
{
    let plan = Plan::new(scene, program, settings);
    let runner = Runner {
        scene,
        program,
        settings,
        plan: &plan,
        shareable: program.rules.iter().map(spec_is_shareable).collect(),
        no_anims: Arc::from([]),
    };
    // The earliest failure as (step, shape, error).
    let failure: Mutex<Option<(usize, usize, EngineError)>> = Mutex::new(None);
    let each = |caches: &mut Vec<StepCache>, si: usize| match runner.shape(si, caches) {
        Ok(timeline) => finish(si, timeline),
        Err((step, e)) => {
            let mut f = failure.lock().unwrap_or_else(|p| p.into_inner());
            if f.as_ref().is_none_or(|(s, i, _)| (step, si) < (*s, *i)) {
                *f = Some((step, si, e));
            }
            T::default()
        }
    };
    let caches = || (0..plan.keys).map(|_| StepCache::default()).collect();
    let n = scene.shapes.len();
    let out: Vec<T> = if n >= PARALLEL_SHAPES {
        (0..n).into_par_iter().map_init(caches, each).collect()
    } else {
        let mut c = caches();
        (0..n).map(|si| each(&mut c, si)).collect()
    };
    // A value error comes from a step the plan did take, so it comes before the reason the
    // plan stopped.
    if let Some((_, _, e)) = failure.into_inner().unwrap_or_else(|p| p.into_inner()) {
        return Err(e);
    }
    if let Some(e) = plan.unfinished {
        return Err(e);
    }
    Ok((
        out,
        ExpandStats {
            slice_tags: plan.slice_tags,
            steps: plan.steps,
            rule_uses: plan.rule_uses,
        },
    ))
}

fn num(e: &Expr, env: &mut dyn Env) -> Result<f64, EngineError> {
    if let Some(x) = arithmetic(e, env) {
        return Ok(x);
    }
    super::finite_number(&eval(e, env)?, e.span, |x| {
        format!("value is not a finite number ({x})")
    })
}

fn shape_note(shape: &Shape) -> String {
    format!("for shape `{}` #{}", shape.tag, shape.id)
}

/// Runs planned histories on shapes.
struct Runner<'a> {
    scene: &'a Scene,
    program: &'a Program,
    settings: &'a Settings,
    plan: &'a Plan,
    /// Whether each rule's arguments are the same for every shape (by rule position).
    shareable: Vec<bool>,
    no_anims: Arc<[Arc<AnimInst>]>,
}

/// Values a worker keeps for the shapes of one step and rule ([`Applied::key`]).
#[derive(Default)]
struct StepCache {
    grids: GridCache,
    /// The rule's spec, when it is the same for every shape.
    spec: Option<SharedSpec>,
    /// The rule's split fractions, when they are the same for every shape.
    split: Option<Arc<[f64]>>,
}

impl Runner<'_> {
    /// Shape `si`'s timeline after every step of its history, or the first error with the
    /// step that met it.
    fn shape(
        &self,
        si: usize,
        caches: &mut [StepCache],
    ) -> Result<Vec<Slice>, (usize, EngineError)> {
        let (plan, settings) = (self.plan, self.settings);
        let class = plan.class_of[si] as usize;
        let shape = &self.scene.shapes[si];
        let sizes = if shape.rig {
            &plan.rig_sizes
        } else {
            &plan.tag_sizes
        };
        let n = sizes[plan.shape_tag_of[si] as usize];
        // Two buffers as long as the final timeline, swapped at every step.
        let mut timeline = Vec::with_capacity(plan.lens[class]);
        let mut next = Vec::with_capacity(plan.lens[class]);
        timeline.push(Slice {
            tag: 0,
            inverted: false,
            t0: 0.0,
            dur: settings.duration,
            anims: self.no_anims.clone(),
        });
        for a in &plan.histories[class] {
            let mut ctx = Ctx {
                rule: &self.program.rules[a.rule],
                outputs: &plan.outputs[a.rule],
                cache: &mut caches[a.key],
                shareable: self.shareable[a.rule],
                settings,
                scene: self.scene,
                step: a.step,
            };
            next.clear();
            for slice in timeline.drain(..) {
                if slice.tag != a.slice_tag {
                    next.push(slice);
                    continue;
                }
                let mut env = ShapeEnv {
                    shape,
                    n,
                    rank: plan.ranks[a.rule]
                        .as_ref()
                        .and_then(|r| r.of(si, shape.rig)),
                    canvas: (self.scene.width, self.scene.height),
                    t0: slice.t0,
                    d: slice.dur,
                    step: a.depth,
                    seed: settings.seed,
                    rand_key: a.rand_key,
                    draws: 0,
                    u: None,
                };
                apply(&mut ctx, &slice, &mut env, &mut next).map_err(|e| (a.step, e))?;
            }
            std::mem::swap(&mut timeline, &mut next);
        }
        Ok(timeline)
    }
}

/// An `animate` rule's resolved spec and easing, shared by every shape of a step when its
/// value and easing do not depend on the shape.
#[derive(Clone)]
struct SharedSpec {
    /// One spec per keyframe interval (one for an ordinary change).
    specs: Arc<[AnimSpec]>,
    ease: Easing,
}

/// What applying a rule to one slice needs besides the slice and the shape.
struct Ctx<'a> {
    rule: &'a CRule,
    /// Slice tag ids of the rule's outputs.
    outputs: &'a [u32],
    /// What the shapes of this step and rule share.
    cache: &'a mut StepCache,
    /// Whether the rule's spec or split is the same for every shape.
    shareable: bool,
    settings: &'a Settings,
    scene: &'a Scene,
    step: usize,
}

/// True when a rule's arguments (an `animate` rule's value and easing, a split's fractions)
/// are the same for every shape, so a step evaluates them once.
fn spec_is_shareable(rule: &CRule) -> bool {
    match &rule.op {
        // A morph's spec holds its shape's own paths.
        Op::Animate(a) if a.kind == AnimType::Morph => false,
        Op::Animate(a) => {
            shape_independent(&a.value) && a.ease.as_ref().is_none_or(shape_independent)
        }
        Op::Timesplit { fractions } => fractions.iter().all(shape_independent),
    }
}

/// A split's fractions, checked: each positive, summing to 1.
/// A split's fractions for `shape` (named in errors; `None` when they do not depend on it).
fn fractions(
    rule: &CRule,
    fs: &[Expr],
    env: &mut dyn Env,
    shape: Option<&Shape>,
) -> Result<Arc<[f64]>, EngineError> {
    let noted = |e: EngineError| match shape {
        Some(s) => e.with_note(shape_note(s)),
        None => e,
    };
    let mut cs = Vec::with_capacity(fs.len());
    for f in fs {
        let c = num(f, env)?;
        if c <= 0.0 {
            return Err(noted(EngineError::at(
                f.span,
                format!("split fractions must be greater than zero, found {c}"),
            )));
        }
        cs.push(c);
    }
    let sum: f64 = cs.iter().sum();
    if (sum - 1.0).abs() > 1e-6 {
        return Err(noted(EngineError::at(
            rule.span,
            format!("split fractions must sum to 1, they sum to {sum}"),
        )));
    }
    Ok(cs.into())
}

/// The errors a rule shows without any shape: its values that do not depend on the shape
/// (split fractions, an `animate` rule's offset, easing and value) evaluated once, as
/// expansion would for every shape. `gmotion check` reports them without a scene, all at
/// once.
pub(crate) fn constant_errors(rule: &CRule) -> Vec<EngineError> {
    // No shape: every variable is unknown (only shape-independent values are evaluated).
    let env = &mut NoShape;
    let mut errors = Vec::new();
    match &rule.op {
        Op::Timesplit { fractions: fs } => {
            if fs.iter().all(shape_independent)
                && let Err(e) = fractions(rule, fs, env, None)
            {
                errors.push(e);
            }
        }
        Op::Animate(a) => {
            if shape_independent(&a.offset) {
                match num(&a.offset, env) {
                    Ok(d) if d < 0.0 => errors.push(negative_offset(&a.offset, d)),
                    Ok(_) => {}
                    Err(e) => errors.push(e),
                }
            }
            if let Some(e) = &a.ease
                && shape_independent(e)
                && let Err(e) = easing(e, env)
            {
                errors.push(e);
            }
            // A follow along another shape (`shape(TAG)`) needs the scene: checked when
            // it runs. Path data is checked here on a scene with no shape. A morph's
            // target is resolved with the shape it morphs.
            let needs_scene =
                a.kind == AnimType::Follow && matches!(a.value.kind, ExprKind::Call { .. });
            if shape_independent(&a.value)
                && !uses_u(&a.value)
                && !needs_scene
                && a.kind != AnimType::Morph
                && let Err(e) = spec(
                    &a.kind,
                    &a.value,
                    env,
                    &crate::scene::SceneBuilder::new(1.0, 1.0).build(),
                )
            {
                errors.push(e);
            }
        }
    }
    errors
}

fn negative_offset(offset: &Expr, delay: f64) -> EngineError {
    EngineError::at(
        offset.span,
        format!("the offset is a delay and cannot be negative, found {delay}"),
    )
}

fn apply(
    ctx: &mut Ctx,
    slice: &Slice,
    env: &mut ShapeEnv,
    out: &mut Vec<Slice>,
) -> Result<(), EngineError> {
    let rule = ctx.rule;
    match &rule.op {
        Op::Timesplit { fractions: fs } => {
            let cs = match &ctx.cache.split {
                Some(cs) => cs.clone(),
                None => {
                    let shape = env.shape;
                    let cs = fractions(rule, fs, env, Some(shape))?;
                    if ctx.shareable {
                        ctx.cache.split = Some(cs.clone());
                    }
                    cs
                }
            };
            let k = cs.len();
            let mut t = slice.t0;
            for j in 0..k {
                // On an inverted slice the split is mirrored: pieces in reverse, tags inverted.
                let o = if slice.inverted { k - 1 - j } else { j };
                let (c, out_tag) = (cs[o], &rule.outputs[o]);
                let dur = if j + 1 == k {
                    slice.t0 + slice.dur - t
                } else {
                    slice.dur * c
                };
                out.push(Slice {
                    tag: ctx.outputs[o],
                    inverted: out_tag.inverted ^ slice.inverted,
                    t0: t,
                    dur,
                    anims: slice.anims.clone(),
                });
                t += dur;
            }
        }
        Op::Animate(a) => {
            let super::rules::Animate {
                kind,
                world,
                offset,
                value,
                ease,
                grid,
                lookup,
                interp,
                orient,
            } = &**a;
            let delay = num(offset, env)?;
            if delay < 0.0 {
                return Err(negative_offset(offset, delay));
            }
            // An offset that reaches the slice end leaves the change no time to play: it
            // would jump at the boundary (and exporters would have nothing to key), so it is
            // an error rather than a silent jump.
            if delay >= slice.dur {
                let mut e = EngineError::at(
                    rule.span,
                    format!(
                        "the offset of shape `{}` #{} is {delay} s, not shorter than its slice ({} s)",
                        env.shape.tag, env.shape.id, slice.dur
                    ),
                );
                e.notes.push(format!(
                    "the slice runs from {} s to {} s; write a smaller offset or split the slice differently",
                    slice.t0,
                    slice.t0 + slice.dur
                ));
                return Err(e);
            }
            let SharedSpec { specs, ease } = match &ctx.cache.spec {
                Some(shared) => shared.clone(),
                None => {
                    let ease = match ease {
                        None => Easing::Linear,
                        Some(e) => easing(e, env)?,
                    };
                    let options = Options {
                        grid,
                        lookup,
                        interp,
                        orient: *orient,
                    };
                    let specs = keyed_specs(ctx, kind, *world, value, &options, env)?;
                    let shared = SharedSpec { specs, ease };
                    if ctx.shareable {
                        ctx.cache.spec = Some(shared.clone());
                    }
                    shared
                }
            };
            if *kind == AnimType::Trim
                && let Some(id) = dashed_stroke(ctx.scene, env.shape)
            {
                return Err(EngineError::at(
                    value.span,
                    format!(
                        "element `{id}` of shape `{}` #{} has a dashed stroke, which a trim cannot compose with (exporters write a trim as the stroke's dash pattern); remove its `stroke-dasharray` or trim another shape",
                        env.shape.tag, env.shape.id
                    ),
                ));
            }
            let out_tag = &rule.outputs[0];
            let inverted = out_tag.inverted ^ slice.inverted;
            let parts = specs.len();
            // A rig only moves (it draws nothing to paint); a shape the rule takes only
            // through an ancestor that moves it (a Lottie parent or null) follows that
            // ancestor's motion, once, and takes only the paint.
            let shape = env.shape;
            let follows = shape.inherited > 0 && !rule.takes(shape.own_tags(), shape.rig);
            let keeps = |spec: &AnimSpec| match spec {
                AnimSpec::Motion { .. } | AnimSpec::Follow { .. } => !follows,
                _ => !shape.rig,
            };
            let insts = specs
                .iter()
                .enumerate()
                .filter(|(_, spec)| keeps(spec))
                .map(|(k, spec)| {
                    Arc::new(AnimInst {
                        step: ctx.step * MAX_KEYS + k,
                        spec: spec.clone(),
                        start: slice.t0,
                        end: slice.t0 + slice.dur,
                        delay,
                        ease: ease.clone(),
                        reversed: inverted,
                        part: (k as f64 / parts as f64, (k + 1) as f64 / parts as f64),
                    })
                });
            out.push(Slice {
                tag: ctx.outputs[0],
                inverted,
                t0: slice.t0,
                dur: slice.dur,
                anims: slice.anims.iter().cloned().chain(insts).collect(),
            });
        }
    }
    Ok(())
}

/// The id (or `<path>`) of the first path of `shape`'s unit whose stroke has a dash
/// pattern, if any.
fn dashed_stroke(scene: &Scene, shape: &Shape) -> Option<String> {
    fn find(node: &Node) -> Option<String> {
        match node {
            Node::Path(p) => p
                .stroke
                .as_ref()
                .filter(|s| s.dash.as_ref().is_some_and(|d| !d.is_empty()))
                .map(|_| {
                    if p.id.is_empty() {
                        "<path>".to_string()
                    } else {
                        p.id.clone()
                    }
                }),
            Node::Group(g) => g.children.iter().find_map(find),
            Node::Image(_) => None,
        }
    }
    let (last, parents) = shape.node_path.split_last()?;
    let mut group = &scene.root;
    for &i in parents {
        match group.children.get(i)? {
            Node::Group(g) => group = g,
            Node::Path(_) | Node::Image(_) => return None,
        }
    }
    find(group.children.get(*last)?)
}

/// True when `e` names the keyframe variable `u`.
fn uses_u(e: &Expr) -> bool {
    mentions(e, &["u"])
}

/// True when `e` names one of the variables `names`.
fn mentions(e: &Expr, names: &[&str]) -> bool {
    match &e.kind {
        ExprKind::Ident(name) => names.contains(&name.as_str()),
        ExprKind::Call { args, .. } => args.iter().any(|a| mentions(&a.value, names)),
        ExprKind::Tuple(items) => items.iter().any(|x| mentions(x, names)),
        ExprKind::Neg(x) => mentions(x, names),
        ExprKind::Binary { lhs, rhs, .. } => mentions(lhs, names) || mentions(rhs, names),
        ExprKind::Num(_) | ExprKind::Str(_) | ExprKind::Color(_) | ExprKind::Size(..) => false,
    }
}

/// True when a rule's values name `k` or `count`, whose planning walks every shape.
pub(super) fn names_rank(rule: &CRule) -> bool {
    let names = &["k", "count"];
    match &rule.op {
        Op::Animate(a) => {
            mentions(&a.value, names)
                || mentions(&a.offset, names)
                || a.ease.as_ref().is_some_and(|e| mentions(e, names))
        }
        Op::Timesplit { fractions } => fractions.iter().any(|f| mentions(f, names)),
    }
}

/// The specs of an `animate` rule: one, or with an n×m×p grid (p > 2) whose value uses
/// `u`, one per keyframe interval. Keyframe k (of p) is the value at `u = k / (p − 1)`,
/// keyframe 0 the slice's start state; interval k carries the shape from keyframe k to
/// keyframe k + 1 (gMotion §3.1: a grid of transforms keyframed at p times, linear in
/// time between them). A value without `u` is the same at every keyframe, so it gives
/// the ordinary change whatever p is.
fn keyed_specs(
    ctx: &mut Ctx,
    kind: &AnimType,
    world: bool,
    value: &Expr,
    options: &Options,
    env: &mut ShapeEnv,
) -> Result<Arc<[AnimSpec]>, EngineError> {
    if *kind == AnimType::Morph {
        if uses_u(value) {
            return Err(EngineError::at(
                value.span,
                "a morph target cannot change with `u`: chain morphs on consecutive slices instead",
            ));
        }
        env.u = None;
        let shape = env.shape;
        let spec = super::morph::spec(ctx.scene, shape, world, value, env)?;
        return Ok(Arc::from([AnimSpec::Morph(Arc::new(spec))]));
    }
    let grid = options.grid;
    let (cols, rows, keys) = grid.unwrap_or(ctx.settings.grid);
    let motion = matches!(kind, AnimType::Affine | AnimType::Towards | AnimType::Path);
    if keys <= 2 && uses_u(value) {
        return Err(EngineError::at(
            value.span,
            "`u` is the keyframe of a grid with keyframes in time: give the rule `grid=1x1x5` (or the header `grid NxMxP`), P from 3 to 64",
        ));
    }
    if keys <= 2 || !uses_u(value) {
        env.u = None;
        let field = spec(kind, value, env, ctx.scene)?;
        return Ok(Arc::from([finish(
            ctx,
            field,
            world,
            (cols, rows),
            options,
        )]));
    }
    if !motion {
        return Err(EngineError::at(
            value.span,
            "`u` (keyframes in time) is for motions: `affine`, `towards` and `path`",
        ));
    }
    let mut fields = Vec::with_capacity(keys - 1);
    for k in 1..keys {
        env.u = Some(k as f64 / (keys - 1) as f64);
        fields.push(spec(kind, value, env, ctx.scene)?);
    }
    env.u = None;
    let mut specs = Vec::with_capacity(keys - 1);
    let mut before: Option<&Keyed> = None;
    for field in &fields {
        let step = match (before, field) {
            (None, f) => f.clone(),
            (Some(Keyed::Field(Field::Constant(a), pa)), Keyed::Field(Field::Constant(b), pb)) => {
                interval(a, *pa, b, *pb)
            }
            (Some(Keyed::Field(Field::Towards(p), _)), Keyed::Field(Field::Towards(q), _)) => {
                Keyed::Field(
                    Field::Constant(Arc::from([Component::Translate(*q - *p)])),
                    Vec2::ZERO,
                )
            }
            _ => {
                return Err(EngineError::at(
                    value.span,
                    "a `path` value cannot change with `u`; use `towards` with a point that does",
                ));
            }
        };
        specs.push(finish(ctx, step, world, (cols, rows), options));
        before = Some(field);
    }
    Ok(specs.into())
}

/// A motion field with the pivot it turns about, a path to travel, or an attribute change.
#[derive(Clone)]
enum Keyed {
    Field(Field, Vec2),
    Route(Arc<crate::motion::follow::Route>),
    Attribute(AnimSpec),
}

/// An `animate` rule's named options.
#[derive(Clone, Copy)]
struct Options<'a> {
    grid: &'a Option<(usize, usize, usize)>,
    lookup: &'a Option<Lookup>,
    interp: &'a Option<Interp>,
    orient: bool,
}

/// The change from keyframe `a` (about pivot `pa`) to keyframe `b` (about `pb`): `b · a⁻¹`,
/// component by component where the two are one component of the same kind about the same
/// pivot (so a turn stays a turn and exporters keep clean channels).
fn interval(a: &[Component], pa: Vec2, b: &[Component], pb: Vec2) -> Keyed {
    use Component::{Rotate, Scale, Skew, Translate};
    if pa == pb {
        let same = match (a, b) {
            ([Translate(x)], [Translate(y)]) => Some(Translate(*y - *x)),
            ([Rotate(x)], [Rotate(y)]) => Some(Rotate(y - x)),
            ([Scale(x)], [Scale(y)]) if x.x != 0.0 && x.y != 0.0 => {
                Some(Scale(Vec2::new(y.x / x.x, y.y / x.y)))
            }
            ([Skew(x0, 0.0)], [Skew(y0, 0.0)]) => Some(Skew(y0 - x0, 0.0)),
            _ => None,
        };
        if let Some(c) = same {
            return Keyed::Field(Field::Constant(Arc::from([c])), pa);
        }
    }
    // `a⁻¹` as inverted components in reverse order, so each plays by its own parameters
    // (a turn undoes as a turn, not as a matrix blend that shrinks on the way).
    let inverse = a.iter().rev().map(|c| match *c {
        Translate(d) => Translate(-d),
        Rotate(r) => Rotate(-r),
        Scale(k) if k.x != 0.0 && k.y != 0.0 => Scale(Vec2::new(1.0 / k.x, 1.0 / k.y)),
        Skew(x, 0.0) => Skew(-x, 0.0),
        Skew(0.0, y) => Skew(0.0, -y),
        other => Component::Matrix(crate::motion::component::product_at(&[other], 1.0).inverse()),
    });
    if pa == pb {
        let cs: Vec<Component> = b.iter().copied().chain(inverse).collect();
        return Keyed::Field(Field::Constant(cs.into()), pa);
    }
    let mut cs: Vec<Component> = vec![Translate(pb)];
    cs.extend_from_slice(b);
    cs.extend([Translate(-pb), Translate(pa)]);
    cs.extend(inverse);
    cs.push(Translate(-pa));
    Keyed::Field(Field::Constant(cs.into()), Vec2::ZERO)
}

/// A spec from a keyed field: the grid built (shared between shapes of the step).
fn finish(
    ctx: &mut Ctx,
    keyed: Keyed,
    world: bool,
    (cols, rows): (usize, usize),
    options: &Options,
) -> AnimSpec {
    let Options {
        lookup,
        interp,
        orient,
        ..
    } = *options;
    match keyed {
        Keyed::Attribute(spec) => spec,
        Keyed::Route(route) => AnimSpec::Follow {
            route,
            world,
            orient,
        },
        Keyed::Field(field, pivot_offset) => AnimSpec::Motion {
            grid: ctx.cache.grids.get(cols, rows, ctx.scene.canvas(), field),
            world,
            pivot_offset,
            lookup: lookup.unwrap_or(ctx.settings.lookup),
            interp: interp.unwrap_or(ctx.settings.interp),
        },
    }
}

/// Evaluates an `animate` rule's value (at the keyframe `env.u`, if any) into what it
/// animates: a motion field with its pivot, or an attribute change.
fn spec(
    kind: &AnimType,
    value: &Expr,
    env: &mut dyn Env,
    scene: &Scene,
) -> Result<Keyed, EngineError> {
    // A trim's 3-tuple is no value of its own: its numbers are read one by one.
    let v = match kind {
        AnimType::Trim => Value::Num(0.0),
        _ => eval(value, env)?,
    };
    let bad = |m: crate::grammar::value::TypeError| EngineError::from(m.at(value.span));
    let spec = match kind {
        AnimType::Affine | AnimType::Towards | AnimType::Path => {
            let mut pivot_offset = Vec2::ZERO;
            let field = match kind {
                AnimType::Affine => {
                    let cs: Vec<Component> = v.as_transform().map_err(bad)?.to_vec();
                    if let Some(c) = cs.iter().find(|c| !c.is_finite()) {
                        return Err(EngineError::at(
                            value.span,
                            format!("transform has a non-finite parameter: {c:?}"),
                        ));
                    }
                    let (cs, offset) = split_conjugation(cs);
                    pivot_offset = offset;
                    Field::Constant(cs.into())
                }
                AnimType::Towards => {
                    let p: Point = v.as_point().map_err(bad)?;
                    Field::Towards(p)
                }
                _ => {
                    let d = v.as_str().map_err(bad)?.to_string();
                    let path = BezPath::from_svg(&d).map_err(|e| {
                        EngineError::at(value.span, format!("invalid SVG path data: {e}"))
                    })?;
                    if path.elements().is_empty() {
                        return Err(EngineError::at(value.span, "the path is empty"));
                    }
                    Field::Path(Arc::new(path))
                }
            };
            return Ok(Keyed::Field(field, pivot_offset));
        }
        AnimType::Follow => return Ok(Keyed::Route(super::follow::route(scene, value, &v)?)),
        AnimType::Fill => AnimSpec::Fill(v.as_color().map_err(bad)?),
        AnimType::Border => AnimSpec::Border(v.as_color().map_err(bad)?),
        AnimType::Opacity => {
            let x = v.as_num().map_err(bad)?;
            if !(0.0..=1.0).contains(&x) {
                return Err(EngineError::at(
                    value.span,
                    format!("opacity lies in [0, 1], found {x}"),
                ));
            }
            AnimSpec::Opacity(x)
        }
        // `keyed_specs` resolves a morph with its shape's paths before reading a value.
        AnimType::Morph => {
            return Err(EngineError::at(
                value.span,
                "a morph target is resolved with the shape it morphs",
            ));
        }
        AnimType::StrokeWidth => {
            let x = v.as_num().map_err(bad)?;
            if !(x.is_finite() && x >= 0.0) {
                return Err(EngineError::at(
                    value.span,
                    format!("stroke width must be ≥ 0, found {x}"),
                ));
            }
            AnimSpec::StrokeWidth(x)
        }
        AnimType::Trim => AnimSpec::Trim(trim_value(value, env)?),
    };
    Ok(Keyed::Attribute(spec))
}

/// A trim's `(START, END[, SHIFT])`, each number checked where it is written: `START` and
/// `END` in `0..=1` with `START ≤ END`, `SHIFT` any number of turns.
fn trim_value(value: &Expr, env: &mut dyn Env) -> Result<Trim, EngineError> {
    let ExprKind::Tuple(items) = &value.kind else {
        return Err(EngineError::at(
            value.span,
            "a trim is `(start, end)` or `(start, end, shift)`: fractions of the path's length and a shift in turns",
        ));
    };
    if !(2..=3).contains(&items.len()) {
        return Err(EngineError::at(
            value.span,
            format!(
                "a trim is `(start, end)` or `(start, end, shift)`, found {} numbers",
                items.len()
            ),
        ));
    }
    let mut nums = [0.0; 3];
    for (k, item) in items.iter().enumerate() {
        let x = eval(item, env)?
            .as_num()
            .map_err(|m| EngineError::from(m.at(item.span)))?;
        if k < 2 && !(0.0..=1.0).contains(&x) {
            let which = if k == 0 { "start" } else { "end" };
            return Err(EngineError::at(
                item.span,
                format!(
                    "the trim's {which} is a fraction of the path's length in [0, 1], found {x}"
                ),
            ));
        }
        nums[k] = x;
    }
    if nums[0] > nums[1] {
        return Err(EngineError::at(
            items[0].span,
            format!(
                "the trim's start {} is past its end {}: write `(start, end)` with start ≤ end (an inverted slice plays it backwards)",
                nums[0], nums[1]
            ),
        ));
    }
    Ok(Trim {
        start: nums[0],
        end: nums[1],
        shift: nums[2],
    })
}

/// Splits `translate(c) … translate(-c)` into the middle and the pivot `c`, so a transform
/// about a point (`rotate(a, cx, cy)`, `scale(s) ` written around a centre) keeps its pivot
/// fixed while it plays instead of interpolating the two translations.
fn split_conjugation(cs: Vec<Component>) -> (Vec<Component>, Vec2) {
    if let [
        Component::Translate(a),
        middle @ ..,
        Component::Translate(b),
    ] = cs.as_slice()
        && !middle.is_empty()
        && (*a + *b).hypot() <= 1e-9 * (1.0 + a.hypot())
    {
        return (middle.to_vec(), *a);
    }
    (cs, Vec2::ZERO)
}

/// An easing from `ease = name` or `ease = name(args…)`.
fn easing(e: &Expr, env: &mut dyn Env) -> Result<Easing, EngineError> {
    let v = eval(e, env)?;
    let (name, args) = match v {
        Value::Keyword(k) => (k, Vec::new()),
        Value::Call { name, args } => {
            let mut nums = Vec::with_capacity(args.len());
            for a in args {
                nums.push(
                    a.as_num()
                        .map_err(|m| EngineError::at(e.span, m.to_string()))?,
                );
            }
            (name, nums)
        }
        _ => {
            return Err(EngineError::at(
                e.span,
                "an easing is a name such as `ease-in-out` or a call such as `cubic(0.4, 0, 0.2, 1)`",
            ));
        }
    };
    // A bad number (`steps(0)`) is located at the argument, a bad name at the whole call.
    let at = match &e.kind {
        ExprKind::Call { args, .. }
            if Easing::NAMES.contains(&name.as_str()) && args.len() == 1 =>
        {
            args[0].span
        }
        _ => e.span,
    };
    Easing::from_call(&name, &args)
        .map_err(|m| EngineError::at(at, m.to_string()).suggesting(Some(&name), Easing::NAMES))
}
