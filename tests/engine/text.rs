//! The text operators `letters()`, `words()` and `lines()` on SVG text drawn with the
//! vendored fonts (`tests/fonts`), as properties counted from the strings: one piece per
//! visible grapheme cluster (a ligature is one, a space none), word or line, numbered in
//! reading order (left to right, right to left for Hebrew), each keeping its paint and its
//! curves; `line_id` and `word_id` give a piece's place; a unit that is not text passes
//! through with a warning naming it.

use gmotion::color::Color;
use gmotion::engine::{RunOptions, RunStats, run};
use gmotion::motion::Animation;
use gmotion::scene::{Node, Paint, Scene};
use kurbo::{PathEl, Point};

use crate::support::{centre_at, scene_of, text_scene_of};

fn svg(body: &str) -> String {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="400" height="300">{body}</svg>"#
    )
}

fn expand(scene: Scene, grammar: &str) -> (Animation, RunStats) {
    let g = gmotion::grammar::parse(grammar)
        .unwrap_or_else(|d| panic!("{}", d.render("case.gm", grammar)));
    run(scene, &g, &RunOptions::default()).unwrap_or_else(|e| panic!("{e}\n{grammar}"))
}

/// The shapes tagged `tag`, by id: (index, id).
fn tagged(a: &Animation, tag: &str) -> Vec<usize> {
    let mut v: Vec<(usize, usize)> = (a.scene.shapes.iter().enumerate())
        .filter(|(_, s)| s.tag == tag)
        .map(|(i, s)| (s.id, i))
        .collect();
    v.sort_unstable();
    v.into_iter().map(|(_, i)| i).collect()
}

fn centroids(a: &Animation, tag: &str) -> Vec<Point> {
    tagged(a, tag)
        .into_iter()
        .map(|i| a.scene.shapes[i].centroid)
        .collect()
}

/// The number of letters, words and lines `text` (SVG body) has by the operators.
fn counts(name: &str, body: &str) -> (usize, usize, usize) {
    let g = "duration 1s\nletters() : t -> [l]\n";
    let count = |op: &str| {
        let grammar = g.replace("letters", op);
        let (a, _) = expand(text_scene_of(name, &svg(body)), &grammar);
        tagged(&a, "l").len()
    };
    (count("letters"), count("words"), count("lines"))
}

#[test]
fn letters_are_the_visible_clusters_in_reading_order() {
    let body = r##"<text id="t" x="20" y="80" font-family="Noto Sans" font-size="40" fill="#1f6feb">Hello <tspan fill="#ff0000">world</tspan></text>"##;
    let (a, _) = expand(
        text_scene_of("hello", &svg(body)),
        "duration 1s\nletters() : t -> [ch]\n",
    );
    let pieces = tagged(&a, "ch");
    // "Hello world": eleven characters, one of them a space.
    assert_eq!(
        pieces.len(),
        "Hello world".chars().filter(|c| !c.is_whitespace()).count()
    );
    let cx: Vec<f64> = centroids(&a, "ch").iter().map(|p| p.x).collect();
    assert!(cx.windows(2).all(|w| w[0] < w[1]), "{cx:?}");
    // Each letter keeps its paint, and its curves (the font's quadratic outlines) where
    // it has any.
    let letters: Vec<char> = "Helloworld".chars().collect();
    for (k, &i) in pieces.iter().enumerate() {
        let s = &a.scene.shapes[i];
        let want = if k < 5 {
            Color::rgb8(0x1f, 0x6f, 0xeb)
        } else {
            Color::rgb8(255, 0, 0)
        };
        assert_eq!(s.fill, want, "letter {k}");
        let node = a.scene.root.node_at(&s.node_path).unwrap();
        let Node::Path(p) = node else {
            panic!("letter {k} is a {node:?}")
        };
        assert!(matches!(
            p.fill.as_ref().map(|f| &f.paint),
            Some(Paint::Solid(_))
        ));
        let curved = (p.path.elements().iter())
            .any(|e| matches!(e, PathEl::QuadTo(..) | PathEl::CurveTo(..)));
        assert!(
            curved || !"eord".contains(letters[k]),
            "letter {k}, {}",
            letters[k]
        );
        // Its box lies within the text's line.
        assert!(
            s.bbox.y0 > 40.0 && s.bbox.y1 < 95.0,
            "letter {k}: {:?}",
            s.bbox
        );
    }
}

