//! `gmotion-learn` on animations made from grammars whose meaning is known: what it learns
//! is checked against properties of the language (docs/grammar.md), not against text it
//! printed before. A stagger `b · id` comes back as `b * id`; every named easing comes back
//! as itself; a slice and its inverted twin come back as a twin; a unit that does not move
//! changes nothing in what is learned of the others; and learning is a fixed point: the
//! learned grammar's own animation is learned as the same grammar.
//!
//! The animations are exported to Lottie by the pipeline (the same writer as `gmotion
//! animate`); that the learned grammars play like their originals in real players is
//! checked end to end by the command line's tests (`cli/tests/learn.rs`).

use std::path::{Path, PathBuf};

use gmotion::canvas::OutputSize;
use gmotion_learn::{Learned, Options, learn, learn_default};
use gmotion_pipeline::{Env, ImportChoices, Imported, Overrides, Project, Writer};

/// A fresh folder for one test's files.
fn fresh_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gmotion-learn-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

/// `n` 20 px squares tagged `s` in a row, and a still circle `c` when `circle`.
fn squares(n: usize, circle: bool) -> String {
    let mut svg = String::from(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="400" height="200" viewBox="0 0 400 200">"#,
    );
    for i in 0..n {
        svg.push_str(&format!(
            r##"<rect data-tag="s" x="{}" y="20" width="20" height="20" fill="#d33"/>"##,
            20 + 40 * i
        ));
    }
    if circle {
        svg.push_str(r##"<circle data-tag="c" cx="300" cy="150" r="20" fill="#36c"/>"##);
    }
    svg.push_str("</svg>");
    svg
}

/// Runs `grammar` on `svg` (both written into `dir` under `name`) and writes its Lottie.
fn export(dir: &Path, name: &str, svg: &str, grammar: &str) -> PathBuf {
    std::fs::write(dir.join(format!("{name}.svg")), svg).unwrap();
    let gm = dir.join(format!("{name}.gm"));
    std::fs::write(&gm, format!("scene {name}.svg\n{grammar}")).unwrap();
    run_to_lottie(&gm, &dir.join(format!("{name}.json")))
}

/// Runs the grammar at `gm` and writes its animation as Lottie to `out`.
fn run_to_lottie(gm: &Path, out: &Path) -> PathBuf {
    let env = Env::default();
    let project = Project::load(None, gm, &ImportChoices::default(), &env)
        .unwrap_or_else(|e| panic!("{}: {e}", gm.display()));
    let run = Overrides::default().run_options(&env.limits).unwrap();
    let rendered = project.run(&run, false).expect("the grammar runs");
    Writer::new(OutputSize::default(), &env.limits)
        .write(&rendered, out, &|| {})
        .expect("the Lottie is written");
    out.to_path_buf()
}

/// Learns the Lottie at `json`, its still scene to be named `still.json`.
fn learned(json: &Path) -> Learned {
    learn(json, "still.json", &Env::default(), &Options::default())
        .unwrap_or_else(|e| panic!("{}: {e}", json.display()))
}

/// The learned grammar's rules (no comments, directives or blank lines).
fn rules(l: &Learned) -> Vec<&str> {
    l.grammar
        .lines()
        .filter(|line| line.contains("->"))
        .collect()
}

/// Writes what was learned beside `dir/NAME` (the grammar and its still scene) and
/// returns the grammar's path, ready to run.
fn write_learned(dir: &Path, l: &Learned) -> PathBuf {
    let anim = l.still_animation(l.duration, l.fps);
    gmotion_output::write(&anim, &dir.join("still.json"), &Default::default())
        .expect("the still scene is written");
    let gm = dir.join("learned.gm");
    std::fs::write(&gm, &l.grammar).unwrap();
    gm
}

#[test]
fn a_stagger_comes_back_as_an_offset_in_id() {
    let dir = fresh_dir("stagger");
    for b in [0.1, 0.25, 0.4] {
        let json = export(
            &dir,
            "row",
            &squares(5, false),
            &format!(
                "duration 4s\nfps 30\n\
                 timesplit(0.6, 0.4) : [all, s] -> [a, rest]\n\
                 animate(affine, world, {b} * id, translate(0, 100), ease=ease-in-out) : [a, s] -> [m]\n"
            ),
        );
        let l = learned(&json);
        assert_eq!(l.report.unexplained().count(), 0, "b = {b}: {}", l.report);
        let moves: Vec<_> = rules(&l)
            .into_iter()
            .filter(|r| r.starts_with("animate"))
            .collect();
        assert_eq!(
            moves.len(),
            1,
            "b = {b}: one rule for the five squares\n{}",
            l.grammar
        );
        assert!(
            moves[0].contains(&format!("{b} * id")),
            "b = {b}: the stagger\n{}",
            l.grammar
        );
    }
}

#[test]
fn every_named_easing_comes_back_as_itself() {
    let dir = fresh_dir("easings");
    for ease in ["linear", "ease", "ease-in", "ease-out", "ease-in-out"] {
        let json = export(
            &dir,
            "one",
            &squares(1, false),
            &format!(
                "duration 2s\nfps 30\n\
                 timesplit(0.75, 0.25) : [all, s] -> [a, rest]\n\
                 animate(affine, world, 0, translate(200, 0), ease={ease}) : [a, s] -> [m]\n"
            ),
        );
        let l = learned(&json);
        assert_eq!(l.report.unexplained().count(), 0, "{ease}: {}", l.report);
        let moves: Vec<_> = rules(&l)
            .into_iter()
            .filter(|r| r.starts_with("animate"))
            .collect();
        assert_eq!(moves.len(), 1, "{ease}\n{}", l.grammar);
        // `linear` is the default and may be left out.
        let named = if ease == "linear" {
            !moves[0].contains("ease=") || moves[0].contains("ease=linear")
        } else {
            moves[0].contains(&format!("ease={ease})"))
                || moves[0].contains(&format!("ease={ease},"))
        };
        assert!(named, "{ease}: {}", moves[0]);
    }
}

#[test]
fn a_slice_and_its_inverted_twin_come_back_as_a_twin() {
    let dir = fresh_dir("twin");
    let json = export(
        &dir,
        "twin",
        &squares(1, false),
        "duration 2s\nfps 30\n\
         timesplit(0.5, 0.5) : [all, s] -> [a, inv_a]\n\
         animate(affine, local, 0, rotate(90) scale(1.5), ease=ease-out) : [a, s] -> [m]\n",
    );
    let l = learned(&json);
    assert_eq!(l.report.unexplained().count(), 0, "{}", l.report);
    let split = rules(&l)
        .into_iter()
        .find(|r| r.starts_with("timesplit"))
        .unwrap_or_else(|| panic!("a timesplit\n{}", l.grammar));
    assert!(
        split.contains("inv_"),
        "the second half is the first's twin: {split}"
    );
    assert_eq!(
        rules(&l)
            .iter()
            .filter(|r| r.starts_with("animate"))
            .count(),
        1,
        "one change, played forwards then backwards\n{}",
        l.grammar
    );
}

#[test]
fn a_still_unit_elsewhere_changes_nothing_learned_of_the_others() {
    let dir = fresh_dir("locality");
    let grammar = "duration 3s\nfps 30\n\
                   timesplit(0.5, 0.5) : [all, s] -> [a, inv_a]\n\
                   animate(affine, world, 0.2 * id, translate(0, 80)) : [a, s] -> [m]\n";
    let alone = learned(&export(&dir, "alone", &squares(4, false), grammar));
    let with = learned(&export(&dir, "with", &squares(4, true), grammar));
    assert_eq!(with.report.unexplained().count(), 0, "{}", with.report);
    let of_s = |l: &Learned| -> Vec<String> {
        rules(l)
            .into_iter()
            .filter(|r| r.contains(", s]"))
            .map(str::to_string)
            .collect()
    };
    assert!(!of_s(&alone).is_empty(), "{}", alone.grammar);
    assert_eq!(of_s(&alone), of_s(&with));
    assert!(
        !rules(&with).iter().any(|r| r.contains(", c]")),
        "the still circle gets no rule\n{}",
        with.grammar
    );
}

#[test]
fn learning_its_own_grammar_again_gives_the_same_grammar() {
    let dir = fresh_dir("fixed_point");
    let json = export(
        &dir,
        "toy",
        &squares(3, true),
        "duration 4s\nfps 30\n\
         timesplit(0.5, 0.5) : [all, (s, c)] -> [a, inv_a]\n\
         animate(affine, world, 0, translate(0, 100), ease=ease-in-out) : [a, s] -> [down]\n\
         timesplit(0.4, 0.6) : [a, c] -> [b, d]\n\
         animate(affine, local, 0, scale(0.5)) : [b, c] -> [small]\n\
         animate(opacity, local, 0, 0.5) : [d, c] -> [faded]\n",
    );
    let first = learned(&json);
    assert_eq!(first.report.unexplained().count(), 0, "{}", first.report);
    let gm = write_learned(&dir, &first);
    let again = learned(&run_to_lottie(&gm, &dir.join("again.json")));
    assert_eq!(
        rules(&again),
        rules(&first),
        "{}\n---\n{}",
        first.grammar,
        again.grammar
    );
}

/// `c`, `b * id`, `c + b * id` or `c - b * id` at `id`.
fn linear_in_id(text: &str, id: f64) -> Option<f64> {
    let (c, rest) = match text.find(" * id") {
        None => return text.parse().ok(),
        Some(at) => (&text[..at], &text[at + " * id".len()..]),
    };
    if !rest.is_empty() {
        return None;
    }
    Some(match c.rsplit_once(' ') {
        None => c.parse::<f64>().ok()? * id,
        Some((head, b)) => {
            let b: f64 = b.parse().ok()?;
            let (a, sign) = head.rsplit_once(' ')?;
            let a: f64 = a.parse().ok()?;
            if sign == "-" { a - b * id } else { a + b * id }
        }
    })
}

/// The fitter cuts time in eighths of a frame: no slice may be shorter (a frame rate such
/// as 29.97 must not leave slivers of a few nanoseconds at the end), and the fractions are
/// written short (a quarter is `0.25`, a stagger of an eighth `0.125 * id`). On the
/// Bodymovin file the command line's tests use, whose first dots share one set.
#[test]
fn an_after_effects_timeline_is_cut_in_whole_pieces_written_short() {
    let json = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cli/tests/data/learn/material_wave_loading.json");
    let l = learned(&json);
    assert_eq!(l.report.unexplained().count(), 0, "{}", l.report);
    let eighth = 1.0 / (8.0 * l.fps);
    let mut shared = 0;
    for split in rules(&l)
        .into_iter()
        .filter(|r| r.starts_with("timesplit("))
    {
        let args = &split["timesplit(".len()..split.find(')').unwrap()];
        let tag = &split[split.find("[all, ").unwrap() + 6..split.find("] ->").unwrap()];
        let set = l.report.sets.iter().find(|s| s.tags == tag).unwrap();
        shared += usize::from(set.units.len() > 1);
        for f in args.split(", ") {
            for number in f
                .split([' ', '*', '+', '-'])
                .filter(|t| !t.is_empty() && *t != "id")
            {
                assert!(number.len() <= 6, "a fraction written long: {split}");
            }
            for &u in &set.units {
                let id = l.still.shapes[u].id as f64;
                let f = linear_in_id(f, id)
                    .unwrap_or_else(|| panic!("a fraction linear in id: {split}"));
                assert!(f * l.duration >= eighth - 1e-9, "a sliver: {split}");
            }
        }
    }
    assert_eq!(shared, 1, "the first dots share a set\n{}", l.grammar);
}

/// Squares tagged by `tags` (one per square, cycled) at the x positions `xs`, 20 px wide.
fn squares_at(xs: &[f64], tags: &[&str]) -> String {
    let mut svg = String::from(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="400" height="200" viewBox="0 0 400 200">"#,
    );
    for (i, x) in xs.iter().enumerate() {
        svg.push_str(&format!(
            r##"<rect data-tag="{}" x="{x}" y="20" width="20" height="20" fill="#d33"/>"##,
            tags[i % tags.len()]
        ));
    }
    svg.push_str("</svg>");
    svg
}

/// The number `NAME` is multiplied by in `rule` (`… 0.004 * cx …`), if any.
fn coefficient(rule: &str, name: &str) -> Option<f64> {
    let at = rule.find(&format!(" * {name}"))?;
    let before = &rule[..at];
    let start = before
        .rfind(|c: char| !(c.is_ascii_digit() || c == '.'))
        .map_or(0, |i| i + 1);
    before[start..].parse().ok()
}

/// Learns `json`, plays the learned grammar again and learns that: the same rules come
/// back only if `animate` gives the shape's variables the values `learn` fitted them with.
fn learned_twice(dir: &Path, json: &Path) -> (Learned, Learned) {
    let first = learned(json);
    let gm = write_learned(dir, &first);
    let again = learned(&run_to_lottie(&gm, &dir.join("again.json")));
    (first, again)
}

#[test]
fn a_stagger_along_x_comes_back_as_an_offset_in_cx() {
    let dir = fresh_dir("stagger_cx");
    // Document order is not left to right: the stagger is no line in `id`.
    let json = export(
        &dir,
        "row",
        &squares_at(&[20.0, 300.0, 100.0, 220.0, 60.0], &["s"]),
        "duration 4s\nfps 30\n\
         timesplit(0.6, 0.4) : [all, s] -> [a, rest]\n\
         animate(affine, world, 0.004 * cx, translate(0, 100), ease=ease-in-out) : [a, s] -> [m]\n",
    );
    let (l, again) = learned_twice(&dir, &json);
    assert_eq!(l.report.unexplained().count(), 0, "{}", l.report);
    let moves: Vec<_> = rules(&l)
        .into_iter()
        .filter(|r| r.starts_with("animate"))
        .collect();
    assert_eq!(
        moves.len(),
        1,
        "one rule for the five squares\n{}",
        l.grammar
    );
    let b = coefficient(moves[0], "cx").unwrap_or_else(|| panic!("a stagger in cx: {}", moves[0]));
    assert!((b - 0.004).abs() < 1e-5, "{}", moves[0]);
    assert_eq!(
        rules(&again),
        rules(&l),
        "{}\n---\n{}",
        l.grammar,
        again.grammar
    );
}

#[test]
fn a_translation_growing_with_id_comes_back_as_one_rule() {
    let dir = fresh_dir("amount_id");
    let json = export(
        &dir,
        "row",
        &squares(5, false),
        "duration 3s\nfps 30\n\
         timesplit(0.5, 0.5) : [all, s] -> [a, rest]\n\
         animate(affine, world, 0, translate(0, 20 + 25 * id), ease=ease-out) : [a, s] -> [m]\n",
    );
    let (l, again) = learned_twice(&dir, &json);
    assert_eq!(l.report.unexplained().count(), 0, "{}", l.report);
    let moves: Vec<_> = rules(&l)
        .into_iter()
        .filter(|r| r.starts_with("animate"))
        .collect();
    assert_eq!(
        moves.len(),
        1,
        "one rule for the five squares\n{}",
        l.grammar
    );
    assert!(
        moves[0].contains("translate(0, 20 + 25 * id)"),
        "{}",
        moves[0]
    );
    assert_eq!(
        rules(&again),
        rules(&l),
        "{}\n---\n{}",
        l.grammar,
        again.grammar
    );
}

#[test]
fn tags_that_move_alike_share_one_rule_set_on_the_tuple_of_them() {
    let dir = fresh_dir("tuple");
    let json = export(
        &dir,
        "two",
        &squares_at(&[20.0, 80.0, 140.0, 200.0, 260.0, 320.0], &["s", "t"]),
        "duration 4s\nfps 30\n\
         timesplit(0.5, 0.5) : [all, (s, t)] -> [a, inv_a]\n\
         animate(affine, local, 0.2 * k, rotate(90), ease=ease-in) : [a, (s, t)] -> [m]\n",
    );
    let (l, again) = learned_twice(&dir, &json);
    assert_eq!(l.report.unexplained().count(), 0, "{}", l.report);
    assert_eq!(
        l.report.sets.len(),
        1,
        "one set for both tags\n{}",
        l.grammar
    );
    assert_eq!(rules(&l).len(), 2, "{}", l.grammar);
    assert!(rules(&l)[1].contains("(s, t)]"), "{}", l.grammar);
    assert_eq!(
        rules(&again),
        rules(&l),
        "{}\n---\n{}",
        l.grammar,
        again.grammar
    );
}

/// A 240 px stroked line tagged `l` (no fill: a trim draws strokes only).
fn line() -> String {
    r##"<svg xmlns="http://www.w3.org/2000/svg" width="300" height="100" viewBox="0 0 300 100"><path data-tag="l" d="M 30 50 L 270 50" fill="none" stroke="#333" stroke-width="8"/></svg>"##.to_string()
}

/// The learned grammar's trim rules.
fn trims(l: &Learned) -> Vec<&str> {
    rules(l)
        .into_iter()
        .filter(|r| r.starts_with("animate(trim,"))
        .collect()
}

#[test]
fn a_trim_drawn_on_from_nothing_comes_back_as_a_draw_on() {
    let dir = fresh_dir("draw_on");
    let json = export(
        &dir,
        "on",
        &line(),
        "duration 2s\nfps 30\n\
         timesplit(0.5, 0.5) : [all, l] -> [a, rest]\n\
         animate(trim, local, 0, (0, 0), ease=ease-out) : [a, l] -> [inv_on]\n",
    );
    let l = learned(&json);
    assert_eq!(l.report.unexplained().count(), 0, "{}", l.report);
    let t = trims(&l);
    // The stroke starts empty and is drawn on: an inverted change from (0, 0), with the
    // easing written (played backwards, ease-out draws on as ease-in would forwards).
    assert_eq!(t.len(), 1, "{}", l.grammar);
    assert!(t[0].contains("(0, 0)"), "{}", t[0]);
    assert!(t[0].contains("ease=ease-out"), "{}", t[0]);
    assert!(t[0].contains("-> [inv_"), "an inverted slice: {}", t[0]);
}

#[test]
fn a_trim_drawn_off_comes_back_and_learning_it_again_is_a_fixed_point() {
    let dir = fresh_dir("draw_off");
    let json = export(
        &dir,
        "off",
        &line(),
        "duration 3s\nfps 30\n\
         timesplit(0.4, 0.6) : [all, l] -> [rest, b]\n\
         animate(trim, local, 0.3, (1, 1), ease=ease-in) : [b, l] -> [gone]\n",
    );
    // No still named: a grammar with trims names an SVG still, which holds them.
    let first = learn_default(
        &json,
        "still.json",
        "still.svg",
        &Env::default(),
        &Options::default(),
    )
    .unwrap();
    assert!(first.still_svg, "{}", first.grammar);
    assert_eq!(first.report.unexplained().count(), 0, "{}", first.report);
    let t = trims(&first);
    assert_eq!(t.len(), 1, "{}", first.grammar);
    assert!(t[0].contains("(1, 1)"), "{}", t[0]);
    assert!(t[0].contains("ease=ease-in"), "{}", t[0]);
    let imported = Imported {
        scene: first.still.clone(),
        source: None,
        package: None,
    };
    Writer::new(OutputSize::default(), &Env::default().limits)
        .write_still(&imported, &dir.join("still.svg"))
        .expect("the SVG still is written");
    let gm = dir.join("learned.gm");
    std::fs::write(&gm, &first.grammar).unwrap();
    let again = learned(&run_to_lottie(&gm, &dir.join("again.json")));
    assert_eq!(
        rules(&again),
        rules(&first),
        "{}\n---\n{}",
        first.grammar,
        again.grammar
    );
}

#[test]
fn an_outline_that_changes_comes_back_as_a_morph() {
    let dir = fresh_dir("morph");
    let json = export(
        &dir,
        "morph",
        &squares(1, false),
        "duration 2s\nfps 30\n\
         timesplit(0.25, 0.5, 0.25) : [all, s] -> [rest, a, after]\n\
         animate(morph, world, 0, \"M 30 10 L 50 30 L 30 50 L 10 30 Z\", ease=ease-in-out) : [a, s] -> [m]\n",
    );
    let l = learn_default(
        &json,
        "still.json",
        "still.svg",
        &Env::default(),
        &Options::default(),
    )
    .unwrap();
    assert_eq!(l.report.unexplained().count(), 0, "{}", l.report);
    // A morph is written natively only onto an SVG still.
    assert!(l.still_svg, "{}", l.grammar);
    let morphs: Vec<&str> = rules(&l)
        .into_iter()
        .filter(|r| r.starts_with("animate(morph,"))
        .collect();
    // The engine brings both outlines to one structure by cutting them at the union of
    // their vertices' fractions of the length, which moves the in-between off the straight
    // vertex paths the exported keys take: the change may take a few pieces, each within
    // the tolerance, all inside the slice that morphs.
    assert!(!morphs.is_empty(), "a morph\n{}", l.grammar);
    assert!(
        !rules(&l).iter().any(|r| r.starts_with("animate(affine,")),
        "nothing moves the square: its outline changes\n{}",
        l.grammar
    );
}

#[test]
fn a_fill_on_a_line_paints_nothing_and_does_not_hide_the_unit_s_colour() {
    // A unit of a filled shape and a filled line (no area: an exporter keeps a stroke's
    // centre line so beside its outline): one colour is painted, and its change is learned.
    let dir = fresh_dir("line_fill");
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100" viewBox="0 0 200 100"><g data-tag="t"><path d="M 30 20 L 30 60" fill="#000"/><rect x="40" y="20" width="20" height="40" fill="#d33"/></g></svg>"##;
    let json = export(
        &dir,
        "tint",
        svg,
        "duration 2s\nfps 30\n\
         timesplit(0.5, 0.5) : [all, t] -> [a, rest]\n\
         animate(fill, local, 0, #3366cc) : [a, t] -> [blue]\n",
    );
    let l = learned(&json);
    assert_eq!(l.report.unexplained().count(), 0, "{}", l.report);
    assert!(
        rules(&l).iter().any(|r| r.starts_with("animate(fill,")),
        "{}",
        l.grammar
    );
}

#[test]
fn a_stroke_width_and_colour_ramp_comes_back() {
    let dir = fresh_dir("stroke");
    let json = export(
        &dir,
        "ramp",
        &line(),
        "duration 2s\nfps 30\n\
         timesplit(0.25, 0.75) : [all, l] -> [rest, a]\n\
         animate(stroke-width, local, 0, 20, ease=ease-in-out) : [a, l] -> [thick]\n\
         animate(border, local, 0, #3366cc, ease=ease-in-out) : [thick, l] -> [blue]\n",
    );
    let l = learned(&json);
    assert_eq!(l.report.unexplained().count(), 0, "{}", l.report);
    let has = |start: &str, value: &str| {
        rules(&l)
            .iter()
            .any(|r| r.starts_with(start) && r.contains(value) && r.contains("ease=ease-in-out"))
    };
    assert!(has("animate(stroke-width,", ", 20,"), "{}", l.grammar);
    assert!(has("animate(border,", "rgb(51, 102, 204)"), "{}", l.grammar);
}

#[test]
fn a_unit_that_fades_out_and_goes_is_learned_as_a_fade() {
    // Faded to nothing, the square draws nothing (a layer the player leaves out): those
    // frames are an opacity of 0, not a drawing that changes structure.
    let dir = fresh_dir("gone");
    let json = export(
        &dir,
        "gone",
        &squares(1, false),
        "duration 2s\nfps 30\n\
         timesplit(0.5, 0.5) : [all, s] -> [a, rest]\n\
         animate(affine, world, 0, translate(100, 0)) : [a, s] -> [m]\n\
         animate(opacity, local, 0, 0) : [m, s] -> [gone]\n",
    );
    let l = learned(&json);
    assert_eq!(l.report.unexplained().count(), 0, "{}", l.report);
    assert!(
        rules(&l)
            .iter()
            .any(|r| r.starts_with("animate(opacity,") && r.contains(", 0)")),
        "{}",
        l.grammar
    );
}
