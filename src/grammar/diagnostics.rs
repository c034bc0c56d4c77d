//! Errors in a grammar file, with their location and a caret rendering.
//!
//! The parser collects every error it can recover from into one [`Diagnostics`], so a user
//! fixes a file in one round instead of one error per run. Errors of meaning (an
//! [`EngineError`](crate::engine::EngineError)) become the same [`Diagnostic`], their notes
//! its help: the command line renders it, the studio sends it to the page whole.

use std::fmt;

use super::ast::Span;

/// One error: where it is, what is wrong, what would have been accepted, and a hint.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// The offending source range; line 0 when the error has no place in the source
    /// ([`Diagnostic::general`]).
    pub span: Span,
    /// What is wrong, in one sentence without a trailing period.
    pub message: String,
    /// What would have been accepted at this point (already quoted, e.g. "`->`").
    pub expected: Vec<String>,
    /// A suggestion for the fix.
    pub help: Option<String>,
}

impl Diagnostic {
    /// An error with a message and nothing else.
    pub fn new(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            span,
            message: message.into(),
            expected: Vec::new(),
            help: None,
        }
    }

    /// An error with no place in the source (a scene that cannot be imported, a run that
    /// fails as a whole).
    pub fn general(message: impl Into<String>) -> Diagnostic {
        Diagnostic::new(Span::default(), message)
    }

    /// Whether the error points at a place in the source.
    pub fn has_place(&self) -> bool {
        self.span.line > 0
    }

    /// The same error with a list of accepted alternatives.
    pub fn with_expected<S: Into<String>>(
        mut self,
        expected: impl IntoIterator<Item = S>,
    ) -> Diagnostic {
        self.expected = expected.into_iter().map(Into::into).collect();
        self
    }

    /// The same error with a hint.
    pub fn with_help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    /// Renders this error as `file:line:col: error: message`, the source line, a caret line
    /// under the span, then the expected alternatives and the hint. An error with no place
    /// is `file: error: message` with each line of the hint as a note.
    pub fn render(&self, file_name: &str, src: &str) -> String {
        if !self.has_place() {
            let mut out = format!("{file_name}: error: {}\n", self.message);
            let expected = self.expected_line();
            for line in expected.iter().chain(&self.help).flat_map(|h| h.lines()) {
                out.push_str(&format!("  note: {line}\n"));
            }
            return out;
        }
        let Span { line, col, .. } = self.span;
        let mut out = format!("{file_name}:{line}:{col}: error: {}\n", self.message);
        let text = source_line(src, self.span.start);
        let gutter = line.to_string().len();
        let pad = " ".repeat(gutter);
        out.push_str(&format!("{pad} |\n{line} | {text}\n"));
        out.push_str(&format!(
            "{pad} | {}\n",
            caret_line(text, col, self.caret_len(src))
        ));
        if let Some(expected) = self.expected_line() {
            out.push_str(&format!("{pad} = {expected}\n"));
        }
        if let Some(help) = &self.help {
            // Further lines of a long hint line up under its first line.
            let help = help.replace('\n', &format!("\n{pad}         "));
            out.push_str(&format!("{pad} = help: {help}\n"));
        }
        out
    }

    /// `expected X` or `expected one of X, Y`, when alternatives are known.
    pub fn expected_line(&self) -> Option<String> {
        match self.expected.len() {
            0 => None,
            1 => Some(format!("expected {}", self.expected[0])),
            _ => Some(format!("expected one of {}", self.expected.join(", "))),
        }
    }

    /// How many characters of the span lie on its first line (at least one, so an empty span
    /// such as "end of file" still gets a caret).
    fn caret_len(&self, src: &str) -> usize {
        let end = self.span.end.min(src.len()).max(self.span.start);
        let text = src.get(self.span.start..end).unwrap_or("");
        text.split(['\n', '\r'])
            .next()
            .unwrap_or("")
            .chars()
            .count()
            .max(1)
    }
}

/// The text of the line holding byte `at` without its line terminator (empty past the
/// end). Lines end at `\n`, `\r\n` or a lone `\r`, as the lexer counts them. Found from the
/// byte offset, not by counting lines from the start, so rendering every error of a file
/// takes time linear in it.
fn source_line(src: &str, at: usize) -> &str {
    let mut at = at.min(src.len());
    while !src.is_char_boundary(at) {
        at -= 1;
    }
    let is_end = |c: char| c == '\n' || c == '\r';
    let start = src[..at].rfind(is_end).map_or(0, |i| i + 1);
    let end = src[start..].find(is_end).map_or(src.len(), |i| start + i);
    &src[start..end]
}

/// Spaces up to column `col` (tabs kept, so the caret lines up with the source above it),
/// then `len` carets.
fn caret_line(text: &str, col: u32, len: usize) -> String {
    let lead: String = text
        .chars()
        .take(col.saturating_sub(1) as usize)
        .map(|c| if c == '\t' { '\t' } else { ' ' })
        .collect();
    let missing = (col.saturating_sub(1) as usize).saturating_sub(lead.chars().count());
    format!("{lead}{}{}", " ".repeat(missing), "^".repeat(len))
}

