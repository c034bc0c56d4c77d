//! Output checks before any work, and whole-or-nothing writes of the files the command line
//! writes itself (the formats are `gmotion-output`'s).

use std::fs;
use std::path::{Path, PathBuf};

use gmotion_pipeline::{Format, OutputError, video};

use super::report::{CliError, Result};

/// Fails early when the output's directory does not exist or is not writable, or it is a
/// video and ffmpeg is not installed, before any expensive work.
pub fn check_writable(path: &Path) -> Result<()> {
    if Format::of(path).is_ok_and(Format::is_video) && video::ffmpeg().is_none() {
        return Err(OutputError::NoFfmpeg {
            path: path.to_path_buf(),
            named: video::named(),
        }
        .into());
    }
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

/// Writes `bytes` to `path` whole or not at all.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    gmotion::atomic::write_bytes(path, bytes)
        .map_err(|e| CliError::msg(format!("{}: cannot write output: {e}", path.display())))
}
