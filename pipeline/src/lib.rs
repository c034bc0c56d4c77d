//! gmotion's pipeline, between the importers and exporters and the front ends (the
//! `gmotion` command and the studio): a [`Project`] — the scene, the Lottie document it
//! came from (if any), the grammar and its settings — loaded once from paths under the
//! import choices and limits of an [`Env`], run once into a [`Rendered`] animation that
//! owns its source, and written by one [`Writer`] that knows every extension (`.json`
//! Lottie, `.svg` SMIL, `.png`, `.gif`, `.apng`, a folder of frames — all through
//! [`gmotion_output`] — and the `.html` page, [`html`]), to a file or to bytes.
//!
//! Loading goes in steps a front end can put its own checks between (the command line
//! checks its outputs once the scene's path is known, before importing it):
//!
//! ```no_run
//! # fn main() -> Result<(), gmotion_pipeline::Error> {
//! use std::path::Path;
//! use gmotion_pipeline::{Env, ImportChoices, Overrides, Project, Writer};
//! let env = Env::default();
//! let project = Project::load(Some(Path::new("art.svg")), Path::new("motion.gm"),
//!     &ImportChoices::default(), &env)?;
//! let run = Overrides::default().run_options(&env.limits)?;
//! let writer = Writer::new(project.grammar.output_size(None, None), &env.limits);
//! let rendered = project.run(&run, false)?;
//! let warnings = writer.write(&rendered, Path::new("art.json"), &|| {})?;
//! let (gif, _) = writer.bytes(&rendered, Path::new("art.gif"))?;
//! # let _ = (warnings, gif); Ok(()) }
//! ```
#![forbid(unsafe_code)]

pub mod env;
pub mod grammar;
pub mod html;
pub mod project;
pub mod scene;
pub mod transitions;
pub mod write;

pub use env::{Env, LIMITS, Limits, short};
pub use gmotion_output::dotlottie::{self, Picked};
pub use gmotion_output::{Format, LottieSource, OutputError, video};
pub use grammar::{GrammarFile, Overrides};
pub use project::{Project, Rescene};
pub use scene::{ImportChoices, Imported, SceneOptions};
pub use transitions::Transitions;
pub use write::{Rendered, Writer};

/// Why the pipeline stopped: a message already worded for a person (it names the file,
/// and a grammar error shows the line with a caret), or an output that could not be
/// written.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An input that cannot be read, imported or run, or a limit passed.
    #[error("{0}")]
    Input(String),
    /// An output that could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
}

impl Error {
    /// An [`Error::Input`] saying `message`.
    pub fn msg(message: impl Into<String>) -> Error {
        Error::Input(message.into())
    }
}

/// The pipeline's result.
pub type Result<T> = std::result::Result<T, Error>;
