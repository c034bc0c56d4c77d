//! Planning an expansion on tags alone: which rule each step applies, to which slices, and
//! what the new slices are called.
//!
//! Everything sequential about expansion (gMotion sec. 3.4/3.6) is decided by tags: the
//! breadth-first order of steps, the random rule of each step, tag ids numbered by first
//! creation, the bound on steps. Values never feed back into it. And under `choice group`
//! every shape of a shape tag takes the same rule at every step, so all of them go through
//! the same sequence of slice tags; under `choice shape`, the shapes that drew the same
//! rules at every step do. Shapes with one such history form a *class*, and the plan steps
//! through classes instead of shapes, without evaluating a single expression. What is left
//! — each shape's values — is independent from shape to shape, so [`super::expand`] then
//! runs each shape's whole history at once, all shapes in parallel.
//!
//! Nothing a shape goes through depends on the rules of other shape tags: steps are ordered
//! per shape tag (slice tags by first creation *for that shape tag*), and the random rule
//! choice and the `rand()` stream of each step are keyed by the shape and the step's place
//! in the shape's own derivation, not by the global step number (see [`super::random`]).

use std::collections::{BTreeSet, HashMap};
use std::sync::Arc;

use crate::grammar::ast::TagRef;
use crate::scene::Scene;

use super::EngineError;
use super::random::{Place, hash_str};
use super::rules::{CRule, MatchKey, Op, Program};
use super::settings::{Choice, Settings};

/// One step as a class of shapes goes through it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Applied {
    /// The expansion step (global: unique, but shifted by rules of other shape tags).
    pub step: usize,
    /// How many steps rewrote this shape's timeline before this one: the `step` of
    /// expressions, which only the shape's own rules change.
    pub depth: usize,
    /// The shape-independent part of the key of this step's `rand()` draws (see
    /// [`super::random`]); each shape adds its id and the draw number.
    pub rand_key: u64,
    /// The slice tag it rewrites.
    pub slice_tag: u32,
    /// The rule, by position in the program.
    pub rule: usize,
    /// Number of the (step, rule) pair: values a step shares between its shapes are
    /// cached under it.
    pub key: usize,
}

/// Where each shape stands among the shapes one rule takes by its shape tags, in paint
/// order: `k` and `count` in the rule's values. Drawings and rigs are counted apart.
pub(super) struct Ranks {
    /// Per shape, its index among the taken shapes of its kind (`u32::MAX`: not taken).
    k: Vec<u32>,
    /// How many drawings, and how many rigs, the rule takes.
    count: [usize; 2],
}

impl Ranks {
    fn new(rule: &CRule, keys: &[MatchKey], key_of: &[u32], scene: &Scene) -> Ranks {
        let taken: Vec<bool> = keys
            .iter()
            .map(|key| rule.takes(key.tags.iter().map(String::as_str), key.rig))
            .collect();
        let mut count = [0; 2];
        let k = key_of
            .iter()
            .zip(&scene.shapes)
            .map(|(&key, s)| {
                if !taken[key as usize] {
                    return u32::MAX;
                }
                let c = &mut count[usize::from(s.rig)];
                *c += 1;
                (*c - 1) as u32
            })
            .collect();
        Ranks { k, count }
    }

    /// Shape `si`'s `(k, count)`, if the rule takes it.
    pub fn of(&self, si: usize, rig: bool) -> Option<(usize, usize)> {
        let k = *self.k.get(si)?;
        (k != u32::MAX).then(|| (k as usize, self.count[usize::from(rig)]))
    }
}

