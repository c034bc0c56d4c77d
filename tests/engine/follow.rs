//! `animate(follow, …)`: motion along a path, checked against its definition (issue 42):
//! the centroid stays on the path at every frame, by arc length, `orient=auto` keeps the
//! shape's heading along the tangent, an inverted twin plays the path backwards, a local
//! spin composes on top, and bad arguments are errors located at the argument.

use gmotion::engine::{EngineError, RunOptions, run};
use gmotion::motion::Animation;
use gmotion::scene::Scene;
use kurbo::{BezPath, ParamCurve, ParamCurveArclen, ParamCurveNearest, Point, Vec2};

use crate::support::centre_at;

/// The default `--tolerance` (canvas units).
const TOLERANCE: f64 = 0.25;

const CURVE: &str = "M 40 180 C 120 20 280 20 360 180";

/// A 400 × 300 scene with one square of side 20 centred at `(x, y)`, tagged `s`.
fn scene(x: f64, y: f64) -> Scene {
    crate::support::squares((400.0, 300.0), &[("s", (x, y), 20.0)], true)
}

fn animate(scene: Scene, src: &str) -> Result<Animation, EngineError> {
    let g =
        gmotion::grammar::parse(src).map_err(|d| EngineError::general(d.render("test.gm", src)))?;
    run(scene, &g, &RunOptions::default()).map(|(a, _)| a)
}

/// The distance from `p` to `path`, and the unit tangent at the nearest point.
fn nearest(path: &BezPath, p: Point) -> (f64, Vec2) {
    let mut best = (f64::INFINITY, Vec2::ZERO);
    for seg in path.segments() {
        let n = seg.nearest(p, 1e-9);
        let d = n.distance_sq.sqrt();
        if d < best.0 {
            let h = 1e-4;
            let (a, b) = ((n.t - h).max(0.0), (n.t + h).min(1.0));
            best = (d, (seg.eval(b) - seg.eval(a)).normalize());
        }
    }
    best
}

/// The arc length of `path` from its start to the point nearest `p`.
fn travelled(path: &BezPath, p: Point) -> f64 {
    let mut total = 0.0;
    let mut best = (f64::INFINITY, 0.0);
    for seg in path.segments() {
        let n = seg.nearest(p, 1e-9);
        if n.distance_sq < best.0 {
            best = (n.distance_sq, total + seg.subsegment(0.0..n.t).arclen(1e-9));
        }
        total += seg.arclen(1e-9);
    }
    best.1
}

fn length(path: &BezPath) -> f64 {
    path.segments().map(|s| s.arclen(1e-9)).sum()
}

/// The frames of `a` (and the instants halfway between them).
fn instants(a: &Animation) -> impl Iterator<Item = f64> + '_ {
    (0..=2 * a.frame_count()).map(|k| k as f64 * 0.5 / a.fps)
}

#[test]
fn the_centroid_stays_on_the_path_by_arc_length() {
    for ease in [
        "linear",
        "ease-in-out",
        "cubic(0.6, 0.1, 0.2, 0.9)",
        "bspline(3)",
    ] {
        let src = format!(
            "duration 2s\nloop false\nanimate(follow, world, 0, \"{CURVE}\", ease={ease}) : [all, s] -> [m]\n"
        );
        let a = animate(scene(40.0, 180.0), &src).unwrap();
        let path = BezPath::from_svg(CURVE).unwrap();
        let total = length(&path);
        let easing = gmotion::signals::Easing::from_call(
            ease.split('(').next().unwrap(),
            &ease
                .split(['(', ')', ','])
                .skip(1)
                .filter_map(|x| x.trim().parse().ok())
                .collect::<Vec<f64>>(),
        )
        .unwrap();
        let sampler = a.sampler();
        let mut head = sampler.playhead();
        for t in instants(&a) {
            let c = centre_at(&a, 0, t);
            let (d, _) = nearest(&path, c);
            assert!(d <= TOLERANCE, "{ease}: {d} px off the path at {t} s");
            // By arc length, at the rule's easing.
            let want = easing.apply((t / 2.0).min(1.0)) * total;
            let got = travelled(&path, c);
            assert!(
                (got - want).abs() <= TOLERANCE,
                "{ease} at {t} s: {got} along, want {want}"
            );
            // The playhead (what renderers use) agrees with the track.
            let played = head.seek(t)[0].transform * a.scene.shapes[0].centroid;
            assert!((played - c).hypot() < 1e-9);
        }
    }
}

#[test]
fn local_places_the_path_on_the_centroid() {
    let a = animate(
        scene(100.0, 100.0),
        &format!(
            "duration 2s\nloop false\nanimate(follow, local, 0, \"{CURVE}\") : [all, s] -> [m]\n"
        ),
    )
    .unwrap();
    let mut path = BezPath::from_svg(CURVE).unwrap();
    path.apply_affine(kurbo::Affine::translate(Vec2::new(60.0, -80.0)));
    for t in instants(&a) {
        let (d, _) = nearest(&path, centre_at(&a, 0, t));
        assert!(d <= TOLERANCE, "{d} px off the placed path at {t} s");
    }
    assert!((centre_at(&a, 0, 2.0) - Point::new(420.0, 100.0)).hypot() < 1e-6);
}

