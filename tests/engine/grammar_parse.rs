//! The grammar language front end: parsing, error recovery and error rendering.

use gmotion::grammar::ast::{Arg, Expr, ExprKind, Grammar, Rule, TagRef};
use gmotion::grammar::{DIRECTIVES, Diagnostics, parse};

fn ok(src: &str) -> Grammar {
    parse(src).unwrap_or_else(|d| panic!("unexpected errors:\n{}", d.render("test.gm", src)))
}

fn errors(src: &str) -> Diagnostics {
    match parse(src) {
        Ok(g) => panic!("expected errors, parsed {} rules", g.rules.len()),
        Err(d) => d,
    }
}

/// The (line, col) of every error.
fn positions(d: &Diagnostics) -> Vec<(u32, u32)> {
    d.iter().map(|d| (d.span.line, d.span.col)).collect()
}

/// Tags as written: `name` or `inv_name`.
fn tags(tags: &[TagRef]) -> Vec<String> {
    tags.iter()
        .map(|t| {
            if t.inverted {
                format!("inv_{}", t.name)
            } else {
                t.name.clone()
            }
        })
        .collect()
}

/// An expression as a fully parenthesised S-expression, to check its structure.
fn sexp(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Num(v) => format!("{v}"),
        ExprKind::Str(s) => format!("{s:?}"),
        ExprKind::Color(c) => c.to_hex(),
        ExprKind::Ident(n) => n.clone(),
        ExprKind::Call { name, args } => {
            let args: Vec<String> = args.iter().map(arg_sexp).collect();
            format!("{name}({})", args.join(" "))
        }
        ExprKind::Tuple(items) => {
            let items: Vec<String> = items.iter().map(sexp).collect();
            format!("(tuple {})", items.join(" "))
        }
        ExprKind::Neg(inner) => format!("(neg {})", sexp(inner)),
        ExprKind::Binary { op, lhs, rhs } => {
            format!("({} {} {})", op.symbol(), sexp(lhs), sexp(rhs))
        }
        ExprKind::Size(c, r, 2) => format!("{c}x{r}"),
        ExprKind::Size(c, r, p) => format!("{c}x{r}x{p}"),
    }
}

fn arg_sexp(a: &Arg) -> String {
    match &a.name {
        Some(n) => format!("{n}={}", sexp(&a.value)),
        None => sexp(&a.value),
    }
}

/// The S-expression of `src` written as the only argument of a rule.
fn expr(src: &str) -> String {
    let g = ok(&format!("op({src}) : a -> []"));
    sexp(&g.rules[0].args[0].value)
}

fn only_rule(src: &str) -> Rule {
    let mut g = ok(src);
    assert_eq!(g.rules.len(), 1);
    g.rules.remove(0)
}

#[test]
fn toy_grammar_of_the_paper() {
    let src = "\
# gMotion, Fig. 4: a square and two circles
duration 6s
timesplit(0.5, 0.5) : [all, (s, c)] -> [a, inv_a]
animate(affine, world, 0, translate(200, 0)) : [a, s] -> [t]
animate(affine, local, 0, scale(0.5)) : [a, c] -> [t]
";
    let g = ok(src);
    assert_eq!(g.directives.len(), 1);
    assert_eq!(g.directives[0].name, "duration");
    assert!(matches!(
        g.directives[0].values[..],
        [Expr {
            kind: ExprKind::Num(6.0),
            ..
        }]
    ));
    assert_eq!(g.rules.len(), 3);

    let split = &g.rules[0];
    assert_eq!(split.op, "timesplit");
    assert_eq!(
        split.args.iter().map(arg_sexp).collect::<Vec<_>>(),
        ["0.5", "0.5"]
    );
    assert_eq!(tags(&split.slice_tags), ["all"]);
    assert_eq!(tags(&split.shape_tags), ["s", "c"]);
    assert_eq!(tags(&split.outputs), ["a", "inv_a"]);
    assert!(!split.spatial);
    assert_eq!((split.priority, split.weight), (0, 1.0));

    let moves = &g.rules[1];
    assert_eq!(
        moves.args.iter().map(arg_sexp).collect::<Vec<_>>(),
        ["affine", "world", "0", "translate(200 0)"]
    );
    assert_eq!(
        (
            tags(&moves.slice_tags),
            tags(&moves.shape_tags),
            tags(&moves.outputs)
        ),
        (vec!["a".into()], vec!["s".into()], vec!["t".into()])
    );
    assert_eq!(sexp(&g.rules[2].args[3].value), "scale(0.5)");

    // Spans point into the source.
    assert_eq!((split.span.line, split.span.col), (3, 1));
    assert_eq!(
        &src[split.span.start..split.span.end],
        "timesplit(0.5, 0.5) : [all, (s, c)] -> [a, inv_a]"
    );
    assert_eq!(&src[moves.op_span.start..moves.op_span.end], "animate");
    assert_eq!(
        (split.outputs[1].span.line, split.outputs[1].span.col),
        (3, 44)
    );
}

