//! The arguments of `animate(follow, REF, OFFSET, PATH, orient=…)` checked: the path (SVG
//! path data, errors located inside the string, or another shape's outline) measured into
//! a [`Route`], and the `orient` option, which no other type takes.

use std::sync::Arc;

use kurbo::BezPath;

use crate::grammar::ast::{Arg, Expr, ExprKind, Span};
use crate::grammar::value::Value;
use crate::motion::follow::Route;
use crate::scene::Scene;

use super::EngineError;
use super::rules::AnimType;

/// Whether a rule's `orient` argument asks the shape to turn with its path: `auto` yes,
/// `none` (the default) no; an error on any other type than `follow`.
pub fn orient(kind: AnimType, arg: Option<&Arg>) -> Result<bool, EngineError> {
    let Some(a) = arg else { return Ok(false) };
    if kind != AnimType::Follow {
        return Err(EngineError::at(
            a.span,
            "`orient` is an option of `follow` only (a shape turning with its path)",
        ));
    }
    match &a.value.kind {
        ExprKind::Ident(s) | ExprKind::Str(s) if s == "auto" => Ok(true),
        ExprKind::Ident(s) | ExprKind::Str(s) if s == "none" => Ok(false),
        _ => Err(EngineError::at(a.span, "orient is `auto` or `none`")),
    }
}

/// The route a `follow` rule's value names: path data or `shape(TAG[, ID])`.
pub fn route(scene: &Scene, value: &Expr, v: &Value) -> Result<Arc<Route>, EngineError> {
    let path = match super::target::shape_outline(scene, v, value.span) {
        Some(outline) => outline?,
        None => {
            let d = v.as_str().map_err(|m| {
                EngineError::at(
                    value.span,
                    format!("{m}; `follow` takes SVG path data or `shape(TAG)`"),
                )
            })?;
            path_data(d, value)?
        }
    };
    Route::new(&path)
        .map(Arc::new)
        .ok_or_else(|| EngineError::at(value.span, "the path has no length to travel"))
}

/// Parses SVG path data (arcs become curves); an error points at the character inside the
/// string literal where parsing stopped.
pub fn path_data(d: &str, value: &Expr) -> Result<BezPath, EngineError> {
    use svgtypes::{Error, SimplePathSegment as S, SimplifyingPathParser};
    let mut out = BezPath::new();
    for seg in SimplifyingPathParser::from(d) {
        let seg = seg.map_err(|e| {
            // svgtypes counts characters from 1; the end of the data when it ran out.
            let at = match &e {
                Error::UnexpectedData(p)
                | Error::InvalidChar(_, p)
                | Error::InvalidString(_, p)
                | Error::InvalidNumber(p) => p.saturating_sub(1),
                _ => d.chars().count(),
            };
            EngineError::at(inside(value, d, at), format!("invalid SVG path data: {e}"))
        })?;
        match seg {
            S::MoveTo { x, y } => out.move_to((x, y)),
            S::LineTo { x, y } => out.line_to((x, y)),
            S::CurveTo {
                x1,
                y1,
                x2,
                y2,
                x,
                y,
            } => out.curve_to((x1, y1), (x2, y2), (x, y)),
            S::Quadratic { x1, y1, x, y } => out.quad_to((x1, y1), (x, y)),
            S::ClosePath => out.close_path(),
        }
    }
    Ok(out)
}

/// The span of character `at` of the string `d` that the literal `value` holds (its
/// opening quote at the span's start); the whole value when it is not a literal on one
/// line.
fn inside(value: &Expr, d: &str, at: usize) -> Span {
    let literal = matches!(&value.kind, ExprKind::Str(s) if s == d);
    let simple = !d.contains(['\n', '\\', '"']);
    if !literal || !simple {
        return value.span;
    }
    let offset: usize = d.chars().take(at).map(char::len_utf8).sum();
    let width = d[offset..].chars().next().map_or(0, char::len_utf8);
    Span {
        line: value.span.line,
        col: value.span.col + 1 + at as u32,
        start: value.span.start + 1 + offset,
        end: value.span.start + 1 + offset + width,
    }
}
