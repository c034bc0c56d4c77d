//! Kinetic type in the real players: a text cut by `letters()`, `words()` and `lines()`
//! (drawn with the vendored fonts in `tests/fonts`), each piece staggered by its `id`,
//! `word_id` or `line_id`, exported to Lottie and SMIL, plays as gmotion draws it in
//! lottie-web (svg and canvas), rlottie, ThorVG and Chromium.

use gmotion::motion::Animation;
use gmotion_export_lottie::{LottieOptions, to_lottie};
use gmotion_export_raster::{compare, render};
use gmotion_export_svg::frame::frame_svg;
use gmotion_export_svg::smil::{SmilOptions, to_smil};

use crate::support::players::{Player, assert_plays_like_model, chromium, frames_to_check};
use crate::support::{run_grammar, text_scene_of};

/// Two lines of type in two colours, one with a gradient, and a line on a path.
const ART: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="320" height="200">
  <defs>
    <linearGradient id="warm" x1="0" y1="0" x2="1" y2="0">
      <stop offset="0" stop-color="#e4572e"/><stop offset="1" stop-color="#f3a712"/>
    </linearGradient>
    <path id="arc" d="M 20 180 Q 160 120 300 180"/>
  </defs>
  <text id="title" x="20" y="50" font-family="Noto Sans" font-size="36" fill="#29335c">Kinetic <tspan fill="url(#warm)">type</tspan></text>
  <text id="lede" x="20" y="90" font-family="Noto Sans" font-size="18" fill="#3b8ea5">one word<tspan x="20" dy="22">at a time</tspan></text>
  <text id="curve" font-family="Noto Sans" font-size="18" fill="#669bbc" stroke="#003049" stroke-width="0.5"><textPath xlink:href="#arc">round we go</textPath></text>
</svg>"##;

fn animation(case: &str, grammar: &str) -> Animation {
    run_grammar(text_scene_of(&format!("kinetic-{case}"), ART), grammar)
}

/// Plays `anim` in every Lottie player and in Chromium's SMIL against gmotion's frames.
fn plays_everywhere(case: &str, anim: &Animation) {
    let (json, _) = to_lottie(anim, &LottieOptions::default()).unwrap();
    let width = (2.0 * anim.scene.width).round() as u32;
    assert_plays_like_model(
        case,
        anim,
        &json,
        &frames_to_check(anim),
        width,
        &Player::ALL,
    );

    let d = crate::support::case_dir("text", case);
    let (svg, _) = to_smil(anim, &SmilOptions::default()).unwrap();
    let file = d.join("out.svg");
    std::fs::write(&file, &svg).unwrap();
    let times: Vec<f64> = (0..=8)
        .map(|k| k as f64 * anim.duration / 8.0 * 0.999)
        .collect();
    let played = chromium(&file, width, &times);
    for (&t, got) in times.iter().zip(&played) {
        let model = render(&frame_svg(anim, t), width).unwrap();
        let off = compare(&model, got, 32);
        assert!(
            off < 0.005,
            "{case} t = {t}: {:.2}% of pixels off the model ({})",
            off * 100.0,
            d.display()
        );
    }
}

#[test]
fn letters_staggered_play_everywhere() {
    let anim = animation(
        "letters",
        "duration 2s\n\
         letters() : title -> [ch]\n\
         letters() : curve -> [ch]\n\
         timesplit(0.5, 0.5) : [all, ch] -> [a, inv_a]\n\
         animate(affine, local, 0.05 * id, scale(0.2) rotate(40)) : [a, ch] -> [pop]\n",
    );
    let ch = anim.scene.shapes.iter().filter(|s| s.tag == "ch").count();
    // "Kinetic type" and "round we go".
    assert_eq!(ch, 11 + 9);
    plays_everywhere("letters", &anim);
}

#[test]
fn words_and_lines_play_everywhere() {
    let anim = animation(
        "words",
        "duration 2s\n\
         words() : title -> [w]\n\
         lines() : lede -> [ln]\n\
         timesplit(0.5, 0.5) : [all, w] -> [a, inv_a]\n\
         animate(affine, world, 0.1 * word_id, translate(0, -12)) : [a, w] -> [up]\n\
         timesplit(0.5, 0.5) : [all, ln] -> [b, inv_b]\n\
         animate(affine, local, 0.2 * line_id, scale(1.2)) : [b, ln] -> [grow]\n",
    );
    let count = |tag: &str| anim.scene.shapes.iter().filter(|s| s.tag == tag).count();
    assert_eq!((count("w"), count("ln")), (2, 2));
    plays_everywhere("words-lines", &anim);
}
