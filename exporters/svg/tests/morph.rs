//! `animate(morph, …)` by its definition: the last frame of a morph is the target drawn in
//! its place (pixels and geometry), an inverted twin is the morph's time reverse, the
//! in-between of a convex outline and a star neither twists nor folds, and bad targets are
//! errors at the argument.

use gmotion::engine::RunOptions;
use gmotion::motion::Animation;
use gmotion_export_raster::{compare, render};
use gmotion_export_svg::frame::frame_svg;
use kurbo::{BezPath, ParamCurve, Point, Shape as _};

use crate::support::{run_grammar, scene_of};

/// A circle, and a star kept out of the drawing.
const SCENE: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="120" height="120" viewBox="0 0 120 120">
  <circle id="logo" cx="50" cy="55" r="35" fill="#d1495b" stroke="#222" stroke-width="2"/>
  <path id="star" display="none" d="M60 10 L72 45 L108 45 L79 66 L90 100 L60 79 L30 100 L41 66 L12 45 L48 45 Z"/>
  <path id="spot" class="spot" d="M5 5 h10 v10 h-10 Z" fill="#00798c"/>
  <path id="spot2" class="spot" d="M105 5 h10 v10 h-10 Z" fill="#00798c"/>
</svg>"##;

const STAR: &str = "M60 10 L72 45 L108 45 L79 66 L90 100 L60 79 L30 100 L41 66 L12 45 L48 45 Z";

fn run(grammar: &str) -> Animation {
    run_grammar(scene_of(SCENE), grammar)
}

/// The error a grammar gives on the scene.
fn error(grammar: &str) -> gmotion::engine::EngineError {
    let g = gmotion::grammar::parse(grammar).unwrap();
    match gmotion::engine::run(scene_of(SCENE), &g, &RunOptions::default()) {
        Ok(_) => panic!("no error for\n{grammar}"),
        Err(e) => e,
    }
}

/// The circle's outline at `t` on the canvas (it sits in the root: its own coordinates).
fn outline(a: &Animation, t: f64) -> BezPath {
    a.tracks[0].outlines_at(t).expect("morphing")[0].clone()
}

/// Points along an outline, `n` per segment.
fn samples(p: &BezPath, n: usize) -> Vec<Point> {
    gmotion::morph::cubics(p)
        .iter()
        .flat_map(|c| (0..n).map(move |k| c.eval(k as f64 / n as f64)))
        .collect()
}

