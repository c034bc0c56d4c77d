//! Timeslice expansion (gMotion sec. 3.4/3.6): every shape starts with one slice tagged
//! `all` covering the whole duration; each step picks the non-terminal slices with the
//! lowest slice tag (tags numbered by first creation, so expansion is breadth-first) on the
//! shapes with the lowest shape tag (lexicographic), together with their `inv_` twins,
//! chooses one rule among the highest-priority matches and applies it to all of them.

use std::collections::{BTreeSet, HashMap};
use std::sync::Arc;

use kurbo::{BezPath, Point, Vec2};
use rayon::prelude::*;

use crate::color::Color;
use crate::grammar::ast::{Expr, ExprKind, TagRef};
use crate::grammar::value::{Env, Value, eval};
use crate::motion::{Component, Field, Grid, Interp, Lookup};
use crate::scene::{Scene, Shape};
use crate::signals::Easing;

use super::EngineError;
use super::random::{hash_str, key, noise2, unit};
use super::rules::{AnimType, CRule, Op, Program};
use super::settings::{Choice, Settings};

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
}

/// One application of `animate` to one slice of one shape.
#[derive(Clone, Debug)]
pub struct AnimInst {
    /// Expansion step that set it (shared by a slice and its `inv_` twin).
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
    "id", "n", "cx", "cy", "w", "h", "x0", "y0", "z", "group", "t0", "d", "step", "W", "H",
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
    canvas: (f64, f64),
    t0: f64,
    d: f64,
    step: usize,
    seed: u64,
    draws: u64,
}

impl Env for ShapeEnv<'_> {
    fn var(&self, name: &str) -> Option<f64> {
        let s = self.shape;
        Some(match name {
            "id" => s.id as f64,
            "n" => self.n as f64,
            "cx" => s.centroid.x,
            "cy" => s.centroid.y,
            "w" => s.bbox.width(),
            "h" => s.bbox.height(),
            "x0" => s.bbox.x0,
            "y0" => s.bbox.y0,
            "z" => s.z as f64,
            "group" => s.group as f64,
            "t0" => self.t0,
            "d" => self.d,
            "step" => self.step as f64,
            "W" => self.canvas.0,
            "H" => self.canvas.1,
            _ => return None,
        })
    }

    fn rand(&mut self) -> f64 {
        self.draws += 1;
        unit(key(&[
            self.seed,
            hash_str(&self.shape.tag),
            self.shape.id as u64,
            self.step as u64,
            self.draws,
        ]))
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

/// Slice tag registry: ids in order of first creation.
struct Tags {
    names: Vec<String>,
    ids: HashMap<String, u32>,
    /// Ids of each rule's outputs once looked up, by rule position and output index, so the
    /// per-shape loop does not hash tag names. Looked up lazily, so ids are still numbered
    /// in order of first creation.
    outputs: Vec<Vec<Option<u32>>>,
}

impl Tags {
    fn id(&mut self, name: &str) -> u32 {
        if let Some(&i) = self.ids.get(name) {
            return i;
        }
        let i = self.names.len() as u32;
        self.names.push(name.to_string());
        self.ids.insert(name.to_string(), i);
        i
    }

    /// The id of output `j` of rule `rule` (its position in the program).
    fn output(&mut self, rule: &CRule, pos: usize, j: usize) -> u32 {
        if let Some(id) = self.outputs[pos][j] {
            return id;
        }
        let id = self.id(&rule.outputs[j].name);
        self.outputs[pos][j] = Some(id);
        id
    }
}

/// Caches which rules match a (slice tag, shape tag) pair, in a table indexed by both ids.
struct Matcher<'a> {
    program: &'a Program,
    shape_tags: usize,
    cache: Vec<Option<Arc<[usize]>>>,
}

