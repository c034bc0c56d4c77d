//! `animate(morph, REF, OFFSET, TARGET)`: the target resolved (another shape of the scene,
//! drawn or kept out of the drawing, or SVG path data) and checked against the unit it
//! morphs, and the outlines a morph plays from and to.
//!
//! The target is held in the canvas's rest frame; compilation (`compile.rs`) places it
//! (`local`: its centroid on the shape's at the slice start) and carries it into each path's
//! own coordinates, where [`crate::morph::correspond`] matches it with the outline the shape
//! has then.

use kurbo::{Affine, BezPath, Point};

use crate::grammar::ast::{Expr, ExprKind, Span};
use crate::grammar::value::{Env, eval};
use crate::scene::{Node, Scene, Shape};

use super::EngineError;

/// What a morph needs of its shape and target, resolved for one shape.
#[derive(Debug)]
pub struct MorphSpec {
    /// `world` (the target where it is) or `local` (moved onto the shape's centroid).
    pub world: bool,
    /// The unit's paths in document order: each path's transform to the canvas and its
    /// drawn geometry in its own coordinates.
    pub art: Vec<(Affine, BezPath)>,
    /// The shape's centroid as drawn (canvas coordinates).
    pub centroid: Point,
    /// The target's paths in canvas coordinates, one per path of the unit.
    pub target: Vec<BezPath>,
}

/// The unit's paths, in document order, with their transforms to the canvas.
fn art(scene: &Scene, shape: &Shape) -> Vec<(Affine, BezPath)> {
    fn walk(node: &Node, abs: Affine, out: &mut Vec<(Affine, BezPath)>) {
        match node {
            Node::Path(p) => out.push((abs, p.path.clone())),
            Node::Group(g) => {
                let abs = abs * g.transform;
                for c in &g.children {
                    walk(c, abs, out);
                }
            }
            Node::Image(_) => {}
        }
    }
    let mut out = Vec::new();
    if let Some(node) = scene.root.node_at(&shape.node_path) {
        walk(node, shape.parent_transform, &mut out);
    }
    out
}

/// The morph of `shape` into the target `value` (`shape(TAG)`, `shape(TAG, ID)` or a
/// string of SVG path data), as a rule sets it.
pub fn spec(
    scene: &Scene,
    shape: &Shape,
    world: bool,
    value: &Expr,
    env: &mut dyn Env,
) -> Result<MorphSpec, EngineError> {
    let target = target(scene, value, env)?;
    let art = art(scene, shape);
    if art.len() != target.len() {
        return Err(EngineError::at(
            value.span,
            format!(
                "shape `{}` #{} has {} path{} but the morph target has {}: a unit morphs path by path into a target of as many paths",
                shape.tag,
                shape.id,
                art.len(),
                if art.len() == 1 { "" } else { "s" },
                target.len()
            ),
        ));
    }
    Ok(MorphSpec {
        world,
        art,
        centroid: shape.centroid,
        target,
    })
}

/// The target's paths in canvas coordinates.
fn target(scene: &Scene, value: &Expr, env: &mut dyn Env) -> Result<Vec<BezPath>, EngineError> {
    if let ExprKind::Call { name, args } = &value.kind
        && name == "shape"
    {
        return named_shape(scene, value.span, args, env);
    }
    let v = eval(value, env)?;
    let d = v.as_str().map_err(|_| {
        EngineError::at(
            value.span,
            "a morph target is `shape(TAG)`, `shape(TAG, ID)` or SVG path data in a string",
        )
    })?;
    let path = path_data(d).map_err(|(pos, what)| {
        EngineError::at(
            inside(value, pos),
            format!("the path data does not parse at character {pos}: {what}"),
        )
    })?;
    if path.elements().is_empty() {
        return Err(EngineError::at(value.span, "the path data is empty"));
    }
    Ok(vec![path])
}

/// The span of character `pos` (1-based) of a string literal written without escapes on
/// one line; the whole value otherwise.
fn inside(value: &Expr, pos: usize) -> Span {
    let ExprKind::Str(s) = &value.kind else {
        return value.span;
    };
    let plain = value.span.end.saturating_sub(value.span.start) == s.len() + 2 && !s.contains('\n');
    let Some((byte, ch)) = s.char_indices().nth(pos.saturating_sub(1)) else {
        return value.span;
    };
    if !plain {
        return value.span;
    }
    let start = value.span.start + 1 + byte;
    Span {
        line: value.span.line,
        col: value.span.col + 1 + (pos as u32 - 1),
        start,
        end: start + ch.len_utf8(),
    }
}

/// SVG path data as a path (arcs as cubics), or where (1-based character) and why it
/// does not parse.
pub fn path_data(d: &str) -> Result<BezPath, (usize, String)> {
    use svgtypes::{Error, SimplePathSegment as S};
    let mut path = BezPath::new();
    for seg in svgtypes::SimplifyingPathParser::from(d) {
        let seg = seg.map_err(|e| {
            let pos = match &e {
                Error::UnexpectedData(p)
                | Error::InvalidChar(_, p)
                | Error::InvalidString(_, p)
                | Error::InvalidNumber(p) => *p,
                _ => d.chars().count().max(1),
            };
            (pos, e.to_string())
        })?;
        match seg {
            S::MoveTo { x, y } => path.move_to((x, y)),
            S::LineTo { x, y } => path.line_to((x, y)),
            S::CurveTo {
                x1,
                y1,
                x2,
                y2,
                x,
                y,
            } => path.curve_to((x1, y1), (x2, y2), (x, y)),
            S::Quadratic { x1, y1, x, y } => path.quad_to((x1, y1), (x, y)),
            S::ClosePath => path.close_path(),
        }
    }
    Ok(path)
}

