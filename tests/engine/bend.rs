//! `lookup=vertex` cuts outlines where the field bends them (issue 42): a band under a
//! 12×1 `path` grid waves along the curve, and the outline drawn through its moved points
//! stays within the tolerance of the exact field, measured at many points of the outline
//! at many frames.

use gmotion::motion::bend::refine;
use gmotion::motion::{Animation, Track};
use kurbo::{Affine, BezPath, ParamCurve, ParamCurveNearest, PathSeg, Point};

const TOLERANCE: f64 = 0.25;

const SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="400" height="240">
<rect data-tag="band" x="20" y="40" width="360" height="24" fill="#2e86ab"/>
<path data-tag="leaf" d="M 60 150 C 120 100 220 100 300 150 C 220 200 120 200 60 150 Z" fill="#e4572e"/>
</svg>"##;

fn anim(grammar: &str) -> Animation {
    crate::support::run_grammar(crate::support::scene_of(SVG), grammar)
}

/// Every segment of `path` with every point moved by `track` at `t`.
fn drawn(path: &BezPath, track: &Track, t: f64) -> Vec<PathSeg> {
    let m = |q: Point| track.deform(q, t);
    path.segments()
        .map(|s| match s {
            PathSeg::Line(l) => PathSeg::Line(kurbo::Line::new(m(l.p0), m(l.p1))),
            PathSeg::Quad(q) => PathSeg::Quad(kurbo::QuadBez::new(m(q.p0), m(q.p1), m(q.p2))),
            PathSeg::Cubic(c) => {
                PathSeg::Cubic(kurbo::CubicBez::new(m(c.p0), m(c.p1), m(c.p2), m(c.p3)))
            }
        })
        .collect()
}

/// The largest distance from the exact field's image of `path` (at 64 points a segment)
/// to the outline drawn through the moved points of `cut`.
fn worst(path: &BezPath, cut: &BezPath, track: &Track, t: f64) -> f64 {
    let outline = drawn(cut, track, t);
    path.segments()
        .flat_map(|s| (0..=64).map(move |k| s.eval(k as f64 / 64.0)))
        .map(|q| {
            let exact = track.deform(q, t);
            outline
                .iter()
                .map(|o| o.nearest(exact, 1e-9).distance_sq.sqrt())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

fn outline(a: &Animation, tag: &str) -> (usize, BezPath) {
    let k = a.scene.shapes.iter().position(|s| s.tag == tag).unwrap();
    let mut out = BezPath::new();
    fn walk(n: &gmotion::scene::Node, m: Affine, out: &mut BezPath) {
        match n {
            gmotion::scene::Node::Path(p) => out.extend((m * p.path.clone()).iter()),
            gmotion::scene::Node::Group(g) => g
                .children
                .iter()
                .for_each(|c| walk(c, m * g.transform, out)),
            gmotion::scene::Node::Image(_) => {}
        }
    }
    walk(
        a.scene.unit_node(k).unwrap(),
        a.scene.shapes[k].parent_transform,
        &mut out,
    );
    (k, out)
}

#[test]
fn a_band_under_a_path_grid_waves_within_the_tolerance() {
    for (grammar, tag) in [
        (
            "duration 2s\nloop false\nanimate(path, world, 0, \"M 0 120 C 100 20 300 220 400 120\", grid=12x1, lookup=vertex, ease=ease-in-out) : [all, band] -> [bent]\n",
            "band",
        ),
        (
            "duration 2s\nloop false\nanimate(path, world, 0, \"M 40 60 L 200 220 L 360 60\", grid=6x6, lookup=vertex) : [all, leaf] -> [pulled]\n",
            "leaf",
        ),
    ] {
        let a = anim(grammar);
        let (k, path) = outline(&a, tag);
        let track = &a.tracks[k];
        let mut bent = false;
        for f in 0..=a.frame_count() {
            let t = a.frame_time(f);
            let cut = refine(&path, Affine::IDENTITY, &[track], &[t], TOLERANCE);
            let w = worst(&path, &cut, track, t);
            assert!(w <= TOLERANCE, "{tag} frame {f}: {w} px from the field");
            // Without the cuts the outline strays (so the test can tell).
            bent |= worst(&path, &path, track, t) > 4.0 * TOLERANCE;
        }
        assert!(bent, "{tag}: the field never bends the outline");
    }
}

#[test]
fn an_unbent_outline_is_left_as_it_is() {
    // A 1×1 grid moves every point alike: nothing to cut.
    let a = anim(
        "duration 2s\nanimate(affine, world, 0, translate(40, 10) rotate(20), lookup=vertex) : [all, leaf] -> [m]\n",
    );
    let (k, path) = outline(&a, "leaf");
    let cut = refine(
        &path,
        Affine::IDENTITY,
        &[&a.tracks[k]],
        &[0.5, 1.0, 2.0],
        TOLERANCE,
    );
    assert!(matches!(cut, std::borrow::Cow::Borrowed(_)));
}
