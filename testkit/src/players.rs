//! Real players as test oracles: a Lottie document is played in lottie-web (its svg and
//! canvas renderers, in headless Chromium), rlottie and ThorVG, and every frame is compared
//! with gmotion's own resvg rendering of the animation model at the same instant.
//!
//! The players are the conformance run's (`tests/conformance/`, installed by its
//! `install.sh`, which `scripts/test.sh` runs first). A missing player is a failure, not a
//! skip: a test that cannot see the player has not checked anything.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::sync::{Mutex, PoisonError};

use gmotion::motion::Animation;
use gmotion_export_raster::{Pixmap, compare, render, save_png};
use gmotion_export_svg::frame::frame_svg;

/// A pixel is off when some premultiplied channel differs by more than this (of 255).
const OFF: u8 = 32;
/// At most this fraction of a frame's pixels may be off (the conformance run's bar).
const MAX_OFF: f64 = 0.005;

/// A player that draws Lottie.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Player {
    /// lottie-web's svg renderer.
    LottieWebSvg,
    /// lottie-web's canvas renderer.
    LottieWebCanvas,
    /// rlottie (rlottie-python).
    Rlottie,
    /// ThorVG (thorvg-python).
    Thorvg,
}

impl Player {
    /// Every player.
    pub const ALL: [Player; 4] = [
        Player::LottieWebSvg,
        Player::LottieWebCanvas,
        Player::Rlottie,
        Player::Thorvg,
    ];

    /// The players that draw a translucent shape as a whole. lottie-web's canvas renderer
    /// applies a group's or a layer's opacity to each fill and stroke in it, so where a
    /// translucent shape's stroke overlaps its own fill it draws the overlap darker
    /// (tests/conformance/matrix.py, KNOWN, has a minimal reproducer). rlottie does that
    /// for a group's opacity, and the exporter keeps a single-path shape's opacity on its
    /// group because rlottie's translucent layers dim everything beneath them a little
    /// (which adds up over many layers). A shape with both a fill and a stroke under
    /// partial opacity is judged by these.
    pub const WHOLE_GROUP_OPACITY: [Player; 2] = [Player::LottieWebSvg, Player::Thorvg];

    fn name(self) -> &'static str {
        match self {
            Player::LottieWebSvg => "lottie-web-svg",
            Player::LottieWebCanvas => "lottie-web-canvas",
            Player::Rlottie => "rlottie",
            Player::Thorvg => "thorvg",
        }
    }
}

/// Frames to play for `anim`: 13 evenly spaced over the timeline, and the frames on both
/// sides of every window and attribute change bound (where a wrong key time shows).
pub fn frames_to_check(anim: &Animation) -> Vec<f64> {
    let last = anim.frame_count() as f64;
    let mut frames: Vec<f64> = (0..=12).map(|k| (k as f64 * last / 12.0).floor()).collect();
    let mut bounds = Vec::new();
    for t in &anim.tracks {
        bounds.extend(t.motions.iter().flat_map(|m| [m.t0, m.t1]));
        bounds.extend(t.fill.iter().chain(&t.stroke).flat_map(|a| [a.t0, a.t1]));
        bounds.extend(
            t.opacity
                .iter()
                .chain(&t.stroke_width)
                .flat_map(|a| [a.t0, a.t1]),
        );
        bounds.extend(t.trim.iter().flat_map(|a| [a.t0, a.t1]));
    }
    for b in bounds {
        let f = b * anim.fps;
        frames.extend([f.floor() - 1.0, f.floor(), f.ceil(), f.ceil() + 1.0]);
    }
    frames.retain(|f| (0.0..last).contains(f));
    frames.sort_by(f64::total_cmp);
    frames.dedup();
    frames
}

fn conformance_dir() -> PathBuf {
    crate::root().join("tests/conformance")
}

/// A player kept running for the whole test binary (its script's `--serve` mode): each test
/// sends it one job list and waits for the answer, so that the tests do not each pay the
/// start of Chromium or of a Python player. The player exits when the test binary closes
/// its stdin, by exiting.
struct Server {
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
}

/// lottie-web in Chromium, rlottie and ThorVG, and Chromium playing SVG (SMIL), each
/// started on first use.
static LOTTIE_WEB: Mutex<Option<Server>> = Mutex::new(None);
static CHROMIUM_SMIL: Mutex<Option<Server>> = Mutex::new(None);
static RLOTTIE: Mutex<Option<Server>> = Mutex::new(None);
static THORVG: Mutex<Option<Server>> = Mutex::new(None);

