//! `gmotion variations`: the grammar run once per seed, each run's frame at one instant,
//! as a labelled contact sheet or a folder of `seed_S.png`; or each run whole, as the
//! animations `seed_S` of one dotLottie package.

use std::path::{Path, PathBuf};

use gmotion::canvas::OutputSize;
use gmotion::engine::RunOptions;
use gmotion_export_raster as raster;
use gmotion_pipeline::dotlottie::Package;
use gmotion_pipeline::{ImportChoices, Project, Rendered, Writer, short};

use super::{Ctx, Files, create_dir, write_all};
use crate::guard;
use crate::report::{CliError, Result};

/// A `variations` command, its flags resolved.
pub struct Variations {
    /// The scene (if given) and the grammar.
    pub files: Files,
    /// The seeds, in order.
    pub seeds: Vec<u64>,
    /// A `.png` contact sheet, a `.lottie` package, or a folder.
    pub output: PathBuf,
    /// The instant shown (default: half the duration).
    pub time: Option<f64>,
    /// Width in pixels of each frame.
    pub width: u32,
    /// A dotLottie theme for a `.lottie` output (`--theme`).
    pub theme: Option<PathBuf>,
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
        let extension = |ext: &str| out.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext));
        let sheet = extension("png");
        if self.theme.is_some() && !extension("lottie") {
            return Err(CliError::msg(
                "--theme is written into a .lottie output (-o set.lottie), and the output is not one",
            ));
        }
        // Read (and checked) before any seed runs.
        let theme = match &self.theme {
            Some(path) => Some(crate::theme::Theme::read(path)?),
            None => None,
        };
        guard::check_not_input(&[out], &[&self.files.grammar])?;
        let env = &ctx.env;
        let project = Project::load(self.files.scene(), &self.files.grammar, &self.choices, env)?;
        project.imported.check_drawable(&project.scene_path)?;
        if extension("lottie") {
            return self.package(&project, theme.as_ref(), ctx);
        }
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

    /// Runs every seed and writes the animations into one dotLottie package, `seed_S`
    /// each, in seed order (the first the one a player shows).
    fn package(
        &self,
        project: &Project,
        theme: Option<&crate::theme::Theme>,
        ctx: &Ctx,
    ) -> Result<()> {
        use rayon::prelude::*;
        let out = self.output.as_path();
        let writer = Writer::new(OutputSize::default(), &ctx.env.limits);
        let texts = self
            .seeds
            .par_iter()
            .map(|&seed| {
                let opts = RunOptions {
                    seed: Some(seed),
                    ..RunOptions::default()
                };
                let rendered = Rendered {
                    package: None,
                    ..project.rendered(&opts)?
                };
                let name = format!("seed_{seed}");
                let (bytes, warnings) =
                    writer.bytes(&rendered, Path::new(&name).with_extension("json").as_path())?;
                for w in &warnings {
                    crate::report::warn(out, w);
                }
                Ok((name, String::from_utf8_lossy(&bytes).into_owned()))
            })
            .collect::<Result<Vec<_>>>()?;
        let mut package = Package::new();
        let error = |e: gmotion_pipeline::dotlottie::PackageError| {
            CliError::msg(format!("{}: {e}", out.display()))
        };
        for (id, text) in &texts {
            package.put_animation(id, text).map_err(error)?;
        }
        let mut bytes = package.to_bytes().map_err(error)?;
        if let Some(theme) = theme {
            // Every seed runs the same grammar, so the first animation's slots are all of
            // theirs.
            let (themed, warnings) =
                theme.add_to(&bytes, out, ctx.env.limits.get("input-bytes"))?;
            for w in &warnings {
                crate::report::warn(out, w);
            }
            bytes = themed;
        }
        gmotion::atomic::write_bytes(out, &bytes)
            .map_err(|e| CliError::msg(format!("{}: cannot write output: {e}", out.display())))?;
        crate::report::note(&format!(
            "wrote {} ({} animations, seeds {} to {})",
            out.display(),
            texts.len(),
            self.seeds[0],
            self.seeds[self.seeds.len() - 1]
        ));
        Ok(())
    }
}
