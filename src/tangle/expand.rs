//! Spatial expansion of a scene with group grammar rules (gTangle sec. 3).
//!
//! Every shape is ⟨t, g, s⟩: tag, group, id in group. One step takes the non-terminal
//! shapes with the lowest group id (breadth-first), picks one rule matching their tag
//! (highest priority, then by weight), and applies it to every one of them; each of the
//! rule's outputs becomes a new group, its shapes numbered in order. The pieces replace
//! their ancestor in the scene tree, keeping its paint, so timeslice rules can animate them
//! afterwards.
//!
//! Random decisions are keyed by where they happen in the derivation, not by the global
//! step or group id (which count every tag's steps and groups, so a rule for one tag would
//! re-roll all the others): every group has a stable key, made from the seed and the
//! imported group for the scene's groups, and from the key of the batch that made it and
//! its output slot for new ones. A batch (a group's shapes of one tag) keys its rule choice
//! on its group's key and its tag, and each shape's draws add the shape's id in the group.

use std::collections::{BTreeMap, HashMap};

use kurbo::{Affine, BezPath, Vec2};
use rayon::prelude::*;

use super::bind::{ShapeEnv, ShapeVars, bind};
use super::boolean::normalize;
use super::noise::{key, unit};
use super::ops::paint::Paint;
use super::ops::text::{self, Drawing};
use super::ops::{Context, Input, Op, Piece};
use super::polygon::{Grid, Region, flatten_rings};
use super::{TangleError, TangleOptions, TangleStats};
use crate::color::Color;
use crate::grammar::ast::Rule;
use crate::scene::{FillRule, Group, Node, PathNode, Scene, Shape};
use crate::text::TextPlace;
use crate::warning::Warning;

/// A shape during expansion.
#[derive(Clone, Debug)]
struct TShape {
    tag: String,
    /// The aliases of an imported shape that some spatial rule names (others cannot change
    /// what happens to it, and would only split its batch).
    aliases: Vec<String>,
    group: usize,
    sid: usize,
    region: Region,
    dir: Vec2,
    cell: (i64, i64),
    paint: Paint,
    /// Came from the scene (matches `all` rules).
    imported: bool,
    /// The stable key of its group (see the module documentation).
    group_key: u64,
    /// How many rules made it: 0 for imported shapes (the `step` of expressions).
    depth: usize,
    /// The drawing it keeps instead of its polygon (a text's glyphs, see [`text`]).
    drawing: Option<Drawing>,
    /// Its line and word in the text it came from (`line_id`, `word_id`).
    text: (usize, usize),
}

/// A piece and the drawing it keeps instead of its polygon, if any.
type Kept = (Piece, Option<Drawing>);

/// An operator bound for one shape, its pieces (or why it left the shape whole), and the
/// drawing each piece keeps, if any.
type Applied = (Op, Result<Vec<Piece>, String>, Vec<Option<Drawing>>);

/// The derivation tree: a shape, replaced by its pieces once a rule is applied.
struct Arena {
    shapes: Vec<Option<TShape>>,
    children: Vec<Vec<usize>>,
}

impl Arena {
    fn push(&mut self, s: TShape) -> usize {
        self.shapes.push(Some(s));
        self.children.push(Vec::new());
        self.shapes.len() - 1
    }

    /// The final shapes under `root`, in paint order. Walked with a stack of its own: a
    /// rule that keeps peeling one piece off the rest (rings by `outline`) makes the tree
    /// as deep as it has steps, deeper than a thread's stack would take recursively.
    fn leaves(&self, root: usize, out: &mut Vec<usize>) {
        let mut stack = vec![root];
        while let Some(n) = stack.pop() {
            if self.children[n].is_empty() {
                if self.shapes[n].is_some() {
                    out.push(n);
                }
            } else {
                // Reversed, so the first child is popped first.
                stack.extend(self.children[n].iter().rev());
            }
        }
    }
}

