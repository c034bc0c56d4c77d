//! Frame documents: an animated frame must show the same picture as an SVG written by hand
//! with the state applied, whatever groups and viewBox the unit sits in.

use std::sync::Arc;

use gmotion::color::Color;
use gmotion::motion::grid::{Field, Grid};
use gmotion::motion::{
    Animation, AttrSeg, Component, Interp, MotionKind, MotionSeg, Timing, Tint, Track,
};
use gmotion::scene::Scene;
use gmotion::signals::Easing;
use gmotion_export_raster::{compare, render};
use gmotion_export_svg::frame::{frame_svg, scene_svg};
use gmotion_import_svg::{ImportOptions, parse};
use kurbo::{Affine, Point, Vec2};

/// A 200×100 canvas showing a 100×50 viewBox, the unit inside a translated group.
fn scene_with(unit: &str) -> Scene {
    let text = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100" viewBox="0 0 100 50">
        <defs><linearGradient id="g" x1="0" x2="1"><stop offset="0" stop-color="#00f"/><stop offset="1" stop-color="#0f0"/></linearGradient>
        <linearGradient id="u" gradientUnits="userSpaceOnUse" x2="100"><stop offset="0" stop-color="#f0f"/><stop offset="1" stop-color="#0ff"/></linearGradient></defs>
        <rect width="100" height="50" fill="#eee"/>
        <g transform="translate(10 5)">{unit}</g></svg>"##
    );
    parse(&text, "frame.svg", &ImportOptions::default())
        .unwrap()
        .scene
}

fn timing() -> Timing {
    Timing {
        start: 0.0,
        end: 1.0,
        delay: 0.0,
        ease: Easing::Linear,
        reversed: false,
    }
}

fn animate(scene: Scene, unit: usize, track: Track) -> Animation {
    let mut tracks = vec![Track::default(); scene.shapes.len()];
    tracks[unit] = track;
    Animation {
        scene,
        duration: 1.0,
        fps: 10.0,
        looping: false,
        tracks,
    }
}

/// A track of one motion of `kind` over the whole second.
fn track(kind: MotionKind) -> Track {
    Track {
        motions: vec![MotionSeg {
            t0: 0.0,
            t1: 1.0,
            timing: timing(),
            kind,
            start: Affine::IDENTITY,
        }],
        ..Track::default()
    }
}

fn rigid(pivot: Point, components: Vec<Component>) -> Track {
    track(MotionKind::Rigid {
        pivot,
        blend: Arc::from([(1.0, Arc::from(components))]),
        interp: Interp::Linear,
    })
}

/// The fraction of differing pixels between the frame and the hand-written picture.
fn differs(frame: &str, unit: &str) -> f64 {
    let expected = scene_svg(&scene_with(unit));
    compare(
        &render(frame, 200).unwrap(),
        &render(&expected, 200).unwrap(),
        32,
    )
}

const RECT: &str = r##"<rect class="r" width="20" height="10" fill="#00f"/>"##;

#[test]
fn rest_frames_are_the_scene() {
    let anim = animate(scene_with(RECT), 1, Track::default());
    let frame = frame_svg(&anim, 0.5);
    assert_eq!(differs(&frame, RECT), 0.0);
}

#[test]
fn canvas_translation_lands_in_canvas_pixels() {
    // 60 canvas px right is 30 user units at the viewBox's scale of 2.
    let anim = animate(
        scene_with(RECT),
        1,
        rigid(
            Point::ORIGIN,
            vec![Component::Translate(Vec2::new(60.0, 0.0))],
        ),
    );
    assert!(
        differs(
            &frame_svg(&anim, 1.0),
            r##"<rect x="30" width="20" height="10" fill="#00f"/>"##
        ) < 1e-3
    );
    assert!(
        differs(
            &frame_svg(&anim, 0.5),
            r##"<rect x="15" width="20" height="10" fill="#00f"/>"##
        ) < 1e-3
    );
    assert!(
        differs(&frame_svg(&anim, 0.5), RECT) > 0.01,
        "the frame must move"
    );
}

