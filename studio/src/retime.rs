//! Retiming: a slice boundary dragged on the timeline becomes new `timesplit` fractions
//! in the grammar's text (issue 43, "a timeline you edit").
//!
//! The expansion keeps no record of which rule cut where, so the rule is found by
//! asking: each `timesplit` whose neighbouring fractions are plain numbers is nudged
//! (one fraction up, the next down by as much, the sum kept), the timelines expanded
//! again, and the first nudge that moves the dragged boundary is the one. A boundary is
//! where the split puts it, `start + length · (f₀ + … + fⱼ)`, linear in the fraction, so
//! the nudge also gives the slope that turns the new time into the new fractions.

use gmotion::Scene;
use gmotion::engine::{self, RunOptions};
use gmotion::grammar::ast::{ExprKind, Grammar, Span};

/// The smallest fraction a retime leaves (a slice of zero length would vanish).
const MIN_FRACTION: f64 = 0.001;

/// What a retime changed: the new text, and the rule and fractions rewritten.
#[derive(Debug)]
pub(crate) struct Retimed {
    pub text: String,
    /// The line of the `timesplit` rewritten.
    pub line: u32,
    /// Its two fractions as written now.
    pub fractions: [String; 2],
}

/// `text` (which parses to `grammar`) with the boundary between slices `boundary` and
/// `boundary + 1` of shape `shape` moved to `time` seconds, by rewriting the two
/// fractions of the `timesplit` that cuts there; or why not.
pub(crate) fn retime(
    text: &str,
    grammar: &Grammar,
    scene: &Scene,
    run: &RunOptions,
    (shape, boundary, time): (usize, usize, f64),
) -> Result<Retimed, String> {
    let at = |g: &Grammar| -> Result<Option<(usize, f64)>, String> {
        let x = engine::timelines(scene, g, run).map_err(|e| e.to_string())?;
        Ok(x.timelines
            .get(shape)
            .and_then(|tl| Some((tl.len(), tl.get(boundary + 1)?.t0))))
    };
    let Some((count, before)) = at(grammar)? else {
        return Err(format!(
            "shape {shape} has no boundary {boundary} (count its slices from 0)"
        ));
    };
    for (r, rule) in grammar.rules.iter().enumerate() {
        if rule.spatial || rule.op != "timesplit" {
            continue;
        }
        let numbers: Vec<Option<(f64, Span)>> = rule
            .args
            .iter()
            .filter(|a| a.name.is_none())
            .map(|a| match a.value.kind {
                ExprKind::Num(v) => Some((v, a.value.span)),
                _ => None,
            })
            .collect();
        for j in 0..numbers.len().saturating_sub(1) {
            let (Some((a, sa)), Some((b, sb))) = (numbers[j], numbers[j + 1]) else {
                continue;
            };
            let nudge = 0.1 * a.min(b);
            if nudge <= 0.0 {
                continue;
            }
            let mut nudged = grammar.clone();
            set_positional(&mut nudged.rules[r].args, j, a + nudge);
            set_positional(&mut nudged.rules[r].args, j + 1, b - nudge);
            let Ok(Some((n, after))) = at(&nudged) else {
                continue;
            };
            if n != count || (after - before).abs() < 1e-9 {
                continue;
            }
            // Seconds per unit of fraction, then the fraction that puts it at `time`.
            let slope = (after - before) / nudge;
            let delta = ((time - before) / slope).clamp(MIN_FRACTION - a, b - MIN_FRACTION);
            let (first, second) = split_sum(a, b, a + delta);
            let mut out = text.to_string();
            // The later span first, so the earlier one's offsets still hold.
            out.replace_range(sb.start..sb.end, &second);
            out.replace_range(sa.start..sa.end, &first);
            return Ok(Retimed {
                text: out,
                line: rule.span.line,
                fractions: [first, second],
            });
        }
    }
    Err(format!(
        "no timesplit with plain-number fractions cuts shape {shape} at boundary {boundary}; \
         edit its fractions in the text"
    ))
}

/// Sets the `j`-th positional argument to the number `v`.
fn set_positional(args: &mut [gmotion::grammar::ast::Arg], j: usize, v: f64) {
    if let Some(arg) = args.iter_mut().filter(|a| a.name.is_none()).nth(j) {
        arg.value.kind = ExprKind::Num(v);
    }
}

/// Two fractions written for `a + b` kept exactly (in millionths, so decimal sums such
/// as `0.4 + 0.6` stay `1`), the first `first` rounded to thousandths.
fn split_sum(a: f64, b: f64, first: f64) -> (String, String) {
    let sum = ((a + b) * 1e6).round() as i64;
    let one = ((first * 1e3).round() as i64 * 1000).clamp(1000, (sum - 1000).max(1000));
    (decimal(one), decimal(sum - one))
}

/// `millionths` as a short decimal (`450000` → `0.45`).
fn decimal(millionths: i64) -> String {
    let text = format!("{:.6}", millionths as f64 / 1e6);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    text.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_sums_keep_their_total() {
        assert_eq!(split_sum(0.5, 0.5, 0.4), ("0.4".into(), "0.6".into()));
        assert_eq!(
            split_sum(0.4, 0.6, 0.4523),
            ("0.452".into(), "0.548".into())
        );
        assert_eq!(split_sum(0.25, 0.25, 0.1), ("0.1".into(), "0.4".into()));
        // Never a zero or negative fraction.
        assert_eq!(split_sum(0.5, 0.5, 0.0), ("0.001".into(), "0.999".into()));
        assert_eq!(split_sum(0.5, 0.5, 1.2), ("0.999".into(), "0.001".into()));
    }
}
