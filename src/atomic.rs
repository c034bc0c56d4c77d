//! All-or-nothing file output: write to a temporary file beside the target, then rename,
//! so a failed export never leaves a partial file where the user expects a result.
//!
//! Three more guarantees hold for a whole run:
//!
//! - **Every temporary file is known.** Each one this module creates is registered until it
//!   is renamed into place or removed, so [`remove_temporaries`] can delete them all (the
//!   command line calls it from its SIGINT/SIGTERM handler), and [`Staging`] removes them
//!   when dropped.
//! - **Several outputs land together.** While a [`Staging`] is open, finished files are
//!   not renamed into place: they wait in their temporary files until
//!   [`Staging::commit`] renames them all, so when a later output fails, none of the
//!   earlier ones is written and no existing file is replaced.
//! - **Only regular files are replaced.** [`check_target`] refuses a directory, a device,
//!   a FIFO or a socket as a file output (renaming over `/dev/full` would replace the
//!   device node with a regular file).

use std::fs::File;
use std::io::{self, BufWriter, IoSlice, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// What is left to do to put one staged output in place.
type Commit = Box<dyn FnOnce() -> io::Result<()> + Send>;

/// Temporary files and folders that exist right now (created here, not yet renamed or
/// removed).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The outputs waiting for [`Staging::commit`], when a staging is open.
static STAGED: Mutex<Option<Vec<Commit>>> = Mutex::new(None);

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    // A panic while holding the lock leaves the list as it was; it is still usable.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Records `path` as a temporary this process owns until [`forget`] is called.
pub fn register(path: &Path) {
    lock(&LIVE).push(path.to_path_buf());
}

/// Forgets a temporary recorded by [`register`] (it was renamed or removed).
pub fn forget(path: &Path) {
    let mut live = lock(&LIVE);
    if let Some(i) = live.iter().position(|p| p == path) {
        live.swap_remove(i);
    }
}

/// Removes every temporary file and folder this process has created and not yet put in
/// place. Safe to call from a signal-handling thread; the targets are never touched.
pub fn remove_temporaries() {
    let live = std::mem::take(&mut *lock(&LIVE));
    for p in live {
        if p.is_dir() {
            let _ = std::fs::remove_dir_all(&p);
        } else {
            let _ = std::fs::remove_file(&p);
        }
    }
}

/// Refuses an existing file at `path` that is write-protected or that the user may not
/// open for writing (a missing file is fine). The rename that puts an output in place needs
/// only the directory's permission, so without this check a file the user may not write
/// would be silently replaced (`cp` refuses it). Write protection counts even for the
/// superuser, who may write anything: a read-only output is a file someone meant to keep.
pub fn check_writable(path: &Path) -> io::Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() && m.permissions().readonly() => Err(io::Error::new(
            io::ErrorKind::PermissionDenied,
            "the file is write-protected; gmotion does not replace it (make it writable or choose another name)",
        )),
        Ok(m) if m.is_file() => match std::fs::OpenOptions::new().append(true).open(path) {
            Ok(_) => Ok(()),
            Err(e) if e.kind() == io::ErrorKind::PermissionDenied => Err(io::Error::new(
                io::ErrorKind::PermissionDenied,
                "you may not write the file; gmotion does not replace it",
            )),
            Err(e) => Err(e),
        },
        _ => Ok(()),
    }
}

/// Refuses an output path that exists and is not a regular file (or a symbolic link to
/// one): a directory, a device, a FIFO or a socket would be replaced by a regular file;
/// and a file the user may not write ([`check_writable`]).
pub fn check_target(path: &Path) -> io::Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() => check_writable(path),
        Ok(m) => {
            let kind = if m.is_dir() {
                "a directory"
            } else {
                "not a regular file (a device, FIFO or socket)"
            };
            Err(io::Error::other(format!(
                "{kind}; gmotion replaces only regular files"
            )))
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e),
    }
}

/// Runs `commit` now, or later with the other outputs when a [`Staging`] is open; `tmp`
/// is removed if the staging is dropped without committing.
pub fn finish(tmp: &Path, commit: Commit) -> io::Result<()> {
    let mut staged = lock(&STAGED);
    match staged.as_mut() {
        Some(list) => {
            list.push(commit);
            Ok(())
        }
        None => {
            drop(staged);
            let r = commit();
            if r.is_err() {
                discard(tmp);
            }
            r
        }
    }
}