/// Domain words of the keys, so choices, draws and group keys never coincide.
const ROOT_GROUP: u64 = 0x7A46_0000_0000_0001;
const CHOICE: u64 = 0x7A46_0000_0000_0002;
const SLOT_GROUP: u64 = 0x7A46_0000_0000_0003;
const UNGROUPED: u64 = 0x7A46_0000_0000_0004;
const NOISE: u64 = 0x6709;

fn hash_str(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Every path under a node with its transform to the node's parent space, in paint order.
/// Images have no outline to split, so a unit's images are not among its pieces' region.
fn collect_paths<'a>(node: &'a Node, m: Affine, out: &mut Vec<(&'a PathNode, Affine)>) {
    match node {
        Node::Path(p) => out.push((p, m)),
        Node::Image(_) => {}
        Node::Group(g) => {
            for c in &g.children {
                collect_paths(c, m * g.transform, out);
            }
        }
    }
}

/// The filled region of a scene unit in canvas coordinates, and the paint its pieces get.
fn unit_geometry(
    scene: &Scene,
    shape: &Shape,
    grid: &Grid,
    tolerance: f64,
) -> Option<(Region, Paint)> {
    let node = scene.root.node_at(&shape.node_path)?;
    let mut paths = Vec::new();
    collect_paths(node, shape.parent_transform, &mut paths);
    let (first, _) = paths.first()?;
    let paint = Paint::of(first);
    let mut rings = Vec::new();
    let mut rule = FillRule::NonZero;
    for (p, m) in &paths {
        rule = p.fill.as_ref().map_or(rule, |f| f.rule);
        rings.extend(flatten_rings(&p.path, *m, tolerance, grid));
    }
    Some((normalize(&rings, rule, grid), paint))
}

/// The rules applicable to a shape with tags `tags`, best priority only.
fn candidates<'r>(rules: &[&'r Rule], tags: &[String], imported: bool) -> Vec<(usize, &'r Rule)> {
    let matching: Vec<(usize, &Rule)> = rules
        .iter()
        .enumerate()
        .filter(|(_, r)| r.spatial && r.takes_shape(tags.iter().map(String::as_str), imported))
        .map(|(i, r)| (i, *r))
        .collect();
    let Some(best) = matching.iter().map(|(_, r)| r.priority).max() else {
        return matching;
    };
    matching
        .into_iter()
        .filter(|(_, r)| r.priority == best)
        .collect()
}

/// One candidate by weight, from a uniform draw `u` in [0, 1).
fn choose<'r>(cands: &[(usize, &'r Rule)], u: f64) -> Option<(usize, &'r Rule)> {
    let total: f64 = cands.iter().map(|(_, r)| r.weight.max(0.0)).sum();
    if total.is_nan() || total <= 0.0 {
        return cands.first().copied();
    }
    let mut x = u * total;
    for &(i, r) in cands {
        x -= r.weight.max(0.0);
        if x < 0.0 {
            return Some((i, r));
        }
    }
    cands.last().copied()
}

/// The canvas-space transform of a unit's children (its parent's, times its own if it is
/// a group).
fn inner_transform(node: &Node, shape: &Shape) -> Affine {
    match node {
        Node::Group(g) => shape.parent_transform * g.transform,
        Node::Path(_) | Node::Image(_) => shape.parent_transform,
    }
}

