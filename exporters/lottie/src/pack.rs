//! Packing (`--pack`): runs of plain shape layers written as one shape layer, each former
//! layer a group of the same name inside it.
//!
//! A web player pays for every layer on every frame whether or not it moves: lottie-web's
//! canvas renderer saves and restores the context, sets its transform and alpha and walks
//! its shape tree layer by layer. Measured with the playback benchmark
//! (`benches/playback/playback.mjs`, docs/performance.md): the gallery's statue, 960 one-unit
//! layers, draws a frame in lottie-web's canvas renderer in four fifths of the time once
//! packed (30 → 24 ms), with the same pixels. The price is the layer tree: After Effects (and gmotion, reading the file back) sees one
//! layer where there were many, so packing is asked for, never the default.
//!
//! A layer is plain when it is a shape layer with nothing of its own a group cannot hold:
//! an identity, static transform; no mask, matte, effect, blend mode, 3D, time stretch or
//! slot on the layer; no layer naming it as parent or matte parent. A run is consecutive
//! plain layers with the same parent, in and out points and start time, at most
//! [`MAX_RUN`] of them; its groups keep
//! the paint order (a layer's first shape is drawn over the next, as the layer before is
//! drawn over the one after), so the packed document draws what the layered one drew.

use serde_json::{Map, Value as Json, json};

/// The most layers packed into one. lottie-web's load time grows with the square of a
/// layer's groups (it looks each one up in a list): the intersections example packed into
/// one layer of 8217 groups took 22 s (canvas) and 35 s (svg) to load instead of 3 and
/// 5 s, while in layers of 64 groups it loads as fast as unpacked and still draws a frame
/// in a little over half the time.
const MAX_RUN: usize = 64;

/// Packs the document's layer list and every precomposition's, in place; returns how many
/// layers were folded into another.
pub fn pack(doc: &mut Json) -> usize {
    let mut folded = 0;
    if let Some(layers) = doc.get_mut("layers").and_then(Json::as_array_mut) {
        folded += pack_list(layers);
    }
    if let Some(assets) = doc.get_mut("assets").and_then(Json::as_array_mut) {
        for asset in assets {
            if let Some(layers) = asset.get_mut("layers").and_then(Json::as_array_mut) {
                folded += pack_list(layers);
            }
        }
    }
    folded
}

/// Packs one composition's layers.
fn pack_list(layers: &mut Vec<Json>) -> usize {
    // Layers another names (as parent or matte parent) keep their place and index.
    let named: Vec<f64> = layers
        .iter()
        .flat_map(|l| ["parent", "tp"].map(|key| l.get(key).and_then(Json::as_f64)))
        .flatten()
        .collect();
    let before = layers.len();
    let mut out: Vec<Json> = Vec::with_capacity(before);
    // The run being gathered: its key and its layers.
    let mut run: Option<(RunKey, Vec<Json>)> = None;
    for layer in layers.drain(..) {
        let key = plain(&layer, &named);
        match (&mut run, key) {
            (Some((current, members)), Some(key)) if *current == key && members.len() < MAX_RUN => {
                members.push(layer)
            }
            (_, key) => {
                if let Some((_, members)) = run.take() {
                    out.push(fold(members));
                }
                match key {
                    Some(key) => run = Some((key, vec![layer])),
                    None => out.push(layer),
                }
            }
        }
    }
    if let Some((_, members)) = run {
        out.push(fold(members));
    }
    *layers = out;
    before - layers.len()
}

/// What layers of one run share: parent, in point, out point, start time.
#[derive(PartialEq)]
struct RunKey([Option<String>; 4]);

