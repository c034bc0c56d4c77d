//! dotLottie, the `.lottie` package: a zip holding a `manifest.json`, one or more Lottie
//! animations, the images they share and themes. Version 2 (what Lottie Creator and
//! `@dotlottie/dotlottie-js` 1.x write, what `@lottiefiles/dotlottie-web` plays) keeps
//! animations in `a/ID.json`, images in `i/`, themes in `t/ID.json`; version 1 kept them in
//! `animations/` and `images/`. Both are read; version 2 is written.
//!
//! A [`Package`] holds what gmotion needs to read one animation of a package and to write it
//! back with the others untouched: every animation's JSON text as it was stored, the image
//! files by name, the themes, and any other file (state machines, fonts, audio) kept as it
//! was. Images an animation embeds as data URLs are moved into `i/` when it is put into a
//! package, named by their content, so animations that show the same picture share one
//! file; reading an animation for import puts them back inline ([`Package::resolved`]).
//!
//! Reading is bounded: at most [`MAX_ENTRIES`] files and at most the caller's byte limit
//! decompressed in total, counted as the bytes come out (a zip bomb stops at the limit,
//! whatever its headers declare).
//!
//! ```
//! use gmotion_lottie::dotlottie::Package;
//!
//! let mut package = Package::new();
//! package.put_animation("wave", r#"{"v":"5.7.0","fr":30,"ip":0,"op":30,"w":10,"h":10,"layers":[]}"#)?;
//! let bytes = package.to_bytes()?;
//! let read = Package::read(&bytes, "wave.lottie", 1 << 20)?;
//! assert_eq!(read.animations[0].id, "wave");
//! # Ok::<(), gmotion_lottie::dotlottie::PackageError>(())
//! ```

use std::collections::BTreeMap;
use std::io::{Cursor, Read, Write};

use base64::Engine as _;
use gmotion::scene::ImageFormat;
use serde_json::Value;

/// Most files a package may hold.
pub const MAX_ENTRIES: usize = 10_000;

/// The manifest's name inside the zip.
const MANIFEST: &str = "manifest.json";

/// Which layout a package was read in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Version {
    /// dotLottie 1.0: `animations/ID.json`, `images/`.
    V1,
    /// dotLottie 2.0: `a/ID.json`, `i/`, `t/ID.json`.
    V2,
}

/// One animation or theme of a package: its id and its JSON text as stored.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// The id the manifest gives it (its file is named after it).
    pub id: String,
    /// The JSON text.
    pub text: String,
}

/// A dotLottie package, held in the version 2 layout whatever it was read in.
#[derive(Clone, Debug, PartialEq)]
pub struct Package {
    /// The layout it was read in ([`Version::V2`] for a new one).
    pub version: Version,
    /// The animations, in the manifest's order; images referenced as `u: "/i/"`.
    pub animations: Vec<Entry>,
    /// The themes, in the manifest's order.
    pub themes: Vec<Entry>,
    /// The image files (`i/NAME`), by name.
    pub images: BTreeMap<String, Vec<u8>>,
    /// Every other file (state machines, fonts, audio), by its path in the zip, kept as it
    /// was read.
    pub others: BTreeMap<String, Vec<u8>>,
    /// The animation a player shows first (`initial.animation`; `activeAnimationId` in
    /// version 1), when the manifest names one.
    pub initial: Option<String>,
}

/// The package a scene was read from and which of its animations the scene is: what a
/// `.lottie` output rewrites (that animation replaced, the others and the themes kept).
#[derive(Clone, Debug, PartialEq)]
pub struct Picked {
    /// The package as read.
    pub package: Package,
    /// The id of the animation the scene is.
    pub id: String,
}

