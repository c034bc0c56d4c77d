//! Recursive-descent parser from tokens to the [`ast`](super::ast).
//!
//! A file is a list of statements, one per line: header directives and rules. When a
//! statement has an error the parser records it, skips to the start of the next statement
//! and goes on, so one run reports every independent error.
//!
//! Line structure: a newline ends a statement, except inside `(…)` and `[…]`, and except
//! before a line that starts with `:`, `->`/`→` or an indented `priority=`/`weight=`, which
//! continue the rule above. Inside brackets, a line whose first token is a name at column 1
//! is taken as a new statement, so a forgotten `)` costs one error, not the rest of the file.

use std::collections::HashMap;

use super::ast::{Arg, BinOp, Directive, Expr, ExprKind, Grammar, Rule, Span, TagRef};
use super::diagnostics::{Diagnostic, Diagnostics, did_you_mean};
use super::directives::{DIRECTIVES, DirectiveKind, DirectiveSpec, directive_spec};
use super::lexer::{Tok, Token, tokenize};

/// The nesting budget of one expression. Parsing, evaluation and every later walk of the
/// tree recurse once per level, so this bounds their stack use (debug builds spend about
/// 10 KiB of stack per bracket level in the parser). A bracket, call or unary minus costs
/// [`NEST_COST`]; each operator in a chain `a + b + …` deepens the tree by one and costs 1.
/// So 64 nested brackets, or a chain of 256 operators, is the limit.
const MAX_NESTING: usize = 256;

/// What one level of recursion in the parser costs of [`MAX_NESTING`].
const NEST_COST: usize = 4;

/// The most terms the expression a `let` name stands for may have.
const MAX_LET_NODES: usize = 4096;

/// The most terms all uses of `let` names in one file may stand for together.
const MAX_LET_TERMS_READ: usize = 1_000_000;

/// An expression's terms and depth.
fn size(e: &Expr) -> (usize, usize) {
    let children: Vec<&Expr> = match &e.kind {
        ExprKind::Call { args, .. } => args.iter().map(|a| &a.value).collect(),
        ExprKind::Tuple(items) => items.iter().collect(),
        ExprKind::Neg(x) => vec![x],
        ExprKind::Binary { lhs, rhs, .. } => vec![lhs, rhs],
        _ => Vec::new(),
    };
    children
        .into_iter()
        .map(size)
        .fold((1, 1), |(n, d), (cn, cd)| (n + cn, d.max(cd + 1)))
}

/// The prefix that marks an inverted tag.
const INV_PREFIX: &str = "inv_";

/// Parses a grammar file. Returns every error found when there is at least one.
pub fn parse(src: &str) -> Result<Grammar, Diagnostics> {
    let mut parser = Parser {
        src,
        toks: tokenize(src),
        pos: 0,
        open: Vec::new(),
        nesting: 0,
        lets: HashMap::new(),
        let_terms_read: 0,
        diags: Diagnostics::default(),
    };
    let grammar = parser.file();
    if parser.diags.is_empty() {
        Ok(grammar)
    } else {
        Err(parser.diags)
    }
}

type PResult<T> = Result<T, Diagnostic>;

/// What a rule matches: slice tags, shape tags, shape tags left out, and whether the rule
/// is spatial (one tag list).
type Matched = (Vec<TagRef>, Vec<TagRef>, Vec<TagRef>, bool);

/// A span from the start of `a` to the end of `b`.
fn join(a: Span, b: Span) -> Span {
    Span {
        end: b.end.max(a.end),
        ..a
    }
}

fn quoted(names: &[&str]) -> Vec<String> {
    names.iter().map(|n| format!("`{n}`")).collect()
}

struct Parser<'a> {
    src: &'a str,
    toks: Vec<Token>,
    pos: usize,
    /// Spans of the brackets opened and not yet closed in the current statement.
    open: Vec<Span>,
    /// Current expression nesting depth.
    nesting: usize,
    /// `let` bindings so far: a later expression naming one reads its expression, with
    /// its number of terms.
    lets: HashMap<String, (Expr, usize)>,
    /// Terms read through `let` names in the whole file (capped: [`MAX_LET_TERMS_READ`]).
    let_terms_read: usize,
    diags: Diagnostics,
}

