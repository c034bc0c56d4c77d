//! Helpers shared by the integration tests.

use std::path::{Path, PathBuf};

pub mod players;

/// The repository's root (the tests belong to the `cli` crate, one folder down).
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the cli crate sits inside the repository")
}

/// A file of `grammars/`.
pub fn grammar_file(name: &str) -> PathBuf {
    root().join("grammars").join(name)
}
