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
//! a rig) hangs under it. With `--units groups` a shape layer's parts are the units: they
//! are gathered under a branch named after their layer (the Lottie source says which
//! layer each part is of), which hangs under the layer's parent like a whole layer.
//!
//! The tree goes out flat, in pre-order, so the page can virtualise it: each entry has
//! its depth, the index after its subtree (`end`), and the shapes it selects.

use gmotion::scene::{Group, Node, Scene};
use gmotion_pipeline::LottieSource;
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

/// A Lottie layer that parts belong to: its index among the root layers, the name a rule
/// selects its parts by (its `nm` as a grammar name), and its `nm` as written when that
/// differs.
type PartLayer = (usize, String, Option<String>);

/// For each unit, the Lottie layer it is a part of, when the units are parts (`--units
/// groups`); `None` for a whole layer, an SVG unit, or when the scene's units are no
/// longer the source's (a group grammar's spatial rules made others).
fn part_layers(scene: &Scene, source: Option<&LottieSource>) -> Vec<Option<PartLayer>> {
    let mut out = vec![None; scene.shapes.len()];
    let Some(source) = source.filter(|s| s.units.len() == scene.shapes.len()) else {
        return out;
    };
    for (slot, unit) in out.iter_mut().zip(&source.units) {
        let layer = unit.layers.first().copied().filter(|_| unit.part.is_some());
        *slot = layer.and_then(|l| {
            let nm = source.document.layers.get(l)?.nm.trim();
            let name = gmotion::tagging::grammar_name(nm).unwrap_or_else(|| format!("layer_{l}"));
            let label = Some(nm.to_string()).filter(|n| !n.is_empty() && *n != name);
            Some((l, name, label))
        });
    }
    out
}

/// Gathers the top-level units that are parts of one Lottie layer under a branch named
/// after it, where the first of them was.
fn gather_parts(top: Vec<Item>, layer_of: &[Option<PartLayer>]) -> Vec<Item> {
    if layer_of.iter().all(Option::is_none) {
        return top;
    }
    let mut out: Vec<Item> = Vec::new();
    let mut branch_of: std::collections::HashMap<usize, usize> = Default::default();
    for item in top {
        let layer = item
            .shape
            .filter(|_| item.children.is_empty())
            .and_then(|i| layer_of.get(i).cloned().flatten());
        let Some((l, name, label)) = layer else {
            out.push(item);
            continue;
        };
        let at = *branch_of.entry(l).or_insert_with(|| {
            out.push(Item {
                name: Some(name),
                label,
                shape: None,
                children: Vec::new(),
            });
            out.len() - 1
        });
        out[at].children.push(item);
    }
    out
}

/// The unit `item` hangs under by parenting: a unit's parent, or for a branch of a
/// layer's parts the parent all its parts follow.
fn parent_of(item: &Item, up: &[Option<usize>]) -> Option<usize> {
    match item.shape {
        Some(i) if item.children.is_empty() => up.get(i).copied().flatten(),
        Some(_) => None,
        None => {
            let mut parts = item
                .children
                .iter()
                .map(|c| c.shape.and_then(|i| up.get(i).copied().flatten()));
            let first = parts.next().flatten()?;
            parts.all(|p| p == Some(first)).then_some(first)
        }
    }
}