impl Parser<'_> {
    // ----- token access -----

    /// True when token `i` is a newline that ends the statement even inside brackets: the
    /// next line starts with a name at column 1.
    fn is_hard_newline(&self, i: usize) -> bool {
        self.toks[i].tok == Tok::Newline
            && self
                .toks
                .get(i + 1)
                .is_some_and(|t| matches!(t.tok, Tok::Ident(_)) && t.span.col == 1)
    }

    /// The current token, skipping newlines inside brackets.
    fn peek(&mut self) -> &Token {
        if !self.open.is_empty() {
            while self.toks[self.pos].tok == Tok::Newline && !self.is_hard_newline(self.pos) {
                self.pos += 1;
            }
        }
        &self.toks[self.pos]
    }

    /// The token right after the current one (no newline skipping).
    fn peek_next(&mut self) -> &Tok {
        self.peek();
        &self.toks[(self.pos + 1).min(self.toks.len() - 1)].tok
    }

    fn at(&mut self, tok: &Tok) -> bool {
        self.peek().tok == *tok
    }

    /// Consumes the current token, tracking bracket nesting.
    fn bump(&mut self) -> Token {
        let token = self.peek().clone();
        match token.tok {
            Tok::Eof => return token,
            Tok::LParen | Tok::LBracket | Tok::LBrace => self.open.push(token.span),
            Tok::RParen | Tok::RBracket | Tok::RBrace => {
                self.open.pop();
            }
            _ => {}
        }
        self.pos += 1;
        token
    }

    fn eat(&mut self, tok: &Tok) -> Option<Token> {
        if self.at(tok) {
            Some(self.bump())
        } else {
            None
        }
    }

    fn expect(&mut self, tok: &Tok, expected: &[&str]) -> PResult<Token> {
        match self.eat(tok) {
            Some(t) => Ok(t),
            None => Err(self.unexpected(expected)),
        }
    }

    /// The span of the last consumed token.
    fn prev_span(&self) -> Span {
        self.toks[self.pos.saturating_sub(1)].span
    }

    /// If the statement continues on a following line whose first token satisfies `starts`,
    /// moves to that token.
    fn continue_line_if(&mut self, starts: impl Fn(&[Token], usize) -> bool) {
        let mut i = self.pos;
        while self.toks[i].tok == Tok::Newline {
            i += 1;
        }
        if i != self.pos && starts(&self.toks, i) {
            self.pos = i;
        }
    }

    /// An error at the current token: "unexpected X", or the lexer's own message for a bad
    /// token, or "unclosed `(`" when a bracket is still open at a statement's end.
    fn unexpected(&mut self, expected: &[&str]) -> Diagnostic {
        let token = self.peek().clone();
        match token.tok {
            Tok::Error { message, help } => {
                let d = Diagnostic::new(token.span, message);
                match help {
                    Some(h) => d.with_help(h),
                    None => d,
                }
            }
            Tok::Newline | Tok::Eof if !self.open.is_empty() => {
                let opener = *self.open.last().unwrap_or(&token.span);
                let which = match self.src.get(opener.start..opener.end) {
                    Some("[") => "[",
                    Some("{") => "{",
                    _ => "(",
                };
                let d = Diagnostic::new(opener, format!("unclosed `{which}`"))
                    .with_expected(expected.iter().copied());
                if token.tok == Tok::Newline {
                    d.with_help("a line that starts with a name at column 1 begins a new statement; indent continuation lines")
                } else {
                    d
                }
            }
            ref tok => {
                let found = match tok {
                    Tok::Num(_) | Tok::Size(..) | Tok::Color(_) => {
                        format!("`{}`", &self.src[token.span.start..token.span.end])
                    }
                    _ => tok.describe(),
                };
                Diagnostic::new(token.span, format!("unexpected {found}"))
                    .with_expected(expected.iter().copied())
            }
        }
    }

    // ----- statements -----

    fn file(&mut self) -> Grammar {
        let mut grammar = Grammar::default();
        let mut seen: HashMap<String, u32> = HashMap::new();
        loop {
            self.open.clear();
            self.nesting = 0;
            while self.toks[self.pos].tok == Tok::Newline {
                self.pos += 1;
            }
            if self.toks[self.pos].tok == Tok::Eof {
                return grammar;
            }
            if let Err(d) = self.statement(&mut grammar, &mut seen) {
                self.diags.push(d);
                self.recover();
            }
        }
    }

    /// Skips the rest of a broken statement: to the next newline outside the brackets it
    /// opened that is followed by something that can start a statement (a name not followed
    /// by `=`, or any token at column 1 that cannot continue a rule), or to any line starting
    /// with a name at column 1.
    fn recover(&mut self) {
        let mut depth = self.open.len() as i64;
        loop {
            match self.toks[self.pos].tok {
                Tok::Eof => return,
                Tok::Newline => {
                    let next = &self.toks[self.pos + 1];
                    let starts_statement = match next.tok {
                        Tok::Ident(_) => {
                            self.toks.get(self.pos + 2).is_none_or(|t| t.tok != Tok::Eq)
                        }
                        Tok::Eof => true,
                        Tok::Colon
                        | Tok::Arrow
                        | Tok::RParen
                        | Tok::RBracket
                        | Tok::Comma
                        | Tok::Newline => false,
                        _ => next.span.col == 1,
                    };
                    if self.is_hard_newline(self.pos) || (depth <= 0 && starts_statement) {
                        return;
                    }
                }
                Tok::LParen | Tok::LBracket | Tok::LBrace => depth += 1,
                Tok::RParen | Tok::RBracket | Tok::RBrace => depth -= 1,
                _ => {}
            }
            self.pos += 1;
        }
    }

    fn statement(&mut self, grammar: &mut Grammar, seen: &mut HashMap<String, u32>) -> PResult<()> {
        let token = self.peek().clone();
        match &token.tok {
            Tok::Ident(name) if name == "let" && matches!(self.peek_next(), Tok::Ident(_)) => {
                self.binding()?;
                self.end_of_statement(&[])
            }
            Tok::Ident(name) => {
                if matches!(self.peek_next(), Tok::LParen | Tok::Colon) {
                    let rule = self.rule(canonical_operator(name))?;
                    self.end_of_statement(&["`priority=`", "`weight=`"])?;
                    grammar.rules.push(rule);
                } else {
                    let directive = self.directive(name.clone())?;
                    self.end_of_statement(&[])?;
                    if let Some(line) = seen.insert(directive.name.clone(), directive.span.line) {
                        return Err(Diagnostic::new(directive.span, format!("`{}` is set twice", directive.name))
                            .with_help(format!("it is first set on line {line}")));
                    }
                    grammar.directives.push(directive);
                }
                Ok(())
            }
            Tok::Color(_) => Err(Diagnostic::new(token.span, "a colour cannot start a statement")
                .with_help("`#` followed by 3, 6 or 8 hex digits is a colour; write comments as `# text`, with a space")),
            _ => Err(self.unexpected(&["a directive", "a rule"])),
        }
    }

    /// `let name = expression`: later expressions that name `name` read the expression in
    /// its place (as if written there), so a formula used by several rules is written once.
    fn binding(&mut self) -> PResult<()> {
        self.bump();
        let name_tok = self.bump();
        let Tok::Ident(name) = name_tok.tok else {
            return Err(self.unexpected(&["a name"]));
        };
        if crate::grammar::value::VARIABLES.contains(&name.as_str()) {
            return Err(Diagnostic::new(
                name_tok.span,
                format!("`{name}` is a variable every shape has"),
            )
            .with_help("a `let` names a new value; choose another name"));
        }
        if let Some((first, _)) = self.lets.get(&name) {
            return Err(
                Diagnostic::new(name_tok.span, format!("`{name}` is bound twice"))
                    .with_help(format!("it is first bound on line {}", first.span.line)),
            );
        }
        self.expect(&Tok::Eq, &["`=`"])?;
        let value = self.expr()?;
        // Bindings of bindings could grow without bound (`let b = a + a`, `let c = b + b`,
        // …): the expression a name stands for is capped, as one written out would be.
        let (nodes, depth) = size(&value);
        if nodes > MAX_LET_NODES || depth * NEST_COST > MAX_NESTING {
            return Err(Diagnostic::new(
                value.span,
                format!(
                    "`{name}` stands for an expression too large ({nodes} terms, {depth} deep)"
                ),
            )
            .with_help(format!(
                "a `let` may stand for at most {MAX_LET_NODES} terms, {} deep",
                MAX_NESTING / NEST_COST
            )));
        }
        self.lets.insert(name, (value, nodes));
        Ok(())
    }

    fn end_of_statement(&mut self, more: &[&str]) -> PResult<()> {
        if matches!(self.peek().tok, Tok::Newline | Tok::Eof) {
            return Ok(());
        }
        let mut expected = vec!["end of line"];
        expected.extend_from_slice(more);
        Err(self.unexpected(&expected))
    }

    // ----- directives -----

    fn directive(&mut self, name: String) -> PResult<Directive> {
        let name_tok = self.bump();
        let Some(spec) = directive_spec(&name) else {
            let mut d = Diagnostic::new(name_tok.span, format!("unknown directive `{name}`"))
                .with_expected(DIRECTIVES.iter().map(|d| format!("`{}`", d.name)));
            if let Some(close) = did_you_mean(&name, DIRECTIVES.iter().map(|d| d.name)) {
                d = d.with_help(format!("did you mean `{close}`?"));
            } else if matches!(name.as_str(), "priority" | "weight") {
                d = d.with_help(format!(
                    "`{name}=` belongs on its rule's line, or on an indented line after it"
                ));
            } else {
                d = d.with_help(
                    "a rule is written `op(args) : [slice_tags, shape_tags] -> [outputs]`",
                );
            }
            return Err(d);
        };
        let mut values = Vec::new();
        let quoted = self.src[self.peek().span.start..].starts_with('"');
        if spec.kind == DirectiveKind::Path
            && !quoted
            && !matches!(self.peek().tok, Tok::Newline | Tok::Eof)
        {
            values.push(self.bare_path());
        } else {
            while !matches!(self.peek().tok, Tok::Newline | Tok::Eof) {
                values.push(self.expr()?);
                self.eat(&Tok::Comma);
            }
        }
        let span = join(name_tok.span, self.prev_span());
        check_directive(spec, &values, span)?;
        Ok(Directive { name, values, span })
    }

    /// Reads a path without quotes: the characters up to the next whitespace. Tokens the
    /// lexer made of them (a path is not made of tokens) are skipped.
    fn bare_path(&mut self) -> Expr {
        let start = self.peek().span;
        let len = self.src[start.start..]
            .find(char::is_whitespace)
            .unwrap_or(self.src.len() - start.start);
        let end = start.start + len;
        while self.toks[self.pos].tok != Tok::Eof && self.toks[self.pos].span.start < end {
            self.pos += 1;
        }
        let span = Span { end, ..start };
        Expr {
            kind: ExprKind::Str(self.src[start.start..end].to_string()),
            span,
        }
    }

    // ----- rules -----

    fn rule(&mut self, op: String) -> PResult<Rule> {
        let op_tok = self.bump();
        let args = if self.eat(&Tok::LParen).is_some() {
            self.args()?
        } else {
            Vec::new()
        };
        self.continue_line_if(|t, i| t[i].tok == Tok::Colon);
        if self.eat(&Tok::Colon).is_none() {
            return Err(self.unexpected(&["`:`"]).with_help(
                "a rule is written `op(args) : [slice_tags, shape_tags] -> [outputs]`",
            ));
        }
        let (slice_tags, shape_tags, shape_excluded, spatial) = self.matched_tags()?;
        self.continue_line_if(|t, i| t[i].tok == Tok::Arrow);
        if self.eat(&Tok::Arrow).is_none() {
            let d = self.unexpected(&["`->`", "`→`"]);
            return Err(Diagnostic {
                message: "missing `->` before the output tags".into(),
                ..d
            }
            .with_help("a rule is written `op(args) : [slice_tags, shape_tags] -> [outputs]`"));
        }
        let outputs = self.outputs()?;
        let mut rule = Rule {
            op,
            op_span: op_tok.span,
            args,
            slice_tags,
            shape_tags,
            shape_excluded,
            outputs,
            priority: 0,
            weight: 1.0,
            spatial,
            span: op_tok.span,
        };
        self.rule_options(&mut rule)?;
        rule.span = join(op_tok.span, self.prev_span());
        check_inversions(&rule)?;
        check_patterns(&rule)?;
        Ok(rule)
    }

    /// Parses what follows `:`: `[slice, shape]` (timeslice rule), `[shape]` or a bare tag
    /// group (spatial rule). Returns (slice tags, shape tags, excluded shape tags, spatial).
    fn matched_tags(&mut self) -> PResult<Matched> {
        if self.eat(&Tok::LBracket).is_none() {
            let (shape, excluded) = self.shape_group()?;
            return Ok((Vec::new(), shape, excluded, true));
        }
        let mut groups = vec![self.shape_group()?];
        while self.eat(&Tok::Comma).is_some() {
            let start = self.peek().span;
            let group = self.shape_group()?;
            if groups.len() == 2 {
                let span = join(start, self.prev_span());
                return Err(Diagnostic::new(
                    span,
                    "a rule matches at most two tag lists: [slice tags, shape tags]",
                )
                .with_help("to match several tags, group them in parentheses: `[(a, b), s]`"));
            }
            groups.push(group);
        }
        self.expect(&Tok::RBracket, &["`,`", "`]`"])?;
        let (shape, excluded) = groups.pop().unwrap_or_default();
        match groups.pop() {
            Some((slice, left_out)) => {
                if let Some(t) = left_out.first() {
                    return Err(Diagnostic::new(t.span, "slice tags cannot leave tags out")
                        .with_help("`- tag` leaves shapes out: write it in the second list, `[a, all - background]`"));
                }
                Ok((slice, shape, excluded, false))
            }
            None => Ok((Vec::new(), shape, excluded, true)),
        }
    }

    /// A tag or a parenthesised list of tags.
    fn tag_group(&mut self) -> PResult<Vec<TagRef>> {
        if self.eat(&Tok::LParen).is_none() {
            return Ok(vec![self.tag()?]);
        }
        let mut tags = vec![self.tag()?];
        while self.eat(&Tok::Comma).is_some() {
            tags.push(self.tag()?);
        }
        self.expect(&Tok::RParen, &["`,`", "`)`"])?;
        Ok(tags)
    }

    /// A tag: a name or a string, `inv_` prefix for inverted. Several words in a row are
    /// one tag joined by `_`, so gTangle's printed `big poly` is the tag `big_poly`.
    fn tag(&mut self) -> PResult<TagRef> {
        let mut token = self.peek().clone();
        let mut written = match &token.tok {
            Tok::Ident(name) | Tok::Str(name) => name.clone(),
            Tok::Star => "*".to_string(),
            _ => return Err(self.unexpected(&["a tag"])),
        };
        self.bump();
        // Tokens written against it are part of it: the pattern `icon-*`, `*_1`, `a-1`.
        if !matches!(token.tok, Tok::Str(_)) {
            while let Some(next) = self.glued(self.pos) {
                written.push_str(&self.src[next.span.start..next.span.end]);
                token.span = join(token.span, next.span);
                self.pos += 1;
            }
        }
        // A following word or whole number continues the tag (`in 2` is `in_2`), unless it
        // is a rule option (`priority=`).
        loop {
            let next = &self.toks[self.pos];
            let word = &self.src[next.span.start..next.span.end];
            let continues = match next.tok {
                Tok::Ident(_) => self.toks.get(self.pos + 1).is_none_or(|t| t.tok != Tok::Eq),
                Tok::Num(_) => word.bytes().all(|b| b.is_ascii_digit()),
                _ => false,
            };
            if !continues {
                break;
            }
            let word = match &next.tok {
                Tok::Ident(name) => name.clone(),
                _ => word.to_string(),
            };
            written = format!("{written}_{word}");
            token.span = join(token.span, self.toks[self.pos].span);
            self.pos += 1;
        }
        let (name, inverted) = match written.strip_prefix(INV_PREFIX) {
            Some(rest) => (rest.to_string(), true),
            None => (written.clone(), false),
        };
        if name.is_empty() {
            return Err(Diagnostic::new(
                token.span,
                format!("empty tag name `{written}`"),
            ));
        }
        if inverted && name.starts_with(INV_PREFIX) {
            return Err(
                Diagnostic::new(token.span, format!("`{written}` is inverted twice")).with_help(
                    format!(
                        "`inv_` undoes itself: write `{}`",
                        &name[INV_PREFIX.len()..]
                    ),
                ),
            );
        }
        Ok(TagRef {
            name,
            inverted,
            span: token.span,
        })
    }

    /// Token `i` when it touches the one before it (no blank between) and may continue a
    /// tag: a name, a whole number, `*`, or a `-` itself touching such a token.
    fn glued(&self, i: usize) -> Option<Token> {
        let (before, token) = (self.toks.get(i.checked_sub(1)?)?, self.toks.get(i)?);
        if token.span.start != before.span.end {
            return None;
        }
        let part = |t: &Token| match t.tok {
            Tok::Ident(_) | Tok::Star => true,
            Tok::Num(_) => self.src[t.span.start..t.span.end]
                .bytes()
                .all(|b| b.is_ascii_digit()),
            _ => false,
        };
        let continues = part(token)
            || (token.tok == Tok::Minus && self.glued(i + 1).is_some_and(|n| n.tok != Tok::Minus));
        continues.then(|| token.clone())
    }

    /// A shape-tag group and what it leaves out: `all - background`, `(a, b) - c`.
    fn shape_group(&mut self) -> PResult<(Vec<TagRef>, Vec<TagRef>)> {
        let tags = self.tag_group()?;
        let mut excluded = Vec::new();
        while self.eat(&Tok::Minus).is_some() {
            excluded.extend(self.tag_group()?);
        }
        Ok((tags, excluded))
    }

    /// The output list `[a, b, …]` (possibly empty) or a single tag.
    fn outputs(&mut self) -> PResult<Vec<TagRef>> {
        if self.eat(&Tok::LBracket).is_none() {
            return Ok(vec![self.tag()?]);
        }
        let mut tags = Vec::new();
        while !self.at(&Tok::RBracket) {
            tags.push(self.tag()?);
            if self.eat(&Tok::Comma).is_none() {
                break;
            }
        }
        self.expect(&Tok::RBracket, &["`,`", "`]`"])?;
        Ok(tags)
    }

    /// `priority=P` and `weight=W`, in any order, each at most once.
    fn rule_options(&mut self, rule: &mut Rule) -> PResult<()> {
        let mut seen: Vec<&str> = Vec::new();
        loop {
            self.continue_line_if(|t, i| {
                matches!(&t[i].tok, Tok::Ident(n) if n == "priority" || n == "weight")
                    && t[i].span.col > 1
                    && t.get(i + 1).is_some_and(|n| n.tok == Tok::Eq)
            });
            let token = self.peek().clone();
            let Tok::Ident(name) = &token.tok else {
                return Ok(());
            };
            let option = match name.as_str() {
                "priority" => "priority",
                "weight" => "weight",
                _ => {
                    let mut d =
                        Diagnostic::new(token.span, format!("unknown rule option `{name}`"))
                            .with_expected(["`priority=`", "`weight=`"]);
                    if let Some(close) = did_you_mean(name, ["priority", "weight"]) {
                        d = d.with_help(format!("did you mean `{close}`?"));
                    }
                    return Err(d);
                }
            };
            self.bump();
            if seen.contains(&option) {
                return Err(Diagnostic::new(
                    token.span,
                    format!("`{option}` is given twice"),
                ));
            }
            seen.push(option);
            self.expect(&Tok::Eq, &["`=`"])?;
            if option == "priority" {
                rule.priority = self.priority()?;
            } else {
                rule.weight = self.weight()?;
            }
        }
    }

    /// An integer literal, possibly negative.
    fn priority(&mut self) -> PResult<i64> {
        let minus = self.eat(&Tok::Minus);
        let token = self.peek().clone();
        let span = minus
            .as_ref()
            .map_or(token.span, |m| join(m.span, token.span));
        let text = &self.src[token.span.start..token.span.end];
        if !matches!(token.tok, Tok::Num(_)) {
            return Err(self.unexpected(&["a whole number"]));
        }
        self.bump();
        if !text.bytes().all(|b| b.is_ascii_digit()) {
            return Err(Diagnostic::new(
                span,
                format!("priority must be a whole number, found `{text}`"),
            ));
        }
        let signed = if minus.is_some() {
            format!("-{text}")
        } else {
            text.to_string()
        };
        signed.parse::<i64>().map_err(|_| {
            Diagnostic::new(span, "priority is too large")
                .with_help("priorities must fit in 64 bits")
        })
    }

    /// A positive number literal.
    fn weight(&mut self) -> PResult<f64> {
        let token = self.peek().clone();
        match token.tok {
            Tok::Num(w) if w > 0.0 => {
                self.bump();
                Ok(w)
            }
            Tok::Num(_) | Tok::Minus => {
                self.bump();
                let span = if token.tok == Tok::Minus {
                    join(token.span, self.peek().span)
                } else {
                    token.span
                };
                Err(Diagnostic::new(span, "weight must be positive")
                    .with_help("a weight of 0 would never be chosen; remove the rule instead"))
            }
            _ => Err(self.unexpected(&["a positive number"])),
        }
    }

    // ----- arguments and expressions -----

    /// Arguments after `(` up to and including `)`: positional, then `name = value`.
    fn args(&mut self) -> PResult<Vec<Arg>> {
        let mut args: Vec<Arg> = Vec::new();
        // Names given so far: checked per argument without a scan of the list before it
        // (100 000 arguments took minutes).
        let mut names: std::collections::HashSet<String> = std::collections::HashSet::new();
        while !self.at(&Tok::RParen) {
            let start = self.peek().span;
            let named = match self.peek().tok.clone() {
                Tok::Ident(name) if *self.peek_next() == Tok::Eq => Some(name),
                _ => None,
            };
            if let Some(name) = &named {
                self.bump();
                self.bump();
                if !names.insert(name.clone()) {
                    return Err(Diagnostic::new(
                        start,
                        format!("argument `{name}` is given twice"),
                    ));
                }
            }
            let value = self.expr()?;
            let span = join(start, value.span);
            if named.is_none() && !names.is_empty() {
                return Err(
                    Diagnostic::new(span, "positional argument after a named one")
                        .with_help("put positional arguments first, then `name = value` ones"),
                );
            }
            args.push(Arg {
                name: named,
                value,
                span,
            });
            if self.eat(&Tok::Comma).is_none() {
                break;
            }
        }
        if self.eat(&Tok::RParen).is_none() {
            let d = self.unexpected(&["`,`", "`)`"]);
            let starts_expr = matches!(
                self.peek().tok,
                Tok::Num(_)
                    | Tok::Str(_)
                    | Tok::Ident(_)
                    | Tok::Color(_)
                    | Tok::Size(..)
                    | Tok::LParen
            );
            return Err(if starts_expr {
                d.with_help("separate arguments with commas")
            } else {
                d
            });
        }
        Ok(args)
    }

    /// An expression: `+ -` over `* / %` (and juxtaposed calls) over unary `-` over `^`.
    fn expr(&mut self) -> PResult<Expr> {
        let base = self.nesting;
        let mut lhs = self.product()?;
        loop {
            let op = match self.peek().tok {
                Tok::Plus => BinOp::Add,
                Tok::Minus => BinOp::Sub,
                _ => break,
            };
            self.deeper(1)?;
            self.bump();
            let rhs = self.product()?;
            lhs = binary(op, lhs, rhs);
        }
        self.nesting = base;
        Ok(lhs)
    }

    fn product(&mut self) -> PResult<Expr> {
        let base = self.nesting;
        let mut lhs = self.unary()?;
        loop {
            // A call right after an operand multiplies it: `translate(1, 0) rotate(30)`.
            let juxtaposed =
                matches!(self.peek().tok, Tok::Ident(_)) && *self.peek_next() == Tok::LParen;
            let op = match self.peek().tok {
                _ if juxtaposed => BinOp::Mul,
                Tok::Star => BinOp::Mul,
                Tok::Slash => BinOp::Div,
                Tok::Percent => BinOp::Rem,
                _ => break,
            };
            self.deeper(1)?;
            if !juxtaposed {
                self.bump();
            }
            let rhs = self.unary()?;
            lhs = binary(op, lhs, rhs);
        }
        self.nesting = base;
        Ok(lhs)
    }

    /// Spends `cost` of the nesting budget (see [`MAX_NESTING`]).
    fn deeper(&mut self, cost: usize) -> PResult<()> {
        self.nesting += cost;
        if self.nesting > MAX_NESTING {
            let span = self.peek().span;
            return Err(Diagnostic::new(span, "expression nested too deeply")
                .with_help("split it into smaller expressions"));
        }
        Ok(())
    }

    fn unary(&mut self) -> PResult<Expr> {
        let base = self.nesting;
        self.deeper(NEST_COST)?;
        let expr = match self.eat(&Tok::Minus) {
            Some(minus) => {
                let inner = self.unary()?;
                let span = join(minus.span, inner.span);
                match inner.kind {
                    ExprKind::Num(v) => Expr {
                        kind: ExprKind::Num(-v),
                        span,
                    },
                    _ => Expr {
                        kind: ExprKind::Neg(Box::new(inner)),
                        span,
                    },
                }
            }
            None => self.power()?,
        };
        self.nesting = base;
        Ok(expr)
    }

    fn power(&mut self) -> PResult<Expr> {
        let base = self.primary()?;
        if self.eat(&Tok::Caret).is_none() {
            return Ok(base);
        }
        let exponent = self.unary()?;
        Ok(binary(BinOp::Pow, base, exponent))
    }

    fn primary(&mut self) -> PResult<Expr> {
        let token = self.peek().clone();
        let kind = match token.tok {
            Tok::Num(v) => ExprKind::Num(v),
            Tok::Size(c, r, p) => ExprKind::Size(c, r, p),
            Tok::Str(s) => ExprKind::Str(s),
            Tok::Color(c) => ExprKind::Color(c),
            Tok::Ident(name) => {
                self.bump();
                if self.toks[self.pos].tok != Tok::LParen {
                    if let Some((bound, nodes)) = self.lets.get(&name) {
                        self.let_terms_read += nodes;
                        if self.let_terms_read > MAX_LET_TERMS_READ {
                            return Err(Diagnostic::new(token.span, "`let` names read too many terms in this file")
                                .with_help(format!("all uses of `let` names together may stand for at most {MAX_LET_TERMS_READ} terms")));
                        }
                        return Ok(bound.clone());
                    }
                    return Ok(Expr {
                        kind: ExprKind::Ident(name),
                        span: token.span,
                    });
                }
                self.bump();
                let args = self.args()?;
                return Ok(Expr {
                    kind: ExprKind::Call { name, args },
                    span: join(token.span, self.prev_span()),
                });
            }
            Tok::LParen => return self.parenthesised(),
            Tok::LBrace | Tok::LBracket => return self.list(),
            _ => return Err(self.unexpected(&["an expression"])),
        };
        self.bump();
        Ok(Expr {
            kind,
            span: token.span,
        })
    }

    /// A list as the papers write one, `{a, b, …}` or `[a, b, …]`: a tuple even with one
    /// item, so `timesplit({0.3, 0.7})` reads as `timesplit(0.3, 0.7)`.
    fn list(&mut self) -> PResult<Expr> {
        let open = self.bump();
        let close = if open.tok == Tok::LBrace {
            Tok::RBrace
        } else {
            Tok::RBracket
        };
        let mut items = Vec::new();
        while !self.at(&close) {
            items.push(self.expr()?);
            if self.eat(&Tok::Comma).is_none() {
                break;
            }
        }
        let closer = if close == Tok::RBrace { "`}`" } else { "`]`" };
        self.expect(&close, &["`,`", closer])?;
        Ok(Expr {
            kind: ExprKind::Tuple(items),
            span: join(open.span, self.prev_span()),
        })
    }

    /// `(e)` or a tuple `(a, b, …)`.
    fn parenthesised(&mut self) -> PResult<Expr> {
        let open = self.bump();
        let first = self.expr()?;
        let mut items = vec![first];
        while self.eat(&Tok::Comma).is_some() {
            if self.at(&Tok::RParen) {
                break;
            }
            items.push(self.expr()?);
        }
        self.expect(&Tok::RParen, &["`,`", "`)`"])?;
        let span = join(open.span, self.prev_span());
        let kind = if items.len() == 1 {
            items.remove(0).kind
        } else {
            ExprKind::Tuple(items)
        };
        Ok(Expr { kind, span })
    }
}

