//! The `gmotion` command: argument definitions and dispatch, a thin layer over the
//! libraries (the engine in `gmotion`, the importers and exporters in their own crates).
#![forbid(unsafe_code)]

/// mimalloc rather than the system allocator: expansion and evaluation make many small
/// short-lived allocations, and glibc returns large freed blocks to the OS only to fault
/// them back in; `cargo bench --bench engine` measured 25–40 % less time with it.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

mod commands;
mod examples;
mod guard;
mod output;
mod report;
mod sheet;
mod stdio;
mod theme;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, CommandFactory, Parser, Subcommand, ValueEnum};

/// Procedural motion graphics from still vector art: timeslice and group grammars, signal
/// filters, and export to Lottie, animated SVG (SMIL), PNG, GIF and APNG.
#[derive(Parser, Debug)]
#[command(
    name = "gmotion",
    version,
    about,
    long_about = None,
    after_help = "Examples:
  gmotion animate art.svg motion.gm -o art.json -o art.gif
  gmotion check motion.gm art.svg
  gmotion convert logo.svg -o logo.json
  gmotion studio art.svg motion.gm
  cat art.svg | gmotion animate - motion.gm -o - --format json > art.json

Exit status: 0 done, 1 bad input or a failed write (nothing is left half-written), 2 bad
command line. docs/cli.md has every command with examples."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Print no warnings and no summary of what was written (errors are still printed).
    #[arg(short, long, global = true)]
    quiet: bool,
    /// The format of an output written to standard output (`-o -`), which has no
    /// extension to tell it.
    #[arg(long, value_enum, global = true)]
    format: Option<FormatArg>,
    /// Raise or lower a limit, `NAME=N` (repeatable): input-bytes, svgz-bytes,
    /// xml-entity-bytes, xml-nodes, css-rules, path-segments, text-chars, text-spans,
    /// filter-pixels, image-pixels, frames, pixels, animation-pixels, steps, pieces,
    /// spatial-seconds, learn-units, learn-samples (see the README's "Limits").
    #[arg(long = "limit", value_name = "NAME=N", global = true)]
    limits: Vec<String>,
    /// A folder whose files an SVG (`<image href>`) or a Lottie file (linked image
    /// assets) may reference, besides its own folder (repeatable).
    #[arg(long = "allow-path", value_name = "DIR", global = true)]
    allow_paths: Vec<PathBuf>,
    /// A folder of fonts for SVG text and Lottie text without embedded glyphs, besides the
    /// system's (repeatable).
    #[arg(long = "font-dir", value_name = "DIR", global = true)]
    font_dirs: Vec<PathBuf>,
    /// A font file for SVG text and Lottie text without embedded glyphs (repeatable).
    #[arg(long = "font-file", value_name = "FILE", global = true)]
    font_files: Vec<PathBuf>,
    /// The family text is drawn in when its own font is not installed (default: the
    /// first installed of Arial, Helvetica, Liberation Sans, DejaVu Sans, Noto Sans, …;
    /// a missing serif or monospace font, such as Georgia or Consolas, in one of its kind).
    #[arg(long = "font-family", value_name = "NAME", global = true)]
    font_family: Option<String>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run the bundled example and write its frames, GIF, Lottie, SMIL and preview.html.
    #[command(
        after_help = "Examples:\n  gmotion demo\n  gmotion demo --list\n  gmotion demo --example toy -o out/toy\n  gmotion demo --example histogram -o out/histogram   # data-driven transitions"
    )]
    Demo {
        /// Output directory.
        #[arg(short, long, default_value = "out/demo")]
        output: PathBuf,
        /// Which bundled example (`--list` names them all).
        #[arg(long, default_value = "abstract")]
        example: String,
        /// List the bundled examples, with what each shows, and write nothing.
        #[arg(long)]
        list: bool,
    },
    /// Convert a still SVG: to PNG (render), Lottie JSON, or a clean SVG. A Lottie input
    /// (`.json`) is written back as it was read to `.json`, played by gmotion's own
    /// renderer to `.gif`, `.apng` or a folder of frames, and drawn at --time to `.png`
    /// and `.svg`.
    #[command(
        after_help = "Examples:\n  gmotion convert logo.svg -o logo.json          # Lottie for the web\n  gmotion convert logo.svg -o logo.png --width 512\n  gmotion convert anim.json -o anim.gif          # play a Lottie file\n  gmotion convert icons/ -o lottie/              # a folder, each file to Lottie\n  gmotion convert a.svg b.svg -o pngs/ --format png --width 256\n  gmotion convert anim.json -o still.png --time 1.5"
    )]
    Convert {
        /// Input SVG or Lottie JSON; several, or a folder, convert each into the folder
        /// `-o DIR/` (in parallel; `--format` picks the format, Lottie JSON by default).
        #[arg(required = true, value_name = "INPUT")]
        inputs: Vec<PathBuf>,
        /// Output file(s): .png, .json (Lottie) or .svg; for a Lottie input also .gif,
        /// .apng or a directory (one PNG per frame). For several inputs, one folder.
        #[arg(short, long, required = true)]
        output: Vec<PathBuf>,
        /// Lottie inputs: the time, in seconds from the composition's start, of the frame
        /// a .png shows (default the first); given, a .svg shows that frame still instead
        /// of playing the whole animation.
        #[arg(long)]
        time: Option<f64>,
        #[command(flatten)]
        size: SizeArgs,
        #[command(flatten)]
        import: ImportArgs,
    },
    /// Run a grammar on a scene and write the animation.
    #[command(
        after_help = "Examples:\n  gmotion animate art.svg motion.gm -o art.json -o art.svg -o art.gif\n  gmotion animate motion.gm -o frames/          # the grammar names its scene\n  gmotion animate art.svg motion.gm -o still.png --time 2\n  gmotion animate anim.json motion.gm -o out.json   # After Effects round trip\n  gmotion animate - motion.gm -o - --format json < art.svg > art.json"
    )]
    #[command(override_usage = "gmotion animate [OPTIONS] --output <OUTPUT> [SCENE] <GRAMMAR>")]
    Animate {
        /// `[SCENE] GRAMMAR`: the scene (SVG or Lottie JSON) may be left out when the grammar names it
        /// with `scene FILE`; given, it overrides that. The grammar is told apart by its
        /// `.gm` extension (else by not being SVG), so either order works.
        #[arg(required = true, num_args = 1..=2, value_name = "FILE")]
        files: Vec<PathBuf>,
        /// Output(s): .json (Lottie), .svg (SMIL), .png (one frame at --time), .gif or
        /// .apng (preview), .html (a self-contained page playing the Lottie in lottie-web
        /// beside the SMIL), or a directory (one PNG per frame).
        #[arg(short, long, required = true)]
        output: Vec<PathBuf>,
        /// Time of the frame written to a .png output, in seconds.
        #[arg(long, default_value_t = 0.0)]
        time: f64,
        /// A dotLottie theme written into the .lottie outputs: JSON, slot id → value
        /// (`{"leaf.fill": "#e4572e", "leaf.opacity": 0.5}`), for the grammar's `slots`.
        #[arg(long, value_name = "FILE")]
        theme: Option<PathBuf>,
        #[command(flatten)]
        run: RunArgs,
        #[command(flatten)]
        render: RenderArgs,
        #[command(flatten)]
        import: ImportArgs,
    },
    /// Data-driven transitions: new target values over time for tagged shapes, turned
    /// into an animation by a signal system (FIR, spring, …), written like `animate`.
    #[command(
        after_help = "Examples:\n  gmotion transitions chart.svg data.json -o chart.json\n  gmotion transitions chart.svg data.csv --system \"spring(0.5, 0.2)\" -o chart.gif"
    )]
    Transitions {
        /// The scene (SVG).
        scene: PathBuf,
        /// The targets (.json or .csv; see docs/transitions.md).
        targets: PathBuf,
        /// Output(s), as for `animate`.
        #[arg(short, long, required = true)]
        output: Vec<PathBuf>,
        /// The system every channel passes through, e.g. `spring(0.5, 0.2)` or
        /// `fir(bspline(3), 0.3)` (default: the file's `system`, else a critically damped
        /// spring).
        #[arg(long)]
        system: Option<String>,
        /// Frames per second (default: the file's `fps`, else 60).
        #[arg(long)]
        fps: Option<f64>,
        /// Length in seconds (default: the file's, else until every channel settles).
        #[arg(long)]
        duration: Option<f64>,
        /// Time of the frame written to a .png output, in seconds.
        #[arg(long, default_value_t = 0.0)]
        time: f64,
        #[command(flatten)]
        render: RenderArgs,
        #[command(flatten)]
        import: ImportArgs,
    },
    /// Parse and validate a grammar without rendering; with a scene (given, or named by
    /// the grammar's `scene`), also expand it and print rule, tag and expansion
    /// statistics.
    #[command(
        override_usage = "gmotion check [OPTIONS] <GRAMMAR> [SCENE]\n       gmotion check --shapes [--json] <SCENE>",
        after_help = "Examples:\n  gmotion check motion.gm art.svg\n  gmotion check --shapes art.svg                # tags, ids, boxes, centroids\n  gmotion check motion.gm --graph rules.svg      # the grammar graph"
    )]
    Check {
        /// `GRAMMAR [SCENE]`: the grammar (.gm), and the scene to expand it on, which
        /// overrides the grammar's `scene`. Told apart as for `animate`. With `--shapes`,
        /// a scene alone.
        #[arg(required = true, num_args = 1..=2, value_name = "FILE")]
        files: Vec<PathBuf>,
        /// Write the grammar graph: `.dot` (Graphviz) or `.svg` (a drawing; group grammars).
        #[arg(long)]
        graph: Option<PathBuf>,
        /// List the scene's units: tag and id, box, centroid (and a Lottie scene's layers).
        #[arg(long)]
        shapes: bool,
        /// With --shapes: print only the units, as JSON (`[{tag, id, z, bbox: [x, y, w, h],
        /// centroid: [x, y]}]`, as the studio's `/api/state` lists them).
        #[arg(long, requires = "shapes")]
        json: bool,
        #[command(flatten)]
        run: RunArgs,
        #[command(flatten)]
        import: ImportArgs,
    },
    /// Learn a grammar from a keyframed animation (a Lottie .json or .lottie, from After
    /// Effects or gmotion's own export): writes a still scene (the art at the reference
    /// frame, its layers' names as tags) and a timeslice grammar naming it, such that
    /// `gmotion animate LEARNED.gm` plays the animation again within the tolerance; the
    /// units of one tag that move alike up to a stagger share one rule set. Prints a
    /// report: each unit's error, the rules and what could not be explained.
    #[command(
        override_usage = "gmotion learn [OPTIONS] <ANIMATION> -o <LEARNED.gm>",
        after_help = "Examples:\n  gmotion learn intro.json -o intro.gm              # intro.gm + intro.json beside it\n  gmotion learn intro.json -o intro.gm --scene art.svg --report report.txt\n  gmotion animate intro.gm -o again.json"
    )]
    Learn {
        /// The animation: a Lottie file (.json) or a dotLottie package (.lottie).
        #[arg(value_name = "ANIMATION")]
        input: PathBuf,
        /// The grammar to write (.gm).
        #[arg(short, long, value_name = "LEARNED.gm")]
        output: PathBuf,
        /// The still scene to write: a Lottie without animation (.json, the default: the
        /// grammar's name with .json) or an SVG (.svg).
        #[arg(long, value_name = "STILL")]
        scene: Option<PathBuf>,
        /// The largest error accepted, in pixels of the composition.
        #[arg(long, default_value_t = 0.25, value_name = "PX")]
        tolerance: f64,
        /// Where to write the report: a file, or `-` for standard output (the default).
        #[arg(long, value_name = "FILE|-")]
        report: Option<PathBuf>,
    },
    /// Render N variations of a grammar (seeds S, S+1, …) at one instant: a contact sheet
    /// (`.png`, each frame labelled with its seed) or a folder with one `seed_S.png` each.
    #[command(
        override_usage = "gmotion variations [OPTIONS] --count <N> -o <OUT> [SCENE] <GRAMMAR>",
        after_help = "Examples:\n  gmotion variations art.svg motion.gm --count 12 -o sheet.png\n  gmotion variations art.svg motion.gm --count 4 --seed-start 40 -o seeds/"
    )]
    Variations {
        /// `[SCENE] GRAMMAR`, as for `animate`.
        #[arg(required = true, num_args = 1..=2, value_name = "FILE")]
        files: Vec<PathBuf>,
        /// How many seeds.
        #[arg(long)]
        count: u32,
        /// The first seed.
        #[arg(long, default_value_t = 0)]
        seed_start: u64,
        /// A `.png` contact sheet, a `.lottie` package (one animation `seed_S` per seed),
        /// or a folder (one PNG per seed).
        #[arg(short, long)]
        output: PathBuf,
        /// The instant shown, in seconds (default: half the duration).
        #[arg(long)]
        time: Option<f64>,
        /// Width in pixels of each frame.
        #[arg(long, default_value_t = 240)]
        width: u32,
        /// With a .lottie output: a dotLottie theme applying to every seed's animation
        /// (JSON, slot id → value, as for `animate --theme`).
        #[arg(long, value_name = "FILE")]
        theme: Option<PathBuf>,
        #[command(flatten)]
        import: ImportArgs,
    },
    /// Open the studio: a local web editor (preview, timeline, layer tree, grammar with
    /// live diagnostics, rule creation, variations, export) served on 127.0.0.1; see
    /// docs/studio.md. Prints `studio: URL` first and runs until interrupted.
    #[command(
        override_usage = "gmotion studio [OPTIONS] [SCENE] <GRAMMAR>",
        after_help = "Examples:\n  gmotion studio art.svg motion.gm\n  gmotion studio motion.gm --port 8080 --no-open"
    )]
    Studio {
        /// `[SCENE] GRAMMAR`, as for `animate`.
        #[arg(required = true, num_args = 1..=2, value_name = "FILE")]
        files: Vec<PathBuf>,
        /// Port on 127.0.0.1 (0: any free port).
        #[arg(long, default_value_t = 0)]
        port: u16,
        /// Do not open a browser.
        #[arg(long)]
        no_open: bool,
        /// Start from an animation instead of a blank grammar: learn GRAMMAR (which must not
        /// exist yet, or be empty) and its still scene from ANIMATION, as `gmotion learn`
        /// does, then open them.
        #[arg(long, value_name = "ANIMATION")]
        learn: Option<PathBuf>,
        #[command(flatten)]
        run: RunArgs,
        #[command(flatten)]
        import: ImportArgs,
    },
    /// Print a shell completion script for bash, zsh, fish, elvish or PowerShell.
    #[command(
        after_help = "Examples:\n  gmotion completions bash > ~/.local/share/bash-completion/completions/gmotion\n  gmotion completions zsh > ~/.zfunc/_gmotion\n  gmotion completions fish > ~/.config/fish/completions/gmotion.fish"
    )]
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
    /// Print the manual page (roff).
    #[command(
        after_help = "Examples:\n  gmotion man | man -l -\n  gmotion man > /usr/local/share/man/man1/gmotion.1"
    )]
    Man,
}