#[test]
fn hebrew_reads_right_to_left() {
    let word = "שלום עולם";
    let body = format!(
        r#"<text id="t" x="20" y="80" font-family="Noto Sans Hebrew" font-size="40">{word}</text>"#
    );
    let (a, _) = expand(
        text_scene_of("hebrew", &svg(&body)),
        "duration 1s\nletters() : t -> [ch]\n",
    );
    let cx: Vec<f64> = centroids(&a, "ch").iter().map(|p| p.x).collect();
    assert_eq!(
        cx.len(),
        word.chars().filter(|c| !c.is_whitespace()).count()
    );
    assert!(cx.windows(2).all(|w| w[0] > w[1]), "{cx:?}");
    // Words too: the first word read is the right one.
    let (w, _) = expand(
        text_scene_of("hebrew-words", &svg(&body)),
        "duration 1s\nwords() : t -> [w]\n",
    );
    let wx: Vec<f64> = centroids(&w, "w").iter().map(|p| p.x).collect();
    assert_eq!(wx.len(), 2);
    assert!(wx[0] > wx[1], "{wx:?}");
}

#[test]
fn a_ligature_is_one_letter() {
    // Noto Sans draws "fi" and "ffi" as one glyph each.
    let lig = |s: &str| {
        counts(
            "ligature",
            &format!(
                r#"<text id="t" x="20" y="80" font-family="Noto Sans" font-size="40">{s}</text>"#
            ),
        )
        .0
    };
    assert_eq!(lig("fi"), 1);
    assert_eq!(lig("office"), 4);
    // Letters apart by spacing are not joined.
    assert_eq!(lig("f i"), 2);
}

#[test]
fn words_and_lines_of_tspan_lines() {
    let body = r#"<text id="t" x="20" y="40" font-family="Noto Sans" font-size="20">one two<tspan x="20" dy="30">three four nine</tspan><tspan x="20" dy="30">six</tspan></text>"#;
    assert_eq!(counts("lines", body), (22, 6, 3));
    // Letters know their line and word.
    let (a, _) = expand(
        text_scene_of("places", &svg(body)),
        "duration 1s\nletters() : t -> [ch]\n",
    );
    let places: Vec<(usize, usize)> = tagged(&a, "ch")
        .into_iter()
        .map(|i| (a.scene.shapes[i].text.line, a.scene.shapes[i].text.word))
        .collect();
    let mut want = Vec::new();
    for (line, words) in [
        vec!["one", "two"],
        vec!["three", "four", "nine"],
        vec!["six"],
    ]
    .iter()
    .enumerate()
    {
        for w in words {
            let word = want.last().map_or(0, |&(_, w): &(usize, usize)| w + 1);
            want.extend(std::iter::repeat_n((line, word), w.len()));
        }
    }
    assert_eq!(places, want);
}

#[test]
fn text_on_a_path_is_a_line() {
    let body = r##"<defs><path id="arc" d="M 20 200 Q 200 40 380 200"/></defs>
        <text id="t" font-family="Noto Sans" font-size="24"><textPath xlink:href="#arc">round the bend</textPath></text>"##;
    assert_eq!(counts("on-path", body), (12, 3, 1));
    // A heading above it is a line of its own.
    let both = format!(
        r##"<text id="t" font-family="Noto Sans" font-size="24"><tspan x="20" y="30">Title</tspan><textPath xlink:href="#arc">round the bend</textPath></text>{}"##,
        r#"<defs><path id="arc" d="M 20 200 Q 200 40 380 200"/></defs>"#
    );
    assert_eq!(counts("on-path-2", &both), (17, 4, 2));
    // Along the path, reading order follows it: left to right on this arc.
    let (a, _) = expand(
        text_scene_of("on-path-order", &svg(body)),
        "duration 1s\nletters() : t -> [ch]\n",
    );
    let cx: Vec<f64> = centroids(&a, "ch").iter().map(|p| p.x).collect();
    assert!(cx.windows(2).all(|w| w[0] < w[1]), "{cx:?}");
}