/// Expands the scene's shapes with the spatial `rules` and returns the new scene (pieces
/// in place of the shapes they came from) with statistics.
///
/// Shapes whose tag no spatial rule consumes are kept as they are. Shapes with no area are
/// kept too, with a warning.
///
/// # Errors
/// A rule's argument that does not evaluate or does not fit its operator; more than
/// `max_steps` steps (naming the rules still rewriting) or `max_shapes` shapes; geometry
/// too large for the integer engine.
pub fn expand(
    scene: &Scene,
    rules: &[&Rule],
    opts: &TangleOptions,
) -> Result<(Scene, TangleStats), TangleError> {
    let spatial: Vec<&Rule> = rules.iter().copied().filter(|r| r.spatial).collect();
    // Whether some spatial rule takes a tag (`all` only imported shapes).
    let consumed = |tags: &[String], imported: bool| {
        spatial
            .iter()
            .any(|r| r.takes_shape(tags.iter().map(String::as_str), imported))
    };
    let mut stats = TangleStats {
        rule_uses: vec![0; spatial.len()],
        ..TangleStats::default()
    };
    let bounds = scene
        .shapes
        .iter()
        .fold(scene.canvas(), |r, s| r.union(s.bbox));
    let grid = Grid::for_bounds(bounds)
        .ok_or_else(|| TangleError::Geometry("the scene's coordinates are not finite".into()))?;
    let ctx = Context {
        grid,
        resolution: opts.resolution.max(grid.quantum() * 16.0),
        max_pieces: opts.max_shapes,
    };
    let tolerance = opts.tolerance.max(grid.quantum() * 4.0);

    let mut arena = Arena {
        shapes: Vec::new(),
        children: Vec::new(),
    };
    let mut roots: Vec<(usize, usize)> = Vec::new(); // (scene shape, arena node)
    let mut pending: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (u, shape) in scene.shapes.iter().enumerate() {
        let aliases: Vec<String> = (shape.aliases.iter())
            .filter(|a| spatial.iter().any(|r| r.names_shape_tag(a)))
            .cloned()
            .collect();
        let tags: Vec<String> = std::iter::once(shape.tag.clone())
            .chain(aliases.iter().cloned())
            .collect();
        if !consumed(&tags, true) {
            continue;
        }
        let Some((region, paint)) = unit_geometry(scene, shape, &grid, tolerance) else {
            continue;
        };
        if region.area() <= 0.0 {
            stats.warnings.push(Warning {
                span: None,
                subject: None,
                message: format!(
                    "shape `{}` #{} encloses no area; left as it is",
                    shape.tag, shape.id
                ),
            });
            continue;
        }
        if !region.edges().all(|(p, _)| grid.holds(p)) {
            return Err(TangleError::Geometry(format!(
                "shape `{}` #{} is too far from the origin",
                shape.tag, shape.id
            )));
        }
        let drawing = shape.text.layout.as_ref().and_then(|layout| {
            let node = scene.root.node_at(&shape.node_path)?;
            Some(Drawing::Glyphs {
                layout: layout.clone(),
                glyphs: (0..layout.glyphs.len()).collect(),
                to_canvas: inner_transform(node, shape),
            })
        });
        let node = arena.push(TShape {
            tag: shape.tag.clone(),
            aliases,
            group: shape.group,
            sid: shape.id,
            region,
            dir: Vec2::new(1.0, 0.0),
            cell: (shape.id as i64, 0),
            paint,
            imported: true,
            group_key: key(&[ROOT_GROUP, opts.seed, shape.group as u64]),
            depth: 0,
            drawing,
            text: (shape.text.line, shape.text.word),
        });
        roots.push((u, node));
        pending.entry(shape.group).or_default().push(node);
    }
    let mut next_group = scene.shapes.iter().map(|s| s.group + 1).max().unwrap_or(1);
    let mut live = roots.len();
    // Pieces made over all steps: the work done, which the `pieces` limit also bounds.
    let mut made = 0usize;
    let mut recent: Vec<usize> = Vec::new();
    // The time budget, checked before each step and before each shape a step cuts (one
    // step may cut thousands of shapes).
    let started = std::time::Instant::now();
    let over_time = |steps: usize, made: usize, recent: &[usize]| {
        let limit = opts.max_time?;
        (started.elapsed() > limit).then(|| {
            let mut rules = recent.to_vec();
            rules.sort_unstable();
            rules.dedup();
            TangleError::MaxTime {
                seconds: limit.as_secs(),
                steps,
                made,
                rules: rules
                    .iter()
                    .map(|&i| (spatial[i].op.clone(), spatial[i].span))
                    .collect(),
            }
        })
    };

    while let Some((_, nodes)) = pending.pop_first() {
        // One batch per tag, in order of first appearance (a group normally has one tag).
        // A batch's tags: the shapes' tag and the aliases rules name.
        let mut batches: Vec<(Vec<String>, bool, Vec<usize>)> = Vec::new();
        // All shapes of a group share its key and depth.
        let (group_key, depth) = {
            let s = arena.shapes[nodes[0]]
                .as_ref()
                .expect("pending shapes are unexpanded");
            (s.group_key, s.depth)
        };
        for n in nodes {
            let s = arena.shapes[n]
                .as_ref()
                .expect("pending shapes are unexpanded");
            match batches
                .iter_mut()
                .find(|(t, imp, _)| t[0] == s.tag && t[1..] == s.aliases[..] && *imp == s.imported)
            {
                Some(b) => b.2.push(n),
                None => {
                    let tags = std::iter::once(s.tag.clone())
                        .chain(s.aliases.iter().cloned())
                        .collect();
                    batches.push((tags, s.imported, vec![n]));
                }
            }
        }
        for (tags, imported, batch) in batches {
            let cands = candidates(&spatial, &tags, imported);
            let step = stats.steps;
            // Keyed by the tag alone unless rules name aliases, so unnamed ids change nothing.
            let batch_key = key(&[group_key, hash_str(&tags.join("\0")), imported as u64]);
            let Some((rule_index, rule)) = choose(&cands, unit(key(&[CHOICE, batch_key]))) else {
                continue;
            };
            if step >= opts.max_steps {
                recent.sort_unstable();
                recent.dedup();
                let names = recent
                    .iter()
                    .map(|&i| (spatial[i].op.clone(), spatial[i].span))
                    .collect();
                return Err(TangleError::MaxSteps {
                    steps: step,
                    rules: names,
                });
            }
            if let Some(e) = over_time(step, made, &recent) {
                return Err(e);
            }
            stats.steps += 1;
            stats.rule_uses[rule_index] += 1;
            if recent.len() >= 64 {
                recent.remove(0);
            }
            recent.push(rule_index);
            let steps = stats.steps;

            let n = batch.len();
            let noise_key = key(&[group_key, NOISE]);
            let results: Vec<Result<Applied, TangleError>> = batch
                .par_iter()
                .map(|&node| {
                    if let Some(e) = over_time(steps, made, &recent) {
                        return Err(e);
                    }
                    let s = arena.shapes[node]
                        .as_ref()
                        .expect("batch shapes are unexpanded");
                    let shape_key = key(&[batch_key, s.sid as u64]);
                    let vars = ShapeVars {
                        sid: s.sid,
                        n,
                        group: s.group,
                        centroid: s.region.centroid(),
                        bbox: s.region.bbox(),
                        canvas: (scene.width, scene.height),
                        step: depth,
                        text: s.text,
                    };
                    let mut env = ShapeEnv::new(vars, shape_key, opts.seed);
                    let op = bind(rule, &mut env)?;
                    let input = Input {
                        region: &s.region,
                        dir: s.dir,
                        paint: &s.paint,
                        cell: s.cell,
                        sid: s.sid,
                        key: shape_key,
                        group_key: noise_key,
                    };
                    if let Op::Text(split) = op {
                        let Some(Drawing::Glyphs {
                            layout,
                            glyphs,
                            to_canvas,
                        }) = &s.drawing
                        else {
                            // An imported text the importer could not lay out says why.
                            let uncut = scene
                                .shapes
                                .iter()
                                .filter(|_| s.imported)
                                .find(|x| x.tag == s.tag && x.id == s.sid)
                                .and_then(|x| x.text.uncut.as_deref());
                            let why = format!(
                                "`{}()`: shape `{}` #{} {}; left as it is",
                                split.name(),
                                s.tag,
                                s.sid,
                                uncut.unwrap_or("did not come from text")
                            );
                            return Ok((op, Err(why), Vec::new()));
                        };
                        let cut = text::cut(
                            split, layout, glyphs, *to_canvas, s.dir, &ctx.grid, tolerance,
                        );
                        let (pieces, drawings) = cut.into_iter().map(|(p, d)| (p, Some(d))).unzip();
                        return Ok((op, Ok(pieces), drawings));
                    }
                    let pieces = op.apply(input, &ctx);
                    // Grouping keeps the shape as it is, drawing and all.
                    let keeps = matches!(op, Op::Ungroup | Op::Regroup { .. });
                    let drawings = match &pieces {
                        Ok(p) if keeps => vec![s.drawing.clone(); p.len()],
                        Ok(p) => vec![None; p.len()],
                        Err(_) => Vec::new(),
                    };
                    Ok((op, pieces, drawings))
                })
                .collect();

            // New groups: one per output slot used, or one per shape for `ungroup`.
            // (0 or 1 + the shape's place in the batch for `ungroup`, slot) → (id, key).
            let mut slot_group: HashMap<(usize, usize), (usize, u64)> = HashMap::new();
            let mut next_sid: HashMap<usize, usize> = HashMap::new();
            let mut produced: Vec<(usize, Vec<Kept>)> = Vec::with_capacity(n);
            let mut ungroup = false;
            for (&node, result) in batch.iter().zip(results) {
                let (op, pieces, drawings) = result?;
                ungroup = op == Op::Ungroup;
                let pieces = match pieces {
                    Ok(p) => p.into_iter().zip(drawings).collect(),
                    Err(message) => {
                        stats
                            .warnings
                            .push(Warning::at(Some(rule.op_span), message));
                        let s = arena.shapes[node]
                            .as_ref()
                            .expect("batch shapes are unexpanded");
                        // A text operator passes a shape that is not text through as it
                        // was drawn; other operators leave its polygon.
                        let drawing = match op {
                            Op::Text(_) => {
                                s.drawing.clone().or(s.imported.then_some(Drawing::Whole))
                            }
                            _ => None,
                        };
                        vec![(
                            Piece {
                                region: s.region.clone(),
                                slot: 0,
                                cell: s.cell,
                                dir: s.dir,
                                paint: s.paint.clone(),
                            },
                            drawing,
                        )]
                    }
                };
                produced.push((node, pieces));
            }
            let mut slots: Vec<usize> = produced
                .iter()
                .flat_map(|(_, ps)| ps.iter().map(|(p, _)| p.slot))
                .collect();
            slots.sort_unstable();
            slots.dedup();
            if !ungroup {
                for &slot in &slots {
                    let k = key(&[SLOT_GROUP, batch_key, slot as u64]);
                    slot_group.insert((0, slot), (next_group, k));
                    next_group += 1;
                }
            }
            made += produced.iter().map(|(_, ps)| ps.len()).sum::<usize>();
            for (k, (node, pieces)) in produced.into_iter().enumerate() {
                let parent_text = arena.shapes[node].as_ref().map_or((0, 0), |s| s.text);
                arena.shapes[node] = None;
                live -= 1;
                // A shape that became one piece is replaced in its own node: the tree then
                // does not deepen (nor grow) by a node for every step of a rule that
                // rewrites its own output one piece at a time.
                let in_place = pieces.len() == 1;
                for (piece, drawing) in pieces {
                    if rule.outputs.is_empty() {
                        continue;
                    }
                    let (g, g_key) = if ungroup {
                        *slot_group.entry((k + 1, piece.slot)).or_insert_with(|| {
                            next_group += 1;
                            let gk = key(&[UNGROUPED, batch_key, k as u64, piece.slot as u64]);
                            (next_group - 1, gk)
                        })
                    } else {
                        slot_group[&(0, piece.slot)]
                    };
                    let sid = next_sid.entry(g).or_insert(0);
                    let tag = rule.outputs[piece.slot % rule.outputs.len()].name.clone();
                    let terminal = !consumed(std::slice::from_ref(&tag), false);
                    let shape = TShape {
                        tag,
                        aliases: Vec::new(),
                        group: g,
                        sid: *sid,
                        region: piece.region,
                        dir: piece.dir,
                        cell: piece.cell,
                        paint: piece.paint,
                        imported: false,
                        group_key: g_key,
                        depth: depth + 1,
                        text: drawing
                            .as_ref()
                            .and_then(Drawing::place)
                            .unwrap_or(parent_text),
                        drawing,
                    };
                    *sid += 1;
                    let child = if in_place {
                        arena.shapes[node] = Some(shape);
                        node
                    } else {
                        let child = arena.push(shape);
                        arena.children[node].push(child);
                        child
                    };
                    live += 1;
                    if !terminal {
                        pending.entry(g).or_default().push(child);
                    }
                }
            }
            if made > opts.max_work() {
                recent.sort_unstable();
                recent.dedup();
                return Err(TangleError::MaxWork {
                    made,
                    steps: stats.steps,
                    limit: opts.max_work(),
                    rules: recent
                        .iter()
                        .map(|&i| (spatial[i].op.clone(), spatial[i].span))
                        .collect(),
                });
            }
            if live > opts.max_shapes {
                return Err(TangleError::MaxShapes {
                    shapes: live,
                    limit: opts.max_shapes,
                });
            }
        }
    }
    stats.groups = next_group;
    let out = rebuild(scene, &arena, &roots, &mut stats);
    Ok((out, stats))
}

