//! The commands: load, run, write.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use gmotion::canvas::{MAX_OUTPUT_SIZE, OutputSize};
use gmotion::engine::expand::Expansion;
use gmotion::engine::{self, EngineError, RunOptions, Settings};
use gmotion::grammar::{self, ast::Grammar};
use gmotion::motion::Animation;
use gmotion::scene::Scene;
use gmotion::{TagFrom, Units, Warning};
use gmotion_export_raster as raster;
use gmotion_import_lottie as lottie_import;
use gmotion_import_svg::{self as svg_import, ImportOptions};
use gmotion_output::{self as output, Format, LottieSource};
use indicatif::{ProgressBar, ProgressStyle};

use super::guard::{self, Limits};
use super::output::{check_writable, write_atomic};
use super::report::{CliError, Result, engine_error};
use super::{Command, ImportArgs, RenderArgs, RunArgs, TagFromArg, UnitsArg};

/// What every command is run under: the limits and the file-access policy.
#[derive(Clone)]
pub struct Ctx {
    /// `--limit` applied to the defaults.
    pub limits: Limits,
    /// `--allow-path` folders.
    pub allow: Vec<PathBuf>,
    /// `--font-dir`, `--font-file`, `--font-family`.
    pub fonts: gmotion_import_svg::fonts::FontOptions,
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
        } => demo(&output, &example, list, ctx),
        Command::Convert {
            inputs,
            output,
            time,
            size,
            import,
        } => match (inputs.as_slice(), size.render()) {
            ([one], render) if !is_batch(&inputs) => {
                convert(one, &output, time, &render, &import, ctx)
            }
            (_, render) => convert_batch(&inputs, &output, time, &render, &import, ctx),
        },
        Command::Animate {
            files,
            output,
            time,
            run,
            render,
            import,
        } => {
            let (scene, grammar) = scene_and_grammar(&files, Order::SceneFirst)?;
            animate(scene, grammar, &output, time, &run, &render, &import, ctx)
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
        } => transitions(
            &scene,
            &targets,
            &output,
            system.as_deref(),
            fps,
            duration,
            time,
            &render,
            &import,
            ctx,
        ),
        Command::Studio {
            files,
            port,
            no_open,
            run,
            import,
        } => {
            let (scene, grammar) = scene_and_grammar(&files, Order::SceneFirst)?;
            studio(scene, grammar, port, no_open, &run, &import, ctx)
        }
        Command::Variations {
            files,
            count,
            seed_start,
            output,
            time,
            width,
            import,
        } => {
            let (scene, grammar) = scene_and_grammar(&files, Order::SceneFirst)?;
            let seeds = (0..u64::from(count)).map(|i| seed_start.saturating_add(i));
            variations(
                scene,
                grammar,
                seeds.collect(),
                &output,
                time,
                width,
                &import,
                ctx,
            )
        }
        Command::Check {
            files,
            graph,
            shapes,
            json,
            run,
            import,
        } => {
            if let [one] = files.as_slice()
                && shapes
                && kind_of(one) == Kind::Scene
            {
                let options = import_options(&import, None, ctx)?;
                let loaded = load_scene(one, &options, ctx)?;
                hint_tags(one, &options, &loaded, ctx);
                super::report::out(&shape_list(one, &loaded, json))?;
                return Ok(());
            }
            if json {
                let (scene, grammar) = scene_and_grammar(&files, Order::GrammarFirst)?;
                let (_, loaded) = load_grammar_and_scene(scene, grammar, &import, ctx)?;
                super::report::out(&shape_list(grammar, &loaded, true))?;
                return Ok(());
            }
            let (scene, grammar) = scene_and_grammar(&files, Order::GrammarFirst)?;
            check(grammar, scene, graph.as_deref(), shapes, &run, &import, ctx)
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

/// A file's kind by its extension (`.gm`; `.svg`, `.json`), else by its first character:
/// SVG starts with `<` and Lottie JSON with `{` (after a byte-order mark and blanks), a
/// grammar never does.
fn kind_of(path: &Path) -> Kind {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("gm") => return Kind::Grammar,
        Some("svg" | "json") => return Kind::Scene,
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

/// The scene (if given) and the grammar among one or two files, told apart by
/// [`kind_of`], else by `order`.
fn scene_and_grammar(files: &[PathBuf], order: Order) -> Result<(Option<&Path>, &Path)> {
    match files {
        [one] => {
            if kind_of(one) == Kind::Scene {
                return Err(CliError::msg(format!(
                    "{}: this is a scene; a grammar (.gm) is needed too, as in `gmotion animate [SCENE] GRAMMAR`",
                    one.display()
                )));
            }
            Ok((None, one))
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
            Ok(if grammar_first {
                (Some(b), a)
            } else {
                (Some(a), b)
            })
        }
        // clap takes one or two.
        _ => Err(CliError::msg(
            "expected a grammar and at most one scene".to_string(),
        )),
    }
}

/// The importer's options: the command line's, else the grammar's, else the defaults.
/// How to import a scene: as SVG, or as Lottie.
struct SceneOptions {
    svg: ImportOptions,
    lottie: lottie_import::ImportOptions,
    /// The grammar whose `reference_time` the Lottie import uses (its path, text and the
    /// directive's place), to blame for a time outside the composition.
    reference_from: Option<(PathBuf, String, gmotion::grammar::ast::Span)>,
}

fn import_options(
    a: &ImportArgs,
    grammar: Option<(&Path, &Loaded)>,
    ctx: &Ctx,
) -> Result<SceneOptions> {
    let default = Settings::default();
    let settings = grammar.map_or(&default, |(_, g)| &g.settings);
    let tag_from = a.tag_from.map(|t| match t {
        TagFromArg::Auto => TagFrom::Auto,
        TagFromArg::DataTag => TagFrom::DataTag,
        TagFromArg::Class => TagFrom::Class,
        TagFromArg::Label => TagFrom::Label,
        TagFromArg::Layer => TagFrom::Layer,
    });
    let units = a.units.map(|u| match u {
        UnitsArg::Auto => Units::Auto,
        UnitsArg::Paths => Units::Paths,
        UnitsArg::Groups => Units::Groups,
    });
    // The tag map: the command line's (relative to the working folder), else the
    // grammar's (relative to the grammar file, a missing one an error at the directive).
    let map_path = match (&a.tags, grammar, &settings.tags) {
        (Some(p), _, _) => Some(p.clone()),
        (None, Some((grammar_path, g)), Some((name, span))) => {
            let path = grammar_path.parent().unwrap_or(Path::new("")).join(name);
            if !path.exists() {
                let e = EngineError::at(
                    *span,
                    format!("tag map `{name}` not found (looked for {})", path.display()),
                );
                return Err(engine_error(grammar_path, &g.src, &e));
            }
            Some(path)
        }
        _ => None,
    };
    let tag_map = map_path
        .map(|p| read_tag_map(&p, ctx).map(std::sync::Arc::new))
        .transpose()?;
    let units = units.or(settings.units).unwrap_or_default();
    Ok(SceneOptions {
        svg: ImportOptions {
            tag_from: tag_from.or(settings.tag_from).unwrap_or_default(),
            units,
            unit_depth: a
                .unit_depth
                .map(|d| d as usize)
                .or(settings.unit_depth)
                .unwrap_or(1),
            tag_map,
        },
        lottie: lottie_import::ImportOptions {
            time: a
                .reference_time
                .or(settings.reference_time.as_ref().map(|(t, _)| *t)),
            max_image_pixels: ctx.limits.get("image-pixels"),
            allowed_dirs: ctx.allow.clone(),
            max_file_bytes: ctx.limits.get("input-bytes"),
            units: match units {
                Units::Groups => lottie_import::Units::Groups,
                Units::Auto | Units::Paths => lottie_import::Units::Layers,
            },
            fonts: Some({
                let fonts = ctx.fonts.clone();
                lottie_import::fonts::SystemFonts::new(move || svg_import::fonts::database(&fonts))
            }),
        },
        reference_from: match (a.reference_time, grammar, &settings.reference_time) {
            (None, Some((path, g)), Some((_, span))) => {
                Some((path.to_path_buf(), g.src.clone(), *span))
            }
            _ => None,
        },
    })
}

/// Reads and parses a tag map file.
fn read_tag_map(path: &Path, ctx: &Ctx) -> Result<svg_import::tagmap::TagMap> {
    let bytes = gmotion::input::read_regular(path, ctx.limits.get("input-bytes"))
        .map_err(|e| CliError::msg(format!("{}: cannot read tag map: {e}", path.display())))?;
    let text = gmotion::input::utf8_text(bytes).map_err(|e| {
        CliError::msg(format!(
            "{}:{e} (the tag map must be UTF-8)",
            path.display()
        ))
    })?;
    svg_import::tagmap::TagMap::parse(&text, &path.display().to_string())
        .map_err(|e| CliError::msg(format!("{e}")))
}

/// The size of every output: `--width`/`--height` if either is given, else the grammar's
/// `width`/`height` (see [`OutputSize`] for what one or both mean).
fn output_size(render: &RenderArgs, settings: &Settings) -> OutputSize {
    if render.width.is_some() || render.height.is_some() {
        OutputSize {
            width: render.width,
            height: render.height,
        }
    } else {
        OutputSize {
            width: settings.width,
            height: settings.height,
        }
    }
}

/// A scene, and the Lottie document it came from when it came from one.
struct LoadedScene {
    scene: Scene,
    source: Option<LottieSource>,
}

/// Whether a scene file is Lottie JSON: by its `.json` extension, else by starting with
/// `{` (an SVG starts with `<`).
fn is_lottie(path: &Path) -> bool {
    if let Some(ext) = path.extension().and_then(|e| e.to_str()) {
        if ext.eq_ignore_ascii_case("json") {
            return true;
        }
        if ext.eq_ignore_ascii_case("svg") || ext.eq_ignore_ascii_case("svgz") {
            return false;
        }
    }
    if !matches!(gmotion::input::irregular_kind(path), Ok(None)) {
        return false;
    }
    let mut head = [0u8; 64];
    let n = std::fs::File::open(path)
        .and_then(|mut f| std::io::Read::read(&mut f, &mut head))
        .unwrap_or(0);
    String::from_utf8_lossy(&head[..n])
        .trim_start_matches('\u{feff}')
        .trim_start()
        .starts_with('{')
}

fn load_scene(path: &Path, options: &SceneOptions, ctx: &Ctx) -> Result<LoadedScene> {
    if is_lottie(path) {
        // Selectors and group depth speak of SVG elements; a Lottie's units are its layers.
        if let Some(map) = &options.svg.tag_map {
            return Err(CliError::msg(format!(
                "{}: error: the tag map {} gives tags to SVG elements; a Lottie scene's units are its layers, tagged by their names",
                path.display(),
                map.source_name
            )));
        }
        if options.svg.units == Units::Paths {
            return Err(CliError::msg(format!(
                "{}: error: --units paths splits SVG groups into their paths; a Lottie scene's units are its layers, or with --units groups the top-level groups of its shape layers",
                path.display()
            )));
        }
        if options.svg.unit_depth != 1 {
            return Err(CliError::msg(format!(
                "{}: error: --unit-depth chooses SVG groups; a Lottie scene's units are its layers",
                path.display()
            )));
        }
        let imported = lottie_import::load(path, &options.lottie).map_err(|e| {
            match (&e, &options.reference_from) {
                (lottie_import::ImportError::ReferenceTime { .. }, Some((grammar, src, span))) => {
                    engine_error(grammar, src, &EngineError::at(*span, e.to_string()))
                }
                _ => CliError::msg(e.to_string()),
            }
        })?;
        for w in &imported.warnings {
            super::report::warn(path, w);
        }
        return Ok(LoadedScene {
            scene: imported.scene,
            source: Some(imported.source),
        });
    }
    let policy = ctx.limits.svg_policy(&ctx.allow, &ctx.fonts);
    let imported = svg_import::load_with(path, &options.svg, &policy)
        .map_err(|e| CliError::msg(e.to_string()))?;
    for w in &imported.warnings {
        super::report::warn(path, w);
    }
    Ok(LoadedScene {
        scene: imported.scene,
        source: None,
    })
}

/// Says which `--tag-from` would name an SVG scene's shapes better, when most of its tags
/// name nothing a designer chose (`st0`, `path`): `check` and `studio` ask, once, as finding
/// out imports the scene again under each other source.
fn hint_tags(path: &Path, options: &SceneOptions, loaded: &LoadedScene, ctx: &Ctx) {
    if loaded.source.is_some() {
        return; // a Lottie scene's tags are its layer names: `--tag-from` does not apply
    }
    let policy = ctx.limits.svg_policy(&ctx.allow, &ctx.fonts);
    if let Some(hint) = svg_import::tag_hint(path, &options.svg, &policy, &loaded.scene) {
        super::report::note(&format!("{}: hint: {hint}", path.display()));
    }
}

/// The units of a scene, one line each: tag and id, bounding box, centroid, the other tags
/// the unit answers to (ids, a tag map's), and for a Lottie scene the layers it moves.
/// With `json`, the units as the studio lists them instead, on one line.
fn shape_list(path: &Path, loaded: &LoadedScene, json: bool) -> String {
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
            guard::short(src.frame),
            (src.frame - src.document.ip) / src.document.fr
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

/// A grammar file, parsed, with its header read.
struct Loaded {
    src: String,
    grammar: Grammar,
    settings: Settings,
}

fn load_grammar(path: &Path, ctx: &Ctx) -> Result<Loaded> {
    let bytes = gmotion::input::read_regular(path, ctx.limits.get("input-bytes"))
        .map_err(|e| CliError::msg(format!("{}: cannot read grammar: {e}", path.display())))?;
    let src = gmotion::input::utf8_text(bytes).map_err(|e| {
        CliError::msg(format!(
            "{}:{e} (the grammar must be UTF-8)",
            path.display()
        ))
    })?;
    let grammar = grammar::parse(&src).map_err(|d| {
        CliError(
            d.render(&path.display().to_string(), &src)
                .trim_end()
                .to_string(),
        )
    })?;
    let settings =
        engine::settings::from_grammar(&grammar).map_err(|e| engine_error(path, &src, &e))?;
    // Every error of meaning at once, as the parser gives every syntax error.
    let errors = engine::check::static_errors(&grammar);
    if !errors.is_empty() {
        let mut text: Vec<String> = errors
            .iter()
            .map(|e| engine_error(path, &src, e).0)
            .collect();
        if errors.len() > 1 {
            text.push(format!("{} errors in {}", errors.len(), path.display()));
        }
        return Err(CliError(text.join("\n\n")));
    }
    Ok(Loaded {
        src,
        grammar,
        settings,
    })
}

/// The scene to use: `given` on the command line, else the grammar's `scene`, resolved
/// against the grammar file's folder (a missing file is an error at the directive).
fn scene_path(given: Option<&Path>, grammar_path: &Path, g: &Loaded) -> Result<Option<PathBuf>> {
    if let Some(p) = given {
        return Ok(Some(p.to_path_buf()));
    }
    let Some((name, span)) = &g.settings.scene else {
        return Ok(None);
    };
    let folder = grammar_path.parent().unwrap_or(Path::new(""));
    let path = folder.join(name);
    if !path.exists() {
        let e = EngineError::at(
            *span,
            format!(
                "scene file `{name}` not found (looked for {})",
                path.display()
            ),
        );
        return Err(engine_error(grammar_path, &g.src, &e));
    }
    Ok(Some(path))
}

/// The grammar run's options; `--fps` is checked here so the message names the flag.
fn run_options(r: &RunArgs, limits: &Limits) -> Result<RunOptions> {
    let steps = limits.get("steps");
    if let Some(m) = r.max_steps
        && m as u64 > steps
    {
        return Err(CliError::msg(format!(
            "--max-steps {m} is more than the limit of {steps} (raise it with --limit steps=N)"
        )));
    }
    if let Some(fps) = r.fps
        && !(fps.is_finite() && fps > 0.0)
    {
        return Err(CliError::msg(format!(
            "--fps must be a positive number, found {fps}"
        )));
    }
    Ok(RunOptions {
        seed: r.seed,
        fps: r.fps,
        max_steps: r.max_steps,
        max_pieces: Some(usize::try_from(limits.get("pieces")).unwrap_or(usize::MAX)),
    })
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

/// Writes `anim` to `out`; `shown` is the Lottie source of its scene, if any, and the
/// slices an HTML preview draws, if known.
fn write_animation(
    anim: &Animation,
    shown: (Option<&LottieSource>, Option<&Expansion>),
    out: &Path,
    time: f64,
    render: &RenderArgs,
    size: OutputSize,
    limits: &Limits,
) -> Result<()> {
    let opts = output::Options {
        tolerance: render.tolerance,
        size,
        time,
        play_svg: false,
        max_pixels: limits.get("pixels"),
        max_animation_pixels: limits.get("animation-pixels"),
    };
    let (source, timelines) = shown;
    if gmotion_studio::is_preview(out) {
        let warnings = gmotion_studio::write_preview(anim, source, timelines, out, &opts)
            .map_err(|e| CliError::msg(e.to_string()))?;
        print_warnings(out, &warnings);
        return Ok(());
    }
    let frames = matches!(
        Format::of(out).map_err(|e| CliError::msg(e.to_string()))?,
        Format::Frames | Format::Gif | Format::Apng
    );
    let pb = progress(if frames { anim.frame_count() } else { 0 }, "rendering");
    let warnings = output::write_over_source(anim, source, out, &opts, &|| pb.inc(1))
        .map_err(|e| CliError::msg(e.to_string()))?;
    pb.finish_and_clear();
    print_warnings(out, &warnings);
    Ok(())
}

fn validate_render(render: &RenderArgs) -> Result<()> {
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
        let frames = !gmotion_studio::is_preview(o)
            && Format::of(o).map_err(|e| CliError::msg(e.to_string()))? == Format::Frames;
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

/// Parses, expands and compiles; errors point into the grammar. Also returns the
/// grammar's header, which says how to write the outputs.
fn build(
    scene: Option<&Path>,
    grammar_path: &Path,
    run: &RunArgs,
    import: &ImportArgs,
    outputs: &[PathBuf],
    timelines: bool,
    ctx: &Ctx,
) -> Result<Built> {
    let g = load_grammar(grammar_path, ctx)?;
    let fps = run.fps.unwrap_or(g.settings.fps);
    ctx.limits.check_frames(
        g.settings.duration * fps,
        &format!(
            "{}: error: duration {}s at {} fps",
            grammar_path.display(),
            guard::short(g.settings.duration),
            guard::short(fps)
        ),
    )?;
    let steps = ctx.limits.get("steps");
    if run.max_steps.is_none() && g.settings.max_steps as u64 > steps {
        return Err(CliError::msg(format!(
            "{}: error: max_steps {} is more than the limit of {steps} (raise it with --limit steps=N)",
            grammar_path.display(),
            g.settings.max_steps
        )));
    }
    let Some(scene_path) = scene_path(scene, grammar_path, &g)? else {
        return Err(CliError::msg(format!(
            "{}: error: no scene to animate: give one on the command line (`gmotion animate SCENE GRAMMAR`) or name it in the grammar (`scene FILE`)",
            grammar_path.display()
        )));
    };
    check_outputs(outputs, &[&scene_path, grammar_path])?;
    let loaded = load_scene(
        &scene_path,
        &import_options(import, Some((grammar_path, &g)), ctx)?,
        ctx,
    )?;
    has_shapes(&loaded, &scene_path)?;
    // A Lottie scene lasts as long as its composition where the grammar does not say.
    if let Some(time) = loaded.scene.time
        && !(g.settings.duration_given && (g.settings.fps_given || run.fps.is_some()))
    {
        let duration = match g.settings.duration_given {
            true => g.settings.duration,
            false => time.duration,
        };
        let fps = run.fps.unwrap_or(if g.settings.fps_given {
            g.settings.fps
        } else {
            time.fps
        });
        ctx.limits.check_frames(
            duration * fps,
            &format!(
                "{}: error: the composition's duration {}s at {} fps",
                scene_path.display(),
                guard::short(duration),
                guard::short(fps)
            ),
        )?;
    }
    let opts = run_options(run, &ctx.limits)?;
    // The preview's timeline picture: the slices, which the run does not keep.
    let timelines = timelines
        .then(|| engine::timelines(&loaded.scene, &g.grammar, &opts).ok())
        .flatten();
    let (anim, stats) = engine::run(loaded.scene, &g.grammar, &opts)
        .map_err(|e| engine_error(grammar_path, &g.src, &e))?;
    for w in &stats.warnings {
        super::report::warn(grammar_path, w);
    }
    Ok(Built {
        anim,
        settings: g.settings,
        source: loaded.source,
        timelines,
    })
}

/// What [`build`] makes.
struct Built {
    anim: Animation,
    settings: Settings,
    source: Option<LottieSource>,
    /// Every shape's final slices, when an HTML preview is written.
    timelines: Option<Expansion>,
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

/// The grammar, and the scene as `animate` finds it (given, else the grammar's `scene`).
fn load_grammar_and_scene(
    scene: Option<&Path>,
    grammar_path: &Path,
    import: &ImportArgs,
    ctx: &Ctx,
) -> Result<(Loaded, LoadedScene)> {
    let g = load_grammar(grammar_path, ctx)?;
    let Some(path) = scene_path(scene, grammar_path, &g)? else {
        return Err(CliError::msg(format!(
            "{}: error: no scene: give one on the command line or name it in the grammar (`scene FILE`)",
            grammar_path.display()
        )));
    };
    let loaded = load_scene(
        &path,
        &import_options(import, Some((grammar_path, &g)), ctx)?,
        ctx,
    )?;
    Ok((g, loaded))
}

/// A scene to animate must draw something: said of the scene's file, not the grammar the
/// engine would blame (the engine refuses an empty scene too, for library callers).
fn has_shapes(loaded: &LoadedScene, path: &Path) -> Result<()> {
    if loaded.scene.shapes.is_empty() {
        return Err(CliError::msg(format!(
            "{}: error: the drawing has no visible shapes to animate (hidden, empty and zero-size elements draw nothing)",
            path.display()
        )));
    }
    Ok(())
}

/// `gmotion studio`: loads the scene as `animate` does (a grammar that does not parse is
/// opened anyway when the scene is given, to be fixed in the studio) and serves.
fn studio(
    scene: Option<&Path>,
    grammar_path: &Path,
    port: u16,
    no_open: bool,
    run: &RunArgs,
    import: &ImportArgs,
    ctx: &Ctx,
) -> Result<()> {
    let loaded = match (
        load_grammar_and_scene(scene, grammar_path, import, ctx),
        scene,
    ) {
        (Ok((g, loaded)), _) => {
            // As `check` does: a scene whose tags look generated gets a hint on the
            // terminal the studio runs in.
            if let Some(path) = scene_path(scene, grammar_path, &g)?
                && let Ok(options) = import_options(import, Some((grammar_path, &g)), ctx)
            {
                hint_tags(&path, &options, &loaded, ctx);
            }
            loaded
        }
        (Err(_), Some(s)) => {
            let options = import_options(import, None, ctx)?;
            let loaded = load_scene(s, &options, ctx)?;
            hint_tags(s, &options, &loaded, ctx);
            loaded
        }
        (Err(e), None) => return Err(e),
    };
    // An edit to the directives that decide the import brings the scene in again, as
    // `animate` would import it under the edited grammar.
    let loader = {
        let (scene, grammar_path, import) = (
            scene.map(Path::to_path_buf),
            grammar_path.to_path_buf(),
            import.clone(),
        );
        let ctx = ctx.clone();
        gmotion_studio::SceneLoader(Box::new(move |settings: &Settings| {
            let g = Loaded {
                src: String::new(),
                grammar: Grammar::default(),
                settings: settings.clone(),
            };
            let path = scene_path(scene.as_deref(), &grammar_path, &g)
                .map_err(|e| e.0)?
                .ok_or("no scene: the grammar names none")?;
            let opts = import_options(&import, Some((&grammar_path, &g)), &ctx).map_err(|e| e.0)?;
            load_scene(&path, &opts, &ctx)
                .map(|l| (l.scene, l.source))
                .map_err(|e| e.0)
        }))
    };
    let studio = gmotion_studio::Studio::bind(gmotion_studio::Config {
        grammar_path: grammar_path.to_path_buf(),
        scene: loaded.scene,
        source: loaded.source,
        loader: Some(loader),
        run: run_options(run, &ctx.limits)?,
        port,
    })
    .map_err(|e| CliError::msg(format!("studio: {e}")))?;
    let url = studio.url();
    {
        use std::io::Write;
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "studio: {url}");
        let _ = out.flush();
    }
    if !no_open {
        gmotion_studio::open_browser(&url);
    }
    studio
        .serve()
        .map_err(|e| CliError::msg(format!("studio: {e}")))
}

/// `gmotion variations`: the grammar run once per seed, each run's frame at `time`, as a
/// labelled contact sheet or a folder of `seed_S.png`.
fn variations(
    scene: Option<&Path>,
    grammar_path: &Path,
    seeds: Vec<u64>,
    out: &Path,
    time: Option<f64>,
    width: u32,
    import: &ImportArgs,
    ctx: &Ctx,
) -> Result<()> {
    use rayon::prelude::*;
    if seeds.is_empty() || width == 0 {
        return Err(CliError::msg("--count and --width must be at least 1"));
    }
    let sheet = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    guard::check_not_input(&[out], &[grammar_path])?;
    let (g, loaded) = load_grammar_and_scene(scene, grammar_path, import, ctx)?;
    if let Some(path) = scene_path(scene, grammar_path, &g)? {
        has_shapes(&loaded, &path)?;
    }
    let t = time.unwrap_or(g.settings.duration / 2.0);
    if !(t.is_finite() && (0.0..=g.settings.duration).contains(&t)) {
        return Err(CliError::msg(format!(
            "--time must lie within the animation, 0..{}s, found {t}",
            g.settings.duration
        )));
    }
    let size = OutputSize {
        width: Some(width),
        height: None,
    };
    let frames = seeds
        .par_iter()
        .map(|&seed| {
            let opts = RunOptions {
                seed: Some(seed),
                ..RunOptions::default()
            };
            let (anim, _) = engine::run(loaded.scene.clone(), &g.grammar, &opts)
                .map_err(|e| engine_error(grammar_path, &g.src, &e))?;
            let svg = gmotion_export_svg::frame::frame_svg(&anim, t);
            raster::render_limited(&svg, size, ctx.limits.get("pixels"))
                .map(|p| (seed, p))
                .map_err(|e| CliError::msg(format!("seed {seed}: {e}")))
        })
        .collect::<Result<Vec<_>>>()?;
    let save = |pm: &raster::Pixmap, path: &Path| {
        raster::save_png(pm, path).map_err(|e| CliError::msg(e.to_string()))
    };
    if sheet {
        let pm = super::sheet::contact_sheet(&frames)
            .ok_or_else(|| CliError::msg(format!("{}: the sheet is too large", out.display())))?;
        raster::check_pixels(pm.width(), pm.height(), ctx.limits.get("pixels"))
            .map_err(|e| CliError::msg(e.to_string()))?;
        save(&pm, out)?;
    } else {
        create_dir(out)?;
        let paths: Vec<PathBuf> = frames
            .iter()
            .map(|(seed, _)| out.join(format!("seed_{seed}.png")))
            .collect();
        let mut next = frames.iter();
        write_all(&paths, |p| {
            next.next().map_or(Ok(()), |(_, pm)| save(pm, p))
        })?;
    }
    super::report::note(&format!(
        "wrote {} ({} seeds from {} at {}s)",
        out.display(),
        frames.len(),
        frames[0].0,
        guard::short(t)
    ));
    Ok(())
}

fn animate(
    scene: Option<&Path>,
    grammar: &Path,
    outputs: &[PathBuf],
    time: f64,
    run: &RunArgs,
    render: &RenderArgs,
    import: &ImportArgs,
    ctx: &Ctx,
) -> Result<()> {
    validate_render(render)?;
    // The tag map is read too: an output must not overwrite it.
    let inputs: Vec<&Path> = scene
        .into_iter()
        .chain([grammar])
        .chain(import.tags.as_deref())
        .collect();
    check_outputs(outputs, &inputs)?;
    let previews = outputs.iter().any(|o| gmotion_studio::is_preview(o));
    let b = build(scene, grammar, run, import, outputs, previews, ctx)?;
    let size = output_size(render, &b.settings);
    let written = write_all(outputs, |o| {
        let shown = (b.source.as_ref(), b.timelines.as_ref());
        write_animation(&b.anim, shown, o, time, render, size, &ctx.limits)
    });
    // The process ends here, and the kernel takes its memory back at once: freeing the
    // scene and every track piece by piece first took milliseconds on a large animation.
    std::mem::forget(b);
    written
}

fn convert(
    input: &Path,
    outputs: &[PathBuf],
    time: Option<f64>,
    render: &RenderArgs,
    import: &ImportArgs,
    ctx: &Ctx,
) -> Result<()> {
    convert_staged(input, outputs, time, render, import, ctx, true)
}

/// [`convert`]; `staged`: the outputs land together (the one staging of the process), else
/// each on its own (a batch converts files in parallel, each with one output).
fn convert_staged(
    input: &Path,
    outputs: &[PathBuf],
    time: Option<f64>,
    render: &RenderArgs,
    import: &ImportArgs,
    ctx: &Ctx,
    staged: bool,
) -> Result<()> {
    validate_render(render)?;
    let outs: Vec<&Path> = outputs.iter().map(PathBuf::as_path).collect();
    let inputs: Vec<&Path> = [input].into_iter().chain(import.tags.as_deref()).collect();
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
    let loaded = load_scene(input, &import_options(import, None, ctx)?, ctx)?;
    // Played outputs draw every frame: a `.svg` without `--time` too.
    let played = |o: &PathBuf| match Format::of(o) {
        Ok(Format::Svg) => time.is_none(),
        Ok(f) => !f.is_still(),
        Err(_) => true,
    };
    if let Some(src) = &loaded.source
        && outputs.iter().any(played)
    {
        ctx.limits.check_frames(
            src.duration() * src.fps(),
            &format!(
                "{}: error: {}s at {} fps",
                input.display(),
                guard::short(src.duration()),
                guard::short(src.fps())
            ),
        )?;
    }
    let size = output_size(render, &settings);
    let opts = output::Options {
        tolerance: render.tolerance,
        size,
        time: time.unwrap_or(0.0),
        play_svg: time.is_none(),
        max_pixels: ctx.limits.get("pixels"),
        max_animation_pixels: ctx.limits.get("animation-pixels"),
    };
    let write = |out: &Path| {
        let warnings =
            output::write_still_over_source(&loaded.scene, loaded.source.as_ref(), out, &opts)
                .map_err(|e| CliError::msg(e.to_string()))?;
        print_warnings(out, &warnings);
        Ok(())
    };
    if staged {
        write_all(outputs, write)
    } else {
        outputs.iter().try_for_each(|o| write(o))
    }
}

/// Whether `convert`'s inputs ask for a batch: several, or a folder.
pub fn is_batch(inputs: &[PathBuf]) -> bool {
    inputs.len() > 1 || inputs.iter().any(|p| p.is_dir())
}

/// Converts several files (or the SVG and Lottie files of folders) into one output folder,
/// in parallel: `DIR/NAME.EXT` each, `EXT` from `--format` (`json` by default). Every file
/// is tried; each failure is printed with its file, then one line says what was done.
fn convert_batch(
    inputs: &[PathBuf],
    outputs: &[PathBuf],
    time: Option<f64>,
    render: &RenderArgs,
    import: &ImportArgs,
    ctx: &Ctx,
) -> Result<()> {
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
            convert_staged(f, &[out], time, render, import, ctx, false)
                .err()
                .map(|e| e.0)
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
        super::report::note(&line);
        Ok(())
    } else {
        Err(CliError(line))
    }
}

fn check(
    grammar_path: &Path,
    scene: Option<&Path>,
    graph: Option<&Path>,
    shapes: bool,
    run: &RunArgs,
    import: &ImportArgs,
    ctx: &Ctx,
) -> Result<()> {
    let loaded = load_grammar(grammar_path, ctx)?;
    let path = scene_path(scene, grammar_path, &loaded)?;
    if let Some(out) = graph {
        let inputs: Vec<&Path> = path.as_deref().into_iter().chain([grammar_path]).collect();
        guard::check_not_input(&[out], &inputs)?;
        guard::check_output_kind(out, false)?;
        check_writable(out)?;
    }
    let scene = path
        .as_ref()
        .map(|p| {
            let options = import_options(import, Some((grammar_path, &loaded)), ctx)?;
            let scene = load_scene(p, &options, ctx)?;
            hint_tags(p, &options, &scene, ctx);
            Ok::<_, CliError>(scene)
        })
        .transpose()?;
    let g = &loaded.grammar;
    let report = engine::check::check(
        g,
        scene.as_ref().map(|s| &s.scene),
        &run_options(run, &ctx.limits)?,
    )
    .map_err(|e| engine_error(grammar_path, &loaded.src, &e))?;
    for w in &report.warnings {
        super::report::warn(grammar_path, w);
    }
    super::report::out(&report.text)?;
    if shapes && let (Some(p), Some(s)) = (&path, &scene) {
        super::report::out(&shape_list(p, s, false))?;
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

#[allow(clippy::too_many_arguments)]
fn transitions(
    scene: &Path,
    targets: &Path,
    outputs: &[PathBuf],
    system: Option<&str>,
    fps: Option<f64>,
    duration: Option<f64>,
    time: f64,
    render: &RenderArgs,
    import: &ImportArgs,
    ctx: &Ctx,
) -> Result<()> {
    validate_render(render)?;
    if let Some(fps) = fps
        && !(fps.is_finite() && fps > 0.0)
    {
        return Err(CliError::msg(format!(
            "--fps must be a positive number, found {fps}"
        )));
    }
    if let Some(d) = duration
        && !(d.is_finite() && d > 0.0)
    {
        return Err(CliError::msg(format!(
            "--duration must be a positive number of seconds, found {d}"
        )));
    }
    check_outputs(outputs, &[scene, targets])?;
    let spec = system
        .map(|s| {
            gmotion::signals::smooth::SmoothSpec::parse(s)
                .map_err(|e| CliError::msg(format!("--system: {e}")))
        })
        .transpose()?;
    let t = gmotion::transitions::targets::Targets::load(targets)
        .map_err(|e| CliError::msg(e.to_string()))?;
    let settings = Settings::default();
    let scene = load_scene(scene, &import_options(import, None, ctx)?, ctx)?.scene;
    let system = t.default_system(spec);
    let fps = t.frame_rate(fps);
    if let Some(d) = duration {
        ctx.limits
            .check_frames(d * fps, &format!("--duration {d}s at {fps} fps"))?;
    }
    // The last target (or the file's own duration) sets how long the animation runs.
    let last = t.end();
    if duration.is_none() {
        ctx.limits.check_frames(
            last * fps,
            &format!(
                "{}: error: targets up to {}s at {} fps",
                targets.display(),
                guard::short(last),
                guard::short(fps)
            ),
        )?;
    }
    let anim =
        gmotion::transitions::run(&scene, &t, &system, fps, duration).map_err(|e| match e {
            // A target naming a missing tag is an error in the targets file: say which.
            gmotion::transitions::TransitionError::Shape { .. } => {
                CliError::msg(format!("{}: {e}", targets.display()))
            }
            e => CliError::msg(e.to_string()),
        })?;
    ctx.limits.check_frames(
        anim.duration * anim.fps,
        &format!(
            "{}: the targets' {}s at {fps} fps",
            targets.display(),
            anim.duration
        ),
    )?;
    let size = output_size(render, &settings);
    write_all(outputs, |o| {
        write_animation(&anim, (None, None), o, time, render, size, &ctx.limits)
    })
}

/// Runs a bundled example (`--list`: names them): its files are written to `out/source/`
/// and its outputs beside.
fn demo(out: &Path, example: &str, list: bool, ctx: &Ctx) -> Result<()> {
    use super::examples::{EXAMPLES, Example, Kind};
    if list {
        let width = EXAMPLES.iter().map(|e| e.name.len()).max().unwrap_or(0);
        let lines: Vec<String> = EXAMPLES
            .iter()
            .map(|e| format!("{:width$}  {}\n", e.name, e.summary()))
            .collect();
        return super::report::out(&lines.concat());
    }
    let Some(e) = Example::named(example) else {
        let names: Vec<&str> = EXAMPLES.iter().map(|e| e.name).collect();
        let hint = gmotion::grammar::diagnostics::did_you_mean(example, names.iter().copied())
            .map(|n| format!(" (did you mean `{n}`?)"))
            .unwrap_or_default();
        return Err(CliError::msg(format!(
            "no bundled example `{example}`{hint}; there are: {}",
            names.join(", ")
        )));
    };
    create_dir(out)?;
    let sources = out.join("source");
    create_dir(&sources)?;
    for (name, bytes) in e.files {
        write_atomic(&sources.join(name), bytes)?;
    }
    let scene = sources.join(e.files[0].0);
    let given = sources.join(e.files[1].0);
    let run = RunArgs {
        seed: None,
        fps: None,
        max_steps: None,
    };
    let import = ImportArgs {
        tag_from: None,
        units: None,
        unit_depth: None,
        tags: None,
        reference_time: None,
    };
    let render = RenderArgs {
        width: None,
        height: None,
        tolerance: super::DEFAULT_TOLERANCE,
    };
    let names = [
        "frames".to_string(),
        format!("{example}.gif"),
        format!("{example}.json"),
        format!("{example}.svg"),
        "preview.html".to_string(),
    ];
    let outputs: Vec<PathBuf> = names.iter().map(|n| out.join(n)).collect();
    if e.kind == Kind::Transitions {
        transitions(
            &scene, &given, &outputs, None, None, None, 0.0, &render, &import, ctx,
        )?;
        let frames = raster::check_frame_folder(&outputs[0]).map_or(0, |f| f.len());
        return demo_written(out, example, frames);
    }
    let Built {
        anim,
        settings,
        source,
        timelines,
    } = build(Some(&scene), &given, &run, &import, &[], true, ctx)?;
    let size = output_size(&render, &settings);
    for o in &outputs {
        write_animation(
            &anim,
            (source.as_ref(), timelines.as_ref()),
            o,
            0.0,
            &render,
            size,
            &ctx.limits,
        )?;
    }
    demo_written(out, example, anim.frame_count())
}

/// What `demo` wrote, and how to look at it.
fn demo_written(out: &Path, example: &str, frames: usize) -> Result<()> {
    super::report::out(&format!(
        "wrote {0}/frames/ ({1} PNG frames), {0}/{2}.gif, {0}/{2}.json (Lottie), {0}/{2}.svg (SMIL), the example's files in {0}/source/\n\
         view: open {0}/preview.html in a browser (lottie-web beside the SMIL, all inside the file, no network)\n",
        out.display(),
        frames,
        example
    ))
}
