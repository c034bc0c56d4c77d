//! The SVG importer under the command's default policy and limits: any bytes as an SVG
//! document (no folder, so it may reference no files), imported into a scene, and that
//! scene written back as a still SVG, as `gmotion convert scene.svg -o still.svg` does.
#![no_main]

use gmotion_import_svg::ImportOptions;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(imported) = gmotion_import_svg::parse(text, "fuzz.svg", &ImportOptions::default()) {
        let _ = gmotion_export_svg::frame::scene_svg(&imported.scene);
    }
});