impl Matcher<'_> {
    fn get(
        &mut self,
        slice_tag: u32,
        shape_tag: u32,
        tags: &Tags,
        shape_tags: &[String],
    ) -> &Arc<[usize]> {
        let i = slice_tag as usize * self.shape_tags + shape_tag as usize;
        if self.cache.len() <= i {
            self.cache.resize(i + 1, None);
        }
        let program = self.program;
        self.cache[i].get_or_insert_with(|| {
            program
                .candidates(
                    &tags.names[slice_tag as usize],
                    &shape_tags[shape_tag as usize],
                )
                .into()
        })
    }
}

fn pick(program: &Program, cands: &[usize], r: f64) -> usize {
    let total: f64 = cands.iter().map(|&i| program.rules[i].weight).sum();
    let mut x = r * total;
    for &i in cands {
        x -= program.rules[i].weight;
        if x < 0.0 {
            return i;
        }
    }
    *cands.last().expect("candidates are never empty")
}

/// Steps on at least this many shapes run in parallel; below, handing work to other
/// threads costs more than it saves.
pub const PARALLEL_SHAPES: usize = 256;

/// Expands every timeline.
pub fn expand(
    scene: &Scene,
    program: &Program,
    settings: &Settings,
) -> Result<Expansion, EngineError> {
    let mut shape_tag_names: Vec<String> = scene.shapes.iter().map(|s| s.tag.clone()).collect();
    shape_tag_names.sort();
    shape_tag_names.dedup();
    let shape_tag_of: Vec<u32> = scene
        .shapes
        .iter()
        .map(|s| shape_tag_names.binary_search(&s.tag).expect("tag listed") as u32)
        .collect();
    let mut shapes_by_tag: Vec<Vec<usize>> = vec![Vec::new(); shape_tag_names.len()];
    for (i, &t) in shape_tag_of.iter().enumerate() {
        shapes_by_tag[t as usize].push(i);
    }

    let mut tags = Tags {
        names: Vec::new(),
        ids: HashMap::new(),
        outputs: program
            .rules
            .iter()
            .map(|r| vec![None; r.outputs.len()])
            .collect(),
    };
    let all = tags.id("all");
    let mut matcher = Matcher {
        program,
        shape_tags: shape_tag_names.len(),
        cache: Vec::new(),
    };
    let no_anims: Arc<[Arc<AnimInst>]> = Arc::from([]);
    let mut timelines: Vec<Vec<Slice>> = scene
        .shapes
        .iter()
        .map(|_| {
            vec![Slice {
                tag: all,
                inverted: false,
                t0: 0.0,
                dur: settings.duration,
                anims: no_anims.clone(),
            }]
        })
        .collect();

    // Count of non-terminal slices per (shape tag, slice tag); the first key is the next step.
    let mut pending: BTreeSet<(u32, u32)> = BTreeSet::new();
    for st in 0..shapes_by_tag.len() {
        if !matcher
            .get(all, st as u32, &tags, &shape_tag_names)
            .is_empty()
        {
            pending.insert((st as u32, all));
        }
    }

    let mut rule_uses = vec![0; program.rules.iter().map(|r| r.index + 1).max().unwrap_or(0)];
    let mut history: Vec<usize> = Vec::new();
    let mut steps = 0;
    // Whether each rule's arguments are the same for every shape (by rule position).
    let shareable: Vec<bool> = program.rules.iter().map(spec_is_shareable).collect();
    let mut created: Vec<u32> = Vec::new();
    while let Some((shape_tag, slice_tag)) = pending.pop_first() {
        if steps >= settings.max_steps {
            return Err(cycle_error(program, &history, settings.max_steps));
        }
        let cands = matcher
            .get(slice_tag, shape_tag, &tags, &shape_tag_names)
            .clone();
        let step_rule = pick(
            program,
            &cands,
            unit(key(&[settings.seed, 0x5EED, steps as u64])),
        );
        let shapes = &shapes_by_tag[shape_tag as usize];
        let job = Step {
            scene,
            program,
            settings,
            shareable: &shareable,
            cands: &cands,
            step_rule,
            slice_tag,
            step: steps,
            n: shapes.len(),
        };
        let taken: Vec<(usize, Vec<Slice>)> = shapes
            .iter()
            .map(|&si| (si, std::mem::take(&mut timelines[si])))
            .collect();
        // Shapes expand independently; a large step runs in parallel with a cache per
        // worker. New slices carry unresolved tags, resolved below in shape order so tag
        // ids are numbered by first creation whatever the thread count.
        let results: Vec<(usize, ShapeResult)> = if shapes.len() >= PARALLEL_SHAPES {
            taken
                .into_par_iter()
                .map_init(StepCache::new, |cache, (si, old)| {
                    (si, job.shape(si, old, cache))
                })
                .collect()
        } else {
            let mut cache = StepCache::new();
            taken
                .into_iter()
                .map(|(si, old)| (si, job.shape(si, old, &mut cache)))
                .collect()
        };
        let mut applied = Vec::new();
        created.clear();
        for (si, result) in results {
            let (mut timeline, rule_i) = result?;
            let rule = &program.rules[rule_i];
            for s in timeline.iter_mut() {
                if let Some(o) = output_index(s.tag) {
                    s.tag = tags.output(rule, rule_i, o);
                    if !created.contains(&s.tag) {
                        created.push(s.tag);
                    }
                }
            }
            timelines[si] = timeline;
            if !applied.contains(&rule_i) {
                applied.push(rule_i);
            }
        }
        for &tag in &created {
            if !matcher
                .get(tag, shape_tag, &tags, &shape_tag_names)
                .is_empty()
            {
                pending.insert((shape_tag, tag));
            }
        }
        for r in applied {
            rule_uses[program.rules[r].index] += 1;
            history.push(r);
        }
        steps += 1;
    }
    Ok(Expansion {
        timelines,
        slice_tags: tags.names,
        steps,
        rule_uses,
    })
}