/// Plays `jobs` on the player in `slot` (started with `program script --serve` if it is not
/// running) and returns the jobs that failed, as the player words them. The player's
/// stderr goes to `players/NAME.log` in the test's temporary folder.
fn ask(
    slot: &Mutex<Option<Server>>,
    name: &str,
    program: &str,
    script: &str,
    jobs: &str,
) -> Vec<String> {
    // A test that failed while holding the lock leaves the player in a good state (it
    // answered before the test's assertions ran), so a poisoned lock is still usable.
    let mut guard = slot.lock().unwrap_or_else(PoisonError::into_inner);
    let log = crate::tmp_dir().join("players").join(format!("{name}.log"));
    if guard.is_none() {
        std::fs::create_dir_all(log.parent().unwrap()).expect("create the players folder");
        let stderr = std::fs::File::create(&log).expect("create the player's log");
        let mut child = Command::new(program)
            .arg(conformance_dir().join(script))
            .arg("--serve")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(stderr)
            .spawn()
            .unwrap_or_else(|e| {
                panic!("{name}: cannot start ({e}); run tests/conformance/install.sh")
            });
        let stdin = child.stdin.take().expect("piped stdin");
        let stdout = BufReader::new(child.stdout.take().expect("piped stdout"));
        *guard = Some(Server {
            child,
            stdin,
            stdout,
        });
    }
    let server = guard.as_mut().expect("started above");
    let mut answer = String::new();
    let asked = writeln!(server.stdin, "{jobs}").and_then(|()| server.stdin.flush());
    let answered = asked.and_then(|()| server.stdout.read_line(&mut answer));
    let errors = match answered {
        Ok(n) if n > 0 => serde_json::from_str::<serde_json::Value>(&answer)
            .ok()
            .and_then(|v| serde_json::from_value::<Vec<String>>(v["errors"].clone()).ok()),
        _ => None,
    };
    match errors {
        Some(errors) => errors,
        None => {
            let status = server.child.try_wait();
            *guard = None;
            panic!(
                "{name} stopped answering ({status:?}, answer {answer:?}); its stderr is in {}",
                log.display()
            )
        }
    }
}

/// Plays `lottie` in `players` at the given frame numbers, `width` pixels wide, and returns
/// the folder holding the frames: `{player}-{frame}.png` (see [`frame_path`]). `case`
/// names the folder under the test's temporary folder. A player that fails to start, or
/// cannot draw the file, fails the test.
pub fn play(case: &str, lottie: &str, frames: &[f64], width: u32, players: &[Player]) -> PathBuf {
    play_with_files(case, lottie, &[], frames, width, players)
}

