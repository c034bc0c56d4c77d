//! The live animation: the grammar text, its diagnostics, the last animation that built,
//! and the version the page polls.

use std::collections::HashMap;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard, OnceLock};
use std::time::{Duration, SystemTime};

use gmotion::Scene;
use gmotion::canvas::OutputSize;
use gmotion::engine::settings::Settings;
use gmotion::engine::{self, RunOptions};
use gmotion::grammar::ast::{Grammar, Span};
use gmotion::grammar::{self, diagnostics::Diagnostic};
use gmotion::tagging::{TagFrom, Units};
use gmotion_pipeline::{LottieSource, Picked, Rendered, Rescene, Writer};
use serde_json::{Value, json};

use crate::Config;

/// A grammar diagnostic as the page reads it: `line` and `column` 1-based (0 when the
/// problem has no place), the byte range `start..end`, the `expected` alternatives (already
/// quoted) and the `help` (`null` without one; lines separated by `\n`).
pub(crate) fn diagnostic_json(d: &Diagnostic) -> Value {
    json!({
        "line": d.span.line,
        "column": d.span.col,
        "start": d.span.start,
        "end": d.span.end,
        "message": d.message,
        "expected": d.expected,
        "help": d.help,
    })
}

/// An animation that built (with the Lottie source its scene came from), with what the
/// page asks about it.
#[derive(Debug)]
pub(crate) struct Built {
    pub rendered: Rendered,
    pub grammar: Grammar,
    pub size: OutputSize,
    /// The scene (and its Lottie source) it was built on.
    pub scene: Arc<Imported>,
    /// `/api/state`'s shapes and timelines, made on first request.
    state: OnceLock<(Value, Value)>,
}

/// A scene as imported, with the Lottie document it came from, if any.
#[derive(Debug)]
pub(crate) struct Imported {
    pub scene: Scene,
    pub source: Option<Arc<LottieSource>>,
    /// The dotLottie package the source came from, if it did.
    pub package: Option<Arc<Picked>>,
    /// The grammar settings it was imported under ([`ImportKey`]).
    key: ImportKey,
}

/// The grammar settings that decide how the scene is imported: when an edit changes them,
/// the scene is imported again.
#[derive(Clone, Debug, PartialEq)]
struct ImportKey {
    scene: Option<String>,
    tag_from: Option<TagFrom>,
    units: Option<Units>,
    unit_depth: Option<usize>,
    tags: Option<String>,
}

impl ImportKey {
    fn of(s: &Settings) -> ImportKey {
        ImportKey {
            scene: s.scene.as_ref().map(|(p, _)| p.clone()),
            tag_from: s.tag_from,
            units: s.units,
            unit_depth: s.unit_depth,
            tags: s.tags.as_ref().map(|(p, _)| p.clone()),
        }
    }
}

#[derive(Debug)]
struct State {
    text: String,
    diagnostics: Vec<Diagnostic>,
    good: Arc<Built>,
    version: u64,
    /// The grammar file's modification time and length when last read or written.
    stamp: Option<(SystemTime, u64)>,
    /// Variations of the current version, by seed.
    seeds: HashMap<u64, Arc<Built>>,
    /// The text last read from or written to the grammar file: the page's edits are
    /// unsaved while `text` differs from it, and Save writes only over this text.
    disk: String,
    /// The file's text when it changed on disk while the page had unsaved edits: kept
    /// beside them until the page chooses ([`Live::resolve`]), never applied over them.
    conflict: Option<String>,
}

/// The live state at one instant (see [`Live::snapshot`]).
#[derive(Debug)]
pub(crate) struct Snapshot {
    pub version: u64,
    /// The last animation that built.
    pub good: Arc<Built>,
    /// The text's diagnostics as JSON.
    pub diagnostics: Value,
    pub text: String,
    /// Whether the text differs from the file's.
    pub unsaved: bool,
    /// The file's new text under unsaved edits, until resolved.
    pub conflict: Option<String>,
}

