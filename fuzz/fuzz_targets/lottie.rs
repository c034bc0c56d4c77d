//! The Lottie importer: any bytes as a Lottie document, imported as `gmotion animate
//! anim.json …` does; its scene evaluated at a second frame and drawn small (what
//! `gmotion convert anim.json -o f.png --time T` does), and the document written back with
//! a motionless animation layered over it (the path `animate anim.json … -o out.json` takes).
#![no_main]

use std::path::Path;

use gmotion::canvas::OutputSize;
use gmotion::motion::{Animation, Track};
use gmotion_import_lottie::ImportOptions;
use libfuzzer_sys::fuzz_target;

/// Small, so a run stays fast: the point is the importer and what it hands the renderer.
const SIZE: OutputSize = OutputSize {
    width: Some(64),
    height: None,
};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(imported) = gmotion_import_lottie::parse(text, "fuzz.json", &ImportOptions::default())
    else {
        return;
    };
    let src = &imported.source;
    if let Ok((scene, _)) = src.scene_at(src.frame_at(src.duration() / 2.0)) {
        let svg = gmotion_export_svg::frame::scene_svg(&scene);
        let _ = gmotion_export_raster::render_limited(&svg, SIZE, 1 << 16);
    }
    let still = Animation {
        tracks: vec![Track::default(); imported.scene.shapes.len()],
        scene: imported.scene,
        duration: src.duration(),
        fps: src.fps(),
        looping: true,
    };
    let opts = gmotion_output::Options::default();
    let _ = gmotion_output::lottie_text(&still, Some(src), Path::new("out.json"), &opts);
});