/// The shortest repeating tail of the rule history, named, as the error for a grammar that
/// does not terminate.
fn cycle_error(program: &Program, history: &[usize], max: usize) -> EngineError {
    let tail = &history[history.len().saturating_sub(64)..];
    let period = (1..=tail.len() / 2)
        .find(|&p| tail.windows(p + 1).all(|w| w[0] == w[p]))
        .unwrap_or(tail.len().min(8));
    let mut cycle: Vec<usize> = tail[tail.len() - period..].to_vec();
    cycle.dedup();
    let first = cycle.first().map(|&r| program.rules[r].span);
    let mut e = EngineError {
        span: first,
        message: format!(
            "the grammar did not terminate within {max} expansion steps (raise `max_steps` or --max-steps if it is just large); these rules keep rewriting each other's output"
        ),
        notes: Vec::new(),
    };
    for r in cycle {
        let rule = &program.rules[r];
        let outs: Vec<_> = rule.outputs.iter().map(tag_text).collect();
        e.notes.push(format!(
            "line {}: {} : [{}, {}] -> [{}]",
            rule.span.line,
            op_name(&rule.op),
            rule.slice_tags.join("|"),
            rule.shape_tags.join("|"),
            outs.join(", ")
        ));
    }
    e
}

fn op_name(op: &Op) -> &'static str {
    match op {
        Op::Timesplit { .. } => "timesplit",
        Op::Animate(_) => "animate",
    }
}

fn tag_text(t: &TagRef) -> String {
    if t.inverted {
        format!("inv_{}", t.name)
    } else {
        t.name.clone()
    }
}

fn num(e: &Expr, env: &mut ShapeEnv) -> Result<f64, EngineError> {
    let v = eval(e, env)?;
    let x = v
        .as_num()
        .map_err(|m| EngineError::at(e.span, m.to_string()))?;
    if !x.is_finite() {
        return Err(EngineError::at(
            e.span,
            format!("value is not a finite number ({x})"),
        ));
    }
    Ok(x)
}

fn shape_note(shape: &Shape) -> String {
    format!("for shape `{}` #{}", shape.tag, shape.id)
}

/// Slice tags of new slices before their ids are assigned: output `o` of the shape's rule.
const UNRESOLVED: u32 = u32::MAX - 4096;

