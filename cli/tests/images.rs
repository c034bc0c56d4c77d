//! Raster images through the real binary, judged by independent players: an SVG holding
//! an embedded PNG (`xlink:href` data URL, as Illustrator writes), a linked PNG beside it,
//! a Figma-style image fill (a pattern whose `use` points at an `<image>` in `defs`), and
//! a skewed, translucent copy. Chromium's drawing of the source is the reference for the
//! import; lottie-web (svg and canvas), rlottie and ThorVG play the Lottie, Chromium plays
//! the SMIL, and animation frames are compared with gmotion's own frames.

use std::path::PathBuf;
#[cfg(feature = "players")]
use std::process::Command;

#[cfg(feature = "players")]
use gmotion_export_raster::compare;

use crate::support::pictures::gmotion;
#[cfg(feature = "players")]
use crate::support::pictures::{Judge, OFF, animate_and_play, load};
#[cfg(feature = "players")]
use crate::support::players::{Player, chromium, frame_path, play};

/// Most pixels that may be off in a frame. Players resample an image each with their own
/// filter (rlottie nearest-neighbour, the others bilinear) and ThorVG does not smooth an
/// image's border, which differ along the picture's colour edges and outline: measured
/// 0.0–2.1 % here (rlottie ≤ 1.9 %, ThorVG ≤ 2.1 %, the rest < 0.01 %). rlottie ignoring
/// the placing rotation (`ddd` written after the transform) put 5–23 % off.
#[cfg(feature = "players")]
const MAX_OFF: f64 = 0.025;

/// A `w`×`h` PNG: four quadrant colours and a dark disc, blocks large enough that
/// resampling filters differ only along edges.
fn picture(w: u32, h: u32) -> Vec<u8> {
    let mut rgba = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            let (dx, dy) = (x as f64 - w as f64 * 0.6, y as f64 - h as f64 * 0.6);
            let c = if dx.hypot(dy) < h as f64 * 0.25 {
                [30, 30, 30, 255]
            } else {
                match (x < w / 2, y < h / 2) {
                    (true, true) => [220, 40, 40, 255],
                    (false, true) => [40, 90, 220, 255],
                    (true, false) => [250, 200, 30, 255],
                    (false, false) => [40, 170, 80, 255],
                }
            };
            rgba.extend_from_slice(&c);
        }
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header().unwrap();
        writer.write_image_data(&rgba).unwrap();
    }
    out
}

fn base64(bytes: &[u8]) -> String {
    use base64::Engine as _;
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

/// A folder with `art.svg` (Illustrator-shaped, with the four images) and `photo.png`.
fn art(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gmotion-images-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("photo.png"), picture(60, 40)).unwrap();
    let logo = base64(&picture(48, 32));
    let svg = format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<!-- Generator: Adobe Illustrator 27.0.0, SVG Export Plug-In . SVG Version: 6.00 Build 0)  -->
<svg version="1.1" id="Layer_1" xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
	 x="0px" y="0px" viewBox="0 0 240 160" width="240" height="160" xml:space="preserve">
<style type="text/css">.st0{{fill:#EEEEEE;}}</style>
<rect class="st0" width="240" height="160"/>
<image id="logo" width="48" height="32" transform="translate(16 16) scale(2)" xlink:href="data:image/png;base64,{logo}"/>
<image id="badge" width="48" height="32" transform="translate(150 20) skewX(20)" opacity="0.6" xlink:href="data:image/png;base64,{logo}"/>
<image id="photo" x="20" y="96" width="90" height="60" xlink:href="photo.png"/>
<rect id="card" x="130" y="90" width="96" height="64" rx="12" fill="url(#pattern0)"/>
<defs>
<pattern id="pattern0" patternContentUnits="objectBoundingBox" width="1" height="1">
<use xlink:href="#image0_1_2" transform="scale(0.0208333 0.03125)"/>
</pattern>
<image id="image0_1_2" width="48" height="32" xlink:href="data:image/png;base64,{logo}"/>
</defs>
</svg>
"##
    );
    std::fs::write(d.join("art.svg"), svg).unwrap();
    d
}

