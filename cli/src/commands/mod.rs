//! The commands, one module each: every command resolves its flags once into a job and
//! runs it through the pipeline library ([`gmotion_pipeline`]); what stays here is what
//! only a command line has (telling files apart, checking outputs before any work, the
//! staging of every output, progress bars, printing).

mod animate;
mod check;
mod convert;
mod demo;
mod learn;
mod studio;
mod transitions;
mod variations;

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use gmotion::Warning;
use gmotion::canvas::MAX_OUTPUT_SIZE;
use gmotion_export_raster as raster;
use gmotion_pipeline::{Env, Format, ImportChoices, Overrides, Rendered, Writer, html};
use indicatif::{ProgressBar, ProgressStyle};

use super::guard;
use super::output::check_writable;
use super::report::{CliError, Result};
use super::{Command, ImportArgs, RenderArgs, RunArgs, TagFromArg, UnitsArg};

pub use convert::is_batch;

/// What every command is run under: the pipeline's environment (limits, file-access
/// policy, fonts, where warnings go) and `--format`.
#[derive(Clone)]
pub struct Ctx {
    /// `--limit`, `--allow-path`, `--font-*`; warnings printed as they arise.
    pub env: Env,
    /// `--format`: the extension of outputs that have none of their own (standard output,
    /// a batch's files).
    pub format: Option<&'static str>,
}

/// Runs one command.
pub fn run(cmd: Command, ctx: &Ctx) -> Result<()> {
    match cmd {
        // Printed by `main` from the argument definitions themselves.
        Command::Completions { .. } | Command::Man => Ok(()),
        Command::Demo {
            output,
            example,
            list,
        } => demo::demo(&output, &example, list, ctx),
        Command::Convert {
            inputs,
            output,
            time,
            size,
            import,
        } => convert::Convert::new(time, &size.render(), &import).run(&inputs, &output, ctx),
        Command::Animate {
            files,
            output,
            time,
            theme,
            run,
            render,
            import,
        } => {
            let files = Files::of(&files, Order::SceneFirst)?;
            animate::Animate::new(files, output, time, &run, render, &import)
                .with_theme(theme)
                .run(ctx)
        }
        Command::Transitions {
            scene,
            targets,
            output,
            system,
            fps,
            duration,
            time,
            render,
            import,
        } => transitions::TransitionsJob {
            spec: gmotion_pipeline::Transitions {
                scene,
                targets,
                system,
                fps,
                duration,
            },
            outputs: output,
            choices: import.choices(render.width.is_some() || render.height.is_some()),
            time,
            render,
        }
        .run(ctx),
        Command::Studio {
            files,
            port,
            no_open,
            learn,
            run,
            import,
        } => studio::StudioJob {
            files: Files::of(&files, Order::SceneFirst)?,
            port,
            no_open,
            learn,
            run: run.overrides(),
            choices: import.choices(false),
        }
        .run(ctx),
        Command::Learn {
            input,
            output,
            scene,
            tolerance,
            report,
        } => learn::Learn {
            input,
            output,
            scene,
            tolerance,
            report,
            report_to_stderr: false,
        }
        .run(ctx),
        Command::Variations {
            files,
            count,
            seed_start,
            output,
            time,
            width,
            theme,
            import,
        } => variations::Variations {
            files: Files::of(&files, Order::SceneFirst)?,
            seeds: (0..u64::from(count))
                .map(|i| seed_start.saturating_add(i))
                .collect(),
            output,
            time,
            width,
            theme,
            choices: import.choices(true),
        }
        .run(ctx),
        Command::Check {
            files,
            graph,
            shapes,
            json,
            run,
            import,
        } => check::Check {
            files,
            graph,
            shapes,
            json,
            run: run.overrides(),
            choices: import.choices(false),
        }
        .run(ctx),
    }
}

