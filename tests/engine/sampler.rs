//! The fast [`Sampler`] against the reference evaluation ([`Track::state_at`]): on every
//! bundled example, the transition examples and grammars with smoothing and stacked
//! motions, both must give bit-identical states at every frame and around every segment
//! boundary, and a [`gmotion::motion::Playhead`] stepping through the same instants must
//! agree with both.

use gmotion::engine::{RunOptions, run};
use gmotion::motion::{Animation, Sampler, ShapeState};
use gmotion_import_svg::{ImportOptions, load};

use crate::support::root;

fn example(name: &str) -> Animation {
    let dir = root().join("grammars");
    let scene = load(&dir.join(format!("{name}.svg")), &ImportOptions::default())
        .unwrap()
        .scene;
    let src = std::fs::read_to_string(dir.join(format!("{name}.gm"))).unwrap();
    let grammar = gmotion::grammar::parse(&src).unwrap();
    run(scene, &grammar, &RunOptions::default()).unwrap().0
}

/// Every frame time plus each segment boundary and its neighbours.
fn instants(anim: &Animation) -> Vec<f64> {
    let mut ts: Vec<f64> = (0..=anim.frame_count())
        .map(|i| anim.frame_time(i))
        .collect();
    for tr in &anim.tracks {
        let bounds = tr
            .motions
            .iter()
            .map(|m| (m.t0, m.t1))
            .chain(tr.fill.iter().map(|m| (m.t0, m.t1)))
            .chain(tr.stroke.iter().map(|m| (m.t0, m.t1)))
            .chain(tr.opacity.iter().map(|m| (m.t0, m.t1)))
            .chain(tr.stroke_width.iter().map(|m| (m.t0, m.t1)));
        // Where each change starts and stops moving inside its window (after a delay, or
        // before it in inverted slices).
        let active = tr
            .motions
            .iter()
            .map(|m| m.timing.active())
            .chain(tr.fill.iter().map(|m| m.timing.active()))
            .chain(tr.stroke.iter().map(|m| m.timing.active()))
            .chain(tr.opacity.iter().map(|m| m.timing.active()))
            .chain(tr.stroke_width.iter().map(|m| m.timing.active()));
        for (a, b) in bounds.chain(active) {
            for t in [a, b] {
                ts.extend([
                    t - 1e-6,
                    t - 1e-9,
                    t - 1e-12,
                    t,
                    t + 1e-12,
                    t + 1e-9,
                    t + 1e-6,
                ]);
            }
        }
    }
    ts.push(-1.0);
    ts.push(anim.duration + 1.0);
    ts.sort_by(f64::total_cmp);
    ts.dedup();
    ts
}

fn assert_same(name: &str, anim: &Animation) {
    let sampler = Sampler::new(anim);
    assert_eq!(sampler.len(), anim.tracks.len());
    let ts = instants(anim);
    let mut moving = 0;
    for &t in &ts {
        let fast = sampler.evaluate(t);
        let slow = anim.evaluate(t);
        for (i, (f, s)) in fast.iter().zip(&slow).enumerate() {
            assert_eq!(f, s, "{name}: shape {i} at t = {t}");
            if *s != ShapeState::REST {
                moving += 1;
            }
        }
    }
    // A playhead moving forward through the same instants, then jumping back.
    let mut head = sampler.playhead();
    for &t in &ts {
        let slow = anim.evaluate(t);
        assert_eq!(head.seek(t), &slow[..], "{name}: playhead at t = {t}");
    }
    for &t in ts.iter().rev().step_by(7) {
        let slow = anim.evaluate(t);
        assert_eq!(head.seek(t), &slow[..], "{name}: playhead back at t = {t}");
    }
    let animated = anim.tracks.iter().any(|t| !t.is_still());
    // A static example (leaf: group grammar only) has nothing to compare but must agree.
    assert!(
        moving > 0 || !animated,
        "{name}: nothing moves, the comparison proves nothing"
    );
}

#[test]
fn sampler_matches_reference_on_every_example() {
    let mut names: Vec<String> = std::fs::read_dir(root().join("grammars"))
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "gm"))
        .filter(|p| p.with_extension("svg").exists())
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        // Every shape's boundaries are instants for every shape, so the check grows with
        // the square of the shapes: intersections (8216 shapes, a delay per patch) took two
        // CPU-minutes. Its rules are intersections_mini's (tests/engine/gallery.rs), checked here,
        // and the 2600-shape case below covers sampling in several parts.
        .filter(|n| n != "intersections")
        .collect();
    names.sort();
    assert!(names.len() >= 7, "examples missing: {names:?}");
    for name in names {
        assert_same(&name, &example(&name));
    }
}

