//! `gmotion check`: what a grammar contains and how it expands, without rendering.

use crate::warning::Warning;
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use crate::grammar::ast::Grammar;
use crate::scene::Scene;

use super::rules::Program;
use super::{EngineError, RunOptions, settings};

/// Every error a grammar shows without a scene, in source order: each timeslice rule's
/// operator, arguments and outputs, its values that do not depend on the shape (split
/// fractions that do not sum to 1, an opacity of 2, a misspelt easing), and slice tags no
/// rule produces. The parser reports every syntax error at once; this does the same for
/// meaning, where [`run`](super::run) stops at the first.
pub fn static_errors(grammar: &Grammar) -> Vec<EngineError> {
    let mut errors = Vec::new();
    for (index, r) in grammar.rules.iter().enumerate().filter(|(_, r)| !r.spatial) {
        match super::rules::check_rule(index, r) {
            Ok(rule) => errors.extend(super::expand::constant_errors(&rule)),
            Err(e) => errors.push(e),
        }
    }
    if let Err(e) = super::rules::check_slice_tags(grammar) {
        errors.push(e);
    }
    errors.sort_by_key(|e| e.span.map(|s| (s.line, s.col)));
    errors
}

/// A readable report of a grammar (and its expansion on a scene, when given).
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Problems that do not stop a run but probably are mistakes.
    pub warnings: Vec<Warning>,
    /// The report text (the warnings are not in it: a caller words them as it words any
    /// other warning).
    pub text: String,
}

/// Checks a grammar, and expands it on `scene` when given.
pub fn check(
    grammar: &Grammar,
    scene: Option<&Scene>,
    opts: &RunOptions,
) -> Result<Report, EngineError> {
    let settings = settings::from_grammar(grammar)?;
    let program = Program::new(grammar)?;
    let mut r = Report::default();
    let mut out = String::new();
    let time_rules = program.rules.len();
    if !program.spatial.is_empty() {
        let spatial: Vec<&crate::grammar::ast::Rule> =
            program.spatial.iter().map(|&i| &grammar.rules[i]).collect();
        let g = crate::tangle::graph_stats(&spatial);
        let _ = writeln!(
            out,
            "group grammar graph: {} nodes, {} edges, depth {}",
            g.nodes, g.edges, g.depth
        );
    }
    let _ = writeln!(
        out,
        "rules: {} ({} timeslice, {} spatial)",
        grammar.rules.len(),
        time_rules,
        program.spatial.len()
    );
    let _ = writeln!(
        out,
        "header: duration {}s, fps {}, grid {}x{}{}, seed {}, lookup {:?}, interp {:?}, loop {}, max_steps {}",
        settings.duration,
        settings.fps,
        settings.grid.0,
        settings.grid.1,
        match settings.grid.2 {
            2 => String::new(),
            p => format!("x{p}"),
        },
        opts.seed.unwrap_or(settings.seed),
        settings.lookup,
        settings.interp,
        settings.looping,
        settings.max_steps
    );

    // Slice tags: where produced, where consumed.
    let mut produced: BTreeMap<String, usize> = BTreeMap::new();
    let mut consumed: BTreeMap<String, usize> = BTreeMap::new();
    let mut shape_tags: BTreeSet<String> = BTreeSet::new();
    produced.insert("all".into(), 0);
    for rule in &program.rules {
        for t in &rule.outputs {
            *produced.entry(t.name.clone()).or_default() += 1;
        }
        for t in &rule.slice_tags {
            *consumed.entry(t.clone()).or_default() += 1;
        }
        shape_tags.extend(rule.shape_tags.iter().cloned());
    }
    let terminal: Vec<_> = produced
        .keys()
        .filter(|t| !consumed.contains_key(*t))
        .cloned()
        .collect();
    let _ = writeln!(
        out,
        "slice tags: {} ({} terminal: {})",
        produced.len(),
        terminal.len(),
        terminal.join(", ")
    );
    for rule in &program.rules {
        let unreachable: Vec<_> = rule
            .slice_tags
            .iter()
            .filter(|t| !produced.contains_key(*t))
            .collect();
        if unreachable.len() == rule.slice_tags.len() {
            r.warnings.push(Warning::new(format!(
                "line {}: rule is unreachable: no rule produces its slice tag(s) {}",
                rule.span.line,
                rule.slice_tags.join(", ")
            )));
        }
    }
    let _ = writeln!(
        out,
        "shape tags used by rules: {}",
        shape_tags.iter().cloned().collect::<Vec<_>>().join(", ")
    );

    if let Some(scene) = scene {
        let mut s = settings.clone();
        if let Some(seed) = opts.seed {
            s.seed = seed;
        }
        if let Some(m) = opts.max_steps {
            s.max_steps = m;
        }
        let _ = writeln!(
            out,
            "scene: {} shapes, tags: {}",
            scene.shapes.len(),
            tag_counts(scene)
        );
        // A group grammar runs first; the timeslice rules then animate its pieces.
        let expanded = super::spatial_stage(scene, grammar, &program, &s, opts)?;
        let scene = match &expanded {
            None => scene,
            Some((pieces, t)) => {
                let _ = writeln!(
                    out,
                    "spatial expansion: {} steps, {} pieces in {} groups, tags: {}",
                    t.steps,
                    pieces.shapes.len(),
                    t.groups,
                    tag_counts(pieces)
                );
                for (&i, &uses) in program.spatial.iter().zip(&t.rule_uses) {
                    if uses == 0 {
                        r.warnings.push(Warning::new(format!(
                            "line {}: spatial rule was never applied on this scene",
                            grammar.rules[i].span.line
                        )));
                    }
                }
                let used = t.rule_uses.iter().filter(|&&u| u > 0).count();
                let _ = writeln!(
                    out,
                    "spatial rules applied: {used} of {}",
                    program.spatial.len()
                );
                r.warnings.extend(t.warnings.iter().cloned());
                pieces
            }
        };
        if time_rules == 0 {
            let _ = writeln!(out, "no timeslice rules: the result stands still");
        } else {
            time_report(scene, &program, &shape_tags, &s, &mut r, &mut out)?;
        }
    }
    r.text = out;
    Ok(r)
}

