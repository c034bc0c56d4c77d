//! `gmotion check`: a grammar parsed and validated (expanded on its scene when there is
//! one, with statistics), the scene's units listed, the grammar graph drawn.

use std::path::{Path, PathBuf};

use gmotion::engine;
use gmotion_pipeline::{Env, GrammarFile, ImportChoices, Imported, Overrides, Project};
use gmotion_pipeline::{SceneOptions, short};

use super::{Ctx, Files, Kind, Order, kind_of};
use crate::guard;
use crate::output::{check_writable, write_atomic};
use crate::report::{self, CliError, Result};

/// A `check` command, its flags resolved.
pub struct Check {
    /// `GRAMMAR [SCENE]`, or with `shapes` a scene alone.
    pub files: Vec<PathBuf>,
    /// Where to write the grammar graph.
    pub graph: Option<PathBuf>,
    /// List the scene's units.
    pub shapes: bool,
    /// With `shapes`: only the units, as JSON.
    pub json: bool,
    /// `--seed`, `--fps`, `--max-steps`.
    pub run: Overrides,
    /// How to import the scene.
    pub choices: ImportChoices,
}

impl Check {
    /// Runs the check.
    pub fn run(self, ctx: &Ctx) -> Result<()> {
        let env = &ctx.env;
        if let [one] = self.files.as_slice()
            && self.shapes
            && kind_of(one) == Kind::Scene
        {
            let options = SceneOptions::new(&self.choices, None, env)?;
            let loaded = Imported::load(one, &options, env)?;
            hint_tags(one, &options, &loaded, env);
            report::out(&shape_list(one, &loaded, self.json))?;
            return Ok(());
        }
        let files = Files::of(&self.files, Order::GrammarFirst)?;
        if self.json {
            let project = Project::load(files.scene(), &files.grammar, &self.choices, env)?;
            report::out(&shape_list(&files.grammar, &project.imported, true))?;
            return Ok(());
        }
        self.check(&files, env)
    }

    /// Checks the grammar (expanded on its scene, if any), lists the scene's units with
    /// `--shapes`, writes the graph with `--graph`.
    fn check(&self, files: &Files, env: &Env) -> Result<()> {
        let grammar_path = &files.grammar;
        let loaded = GrammarFile::load(grammar_path, env)?;
        let path = loaded.scene_path(files.scene())?;
        let graph = self.graph.as_deref();
        if let Some(out) = graph {
            let inputs: Vec<&Path> = path
                .as_deref()
                .into_iter()
                .chain([grammar_path.as_path()])
                .collect();
            guard::check_not_input(&[out], &inputs)?;
            guard::check_output_kind(out, false)?;
            check_writable(out)?;
        }
        let scene = path
            .as_ref()
            .map(|p| {
                let options = SceneOptions::new(&self.choices, Some(&loaded), env)?;
                let scene = Imported::load(p, &options, env)?;
                hint_tags(p, &options, &scene, env);
                Ok::<_, CliError>(scene)
            })
            .transpose()?;
        let g = &loaded.grammar;
        let checked = engine::check::check(
            g,
            scene.as_ref().map(|s| &s.scene),
            &self.run.run_options(&env.limits)?,
        )
        .map_err(|e| loaded.error(&e))?;
        for w in &checked.warnings {
            report::warn(grammar_path, w);
        }
        report::out(&checked.text)?;
        if self.shapes
            && let (Some(p), Some(s)) = (&path, &scene)
        {
            report::out(&shape_list(p, s, false))?;
        }
        if let Some(out) = graph {
            let rules: Vec<&gmotion::grammar::ast::Rule> = g.rules.iter().collect();
            let spatial = rules.iter().any(|r| r.spatial);
            let svg = out
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
            let text = match (svg, spatial) {
                (true, true) => gmotion::tangle::graph::graph_svg(&rules),
                (true, false) => {
                    return Err(CliError::msg(format!(
                        "{}: drawings are made for group grammars; write the timeslice graph as .dot",
                        out.display()
                    )));
                }
                (_, true) => gmotion::tangle::graph::graph_dot(&rules),
                (_, false) => engine::check::dot(g),
            };
            write_atomic(out, text.as_bytes())?;
        }
        Ok(())
    }
}

