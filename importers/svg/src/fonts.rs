//! The fonts text is drawn with, and what the user is told when a text's font is missing.
//!
//! usvg draws text with the fonts of a font database; a generic family (`sans-serif`) maps
//! to a named one, and a text whose families all fail to resolve is dropped without a word.
//! fontdb's generic families default to Windows fonts (`Times New Roman`, `Arial`), absent
//! from most Linux machines, so here each generic family maps to the first installed of a
//! list of common fonts: a `sans-serif` line is drawn, and a text in a missing font falls
//! back to the generic family it most likely belongs to ([`fallback_for`]: a missing Arial
//! or Montserrat is drawn sans-serif, a missing Georgia serif) instead of vanishing, with
//! a warning naming the font and the element.

use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

use usvg::fontdb::{Database, Family, Query, Stretch, Style, Weight};

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
    // With `--font-family`, every text in a missing font is drawn in it ([`fallback_for`]
    // sends them all to sans-serif, which is that family), and so is usvg's last resort.
    db.set_serif_family(if opts.default_family.is_some() {
        sans
    } else {
        serif
    });
    db
}

/// Serif families a text may name: missing, they fall back to the serif family.
const KNOWN_SERIF: &[&str] = &[
    "Times New Roman",
    "Times",
    "Georgia",
    "Garamond",
    "EB Garamond",
    "Baskerville",
    "Palatino",
    "Palatino Linotype",
    "Book Antiqua",
    "Cambria",
    "Constantia",
    "Didot",
    "Bodoni",
    "Bodoni 72",
    "Caslon",
    "Minion Pro",
    "Century",
    "Century Schoolbook",
    "Cochin",
    "Hoefler Text",
    "Merriweather",
    "Lora",
    "Playfair Display",
    "Libre Baskerville",
    "Crimson Text",
    "Cormorant",
];

/// Monospace families a text may name: missing, they fall back to the monospace family.
const KNOWN_MONOSPACE: &[&str] = &[
    "Courier",
    "Courier New",
    "Consolas",
    "Menlo",
    "Monaco",
    "Lucida Console",
    "Andale Mono",
    "Source Code Pro",
    "Fira Code",
    "Fira Mono",
    "JetBrains Mono",
    "Inconsolata",
];

/// The generic family a missing named family falls back to: serif for a serif family
/// (known by name, or `… Serif` without `Sans`), monospace for a monospace one, else
/// sans-serif, as most fonts in designs are (Arial, Helvetica, Montserrat, Roboto); with
/// `--font-family` always that family, which sans-serif is mapped to. Names as exports
/// write them count too: Illustrator's PostScript names (`Georgia-Bold`,
/// `TimesNewRomanPSMT`, `Montserrat-SemiBold`) are read up to the style after the hyphen.
///
/// ```
/// use gmotion_import_svg::fonts::{FontOptions, fallback_for};
/// use usvg::fontdb::Family;
/// let opts = FontOptions::default();
/// assert_eq!(fallback_for("Montserrat-SemiBold", &opts), Family::SansSerif);
/// assert_eq!(fallback_for("TimesNewRomanPSMT", &opts), Family::Serif);
/// ```
pub fn fallback_for(family: &str, opts: &FontOptions) -> Family<'static> {
    if opts.default_family.is_some() {
        return Family::SansSerif;
    }
    // Compared without case, blanks and the `PS`/`MT` marks of PostScript names, so
    // `TimesNewRomanPSMT` and `MinionPro-Regular` are Times New Roman and Minion Pro.
    let key = |name: &str| {
        let k: String = name
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_ascii_lowercase();
        let k = k.strip_suffix("mt").unwrap_or(&k);
        k.strip_suffix("ps").unwrap_or(k).to_string()
    };
    let base = key(family.split('-').next().unwrap_or(family));
    let is = |list: &[&str]| list.iter().any(|k| key(k) == base || key(k) == key(family));
    let lower = family.to_ascii_lowercase();
    if is(KNOWN_SERIF) || (lower.contains("serif") && !lower.contains("sans")) {
        Family::Serif
    } else if is(KNOWN_MONOSPACE) || lower.contains("mono") || lower.contains(" code") {
        Family::Monospace
    } else {
        Family::SansSerif
    }
}