fn unresolved(o: usize) -> u32 {
    UNRESOLVED + o as u32
}

fn output_index(tag: u32) -> Option<usize> {
    (tag >= UNRESOLVED).then(|| (tag - UNRESOLVED) as usize)
}

/// A shape's timeline after a step, with the rule it used.
type ShapeResult = Result<(Vec<Slice>, usize), EngineError>;

/// What one expansion step applies to every shape of its shape tag.
struct Step<'a> {
    scene: &'a Scene,
    program: &'a Program,
    settings: &'a Settings,
    shareable: &'a [bool],
    cands: &'a [usize],
    /// The rule chosen for the step (every shape uses it unless `choice shape`).
    step_rule: usize,
    slice_tag: u32,
    step: usize,
    /// Shapes with this shape tag.
    n: usize,
}

/// Values a worker keeps for the shapes of one step.
struct StepCache {
    grids: GridCache,
    /// Shared specs, by rule position.
    specs: Vec<Option<SharedSpec>>,
    /// Shared split fractions, by rule position.
    splits: Vec<Option<Arc<[f64]>>>,
}

impl StepCache {
    fn new() -> StepCache {
        StepCache {
            grids: GridCache::default(),
            specs: Vec::new(),
            splits: Vec::new(),
        }
    }
}

impl Step<'_> {
    /// Shape `si`'s timeline after the step, with the rule it used; new slices carry
    /// [`unresolved`] tags.
    fn shape(&self, si: usize, old: Vec<Slice>, cache: &mut StepCache) -> ShapeResult {
        let (program, settings) = (self.program, self.settings);
        let rules = program.rules.len();
        cache.specs.resize(rules, None);
        cache.splits.resize(rules, None);
        let shape = &self.scene.shapes[si];
        let rule_i = match settings.choice {
            Choice::Group => self.step_rule,
            Choice::Shape => pick(
                program,
                self.cands,
                unit(key(&[
                    settings.seed,
                    0x5EED,
                    self.step as u64,
                    hash_str(&shape.tag),
                    shape.id as u64,
                ])),
            ),
        };
        let rule = &program.rules[rule_i];
        let mut new = Vec::with_capacity(old.len() + rule.outputs.len());
        for slice in old {
            if slice.tag != self.slice_tag {
                new.push(slice);
                continue;
            }
            let mut env = ShapeEnv {
                shape,
                n: self.n,
                canvas: (self.scene.width, self.scene.height),
                t0: slice.t0,
                d: slice.dur,
                step: self.step,
                seed: settings.seed,
                draws: 0,
            };
            let mut ctx = Ctx {
                rule,
                pos: rule_i,
                grids: &mut cache.grids,
                specs: &mut cache.specs,
                splits: &mut cache.splits,
                shareable: self.shareable,
                settings,
                scene: self.scene,
                step: self.step,
            };
            apply(&mut ctx, &slice, &mut env, &mut new)?;
        }
        Ok((new, rule_i))
    }
}

/// An `animate` rule's resolved spec and easing, shared by every shape of a step when its
/// value and easing do not depend on the shape.
#[derive(Clone)]
struct SharedSpec {
    spec: AnimSpec,
    ease: Easing,
}

/// What applying a rule to one slice needs besides the slice and the shape.
struct Ctx<'a> {
    rule: &'a CRule,
    /// The rule's position in the program.
    pos: usize,
    grids: &'a mut GridCache,
    /// Shared specs of this step, by rule position.
    specs: &'a mut [Option<SharedSpec>],
    /// Shared split fractions of this step, by rule position.
    splits: &'a mut [Option<Arc<[f64]>>],
    /// Whether each rule's spec can be shared, by rule position.
    shareable: &'a [bool],
    settings: &'a Settings,
    scene: &'a Scene,
    step: usize,
}

