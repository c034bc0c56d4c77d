//! The papers' grammars typed in exactly as printed (rule numbers, `{…}` lists, `TimeSplit`,
//! quoted names, `tran` / `rot_scale`, `→`, gTangle's `⟨tags⟩` with spaces), run on scenes
//! shaped like the papers' figures, and judged by what the papers' definitions say they do.

use gmotion::engine::{RunOptions, run, timelines};
use gmotion::motion::Animation;
use gmotion::scene::Scene;
use kurbo::{Point, Rect};

use crate::support::{centre_at, same_point};

/// gMotion Fig. 4, as printed (the figure's fifth rule is the one the text prints twice,
/// `5. animate ("affine", "world", 0.0, rot_scale(45, 0.5))`).
const FIG_4: &str = r#"1. timesplit({0.3, 0.4, 0.3}) : [(all), (all)] -> ["a1", "a2", "inv_a1"]
2. animate("affine", "world", 0.0, tran(400.0, 0.0)) : [("a1"), ("c")] -> ["t1"]
3. animate("affine", "world", 0.0, tran(-400.0, 0.0)) : [("a1"), ("s")] -> ["t3"]
4. animate("affine", "local", 0.0, scale(0.5)) : [("a2"), ("c")] -> ["t2"]
5. animate ("affine", "world", 0.0, rot_scale(45, 0.5)) : [("a2"), ("s")] -> ["t4"]
"#;

/// gMotion Fig. 5: its third rule exactly as printed (`TimeSplit`, braces, subscripts,
/// `→`, the shape-tag placeholder `Is`); the first is the split it refines.
const FIG_5: &str = "1. TimeSplit({0.5, 0.5}) : [(all), (Is)] → [t₁, inv_t₁]
3. TimeSplit({0.625, 0.375}) : [(t₁), (Is)] → [t₂, t₃]
";

/// gTangle Fig. 9, as printed: tags with spaces between angle brackets.
const FIG_9: &str = "1. outline(25) : big poly → [⟨in⟩, ⟨out⟩]
2. place(20, 25) : out → [⟨blob⟩, ⟨rem⟩]
3. regularSplit(line, 90, 1) : in → [⟨quads⟩]
4. regroup(2) : quads → [⟨ung quads⟩]
5. outline(7) : ung quads → [⟨in 2⟩, ⟨out 2⟩]
6. outline(5) : in 2 → [⟨in 3⟩, ⟨out 3⟩]
7. stipling() : in 3 → [⟨term⟩, ⟨term⟩]
8. regularSplit(line, 50, 0) : ung quads → [⟨slices⟩]
9. regroup(2) : slices → [⟨reg slices⟩]
10. regularSplit(line, 10, 0) : reg slices → [⟨final⟩]
11. outline(3) : final → [⟨tiny⟩, ⟨tiny out⟩]
12. invert() : rem → [⟨term⟩, ⟨term⟩]
";

/// Squares: (tag, centre, side), on a 1200 × 600 canvas.
fn squares(items: &[(&str, (f64, f64), f64)]) -> Scene {
    crate::support::squares((1200.0, 600.0), items, false)
}

fn parsed(src: &str) -> gmotion::grammar::ast::Grammar {
    gmotion::grammar::parse(src).unwrap_or_else(|d| panic!("{}", d.render("paper.gm", src)))
}