impl Command {
    /// The files the command reads and the outputs it writes, where `-` may stand for
    /// standard input or output.
    fn io_paths(&mut self) -> (Vec<&mut PathBuf>, Vec<&mut PathBuf>) {
        match self {
            Command::Convert { inputs, output, .. } => {
                (inputs.iter_mut().collect(), output.iter_mut().collect())
            }
            Command::Animate { files, output, .. } => {
                (files.iter_mut().collect(), output.iter_mut().collect())
            }
            Command::Transitions {
                scene,
                targets,
                output,
                ..
            } => (vec![scene, targets], output.iter_mut().collect()),
            Command::Check { files, graph, .. } => {
                (files.iter_mut().collect(), graph.iter_mut().collect())
            }
            Command::Variations { files, output, .. } => (files.iter_mut().collect(), vec![output]),
            // Its three outputs go to files it names itself (the report's `-` is its own).
            Command::Learn { .. }
            | Command::Demo { .. }
            | Command::Studio { .. }
            | Command::Completions { .. }
            | Command::Man => (Vec::new(), Vec::new()),
        }
    }
}

/// `--format`: the extension an output to standard output would have.
#[derive(ValueEnum, Clone, Copy, Debug)]
enum FormatArg {
    /// Lottie JSON.
    Json,
    /// Animated SVG (SMIL), or a still SVG for `convert`.
    Svg,
    /// One PNG frame.
    Png,
    /// Animated GIF.
    Gif,
    /// Animated PNG.
    Apng,
    /// A self-contained HTML preview.
    Html,
}

