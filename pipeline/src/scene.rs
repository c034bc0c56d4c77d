//! A scene imported from an SVG or Lottie file under a front end's choices (else the
//! grammar's, else the defaults), with the Lottie document it came from.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gmotion::engine::{EngineError, Settings};
use gmotion::scene::Scene;
use gmotion::{TagFrom, Units};
use gmotion_import_lottie as lottie_import;
use gmotion_import_svg::{self as svg_import, ImportOptions};
use gmotion_output::LottieSource;
use gmotion_output::dotlottie::{Package, Picked};

use crate::env::Env;
use crate::grammar::GrammarFile;
use crate::{Error, Result};

/// How a front end asks for a scene to be imported (`--tag-from`, `--units`,
/// `--unit-depth`, `--tags`, `--reference-time`); what it leaves out the grammar's header
/// decides, else the default.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportChoices {
    /// Where tags come from.
    pub tag_from: Option<TagFrom>,
    /// What the animated units are.
    pub units: Option<Units>,
    /// SVG scenes: how deep a group must sit to become a unit.
    pub unit_depth: Option<u32>,
    /// SVG scenes: a tag map file (relative to the working folder).
    pub tags: Option<PathBuf>,
    /// Lottie scenes: the time, in seconds, at which units are measured.
    pub reference_time: Option<f64>,
    /// dotLottie scenes: the id of the animation to read (default: the package's initial
    /// animation, else its first).
    pub animation: Option<String>,
    /// The front end sets the outputs' size (`--width`, `--height`): no image is drawn at
    /// the canvas's own size, so a canvas past the `pixels` limit is not worth a warning.
    pub sized: bool,
}

/// How to import a scene: as SVG, or as Lottie.
#[derive(Debug)]
pub struct SceneOptions {
    /// The SVG importer's options.
    pub svg: ImportOptions,
    /// The Lottie importer's options.
    pub lottie: lottie_import::ImportOptions,
    /// The grammar whose `reference_time` the Lottie import uses (its path, text and the
    /// directive's place), to blame for a time outside the composition.
    reference_from: Option<(PathBuf, String, gmotion::grammar::ast::Span)>,
    /// dotLottie scenes: the animation to read ([`ImportChoices::animation`]).
    animation: Option<String>,
    /// The outputs' size is set (by the front end or the grammar's `width`/`height`), not
    /// the canvas's own: the importer need not warn of a canvas too big to draw.
    sized: bool,
}

impl SceneOptions {
    /// The importer's options: `choices`, else `grammar`'s header, else the defaults. A
    /// tag map the grammar names is found beside the grammar (a missing one is an error
    /// at the directive) and read.
    pub fn new(
        choices: &ImportChoices,
        grammar: Option<&GrammarFile>,
        env: &Env,
    ) -> Result<SceneOptions> {
        let default = Settings::default();
        let settings = grammar.map_or(&default, |g| &g.settings);
        // The tag map: the front end's (relative to the working folder), else the
        // grammar's (relative to the grammar file, a missing one an error at the directive).
        let map_path = match (&choices.tags, grammar, &settings.tags) {
            (Some(p), _, _) => Some(p.clone()),
            (None, Some(g), Some((name, span))) => {
                let path = g.path.parent().unwrap_or(Path::new("")).join(name);
                if !path.exists() {
                    let e = EngineError::at(
                        *span,
                        format!("tag map `{name}` not found (looked for {})", path.display()),
                    );
                    return Err(g.error(&e));
                }
                Some(path)
            }
            _ => None,
        };
        let tag_map = map_path
            .map(|p| read_tag_map(&p, env).map(Arc::new))
            .transpose()?;
        let units = choices.units.or(settings.units).unwrap_or_default();
        Ok(SceneOptions {
            svg: ImportOptions {
                tag_from: choices.tag_from.or(settings.tag_from).unwrap_or_default(),
                units,
                unit_depth: choices
                    .unit_depth
                    .map(|d| d as usize)
                    .or(settings.unit_depth)
                    .unwrap_or(1),
                tag_map,
            },
            lottie: lottie_import::ImportOptions {
                time: choices
                    .reference_time
                    .or(settings.reference_time.as_ref().map(|(t, _)| *t)),
                max_image_pixels: env.limits.get("image-pixels"),
                allowed_dirs: env.allow.clone(),
                max_file_bytes: env.limits.get("input-bytes"),
                units: match units {
                    Units::Groups => lottie_import::Units::Groups,
                    Units::Auto | Units::Paths => lottie_import::Units::Layers,
                },
                fonts: Some({
                    let fonts = env.fonts.clone();
                    lottie_import::fonts::SystemFonts::new(move || {
                        svg_import::fonts::database(&fonts)
                    })
                }),
            },
            reference_from: match (choices.reference_time, grammar, &settings.reference_time) {
                (None, Some(g), Some((_, span))) => Some((g.path.clone(), g.src.clone(), *span)),
                _ => None,
            },
            animation: choices.animation.clone(),
            sized: choices.sized || settings.width.is_some() || settings.height.is_some(),
        })
    }
}

