//! `gmotion transitions`: data-driven transitions of a scene, written like `animate`.

use std::path::PathBuf;

use gmotion::engine::Settings;
use gmotion_pipeline::grammar::output_size;
use gmotion_pipeline::{ImportChoices, Transitions};

use super::{Ctx, animation_writer, check_outputs, validate_render, write_all, write_animation};
use crate::RenderArgs;
use crate::report::{CliError, Result};

/// A `transitions` command, its flags resolved.
pub struct TransitionsJob {
    /// The scene, the targets, the system, the rate and the length.
    pub spec: Transitions,
    /// Where to write.
    pub outputs: Vec<PathBuf>,
    /// The time of a `.png` output's frame.
    pub time: f64,
    /// Size and tolerance of the outputs.
    pub render: RenderArgs,
    /// How to import the scene.
    pub choices: ImportChoices,
}

impl TransitionsJob {
    /// Checks the flags and the outputs, runs and writes every output, all or none.
    pub fn run(&self, ctx: &Ctx) -> Result<()> {
        let spec = &self.spec;
        validate_render(&self.render)?;
        if let Some(fps) = spec.fps
            && !(fps.is_finite() && fps > 0.0)
        {
            return Err(CliError::msg(format!(
                "--fps must be a positive number, found {fps}"
            )));
        }
        if let Some(d) = spec.duration
            && !(d.is_finite() && d > 0.0)
        {
            return Err(CliError::msg(format!(
                "--duration must be a positive number of seconds, found {d}"
            )));
        }
        check_outputs(&self.outputs, &[&spec.scene, &spec.targets])?;
        let rendered = spec.run(&self.choices, &ctx.env)?;
        let size = output_size(self.render.width, self.render.height, &Settings::default());
        let writer = animation_writer(&self.render, size, self.time, ctx)?;
        write_all(&self.outputs, |o| write_animation(&writer, &rendered, o))
    }
}
