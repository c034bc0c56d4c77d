//! The resvg static corpus through gmotion's own path: import → scene model → SVG text →
//! resvg, against each file's reference rendering. A file passes when at most 1% of its
//! pixels differ by more than 32/255 in some channel.
//!
//! Text is drawn with the fonts installed here, and the references were made with Noto
//! Sans. Where resvg itself, rendering the source file directly with the fonts here, does
//! not reproduce the reference either, the reference cannot be reached on this machine; such
//! a file passes when gmotion's rendering matches resvg's direct one instead (reported as
//! a separate count, so it is visible how many files were judged that way).
//!
//! Every file must pass except those in `KNOWN_FAILURES`, each named with its reason.
//!
//! The corpus is `tests/corpus/resvg` (vendored, see its LICENSE.md), or `$GMOTION_CORPUS`.
//! Set `GMOTION_CORPUS_OUT` to a directory to get each failing file's rendering there.

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use gmotion_export_raster::{Pixmap, compare, render, save_png};
use gmotion_export_svg::frame::scene_svg;
use gmotion_import_svg::{ImportOptions, load};
use rayon::prelude::*;

use crate::support::files_with_extension;

const TOLERANCE: u8 = 32;
const MAX_DIFFERING: f64 = 0.01;
/// Files known to fail, each with why. Any other failure fails the test by name, and so
/// does a listed file that passes (the list must stay true, so a fix is noticed).
const KNOWN_FAILURES: &[(&str, &str)] = &[(
    "structure__svg__not-UTF-8-encoding.svg",
    "Windows-1252 text (only UTF-8 is read)",
)];

fn corpus_dir() -> PathBuf {
    match std::env::var_os("GMOTION_CORPUS") {
        Some(dir) => PathBuf::from(dir),
        None => crate::support::root().join("tests/corpus/resvg"),
    }
}

/// How a file was judged.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Oracle {
    /// Against the reference PNG.
    Reference,
    /// Against resvg's direct rendering of the source, the reference being out of reach
    /// with the fonts installed here.
    Resvg,
}

struct Outcome {
    name: String,
    /// The differing fraction, or why there is none.
    result: Result<f64, String>,
    oracle: Oracle,
    import: Duration,
    write: Duration,
    render: Duration,
}

impl Outcome {
    fn passed(&self) -> bool {
        matches!(self.result, Ok(d) if d <= MAX_DIFFERING)
    }
}

fn check(svg: &Path, out_dir: Option<&Path>) -> Outcome {
    let name = svg
        .file_name()
        .unwrap_or_default()
        .to_string_lossy()
        .into_owned();
    let mut o = Outcome {
        name,
        result: Err(String::new()),
        oracle: Oracle::Reference,
        import: Duration::ZERO,
        write: Duration::ZERO,
        render: Duration::ZERO,
    };
    let reference = match Pixmap::load_png(svg.with_extension("png")) {
        Ok(p) => p,
        Err(e) => {
            o.result = Err(format!("no reference PNG: {e}"));
            return o;
        }
    };
    let t = Instant::now();
    let imported = load(svg, &ImportOptions::default());
    o.import = t.elapsed();
    let scene = match imported {
        Ok(i) => i.scene,
        Err(e) => {
            o.result = Err(format!("import failed: {e}"));
            return o;
        }
    };
    let t = Instant::now();
    let text = scene_svg(&scene);
    o.write = t.elapsed();
    let t = Instant::now();
    // The references are 300 px wide except a few whose size resvg derives itself; render
    // at the reference's width and require the height to agree up to rounding.
    let rendered = render(&text, reference.width());
    o.render = t.elapsed();
    let pixmap = match rendered {
        Ok(p) => p,
        Err(e) => {
            o.result = Err(format!("render failed: {e}"));
            return o;
        }
    };
    if pixmap.height().abs_diff(reference.height()) > 1 {
        o.result = Err(format!(
            "size {}x{} vs reference {}x{}",
            pixmap.width(),
            pixmap.height(),
            reference.width(),
            reference.height()
        ));
    } else {
        o.result = Ok(compare(&pixmap, &reference, TOLERANCE));
    }
    if !o.passed()
        && let Some(direct) = resvg_direct(svg, &pixmap)
        && compare(&direct, &reference, TOLERANCE) > MAX_DIFFERING
    {
        o.oracle = Oracle::Resvg;
        o.result = Ok(compare(&pixmap, &direct, TOLERANCE));
    }
    if let (Some(dir), false) = (out_dir, o.passed()) {
        let stem = svg.file_stem().unwrap_or_default().to_string_lossy();
        save_png(&pixmap, &dir.join(format!("{stem}.png"))).expect("write the failing rendering");
        std::fs::write(dir.join(format!("{stem}.svg")), &text).expect("write the failing SVG");
    }
    o
}