impl FormatArg {
    fn extension(self) -> &'static str {
        match self {
            FormatArg::Json => "json",
            FormatArg::Svg => "svg",
            FormatArg::Png => "png",
            FormatArg::Gif => "gif",
            FormatArg::Apng => "apng",
            FormatArg::Html => "html",
        }
    }
}

/// Options of the grammar run.
#[derive(Args, Debug, Clone)]
struct RunArgs {
    /// Random seed (overrides the grammar's `seed`).
    #[arg(long)]
    seed: Option<u64>,
    /// Frames per second (overrides the grammar's `fps`).
    #[arg(long)]
    fps: Option<f64>,
    /// Stop expansion after this many steps with an error (overrides `max_steps`).
    #[arg(long)]
    max_steps: Option<usize>,
    /// Slice tags written as named Lottie markers, comma-separated, e.g. `in,hold,out`
    /// (overrides the grammar's `markers`).
    #[arg(long, value_delimiter = ',', value_name = "TAGS")]
    markers: Option<Vec<String>>,
}

/// Options of rendered and exported output.
#[derive(Args, Debug, Clone)]
struct RenderArgs {
    /// Width in pixels of every output (Lottie, SVG, PNG, GIF, APNG, frames); without
    /// --height the height follows the scene's aspect ratio. With --height the art is
    /// scaled to fit and centred. Either flag replaces the grammar's `width` and `height`.
    #[arg(long)]
    width: Option<u32>,
    /// Height in pixels of every output (see --width).
    #[arg(long)]
    height: Option<u32>,
    /// Error bound in canvas pixels when an exporter must bake motion into keyframes.
    #[arg(long, default_value_t = DEFAULT_TOLERANCE)]
    tolerance: f64,
    #[command(flatten)]
    video: VideoArgs,
    #[command(flatten)]
    lottie: LottieArgs,
}