/// The candidate closest to `name` by edit distance, when it is close enough to be a likely
/// typo (at most a third of the name's length, and at least one edit allowed). Case and
/// word separators do not count, so `easeInOut` finds `ease-in-out`.
pub fn did_you_mean<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    let folded = |s: &str| -> String {
        s.chars()
            .filter(|c| !matches!(c, '-' | '_' | ' '))
            .flat_map(char::to_lowercase)
            .collect()
    };
    let name = folded(name);
    let len = name.chars().count();
    let limit = (len / 3).max(1);
    candidates
        .into_iter()
        .map(|c| (folded(c), c))
        // The distance is at least the difference in length: most candidates are ruled out
        // without the quadratic comparison (a file of unknown words stays fast to report).
        .filter(|(f, _)| f.chars().count().abs_diff(len) <= limit)
        .map(|(f, c)| (edit_distance(&name, &f), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// Edit distance over characters, counting a swap of two neighbours as one edit (optimal
/// string alignment), since `wrold` for `world` is one slip of the fingers.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut before: Vec<usize> = Vec::new();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for i in 1..=a.len() {
        let mut row = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            row[j] = (prev[j] + 1).min(row[j - 1] + 1).min(prev[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                row[j] = row[j].min(before[j - 2] + 1);
            }
        }
        before = std::mem::replace(&mut prev, row);
    }
    prev[b.len()]
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.span.line, self.span.col, self.message)?;
        match self.expected.len() {
            0 => {}
            1 => write!(f, " (expected {})", self.expected[0])?,
            _ => write!(f, " (expected one of {})", self.expected.join(", "))?,
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostic {}

/// The most errors kept and shown for one file; the rest are counted. A file of garbage
/// (200 000 lines of it) would otherwise print hundreds of megabytes nobody reads.
pub const MAX_SHOWN: usize = 100;

/// Every error found in one grammar file, in source order: the first [`MAX_SHOWN`], and a
/// count of the rest.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Diagnostics {
    /// The errors kept (at most [`MAX_SHOWN`]).
    pub items: Vec<Diagnostic>,
    /// Errors found after the first [`MAX_SHOWN`], counted but not kept.
    pub omitted: usize,
}

impl Diagnostics {
    /// Adds an error (counts it only, past the first [`MAX_SHOWN`]).
    pub fn push(&mut self, diagnostic: Diagnostic) {
        if self.items.len() < MAX_SHOWN {
            self.items.push(diagnostic);
        } else {
            self.omitted += 1;
        }
    }

    /// Number of errors, those counted but not kept included.
    pub fn len(&self) -> usize {
        self.items.len() + self.omitted
    }

    /// True when there are no errors.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The errors in source order.
    pub fn iter(&self) -> std::slice::Iter<'_, Diagnostic> {
        self.items.iter()
    }

    /// Renders every error (see [`Diagnostic::render`]), separated by blank lines and
    /// followed by a count when there are several.
    pub fn render(&self, file_name: &str, src: &str) -> String {
        let mut out: Vec<String> = self
            .items
            .iter()
            .map(|d| d.render(file_name, src))
            .collect();
        if self.omitted > 0 {
            out.push(format!(
                "… {} more errors not shown (the first {MAX_SHOWN} are)\n",
                self.omitted
            ));
        }
        if self.len() > 1 {
            out.push(format!("{} errors in {file_name}\n", self.len()));
        }
        out.join("\n")
    }
}

impl From<Diagnostic> for Diagnostics {
    fn from(diagnostic: Diagnostic) -> Diagnostics {
        Diagnostics {
            items: vec![diagnostic],
            omitted: 0,
        }
    }
}

impl<'a> IntoIterator for &'a Diagnostics {
    type Item = &'a Diagnostic;
    type IntoIter = std::slice::Iter<'a, Diagnostic>;
    fn into_iter(self) -> Self::IntoIter {
        self.items.iter()
    }
}

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, d) in self.items.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{d}")?;
        }
        if self.omitted > 0 {
            write!(f, "\n… {} more errors", self.omitted)?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostics {}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(line: u32, col: u32, start: usize, end: usize) -> Span {
        Span {
            line,
            col,
            start,
            end,
        }
    }

    #[test]
    fn suggestions_catch_typos_only() {
        let names = ["duration", "fps", "grid", "seed"];
        assert_eq!(did_you_mean("durration", names), Some("duration"));
        assert_eq!(did_you_mean("sed", names), Some("seed"));
        assert_eq!(did_you_mean("colour", names), None);
    }

    #[test]
    fn caret_sits_under_the_span() {
        let src = "duration 6s\nfoo bar baz\n";
        let d = Diagnostic::new(span(2, 5, 16, 19), "unknown thing")
            .with_expected(["`a`", "`b`"])
            .with_help("try harder");
        let text = d.render("g.gm", src);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "g.gm:2:5: error: unknown thing");
        assert_eq!(lines[2], "2 | foo bar baz");
        assert_eq!(lines[3], "  |     ^^^");
        assert_eq!(lines[4], "  = expected one of `a`, `b`");
        assert_eq!(lines[5], "  = help: try harder");
    }

    #[test]
    fn multi_line_help_is_indented() {
        let d = Diagnostic::new(span(1, 1, 0, 1), "x").with_help("first\nsecond");
        let text = d.render("f", "a");
        assert!(
            text.ends_with("  = help: first\n          second\n"),
            "{text}"
        );
    }

    /// The caret line of an error at `at` in `src`.
    fn caret_line(src: &str, at: Span) -> String {
        let d = Diagnostic::new(at, "x");
        d.render("f", src).lines().nth(3).unwrap().to_string()
    }

    #[test]
    fn tabs_are_kept_and_empty_spans_get_one_caret() {
        assert_eq!(caret_line("\tab", span(1, 3, 2, 2)), "  | \t ^");
    }

    #[test]
    fn multi_line_span_underlines_its_first_line_only() {
        assert_eq!(caret_line("ab(\ncd)", span(1, 3, 2, 7)), "  |   ^");
    }
}
