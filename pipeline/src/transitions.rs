//! Data-driven transitions: a scene, a targets file and a signal system, run into an
//! animation (docs/transitions.md).

use std::path::PathBuf;

use gmotion::signals::smooth::SmoothSpec;
use gmotion::transitions::{TransitionError, targets::Targets};

use crate::env::{Env, short};
use crate::scene::{ImportChoices, Imported, SceneOptions};
use crate::write::Rendered;
use crate::{Error, Result};

/// A transitions run: new target values over time for tagged shapes of a scene, passed
/// through a signal system.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Transitions {
    /// The scene (SVG).
    pub scene: PathBuf,
    /// The targets (.json or .csv).
    pub targets: PathBuf,
    /// The system every channel passes through (`spring(0.5, 0.2)`…); default the file's,
    /// else a critically damped spring.
    pub system: Option<String>,
    /// Frames per second; default the file's, else 60.
    pub fps: Option<f64>,
    /// Length in seconds; default the file's, else until every channel settles.
    pub duration: Option<f64>,
}

impl Transitions {
    /// Reads the targets, imports the scene under `choices` and runs; refuses a run whose
    /// frames would pass the `frames` limit.
    pub fn run(&self, choices: &ImportChoices, env: &Env) -> Result<Rendered> {
        let spec = self
            .system
            .as_deref()
            .map(|s| SmoothSpec::parse(s).map_err(|e| Error::msg(format!("--system: {e}"))))
            .transpose()?;
        let targets = &self.targets;
        let t = Targets::load(targets).map_err(|e| Error::msg(e.to_string()))?;
        let options = SceneOptions::new(choices, None, env)?;
        let scene = Imported::load(&self.scene, &options, env)?.scene;
        let system = t.default_system(spec);
        let fps = t.frame_rate(self.fps);
        let limits = &env.limits;
        if let Some(d) = self.duration {
            limits.check_frames(d * fps, &format!("--duration {d}s at {fps} fps"))?;
        }
        // The last target (or the file's own duration) sets how long the animation runs.
        let last = t.end();
        if self.duration.is_none() {
            limits.check_frames(
                last * fps,
                &format!(
                    "{}: error: targets up to {}s at {} fps",
                    targets.display(),
                    short(last),
                    short(fps)
                ),
            )?;
        }
        let anim = gmotion::transitions::run(&scene, &t, &system, fps, self.duration).map_err(
            |e| match e {
                // A target naming a missing tag is an error in the targets file: say which.
                TransitionError::Shape { .. } => Error::msg(format!("{}: {e}", targets.display())),
                e => Error::msg(e.to_string()),
            },
        )?;
        limits.check_frames(
            anim.duration * anim.fps,
            &format!(
                "{}: the targets' {}s at {fps} fps",
                targets.display(),
                anim.duration
            ),
        )?;
        Ok(Rendered {
            anim,
            source: None,
            package: None,
            markers: Vec::new(),
            slots: Default::default(),
            timelines: None,
        })
    }
}