/// True when a rule's arguments (an `animate` rule's value and easing, a split's fractions)
/// are the same for every shape, so a step evaluates them once.
fn spec_is_shareable(rule: &CRule) -> bool {
    match &rule.op {
        Op::Animate(a) => {
            shape_independent(&a.value) && a.ease.as_ref().is_none_or(shape_independent)
        }
        Op::Timesplit { fractions } => fractions.iter().all(shape_independent),
    }
}

/// A split's fractions, checked: each positive, summing to 1.
fn fractions(rule: &CRule, fs: &[Expr], env: &mut ShapeEnv) -> Result<Arc<[f64]>, EngineError> {
    let mut cs = Vec::with_capacity(fs.len());
    for f in fs {
        let c = num(f, env)?;
        if c <= 0.0 {
            let mut e = EngineError::at(
                f.span,
                format!("split fractions must be greater than zero, found {c}"),
            );
            e.notes.push(shape_note(env.shape));
            return Err(e);
        }
        cs.push(c);
    }
    let sum: f64 = cs.iter().sum();
    if (sum - 1.0).abs() > 1e-6 {
        let mut e = EngineError::at(
            rule.span,
            format!("split fractions must sum to 1, they sum to {sum}"),
        );
        e.notes.push(shape_note(env.shape));
        return Err(e);
    }
    Ok(cs.into())
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
            let cs = match &ctx.splits[ctx.pos] {
                Some(cs) => cs.clone(),
                None => {
                    let cs = fractions(rule, fs, env)?;
                    if ctx.shareable[ctx.pos] {
                        ctx.splits[ctx.pos] = Some(cs.clone());
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
                    tag: unresolved(o),
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
            } = &**a;
            let delay = num(offset, env)?;
            if delay < 0.0 {
                return Err(EngineError::at(
                    offset.span,
                    format!("the offset is a delay and cannot be negative, found {delay}"),
                ));
            }
            let SharedSpec { spec, ease } = match &ctx.specs[ctx.pos] {
                Some(shared) => shared.clone(),
                None => {
                    let ease = match ease {
                        None => Easing::Linear,
                        Some(e) => easing(e, env)?,
                    };
                    let spec = spec(ctx, kind, *world, value, grid, lookup, interp, env)?;
                    let shared = SharedSpec { spec, ease };
                    if ctx.shareable[ctx.pos] {
                        ctx.specs[ctx.pos] = Some(shared.clone());
                    }
                    shared
                }
            };
            let out_tag = &rule.outputs[0];
            let inverted = out_tag.inverted ^ slice.inverted;
            let inst = Arc::new(AnimInst {
                step: ctx.step,
                spec,
                start: slice.t0,
                end: slice.t0 + slice.dur,
                delay: delay.min(slice.dur),
                ease,
                reversed: inverted,
            });
            out.push(Slice {
                tag: unresolved(0),
                inverted,
                t0: slice.t0,
                dur: slice.dur,
                anims: slice.anims.iter().cloned().chain([inst]).collect(),
            });
        }
    }
    Ok(())
}

/// Evaluates an `animate` rule's value into what it animates.
#[allow(clippy::too_many_arguments)]
fn spec(
    ctx: &mut Ctx,
    kind: &AnimType,
    world: bool,
    value: &Expr,
    grid: &Option<(usize, usize)>,
    lookup: &Option<Lookup>,
    interp: &Option<Interp>,
    env: &mut ShapeEnv,
) -> Result<AnimSpec, EngineError> {
    let settings = ctx.settings;
    let v = eval(value, env)?;
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
            let (cols, rows) = grid.unwrap_or(settings.grid);
            AnimSpec::Motion {
                grid: ctx.grids.get(cols, rows, ctx.scene.canvas(), field),
                world,
                pivot_offset,
                lookup: lookup.unwrap_or(settings.lookup),
                interp: interp.unwrap_or(settings.interp),
            }
        }
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
    };
    Ok(spec)
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
fn easing(e: &Expr, env: &mut ShapeEnv) -> Result<Easing, EngineError> {
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
    Easing::from_call(&name, &args).map_err(|m| EngineError::at(e.span, m.to_string()))
}