#[test]
fn local_rotation_turns_about_the_centroid() {
    let scene = scene_with(RECT);
    let centroid = scene.shapes[1].centroid;
    // The rect's centre in its own coordinates is (10, 5); on the canvas (40, 20).
    assert!(centroid.distance(Point::new(40.0, 20.0)) < 1e-6);
    let anim = animate(scene, 1, rigid(centroid, vec![Component::Rotate(90.0)]));
    let want = r##"<rect transform="rotate(90 10 5)" width="20" height="10" fill="#00f"/>"##;
    assert!(differs(&frame_svg(&anim, 1.0), want) < 1e-3);
}

#[test]
fn tints_reach_solid_colours_and_gradient_stops() {
    let red = Tint::full(Color::rgb(1.0, 0.0, 0.0));
    let tint = |from, to| {
        vec![AttrSeg {
            t0: 0.0,
            t1: 1.0,
            timing: timing(),
            from,
            to,
        }]
    };
    let unit = r##"<g class="u"><rect width="20" height="10" fill="#00f"/><rect y="12" width="20" height="10" fill="url(#g)" stroke="#0f0" stroke-width="2"/></g>"##;
    let track = Track {
        fill: tint(Tint::NONE, red),
        stroke: tint(red, red),
        ..Track::default()
    };
    let anim = animate(scene_with(unit), 1, track);
    let want = r##"<rect width="20" height="10" fill="#f00"/><rect y="12" width="20" height="10" fill="#f00" stroke="#f00" stroke-width="2"/>"##;
    let frame = frame_svg(&anim, 1.0);
    assert!(differs(&frame, want) < 1e-3);
    // Half way the solid fill is the even mix of blue and red.
    let frame = frame_svg(&anim, 0.5);
    assert!(frame.contains("fill=\"#800080\""), "{frame}");
    assert!(!frame.contains("fill=\"#0000ff\""), "{frame}");
}

#[test]
fn opacity_and_stroke_width_factors_apply() {
    let unit = r##"<rect width="20" height="10" fill="#00f" stroke="#000" stroke-width="2"/>"##;
    let factor = |v| {
        vec![AttrSeg {
            t0: 0.0,
            t1: 1.0,
            timing: timing(),
            from: 1.0,
            to: v,
        }]
    };
    let track = Track {
        opacity: factor(0.5),
        stroke_width: factor(3.0),
        ..Track::default()
    };
    let anim = animate(scene_with(unit), 1, track);
    let want = r##"<rect width="20" height="10" fill="#00f" stroke="#000" stroke-width="6" opacity="0.5"/>"##;
    assert!(differs(&frame_svg(&anim, 1.0), want) < 1e-3);
}

#[test]
fn vertex_deformation_moves_every_point() {
    let scene = scene_with(RECT);
    let field = Field::Constant(Arc::from([Component::Translate(Vec2::new(60.0, 0.0))]));
    let grid = Arc::new(Grid::new(2, 2, scene.canvas(), field));
    let track = track(MotionKind::Vertex { grid, pivot: None });
    assert!(track.deforms());
    let anim = animate(scene, 1, track);
    assert!(
        differs(
            &frame_svg(&anim, 1.0),
            r##"<rect x="30" width="20" height="10" fill="#00f"/>"##
        ) < 1e-3
    );
}

#[test]
fn frames_share_definitions() {
    let unit = r##"<rect class="a" width="20" height="10" fill="url(#u)"/><rect class="a" y="12" width="20" height="10" fill="url(#u)"/>"##;
    let scene = scene_with(unit);
    let text = scene_svg(&scene);
    assert_eq!(text.matches("<linearGradient").count(), 1, "{text}");
    let anim = animate(
        scene,
        1,
        rigid(Point::ORIGIN, vec![Component::Rotate(33.0)]),
    );
    // A moving frame still writes the gradient both units use once.
    let frame = frame_svg(&anim, 0.37);
    assert_eq!(frame.matches("<linearGradient").count(), 1, "{frame}");
}

