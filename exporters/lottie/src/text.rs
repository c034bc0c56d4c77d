//! Lottie JSON as it was written: the document's head, each layer and its tail as pieces
//! of their own, rather than one string. A large export goes to its file straight from
//! the pieces, a thousand to a system call, instead of first being copied into one
//! allocation of its whole size: at the intersections scale that copy was 16 MB of fresh
//! memory, faulted in page by page on the one thread left at the end of an export.

use std::io::{self, Write};

/// Lottie JSON text, in pieces that make the document when joined in order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LottieText {
    pieces: Vec<Vec<u8>>,
}

impl LottieText {
    /// The text made of `pieces`, each valid UTF-8 on its own.
    pub(crate) fn new(pieces: Vec<Vec<u8>>) -> LottieText {
        LottieText { pieces }
    }

    /// The length of the text in bytes.
    pub fn len(&self) -> usize {
        self.pieces.iter().map(Vec::len).sum()
    }

    /// How many pieces the text is held in.
    pub fn pieces(&self) -> usize {
        self.pieces.len()
    }

    /// Whether the text is empty.
    pub fn is_empty(&self) -> bool {
        self.pieces.iter().all(Vec::is_empty)
    }

    /// Writes the text to `out`. A writer that takes vectored writes (a file, or a
    /// `BufWriter` over one) gets many pieces a call.
    pub fn write_to(&self, out: &mut impl Write) -> io::Result<()> {
        gmotion::atomic::write_pieces(out, self.pieces.iter().map(Vec::as_slice))
    }

    /// The text as one string.
    pub fn into_string(self) -> String {
        let mut out = Vec::with_capacity(self.len());
        for p in self.pieces {
            out.extend_from_slice(&p);
        }
        String::from_utf8(out).expect("every piece is UTF-8 (serde_json writes UTF-8)")
    }
}

impl From<String> for LottieText {
    fn from(s: String) -> LottieText {
        LottieText::new(vec![s.into_bytes()])
    }
}
