//! `gmotion learn`: a grammar and its still scene learned from a keyframed animation
//! ([`gmotion_learn`]), both written or neither, and the report printed.

use std::path::{Path, PathBuf};

use gmotion::canvas::OutputSize;
use gmotion_pipeline::{Imported, Writer};

use super::Ctx;
use crate::output::{check_writable, write_atomic};
use crate::report::{self, CliError, Result};

/// A `learn` command, its flags resolved.
pub struct Learn {
    /// The animation.
    pub input: PathBuf,
    /// The grammar to write.
    pub output: PathBuf,
    /// The still scene to write (default: beside the grammar, with its name).
    pub scene: Option<PathBuf>,
    /// The largest error accepted, in pixels.
    pub tolerance: f64,
    /// Where the report goes (`-` or none: standard output).
    pub report: Option<PathBuf>,
    /// A report for standard output goes to standard error instead (the studio's first
    /// line of output is its address).
    pub report_to_stderr: bool,
}

impl Learn {
    /// Learns, writes the grammar, the still scene and a report file (all or nothing), or
    /// prints the report.
    pub fn run(self, ctx: &Ctx) -> Result<()> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(CliError::msg(format!(
                "error: --tolerance must be a positive number of pixels, not {}",
                self.tolerance
            )));
        }
        if self.output.as_os_str() == "-" || self.output.extension().is_none_or(|e| e != "gm") {
            return Err(CliError::msg(format!(
                "{}: error: the learned grammar is written to a .gm file",
                self.output.display()
            )));
        }
        let still = self.still_path()?;
        let ext = still.extension().and_then(|e| e.to_str()).unwrap_or("");
        if ext != "json" && ext != "svg" {
            return Err(CliError::msg(format!(
                "{}: error: the still scene is a Lottie (.json) or an SVG (.svg)",
                still.display()
            )));
        }
        if same_file(&still, &self.input) || same_file(&self.output, &self.input) {
            return Err(CliError::msg(format!(
                "{}: error: would overwrite the animation being learned; name another output",
                self.input.display()
            )));
        }
        check_writable(&self.output)?;
        check_writable(&still)?;
        if let Some(r) = self.report.as_ref().filter(|r| r.as_os_str() != "-") {
            check_writable(r)?;
        }
        let env = &ctx.env;
        let opts = gmotion_learn::Options {
            tolerance: self.tolerance,
            max_units: env.limits.get("learn-units"),
            max_samples: env.limits.get("learn-samples"),
            ..Default::default()
        };
        let learned = if self.scene.is_some() {
            gmotion_learn::learn(&self.input, &scene_name(&self.output, &still), env, &opts)
        } else {
            // No still named: a Lottie, or an SVG when the grammar needs one (trims).
            let svg = still.with_extension("svg");
            gmotion_learn::learn_default(
                &self.input,
                &scene_name(&self.output, &still),
                &scene_name(&self.output, &svg),
                env,
                &opts,
            )
        }
        .map_err(|e| CliError::msg(e.to_string()))?;
        let still = if learned.still_svg && self.scene.is_none() {
            let svg = still.with_extension("svg");
            if same_file(&svg, &self.input) {
                return Err(CliError::msg(format!(
                    "{}: error: would overwrite the animation being learned; name another output",
                    self.input.display()
                )));
            }
            check_writable(&svg)?;
            svg
        } else {
            still
        };
        let staging = gmotion::atomic::Staging::begin();
        let warnings = if !learned.still_svg {
            let anim = learned.still_animation(learned.duration, learned.fps);
            gmotion_output::write(&anim, &still, &gmotion_output::Options::default())
                .map_err(|e| CliError::msg(e.to_string()))?
        } else {
            let imported = Imported {
                scene: learned.still.clone(),
                source: None,
                package: None,
            };
            Writer::new(OutputSize::default(), &env.limits).write_still(&imported, &still)?
        };
        for w in warnings {
            report::warn(&still, &w);
        }
        // A Lottie still named with --scene cannot carry trims or morphs: `animate` would
        // leave them out.
        if !learned.still_svg
            && ["animate(trim,", "animate(morph,"]
                .iter()
                .any(|r| learned.grammar.contains(r))
        {
            report::warn(
                &still,
                "the grammar trims or morphs units, which `animate` does not layer onto a Lottie still; name an SVG still (--scene STILL.svg) to keep them",
            );
        }
        write_atomic(&self.output, learned.grammar.as_bytes())?;
        let text = learned.report.to_string();
        let to_file = self.report.as_ref().filter(|r| r.as_os_str() != "-");
        if let Some(r) = to_file {
            write_atomic(r, text.as_bytes())?;
        }
        staging
            .commit()
            .map_err(|e| CliError::msg(format!("cannot put the outputs in place: {e}")))?;
        if to_file.is_none() {
            if self.report_to_stderr {
                eprint!("{text}");
            } else {
                report::out(&text)?;
            }
        }
        Ok(())
    }

    /// The still scene's path: `--scene`, else the grammar's with `.json` (or
    /// `.still.json` when that is the animation itself; `.svg` in place of `.json` when
    /// the grammar needs an SVG still, chosen after learning).
    fn still_path(&self) -> Result<PathBuf> {
        if let Some(s) = &self.scene {
            return Ok(s.clone());
        }
        let plain = self.output.with_extension("json");
        Ok(if same_file(&plain, &self.input) {
            self.output.with_extension("still.json")
        } else {
            plain
        })
    }
}

/// Whether two paths name one file (the second existing).
fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

/// How the grammar at `grammar` names the still scene at `still`: its file name when both
/// sit in one folder, else its absolute path.
fn scene_name(grammar: &Path, still: &Path) -> String {
    let folder = |p: &Path| {
        let parent = p.parent().unwrap_or(Path::new(""));
        let parent = if parent.as_os_str().is_empty() {
            Path::new(".")
        } else {
            parent
        };
        parent.canonicalize().ok()
    };
    match (folder(grammar), folder(still), still.file_name()) {
        (Some(g), Some(s), Some(name)) if g == s => name.to_string_lossy().into_owned(),
        (_, Some(s), Some(name)) => s.join(name).to_string_lossy().into_owned(),
        _ => still.to_string_lossy().into_owned(),
    }
}