/// The outcome of planning.
pub(super) struct Plan {
    /// Each shape's class.
    pub class_of: Vec<u32>,
    /// Per class: the steps its shapes go through, in order.
    pub histories: Vec<Vec<Applied>>,
    /// Per class: how many slices its shapes end with (none split away, so also the most
    /// they have at any point).
    pub lens: Vec<usize>,
    /// Each shape's shape tag, and the number of shapes per shape tag (`n` in expressions).
    pub shape_tag_of: Vec<u32>,
    /// Drawings per shape tag.
    pub tag_sizes: Vec<usize>,
    /// Rigs per shape tag (the `n` of a rig).
    pub rig_sizes: Vec<usize>,
    /// Per rule position, for the rules whose values name `k` or `count`: where each
    /// shape stands among those the rule takes.
    pub ranks: Vec<Option<Ranks>>,
    /// Slice tag ids of each rule's outputs, by rule position and output.
    pub outputs: Vec<Vec<u32>>,
    /// Number of [`Applied::key`]s.
    pub keys: usize,
    /// Slice tag names by id (creation order; `all` is 0).
    pub slice_tags: Vec<String>,
    /// Steps taken.
    pub steps: usize,
    /// Uses per grammar rule index.
    pub rule_uses: Vec<usize>,
    /// Why planning stopped before expansion ended (too many steps or slices), if it did.
    /// The plan then holds the steps taken up to there, so an error in their values, which
    /// expanding step after step would have met first, can still be reported instead.
    pub unfinished: Option<EngineError>,
}

/// Most slices one shape's timeline may be cut into. A grammar that keeps splitting its
/// own output doubles the count every step and would exhaust memory long before
/// `max_steps`; no animation needs slices this short (10 000 in a 10 s timeline are a
/// millisecond each).
pub const MAX_SLICES_PER_SHAPE: usize = 10_000;

/// Most slices over all shapes (about 2 GB of timelines): bounds a grammar that splits
/// every shape of a large scene almost to [`MAX_SLICES_PER_SHAPE`].
pub const MAX_SLICES: usize = 1 << 25;

/// A class of shapes while planning: its slices' tags (with their `inv_` flag) in time
/// order, and the steps that made them.
#[derive(Clone, Default)]
struct Class {
    slices: Vec<(u32, bool)>,
    history: Vec<Applied>,
    /// How many steps have rewritten each slice tag (id, count) on these shapes: with the
    /// tag's name, the step's place in the shapes' own derivation.
    visits: Vec<(u32, u64)>,
}

impl Class {
    /// How many steps rewrote slice tag `tag` on this class before.
    fn visits(&self, tag: u32) -> u64 {
        self.visits.iter().find(|v| v.0 == tag).map_or(0, |v| v.1)
    }

    fn has(&self, tag: u32) -> bool {
        self.slices.iter().any(|&(t, _)| t == tag)
    }
}

/// Slice tag registry: ids in order of first creation.
struct Tags {
    names: Vec<String>,
    /// [`hash_str`] of each name, for random keys.
    hashes: Vec<u64>,
    ids: HashMap<String, u32>,
    /// Ids of each rule's outputs once looked up, by rule position and output index.
    /// Looked up lazily, so ids are still numbered in order of first creation.
    outputs: Vec<Vec<Option<u32>>>,
}

impl Tags {
    fn id(&mut self, name: &str) -> u32 {
        if let Some(&i) = self.ids.get(name) {
            return i;
        }
        let i = self.names.len() as u32;
        self.names.push(name.to_string());
        self.hashes.push(hash_str(name));
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

/// Caches which rules match a (slice tag, match key) pair, in a table indexed by both ids.
struct Matcher<'a> {
    program: &'a Program,
    /// Per match key, what rules can tell of its shapes.
    key_tags: &'a [MatchKey],
    cache: Vec<Option<Arc<[usize]>>>,
}

impl Matcher<'_> {
    fn get(&mut self, slice_tag: u32, key: u32, tags: &Tags) -> &Arc<[usize]> {
        let i = slice_tag as usize * self.key_tags.len() + key as usize;
        if self.cache.len() <= i {
            self.cache.resize(i + 1, None);
        }
        let (program, key_tags) = (self.program, self.key_tags);
        self.cache[i].get_or_insert_with(|| {
            program
                .candidates(&tags.names[slice_tag as usize], &key_tags[key as usize])
                .into()
        })
    }
}

