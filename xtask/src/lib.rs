//! Repository chores, kept out of the libraries: the generators of the three transitions
//! examples in `grammars/` (the signals-and-systems paper's sec. 8 applications), of the
//! gMotion gallery's scenes (and the intersections rules) and the signal plots in
//! `docs/img/`. Run them with `cargo xtask` (see `main.rs`).
#![forbid(unsafe_code)]

pub mod gallery;
pub mod histogram;
pub mod permutation;
pub mod plot;
pub mod revisions;

use std::path::{Path, PathBuf};

use gmotion::transitions::Targets;

/// Why an example could not be generated or written.
#[derive(Debug, thiserror::Error)]
#[error("{file}: {message}")]
pub struct ExampleError {
    /// The file being made.
    pub file: &'static str,
    /// What went wrong.
    pub message: String,
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
    /// Writes `<dir>/<name>.svg` and `<dir>/<name>.targets.json`, each whole or not at all.
    pub fn write(&self, dir: &Path) -> std::io::Result<(PathBuf, PathBuf)> {
        let svg = dir.join(format!("{}.svg", self.name));
        let json = dir.join(format!("{}.targets.json", self.name));
        gmotion::atomic::write_bytes(&svg, self.svg.as_bytes())?;
        gmotion::atomic::write_bytes(&json, self.targets.to_json().as_bytes())?;
        Ok((svg, json))
    }
}

/// The three examples of the paper's sec. 8.
pub fn examples() -> Result<Vec<Example>, ExampleError> {
    Ok(vec![
        histogram::example(),
        permutation::example(),
        revisions::example()?,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed examples are what the generators make: a generator change that is not
    /// regenerated (`cargo xtask transitions`) fails here, and so does a hand edit.
    #[test]
    fn committed_examples_are_regenerated_exactly() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../grammars");
        for ex in examples().unwrap() {
            let svg = std::fs::read_to_string(dir.join(format!("{}.svg", ex.name))).unwrap();
            let json =
                std::fs::read_to_string(dir.join(format!("{}.targets.json", ex.name))).unwrap();
            assert!(
                svg == ex.svg,
                "grammars/{}.svg differs from its generator",
                ex.name
            );
            assert!(
                json == ex.targets.to_json(),
                "grammars/{}.targets.json differs from its generator",
                ex.name
            );
        }
    }
}
