//! Group grammar operators and expansion, tested as properties on random polygons with
//! holes: splits and outlines partition their parent, placed shapes and stipples lie inside
//! it without overlapping, degenerate input never panics, and expansion is deterministic.

use gmotion::grammar::ast::Rule;
use gmotion::scene::{FillRule, Node, Scene};
use gmotion::tangle::boolean::{difference, normalize, union_all};
use gmotion::tangle::field::FieldKind;
use gmotion::tangle::noise::{Rng, key};
use gmotion::tangle::ops::outline::outline;
use gmotion::tangle::ops::perturb::perturb;
use gmotion::tangle::ops::regular_split::{Curve, SplitParams, regular_split};
use gmotion::tangle::ops::stipple::{StippleKind, StippleParams, stipple};
use gmotion::tangle::ops::streamline::streamline_split;
use gmotion::tangle::place::{PlaceParams, PlaceShape, place};
use gmotion::tangle::polygon::{Grid, Polygon, Region};
use gmotion::tangle::{TangleError, TangleOptions, expand};
use gmotion_import_svg::{ImportOptions, parse as parse_svg};
use kurbo::{Point, Rect, Vec2};
use proptest::prelude::*;

fn grid() -> Grid {
    Grid::for_bounds(Rect::new(-600.0, -600.0, 600.0, 600.0)).unwrap()
}

/// A star-shaped ring: `radii` around `c`, turned by `turn`.
fn star(c: Point, radii: &[f64], scale: f64, turn: f64) -> Vec<Point> {
    let n = radii.len();
    (0..n)
        .map(|k| {
            let a = turn + std::f64::consts::TAU * k as f64 / n as f64;
            c + Vec2::from_angle(a) * (radii[k] * scale)
        })
        .collect()
}

/// A random polygon with up to three holes, valid (normalised by the engine).
fn holed_polygon() -> impl Strategy<Value = Region> {
    (
        proptest::collection::vec(0.6f64..1.0, 5..24),
        0usize..4,
        proptest::collection::vec(proptest::collection::vec(0.5f64..1.0, 4..9), 3),
        20.0f64..250.0,
        -100.0f64..100.0,
        -100.0f64..100.0,
        0.0f64..6.3,
    )
        .prop_map(|(radii, holes, hole_radii, scale, cx, cy, turn)| {
            let c = Point::new(cx, cy);
            let mut rings = vec![star(c, &radii, scale, turn)];
            for (h, hr) in hole_radii.iter().take(holes).enumerate() {
                // Hole centres 0.45 r apart on a circle, radius at most 0.2 r: inside the
                // outer ring (whose radius is at least 0.6 r) and apart from each other.
                let at = c + Vec2::from_angle(turn + 2.1 * h as f64) * (0.3 * scale);
                let mut ring = star(at, hr, 0.2 * scale, turn);
                ring.reverse();
                rings.push(ring);
            }
            normalize(&rings, FillRule::EvenOdd, &grid())
        })
}

/// A random self-intersecting vertex soup, as a designer's broken path might be.
fn tangled_path() -> impl Strategy<Value = Vec<Point>> {
    proptest::collection::vec((-150.0f64..150.0, -150.0f64..150.0), 3..14)
        .prop_map(|v| v.into_iter().map(|(x, y)| Point::new(x, y)).collect())
}

