//! The timeslice engine on hand-built scenes: expansion order and semantics from gMotion
//! sec. 3, loops closing for every animation type, determinism and errors.

use gmotion::color::Color;
use gmotion::engine::{EngineError, RunOptions, run};
use gmotion::motion::{Animation, ShapeState};
use gmotion::scene::{Node, Scene};
use kurbo::{Affine, Point};

use crate::support::{centre_at, same_point};
use proptest::prelude::*;

/// A 400 × 300 scene of stroked squares: (tag, centre, side).
fn scene(items: &[(&str, (f64, f64), f64)]) -> Scene {
    crate::support::squares((400.0, 300.0), items, true)
}

fn animate(scene: Scene, src: &str) -> Result<Animation, EngineError> {
    let g =
        gmotion::grammar::parse(src).map_err(|d| EngineError::general(d.render("test.gm", src)))?;
    run(scene, &g, &RunOptions::default()).map(|(a, _)| a)
}

/// Squares of side 4 tagged `d`, centred at height `y` and each of `xs`.
fn dots(y: f64, xs: &[f64]) -> Vec<(&'static str, (f64, f64), f64)> {
    xs.iter().map(|&x| ("d", (x, y), 4.0)).collect()
}

/// [`animate`] on a [`scene`] of `items`, which must succeed.
fn animated(items: &[(&str, (f64, f64), f64)], src: &str) -> Animation {
    animate(scene(items), src).unwrap()
}

/// `g` run on `s` with `seed`, which must succeed.
fn with_seed(s: &Scene, g: &gmotion::grammar::ast::Grammar, seed: u64) -> Animation {
    let opts = RunOptions {
        seed: Some(seed),
        ..Default::default()
    };
    run(s.clone(), g, &opts).unwrap().0
}

/// The loop warnings `src` gives on `items`.
fn loop_warnings(items: &[(&str, (f64, f64), f64)], src: &str) -> Vec<String> {
    let g = gmotion::grammar::parse(src).unwrap();
    let (_, stats) = run(scene(items), &g, &RunOptions::default()).unwrap();
    (stats.warnings.iter())
        .map(|w| w.message.clone())
        .filter(|m| m.contains("the animation loops"))
        .collect()
}

/// The loop check compares pictures, not shapes: a shape that ends where another of its
/// tag started covers that one's start. Each shape's two looks are compared by hash, and
/// looks whose hashes meet are compared again whole; here they meet, so this is what
/// tells a covered start from one that pops.
#[test]
fn a_loop_pops_where_no_shape_ends_on_a_start() {
    let two = dots(150.0, &[100.0, 140.0]);
    // Both move right by one spacing: the second's start is covered, the first's is not.
    let shifted = loop_warnings(
        &two,
        "duration 2s\nanimate(affine, world, 0, translate(40, 0)) : [all, d] -> [m]\n",
    );
    assert_eq!(shifted.len(), 1, "{shifted:?}");
    assert!(
        shifted[0].contains("`d` #0 ends where it did not start (40.0 px away), so it jumps"),
        "{shifted:?}"
    );
    // The two trade places: the picture at the end is the first one.
    let swapped = loop_warnings(
        &two,
        "duration 2s\nanimate(affine, world, 0, translate(40 - 80 * id, 0)) : [all, d] -> [m]\n",
    );
    assert!(swapped.is_empty(), "{swapped:?}");
}

#[test]
fn toy_grammar_moves_square_and_loops() {
    let a = animated(
        &[("s", (50.0, 150.0), 40.0), ("c", (200.0, 150.0), 20.0)],
        "duration 4s\n\
         timesplit(0.5, 0.5) : [all, (s, c)] -> [a, inv_a]\n\
         animate(affine, world, 0, translate(100, 0)) : [a, s] -> [t]\n\
         animate(affine, local, 0, scale(0.5)) : [a, c] -> [t]\n",
    );
    assert!(same_point(centre_at(&a, 0, 0.0), Point::new(50.0, 150.0)));
    assert!(same_point(centre_at(&a, 0, 1.0), Point::new(100.0, 150.0)));
    assert!(same_point(centre_at(&a, 0, 2.0), Point::new(150.0, 150.0)));
    assert!(same_point(centre_at(&a, 0, 3.0), Point::new(100.0, 150.0)));
    assert!(same_point(centre_at(&a, 0, 4.0), Point::new(50.0, 150.0)));
    // The circle scales about its own centre, which therefore never moves.
    let m = a.tracks[1].transform_at(2.0);
    assert!(same_point(
        m * Point::new(200.0, 150.0),
        Point::new(200.0, 150.0)
    ));
    assert!((m.determinant() - 0.25).abs() < 1e-9);
    assert_eq!(a.tracks[1].transform_at(4.0), Affine::IDENTITY);
}

#[test]
fn inverted_split_mirrors_tags_and_fractions() {
    // all -> [a, inv_a]; then a splits 0.25/0.75 into [x, y]. On inv_a the split is mirrored:
    // inv_y first (0.75 of it), then inv_x (0.25). Only x moves: at 0.25·2s forward, and in
    // the last 0.25·2s of the timeline backwards.
    let a = animated(
        &[("s", (50.0, 50.0), 10.0)],
        "duration 4s\n\
         timesplit(0.5, 0.5) : [all, s] -> [a, inv_a]\n\
         timesplit(0.25, 0.75) : [a, s] -> [x, y]\n\
         animate(affine, world, 0, translate(40, 0)) : [x, s] -> [mx]\n",
    );
    for (t, x) in [
        (0.5, 90.0),
        (2.0, 90.0),
        (3.5, 90.0),
        (3.75, 70.0),
        (4.0, 50.0),
    ] {
        assert!(
            same_point(centre_at(&a, 0, t), Point::new(x, 50.0)),
            "t = {t}"
        );
    }
}

#[test]
fn priority_wins_and_seed_chooses_among_equals() {
    let s = scene(&[("s", (50.0, 50.0), 10.0)]);
    let src = "duration 1s\n\
         animate(affine, world, 0, translate(10, 0)) : [all, s] -> [t]\n\
         animate(affine, world, 0, translate(0, 10)) : [all, s] -> [t]\n\
         animate(affine, world, 0, translate(-10, 0)) : [all, s] -> [t] priority=1\n";
    let a = animate(s.clone(), src).unwrap();
    assert!(same_point(centre_at(&a, 0, 1.0), Point::new(40.0, 50.0)));
    // Without the priority rule, seeds pick between the two others, and both occur.
    let src2: String = src.lines().take(3).collect::<Vec<_>>().join("\n");
    let g = gmotion::grammar::parse(&src2).unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for seed in 0..40 {
        let a = with_seed(&s, &g, seed);
        let p = centre_at(&a, 0, 1.0);
        seen.insert(((p.x - 50.0).round() as i64, (p.y - 50.0).round() as i64));
    }
    assert_eq!(seen.into_iter().collect::<Vec<_>>(), vec![(0, 10), (10, 0)]);
}

#[test]
fn offsets_delay_and_expressions_stagger() {
    let a = animated(
        &dots(10.0, &[10.0, 30.0, 50.0]),
        "duration 2s\nanimate(affine, world, 0.5 * id, translate(0, 10)) : [all, d] -> [m]\n",
    );
    // Shape 2 starts at 1s and has 1s to travel.
    assert!(same_point(centre_at(&a, 2, 0.9), Point::new(50.0, 10.0)));
    assert!(same_point(centre_at(&a, 2, 1.5), Point::new(50.0, 15.0)));
    // Shape 1 starts at 0.5s and has 1.5s.
    assert!(same_point(centre_at(&a, 1, 1.25), Point::new(30.0, 15.0)));
    assert!(same_point(centre_at(&a, 0, 1.0), Point::new(10.0, 15.0)));
}