/// Why a package could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum PackageError {
    /// The bytes are not a zip archive.
    #[error("{name}: not a dotLottie file (a .lottie is a zip archive): {message}")]
    NotZip {
        /// The file.
        name: String,
        /// What the zip reader said.
        message: String,
    },
    /// The archive is damaged, or holds more than a package may.
    #[error("{name}: {message}")]
    Archive {
        /// The file.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The decompressed files pass the byte limit.
    #[error(
        "{name}: `{entry}` decompresses past the limit of {limit} bytes for the whole package (a zip bomb?); raise it with --limit input-bytes=N"
    )]
    TooLarge {
        /// The file.
        name: String,
        /// The file inside the zip being read when the limit was passed.
        entry: String,
        /// The limit.
        limit: u64,
    },
    /// The manifest is missing or not what dotLottie says it is.
    #[error("{name}: {MANIFEST}: {message}")]
    Manifest {
        /// The file.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The manifest names a file the zip does not hold.
    #[error("{name}: the manifest names {what} `{id}`, but the package has no `{path}`")]
    Missing {
        /// The file.
        name: String,
        /// "animation" or "theme".
        what: &'static str,
        /// Its id.
        id: String,
        /// Where it should be.
        path: String,
    },
    /// A file that must be text is not UTF-8.
    #[error("{name}: `{entry}` is not UTF-8 text")]
    NotUtf8 {
        /// The file.
        name: String,
        /// The file inside the zip.
        entry: String,
    },
    /// An animation's JSON does not parse.
    #[error("{name}: {entry}:{line}:{column}: malformed JSON: {message}")]
    Json {
        /// The file.
        name: String,
        /// The file inside the zip.
        entry: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What serde_json said.
        message: String,
    },
    /// An animation asked for by id is not in the package.
    #[error(
        "{name}: no animation `{id}` in the package; it holds {}",
        list(available)
    )]
    NoAnimation {
        /// The file.
        name: String,
        /// The id asked for.
        id: String,
        /// The ids it holds.
        available: Vec<String>,
    },
    /// An animation links an image the package does not hold.
    #[error("{name}: animation `{id}` shows image `{image}`, which the package does not hold")]
    MissingImage {
        /// The file.
        name: String,
        /// The animation.
        id: String,
        /// The image's file name.
        image: String,
    },
    /// The zip could not be written.
    #[error("cannot write the dotLottie package: {0}")]
    Write(String),
}