/// A tangle piece waiting for its place in the new shape list.
struct PieceShape {
    tag: String,
    group: usize,
    parent_transform: Affine,
    region: Region,
    paint: Paint,
    text: (usize, usize),
}

/// The scene with every expanded unit replaced by a group of its final pieces, and the
/// shape list rebuilt in paint order.
fn rebuild(
    scene: &Scene,
    arena: &Arena,
    roots: &[(usize, usize)],
    stats: &mut TangleStats,
) -> Scene {
    let mut out = scene.clone();
    let base = scene.shapes.len();
    let mut pieces: Vec<PieceShape> = Vec::new();
    for &(u, root) in roots {
        let shape = &scene.shapes[u];
        let Some(node) = scene.root.node_at(&shape.node_path) else {
            continue;
        };
        let to_canvas = inner_transform(node, shape);
        if to_canvas.determinant().abs() < 1e-12 {
            stats.warnings.push(Warning {
                span: None,
                subject: None,
                message: format!(
                    "shape `{}` #{} has a degenerate transform; left as it is",
                    shape.tag, shape.id
                ),
            });
            continue;
        }
        let back = to_canvas.inverse();
        let mut leaves = Vec::new();
        arena.leaves(root, &mut leaves);
        let mut children = Vec::with_capacity(leaves.len());
        for leaf in leaves {
            let Some(s) = arena.shapes[leaf].as_ref() else {
                continue;
            };
            let id = format!("{}-g{}-s{}", s.tag, s.group, s.sid);
            let unit = base + pieces.len();
            children.push(match &s.drawing {
                Some(d) => drawn(d, node, id, unit),
                None => {
                    let path: BezPath = back * s.region.to_bezpath();
                    Node::Path(s.paint.node(id, path, unit))
                }
            });
            pieces.push(PieceShape {
                tag: s.tag.clone(),
                group: s.group,
                parent_transform: to_canvas,
                region: s.region.clone(),
                paint: s.paint.clone(),
                text: s.text,
            });
        }
        let wrapper = match node {
            Node::Group(g) => Group {
                children,
                unit: None,
                ..g.clone()
            },
            Node::Path(_) | Node::Image(_) => Group {
                id: node.id().to_string(),
                children,
                ..Group::new()
            },
        };
        if let Some(slot) = out.root.node_at_mut(&shape.node_path) {
            *slot = Node::Group(wrapper);
        }
    }
    stats.shapes = pieces.len();
    // Walk the tree in paint order: old units keep their data, pieces get theirs.
    let mut shapes = Vec::new();
    let mut per_tag: HashMap<String, usize> = HashMap::new();
    let mut path = Vec::new();
    renumber(
        &mut out.root,
        &mut path,
        scene,
        &pieces,
        base,
        &mut shapes,
        &mut per_tag,
    );
    out.shapes = shapes;
    out
}