/// Removes a temporary file or folder and forgets it.
fn discard(tmp: &Path) {
    if tmp.is_dir() {
        let _ = std::fs::remove_dir_all(tmp);
    } else {
        let _ = std::fs::remove_file(tmp);
    }
    forget(tmp);
}

/// Outputs written together: while a `Staging` lives, every file written through this
/// module waits in its temporary file; [`Staging::commit`] puts them all in place, and
/// dropping it uncommitted removes them. One staging at a time per process.
#[derive(Debug)]
pub struct Staging {
    _private: (),
}

impl Staging {
    /// Opens a staging.
    pub fn begin() -> Staging {
        *lock(&STAGED) = Some(Vec::new());
        Staging { _private: () }
    }

    /// Puts every staged output in place, in the order written. Renames within a folder
    /// do not fail in practice once the data is written; should one fail, the others
    /// are still put in place and the first error is returned.
    pub fn commit(self) -> io::Result<()> {
        let list = lock(&STAGED).take().unwrap_or_default();
        let mut first = Ok(());
        for c in list {
            let r = c();
            if first.is_ok() {
                first = r;
            }
        }
        remove_temporaries();
        first
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        // Committed: the list is gone. Dropped early (an error, a panic): discard.
        if lock(&STAGED).take().is_some() {
            remove_temporaries();
        }
    }
}

/// Creates `path` by running `write` on a buffered temporary file in the same directory
/// and renaming it into place once `write` and the flush succeed (or when the open
/// [`Staging`] commits). On error the temporary file is removed and `path` is left as it
/// was. A `path` that exists and is not a regular file is refused ([`check_target`]).
pub fn write_with<E, F>(path: &Path, write: F) -> Result<(), E>
where
    E: From<io::Error>,
    F: FnOnce(&mut BufWriter<File>) -> Result<(), E>,
{
    write_via(path, |tmp| {
        let mut out = BufWriter::new(File::create(tmp)?);
        write(&mut out)?;
        let file = out.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        Ok(())
    })
}

/// Has `make` write the file `path` will hold (a writer of its own, or an encoder process
/// that writes a file by name): `make` is given a registered temporary path beside `path`,
/// which is renamed into place when `make` succeeds (or when the open [`Staging`] commits)
/// and removed when it fails. `make` flushes what it wrote to the disk itself. A `path`
/// that exists and is not a regular file is refused ([`check_target`]).
pub fn write_via<E, F>(path: &Path, make: F) -> Result<(), E>
where
    E: From<io::Error>,
    F: FnOnce(&Path) -> Result<(), E>,
{
    check_target(path)?;
    let tmp = temp_path(path);
    register(&tmp);
    let result = make(&tmp);
    if result.is_err() {
        // The temporary file is ours and incomplete; failing to remove it changes nothing.
        discard(&tmp);
        return result;
    }
    let (from, to) = (tmp.clone(), path.to_path_buf());
    finish(
        &tmp,
        Box::new(move || {
            std::fs::rename(&from, &to)?;
            forget(&from);
            Ok(())
        }),
    )?;
    Ok(())
}

/// Writes `bytes` to `path` atomically.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_with(path, |out| out.write_all(bytes))
}

/// How many pieces one `write_vectored` call is given (Linux's `IOV_MAX`).
const PIECES_PER_WRITE: usize = 1024;