/// The distance from `q` to the nearest point of `path`.
fn distance(path: &BezPath, q: Point) -> f64 {
    path.segments()
        .map(|s| {
            kurbo::ParamCurveNearest::nearest(&s, q, 1e-9)
                .distance_sq
                .sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The last frame of a `world` morph is the star where it is drawn: every point of the
/// morphed outline lies on the star and every point of the star on it, and the frame's
/// pixels are those of the star drawn in the circle's paint.
#[test]
fn last_frame_is_the_target_in_its_place() {
    let a = run(
        "duration 2s\nfps 30\nanimate(morph, world, 0, shape(star), ease=ease-in-out) : [all, logo] -> [m]\n",
    );
    let star = BezPath::from_svg(STAR).unwrap();
    let end = outline(&a, 2.0);
    for q in samples(&end, 8) {
        assert!(distance(&star, q) < 1e-6, "{q:?} off the star");
    }
    for q in samples(&star, 8) {
        assert!(distance(&end, q) < 1e-6, "star point {q:?} not reached");
    }
    assert!((end.area().abs() - star.area().abs()).abs() < 1e-6);
    let drawn = SCENE
        .replace(
            r#"<circle id="logo" cx="50" cy="55" r="35""#,
            &format!(r#"<path d="{STAR}""#),
        )
        .replace(
            r#"<path id="star" display="none""#,
            r#"<path id="gone" display="none""#,
        );
    let want = render(
        &gmotion_export_svg::frame::scene_svg(&scene_of(&drawn)),
        240,
    )
    .unwrap();
    let got = render(&frame_svg(&a, 2.0), 240).unwrap();
    // An edge the morph cut in two is rasterised a shade differently (up to 11/255 along
    // it); a star out of place would differ by far more than 16/255, in thousands of pixels.
    let off = compare(&want, &got, 16);
    assert!(off < 1e-4, "the last frame is not the star: {off}");
    // `local` centres the star on the circle's centroid instead.
    let l =
        run("duration 2s\nfps 30\nanimate(morph, local, 0, shape(star)) : [all, logo] -> [m]\n");
    let c = gmotion::morph::centroid(&[outline(&l, 2.0)]).unwrap();
    assert!((c - Point::new(50.0, 55.0)).hypot() < 1e-6, "{c:?}");
}

/// An inverted twin is the time reverse of its morph, and `[a, inv_a]` ends as drawn.
#[test]
fn inverted_twin_is_the_time_reverse() {
    let a = run(
        "duration 2s\nfps 30\ntimesplit(0.5, 0.5) : [all, logo] -> [a, inv_a]\nanimate(morph, local, 0, shape(star), ease=ease-in) : [a, logo] -> [m]\n",
    );
    for k in 0..=30 {
        let t = k as f64 / 30.0;
        let (x, y) = (outline(&a, t), outline(&a, 2.0 - t));
        assert_eq!(x.elements().len(), y.elements().len());
        for (p, q) in samples(&x, 3).into_iter().zip(samples(&y, 3)) {
            assert!((p - q).hypot() < 1e-9, "t = {t}: {p:?} vs {q:?}");
        }
    }
    let circle = kurbo::Circle::new((50.0, 55.0), 35.0).to_path(1e-3);
    for q in samples(&outline(&a, 2.0), 4) {
        assert!(
            distance(&circle, q) < 1e-2,
            "{q:?} off the circle at the end"
        );
    }
}

/// Whether two segments of a polyline cross (sharing no end).
fn crosses(a: (Point, Point), b: (Point, Point)) -> bool {
    let side = |p: Point, q: Point, r: Point| (q - p).cross(r - p);
    let (d1, d2) = (side(b.0, b.1, a.0), side(b.0, b.1, a.1));
    let (d3, d4) = (side(a.0, a.1, b.0), side(a.0, a.1, b.1));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// The in-between of the circle and the star never crosses itself (checked on the outline
/// flattened finely, at 41 instants, for `local` and `world`, and from a square too).
#[test]
fn convex_to_star_never_folds() {
    let grammars = [
        "duration 2s\nfps 30\nanimate(morph, local, 0, shape(star)) : [all, logo] -> [m]\n",
        "duration 2s\nfps 30\nanimate(morph, world, 0, shape(star)) : [all, logo] -> [m]\n",
        "duration 2s\nfps 30\nanimate(morph, local, 0, \"M 20 20 H 80 V 80 H 20 Z\") : [all, logo] -> [sq]\nanimate(morph, local, 0, shape(star)) : [all, spot] -> [st]\n",
    ];
    for g in grammars {
        let a = run(g);
        for u in 0..a.tracks.len() {
            if a.tracks[u].morphs.is_empty() {
                continue;
            }
            for k in 0..=40 {
                let t = 2.0 * k as f64 / 40.0;
                let o = a.tracks[u].outlines_at(t).unwrap()[0].clone();
                let mut pts = Vec::new();
                kurbo::flatten(o.iter(), 1e-3, |el| {
                    if let Some(p) = el.end_point() {
                        pts.push(p);
                    }
                });
                let n = pts.len();
                let edges: Vec<(Point, Point)> =
                    (0..n).map(|i| (pts[i], pts[(i + 1) % n])).collect();
                for i in 0..n {
                    for j in i + 2..n {
                        if (i == 0 && j == n - 1) || (edges[i].0 - edges[i].1).hypot() < 1e-9 {
                            continue;
                        }
                        assert!(
                            !crosses(edges[i], edges[j]),
                            "{g}unit {u} at {t} s: edges {i} and {j} cross"
                        );
                    }
                }
            }
        }
    }
}

/// Bad targets are errors at the argument.
#[test]
fn bad_targets_are_errors_at_the_argument() {
    let e = error("animate(morph, local, 0, shape(moon)) : [all, logo] -> [m]\n");
    let s = e.span.unwrap();
    assert_eq!((s.line, s.col), (1, 32), "{e}");
    assert!(e.message.contains("no shape answers to `moon`"), "{e}");
    let e = error("animate(morph, local, 0, shape(spot)) : [all, logo] -> [m]\n");
    assert!(e.message.contains("2 shapes answer to `spot`"), "{e}");
    assert_eq!(e.span.unwrap().col, 32);
    let e = error("animate(morph, local, 0, shape(spot, 2)) : [all, logo] -> [m]\n");
    assert!(e.message.contains("from 0 to 1, found 2"), "{e}");
    assert_eq!(e.span.unwrap().col, 38);
    run("duration 1s\nanimate(morph, local, 0, shape(spot, 1)) : [all, logo] -> [m]\n");
    // Where the path data stops parsing: the `X` at character 10 of the string.
    let e = error("animate(morph, local, 0, \"M 0 0 L 5 X\") : [all, logo] -> [m]\n");
    let s = e.span.unwrap();
    assert_eq!((s.line, s.col), (1, 27 + 10), "{e}");
    assert!(e.message.contains("at character 11"), "{e}");
    let g = "animate(morph, local, 0, \"M 0 0 L 5 X\") : [all, logo] -> [m]\n";
    assert_eq!(&g[s.start..s.end], "X");
    let e = error("animate(morph, local, 0, 5) : [all, logo] -> [m]\n");
    assert!(e.message.contains("a morph target is"), "{e}");
}