/// `scene_svg` of the imported `src` renders as `src` itself does.
fn reproduces(src: &str) -> f64 {
    let scene = parse(src, "src.svg", &ImportOptions::default())
        .unwrap()
        .scene;
    compare(
        &render(&scene_svg(&scene), 200).unwrap(),
        &render(src, 200).unwrap(),
        32,
    )
}

#[test]
fn clip_content_keeps_nested_clips_in_place() {
    // The inner clip is set on a `use` whose target has a transform of its own: the writer
    // flattens the two into one path and must move the inner clip to match.
    let src = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="200">
        <defs><rect id="r" transform="scale(2)" width="50" height="60"/></defs>
        <clipPath id="inner"><rect x="0" y="0" width="40" height="200"/></clipPath>
        <clipPath id="outer"><use href="#r" transform="translate(20 10)" clip-path="url(#inner)"/>
            <circle cx="150" cy="150" r="30"/></clipPath>
        <rect width="200" height="200" fill="green" clip-path="url(#outer)"/></svg>"##;
    assert!(reproduces(src) < 1e-3);
    let text = scene_svg(
        &parse(src, "src.svg", &ImportOptions::default())
            .unwrap()
            .scene,
    );
    assert!(text.matches("<clipPath").count() == 2, "{text}");
}

/// A fresh, empty folder of this test's own.
fn folder(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("gmotion-frames-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The names in `dir`, sorted.
fn names(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn blank_frames(n: usize) -> Vec<resvg::tiny_skia::Pixmap> {
    (0..n)
        .map(|_| resvg::tiny_skia::Pixmap::new(3, 2).unwrap())
        .collect()
}

#[test]
fn frame_folders_hold_only_the_latest_run() {
    use gmotion_export_raster::{frame_file_name, write_frames};
    let parent = folder("fresh");
    let dir = parent.join("frames");
    write_frames(&blank_frames(5), &dir).unwrap();
    let five: Vec<String> = (0..5).map(frame_file_name).collect();
    assert_eq!(names(&dir), five);
    // A shorter run leaves no stale frames of the longer one.
    write_frames(&blank_frames(3), &dir).unwrap();
    assert_eq!(names(&dir), five[..3].to_vec());
    let png = resvg::tiny_skia::Pixmap::load_png(dir.join(&five[2])).unwrap();
    assert_eq!((png.width(), png.height()), (3, 2));
    // Nothing is left beside the folder (the hidden staging folder is gone).
    assert_eq!(names(&parent), ["frames"]);
    std::fs::remove_dir_all(&parent).unwrap();
}

#[test]
fn frame_folders_holding_other_files_are_refused_untouched() {
    use gmotion_export_raster::{RenderError, write_frames};
    // Each intruder alone makes the folder someone else's: a note, a frame-like name that
    // is not gmotion's pattern, and a folder named like a frame.
    for (intruder, is_dir) in [
        ("notes.txt", false),
        ("frame_1.png", false),
        ("frame_00009.png", true),
    ] {
        let parent = folder(&format!("refuse-{intruder}"));
        let dir = parent.join("frames");
        std::fs::create_dir(&dir).unwrap();
        std::fs::write(dir.join("frame_00000.png"), b"old").unwrap();
        if is_dir {
            std::fs::create_dir(dir.join(intruder)).unwrap();
        } else {
            std::fs::write(dir.join(intruder), b"mine").unwrap();
        }
        let before = names(&dir);
        let err = write_frames(&blank_frames(2), &dir).unwrap_err();
        assert!(
            matches!(&err, RenderError::FolderInUse { others, .. } if others == &[intruder]),
            "{intruder}: {err}"
        );
        assert!(err.to_string().contains(intruder), "{err}");
        assert_eq!(names(&dir), before, "{intruder}: the folder changed");
        assert_eq!(std::fs::read(dir.join("frame_00000.png")).unwrap(), b"old");
        assert_eq!(
            names(&parent),
            ["frames"],
            "{intruder}: something was written"
        );
        std::fs::remove_dir_all(&parent).unwrap();
    }
}