/// resvg's own rendering of the source file, at the size of `like`, with the system fonts.
fn resvg_direct(svg: &Path, like: &Pixmap) -> Option<Pixmap> {
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    let fontdb = FONTS.get_or_init(|| {
        let mut db = usvg::fontdb::Database::new();
        db.load_system_fonts();
        Arc::new(db)
    });
    let opt = usvg::Options {
        fontdb: fontdb.clone(),
        resources_dir: svg.parent().map(Path::to_path_buf),
        ..Default::default()
    };
    let tree = usvg::Tree::from_data(&std::fs::read(svg).ok()?, &opt).ok()?;
    let scale = like.width() as f32 / tree.size().width();
    let mut pixmap = Pixmap::new(like.width(), like.height())?;
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    Some(pixmap)
}

#[test]
fn corpus_round_trips_through_the_scene_model() {
    let dir = corpus_dir();
    let files = files_with_extension(&dir, "svg", "set GMOTION_CORPUS");
    assert!(!files.is_empty(), "no SVG files in {}", dir.display());
    let out_dir = std::env::var_os("GMOTION_CORPUS_OUT").map(PathBuf::from);
    if let Some(d) = &out_dir {
        std::fs::create_dir_all(d).expect("create GMOTION_CORPUS_OUT");
    }

    let wall = Instant::now();
    let outcomes: Vec<Outcome> = files
        .par_iter()
        .map(|f| check(f, out_dir.as_deref()))
        .collect();
    let wall = wall.elapsed();

    let failed: Vec<&Outcome> = outcomes.iter().filter(|o| !o.passed()).collect();
    for o in outcomes
        .iter()
        .filter(|o| o.passed() && o.oracle == Oracle::Resvg)
    {
        println!(
            "via resvg: {} (resvg here does not reproduce the reference either)",
            o.name
        );
    }
    for o in &failed {
        match &o.result {
            Ok(d) => println!("FAIL {}: {:.2}% of pixels differ", o.name, d * 100.0),
            Err(e) => println!("FAIL {}: {e}", o.name),
        }
    }
    let n = outcomes.len() as f64;
    // Mean and median in ms: the mean carries one-off costs (the first text file scans the
    // system fonts), the median is the typical file.
    let per_file = |f: fn(&Outcome) -> Duration| {
        let mut ms: Vec<f64> = outcomes.iter().map(|o| f(o).as_secs_f64() * 1e3).collect();
        ms.sort_by(f64::total_cmp);
        format!("{:.3}/{:.3}", ms.iter().sum::<f64>() / n, ms[ms.len() / 2])
    };
    let rate = (outcomes.len() - failed.len()) as f64 / n;
    let via_resvg = outcomes
        .iter()
        .filter(|o| o.passed() && o.oracle == Oracle::Resvg)
        .count();
    println!(
        "corpus: {}/{} passed ({:.1}%), {} of them against resvg's direct rendering; per file (mean/median ms): import {}, write {}, render {}; wall {:.1} s",
        outcomes.len() - failed.len(),
        outcomes.len(),
        rate * 100.0,
        via_resvg,
        per_file(|o| o.import),
        per_file(|o| o.write),
        per_file(|o| o.render),
        wall.as_secs_f64()
    );
    let known = |name: &str| KNOWN_FAILURES.iter().any(|(k, _)| *k == name);
    let new: Vec<&str> = failed
        .iter()
        .map(|o| o.name.as_str())
        .filter(|n| !known(n))
        .collect();
    let fixed: Vec<&str> = KNOWN_FAILURES
        .iter()
        .map(|(k, _)| *k)
        .filter(|k| outcomes.iter().any(|o| o.name == *k && o.passed()))
        .collect();
    let missing: Vec<&str> = KNOWN_FAILURES
        .iter()
        .map(|(k, _)| *k)
        .filter(|k| !outcomes.iter().any(|o| o.name == *k))
        .collect();
    assert!(
        new.is_empty() && fixed.is_empty() && missing.is_empty(),
        "new failures: {new:?}; listed as failing but passing now (remove them from \
         KNOWN_FAILURES): {fixed:?}; listed but not in the corpus: {missing:?}"
    );
}