/// The node of a piece that keeps drawing `d` (`unit` its shape index), in the
/// coordinates the unit node `unit_node` draws its children in.
fn drawn(d: &Drawing, unit_node: &Node, id: String, unit: usize) -> Node {
    match d {
        Drawing::Glyphs { layout, glyphs, .. } => {
            let mut paths = glyphs
                .iter()
                .map(|&i| Node::Path(layout.glyphs[i].path.clone()));
            match (glyphs.len(), paths.next()) {
                (1, Some(Node::Path(p))) => Node::Path(PathNode {
                    id,
                    unit: Some(unit),
                    ..p
                }),
                (_, first) => Node::Group(Group {
                    id,
                    children: first.into_iter().chain(paths).collect(),
                    unit: Some(unit),
                    ..Group::new()
                }),
            }
        }
        Drawing::Whole => {
            let mut node = match unit_node {
                Node::Group(g) => Node::Group(Group {
                    id,
                    children: g.children.clone(),
                    ..Group::new()
                }),
                other => other.clone(),
            };
            node.set_unit(Some(unit));
            node
        }
    }
}

fn renumber(
    g: &mut Group,
    path: &mut Vec<usize>,
    scene: &Scene,
    pieces: &[PieceShape],
    base: usize,
    shapes: &mut Vec<Shape>,
    per_tag: &mut HashMap<String, usize>,
) {
    for (i, child) in g.children.iter_mut().enumerate() {
        path.push(i);
        if let Some(u) = child.unit() {
            let mut shape = if u < base {
                scene.shapes[u].clone()
            } else {
                let p = &pieces[u - base];
                let solid = |c: Option<Color>| c.unwrap_or(Color::BLACK);
                let fill = p.paint.fill.as_ref().and_then(|f| match f.paint {
                    crate::scene::Paint::Solid(c) => Some(c),
                    _ => None,
                });
                let stroke = p.paint.stroke.as_ref().and_then(|s| match s.paint {
                    crate::scene::Paint::Solid(c) => Some(c),
                    _ => None,
                });
                Shape {
                    tag: p.tag.clone(),
                    aliases: Vec::new(),
                    inherited: 0,
                    rig: false,
                    id: 0,
                    group: p.group,
                    z: 0,
                    node_path: Vec::new(),
                    parent_transform: p.parent_transform,
                    centroid: p.region.centroid(),
                    bbox: p.region.bbox(),
                    fill: solid(fill),
                    stroke: solid(stroke),
                    stroke_width: p.paint.stroke_width(),
                    text: TextPlace {
                        layout: None,
                        line: p.text.0,
                        word: p.text.1,
                        uncut: None,
                    },
                }
            };
            let id = per_tag.entry(shape.tag.clone()).or_insert(0);
            shape.id = *id;
            *id += 1;
            shape.z = shapes.len();
            shape.node_path = path.clone();
            let index = shapes.len();
            child.set_unit(Some(index));
            shapes.push(shape);
        }
        if let Node::Group(c) = child {
            renumber(c, path, scene, pieces, base, shapes, per_tag);
        }
        path.pop();
    }
}