/// Options of Lottie outputs (`.json`, `.lottie`, and the `.html` page's Lottie).
#[derive(Args, Debug, Clone, Default)]
struct LottieArgs {
    /// Write runs of plain shape layers as one layer of named groups: the same picture,
    /// faster in web players, but one layer where After Effects would show many.
    #[arg(long)]
    pack: bool,
}

/// Options of video outputs (`.mp4`, `.webm`, `.mov`).
#[derive(Args, Debug, Clone, Default)]
struct VideoArgs {
    /// The colour video frames are drawn on, `#rrggbb` or a CSS name (default white).
    #[arg(long, value_name = "COLOR")]
    background: Option<String>,
    /// Keep the transparency in `.webm` (VP9 with alpha) and `.mov` (ProRes 4444) video.
    #[arg(long)]
    transparent: bool,
}

/// The output size of `convert`, which has no grammar and bakes no motion (so neither
/// the grammar's size nor `--tolerance` applies).
#[derive(Args, Debug, Clone)]
struct SizeArgs {
    /// Width in pixels of every output; without --height the height follows the
    /// picture's aspect ratio. With --height the art is scaled to fit and centred.
    #[arg(long)]
    width: Option<u32>,
    /// Height in pixels of every output (see --width).
    #[arg(long)]
    height: Option<u32>,
    #[command(flatten)]
    video: VideoArgs,
    #[command(flatten)]
    lottie: LottieArgs,
}

