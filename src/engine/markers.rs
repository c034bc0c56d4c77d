//! Markers: the grammar's phases as named spans of the timeline (`markers in hold out`), what
//! a web page plays by name (lottie-web's `goToAndPlay('idle', true)`, dotlottie-web's
//! `setMarker`).
//!
//! A slice counts as tag `T` when it carries `T` or came from a slice that did: an `animate`
//! renames the slice it animates, and a `timesplit` cuts it into pieces, yet the pieces of
//! `in` are still the way in. Which tags come from which is read from the rules (a rule on
//! `a` turns `a` into its outputs, and `inv_a` into their inversions), so a tag that rules
//! on different tags both write counts as each of them. A marker spans from the earliest
//! start to the latest end of the slices that count as its tag, over every shape.

use std::collections::{HashMap, HashSet};

use crate::grammar::ast::Span;

use super::EngineError;
use super::expand::Slice;
use super::rules::Program;

/// A named span of the animation, in seconds.
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    /// The slice tag it is named after.
    pub name: String,
    /// When the first slice counting as the tag starts.
    pub start: f64,
    /// When the last one ends.
    pub end: f64,
}

/// A final slice's tag (its id and whether it is inverted) and its span: what one shape
/// adds to the markers.
pub type SliceSpan = (u32, bool, f64, f64);

/// The spans of `timeline`'s slices, one per tag (the earliest start, the latest end).
pub fn spans_of(timeline: &[Slice]) -> Vec<SliceSpan> {
    let mut spans: Vec<SliceSpan> = Vec::new();
    for s in timeline {
        let (t0, t1) = (s.t0, s.t0 + s.dur);
        match spans
            .iter_mut()
            .find(|(tag, inv, ..)| *tag == s.tag && *inv == s.inverted)
        {
            Some(span) => {
                span.2 = span.2.min(t0);
                span.3 = span.3.max(t1);
            }
            None => spans.push((s.tag, s.inverted, t0, t1)),
        }
    }
    spans
}

/// The markers `names` asks for, from every shape's `spans` (slice tag ids index
/// `slice_tags`) and the rules of `program`. A name that no slice counts as is an error at
/// the directive (a name without a span came from the command line's `--markers`), naming
/// the slice tags there are.
pub fn collect(
    names: &[(String, Option<Span>)],
    slice_tags: &[String],
    program: &Program,
    spans: impl IntoIterator<Item = SliceSpan>,
) -> Result<Vec<Marker>, EngineError> {
    // Where each tag (name, inverted) leads in one rule application.
    let mut leads: HashMap<(&str, bool), Vec<(&str, bool)>> = HashMap::new();
    for rule in &program.rules {
        for input in &rule.slice_tags {
            for out in &rule.outputs {
                let name = out.name.as_str();
                leads
                    .entry((input.as_str(), false))
                    .or_default()
                    .push((name, out.inverted));
                leads
                    .entry((input.as_str(), true))
                    .or_default()
                    .push((name, !out.inverted));
            }
        }
    }
    // The span of each final tag over every shape.
    let mut total: HashMap<(u32, bool), (f64, f64)> = HashMap::new();
    for (tag, inv, t0, t1) in spans {
        let e = total.entry((tag, inv)).or_insert((t0, t1));
        e.0 = e.0.min(t0);
        e.1 = e.1.max(t1);
    }
    let mut markers = Vec::with_capacity(names.len());
    for (name, span) in names {
        let start = match name.strip_prefix("inv_") {
            Some(base) => (base, true),
            None => (name.as_str(), false),
        };
        // Every tag that comes from `name`, itself included.
        let mut reached: HashSet<(&str, bool)> = HashSet::from([start]);
        let mut stack = vec![start];
        while let Some(t) = stack.pop() {
            for &next in leads.get(&t).into_iter().flatten() {
                if reached.insert(next) {
                    stack.push(next);
                }
            }
        }
        let covered = total
            .iter()
            .filter(|((tag, inv), _)| {
                slice_tags
                    .get(*tag as usize)
                    .is_some_and(|t| reached.contains(&(t.as_str(), *inv)))
            })
            .map(|(_, &span)| span)
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)));
        let Some((start, end)) = covered else {
            let mut known: Vec<String> = total
                .keys()
                .filter_map(|(tag, inv)| {
                    let t = slice_tags.get(*tag as usize)?;
                    Some(if *inv { format!("inv_{t}") } else { t.clone() })
                })
                .collect();
            known.sort();
            known.dedup();
            let what =
                format!("marker `{name}`: no slice carries this tag or comes from one that does");
            let mut e = match span {
                Some(span) => EngineError::at(*span, what),
                None => EngineError::general(format!("--markers: {what}")),
            };
            e.notes.push(format!(
                "the slices end up tagged {}",
                known
                    .iter()
                    .map(|t| format!("`{t}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
            return Err(e);
        };
        markers.push(Marker {
            name: name.clone(),
            start,
            end,
        });
    }
    Ok(markers)
}
