//! `--theme FILE`: a dotLottie theme written into `.lottie` outputs.
//!
//! The file is JSON, slot id → value: a colour string (`"#e4572e"`, or a CSS name) for a
//! colour slot (`TAG.fill`, `TAG.stroke`), a number from 0 to 1 for an opacity slot
//! (`TAG.opacity`), or a whole Lottie property (`{"a": 1, "k": [keyframes]}`, values as
//! Lottie writes them: colours 0–1, opacity 0–100) to animate it. It becomes the dotLottie 2.0
//! theme `t/ID.json` (ID the file's stem), `{"rules": [{"id", "type": "Color" | "Scalar",
//! "value" | "keyframes"}]}`, listed in the manifest's `themes`; a player applies it with
//! `setTheme(ID)`. A slot the animation does not have is a warning naming it; a file that
//! is not such JSON an error with its line and column.

use std::path::{Path, PathBuf};

use serde_json::{Map, Value as Json, json};

use gmotion::Warning;
use gmotion::color::Color;
use gmotion_pipeline::dotlottie::{Entry, Package};

use crate::report::{CliError, Result};

/// A theme read from its file.
#[derive(Clone, Debug)]
pub struct Theme {
    /// Its file, named in messages.
    path: PathBuf,
    /// Its id: the file's stem.
    id: String,
    /// Slot id → value, in the file's order.
    values: Map<String, Json>,
}

/// The most bytes a theme file may have: a theme names a few slots.
const MAX_BYTES: u64 = 16 << 20;

impl Theme {
    /// Reads the theme at `path`; JSON that is not an object of slot values is an error
    /// with its line and column.
    pub fn read(path: &Path) -> Result<Theme> {
        let name = path.display();
        let size = std::fs::metadata(path)
            .map_err(|e| CliError::msg(format!("{name}: error: {e}")))?
            .len();
        if size > MAX_BYTES {
            return Err(CliError::msg(format!(
                "{name}: error: a theme of {size} bytes; at most {MAX_BYTES}"
            )));
        }
        let text = std::fs::read_to_string(path)
            .map_err(|e| CliError::msg(format!("{name}: error: {e}")))?;
        let values: Json = serde_json::from_str(&text).map_err(|e| {
            CliError::msg(format!(
                "{name}:{}:{}: error: {}",
                e.line(),
                e.column(),
                e.to_string()
                    .rsplit_once(" at line")
                    .map_or(e.to_string(), |(m, _)| m.to_string())
            ))
        })?;
        let Json::Object(values) = values else {
            return Err(CliError::msg(format!(
                "{name}:1:1: error: a theme is an object of slot values, e.g. {{\"leaf.fill\": \"#e4572e\"}}"
            )));
        };
        let id = path
            .file_stem()
            .map(|s| gmotion_pipeline::dotlottie::id_for(&s.to_string_lossy()))
            .unwrap_or_else(|| "theme".to_string());
        let theme = Theme {
            path: path.to_path_buf(),
            id,
            values,
        };
        // Each value is checked now, before any output is written.
        for (slot, v) in &theme.values {
            theme.rule(slot, v, kind_of_id(slot))?;
        }
        Ok(theme)
    }

    /// The `.lottie` package `bytes` (the output `out`) with this theme added, its rules
    /// for the slots the animation has; a warning names each slot it does not have.
    pub fn add_to(
        &self,
        bytes: &[u8],
        out: &Path,
        max_bytes: u64,
    ) -> Result<(Vec<u8>, Vec<Warning>)> {
        let name = out.display().to_string();
        let failed = |e: &dyn std::fmt::Display| CliError::msg(format!("{name}: error: {e}"));
        let mut package = Package::read(bytes, &name, max_bytes).map_err(|e| failed(&e))?;
        let animation = package.pick(None, &name).map_err(|e| failed(&e))?;
        let doc: Json = serde_json::from_str(&animation.text).map_err(|e| failed(&e))?;
        let slots = doc.get("slots").and_then(Json::as_object);
        let mut rules = Vec::new();
        let mut warnings = Vec::new();
        for (slot, v) in &self.values {
            match slots.and_then(|s| s.get(slot)) {
                Some(there) => rules.push(self.rule(slot, v, kind_of_slot(there))?),
                None => warnings.push(Warning::new(format!(
                    "theme {}: the animation has no slot `{slot}` (it has {}); the rule is left out",
                    self.path.display(),
                    match slots {
                        Some(s) if !s.is_empty() => {
                            s.keys().map(|k| format!("`{k}`")).collect::<Vec<_>>().join(", ")
                        }
                        _ => "none: add the `slots` directive to the grammar".to_string(),
                    }
                ))),
            }
        }
        package.themes.retain(|t| t.id != self.id);
        package.themes.push(Entry {
            id: self.id.clone(),
            text: json!({ "rules": rules }).to_string(),
        });
        let bytes = package.to_bytes().map_err(|e| failed(&e))?;
        Ok((bytes, warnings))
    }