impl SizeArgs {
    /// As [`RenderArgs`] with the default tolerance, which a still never uses.
    fn render(&self) -> RenderArgs {
        RenderArgs {
            width: self.width,
            height: self.height,
            tolerance: DEFAULT_TOLERANCE,
            video: self.video.clone(),
            lottie: self.lottie.clone(),
        }
    }
}

/// `--tolerance`'s default, in canvas pixels.
const DEFAULT_TOLERANCE: f64 = 0.25;

/// How SVG elements become tagged shapes.
#[derive(Args, Debug, Clone)]
struct ImportArgs {
    /// Where tags come from (overrides a grammar's `tag_from`; default `auto`).
    #[arg(long, value_enum)]
    tag_from: Option<TagFromArg>,
    /// What the animated units are (overrides a grammar's `units`; default `auto`).
    #[arg(long, value_enum)]
    units: Option<UnitsArg>,
    /// SVG scenes: how deep a group must sit to become a unit; 2 makes the groups inside
    /// the top-level layers the units (overrides a grammar's `unit_depth`; default 1).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    unit_depth: Option<u32>,
    /// SVG scenes: a tag map giving elements tags and units by CSS-like selector, one
    /// `SELECTOR -> TAG [unit]` per line (overrides a grammar's `tags`; see docs/cli.md).
    #[arg(long, value_name = "FILE")]
    tags: Option<PathBuf>,
    /// Lottie scenes: the time, in seconds from the composition's start, at which units
    /// are measured (default 0, the first frame).
    #[arg(long, value_name = "SECONDS")]
    reference_time: Option<f64>,
    /// dotLottie scenes (.lottie): the id of the animation to read (default: the
    /// package's initial animation, else its first; `check` lists them).
    #[arg(long, value_name = "ID")]
    animation: Option<String>,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
enum TagFromArg {
    /// data-tag, then the first class that is not a generated style class (st0, cls-1,
    /// fil0), then inkscape:label, then the enclosing layer's id.
    Auto,
    /// Only `data-tag`.
    DataTag,
    /// Only the first `class`, generated style classes (st0) included.
    Class,
    /// Only `inkscape:label`.
    Label,
    /// Only the enclosing layer's (group's) id.
    Layer,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
enum UnitsArg {
    /// Tagged groups move as one; other paths move alone (Lottie: the layers).
    Auto,
    /// Every path is its own unit (SVG only).
    Paths,
    /// Tagged groups are the units (Lottie: each top-level group of a shape layer).
    Groups,
}

/// Parses arguments, runs the command, prints errors; the exit code says how it went
/// (clap's own exit code, 2, for a bad command line).
fn main() -> ExitCode {
    let mut cli = Cli::parse();
    report::set_quiet(cli.quiet);
    match cli.command {
        Command::Completions { shell } => {
            clap_complete::generate(
                shell,
                &mut Cli::command(),
                "gmotion",
                &mut std::io::stdout(),
            );
            return ExitCode::SUCCESS;
        }
        Command::Man => {
            return match clap_mangen::Man::new(Cli::command()).render(&mut std::io::stdout()) {
                Ok(()) => ExitCode::SUCCESS,
                // `gmotion man | head` is not an error.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("standard output: cannot write: {e}");
                    ExitCode::FAILURE
                }
            };
        }
        _ => {}
    }
    guard::clean_up_on_signals();
    let limits = match gmotion_pipeline::Limits::parse(&cli.limits) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let given: Vec<PathBuf> = cli
        .command
        .io_paths()
        .1
        .iter()
        .map(|p| p.to_path_buf())
        .collect();
    let format = cli.format.map(FormatArg::extension);
    let (mut inputs, mut outputs) = cli.command.io_paths();
    let stdio = stdio::Stdio::prepare(&mut inputs, &mut outputs, format, limits.get("input-bytes"));
    let written: Vec<PathBuf> = outputs.iter().map(|p| p.to_path_buf()).collect();
    let batch =
        matches!(&cli.command, Command::Convert { inputs, .. } if commands::is_batch(inputs));
    let summary = !batch
        && !matches!(
            cli.command,
            Command::Check { .. }
                | Command::Demo { .. }
                | Command::Variations { .. }
                | Command::Learn { .. }
        );
    let fonts = gmotion_import_svg::fonts::FontOptions {
        dirs: cli.font_dirs,
        files: cli.font_files,
        default_family: cli.font_family,
    };
    if let Some(missing) = gmotion_import_svg::fonts::missing_files(&fonts).first() {
        eprintln!("{}: no such font file or folder", missing.display());
        return ExitCode::FAILURE;
    }
    let ctx = commands::Ctx {
        env: gmotion_pipeline::Env {
            limits,
            allow: cli.allow_paths,
            fonts,
            warn: |origin, warning| report::warn(origin, warning),
        },
        format,
    };
    let result = stdio.and_then(|stdio| {
        commands::run(cli.command, &ctx)?;
        stdio.finish()
    });
    match result {
        Ok(()) => {
            if summary {
                report::wrote(&given, &written);
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    #[test]
    fn the_limit_flag_names_every_limit() {
        let cmd = super::Cli::command();
        let flag = cmd
            .get_arguments()
            .find(|a| a.get_long() == Some("limit"))
            .expect("--limit");
        let help = flag
            .get_long_help()
            .or(flag.get_help())
            .expect("help")
            .to_string();
        for (name, _, _) in gmotion_pipeline::LIMITS {
            assert!(
                help.contains(name),
                "--limit's help does not name {name}: {help}"
            );
        }
    }
}