/// The *match keys* of a scene's shapes: shapes that answer to the same tags as far as the
/// program can tell (the same shape tag, and the same aliases among those some rule names)
/// share one, and rules see nothing else of a shape. Without aliases that rules name, the
/// keys are the shape tags. Returns each key's tags and each shape's key.
fn match_keys(scene: &Scene, program: &Program) -> (Vec<MatchKey>, Vec<u32>) {
    let mut named: HashMap<&str, bool> = HashMap::new();
    let shape_keys: Vec<MatchKey> = scene
        .shapes
        .iter()
        .map(|s| {
            let mut tags = vec![s.tag.clone()];
            for a in &s.aliases {
                if *named
                    .entry(a.as_str())
                    .or_insert_with(|| program.names_shape_tag(a))
                {
                    tags.push(a.clone());
                }
            }
            MatchKey { rig: s.rig, tags }
        })
        .collect();
    // Sorted, so that without aliases the keys are the shape tags in the order steps have
    // always taken them.
    let mut key_tags = shape_keys.clone();
    key_tags.sort();
    key_tags.dedup();
    let key_of = shape_keys
        .iter()
        .map(|k| key_tags.binary_search(k).expect("key listed") as u32)
        .collect();
    (key_tags, key_of)
}

/// A rule among `cands` drawn by weight with `r` in [0, 1).
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

/// What one step rewrites: its slice tag and step number, and the keys of its draws.
struct StepAt {
    step: usize,
    slice_tag: u32,
    rand_key: u64,
}

/// Rewrites a class's slices as rule `pos` does at a step, naming the new slices (which
/// numbers tags met for the first time) and noting each new tag in `created` once.
fn rewrite(
    class: &mut Class,
    program: &Program,
    pos: usize,
    at: StepAt,
    key: usize,
    tags: &mut Tags,
    created: &mut Vec<u32>,
) {
    let rule = &program.rules[pos];
    let k = match &rule.op {
        Op::Timesplit { fractions } => fractions.len(),
        Op::Animate(_) => 1,
    };
    let mut slices = Vec::with_capacity(class.slices.len() + k - 1);
    for &(tag, inverted) in &class.slices {
        if tag != at.slice_tag {
            slices.push((tag, inverted));
            continue;
        }
        for j in 0..k {
            // On an inverted slice a split is mirrored: pieces in reverse, tags inverted.
            let o = if inverted { k - 1 - j } else { j };
            let id = tags.output(rule, pos, o);
            if !created.contains(&id) {
                created.push(id);
            }
            slices.push((id, rule.outputs[o].inverted ^ inverted));
        }
    }
    class.slices = slices;
    class.history.push(Applied {
        step: at.step,
        depth: class.history.len(),
        rand_key: at.rand_key,
        slice_tag: at.slice_tag,
        rule: pos,
        key,
    });
    match class.visits.iter_mut().find(|v| v.0 == at.slice_tag) {
        Some(v) => v.1 += 1,
        None => class.visits.push((at.slice_tag, 1)),
    }
}

