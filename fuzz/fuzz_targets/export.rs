//! Grammar + scene → every export, as `gmotion animate SCENE GRAMMAR -o x.json -o x.svg -o
//! f.png` runs them under the command's default limits. The first byte picks one of the
//! bundled example scenes, the rest is the grammar; a grammar that runs is written as
//! Lottie and SMIL text and one frame is drawn small (tiny-skia's panics on huge numbers
//! were found this way).
#![no_main]

use std::path::Path;

use gmotion::canvas::OutputSize;
use gmotion::engine::{self, RunOptions};
use gmotion_import_svg::ImportOptions;
use libfuzzer_sys::fuzz_target;

/// The small example scenes; a seed is the index byte followed by a grammar for it.
const SCENES: &[&str] = &[
    include_str!("../../grammars/toy.svg"),
    include_str!("../../grammars/leaf.svg"),
    include_str!("../../grammars/growing_tangle.svg"),
    include_str!("../../grammars/regroup.svg"),
    include_str!("../../grammars/cube.svg"),
    include_str!("../../grammars/variations.svg"),
    include_str!("../../grammars/priorities.svg"),
    include_str!("../../grammars/intersections_mini.svg"),
    include_str!("../../grammars/abstract.svg"),
    include_str!("../../grammars/panel.svg"),
];

/// Fewer frames than the command's default limit (10 000), so each run stays fast; the
/// exporters' cost per frame is what matters here, not the count.
const MAX_FRAMES: f64 = 600.0;

const SIZE: OutputSize = OutputSize {
    width: Some(48),
    height: None,
};

fuzz_target!(|data: &[u8]| {
    let Some((&pick, rest)) = data.split_first() else {
        return;
    };
    let Ok(src) = std::str::from_utf8(rest) else {
        return;
    };
    let Ok(g) = gmotion::grammar::parse(src) else {
        return;
    };
    let Ok(settings) = engine::settings::from_grammar(&g) else {
        return;
    };
    if !engine::check::static_errors(&g).is_empty()
        || !(settings.duration * settings.fps <= MAX_FRAMES)
        || settings.max_steps > 2_000
    {
        return;
    }
    let svg = SCENES[usize::from(pick) % SCENES.len()];
    let scene = gmotion_import_svg::parse(svg, "scene.svg", &ImportOptions::default())
        .expect("a bundled scene imports")
        .scene;
    let opts = RunOptions {
        max_pieces: Some(20_000),
        ..RunOptions::default()
    };
    let Ok((anim, _)) = engine::run(scene, &g, &opts) else {
        return;
    };
    let out = gmotion_output::Options {
        size: SIZE,
        time: anim.duration / 2.0,
        max_pixels: 1 << 16,
        ..gmotion_output::Options::default()
    };
    let _ = gmotion_output::lottie_text(&anim, None, &[], Path::new("x.json"), &out);
    let _ = gmotion_output::smil_text(&anim, None, Path::new("x.svg"), &out);
    let frame = gmotion_export_svg::frame::frame_svg(&anim, out.time);
    let _ = gmotion_export_raster::render_limited(&frame, SIZE, out.max_pixels);
});