#[test]
fn towards_and_path_reach_their_targets_with_exact_lookup() {
    let a = animated(
        &[("d", (10.0, 10.0), 4.0), ("e", (300.0, 200.0), 4.0)],
        "duration 1s\nlookup exact\n\
         animate(towards, world, 0, (200, 100)) : [all, d] -> [m]\n\
         animate(path, world, 0, \"M 0 250 L 400 250\") : [all, e] -> [m]\n",
    );
    assert!(same_point(centre_at(&a, 0, 1.0), Point::new(200.0, 100.0)));
    assert!(same_point(centre_at(&a, 1, 1.0), Point::new(300.0, 250.0)));
}

#[test]
fn nearest_grid_lookup_moves_a_cell_together() {
    // 2x1 grid over a 400-wide canvas: cell centres at x=100 and x=300.
    let a = animated(
        &dots(150.0, &[20.0, 180.0, 250.0]),
        "duration 1s\ngrid 2x1\nanimate(towards, world, 0, (200, 150)) : [all, d] -> [m]\n",
    );
    let d0 = centre_at(&a, 0, 1.0) - Point::new(20.0, 150.0);
    let d1 = centre_at(&a, 1, 1.0) - Point::new(180.0, 150.0);
    let d2 = centre_at(&a, 2, 1.0) - Point::new(250.0, 150.0);
    assert!((d0 - d1).hypot() < 1e-9, "same cell, same translation");
    assert!((d0.x - 100.0).abs() < 1e-9 && (d2.x + 100.0).abs() < 1e-9);
}

#[test]
fn split_of_an_animated_slice_keeps_the_motion() {
    let a = animated(
        &[("s", (0.0, 0.0), 2.0)],
        "duration 2s\n\
         animate(affine, world, 0, translate(100, 0)) : [all, s] -> [m]\n\
         timesplit(0.3, 0.7) : [m, s] -> [p, q]\n",
    );
    for t in [0.0, 0.3, 0.6, 1.0, 1.7, 2.0] {
        assert!(
            same_point(centre_at(&a, 0, t), Point::new(50.0 * t, 0.0)),
            "t = {t}"
        );
    }
}

#[test]
fn a_grammar_that_never_terminates_names_its_cycle() {
    let s = scene(&[("s", (0.0, 0.0), 2.0)]);
    let err = animate(
        s,
        "duration 1s\nmax_steps 50\n\
         timesplit(0.5, 0.5) : [all, s] -> [x, z]\n\
         animate(opacity, local, 0, 0.5) : [x, s] -> [y]\n\
         animate(opacity, local, 0, 1) : [y, s] -> [x]\n",
    )
    .unwrap_err();
    assert!(err.message.contains("did not terminate within 50"), "{err}");
    assert!(
        err.notes.iter().any(|n| n.contains("line 4"))
            && err.notes.iter().any(|n| n.contains("line 5")),
        "{err}"
    );
}

#[test]
fn split_fractions_must_sum_to_one() {
    let s = scene(&[("s", (0.0, 0.0), 2.0)]);
    let err = animate(s, "duration 1s\ntimesplit(0.5, 0.6) : [all, s] -> [x, y]\n").unwrap_err();
    assert!(err.message.contains("sum to 1"), "{err}");
    assert_eq!(err.span.unwrap().line, 2);
}

#[test]
fn same_seed_same_animation() {
    let s = scene(&[
        ("s", (10.0, 10.0), 2.0),
        ("s", (40.0, 10.0), 2.0),
        ("t", (70.0, 10.0), 2.0),
    ]);
    let src = "duration 3s\nchoice shape\n\
               animate(affine, world, rand(0, 1), translate(rand(-50, 50), rand(-50, 50))) : [all, all] -> [m]\n\
               animate(affine, local, 0, rotate(rand(0, 360))) : [all, all] -> [m]\n";
    let g = gmotion::grammar::parse(src).unwrap();
    let eval = |seed| {
        let a = with_seed(&s, &g, seed);
        (0..30)
            .map(|i| a.evaluate(i as f64 * 0.1))
            .collect::<Vec<Vec<ShapeState>>>()
    };
    assert_eq!(eval(7), eval(7));
    assert_ne!(eval(7), eval(8));
}

