//! Writing outputs without leaving partial files: everything goes to a temporary sibling and
//! is renamed into place only when complete.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use super::report::{CliError, Result};

/// What an output path asks for, by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// One PNG.
    Png,
    /// Lottie JSON.
    Lottie,
    /// SVG (animated SMIL, or a clean still).
    Svg,
    /// Animated GIF preview.
    Gif,
    /// Animated PNG preview.
    Apng,
    /// A directory of PNG frames.
    Dir,
}

impl Format {
    /// The format of `path`: by extension, or a directory when it has none.
    pub fn of(path: &Path) -> Result<Format> {
        if path.is_dir() {
            return Ok(Format::Dir);
        }
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("png") => Ok(Format::Png),
            Some("json") => Ok(Format::Lottie),
            Some("svg") => Ok(Format::Svg),
            Some("gif") => Ok(Format::Gif),
            Some("apng") => Ok(Format::Apng),
            None => Ok(Format::Dir),
            Some(other) => Err(CliError::msg(format!(
                "{}: unknown output format `.{other}`; use .png, .json (Lottie), .svg, .gif, .apng or a directory",
                path.display()
            ))),
        }
    }
}

/// Fails early when the output's directory does not exist or is not writable, before any
/// expensive work.
pub fn check_writable(path: &Path) -> Result<()> {
    let dir = parent_dir(path);
    if !dir.is_dir() {
        return Err(CliError::msg(format!(
            "{}: cannot write output: directory {} does not exist",
            path.display(),
            dir.display()
        )));
    }
    let probe = temp_sibling(&dir.join(".gmotion-probe"));
    match fs::File::create(&probe) {
        Ok(_) => {
            let _ = fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(CliError::msg(format!(
            "{}: cannot write output: {e}",
            path.display()
        ))),
    }
}

fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

fn temp_sibling(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    parent_dir(path).join(format!(".{name}.{}.tmp", std::process::id()))
}

/// Writes `bytes` to `path` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temp_sibling(path);
    let res = (|| -> std::io::Result<()> {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    res.map_err(|e| {
        let _ = fs::remove_file(&tmp);
        CliError::msg(format!("{}: cannot write output: {e}", path.display()))
    })
}