/// Reads and parses a tag map file.
fn read_tag_map(path: &Path, env: &Env) -> Result<svg_import::tagmap::TagMap> {
    let bytes = gmotion::input::read_regular(path, env.limits.get("input-bytes"))
        .map_err(|e| Error::msg(format!("{}: cannot read tag map: {e}", path.display())))?;
    let text = gmotion::input::utf8_text(bytes).map_err(|e| {
        Error::msg(format!(
            "{}:{e} (the tag map must be UTF-8)",
            path.display()
        ))
    })?;
    svg_import::tagmap::TagMap::parse(&text, &path.display().to_string())
        .map_err(|e| Error::msg(format!("{e}")))
}

/// A scene, and the Lottie document it came from when it came from one (shared: every
/// run of the scene draws it).
#[derive(Clone, Debug)]
pub struct Imported {
    /// The scene.
    pub scene: Scene,
    /// Its Lottie document.
    pub source: Option<Arc<LottieSource>>,
    /// The dotLottie package the document was read from, if it was, and which of its
    /// animations it is: a `.lottie` output keeps the others.
    pub package: Option<Arc<Picked>>,
}

/// Whether a scene file is a dotLottie package: by its `.lottie` extension, else by
/// starting as a zip archive does.
pub fn is_dotlottie(path: &Path) -> bool {
    if let Some(ext) = path.extension().and_then(|e| e.to_str()) {
        if ext.eq_ignore_ascii_case("lottie") {
            return true;
        }
        if ext.eq_ignore_ascii_case("json") || ext.eq_ignore_ascii_case("svg") {
            return false;
        }
    }
    if !matches!(gmotion::input::irregular_kind(path), Ok(None)) {
        return false;
    }
    let mut head = [0u8; 4];
    let n = std::fs::File::open(path)
        .and_then(|mut f| std::io::Read::read(&mut f, &mut head))
        .unwrap_or(0);
    Package::sniff(&head[..n])
}

/// Whether a scene file is Lottie: JSON by its `.json` extension or by starting with `{`
/// (an SVG starts with `<`), or a dotLottie package ([`is_dotlottie`]).
pub fn is_lottie(path: &Path) -> bool {
    if is_dotlottie(path) {
        return true;
    }
    if let Some(ext) = path.extension().and_then(|e| e.to_str()) {
        if ext.eq_ignore_ascii_case("json") {
            return true;
        }
        if ext.eq_ignore_ascii_case("svg") || ext.eq_ignore_ascii_case("svgz") {
            return false;
        }
    }
    if !matches!(gmotion::input::irregular_kind(path), Ok(None)) {
        return false;
    }
    let mut head = [0u8; 64];
    let n = std::fs::File::open(path)
        .and_then(|mut f| std::io::Read::read(&mut f, &mut head))
        .unwrap_or(0);
    String::from_utf8_lossy(&head[..n])
        .trim_start_matches('\u{feff}')
        .trim_start()
        .starts_with('{')
}

impl Imported {
    /// Imports the scene at `path` (Lottie or SVG, [`is_lottie`]) under `options`; the
    /// importer's warnings go to [`Env::warn`].
    pub fn load(path: &Path, options: &SceneOptions, env: &Env) -> Result<Imported> {
        if is_lottie(path) {
            return Imported::load_lottie(path, options, env);
        }
        let mut policy = env.svg_policy();
        if options.sized {
            policy.max_canvas_pixels = u64::MAX;
        }
        let imported = svg_import::load_with(path, &options.svg, &policy)
            .map_err(|e| Error::msg(e.to_string()))?;
        for w in &imported.warnings {
            (env.warn)(path, w);
        }
        if options.animation.is_some() {
            return Err(Error::msg(format!(
                "{}: error: --animation picks an animation of a dotLottie (.lottie) package; this scene is SVG",
                path.display()
            )));
        }
        Ok(Imported {
            scene: imported.scene,
            source: None,
            package: None,
        })
    }

