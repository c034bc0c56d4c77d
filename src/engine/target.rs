//! `shape(TAG)` and `shape(TAG, ID)`: another shape of the scene named as an operand (the
//! path a `follow` travels), read for its outline in canvas coordinates.

use kurbo::{Affine, BezPath};

use crate::grammar::ast::Span;
use crate::grammar::value::Value;
use crate::scene::{Node, Scene};

use super::EngineError;

/// If `v` is a `shape(…)` call: the outline of the one shape it names, in canvas
/// coordinates (every path of the unit, subpaths in paint order). `None` for any other
/// value.
pub fn shape_outline(scene: &Scene, v: &Value, span: Span) -> Option<Result<BezPath, EngineError>> {
    let Value::Call { name, args } = v else {
        return None;
    };
    if name != "shape" {
        return None;
    }
    Some(outline(scene, args, span))
}

fn outline(scene: &Scene, args: &[Value], span: Span) -> Result<BezPath, EngineError> {
    let usage = "`shape(TAG)` or `shape(TAG, ID)` names a shape by its tag and id";
    let (tag, id) = match args {
        [Value::Keyword(t) | Value::Str(t)] => (t.as_str(), None),
        [Value::Keyword(t) | Value::Str(t), Value::Num(i)] if *i >= 0.0 && i.fract() == 0.0 => {
            (t.as_str(), Some(*i as usize))
        }
        _ => return Err(EngineError::at(span, usage)),
    };
    let found: Vec<usize> = scene
        .shapes
        .iter()
        .enumerate()
        .filter(|(_, s)| s.tags().any(|t| t == tag) && id.is_none_or(|i| s.id == i))
        .map(|(k, _)| k)
        .collect();
    let k = match found.as_slice() {
        [k] => *k,
        [] => {
            let tags = scene.shapes.iter().flat_map(|s| s.tags());
            let what = match id {
                Some(i) => format!("`{tag}` #{i}"),
                None => format!("`{tag}`"),
            };
            return Err(EngineError::at(span, format!("no shape is tagged {what}"))
                .suggesting(Some(tag), tags));
        }
        many => {
            return Err(EngineError::at(
                span,
                format!(
                    "{} shapes are tagged `{tag}`; name one with `shape({tag}, ID)`",
                    many.len()
                ),
            ));
        }
    };
    let mut out = BezPath::new();
    if let Some(node) = scene.unit_node(k) {
        collect(node, scene.shapes[k].parent_transform, &mut out);
    }
    Ok(out)
}

fn collect(node: &Node, to_canvas: Affine, out: &mut BezPath) {
    match node {
        Node::Path(p) => out.extend((to_canvas * p.path.clone()).elements().iter().copied()),
        Node::Group(g) => {
            let m = to_canvas * g.transform;
            for c in &g.children {
                collect(c, m, out);
            }
        }
        Node::Image(_) => {}
    }
}
