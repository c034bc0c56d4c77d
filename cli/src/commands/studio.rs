//! `gmotion studio`: the local web editor on a grammar and its scene.

use std::path::{Path, PathBuf};

use gmotion_pipeline::{ImportChoices, Imported, Overrides, Project, Rescene, SceneOptions};

use super::check::hint_tags;
use super::{Ctx, Files};
use crate::report::{CliError, Result};

/// A `studio` command, its flags resolved.
pub struct StudioJob {
    /// The scene (if given) and the grammar.
    pub files: Files,
    /// The port on 127.0.0.1 (0: any free port).
    pub port: u16,
    /// Do not open a browser.
    pub no_open: bool,
    /// `--learn ANIMATION`: the grammar and its still scene learned from it first.
    pub learn: Option<PathBuf>,
    /// `--seed`, `--fps`, `--max-steps`.
    pub run: Overrides,
    /// How to import the scene.
    pub choices: ImportChoices,
}

impl StudioJob {
    /// Loads the scene as `animate` does (a grammar that does not parse is opened anyway
    /// when the scene is given, to be fixed in the studio) and serves until interrupted.
    pub fn run(self, ctx: &Ctx) -> Result<()> {
        let env = &ctx.env;
        let (scene, grammar_path) = (self.files.scene(), &self.files.grammar);
        if let Some(animation) = &self.learn {
            learn_first(animation, scene, grammar_path, ctx)?;
        } else if scene.is_some() {
            create_empty(grammar_path)?;
        }
        let imported = match (
            Project::load(scene, grammar_path, &self.choices, env),
            scene,
        ) {
            (Ok(project), _) => {
                // As `check` does: a scene whose tags look generated gets a hint on the
                // terminal the studio runs in.
                if let Ok(options) = SceneOptions::new(&self.choices, Some(&project.grammar), env) {
                    hint_tags(&project.scene_path, &options, &project.imported, env);
                }
                project.imported
            }
            (Err(_), Some(s)) => {
                let options = SceneOptions::new(&self.choices, None, env)?;
                let imported = Imported::load(s, &options, env)?;
                hint_tags(s, &options, &imported, env);
                imported
            }
            (Err(e), None) => return Err(e.into()),
        };
        // An edit to the directives that decide the import brings the scene in again, as
        // `animate` would import it under the edited grammar.
        let rescene = Rescene {
            given: self.files.scene.clone(),
            grammar_path: grammar_path.clone(),
            choices: self.choices.clone(),
            env: env.clone(),
        };
        let studio = gmotion_studio::Studio::bind(gmotion_studio::Config {
            grammar_path: grammar_path.clone(),
            imported,
            rescene: Some(rescene),
            run: self.run.run_options(&env.limits)?,
            port: self.port,
        })
        .map_err(|e| CliError::msg(format!("studio: {e}")))?;
        let url = studio.url();
        {
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            let _ = writeln!(out, "studio: {url}");
            let _ = out.flush();
        }
        if !self.no_open {
            gmotion_studio::open_browser(&url);
        }
        studio
            .serve()
            .map_err(|e| CliError::msg(format!("studio: {e}")))
    }
}

/// `--learn`: writes `grammar` and its still scene learned from `animation` (gMotion's
/// first future work: start from a designer's own animation, not a blank grammar). The
/// grammar names its scene, so none may be given; an existing grammar with any text in it
/// is never replaced.
fn learn_first(
    animation: &Path,
    scene: Option<&Path>,
    grammar: &Path,
    ctx: &super::Ctx,
) -> Result<()> {
    if let Some(s) = scene {
        return Err(CliError::msg(format!(
            "{}: error: --learn writes the still scene the learned grammar names; give only the grammar to write (`gmotion studio --learn ANIMATION NEW.gm`)",
            s.display()
        )));
    }
    let existing = std::fs::metadata(grammar).map(|m| m.len()).unwrap_or(0);
    if existing > 0 {
        return Err(CliError::msg(format!(
            "{}: error: the grammar exists and is not empty; --learn writes a new grammar (name another file)",
            grammar.display()
        )));
    }
    super::learn::Learn {
        input: animation.to_path_buf(),
        output: grammar.to_path_buf(),
        scene: None,
        tolerance: crate::DEFAULT_TOLERANCE,
        report: None,
        report_to_stderr: true,
    }
    .run(ctx)
}

/// Creates `path` empty when it does not exist, so a session can start from an empty
/// grammar on a given scene (gMotion §4.3); an existing file is left as it is.
fn create_empty(path: &std::path::Path) -> Result<()> {
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
    {
        Ok(_) => {
            eprintln!("studio: created the empty grammar {}", path.display());
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        Err(e) => Err(CliError::msg(format!(
            "studio: cannot create the grammar {}: {e}",
            path.display()
        ))),
    }
}
