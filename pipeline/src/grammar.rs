//! A grammar file read, parsed and checked, with its header's settings; the run options
//! a front end overrides; grammar errors worded against the grammar's text.

use std::path::{Path, PathBuf};

use gmotion::canvas::OutputSize;
use gmotion::engine::{self, EngineError, RunOptions, Settings};
use gmotion::grammar::ast::Grammar;
use gmotion::grammar::diagnostics::Diagnostic;

use crate::env::{Env, Limits, short};
use crate::{Error, Result};

/// A grammar file, parsed, with its header read.
#[derive(Clone, Debug)]
pub struct GrammarFile {
    /// Where it was read from: named in errors, and the folder its `scene` and `tags`
    /// are found in.
    pub path: PathBuf,
    /// Its text, which errors quote.
    pub src: String,
    /// The grammar.
    pub grammar: Grammar,
    /// Its header.
    pub settings: Settings,
}

impl GrammarFile {
    /// Reads, parses and checks the grammar at `path`: every syntax error, else every error
    /// of meaning, at once.
    pub fn load(path: &Path, env: &Env) -> Result<GrammarFile> {
        let bytes = gmotion::input::read_regular(path, env.limits.get("input-bytes"))
            .map_err(|e| Error::msg(format!("{}: cannot read grammar: {e}", path.display())))?;
        let src = gmotion::input::utf8_text(bytes).map_err(|e| {
            Error::msg(format!(
                "{}:{e} (the grammar must be UTF-8)",
                path.display()
            ))
        })?;
        let grammar = gmotion::grammar::parse(&src).map_err(|d| {
            Error::msg(
                d.render(&path.display().to_string(), &src)
                    .trim_end()
                    .to_string(),
            )
        })?;
        let settings =
            engine::settings::from_grammar(&grammar).map_err(|e| located(path, &src, &e))?;
        // Every error of meaning at once, as the parser gives every syntax error.
        let errors = engine::check::static_errors(&grammar);
        if !errors.is_empty() {
            let mut text: Vec<String> = errors
                .iter()
                .map(|e| located(path, &src, e).to_string())
                .collect();
            if errors.len() > 1 {
                text.push(format!("{} errors in {}", errors.len(), path.display()));
            }
            return Err(Error::msg(text.join("\n\n")));
        }
        Ok(GrammarFile {
            path: path.to_path_buf(),
            src,
            grammar,
            settings,
        })
    }

    /// A grammar of `settings` alone, read from `path` (no rules, no text): what decides
    /// a scene's import ([`crate::Rescene`]).
    pub fn of_settings(path: &Path, settings: Settings) -> GrammarFile {
        GrammarFile {
            path: path.to_path_buf(),
            src: String::new(),
            grammar: Grammar::default(),
            settings,
        }
    }

    /// `e` worded against this grammar's text.
    pub fn error(&self, e: &EngineError) -> Error {
        located(&self.path, &self.src, e)
    }

    /// The scene to use: `given`, else the grammar's `scene`, resolved against the
    /// grammar file's folder (a missing file is an error at the directive).
    pub fn scene_path(&self, given: Option<&Path>) -> Result<Option<PathBuf>> {
        if let Some(p) = given {
            return Ok(Some(p.to_path_buf()));
        }
        let Some((name, span)) = &self.settings.scene else {
            return Ok(None);
        };
        let folder = self.path.parent().unwrap_or(Path::new(""));
        let path = folder.join(name);
        if !path.exists() {
            let e = EngineError::at(
                *span,
                format!(
                    "scene file `{name}` not found (looked for {})",
                    path.display()
                ),
            );
            return Err(self.error(&e));
        }
        Ok(Some(path))
    }

