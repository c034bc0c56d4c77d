//! The commands: load, run, write.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use gmotion::engine::{self, RunOptions};
use gmotion::exporters::{frame, lottie, raster, smil};
use gmotion::grammar::{self, ast::Grammar};
use gmotion::importers::svg::{self as svg_import, ImportOptions, TagFrom, Units};
use gmotion::motion::Animation;
use gmotion::scene::Scene;
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use super::output::{Format, check_writable, write_atomic, write_dir};
use super::report::{CliError, Result, engine_error};
use super::{Command, ImportArgs, RenderArgs, RunArgs, TagFromArg, UnitsArg};

/// Runs one command.
pub fn run(cmd: Command) -> Result<()> {
    match cmd {
        Command::Demo { output, example } => demo(&output, &example),
        Command::Convert {
            input,
            output,
            render,
            import,
        } => convert(&input, &output, &render, &import),
        Command::Animate {
            scene,
            grammar,
            output,
            time,
            run,
            render,
            import,
        } => animate(&scene, &grammar, &output, time, &run, &render, &import),
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
        ),
        Command::Check {
            grammar,
            scene,
            graph,
            run,
            import,
        } => check(&grammar, scene.as_deref(), graph.as_deref(), &run, &import),
    }
}

fn import_options(a: &ImportArgs) -> ImportOptions {
    ImportOptions {
        tag_from: match a.tag_from {
            TagFromArg::Auto => TagFrom::Auto,
            TagFromArg::DataTag => TagFrom::DataTag,
            TagFromArg::Class => TagFrom::Class,
            TagFromArg::Label => TagFrom::Label,
            TagFromArg::Layer => TagFrom::Layer,
        },
        units: match a.units {
            UnitsArg::Auto => Units::Auto,
            UnitsArg::Paths => Units::Paths,
            UnitsArg::Groups => Units::Groups,
        },
    }
}

fn load_scene(path: &Path, a: &ImportArgs) -> Result<Scene> {
    let imported =
        svg_import::load(path, &import_options(a)).map_err(|e| CliError::msg(e.to_string()))?;
    for w in &imported.warnings {
        eprintln!("{}: warning: {w}", path.display());
    }
    Ok(imported.scene)
}

fn load_grammar(path: &Path) -> Result<(String, Grammar)> {
    let bytes = std::fs::read(path)
        .map_err(|e| CliError::msg(format!("{}: cannot read grammar: {e}", path.display())))?;
    let src = String::from_utf8(bytes).map_err(|e| {
        CliError::msg(format!(
            "{}: the grammar is not UTF-8 text (byte {})",
            path.display(),
            e.utf8_error().valid_up_to()
        ))
    })?;
    let g = grammar::parse(&src).map_err(|d| {
        CliError(
            d.render(&path.display().to_string(), &src)
                .trim_end()
                .to_string(),
        )
    })?;
    Ok((src, g))
}

fn run_options(r: &RunArgs) -> RunOptions {
    RunOptions {
        seed: r.seed,
        fps: r.fps,
        max_steps: r.max_steps,
    }
}

