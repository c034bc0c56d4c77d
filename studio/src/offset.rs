//! Moving a change: the start of a shape's change dragged on the timeline becomes a new
//! `offset` of the `animate` rule that set it (issue 43, "drag a shape's change to move
//! its offset").
//!
//! As for retiming, the rule is found by asking: each `animate` rule's offset is nudged
//! in the text and the timelines expanded again; the rule whose nudge moves the dragged
//! change is the one. The offset is then rewritten as a whole: a number becomes the new
//! delay; a stagger `a + b·v` (or `b·v`, `v·b`; `v` a variable such as `id`) keeps its
//! form, the first shape's drag (`v` = 0) moving `a` and any other's scaling `b`; any other
//! expression gains `+ Δ`.

use gmotion::Scene;
use gmotion::engine::{self, RunOptions};
use gmotion::grammar::ast::{BinOp, Expr, ExprKind, Grammar, Rule, Span};
use gmotion::grammar::parse;

/// How far a nudge moves an offset (seconds).
pub(crate) const NUDGE: f64 = 0.001;

/// What a move changed: the new text, the rule's line, its offset as written now.
#[derive(Debug)]
pub(crate) struct Moved {
    pub text: String,
    pub line: u32,
    pub offset: String,
}

/// Where one forward change on a slice starts and the slice it was set on.
#[derive(Clone, Copy, Debug)]
struct Change {
    start: f64,
    slice_start: f64,
    slice_end: f64,
    delay: f64,
}

/// The forward changes on slice `slice` of shape `shape` under `g`.
fn changes(
    scene: &Scene,
    g: &Grammar,
    run: &RunOptions,
    shape: usize,
    slice: usize,
) -> Option<Vec<Change>> {
    let x = engine::timelines(scene, g, run).ok()?;
    let s = x.timelines.get(shape)?.get(slice)?;
    Some(
        s.anims
            .iter()
            .filter(|a| !a.reversed)
            .map(|a| Change {
                start: a.timing().active().0,
                slice_start: a.start,
                slice_end: a.end,
                delay: a.delay,
            })
            .collect(),
    )
}

/// `text` (which parses to `grammar`) with the forward change on slice `slice` of shape
/// `shape` that starts at `from` seconds made to start at `time`, by rewriting its
/// `animate` rule's offset; or why not.
pub(crate) fn move_offset(
    text: &str,
    grammar: &Grammar,
    scene: &Scene,
    run: &RunOptions,
    (shape, slice, from, time): (usize, usize, f64, f64),
) -> Result<Moved, String> {
    let before = changes(scene, grammar, run, shape, slice)
        .ok_or_else(|| format!("shape {shape} has no slice {slice}"))?;
    let Some(e) = before.iter().position(|c| (c.start - from).abs() < 1e-6) else {
        return Err(format!(
            "no change on slice {slice} of shape {shape} starts at {from} s (an inverted \
             slice's change moves with its twin's)"
        ));
    };
    let change = before[e];
    for rule in grammar
        .rules
        .iter()
        .filter(|r| !r.spatial && r.op == "animate")
    {
        let Some(offset) = rule.args.iter().filter(|a| a.name.is_none()).nth(2) else {
            continue;
        };
        let span = offset.value.span;
        let Some(nudged) = with_offset_nudged(text, rule) else {
            continue;
        };
        let Ok(g) = parse(&nudged) else { continue };
        let Some(after) = changes(scene, &g, run, shape, slice) else {
            continue;
        };
        if after.len() != before.len() || (after[e].start - change.start - NUDGE).abs() > 1e-7 {
            continue;
        }
        let longest = change.slice_end - change.slice_start - NUDGE;
        let delay = (time - change.slice_start).clamp(0.0, longest.max(0.0));
        let written = rewrite(&offset.value, text, change.delay, delay);
        let mut out = text.to_string();
        out.replace_range(span.start..span.end, &written.0);
        return Ok(Moved {
            text: out,
            line: rule.span.line,
            offset: written.1,
        });
    }
    Err(format!(
        "no animate rule's offset sets the change at {from} s on slice {slice} of shape {shape}"
    ))
}