/// The operator a rule names, with the papers' spellings folded in: gMotion's Fig. 5
/// writes `TimeSplit`.
fn canonical_operator(name: &str) -> String {
    ["timesplit", "animate"]
        .into_iter()
        .find(|op| op.eq_ignore_ascii_case(name))
        .map_or_else(|| name.to_string(), str::to_string)
}

fn binary(op: BinOp, lhs: Expr, rhs: Expr) -> Expr {
    let span = join(lhs.span, rhs.span);
    Expr {
        kind: ExprKind::Binary {
            op,
            lhs: Box::new(lhs),
            rhs: Box::new(rhs),
        },
        span,
    }
}

/// Checks that a directive has one value of the form its spec asks for.
fn check_directive(spec: &DirectiveSpec, values: &[Expr], span: Span) -> PResult<()> {
    let name = spec.name;
    let what = match spec.kind {
        DirectiveKind::Seconds => "a positive duration such as `6s` or `500ms`".to_string(),
        DirectiveKind::Instant => "a time such as `0`, `1.5s` or `500ms`".to_string(),
        DirectiveKind::Positive => "a positive number".to_string(),
        DirectiveKind::Count => "a positive whole number".to_string(),
        DirectiveKind::Seed => "a whole number from 0 to 2^53".to_string(),
        DirectiveKind::Size => "a size such as `4x4`".to_string(),
        DirectiveKind::Path => "a file path".to_string(),
        DirectiveKind::OneOf(words) => format!("one of {}", quoted(words).join(", ")),
        DirectiveKind::Expr => "an expression".to_string(),
        DirectiveKind::Names => "one or more slice tags, such as `in hold out`".to_string(),
        DirectiveKind::SomeOf(words) => format!("one or more of {}", quoted(words).join(", ")),
    };
    if let DirectiveKind::SomeOf(words) = spec.kind {
        if values.is_empty() {
            return Err(
                Diagnostic::new(span, format!("`{name}` needs a value")).with_expected([what])
            );
        }
        for (k, v) in values.iter().enumerate() {
            let word = match &v.kind {
                ExprKind::Ident(w) if words.contains(&w.as_str()) => w,
                _ => {
                    return Err(Diagnostic::new(v.span, format!("unknown `{name}` value"))
                        .with_expected([what]));
                }
            };
            if values[..k]
                .iter()
                .any(|u| matches!(&u.kind, ExprKind::Ident(w) if w == word))
            {
                return Err(Diagnostic::new(
                    v.span,
                    format!("`{word}` is given twice in `{name}`"),
                ));
            }
        }
        return Ok(());
    }
    if spec.kind == DirectiveKind::Names {
        if values.is_empty() {
            return Err(
                Diagnostic::new(span, format!("`{name}` needs a value")).with_expected([what])
            );
        }
        for v in values {
            if !matches!(&v.kind, ExprKind::Ident(_)) {
                return Err(
                    Diagnostic::new(v.span, format!("`{name}` takes slice tags"))
                        .with_expected([what]),
                );
            }
        }
        return Ok(());
    }
    let [value] = values else {
        let at = values.get(1).map_or(span, |v| v.span);
        let message = if values.is_empty() {
            format!("`{name}` needs a value")
        } else {
            format!("`{name}` takes one value")
        };
        return Err(Diagnostic::new(at, message).with_expected([what]));
    };
    let ok = match (&spec.kind, &value.kind) {
        (DirectiveKind::Seconds | DirectiveKind::Positive, ExprKind::Num(v)) => *v > 0.0,
        (DirectiveKind::Instant, ExprKind::Num(v)) => *v >= 0.0 && v.is_finite(),
        (DirectiveKind::Count, ExprKind::Num(v)) => {
            *v >= 1.0 && v.fract() == 0.0 && *v <= f64::from(u32::MAX)
        }
        (DirectiveKind::Seed, ExprKind::Num(v)) => {
            *v >= 0.0 && v.fract() == 0.0 && *v <= 2f64.powi(53)
        }
        (DirectiveKind::Size, ExprKind::Size(c, r, p)) => *c >= 1 && *r >= 1 && *p >= 2,
        (DirectiveKind::Size, ExprKind::Num(v)) => *v >= 1.0 && v.fract() == 0.0,
        (DirectiveKind::Path, ExprKind::Str(s)) => !s.is_empty(),
        (DirectiveKind::OneOf(words), ExprKind::Ident(w) | ExprKind::Str(w)) => {
            words.contains(&w.as_str())
        }
        (DirectiveKind::Expr, _) => true,
        _ => false,
    };
    if ok {
        return Ok(());
    }
    let mut d =
        Diagnostic::new(value.span, format!("invalid value for `{name}`")).with_expected([what]);
    if let (DirectiveKind::OneOf(words), ExprKind::Ident(w) | ExprKind::Str(w)) =
        (&spec.kind, &value.kind)
        && let Some(close) = did_you_mean(w, words.iter().copied())
    {
        d = d.with_help(format!("did you mean `{close}`?"));
    }
    if matches!(
        value.kind,
        ExprKind::Neg(_) | ExprKind::Binary { .. } | ExprKind::Call { .. }
    ) && spec.kind != DirectiveKind::Expr
    {
        d = d.with_help("header values are literals; nothing is computed before the shapes exist");
    }
    Err(d)
}