fn loop_grammar(kind: &str, reference: &str, value: &str, ease: &str) -> String {
    format!(
        "duration 3s\n\
         timesplit(0.3, 0.3, 0.4) : [all, s] -> [a, b, inv_a]\n\
         animate({kind}, {reference}, 0.1, {value}{ease}) : [a, s] -> [done]\n"
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// `[a, b, inv_a]` with a neutral `b` ends where it began, for every animation type.
    #[test]
    fn inverted_slices_close_loops(
        kind in 0usize..7,
        x in -200.0f64..200.0, y in -200.0f64..200.0,
        angle in -170.0f64..170.0, k in 0.3f64..3.0,
        r in 0u8..=255, g in 0u8..=255, b in 0u8..=255,
        world in any::<bool>(), eased in any::<bool>(),
        cx in 0.0f64..400.0, cy in 0.0f64..300.0,
    ) {
        let reference = if world { "world" } else { "local" };
        let value = match kind {
            0 => format!("translate({x}, {y}) rotate({angle}) scale({k})"),
            1 => format!("({x}, {y})"),
            2 => format!("\"M {x} {y} L {cx} {cy}\""),
            3 => format!("rgb({r}, {g}, {b})"),
            4 => format!("rgb({r}, {g}, {b})"),
            5 => format!("{}", k / 3.0),
            _ => format!("{k}"),
        };
        let kind_name = ["affine", "towards", "path", "fill", "border", "opacity", "stroke-width"][kind];
        let ease = if eased { ", ease=ease-in-out" } else { "" };
        let src = loop_grammar(kind_name, reference, &value, ease);
        let s = scene(&[("s", (cx, cy), 30.0)]);
        let a = animate(s, &src).unwrap();
        let start = a.tracks[0].state_at(0.0);
        let end = a.tracks[0].state_at(3.0);
        let mid = a.tracks[0].state_at(1.2);
        for (p, q) in start.transform.as_coeffs().iter().zip(end.transform.as_coeffs()) {
            prop_assert!((p - q).abs() < 1e-6, "{src}: {:?} vs {:?}", start, end);
        }
        prop_assert!((start.opacity - end.opacity).abs() < 1e-9);
        prop_assert!((start.stroke_width - end.stroke_width).abs() < 1e-9);
        let base = Color::rgb(0.2, 0.4, 0.6);
        let (f0, f1) = (start.fill.apply(base), end.fill.apply(base));
        prop_assert!((f0.r - f1.r).abs() < 1e-5 && (f0.g - f1.g).abs() < 1e-5 && (f0.b - f1.b).abs() < 1e-5);
        let (s0, s1) = (start.stroke.apply(base), end.stroke.apply(base));
        prop_assert!((s0.r - s1.r).abs() < 1e-5 && (s0.g - s1.g).abs() < 1e-5 && (s0.b - s1.b).abs() < 1e-5);
        // And something really happened in between (the neutral slice holds the change).
        let moved = match kind {
            0..=2 => (mid.transform * Point::new(cx, cy) - Point::new(cx, cy)).hypot() > 1e-3
                || (mid.transform.determinant() - 1.0).abs() > 1e-3,
            3 => mid.fill.weight > 0.99,
            4 => mid.stroke.weight > 0.99,
            5 => (mid.opacity - k / 3.0).abs() < 1e-9,
            _ => (mid.stroke_width - k / 2.0).abs() < 1e-9,
        };
        let trivially_still = kind <= 2 && x.abs() < 1e-3 && y.abs() < 1e-3;
        prop_assert!(moved || trivially_still || kind == 1 || kind == 2, "{src}: nothing happened: {mid:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Two motions set on one slice (local then world, or the reverse) are undone by the
    /// inverted twin in the opposite order, about the pivot the twin began at.
    #[test]
    fn stacked_motions_on_one_slice_close_loops(
        first_local in any::<bool>(), second_local in any::<bool>(),
        sx in 0.2f64..2.0, sy in 0.2f64..2.0, angle in -90.0f64..90.0,
        dx in -80.0f64..80.0, dy in -80.0f64..80.0, grid in 1u32..5,
    ) {
        let r1 = if first_local { "local" } else { "world" };
        let r2 = if second_local { "local" } else { "world" };
        let src = format!(
            "duration 2s\ngrid {grid}x{grid}\n\
             timesplit(0.4, 0.2, 0.4) : [all, s] -> [go, hold, inv_go]\n\
             animate(affine, {r1}, 0, scale({sx}, {sy}) rotate({angle})) : [go, s] -> [a]\n\
             animate(affine, {r2}, 0, translate({dx}, {dy})) : [a, s] -> [b]\n"
        );
        let a = animate(scene(&[("s", (120.0, 90.0), 20.0)]), &src).unwrap();
        let end = a.tracks[0].transform_at(2.0);
        for (p, q) in end.as_coeffs().iter().zip(Affine::IDENTITY.as_coeffs()) {
            prop_assert!((p - q).abs() < 1e-6, "{src}: ends at {end:?}");
        }
    }
}

#[test]
fn rotation_about_a_point_keeps_the_point_fixed_while_playing() {
    let a = animated(
        &[("s", (200.0, 50.0), 10.0)],
        "duration 1s\nanimate(affine, world, 0, rotate(180, 200, 150)) : [all, s] -> [m]\n",
    );
    for t in [0.25, 0.5, 0.75, 1.0] {
        let p = centre_at(&a, 0, t);
        assert!(
            ((p - Point::new(200.0, 150.0)).hypot() - 100.0).abs() < 1e-6,
            "t = {t}: {p:?}"
        );
    }
    assert!(same_point(centre_at(&a, 0, 0.5), Point::new(300.0, 150.0)));
}

/// The largest jump in velocity between consecutive frames of a shape's centre.
fn max_velocity_jump(a: &Animation, fps: f64) -> f64 {
    let n = (a.duration * fps).round() as usize;
    let p: Vec<Point> = (0..=n).map(|i| centre_at(a, 0, i as f64 / fps)).collect();
    let v: Vec<kurbo::Vec2> = p.windows(2).map(|w| (w[1] - w[0]) * fps).collect();
    v.windows(2)
        .map(|w| (w[1] - w[0]).hypot())
        .fold(0.0, f64::max)
}

#[test]
fn smoothing_makes_slice_boundaries_velocity_continuous() {
    let grammar = |smoothing: &str| {
        format!(
            "duration 4s\nfps 60\n{smoothing}\n\
             timesplit(0.25, 0.25, 0.25, 0.25) : [all, s] -> [a, b, inv_b, inv_a]\n\
             animate(affine, world, 0, translate(100, 0)) : [a, s] -> [ma]\n\
             animate(affine, world, 0, translate(0, 100)) : [b, s] -> [mb]\n"
        )
    };
    let raw = animate(scene(&[("s", (50.0, 50.0), 10.0)]), &grammar("")).unwrap();
    let smooth = animate(
        scene(&[("s", (50.0, 50.0), 10.0)]),
        &grammar("smoothing spring(0.4, 0)"),
    )
    .unwrap();
    let (jr, js) = (
        max_velocity_jump(&raw, 60.0),
        max_velocity_jump(&smooth, 60.0),
    );
    // Unsmoothed, the velocity turns a corner of 100 px/s at once; the spring spreads it.
    assert!(jr > 99.0, "raw jump {jr}");
    assert!(js < jr / 5.0, "smoothed jump {js} vs raw {jr}");
    // The loop still closes and the shape still travels most of the way.
    assert!(
        same_point(centre_at(&smooth, 0, 4.0), centre_at(&smooth, 0, 0.0))
            || (centre_at(&smooth, 0, 4.0) - centre_at(&smooth, 0, 0.0)).hypot() < 1.0
    );
    let far = (0..=240)
        .map(|i| centre_at(&smooth, 0, i as f64 / 60.0).x)
        .fold(0.0, f64::max);
    assert!(far > 130.0, "reached x = {far}");
}

#[test]
fn bad_smoothing_is_an_error_at_the_directive() {
    let err = animate(
        scene(&[("s", (0.0, 0.0), 2.0)]),
        "duration 1s\nsmoothing spring(-1, 0)\nanimate(opacity, local, 0, 0.5) : [all, s] -> [m]\n",
    )
    .unwrap_err();
    assert_eq!(err.span.map(|s| s.line), Some(2), "{err}");
}

/// Steps over many shapes expand in parallel: the tracks (and the slice tags, numbered by
/// first creation) must not depend on the number of threads, nor on the error reported.
#[test]
fn large_steps_expand_the_same_on_any_number_of_threads() {
    let items: Vec<(&str, (f64, f64), f64)> = (0..900)
        .map(|i| {
            let tag = ["p", "q"][i % 2];
            ((tag), ((i % 30) as f64 * 13.0, (i / 30) as f64 * 10.0), 4.0)
        })
        .collect();
    let src = "duration 3s\nfps 10\ngrid 5x4\n\
        timesplit(0.4, 0.2, 0.4) : [all, all] -> [a, hold, inv_a]\n\
        timesplit(rand(0.2, 0.8), 1 - 0, 0) : [hold, q] -> [x, y, z]\n\
        timesplit(0.5, 0.5) : [a, p] -> [a1, a2]\n\
        timesplit(0.5, 0.5) : [a, q] -> [a2, a1]\n\
        animate(affine, local, rand(0, 0.3), rotate(20 + id) scale(1.1)) : [a1, all] -> [m]\n\
        animate(towards, world, 0.001 * id, (200, 150)) : [a2, all] -> [t]\n\
        animate(fill, local, 0, #ff0000) : [m, p] -> [f]\n";
    let run_on = |threads: usize, src: &str| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let g = gmotion::grammar::parse(src).unwrap();
            run(scene(&items), &g, &RunOptions::default())
                .map(|(a, stats)| format!("{:?} {:?} {:?}", a.tracks, stats.steps, stats.rule_uses))
                .map_err(|e| format!("{e:?}"))
        })
    };
    // The `[hold, q]` split sums to 1 + rand: an error, reported for the same shape.
    let bad_one = run_on(1, src);
    let bad_two = run_on(2, src);
    assert!(bad_one.is_err(), "{bad_one:?}");
    assert_eq!(bad_one, bad_two);
    let good = src.replace("rand(0.2, 0.8), 1 - 0, 0", "0.25, 0.5, 0.25");
    let one = run_on(1, &good).unwrap();
    let two = run_on(2, &good).unwrap();
    assert!(one.contains("Rigid"), "nothing moved");
    assert_eq!(one, two);
}

