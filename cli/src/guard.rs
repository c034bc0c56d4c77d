//! Hostile input on the command line's side: outputs that may not overwrite inputs, and
//! removal of temporary files on SIGINT/SIGTERM (the limits users can see and raise,
//! `--limit NAME=N`, are the pipeline's: [`gmotion_pipeline::env`]).

use std::path::Path;

use super::report::{CliError, Result};

/// The identity of an existing file (device and inode), following symbolic links.
#[cfg(unix)]
fn identity(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn identity(path: &Path) -> Option<std::path::PathBuf> {
    path.canonicalize().ok()
}

/// Refuses an output that is one of the inputs (the same file, through any link or
/// spelling), and an existing output that is a device, FIFO or socket, or a directory
/// where a file is written.
pub fn check_not_input(outputs: &[&Path], inputs: &[&Path]) -> Result<()> {
    for o in outputs {
        let Some(id) = identity(o) else {
            continue;
        };
        if let Some(i) = inputs.iter().find(|i| identity(i).as_ref() == Some(&id)) {
            return Err(CliError::msg(format!(
                "{}: refusing to write over an input ({} is the same file); choose another output",
                o.display(),
                i.display()
            )));
        }
    }
    Ok(())
}

/// Refuses an existing output that is not a regular file (a directory is allowed only for
/// a frames folder, `frames_ok`) or that the user may not write, before any work.
pub fn check_output_kind(o: &Path, frames_ok: bool) -> Result<()> {
    match gmotion::input::irregular_kind(o) {
        Ok(Some("a directory")) if frames_ok => Ok(()),
        Ok(Some(kind)) => Err(CliError::msg(format!(
            "{}: cannot write output: it is {kind}; gmotion writes outputs as regular files (or a folder of frames)",
            o.display()
        ))),
        _ => gmotion::atomic::check_writable(o)
            .map_err(|e| CliError::msg(format!("{}: cannot write output: {e}", o.display()))),
    }
}

/// Removes every temporary file on SIGINT and SIGTERM, then exits with 128 + the signal.
/// SIGXFSZ (a write past the file-size limit, `ulimit -f`) would kill the process where
/// it stands, leaving its temporary file; caught, the write fails with EFBIG instead and
/// the output is abandoned like any failed write, with a message.
pub fn clean_up_on_signals() {
    use signal_hook::consts::{SIGINT, SIGTERM, SIGXFSZ};
    let _ = signal_hook::flag::register(
        SIGXFSZ,
        std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false)),
    );
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            gmotion::atomic::remove_temporaries();
            std::process::exit(128 + sig);
        }
    });
}