/// Says which `--tag-from` would name an SVG scene's shapes better, when most of its tags
/// name nothing a designer chose (`st0`, `path`): `check` and `studio` ask, once, as finding
/// out imports the scene again under each other source.
pub fn hint_tags(path: &Path, options: &SceneOptions, loaded: &Imported, env: &Env) {
    if let Some(hint) = loaded.tag_hint(path, options, env) {
        report::note(&format!("{}: hint: {hint}", path.display()));
    }
}

/// The units of a scene, one line each: tag and id, bounding box, centroid, the other tags
/// the unit answers to (ids, a tag map's), and for a Lottie scene the layers it moves (and
/// the animations of the dotLottie package it was read from).
/// With `json`, the units as the studio lists them instead, on one line.
fn shape_list(path: &Path, loaded: &Imported, json: bool) -> String {
    use std::fmt::Write as _;
    let scene = &loaded.scene;
    if json {
        return format!("{}\n", gmotion_studio::shapes_json(scene));
    }
    let rigs = scene.shapes.iter().filter(|s| s.rig).count();
    let mut out = format!(
        "{}: {} units{} ({} × {})\n",
        path.display(),
        scene.shapes.len() - rigs,
        match rigs {
            0 => String::new(),
            n => format!(" and {n} rig{}", if n == 1 { "" } else { "s" }),
        },
        scene.width,
        scene.height
    );
    if let Some(src) = &loaded.source {
        let _ = writeln!(
            out,
            "  measured at frame {} ({:.3}s from the start; `reference_time` sets another)",
            short(src.frame),
            (src.frame - src.document.ip) / src.document.fr
        );
    }
    if let Some(picked) = &loaded.package {
        let names = |ids: Vec<String>| {
            ids.iter()
                .map(|id| match id == &picked.id {
                    true => format!("`{id}` (read)"),
                    false => format!("`{id}`"),
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        let pkg = &picked.package;
        let _ = writeln!(
            out,
            "  dotLottie package: animations {}{} (`--animation ID` reads another)",
            names(pkg.ids()),
            match pkg.themes.len() {
                0 => String::new(),
                _ => format!(
                    "; themes {}",
                    names(pkg.themes.iter().map(|t| t.id.clone()).collect())
                ),
            }
        );
    }
    for (i, s) in scene.shapes.iter().enumerate() {
        let b = s.bbox;
        let (at, what) = match s.rig {
            true => ("anchor", "rig "),
            false => ("centroid", ""),
        };
        let _ = write!(
            out,
            "  {what}{}:{}  box [{:.1}, {:.1}, {:.1}, {:.1}]  {at} ({:.1}, {:.1})",
            s.tag, s.id, b.x0, b.y0, b.x1, b.y1, s.centroid.x, s.centroid.y
        );
        let (own, inherited) = s.aliases.split_at(s.aliases.len() - s.inherited);
        if !own.is_empty() {
            let _ = write!(out, "  also {}", own.join(", "));
        }
        if !inherited.is_empty() {
            let _ = write!(out, "  follows {}", inherited.join(", "));
        }
        if let Some(src) = &loaded.source
            && let Some(unit) = src.units.get(i)
        {
            let names: Vec<String> = unit
                .layers
                .iter()
                .filter_map(|&li| src.document.layers.get(li))
                .map(|l| match l.ind {
                    Some(ind) => format!("\"{}\" (ind {ind})", l.nm),
                    None => format!("\"{}\"", l.nm),
                })
                .collect();
            let _ = write!(out, "  layer {}", names.join(" + matte "));
            if let Some(k) = unit.part
                && let Some(item) = unit
                    .layers
                    .first()
                    .and_then(|&li| src.document.layers.get(li))
                    .and_then(|l| l.shapes.get(k))
            {
                let kind = item.kind.part_name().unwrap_or("item");
                let _ = write!(out, " {kind} \"{}\" ({})", item.nm, item.at);
            }
        }
        out.push('\n');
    }
    out
}