/// The run key of `layer` if it is plain (see the module's comment), `None` otherwise.
fn plain(layer: &Json, named: &[f64]) -> Option<RunKey> {
    let l = layer.as_object()?;
    if l.get("ty").and_then(Json::as_f64) != Some(4.0) || !l.get("shapes")?.is_array() {
        return None;
    }
    if let Some(ind) = l.get("ind").and_then(Json::as_f64)
        && named.contains(&ind)
    {
        return None;
    }
    // Fields a group cannot take over, unless they hold their default.
    let default = |key: &str, value: f64| l.get(key).is_none_or(|v| v.as_f64() == Some(value));
    let known = [
        "ty", "nm", "ind", "parent", "ks", "shapes", "ip", "op", "st", "bm", "ddd", "sr", "ao",
        "hasMask", "mn",
    ];
    let layer_own = l.keys().all(|k| known.contains(&k.as_str()))
        && default("bm", 0.0)
        && default("ddd", 0.0)
        && default("sr", 1.0)
        && default("ao", 0.0)
        && l.get("hasMask").is_none_or(|m| m == &Json::Bool(false));
    if !(layer_own && identity(l.get("ks")?.as_object()?)) {
        return None;
    }
    let text = |key: &str| l.get(key).map(Json::to_string);
    Some(RunKey([text("parent"), text("ip"), text("op"), text("st")]))
}

/// Whether a layer transform is the identity and static, with no slot: no rotation, skew
/// or scale, full opacity, and the position on the anchor point (After Effects writes
/// both as the layer's centre).
fn identity(ks: &Map<String, Json>) -> bool {
    // A static property's value, if the property holds nothing else (`ix` is After
    // Effects' property index, of no consequence to a player).
    let value = |prop: &Json| -> Option<Json> {
        let p = prop.as_object()?;
        let static_ = p.keys().all(|k| k == "a" || k == "k" || k == "ix")
            && p.get("a").and_then(Json::as_f64) != Some(1.0);
        static_.then(|| p.get("k").cloned()).flatten()
    };
    // Every component of a number or list one of `neutral`.
    let all = |v: &Json, neutral: &[f64]| match v {
        Json::Array(xs) => xs
            .iter()
            .all(|x| x.as_f64().is_some_and(|x| neutral.contains(&x))),
        v => v.as_f64().is_some_and(|x| neutral.contains(&x)),
    };
    let point = |key: &str| -> Option<[f64; 3]> {
        let Some(prop) = ks.get(key) else {
            return Some([0.0; 3]);
        };
        let v = value(prop)?;
        let xs = v.as_array()?;
        let at = |i: usize| xs.get(i).map_or(Some(0.0), Json::as_f64);
        Some([at(0)?, at(1)?, at(2)?])
    };
    let on_anchor = matches!((point("p"), point("a")), (Some(p), Some(a)) if p == a);
    on_anchor
        && ks.iter().all(|(key, prop)| {
            let neutral: &[f64] = match key.as_str() {
                "a" | "p" => return true,
                "sk" | "sa" | "r" => &[0.0],
                // A 3D scale's third component is 100 too.
                "s" | "o" => &[100.0],
                _ => return false,
            };
            value(prop).is_some_and(|v| all(&v, neutral))
        })
}

/// One layer holding `members` in order: the first keeps its fields, the rest lend their
/// shapes, each member's shapes one group named as the member was.
fn fold(mut members: Vec<Json>) -> Json {
    if members.len() == 1 {
        return members.pop().expect("a run has a layer");
    }
    let names: Vec<String> = members
        .iter()
        .map(|m| m.get("nm").and_then(Json::as_str).unwrap_or("").to_string())
        .collect();
    let mut shapes = Vec::new();
    for (member, name) in members.iter_mut().zip(&names) {
        let own = match member.get_mut("shapes").map(Json::take) {
            Some(Json::Array(own)) => own,
            _ => Vec::new(),
        };
        shapes.push(as_group(own, name));
    }
    let mut layer = members.swap_remove(0);
    let last = names.last().map(String::as_str).unwrap_or("");
    layer["nm"] = Json::from(format!("{} … {last}", names[0]));
    layer["shapes"] = Json::Array(shapes);
    layer
}

