//! Data-driven transitions: a TARGETS file lists, over time, new target values for
//! attributes of tagged shapes; each (shape, channel) is driven through a system from
//! [`crate::signals`] and the smoothed signals become an ordinary [`Animation`].
//!
//! ```text
//! Targets ──▶ per-frame input signals ──▶ SmoothSpec systems ──▶ Samples ──▶ Animation tracks
//!  (file)      (sample and hold)          (one per channel)      (per frame)   (MotionSeg/AttrSeg per frame)
//! ```
//!
//! The file formats are documented in `docs/transitions.md`. Targets take effect on the
//! first frame at or after their time; targets at `time ≤ 0` set the starting state, at
//! rest. The paper's three applications (sec. 8) are generators in [`histogram`],
//! [`permutation`] and [`revisions`], each producing an SVG scene and a TARGETS file.

pub mod histogram;
pub mod permutation;
pub mod revisions;
pub mod samples;
pub mod targets;
pub mod tracks;

use std::path::{Path, PathBuf};

use crate::motion::Animation;
use crate::scene::Scene;
use crate::signals::{SignalError, SmoothSpec};
pub use samples::{ChannelSamples, FrameState, Samples, ShapeSamples, sample};
pub use targets::{Attr, Channel, Target, TargetValue, Targets};

/// The system used when neither the caller nor the file names one: a critically damped
/// spring with a half-second pace.
pub const DEFAULT_SYSTEM: &str = "spring(0.5, 0)";

/// Why transitions could not be produced.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TransitionError {
    /// The TARGETS file could not be read.
    #[error("{path}: cannot read the file: {message}")]
    Read {
        /// The file.
        path: String,
        /// What the system said.
        message: String,
    },
    /// The TARGETS text is malformed.
    #[error("{file}{location}: {message}")]
    Parse {
        /// `path: ` when known, else empty.
        file: String,
        /// Where (`line 3`, `targets[12]`, `line 1, column 9`).
        location: String,
        /// What is wrong.
        message: String,
    },
    /// A target names a shape that the scene does not have.
    #[error("{location}: {message}")]
    Shape {
        /// Where the target was written.
        location: String,
        /// What is missing, with the tags the scene has.
        message: String,
    },
    /// A system or a parameter (fps, duration) is invalid.
    #[error("{context}: {source}")]
    Signal {
        /// Which channel or parameter.
        context: String,
        /// The underlying error.
        source: SignalError,
    },
    /// Writing an example failed.
    #[error("{path}: {message}")]
    Write {
        /// The file.
        path: String,
        /// What happened.
        message: String,
    },
}

impl TransitionError {
    pub(crate) fn parse(location: String, message: String) -> TransitionError {
        TransitionError::Parse {
            file: String::new(),
            location,
            message,
        }
    }

    /// Prefixes a parse error with its file name.
    pub(crate) fn in_file(self, path: &str) -> TransitionError {
        match self {
            TransitionError::Parse {
                location, message, ..
            } => TransitionError::Parse {
                file: format!("{path}: "),
                location,
                message,
            },
            other => other,
        }
    }
}

/// Runs TARGETS on a scene: every targeted (shape, channel) is smoothed by its system —
/// a per-channel override from the file, else `system` — at `fps`, for `duration`
/// seconds (default: the file's duration, else the last target time plus the time the
/// slowest system takes to settle within 0.1 %). The result has one motion window per
/// frame in which a shape's transform changes (rigid, exact at frame times) and one
/// attribute window per frame in which its opacity or fill changes.
///
/// Callers choose `system` by precedence: an explicit option, else `targets.system`,
/// else [`DEFAULT_SYSTEM`] — see [`Targets::default_system`].
pub fn run(
    scene: &Scene,
    targets: &Targets,
    system: &SmoothSpec,
    fps: f64,
    duration: Option<f64>,
) -> Result<Animation, TransitionError> {
    let samples = sample(scene, targets, system, fps, duration)?;
    Ok(tracks::animation(scene, &samples))
}

impl Targets {
    /// The system to use by default: `option` if given, else the file's `system`, else
    /// [`DEFAULT_SYSTEM`].
    pub fn default_system(&self, option: Option<SmoothSpec>) -> SmoothSpec {
        option.or_else(|| self.system.clone()).unwrap_or_else(|| {
            SmoothSpec::parse(DEFAULT_SYSTEM).expect("the default system parses")
        })
    }
}

/// A generated example: an SVG scene and its TARGETS, ready to be written side by side.
#[derive(Clone, Debug)]
pub struct Example {
    /// File stem (`histogram` → `histogram.svg`, `histogram.targets.json`).
    pub name: &'static str,
    /// The scene as SVG text; shapes carry `class` tags.
    pub svg: String,
    /// The targets.
    pub targets: Targets,
}

impl Example {
    /// Writes `<dir>/<name>.svg` and `<dir>/<name>.targets.json` (each through a
    /// temporary file and a rename, so nothing partial is left behind).
    pub fn write(&self, dir: &Path) -> Result<(PathBuf, PathBuf), TransitionError> {
        let svg = dir.join(format!("{}.svg", self.name));
        let json = dir.join(format!("{}.targets.json", self.name));
        write_atomic(&svg, &self.svg)?;
        write_atomic(&json, &self.targets.to_json())?;
        Ok((svg, json))
    }
}

fn write_atomic(path: &Path, text: &str) -> Result<(), TransitionError> {
    let err = |e: std::io::Error| TransitionError::Write {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, text).map_err(err)?;
    std::fs::rename(&tmp, path).map_err(err)
}

/// The three examples of the paper's sec. 8.
pub fn examples() -> Result<Vec<Example>, TransitionError> {
    Ok(vec![
        histogram::example(),
        permutation::example(),
        revisions::example()?,
    ])
}

/// Writes the three examples into `dir` (the repository keeps them in `grammars/`) and
/// returns the files written.
pub fn write_examples(dir: &Path) -> Result<Vec<PathBuf>, TransitionError> {
    let mut out = Vec::new();
    for ex in examples()? {
        let (svg, json) = ex.write(dir)?;
        out.extend([svg, json]);
    }
    Ok(out)
}
