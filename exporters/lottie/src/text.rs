//! Lottie JSON as the exporter hands it over: a text already written (a source written
//! back, a document with slots or packed), the document's model, written when its
//! destination is known, or a document whose layers are built as they are written. A
//! large export is written straight to its file a run of layers at a time
//! ([`crate::model::Animation::write_to`]), each run freed once written, instead of first
//! being turned into a text as large as the file (856 MB for 999 000 shapes); a large
//! scene's layers are built a run at a time too ([`crate::layers::Builder::write_root`]).

use std::fmt;
use std::fs::File;
use std::io::{self, Read, Seek, SeekFrom, Write};
use std::path::PathBuf;

use crate::model::Animation;

/// Writes a document whose layers are built as they are written.
type Stream<'a> = Box<dyn FnOnce(&mut dyn Write) -> io::Result<()> + Send + 'a>;

/// Lottie JSON, as text or as what writes it: it borrows the animation it is written
/// from while its layers are still to be built.
pub struct LottieText<'a> {
    held: Held<'a>,
}

enum Held<'a> {
    Text(Vec<u8>),
    Document(Box<Animation>),
    Stream(Stream<'a>),
    /// A document without its root layers, which are in a temporary file: the length
    /// of each run's text there, the first run (the bottom layers) first.
    Spilled(Box<Animation>, Spill, Vec<u64>),
}

impl fmt::Debug for LottieText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let held = match &self.held {
            Held::Text(text) => format!("{} bytes of text", text.len()),
            Held::Document(doc) => format!("a document of {} layers", doc.layers.len()),
            Held::Stream(_) => "a document built as it is written".to_string(),
            Held::Spilled(_, _, runs) => format!("a document of {} runs of layers", runs.len()),
        };
        f.debug_struct("LottieText").field("held", &held).finish()
    }
}

impl<'a> LottieText<'a> {
    /// The text `doc` writes, written when asked for.
    pub(crate) fn document(doc: Animation) -> LottieText<'a> {
        LottieText {
            held: Held::Document(Box::new(doc)),
        }
    }

    /// The text `write` writes, built as it is written.
    pub(crate) fn stream(
        write: impl FnOnce(&mut dyn Write) -> io::Result<()> + Send + 'a,
    ) -> LottieText<'a> {
        LottieText {
            held: Held::Stream(Box::new(write)),
        }
    }

    /// The text `doc` writes with the root layers whose runs' texts (each layer after a
    /// comma, topmost first) `spill` holds, first run first, `runs` long.
    pub(crate) fn spilled(doc: Animation, spill: Spill, runs: Vec<u64>) -> LottieText<'a> {
        LottieText {
            held: Held::Spilled(Box::new(doc), spill, runs),
        }
    }

    /// Writes the text to `out`, freeing what is written as it goes. A writer that takes
    /// vectored writes (a file, or a `BufWriter` over one) gets many pieces a call.
    pub fn write_to(self, out: &mut dyn Write) -> io::Result<()> {
        match self.held {
            Held::Text(text) => out.write_all(&text),
            Held::Document(doc) => doc.write_to(out),
            Held::Stream(write) => write(out),
            Held::Spilled(doc, spill, runs) => {
                doc.write_with(out, |out| spill.copy_runs(&runs, out))
            }
        }
    }

    /// How the text is held: `text`, `document`, `stream` or `spilled`.
    #[cfg(test)]
    pub(crate) fn held(&self) -> &'static str {
        match self.held {
            Held::Text(_) => "text",
            Held::Document(_) => "document",
            Held::Stream(_) => "stream",
            Held::Spilled(..) => "spilled",
        }
    }

    /// The text as one string.
    pub fn into_string(self) -> String {
        let bytes = match self.held {
            Held::Text(text) => text,
            held => {
                let mut out = Vec::new();
                LottieText { held }
                    .write_to(&mut out)
                    .expect("writing into memory does not fail");
                out
            }
        };
        String::from_utf8(bytes).expect("the text is UTF-8 (serde_json writes UTF-8)")
    }
}

impl From<String> for LottieText<'_> {
    fn from(s: String) -> Self {
        LottieText {
            held: Held::Text(s.into_bytes()),
        }
    }
}

/// A temporary file that holds a document's root layers while they are built, a run at a
/// time from the bottom, until they are copied to the output from the top
/// ([`crate::layers::Builder::spill_root`]): removed when dropped, and at once where the
/// system lets an open file be removed.
pub(crate) struct Spill {
    file: File,
    /// Where the file is, while it could not be removed.
    path: Option<PathBuf>,
}

impl Spill {
    /// A new, empty file in the system's temporary folder.
    pub(crate) fn create() -> io::Result<Spill> {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static NEXT: AtomicUsize = AtomicUsize::new(0);
        let path = std::env::temp_dir().join(format!(
            ".gmotion-layers-{}-{}.tmp",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        ));
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(&path)?;
        // Removed while open, nothing is left behind should the process be killed.
        let path = std::fs::remove_file(&path).err().map(|_| path);
        Ok(Spill { file, path })
    }

    /// The file, to write the runs to.
    pub(crate) fn file(&mut self) -> &mut File {
        &mut self.file
    }

    /// Copies the runs `runs` long (written one after the other, each layer after a
    /// comma) to `out`, the last run first, without the comma before the first layer.
    fn copy_runs(mut self, runs: &[u64], out: &mut dyn Write) -> io::Result<()> {
        let mut buf = vec![0; 1 << 20];
        let mut end: u64 = runs.iter().sum();
        let mut first = true;
        for &len in runs.iter().rev() {
            let start = end - len;
            if len > 0 {
                let skip = u64::from(first);
                self.file.seek(SeekFrom::Start(start + skip))?;
                let mut run = (&mut self.file).take(len - skip);
                let mut copied = 0;
                loop {
                    let n = run.read(&mut buf)?;
                    if n == 0 {
                        break;
                    }
                    out.write_all(&buf[..n])?;
                    copied += n as u64;
                }
                if copied != len - skip {
                    return Err(io::ErrorKind::UnexpectedEof.into());
                }
                first = false;
            }
            end = start;
        }
        Ok(())
    }
}

impl Drop for Spill {
    fn drop(&mut self) {
        if let Some(path) = &self.path {
            let _ = std::fs::remove_file(path);
        }
    }
}
