//! Kinetic type on Lottie text layers: `letters()`, `words()` and `lines()` cut a text layer
//! drawn from the glyph outlines its file embeds (`chars`, After Effects' "glyphs" export)
//! into pieces in reading order; the export writes the pieces as shape content in place of
//! the text layer (its place in the stack, parent, timing and transform kept), and plays as
//! gmotion draws it in lottie-web (svg and canvas), rlottie, ThorVG and Chromium's SMIL.
//! A text layer set in fonts (no `chars`) and a layer that is not text pass through whole,
//! with a warning naming them. The fixtures are in `tests/corpus/lottie-text`.

use std::path::{Path, PathBuf};

use serde_json::Value;

use gmotion::scene::{Node, Paint};
use gmotion_import_lottie::ImportOptions;

use crate::support::pictures::gmotion;
use crate::support::{case_dir, root, run_grammar};

fn fixture(name: &str) -> PathBuf {
    root().join("tests/corpus/lottie-text").join(name)
}

/// `name` copied into a fresh folder for `case`, with `grammar` beside it as `g.gm`.
fn folder(case: &str, name: &str, grammar: &str) -> PathBuf {
    let d = case_dir("lottie_text", case);
    std::fs::copy(fixture(name), d.join(name)).unwrap();
    std::fs::write(d.join("g.gm"), grammar).unwrap();
    d
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The text the fixture's `title` layer shows: its first document's `t`.
fn title_text() -> String {
    let doc = json(&fixture("glyphs.json"));
    doc["layers"][0]["t"]["d"]["k"][0]["s"]["t"]
        .as_str()
        .unwrap()
        .to_string()
}

#[test]
fn letters_cut_a_glyph_text_layer_into_its_visible_glyphs_in_reading_order() {
    let imported =
        gmotion_import_lottie::load(&fixture("glyphs.json"), &ImportOptions::default()).unwrap();
    let whole = imported
        .scene
        .shapes
        .iter()
        .find(|s| s.tag == "title")
        .unwrap()
        .bbox;
    let text = title_text();
    // Every letter but the spaces and the line break has a glyph with an outline.
    let visible: Vec<char> = text.chars().filter(|c| !c.is_whitespace()).collect();
    let anim = run_grammar(
        imported.scene.clone(),
        "duration 1s\nletters() : title -> [ch]\n",
    );
    let mut ch: Vec<_> = anim.scene.shapes.iter().filter(|s| s.tag == "ch").collect();
    ch.sort_by_key(|s| s.id);
    assert_eq!(
        ch.len(),
        visible.len(),
        "one piece per visible glyph of {text:?}"
    );
    // Reading order: line by line, left to right on a line (the rig turns the text by
    // only 4°); words and lines numbered from 0 as the text has them.
    let lines: Vec<usize> = ch.iter().map(|s| s.text.line).collect();
    let words: Vec<usize> = ch.iter().map(|s| s.text.word).collect();
    assert_eq!(lines, [0, 0, 0, 0, 0, 1, 1, 1, 1]);
    assert_eq!(words, [0, 0, 1, 1, 1, 2, 2, 2, 2]);
    for w in ch.windows(2) {
        if w[0].text.line == w[1].text.line {
            assert!(
                w[0].centroid.x < w[1].centroid.x,
                "{:?}",
                (w[0].id, w[1].id)
            );
        } else {
            assert!(w[0].centroid.y < w[1].centroid.y);
        }
    }
    for s in &ch {
        let b = s.bbox;
        assert!(
            whole.inflate(0.01, 0.01).contains_rect(b),
            "piece {} {b:?} outside the text {whole:?}",
            s.id
        );
        // Each piece keeps its glyph's Bézier outline and the text's fill colour.
        let Some(Node::Path(p)) = anim.scene.root.node_at(&s.node_path) else {
            panic!("piece {} is not one glyph path", s.id);
        };
        assert!(!p.path.elements().is_empty());
        let Some(Paint::Solid(c)) = p.fill.as_ref().map(|f| f.paint.clone()) else {
            panic!("piece {} lost its fill", s.id);
        };
        assert!((c.r - 0.16).abs() < 1e-3 && (c.b - 0.36).abs() < 1e-3);
    }
    // The I of "HI" is narrower than the H, the L of "LOT" than the O.
    assert!(ch[1].bbox.width() < ch[0].bbox.width());
    assert!(ch[2].bbox.width() < ch[3].bbox.width());
    let count = |op: &str| {
        let anim = run_grammar(imported.scene.clone(), &format!("{op} : title -> [p]\n"));
        anim.scene.shapes.iter().filter(|s| s.tag == "p").count()
    };
    assert_eq!(count("words()"), 3);
    assert_eq!(count("lines()"), 2);
}

/// The same property over many texts: random runs of the fixture's letters, spaces and line
/// breaks (`\r`), leading, doubled and trailing ones included. The pieces are the visible
/// letters, in the order they are written; words and lines are numbered from 0 over those
/// that show a letter.
#[test]
fn letters_make_one_piece_per_visible_glyph_of_any_text() {
    let source = json(&fixture("glyphs.json"));
    let alphabet = ['H', 'I', 'L', 'O', 'T', ' ', ' ', '\r'];
    let mut seed: u64 = 42;
    let mut next = |n: usize| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 33) as usize % n
    };
    for case in 0..24 {
        let len = 1 + next(14);
        let mut text: String = (0..len).map(|_| alphabet[next(alphabet.len())]).collect();
        if text.chars().all(char::is_whitespace) {
            text.push('H');
        }
        let mut doc = source.clone();
        doc["layers"][0]["t"]["d"]["k"][0]["s"]["t"] = Value::String(text.clone());
        let imported = gmotion_import_lottie::from_json(doc, "case", &ImportOptions::default())
            .unwrap_or_else(|e| panic!("{text:?}: {e}"));
        let anim = run_grammar(imported.scene, "duration 1s\nletters() : title -> [ch]\n");
        let mut ch: Vec<_> = anim.scene.shapes.iter().filter(|s| s.tag == "ch").collect();
        ch.sort_by_key(|s| s.id);
        // What the text says: each visible letter's word and line, numbered densely.
        let (mut want, mut word, mut line) = (Vec::new(), 0usize, 0usize);
        let (mut in_word, mut line_shown, mut any) = (false, false, false);
        for c in text.chars() {
            if c == '\r' {
                line += usize::from(line_shown);
                line_shown = false;
                in_word = false;
            } else if c == ' ' {
                in_word = false;
            } else {
                if !in_word && any {
                    word += 1;
                }
                in_word = true;
                line_shown = true;
                any = true;
                want.push((word, line));
            }
        }
        let got: Vec<(usize, usize)> = ch.iter().map(|s| (s.text.word, s.text.line)).collect();
        assert_eq!(got, want, "case {case}: {text:?}");
        for w in ch.windows(2) {
            if w[0].text.line == w[1].text.line {
                assert!(w[0].centroid.x < w[1].centroid.x, "case {case}: {text:?}");
            } else {
                assert!(w[0].centroid.y < w[1].centroid.y, "case {case}: {text:?}");
            }
        }
    }
}

