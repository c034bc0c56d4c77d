//! The Lottie importer: any bytes as a Lottie document, imported as `gmotion animate
//! anim.json …` does; its scene evaluated at a second frame and drawn small (what
//! `gmotion convert anim.json -o f.png --time T` does), and the document written back with
//! a grammar's motion (turn, fade, tint, widen every unit) layered over it (the path
//! `animate anim.json … -o out.json` takes). Inputs of odd length are imported with
//! `--units groups`.
#![no_main]

use std::path::Path;

use gmotion::canvas::OutputSize;
use gmotion::engine::{self, RunOptions};
use gmotion_import_lottie::{ImportOptions, Units};
use libfuzzer_sys::fuzz_target;

/// Small, so a run stays fast: the point is the importer and what it hands the renderer.
const SIZE: OutputSize = OutputSize {
    width: Some(64),
    height: None,
};

/// Motion of every kind the layered export writes, on every unit.
const GRAMMAR: &str = "duration 1s\nfps 10\n\
    animate(affine, local, 0, rotate(90)) : [all, all] -> [turned]\n\
    animate(opacity, local, 0, 0.5) : [turned, all] -> [faded]\n\
    animate(fill, local, 0, #3366ff) : [faded, all] -> [blue]\n\
    animate(stroke-width, local, 0, 3) : [blue, all] -> [wide]\n";

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let opts = ImportOptions {
        units: if data.len() % 2 == 1 {
            Units::Groups
        } else {
            Units::Layers
        },
        ..ImportOptions::default()
    };
    let Ok(imported) = gmotion_import_lottie::parse(text, "fuzz.json", &opts) else {
        return;
    };
    let src = &imported.source;
    if let Ok((scene, _)) = src.scene_at(src.frame_at(src.duration() / 2.0)) {
        let svg = gmotion_export_svg::frame::scene_svg(&scene);
        let _ = gmotion_export_raster::render_limited(&svg, SIZE, 1 << 16);
    }
    let Ok(g) = gmotion::grammar::parse(GRAMMAR) else {
        return;
    };
    let Ok((anim, _)) = engine::run(imported.scene, &g, &RunOptions::default()) else {
        return;
    };
    let opts = gmotion_output::Options::default();
    let _ = gmotion_output::lottie_text(&anim, Some(src), &[], Path::new("out.json"), &opts);
});