/// Why [`Live::save`] did not write.
#[derive(Debug)]
pub enum SaveError {
    /// The file changed on disk since it was last read: writing would lose that change.
    /// The new text on disk is now the pending conflict.
    Changed,
    /// The file could not be written.
    Io(io::Error),
}

/// How the page settles a conflict between its unsaved text and the file's new text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resolution {
    /// Keep the page's text (the next Save writes it over the file's).
    Mine,
    /// Replace the page's text with the file's.
    Theirs,
}

/// Why [`Live::merge`] left the page's text as it was.
#[derive(Debug, PartialEq, Eq)]
pub enum MergeError {
    /// There was no conflict to settle.
    NoConflict,
    /// A text is longer than [`MAX_MERGE_LINES`]: a line diff of two large, unrelated texts
    /// takes time quadratic in their length, which the page's request must not wait for.
    TooLarge,
    /// Both sides changed the same lines, at this many places; the conflict stays pending
    /// (no conflict markers are ever written into the text).
    Overlap(usize),
}

/// The most lines a text may have for [`Live::merge`] to merge it.
pub const MAX_MERGE_LINES: usize = 20_000;

/// The studio's live state, shared by the request threads and the file watcher.
#[derive(Debug)]
pub struct Live {
    grammar_path: PathBuf,
    /// The scene new builds run on.
    imported: Mutex<Arc<Imported>>,
    rescene: Option<Rescene>,
    /// The scene file as last imported, watched so that an edit to it (the art saved
    /// again in its design tool) is imported again; `None` without a `rescene`.
    scene_file: Mutex<SceneFile>,
    run: RunOptions,
    state: Mutex<State>,
    /// Serialises builds, so edits apply in the order they arrive.
    building: Mutex<()>,
}

/// The scene file a studio runs on and its modification stamp when last looked at.
#[derive(Debug, Default)]
struct SceneFile {
    path: Option<PathBuf>,
    stamp: Option<(SystemTime, u64)>,
    /// The file changed since it was last imported: the next build imports it again.
    stale: bool,
}

/// The most variations kept built at once.
const MAX_SEEDS: usize = 64;

/// Runs `text` on the scene, with `seed` over the grammar's.
/// Every shape of `scene` as `/api/state` and `gmotion check --shapes --json` list them:
/// `[{tag, aliases, id, z, bbox: [x, y, w, h], centroid: [x, y]}]`, in scene order
/// (`aliases`: the other tags the shape answers to, such as its element's id).
pub fn shapes_json(scene: &Scene) -> Value {
    scene
        .shapes
        .iter()
        .map(|s| {
            let own = s.aliases.len() - s.inherited;
            json!({
                "tag": s.tag,
                "aliases": s.aliases[..own],
                "follows": s.aliases[own..],
                "rig": s.rig,
                "id": s.id,
                "z": s.z,
                "bbox": [s.bbox.x0, s.bbox.y0, s.bbox.width(), s.bbox.height()],
                "centroid": [s.centroid.x, s.centroid.y],
            })
        })
        .collect()
}

/// The changes playing on slice `s` as `[[from, to], …]` seconds, clipped to the slice
/// (keyframe ticks on the timeline; a forward change's `from` is what a drag moves).
fn changes_json(s: &gmotion::engine::expand::Slice) -> Value {
    let (t0, t1) = (s.t0, s.t0 + s.dur);
    let mut out: Vec<(f64, f64)> = Vec::new();
    for a in s.anims.iter() {
        let (from, to) = a.timing().active();
        let (from, to) = (from.max(t0), to.min(t1));
        if from < to && !out.contains(&(from, to)) {
            out.push((from, to));
        }
    }
    out.into_iter().map(|(a, b)| json!([a, b])).collect()
}