/// Segments `ab` and `cd` cross at a point interior to both.
fn properly_cross(a: Point, b: Point, c: Point, d: Point) -> bool {
    let o = |p: Point, q: Point, r: Point| (q - p).cross(r - p);
    let (d1, d2, d3, d4) = (o(c, d, a), o(c, d, b), o(a, b, c), o(a, b, d));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// Whether any two non-adjacent edges of one polygon cross.
fn self_intersects(p: &Polygon) -> bool {
    let edges: Vec<(Point, Point)> = p.edges().collect();
    for i in 0..edges.len() {
        for j in i + 1..edges.len() {
            let (a, b) = edges[i];
            let (c, d) = edges[j];
            if a == c || a == d || b == c || b == d {
                continue;
            }
            if properly_cross(a, b, c, d) {
                return true;
            }
        }
    }
    false
}

/// Total area covered more than once: the pieces' area sum minus their union's area (at
/// least every pairwise overlap, at most their sum).
fn overlap_area(pieces: &[Region], grid: &Grid) -> f64 {
    let sum: f64 = pieces.iter().map(Region::area).sum();
    sum - union_all(pieces.iter(), grid).area()
}

/// The gTangle validity property: pieces tile the parent.
fn assert_partition(parent: &Region, pieces: &[Region], grid: &Grid) -> Result<(), TestCaseError> {
    let a = parent.area();
    let sum: f64 = pieces.iter().map(Region::area).sum();
    prop_assert!((sum - a).abs() <= 1e-3 * a, "area sum {sum} vs parent {a}");
    let union = union_all(pieces.iter(), grid);
    let over = sum - union.area();
    prop_assert!(over <= 1e-3 * a, "overlap {over} of {a}");
    let outside = difference(&union, parent, grid).area();
    prop_assert!(outside <= 1e-3 * a, "pieces stick out by {outside}");
    for poly in pieces.iter().flat_map(|p| &p.polygons) {
        prop_assert!(!self_intersects(poly), "self-intersecting piece boundary");
    }
    Ok(())
}

fn pieces_of(r: Region) -> Vec<Region> {
    r.polygons.into_iter().map(Region::from_polygon).collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn regular_splits_partition(
        region in holed_polygon(),
        offsets in proptest::collection::vec(4.0f64..60.0, 1..4),
        dual in any::<bool>(),
        zigzag in any::<bool>(),
        angle in 0.0f64..6.3,
    ) {
        let g = grid();
        let curve = if zigzag {
            Curve::Polyline(vec![Point::new(0.0, 0.0), Point::new(6.0, 5.0), Point::new(12.0, 0.0)])
        } else {
            Curve::Line
        };
        let params = SplitParams { curve, offsets, dual };
        let pieces = regular_split(&region, Vec2::from_angle(angle), &params, &g).unwrap();
        prop_assert!(!pieces.is_empty());
        let regions: Vec<Region> = pieces.into_iter().map(|p| p.region).collect();
        assert_partition(&region, &regions, &g)?;
    }

    #[test]
    fn outlines_partition(region in holed_polygon(), d in 0.5f64..80.0) {
        let g = grid();
        let (out, inner) = outline(&region, d, &g).unwrap();
        let mut pieces = pieces_of(out);
        pieces.extend(pieces_of(inner.clone()));
        assert_partition(&region, &pieces, &g)?;
        // The inner shapes keep their distance from the outline.
        for p in inner.polygons.iter().flat_map(|p| p.outer.iter()) {
            prop_assert!(region.boundary_distance(*p) >= 0.95 * d, "inner vertex too close");
        }
    }

    #[test]
    fn streamline_splits_partition(region in holed_polygon(), which in 0usize..3, spacing in 6.0f64..40.0) {
        let g = grid();
        let kind = match which {
            0 => FieldKind::Outline,
            1 => FieldKind::Strip,
            _ => FieldKind::Circular(region.centroid()),
        };
        let pieces = streamline_split(&region, kind, spacing, 1.0, Vec2::new(1.0, 0.0), &g).unwrap();
        prop_assert!(!pieces.is_empty());
        assert_partition(&region, &pieces, &g)?;
    }

    #[test]
    fn placed_shapes_fit_and_keep_apart(
        region in holed_polygon(),
        which in 0usize..3,
        size in 4.0f64..30.0,
        spread in 1.0f64..2.0,
        seed in any::<u64>(),
    ) {
        let g = grid();
        let shape = match which {
            0 => PlaceShape::Circle,
            1 => PlaceShape::Square,
            _ => PlaceShape::Path(normalize(
                &[vec![Point::new(0.0, 0.0), Point::new(4.0, 1.0), Point::new(1.0, 4.0)]],
                FillRule::NonZero,
                &g,
            )),
        };
        let params = PlaceParams { shape, size, distance: size * spread };
        // A coarse working resolution keeps the (debug-build) rasters small; validity does
        // not depend on it.
        let out = place(&region, &params, Vec2::new(1.0, 0.0), &mut Rng::new(seed), &g, (2.0, LIMIT)).unwrap();
        let a = region.area();
        for p in &out.placed {
            prop_assert!(difference(p, &region, &g).area() <= 1e-9 * a + 1e-6, "placed shape outside");
        }
        prop_assert!(overlap_area(&out.placed, &g) <= 1e-9 * a + 1e-6, "placed shapes overlap");
        let mut all = out.placed.clone();
        all.extend(pieces_of(out.remainder));
        assert_partition(&region, &all, &g)?;
    }

    #[test]
    fn stipples_lie_inside(region in holed_polygon(), which in 0usize..3, density in 0.2f64..4.0, seed in any::<u64>()) {
        let g = grid();
        let kind = [StippleKind::Dots, StippleKind::Dashes, StippleKind::Curves][which];
        let params = StippleParams { kind, density, size: 1.5 };
        let marks = stipple(&region, &params, &mut Rng::new(seed), &g, 0.5).unwrap();
        for m in &marks.polygons {
            let m = Region::from_polygon(m.clone());
            prop_assert!(difference(&m, &region, &g).area() <= 1e-9, "mark outside");
        }
    }

    #[test]
    fn perturbation_keeps_valid_polygons(region in holed_polygon(), amplitude in 0.0f64..4.0, seed in any::<u64>()) {
        let g = grid();
        let moved = perturb(&region, amplitude, 15.0, seed, &g).unwrap();
        for p in &moved.polygons {
            prop_assert!(!self_intersects(p));
        }
        // Every vertex moved by at most the amplitude (lattice points added on edges too).
        prop_assert!((moved.area() - region.area()).abs() <= 0.5 * region.area() + 1.0);
    }

    #[test]
    fn broken_input_never_panics(points in tangled_path(), d in 0.1f64..500.0, seed in any::<u64>()) {
        let g = grid();
        let region = normalize(&[points], FillRule::NonZero, &g);
        let params = SplitParams { curve: Curve::Line, offsets: vec![d], dual: true };
        if let Ok(pieces) = regular_split(&region, Vec2::new(0.6, 0.8), &params, &g) {
            let regions: Vec<Region> = pieces.into_iter().map(|p| p.region).collect();
            // (The overlap check is quadratic; thousands of cells are checked elsewhere.)
            if region.area() > 0.0 && regions.len() < 400 {
                assert_partition(&region, &regions, &g)?;
            }
        }
        let (out, inner) = outline(&region, d, &g).unwrap();
        prop_assert!((out.area() + inner.area() - region.area()).abs() <= 1e-3 * region.area() + 1e-9);
        let _ = streamline_split(&region, FieldKind::Outline, d.max(2.0), 1.0, Vec2::new(1.0, 0.0), &g);
        let params = PlaceParams { shape: PlaceShape::Circle, size: d, distance: d };
        let out = place(&region, &params, Vec2::new(1.0, 0.0), &mut Rng::new(seed), &g, (0.5, LIMIT)).unwrap();
        prop_assert!(out.placed.iter().all(|p| difference(p, &region, &g).area() <= 1e-6));
    }
}

#[test]
fn degenerate_shapes_give_clean_results() {
    let g = grid();
    let empty = Region::default();
    let flat = normalize(
        &[vec![
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(20.0, 0.0),
        ]],
        FillRule::NonZero,
        &g,
    );
    for r in [&empty, &flat] {
        assert_eq!(r.area(), 0.0);
        let params = SplitParams {
            curve: Curve::Line,
            offsets: vec![5.0],
            dual: true,
        };
        assert!(
            regular_split(r, Vec2::new(1.0, 0.0), &params, &g)
                .unwrap()
                .is_empty()
        );
        let (out, inner) = outline(r, 3.0, &g).unwrap();
        assert!(out.is_empty() && inner.is_empty());
        assert!(
            streamline_split(r, FieldKind::Strip, 5.0, 1.0, Vec2::new(1.0, 0.0), &g)
                .unwrap()
                .is_empty()
        );
        let params = PlaceParams::new(PlaceShape::Circle, 5.0, 6.0);
        assert!(
            place(
                r,
                &params,
                Vec2::new(1.0, 0.0),
                &mut Rng::new(1),
                &g,
                (0.5, LIMIT)
            )
            .unwrap()
            .placed
            .is_empty()
        );
        let s = StippleParams {
            kind: StippleKind::Dots,
            density: 1.0,
            size: 1.0,
        };
        assert!(
            stipple(r, &s, &mut Rng::new(1), &g, 0.5)
                .unwrap()
                .is_empty()
        );
    }
    // A split far from the shape's scale misses it: the shape comes back whole.
    let square = normalize(
        &[star(Point::ZERO, &[1.0; 4], 10.0, 0.785)],
        FillRule::NonZero,
        &g,
    );
    let params = SplitParams {
        curve: Curve::Line,
        offsets: vec![1000.0],
        dual: false,
    };
    let pieces = regular_split(&square, Vec2::new(1.0, 0.0), &params, &g).unwrap();
    assert_eq!(pieces.len(), 1);
    assert!((pieces[0].region.area() - square.area()).abs() < 1e-9);
    // Places larger than the shape place nothing.
    let params = PlaceParams::new(PlaceShape::Square, 500.0, 600.0);
    let mut rng = Rng::new(key(&[2]));
    let out = place(
        &square,
        &params,
        Vec2::new(1.0, 0.0),
        &mut rng,
        &g,
        (0.5, LIMIT),
    )
    .unwrap();
    assert!(out.placed.is_empty());
    assert_eq!(out.remainder, square);
    // Shapes 40 times larger than their distance overlap thousands of neighbours each:
    // refused (a located warning at the rule), where resolving them took 35 s.
    let params = PlaceParams::new(PlaceShape::Circle, 20.0, 0.5);
    let big = Region::from_rect(Rect::new(0.0, 0.0, 300.0, 300.0));
    let g = Grid::for_bounds(big.bbox()).unwrap();
    let err = place(
        &big,
        &params,
        Vec2::new(1.0, 0.0),
        &mut rng,
        &g,
        (0.5, usize::MAX),
    )
    .unwrap_err();
    assert!(err.contains("too many neighbours"), "{err}");
    // Room for more pieces than the limit is refused before any is placed (on the leaf,
    // `place(0.01, 0.011)` made 398 805 pieces in 15 s and 1.5 GB).
    let params = PlaceParams::new(PlaceShape::Circle, 1.0, 1.2);
    let err = place(
        &big,
        &params,
        Vec2::new(1.0, 0.0),
        &mut rng,
        &g,
        (0.5, 10_000),
    )
    .unwrap_err();
    assert!(
        err.contains("more than the limit of 10000") && err.contains("--limit pieces"),
        "{err}"
    );
}

/// The default `pieces` limit, as `gmotion` applies it.
const LIMIT: usize = gmotion::tangle::DEFAULT_MAX_PIECES;

// ---- expansion on scenes ----

const TILE_SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="120">
  <rect class="tile" x="10" y="10" width="80" height="80" fill="white" stroke="black"/>
  <g transform="translate(100 0) scale(2)">
    <circle class="disc" cx="25" cy="25" r="20" fill="#cde" stroke="black" stroke-width="0.5"/>
  </g>
  <path class="line" d="M0 110 L200 110" stroke="black"/>
</svg>"##;

fn scene() -> Scene {
    parse_svg(TILE_SVG, "tile.svg", &ImportOptions::default())
        .unwrap()
        .scene
}

fn run(grammar: &str, seed: u64) -> Result<(Scene, gmotion::tangle::TangleStats), TangleError> {
    run_with(
        grammar,
        &TangleOptions {
            seed,
            ..TangleOptions::default()
        },
    )
}

/// Expands the tile scene by `grammar` with `opts`.
fn run_with(
    grammar: &str,
    opts: &TangleOptions,
) -> Result<(Scene, gmotion::tangle::TangleStats), TangleError> {
    let g = gmotion::grammar::parse(grammar).unwrap();
    let rules: Vec<&Rule> = g.rules.iter().collect();
    expand(&scene(), &rules, opts)
}

fn canvas_area(s: &Scene, tag: &str) -> f64 {
    let g = grid();
    let mut total = 0.0;
    for shape in s.shapes.iter().filter(|sh| sh.tag == tag) {
        let Some(Node::Path(p)) = s.unit_node(
            s.shapes
                .iter()
                .position(|x| std::ptr::eq(x, shape))
                .unwrap(),
        ) else {
            panic!("pieces are paths");
        };
        let rings =
            gmotion::tangle::polygon::flatten_rings(&p.path, shape.parent_transform, 0.01, &g);
        total += normalize(&rings, FillRule::NonZero, &g).area();
    }
    total
}

#[test]
fn expansion_replaces_shapes_with_pieces_in_place() {
    let (s, stats) = run(
        "regularSplit(line, 20, 1) : tile -> [cell]\noutline(4) : disc -> [ring, core]\n",
        1,
    )
    .unwrap();
    assert_eq!(stats.steps, 2);
    let cells = s.shapes.iter().filter(|x| x.tag == "cell").count();
    assert_eq!(cells, 16);
    assert_eq!(s.shapes.iter().filter(|x| x.tag == "ring").count(), 1);
    assert_eq!(s.shapes.iter().filter(|x| x.tag == "core").count(), 1);
    assert_eq!(s.shapes.iter().filter(|x| x.tag == "line").count(), 1);
    assert_eq!(stats.shapes, 18);
    // Areas in canvas space survive the trip through the scene tree and its transforms.
    assert!((canvas_area(&s, "cell") - 6400.0).abs() < 1.0);
    // The disc was flattened to within the default tolerance of 0.5, which loses at most
    // 2/3 · 0.5 · perimeter of its area.
    let disc = std::f64::consts::PI * 40.0 * 40.0;
    let lost = disc - canvas_area(&s, "ring") - canvas_area(&s, "core");
    assert!(
        (0.0..2.0 / 3.0 * 0.5 * std::f64::consts::TAU * 40.0).contains(&lost),
        "{lost}"
    );
    // Shapes are listed in paint order with valid node paths, ids per tag.
    for (i, sh) in s.shapes.iter().enumerate() {
        assert_eq!(sh.z, i);
        assert_eq!(s.unit_node(i).and_then(Node::unit), Some(i));
    }
    let ids: Vec<usize> = s
        .shapes
        .iter()
        .filter(|x| x.tag == "cell")
        .map(|x| x.id)
        .collect();
    assert_eq!(ids, (0..16).collect::<Vec<_>>());
    // All cells of one split share a group; the ring and core get groups of their own.
    let groups: std::collections::HashSet<usize> = s
        .shapes
        .iter()
        .filter(|x| x.tag == "cell")
        .map(|x| x.group)
        .collect();
    assert_eq!(groups.len(), 1);
    let ring = s.shapes.iter().find(|x| x.tag == "ring").unwrap().group;
    let core = s.shapes.iter().find(|x| x.tag == "core").unwrap().group;
    assert!(ring != core && !groups.contains(&ring));
}

#[test]
fn regroup_deals_a_chessboard() {
    let g = "regularSplit(line, 20, 1) : tile -> [cell]\nregroup(2, chessboard) : cell -> [a, b]\nfill(#000000) : a -> [black]\n";
    let (s, _) = run(g, 3).unwrap();
    let black: Vec<_> = s.shapes.iter().filter(|x| x.tag == "black").collect();
    let white: Vec<_> = s.shapes.iter().filter(|x| x.tag == "b").collect();
    assert_eq!((black.len(), white.len()), (8, 8));
    assert!(black.iter().all(|x| x.fill == gmotion::color::Color::BLACK));
    // Chessboard: no two black cells share an edge (their centroids are never 20 apart).
    for a in &black {
        for b in &black {
            let d = (a.centroid - b.centroid).hypot();
            assert!(!(1.0..=25.0).contains(&d), "adjacent black cells {d}");
        }
    }
}

#[test]
fn expansion_is_deterministic_and_seeded() {
    let g = "regularSplit(line, 10, 1) : tile -> [c]\nungroup() : c -> [u]\nstipple(dots, 2) : u -> [s, dots] weight=2\nfill(#102030) : u -> [f]\n";
    let fingerprint = |s: &Scene| -> Vec<(String, usize, i64, i64)> {
        s.shapes
            .iter()
            .map(|x| {
                (
                    x.tag.clone(),
                    x.group,
                    (x.centroid.x * 1e6) as i64,
                    (x.bbox.area() * 1e6) as i64,
                )
            })
            .collect()
    };
    let (a, sa) = run(g, 7).unwrap();
    // Whatever the thread count.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let (b, _) = pool.install(|| run(g, 7)).unwrap();
    assert_eq!(fingerprint(&a), fingerprint(&b));
    // 64 groups chose independently; another seed changes some choices.
    assert_eq!(sa.steps, 2 + 64);
    let (c, _) = run(g, 8).unwrap();
    assert_ne!(fingerprint(&a), fingerprint(&c));
    let tags: std::collections::HashSet<&str> = a.shapes.iter().map(|x| x.tag.as_str()).collect();
    assert!(tags.contains("f") && tags.contains("dots"));
}

#[test]
fn runaway_grammars_stop_with_an_error() {
    for (grammar, op) in [
        ("outline(1) : tile -> [tile, tile]\n", "outline"),
        ("regroup(1) : tile -> [tile]\n", "regroup"),
    ] {
        let opts = TangleOptions {
            max_steps: 40,
            ..TangleOptions::default()
        };
        let err = run_with(grammar, &opts).unwrap_err();
        assert!(
            matches!(err, TangleError::MaxSteps { steps: 40, .. }),
            "{err}"
        );
        assert!(err.to_string().contains(&format!("`{op}` at 1:1")), "{err}");
    }
    let opts = TangleOptions {
        max_shapes: 1000,
        ..TangleOptions::default()
    };
    let err = run_with("regularSplit(line, 2, 1) : tile -> [tile]\n", &opts).unwrap_err();
    assert!(
        matches!(err, TangleError::MaxShapes { limit: 1000, .. }),
        "{err}"
    );
}

#[test]
fn bad_arguments_point_at_the_rule() {
    for (g, needle) in [
        ("outline(-3) : tile -> [a]\n", "positive"),
        ("outline(red) : tile -> [a]\n", "expected a number"),
        (
            "regroup(2, diagonal) : tile -> [a]\n",
            "unknown regroup mode",
        ),
        ("frobnicate(2) : tile -> [a]\n", "unknown spatial operator"),
        ("regularSplit(line) : tile -> [a]\n", "offsets"),
        (
            "place(blob, 3, 4) : tile -> [b, a]\n",
            "circle, square or path",
        ),
        ("fill(1, 2) : tile -> [a]\n", "at most 1"),
    ] {
        let err = run(g, 1).unwrap_err();
        let TangleError::Arg { span, message } = &err else {
            panic!("{err}")
        };
        assert_eq!(span.line, 1, "{g}");
        assert!(message.contains(needle), "{g}: {message}");
    }
}

#[test]
fn operator_warnings_leave_shapes_whole() {
    // A split curve whose ends meet cannot repeat; the tile passes through with a warning.
    let (s, stats) = run("regularSplit(\"M0 0 L5 5 L0 0\", 10) : tile -> [a]\n", 1).unwrap();
    assert_eq!(stats.warnings.len(), 1);
    assert_eq!(stats.warnings[0].span.map(|s| s.line), Some(1));
    assert_eq!(s.shapes.iter().filter(|x| x.tag == "a").count(), 1);
    assert!((canvas_area(&s, "a") - 6400.0).abs() < 1e-6);
}

#[test]
fn zero_area_input_is_warned_about_and_kept() {
    let (s, stats) = run("outline(2) : line -> [b, a]\n", 1).unwrap();
    assert!(stats.warnings.iter().any(|w| w.message.contains("no area")));
    assert_eq!(s.shapes.iter().filter(|x| x.tag == "line").count(), 1);
}

// ---- the documentation ----

/// The "Spatial (group grammar) operators" section of docs/grammar.md.
fn spatial_docs() -> String {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/grammar.md"))
        .expect("docs/grammar.md reads");
    let start = doc
        .find("## Spatial (group grammar) operators")
        .expect("the spatial section exists");
    let end = doc[start + 3..]
        .find("\n## ")
        .map_or(doc.len(), |e| start + 3 + e);
    doc[start..end].to_string()
}

#[test]
fn documented_examples_parse_and_bind() {
    use gmotion::tangle::bind::{ShapeEnv, ShapeVars, bind};
    let section = spatial_docs();
    let blocks: Vec<&str> = section.split("```").skip(1).step_by(2).collect();
    assert_eq!(blocks.len(), 7, "one example per operator family");
    let vars = ShapeVars {
        sid: 0,
        n: 1,
        group: 0,
        centroid: Point::new(50.0, 50.0),
        bbox: Rect::new(0.0, 0.0, 100.0, 100.0),
        canvas: (100.0, 100.0),
        step: 0,
        text: (0, 0),
    };
    for block in blocks {
        let g = gmotion::grammar::parse(block).unwrap_or_else(|e| panic!("{block}: {e:?}"));
        for rule in &g.rules {
            assert!(rule.spatial, "{block}");
            bind(rule, &mut ShapeEnv::new(vars, 1, 1)).unwrap_or_else(|e| panic!("{block}: {e}"));
        }
    }
}

#[test]
fn documented_pictures_have_their_sources() {
    let section = spatial_docs();
    let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/img"));
    let pictures: Vec<&str> = section
        .split("](img/")
        .skip(1)
        .map(|s| s.split(')').next().expect("a closing parenthesis"))
        .collect();
    assert_eq!(pictures.len(), 7);
    for png in pictures {
        assert!(dir.join(png).exists(), "{png}");
        let stem = png.trim_end_matches(".png");
        let svg = std::fs::read_to_string(dir.join(format!("{stem}.svg"))).expect("scene reads");
        let src = std::fs::read_to_string(dir.join(format!("{stem}.gm"))).expect("grammar reads");
        let scene = parse_svg(&svg, stem, &ImportOptions::default())
            .expect("scene imports")
            .scene;
        let g = gmotion::grammar::parse(&src).expect("grammar parses");
        let rules: Vec<&Rule> = g.rules.iter().collect();
        let opts = TangleOptions::with_seed(3);
        let (_, stats) = expand(&scene, &rules, &opts).expect("grammar expands");
        assert!(stats.warnings.is_empty(), "{stem}: {:?}", stats.warnings);
        assert!(stats.shapes > 0, "{stem}");
    }
}
