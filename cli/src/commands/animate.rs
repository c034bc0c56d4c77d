//! `gmotion animate`: a grammar run on a scene, written to every output.

use std::path::{Path, PathBuf};

use gmotion::engine::Settings;
use gmotion_pipeline::grammar::output_size;
use gmotion_pipeline::{GrammarFile, ImportChoices, Overrides, Project, Rendered, html};

use super::write_animation;
use super::{Ctx, Files, animation_writer, check_outputs, validate_render, write_all};
use crate::report::{CliError, Result};
use crate::theme::Theme;
use crate::{RenderArgs, RunArgs};

/// An `animate` command, its flags resolved.
pub struct Animate {
    files: Files,
    outputs: Vec<PathBuf>,
    /// The time of a `.png` output's frame.
    time: f64,
    run: Overrides,
    render: RenderArgs,
    choices: ImportChoices,
    /// `--theme`: the theme file written into the `.lottie` outputs.
    theme: Option<PathBuf>,
}

impl Animate {
    /// The job `animate`'s flags ask for.
    pub fn new(
        files: Files,
        outputs: Vec<PathBuf>,
        time: f64,
        run: &RunArgs,
        render: RenderArgs,
        import: &crate::ImportArgs,
    ) -> Animate {
        Animate {
            files,
            outputs,
            time,
            run: run.overrides(),
            choices: import.choices(render.width.is_some() || render.height.is_some()),
            render,
            theme: None,
        }
    }

    /// This job with `--theme FILE`, if given.
    pub fn with_theme(self, theme: Option<PathBuf>) -> Animate {
        Animate { theme, ..self }
    }

    /// Checks the outputs, builds the animation and writes every output, all or none.
    pub fn run(self, ctx: &Ctx) -> Result<()> {
        let Animate {
            files,
            outputs,
            time,
            run,
            render,
            choices,
            theme,
        } = self;
        validate_render(&render)?;
        let theme = match &theme {
            Some(path) => Some(Theme::read(path)?),
            None => None,
        };
        let packaged = |o: &Path| o.extension().is_some_and(|e| e == "lottie");
        if theme.is_some() && !outputs.iter().any(|o| packaged(o)) {
            return Err(CliError::msg(
                "--theme is written into .lottie outputs, and none is given (add -o NAME.lottie)",
            ));
        }
        // The tag map is read too: an output must not overwrite it.
        let inputs: Vec<&Path> = files
            .scene()
            .into_iter()
            .chain([files.grammar.as_path()])
            .chain(choices.tags.as_deref())
            .collect();
        check_outputs(&outputs, &inputs)?;
        let pages = outputs.iter().any(|o| html::is_page(o));
        let build = Build {
            files: &files,
            run,
            choices: &choices,
            outputs: &outputs,
            timelines: pages,
        };
        let (rendered, settings) = build.run(ctx)?;
        let size = output_size(render.width, render.height, &settings);
        let writer = animation_writer(&render, size, time, ctx)?;
        let max_bytes = ctx.env.limits.get("input-bytes");
        let written = write_all(&outputs, |o| match theme.as_ref().filter(|_| packaged(o)) {
            // The package is made in memory, the theme added, then written once.
            Some(theme) => {
                let (bytes, mut warnings) = writer.bytes(&rendered, o)?;
                let (bytes, said) = theme.add_to(&bytes, o, max_bytes)?;
                warnings.extend(said);
                gmotion::atomic::write_bytes(o, &bytes).map_err(|e| {
                    CliError::msg(format!("{}: error: cannot write: {e}", o.display()))
                })?;
                for w in &warnings {
                    crate::report::warn(o, w);
                }
                Ok(())
            }
            None => write_animation(&writer, &rendered, o),
        });
        // The process ends here, and the kernel takes its memory back at once: freeing the
        // scene and every track piece by piece first took milliseconds on a large animation.
        std::mem::forget(rendered);
        written
    }
}

/// What `animate` and `demo` build: the grammar run on its scene, with the checks a
/// command line makes on the way (its outputs once the scene's path is known).
pub struct Build<'a> {
    /// The scene (if given) and the grammar.
    pub files: &'a Files,
    /// `--seed`, `--fps`, `--max-steps`.
    pub run: Overrides,
    /// How to import the scene.
    pub choices: &'a ImportChoices,
    /// The outputs, checked before the scene is imported.
    pub outputs: &'a [PathBuf],
    /// Whether to keep the slices an HTML page draws.
    pub timelines: bool,
}

impl Build<'_> {
    /// Parses, expands and compiles; errors point into the grammar. Also returns the
    /// grammar's header, which says how to write the outputs.
    pub fn run(&self, ctx: &Ctx) -> Result<(Rendered, Settings)> {
        let env = &ctx.env;
        let grammar_path = &self.files.grammar;
        let g = GrammarFile::load(grammar_path, env)?;
        g.check_limits(self.run.fps, self.run.max_steps.is_some(), &env.limits)?;
        let Some(scene_path) = g.scene_path(self.files.scene())? else {
            return Err(CliError::msg(format!(
                "{}: error: no scene to animate: give one on the command line (`gmotion animate SCENE GRAMMAR`) or name it in the grammar (`scene FILE`)",
                grammar_path.display()
            )));
        };
        check_outputs(self.outputs, &[&scene_path, grammar_path])?;
        let project = Project::import(g, scene_path, self.choices, env)?;
        project.imported.check_drawable(&project.scene_path)?;
        project.check_composition(self.run.fps)?;
        let opts = self.run.run_options(&env.limits)?;
        let settings = project.grammar.settings.clone();
        Ok((project.run(&opts, self.timelines)?, settings))
    }
}