impl Plan {
    /// Plans the expansion of every shape of `scene`. A grammar that does not terminate
    /// within `settings.max_steps` steps, or cuts timelines into more slices than
    /// [`MAX_SLICES_PER_SHAPE`] or [`MAX_SLICES`], stops early with
    /// [`Plan::unfinished`] set.
    pub fn new(scene: &Scene, program: &Program, settings: &Settings) -> Plan {
        let mut shape_tag_names: Vec<String> = scene.shapes.iter().map(|s| s.tag.clone()).collect();
        shape_tag_names.sort();
        shape_tag_names.dedup();
        let shape_tag_of: Vec<u32> = scene
            .shapes
            .iter()
            .map(|s| shape_tag_names.binary_search(&s.tag).expect("tag listed") as u32)
            .collect();
        // `n` counts drawings and rigs apart: a rig named like a layer is not one more.
        let mut tag_sizes = vec![0; shape_tag_names.len()];
        let mut rig_sizes = vec![0; shape_tag_names.len()];
        for (s, &t) in scene.shapes.iter().zip(&shape_tag_of) {
            match s.rig {
                false => tag_sizes[t as usize] += 1,
                true => rig_sizes[t as usize] += 1,
            }
        }
        // Steps go by match key: a key is a shape tag unless a rule names an alias.
        let (key_tags, key_of) = match_keys(scene, program);
        let ranks = program
            .rules
            .iter()
            .map(|r| super::expand::names_rank(r).then(|| Ranks::new(r, &key_tags, &key_of, scene)))
            .collect();
        let mut shapes_by_key: Vec<Vec<usize>> = vec![Vec::new(); key_tags.len()];
        for (i, &k) in key_of.iter().enumerate() {
            shapes_by_key[k as usize].push(i);
        }

        let mut tags = Tags {
            names: Vec::new(),
            hashes: Vec::new(),
            ids: HashMap::new(),
            outputs: program
                .rules
                .iter()
                .map(|r| vec![None; r.outputs.len()])
                .collect(),
        };
        let all = tags.id("all");
        // A key's random draws are keyed by its shape tag, and by the aliases that make it
        // a key of its own, so adding an alias no rule names changes no draw.
        let tag_hashes: Vec<u64> = key_tags
            .iter()
            .map(|k| hash_str(&k.tags.join("\0")))
            .collect();
        let mut matcher = Matcher {
            program,
            key_tags: &key_tags,
            cache: Vec::new(),
        };
        // Every shape starts as one slice `all`; class `k` holds the shapes of match key `k`.
        let mut classes: Vec<Class> = vec![
            Class {
                slices: vec![(all, false)],
                ..Class::default()
            };
            key_tags.len()
        ];
        let mut class_of = key_of.clone();

        // Per match key, its slice tags in order of first creation on its own shapes (`all`
        // first). Steps follow this order rather than the global ids, which a rule for
        // another shape tag can shift by creating a shared tag name first.
        let mut order: Vec<Vec<u32>> = vec![vec![all]; key_tags.len()];
        let mut rank: Vec<HashMap<u32, u32>> = vec![HashMap::from([(all, 0)]); key_tags.len()];
        // The (match key, slice tag rank) pairs with slices left to rewrite; the first is
        // next.
        let mut pending: BTreeSet<(u32, u32)> = BTreeSet::new();
        for st in 0..shapes_by_key.len() as u32 {
            if !matcher.get(all, st, &tags).is_empty() {
                pending.insert((st, 0));
            }
        }

        let mut rule_uses = vec![0; program.rules.iter().map(|r| r.index + 1).max().unwrap_or(0)];
        let mut history: Vec<usize> = Vec::new();
        let mut steps = 0;
        let mut keys = 0;
        let mut created: Vec<u32> = Vec::new();
        let mut total_slices = scene.shapes.len();
        let mut unfinished = None;
        // The most slices any class has.
        let mut longest = 1;
        while let Some((shape_tag, r)) = pending.pop_first() {
            if steps >= settings.max_steps {
                unfinished = Some(cycle_error(program, &history, settings.max_steps));
                break;
            }
            let st = shape_tag as usize;
            let slice_tag = order[st][r as usize];
            let cands = matcher.get(slice_tag, shape_tag, &tags).clone();
            // Where this step is in a class's own derivation, as random keys take it.
            let slice_hash = tags.hashes[slice_tag as usize];
            let place = |class: &Class| Place {
                seed: settings.seed,
                shape_tag: tag_hashes[st],
                slice_tag: slice_hash,
                visits: class.visits(slice_tag),
            };
            let at = |place: &Place| StepAt {
                step: steps,
                slice_tag,
                rand_key: place.draw_key(),
            };
            created.clear();
            // The rules applied, in the order shapes took them.
            let mut applied: Vec<usize> = Vec::new();
            match settings.choice {
                Choice::Group => {
                    let class = &mut classes[st];
                    let p = place(class);
                    let rule = pick(program, &cands, p.choice(None));
                    applied.push(rule);
                    let before = class.slices.len();
                    rewrite(class, program, rule, at(&p), keys, &mut tags, &mut created);
                    keys += 1;
                    let added = class.slices.len() - before;
                    total_slices += added * shapes_by_key[st].len();
                    longest = longest.max(class.slices.len());
                }
                Choice::Shape => {
                    // Each shape draws its rule; shapes of one class that draw the same
                    // rule form a new class, made when its first shape is met (so tags are
                    // numbered in shape order, as they are created).
                    // (old class, rule) → new class.
                    let mut split: HashMap<(u32, usize), u32> = HashMap::new();
                    let mut rule_keys: Vec<(usize, usize)> = Vec::new();
                    for &si in &shapes_by_key[st] {
                        let old = class_of[si];
                        if !classes[old as usize].has(slice_tag) {
                            continue;
                        }
                        let p = place(&classes[old as usize]);
                        let rule = pick(program, &cands, p.choice(Some(scene.shapes[si].id)));
                        if !applied.contains(&rule) {
                            applied.push(rule);
                        }
                        class_of[si] = match split.get(&(old, rule)) {
                            Some(&new) => new,
                            None => {
                                let key = match rule_keys.iter().find(|k| k.0 == rule) {
                                    Some(k) => k.1,
                                    None => {
                                        rule_keys.push((rule, keys));
                                        keys += 1;
                                        keys - 1
                                    }
                                };
                                let mut class = classes[old as usize].clone();
                                rewrite(
                                    &mut class,
                                    program,
                                    rule,
                                    at(&p),
                                    key,
                                    &mut tags,
                                    &mut created,
                                );
                                longest = longest.max(class.slices.len());
                                classes.push(class);
                                let new = classes.len() as u32 - 1;
                                split.insert((old, rule), new);
                                new
                            }
                        };
                        let new = class_of[si] as usize;
                        total_slices +=
                            classes[new].slices.len() - classes[old as usize].slices.len();
                    }
                    // No shape is left in a class that was split.
                    for (old, _) in split.into_keys() {
                        classes[old as usize] = Class::default();
                    }
                }
            }
            for &tag in &created {
                let next = order[st].len() as u32;
                let r = *rank[st].entry(tag).or_insert(next);
                if r == next {
                    order[st].push(tag);
                }
                if !matcher.get(tag, shape_tag, &tags).is_empty() {
                    pending.insert((shape_tag, r));
                }
            }
            for r in applied {
                rule_uses[program.rules[r].index] += 1;
                history.push(r);
            }
            steps += 1;
            if longest > MAX_SLICES_PER_SHAPE || total_slices > MAX_SLICES {
                unfinished = Some(slices_error(program, &history, longest, total_slices));
                break;
            }
        }
        let lens = classes.iter().map(|c| c.slices.len()).collect();
        Plan {
            class_of,
            histories: classes.into_iter().map(|c| c.history).collect(),
            lens,
            shape_tag_of,
            tag_sizes,
            rig_sizes,
            ranks,
            outputs: tags
                .outputs
                .into_iter()
                .map(|o| o.into_iter().map(|id| id.unwrap_or(u32::MAX)).collect())
                .collect(),
            keys,
            slice_tags: tags.names,
            steps,
            rule_uses,
            unfinished,
        }
    }
}

