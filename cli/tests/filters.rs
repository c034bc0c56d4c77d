//! Filters through the real binary, judged by independent players: blurs and drop
//! shadows as Figma (flood, hard-alpha matrix, offset, blur, composite, tint, blends),
//! Illustrator (blur of `SourceAlpha`, offset, flood, composite, merge), CSS
//! (`filter: drop-shadow(…)`) and hand-written SVG (`feGaussianBlur`, `feDropShadow`, an
//! anisotropic blur) write them, and a filter no effect expresses (`feMorphology`), which
//! is drawn as an image with one warning naming it.
//!
//! Chromium's drawing of the source is the reference for gmotion's PNG, for its SVG
//! (played in Chromium) and for its Lottie in the players that draw Lottie effects
//! (lottie-web's svg renderer, ThorVG); lottie-web's drawing of the Lottie is the reference
//! for gmotion's own render of that Lottie (the effects read back). rlottie and lottie-web's canvas renderer draw no
//! effects: they must draw the same picture without the blurs and shadows, and the export
//! says so in a warning.

#[cfg(feature = "players")]
use std::path::Path;
use std::path::PathBuf;

#[cfg(feature = "players")]
use gmotion_export_raster::compare;

#[cfg(feature = "players")]
use crate::support::pictures::{Judge, OFF, animate_and_play};
use crate::support::pictures::{gmotion, load};
#[cfg(feature = "players")]
use crate::support::players::{Player, chromium, frame_path, play};

/// Most pixels that may be off in a picture. Blurs are approximated differently by
/// Skia (Chromium), resvg and ThorVG, which shows on the soft edges only: measured
/// 0.01–0.40 % (gmotion's PNG 0.40 %, its SVG 0.04 %, lottie-web 0.02 %, ThorVG 0.04 %;
/// animated frames ≤ 0.36 %). A player that drops the effects is 7.7–8.6 % off.
#[cfg(feature = "players")]
const MAX_OFF: f64 = 0.01;

/// The filters of the picture, by the id of the element they are on, and whether a
/// player without Lottie effects still draws them (only the rasterised one).
#[cfg(feature = "players")]
const FILTERED: [(&str, bool); 7] = [
    ("card", false),
    ("badge", false),
    ("glow", false),
    ("chip", false),
    ("streak", false),
    ("pill", false),
    ("outline", true),
];