impl ImportArgs {
    /// The pipeline's import choices these flags make; `sized`: the command's own flags
    /// set the outputs' size (`--width`, `--height`).
    fn choices(&self, sized: bool) -> ImportChoices {
        ImportChoices {
            tag_from: self.tag_from.map(|t| match t {
                TagFromArg::Auto => gmotion::TagFrom::Auto,
                TagFromArg::DataTag => gmotion::TagFrom::DataTag,
                TagFromArg::Class => gmotion::TagFrom::Class,
                TagFromArg::Label => gmotion::TagFrom::Label,
                TagFromArg::Layer => gmotion::TagFrom::Layer,
            }),
            units: self.units.map(|u| match u {
                UnitsArg::Auto => gmotion::Units::Auto,
                UnitsArg::Paths => gmotion::Units::Paths,
                UnitsArg::Groups => gmotion::Units::Groups,
            }),
            unit_depth: self.unit_depth,
            tags: self.tags.clone(),
            reference_time: self.reference_time,
            animation: self.animation.clone(),
            sized,
        }
    }
}

impl RunArgs {
    /// The pipeline's overrides of the grammar's header these flags make.
    fn overrides(&self) -> Overrides {
        Overrides {
            seed: self.seed,
            fps: self.fps,
            max_steps: self.max_steps,
            markers: self.markers.clone(),
        }
    }
}

/// What a file named on the command line holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Grammar,
    Scene,
    /// Unreadable, or nothing to tell by: its place on the command line decides.
    Unknown,
}

/// A file's kind by its extension (`.gm`; `.svg`, `.json`, `.lottie`), else by its first
/// bytes: SVG starts with `<` and Lottie JSON with `{` (after a byte-order mark and blanks),
/// a dotLottie package as a zip does (`PK`), a grammar never does.
fn kind_of(path: &Path) -> Kind {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("gm") => return Kind::Grammar,
        Some("svg" | "json" | "lottie") => return Kind::Scene,
        _ => {}
    }
    // A FIFO or device is not opened (it could block or never end); reading it later
    // gives the error.
    if !matches!(gmotion::input::irregular_kind(path), Ok(None)) {
        return Kind::Unknown;
    }
    let mut head = [0u8; 512];
    let n = match std::fs::File::open(path).and_then(|mut f| std::io::Read::read(&mut f, &mut head))
    {
        Ok(n) => n,
        Err(_) => return Kind::Unknown,
    };
    if gmotion_pipeline::dotlottie::Package::sniff(&head[..n]) {
        return Kind::Scene;
    }
    let text = String::from_utf8_lossy(&head[..n]);
    match text
        .trim_start_matches('\u{feff}')
        .trim_start()
        .chars()
        .next()
    {
        Some('<' | '{') => Kind::Scene,
        Some(_) => Kind::Grammar,
        None => Kind::Unknown,
    }
}

/// The order a command lists its files in, which decides when their kinds do not.
#[derive(Clone, Copy)]
enum Order {
    /// `animate [SCENE] GRAMMAR`.
    SceneFirst,
    /// `check GRAMMAR [SCENE]`.
    GrammarFirst,
}

/// The scene (if given) and the grammar among a command's one or two files.
#[derive(Clone, Debug)]
struct Files {
    scene: Option<PathBuf>,
    grammar: PathBuf,
}

impl Files {
    /// The scene and the grammar among `files`, told apart by [`kind_of`], else by
    /// `order`.
    fn of(files: &[PathBuf], order: Order) -> Result<Files> {
        match files {
            [one] => {
                if kind_of(one) == Kind::Scene {
                    return Err(CliError::msg(format!(
                        "{}: this is a scene; a grammar (.gm) is needed too, as in `gmotion animate [SCENE] GRAMMAR`",
                        one.display()
                    )));
                }
                Ok(Files {
                    scene: None,
                    grammar: one.clone(),
                })
            }
            [a, b] => {
                let (ka, kb) = (kind_of(a), kind_of(b));
                let grammar_first = if ka != kb && (ka == Kind::Grammar || kb == Kind::Scene) {
                    true
                } else if ka != kb && (kb == Kind::Grammar || ka == Kind::Scene) {
                    false
                } else {
                    matches!(order, Order::GrammarFirst)
                };
                let (scene, grammar) = if grammar_first { (b, a) } else { (a, b) };
                Ok(Files {
                    scene: Some(scene.clone()),
                    grammar: grammar.clone(),
                })
            }
            // clap takes one or two.
            _ => Err(CliError::msg(
                "expected a grammar and at most one scene".to_string(),
            )),
        }
    }

    /// The given scene, if any.
    fn scene(&self) -> Option<&Path> {
        self.scene.as_deref()
    }
}