/// Shapes expand independently (in parallel), but an error is the one expanding step after
/// step meets first: the earliest step's, even when a shape earlier in the scene fails at a
/// later step.
#[test]
fn the_earliest_steps_error_is_reported() {
    let items: Vec<(&str, (f64, f64), f64)> = (0..100)
        .map(|i| ("s", ((i % 10) as f64 * 30.0, (i / 10) as f64 * 30.0), 4.0))
        .collect();
    // Step 1 (slice tag `a`) fails on the last shape only, step 2 (`b`) on the first only.
    let src = "duration 2s\n\
        timesplit(0.5, 0.5) : [all, s] -> [a, b]\n\
        animate(opacity, local, 0, 0.5 + 0 * sqrt(98.5 - id)) : [a, s] -> [m]\n\
        animate(opacity, local, 0, 0.5 + 0 * sqrt(id - 0.5)) : [b, s] -> [n]\n";
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let err = pool.install(|| animate(scene(&items), src)).unwrap_err();
        assert_eq!(
            err.span.map(|s| s.line),
            Some(3),
            "{threads} threads: {err}"
        );
    }
    // Without the step-1 failure, the step-2 one is reported.
    let err = animate(scene(&items), &src.replace("98.5 - id", "id + 1")).unwrap_err();
    assert_eq!(err.span.map(|s| s.line), Some(4), "{err}");
}

/// `n` 4 px squares on a 20-column grid 15 px apart, tagged alternately by `tags`.
fn grid_of_squares(n: usize, tags: [&'static str; 2]) -> Vec<(&'static str, (f64, f64), f64)> {
    (0..n)
        .map(|i| {
            (
                tags[i % 2],
                ((i % 20) as f64 * 15.0, (i / 20) as f64 * 15.0),
                4.0,
            )
        })
        .collect()
}

/// With `choice shape` each shape draws its own rule, and what follows a rule applies only
/// to the shapes that drew it: shapes moved right turn red, shapes moved down keep their
/// colour and then grow, whatever the number of threads.
#[test]
fn per_shape_choice_follows_each_shapes_own_draws() {
    let items = grid_of_squares(300, ["p", "q"]);
    let src = "duration 2s\nchoice shape\n\
        timesplit(0.5, 0.5) : [all, all] -> [a, b]\n\
        animate(affine, world, 0, translate(10, 0)) : [a, all] -> [right]\n\
        animate(affine, world, 0, translate(0, 10)) : [a, all] -> [down] weight=2\n\
        animate(fill, local, 0, #ff0000) : [right, all] -> [red]\n\
        animate(affine, local, 0, scale(2)) : [down, q] -> [big]\n\
        animate(opacity, local, 0, 0.5) : [b, all] -> [faded]\n";
    let run_on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| animate(scene(&items), src).unwrap())
    };
    let a = run_on(2);
    let (mut right, mut down) = (0, 0);
    for (i, shape) in a.scene.shapes.iter().enumerate() {
        let end = a.tracks[i].state_at(2.0);
        let moved = end.transform * shape.centroid - shape.centroid;
        let red = end.fill != a.tracks[i].state_at(0.0).fill;
        if (moved.x - 10.0).abs() < 1e-9 && moved.y.abs() < 1e-9 {
            right += 1;
            assert!(red, "shape {i} moved right but did not turn red");
        } else {
            down += 1;
            assert!(
                (moved.y - 10.0).abs() < 1e-9 && moved.x.abs() < 1e-9,
                "shape {i}: {moved:?}"
            );
            assert!(!red, "shape {i} moved down but turned red");
            let grew = end.transform.determinant() > 3.9;
            assert_eq!(grew, shape.tag == "q", "shape {i} ({}): scale", shape.tag);
        }
        assert!((end.opacity - 0.5).abs() < 1e-9, "shape {i}: opacity");
    }
    // Both rules drawn, about 1 : 2.
    assert!(right > 60 && down > 130, "right {right}, down {down}");
    let one = run_on(1);
    assert_eq!(format!("{:?}", a.tracks), format!("{:?}", one.tracks));
}