fn animated(scene: Scene, src: &str) -> Animation {
    run(scene, &parsed(src), &RunOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

#[test]
fn fig_4_as_printed_slides_scales_and_turns() {
    let scene = squares(&[
        ("s", (600.0, 300.0), 80.0),
        ("c", (200.0, 150.0), 40.0),
        ("c", (200.0, 450.0), 40.0),
    ]);
    let a = animated(scene, FIG_4);
    let d = a.duration;
    // a1 (the first 0.3): circles 400 to the right, the square 400 to the left, in world
    // coordinates.
    assert!(same_point(
        centre_at(&a, 0, 0.3 * d),
        Point::new(200.0, 300.0)
    ));
    assert!(same_point(
        centre_at(&a, 1, 0.3 * d),
        Point::new(600.0, 150.0)
    ));
    assert!(same_point(
        centre_at(&a, 2, 0.3 * d),
        Point::new(600.0, 450.0)
    ));
    // a2 (the next 0.4): circles halve about their own centres ("local"), which stay put.
    let m = a.tracks[1].transform_at(0.7 * d);
    assert!(same_point(
        centre_at(&a, 1, 0.7 * d),
        Point::new(600.0, 150.0)
    ));
    assert!((m.determinant() - 0.25).abs() < 1e-9);
    // The square turns 45° and halves about the world origin ("world"): its centre goes
    // where rot_scale(45, 0.5) sends (200, 300).
    let (sin, cos) = 45f64.to_radians().sin_cos();
    let expected = Point::new(
        0.5 * (cos * 200.0 - sin * 300.0),
        0.5 * (sin * 200.0 + cos * 300.0),
    );
    assert!(
        same_point(centre_at(&a, 0, 0.7 * d), expected),
        "{:?}",
        centre_at(&a, 0, 0.7 * d)
    );
    // inv_a1 (the last 0.3) plays a1 backwards: the slide is undone by the end.
    let slide_back = centre_at(&a, 1, d) - centre_at(&a, 1, 0.7 * d);
    assert!((slide_back.x + 400.0).abs() < 1e-6 && slide_back.y.abs() < 1e-6);
}

#[test]
fn fig_5_as_printed_mirrors_an_inverted_split() {
    let scene = squares(&[("Is", (100.0, 100.0), 20.0)]);
    let g = parsed(FIG_5);
    let x = timelines(&scene, &g, &RunOptions::default()).unwrap();
    let d = gmotion::engine::Settings::default().duration;
    let slices: Vec<(String, f64)> = x.timelines[0]
        .iter()
        .map(|s| {
            let name = &x.slice_tags[s.tag as usize];
            let tag = if s.inverted {
                format!("inv_{name}")
            } else {
                name.clone()
            };
            (tag, s.dur / d)
        })
        .collect();
    // gMotion §3.7: on an inverted slice the split's tags and fractions run backwards.
    let expected = [
        ("t2", 0.5 * 0.625),
        ("t3", 0.5 * 0.375),
        ("inv_t3", 0.5 * 0.375),
        ("inv_t2", 0.5 * 0.625),
    ];
    assert_eq!(slices.len(), expected.len(), "{slices:?}");
    for ((tag, f), (want_tag, want_f)) in slices.iter().zip(expected) {
        assert_eq!(tag, want_tag, "{slices:?}");
        assert!((f - want_f).abs() < 1e-12, "{slices:?}");
    }
}

#[test]
fn fig_9_as_printed_draws_what_its_names_say() {
    // Its first two rules on a square: `in` is the inner part, `out` the ring, and `blob`
    // the placed pieces inside the ring, `rem` what is left of it.
    let first_two: String = FIG_9.lines().take(2).map(|l| format!("{l}\n")).collect();
    let a = animated(squares(&[("big_poly", (300.0, 300.0), 300.0)]), &first_two);
    let boxes = |tag: &str| -> Vec<Rect> {
        let shapes = a.scene.shapes.iter().filter(|s| s.tag == tag);
        shapes.map(|s| s.bbox).collect()
    };
    let inner = boxes("in");
    assert_eq!(inner.len(), 1);
    assert!((inner[0].width() - 250.0).abs() < 0.5, "{inner:?}");
    let rem = boxes("rem");
    assert!(
        !rem.is_empty() && rem.iter().all(|r| r.width() > 299.0),
        "{rem:?}"
    );
    let blobs = boxes("blob");
    assert!(blobs.len() > 10, "{} blobs", blobs.len());
    assert!(
        blobs
            .iter()
            .all(|b| b.width() <= 20.5 && !inner[0].contains(b.center()))
    );
    // The whole grammar runs on the leaf and applies every rule.
    let leaf =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/grammars/leaf.svg")).unwrap();
    let scene = gmotion_import_svg::parse(&leaf, "leaf.svg", &Default::default())
        .unwrap()
        .scene;
    let (_, stats) = run(scene, &parsed(FIG_9), &RunOptions::default()).unwrap();
    assert!(stats.spatial_steps >= 12, "{} steps", stats.spatial_steps);
}

/// gMotion §3.1: a motion is an n×m×p tensor, a spatial grid keyframed at p times and
/// interpolated linearly in time between them. With `grid=1x1x5` the value is evaluated at
/// `u = 0, 1/4, …, 1`; the shape passes through each keyframe at its instant, moves
/// linearly between them, and the inverted twin retraces the same points backwards.
#[test]
fn an_nxmxp_grid_passes_through_its_keyframes_linearly_in_time() {
    let scene = || squares(&[("s", (100.0, 300.0), 20.0)]);
    let hop = "duration 4s
timesplit(0.5, 0.5) : [all, s] -> [a, inv_a]
animate(affine, world, 0, translate(300 * u, -120 * sin(pi * u)), grid=1x1x5) : [a, s] -> [m]
";
    let a = animated(scene(), hop);
    let key = |u: f64| {
        Point::new(
            100.0 + 300.0 * u,
            300.0 - 120.0 * (std::f64::consts::PI * u).sin(),
        )
    };
    for k in 0..=4 {
        let u = f64::from(k) / 4.0;
        // Forward over the first 2 s, backwards over the last 2 s.
        assert!(same_point(centre_at(&a, 0, 2.0 * u), key(u)), "k = {k}");
        assert!(
            same_point(centre_at(&a, 0, 4.0 - 2.0 * u), key(u)),
            "k = {k}, inverted"
        );
    }
    for k in 0..4 {
        let (u0, u1) = (f64::from(k) / 4.0, f64::from(k + 1) / 4.0);
        let mid = key(u0).midpoint(key(u1));
        assert!(
            same_point(centre_at(&a, 0, u0 + u1), mid),
            "between keyframes {k} and {}",
            k + 1
        );
    }
    // A value without `u` is the same at every keyframe: the ordinary two-keyframe motion,
    // whatever p is (here with an easing, which applies to the whole change).
    let plain = |grid: &str| {
        animated(
            scene(),
            &format!(
                "duration 2s\nanimate(affine, local, 0.2, rotate(90) translate(40, 0), ease=ease-in-out, grid={grid}) : [all, s] -> [m]\n"
            ),
        )
    };
    let (two, nine) = (plain("1x1"), plain("1x1x9"));
    for i in 0..=40 {
        let t = f64::from(i) * 0.05;
        let (m, n) = (
            two.tracks[0].transform_at(t),
            nine.tracks[0].transform_at(t),
        );
        let (m, n) = (m.as_coeffs(), n.as_coeffs());
        let diff = m.iter().zip(n).map(|(x, y)| (x - y).abs());
        assert!(diff.fold(0.0, f64::max) < 1e-9, "t = {t}");
    }
}

#[test]
fn keyframes_in_time_are_refused_where_they_mean_nothing() {
    let refuse = |rule: &str, says: &str| {
        let src = format!("duration 1s\n{rule} : [all, s] -> [m]\n");
        let g = parsed(&src);
        let e = run(
            squares(&[("s", (10.0, 10.0), 4.0)]),
            &g,
            &RunOptions::default(),
        )
        .err()
        .unwrap_or_else(|| panic!("{rule} was accepted"));
        assert!(e.to_string().contains(says), "{rule}: {e}");
    };
    refuse(
        "animate(affine, world, 0, translate(10 * u, 0))",
        "grid=1x1x5",
    );
    refuse(
        "animate(fill, local, 0, hsl(360 * u, 50%, 50%), grid=1x1x4)",
        "for motions",
    );
    refuse(
        "animate(affine, world, 0, translate(1, 0), grid=2x2x1)",
        "NxMxP",
    );
    refuse(
        "animate(affine, world, 0, translate(1, 0), grid=2x2x65)",
        "NxMxP",
    );
}