/// A `*` pattern picks among the tags shapes already have, so it belongs in the shape
/// tags only: a slice tag or an output tag is one name.
fn check_patterns(rule: &Rule) -> PResult<()> {
    let slice = rule
        .slice_tags
        .iter()
        .map(|t| (t, "slice tags are names; patterns pick shape tags"));
    let out = rule
        .outputs
        .iter()
        .map(|t| (t, "an output tag is the one name the rule gives"));
    match slice.chain(out).find(|(t, _)| t.name.contains('*')) {
        Some((t, why)) => {
            Err(Diagnostic::new(t.span, format!("`{}` is a pattern here", t.name)).with_help(why))
        }
        None => Ok(()),
    }
}

/// `inv_` marks a timeslice played backwards, so it is meaningful only on the tags a
/// timeslice rule gives its outputs. Rules match a slice together with its `inv_` twin, and
/// shapes have no direction, so `inv_` anywhere else is a mistake.
fn check_inversions(rule: &Rule) -> PResult<()> {
    let first_inverted = |tags: &[TagRef]| {
        tags.iter()
            .find(|t| t.inverted)
            .map(|t| (t.span, t.name.clone()))
    };
    if let Some((span, name)) = first_inverted(&rule.slice_tags) {
        return Err(
            Diagnostic::new(span, format!("match `{name}`, not `inv_{name}`")).with_help(format!(
                "a rule for `{name}` also expands its `inv_{name}` twin, played backwards"
            )),
        );
    }
    if let Some((span, _)) = first_inverted(&rule.shape_tags) {
        let help = if rule.spatial {
            "spatial rules match shape tags; only timeslice tags have `inv_` twins"
        } else {
            "the second list matches shape tags; only timeslice tags have `inv_` twins"
        };
        return Err(Diagnostic::new(span, "shape tags cannot be inverted").with_help(help));
    }
    if rule.spatial
        && let Some((span, _)) = first_inverted(&rule.outputs)
    {
        return Err(
            Diagnostic::new(span, "shape tags cannot be inverted").with_help(
                "a spatial rule's outputs are shape tags; only timeslice tags have `inv_` twins",
            ),
        );
    }
    Ok(())
}