/// [`play`], with `files` (path relative to the Lottie file, contents) written beside it
/// first: the pictures its image assets link.
pub fn play_with_files(
    case: &str,
    lottie: &str,
    files: &[(&str, &[u8])],
    frames: &[f64],
    width: u32,
    players: &[Player],
) -> PathBuf {
    let dir = crate::tmp_dir().join("players").join(case);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create the case folder");
    for (name, bytes) in files {
        let path = dir.join(name);
        std::fs::create_dir_all(path.parent().expect("a file in the case folder"))
            .expect("create the file's folder");
        std::fs::write(&path, bytes).expect("write a file beside the Lottie file");
    }
    let json = dir.join("anim.json");
    std::fs::write(&json, lottie).expect("write the Lottie file");

    let mut jobs = Vec::new();
    for &p in players {
        let out: Vec<String> = frames
            .iter()
            .map(|f| {
                dir.join(format!("{}-{f}.png", p.name()))
                    .display()
                    .to_string()
            })
            .collect();
        let mut job = serde_json::json!({
            "json": json.display().to_string(),
            "width": width,
            "frames": frames,
            "out": out,
        });
        if p == Player::LottieWebCanvas {
            job["renderer"] = "canvas".into();
        }
        jobs.push((p, job));
    }
    let jobs_of = |pick: &dyn Fn(Player) -> bool| -> Option<String> {
        let list: Vec<&serde_json::Value> = jobs
            .iter()
            .filter(|(p, _)| pick(*p))
            .map(|(_, j)| j)
            .collect();
        (!list.is_empty()).then(|| serde_json::to_string(&list).expect("jobs as JSON"))
    };
    // The three players are separate processes: asked together, a test waits for the
    // slowest rather than for the sum (the suite's longest tests are mostly this wait).
    let asks = [
        (
            jobs_of(&|p| matches!(p, Player::LottieWebSvg | Player::LottieWebCanvas)),
            &LOTTIE_WEB,
            "lottie-web",
            "node",
            "lottie_web.mjs",
        ),
        (
            jobs_of(&|p| p == Player::Rlottie),
            &RLOTTIE,
            "rlottie",
            "python3",
            "rlottie_render.py",
        ),
        (
            jobs_of(&|p| p == Player::Thorvg),
            &THORVG,
            "thorvg",
            "python3",
            "thorvg_render.py",
        ),
    ];
    let failures: Vec<String> = std::thread::scope(|scope| {
        let asked: Vec<_> = asks
            .iter()
            .filter_map(|(jobs, slot, name, program, script)| {
                let jobs = jobs.as_deref()?;
                Some(scope.spawn(move || ask(slot, name, program, script, jobs)))
            })
            .collect();
        asked
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    assert!(
        failures.is_empty(),
        "{case}: players could not draw it (files in {}):\n{}",
        dir.display(),
        failures.join("\n")
    );
    dir
}

/// Where [`play`] put `player`'s frame `frame`.
pub fn frame_path(dir: &Path, player: Player, frame: f64) -> PathBuf {
    dir.join(format!("{}-{frame}.png", player.name()))
}

/// Plays `lottie` (the export of `anim`) in `players` at the given frame numbers and
/// asserts that every frame matches gmotion's own rendering of `anim` at `frame / fps`,
/// `width` pixels wide. `case` names the files written under the test's temporary folder.
pub fn assert_plays_like_model(
    case: &str,
    anim: &Animation,
    lottie: &str,
    frames: &[f64],
    width: u32,
    players: &[Player],
) {
    // The model's frames are drawn while the players draw theirs.
    let (dir, models) = std::thread::scope(|scope| {
        let models = scope.spawn(|| {
            frames
                .iter()
                .map(|&f| render(&frame_svg(anim, f / anim.fps), width).expect("render the model"))
                .collect::<Vec<_>>()
        });
        let dir = play(case, lottie, frames, width, players);
        let models = models
            .join()
            .unwrap_or_else(|e| std::panic::resume_unwind(e));
        (dir, models)
    });
    let mut failures = Vec::new();
    for (&f, model) in frames.iter().zip(models) {
        save_png(&model, &dir.join(format!("model-{f}.png"))).expect("save the model frame");
        for &p in players {
            let got_path = frame_path(&dir, p, f);
            match Pixmap::load_png(&got_path) {
                Ok(got) if (got.width(), got.height()) == (model.width(), model.height()) => {
                    let off = compare(&model, &got, OFF);
                    if off > MAX_OFF {
                        failures.push(format!("{} frame {f}: {:.2}% off", p.name(), off * 100.0));
                    }
                }
                Ok(got) => failures.push(format!(
                    "{} frame {f}: {}x{} px, model {}x{}",
                    p.name(),
                    got.width(),
                    got.height(),
                    model.width(),
                    model.height()
                )),
                Err(e) => failures.push(format!("{} frame {f}: no frame ({e})", p.name())),
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{case}: players differ from the model (files in {}):\n{}",
        dir.display(),
        failures.join("\n")
    );
}

/// Chromium's drawing of the SVG document `svg` at each time (seconds), `width` px wide,
/// as `tests/conformance/smil.mjs` shoots it (the file loaded from disk, so its linked
/// files resolve), in the Chromium kept running for the whole test binary. The PNGs are
/// written beside `svg`.
pub fn chromium(svg: &Path, width: u32, times: &[f64]) -> Vec<Pixmap> {
    let prefix = svg.with_extension("chromium");
    let job = serde_json::json!([{
        "svg": svg,
        "width": width,
        "out_prefix": prefix,
        "times": times,
    }]);
    let errors = ask(
        &CHROMIUM_SMIL,
        "chromium-smil",
        "node",
        "smil.mjs",
        &job.to_string(),
    );
    assert!(errors.is_empty(), "smil.mjs: {}", errors.join("\n"));
    (0..times.len())
        .map(|i| {
            let png = PathBuf::from(format!("{}-{i}.png", prefix.display()));
            Pixmap::load_png(&png).unwrap_or_else(|e| panic!("{}: {e}", png.display()))
        })
        .collect()
}