/// The family a text whose named families (the first of them `missing`) are all absent is
/// drawn in ([`fallback_for`]).
pub fn fallback_family(db: &Database, missing: &str, opts: &FontOptions) -> String {
    db.family_name(&fallback_for(missing, opts)).to_string()
}

/// usvg's font choice with the fallback of [`fallback_for`]: usvg's own ends every text's
/// families with `serif`, so a text in a missing Arial would be drawn in a serif font.
/// Generic families the text names itself keep their place (`Montserrat, sans-serif`
/// falls back as its author asked).
pub fn resolver(opts: &FontOptions) -> usvg::FontResolver<'static> {
    let opts = opts.clone();
    usvg::FontResolver {
        select_font: Box::new(move |font, db| {
            let mut families: Vec<Family> = font
                .families()
                .iter()
                .map(|f| match f {
                    usvg::FontFamily::Serif => Family::Serif,
                    usvg::FontFamily::SansSerif => Family::SansSerif,
                    usvg::FontFamily::Cursive => Family::Cursive,
                    usvg::FontFamily::Fantasy => Family::Fantasy,
                    usvg::FontFamily::Monospace => Family::Monospace,
                    usvg::FontFamily::Named(s) => Family::Name(s),
                })
                .collect();
            let first_named = font.families().iter().find_map(|f| match f {
                usvg::FontFamily::Named(n) => Some(n.as_str()),
                _ => None,
            });
            families.push(first_named.map_or(Family::SansSerif, |n| fallback_for(n, &opts)));
            // The last resort usvg itself ends with.
            families.push(Family::Serif);
            let query = Query {
                families: &families,
                weight: Weight(font.weight()),
                stretch: stretch(font.stretch()),
                style: match font.style() {
                    usvg::FontStyle::Normal => Style::Normal,
                    usvg::FontStyle::Italic => Style::Italic,
                    usvg::FontStyle::Oblique => Style::Oblique,
                },
            };
            db.query(&query)
        }),
        select_fallback: usvg::FontResolver::default_fallback_selector(),
    }
}

fn stretch(s: usvg::FontStretch) -> Stretch {
    match s {
        usvg::FontStretch::UltraCondensed => Stretch::UltraCondensed,
        usvg::FontStretch::ExtraCondensed => Stretch::ExtraCondensed,
        usvg::FontStretch::Condensed => Stretch::Condensed,
        usvg::FontStretch::SemiCondensed => Stretch::SemiCondensed,
        usvg::FontStretch::Normal => Stretch::Normal,
        usvg::FontStretch::SemiExpanded => Stretch::SemiExpanded,
        usvg::FontStretch::Expanded => Stretch::Expanded,
        usvg::FontStretch::ExtraExpanded => Stretch::ExtraExpanded,
        usvg::FontStretch::UltraExpanded => Stretch::UltraExpanded,
    }
}

/// The font options' files and folders that do not exist (reported as errors).
pub fn missing_files(opts: &FontOptions) -> Vec<PathBuf> {
    let files = opts.files.iter().filter(|f| !f.is_file());
    let dirs = opts.dirs.iter().filter(|d| !d.is_dir());
    files.chain(dirs).cloned().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_family_falls_back_to_its_kind() {
        let opts = FontOptions::default();
        for sans in [
            "Arial",
            "Montserrat",
            "Montserrat-SemiBold",
            "Helvetica Neue",
            "Roboto",
        ] {
            assert_eq!(fallback_for(sans, &opts), Family::SansSerif, "{sans}");
        }
        for serif in [
            "Georgia",
            "Georgia-Bold",
            "Times New Roman",
            "TimesNewRomanPSMT",
            "MinionPro-Regular",
            "PT Serif",
        ] {
            assert_eq!(fallback_for(serif, &opts), Family::Serif, "{serif}");
        }
        for mono in ["Consolas", "CourierNewPSMT", "Roboto Mono", "Fira Code"] {
            assert_eq!(fallback_for(mono, &opts), Family::Monospace, "{mono}");
        }
        assert_eq!(fallback_for("PT Sans", &opts), Family::SansSerif);
    }

    #[test]
    fn the_chosen_family_takes_every_missing_font() {
        let opts = FontOptions {
            default_family: Some("DejaVu Sans".into()),
            ..FontOptions::default()
        };
        assert_eq!(fallback_for("Georgia", &opts), Family::SansSerif);
        assert_eq!(fallback_for("Consolas", &opts), Family::SansSerif);
    }
}