#[test]
fn orient_auto_keeps_the_heading_along_the_tangent() {
    // A loop with a corner-free turn through every direction.
    let d = "M 100 150 C 100 50 300 50 300 150 S 100 250 100 150";
    let a = animate(
        scene(100.0, 150.0),
        &format!(
            "duration 2s\nloop false\nanimate(follow, world, 0, \"{d}\", orient=auto, ease=ease-in-out) : [all, s] -> [m]\n"
        ),
    )
    .unwrap();
    let path = BezPath::from_svg(d).unwrap();
    // The path leaves its start straight up.
    let start = Vec2::new(0.0, -1.0);
    for t in instants(&a) {
        let m = a.tracks[0].transform_at(t);
        let c = m * a.scene.shapes[0].centroid;
        let (dist, tangent) = nearest(&path, c);
        assert!(dist <= TOLERANCE);
        // The shape's own x axis, turned by the transform, makes the angle the tangent
        // makes with the start tangent.
        let [m00, m10, ..] = m.as_coeffs();
        let axis = Vec2::new(m00, m10).normalize();
        let want = start.cross(tangent).atan2(start.dot(tangent));
        let got = axis.y.atan2(axis.x);
        let diff = (got - want).sin().abs();
        // 10 px from the centre (the square's half side), the heading's error in pixels.
        assert!(
            diff * 10.0 <= TOLERANCE,
            "at {t} s: heading {got}, tangent {want}"
        );
    }
}

#[test]
fn the_inverted_twin_plays_the_path_backwards() {
    let a = animate(
        scene(40.0, 180.0),
        &format!(
            "duration 4s\ntimesplit(0.5, 0.5) : [all, s] -> [a, inv_a]\nanimate(follow, local, 0, \"{CURVE}\", orient=auto, ease=ease-in) : [a, s] -> [m]\n"
        ),
    )
    .unwrap();
    for k in 0..=40 {
        let x = k as f64 * 0.05;
        let fwd = a.tracks[0].transform_at(2.0 - x);
        let back = a.tracks[0].transform_at(2.0 + x);
        for (p, q) in fwd.as_coeffs().iter().zip(back.as_coeffs()) {
            assert!((p - q).abs() < 1e-6, "at ±{x} s: {fwd:?} vs {back:?}");
        }
    }
    assert!((centre_at(&a, 0, 4.0) - Point::new(40.0, 180.0)).hypot() < 1e-6);
}

#[test]
fn a_local_spin_turns_about_the_travelling_centre() {
    let a = animate(
        scene(40.0, 180.0),
        &format!(
            "duration 2s\nloop false\nanimate(follow, world, 0, \"{CURVE}\") : [all, s] -> [m]\nanimate(affine, local, 0, rotate(360)) : [m, s] -> [n]\n"
        ),
    )
    .unwrap();
    let path = BezPath::from_svg(CURVE).unwrap();
    for t in instants(&a) {
        let (d, _) = nearest(&path, centre_at(&a, 0, t));
        assert!(d <= TOLERANCE, "{d} px off the path at {t} s");
    }
    let m = a.tracks[0].transform_at(0.5);
    assert!(
        (m.as_coeffs()[0] - 0.0).abs() < 1e-6,
        "a quarter turn at a quarter of the way"
    );
}

#[test]
fn a_follow_on_a_grid_moves_every_cell_alike() {
    let s = crate::support::squares(
        (400.0, 300.0),
        &[("s", (50.0, 50.0), 10.0), ("s", (300.0, 250.0), 10.0)],
        true,
    );
    let a = animate(
        s,
        "duration 2s\nloop false\ngrid 4x4\nanimate(follow, local, 0, \"M0 0 C 50 -50 100 50 150 0\") : [all, s] -> [m]\n",
    )
    .unwrap();
    for t in [0.5, 1.0, 2.0] {
        let d0 = centre_at(&a, 0, t) - Point::new(50.0, 50.0);
        let d1 = centre_at(&a, 1, t) - Point::new(300.0, 250.0);
        assert!((d0 - d1).hypot() < 1e-9);
    }
}

/// The error `src` gives, with its place.
fn error(src: &str) -> EngineError {
    animate(scene(50.0, 50.0), src).unwrap_err()
}

#[test]
fn orient_is_an_error_on_other_types() {
    let src = "animate(affine, local, 0, rotate(30), orient=auto) : [all, s] -> [m]\n";
    let e = error(src);
    let span = e.span.expect("located");
    assert_eq!(&src[span.start..span.end], "orient=auto");
    assert!(e.message.contains("follow"), "{}", e.message);
}

#[test]
fn bad_path_data_is_located_inside_the_string() {
    let src = "animate(follow, local, 0, \"M 0 0 L 10 x 20\") : [all, s] -> [m]\n";
    let e = error(src);
    let span = e.span.expect("located");
    assert_eq!(&src[span.start..span.end], "x", "{}", e.message);
    assert_eq!(span.col as usize, src.find('x').unwrap() + 1);
    let e = error("animate(follow, local, 0, \"M 5 5\") : [all, s] -> [m]\n");
    assert!(e.message.contains("no length"), "{}", e.message);
    let e = error("animate(follow, local, 0, shape(nothing)) : [all, s] -> [m]\n");
    assert!(e.message.contains("no shape is tagged"), "{}", e.message);
}

#[test]
fn follows_another_shapes_outline() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="400" height="300">
        <path data-tag="track" d="M 40 180 C 120 20 280 20 360 180" fill="none" stroke="black"/>
        <rect data-tag="s" x="30" y="170" width="20" height="20" fill="red"/>
        </svg>"#;
    let a = crate::support::run_grammar(
        crate::support::scene_of(svg),
        "duration 2s\nloop false\nanimate(follow, world, 0, shape(track)) : [all, s] -> [m]\n",
    );
    let path = BezPath::from_svg(CURVE).unwrap();
    let s = a.scene.shapes.iter().position(|x| x.tag == "s").unwrap();
    for t in instants(&a) {
        let (d, _) = nearest(&path, centre_at(&a, s, t));
        assert!(d <= TOLERANCE, "{d} px off the outline at {t} s");
    }
}
