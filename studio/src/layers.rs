//! The layer tree the page's shape list shows (`GET /api/layers`): the scene's own
//! hierarchy, with the names the importer kept.
//!
//! An SVG scene keeps its groups in the node tree with their ids (synthetic ids dropped)
//! and labels (`inkscape:label`, `data-name`), so a named group holding units becomes a
//! branch and an unnamed one is looked through (its units join the branch around it, as
//! a designer never named it). A Lottie scene's
//! units are its layers, flat in the tree (each drawn at its world transform), and its
//! hierarchy is the parenting the importer records as the names a unit follows
//! ([`Shape::inherited`]): a unit whose nearest parent layer is another unit (a drawing or
//! a rig) hangs under it.
//!
//! The tree goes out flat, in pre-order, so the page can virtualise it: each entry has
//! its depth, the index after its subtree (`end`), and the shapes it selects.

use gmotion::scene::{Group, Node, Scene};
use serde_json::{Value, json};

/// A branch or leaf before it is flattened.
struct Item {
    /// The group's id (its label when it has none), or `None` for a unit.
    name: Option<String>,
    /// The name the designer gave the group besides its id: its label, or the name an
    /// escaped id spells.
    label: Option<String>,
    /// The unit this item is (a Lottie parent layer is both a unit and a branch).
    shape: Option<usize>,
    children: Vec<Item>,
}

/// The items under `g`: units as leaves, named groups holding units as branches, unnamed
/// groups looked through.
fn items(g: &Group) -> Vec<Item> {
    let mut out = Vec::new();
    for child in &g.children {
        if let Some(unit) = child.unit() {
            out.push(Item {
                name: None,
                label: None,
                shape: Some(unit),
                children: Vec::new(),
            });
            continue;
        }
        let Node::Group(inner) = child else { continue };
        let under = items(inner);
        if under.is_empty() {
            continue;
        }
        let label = inner.label.trim();
        if inner.id.is_empty() && label.is_empty() {
            out.extend(under);
        } else {
            let name = if inner.id.is_empty() {
                label
            } else {
                &inner.id
            };
            // Illustrator escapes a layer's name into its id (`Layer_x0020_1`): the name
            // as the designer wrote it goes beside the id.
            let label = Some(label.to_string())
                .filter(|l| !l.is_empty())
                .or_else(|| gmotion::tagging::unescape_id(&inner.id))
                .filter(|l| l != name);
            out.push(Item {
                name: Some(name.to_string()),
                label,
                shape: None,
                children: under,
            });
        }
    }
    out
}

/// The unit each unit hangs under by parenting: the first name it follows (nearest parent
/// first) that is the tag of exactly one other unit. `None` for a unit that follows no
/// unit (every SVG unit).
fn parents(scene: &Scene) -> Vec<Option<usize>> {
    let mut by_tag: std::collections::HashMap<&str, Option<usize>> = Default::default();
    for (i, s) in scene.shapes.iter().enumerate() {
        by_tag
            .entry(s.tag.as_str())
            .and_modify(|e| *e = None)
            .or_insert(Some(i));
    }
    let mut up: Vec<Option<usize>> = scene
        .shapes
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let own = s.aliases.len().saturating_sub(s.inherited);
            s.aliases[own..]
                .iter()
                .find_map(|name| by_tag.get(name.as_str()).copied().flatten())
                .filter(|&j| j != i)
        })
        .collect();
    // Parenting has no cycles, but tags are names: a chain that comes back to where it
    // started is cut there rather than looping.
    for i in 0..up.len() {
        let mut at = up[i];
        let mut hops = 0;
        while let Some(j) = at {
            if j == i || hops > up.len() {
                up[i] = None;
                break;
            }
            at = up[j];
            hops += 1;
        }
    }
    up
}

/// Hangs the units that follow another unit under it (Lottie parenting).
fn nest(top: Vec<Item>, up: &[Option<usize>]) -> Vec<Item> {
    if up.iter().all(Option::is_none) {
        return top;
    }
    // Only units at the top level are layers a parent can take; units inside named
    // groups stay where the groups put them.
    let mut kids: Vec<Vec<usize>> = vec![Vec::new(); up.len()];
    let mut roots = Vec::new();
    for item in top {
        match item.shape {
            Some(i) if item.children.is_empty() && up.get(i).copied().flatten().is_some() => {
                kids[up[i].unwrap_or(i)].push(i);
            }
            _ => roots.push(item),
        }
    }
    fn grow(i: usize, kids: &[Vec<usize>]) -> Item {
        Item {
            name: None,
            label: None,
            shape: Some(i),
            children: kids[i].iter().map(|&k| grow(k, kids)).collect(),
        }
    }
    roots
        .into_iter()
        .map(|item| match item.shape {
            Some(i) if item.children.is_empty() => grow(i, &kids),
            _ => item,
        })
        .collect()
}

/// Writes `item` and its subtree at `depth` into `out` in pre-order; returns the shapes
/// it selects.
fn flatten(item: &Item, depth: usize, out: &mut Vec<Value>) -> Vec<usize> {
    let at = out.len();
    out.push(Value::Null);
    let mut shapes: Vec<usize> = item.shape.into_iter().collect();
    for child in &item.children {
        shapes.extend(flatten(child, depth + 1, out));
    }
    shapes.sort_unstable();
    out[at] = json!({
        "name": item.name,
        "label": item.label,
        "shape": item.shape,
        "depth": depth,
        "end": out.len(),
        "shapes": if item.children.is_empty() { Value::Null } else { json!(shapes) },
    });
    shapes
}