/// Writes `pieces` to `out` in order, a thousand to a call for a writer that takes
/// vectored writes (a file, or a `BufWriter` over one): a large document held in pieces
/// goes to its file without first being copied into one allocation of its whole size.
pub fn write_pieces<'a>(
    out: &mut impl Write,
    pieces: impl IntoIterator<Item = &'a [u8]>,
) -> io::Result<()> {
    let mut pieces = pieces.into_iter().peekable();
    let mut slices: Vec<IoSlice<'a>> = Vec::with_capacity(PIECES_PER_WRITE);
    while pieces.peek().is_some() {
        slices.clear();
        slices.extend(pieces.by_ref().take(PIECES_PER_WRITE).map(IoSlice::new));
        let mut rest = &mut slices[..];
        // Skips empty pieces at the front, so a return of 0 below means no progress.
        IoSlice::advance_slices(&mut rest, 0);
        while !rest.is_empty() {
            match out.write_vectored(rest) {
                Ok(0) => return Err(io::ErrorKind::WriteZero.into()),
                Ok(n) => IoSlice::advance_slices(&mut rest, n),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
    }
    Ok(())
}

/// `dir/.name.<pid>-<n>.tmp`: hidden, unique per process and call, on the same file system
/// as `path` so the rename cannot cross devices.
///
/// The name is cut so the temporary name stays within `NAME_MAX` (255 bytes) when the output's
/// own name is near it: an output named with 255 bytes would otherwise fail to be written
/// because its temporary sibling's name is too long.
pub fn temp_path(path: &Path) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    let suffix = format!(".{}-{n}.tmp", std::process::id());
    let mut keep = name.len().min(NAME_MAX - 1 - suffix.len());
    while !name.is_char_boundary(keep) {
        keep -= 1;
    }
    path.with_file_name(format!(".{}{suffix}", &name[..keep]))
}

/// The longest file name, in bytes, of the file systems gmotion writes to (Linux, macOS and
/// Windows all allow 255).
const NAME_MAX: usize = 255;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_fit_the_name_limit() {
        for name in ["a".repeat(255), "é".repeat(127), "out.json".into()] {
            let tmp = temp_path(&Path::new("dir").join(&name));
            let t = tmp.file_name().unwrap().to_str().unwrap();
            assert!(t.len() <= NAME_MAX, "{} bytes: {t}", t.len());
            assert!(t.starts_with('.') && t.ends_with(".tmp"), "{t}");
            // Short names are kept whole, so a temporary file is easy to trace to its output.
            if name.len() < 200 {
                assert!(t.starts_with(&format!(".{name}.")), "{t}");
            }
        }
    }

    /// A writer that takes at most `most` bytes a call, counting its calls.
    struct Trickle {
        out: Vec<u8>,
        most: usize,
        calls: usize,
    }

    impl Write for Trickle {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            self.write_vectored(&[IoSlice::new(buf)])
        }

        fn write_vectored(&mut self, bufs: &[IoSlice<'_>]) -> io::Result<usize> {
            self.calls += 1;
            let mut n = 0;
            for b in bufs {
                let take = b.len().min(self.most - n);
                self.out.extend_from_slice(&b[..take]);
                n += take;
                if n == self.most {
                    break;
                }
            }
            Ok(n)
        }

        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn pieces_are_written_whole_and_in_order_through_short_writes() {
        let pieces: Vec<Vec<u8>> = (0..3000)
            .map(|k| format!(",{k}").into_bytes())
            .chain([Vec::new(), b"]}".to_vec()])
            .collect();
        let joined = pieces.concat();
        let slices = || pieces.iter().map(Vec::as_slice);
        for most in [1, 7, 4096, usize::MAX / 2] {
            let mut w = Trickle {
                out: Vec::new(),
                most,
                calls: 0,
            };
            write_pieces(&mut w, slices()).unwrap();
            assert_eq!(w.out, joined, "{most} a call");
        }
        // Whole pieces go a thousand to a call.
        let mut w = Trickle {
            out: Vec::new(),
            most: usize::MAX / 2,
            calls: 0,
        };
        write_pieces(&mut w, slices()).unwrap();
        assert_eq!(w.calls, 3);
    }

    #[test]
    fn a_writer_that_takes_nothing_is_an_error_not_a_loop() {
        let mut w = Trickle {
            out: Vec::new(),
            most: 0,
            calls: 0,
        };
        let e = write_pieces(&mut w, [b"{}".as_slice()]).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::WriteZero);
    }

    #[test]
    fn failed_write_leaves_nothing() {
        let dir = std::env::temp_dir().join(format!("gmotion-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("out.txt");
        let r: io::Result<()> = write_with(&target, |out| {
            out.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        });
        assert!(r.is_err());
        assert!(!target.exists());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        write_bytes(&target, b"done").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"done");

        // Staged: nothing lands until commit; dropped, nothing lands at all.
        let (a, b) = (dir.join("a.txt"), dir.join("b.txt"));
        let staging = Staging::begin();
        write_bytes(&a, b"a").unwrap();
        write_bytes(&target, b"new").unwrap();
        assert!(!a.exists());
        drop(staging);
        assert!(!a.exists());
        assert_eq!(std::fs::read(&target).unwrap(), b"done");
        let staging = Staging::begin();
        write_bytes(&a, b"a").unwrap();
        write_bytes(&b, b"b").unwrap();
        staging.commit().unwrap();
        assert_eq!(std::fs::read(&b).unwrap(), b"b");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 3);

        // A directory is not replaced.
        assert!(write_bytes(&dir, b"x").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
