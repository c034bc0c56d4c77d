//! Lottie JSON as the exporter hands it over: a text already written (a source written
//! back, a document with slots or packed), the document's model, written when its
//! destination is known, or a document whose layers are built as they are written. A
//! large export is written straight to its file a run of layers at a time
//! ([`crate::model::Animation::write_to`]), each run freed once written, instead of first
//! being turned into a text as large as the file (856 MB for 999 000 shapes); a large
//! scene's layers are built a run at a time too ([`crate::layers::Builder::write_root`]).

use std::fmt;
use std::io::{self, Write};

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
}

impl fmt::Debug for LottieText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let held = match &self.held {
            Held::Text(text) => format!("{} bytes of text", text.len()),
            Held::Document(doc) => format!("a document of {} layers", doc.layers.len()),
            Held::Stream(_) => "a document built as it is written".to_string(),
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

    /// Writes the text to `out`, freeing what is written as it goes. A writer that takes
    /// vectored writes (a file, or a `BufWriter` over one) gets many pieces a call.
    pub fn write_to(self, out: &mut dyn Write) -> io::Result<()> {
        match self.held {
            Held::Text(text) => out.write_all(&text),
            Held::Document(doc) => doc.write_to(out),
            Held::Stream(write) => write(out),
        }
    }

    /// Whether the layers are built as they are written.
    #[cfg(test)]
    pub(crate) fn is_streamed(&self) -> bool {
        matches!(self.held, Held::Stream(_))
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