fn progress(len: usize, what: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() || len < 8 {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::new(len as u64);
    if let Ok(style) = ProgressStyle::with_template("{msg} {bar:40} {pos}/{len} frames ({eta})") {
        pb.set_style(style);
    }
    pb.set_message(what.to_string());
    pb
}

fn print_warnings(out: &Path, warnings: &[Warning]) {
    for w in warnings {
        super::report::warn(out, w);
    }
}

/// The pipeline's writer for an animation's outputs: `render`'s tolerance, `size`, the
/// `.png` frame at `time`, under the command line's limits.
fn animation_writer(
    render: &RenderArgs,
    size: gmotion::canvas::OutputSize,
    time: f64,
    ctx: &Ctx,
) -> Result<Writer> {
    let mut writer = Writer::new(size, &ctx.env.limits);
    writer.options.tolerance = render.tolerance;
    writer.options.time = time;
    render.video.apply(&mut writer)?;
    writer.options.pack = render.lottie.pack;
    Ok(writer)
}

impl crate::VideoArgs {
    /// `--background` as 8-bit RGB, if given; one that is no colour is an error.
    fn background(&self) -> Result<Option<[u8; 3]>> {
        let Some(text) = &self.background else {
            return Ok(None);
        };
        let [r, g, b, _] = gmotion::color::Color::parse(text)
            .ok_or_else(|| {
                CliError::msg(format!(
                    "--background must be a colour (#rrggbb or a CSS name), found `{text}`"
                ))
            })?
            .to_rgba8();
        Ok(Some([r, g, b]))
    }

    /// Sets the video options of `writer`.
    fn apply(&self, writer: &mut Writer) -> Result<()> {
        if let Some(bg) = self.background()? {
            writer.options.background = bg;
        }
        writer.options.transparent = self.transparent;
        Ok(())
    }
}

/// Writes `r` to `out` with `writer`, with a progress bar for outputs drawn frame by frame.
fn write_animation(writer: &Writer, r: &Rendered, out: &Path) -> Result<()> {
    let frames = Writer::draws_every_frame(out)?;
    let pb = progress(if frames { r.anim.frame_count() } else { 0 }, "rendering");
    let warnings = writer.write(r, out, &|| pb.inc(1))?;
    pb.finish_and_clear();
    print_warnings(out, &warnings);
    Ok(())
}

fn validate_render(render: &RenderArgs) -> Result<()> {
    render.video.background()?;
    if !(render.tolerance.is_finite() && render.tolerance > 0.0) {
        return Err(CliError::msg(format!(
            "--tolerance must be a positive number of pixels, found {}",
            render.tolerance
        )));
    }
    for (flag, v) in [("--width", render.width), ("--height", render.height)] {
        if let Some(v) = v
            && !(1..=MAX_OUTPUT_SIZE).contains(&v)
        {
            return Err(CliError::msg(format!(
                "{flag} must be between 1 and {MAX_OUTPUT_SIZE}, found {v}"
            )));
        }
    }
    Ok(())
}

/// Checks each output can be written before any work: a known format, an existing
/// folder, and a frames folder that may be written fresh.
fn check_outputs(outputs: &[PathBuf], inputs: &[&Path]) -> Result<()> {
    let outs: Vec<&Path> = outputs.iter().map(PathBuf::as_path).collect();
    guard::check_not_input(&outs, inputs)?;
    for o in outputs {
        let frames = !html::is_page(o) && Format::of(o)? == Format::Frames;
        guard::check_output_kind(o, frames)?;
        if frames {
            raster::check_frame_folder(o).map_err(|e| CliError::msg(e.to_string()))?;
        }
        check_writable(o)?;
    }
    Ok(())
}

/// Writes every output with `write`, all or none: each waits in its temporary file until
/// all are written, then all are renamed into place.
fn write_all(outputs: &[PathBuf], mut write: impl FnMut(&Path) -> Result<()>) -> Result<()> {
    let staging = gmotion::atomic::Staging::begin();
    for o in outputs {
        write(o)?;
    }
    staging
        .commit()
        .map_err(|e| CliError::msg(format!("cannot put the outputs in place: {e}")))
}

/// Creates the output folder `out` (and its parents).
fn create_dir(out: &Path) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| {
        CliError::msg(format!(
            "{}: cannot create output directory: {e}",
            out.display()
        ))
    })
}
