//! The transitions targets parser (JSON or CSV by content) and the signal-system
//! descriptions it names, as `gmotion transitions SCENE TARGETS` reads them; a parsed file
//! is run on a small scene when its frames are within the command's default limit.
#![no_main]

use gmotion::transitions::targets::Targets;
use gmotion_import_svg::ImportOptions;
use libfuzzer_sys::fuzz_target;

/// A few shapes of each tag the bundled targets files and the tests name.
const SCENE: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="320" height="100">
<rect data-tag="bar" x="10" y="10" width="10" height="20" fill="#36c"/>
<rect data-tag="bar" x="22" y="10" width="10" height="25" fill="#36c"/>
<rect data-tag="bar" x="34" y="10" width="10" height="30" fill="#36c"/>
<rect data-tag="bar" x="46" y="10" width="10" height="35" fill="#36c"/>
<rect data-tag="brush" x="58" y="10" width="10" height="20" fill="#36c"/>
<rect data-tag="brush" x="70" y="10" width="10" height="25" fill="#36c"/>
<rect data-tag="item" x="82" y="10" width="10" height="20" fill="#36c"/>
<rect data-tag="item" x="94" y="10" width="10" height="25" fill="#36c"/>
<rect data-tag="item" x="106" y="10" width="10" height="30" fill="#36c"/>
<rect data-tag="item" x="118" y="10" width="10" height="35" fill="#36c"/>
<rect data-tag="item" x="130" y="10" width="10" height="40" fill="#36c"/>
<rect data-tag="item" x="142" y="10" width="10" height="45" fill="#36c"/>
<rect data-tag="item" x="154" y="10" width="10" height="50" fill="#36c"/>
<rect data-tag="item" x="166" y="10" width="10" height="55" fill="#36c"/>
<rect data-tag="char" x="178" y="10" width="10" height="20" fill="#36c"/>
<rect data-tag="char" x="190" y="10" width="10" height="25" fill="#36c"/>
<rect data-tag="char" x="202" y="10" width="10" height="30" fill="#36c"/>
<rect data-tag="char" x="214" y="10" width="10" height="35" fill="#36c"/>
<rect data-tag="box" x="226" y="10" width="10" height="20" fill="#36c"/>
<rect data-tag="box" x="238" y="10" width="10" height="25" fill="#36c"/>
<rect data-tag="box" x="250" y="10" width="10" height="30" fill="#36c"/>
<rect data-tag="box" x="262" y="10" width="10" height="35" fill="#36c"/>
<rect data-tag="box" x="274" y="10" width="10" height="40" fill="#36c"/>
<rect data-tag="ball" x="286" y="10" width="10" height="20" fill="#36c"/>
<rect data-tag="ball" x="298" y="10" width="10" height="25" fill="#36c"/>
</svg>"##;

/// The command's default `frames` limit.
const MAX_FRAMES: f64 = 10_000.0;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(t) = Targets::parse(text) else {
        return;
    };
    let system = t.default_system(None);
    let fps = t.frame_rate(None);
    if !(t.end() * fps <= MAX_FRAMES) {
        return;
    }
    let scene = gmotion_import_svg::parse(SCENE, "scene.svg", &ImportOptions::default())
        .expect("the fixed scene imports")
        .scene;
    let _ = gmotion::transitions::run(&scene, &t, &system, fps, None);
});
