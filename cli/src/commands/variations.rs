//! `gmotion variations`: the grammar run once per seed, each run's frame at one instant,
//! as a labelled contact sheet or a folder of `seed_S.png`.

use std::path::{Path, PathBuf};

use gmotion::canvas::OutputSize;
use gmotion::engine::RunOptions;
use gmotion_export_raster as raster;
use gmotion_pipeline::{ImportChoices, Project, short};

use super::{Ctx, Files, create_dir, write_all};
use crate::guard;
use crate::report::{CliError, Result};

/// A `variations` command, its flags resolved.
pub struct Variations {
    /// The scene (if given) and the grammar.
    pub files: Files,
    /// The seeds, in order.
    pub seeds: Vec<u64>,
    /// A `.png` contact sheet, or a folder.
    pub output: PathBuf,
    /// The instant shown (default: half the duration).
    pub time: Option<f64>,
    /// Width in pixels of each frame.
    pub width: u32,
    /// How to import the scene.
    pub choices: ImportChoices,
}

impl Variations {
    /// Renders every seed's frame and writes the sheet or the folder.
    pub fn run(self, ctx: &Ctx) -> Result<()> {
        use rayon::prelude::*;
        let (out, width) = (self.output.as_path(), self.width);
        if self.seeds.is_empty() || width == 0 {
            return Err(CliError::msg("--count and --width must be at least 1"));
        }
        let sheet = out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        guard::check_not_input(&[out], &[&self.files.grammar])?;
        let env = &ctx.env;
        let project = Project::load(self.files.scene(), &self.files.grammar, &self.choices, env)?;
        project.imported.check_drawable(&project.scene_path)?;
        let duration = project.grammar.settings.duration;
        let t = self.time.unwrap_or(duration / 2.0);
        if !(t.is_finite() && (0.0..=duration).contains(&t)) {
            return Err(CliError::msg(format!(
                "--time must lie within the animation, 0..{duration}s, found {t}"
            )));
        }
        let size = OutputSize {
            width: Some(width),
            height: None,
        };
        let pixels = env.limits.get("pixels");
        let frames = self
            .seeds
            .par_iter()
            .map(|&seed| {
                let opts = RunOptions {
                    seed: Some(seed),
                    ..RunOptions::default()
                };
                let anim = project.animate(&opts)?;
                let svg = gmotion_export_svg::frame::frame_svg(&anim, t);
                raster::render_limited(&svg, size, pixels)
                    .map(|p| (seed, p))
                    .map_err(|e| CliError::msg(format!("seed {seed}: {e}")))
            })
            .collect::<Result<Vec<_>>>()?;
        let save = |pm: &raster::Pixmap, path: &Path| {
            raster::save_png(pm, path).map_err(|e| CliError::msg(e.to_string()))
        };
        if sheet {
            let pm = crate::sheet::contact_sheet(&frames).ok_or_else(|| {
                CliError::msg(format!("{}: the sheet is too large", out.display()))
            })?;
            raster::check_pixels(pm.width(), pm.height(), pixels)
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
        crate::report::note(&format!(
            "wrote {} ({} seeds from {} at {}s)",
            out.display(),
            frames.len(),
            frames[0].0,
            short(t)
        ));
        Ok(())
    }
}