/// `text` parsed, with its settings: every syntax error, else every error of meaning
/// found without a scene (as `gmotion check` reports them).
fn parse(text: &str) -> Result<(Grammar, Settings), Vec<Diagnostic>> {
    let grammar = grammar::parse(text).map_err(|ds| {
        let mut items = ds.items;
        // Past the first hundred, errors are counted (as `gmotion check` prints them).
        if ds.omitted > 0 {
            items.push(Diagnostic::general(format!(
                "… {} more errors not shown (the first {} are)",
                ds.omitted,
                grammar::diagnostics::MAX_SHOWN
            )));
        }
        items
    })?;
    let settings =
        engine::settings::from_grammar(&grammar).map_err(|e| vec![Diagnostic::from(&e)])?;
    let errors = engine::check::static_errors(&grammar);
    if !errors.is_empty() {
        return Err(errors.iter().map(Diagnostic::from).collect());
    }
    Ok((grammar, settings))
}

/// Runs `grammar` on `imported`.
fn build(
    imported: Arc<Imported>,
    run: &RunOptions,
    (grammar, settings): (Grammar, Settings),
) -> Result<Built, Vec<Diagnostic>> {
    let (anim, stats) = engine::run(imported.scene.clone(), &grammar, run)
        .map_err(|e| vec![Diagnostic::from(&e)])?;
    Ok(Built {
        rendered: Rendered {
            anim,
            source: imported.source.clone(),
            package: imported.package.clone(),
            markers: stats.markers,
            slots: stats.slots,
            timelines: None,
        },
        grammar,
        size: OutputSize {
            width: settings.width,
            height: settings.height,
        },
        scene: imported,
        state: OnceLock::new(),
    })
}

fn stamp(path: &Path) -> Option<(SystemTime, u64)> {
    let m = std::fs::metadata(path).ok()?;
    Some((m.modified().ok()?, m.len()))
}