/// `Track::deform` (used for shapes that deform per vertex) must compose motions that share
/// a slice in the same order as `Track::transform_at`: on a rigid-only track both move every
/// point alike.
#[test]
fn deform_composes_like_transform_at() {
    let items = [("s", (120.0, 80.0), 30.0), ("s", (260.0, 200.0), 20.0)];
    let src = "duration 2s\nfps 10\n\
        timesplit(0.5, 0.5) : [all, all] -> [a, inv_a]\n\
        animate(affine, local, 0, rotate(70) scale(1.3, 0.8)) : [a, all] -> [m]\n\
        animate(affine, world, 0.1, translate(60, -20) rotate(15)) : [m, all] -> [w]\n\
        animate(affine, local, 0, skew(12, 0)) : [w, all] -> [k]\n";
    let a = animate(scene(&items), src).unwrap();
    let mut checked = 0;
    for (track, shape) in a.tracks.iter().zip(&a.scene.shapes) {
        assert!(track.motions.len() >= 3, "{} motions", track.motions.len());
        for i in 0..=40 {
            let t = i as f64 * 0.05;
            let m = track.transform_at(t);
            for p in [
                Point::new(shape.bbox.x0, shape.bbox.y0),
                Point::new(shape.bbox.x1, shape.bbox.y0),
                Point::new(shape.bbox.x1, shape.bbox.y1),
            ] {
                let got = track.deform(p, t);
                let want = m * p;
                assert!(
                    (got - want).hypot() < 1e-6,
                    "t = {t}: deform {got:?}, transform {want:?}"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 0);
}

// ---------------------------------------------------------------------------------------
// Inverted slices and offsets (issue 13, item 2): an inverted slice is its twin's
// animation with start and end values swapped (gMotion sec. 3.2) — `[inv_a, a]` at t is
// `[a, inv_a]` at t + D/2 — a twin undoes only its own motion, and an offset must leave
// the change time to play.
// ---------------------------------------------------------------------------------------

/// Whether two states agree within `tol` (transform coefficients, tints, opacity, width).
fn same_state(a: &ShapeState, b: &ShapeState, tol: f64) -> bool {
    let m = a
        .transform
        .as_coeffs()
        .iter()
        .zip(b.transform.as_coeffs())
        .all(|(x, y)| (x - y).abs() <= tol * (1.0 + x.abs()));
    let tint = |p: gmotion::motion::Tint, q: gmotion::motion::Tint| {
        (p.weight - q.weight).abs() as f64 <= tol
            && p.sum
                .iter()
                .zip(q.sum)
                .all(|(x, y)| ((x - y).abs() as f64) <= tol)
    };
    m && tint(a.fill, b.fill)
        && tint(a.stroke, b.stroke)
        && (a.opacity - b.opacity).abs() <= tol
        && (a.stroke_width - b.stroke_width).abs() <= tol
}

#[test]
fn an_inverted_twin_keeps_the_motion_it_inherited() {
    // The dot travels 80 px over the whole timeline; the middle pieces swell and shrink it
    // about its own (moving) centre. The swell must not disturb the travel: the centre stays
    // on the straight track at every instant and the scale is undone by the end of
    // `inv_swell` (before the fix it ran the translation backwards, ending 24 px behind).
    let src = "duration 1s\n\
         animate(affine, world, 0, translate(80, 0)) : [all, dot] -> [moving]\n\
         timesplit(0.2, 0.3, 0.3, 0.2) : [moving, dot] -> [pre, swell, inv_swell, post]\n\
         animate(affine, local, 0, scale(2)) : [swell, dot] -> [big]\n";
    let a = animate(scene(&[("dot", (50.0, 150.0), 10.0)]), src).unwrap();
    for i in 0..=40 {
        let t = i as f64 / 40.0;
        let want = Point::new(50.0 + 80.0 * t, 150.0);
        assert!(
            same_point(centre_at(&a, 0, t), want),
            "t = {t}: {:?}",
            centre_at(&a, 0, t)
        );
    }
    let m = a.tracks[0].transform_at(0.8);
    assert!((m.determinant() - 1.0).abs() < 1e-9, "{m:?}");
    assert!((a.tracks[0].transform_at(0.5).determinant() - 4.0).abs() < 1e-9);
}

#[test]
fn an_inherited_spin_keeps_its_centre_through_a_twin_that_travels() {
    // A local spin over the whole timeline; the first half of it travels and comes back.
    // The square spins about its own centre throughout: its centre is on the travel path.
    let src = "duration 2s\n\
         animate(affine, local, 0, rotate(360)) : [all, s] -> [spin]\n\
         timesplit(0.25, 0.25, 0.5) : [spin, s] -> [go, inv_go, rest]\n\
         animate(affine, world, 0, translate(100, 0)) : [go, s] -> [went]\n";
    let a = animate(scene(&[("s", (100.0, 100.0), 20.0)]), src).unwrap();
    for i in 0..=40 {
        let t = i as f64 / 20.0;
        let dx = if t <= 0.5 {
            200.0 * t
        } else if t <= 1.0 {
            200.0 * (1.0 - t)
        } else {
            0.0
        };
        assert!(
            same_point(centre_at(&a, 0, t), Point::new(100.0 + dx, 100.0)),
            "t = {t}: {:?}",
            centre_at(&a, 0, t)
        );
    }
    let end = a.tracks[0].transform_at(2.0);
    assert!(
        end.as_coeffs()
            .iter()
            .zip(Affine::IDENTITY.as_coeffs())
            .all(|(x, y)| (x - y).abs() < 1e-9)
    );
}

#[test]
fn an_inverted_slice_that_comes_first_starts_in_its_twins_end_state() {
    // An entrance: `[inv_in, in]` starts where `in` ends — moved, faded and recoloured —
    // and plays back to the drawn state, then `in` plays forward again.
    let rules = "animate(affine, world, 0, translate(100, 0), ease=ease-out) : [in, s] -> [m]\n\
         animate(opacity, local, 0, 0.2) : [m, s] -> [o]\n\
         animate(fill, local, 0, #ff0000) : [o, s] -> [f]\n";
    let first = format!("duration 2s\ntimesplit(0.5, 0.5) : [all, s] -> [inv_in, in]\n{rules}");
    let last = format!("duration 2s\ntimesplit(0.5, 0.5) : [all, s] -> [in, inv_in]\n{rules}");
    let sc = || scene(&[("s", (50.0, 50.0), 10.0)]);
    let (a, b) = (
        animate(sc(), &first).unwrap(),
        animate(sc(), &last).unwrap(),
    );
    let s0 = a.tracks[0].state_at(0.0);
    assert!(same_point(
        s0.transform * Point::new(50.0, 50.0),
        Point::new(150.0, 50.0)
    ));
    assert!((s0.opacity - 0.2).abs() < 1e-9);
    assert!((s0.fill.weight - 1.0).abs() < 1e-6 && (s0.fill.sum[0] - 1.0).abs() < 1e-6);
    let s1 = a.tracks[0].state_at(1.0);
    assert!(same_state(&s1, &ShapeState::REST, 1e-9), "{s1:?}");
    for i in 0..=16 {
        let t = i as f64 / 8.0;
        let u = (t + 1.0) % 2.0;
        let (p, q) = (a.tracks[0].state_at(t), b.tracks[0].state_at(u));
        assert!(same_state(&p, &q, 1e-9), "t = {t}: {p:?} vs {q:?}");
    }
}

#[test]
fn a_pre_applied_entrance_waits_in_its_start_state() {
    // `[wait, inv_in, hold]`: the shape waits moved and invisible, then enters.
    let src = "duration 3s\n\
         timesplit(1/3, 1/3, 1/3) : [all, s] -> [wait, inv_in, hold]\n\
         animate(affine, world, 0, translate(0, -60)) : [in, s] -> [m]\n\
         animate(opacity, local, 0, 0) : [m, s] -> [o]\n";
    let a = animate(scene(&[("s", (50.0, 100.0), 10.0)]), src).unwrap();
    for t in [0.0, 0.5, 1.0] {
        let s = a.tracks[0].state_at(t);
        assert!(
            same_point(
                s.transform * Point::new(50.0, 100.0),
                Point::new(50.0, 40.0)
            ),
            "{t}"
        );
        assert!(s.opacity.abs() < 1e-9, "{t}: {s:?}");
    }
    assert!(same_point(centre_at(&a, 0, 1.5), Point::new(50.0, 70.0)));
    assert!(same_state(
        &a.tracks[0].state_at(2.5),
        &ShapeState::REST,
        1e-9
    ));
}

#[test]
fn an_offset_not_shorter_than_its_slice_is_a_located_error() {
    // Slices of 1 s; shape #2 would wait 1 s, the whole slice.
    let src = "duration 2s\n\
         timesplit(0.5, 0.5) : [all, d] -> [a, inv_a]\n\
         animate(affine, world, 0.5 * id, translate(0, 10)) : [a, d] -> [m]\n";
    let sc = || scene(&dots(10.0, &[10.0, 30.0, 50.0]));
    let e = animate(sc(), src).unwrap_err();
    let span = e.span.expect("located");
    assert_eq!((span.line, span.col), (3, 1), "{e}");
    assert!(
        e.message.contains("`d` #2") && e.message.contains("1 s"),
        "{e}"
    );
    // `gmotion check` on the scene reports the same error.
    let g = gmotion::grammar::parse(src).unwrap();
    let c = gmotion::engine::check::check(&g, Some(&sc()), &RunOptions::default()).unwrap_err();
    assert_eq!(c, e);
    // Just inside the slice is fine.
    let ok = src.replace("0.5 * id", "0.49 * id");
    assert!(animate(sc(), &ok).is_ok());
}

/// A random change: (type, ref, value, easing, extra named arguments).
fn change_strategy() -> impl Strategy<Value = String> {
    change_with(prop_oneof![
        Just("nearest"),
        Just("bilinear"),
        Just("exact")
    ])
}

/// [`change_strategy`], or a local per-vertex motion: the first change of
/// `inverted_first_is_the_loop_turned_by_half`, which composes innermost there (a
/// pre-applied vertex motion deforms the drawn art, so it must lie under every other).
fn inner_change_strategy() -> impl Strategy<Value = String> {
    change_with(prop_oneof![
        Just("nearest"),
        Just("bilinear"),
        Just("exact"),
        Just("vertex")
    ])
}

/// A random change reading its grid with one of `lookup` (a vertex one always local).
fn change_with(lookup: impl Strategy<Value = &'static str>) -> impl Strategy<Value = String> {
    let affine = (
        -150.0f64..150.0,
        -150.0f64..150.0,
        -170.0f64..170.0,
        0.3f64..2.5,
        0.3f64..2.5,
        -30.0f64..30.0,
        0usize..4,
    )
        .prop_map(|(x, y, r, sx, sy, k, which)| match which {
            0 => format!("translate({x}, {y}) rotate({r})"),
            1 => format!("rotate({r}) scale({sx}, {sy})"),
            2 => format!("scale({sx}) skew({k}, 0) translate({x}, 0)"),
            _ => format!("rotate({r}, {x}, {y})"),
        });
    let colour =
        (0u8..=255, 0u8..=255, 0u8..=255).prop_map(|(r, g, b)| format!("rgb({r}, {g}, {b})"));
    let kind = prop_oneof![
        affine.prop_map(|v| ("affine", v)),
        (0.0f64..400.0, 0.0f64..300.0).prop_map(|(x, y)| ("towards", format!("({x}, {y})"))),
        (0.0f64..400.0, 0.0f64..300.0).prop_map(|(x, y)| ("path", format!("\"M 0 0 L {x} {y}\""))),
        colour.clone().prop_map(|c| ("fill", c)),
        colour.prop_map(|c| ("border", c)),
        (0.0f64..1.0).prop_map(|o| ("opacity", format!("{o}"))),
        (0.0f64..8.0).prop_map(|w| ("stroke-width", format!("{w}"))),
    ];
    let ease = prop_oneof![
        Just(String::new()),
        Just(", ease=ease-in-out".to_string()),
        (0.0f64..1.0, -0.5f64..1.5, 0.0f64..1.0, -0.5f64..1.5)
            .prop_map(|(a, b, c, d)| format!(", ease=cubic({a}, {b}, {c}, {d})")),
        (2u32..6).prop_map(|k| format!(", ease=bspline({k})")),
        (1u32..4).prop_map(|n| format!(", ease=poles({n})")),
    ];
    (kind, any::<bool>(), ease, lookup, 1usize..4, any::<bool>(), 0.0f64..0.5).prop_map(
        |((ty, value), world, ease, lookup, grid, alexa, offset)| {
            let r = if world && lookup != "vertex" { "world" } else { "local" };
            let interp = if alexa { "alexa" } else { "linear" };
            format!(
                "animate({ty}, {r}, {offset} * d, {value}{ease}, grid={grid}x{grid}, lookup={lookup}, interp={interp})"
            )
        },
    )
}

/// Two squares whose centroids lie off every cell boundary of the 1x1 … 3x3 grids the
/// strategies use: a centroid exactly between two rows (y = 200 on a 3-row grid of a 300 px
/// canvas) reads either row depending on the last bit of a state that an undone twin left
/// at the identity up to rounding, which is not what these properties are about.
fn two_squares() -> Scene {
    scene(&[("s", (120.0, 90.0), 20.0), ("s", (300.0, 210.0), 30.0)])
}

/// Every shape's state at `t`.
fn states(a: &Animation, t: f64) -> Vec<ShapeState> {
    a.tracks.iter().map(|tr| tr.state_at(t)).collect()
}

/// The corners of [`two_squares`] and points inside them, deformed by every track at `t`
/// (per-vertex motions move them through the grid; rigid ones as a whole).
fn deformed(a: &Animation, t: f64) -> Vec<Point> {
    let points = [
        (110.0, 80.0),
        (130.0, 100.0),
        (123.0, 86.0),
        (285.0, 195.0),
        (315.0, 225.0),
        (296.0, 219.0),
    ];
    a.tracks
        .iter()
        .flat_map(|tr| {
            points
                .iter()
                .map(move |&(x, y)| tr.deform(Point::new(x, y), t))
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// `[inv_a, a]` at t equals `[a, inv_a]` at t + D/2, for every kind of change, easing,
    /// lookup and interpolation, also when `a` splits into two animated pieces (so the
    /// inverted half is two pre-applied slices, `[inv_c, inv_b, b, c]`).
    #[test]
    fn inverted_first_is_the_loop_turned_by_half(
        c1 in inner_change_strategy(), c2 in change_strategy(), nested in any::<bool>(),
        ts in proptest::collection::vec(0.0f64..2.0, 8),
    ) {
        let body = if nested {
            format!("timesplit(0.4, 0.6) : [a, s] -> [b, c]\n{c1} : [b, s] -> [bd]\n{c2} : [c, s] -> [cd]\n")
        } else {
            format!("{c1} : [a, s] -> [x]\n{c2} : [x, s] -> [y]\n")
        };
        let first = format!("duration 2s\ntimesplit(0.5, 0.5) : [all, s] -> [inv_a, a]\n{body}");
        let last = format!("duration 2s\ntimesplit(0.5, 0.5) : [all, s] -> [a, inv_a]\n{body}");
        let a = animate(two_squares(), &first).unwrap();
        let b = animate(two_squares(), &last).unwrap();
        for t in ts.iter().copied().chain([0.0, 0.5, 1.0, 2.0]) {
            let u = (t + 1.0) % 2.0;
            for (p, q) in states(&a, t).iter().zip(states(&b, u)) {
                prop_assert!(same_state(p, &q, 1e-7), "{first}\nt = {t}: {p:?}\nvs {q:?}");
            }
            for (p, q) in deformed(&a, t).into_iter().zip(deformed(&b, u)) {
                prop_assert!((p - q).hypot() <= 1e-6 * (1.0 + q.to_vec2().hypot()), "{first}\nt = {t}: {p:?} vs {q:?}");
            }
        }
    }

    /// Loops close: `[a, inv_a]`, `[inv_a, a]` and `[a, b, inv_b, inv_a]` end in the state
    /// they start in.
    #[test]
    fn inverted_twins_close_loops(
        c1 in change_strategy(), c2 in change_strategy(), layout in 0usize..3,
    ) {
        let split = match layout {
            0 => "timesplit(0.5, 0.5) : [all, s] -> [a, inv_a]",
            1 => "timesplit(0.5, 0.5) : [all, s] -> [inv_a, a]",
            _ => "timesplit(0.2, 0.3, 0.3, 0.2) : [all, s] -> [a, b, inv_b, inv_a]",
        };
        let mut src = format!("duration 2s\n{split}\n{c1} : [a, s] -> [ad]\n");
        if layout == 2 {
            src.push_str(&format!("{c2} : [b, s] -> [bd]\n"));
        } else {
            src.push_str(&format!("{c2} : [ad, s] -> [bd]\n"));
        }
        let a = animate(two_squares(), &src).unwrap();
        for (p, q) in states(&a, 0.0).iter().zip(states(&a, 2.0)) {
            prop_assert!(same_state(p, &q, 1e-7), "{src}\n{p:?}\nvs {q:?}");
        }
    }

    /// Splitting a moving slice into pieces, some inverted, keeps the parent's motion: with
    /// a twin that changes no transform (an attribute, or the identity) at every instant, and
    /// with any twin outside the twin's two pieces.
    #[test]
    fn twins_keep_the_motion_their_pieces_inherited(
        parent in 0usize..5, second in any::<bool>(), twin in change_strategy(), neutral in 0usize..3,
        ts in proptest::collection::vec(0.0f64..2.0, 8),
    ) {
        let motion = [
            "animate(affine, world, 0, translate(120, -40))",
            "animate(towards, world, 0, (200, 150), lookup=exact)",
            "animate(affine, local, 0, rotate(200))",
            "animate(affine, local, 0, scale(1.7), ease=ease-in)",
            "animate(affine, world, 0, rotate(25, 200, 150))",
        ][parent];
        let mut head = format!("duration 2s\n{motion} : [all, s] -> [p]\n");
        if second {
            head.push_str("animate(affine, local, 0, rotate(-90)) : [p, s] -> [q]\n");
        }
        let last = if second { "q" } else { "p" };
        // A world twin that stretches unevenly wraps an inherited rotation, which the
        // component model can only approximate between window ends (docs/grammar.md,
        // "Inverted tags"); such a twin is made local, where it lies inside the inheritance.
        let uneven = twin.contains("skew(")
            || twin.split("scale(").nth(1).is_some_and(|r| r.split(')').next().is_some_and(|a| a.contains(',')));
        let twin = if uneven { twin.replacen(", world,", ", local,", 1) } else { twin };
        let twin_rule = match neutral {
            0 => twin.clone(),
            1 => "animate(opacity, local, 0, 0.3)".to_string(),
            _ => "animate(affine, local, 0, translate(0, 0))".to_string(),
        };
        let split = format!(
            "{head}timesplit(0.15, 0.25, 0.25, 0.35) : [{last}, s] -> [pre, x, inv_x, post]\n\
             {twin_rule} : [x, s] -> [xd]\n"
        );
        let reference = animate(two_squares(), &head).unwrap();
        let a = animate(two_squares(), &split).unwrap();
        let outside = |t: f64| !(0.3 + 1e-9..1.3 - 1e-9).contains(&t);
        for t in ts.iter().copied().chain([0.0, 0.3, 0.8, 1.3, 2.0]) {
            for (p, q) in states(&a, t).iter().zip(states(&reference, t)) {
                if neutral == 0 && !outside(t) {
                    continue;
                }
                let (mp, mq) = (p.transform.as_coeffs(), q.transform.as_coeffs());
                let ok = mp.iter().zip(mq).all(|(x, y)| (x - y).abs() <= 1e-7 * (1.0 + x.abs()));
                prop_assert!(ok, "{split}\nt = {t}: {p:?}\nvs {q:?}");
                if outside(t) {
                    prop_assert!(same_state(p, &q, 1e-7), "{split}\nt = {t}: {p:?}\nvs {q:?}");
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Edit-stable randomness (issue 13, item 3): a rule's random choice and `rand()` depend on
// the seed, the shape and the step's place in the shape's own derivation, so editing the
// rules of one shape tag leaves every shape of another tag byte-identical.
// ---------------------------------------------------------------------------------------

/// A grammar for shape tags `a`, `b`, `c` with weighted choices between several rules of
/// one match, `rand()` in offsets, values and easings, `step` in a value and slice tag names
/// shared between the tags; `a_rules` are the rules that match only `a`.
fn edit_grammar(choice: &str, a_rules: &str) -> String {
    format!(
        "duration 4s\nfps 10\nchoice {choice}\n\
         {a_rules}\n\
         timesplit(0.5, 0.5) : [all, all] -> [p, inv_p]\n\
         animate(affine, local, rand(0, 0.2), rotate(rand(-40, 40) + 5 * step)) : [p, b] -> [q] weight=2\n\
         animate(affine, world, 0, translate(rand(-30, 30), rand(-30, 30))) : [p, b] -> [q]\n\
         animate(fill, local, 0, lerp(#ff0000, #0000ff, rand())) : [p, b] -> [r] weight=0.5\n\
         animate(affine, local, 0, rotate(rand(-90, 90))) : [p, c] -> [q]\n\
         animate(affine, local, 0, scale(0.5), ease=cubic(rand(), 0, 0.5, 1)) : [p, c] -> [q] weight=3\n\
         timesplit(0.5, 0.5) : [q, (b, c)] -> [s, t]\n\
         animate(opacity, local, 0, rand(0.2, 1)) : [s, all] -> [u]\n\
         animate(affine, local, 0, scale(rand(0.5, 1.5))) : [t, all] -> [u]\n\
         animate(affine, local, 0, rotate(rand(0, 90))) : [t, all] -> [v] weight=0.5\n"
    )
}

/// The rules for `a` before the edits.
const A_RULES: &str = "\
    animate(affine, world, 0, translate(rand(0, 50), 0)) : [p, a] -> [q]\n\
    animate(affine, world, 0, translate(0, rand(0, 50))) : [p, a] -> [q]\n";

/// Every shape's track as text (Rust prints each `f64` so that it reads back bit for bit)
/// and its sampled state at 41 instants.
fn per_shape_output(a: &Animation) -> Vec<String> {
    (0..a.tracks.len())
        .map(|i| {
            let states: Vec<ShapeState> = (0..=40)
                .map(|k| a.tracks[i].state_at(k as f64 * 0.1))
                .collect();
            format!("{:?}\n{states:?}", a.tracks[i])
        })
        .collect()
}

#[test]
fn editing_the_rules_of_one_shape_tag_leaves_the_others_byte_identical() {
    // 72 shapes, so expansion runs in parallel; tags interleaved in document order.
    let items: Vec<(&str, (f64, f64), f64)> = (0..72)
        .map(|i| {
            (
                ["a", "b", "c"][i % 3],
                ((i % 12) as f64 * 30.0 + 20.0, (i / 12) as f64 * 40.0 + 20.0),
                6.0,
            )
        })
        .collect();
    let s = scene(&items);
    let edits: [(&str, String); 5] = [
        // A new candidate for `a` (the global step count of everything after it grows).
        (
            "add a candidate",
            format!(
                "{A_RULES}animate(opacity, local, 0, rand(0.1, 0.9)) : [p, a] -> [w] weight=2\n"
            ),
        ),
        // A rule above everything else that creates `t` and `s` for `a` before `b` and `c`
        // do, in the other order, and that wins over the shared split (priority).
        (
            "insert a split at the top",
            format!("timesplit(0.25, 0.75) : [all, a] -> [t, s] priority=1\n{A_RULES}"),
        ),
        (
            "remove a candidate",
            A_RULES.lines().next().unwrap().to_string(),
        ),
        (
            "change numbers and weights",
            A_RULES
                .replace("rand(0, 50)", "rand(10, 90)")
                .replace("-> [q]\n", "-> [q] weight=4\n"),
        ),
        (
            "give `a` a deeper derivation",
            format!(
                "{A_RULES}timesplit(0.5, 0.5) : [q, a] -> [s, t]\n\
                 animate(affine, local, rand(0, 0.1), scale(rand(1, 2))) : [s, a] -> [x]\n"
            ),
        ),
    ];
    let run_with = |src: &str, seed: u64| {
        let g = gmotion::grammar::parse(src).unwrap();
        per_shape_output(&with_seed(&s, &g, seed))
    };
    for choice in ["group", "shape"] {
        let base_src = edit_grammar(choice, A_RULES);
        let base: Vec<Vec<String>> = (0..20).map(|seed| run_with(&base_src, seed)).collect();
        // The grammar is random where it matters: other seeds give other `b` and `c`
        // animations (so byte equality below is not equality of constant output).
        let moved = (1..20)
            .filter(|&seed| {
                (0..items.len()).any(|i| items[i].0 != "a" && base[seed][i] != base[0][i])
            })
            .count();
        assert_eq!(moved, 19, "choice {choice}: the seed changes too little");
        for (what, a_rules) in &edits {
            let src = edit_grammar(choice, a_rules);
            let mut a_changed = 0;
            for (seed, before) in base.iter().enumerate() {
                let after = run_with(&src, seed as u64);
                for (i, item) in items.iter().enumerate() {
                    if item.0 == "a" {
                        continue;
                    }
                    if before[i] != after[i] {
                        let at = before[i]
                            .bytes()
                            .zip(after[i].bytes())
                            .position(|(x, y)| x != y)
                            .unwrap_or(0);
                        let near = |s: &str| -> String {
                            s.chars().skip(at.saturating_sub(80)).take(160).collect()
                        };
                        panic!(
                            "choice {choice}, seed {seed}, edit `{what}`: shape {i} (`{}`) changed at byte {at}:\n\
                             before …{}…\nafter  …{}…",
                            item.0,
                            near(&before[i]),
                            near(&after[i])
                        );
                    }
                }
                if (0..items.len()).any(|i| items[i].0 == "a" && before[i] != after[i]) {
                    a_changed += 1;
                }
            }
            // The edits do change `a` (so the comparison sees edits at all): in most
            // seeds; removing one of two equal candidates only where it was drawn.
            assert!(
                a_changed >= 5,
                "choice {choice}, edit `{what}`: `a` changed in {a_changed} of 20 seeds"
            );
        }
    }
}

/// The stable keys keep the other promises: same result on one thread and on two, and a
/// slice and its `inv_` twin draw the same numbers (the twin plays the motion backwards, so
/// the shape is back at rest at the end of the pair).
#[test]
fn stable_random_keys_are_thread_independent_and_shared_by_twins() {
    let items = grid_of_squares(200, ["a", "b"]);
    // Shapes that moved (so the twin check saw motion) under `choice group`.
    let mut group_moving = 0;
    for (choice, seed) in [("group", 0), ("group", 1), ("group", 2), ("shape", 0)] {
        let src = format!(
            "duration 2s\nchoice {choice}\nseed {seed}\n\
             timesplit(0.5, 0.5) : [all, all] -> [p, inv_p]\n\
             animate(affine, world, rand(0, 0.3), translate(rand(-20, 20), rand(-20, 20)) rotate(rand(0, 90))) : [p, all] -> [m]\n\
             animate(opacity, local, 0, rand(0, 1)) : [p, all] -> [m] weight=2\n"
        );
        let run_on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| animate(scene(&items), &src).unwrap())
        };
        let (one, two) = (run_on(1), run_on(2));
        assert_eq!(
            per_shape_output(&one),
            per_shape_output(&two),
            "choice {choice}"
        );
        let mut moving = 0;
        for (i, track) in two.tracks.iter().enumerate() {
            let (mid, end) = (track.state_at(1.0), track.state_at(2.0));
            if !track.motions.is_empty() {
                moving += 1;
                assert!(
                    (end.transform * two.scene.shapes[i].centroid - two.scene.shapes[i].centroid)
                        .hypot()
                        < 1e-9,
                    "choice {choice}, shape {i}: the twin did not undo the motion"
                );
                assert!(mid.transform != kurbo::Affine::IDENTITY);
            } else {
                assert!((end.opacity - 1.0).abs() < 1e-9, "shape {i}: {end:?}");
            }
        }
        if choice == "shape" {
            assert!(moving > 20 && moving < 180, "choice shape: {moving} moving");
        } else {
            // One draw per shape tag: each tag's 100 shapes move together or not at all.
            assert_eq!(moving % 100, 0, "choice group: {moving} moving");
            group_moving += moving;
        }
    }
    assert!(group_moving > 0, "no seed moved a shape under choice group");
}

/// The same promise for group grammars: a tile and a disc, each cut into cells that choose
/// at random between colours, wobbles (`perturb`, seeded by the group) and `rand()` sizes.
/// Editing only the tile's rules leaves every piece of the disc as it was, although the
/// tile comes first and its new rules shift the global step count and group ids.
#[test]
fn editing_the_spatial_rules_of_one_tag_leaves_the_others_pieces_identical() {
    use gmotion_import_svg::{ImportOptions, parse as parse_svg};
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="120">
      <rect class="tile" x="10" y="10" width="80" height="80" fill="white" stroke="black"/>
      <circle class="disc" cx="150" cy="50" r="40" fill="#cde" stroke="black"/>
    </svg>"##;
    let scene = parse_svg(svg, "t.svg", &ImportOptions::default())
        .unwrap()
        .scene;
    let disc = "regularSplit(line, 10, 1) : disc -> [dc]\n\
        ungroup() : dc -> [du]\n\
        fill(#102030) : du -> [d_dark] weight=2\n\
        perturb(rand(1, 3), 8) : du -> [d_wobbly]\n\
        outline(rand(0.5, 2)) : du -> [d_in, d_ring]\n";
    let tile = "regularSplit(line, 12, 1) : tile -> [tc]\n\
        ungroup() : tc -> [tu]\n\
        fill(#ff0000) : tu -> [t_red]\n\
        perturb(rand(1, 2), 6) : tu -> [t_wobbly]\n";
    let edits = [
        format!("{tile}fill(#00ff00) : tu -> [t_green] weight=3\n"),
        format!("outline(rand(1, 4)) : tile -> [tc, t_ring] priority=1\n{tile}"),
        tile.replace("perturb(rand(1, 2), 6) : tu -> [t_wobbly]\n", ""),
        tile.replace("rand(1, 2), 6", "rand(2, 5), 9")
            .replace("regularSplit(line, 12, 1)", "regularSplit(line, 7, 1)"),
    ];
    // The pieces of each tag family: tag, paint and geometry, in paint order.
    let pieces = |tiles: &str, seed: u64, family: char| -> Vec<String> {
        let g = gmotion::grammar::parse(&format!("{tiles}{disc}")).unwrap();
        let rules: Vec<&gmotion::grammar::ast::Rule> = g.rules.iter().collect();
        let opts = gmotion::tangle::TangleOptions {
            seed,
            ..Default::default()
        };
        let (out, _) = gmotion::tangle::expand(&scene, &rules, &opts).unwrap();
        (0..out.shapes.len())
            .filter(|&i| out.shapes[i].tag.starts_with(family))
            .map(|i| match out.unit_node(i) {
                Some(Node::Path(p)) => format!(
                    "{} {:?} {:?} {}",
                    out.shapes[i].tag,
                    p.fill,
                    out.shapes[i].parent_transform,
                    p.path.to_svg()
                ),
                other => panic!("piece {i} is not a path: {other:?}"),
            })
            .collect()
    };
    let mut tile_changed = vec![0; edits.len()];
    for seed in 0..20 {
        let (disc_before, tile_before) = (pieces(tile, seed, 'd'), pieces(tile, seed, 't'));
        assert!(
            disc_before.len() > 20,
            "seed {seed}: {} disc pieces",
            disc_before.len()
        );
        for (e, edit) in edits.iter().enumerate() {
            let disc_after = pieces(edit, seed, 'd');
            assert!(
                disc_before == disc_after,
                "seed {seed}, edit {e}: the disc's pieces changed ({} before, {} after)",
                disc_before.len(),
                disc_after.len()
            );
            if pieces(edit, seed, 't') != tile_before {
                tile_changed[e] += 1;
            }
        }
    }
    // Each edit does change the tile.
    assert!(tile_changed.iter().all(|&n| n >= 5), "{tile_changed:?}");
}

#[test]
fn tag_patterns_and_exclusions_choose_the_shapes() {
    let items = [
        ("icon-home", (50.0, 50.0), 10.0),
        ("icon-user", (100.0, 50.0), 10.0),
        ("logo", (150.0, 50.0), 10.0),
        ("bg", (200.0, 50.0), 10.0),
    ];
    let a = animated(
        &items,
        "duration 1s\n\
         let dx = 10 * (id + 1)\n\
         animate(affine, world, 0, translate(dx, 0)) : [all, icon-* - icon-home] -> [m]\n\
         animate(affine, world, 0, translate(0, 20)) : [all, all - (icon-*, bg)] -> [n]\n",
    );
    let moved: Vec<Point> = (0..4)
        .map(|i| centre_at(&a, i, 1.0) - centre_at(&a, i, 0.0).to_vec2())
        .collect();
    assert!(same_point(moved[0], Point::ZERO), "icon-home is left out");
    assert!(
        same_point(moved[1], Point::new(10.0, 0.0)),
        "icon-user matches icon-*"
    );
    assert!(
        same_point(moved[2], Point::new(0.0, 20.0)),
        "logo is all but icons and bg"
    );
    assert!(same_point(moved[3], Point::ZERO), "bg is left out");
    // A pattern that names no shape is an error at the pattern, as an unknown tag is.
    let e = animate(
        scene(&items),
        "duration 1s\nanimate(affine, world, 0, scale(2)) : [all, button-*] -> [m]\n",
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("matches the pattern `button-*`"),
        "{e}"
    );
}