    /// The theme rule setting `slot` (a colour slot, or not) to `v`.
    fn rule(&self, slot: &str, v: &Json, color: bool) -> Result<Json> {
        let bad = |what: &str| {
            CliError::msg(format!(
                "{}: error: slot `{slot}`: {what}",
                self.path.display()
            ))
        };
        let ty = if color { "Color" } else { "Scalar" };
        let value = |k: &Json| -> Result<Json> {
            match (color, k) {
                (true, Json::Array(c)) if c.len() >= 3 && c.iter().all(Json::is_number) => {
                    Ok(Json::Array(c[..3].to_vec()))
                }
                (false, Json::Number(_)) => Ok(k.clone()),
                (false, Json::Array(c)) if c.len() == 1 && c[0].is_number() => Ok(c[0].clone()),
                _ => Err(bad(&format!("`{k}` is no {} value", ty.to_lowercase()))),
            }
        };
        Ok(match v {
            Json::String(s) if color => {
                let c = Color::parse(s)
                    .ok_or_else(|| bad(&format!("`{s}` is no colour (#rrggbb or a CSS name)")))?;
                json!({ "id": slot, "type": ty, "value": [c.r, c.g, c.b] })
            }
            Json::Number(n) if !color => {
                let x = n.as_f64().filter(|x| (0.0..=1.0).contains(x));
                let x = x.ok_or_else(|| bad(&format!("opacity {n} is not between 0 and 1")))?;
                json!({ "id": slot, "type": ty, "value": x * 100.0 })
            }
            Json::Object(p) => match (p.get("a").and_then(Json::as_f64), p.get("k")) {
                (Some(a), Some(Json::Array(keys))) if a != 0.0 => {
                    let mut frames = Vec::with_capacity(keys.len());
                    for key in keys {
                        let (Some(t), Some(s)) = (key.get("t"), key.get("s")) else {
                            return Err(bad("a keyframe needs `t` and `s`"));
                        };
                        let mut f = json!({ "frame": t, "value": value(s)? });
                        if key.get("h").and_then(Json::as_f64) == Some(1.0) {
                            f["hold"] = json!(true);
                        }
                        if let (Some(i), Some(o)) = (key.get("i"), key.get("o")) {
                            f["inTangent"] = i.clone();
                            f["outTangent"] = o.clone();
                        }
                        frames.push(f);
                    }
                    json!({ "id": slot, "type": ty, "keyframes": frames })
                }
                (_, Some(k)) => json!({ "id": slot, "type": ty, "value": value(k)? }),
                _ => return Err(bad("a Lottie property needs `k`")),
            },
            _ if color => {
                return Err(bad(
                    "a colour slot takes a colour string or a Lottie property",
                ));
            }
            _ => {
                return Err(bad(
                    "an opacity slot takes a number from 0 to 1 or a Lottie property",
                ));
            }
        })
    }
}

/// Whether a slot id names a colour slot by its kind (`TAG.fill`, `TAG.stroke`): what a
/// value is checked as before the animation exists.
fn kind_of_id(slot: &str) -> bool {
    !slot.ends_with(".opacity")
}

/// Whether a document's slot holds a colour (a vector value) rather than a number.
fn kind_of_slot(slot: &Json) -> bool {
    let k = &slot["p"]["k"];
    let first = match k.get(0).and_then(|f| f.get("s")) {
        Some(s) => s,
        None => k,
    };
    first.as_array().is_some_and(|v| v.len() >= 3)
}