#[test]
fn a_text_layer_without_glyphs_and_a_layer_that_is_not_text_pass_through_whole() {
    let grammar = "duration 1s\nletters() : title -> [ch]\nletters() : bg -> [b]\n\
                   animate(affine, local, 0.1 * id, rotate(20)) : [all, ch] -> [turn]\n";
    let d = folder("pass-through", "fonts-only.json", grammar);
    let err = gmotion(
        &d,
        &["animate", "fonts-only.json", "g.gm", "-o", "out.json"],
    );
    assert!(
        err.contains("`letters()`: shape `title` #0 is the Lottie text layer `title` ($.layers[0]) without glyph outlines of its own (`chars`)"),
        "{err}"
    );
    assert!(
        err.contains("`letters()`: shape `bg` #0 did not come from text; left as it is"),
        "{err}"
    );
    // Both layers are written back as they were: the text layer is still text.
    let out = json(&d.join("out.json"));
    let source = json(&fixture("fonts-only.json"));
    let layer = |doc: &Value, nm: &str| {
        doc["layers"]
            .as_array()
            .unwrap()
            .iter()
            .find(|l| l["nm"] == nm)
            .cloned()
            .unwrap()
    };
    assert_eq!(layer(&out, "title")["ty"], 5);
    assert_eq!(layer(&out, "title")["t"], layer(&source, "title")["t"]);
    assert_eq!(layer(&out, "bg")["shapes"], layer(&source, "bg")["shapes"]);
}

