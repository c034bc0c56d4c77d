//! An animated SVG as a document and the edits spliced into it, rather than one string:
//! what [`super::smil_document`] returns, and how a tinted copy of a definition is put
//! together. A large export is not held at all: [`super::SmilWriter`] streams it.

use std::io::{self, Write};

/// Animated SVG text: a document and the edits spliced into it, in order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SmilText {
    /// The static document the edits apply to.
    doc: String,
    /// `(start, end, text)`: `doc[start..end]` replaced by `text`, sorted by position;
    /// ranges do not overlap.
    edits: Vec<(usize, usize, String)>,
}

impl SmilText {
    /// `doc` with `edits` applied; `edits` sorted by position, ranges not overlapping.
    pub(crate) fn new(doc: String, edits: Vec<(usize, usize, String)>) -> SmilText {
        SmilText { doc, edits }
    }

    /// The text's pieces in order: the kept document before each edit, then the edit's.
    fn pieces(&self) -> impl Iterator<Item = &str> {
        let mut at = 0;
        self.edits
            .iter()
            .flat_map(move |(start, end, text)| {
                let kept = &self.doc[at..(*start).max(at)];
                at = at.max(*end);
                [kept, text.as_str()]
            })
            .chain(std::iter::once_with(move || {
                let last = self.edits.iter().map(|e| e.1).max().unwrap_or(0);
                &self.doc[last..]
            }))
    }

    /// The length of the text in bytes.
    pub fn len(&self) -> usize {
        self.pieces().map(str::len).sum()
    }

    /// Whether the text is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// How many edits the text holds (what freeing it costs).
    pub fn edits(&self) -> usize {
        self.edits.len()
    }

    /// Writes the text to `out`. A writer that takes vectored writes (a file, or a
    /// `BufWriter` over one) gets many pieces a call.
    pub fn write_to(&self, out: &mut impl Write) -> io::Result<()> {
        gmotion::atomic::write_pieces(out, self.pieces().map(str::as_bytes))
    }

    /// The text as one string.
    pub fn into_string(self) -> String {
        if self.edits.is_empty() {
            return self.doc;
        }
        let mut out = String::with_capacity(self.len());
        self.push_to(&mut out);
        out
    }

    /// Appends the text to `out`.
    pub fn push_to(&self, out: &mut String) {
        for p in self.pieces() {
            out.push_str(p);
        }
    }
}

impl From<String> for SmilText {
    fn from(doc: String) -> SmilText {
        SmilText::new(doc, Vec::new())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_join_to_the_edited_document() {
        let doc = "<svg>\n<g id=\"a\"/>\n<path id=\"b\"/>\n</svg>\n".to_string();
        let at = |s: &str| doc.find(s).unwrap();
        let edits = vec![
            (at("<g"), at("<g"), "<g transform=\"x\">".to_string()),
            (at(" id=\"b\""), at(" id=\"b\"") + 7, String::new()),
            (at("/>\n</svg>"), at("/>\n</svg>"), ">".to_string()),
        ];
        let text = SmilText::new(doc.clone(), edits);
        let joined = text.clone().into_string();
        assert_eq!(
            joined,
            "<svg>\n<g transform=\"x\"><g id=\"a\"/>\n<path>/>\n</svg>\n"
        );
        assert_eq!(text.len(), joined.len());
        let mut written = Vec::new();
        text.write_to(&mut written).unwrap();
        assert_eq!(written, joined.as_bytes());
        assert_eq!(SmilText::from(doc.clone()).into_string(), doc);
    }
}