/// A layer's shapes as one group named `name`: the group they already are when the layer
/// holds just that, else a new one with an identity transform.
fn as_group(mut shapes: Vec<Json>, name: &str) -> Json {
    if let [only] = shapes.as_mut_slice()
        && only.get("ty").and_then(Json::as_str) == Some("gr")
        && only.get("nm").and_then(Json::as_str) == Some(name)
    {
        return only.take();
    }
    shapes.push(json!({
        "ty": "tr",
        "a": {"a": 0, "k": [0, 0]},
        "p": {"a": 0, "k": [0, 0]},
        "s": {"a": 0, "k": [100, 100]},
        "r": {"a": 0, "k": 0},
        "o": {"a": 0, "k": 100},
    }));
    json!({"ty": "gr", "nm": name, "it": shapes})
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layer(ind: u32, nm: &str) -> Json {
        json!({
            "ty": 4, "nm": nm, "ind": ind,
            "ks": {"a": {"a": 0, "k": [0, 0]}, "p": {"a": 0, "k": [0, 0]},
                   "s": {"a": 0, "k": [100, 100]}, "r": {"a": 0, "k": 0}, "o": {"a": 0, "k": 100}},
            "shapes": [{"ty": "gr", "nm": nm, "it": [{"ty": "tr"}]}],
            "ip": 0, "op": 60, "st": 0, "bm": 0
        })
    }

    #[test]
    fn a_run_of_plain_layers_becomes_one_in_paint_order() {
        let mut doc = json!({"layers": [layer(1, "a"), layer(2, "b"), layer(3, "c")]});
        assert_eq!(pack(&mut doc), 2);
        let layers = doc["layers"].as_array().unwrap();
        assert_eq!(layers.len(), 1);
        let names: Vec<&str> = layers[0]["shapes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|g| g["nm"].as_str().unwrap())
            .collect();
        assert_eq!(names, ["a", "b", "c"]);
        assert_eq!(layers[0]["nm"], "a … c");
    }

    #[test]
    fn a_long_run_is_cut_into_layers_of_at_most_max_run() {
        let list: Vec<Json> = (0..2 * MAX_RUN as u32 + 1)
            .map(|k| layer(k + 1, &format!("u{k}")))
            .collect();
        let mut doc = json!({ "layers": list });
        pack(&mut doc);
        let sizes: Vec<usize> = doc["layers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l["shapes"].as_array().unwrap().len())
            .collect();
        assert_eq!(sizes, [MAX_RUN, MAX_RUN, 1]);
    }

    #[test]
    fn what_a_group_cannot_hold_breaks_the_run() {
        let mut moved = layer(2, "moved");
        moved["ks"]["o"] = json!({"a": 0, "k": 50});
        let mut parent = layer(4, "parent");
        parent["ty"] = json!(3);
        let mut child = layer(5, "child");
        child["parent"] = json!(4);
        let mut matte = layer(6, "matte");
        matte["td"] = json!(1);
        let mut later = layer(7, "later");
        later["ip"] = json!(10);
        let list = vec![
            layer(1, "a"),
            moved,
            layer(3, "b"),
            parent,
            child,
            matte,
            layer(8, "c"),
            later,
        ];
        let mut doc = json!({ "layers": list.clone() });
        assert_eq!(pack(&mut doc), 0);
        assert_eq!(doc["layers"], Json::Array(list));
    }

    #[test]
    fn shapes_of_a_layer_without_its_group_are_wrapped_in_one() {
        let mut bare = layer(2, "bare");
        bare["shapes"] = json!([{"ty": "sh"}, {"ty": "fl"}]);
        let mut doc = json!({"layers": [layer(1, "a"), bare]});
        pack(&mut doc);
        let group = &doc["layers"][0]["shapes"][1];
        assert_eq!(group["nm"], "bare");
        assert_eq!(group["it"].as_array().unwrap().len(), 3);
        assert_eq!(group["it"][2]["ty"], "tr");
    }
}