#[test]
fn a_cut_text_layer_is_written_as_shapes_in_its_place() {
    // The card is not text: it passes through `letters()` whole beside the cut text.
    let grammar = "duration 2s\nletters() : title -> [ch]\nletters() : bg -> [card]\n\
                   animate(affine, local, 0.05 * id, scale(0.5)) : [all, ch] -> [pop]\n\
                   animate(affine, local, 0, rotate(5)) : [all, card] -> [tilt]\n";
    let d = folder("shapes", "glyphs.json", grammar);
    let err = gmotion(&d, &["animate", "glyphs.json", "g.gm", "-o", "out.json"]);
    assert!(
        err.contains("shape `bg` #0 did not come from text"),
        "{err}"
    );
    let out = json(&d.join("out.json"));
    let source = json(&fixture("glyphs.json"));
    let (was, now) = (&source["layers"][0], &out["layers"][0]);
    assert_eq!(now["ty"], 4, "the text layer became a shape layer");
    assert!(now.get("t").is_none());
    for key in ["ind", "nm", "parent", "ip", "op", "st", "ks", "sr"] {
        assert_eq!(now[key], was[key], "`{key}` kept");
    }
    // One group per visible glyph, the first piece drawn first (last in the list).
    let groups = now["shapes"].as_array().unwrap();
    let visible = title_text().chars().filter(|c| !c.is_whitespace()).count();
    assert_eq!(groups.len(), visible);
    assert_eq!(groups.last().unwrap()["nm"], "gmotion ch 0");
    // The other layers keep their places, the card its drawing.
    assert_eq!(out["layers"][1]["nm"], "bg");
    assert_eq!(out["layers"][1]["shapes"], source["layers"][1]["shapes"]);
    assert_eq!(out["layers"][2]["nm"], "rig");
}

/// Animates `doc` (the glyph text fixture, or a variation of it) with `grammar` to Lottie,
/// SMIL and frames in a folder for `case`, and plays both in every player against
/// gmotion's own frames, which move.
#[cfg(feature = "players")]
fn plays_everywhere(case: &str, doc: &Value, grammar: &str) {
    use crate::support::pictures::{Judge, load};
    use crate::support::players::{Player, chromium, frame_path, play};

    let d = folder(case, "glyphs.json", grammar);
    std::fs::write(d.join("glyphs.json"), doc.to_string()).unwrap();
    let width = 320;
    gmotion(
        &d,
        &[
            "animate",
            "glyphs.json",
            "g.gm",
            "-o",
            "anim.json",
            "-o",
            "anim.svg",
            "-o",
            "frames/",
        ],
    );
    let fps = 30.0;
    let frames = [0.0, 8.0, 15.0, 22.0, 30.0, 40.0, 52.0, 59.0];
    let ours: Vec<_> = frames
        .iter()
        .map(|f| load(&d.join(format!("frames/frame_{:05}.png", *f as usize))))
        .collect();
    // The pieces move: some frame differs from the first.
    assert!(
        ours[1..]
            .iter()
            .any(|f| gmotion_export_raster::compare(&ours[0], f, 32) > 0.005),
        "{case}: nothing moves"
    );
    let lottie = std::fs::read_to_string(d.join("anim.json")).unwrap();
    let played = play(
        &format!("lottie-text-{case}"),
        &lottie,
        &frames,
        width,
        &Player::ALL,
    );
    // The SMIL of a Lottie that moves by itself is played frame by frame: sampled midway
    // through each frame, as a discrete switch lands on the frame's start.
    let times: Vec<f64> = frames.iter().map(|f| (f + 0.5) / fps).collect();
    let smil = chromium(&d.join("anim.svg"), width, &times);
    let mut judge = Judge::new(0.005);
    for (k, f) in frames.iter().enumerate() {
        for &p in &Player::ALL {
            let got = load(&frame_path(&played, p, *f));
            judge.close(&format!("{case}: {p:?} frame {f}"), &ours[k], &got);
        }
        judge.close(&format!("{case}: SMIL frame {f}"), &ours[k], &smil[k]);
    }
    judge.assert_all_close(&d);
}

