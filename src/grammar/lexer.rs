//! Turns grammar source into tokens.
//!
//! The lexer never stops at a bad character: it emits an [`Tok::Error`] token and goes on, so
//! the parser reports the error where it meets it and keeps looking for more. Newlines are
//! tokens; whether one ends a statement is the parser's call (it ignores them inside
//! brackets).

use super::ast::Span;
use crate::color::Color;

/// A token kind with its payload.
#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    /// An identifier or tag name: `animate`, `ease-in-out`, `inv_a1`.
    Ident(String),
    /// A number with its unit folded in (`500ms` → 0.5).
    Num(f64),
    /// A grid size `4x4`, or `4x4x3` with keyframes in time (2 when not written).
    Size(u32, u32, u32),
    /// A string literal, escapes resolved.
    Str(String),
    /// A colour literal `#rgb`, `#rrggbb`, `#rrggbbaa`.
    Color(Color),
    /// `(`
    LParen,
    /// `)`
    RParen,
    /// `{`, the papers' list brackets: `timesplit({0.3, 0.4, 0.3})`.
    LBrace,
    /// `}`
    RBrace,
    /// `[`
    LBracket,
    /// `]`
    RBracket,
    /// `,`
    Comma,
    /// `:`
    Colon,
    /// `=`
    Eq,
    /// `->` or `→`
    Arrow,
    /// `+`
    Plus,
    /// `-`
    Minus,
    /// `*`
    Star,
    /// `/`
    Slash,
    /// `%` used as the remainder operator
    Percent,
    /// `^`
    Caret,
    /// End of a line (comments end at it too).
    Newline,
    /// End of the source.
    Eof,
    /// Something that is not a token; the parser reports it when it reaches it.
    Error {
        /// What is wrong.
        message: String,
        /// How to fix it.
        help: Option<String>,
    },
}

impl Tok {
    /// How the token is named in error messages.
    pub fn describe(&self) -> String {
        match self {
            Tok::Ident(name) => format!("`{name}`"),
            Tok::Num(_) => "a number".into(),
            Tok::Size(..) => "a size".into(),
            Tok::Str(_) => "a string".into(),
            Tok::Color(_) => "a colour".into(),
            Tok::LParen => "`(`".into(),
            Tok::RParen => "`)`".into(),
            Tok::LBrace => "`{`".into(),
            Tok::RBrace => "`}`".into(),
            Tok::LBracket => "`[`".into(),
            Tok::RBracket => "`]`".into(),
            Tok::Comma => "`,`".into(),
            Tok::Colon => "`:`".into(),
            Tok::Eq => "`=`".into(),
            Tok::Arrow => "`->`".into(),
            Tok::Plus => "`+`".into(),
            Tok::Minus => "`-`".into(),
            Tok::Star => "`*`".into(),
            Tok::Slash => "`/`".into(),
            Tok::Percent => "`%`".into(),
            Tok::Caret => "`^`".into(),
            Tok::Newline => "end of line".into(),
            Tok::Eof => "end of file".into(),
            Tok::Error { .. } => "an invalid token".into(),
        }
    }
}

/// A token and where it is.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    /// What it is.
    pub tok: Tok,
    /// Where it is.
    pub span: Span,
}

/// Splits `src` into tokens, ending with [`Tok::Eof`].
pub fn tokenize(src: &str) -> Vec<Token> {
    let mut lexer = Lexer {
        src,
        pos: 0,
        line: 1,
        col: 1,
        tokens: Vec::new(),
    };
    lexer.run();
    lexer.tokens
}

/// True for characters that may continue an identifier (`-` is handled separately).
fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// True for characters that may start an identifier.
fn is_ident_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

/// `t₁` reads as `t1`: the papers subscript their tag numbers.
fn plain_subscripts(name: &str) -> String {
    name.chars()
        .map(|c| match c {
            '₀'..='₉' => char::from(b'0' + (c as u32 - '₀' as u32) as u8),
            c => c,
        })
        .collect()
}

struct Lexer<'a> {
    src: &'a str,
    pos: usize,
    line: u32,
    col: u32,
    tokens: Vec<Token>,
}

