//! The grammar's syntax tree, as the parser produces it. Every node keeps its [`Span`] so
//! later stages (validation, expansion) can point at the source.

/// A location in the grammar source: 1-based line and column plus byte offsets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Span {
    /// 1-based line.
    pub line: u32,
    /// 1-based column (in characters).
    pub col: u32,
    /// Byte offset of the first character.
    pub start: usize,
    /// Byte offset one past the last character.
    pub end: usize,
}

/// A parsed grammar file.
#[derive(Clone, Debug, Default)]
pub struct Grammar {
    /// Header directives in source order (`duration 6s`, `grid 4x4`, …).
    pub directives: Vec<Directive>,
    /// Rules in source order.
    pub rules: Vec<Rule>,
}

/// A header directive: a name and its value(s), e.g. `duration 6s`, `grid 4x4`,
/// `scene "toy.svg"`, `lookup bilinear`.
#[derive(Clone, Debug)]
pub struct Directive {
    /// Directive name.
    pub name: String,
    /// Its values (most directives take one).
    pub values: Vec<Expr>,
    /// Where it is.
    pub span: Span,
}

/// A tag as written in a rule: a name, possibly with the `inv_` prefix (or, for shape
/// tags, a pattern: [`tag_matches`]).
#[derive(Clone, Debug, PartialEq)]
pub struct TagRef {
    /// The tag without the `inv_` prefix.
    pub name: String,
    /// True when written with the `inv_` prefix.
    pub inverted: bool,
    /// Where it is.
    pub span: Span,
}

/// Whether a shape tag as written in a rule (`icon`, or a pattern with `*` standing for
/// any run of characters: `icon-*`, `*_1`, `Layer_*`) names `tag`. `all` is not special
/// here: what it takes depends on the kind of rule.
pub fn tag_matches(written: &str, tag: &str) -> bool {
    let Some((first, rest)) = written.split_once('*') else {
        return written == tag;
    };
    let Some(mut left) = tag.strip_prefix(first) else {
        return false;
    };
    let mut parts: Vec<&str> = rest.split('*').collect();
    let last = parts.pop().unwrap_or("");
    for part in parts {
        match left.find(part) {
            Some(i) => left = &left[i + part.len()..],
            None => return false,
        }
    }
    left.len() >= last.len() && left.ends_with(last)
}

/// Whether a rule's shape tags (with `all` taking every shape when `all_counts`), less its
/// exclusions, take a shape whose tags are `tags` (its tag and its aliases): one of them
/// must be named and none left out, so `all - background` leaves out a shape that answers
/// to `background` under any of its names.
pub fn takes_shape<'t>(
    included: &[String],
    excluded: &[String],
    tags: impl IntoIterator<Item = &'t str> + Clone,
    all_counts: bool,
) -> bool {
    let names = |t: &str| tags.clone().into_iter().any(|tag| tag_matches(t, tag));
    included
        .iter()
        .any(|t| (all_counts && t == "all") || names(t))
        && !excluded.iter().any(|t| names(t))
}

/// One production: `op(args) : [slice tags, shape tags] -> [outputs] priority=P weight=W`,
/// or for spatial (group grammar) rules `op(args) : shape_tags -> [outputs]`.
#[derive(Clone, Debug)]
pub struct Rule {
    /// Operator name (`timesplit`, `animate`, `outline`, …).
    pub op: String,
    /// Where the operator name is.
    pub op_span: Span,
    /// Operator arguments, positional first then named.
    pub args: Vec<Arg>,
    /// Timeslice tags matched; empty for spatial rules.
    pub slice_tags: Vec<TagRef>,
    /// Shape tags matched (`all` matches every shape; `icon-*` is a pattern).
    pub shape_tags: Vec<TagRef>,
    /// Shape tags left out of those: `[a, all - background]`.
    pub shape_excluded: Vec<TagRef>,
    /// Output tags.
    pub outputs: Vec<TagRef>,
    /// Priority: among matching rules only the highest priority ones are candidates.
    pub priority: i64,
    /// Relative weight for the random choice among candidates (default 1).
    pub weight: f64,
    /// True for rules written with a single tag list (spatial, group-grammar rules).
    pub spatial: bool,
    /// The whole rule.
    pub span: Span,
}

impl Rule {
    /// Whether the rule takes a shape with tags `tags` (`all` taking every shape when
    /// `all_counts`): [`takes_shape`] on its tags as written.
    pub fn takes_shape<'t>(
        &self,
        tags: impl IntoIterator<Item = &'t str> + Clone,
        all_counts: bool,
    ) -> bool {
        let names =
            |tags: &[TagRef]| -> Vec<String> { tags.iter().map(|t| t.name.clone()).collect() };
        takes_shape(
            &names(&self.shape_tags),
            &names(&self.shape_excluded),
            tags,
            all_counts,
        )
    }

    /// Whether the rule names `tag` (or a pattern matching it) among the shape tags it
    /// takes or leaves out; `all` names no tag.
    pub fn names_shape_tag(&self, tag: &str) -> bool {
        (self.shape_tags.iter())
            .chain(&self.shape_excluded)
            .any(|t| t.name != "all" && tag_matches(&t.name, tag))
    }
}

/// An operator argument, positional (`name == None`) or named (`ease = ease-in`).
#[derive(Clone, Debug)]
pub struct Arg {
    /// Name for named arguments.
    pub name: Option<String>,
    /// The value.
    pub value: Expr,
    /// Where it is.
    pub span: Span,
}

/// An expression.
#[derive(Clone, Debug)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Where it is.
    pub span: Span,
}

/// Binary operators, by increasing precedence groups: `+ -`, then `* / %`, then `^`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*` (also transform product; juxtaposed transforms parse as `*`)
    Mul,
    /// `/`
    Div,
    /// `%`
    Rem,
    /// `^` (power)
    Pow,
}

impl BinOp {
    /// The operator as the grammar spells it.
    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Rem => "%",
            BinOp::Pow => "^",
        }
    }
}

/// Expression kinds.
#[derive(Clone, Debug)]
pub enum ExprKind {
    /// A number; unit suffixes are folded in (`6s` → 6, `500ms` → 0.5, `30deg` → 30,
    /// `50%` → 0.5).
    Num(f64),
    /// A string literal (path data, file names).
    Str(String),
    /// A colour literal `#rrggbb`.
    Color(crate::color::Color),
    /// A bare identifier: a variable (`id`, `cx`…), a keyword (`affine`, `world`) or a
    /// colour name.
    Ident(String),
    /// A call `name(args)`: functions (`rand`, `noise`, `sin`), transforms (`translate`),
    /// colours (`rgb`), easings (`cubic`).
    Call {
        /// Function name (may contain `-`, as in `ease-in-out`).
        name: String,
        /// Arguments.
        args: Vec<Arg>,
    },
    /// A parenthesised tuple `(a, b, …)` of two or more items (points).
    Tuple(Vec<Expr>),
    /// Unary minus.
    Neg(Box<Expr>),
    /// A binary operation.
    Binary {
        /// Operator.
        op: BinOp,
        /// Left operand.
        lhs: Box<Expr>,
        /// Right operand.
        rhs: Box<Expr>,
    },
    /// A grid size `4x4`, or `4x4x3` with keyframes in time (2 when not written).
    Size(u32, u32, u32),
}