#[cfg(feature = "players")]
#[test]
fn images_import_as_chromium_draws_them_and_play_in_every_player() {
    let d = art("still");
    let err = gmotion(
        &d,
        &[
            "convert", "art.svg", "-o", "art.png", "-o", "art.json", "--width", "480",
        ],
    );
    assert!(
        !err.contains("image"),
        "no image is dropped or refused:\n{err}"
    );
    let reference = chromium(&d.join("art.svg"), 480, &[0.0]).remove(0);
    let mut judge = Judge::new(MAX_OFF);
    judge.close("gmotion's PNG", &reference, &load(&d.join("art.png")));
    let json = std::fs::read_to_string(d.join("art.json")).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
    let images = doc["assets"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|a| {
            a["p"]
                .as_str()
                .is_some_and(|p| p.starts_with("data:image/png;base64,"))
        })
        .count();
    // The logo is drawn three times (plain, skewed, as a pattern's tile): one asset.
    assert_eq!(images, 2, "one embedded asset per distinct picture");
    let played = play("images-still", &json, &[0.0], 480, &Player::ALL);
    for p in Player::ALL {
        judge.close(
            &format!("{p:?}"),
            &reference,
            &load(&frame_path(&played, p, 0.0)),
        );
    }
    judge.assert_all_close(&d);
}

#[cfg(feature = "players")]
#[test]
fn images_are_units_that_move_by_their_ids_in_every_format() {
    let d = art("animated");
    std::fs::write(
        d.join("art.gm"),
        "scene art.svg\nduration 2s\nfps 10\n\
         timesplit(0.5, 0.5) : [all, (image)] -> [go, inv_go]\n\
         animate(affine, local, 0, rotate(90) scale(0.5)) : [go, logo] -> [turned]\n\
         animate(affine, local, 0, translate(-60, -20)) : [go, photo] -> [moved]\n\
         animate(opacity, local, 0, 0.3) : [go, badge] -> [faded]\n",
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_gmotion"))
        .current_dir(&d)
        .args(["check", "--shapes", "--json", "art.svg"])
        .output()
        .unwrap();
    let shapes: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let aliases: Vec<String> = shapes
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s["tag"] == "image")
        .flat_map(|s| s["aliases"].as_array().unwrap().clone())
        .map(|a| a.as_str().unwrap().to_string())
        .collect();
    assert_eq!(
        aliases,
        ["logo", "badge", "photo"],
        "images are units, their ids tags"
    );

    let mut judge = Judge::new(MAX_OFF);
    let frames = [0.0, 5.0, 9.0, 10.0, 15.0];
    let ours = animate_and_play(
        "images-animated",
        &d,
        480,
        10.0,
        &frames,
        &Player::ALL,
        &mut judge,
    );
    // The frames moved: the rotated logo is not where it rested.
    assert!(compare(&ours[0], &ours[3], OFF) > 0.05, "the images move");
    judge.assert_all_close(&d);
}

#[test]
fn an_image_outside_the_folder_is_refused_with_a_warning_naming_it() {
    let d = art("outside");
    let inner = d.join("inner");
    std::fs::create_dir_all(&inner).unwrap();
    std::fs::write(
        inner.join("a.svg"),
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="50" height="50"><image id="far" width="50" height="50" href="../photo.png"/><circle cx="25" cy="25" r="10"/></svg>"#,
    )
    .unwrap();
    let err = gmotion(&inner, &["convert", "a.svg", "-o", "a.json"]);
    assert!(
        err.contains("photo.png"),
        "the warning names the file:\n{err}"
    );
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(inner.join("a.json")).unwrap()).unwrap();
    assert!(
        doc.get("assets").is_none(),
        "nothing read from outside the folder"
    );
}