fn list(ids: &[String]) -> String {
    if ids.is_empty() {
        return "none".into();
    }
    ids.iter()
        .map(|i| format!("`{i}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

impl Default for Package {
    fn default() -> Package {
        Package::new()
    }
}

impl Package {
    /// An empty version 2 package.
    pub fn new() -> Package {
        Package {
            version: Version::V2,
            animations: Vec::new(),
            themes: Vec::new(),
            images: BTreeMap::new(),
            others: BTreeMap::new(),
            initial: None,
        }
    }

    /// Whether `bytes` start like a zip archive (a `.lottie` given under another name).
    pub fn sniff(bytes: &[u8]) -> bool {
        bytes.starts_with(b"PK\x03\x04")
    }

    /// Reads a package from `bytes`; `name` names it in errors; at most `max_bytes` are
    /// decompressed in total.
    pub fn read(bytes: &[u8], name: &str, max_bytes: u64) -> Result<Package, PackageError> {
        let mut zip =
            zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| PackageError::NotZip {
                name: name.to_string(),
                message: e.to_string(),
            })?;
        if zip.len() > MAX_ENTRIES {
            return Err(PackageError::Archive {
                name: name.to_string(),
                message: format!(
                    "holds {} files, more than a package may ({MAX_ENTRIES})",
                    zip.len()
                ),
            });
        }
        let mut files = BTreeMap::new();
        let mut left = max_bytes;
        for i in 0..zip.len() {
            let mut file = zip.by_index(i).map_err(|e| PackageError::Archive {
                name: name.to_string(),
                message: format!("file {i} of the archive: {e}"),
            })?;
            if file.is_dir() {
                continue;
            }
            let entry = file.name().map_or_else(
                |_| String::from_utf8_lossy(file.name_raw()).into_owned(),
                |n| n.into_owned(),
            );
            let mut data = Vec::new();
            // Counted as it comes out: the header's size is the archive's word, not a bound.
            (&mut file)
                .take(left.saturating_add(1))
                .read_to_end(&mut data)
                .map_err(|e| PackageError::Archive {
                    name: name.to_string(),
                    message: format!("`{entry}`: {e}"),
                })?;
            if data.len() as u64 > left {
                return Err(PackageError::TooLarge {
                    name: name.to_string(),
                    entry,
                    limit: max_bytes,
                });
            }
            left -= data.len() as u64;
            files.insert(entry, data);
        }
        Package::from_files(files, name)
    }

    /// The package the files of an archive make, by path.
    fn from_files(
        mut files: BTreeMap<String, Vec<u8>>,
        name: &str,
    ) -> Result<Package, PackageError> {
        let manifest_error = |message: String| PackageError::Manifest {
            name: name.to_string(),
            message,
        };
        let manifest = files
            .remove(MANIFEST)
            .ok_or_else(|| manifest_error("missing: a dotLottie holds a manifest.json".into()))?;
        let manifest: Value = serde_json::from_slice(&manifest)
            .map_err(|e| manifest_error(format!("{}:{}: {e}", e.line(), e.column())))?;
        let version = match manifest.get("version") {
            Some(Value::String(v)) if v == "2" || v.starts_with("2.") => Version::V2,
            _ => Version::V1,
        };
        let ids = |key: &str| -> Result<Vec<String>, PackageError> {
            match manifest.get(key) {
                None => Ok(Vec::new()),
                Some(Value::Array(items)) => items
                    .iter()
                    .enumerate()
                    .map(|(i, item)| match item.get("id") {
                        Some(Value::String(id)) => Ok(id.clone()),
                        _ => Err(manifest_error(format!("{key}[{i}] has no string `id`"))),
                    })
                    .collect(),
                Some(_) => Err(manifest_error(format!("`{key}` is not a list"))),
            }
        };
        let animation_ids = ids("animations")?;
        if animation_ids.is_empty() {
            return Err(manifest_error("lists no animation".into()));
        }
        let (animations_dir, images_dir) = match version {
            Version::V2 => ("a/", "i/"),
            Version::V1 => ("animations/", "images/"),
        };
        let mut text_of = |what: &'static str, dir: &str, id: &str| {
            let path = format!("{dir}{id}.json");
            let data = files.remove(&path).ok_or_else(|| PackageError::Missing {
                name: name.to_string(),
                what,
                id: id.to_string(),
                path: path.clone(),
            })?;
            String::from_utf8(data).map_err(|_| PackageError::NotUtf8 {
                name: name.to_string(),
                entry: path,
            })
        };
        let mut animations = Vec::new();
        for id in animation_ids {
            let text = text_of("animation", animations_dir, &id)?;
            let text = match version {
                Version::V2 => text,
                Version::V1 => relinked(&text, name, &id)?,
            };
            animations.push(Entry { id, text });
        }
        let mut themes = Vec::new();
        if version == Version::V2 {
            for id in ids("themes")? {
                let text = text_of("theme", "t/", &id)?;
                themes.push(Entry { id, text });
            }
        }
        let mut images = BTreeMap::new();
        let mut others = BTreeMap::new();
        for (path, data) in files {
            match path.strip_prefix(images_dir) {
                Some(image) if !image.is_empty() => {
                    images.insert(image.to_string(), data);
                }
                _ => {
                    others.insert(path, data);
                }
            }
        }
        let initial = match version {
            Version::V2 => manifest.pointer("/initial/animation"),
            Version::V1 => manifest.get("activeAnimationId"),
        }
        .and_then(Value::as_str)
        .filter(|id| !id.is_empty())
        .map(str::to_string);
        Ok(Package {
            version,
            animations,
            themes,
            images,
            others,
            initial,
        })
    }

    /// The ids of the animations, in order.
    pub fn ids(&self) -> Vec<String> {
        self.animations.iter().map(|a| a.id.clone()).collect()
    }

    /// The animation `id`, or (without one) the one a player shows first: the manifest's
    /// initial animation, else the first. `name` names the package in errors.
    pub fn pick(&self, id: Option<&str>, name: &str) -> Result<&Entry, PackageError> {
        let wanted = id.or(self.initial.as_deref());
        let found = match wanted {
            Some(w) => self.animations.iter().find(|a| a.id == w),
            None => self.animations.first(),
        };
        // An initial animation the list lacks falls back to the first, as players do.
        let found = match (found, id) {
            (None, None) => self.animations.first(),
            (found, _) => found,
        };
        found.ok_or_else(|| PackageError::NoAnimation {
            name: name.to_string(),
            id: wanted.unwrap_or_default().to_string(),
            available: self.ids(),
        })
    }

    /// The JSON of animation `entry` with the images it links from the package put inline
    /// as data URLs, as a player reads it: what the Lottie importer takes.
    pub fn resolved(&self, entry: &Entry, name: &str) -> Result<Value, PackageError> {
        let path = format!("a/{}.json", entry.id);
        let mut json: Value = serde_json::from_str(entry.text.trim_start_matches('\u{feff}'))
            .map_err(|e| {
                let message = e.to_string();
                let message = message
                    .rsplit_once(" at line ")
                    .map_or(message.as_str(), |(m, _)| m)
                    .to_string();
                PackageError::Json {
                    name: name.to_string(),
                    entry: path,
                    line: e.line(),
                    column: e.column(),
                    message,
                }
            })?;
        for asset in assets_mut(&mut json) {
            let Some(file) = linked_image(asset) else {
                continue;
            };
            let data = self
                .images
                .get(&file)
                .ok_or_else(|| PackageError::MissingImage {
                    name: name.to_string(),
                    id: entry.id.clone(),
                    image: file.clone(),
                })?;
            let mime = ImageFormat::sniff(data).map_or("application/octet-stream", |f| f.mime());
            let url = format!(
                "data:{mime};base64,{}",
                base64::engine::general_purpose::STANDARD.encode(data)
            );
            asset.insert("u".into(), Value::String(String::new()));
            asset.insert("p".into(), Value::String(url));
            asset.insert("e".into(), Value::from(1));
        }
        Ok(json)
    }

    /// Puts the animation `id` (Lottie JSON `text`) into the package, replacing one of the
    /// same id or appending it. Images it embeds as data URLs move into `i/`, named by
    /// their content (an image the package already holds is shared, not stored twice).
    pub fn put_animation(&mut self, id: &str, text: &str) -> Result<(), PackageError> {
        let text = if text.contains("\"data:") {
            self.images_moved_out(text)?
        } else {
            text.to_string()
        };
        let entry = Entry {
            id: id.to_string(),
            text,
        };
        match self.animations.iter_mut().find(|a| a.id == id) {
            Some(old) => *old = entry,
            None => self.animations.push(entry),
        }
        Ok(())
    }

    /// `text` with every data-URL image moved into [`Package::images`].
    fn images_moved_out(&mut self, text: &str) -> Result<String, PackageError> {
        let mut json: Value = serde_json::from_str(text)
            .map_err(|e| PackageError::Write(format!("the animation is not JSON: {e}")))?;
        let mut moved = false;
        for asset in assets_mut(&mut json) {
            let Some(url) = asset.get("p").and_then(Value::as_str) else {
                continue;
            };
            let Some((data, format)) = data_url(url) else {
                continue;
            };
            let file = self.image_file(data, format);
            asset.insert("u".into(), Value::String("/i/".into()));
            asset.insert("p".into(), Value::String(file));
            asset.insert("e".into(), Value::from(0));
            moved = true;
        }
        if !moved {
            return Ok(text.to_string());
        }
        serde_json::to_string(&json).map_err(|e| PackageError::Write(e.to_string()))
    }

    /// The name under which `data` is kept in `i/`: one already holding the same bytes, or
    /// a new one made from a hash of them.
    fn image_file(&mut self, data: Vec<u8>, format: Option<ImageFormat>) -> String {
        if let Some((name, _)) = self.images.iter().find(|(_, d)| **d == data) {
            return name.clone();
        }
        let ext = match format {
            Some(ImageFormat::Png) => "png",
            Some(ImageFormat::Jpeg) => "jpg",
            Some(ImageFormat::Gif) => "gif",
            Some(ImageFormat::Webp) => "webp",
            None => "bin",
        };
        let hash = fnv1a(&data);
        let mut name = format!("{hash:016x}.{ext}");
        let mut n = 1;
        while self.images.contains_key(&name) {
            name = format!("{hash:016x}-{n}.{ext}");
            n += 1;
        }
        self.images.insert(name.clone(), data);
        name
    }

    /// The package as a version 2 zip: the manifest first, then animations, themes,
    /// images and the other files. JSON is deflated, images (compressed already) stored;
    /// every file is dated 1980-01-01 so the same package is the same bytes.
    pub fn to_bytes(&self) -> Result<Vec<u8>, PackageError> {
        let write_error = |e: &dyn std::fmt::Display| PackageError::Write(e.to_string());
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        let deflated = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .last_modified_time(zip::DateTime::default());
        let stored = deflated.compression_method(zip::CompressionMethod::Stored);
        let mut put = |path: &str, data: &[u8], compress: bool| -> Result<(), PackageError> {
            zip.start_file(path, if compress { deflated } else { stored })
                .map_err(|e| write_error(&e))?;
            zip.write_all(data).map_err(|e| write_error(&e))
        };
        put(MANIFEST, self.manifest().to_string().as_bytes(), true)?;
        for a in &self.animations {
            put(&format!("a/{}.json", a.id), a.text.as_bytes(), true)?;
        }
        for t in &self.themes {
            put(&format!("t/{}.json", t.id), t.text.as_bytes(), true)?;
        }
        for (name, data) in &self.images {
            put(&format!("i/{name}"), data, false)?;
        }
        for (path, data) in &self.others {
            put(path, data, true)?;
        }
        Ok(zip.finish().map_err(|e| write_error(&e))?.into_inner())
    }

    /// The version 2 manifest of the package.
    fn manifest(&self) -> Value {
        let entries = |list: &[Entry]| -> Value {
            list.iter()
                .map(|e| serde_json::json!({ "id": e.id }))
                .collect()
        };
        let mut manifest = serde_json::json!({
            "version": "2",
            "generator": concat!("gmotion ", env!("CARGO_PKG_VERSION")),
            "animations": entries(&self.animations),
        });
        if !self.themes.is_empty() {
            manifest["themes"] = entries(&self.themes);
        }
        let initial = self
            .initial
            .as_ref()
            .filter(|id| self.animations.iter().any(|a| &&a.id == id))
            .or(self.animations.first().map(|a| &a.id));
        if let Some(id) = initial {
            manifest["initial"] = serde_json::json!({ "animation": id });
        }
        manifest
    }
}

/// An id a package can hold for `stem` (a file name without extension): letters, digits,
/// `-` and `_` kept, anything else `_`, never empty.
pub fn id_for(stem: &str) -> String {
    let id: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if id.is_empty() {
        "animation".into()
    } else {
        id
    }
}

/// The image assets of a Lottie document (at the top level: precomposition assets hold
/// layers, not files), as JSON objects.
fn assets_mut(json: &mut Value) -> impl Iterator<Item = &mut serde_json::Map<String, Value>> {
    json.get_mut("assets")
        .and_then(Value::as_array_mut)
        .into_iter()
        .flatten()
        .filter_map(Value::as_object_mut)
        .filter(|a| !a.contains_key("layers"))
}

/// The package file an asset links (`e` not 1, `u` the image folder or empty, `p` a file
/// name), if it links one.
fn linked_image(asset: &serde_json::Map<String, Value>) -> Option<String> {
    if asset.get("e").and_then(Value::as_i64) == Some(1) {
        return None;
    }
    let p = asset.get("p")?.as_str()?;
    if p.is_empty() || p.starts_with("data:") {
        return None;
    }
    let u = asset.get("u").and_then(Value::as_str).unwrap_or("");
    let folder = u.trim_start_matches('/');
    matches!(folder, "" | "i/" | "images/").then(|| p.to_string())
}

/// The bytes of a base64 data URL and their image format, if `url` is one.
fn data_url(url: &str) -> Option<(Vec<u8>, Option<ImageFormat>)> {
    let (head, body) = url.strip_prefix("data:")?.split_once(',')?;
    if !head.ends_with(";base64") {
        return None;
    }
    let data = base64::engine::general_purpose::STANDARD
        .decode(body.trim())
        .ok()?;
    let format = ImageFormat::sniff(&data);
    Some((data, format))
}

/// A version 1 animation's text with its images linked in the version 2 folder.
fn relinked(text: &str, name: &str, id: &str) -> Result<String, PackageError> {
    if !text.contains("images/") {
        return Ok(text.to_string());
    }
    let mut json: Value = serde_json::from_str(text).map_err(|e| PackageError::Json {
        name: name.to_string(),
        entry: format!("animations/{id}.json"),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    for asset in assets_mut(&mut json) {
        if linked_image(asset).is_some() {
            asset.insert("u".into(), Value::String("/i/".into()));
        }
    }
    Ok(json.to_string())
}

/// FNV-1a, 64 bits: a stable name for an image's bytes (not a security measure; equal
/// names with different bytes get a suffix).
fn fnv1a(data: &[u8]) -> u64 {
    data.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOC: &str = r#"{"v":"5.7.0","fr":30,"ip":0,"op":30,"w":10,"h":10,"layers":[]}"#;
    const PNG_1X1: &str = "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg==";

    fn with_image() -> String {
        format!(
            r#"{{"v":"5.7.0","fr":30,"ip":0,"op":30,"w":10,"h":10,"assets":[{{"id":"img","w":1,"h":1,"u":"","p":"data:image/png;base64,{PNG_1X1}","e":1}}],"layers":[]}}"#
        )
    }

    #[test]
    fn written_package_reads_back() {
        let mut p = Package::new();
        p.put_animation("one", DOC).unwrap();
        p.put_animation("two", &with_image()).unwrap();
        let bytes = p.to_bytes().unwrap();
        assert!(Package::sniff(&bytes));
        let mut back = Package::read(&bytes, "x.lottie", 1 << 20).unwrap();
        // The manifest names the first animation the initial one.
        assert_eq!(back.initial.take().as_deref(), Some("one"));
        assert_eq!(back, p);
        assert_eq!(back.ids(), ["one", "two"]);
        assert_eq!(back.images.len(), 1);
        // Resolved for import, the image is inline again.
        let json = back.resolved(&back.animations[1], "x.lottie").unwrap();
        assert_eq!(json["assets"][0]["e"], 1);
        assert!(
            json["assets"][0]["p"]
                .as_str()
                .unwrap()
                .starts_with("data:image/png;base64,")
        );
        // The same bytes make the same package.
        assert_eq!(p.to_bytes().unwrap(), bytes);
    }

    #[test]
    fn shared_images_are_stored_once() {
        let mut p = Package::new();
        p.put_animation("a", &with_image()).unwrap();
        p.put_animation("b", &with_image()).unwrap();
        assert_eq!(p.images.len(), 1);
        assert_eq!(p.animations[0].text, p.animations[1].text);
    }

    #[test]
    fn a_zip_bomb_stops_at_the_limit() {
        let mut p = Package::new();
        let big = format!(r#"{{"pad":"{}","layers":[]}}"#, "0".repeat(1 << 20));
        p.put_animation("big", &big).unwrap();
        let bytes = p.to_bytes().unwrap();
        assert!(bytes.len() < 20_000, "deflate squeezes the padding");
        let err = Package::read(&bytes, "bomb.lottie", 100_000).unwrap_err();
        assert!(matches!(err, PackageError::TooLarge { .. }), "{err}");
    }

    #[test]
    fn bad_packages_say_why() {
        let not_zip = Package::read(b"{}", "x.lottie", 1 << 20).unwrap_err();
        assert!(matches!(not_zip, PackageError::NotZip { .. }), "{not_zip}");
        let mut p = Package::new();
        p.put_animation("one", DOC).unwrap();
        p.animations.push(Entry {
            id: "gone".into(),
            text: DOC.into(),
        });
        let mut files = BTreeMap::new();
        files.insert(MANIFEST.to_string(), p.manifest().to_string().into_bytes());
        files.insert("a/one.json".to_string(), DOC.as_bytes().to_vec());
        let missing = Package::from_files(files, "x.lottie").unwrap_err();
        assert_eq!(
            missing.to_string(),
            "x.lottie: the manifest names animation `gone`, but the package has no `a/gone.json`"
        );
        let err = p.pick(Some("nope"), "x.lottie").unwrap_err();
        assert!(err.to_string().contains("`one`, `gone`"), "{err}");
    }

    #[test]
    fn version_1_is_read_in_the_version_2_layout() {
        let mut files = BTreeMap::new();
        let manifest =
            r#"{"version":"1.0","activeAnimationId":"b","animations":[{"id":"a"},{"id":"b"}]}"#;
        files.insert(MANIFEST.to_string(), manifest.as_bytes().to_vec());
        files.insert("animations/a.json".into(), DOC.as_bytes().to_vec());
        let linked = r#"{"assets":[{"id":"i","u":"/images/","p":"x.png","e":0}],"layers":[]}"#;
        files.insert("animations/b.json".into(), linked.as_bytes().to_vec());
        let png = base64::engine::general_purpose::STANDARD
            .decode(PNG_1X1)
            .unwrap();
        files.insert("images/x.png".into(), png);
        let p = Package::from_files(files, "old.lottie").unwrap();
        assert_eq!(p.version, Version::V1);
        assert_eq!(p.pick(None, "old.lottie").unwrap().id, "b");
        assert!(p.animations[1].text.contains("\"/i/\""));
        let json = p.resolved(&p.animations[1], "old.lottie").unwrap();
        assert!(
            json["assets"][0]["p"]
                .as_str()
                .unwrap()
                .starts_with("data:image/png")
        );
    }
}
