//! Reading input files safely: regular files only (a FIFO would block forever, a device
//! such as `/dev/zero` would be read until memory runs out), and at most a given size.

use std::io::{self, Read};
use std::path::{Path, PathBuf};

/// The default largest input file gmotion reads (scene, grammar, targets): 256 MiB.
pub const DEFAULT_MAX_INPUT_BYTES: u64 = 256 << 20;

/// What `path` is when it is not a regular file (`None` when it is one, or is a symbolic
/// link to one). Nothing is opened, so a FIFO does not block.
pub fn irregular_kind(path: &Path) -> io::Result<Option<&'static str>> {
    let m = std::fs::metadata(path)?;
    let ft = m.file_type();
    if ft.is_file() {
        return Ok(None);
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ft.is_fifo() {
            return Ok(Some("a FIFO"));
        }
        if ft.is_char_device() || ft.is_block_device() {
            return Ok(Some("a device"));
        }
        if ft.is_socket() {
            return Ok(Some("a socket"));
        }
    }
    Ok(Some(if ft.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }))
}

/// Where a file referenced by another (an SVG's `<image href>`, a Lottie image asset's
/// `u` + `p`) may be read from: the referring file's folder and the folders the user
/// allowed, regular files of at most `max_bytes`.
#[derive(Clone, Debug)]
pub struct References<'a> {
    /// What refers to the files, as messages name it: `SVG`, `Lottie file`.
    pub owner: &'a str,
    /// The referring file's folder (`None` for text without a file: nothing is read).
    pub dir: Option<&'a Path>,
    /// Other folders the user allowed (`--allow-path DIR`).
    pub allowed: &'a [PathBuf],
    /// Largest file read (`--limit input-bytes=N`).
    pub max_bytes: u64,
}

impl References<'_> {
    /// The canonical path of `href` (relative to [`References::dir`], `file://` allowed)
    /// when it may be read, else why not: another scheme, a path resolving outside every
    /// allowed folder (through `..`, an absolute path or a symbolic link), something other
    /// than a regular file, or a file over the size limit.
    pub fn check(&self, href: &str) -> Result<PathBuf, String> {
        let owner = self.owner;
        let raw = href.strip_prefix("file://").unwrap_or(href);
        if raw.contains("://") {
            return Err("only files and data URIs are read".into());
        }
        let Some(dir) = self.dir else {
            return Err(format!(
                "{owner} text without a folder may reference data URIs only"
            ));
        };
        let real = dir
            .join(raw)
            .canonicalize()
            .map_err(|e| format!("cannot resolve it ({e})"))?;
        let mut roots: Vec<PathBuf> = std::iter::once(dir.to_path_buf())
            .chain(self.allowed.iter().cloned())
            .filter_map(|d| d.canonicalize().ok())
            .collect();
        roots.dedup();
        if !roots.iter().any(|r| real.starts_with(r)) {
            return Err(format!(
                "{} lies outside the {owner}'s folder (it may reference files in its own folder; allow another with --allow-path DIR)",
                real.display()
            ));
        }
        match irregular_kind(&real) {
            Ok(None) => {}
            Ok(Some(kind)) => return Err(format!("it is {kind}, not a regular file")),
            Err(e) => return Err(e.to_string()),
        }
        let len = std::fs::metadata(&real).map(|m| m.len()).unwrap_or(0);
        if len > self.max_bytes {
            return Err(format!(
                "it is larger than the limit of {} bytes (raise it with --limit input-bytes=N)",
                self.max_bytes
            ));
        }
        Ok(real)
    }
}

/// A file that could not be read, and why: the error every reader of input files returns.
#[derive(Debug, thiserror::Error)]
#[error("{}: cannot read the file: {source}", path.display())]
pub struct ReadError {
    /// The file.
    pub path: PathBuf,
    /// What the system (or a limit) said.
    #[source]
    pub source: io::Error,
}

impl ReadError {
    /// Wraps an error met reading `path` (for `map_err`).
    pub fn at(path: &Path) -> impl FnOnce(io::Error) -> ReadError + '_ {
        move |source| ReadError {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Reads `path` whole if it is a regular file of at most `max_bytes` bytes. Anything else
/// is an error whose message says why (`is a FIFO; gmotion reads regular files only`,
/// `is larger than the limit of … bytes`); the file is not opened when it is not regular.
pub fn read_regular(path: &Path, max_bytes: u64) -> io::Result<Vec<u8>> {
    if let Some(kind) = irregular_kind(path)? {
        return Err(io::Error::other(format!(
            "it is {kind}; gmotion reads input from regular files only"
        )));
    }
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(io::Error::other(format!(
            "the file is larger than the limit of {max_bytes} bytes (raise it with --limit input-bytes=N)"
        )));
    }
    Ok(bytes)
}

/// [`read_regular`] as UTF-8 text; invalid UTF-8 is an error naming the line and column
/// of the first bad byte, and UTF-16 (told by its byte-order mark) is named as such.
pub fn read_text(path: &Path, max_bytes: u64) -> io::Result<String> {
    let bytes = read_regular(path, max_bytes)?;
    utf8_text(bytes).map_err(io::Error::other)
}

/// `bytes` as UTF-8 text, or a message naming where it is not (`line L, column C`) or that
/// it is UTF-16.
pub fn utf8_text(bytes: Vec<u8>) -> Result<String, String> {
    // Valid text keeps its buffer; only a failure is looked at again, to say where.
    String::from_utf8(bytes).map_err(|e| match utf8_str(e.as_bytes()) {
        Err(located) => located,
        Ok(_) => e.to_string(),
    })
}

/// [`utf8_text`] for borrowed bytes: the same check and the same located message
/// (`L:C: the file is not UTF-8 text …`), shared by every reader of text files.
///
/// ```
/// use gmotion::input::utf8_str;
/// assert_eq!(utf8_str(b"<svg/>"), Ok("<svg/>"));
/// let err = utf8_str(b"<svg>\n<text>caf\xe9</text>").unwrap_err();
/// assert!(err.starts_with("2:10: the file is not UTF-8 text (invalid byte 0xe9"), "{err}");
/// ```
pub fn utf8_str(bytes: &[u8]) -> Result<&str, String> {
    if bytes.starts_with(&[0xff, 0xfe]) || bytes.starts_with(&[0xfe, 0xff]) {
        return Err(
            "1:1: the file is UTF-16 text (it starts with a UTF-16 byte-order mark); save it as UTF-8"
                .into(),
        );
    }
    std::str::from_utf8(bytes).map_err(|e| {
        let at = e.valid_up_to();
        let good = &bytes[..at];
        let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
        let start = good.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        let column = String::from_utf8_lossy(&good[start..]).chars().count() + 1;
        format!(
            "{line}:{column}: the file is not UTF-8 text (invalid byte 0x{:02x} at byte {at})",
            bytes[at]
        )
    })
}