/// The error for a grammar that does not terminate, naming the rules it keeps applying.
fn cycle_error(program: &Program, history: &[usize], max: usize) -> EngineError {
    named_cycle(
        program,
        history,
        format!(
            "the grammar did not terminate within {max} expansion steps (raise `max_steps` or --max-steps if it is just large); these rules keep rewriting each other's output"
        ),
    )
}

/// The error for a grammar that cuts timelines into too many slices.
fn slices_error(program: &Program, history: &[usize], longest: usize, total: usize) -> EngineError {
    let what = if longest > MAX_SLICES_PER_SHAPE {
        format!("a shape's timeline into {longest} slices (at most {MAX_SLICES_PER_SHAPE})")
    } else {
        format!("the timelines into {total} slices in all (at most {MAX_SLICES})")
    };
    named_cycle(
        program,
        history,
        format!("the grammar cuts {what}; these rules keep splitting each other's output"),
    )
}

/// An error at the first of the rules in the shortest repeating tail of the rule history,
/// with a note naming each of them.
fn named_cycle(program: &Program, history: &[usize], message: String) -> EngineError {
    let tail = &history[history.len().saturating_sub(64)..];
    let period = (1..=tail.len() / 2)
        .find(|&p| tail.windows(p + 1).all(|w| w[0] == w[p]))
        .unwrap_or(tail.len().min(8));
    let mut cycle: Vec<usize> = tail[tail.len() - period..].to_vec();
    cycle.dedup();
    let first = cycle.first().map(|&r| program.rules[r].span);
    let mut e = EngineError {
        span: first,
        message,
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
