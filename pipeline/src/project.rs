//! A project: a grammar and the scene it runs on, loaded once from paths, run once.

use std::path::{Path, PathBuf};

use gmotion::engine::{self, RunOptions, Settings};
use gmotion::motion::Animation;

use crate::env::{Env, short};
use crate::grammar::GrammarFile;
use crate::scene::{ImportChoices, Imported, SceneOptions};
use crate::write::Rendered;
use crate::{Error, Result};

/// A grammar and the scene it runs on (with the Lottie document the scene came from).
#[derive(Clone, Debug)]
pub struct Project {
    /// The grammar, with its settings.
    pub grammar: GrammarFile,
    /// Where the scene was read from.
    pub scene_path: PathBuf,
    /// The scene, imported under the grammar.
    pub imported: Imported,
    /// What it was loaded under, and runs under.
    pub env: Env,
}

impl Project {
    /// Reads the grammar at `grammar`, finds its scene (`scene` if given, else the
    /// grammar's `scene`) and imports it under `choices`, else the grammar's header.
    pub fn load(
        scene: Option<&Path>,
        grammar: &Path,
        choices: &ImportChoices,
        env: &Env,
    ) -> Result<Project> {
        let g = GrammarFile::load(grammar, env)?;
        let Some(path) = g.scene_path(scene)? else {
            return Err(Error::msg(format!(
                "{}: error: no scene: give one on the command line or name it in the grammar (`scene FILE`)",
                grammar.display()
            )));
        };
        Project::import(g, path, choices, env)
    }

    /// [`Project::load`]'s last step, for a front end that checks something between
    /// reading the grammar and importing the scene at `scene_path`.
    pub fn import(
        grammar: GrammarFile,
        scene_path: PathBuf,
        choices: &ImportChoices,
        env: &Env,
    ) -> Result<Project> {
        let options = SceneOptions::new(choices, Some(&grammar), env)?;
        let imported = Imported::load(&scene_path, &options, env)?;
        Ok(Project {
            grammar,
            scene_path,
            imported,
            env: env.clone(),
        })
    }

    /// A Lottie scene lasts as long as its composition, at its frame rate, where the
    /// grammar (or `fps`, the front end's override) does not say: refuses a composition
    /// whose frames would pass the `frames` limit.
    pub fn check_composition(&self, fps: Option<f64>) -> Result<()> {
        let s = &self.grammar.settings;
        let Some(time) = self.imported.scene.time else {
            return Ok(());
        };
        if s.duration_given && (s.fps_given || fps.is_some()) {
            return Ok(());
        }
        let duration = match s.duration_given {
            true => s.duration,
            false => time.duration,
        };
        let fps = fps.unwrap_or(if s.fps_given { s.fps } else { time.fps });
        self.env.limits.check_frames(
            duration * fps,
            &format!(
                "{}: error: the composition's duration {}s at {} fps",
                self.scene_path.display(),
                short(duration),
                short(fps)
            ),
        )
    }

    /// The grammar run once on a copy of the scene with `opts` (seeds of variations).
    pub fn animate(&self, opts: &RunOptions) -> Result<Animation> {
        engine::run(self.imported.scene.clone(), &self.grammar.grammar, opts)
            .map(|(anim, _)| anim)
            .map_err(|e| self.grammar.error(&e))
    }

    /// The grammar run on the scene with `opts` (the project kept for more runs), as what
    /// the writer writes: the animation, the Lottie source and package it moves, its
    /// markers.
    pub fn rendered(&self, opts: &RunOptions) -> Result<Rendered> {
        let (anim, stats) = engine::run(self.imported.scene.clone(), &self.grammar.grammar, opts)
            .map_err(|e| self.grammar.error(&e))?;
        Ok(Rendered {
            anim,
            source: self.imported.source.clone(),
            package: self.imported.package.clone(),
            markers: stats.markers,
            slots: stats.slots,
            timelines: None,
        })
    }

    /// The grammar run on the scene with `opts`, its warnings told to [`Env::warn`]; with
    /// `timelines`, every shape's final slices too (what the HTML page draws, and the run
    /// does not keep).
    pub fn run(self, opts: &RunOptions, timelines: bool) -> Result<Rendered> {
        let Project {
            grammar,
            imported,
            env,
            ..
        } = self;
        let timelines = timelines
            .then(|| engine::timelines(&imported.scene, &grammar.grammar, opts).ok())
            .flatten();
        let (anim, mut stats) =
            engine::run(imported.scene, &grammar.grammar, opts).map_err(|e| grammar.error(&e))?;
        for w in &stats.warnings {
            (env.warn)(&grammar.path, w);
        }
        Ok(Rendered {
            anim,
            source: imported.source,
            package: imported.package,
            markers: std::mem::take(&mut stats.markers),
            slots: stats.slots,
            timelines,
        })
    }
}

/// How to import a project's scene again under edited grammar settings (the front end's
/// choices still first): what the studio does when an edit changes `scene`, `tag_from`,
/// `units`, `unit_depth` or `tags`.
#[derive(Clone, Debug)]
pub struct Rescene {
    /// The scene given by the front end, which the grammar's `scene` does not replace.
    pub given: Option<PathBuf>,
    /// The grammar file, whose folder the grammar's `scene` and `tags` are found in.
    pub grammar_path: PathBuf,
    /// The front end's import choices.
    pub choices: ImportChoices,
    /// What the import runs under.
    pub env: Env,
}

impl Rescene {
    /// The scene imported under `settings`.
    pub fn import(&self, settings: &Settings) -> Result<Imported> {
        let g = GrammarFile::of_settings(&self.grammar_path, settings.clone());
        let path = g
            .scene_path(self.given.as_deref())?
            .ok_or_else(|| Error::msg("no scene: the grammar names none"))?;
        let options = SceneOptions::new(&self.choices, Some(&g), &self.env)?;
        Imported::load(&path, &options, &self.env)
    }

    /// The scene file a grammar with `settings` runs on (the one given, else the grammar's
    /// `scene`), if any: what a front end watches to import it again when it changes.
    pub fn scene_path(&self, settings: &Settings) -> Option<PathBuf> {
        GrammarFile::of_settings(&self.grammar_path, settings.clone())
            .scene_path(self.given.as_deref())
            .ok()
            .flatten()
    }
}