/// A staggered per-letter pop and fade on the text layer, under its rocking parent.
#[cfg(feature = "players")]
#[test]
fn staggered_letters_of_a_glyph_text_layer_play_everywhere() {
    plays_everywhere(
        "letters",
        &json(&fixture("glyphs.json")),
        "duration 2s\n\
         letters() : title -> [ch]\n\
         timesplit(0.5, 0.5) : [all, ch] -> [a, inv_a]\n\
         animate(affine, local, 0.05 * id, translate(0, -30) scale(0.3) rotate(40)) : [a, ch] -> [pop]\n\
         animate(opacity, local, 0.05 * id, 0.3) : [pop, ch] -> [fade]\n",
    );
}

/// Words rising one after the other, line by line, and turning red.
#[cfg(feature = "players")]
#[test]
fn staggered_words_of_a_glyph_text_layer_play_everywhere() {
    plays_everywhere(
        "words",
        &json(&fixture("glyphs.json")),
        "duration 2s\n\
         words() : title -> [w]\n\
         timesplit(0.5, 0.5) : [all, w] -> [b, inv_b]\n\
         animate(affine, world, 0.1 * word_id + 0.3 * line_id, translate(0, -20), ease=ease-out) : [b, w] -> [rise]\n\
         animate(fill, local, 0.1 * word_id, #d1495b) : [rise, w] -> [red]\n",
    );
}

/// A text layer under a mask: the shape layer written in its place keeps the mask, which
/// clips the letters where they move.
#[cfg(feature = "players")]
#[test]
fn staggered_letters_of_a_masked_text_layer_play_everywhere() {
    let mut doc = json(&fixture("glyphs.json"));
    doc["layers"][0]["hasMask"] = Value::Bool(true);
    doc["layers"][0]["masksProperties"] = serde_json::json!([{
        "inv": false, "mode": "a", "nm": "Mask 1",
        "pt": {"a": 0, "k": {"c": true,
            "v": [[0, -80], [120, -80], [120, 80], [0, 80]],
            "i": [[0, 0], [0, 0], [0, 0], [0, 0]], "o": [[0, 0], [0, 0], [0, 0], [0, 0]]}},
        "o": {"a": 0, "k": 100}, "x": {"a": 0, "k": 0}
    }]);
    plays_everywhere(
        "masked",
        &doc,
        "duration 2s\n\
         letters() : title -> [ch]\n\
         timesplit(0.5, 0.5) : [all, ch] -> [a, inv_a]\n\
         animate(affine, local, 0.05 * id, translate(0, -30) rotate(40)) : [a, ch] -> [pop]\n",
    );
    let out = json(&crate::support::tmp_dir().join("lottie_text/masked/anim.json"));
    assert_eq!(out["layers"][0]["ty"], 4);
    assert_eq!(
        out["layers"][0]["masksProperties"],
        doc["layers"][0]["masksProperties"]
    );
}