/// The timeslice grammar as a Graphviz graph: one node per slice tag, one edge per rule
/// from each tag it matches to each tag it produces, labelled with the operator and line.
pub fn dot(grammar: &Grammar) -> String {
    let mut out = String::from(
        "digraph grammar {\n  rankdir=LR;\n  node [shape=box, style=rounded, fontname=\"sans-serif\"];\n",
    );
    for rule in grammar.rules.iter().filter(|r| !r.spatial) {
        for from in &rule.slice_tags {
            for to in &rule.outputs {
                let to_name = if to.inverted {
                    format!("inv_{}", to.name)
                } else {
                    to.name.clone()
                };
                let shapes: Vec<_> = rule.shape_tags.iter().map(|t| t.name.as_str()).collect();
                let _ = writeln!(
                    out,
                    "  \"{}\" -> \"{}\" [label=\"{} [{}] l.{}\"];",
                    from.name,
                    to_name,
                    rule.op,
                    shapes.join(","),
                    rule.span.line
                );
            }
        }
    }
    out.push_str("}\n");
    out
}

/// The scene's shape tags with their counts, as `tag ×n, …`.
fn tag_counts(scene: &Scene) -> String {
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for s in &scene.shapes {
        *counts.entry(s.tag.as_str()).or_default() += 1;
    }
    let list: Vec<_> = counts.iter().map(|(t, n)| format!("{t} ×{n}")).collect();
    list.join(", ")
}

/// The timeslice part of a report on `scene` (the pieces, after a group grammar): tags no
/// shape has or no rule takes, then the expansion's statistics.
fn time_report(
    scene: &Scene,
    program: &Program,
    shape_tags: &BTreeSet<String>,
    settings: &settings::Settings,
    r: &mut Report,
    out: &mut String,
) -> Result<(), EngineError> {
    let tags: BTreeSet<&str> = scene.shapes.iter().flat_map(|s| s.tags()).collect();
    for t in shape_tags {
        if t != "all" && !tags.iter().any(|s| crate::grammar::ast::tag_matches(t, s)) {
            r.warnings.push(Warning::new(format!(
                "shape tag `{t}` is used by rules but no shape in the scene has it"
            )));
        }
    }
    // A shape tag is still when none of its shapes is taken under any of its names.
    let mut still: BTreeMap<&str, bool> = BTreeMap::new();
    // A rig no rule names is only a layer's parent: nothing to warn about.
    for s in scene.shapes.iter().filter(|s| !s.rig) {
        let taken = program.rules.iter().any(|rule| rule.takes(s.tags(), false));
        *still.entry(s.tag.as_str()).or_insert(true) &= !taken;
    }
    for (t, _) in still.into_iter().filter(|(_, still)| *still) {
        r.warnings.push(Warning::new(format!(
            "shapes tagged `{t}` match no rule and stay still"
        )));
    }
    let exp = super::expand::expand(scene, program, settings)?;
    let slices: usize = exp.timelines.iter().map(Vec::len).sum();
    let _ = writeln!(
        out,
        "expansion: {} steps, {} slices ({:.1} per shape), {} slice tags created",
        exp.steps,
        slices,
        slices as f64 / scene.shapes.len() as f64,
        exp.slice_tags.len()
    );
    for rule in &program.rules {
        let uses = exp.rule_uses.get(rule.index).copied().unwrap_or(0);
        if uses == 0 {
            r.warnings.push(Warning::new(format!(
                "line {}: rule was never applied on this scene",
                rule.span.line
            )));
        }
    }
    let used = exp.rule_uses.iter().filter(|&&u| u > 0).count();
    let _ = writeln!(out, "rules applied: {used} of {}", program.rules.len());
    if settings.looping {
        let tracks: Vec<_> = (exp.timelines.iter().zip(&scene.shapes))
            .map(|(timeline, shape)| super::compile::track(shape, timeline))
            .collect();
        r.warnings.extend(super::seam::loop_warning(
            &scene.shapes,
            &tracks,
            settings.duration,
            scene.canvas(),
        ));
    }
    Ok(())
}