    fn load_lottie(path: &Path, options: &SceneOptions, env: &Env) -> Result<Imported> {
        // Selectors and group depth speak of SVG elements; a Lottie's units are its layers.
        if let Some(map) = &options.svg.tag_map {
            return Err(Error::msg(format!(
                "{}: error: the tag map {} gives tags to SVG elements; a Lottie scene's units are its layers, tagged by their names",
                path.display(),
                map.source_name
            )));
        }
        if options.svg.units == Units::Paths {
            return Err(Error::msg(format!(
                "{}: error: --units paths splits SVG groups into their paths; a Lottie scene's units are its layers, or with --units groups the top-level groups of its shape layers",
                path.display()
            )));
        }
        if options.svg.unit_depth != 1 {
            return Err(Error::msg(format!(
                "{}: error: --unit-depth chooses SVG groups; a Lottie scene's units are its layers",
                path.display()
            )));
        }
        let (imported, package) = if is_dotlottie(path) {
            let (imported, picked) = Imported::read_package(path, options, env)?;
            (imported, Some(Arc::new(picked)))
        } else if options.animation.is_some() {
            return Err(Error::msg(format!(
                "{}: error: --animation picks an animation of a dotLottie (.lottie) package; this is a plain Lottie file with one",
                path.display()
            )));
        } else {
            (lottie_import::load(path, &options.lottie), None)
        };
        let imported = imported.map_err(|e| match (&e, &options.reference_from) {
            (lottie_import::ImportError::ReferenceTime { .. }, Some((grammar, src, span))) => {
                crate::grammar::located(grammar, src, &EngineError::at(*span, e.to_string()))
            }
            _ => Error::msg(e.to_string()),
        })?;
        for w in &imported.warnings {
            (env.warn)(path, w);
        }
        Ok(Imported {
            scene: imported.scene,
            source: Some(Arc::new(imported.source)),
            package,
        })
    }

    /// Reads the dotLottie package at `path` and imports the animation
    /// [`ImportChoices::animation`] names (else the package's initial one): the import's
    /// result, and the package with the id picked. The images the animation links from
    /// the package are put inline first, so it draws them.
    fn read_package(
        path: &Path,
        options: &SceneOptions,
        env: &Env,
    ) -> Result<(
        std::result::Result<lottie_import::Imported, lottie_import::ImportError>,
        Picked,
    )> {
        let name = path.display().to_string();
        let limit = env.limits.get("input-bytes");
        let bytes = gmotion::input::read_regular(path, limit)
            .map_err(|e| Error::msg(format!("{name}: error: cannot read the scene: {e}")))?;
        let package =
            Package::read(&bytes, &name, limit).map_err(|e| Error::msg(format!("error: {e}")))?;
        let entry = package
            .pick(options.animation.as_deref(), &name)
            .map_err(|e| Error::msg(format!("error: {e}")))?;
        let json = package
            .resolved(entry, &name)
            .map_err(|e| Error::msg(format!("error: {e}")))?;
        let source_name = format!("{name} (animation `{}`)", entry.id);
        let imported = lottie_import::from_json(json, &source_name, &options.lottie);
        let id = entry.id.clone();
        Ok((imported, Picked { package, id }))
    }

    /// Which `--tag-from` would name an SVG scene's shapes better, when most of its tags
    /// name nothing a designer chose (`st0`, `path`): finding out imports the scene at
    /// `path` again under each other source. `None` for a Lottie scene, whose tags are its
    /// layer names.
    pub fn tag_hint(&self, path: &Path, options: &SceneOptions, env: &Env) -> Option<String> {
        if self.source.is_some() {
            return None;
        }
        svg_import::tag_hint(path, &options.svg, &env.svg_policy(), &self.scene)
    }

    /// A scene to animate must draw something: said of the scene's file at `path`, not the
    /// grammar the engine would blame (the engine refuses an empty scene too).
    pub fn check_drawable(&self, path: &Path) -> Result<()> {
        if self.scene.shapes.is_empty() {
            return Err(Error::msg(format!(
                "{}: error: the drawing has no visible shapes to animate (hidden, empty and zero-size elements draw nothing)",
                path.display()
            )));
        }
        Ok(())
    }
}