/// Hangs the units (and layers of parts) that follow another unit under it (Lottie
/// parenting).
fn nest(top: Vec<Item>, up: &[Option<usize>]) -> Vec<Item> {
    if up.iter().all(Option::is_none) {
        return top;
    }
    // Only items at the top level are layers a parent can take; units inside named
    // groups stay where the groups put them.
    let mut kids: Vec<Vec<Item>> = (0..up.len()).map(|_| Vec::new()).collect();
    let mut roots = Vec::new();
    for item in top {
        match parent_of(&item, up) {
            Some(j) if j < kids.len() => kids[j].push(item),
            _ => roots.push(item),
        }
    }
    // Parenting has no cycles (`parents` cut them), so every list is taken once.
    fn grow(mut item: Item, kids: &mut [Vec<Item>]) -> Item {
        let children = std::mem::take(&mut item.children);
        item.children = children.into_iter().map(|c| grow(c, kids)).collect();
        if let Some(i) = item.shape {
            let mine = std::mem::take(&mut kids[i]);
            item.children
                .extend(mine.into_iter().map(|c| grow(c, kids)));
        }
        item
    }
    roots
        .into_iter()
        .map(|item| grow(item, &mut kids))
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
/// `source` is the Lottie document the scene came from, if it did (it says which layer
/// each part is of).
pub(crate) fn layers_json(scene: &Scene, source: Option<&LottieSource>) -> Value {
    let top = gather_parts(items(&scene.root), &part_layers(scene, source));
    let top = nest(top, &parents(scene));
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
        let layers = layers_json(&s, None);
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
        let layers = layers_json(&s, None);
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
        let layers = layers_json(&s, None);
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
        let layers = layers_json(&s, None);
        let shapes: Vec<(Option<u64>, u64)> = layers
            .as_array()
            .unwrap()
            .iter()
            .map(|e| (e["shape"].as_u64(), e["depth"].as_u64().unwrap()))
            .collect();
        assert_eq!(shapes, vec![(Some(0), 0), (Some(1), 1), (Some(2), 0)]);
        assert_eq!(layers[0]["shapes"], json!([0, 1]));
    }

    #[test]
    fn a_labelled_group_without_an_id_is_a_branch() {
        // Illustrator's `data-name` (or an Inkscape label) on a group with no id and no
        // transform: the group is kept with its name, its shapes under it.
        let s = scene(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100">
              <g data-name="Left Wing"><rect x="1" y="1" width="5" height="5"/><rect x="9" y="1" width="5" height="5"/></g>
              <g><rect x="20" y="1" width="5" height="5"/></g></svg>"#,
        );
        let layers = layers_json(&s, None);
        let rows: Vec<(Option<&str>, u64)> = layers
            .as_array()
            .unwrap()
            .iter()
            .map(|e| (e["name"].as_str(), e["depth"].as_u64().unwrap()))
            .collect();
        assert_eq!(
            rows,
            vec![(Some("Left Wing"), 0), (None, 1), (None, 1), (None, 0)]
        );
        assert_eq!(layers[0]["shapes"], json!([0, 1]));
    }

    /// A Lottie document of a null `Rig`, a shape layer `Car` parented to it drawing two
    /// top-level groups, and an unparented shape layer `Sun Disc` drawing one, imported with
    /// `--units groups` (each group a unit).
    fn parts_scene() -> (Scene, LottieSource) {
        let fixed = |v: Value| json!({"a": 0, "k": v});
        let ks = json!({"o": fixed(json!(100)), "r": fixed(json!(0)), "p": fixed(json!([50, 50, 0])),
            "a": fixed(json!([0, 0, 0])), "s": fixed(json!([100, 100, 100]))});
        let group = |nm: &str, x: f64| {
            json!({"ty": "gr", "nm": nm, "it": [
                {"ty": "rc", "d": 1, "p": fixed(json!([x, 0])), "s": fixed(json!([10, 10])), "r": fixed(json!(0))},
                {"ty": "fl", "c": fixed(json!([1, 0, 0, 1])), "o": fixed(json!(100)), "r": 1},
                {"ty": "tr", "p": fixed(json!([0, 0])), "a": fixed(json!([0, 0])), "s": fixed(json!([100, 100])),
                 "r": fixed(json!(0)), "o": fixed(json!(100))}]})
        };
        let layer = |nm: &str, ind: i64, parent: Option<i64>, shapes: Value| {
            let mut l = json!({"ddd": 0, "ty": 4, "nm": nm, "ind": ind, "ip": 0, "op": 60, "st": 0,
                "sr": 1, "ks": ks, "ao": 0, "bm": 0, "shapes": shapes});
            if let Some(p) = parent {
                l["parent"] = json!(p);
            }
            l
        };
        let doc = json!({"v": "5.7.0", "fr": 30, "ip": 0, "op": 60, "w": 100, "h": 100, "ddd": 0,
        "assets": [], "layers": [
            layer("Sun Disc", 3, None, json!([group("Disc", 20.0)])),
            {"ddd": 0, "ty": 3, "nm": "Rig", "ind": 1, "ip": 0, "op": 60, "st": 0, "sr": 1, "ks": ks, "ao": 0},
            layer("Car", 2, Some(1), json!([group("Body", 0.0), group("Wheel", -20.0)])),
        ]});
        let opts = gmotion_import_lottie::ImportOptions {
            units: gmotion_import_lottie::Units::Groups,
            ..Default::default()
        };
        let imported = gmotion_import_lottie::from_json(doc, "parts.json", &opts)
            .expect("the test document imports");
        (imported.scene, imported.source)
    }

    #[test]
    fn a_lottie_layers_parts_are_nested_under_it() {
        let (s, source) = parts_scene();
        let rows = |layers: &Value| -> Vec<(String, u64)> {
            layers
                .as_array()
                .unwrap()
                .iter()
                .map(|e| {
                    let name = match e["shape"].as_u64() {
                        Some(i) => s.shapes[i as usize].tag.clone(),
                        None => e["name"].as_str().unwrap().to_string(),
                    };
                    (name, e["depth"].as_u64().unwrap())
                })
                .collect()
        };
        let nested = layers_json(&s, Some(&source));
        let mut got = rows(&nested);
        // The rig's subtree: the Car layer under it.
        let rig = got.iter().position(|(n, _)| n == "Rig").unwrap();
        assert_eq!(
            got[rig..rig + 4],
            [("Rig", 0), ("Car", 1), ("Wheel", 2), ("Body", 2)].map(|(n, d)| (n.to_string(), d)),
            "{nested:#}"
        );
        got.drain(rig..rig + 4);
        assert_eq!(
            got,
            [("Sun_Disc", 0), ("Disc", 1)].map(|(n, d)| (n.to_string(), d)),
            "{nested:#}"
        );
        // The layer's name as written goes beside the name a rule selects it by.
        let sun = nested
            .as_array()
            .unwrap()
            .iter()
            .find(|e| e["name"] == "Sun_Disc")
            .unwrap();
        assert_eq!(sun["label"], "Sun Disc");
        // Selecting the layer selects its parts.
        let car = nested
            .as_array()
            .unwrap()
            .iter()
            .find(|e| e["name"] == "Car")
            .unwrap();
        assert_eq!(car["shapes"].as_array().unwrap().len(), 2);
        // Without the source (or with other units than its own) the parts stay flat.
        assert!(rows(&layers_json(&s, None)).iter().all(|(n, _)| n != "Car"));
    }
}