#[test]
fn sampler_matches_reference_with_smoothing_blends_and_alexa() {
    let dir = root().join("grammars");
    let scene = load(&dir.join("toy.svg"), &ImportOptions::default())
        .unwrap()
        .scene;
    // Bilinear lookups give blends of several cells, Alexa interpolation and a vertex
    // grid take the general path, two motions share a slice, smoothing rewrites tracks.
    for src in [
        "duration 4s\nfps 20\ngrid 3x3\nlookup bilinear\n\
         timesplit(0.3, 0.4, 0.3) : [all, all] -> [a, b, inv_a]\n\
         animate(towards, world, 0.1 * id, (100, 50)) : [a, all] -> [m]\n\
         animate(affine, local, 0, rotate(40) scale(1.3)) : [m, all] -> [m2]\n\
         animate(fill, local, 0, #ff0000, ease = ease-in-out) : [m2, all] -> [m3]\n\
         animate(opacity, local, 0, 0.4) : [b, all] -> [b2]\n",
        "duration 3s\nfps 20\ninterp alexa\n\
         timesplit(0.5, 0.5) : [all, all] -> [a, inv_a]\n\
         animate(affine, world, 0, rotate(60, 100, 100) translate(20, 0)) : [a, all] -> [x]\n",
        "duration 3s\nfps 20\ngrid 4x4\nlookup vertex\n\
         timesplit(0.5, 0.5) : [all, all] -> [a, inv_a]\n\
         animate(towards, world, 0, (50, 50)) : [a, all] -> [x]\n\
         animate(stroke-width, local, 0, 6) : [x, all] -> [y]\n",
        "duration 4s\nfps 25\nsmoothing spring(4, 0.6)\n\
         timesplit(0.25, 0.25, 0.25, 0.25) : [all, all] -> [a, b, inv_b, inv_a]\n\
         animate(affine, local, 0, translate(40, 0)) : [a, all] -> [x]\n\
         animate(affine, world, 0, translate(0, 30) rotate(20)) : [b, all] -> [y]\n",
    ] {
        let grammar = gmotion::grammar::parse(src).unwrap();
        let anim = run(scene.clone(), &grammar, &RunOptions::default())
            .unwrap_or_else(|e| panic!("{src}: {}", e.message))
            .0;
        assert_same(src, &anim);
    }
}

#[test]
fn sampler_matches_reference_on_transitions() {
    use gmotion::transitions::{Targets, run};
    let dir = root().join("grammars");
    for name in ["histogram", "permutation", "revisions"] {
        let scene = load(&dir.join(format!("{name}.svg")), &ImportOptions::default())
            .unwrap()
            .scene;
        let targets = Targets::load(&dir.join(format!("{name}.targets.json"))).unwrap();
        let system = targets.default_system(None);
        let anim = run(&scene, &targets, &system, 30.0, None).unwrap();
        assert_same(name, &anim);
    }
}

#[test]
fn sampler_matches_reference_across_parts() {
    // More shapes than one part of the sampler holds (parts are compiled in parallel and
    // renumber their shared products), with tag-wide rotations and skews that every shape
    // of a tag shares and staggered delays so shapes reach them at different progress.
    let mut svg =
        String::from(r#"<svg xmlns="http://www.w3.org/2000/svg" width="520" height="500">"#);
    for i in 0..2600 {
        let (x, y) = ((i % 52) * 10, (i / 52) * 10);
        svg.push_str(&format!(
            r##"<rect class="t{}" x="{x}" y="{y}" width="6" height="6" fill="#336699"/>"##,
            i % 3
        ));
    }
    svg.push_str("</svg>");
    let scene = gmotion_import_svg::parse(&svg, "parts.svg", &ImportOptions::default())
        .unwrap()
        .scene;
    assert_eq!(scene.shapes.len(), 2600);
    let src = "duration 2s\nfps 15\n\
         timesplit(0.5, 0.5) : [all, all] -> [a, inv_a]\n\
         animate(affine, local, 0.0004 * id, rotate(45) scale(1.2)) : [a, t0] -> [r]\n\
         animate(affine, world, 0, skew(12, 0)) : [a, t1] -> [s]\n\
         animate(affine, local, 0, rotate(-30)) : [a, t2] -> [u]\n\
         animate(affine, local, 0.0002 * id, skew(0, 8)) : [u, t2] -> [v]\n";
    let grammar = gmotion::grammar::parse(src).unwrap();
    let anim = run(scene, &grammar, &RunOptions::default()).unwrap().0;
    // Frame times only: the boundary neighbourhoods of 2600 tracks would make this slow,
    // and the examples already probe them.
    let sampler = Sampler::new(&anim);
    assert_eq!(sampler.len(), 2600);
    let mut head = sampler.playhead();
    let mut moving = 0;
    for i in 0..=anim.frame_count() {
        let t = anim.frame_time(i);
        let slow = anim.evaluate(t);
        assert_eq!(sampler.evaluate(t), slow, "sampler at t = {t}");
        assert_eq!(head.seek(t), &slow[..], "playhead at t = {t}");
        moving += slow.iter().filter(|s| **s != ShapeState::REST).count();
    }
    assert!(moving > 2600 * 10, "too little moves: {moving}");
}
