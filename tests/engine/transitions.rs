//! Data-driven transitions (`gmotion::transitions`): the animation built from smoothed
//! samples reproduces them at every frame, and bad targets are reported by line.

use gmotion::motion::Tint;
use gmotion::scene::Scene;
use gmotion::signals::SmoothSpec;
use gmotion::transitions::{self, Targets, sample, tracks};
use gmotion_import_svg::{ImportOptions, parse};

use crate::support::grammar_file;

/// Every frame of every track reproduces the samples it was built from.
fn assert_tracks_reproduce(
    scene: &Scene,
    targets: &Targets,
    system: &SmoothSpec,
    fps: f64,
) -> usize {
    let samples = sample(scene, targets, system, fps, None).unwrap();
    let anim = tracks::animation(scene, &samples);
    assert_eq!(anim.tracks.len(), scene.shapes.len());
    let mut windows = 0;
    for s in &samples.shapes {
        let track = &anim.tracks[s.shape];
        windows += track.motions.len();
        for k in 0..samples.frames {
            let t = samples.time(k);
            let want = s.state(k);
            let got = track.state_at(t);
            let m = want.transform(s.anchor);
            for (a, b) in got.transform.as_coeffs().iter().zip(m.as_coeffs()) {
                assert!(
                    (a - b).abs() < 1e-6 * (1.0 + b.abs()),
                    "shape {} frame {k}: {a} vs {b}",
                    s.shape
                );
            }
            assert!((got.opacity - want.opacity.clamp(0.0, 1.0)).abs() < 1e-12);
            if let Some(f) = want.fill {
                let c = |x: f64| x.clamp(0.0, 1.0) as f32;
                let tint = Tint {
                    sum: [c(f[0]), c(f[1]), c(f[2])],
                    weight: c(f[3]),
                };
                assert!((got.fill.weight - tint.weight).abs() < 1e-6, "frame {k}");
                for c in 0..3 {
                    assert!((got.fill.sum[c] - tint.sum[c]).abs() < 1e-6);
                }
            }
        }
    }
    windows
}

#[test]
fn examples_run_and_tracks_reproduce_samples() {
    for name in ["histogram", "permutation", "revisions"] {
        let svg = std::fs::read_to_string(grammar_file(&format!("{name}.svg"))).unwrap();
        let json = std::fs::read_to_string(grammar_file(&format!("{name}.targets.json"))).unwrap();
        let scene = parse(&svg, name, &ImportOptions::default()).unwrap().scene;
        let targets = Targets::parse(&json).unwrap();
        let system = targets.default_system(None);
        let windows = assert_tracks_reproduce(&scene, &targets, &system, 30.0);
        assert!(windows > 100, "{name}: only {windows} motion windows");
    }
}

#[test]
fn rotation_with_non_uniform_scale_stays_exact() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="200">
        <rect class="box" x="20" y="30" width="40" height="20" fill="#f00"/>
        <rect class="box" x="100" y="100" width="30" height="30" fill="#00f"/></svg>"##;
    let scene = parse(svg, "test", &ImportOptions::default()).unwrap().scene;
    let csv = "# anchor.box: 0 1\ntime,tag,id,attr,value\n0,box,0,rotate,30\n0.2,box,*,rotate,-45\n\
               0.3,box,0,sx,2\n0.5,box,1,sy,0\n0.6,box,*,x,150\n0.7,box,1,opacity,0.2\n0.8,box,0,fill,#00ff00\n";
    let targets = Targets::parse(csv).unwrap();
    for text in ["spring(0.3, 0.4)", "fir(bspline(3), 0.2)", "none"] {
        let system = SmoothSpec::parse(text).unwrap();
        assert_tracks_reproduce(&scene, &targets, &system, 24.0);
    }
}

#[test]
fn unknown_shapes_are_reported_with_their_line() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="50" height="50">
        <rect class="box" x="0" y="0" width="10" height="10"/></svg>"##;
    let scene = parse(svg, "test", &ImportOptions::default()).unwrap().scene;
    let system = SmoothSpec::Identity;
    for (csv, needle) in [
        (
            "time,tag,id,attr,value\n1,ball,0,x,3\n",
            "line 2: no shape has the tag `ball`",
        ),
        (
            "time,tag,id,attr,value\n1,box,4,x,3\n",
            "line 2: shape `box` #4 does not exist",
        ),
    ] {
        let targets = Targets::parse(csv).unwrap();
        let msg = transitions::run(&scene, &targets, &system, 30.0, None)
            .unwrap_err()
            .to_string();
        assert!(msg.contains(needle), "{msg}");
    }
    let targets = Targets::parse("time,tag,id,attr,value\n1,box,0,x,3\n").unwrap();
    let arc = SmoothSpec::parse("arc(0.5, 1)").unwrap();
    assert!(transitions::run(&scene, &targets, &system, 0.0, None).is_err());
    assert!(transitions::run(&scene, &targets, &arc, 30.0, Some(-1.0)).is_err());
    let ok = transitions::run(&scene, &targets, &arc, 30.0, None).unwrap();
    assert!(ok.duration > 1.0 && ok.duration < 2.5, "{}", ok.duration);
}
