//! Setting a rule's value: what the canvas handles, the colour picker and the easing
//! curve editor write (issue 43, "handles on the canvas").
//!
//! Two questions, as the page asks them. Which `animate` rules change a shape in the slice
//! under the playhead (`rules_at`)? As for moving an offset, the engine is asked: each
//! rule's offset is nudged in the text and the timelines expanded again; a rule whose nudge
//! moves a change on that slice is one of them, and the change's eased progress at the
//! playhead tells the page how far along it is (so a drag at mid-change moves the value by
//! twice the drag). And what does the text become when one argument of a rule (its value
//! or its `ease=`) is replaced by new text (`set_value`)? The replacement must read as that
//! one argument and nothing more: text that would close the call or start another rule is
//! refused before the grammar is built.

use gmotion::Scene;
use gmotion::engine::{self, RunOptions};
use gmotion::grammar::ast::{Grammar, Rule};
use gmotion::grammar::parse;
use serde_json::{Value, json};

use crate::offset::{NUDGE, with_offset_nudged};

/// The argument of an `animate` rule an edit replaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Arg {
    /// The value (the fourth argument): a transform, a colour, a number…
    Value,
    /// The `ease=` argument (added when the rule has none).
    Ease,
}

impl Arg {
    /// `value` or `ease`, as the API names them.
    pub fn named(name: &str) -> Option<Arg> {
        match name {
            "value" => Some(Arg::Value),
            "ease" => Some(Arg::Ease),
            _ => None,
        }
    }
}

/// What a value edit changed: the new text, the rule's line and the argument as written.
#[derive(Debug)]
pub(crate) struct Set {
    pub text: String,
    pub line: u32,
    pub value: String,
}

/// The non-spatial `animate` rules of `g`.
fn animate_rules(g: &Grammar) -> impl Iterator<Item = (usize, &Rule)> {
    g.rules
        .iter()
        .enumerate()
        .filter(|(_, r)| !r.spatial && r.op == "animate")
}

/// The text of `rule`'s argument `arg` in `text`, with its byte range; `None` for an
/// `ease=` the rule does not write.
fn arg_text<'a>(text: &'a str, rule: &Rule, arg: Arg) -> Option<(&'a str, usize, usize)> {
    let found = match arg {
        Arg::Value => rule.args.iter().filter(|a| a.name.is_none()).nth(3),
        Arg::Ease => rule.args.iter().find(|a| a.name.as_deref() == Some("ease")),
    }?;
    let span = found.value.span;
    Some((&text[span.start..span.end], span.start, span.end))
}

/// The starts and ends of the changes on the slice of shape `shape` under time `t`, with
/// each change's eased progress at `t`; `None` when the grammar does not expand.
fn changes_at(
    scene: &Scene,
    g: &Grammar,
    run: &RunOptions,
    shape: usize,
    t: f64,
) -> Option<Vec<((f64, f64), f64)>> {
    let x = engine::timelines(scene, g, run).ok()?;
    let slices = x.timelines.get(shape)?;
    let slice = slices
        .iter()
        .find(|s| t >= s.t0 && t < s.t0 + s.dur)
        .or_else(|| slices.last().filter(|s| t >= s.t0))?;
    Some(
        slice
            .anims
            .iter()
            .map(|a| {
                let timing = a.timing();
                (timing.active(), timing.progress(t))
            })
            .collect(),
    )
}

/// The `animate` rules of `text` (which parses to `grammar`) that change shape `shape` in
/// the slice under time `t`, as `[{rule, line, column, type, ref, value, ease, progress}]`:
/// `rule` its index, `type` and `ref` its first two arguments as written, `value` and `ease` its text (`ease` `null` when
/// the rule has none), `progress` the eased progress of its change at `t` (0 before it
/// starts, 1 once done; an inverted slice's change runs from 1 back to 0).
pub(crate) fn rules_at(
    text: &str,
    grammar: &Grammar,
    scene: &Scene,
    run: &RunOptions,
    (shape, t): (usize, f64),
) -> Result<Value, String> {
    let before = changes_at(scene, grammar, run, shape, t)
        .ok_or_else(|| format!("there is no shape {shape}"))?;
    let mut out = Vec::new();
    for (i, rule) in animate_rules(grammar) {
        let Some(nudged) = with_offset_nudged(text, rule) else {
            continue;
        };
        let Ok(g) = parse(&nudged) else { continue };
        let Some(after) = changes_at(scene, &g, run, shape, t) else {
            continue;
        };
        // The first change the nudge moved is this rule's.
        let moved = before.iter().zip(&after).find(|(b, a)| {
            (b.0.0 - a.0.0).abs() > NUDGE / 2.0 || (b.0.1 - a.0.1).abs() > NUDGE / 2.0
        });
        let Some(((_, progress), _)) = moved else {
            continue;
        };
        let kind = rule
            .args
            .first()
            .map_or("", |a| &text[a.value.span.start..a.value.span.end]);
        let reference = rule
            .args
            .get(1)
            .map_or("", |a| &text[a.value.span.start..a.value.span.end]);
        out.push(json!({
            "rule": i,
            "ref": reference.trim_matches('"'),
            "line": rule.span.line,
            "column": rule.span.col,
            "type": kind.trim_matches('"'),
            "value": arg_text(text, rule, Arg::Value).map(|v| v.0),
            "ease": arg_text(text, rule, Arg::Ease).map(|v| v.0),
            "progress": progress,
        }));
    }
    Ok(Value::Array(out))
}

