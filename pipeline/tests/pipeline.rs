//! The pipeline end to end: a project loaded from the bundled examples, run, and written
//! by the one writer to bytes and to files (the same bytes), for every extension.

use std::path::{Path, PathBuf};

use gmotion::canvas::OutputSize;
use gmotion_pipeline::{
    Env, Error, ImportChoices, OutputError, Overrides, Project, Rendered, Transitions, Writer,
};

/// A file of the repository's bundled examples.
fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../grammars")
        .join(name)
}

/// A fresh folder for one test's files.
fn fresh_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gmotion-pipeline-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

/// The toy example (a square and four circles, 6 s at 30 fps) run with its timelines.
fn toy(env: &Env) -> Rendered {
    let project = Project::load(None, &example("toy.gm"), &ImportChoices::default(), env)
        .expect("the toy loads");
    let run = Overrides::default()
        .run_options(&env.limits)
        .expect("run options");
    project.run(&run, true).expect("the toy runs")
}

/// A writer of small pictures (the frames stay cheap to draw).
fn small(env: &Env) -> Writer {
    let size = OutputSize {
        width: Some(48),
        height: None,
    };
    Writer::new(size, &env.limits)
}

#[test]
fn every_extension_to_bytes_is_what_the_file_gets() {
    let env = Env::default();
    let rendered = toy(&env);
    assert!(rendered.source.is_none() && rendered.timelines.is_some());
    let writer = small(&env);
    let dir = fresh_dir("bytes");
    let starts: [(&str, &[u8]); 6] = [
        ("json", b"{"),
        ("svg", b"<svg"),
        ("png", b"\x89PNG"),
        ("gif", b"GIF89a"),
        ("apng", b"\x89PNG"),
        ("html", b"<!doctype html>"),
    ];
    for (ext, start) in starts {
        let path = dir.join(format!("toy.{ext}"));
        let (bytes, _) = writer.bytes(&rendered, &path).expect(ext);
        assert!(bytes.starts_with(start), ".{ext} starts {:?}", &bytes[..8]);
        assert!(!path.exists(), "bytes of .{ext} wrote a file");
        writer.write(&rendered, &path, &|| {}).expect(ext);
        let written = std::fs::read(&path).expect("the written file");
        assert!(written == bytes, ".{ext}: the file and the bytes differ");
    }
    let html = String::from_utf8(writer.bytes(&rendered, &dir.join("p.html")).unwrap().0).unwrap();
    // The page carries the timeline's data: the toy's shapes, each a row.
    assert!(
        html.contains("lottie.loadAnimation") && html.contains("const timeline = {\"duration\"")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_folder_of_frames_is_files_not_bytes() {
    let env = Env::default();
    let rendered = toy(&env);
    let writer = small(&env);
    let dir = fresh_dir("frames");
    let frames = dir.join("frames");
    match writer.bytes(&rendered, &frames) {
        Err(Error::Output(OutputError::FramesInMemory { path })) => assert_eq!(path, frames),
        other => panic!("expected FramesInMemory, got {other:?}"),
    }
    let ticks = std::sync::atomic::AtomicUsize::new(0);
    writer
        .write(&rendered, &frames, &|| {
            ticks.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        })
        .expect("the frames");
    let count = std::fs::read_dir(&frames).expect("the folder").count();
    assert_eq!(count, rendered.anim.frame_count());
    assert_eq!(ticks.into_inner(), count);
    assert!(Writer::draws_every_frame(&frames).unwrap());
    assert!(!Writer::draws_every_frame(Path::new("a.html")).unwrap());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_lottie_scene_travels_with_its_source() {
    let env = Env::default();
    let dir = fresh_dir("lottie");
    // The toy's still scene written as Lottie, then animated as a Lottie scene.
    let still = gmotion_pipeline::Imported::load(
        &example("toy.svg"),
        &gmotion_pipeline::SceneOptions::new(&ImportChoices::default(), None, &env).unwrap(),
        &env,
    )
    .expect("the toy scene");
    let lottie = dir.join("toy.json");
    small(&env)
        .write_still(&still, &lottie)
        .expect("a still Lottie");
    // The still Lottie's layers are tagged by their names: the toy's shapes are `shapes`.
    let grammar = dir.join("slide.gm");
    std::fs::write(
        &grammar,
        "duration 1s\nfps 10\nanimate(affine, world, 0, translate(10, 0)) : [all, shapes] -> [moved]\n",
    )
    .expect("the grammar");
    let project = Project::load(Some(&lottie), &grammar, &ImportChoices::default(), &env)
        .expect("the Lottie scene loads");
    assert!(project.imported.source.is_some());
    let run = Overrides::default().run_options(&env.limits).unwrap();
    let rendered = project.run(&run, false).expect("it runs");
    assert!(rendered.source.is_some());
    let (json, _) = small(&env)
        .bytes(&rendered, &dir.join("out.json"))
        .expect("the Lottie");
    assert!(json.starts_with(b"{"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn transitions_run_into_an_animation() {
    let env = Env::default();
    let spec = Transitions {
        scene: example("histogram.svg"),
        targets: example("histogram.targets.json"),
        ..Transitions::default()
    };
    let rendered = spec
        .run(&ImportChoices::default(), &env)
        .expect("transitions");
    assert!(rendered.anim.frame_count() > 1);
    let (svg, _) = small(&env)
        .bytes(&rendered, Path::new("histogram.svg"))
        .expect("SMIL");
    assert!(svg.starts_with(b"<svg"));
}

#[test]
fn a_missing_grammar_is_named() {
    let env = Env::default();
    let missing = example("no-such-grammar.gm");
    let e = Project::load(None, &missing, &ImportChoices::default(), &env).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains(&missing.display().to_string()) && text.contains("cannot read grammar"),
        "{text}"
    );
}

#[test]
fn a_missing_scene_is_named() {
    let env = Env::default();
    let missing = example("no-such-scene.svg");
    let e = Project::load(
        Some(&missing),
        &example("toy.gm"),
        &ImportChoices::default(),
        &env,
    )
    .unwrap_err();
    let text = e.to_string();
    assert!(text.contains(&missing.display().to_string()), "{text}");
}

#[test]
fn a_limit_passed_is_refused_before_the_run() {
    let env = Env {
        limits: gmotion_pipeline::Limits::parse(&["frames=10".to_string()]).unwrap(),
        ..Env::default()
    };
    let g = gmotion_pipeline::GrammarFile::load(&example("toy.gm"), &env).unwrap();
    let e = g.check_limits(None, false, &env.limits).unwrap_err();
    assert!(e.to_string().contains("more than the limit of 10"), "{e}");
}