/// `shape(TAG)` or `shape(TAG, ID)`: the shapes answering to TAG, drawn ones first then
/// key shapes, each in document order; ID picks one of them (from 0), and is needed when
/// there are several.
fn named_shape(
    scene: &Scene,
    span: Span,
    args: &[crate::grammar::ast::Arg],
    env: &mut dyn Env,
) -> Result<Vec<BezPath>, EngineError> {
    let usage = "`shape` takes a tag and optionally an id: `shape(TAG)` or `shape(TAG, ID)`";
    let (tag_arg, id_arg) = match args {
        [t] if t.name.is_none() => (t, None),
        [t, i] if t.name.is_none() && i.name.is_none() => (t, Some(i)),
        _ => return Err(EngineError::at(span, usage)),
    };
    let ExprKind::Ident(tag) = &tag_arg.value.kind else {
        return Err(EngineError::at(tag_arg.span, usage));
    };
    let drawn = scene
        .shapes
        .iter()
        .filter(|s| !s.rig && s.tags().any(|t| t == tag))
        .map(Candidate::Drawn);
    let keys = scene
        .keys
        .iter()
        .filter(|k| k.tags().any(|t| t == tag))
        .map(Candidate::Key);
    let found: Vec<Candidate> = drawn.chain(keys).collect();
    if found.is_empty() {
        let mut known: Vec<&str> = scene
            .shapes
            .iter()
            .map(|s| s.tag.as_str())
            .chain(scene.keys.iter().map(|k| k.tag.as_str()))
            .collect();
        known.sort_unstable();
        known.dedup();
        let hint = crate::grammar::diagnostics::did_you_mean(tag, known.iter().copied())
            .map(|m| format!(" (did you mean `{m}`?)"))
            .unwrap_or_default();
        let mut e = EngineError::at(
            tag_arg.span,
            format!("no shape answers to `{tag}`, drawn or kept out of the drawing{hint}"),
        );
        e.notes
            .push(format!("the scene's tags: {}", known.join(", ")));
        return Err(e);
    }
    let pick = match id_arg {
        None if found.len() > 1 => {
            return Err(EngineError::at(
                tag_arg.span,
                format!(
                    "{} shapes answer to `{tag}`; say which with `shape({tag}, ID)`, ID from 0 to {}",
                    found.len(),
                    found.len() - 1
                ),
            ));
        }
        None => &found[0],
        Some(a) => {
            let x = eval(&a.value, env)?
                .as_num()
                .map_err(|m| EngineError::from(m.at(a.span)))?;
            if !(x >= 0.0 && x.fract() == 0.0 && (x as usize) < found.len()) {
                return Err(EngineError::at(
                    a.span,
                    format!(
                        "{} shape{} answer{} to `{tag}`: the id is a whole number from 0 to {}, found {x}",
                        found.len(),
                        if found.len() == 1 { "" } else { "s" },
                        if found.len() == 1 { "s" } else { "" },
                        found.len() - 1
                    ),
                ));
            }
            &found[x as usize]
        }
    };
    Ok(match pick {
        Candidate::Drawn(s) => art(scene, s).into_iter().map(|(abs, p)| abs * p).collect(),
        Candidate::Key(k) => k.paths.clone(),
    })
}

enum Candidate<'a> {
    Drawn(&'a Shape),
    Key(&'a crate::scene::KeyShape),
}

/// The target placed by the spec's reference (`local`: its centroid on `centroid`, the
/// shape's at the slice start) and carried into each path's own coordinates.
pub fn placed(spec: &MorphSpec, centroid: Point) -> Vec<BezPath> {
    let shift = if spec.world {
        Affine::IDENTITY
    } else {
        let c =
            crate::morph::centroid(&spec.target).unwrap_or_else(|| bounds(&spec.target).center());
        Affine::translate(centroid - c)
    };
    spec.art
        .iter()
        .zip(&spec.target)
        .map(|((abs, _), target)| {
            let back = if abs.determinant().abs() > 1e-12 {
                abs.inverse()
            } else {
                Affine::IDENTITY
            };
            (back * shift) * target.clone()
        })
        .collect()
}

/// The centroid of outlines given in their paths' own coordinates (carried to the canvas).
pub fn centroid_of(spec: &MorphSpec, outlines: &[BezPath]) -> Point {
    let canvas: Vec<BezPath> = spec
        .art
        .iter()
        .zip(outlines)
        .map(|((abs, _), p)| *abs * p.clone())
        .collect();
    crate::morph::centroid(&canvas).unwrap_or_else(|| bounds(&canvas).center())
}

fn bounds(paths: &[BezPath]) -> kurbo::Rect {
    paths
        .iter()
        .map(kurbo::Shape::bounding_box)
        .reduce(|a, b| a.union(b))
        .unwrap_or(kurbo::Rect::ZERO)
}