/// `scene`'s layer tree as `[{name, label, shape, depth, end, shapes}]` in pre-order (see
/// `docs/studio.md`, "The API"): `name` a group's id (its label without one; `null` for
/// a unit), `label` the designer's other name for it (an Inkscape label, a `data-name`,
/// the name an escaped id spells; `null` without one), `shape` the
/// unit's index in `/api/state`'s `shapes` (`null` for a group), `end` the index after
/// the entry's subtree, `shapes` every unit the entry selects (`null` for a leaf).
pub(crate) fn layers_json(scene: &Scene) -> Value {
    let top = nest(items(&scene.root), &parents(scene));
    let mut out = Vec::new();
    let mut seen = vec![false; scene.shapes.len()];
    for item in &top {
        for s in flatten(item, 0, &mut out) {
            if let Some(x) = seen.get_mut(s) {
                *x = true;
            }
        }
    }
    // Every unit is reachable: one the tree walk did not meet (a group grammar's piece
    // with no node of its own) is listed at the top level.
    for (i, _) in seen.iter().enumerate().filter(|(_, s)| !**s) {
        let leaf = Item {
            name: None,
            label: None,
            shape: Some(i),
            children: Vec::new(),
        };
        flatten(&leaf, 0, &mut out);
    }
    Value::Array(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(svg: &str) -> Scene {
        gmotion_import_svg::parse(svg, "test.svg", &Default::default())
            .expect("the test SVG imports")
            .scene
    }

    #[test]
    fn named_groups_are_branches_and_unnamed_ones_are_looked_through() {
        let s = scene(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">
              <g id="face"><g><circle id="eye_l" cx="10" cy="10" r="5"/></g>
                <circle id="eye_r" cx="30" cy="10" r="5"/>
                <g id="mouth"><rect x="10" y="40" width="20" height="5"/></g></g>
              <rect id="floor" x="0" y="90" width="100" height="10"/></svg>"#,
        );
        let layers = layers_json(&s);
        let rows: Vec<(Option<&str>, Option<u64>, u64, u64)> = layers
            .as_array()
            .unwrap()
            .iter()
            .map(|e| {
                (
                    e["name"].as_str(),
                    e["shape"].as_u64(),
                    e["depth"].as_u64().unwrap(),
                    e["end"].as_u64().unwrap(),
                )
            })
            .collect();
        assert_eq!(
            rows,
            vec![
                (Some("face"), None, 0, 5),
                (None, Some(0), 1, 2),
                (None, Some(1), 1, 3),
                (Some("mouth"), None, 1, 5),
                (None, Some(2), 2, 5),
                (None, Some(3), 0, 6),
            ]
        );
        assert_eq!(layers[0]["shapes"], json!([0, 1, 2]));
        assert!(layers[0]["label"].is_null());
        assert_eq!(layers[3]["shapes"], json!([2]));
        assert!(layers[1]["shapes"].is_null());
    }

    #[test]
    fn an_escaped_id_gives_the_name_it_spells() {
        let s = scene(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">
              <g id="Layer_x0020_1"><rect x="1" y="1" width="5" height="5"/></g></svg>"#,
        );
        let layers = layers_json(&s);
        assert_eq!(layers[0]["name"], "Layer_x0020_1");
        assert_eq!(layers[0]["label"], "Layer 1");
    }

    #[test]
    fn labels_name_groups_beside_their_ids() {
        let s = scene(
            r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="100" height="100">
              <g id="layer1" inkscape:label="Background" inkscape:groupmode="layer"><rect x="1" y="1" width="5" height="5"/></g>
              <g id="Left_Arm" data-name="Left Arm"><rect x="10" y="1" width="5" height="5"/></g>
              <g id="plain"><rect x="20" y="1" width="5" height="5"/></g></svg>"#,
        );
        let layers = layers_json(&s);
        let named: Vec<(&str, Option<&str>)> = layers
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|e| Some((e["name"].as_str()?, e["label"].as_str())))
            .collect();
        assert_eq!(
            named,
            vec![
                ("layer1", Some("Background")),
                ("Left_Arm", Some("Left Arm")),
                ("plain", None),
            ]
        );
    }

    #[test]
    fn a_unit_following_another_hangs_under_it() {
        let mut s = scene(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">
              <rect data-tag="arm" x="0" y="0" width="10" height="10"/>
              <rect data-tag="hand" x="20" y="0" width="10" height="10"/>
              <rect data-tag="leg" x="40" y="0" width="10" height="10"/></svg>"#,
        );
        // As the Lottie importer records parenting: the hand follows the arm.
        s.shapes[1].aliases.push("arm".into());
        s.shapes[1].inherited = 1;
        let layers = layers_json(&s);
        let shapes: Vec<(Option<u64>, u64)> = layers
            .as_array()
            .unwrap()
            .iter()
            .map(|e| (e["shape"].as_u64(), e["depth"].as_u64().unwrap()))
            .collect();
        assert_eq!(shapes, vec![(Some(0), 0), (Some(1), 1), (Some(2), 0)]);
        assert_eq!(layers[0]["shapes"], json!([0, 1]));
    }
}