#[test]
fn line_id_and_word_id_drive_motion() {
    let body = r#"<text id="t" x="20" y="40" font-family="Noto Sans" font-size="20">ab cd<tspan x="20" dy="30">ef</tspan></text>"#;
    let grammar = "duration 1s\nloop false\nletters() : t -> [ch]\n\
        animate(affine, world, 0, translate(100 * word_id, 10 * line_id)) : [all, ch] -> [m]\n";
    let (a, _) = expand(text_scene_of("vars", &svg(body)), grammar);
    let ch = tagged(&a, "ch");
    assert_eq!(ch.len(), 6);
    let want = [
        (0.0, 0.0),
        (0.0, 0.0),
        (100.0, 0.0),
        (100.0, 0.0),
        (200.0, 10.0),
        (200.0, 10.0),
    ];
    for (&i, (dx, dy)) in ch.iter().zip(want) {
        let moved = centre_at(&a, i, 1.0) - a.scene.shapes[i].centroid;
        assert!(
            (moved.x - dx).abs() < 1e-6 && (moved.y - dy).abs() < 1e-6,
            "{i}: {moved:?}"
        );
    }
    // Shapes that did not come from text have both at 0.
    let plain = scene_of(&svg(
        r#"<rect id="r" x="10" y="10" width="20" height="20"/>"#,
    ));
    let (p, _) = expand(
        plain,
        "duration 1s\nloop false\nanimate(affine, world, 0, translate(5 + word_id, 5 + line_id)) : [all, r] -> [m]\n",
    );
    let moved = centre_at(&p, 0, 1.0) - p.scene.shapes[0].centroid;
    assert!((moved.x - 5.0).abs() < 1e-9 && (moved.y - 5.0).abs() < 1e-9);
}

#[test]
fn a_per_letter_stagger_scales_each_letter_about_its_centroid() {
    let body =
        r#"<text id="title" x="20" y="80" font-family="Noto Sans" font-size="40">Hey you</text>"#;
    let grammar = "duration 2s\nloop false\nletters() : title -> [ch]\n\
        timesplit(0.5, 0.5) : [all, ch] -> [a, b]\n\
        animate(affine, local, 0.05 * id, scale(0.2)) : [a, ch] -> [s]\n";
    let (a, _) = expand(text_scene_of("stagger", &svg(body)), grammar);
    let ch = tagged(&a, "ch");
    assert_eq!(ch.len(), 6);
    for (k, &i) in ch.iter().enumerate() {
        // The pivot is the letter's own centroid: it stays where it is.
        let c = a.scene.shapes[i].centroid;
        for t in [0.3, 0.6, 1.0, 1.5] {
            let at = centre_at(&a, i, t);
            assert!(
                (at - c).hypot() < 1e-6,
                "letter {k} at {t}: {at:?} vs {c:?}"
            );
        }
        // Letter k starts 0.05 k later: at 0.05 k its scale is still 1.
        let m = a.tracks[i].transform_at(0.05 * k as f64);
        assert!((m.determinant() - 1.0).abs() < 1e-6, "letter {k}");
        let end = a.tracks[i].transform_at(1.0);
        assert!(end.determinant() < 1.0 - 1e-3, "letter {k} did not shrink");
    }
}

#[test]
fn letters_on_a_shape_that_is_not_text_warn_and_leave_it() {
    let art = svg(r##"<path id="blob" d="M 10 10 C 60 0 90 40 60 80 Z" fill="#336699"/>"##);
    let scene = scene_of(&art);
    let before = match scene.root.node_at(&scene.shapes[0].node_path) {
        Some(Node::Path(p)) => p.path.clone(),
        other => panic!("{other:?}"),
    };
    let (a, stats) = expand(scene, "duration 1s\nletters() : blob -> [ch]\n");
    let warned: Vec<String> = stats.warnings.iter().map(|w| w.message.clone()).collect();
    assert!(
        warned.iter().any(|w| w.contains("letters()")
            && w.contains("`path` #0")
            && w.contains("did not come from text")),
        "{warned:?}"
    );
    // One piece, drawn as it was: the curve is still a curve, not a polygon.
    let ch = tagged(&a, "ch");
    assert_eq!(ch.len(), 1);
    let node = a
        .scene
        .root
        .node_at(&a.scene.shapes[ch[0]].node_path)
        .unwrap();
    let Node::Path(p) = node else {
        panic!("{node:?}")
    };
    assert_eq!(p.path, before);
}

#[test]
fn the_text_operators_take_no_arguments() {
    let body = r#"<text id="t" x="20" y="80" font-family="Noto Sans" font-size="40">Hi</text>"#;
    for op in ["letters", "words", "lines"] {
        let src = format!("duration 1s\n{op}(2) : t -> [ch]\n");
        let g = gmotion::grammar::parse(&src).unwrap();
        let err = run(
            text_scene_of("args", &svg(body)),
            &g,
            &RunOptions::default(),
        )
        .unwrap_err();
        let span = err.span.expect("located");
        assert_eq!(
            (span.line, span.col),
            (2, op.len() as u32 + 2),
            "{op}: {err}"
        );
        assert!(
            err.to_string().contains("takes no arguments"),
            "{op}: {err}"
        );
    }
}