/// `text` (which parses to `grammar`) with argument `arg` of the `animate` rule on line
/// `line` replaced by `new` (an `ease=` the rule lacks is added after its last argument);
/// or why not. The result is not built here: the caller applies it only if it builds.
pub(crate) fn set_value(
    text: &str,
    grammar: &Grammar,
    (line, arg, new): (u32, Arg, &str),
) -> Result<Set, String> {
    let new = new.trim();
    // One line: a comment (`#` not starting a colour) or a call left open is caught when
    // the text is read back below.
    if new.is_empty() || new.contains(['\n', '\r']) {
        return Err(format!("`{new}` is not one value: a value is one line"));
    }
    let (index, rule) = animate_rules(grammar)
        .find(|(_, r)| r.span.line == line)
        .ok_or_else(|| format!("line {line} has no animate rule"))?;
    let mut out = text.to_string();
    match arg_text(text, rule, arg) {
        Some((_, start, end)) => out.replace_range(start..end, new),
        None => {
            let last = rule
                .args
                .last()
                .ok_or_else(|| format!("the rule on line {line} has no arguments"))?;
            out.insert_str(last.span.end, &format!(", ease={new}"));
        }
    }
    // The new text must be read back as that argument, whole: `1) : [a, b] -> [c]` and
    // the like would make another rule of the line.
    let again = parse(&out).map_err(|ds| {
        let why = ds
            .items
            .first()
            .map_or(String::new(), |d| d.message.clone());
        format!("`{new}` does not read as a value ({why}); the text is unchanged")
    })?;
    let same = again.rules.len() == grammar.rules.len()
        && again
            .rules
            .get(index)
            .and_then(|r| arg_text(&out, r, arg))
            .is_some_and(|(v, _, _)| v == new);
    if !same {
        return Err(format!(
            "`{new}` does not read as one value of the rule; the text is unchanged"
        ));
    }
    Ok(Set {
        text: out,
        line: rule.span.line,
        value: new.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOY: &str = "timesplit(0.5, 0.5) : [all, s] -> [a, inv_a]\n\
        animate(affine, world, 0, translate(30, -10)) : [a, s] -> [moved]\n\
        animate(fill, local, 0, #e4572e, ease=ease-in) : [a, s] -> [red]\n";

    fn set(line: u32, arg: Arg, new: &str) -> Result<String, String> {
        let g = parse(TOY).unwrap();
        set_value(TOY, &g, (line, arg, new)).map(|s| s.text)
    }

    #[test]
    fn a_value_is_rewritten_in_place() {
        let out = set(2, Arg::Value, "translate(42, -4)").unwrap();
        assert!(out.contains("animate(affine, world, 0, translate(42, -4)) : [a, s]"));
        let out = set(3, Arg::Value, "#00ff00").unwrap();
        assert!(out.contains("animate(fill, local, 0, #00ff00, ease=ease-in)"));
        let out = set(3, Arg::Value, "lerp(#00ff00, #0000ff, 0.5)").unwrap();
        assert!(out.contains("0, lerp(#00ff00, #0000ff, 0.5), ease=ease-in)"));
    }

    #[test]
    fn an_easing_is_replaced_or_added() {
        let out = set(3, Arg::Ease, "cubic(0.1, 0.2, 0.3, 1)").unwrap();
        assert!(out.contains("#e4572e, ease=cubic(0.1, 0.2, 0.3, 1)) :"));
        let out = set(2, Arg::Ease, "ease-out").unwrap();
        assert!(out.contains("translate(30, -10), ease=ease-out) :"));
    }

    #[test]
    fn text_that_is_not_one_value_is_refused() {
        for bad in [
            "translate(1, 0)) : [a, s] -> [x]\nanimate(opacity, local, 0, 0",
            "translate(1, 0), 3",
            "translate(1,",
            "",
            "1 # a comment",
            "1\n2",
        ] {
            assert!(set(2, Arg::Value, bad).is_err(), "{bad:?} accepted");
        }
        assert!(set(1, Arg::Value, "1").is_err(), "a timesplit has no value");
        assert!(set(9, Arg::Value, "1").is_err(), "no rule on line 9");
    }
}
