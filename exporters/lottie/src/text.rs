//! Lottie JSON as it was written: the document's head, each layer and its tail as pieces
//! of their own, rather than one string. A large export goes to its file straight from
//! the pieces, a thousand to a system call, instead of first being copied into one
//! allocation of its whole size: at the intersections scale that copy was 16 MB of fresh
//! memory, faulted in page by page on the one thread left at the end of an export.

use std::io::{self, IoSlice, Write};

/// Lottie JSON text, in pieces that make the document when joined in order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LottieText {
    pieces: Vec<Vec<u8>>,
}

/// How many pieces one `write_vectored` call is given (Linux's `IOV_MAX`).
const PIECES_PER_WRITE: usize = 1024;

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
        for chunk in self.pieces.chunks(PIECES_PER_WRITE) {
            let mut slices: Vec<IoSlice<'_>> = chunk.iter().map(|p| IoSlice::new(p)).collect();
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

#[cfg(test)]
mod tests {
    use super::*;

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
        let text = LottieText::new(pieces);
        let joined = text.clone().into_string();
        assert_eq!(joined.len(), text.len());
        for most in [1, 7, 4096, usize::MAX / 2] {
            let mut w = Trickle {
                out: Vec::new(),
                most,
                calls: 0,
            };
            text.write_to(&mut w).unwrap();
            assert_eq!(String::from_utf8(w.out).unwrap(), joined, "{most} a call");
        }
        // Whole pieces go a thousand to a call.
        let mut w = Trickle {
            out: Vec::new(),
            most: usize::MAX / 2,
            calls: 0,
        };
        text.write_to(&mut w).unwrap();
        assert_eq!(w.calls, 3);
    }

    #[test]
    fn a_writer_that_takes_nothing_is_an_error_not_a_loop() {
        let text = LottieText::from("{}".to_string());
        let mut w = Trickle {
            out: Vec::new(),
            most: 0,
            calls: 0,
        };
        let e = text.write_to(&mut w).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::WriteZero);
    }
}