/// The offset `expr` (of `text`) rewritten so that this shape's delay `d0` becomes `d1`:
/// the text that replaces the expression, and the offset as it then reads.
fn rewrite(expr: &Expr, text: &str, d0: f64, d1: f64) -> (String, String) {
    let whole = &text[expr.span.start..expr.span.end];
    let patched = |span: Span, by: &str| {
        let (s, e) = (span.start - expr.span.start, span.end - expr.span.start);
        format!("{}{by}{}", &whole[..s], &whole[e..])
    };
    let done = |s: String| (s.clone(), s);
    match stagger(expr) {
        Some((a, b, b_span)) if b != 0.0 => {
            let v = (d0 - a.map_or(0.0, |(a, _)| a)) / b;
            if v.abs() < 1e-9 {
                // The first shape: its delay is `a`.
                return done(match a {
                    Some((_, a_span)) => patched(a_span, &decimal(d1)),
                    None => format!("{} + {whole}", decimal(d1)),
                });
            }
            let a = a.map_or(0.0, |(a, _)| a);
            done(patched(b_span, &decimal((d1 - a) / v)))
        }
        _ => match expr.kind {
            ExprKind::Num(_) => done(decimal(d1)),
            _ => {
                let delta = d1 - d0;
                let sign = if delta < 0.0 { "-" } else { "+" };
                done(format!("{whole} {sign} {}", decimal(delta.abs())))
            }
        },
    }
}

/// A stagger `a + b·v`: `a` with its place if written, `b` and its place.
type Stagger = (Option<(f64, Span)>, f64, Span);

/// `expr` read as `a + b·v`, `b·v` or `v·b` (`v` a variable, `a` and `b` numbers).
fn stagger(expr: &Expr) -> Option<Stagger> {
    let product = |e: &Expr| -> Option<(f64, Span)> {
        let ExprKind::Binary {
            op: BinOp::Mul,
            lhs,
            rhs,
        } = &e.kind
        else {
            return None;
        };
        match (&lhs.kind, &rhs.kind) {
            (ExprKind::Num(b), ExprKind::Ident(_)) => Some((*b, lhs.span)),
            (ExprKind::Ident(_), ExprKind::Num(b)) => Some((*b, rhs.span)),
            _ => None,
        }
    };
    if let Some((b, span)) = product(expr) {
        return Some((None, b, span));
    }
    let ExprKind::Binary {
        op: BinOp::Add,
        lhs,
        rhs,
    } = &expr.kind
    else {
        return None;
    };
    match (&lhs.kind, product(rhs), &rhs.kind, product(lhs)) {
        (ExprKind::Num(a), Some((b, span)), _, _) => Some((Some((*a, lhs.span)), b, span)),
        (_, _, ExprKind::Num(a), Some((b, span))) => Some((Some((*a, rhs.span)), b, span)),
        _ => None,
    }
}

/// `v` rounded to thousandths, written short (`0.150` → `0.15`).
fn decimal(v: f64) -> String {
    let text = format!("{:.3}", (v * 1e3).round() / 1e3);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".into()
    } else {
        text.into()
    }
}

/// The grammar `text` with `rule`'s offset (its third positional argument) delayed by
/// [`NUDGE`] seconds: expanding it shows which changes that rule starts. `None` for a rule
/// without an offset.
pub(crate) fn with_offset_nudged(text: &str, rule: &Rule) -> Option<String> {
    let span = rule
        .args
        .iter()
        .filter(|a| a.name.is_none())
        .nth(2)?
        .value
        .span;
    Some(format!(
        "{}({}) + {NUDGE}{}",
        &text[..span.start],
        &text[span.start..span.end],
        &text[span.end..]
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The offset (third argument) of the first rule of `text`, rewritten from `d0` to `d1`.
    fn moved(offset: &str, d0: f64, d1: f64) -> String {
        let text = format!("animate(opacity, local, {offset}, 0) : [all, all] -> [x]\n");
        let g = parse(&text).unwrap();
        let e = &g.rules[0].args[2].value;
        rewrite(e, &text, d0, d1).0
    }

    #[test]
    fn offsets_are_rewritten_as_a_whole() {
        assert_eq!(moved("0.5", 0.5, 0.25), "0.25");
        // A stagger: the first shape (id 0) moves `a`, another scales `b`.
        assert_eq!(moved("0.1 + 0.15 * id", 0.1, 0.3), "0.3 + 0.15 * id");
        assert_eq!(moved("0.1 + 0.15 * id", 0.4, 0.7), "0.1 + 0.3 * id");
        assert_eq!(moved("0.15 * id", 0.3, 0.6), "0.3 * id");
        assert_eq!(moved("id * 0.15", 0.3, 0.6), "id * 0.3");
        assert_eq!(moved("0.15 * id", 0.0, 0.2), "0.2 + 0.15 * id");
        // Anything else gains the difference.
        assert_eq!(moved("rand(0, 1)", 0.4, 0.5), "rand(0, 1) + 0.1");
        assert_eq!(moved("d / 4", 0.5, 0.25), "d / 4 - 0.25");
    }
}
