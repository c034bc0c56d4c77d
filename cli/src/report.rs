//! Error messages for the terminal: grammar errors with the source line and a caret.

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use gmotion::engine::EngineError;
use gmotion::grammar::diagnostics::Diagnostic;

/// An error already worded for the user.
#[derive(Debug)]
pub struct CliError(pub String);

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl CliError {
    /// A plain message.
    pub fn msg(m: impl Into<String>) -> CliError {
        CliError(m.into())
    }
}

/// Result of a command.
pub type Result<T> = std::result::Result<T, CliError>;

/// An engine error rendered against the grammar source.
pub fn engine_error(grammar_path: &Path, src: &str, e: &EngineError) -> CliError {
    let name = grammar_path.display().to_string();
    CliError(
        Diagnostic::from(e)
            .render(&name, src)
            .trim_end()
            .to_string(),
    )
}

/// `--quiet`: warnings and the summary of what was written are not printed (errors are).
static QUIET: AtomicBool = AtomicBool::new(false);

/// Sets `--quiet` for the rest of the run.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Prints a warning about `origin` (the file it concerns) on standard error, unless quiet.
pub fn warn(origin: &Path, warning: impl fmt::Display) {
    if QUIET.load(Ordering::Relaxed) {
        return;
    }
    // An importer's warning names its file itself: the file is said once.
    let origin = origin.display().to_string();
    let text = warning.to_string();
    let text = text.strip_prefix(&format!("{origin}: ")).unwrap_or(&text);
    eprintln!("{origin}: warning: {text}");
}

/// Prints a line on standard error, unless quiet.
pub fn note(line: &str) {
    if !QUIET.load(Ordering::Relaxed) {
        eprintln!("{line}");
    }
}

/// Prints one line on standard error saying what was written, unless quiet: each output
/// as given on the command line (`-` is standard output), with its size or frame count.
pub fn wrote(given: &[PathBuf], written: &[PathBuf]) {
    if QUIET.load(Ordering::Relaxed) || given.is_empty() {
        return;
    }
    let items: Vec<String> = given
        .iter()
        .zip(written)
        .map(|(name, file)| {
            let shown = if name.as_os_str() == "-" {
                "standard output".to_string()
            } else {
                name.display().to_string().trim_end_matches('/').to_string()
            };
            if gmotion_export_raster::FrameNames::is_pattern(file) {
                let frames = gmotion_export_raster::check_frame_folder(file).map_or(0, |f| f.len());
                return format!("{shown} ({frames} frames)");
            }
            match std::fs::metadata(file) {
                Ok(m) if m.is_dir() => {
                    let frames = std::fs::read_dir(file).map_or(0, |d| d.count());
                    format!("{shown}/ ({frames} frames)")
                }
                Ok(m) => format!("{shown} ({})", size(m.len())),
                Err(_) => shown,
            }
        })
        .collect();
    eprintln!("wrote {}", items.join(", "));
}

/// A byte count for people: `812 B`, `12.4 kB`, `3.1 MB`.
fn size(bytes: u64) -> String {
    match bytes {
        b if b < 1000 => format!("{b} B"),
        b if b < 1_000_000 => format!("{:.1} kB", b as f64 / 1e3),
        b => format!("{:.1} MB", b as f64 / 1e6),
    }
}

/// Writes `text` to standard output. A reader that closed the pipe early (`gmotion check
/// … | head`) is not an error: the rest is simply not wanted.
pub fn out(text: &str) -> Result<()> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(CliError::msg(format!("standard output: cannot write: {e}")))
        }
        _ => Ok(()),
    }
}
