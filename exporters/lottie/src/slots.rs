//! Slots (the Lottie spec's `sid`): each tag's solid fill colour, stroke colour or opacity
//! given a slot id (`TAG.fill`, `TAG.stroke`, `TAG.opacity`, what the grammar's `slots`
//! directive asks for), its value kept in place and also written into the document's
//! `slots` (`{"TAG.fill": {"p": PROPERTY}}`). A player that reads slots (lottie-web at load,
//! dotlottie-web and ThorVG) draws the slot's value; one that does not draws the property
//! as it is, the same thing.
//!
//! A slot holds one property, so the shapes of a tag share it: it is written only when
//! every property of that tag and kind is the same (the same colour, or the same
//! keyframes: an animated colour is slotted whole, and a theme that sets it replaces the
//! animation). Where they differ, slotting them would recolour the document in every player
//! that reads slots, so that slot is left out with a warning.
//!
//! The layer builder marks each property with its slot id ([`MARK`], on the fill or
//! stroke item, or on the unit's layer for its opacity); [`write()`] moves the marks into
//! the properties and writes `slots`. Nothing is marked without the directive, so other
//! documents are written byte for byte as before.

use serde_json::{Map, Value as Json};

/// The key of a slot mark, never left in a written document.
pub const MARK: &str = "gmotion_sid";

/// Moves the slot marks of `doc` into the properties they mark (as `sid`) and writes the
/// document's `slots`; returns a warning for each slot left out.
pub fn write(doc: &mut Json) -> Vec<String> {
    // The first property of each slot id, and how many different ones it has.
    let mut seen: Vec<(String, Json, usize)> = Vec::new();
    visit(
        doc,
        &mut |id, prop| match seen.iter_mut().find(|(s, ..)| s == id) {
            Some((_, first, n)) => {
                if first != prop {
                    *n += 1;
                }
            }
            None => seen.push((id.to_string(), prop.clone(), 1)),
        },
    );
    let kept = |id: &str| seen.iter().any(|(s, _, n)| s == id && *n == 1);
    remove_marks(doc, &mut |id, prop| {
        if kept(id)
            && let Some(p) = prop.as_object_mut()
        {
            p.insert("sid".to_string(), Json::String(id.to_string()));
        }
    });
    let mut warnings = Vec::new();
    let mut slots = Map::new();
    for (id, prop, n) in seen {
        if n > 1 {
            let (tag, kind) = id.rsplit_once('.').unwrap_or((id.as_str(), ""));
            warnings.push(format!(
                "slot `{id}` is not written: the shapes tagged `{tag}` have {} different {kind} \
                 properties and a slot holds one (give them different tags to slot them)",
                if n > 9 {
                    "many".to_string()
                } else {
                    n.to_string()
                },
            ));
            continue;
        }
        let mut p = Map::new();
        p.insert("p".to_string(), prop);
        slots.insert(id, Json::Object(p));
    }
    if !slots.is_empty()
        && let Some(d) = doc.as_object_mut()
    {
        d.insert("slots".to_string(), Json::Object(slots));
    }
    warnings
}

/// Calls `f` with each marked property of `doc` and its slot id, marks left in place.
fn visit(doc: &mut Json, f: &mut dyn FnMut(&str, &mut Json)) {
    walk(doc, false, f);
}

/// Calls `f` with each marked property of `doc` and its slot id, taking the marks out.
fn remove_marks(doc: &mut Json, f: &mut dyn FnMut(&str, &mut Json)) {
    walk(doc, true, f);
}

fn walk(doc: &mut Json, take: bool, f: &mut dyn FnMut(&str, &mut Json)) {
    if let Some(layers) = doc.get_mut("layers").and_then(Json::as_array_mut) {
        layers.iter_mut().for_each(|l| layer(l, take, f));
    }
    if let Some(assets) = doc.get_mut("assets").and_then(Json::as_array_mut) {
        for a in assets {
            if let Some(layers) = a.get_mut("layers").and_then(Json::as_array_mut) {
                layers.iter_mut().for_each(|l| layer(l, take, f));
            }
        }
    }
}

/// The mark's slot id in `o` (taken out when `take`).
fn mark(o: &mut Map<String, Json>, take: bool) -> Option<Json> {
    match take {
        true => o.shift_remove(MARK),
        false => o.get(MARK).cloned(),
    }
}

fn layer(l: &mut Json, take: bool, f: &mut dyn FnMut(&str, &mut Json)) {
    let Some(o) = l.as_object_mut() else {
        return;
    };
    // A layer's mark is `[id, on_group]`: its opacity is on the layer's transform, or on
    // its first group's (one path, whose opacity the builder puts there).
    if let Some(Json::Array(m)) = mark(o, take)
        && let [Json::String(id), Json::Bool(on_group)] = m.as_slice()
    {
        let prop = match on_group {
            true => (o.get_mut("shapes"))
                .and_then(|s| s.get_mut(0))
                .and_then(|g| g.get_mut("it"))
                .and_then(Json::as_array_mut)
                .and_then(|it| it.last_mut())
                .and_then(|tr| tr.get_mut("o")),
            false => o.get_mut("ks").and_then(|ks| ks.get_mut("o")),
        };
        if let Some(prop) = prop {
            f(id, prop);
        }
    }
    if let Some(shapes) = o.get_mut("shapes").and_then(Json::as_array_mut) {
        shapes.iter_mut().for_each(|s| shape(s, take, f));
    }
}

fn shape(s: &mut Json, take: bool, f: &mut dyn FnMut(&str, &mut Json)) {
    let Some(o) = s.as_object_mut() else {
        return;
    };
    if let Some(Json::String(id)) = mark(o, take)
        && let Some(c) = o.get_mut("c")
    {
        f(&id, c);
    }
    if let Some(items) = o.get_mut("it").and_then(Json::as_array_mut) {
        items.iter_mut().for_each(|s| shape(s, take, f));
    }
}
