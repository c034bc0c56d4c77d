//! `-` on the command line: standard input as an input file, standard output as an output.
//!
//! Every reader and writer of the tool works on paths (formats are told by extension or
//! content, writes are staged and atomic), so `-` is mapped onto files in a private
//! temporary folder: standard input is read into `stdin.EXT` (its kind sniffed from its
//! first character) before the command runs, and an output `-` is written as
//! `stdout.EXT` (`EXT` from `--format`) and copied to standard output after every output
//! has been written. A failed command prints nothing on standard output.

use std::fs;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use super::report::{CliError, Result};

/// The temporary folder behind the `-` arguments of one run; removed when dropped.
pub struct Stdio {
    dir: PathBuf,
    /// The files standing for standard output, copied out by [`Stdio::finish`].
    outputs: Vec<PathBuf>,
}

impl Drop for Stdio {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.dir);
    }
}

/// True when `path` is the `-` of standard input or output.
pub fn is_dash(path: &Path) -> bool {
    path.as_os_str() == "-"
}

impl Stdio {
    /// Replaces every `-` among `inputs` by a file holding standard input (at most
    /// `max_bytes`), and every `-` among `outputs` by a file of format `format` to be
    /// copied to standard output.
    pub fn prepare(
        inputs: &mut [&mut PathBuf],
        outputs: &mut [&mut PathBuf],
        format: Option<&str>,
        max_bytes: u64,
    ) -> Result<Stdio> {
        let dir = std::env::temp_dir().join(format!("gmotion-stdio-{}", std::process::id()));
        let mut stdio = Stdio {
            dir,
            outputs: Vec::new(),
        };
        let dashed_in = inputs.iter().filter(|p| is_dash(p)).count();
        let dashed_out = outputs.iter().filter(|p| is_dash(p)).count();
        if dashed_in + dashed_out == 0 {
            return Ok(stdio);
        }
        if dashed_in > 1 || dashed_out > 1 {
            return Err(CliError::msg(
                "`-` may stand for standard input once and for standard output once",
            ));
        }
        fs::create_dir_all(&stdio.dir).map_err(|e| {
            CliError::msg(format!(
                "{}: cannot make a temporary folder: {e}",
                stdio.dir.display()
            ))
        })?;
        for p in inputs.iter_mut().filter(|p| is_dash(p)) {
            **p = stdio.read_stdin(max_bytes)?;
        }
        for p in outputs.iter_mut().filter(|p| is_dash(p)) {
            let Some(ext) = format else {
                return Err(CliError::msg(
                    "-o -: standard output has no extension to tell the format; add --format json, svg, png, gif, apng or html",
                ));
            };
            let file = stdio.dir.join(format!("stdout.{ext}"));
            stdio.outputs.push(file.clone());
            **p = file;
        }
        Ok(stdio)
    }

    fn read_stdin(&self, max_bytes: u64) -> Result<PathBuf> {
        let mut bytes = Vec::new();
        std::io::stdin()
            .take(max_bytes.saturating_add(1))
            .read_to_end(&mut bytes)
            .map_err(|e| CliError::msg(format!("standard input: cannot read: {e}")))?;
        if bytes.len() as u64 > max_bytes {
            return Err(CliError::msg(format!(
                "standard input: more than {max_bytes} bytes (the input-bytes limit; raise it with --limit input-bytes=N)"
            )));
        }
        let first = bytes
            .strip_prefix("\u{feff}".as_bytes())
            .unwrap_or(&bytes)
            .iter()
            .find(|b| !b.is_ascii_whitespace());
        let ext = match first {
            Some(b'<') => "svg",
            Some(b'{') => "json",
            _ => "gm",
        };
        let file = self.dir.join(format!("stdin.{ext}"));
        fs::write(&file, &bytes)
            .map_err(|e| CliError::msg(format!("{}: cannot write: {e}", file.display())))?;
        Ok(file)
    }

    /// Copies the standard-output files to standard output.
    pub fn finish(&self) -> Result<()> {
        let mut out = std::io::stdout().lock();
        for file in &self.outputs {
            let bytes = fs::read(file).map_err(|e| {
                CliError::msg(format!("-o -: the output was not written ({e}); a folder of frames cannot go to standard output"))
            })?;
            out.write_all(&bytes)
                .and_then(|()| out.flush())
                .map_err(|e| CliError::msg(format!("standard output: cannot write: {e}")))?;
        }
        Ok(())
    }
}
