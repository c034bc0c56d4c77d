//! Lottie JSON as the exporter hands it over: a text already written (a source written
//! back, a document with slots or packed), or the document's model, written when its
//! destination is known. A large export is written straight to its file a run of layers
//! at a time ([`crate::model::Animation::write_to`]), each run freed once written, instead
//! of first being turned into a text as large as the file (856 MB for 999 000 shapes).

use std::io::{self, Write};

use crate::model::Animation;

/// Lottie JSON, as text or as the document that writes it.
#[derive(Clone, Debug)]
pub struct LottieText {
    held: Held,
}

#[derive(Clone, Debug)]
enum Held {
    Text(Vec<u8>),
    Document(Box<Animation>),
}

impl LottieText {
    /// The text `doc` writes, written when asked for.
    pub(crate) fn document(doc: Animation) -> LottieText {
        LottieText {
            held: Held::Document(Box::new(doc)),
        }
    }

    /// Writes the text to `out`, freeing what is written as it goes. A writer that takes
    /// vectored writes (a file, or a `BufWriter` over one) gets many pieces a call.
    pub fn write_to(self, out: &mut dyn Write) -> io::Result<()> {
        match self.held {
            Held::Text(text) => out.write_all(&text),
            Held::Document(doc) => doc.write_to(out),
        }
    }

    /// The text as one string.
    pub fn into_string(self) -> String {
        let bytes = match self.held {
            Held::Text(text) => text,
            Held::Document(doc) => {
                let mut out = Vec::new();
                doc.write_to(&mut out)
                    .expect("writing into memory does not fail");
                out
            }
        };
        String::from_utf8(bytes).expect("the text is UTF-8 (serde_json writes UTF-8)")
    }
}

impl From<String> for LottieText {
    fn from(s: String) -> LottieText {
        LottieText {
            held: Held::Text(s.into_bytes()),
        }
    }
}
