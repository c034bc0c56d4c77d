//! The fonts text is drawn with, and what the user is told when a text's font is missing.
//!
//! usvg draws text with the fonts of a font database; a generic family (`sans-serif`) maps
//! to a named one, and a text whose families all fail to resolve is dropped without a word.
//! fontdb's generic families default to Windows fonts (`Times New Roman`, `Arial`), absent
//! from most Linux machines, so here each generic family maps to the first installed of a
//! list of common fonts: a `sans-serif` line is drawn, and a text in a missing font falls
//! back to the default family instead of vanishing, with a warning naming the font and
//! the element.

use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

use usvg::fontdb::Database;

/// Where fonts come from besides the system's, and the family used when a text's own
/// cannot be found (`--font-dir`, `--font-file`, `--font-family`, as resvg takes them).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FontOptions {
    /// Folders whose font files are loaded (recursively).
    pub dirs: Vec<PathBuf>,
    /// Font files loaded.
    pub files: Vec<PathBuf>,
    /// The family drawn when a text's families are not installed (default: the first
    /// installed of Arial, Helvetica, Liberation Sans, DejaVu Sans, Noto Sans, …).
    pub default_family: Option<String>,
}

/// Common sans-serif families, most wanted first.
const SANS_SERIF: &[&str] = &[
    "Arial",
    "Helvetica",
    "Liberation Sans",
    "DejaVu Sans",
    "Noto Sans",
    "Open Sans",
    "Roboto",
];

/// Common serif families.
const SERIF: &[&str] = &[
    "Times New Roman",
    "Times",
    "Liberation Serif",
    "DejaVu Serif",
    "Noto Serif",
];

/// Common monospace families.
const MONOSPACE: &[&str] = &[
    "Courier New",
    "Liberation Mono",
    "DejaVu Sans Mono",
    "Noto Sans Mono",
];

/// The font database for `opts`: the system fonts (scanned once per process) with the
/// extra folders and files, its generic families mapped to installed fonts.
pub fn database(opts: &FontOptions) -> Arc<Database> {
    static SYSTEM: OnceLock<Arc<Database>> = OnceLock::new();
    let plain = opts.dirs.is_empty() && opts.files.is_empty() && opts.default_family.is_none();
    if plain {
        return SYSTEM
            .get_or_init(|| Arc::new(mapped(system(), &FontOptions::default())))
            .clone();
    }
    let mut db = system();
    for dir in &opts.dirs {
        db.load_fonts_dir(dir);
    }
    for file in &opts.files {
        // A file that is not a font is reported by [`missing_files`]; fontdb skips it.
        let _ = db.load_font_file(file);
    }
    Arc::new(mapped(db, opts))
}

fn system() -> Database {
    let mut db = Database::new();
    db.load_system_fonts();
    db
}

/// Whether a family named `name` is installed in `db` (case aside, as CSS matches names).
pub fn installed(db: &Database, name: &str) -> bool {
    db.faces()
        .any(|f| f.families.iter().any(|(n, _)| n.eq_ignore_ascii_case(name)))
}

/// The first of `wanted` that `db` has, else any family it has.
fn first_installed(db: &Database, wanted: &[&str]) -> Option<String> {
    wanted
        .iter()
        .find(|w| installed(db, w))
        .map(|w| (*w).to_string())
        .or_else(|| {
            db.faces()
                .next()
                .and_then(|f| f.families.first())
                .map(|(n, _)| n.clone())
        })
}

/// `db` with each generic family set to an installed font, and `serif` (usvg's last
/// resort for any text) to the default family.
fn mapped(mut db: Database, opts: &FontOptions) -> Database {
    let sans = opts
        .default_family
        .clone()
        .filter(|f| installed(&db, f))
        .or_else(|| first_installed(&db, SANS_SERIF));
    let Some(sans) = sans else {
        return db; // no font at all: text is dropped, and said so
    };
    let serif = first_installed(&db, SERIF).unwrap_or_else(|| sans.clone());
    let mono = first_installed(&db, MONOSPACE).unwrap_or_else(|| sans.clone());
    db.set_sans_serif_family(sans.clone());
    db.set_cursive_family(sans.clone());
    db.set_fantasy_family(sans.clone());
    db.set_monospace_family(mono);
    // usvg appends `serif` to every text's families as its fallback: a missing font is
    // drawn in the default family, so serif maps to it unless a serif text asked for it.
    db.set_serif_family(if opts.default_family.is_some() {
        sans
    } else {
        serif
    });
    db
}

/// The family a text whose named families are all missing is drawn in.
pub fn fallback_family(db: &Database) -> String {
    db.family_name(&usvg::fontdb::Family::Serif).to_string()
}

/// The font options' files and folders that do not exist (reported as errors).
pub fn missing_files(opts: &FontOptions) -> Vec<PathBuf> {
    let files = opts.files.iter().filter(|f| !f.is_file());
    let dirs = opts.dirs.iter().filter(|d| !d.is_dir());
    files.chain(dirs).cloned().collect()
}
