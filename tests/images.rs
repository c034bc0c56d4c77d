//! Raster images through the real binary, judged by independent players: an SVG holding
//! an embedded PNG (`xlink:href` data URL, as Illustrator writes), a linked PNG beside it,
//! a Figma-style image fill (a pattern whose `use` points at an `<image>` in `defs`), and
//! a skewed, translucent copy. Chromium's drawing of the source is the reference for the
//! import; lottie-web (svg and canvas), rlottie and ThorVG play the Lottie, Chromium plays
//! the SMIL, and animation frames are compared with gmotion's own frames.

use std::path::{Path, PathBuf};
use std::process::Command;

use gmotion_export_raster::{Pixmap, compare};

use crate::support::players::{Player, chromium, frame_path, play};

/// A pixel is off when a premultiplied channel differs by more than this (of 255), as in
/// the players' other tests.
const OFF: u8 = 32;

/// Most pixels that may be off in a frame. Players resample an image each with their own
/// filter (rlottie nearest-neighbour, the others bilinear) and ThorVG does not smooth an
/// image's border, which differ along the picture's colour edges and outline: measured
/// 0.0–2.1 % here (rlottie ≤ 1.9 %, ThorVG ≤ 2.1 %, the rest < 0.01 %). rlottie ignoring
/// the placing rotation (`ddd` written after the transform) put 5–23 % off.
const MAX_OFF: f64 = 0.025;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gmotion"))
}

/// Runs the binary in `dir`, asserting success, and returns its standard error.
fn run(dir: &Path, args: &[&str]) -> String {
    let out = bin().current_dir(dir).args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "gmotion {args:?} failed:\n{err}");
    err
}

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

fn load(path: &Path) -> Pixmap {
    Pixmap::load_png(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Asserts `got` is within [`MAX_OFF`] of `want`, naming what was compared.
fn close(what: &str, want: &Pixmap, got: &Pixmap, failures: &mut Vec<String>) {
    if (want.width(), want.height()) != (got.width(), got.height()) {
        failures.push(format!("{what}: {}x{} px", got.width(), got.height()));
        return;
    }
    let off = compare(want, got, OFF);
    if off > MAX_OFF {
        failures.push(format!("{what}: {:.2}% off", off * 100.0));
    }
}

#[test]
fn images_import_as_chromium_draws_them_and_play_in_every_player() {
    let d = art("still");
    let err = run(
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
    let mut failures = Vec::new();
    close(
        "gmotion's PNG",
        &reference,
        &load(&d.join("art.png")),
        &mut failures,
    );
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
        close(
            &format!("{p:?}"),
            &reference,
            &load(&frame_path(&played, p, 0.0)),
            &mut failures,
        );
    }
    assert!(
        failures.is_empty(),
        "files in {}:\n{}",
        d.display(),
        failures.join("\n")
    );
}

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
    let out = bin()
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

    run(
        &d,
        &[
            "animate",
            "art.svg",
            "art.gm",
            "-o",
            "anim.json",
            "-o",
            "anim.svg",
            "-o",
            "frames/",
            "--width",
            "480",
        ],
    );
    let frames = [0.0, 5.0, 9.0, 10.0, 15.0];
    let ours: Vec<Pixmap> = frames
        .iter()
        .map(|f| load(&d.join(format!("frames/frame_{:05}.png", *f as usize))))
        .collect();
    let mut failures = Vec::new();
    // The frames moved: the rotated logo is not where it rested.
    assert!(compare(&ours[0], &ours[3], OFF) > 0.05, "the images move");
    let json = std::fs::read_to_string(d.join("anim.json")).unwrap();
    let played = play("images-animated", &json, &frames, 480, &Player::ALL);
    let times: Vec<f64> = frames.iter().map(|f| f / 10.0).collect();
    let smil = chromium(&d.join("anim.svg"), 480, &times);
    for (k, f) in frames.iter().enumerate() {
        for p in Player::ALL {
            let got = load(&frame_path(&played, p, *f));
            close(&format!("{p:?} frame {f}"), &ours[k], &got, &mut failures);
        }
        close(
            &format!("SMIL frame {f}"),
            &ours[k],
            &smil[k],
            &mut failures,
        );
    }
    assert!(
        failures.is_empty(),
        "files in {}:\n{}",
        d.display(),
        failures.join("\n")
    );
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
    let err = run(&inner, &["convert", "a.svg", "-o", "a.json"]);
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