#[test]
fn papers_quoted_notation_reads_the_same() {
    let g = ok(r#"
timesplit(0.3, 0.4, 0.3) : [("all"), ("all")] -> ["a1", "a2", "inv_a1"]
animate("affine", "world", 0.0, translate(400.0, 0.0)) : [("a1"), ("c")] -> ["t1"]
"#);
    assert_eq!(tags(&g.rules[0].outputs), ["a1", "a2", "inv_a1"]);
    assert_eq!(tags(&g.rules[1].shape_tags), ["c"]);
    assert_eq!(sexp(&g.rules[1].args[0].value), "\"affine\"");
}

#[test]
fn unicode_arrow_equals_ascii_arrow() {
    let a = only_rule("timesplit(0.5, 0.5) : [all, s] → [x, y]");
    let b = only_rule("timesplit(0.5, 0.5) : [all, s] -> [x, y]");
    assert_eq!(tags(&a.outputs), tags(&b.outputs));
    assert_eq!(tags(&a.outputs), ["x", "y"]);
}

#[test]
fn comments_run_to_the_end_of_the_line() {
    let g = ok("\
// a line comment
# another one: op(1) : [a, s] -> [b]
duration 2s   # trailing
op(1) : [a, s] -> [b] // trailing too
op(2) : [a, s] -> [c] #trailing without a space
");
    assert_eq!(g.directives.len(), 1);
    assert_eq!(g.rules.len(), 2);
    assert_eq!(tags(&g.rules[1].outputs), ["c"]);
}

#[test]
fn hash_followed_by_hex_digits_and_a_space_is_a_colour_not_a_comment() {
    let d = errors("#fed up\n");
    assert_eq!(positions(&d), [(1, 1)]);
    assert!(d.items[0].help.as_deref().unwrap_or("").contains("# text"));
    let g = ok("# fed up\n#fedup\nfill(#f80, #ff8800, #ff880080) : [a, s] -> [] // trailing\n");
    let colours: Vec<String> = g.rules[0].args.iter().map(|a| sexp(&a.value)).collect();
    assert_eq!(colours, ["#ff8800", "#ff8800", "#ff8800"]);
}

#[test]
fn operator_precedence_and_associativity() {
    for (src, tree) in [
        ("1 + 2 * 3", "(+ 1 (* 2 3))"),
        ("1 - 2 - 3", "(- (- 1 2) 3)"),
        ("8 / 4 % 3", "(% (/ 8 4) 3)"),
        ("2 ^ 3 ^ 2", "(^ 2 (^ 3 2))"),
        ("-x ^ 2", "(neg (^ x 2))"),
        ("-2", "-2"),
        ("2 * -x", "(* 2 (neg x))"),
        ("(1 + 2) * 3", "(* (+ 1 2) 3)"),
        ("(cx, cy - 10)", "(tuple cx (- cy 10))"),
    ] {
        assert_eq!(expr(src), tree, "{src}");
    }
    assert_eq!(
        expr("rand(0, n) + noise(cx, cy) * 5"),
        "(+ rand(0 n) (* noise(cx cy) 5))"
    );
}

#[test]
fn juxtaposed_calls_are_products() {
    assert_eq!(
        expr("translate(10, 0) rotate(30)"),
        "(* translate(10 0) rotate(30))"
    );
    assert_eq!(
        expr("translate(10,0) rotate(30) scale(2)"),
        "(* (* translate(10 0) rotate(30)) scale(2))"
    );
    assert_eq!(
        expr("a + translate(1) scale(2)"),
        "(+ a (* translate(1) scale(2)))"
    );
    // Across lines inside brackets too.
    let r =
        only_rule("animate(affine, local, 0,\n    translate(1, 0)\n    rotate(5)) : [a, s] -> [t]");
    assert_eq!(sexp(&r.args[3].value), "(* translate(1 0) rotate(5))");
}

#[test]
fn dashes_in_names_and_subtraction() {
    for (src, tree) in [
        ("ease-in-out", "ease-in-out"),
        ("stroke-width", "stroke-width"),
        ("a - b", "(- a b)"),
        ("a -b", "(- a b)"),
        ("id-1", "(- id 1)"),
        ("w-h", "w-h"),
    ] {
        assert_eq!(expr(src), tree, "{src}");
    }
}

#[test]
fn units_fold_into_numbers() {
    for (src, tree) in [
        ("6s", "6"),
        ("500ms", "0.5"),
        ("30deg", "30"),
        ("50%", "0.5"),
        ("2.5e-1", "0.25"),
        ("7%3", "(% 7 3)"),
        ("4x4", "4x4"),
    ] {
        assert_eq!(expr(src), tree, "{src}");
    }
    let d = errors("op(5px) : a -> []");
    assert_eq!(d.items[0].message, "unknown unit `px`");
    assert_eq!(positions(&d), [(1, 4)]);
}

#[test]
fn numbers_too_large_are_rejected() {
    let d = errors(
        "op(1e999) : a -> []\nop(1) : a -> [] priority=99999999999999999999\ngrid 99999999999x2",
    );
    assert_eq!(positions(&d), [(1, 4), (2, 26), (3, 6)]);
    assert!(d.items[0].message.contains("too large"));
    assert!(d.items[1].message.contains("too large"));
    assert!(d.items[2].message.contains("too large"));
}

#[test]
fn named_arguments() {
    let r = only_rule(
        "animate(affine, local, 0, rotate(90), ease = ease-in, grid=4x2, lookup=bilinear) : [a, s] -> [t]",
    );
    let named: Vec<String> = r
        .args
        .iter()
        .filter(|a| a.name.is_some())
        .map(arg_sexp)
        .collect();
    assert_eq!(named, ["ease=ease-in", "grid=4x2", "lookup=bilinear"]);
    let d = errors("op(ease=linear, 1) : a -> []\nop(x=1, x=2) : a -> []");
    assert_eq!(positions(&d), [(1, 17), (2, 9)]);
    assert!(
        d.items[0]
            .message
            .contains("positional argument after a named one")
    );
    assert!(d.items[1].message.contains("given twice"));
}

#[test]
fn spatial_rules_have_one_tag_list() {
    let g = ok("\
outline(25) : big_poly -> [in, out]
regroup(3) : [leaf] -> [a]
split(4) : (a, b) -> [c]
ungroup : x -> y
");
    // Each rule as "spatial | slice tags | shape tags | outputs".
    let forms: Vec<String> = g
        .rules
        .iter()
        .map(|r| {
            let (slice, shape, out) = (tags(&r.slice_tags), tags(&r.shape_tags), tags(&r.outputs));
            format!(
                "{} | {} | {} | {}",
                r.spatial,
                slice.join(" "),
                shape.join(" "),
                out.join(" ")
            )
        })
        .collect();
    assert_eq!(
        forms,
        [
            "true |  | big_poly | in out",
            "true |  | leaf | a",
            "true |  | a b | c",
            "true |  | x | y",
        ]
    );
    assert!(g.rules[3].args.is_empty());
}

#[test]
fn empty_outputs() {
    let r = only_rule("animate(fill, local, 0, red) : [a, s] -> []");
    assert!(r.outputs.is_empty());
}

#[test]
fn priorities_and_weights() {
    let g = ok("\
op(1) : [a, s] -> [b] priority=2 weight=0.5
op(2) : [a, s] -> [c] weight=3 priority=-1
op(3) : [a, s] -> [d]
op(4) : [a, s] -> [e]
    priority=7
");
    let got: Vec<(i64, f64)> = g.rules.iter().map(|r| (r.priority, r.weight)).collect();
    assert_eq!(got, [(2, 0.5), (-1, 3.0), (0, 1.0), (7, 1.0)]);
    let d = errors(
        "\
op(1) : [a, s] -> [b] priority=1.5
op(1) : [a, s] -> [b] weight=0
op(1) : [a, s] -> [b] weight=-2
op(1) : [a, s] -> [b] priority=1 priority=2
op(1) : [a, s] -> [b] priorty=1
",
    );
    assert_eq!(positions(&d), [(1, 32), (2, 30), (3, 30), (4, 34), (5, 23)]);
    assert_eq!(d.items[4].help.as_deref(), Some("did you mean `priority`?"));
}

#[test]
fn several_errors_are_reported_at_once() {
    let src = "\
duration 6s
timesplit(0.5 0.5) : [all, s] -> [a, inv_a]
animate(affine, world, 0, translate(200, 0)) : [a, s] -> [t]
animate(affine, local, 0, scale(0.5)) : [a, c] [t]
animate(fill, local, 0, red) : [t, c] -> [u]
loop maybe
";
    let d = errors(src);
    assert_eq!(positions(&d), [(2, 15), (4, 48), (6, 6)]);
    assert_eq!(d.items[0].expected, ["`,`", "`)`"]);
    assert_eq!(d.items[1].message, "missing `->` before the output tags");
    assert_eq!(d.items[2].expected, ["one of `true`, `false`"]);
}

#[test]
fn rendering_shows_the_line_and_a_caret() {
    let src = "duration 6s\nanimate(affine, local, 0, scale(0.5)) : [a, c] [t]\n";
    let text = errors(src).render("toy.gm", src);
    let expected = "\
toy.gm:2:48: error: missing `->` before the output tags
  |
2 | animate(affine, local, 0, scale(0.5)) : [a, c] [t]
  |                                                ^
  = expected one of `->`, `→`
  = help: a rule is written `op(args) : [slice_tags, shape_tags] -> [outputs]`
";
    assert_eq!(text, expected);
}

#[test]
fn rendering_counts_several_errors_and_underlines_whole_tokens() {
    let src = "durration 6s\nlookup bilinar\n";
    let text = errors(src).render("g.gm", src);
    assert!(
        text.contains(
            "g.gm:1:1: error: unknown directive `durration`\n  |\n1 | durration 6s\n  | ^^^^^^^^^\n"
        ),
        "{text}"
    );
    assert!(text.contains("g.gm:2:8: error: invalid value for `lookup`\n  |\n2 | lookup bilinar\n  |        ^^^^^^^\n"), "{text}");
    assert!(text.ends_with("2 errors in g.gm\n"), "{text}");
}

#[test]
fn unknown_directive_lists_the_known_ones() {
    let d = errors("durration 6s");
    let e = &d.items[0];
    assert_eq!(e.message, "unknown directive `durration`");
    assert_eq!(e.expected.len(), DIRECTIVES.len());
    assert!(e.expected.contains(&"`smoothing`".to_string()));
    assert_eq!(e.help.as_deref(), Some("did you mean `duration`?"));
}

#[test]
fn directives_and_their_values() {
    let g = ok("\
duration 500ms
fps 24
grid 4x3
seed 42
scene ../art/toy-1.svg   # a bare path runs to the first space
width 640
height 480
lookup bilinear
interp alexa
loop true
max_steps 500
choice shape
tag_from data-tag
units groups
smoothing spring(0.3, 0.1)
");
    let shown: Vec<String> = g
        .directives
        .iter()
        .map(|d| format!("{} {}", d.name, sexp(&d.values[0])))
        .collect();
    assert_eq!(
        shown,
        [
            "duration 0.5",
            "fps 24",
            "grid 4x3",
            "seed 42",
            "scene \"../art/toy-1.svg\"",
            "width 640",
            "height 480",
            "lookup bilinear",
            "interp alexa",
            "loop true",
            "max_steps 500",
            "choice shape",
            "tag_from data-tag",
            "units groups",
            "smoothing spring(0.3 0.1)",
        ]
    );
    assert_eq!(ok("scene \"my art/toy.svg\"").directives[0].values.len(), 1);
    assert_eq!(sexp(&ok("grid 3").directives[0].values[0]), "3");
}

#[test]
fn bad_directive_values() {
    let d = errors(
        "\
duration -2s
duration
fps 0
grid 0x4
seed 1.5
width 2 * 320
lookup nearest bilinear
duration 1s
duration 2s
",
    );
    assert_eq!(
        positions(&d),
        [
            (1, 10),
            (2, 1),
            (3, 5),
            (4, 6),
            (5, 6),
            (6, 7),
            (7, 16),
            (9, 1)
        ]
    );
    assert!(
        d.items[5]
            .help
            .as_deref()
            .unwrap_or("")
            .contains("literals")
    );
    assert_eq!(d.items[7].message, "`duration` is set twice");
    assert_eq!(
        d.items[7].help.as_deref(),
        Some("it is first set on line 8")
    );
}

#[test]
fn unterminated_string() {
    let src = "animate(path, world, 0, \"M 0 0 L 10 10) : [a, s] -> [t]\nduration 2s\nfps x\n";
    let d = errors(src);
    assert_eq!(positions(&d), [(1, 25), (3, 5)]);
    assert_eq!(d.items[0].message, "unterminated string");
    assert_eq!(
        errors("scene \"art/toy.svg\n").items[0].message,
        "unterminated string"
    );
    let text = d.render("g", src);
    // The caret runs from the quote to the end of the line.
    let rest = src.lines().next().unwrap().len() - 24;
    assert!(
        text.contains(&format!("  | {}{}\n", " ".repeat(24), "^".repeat(rest))),
        "{text}"
    );
}

#[test]
fn empty_and_comment_only_files_are_valid() {
    for src in ["", "\n\n", "# nothing here\n// nor here", "   \t\n"] {
        let g = ok(src);
        assert!(g.rules.is_empty() && g.directives.is_empty());
    }
}

#[test]
fn missing_arrow_and_missing_colon() {
    let d =
        errors("timesplit(0.5, 0.5) : [all, s] [a, b]\ntimesplit(0.5, 0.5) [all, s] -> [a, b]\n");
    assert_eq!(positions(&d), [(1, 32), (2, 21)]);
    assert_eq!(d.items[0].expected, ["`->`", "`→`"]);
    assert_eq!(d.items[1].expected, ["`:`"]);
    let d = errors("op(1) : [a, s]\n");
    assert_eq!(positions(&d), [(1, 15)]);
    assert_eq!(d.items[0].message, "missing `->` before the output tags");
}

#[test]
fn a_rule_may_span_lines() {
    let g = ok("\
timesplit(
    0.3, 0.4,
    0.3)
    : [all, all]
    -> [a1, a2, inv_a1]
animate(affine, world, 0, translate(400, 0))
    : [a1, c] -> [t1] weight=2
");
    assert_eq!(g.rules.len(), 2);
    assert_eq!(tags(&g.rules[0].outputs), ["a1", "a2", "inv_a1"]);
    assert_eq!(g.rules[1].weight, 2.0);
}

#[test]
fn an_unclosed_bracket_costs_one_error() {
    let src = "\
animate(affine, world, 0, translate(200, 0) : [a, s] -> [t]
timesplit(0.5, 0.5 : [all, s] -> [a, b]
animate(affine, local, 0, scale(0.5)
fps 30
op(1) : [a, s -> [b]
seed 1
";
    let d = errors(src);
    assert_eq!(positions(&d), [(1, 45), (2, 20), (3, 8), (5, 15)]);
    assert_eq!(d.items[2].message, "unclosed `(`");
    assert!(d.items[2].help.as_deref().unwrap_or("").contains("indent"));
}

#[test]
fn inverted_tags_only_where_they_mean_something() {
    let d = errors(
        "\
op(1) : [inv_a, s] -> [b]
op(1) : [a, inv_s] -> [b]
outline(2) : inv_a -> [b]
outline(2) : a -> [inv_b]
op(1) : [a, s] -> [inv_inv_b]
",
    );
    assert_eq!(positions(&d), [(1, 10), (2, 13), (3, 14), (4, 20), (5, 20)]);
    assert_eq!(d.items[0].message, "match `a`, not `inv_a`");
}

#[test]
fn too_many_tag_lists() {
    let d = errors("op(1) : [a, b, c] -> [d]");
    assert_eq!(positions(&d), [(1, 16)]);
    assert!(
        d.items[0]
            .help
            .as_deref()
            .unwrap_or("")
            .contains("[(a, b), s]")
    );
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let deep = format!("op({}1{}) : a -> []", "(".repeat(5000), ")".repeat(5000));
    assert!(errors(&deep).items[0].message.contains("nested"));
    let long = format!("op(1{}) : a -> []", " + 1".repeat(5000));
    assert!(errors(&long).items[0].message.contains("nested"));
    let negs = format!("op({}1) : a -> []", "-".repeat(5000));
    assert!(errors(&negs).items[0].message.contains("nested"));
    // A realistic long expression is fine.
    ok(&format!("op(1{}) : a -> []", " + 1".repeat(100)));
}

#[test]
fn lexer_errors_are_reported_in_place() {
    let d = errors(
        "op(a @ b) : a -> []\nop(a $ 1) : a -> []\nop('x') : a -> []\nop(\"\\q\") : a -> []",
    );
    assert_eq!(positions(&d), [(1, 6), (2, 6), (3, 4), (4, 5)]);
    assert_eq!(d.items[0].message, "unexpected character `@`");
    assert!(d.items[3].message.contains("escape"));
}

mod never_panics {
    use gmotion::grammar::{Env, eval};
    use proptest::prelude::*;

    /// A shape with every variable set to 2 and a fixed random draw.
    struct Shape;

    impl Env for Shape {
        fn var(&self, name: &str) -> Option<f64> {
            ["id", "n", "cx", "cy", "w", "h"]
                .contains(&name)
                .then_some(2.0)
        }
        fn rand(&mut self) -> f64 {
            0.5
        }
        fn noise(&self, _: f64, _: f64) -> f64 {
            0.0
        }
    }

    proptest! {
        /// Any text parses or fails with errors whose spans lie inside the source, and
        /// rendering them works.
        #[test]
        fn on_any_input(src in "[a-z_0-9 ()\\[\\],:=+*/%^#\"\\-→>.\n\t]{0,80}") {
            match gmotion::grammar::parse(&src) {
                Ok(_) => {}
                Err(d) => {
                    prop_assert!(!d.is_empty());
                    for e in &d {
                        prop_assert!(e.span.start <= e.span.end && e.span.end <= src.len(), "{e:?}");
                        prop_assert!(src.is_char_boundary(e.span.start) && src.is_char_boundary(e.span.end));
                    }
                    let text = d.render("fuzz", &src);
                    prop_assert!(text.contains("fuzz:"));
                }
            }
        }

        /// Any expression built from the language's pieces evaluates or fails with an
        /// error inside the source.
        #[test]
        fn when_evaluating(
            parts in prop::collection::vec(
                prop::sample::select(vec![
                    "1", "0", "-", "+", "*", "/", "%", "^", "(", ")", ",", "id", "w-h", "1e300",
                    "50%", "#f80", "red", "\"s\"", "translate(1, 2)", "rotate(", "scale(",
                    "rgb(", "hsl(", "lerp(", "rand(", "min(", "sqrt(", "ln(", "(1, 2)", "4x4",
                    "cubic(", "point(", "pi",
                ]),
                1..12,
            )
        ) {
            let expr = parts.join(" ");
            let src = format!("op({expr}) : a -> []");
            if let Ok(g) = gmotion::grammar::parse(&src) {
                for arg in &g.rules[0].args {
                    if let Err(e) = eval(&arg.value, &mut Shape) {
                        prop_assert!(e.span.end <= src.len(), "{e:?}");
                        prop_assert!(!e.message.is_empty());
                    }
                }
            }
        }
    }
}

#[test]
fn every_directive_is_documented() {
    let doc =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/grammar.md")).unwrap();
    for d in DIRECTIVES {
        let row = format!("| `{}` |", d.name);
        let line = doc.lines().find(|l| l.starts_with(&row));
        let line =
            line.unwrap_or_else(|| panic!("docs/grammar.md has no table row for `{}`", d.name));
        assert!(
            line.contains(&format!("`{}`", d.default)) || line.contains(d.default),
            "`{}`: default `{}` not in {line}",
            d.name,
            d.default
        );
    }
}

#[test]
fn the_papers_notation_reads_as_gmotions() {
    // gMotion Fig. 4 / Fig. 5 and gTangle Fig. 9 as printed, against gmotion's own spelling.
    let same = |paper: &str, ours: &str| {
        let (p, o) = (ok(paper), ok(ours));
        assert_eq!(
            format!("{:?}", strip(&p)),
            format!("{:?}", strip(&o)),
            "{paper}"
        );
    };
    same(
        "1. TimeSplit({0.3, 0.7}) : [(all), (s)] → [t₁, inv_t₁]",
        "timesplit((0.3, 0.7)) : [all, s] -> [t1, inv_t1]",
    );
    same(
        "12. outline(25) : big poly → [⟨in 2⟩, ⟨tiny out⟩]",
        "outline(25) : big_poly -> [in_2, tiny_out]",
    );
    same(
        "3) place(20, 25) : out → [⟨blob⟩, ⟨rem⟩]",
        "place(20, 25) : out -> [blob, rem]",
    );
    same(
        "timesplit([0.5, 0.5]) : [all, s] -> [a, b]",
        "timesplit((0.5, 0.5)) : [all, s] -> [a, b]",
    );
    // A single output tag followed by a rule option is not a two-word tag.
    let g = ok("animate(affine, world, 0, scale(2)) : [a, s] -> t priority=2");
    assert_eq!(g.rules[0].outputs[0].name, "t");
    assert_eq!(g.rules[0].priority, 2);
    // A number with a dot elsewhere than at the start of a line is still a number.
    let g = ok("timesplit(0.5, 0.5) : [all, s] -> [a, b]");
    assert_eq!(g.rules.len(), 1);
    // An unclosed angle tag and an unclosed brace are located errors.
    assert_eq!(positions(&errors("outline(2) : a → [⟨in]")), [(1, 19)]);
    let d = errors("timesplit({0.5, 0.5) : [all, s] -> [a, b]");
    assert_eq!(positions(&d), [(1, 20)]);
    assert!(
        d.items[0].expected.iter().any(|e| e == "`}`"),
        "{:?}",
        d.items[0]
    );
}

/// A grammar's rules with the places they were written at dropped, to compare spellings.
type Spelling = (String, Vec<String>, [Vec<String>; 3]);

fn strip(g: &Grammar) -> Vec<Spelling> {
    g.rules
        .iter()
        .map(|r| {
            let args = r.args.iter().map(|a| expr_text(&a.value)).collect();
            let lists = [tags(&r.slice_tags), tags(&r.shape_tags), tags(&r.outputs)];
            (r.op.clone(), args, lists)
        })
        .collect()
}

/// An expression written out without its places.
fn expr_text(e: &gmotion::grammar::ast::Expr) -> String {
    use gmotion::grammar::ast::ExprKind;
    match &e.kind {
        ExprKind::Num(v) => v.to_string(),
        ExprKind::Ident(s) => s.clone(),
        ExprKind::Tuple(items) => {
            let items: Vec<String> = items.iter().map(expr_text).collect();
            format!("({})", items.join(", "))
        }
        ExprKind::Binary { op, lhs, rhs } => {
            format!("({} {op:?} {})", expr_text(lhs), expr_text(rhs))
        }
        ExprKind::Neg(x) => format!("-{}", expr_text(x)),
        ExprKind::Call { name, args } => {
            let args: Vec<String> = args.iter().map(|a| expr_text(&a.value)).collect();
            format!("{name}({})", args.join(", "))
        }
        other => format!("{other:?}"),
    }
}

#[test]
fn shape_tag_patterns_exclusions_and_lets() {
    let g = ok("let col = id % 6
let delay = 0.1 * col
animate(affine, world, delay, translate(10 * col, 0)) : [a, icon-* - icon-home] -> [m]
outline(2) : (Layer_*, *_1) - bg -> [x, y]
");
    let r = &g.rules[0];
    assert_eq!(tags(&r.shape_tags), ["icon-*"]);
    assert_eq!(tags(&r.shape_excluded), ["icon-home"]);
    // A `let` name reads as its expression.
    assert_eq!(
        expr_text(&r.args[2].value),
        expr_text(&ok("op(0.1 * (id % 6)) : a -> []").rules[0].args[0].value)
    );
    let s = &g.rules[1];
    assert!(s.spatial);
    assert_eq!(tags(&s.shape_tags), ["Layer_*", "*_1"]);
    assert_eq!(tags(&s.shape_excluded), ["bg"]);
    assert!(r.takes_shape(["icon-user"], true) && !r.takes_shape(["icon-home"], true));
    assert!(!r.takes_shape(["logo"], true));
    assert!(
        s.takes_shape(["Layer_2"], true)
            && s.takes_shape(["tile_1"], true)
            && !s.takes_shape(["bg"], true)
    );
    // A shape answers to all of its tags: one named is enough, one left out is too many.
    assert!(r.takes_shape(["logo", "icon-user"], true));
    assert!(!s.takes_shape(["Layer_2", "bg"], true));
    // Patterns pick shape tags only; a bound name is bound once and renames no variable.
    let d = errors(
        "timesplit(0.5, 0.5) : [a*, s] -> [b, c]\nanimate(affine, world, 0, scale(2)) : [a, s] -> [t*]\nlet cx = 2\nlet q = 1\nlet q = 2\n",
    );
    assert_eq!(positions(&d), [(1, 24), (2, 50), (3, 5), (5, 5)]);
    // A binding of bindings that would grow without bound is refused where it is bound.
    let mut src = String::from("let a0 = id\n");
    for i in 1..20 {
        src.push_str(&format!("let a{i} = a{} + a{}\n", i - 1, i - 1));
    }
    let d = errors(&src);
    assert!(d.items[0].message.contains("too large"), "{:?}", d.items[0]);
}

#[test]
fn tag_patterns_match_as_globs() {
    use gmotion::grammar::ast::tag_matches;
    for (pattern, tag, yes) in [
        ("icon-*", "icon-home", true),
        ("icon-*", "icon-", true),
        ("icon-*", "logo", false),
        ("*_1", "Layer_1", true),
        ("*_1", "Layer_12", false),
        ("a*b*c", "a-x-b-y-c", true),
        ("a*b*c", "acb", false),
        ("*", "anything", true),
        ("a**", "a", true),
        ("ab*ba", "aba", false),
        ("plain", "plain", true),
    ] {
        assert_eq!(tag_matches(pattern, tag), yes, "{pattern} ~ {tag}");
    }
}