fn pixel_width(requested: Option<u32>, scene: &Scene) -> Result<u32> {
    let w = requested.unwrap_or_else(|| scene.width.round().max(1.0) as u32);
    if w == 0 || w > 16_384 {
        return Err(CliError::msg(format!(
            "--width must be between 1 and 16384, found {w}"
        )));
    }
    Ok(w)
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

/// Renders frames `0..n` in parallel (order and bytes do not depend on thread count).
fn render_frames(
    anim: &Animation,
    width: u32,
    what: &str,
) -> Result<Vec<resvg::tiny_skia::Pixmap>> {
    let n = anim.frame_count();
    let pb = progress(n, what);
    let sampler = anim.sampler();
    let frames: std::result::Result<Vec<_>, _> = (0..n)
        .into_par_iter()
        .map(|i| {
            let svg = frame::sampled_frame_svg(anim, &sampler, anim.frame_time(i));
            let r = raster::render(&svg, width);
            pb.inc(1);
            r
        })
        .collect();
    pb.finish_and_clear();
    frames.map_err(|e| CliError::msg(format!("rendering failed: {e}")))
}

fn png_bytes(p: &resvg::tiny_skia::Pixmap) -> Result<Vec<u8>> {
    p.encode_png()
        .map_err(|e| CliError::msg(format!("PNG encoding failed: {e}")))
}

fn print_warnings<W: std::fmt::Display>(out: &Path, warnings: &[W]) {
    for w in warnings {
        eprintln!("{}: warning: {w}", out.display());
    }
}

fn write_animation(anim: &Animation, out: &Path, time: f64, render: &RenderArgs) -> Result<()> {
    let width = pixel_width(render.width, &anim.scene)?;
    match Format::of(out)? {
        Format::Png => {
            if !time.is_finite() || time < 0.0 || time > anim.duration {
                return Err(CliError::msg(format!(
                    "--time must lie within the animation, 0..{}s, found {time}",
                    anim.duration
                )));
            }
            let svg = frame::frame_svg(anim, time);
            let pm = raster::render(&svg, width)
                .map_err(|e| CliError::msg(format!("rendering failed: {e}")))?;
            write_atomic(out, &png_bytes(&pm)?)
        }
        Format::Dir => {
            let frames = render_frames(anim, width, "rendering")?;
            let files: Result<Vec<_>> = frames
                .iter()
                .enumerate()
                .map(|(i, f)| Ok((format!("frame_{i:05}.png"), png_bytes(f)?)))
                .collect();
            write_dir(out, &files?)
        }
        Format::Gif => {
            let frames = render_frames(anim, width, "rendering")?;
            raster::write_gif(&frames, anim.fps, anim.looping, out)
                .map_err(|e| CliError::msg(format!("{}: {e}", out.display())))
        }
        Format::Apng => {
            let frames = render_frames(anim, width, "rendering")?;
            raster::write_apng(&frames, anim.fps, anim.looping, out)
                .map_err(|e| CliError::msg(format!("{}: {e}", out.display())))
        }
        Format::Lottie => {
            let opts = lottie::LottieOptions {
                tolerance: render.tolerance,
                ..Default::default()
            };
            let (json, warnings) = lottie::to_lottie(anim, &opts)
                .map_err(|e| CliError::msg(format!("{}: {e}", out.display())))?;
            print_warnings(out, &warnings);
            write_atomic(out, json.as_bytes())
        }
        Format::Svg => {
            let opts = smil::SmilOptions {
                tolerance: render.tolerance,
                ..Default::default()
            };
            let (svg, warnings) = smil::to_smil(anim, &opts)
                .map_err(|e| CliError::msg(format!("{}: {e}", out.display())))?;
            print_warnings(out, &warnings);
            write_atomic(out, svg.as_bytes())
        }
    }
}

fn validate_render(render: &RenderArgs) -> Result<()> {
    if !(render.tolerance.is_finite() && render.tolerance > 0.0) {
        return Err(CliError::msg(format!(
            "--tolerance must be a positive number of pixels, found {}",
            render.tolerance
        )));
    }
    Ok(())
}

/// Parses, expands and compiles; errors point into the grammar.
fn build(
    scene_path: &Path,
    grammar_path: &Path,
    run: &RunArgs,
    import: &ImportArgs,
) -> Result<Animation> {
    let (src, g) = load_grammar(grammar_path)?;
    let scene = load_scene(scene_path, import)?;
    let (anim, stats) = engine::run(scene, &g, &run_options(run))
        .map_err(|e| engine_error(grammar_path, &src, &e))?;
    for w in &stats.warnings {
        eprintln!("{}: warning: {w}", grammar_path.display());
    }
    Ok(anim)
}

fn animate(
    scene: &Path,
    grammar: &Path,
    outputs: &[PathBuf],
    time: f64,
    run: &RunArgs,
    render: &RenderArgs,
    import: &ImportArgs,
) -> Result<()> {
    validate_render(render)?;
    for o in outputs {
        Format::of(o)?;
        check_writable(o)?;
    }
    let anim = build(scene, grammar, run, import)?;
    for o in outputs {
        write_animation(&anim, o, time, render)?;
    }
    Ok(())
}

fn convert(
    input: &Path,
    outputs: &[PathBuf],
    render: &RenderArgs,
    import: &ImportArgs,
) -> Result<()> {
    validate_render(render)?;
    for o in outputs {
        check_writable(o)?;
    }
    let scene = load_scene(input, import)?;
    for out in outputs {
        match Format::of(out)? {
            Format::Png => {
                let width = pixel_width(render.width, &scene)?;
                let pm = raster::render(&frame::scene_svg(&scene), width)
                    .map_err(|e| CliError::msg(format!("rendering failed: {e}")))?;
                write_atomic(out, &png_bytes(&pm)?)?;
            }
            Format::Lottie => {
                let opts = lottie::LottieOptions {
                    tolerance: render.tolerance,
                    ..Default::default()
                };
                let (json, warnings) = lottie::still_to_lottie(&scene, &opts)
                    .map_err(|e| CliError::msg(format!("{}: {e}", out.display())))?;
                print_warnings(out, &warnings);
                write_atomic(out, json.as_bytes())?;
            }
            Format::Svg => write_atomic(out, frame::scene_svg(&scene).as_bytes())?,
            other => {
                return Err(CliError::msg(format!(
                    "{}: `convert` writes a still picture (.png, .json, .svg), not {other:?}",
                    out.display()
                )));
            }
        }
    }
    Ok(())
}

fn check(
    grammar_path: &Path,
    scene: Option<&Path>,
    graph: Option<&Path>,
    run: &RunArgs,
    import: &ImportArgs,
) -> Result<()> {
    let (src, g) = load_grammar(grammar_path)?;
    if let Some(out) = graph {
        check_writable(out)?;
    }
    let scene = scene.map(|p| load_scene(p, import)).transpose()?;
    let report = engine::check::check(&g, scene.as_ref(), &run_options(run))
        .map_err(|e| engine_error(grammar_path, &src, &e))?;
    print!("{}", report.text);
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
            (_, false) => engine::check::dot(&g),
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
    fps: f64,
    duration: Option<f64>,
    time: f64,
    render: &RenderArgs,
    import: &ImportArgs,
) -> Result<()> {
    validate_render(render)?;
    if !(fps.is_finite() && fps > 0.0) {
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
    for o in outputs {
        Format::of(o)?;
        check_writable(o)?;
    }
    let spec = system
        .map(|s| {
            gmotion::signals::smooth::SmoothSpec::parse(s)
                .map_err(|e| CliError::msg(format!("--system: {e}")))
        })
        .transpose()?;
    let t = gmotion::transitions::targets::Targets::load(targets)
        .map_err(|e| CliError::msg(e.to_string()))?;
    let scene = load_scene(scene, import)?;
    let system = t.default_system(spec);
    let anim =
        gmotion::transitions::run(&scene, &t, &system, fps, duration).map_err(|e| match e {
            // A target naming a missing tag is an error in the targets file: say which.
            gmotion::transitions::TransitionError::Shape { .. } => {
                CliError::msg(format!("{}: {e}", targets.display()))
            }
            e => CliError::msg(e.to_string()),
        })?;
    for o in outputs {
        write_animation(&anim, o, time, render)?;
    }
    Ok(())
}

/// The folder that holds the bundled examples.
fn grammars_dir() -> PathBuf {
    let here = PathBuf::from("grammars");
    if here.is_dir() {
        return here;
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("grammars")
}

fn demo(out: &Path, example: &str) -> Result<()> {
    let dir = grammars_dir();
    let grammar = dir.join(format!("{example}.gm"));
    let scene = dir.join(format!("{example}.svg"));
    if !grammar.is_file() {
        return Err(CliError::msg(format!(
            "no bundled example `{example}` ({} not found)",
            grammar.display()
        )));
    }
    std::fs::create_dir_all(out).map_err(|e| {
        CliError::msg(format!(
            "{}: cannot create output directory: {e}",
            out.display()
        ))
    })?;
    let run = RunArgs {
        seed: None,
        fps: None,
        max_steps: None,
    };
    let import = ImportArgs {
        tag_from: TagFromArg::Auto,
        units: UnitsArg::Auto,
    };
    let render = RenderArgs {
        width: None,
        tolerance: 0.25,
    };
    let anim = build(&scene, &grammar, &run, &import)?;
    let names = [
        "frames",
        &format!("{example}.gif"),
        &format!("{example}.json"),
        &format!("{example}.svg"),
    ];
    for n in names {
        write_animation(&anim, &out.join(n), 0.0, &render)?;
    }
    let json = std::fs::read_to_string(out.join(format!("{example}.json")))
        .map_err(|e| CliError::msg(format!("{}: {e}", out.display())))?;
    let html = viewer_html(example, &json);
    write_atomic(&out.join("view.html"), html.as_bytes())?;
    println!(
        "wrote {0}/frames/ ({1} PNG frames), {0}/{2}.gif, {0}/{2}.json (Lottie), {0}/{2}.svg (SMIL)\n\
         view: open {0}/{2}.svg in a browser (SMIL plays by itself); {0}/view.html plays the Lottie with lottie-web",
        out.display(),
        anim.frame_count(),
        example
    );
    Ok(())
}

/// A page that plays the Lottie beside the SMIL, for a quick look in a browser. The
/// Lottie JSON is embedded because browsers refuse `fetch` from `file://` pages.
fn viewer_html(example: &str, lottie_json: &str) -> String {
    let data = lottie_json.replace("</", "<\\/");
    format!(
        r#"<!doctype html>
<meta charset="utf-8"><title>gmotion: {example}</title>
<style>body{{font:14px sans-serif;display:flex;gap:24px}} figure{{margin:0}} #lottie,img{{width:400px}}</style>
<figure><div id="lottie"></div><figcaption>Lottie ({example}.json) in lottie-web</figcaption></figure>
<figure><img src="{example}.svg"><figcaption>SMIL ({example}.svg)</figcaption></figure>
<script src="https://unpkg.com/lottie-web@5/build/player/lottie.min.js"></script>
<script>
const data = {data};
lottie.loadAnimation({{container: document.getElementById("lottie"), renderer: "svg", loop: true, autoplay: true, animationData: data}});
</script>
"#
    )
}