impl Live {
    /// Reads the grammar file and builds it; a grammar that does not build leaves the
    /// scene still, with the grammar's diagnostics.
    pub fn new(config: Config) -> io::Result<Live> {
        let text = std::fs::read_to_string(&config.grammar_path)?;
        let text_on_disk = text.clone();
        let stamp = stamp(&config.grammar_path);
        let parsed = parse(&text);
        let scene_path = config.rescene.as_ref().and_then(|r| {
            let settings = parsed
                .as_ref()
                .map_or_else(|_| Settings::default(), |p| p.1.clone());
            r.scene_path(&settings)
        });
        let scene_file = SceneFile {
            stamp: scene_path.as_deref().and_then(self::stamp),
            path: scene_path,
            stale: false,
        };
        let imported = Arc::new(Imported {
            scene: config.imported.scene,
            source: config.imported.source,
            package: config.imported.package,
            // The scene was imported under the grammar as it was at start.
            key: match &parsed {
                Ok((_, settings)) => ImportKey::of(settings),
                Err(_) => ImportKey::of(&Settings::default()),
            },
        });
        let (good, diagnostics) = match parsed.and_then(|p| build(imported.clone(), &config.run, p))
        {
            Ok(b) => (b, Vec::new()),
            // The scene still, under an empty grammar.
            Err(d) => match parse("").and_then(|p| build(imported.clone(), &config.run, p)) {
                Ok(still) => (still, d),
                Err(e) => {
                    let why = e.first().map_or("", |e| e.message.as_str());
                    return Err(io::Error::other(format!("the scene does not run: {why}")));
                }
            },
        };
        Ok(Live {
            grammar_path: config.grammar_path,
            imported: Mutex::new(imported),
            rescene: config.rescene,
            scene_file: Mutex::new(scene_file),
            run: config.run,
            state: Mutex::new(State {
                text,
                diagnostics,
                good: Arc::new(good),
                version: 1,
                stamp,
                seeds: HashMap::new(),
                disk: text_on_disk,
                conflict: None,
            }),
            building: Mutex::new(()),
        })
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Replaces the grammar text; the animation is replaced (and the version bumped) only
    /// when the text builds and differs from the current text. Returns the version and the
    /// text's diagnostics.
    pub fn set_text(&self, text: String) -> (u64, Vec<Diagnostic>) {
        // With `keep_broken`, errors come back as the text's diagnostics.
        match self.apply(text, true) {
            Ok(done) => done,
            Err(d) => (self.version(), d),
        }
    }

    /// Applies `text` as [`Live::set_text`] does, or, unless `keep_broken`, leaves the
    /// current text as it is when `text` has errors and returns them: the studio's own
    /// edits (retime) never leave a grammar that does not build.
    fn apply(
        &self,
        text: String,
        keep_broken: bool,
    ) -> Result<(u64, Vec<Diagnostic>), Vec<Diagnostic>> {
        let _b = self.building.lock().unwrap_or_else(|p| p.into_inner());
        {
            let st = self.lock();
            if st.text == text {
                return Ok((st.version, st.diagnostics.clone()));
            }
        }
        self.build_text(text, keep_broken)
    }

    /// Builds `text` as [`Live::set_text`] does even when it is the current text (the
    /// scene changed under it).
    fn apply_forced(&self, text: String) -> Result<(u64, Vec<Diagnostic>), Vec<Diagnostic>> {
        let _b = self.building.lock().unwrap_or_else(|p| p.into_inner());
        self.build_text(text, true)
    }

    /// The build behind [`Live::apply`], run under the `building` lock.
    fn build_text(
        &self,
        text: String,
        keep_broken: bool,
    ) -> Result<(u64, Vec<Diagnostic>), Vec<Diagnostic>> {
        let built = parse(&text).and_then(|(grammar, settings)| {
            let imported = self.imported_for(&settings)?;
            build(imported, &self.run, (grammar, settings))
        });
        let mut st = self.lock();
        match built {
            Ok(b) => {
                st.good = Arc::new(b);
                st.diagnostics.clear();
                st.seeds.clear();
                st.version += 1;
            }
            Err(d) if !keep_broken => return Err(d),
            Err(d) => st.diagnostics = d,
        }
        st.text = text;
        Ok((st.version, st.diagnostics.clone()))
    }

    /// The scene for a grammar with `settings`: the current one, or, when the settings
    /// that decide the import changed (`scene`, `tag_from`, `units`, `unit_depth`, `tags`),
    /// the scene imported again under them (which becomes the current one).
    fn imported_for(&self, settings: &Settings) -> Result<Arc<Imported>, Vec<Diagnostic>> {
        let mut current = self.imported.lock().unwrap_or_else(|p| p.into_inner());
        let key = ImportKey::of(settings);
        let stale = self.scene_file().stale;
        let Some(rescene) = self
            .rescene
            .as_ref()
            .filter(|_| stale || current.key != key)
        else {
            return Ok(Arc::clone(&current));
        };
        let path = rescene.scene_path(settings);
        // Stamped before reading: a save landing while the import runs is seen next time.
        let seen = path.as_deref().and_then(stamp);
        let again = rescene.import(settings).map_err(|why| {
            let first = Span {
                line: 1,
                col: 1,
                ..Span::default()
            };
            let message = if stale {
                format!(
                    "the scene file changed and could not be imported: {why}; the last \
                     animation that built stays until it can"
                )
            } else {
                format!("the scene could not be imported under these settings: {why}")
            };
            vec![Diagnostic::new(first, message)]
        })?;
        *self.scene_file() = SceneFile {
            path,
            stamp: seen,
            stale: false,
        };
        let (scene, source, package) = (again.scene, again.source, again.package);
        *current = Arc::new(Imported {
            scene,
            source,
            package,
            key,
        });
        Ok(Arc::clone(&current))
    }

    fn scene_file(&self) -> MutexGuard<'_, SceneFile> {
        self.scene_file.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Imports the scene again when its file changed since it was last imported (or
    /// since the last look, while it cannot be), and builds the current text on it: the
    /// art saved again in its design tool shows in the page. A scene deleted or broken
    /// meanwhile leaves the last animation that built, with a diagnostic saying why.
    fn follow_scene(&self) {
        {
            let mut file = self.scene_file();
            let Some(path) = file.path.as_deref() else {
                return;
            };
            let now = stamp(path);
            if now == file.stamp {
                return;
            }
            file.stamp = now;
            file.stale = true;
        }
        let text = self.text();
        // Through `apply` with the text it already has: forced, as only the scene changed.
        let _ = self.apply_forced(text);
    }

    /// What the page polls, read under one lock so that the version, text and
    /// diagnostics answered belong together (read one by one, an edit landing between two
    /// reads paired a version with another version's text).
    pub(crate) fn snapshot(&self) -> Snapshot {
        let st = self.lock();
        Snapshot {
            version: st.version,
            good: Arc::clone(&st.good),
            diagnostics: Value::Array(st.diagnostics.iter().map(diagnostic_json).collect()),
            text: st.text.clone(),
            unsaved: st.text != st.disk,
            conflict: st.conflict.clone(),
        }
    }

    /// The current version.
    pub fn version(&self) -> u64 {
        self.lock().version
    }

    /// The current text.
    pub fn text(&self) -> String {
        self.lock().text.clone()
    }

    /// The last animation that built.
    pub(crate) fn good(&self) -> Arc<Built> {
        Arc::clone(&self.lock().good)
    }

    /// The last good animation's grammar run with `seed` over its own (built once per
    /// version).
    pub(crate) fn with_seed(&self, seed: u64) -> Result<Arc<Built>, String> {
        let (good, version) = {
            let st = self.lock();
            if let Some(b) = st.seeds.get(&seed) {
                return Ok(Arc::clone(b));
            }
            (Arc::clone(&st.good), st.version)
        };
        let run = RunOptions {
            seed: Some(seed),
            ..self.run.clone()
        };
        let (anim, stats) = engine::run(good.scene.scene.clone(), &good.grammar, &run)
            .map_err(|e| e.to_string())?;
        let built = Arc::new(Built {
            rendered: Rendered {
                anim,
                source: good.scene.source.clone(),
                package: good.scene.package.clone(),
                markers: stats.markers,
                slots: stats.slots,
                timelines: None,
            },
            grammar: good.grammar.clone(),
            size: good.size,
            scene: Arc::clone(&good.scene),
            state: OnceLock::new(),
        });
        let mut st = self.lock();
        if st.version == version {
            if st.seeds.len() >= MAX_SEEDS {
                st.seeds.clear();
            }
            st.seeds.insert(seed, Arc::clone(&built));
        }
        Ok(built)
    }

    /// `/api/state`'s shapes and timelines of `built`.
    pub(crate) fn shapes_and_timelines(&self, built: &Built) -> (Value, Value) {
        built
            .state
            .get_or_init(|| {
                let shapes = shapes_json(&built.rendered.anim.scene);
                let timelines = match engine::timelines(&built.scene.scene, &built.grammar, &self.run) {
                    Ok(x) => x
                        .timelines
                        .iter()
                        .map(|tl| {
                            tl.iter()
                                .map(|s| {
                                    json!({
                                        "tag": x.slice_tags.get(s.tag as usize).map_or("?", |t| t.as_str()),
                                        "start": s.t0,
                                        "end": s.t0 + s.dur,
                                        "inverted": s.inverted,
                                        "changes": changes_json(s),
                                    })
                                })
                                .collect()
                        })
                        .collect(),
                    // The still scene: one `all` slice per shape.
                    Err(_) => built
                        .rendered
                        .anim
                        .scene
                        .shapes
                        .iter()
                        .map(|_| json!([{"tag": "all", "start": 0.0, "end": built.rendered.anim.duration, "inverted": false}]))
                        .collect(),
                };
                (shapes, Value::Array(timelines))
            })
            .clone()
    }

    /// `built` as `ext` (`json` Lottie, `svg` SMIL, `html` the page, `png` the frame at
    /// `time`, `gif`), straight from the pipeline's writer: the bytes, or why not.
    pub(crate) fn export(&self, built: &Built, ext: &str, time: f64) -> Result<Vec<u8>, String> {
        self.export_sized(built, ext, time, built.size)
    }

    /// [`Live::export`] at `size` (a frame drawn at the size the page shows it).
    pub(crate) fn export_sized(
        &self,
        built: &Built,
        ext: &str,
        time: f64,
        size: OutputSize,
    ) -> Result<Vec<u8>, String> {
        let mut writer = Writer::new(size, &gmotion_pipeline::Limits::default());
        writer.options.time = time;
        let named = Path::new("studio").with_extension(ext);
        let bytes = if ext == "html" {
            // The page's timeline: the slices, which a build does not keep.
            let page = Rendered {
                timelines: engine::timelines(&built.scene.scene, &built.grammar, &self.run).ok(),
                ..built.rendered.clone()
            };
            writer.bytes(&page, &named)
        } else {
            writer.bytes(&built.rendered, &named)
        };
        bytes.map(|(b, _)| b).map_err(|e| e.to_string())
    }

    /// The Lottie JSON of the live animation (what `GET /api/lottie` answers).
    pub fn lottie(&self) -> Result<Vec<u8>, String> {
        self.export(&self.good(), "json", 0.0)
    }

    /// Whether the text differs from the file's (as last read or written).
    pub fn unsaved(&self) -> bool {
        let st = self.lock();
        st.text != st.disk
    }

    /// The file's new text when it changed on disk under unsaved edits, until resolved.
    pub fn conflict(&self) -> Option<String> {
        self.lock().conflict.clone()
    }

    /// Settles the pending conflict: `Mine` keeps the text (the file's text counts as
    /// read, so the next Save may write over it), `Theirs` takes the file's text. Returns
    /// false when there was no conflict.
    pub fn resolve(&self, how: Resolution) -> bool {
        let theirs = {
            let mut st = self.lock();
            let Some(theirs) = st.conflict.take() else {
                return false;
            };
            st.disk = theirs.clone();
            theirs
        };
        if how == Resolution::Theirs {
            self.set_text(theirs);
        }
        true
    }

    /// Settles the pending conflict by a three-way merge: the changes the page made to the
    /// text last read from the file, and those the file's new text made to it, both kept
    /// (line by line). When they touch the same lines nothing changes and the conflict
    /// stays pending for keep mine or take theirs. On success the file's new text counts
    /// as read, and the merged text is the page's, unsaved.
    pub fn merge(&self) -> Result<(), MergeError> {
        let merged = {
            let mut st = self.lock();
            let Some(theirs) = st.conflict.as_deref() else {
                return Err(MergeError::NoConflict);
            };
            let texts = [st.disk.as_str(), st.text.as_str(), theirs];
            if texts.iter().any(|t| t.lines().count() > MAX_MERGE_LINES) {
                return Err(MergeError::TooLarge);
            }
            let merged = diffy::merge(texts[0], texts[1], texts[2]).map_err(|marked| {
                MergeError::Overlap(marked.lines().filter(|l| l.starts_with("<<<<<<<")).count())
            })?;
            st.disk = st.conflict.take().unwrap_or_default();
            merged
        };
        self.set_text(merged);
        Ok(())
    }

    /// Writes the current text to the grammar file (atomically) and returns the path;
    /// refuses ([`SaveError::Changed`]) when the file's text is no longer the text last
    /// read from it, whether or not the watcher has seen the change yet, so an edit made
    /// elsewhere is never overwritten without the page choosing to.
    pub fn save(&self) -> Result<&Path, SaveError> {
        // One save at a time, and none beside a build. The file is read and written outside
        // the state's lock: the write ends in an fsync, and `/api/status` would wait for it.
        let _b = self.building.lock().unwrap_or_else(|p| p.into_inner());
        let now = read_text(&self.grammar_path);
        let (text, before) = {
            let mut st = self.lock();
            if let Some(now) = now
                && now != st.disk
            {
                if now != st.text {
                    st.conflict = Some(now);
                    return Err(SaveError::Changed);
                }
                // The file already holds this text: nothing would be lost.
                st.disk = now;
            }
            if st.conflict.is_some() {
                return Err(SaveError::Changed);
            }
            // Counted as the file's text already, so that the watcher, seeing the file
            // change under it, takes the change for this save and not for a conflict.
            let text = st.text.clone();
            let before = std::mem::replace(&mut st.disk, text.clone());
            (text, before)
        };
        let written = gmotion::atomic::write_bytes(&self.grammar_path, text.as_bytes());
        let mut st = self.lock();
        if let Err(e) = written {
            if st.disk == text {
                st.disk = before;
            }
            return Err(SaveError::Io(e));
        }
        st.stamp = stamp(&self.grammar_path);
        Ok(&self.grammar_path)
    }

    /// Polls the grammar file every 300 ms and takes in its text when its modification
    /// time or length changes, unless the page has unsaved edits: then the file's text
    /// becomes a conflict for the page to settle. Polling rather than a file-watcher
    /// crate: one `stat` a third of a second costs nothing, needs no dependency, and sees
    /// the atomic rename-over that editors (and `save`) do, which inotify watches on the
    /// file lose.
    pub fn watch(&self) -> ! {
        loop {
            std::thread::sleep(Duration::from_millis(300));
            self.follow_scene();
            let now = stamp(&self.grammar_path);
            if now.is_none() || now == self.lock().stamp {
                continue;
            }
            let Some(text) = read_text(&self.grammar_path) else {
                continue;
            };
            let take = {
                let mut st = self.lock();
                st.stamp = now;
                if text == st.disk || text == st.text {
                    st.disk = text.clone();
                    st.conflict = None;
                    false
                } else if st.text == st.disk {
                    st.disk = text.clone();
                    true
                } else {
                    st.conflict = Some(text.clone());
                    false
                }
            };
            if take {
                self.set_text(text);
            }
        }
    }

    /// Moves the boundary between slices `boundary` and `boundary + 1` of shape `shape`
    /// to `time` seconds by rewriting the `timesplit` fractions that put it there (see
    /// `retime`), and applies the new text as an edit: the text, its version and
    /// diagnostics, the rule's line and its new fractions; or why not.
    pub(crate) fn retime(
        &self,
        shape: usize,
        boundary: usize,
        time: f64,
    ) -> Result<(crate::retime::Retimed, u64, Vec<Diagnostic>), String> {
        let text = self.text();
        let good = self.good();
        if !self.lock().diagnostics.is_empty() {
            return Err("the grammar has errors: fix them before retiming".into());
        }
        let (grammar, _) = parse(&text).map_err(|_| "the grammar has errors".to_string())?;
        let done = crate::retime::retime(
            &text,
            &grammar,
            &good.scene.scene,
            &self.run,
            (shape, boundary, time),
        )?;
        let (version, diagnostics) = self.apply(done.text.clone(), false).map_err(|d| {
            let why = d.first().map_or("", |d| d.message.as_str());
            format!("that time would break the grammar ({why}); the text is unchanged")
        })?;
        Ok((done, version, diagnostics))
    }

    /// Makes the forward change on slice `slice` of shape `shape` that starts at `from`
    /// seconds start at `time` by rewriting its `animate` rule's offset (see `offset`),
    /// applied as an edit only when the result builds: the text, the version and the
    /// rule's line and new offset; or why not.
    pub(crate) fn move_offset(
        &self,
        target: (usize, usize, f64, f64),
    ) -> Result<(crate::offset::Moved, u64), String> {
        let text = self.text();
        let good = self.good();
        if !self.lock().diagnostics.is_empty() {
            return Err("the grammar has errors: fix them before moving a change".into());
        }
        let (grammar, _) = parse(&text).map_err(|_| "the grammar has errors".to_string())?;
        let done =
            crate::offset::move_offset(&text, &grammar, &good.scene.scene, &self.run, target)?;
        let (version, _) = self.apply(done.text.clone(), false).map_err(|d| {
            let why = d.first().map_or("", |d| d.message.as_str());
            format!("that time would break the grammar ({why}); the text is unchanged")
        })?;
        Ok((done, version))
    }

    /// The `animate` rules that change shape `shape` in the slice under time `t` (see
    /// `value::rules_at`): what a drag on the canvas rewrites; or why not.
    pub(crate) fn rules_at(&self, shape: usize, t: f64) -> Result<Value, String> {
        let text = self.text();
        let good = self.good();
        if !self.lock().diagnostics.is_empty() {
            return Err("the grammar has errors: fix them before editing on the canvas".into());
        }
        let (grammar, _) = parse(&text).map_err(|_| "the grammar has errors".to_string())?;
        crate::value::rules_at(&text, &grammar, &good.scene.scene, &self.run, (shape, t))
    }

    /// Replaces argument `arg` of the `animate` rule on line `line` by `new` (see
    /// `value::set_value`), applied as an edit only when the result builds: the text, the
    /// version, the rule's line and the value written; or why not.
    pub(crate) fn set_value(
        &self,
        (line, arg, new): (u32, crate::value::Arg, &str),
    ) -> Result<(crate::value::Set, u64), String> {
        let text = self.text();
        if !self.lock().diagnostics.is_empty() {
            return Err("the grammar has errors: fix them before setting a value".into());
        }
        let (grammar, _) = parse(&text).map_err(|_| "the grammar has errors".to_string())?;
        let done = crate::value::set_value(&text, &grammar, (line, arg, new))?;
        let (version, _) = self.apply(done.text.clone(), false).map_err(|d| {
            let why = d.first().map_or("", |d| d.message.as_str());
            format!(
                "`{}` would break the grammar ({why}); the text is unchanged",
                done.value
            )
        })?;
        Ok((done, version))
    }

    /// Every shape's bounding box at `t` (the frame shown, for hit-testing), `None` for a
    /// shape that is invisible then: the rest box moved by the shape's transform at `t`.
    pub(crate) fn boxes_at(built: &Built, t: f64) -> Value {
        let anim = &built.rendered.anim;
        anim.scene
            .shapes
            .iter()
            .zip(&anim.tracks)
            .map(|(shape, track)| {
                let state = track.state_at(t);
                if state.opacity <= 0.0 {
                    return Value::Null;
                }
                let b = state.transform.transform_rect_bbox(shape.bbox);
                json!([b.x0, b.y0, b.width(), b.height()])
            })
            .collect()
    }
}

/// The grammar file's text, `None` when it cannot be read as UTF-8 (gone, or a partial
/// write): the watcher tries again on the next change.
fn read_text(path: &Path) -> Option<String> {
    std::fs::read_to_string(path).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The diagnostics of `text` as the page receives them.
    fn page(text: &str) -> Vec<Value> {
        parse(text)
            .err()
            .unwrap()
            .iter()
            .map(diagnostic_json)
            .collect()
    }

    #[test]
    fn every_error_of_meaning_reaches_the_page_with_its_help() {
        let d = page(
            "duration 2s\n\
             timesplit(0.5, 0.6) : [all, s] -> [a, b]\n\
             animate(opacity, local, 0, 2) : [a, s] -> [m]\n\
             animate(afine, world, 0, translate(1, 0)) : [b, s] -> [n]\n",
        );
        let at: Vec<(u64, u64)> = d
            .iter()
            .map(|x| (x["line"].as_u64().unwrap(), x["column"].as_u64().unwrap()))
            .collect();
        assert_eq!(at, vec![(2, 1), (3, 28), (4, 9)], "{d:?}");
        assert_eq!(d[2]["help"], "did you mean `affine`?", "{d:?}");
        assert!(d[2]["end"].as_u64() > d[2]["start"].as_u64(), "{d:?}");
    }

    #[test]
    fn a_flood_of_errors_shows_the_first_hundred_and_counts_the_rest() {
        let text: String = (0..250).map(|i| format!("zzz @@ {i}\n")).collect();
        let d = page(&text);
        assert_eq!(d.len(), 101, "{:?}", &d[..3]);
        assert_eq!(d[99]["line"], 100);
        assert_eq!(d[100]["line"], 0);
        assert!(
            d[100]["message"]
                .as_str()
                .unwrap()
                .contains("150 more errors"),
            "{:?}",
            d[100]
        );
    }

    #[test]
    fn syntax_errors_keep_what_was_expected() {
        let d = page("duration 2s\ntimesplit(0.5 : [all, s]\n");
        assert_eq!(d[0]["line"], 2, "{d:?}");
        let expected = d[0]["expected"].as_array().unwrap();
        assert!(!expected.is_empty(), "{d:?}");
    }
}