    /// Refuses a grammar whose run would pass the `frames` limit (its duration at `fps`,
    /// else its own rate) or whose `max_steps` passes the `steps` limit (unless `--max-steps`
    /// overrides it, `max_steps_given`).
    pub fn check_limits(
        &self,
        fps: Option<f64>,
        max_steps_given: bool,
        limits: &Limits,
    ) -> Result<()> {
        let s = &self.settings;
        let fps_flag = fps.is_some();
        let fps = fps.unwrap_or(s.fps);
        // What to blame: an unusually high frame rate where it was set (the `--fps` flag,
        // which has no place in the file, or the grammar's `fps`), else the duration.
        let what = if fps_flag && fps > 240.0 {
            let written = self.grammar.directives.iter().any(|d| d.name == "duration");
            let duration = if written {
                format!(
                    "the duration {}s ({})",
                    short(s.duration),
                    self.at("duration")
                )
            } else {
                format!("the default duration {}s", short(s.duration))
            };
            format!("--fps {} with {duration}", short(fps))
        } else {
            let culprit = if fps > 240.0 { "fps" } else { "duration" };
            format!(
                "{}: error: duration {}s at {} fps",
                self.at(culprit),
                short(s.duration),
                short(fps)
            )
        };
        limits.check_frames(s.duration * fps, &what)?;
        let steps = limits.get("steps");
        if !max_steps_given && s.max_steps as u64 > steps {
            return Err(Error::msg(format!(
                "{}: error: max_steps {} is more than the limit of {steps} (raise it with --limit steps=N)",
                self.at("max_steps"),
                s.max_steps
            )));
        }
        Ok(())
    }

    /// `path:line:col` of the directive `name` (its last occurrence, the one that counts),
    /// or the path alone when the grammar does not write it.
    fn at(&self, name: &str) -> String {
        let path = self.path.display();
        match self
            .grammar
            .directives
            .iter()
            .rev()
            .find(|d| d.name == name)
        {
            Some(d) => format!("{path}:{}:{}", d.span.line, d.span.col),
            None => path.to_string(),
        }
    }

    /// The size of every output: `width`/`height` if either is given, else the grammar's
    /// `width`/`height` (see [`OutputSize`] for what one or both mean).
    pub fn output_size(&self, width: Option<u32>, height: Option<u32>) -> OutputSize {
        output_size(width, height, &self.settings)
    }
}

/// The size of every output: `width`/`height` if either is given, else `settings`'
/// `width`/`height`.
pub fn output_size(width: Option<u32>, height: Option<u32>, settings: &Settings) -> OutputSize {
    if width.is_some() || height.is_some() {
        OutputSize { width, height }
    } else {
        OutputSize {
            width: settings.width,
            height: settings.height,
        }
    }
}

/// An engine error rendered against the grammar source `src` read from `grammar_path`:
/// the line with a caret when the error has a place.
pub fn located(grammar_path: &Path, src: &str, e: &EngineError) -> Error {
    let name = grammar_path.display().to_string();
    Error::msg(Diagnostic::from(e).render(&name, src).trim_end())
}

/// What a front end overrides of a grammar's header for the run (`--seed`, `--fps`,
/// `--max-steps`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Random seed.
    pub seed: Option<u64>,
    /// Frames per second.
    pub fps: Option<f64>,
    /// Most expansion steps.
    pub max_steps: Option<usize>,
    /// The slice tags written as markers, in place of the grammar's `markers`.
    pub markers: Option<Vec<String>>,
}

impl Overrides {
    /// The run's options under `limits`; a `max_steps` past the `steps` limit or an `fps`
    /// that is not a positive number is refused, naming its flag.
    pub fn run_options(&self, limits: &Limits) -> Result<RunOptions> {
        let steps = limits.get("steps");
        if let Some(m) = self.max_steps
            && m as u64 > steps
        {
            return Err(Error::msg(format!(
                "--max-steps {m} is more than the limit of {steps} (raise it with --limit steps=N)"
            )));
        }
        if let Some(fps) = self.fps
            && !(fps.is_finite() && fps > 0.0)
        {
            return Err(Error::msg(format!(
                "--fps must be a positive number, found {fps}"
            )));
        }
        Ok(RunOptions {
            seed: self.seed,
            fps: self.fps,
            max_steps: self.max_steps,
            markers: self.markers.clone(),
            max_pieces: Some(usize::try_from(limits.get("pieces")).unwrap_or(usize::MAX)),
            max_spatial_time: Some(std::time::Duration::from_secs(
                limits.get("spatial-seconds"),
            )),
        })
    }
}
