//! `gmotion demo`: a bundled example run and written to every format.

use std::path::{Path, PathBuf};

use gmotion_export_raster as raster;
use gmotion_pipeline::grammar::output_size;
use gmotion_pipeline::{ImportChoices, Overrides, Transitions};

use super::animate::Build;
use super::transitions::TransitionsJob;
use super::{Ctx, Files, animation_writer, create_dir, write_animation};
use crate::examples::{EXAMPLES, Example, Kind};
use crate::output::write_atomic;
use crate::report::{self, CliError, Result};
use crate::{DEFAULT_TOLERANCE, RenderArgs};

/// Runs a bundled example (`--list`: names them): its files are written to `out/source/`
/// and its outputs beside.
pub fn demo(out: &Path, example: &str, list: bool, ctx: &Ctx) -> Result<()> {
    if list {
        let width = EXAMPLES.iter().map(|e| e.name.len()).max().unwrap_or(0);
        let lines: Vec<String> = EXAMPLES
            .iter()
            .map(|e| format!("{:width$}  {}\n", e.name, e.summary()))
            .collect();
        return report::out(&lines.concat());
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
    let render = RenderArgs {
        width: None,
        height: None,
        tolerance: DEFAULT_TOLERANCE,
        video: Default::default(),
        lottie: Default::default(),
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
        TransitionsJob {
            spec: Transitions {
                scene,
                targets: given,
                ..Transitions::default()
            },
            outputs: outputs.clone(),
            time: 0.0,
            render,
            choices: ImportChoices::default(),
        }
        .run(ctx)?;
        let frames = raster::check_frame_folder(&outputs[0]).map_or(0, |f| f.len());
        return demo_written(out, example, frames);
    }
    let files = Files {
        scene: Some(scene),
        grammar: given,
    };
    let (rendered, settings) = Build {
        files: &files,
        run: Overrides::default(),
        choices: &ImportChoices::default(),
        outputs: &[],
        timelines: true,
    }
    .run(ctx)?;
    let size = output_size(render.width, render.height, &settings);
    let writer = animation_writer(&render, size, 0.0, ctx)?;
    for o in &outputs {
        write_animation(&writer, &rendered, o)?;
    }
    demo_written(out, example, rendered.anim.frame_count())
}

/// What `demo` wrote, and how to look at it.
fn demo_written(out: &Path, example: &str, frames: usize) -> Result<()> {
    report::out(&format!(
        "wrote {0}/frames/ ({1} PNG frames), {0}/{2}.gif, {0}/{2}.json (Lottie), {0}/{2}.svg (SMIL), the example's files in {0}/source/\n\
         view: open {0}/preview.html in a browser (lottie-web beside the SMIL, all inside the file, no network)\n",
        out.display(),
        frames,
        example
    ))
}
