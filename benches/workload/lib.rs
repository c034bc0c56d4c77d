//! What the benchmarks run: generated workloads, shared by the engine benchmark's scaling
//! group and the studio's (`benches/put.rs`, at the sizes of gMotion's teaser and
//! intersections) — a grid of squares over some shape tags, and a grammar with a chain of
//! rules per tag — and gMotion's Table 1 as the example files that re-create it
//! ([`table1`]), which the gallery test holds to the paper's counts too.
//!
//! The benchmarks are a crate of their own so that criterion is built only for them: the
//! tests depend on this library alone, never on the benchmark harness.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use gmotion::scene::{Scene, SceneBuilder};
use kurbo::{BezPath, Rect};

pub mod table1;

/// The repository's top folder, where `grammars/`, `tests/` and `target/` are.
pub fn repo_root() -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    here.parent().unwrap_or(here).to_path_buf()
}

/// A scene of `n` small squares on a grid, spread over `tags` shape tags.
pub fn scene(n: usize, tags: usize) -> Scene {
    let side = (n as f64).sqrt().ceil() as usize;
    let (w, h) = (1920.0, 1080.0);
    let mut b = SceneBuilder::new(w, h);
    for i in 0..n {
        let (c, r) = (i % side, i / side);
        let x = (c as f64 + 0.5) * w / side as f64;
        let y = (r as f64 + 0.5) * h / side as f64;
        let rect = Rect::from_center_size((x, y), (4.0, 4.0));
        let t = (c * 7 + r * 3) % tags;
        let mut path = BezPath::new();
        path.move_to(rect.origin());
        path.line_to((rect.x1, rect.y0));
        path.line_to((rect.x1, rect.y1));
        path.line_to((rect.x0, rect.y1));
        path.close_path();
        b = b.path(&format!("g{t}"), path, None, None);
    }
    b.build()
}

/// A grammar with `1 + 10·tags + extra` rules: a shared split, then per shape tag a chain
/// of splits and animations of every type, so steps ≈ 16 per shape tag.
pub fn grammar(tags: usize, duration: f64, fps: f64) -> String {
    let mut g = format!("duration {duration}s\nfps {fps}\ngrid 8x6\n");
    g.push_str("timesplit(0.3, 0.4, 0.3) : [all, all] -> [a, b, inv_a]\n");
    for i in 0..tags {
        let t = format!("g{i}");
        let _ = writeln!(g, "timesplit(0.5, 0.5) : [a, {t}] -> [a{i}x, a{i}y]");
        let _ = writeln!(
            g,
            "animate(affine, local, 0.01 * (id % 30), rotate(30 + {i}) scale(1.2)) : [a{i}x, {t}] -> [a{i}r]"
        );
        let _ = writeln!(
            g,
            "animate(fill, local, 0, #ff{:02x}00) : [a{i}r, {t}] -> [a{i}f]",
            i * 20 % 256
        );
        let _ = writeln!(
            g,
            "animate(towards, world, rand(0, 0.1), (960, 540)) : [a{i}y, {t}] -> [a{i}t]"
        );
        let _ = writeln!(g, "timesplit(0.25, 0.75) : [b, {t}] -> [b{i}x, b{i}y]");
        let _ = writeln!(
            g,
            "animate(affine, world, 0, translate({}, 20)) : [b{i}x, {t}] -> [b{i}m]",
            10 * i
        );
        let _ = writeln!(
            g,
            "animate(opacity, local, 0, 0.5) : [b{i}m, {t}] -> [b{i}o]"
        );
        let _ = writeln!(
            g,
            "timesplit(0.5, 0.5) : [b{i}y, {t}] -> [c{i}x, inv_c{i}x]"
        );
        let _ = writeln!(
            g,
            "animate(affine, local, 0, skew(10, 0) scale(0.8)) : [c{i}x, {t}] -> [c{i}s]"
        );
        let _ = writeln!(
            g,
            "animate(border, local, 0, #0000ff) : [c{i}s, {t}] -> [c{i}b]"
        );
    }
    g
}

/// An SVG of `n` filled 3 px squares in a grid 1000 wide, one `<rect data-tag="s">` a
/// line: the scale benchmark's scene (issue 46), written as a designer's export would be.
pub fn squares_svg(n: usize) -> String {
    const COLUMNS: usize = 1000;
    let rows = n.div_ceil(COLUMNS).max(1);
    let (w, h) = (COLUMNS * 4, rows * 4);
    let mut svg = String::with_capacity(80 * n + 200);
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
    );
    for i in 0..n {
        let (x, y) = ((i % COLUMNS) * 4, (i / COLUMNS) * 4);
        let _ = writeln!(
            svg,
            r##"<rect data-tag="s" x="{x}" y="{y}" width="3" height="3" fill="#e4572e"/>"##
        );
    }
    svg.push_str("</svg>\n");
    svg
}

/// The scale benchmark's grammar over [`squares_svg`]'s squares: three slices, the first
/// split again into a translation and its inverted twin, the last a rotation staggered
/// by id, so every shape has its own delay.
pub fn squares_grammar() -> String {
    "duration 3s\nfps 30\n\
     timesplit(0.4, 0.2, 0.4) : [all, s] -> [a, b, c]\n\
     timesplit(0.5, 0.5) : [a, s] -> [a1, inv_a1]\n\
     animate(affine, world, 0, translate(2, 0), ease=ease-in-out) : [a1, s] -> [t]\n\
     animate(affine, local, 0.000001 * id, rotate(90)) : [c, s] -> [r]\n"
        .to_string()
}
