//! `gmotion convert`: a still SVG (or a Lottie file, which plays) to PNG, Lottie JSON or
//! a clean SVG; several files, or a folder, into one folder in parallel.

use std::path::{Path, PathBuf};

use gmotion::engine::Settings;
use gmotion_pipeline::grammar::output_size;
use gmotion_pipeline::scene::is_lottie;
use gmotion_pipeline::{Format, ImportChoices, Imported, SceneOptions, Writer, short};

use super::{Ctx, create_dir, print_warnings, validate_render, write_all};
use crate::RenderArgs;
use crate::guard;
use crate::output::check_writable;
use crate::report::{CliError, Result};

/// A `convert` command, its flags resolved (the inputs and outputs aside).
pub struct Convert {
    /// Lottie inputs: the time of the frame a `.png` shows; given, a `.svg` shows that
    /// frame still instead of playing.
    time: Option<f64>,
    render: RenderArgs,
    choices: ImportChoices,
}

impl Convert {
    /// The job `convert`'s flags ask for.
    pub fn new(time: Option<f64>, render: &RenderArgs, import: &crate::ImportArgs) -> Convert {
        Convert {
            time,
            render: render.clone(),
            choices: import.choices(render.width.is_some() || render.height.is_some()),
        }
    }

    /// Converts `inputs` to `outputs`: one file, or a batch ([`is_batch`]).
    pub fn run(&self, inputs: &[PathBuf], outputs: &[PathBuf], ctx: &Ctx) -> Result<()> {
        match inputs {
            [one] if !is_batch(inputs) => self.one(one, outputs, ctx, true),
            _ => self.batch(inputs, outputs, ctx),
        }
    }

    /// Converts `input` to each of `outputs`; `staged`: the outputs land together (the one
    /// staging of the process), else each on its own (a batch converts files in parallel,
    /// each with one output).
    fn one(&self, input: &Path, outputs: &[PathBuf], ctx: &Ctx, staged: bool) -> Result<()> {
        let time = self.time;
        validate_render(&self.render)?;
        let outs: Vec<&Path> = outputs.iter().map(PathBuf::as_path).collect();
        let inputs: Vec<&Path> = [input]
            .into_iter()
            .chain(self.choices.tags.as_deref())
            .collect();
        guard::check_not_input(&outs, &inputs)?;
        // A Lottie input moves, so it can be played to a folder of frames.
        let moves = is_lottie(input);
        for o in outputs {
            guard::check_output_kind(o, moves)?;
            check_writable(o)?;
        }
        if !moves && time.is_some_and(|t| t != 0.0) {
            return Err(CliError::msg(format!(
                "{}: error: --time picks a frame of a Lottie input; an SVG is still",
                input.display()
            )));
        }
        let settings = Settings::default();
        let env = &ctx.env;
        let loaded = Imported::load(input, &SceneOptions::new(&self.choices, None, env)?, env)?;
        // Played outputs draw every frame: a `.svg` without `--time` too.
        let played = |o: &PathBuf| match Format::of(o) {
            Ok(Format::Svg) => time.is_none(),
            Ok(f) => !f.is_still(),
            Err(_) => true,
        };
        if let Some(src) = &loaded.source
            && outputs.iter().any(played)
        {
            env.limits.check_frames(
                src.duration() * src.fps(),
                &format!(
                    "{}: error: {}s at {} fps",
                    input.display(),
                    short(src.duration()),
                    short(src.fps())
                ),
            )?;
        }
        let size = output_size(self.render.width, self.render.height, &settings);
        let mut writer = Writer::new(size, &env.limits);
        writer.options.tolerance = self.render.tolerance;
        writer.options.time = time.unwrap_or(0.0);
        writer.options.play_svg = time.is_none();
        self.render.video.apply(&mut writer)?;
        writer.options.pack = self.render.lottie.pack;
        let write = |out: &Path| {
            let warnings = writer.write_still(&loaded, out)?;
            print_warnings(out, &warnings);
            Ok(())
        };
        if staged {
            write_all(outputs, write)
        } else {
            outputs.iter().try_for_each(|o| write(o))
        }
    }

    /// Converts several files (or the SVG and Lottie files of folders) into one output
    /// folder, in parallel: `DIR/NAME.EXT` each, `EXT` from `--format` (`json` by
    /// default). Every file is tried; each failure is printed with its file, then one line
    /// says what was done.
    fn batch(&self, inputs: &[PathBuf], outputs: &[PathBuf], ctx: &Ctx) -> Result<()> {
        use rayon::prelude::*;
        let [dir] = outputs else {
            return Err(CliError::msg(
                "several inputs convert into one folder: give one -o DIR/",
            ));
        };
        let ext = ctx.format.unwrap_or("json");
        if !matches!(ext, "json" | "svg" | "png") {
            return Err(CliError::msg(format!(
                "--format {ext}: a batch converts to json (Lottie), svg or png"
            )));
        }
        let mut files = Vec::new();
        for input in inputs {
            if input.is_dir() {
                let entries = std::fs::read_dir(input)
                    .map_err(|e| CliError::msg(format!("{}: cannot list: {e}", input.display())))?;
                let mut found: Vec<PathBuf> = entries
                    .filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.is_file())
                    .filter(|p| {
                        p.extension().and_then(|x| x.to_str()).is_some_and(|x| {
                            ["svg", "svgz", "json"].contains(&x.to_ascii_lowercase().as_str())
                        })
                    })
                    .collect();
                found.sort();
                files.extend(found);
            } else {
                files.push(input.clone());
            }
        }
        if files.is_empty() {
            return Err(CliError::msg(
                "no SVG or Lottie file to convert (.svg, .svgz, .json)",
            ));
        }
        let mut names = std::collections::HashSet::new();
        for f in &files {
            let stem = f
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            if !names.insert(stem.clone()) {
                return Err(CliError::msg(format!(
                    "two inputs would both be written to {}",
                    dir.join(format!("{stem}.{ext}")).display()
                )));
            }
        }
        guard::check_output_kind(dir, true)?;
        create_dir(dir)?;
        let failed: Vec<String> = files
            .par_iter()
            .filter_map(|f| {
                let stem = f
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default();
                let out = dir.join(format!("{stem}.{ext}"));
                self.one(f, &[out], ctx, false).err().map(|e| e.0)
            })
            .collect();
        for e in &failed {
            eprintln!("{e}");
        }
        let done = files.len() - failed.len();
        let line = format!(
            "converted {done} of {} files to {}/{}",
            files.len(),
            dir.display().to_string().trim_end_matches('/'),
            if failed.is_empty() {
                String::new()
            } else {
                format!(" ({} failed)", failed.len())
            }
        );
        if failed.is_empty() {
            crate::report::note(&line);
            Ok(())
        } else {
            Err(CliError(line))
        }
    }
}

/// Whether `convert`'s inputs ask for a batch: several, or a folder.
pub fn is_batch(inputs: &[PathBuf]) -> bool {
    inputs.len() > 1 || inputs.iter().any(|p| p.is_dir())
}