/// The picture, with the filters of the elements for which `keep` answers false removed.
#[cfg(feature = "players")]
fn picture(keep: impl Fn(&str) -> bool) -> String {
    let attr = |id: &str, filter: &str| {
        if keep(id) {
            filter.to_string()
        } else {
            String::new()
        }
    };
    format!(
        r##"<svg width="320" height="200" viewBox="0 0 320 200" fill="none" xmlns="http://www.w3.org/2000/svg">
<!-- Shaped like a Figma export: filter0_d_12_3 and friends in defs at the end. -->
<rect width="320" height="200" fill="#F4F1EA"/>
<g id="card" {card}>
<rect x="24" y="20" width="80" height="60" rx="10" fill="#457B9D"/>
<rect x="36" y="34" width="40" height="8" rx="4" fill="white"/>
</g>
<g id="badge" {badge}>
<circle cx="160" cy="50" r="28" fill="#2A9D8F"/>
<circle cx="160" cy="50" r="12" fill="white"/>
</g>
<circle id="glow" cx="250" cy="50" r="24" fill="#E63946" {glow}/>
<rect id="chip" x="20" y="116" width="70" height="50" rx="25" fill="#F4A261" {chip}/>
<rect id="streak" x="120" y="120" width="60" height="40" fill="#264653" {streak}/>
<rect id="pill" x="210" y="110" width="80" height="30" rx="15" fill="#8E7DBE" {pill}/>
<rect id="outline" x="216" y="160" width="68" height="14" fill="#E9C46A" {outline}/>
<defs>
<filter id="filter0_d_12_3" x="4" y="4" width="130" height="110" filterUnits="userSpaceOnUse" color-interpolation-filters="sRGB">
<feFlood flood-opacity="0" result="BackgroundImageFix"/>
<feColorMatrix in="SourceAlpha" type="matrix" values="0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 127 0" result="hardAlpha"/>
<feOffset dx="4" dy="6"/>
<feGaussianBlur stdDeviation="5"/>
<feComposite in2="hardAlpha" operator="out"/>
<feColorMatrix type="matrix" values="0 0 0 0 0.1 0 0 0 0 0.15 0 0 0 0 0.4 0 0 0 0.45 0"/>
<feBlend mode="normal" in2="BackgroundImageFix" result="effect1_dropShadow_12_3"/>
<feBlend mode="normal" in="SourceGraphic" in2="effect1_dropShadow_12_3" result="shape"/>
</filter>
<filter id="ai_shadow" x="-60%" y="-60%" width="220%" height="220%">
<feGaussianBlur in="SourceAlpha" stdDeviation="3"/>
<feOffset dx="5" dy="5" result="offsetblur"/>
<feFlood flood-color="#AA0000" flood-opacity="0.7"/>
<feComposite in2="offsetblur" operator="in"/>
<feMerge><feMergeNode/><feMergeNode in="SourceGraphic"/></feMerge>
</filter>
<filter id="soft" x="-100%" y="-100%" width="300%" height="300%">
<feGaussianBlur stdDeviation="5"/>
</filter>
<filter id="lifted" x="-50%" y="-50%" width="200%" height="200%">
<feDropShadow dx="-3" dy="5" stdDeviation="3" flood-color="#1D3557" flood-opacity="0.6"/>
</filter>
<filter id="motion" x="-40%" y="-20%" width="180%" height="140%">
<feGaussianBlur stdDeviation="8 1"/>
</filter>
<filter id="fat" x="-20%" y="-60%" width="140%" height="220%">
<feMorphology operator="dilate" radius="3"/>
</filter>
</defs>
</svg>
"##,
        card = attr("card", r#"filter="url(#filter0_d_12_3)""#),
        badge = attr("badge", r#"filter="url(#ai_shadow)""#),
        glow = attr("glow", r#"filter="url(#soft)""#),
        chip = attr("chip", r#"filter="url(#lifted)""#),
        streak = attr("streak", r#"filter="url(#motion)""#),
        pill = attr(
            "pill",
            r#"filter="drop-shadow(3px 4px 2px rgba(0,0,0,0.5))""#
        ),
        outline = attr("outline", r#"filter="url(#fat)""#),
    )
}

fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gmotion-filters-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[cfg(feature = "players")]
#[test]
fn blurs_and_drop_shadows_export_as_effects_and_the_rest_as_images() {
    let d = folder("still");
    std::fs::write(d.join("art.svg"), picture(|_| true)).unwrap();
    // What players without effects draw: the picture without its blurs and shadows.
    std::fs::write(
        d.join("plain.svg"),
        picture(|id| FILTERED.iter().any(|&(f, kept)| f == id && kept)),
    )
    .unwrap();
    let err = gmotion(
        &d,
        &[
            "convert", "art.svg", "-o", "art.png", "-o", "art.json", "-o", "out.svg", "--width",
            "640",
        ],
    );
    let filter_warnings: Vec<&str> = err.lines().filter(|l| l.contains("filter")).collect();
    assert_eq!(
        filter_warnings.len(),
        1,
        "one warning, for the filter drawn as an image:\n{err}"
    );
    assert!(
        filter_warnings[0].contains("id=\"outline\"") && filter_warnings[0].contains("image"),
        "the warning names the element: {}",
        filter_warnings[0]
    );
    assert!(
        err.contains("rlottie"),
        "the export says which players draw no effects:\n{err}"
    );

    let json = std::fs::read_to_string(d.join("art.json")).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
    let mut effects: Vec<i64> = Vec::new();
    for l in doc["layers"].as_array().unwrap() {
        for e in l["ef"].as_array().into_iter().flatten() {
            effects.push(e["ty"].as_i64().unwrap());
        }
    }
    effects.sort();
    // Four drop shadows, a blur, and the anisotropic blur as one per axis.
    assert_eq!(effects, [25, 25, 25, 25, 29, 29, 29], "Lottie effects");

    let reference = chromium(&d.join("art.svg"), 640, &[0.0]).remove(0);
    let plain = chromium(&d.join("plain.svg"), 640, &[0.0]).remove(0);
    let ours = chromium(&d.join("out.svg"), 640, &[0.0]).remove(0);
    let mut judge = Judge::new(MAX_OFF);
    judge.close("gmotion's PNG", &reference, &load(&d.join("art.png")));
    judge.close("gmotion's SVG in Chromium", &reference, &ours);
    let played = play("filters-still", &json, &[0.0], 640, &Player::ALL);
    // gmotion reads its own Lottie back and draws the effects as lottie-web does.
    gmotion(
        &d,
        &["convert", "art.json", "-o", "own.png", "--width", "640"],
    );
    judge.close(
        "gmotion's render of its Lottie",
        &load(&frame_path(&played, Player::LottieWebSvg, 0.0)),
        &load(&d.join("own.png")),
    );
    for p in Player::ALL {
        let want = match p {
            Player::LottieWebSvg | Player::Thorvg => &reference,
            Player::LottieWebCanvas | Player::Rlottie => &plain,
        };
        judge.close(&format!("{p:?}"), want, &load(&frame_path(&played, p, 0.0)));
    }
    judge.assert_all_close(&d);
}

#[cfg(feature = "players")]
#[test]
fn filtered_shapes_move_with_their_effects() {
    let d = folder("animated");
    std::fs::write(d.join("art.svg"), picture(|_| true)).unwrap();
    // Each moves well outside its filter's region at rest: the region goes with it.
    std::fs::write(
        d.join("art.gm"),
        "duration 2s\nfps 10\n\
         animate(affine, local, 0, translate(40, 90) rotate(30)) : [all, glow] -> [a]\n\
         animate(affine, local, 0, translate(120, 60) scale(0.6)) : [all, chip] -> [b]\n\
         animate(affine, local, 0, translate(-100, 0)) : [all, card] -> [c]\n\
         animate(opacity, local, 0, 0.4) : [all, pill] -> [d]\n",
    )
    .unwrap();
    moves_alike_in_players("filters-animated", &d);
}

/// Plays `d`'s `art.svg` with `art.gm` in lottie-web and ThorVG at the first, middle and
/// last frame: they draw what gmotion draws, and the shapes moved.
#[cfg(feature = "players")]
fn moves_alike_in_players(name: &str, d: &Path) {
    let mut judge = Judge::new(MAX_OFF);
    let players = [Player::LottieWebSvg, Player::Thorvg];
    let ours = animate_and_play(name, d, 640, 10.0, &[0.0, 10.0, 19.0], &players, &mut judge);
    assert!(compare(&ours[0], &ours[2], OFF) > 0.05, "the shapes move");
    judge.assert_all_close(d);
}

#[cfg(feature = "players")]
#[test]
fn filtered_shapes_moved_by_their_own_vertices_are_not_cut_off() {
    // A per-vertex motion (`lookup vertex` on a grid) moves the outline inside its filtered
    // group, not the group: the tight regions Figma writes would cut the shape off where
    // it goes, which no Lottie player does (the effect follows the layer). The region
    // grows instead, as it does for a unit inside the group.
    let d = folder("deformed");
    std::fs::write(
        d.join("art.svg"),
        picture(|id| id == "card" || id == "chip"),
    )
    .unwrap();
    std::fs::write(
        d.join("art.gm"),
        "duration 2s\nfps 10\ngrid 3x2\nlookup vertex\n\
         animate(affine, local, 0, translate(150, 40)) : [all, card] -> [a]\n\
         animate(affine, local, 0, translate(170, -60)) : [all, chip] -> [b]\n",
    )
    .unwrap();
    moves_alike_in_players("filters-deformed", &d);
}

#[test]
fn a_css_filter_usvg_cannot_read_is_warned_about() {
    let d = folder("css");
    std::fs::write(
        d.join("a.svg"),
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="60">
<rect id="pill" x="10" y="10" width="60" height="30" fill="#8E7DBE" style="filter: drop-shadow(3px 4px 2px rgba(0, 0, 0, 0.5))"/>
<rect id="fine" x="10" y="45" width="60" height="10" fill="#8E7DBE" style="filter: drop-shadow(3px 4px 2px #00000080)"/>
</svg>"##,
    )
    .unwrap();
    let err = gmotion(&d, &["convert", "a.svg", "-o", "a.json"]);
    let warnings: Vec<&str> = err.lines().filter(|l| l.contains("filter")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(
        warnings[0].contains("id=\"pill\"") && warnings[0].contains("line 2"),
        "{err}"
    );
    let json = std::fs::read_to_string(d.join("a.json")).unwrap();
    assert!(
        json.contains("\"ty\":25"),
        "the readable one is a drop shadow"
    );
}

#[test]
fn lottie_effects_that_are_not_drawn_are_named() {
    let d = folder("lottie-in");
    let doc = r#"{"v": "5.7.0", "fr": 30, "ip": 0, "op": 30, "w": 100, "h": 100, "layers": [{"ddd": 0, "ty": 4, "nm": "sq", "ind": 1, "ip": 0, "op": 30, "st": 0, "ks": {},
        "ef": [{"ty": 5, "nm": "Slider Control", "en": 1, "ef": [{"ty": 0, "nm": "Slider", "v": {"a": 0, "k": 3}}]},
               {"ty": 20, "nm": "Tint", "en": 1, "ef": []},
               {"ty": 29, "nm": "Gaussian Blur", "en": 0, "ef": [{"ty": 0, "v": {"a": 0, "k": 40}}]}],
        "shapes": [{"ty": "rc", "d": 1, "p": {"a": 0, "k": [50, 50]}, "s": {"a": 0, "k": [40, 40]}, "r": {"a": 0, "k": 0}}, {"ty": "fl", "c": {"a": 0, "k": [1, 0, 0, 1]}, "o": {"a": 0, "k": 100}}]}]}"#;
    std::fs::write(d.join("a.json"), doc).unwrap();
    let err = gmotion(&d, &["convert", "a.json", "-o", "a.png"]);
    let effects: Vec<&str> = err.lines().filter(|l| l.contains("effect")).collect();
    assert_eq!(effects.len(), 1, "only the tint is not drawn:\n{err}");
    assert!(
        effects[0].contains("$.layers[0].ef[1]") && effects[0].contains("\"Tint\""),
        "{err}"
    );
    // The disabled blur draws nothing: the square keeps its hard edge.
    let png = load(&d.join("a.png"));
    let edge = png.pixel(30, 50).unwrap();
    assert_eq!(edge.alpha(), 255, "the square's edge is not blurred");
}