impl Lexer<'_> {
    fn peek(&self) -> Option<char> {
        self.src[self.pos..].chars().next()
    }

    fn peek_at(&self, n: usize) -> Option<char> {
        self.src[self.pos..].chars().nth(n)
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek()?;
        self.pos += c.len_utf8();
        // A lone carriage return (classic Mac OS line endings) ends a line too; in `\r\n`
        // the `\n` does.
        if c == '\n' || (c == '\r' && self.peek() != Some('\n')) {
            self.line += 1;
            self.col = 1;
        } else {
            self.col += 1;
        }
        Some(c)
    }

    fn bump_while(&mut self, f: impl Fn(char) -> bool) {
        while self.peek().is_some_and(&f) {
            self.bump();
        }
    }

    fn push(&mut self, tok: Tok, start: (usize, u32, u32)) {
        let (pos, line, col) = start;
        self.tokens.push(Token {
            tok,
            span: Span {
                line,
                col,
                start: pos,
                end: self.pos,
            },
        });
    }

    fn error(&mut self, start: (usize, u32, u32), message: String, help: Option<&str>) {
        self.push(
            Tok::Error {
                message,
                help: help.map(str::to_string),
            },
            start,
        );
    }

    fn run(&mut self) {
        loop {
            // A byte-order mark, which some Windows editors write, is whitespace too.
            while let Some(c) = self.peek() {
                let blank = matches!(c, ' ' | '\t' | '\u{feff}')
                    || (c == '\r' && self.peek_at(1) == Some('\n'));
                if !blank {
                    break;
                }
                self.bump();
            }
            let start = (self.pos, self.line, self.col);
            let Some(c) = self.peek() else {
                self.push(Tok::Eof, start);
                return;
            };
            match c {
                '\n' | '\r' => {
                    self.bump();
                    self.push(Tok::Newline, start);
                }
                '#' => {
                    if !self.colour(start) {
                        self.skip_comment();
                    }
                }
                '/' if self.peek_at(1) == Some('/') => self.skip_comment(),
                '"' => self.string(start),
                '0'..='9' if self.rule_label() => {}
                '0'..='9' => self.number(start),
                '⟨' | '〈' => self.angle_tag(start),
                '.' if self.peek_at(1).is_some_and(|d| d.is_ascii_digit()) => self.number(start),
                c if is_ident_start(c) => self.ident(start),
                '-' if self.peek_at(1) == Some('>') => {
                    self.bump();
                    self.bump();
                    self.push(Tok::Arrow, start);
                }
                _ => {
                    self.bump();
                    let tok = match c {
                        '(' => Tok::LParen,
                        ')' => Tok::RParen,
                        '{' => Tok::LBrace,
                        '}' => Tok::RBrace,
                        '[' => Tok::LBracket,
                        ']' => Tok::RBracket,
                        ',' => Tok::Comma,
                        ':' => Tok::Colon,
                        '=' => Tok::Eq,
                        '→' => Tok::Arrow,
                        '+' => Tok::Plus,
                        '-' => Tok::Minus,
                        '*' => Tok::Star,
                        '/' => Tok::Slash,
                        '%' => Tok::Percent,
                        '^' => Tok::Caret,
                        _ => {
                            let help = match c {
                                '\'' => Some("strings use double quotes: \"...\""),
                                ';' => Some("rules end at the end of the line; no `;` is needed"),
                                _ => None,
                            };
                            self.error(start, format!("unexpected character `{c}`"), help);
                            continue;
                        }
                    };
                    self.push(tok, start);
                }
            }
        }
    }

    /// Skips to the end of the line, leaving the newline for the next token.
    fn skip_comment(&mut self) {
        self.bump_while(|c| c != '\n' && c != '\r');
    }

    /// Lexes `#` + 3, 6 or 8 hex digits not followed by a word character as a colour.
    /// Returns false (consuming nothing) when the `#` starts a comment instead.
    fn colour(&mut self, start: (usize, u32, u32)) -> bool {
        let rest = &self.src[self.pos + 1..];
        let digits = rest.chars().take_while(|c| c.is_ascii_hexdigit()).count();
        let after = rest[digits..].chars().next();
        if !matches!(digits, 3 | 6 | 8) || after.is_some_and(|c| is_ident_char(c) || c == '-') {
            return false;
        }
        let text = &self.src[self.pos..self.pos + 1 + digits];
        let Some(color) = Color::parse(text) else {
            return false;
        };
        for _ in 0..=digits {
            self.bump();
        }
        self.push(Tok::Color(color), start);
        true
    }

    /// Lexes a string literal; strings end on the line they start.
    fn string(&mut self, start: (usize, u32, u32)) {
        self.bump();
        let mut value = String::new();
        loop {
            match self.peek() {
                None | Some('\n' | '\r') => {
                    self.error(
                        start,
                        "unterminated string".into(),
                        Some("a string ends with `\"` on the line it starts on"),
                    );
                    return;
                }
                Some('"') => {
                    self.bump();
                    self.push(Tok::Str(value), start);
                    return;
                }
                Some('\\') => {
                    let esc_start = (self.pos, self.line, self.col);
                    self.bump();
                    let escaped = match self.peek() {
                        Some('"') => '"',
                        Some('\\') => '\\',
                        Some('n') => '\n',
                        Some('t') => '\t',
                        other => {
                            // Report the bad escape and drop the rest of the string, so one
                            // mistake gives one error.
                            self.bump_while(|c| c != '"' && c != '\n' && c != '\r');
                            if self.peek() == Some('"') {
                                self.bump();
                            }
                            let shown = other
                                .filter(|c| *c != '\n')
                                .map(String::from)
                                .unwrap_or_default();
                            let message = format!("unknown escape `\\{shown}` in string");
                            let help = Some("the escapes are \\\" \\\\ \\n \\t");
                            // Point at the escape, but let the token cover the whole string so
                            // the parser skips it as one piece.
                            self.tokens.push(Token {
                                tok: Tok::Error {
                                    message,
                                    help: help.map(str::to_string),
                                },
                                span: Span {
                                    line: esc_start.1,
                                    col: esc_start.2,
                                    start: esc_start.0,
                                    end: self.pos,
                                },
                            });
                            return;
                        }
                    };
                    self.bump();
                    value.push(escaped);
                }
                Some(c) => {
                    self.bump();
                    value.push(c);
                }
            }
        }
    }

    /// Lexes a number with an optional unit (`s`, `ms`, `deg`, `%`) or a size `NxM`.
    fn number(&mut self, start: (usize, u32, u32)) {
        let digits = |lx: &mut Lexer| lx.bump_while(|c| c.is_ascii_digit());
        digits(self);
        let int_end = self.pos;
        // A size: integer, `x`, integer, with no spaces.
        if self.peek() == Some('x') && self.peek_at(1).is_some_and(|c| c.is_ascii_digit()) {
            self.bump();
            let rows_start = self.pos;
            digits(self);
            let (cols, rows) = (&self.src[start.0..int_end], &self.src[rows_start..self.pos]);
            // The paper's n×m×p: a third number is the keyframes in time.
            let mut keys = "2";
            if self.peek() == Some('x') && self.peek_at(1).is_some_and(|c| c.is_ascii_digit()) {
                self.bump();
                let keys_start = self.pos;
                digits(self);
                keys = &self.src[keys_start..self.pos];
            }
            if self.peek().is_some_and(|c| is_ident_char(c) || c == '.') {
                self.bump_while(|c| is_ident_char(c) || c == '.');
                self.error(
                    start,
                    "a size is written `NxM` or `NxMxP` with whole numbers, e.g. `4x4`".into(),
                    None,
                );
                return;
            }
            match (
                cols.parse::<u32>(),
                rows.parse::<u32>(),
                keys.parse::<u32>(),
            ) {
                (Ok(c), Ok(r), Ok(p)) => self.push(Tok::Size(c, r, p), start),
                _ => self.error(
                    start,
                    "size too large".into(),
                    Some("sizes must fit in 32 bits"),
                ),
            }
            return;
        }
        if self.peek() == Some('.') && self.peek_at(1).is_some_and(|c| c.is_ascii_digit()) {
            self.bump();
            digits(self);
        }
        if matches!(self.peek(), Some('e' | 'E')) {
            let sign = usize::from(matches!(self.peek_at(1), Some('+' | '-')));
            if self.peek_at(1 + sign).is_some_and(|c| c.is_ascii_digit()) {
                for _ in 0..=sign {
                    self.bump();
                }
                digits(self);
            }
        }
        let text = &self.src[start.0..self.pos];
        let Ok(mut value) = text.parse::<f64>() else {
            self.error(start, format!("invalid number `{text}`"), None);
            return;
        };
        let unit_start = self.pos;
        if self.peek() == Some('%')
            && !self
                .peek_at(1)
                .is_some_and(|c| is_ident_char(c) || c == '(' || c == '.')
        {
            self.bump();
            value /= 100.0;
        } else {
            self.bump_while(is_ident_char);
            match &self.src[unit_start..self.pos] {
                "" | "s" | "deg" => {}
                "ms" => value /= 1000.0,
                unit => {
                    let message = format!("unknown unit `{unit}`");
                    let help = "units are `s`, `ms`, `deg` and `%`; put a space or an operator between a number and a name";
                    self.error(start, message, Some(help));
                    return;
                }
            }
        }
        if value.is_finite() {
            self.push(Tok::Num(value), start);
        } else {
            self.error(
                start,
                format!("number `{text}` is too large"),
                Some("numbers must fit in a 64-bit float"),
            );
        }
    }

    /// Lexes an identifier: a letter or `_`, then letters, digits, `_`, and `-` when a letter
    /// follows it directly (`ease-in-out`; `a - b` and `a-1` stay subtractions).
    fn ident(&mut self, start: (usize, u32, u32)) {
        loop {
            self.bump_while(is_ident_char);
            if self.peek() == Some('-') && self.peek_at(1).is_some_and(char::is_alphabetic) {
                self.bump();
            } else {
                break;
            }
        }
        let name = plain_subscripts(&self.src[start.0..self.pos]);
        self.push(Tok::Ident(name), start);
    }

    /// Skips a rule number such as `1.` or `12)` at the start of a line, as the papers
    /// number their rules (gMotion Fig. 4, gTangle Fig. 9). Only a whole number directly
    /// followed by `.` or `)` and a blank, as the first thing on its line, is a label.
    fn rule_label(&mut self) -> bool {
        let first_on_line = self.tokens.last().is_none_or(|t| t.tok == Tok::Newline);
        if !first_on_line {
            return false;
        }
        let rest = &self.src[self.pos..];
        let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
        let mut after = rest[digits..].chars();
        let is_label = matches!(after.next(), Some('.' | ')'))
            && after.next().is_some_and(|c| c == ' ' || c == '\t');
        if is_label {
            for _ in 0..=digits {
                self.bump();
            }
        }
        is_label
    }

    /// A tag between angle brackets, as gTangle prints its output tags: `⟨in 2⟩` is the
    /// tag `in_2` (words joined as the parser joins them outside brackets).
    fn angle_tag(&mut self, start: (usize, u32, u32)) {
        self.bump();
        let body_start = self.pos;
        self.bump_while(|c| !matches!(c, '⟩' | '〉' | '\n' | '\r'));
        let body = &self.src[body_start..self.pos];
        if !matches!(self.peek(), Some('⟩' | '〉')) {
            self.error(
                start,
                "unclosed `⟨`".into(),
                Some("an angle-bracketed tag ends with `⟩` on its line"),
            );
            return;
        }
        self.bump();
        let name = plain_subscripts(&body.split_whitespace().collect::<Vec<_>>().join("_"));
        if name.is_empty() {
            self.error(start, "empty tag `⟨⟩`".into(), None);
        } else {
            self.push(Tok::Str(name), start);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(src: &str) -> Vec<Tok> {
        tokenize(src).into_iter().map(|t| t.tok).collect()
    }

    fn ident(s: &str) -> Tok {
        Tok::Ident(s.into())
    }

    #[test]
    fn units_fold_into_values() {
        assert_eq!(
            kinds("6s 500ms 30deg 50% 1e3 .5"),
            vec![
                Tok::Num(6.0),
                Tok::Num(0.5),
                Tok::Num(30.0),
                Tok::Num(0.5),
                Tok::Num(1000.0),
                Tok::Num(0.5),
                Tok::Eof
            ]
        );
    }

    #[test]
    fn percent_before_an_operand_is_the_remainder() {
        assert_eq!(
            kinds("7%3"),
            vec![Tok::Num(7.0), Tok::Percent, Tok::Num(3.0), Tok::Eof]
        );
        assert_eq!(
            kinds("id%2"),
            vec![ident("id"), Tok::Percent, Tok::Num(2.0), Tok::Eof]
        );
    }

    #[test]
    fn dashes_join_identifiers_only_before_letters() {
        assert_eq!(kinds("ease-in-out"), vec![ident("ease-in-out"), Tok::Eof]);
        assert_eq!(
            kinds("a - b"),
            vec![ident("a"), Tok::Minus, ident("b"), Tok::Eof]
        );
        assert_eq!(
            kinds("id-1"),
            vec![ident("id"), Tok::Minus, Tok::Num(1.0), Tok::Eof]
        );
        assert_eq!(
            kinds("a->[b]"),
            vec![
                ident("a"),
                Tok::Arrow,
                Tok::LBracket,
                ident("b"),
                Tok::RBracket,
                Tok::Eof
            ]
        );
    }

    #[test]
    fn hash_is_a_colour_only_before_hex_digits() {
        let red = Color::rgb(1.0, 0.0, 0.0);
        assert_eq!(kinds("#f00 # note"), vec![Tok::Color(red), Tok::Eof]);
        assert_eq!(kinds("#ff0000"), vec![Tok::Color(red), Tok::Eof]);
        assert_eq!(
            kinds("#fade out\n1"),
            vec![Tok::Newline, Tok::Num(1.0), Tok::Eof]
        );
        assert_eq!(kinds("#bad-idea"), vec![Tok::Eof]);
        assert_eq!(
            kinds("x // comment\ny"),
            vec![ident("x"), Tok::Newline, ident("y"), Tok::Eof]
        );
    }

    #[test]
    fn sizes_and_arrows() {
        assert_eq!(
            kinds("4x3 → ->"),
            vec![Tok::Size(4, 3, 2), Tok::Arrow, Tok::Arrow, Tok::Eof]
        );
    }

    #[test]
    fn strings_unescape_and_must_close_on_their_line() {
        assert_eq!(
            kinds(r#""a\"b\\""#),
            vec![Tok::Str("a\"b\\".into()), Tok::Eof]
        );
        let toks = tokenize("\"abc\nx");
        assert!(
            matches!(&toks[0].tok, Tok::Error { message, .. } if message == "unterminated string")
        );
        assert_eq!(toks[1].tok, Tok::Newline);
    }

    #[test]
    fn bad_numbers_are_error_tokens() {
        for src in ["1e999", "5px", "99999999999x2", "2x3.5"] {
            let toks = tokenize(src);
            assert!(matches!(toks[0].tok, Tok::Error { .. }), "{src}: {toks:?}");
            assert_eq!(toks.len(), 2, "{src}: {toks:?}");
        }
    }

    #[test]
    fn byte_order_mark_and_crlf_are_whitespace() {
        assert_eq!(
            kinds("\u{feff}a\r\nb"),
            vec![ident("a"), Tok::Newline, ident("b"), Tok::Eof]
        );
    }

    #[test]
    fn spans_count_characters_and_lines() {
        let toks = tokenize("a\n  →b");
        assert_eq!(
            toks[2].span,
            Span {
                line: 2,
                col: 3,
                start: 4,
                end: 7
            }
        );
        assert_eq!(
            toks[3].span,
            Span {
                line: 2,
                col: 4,
                start: 7,
                end: 8
            }
        );
    }
}
