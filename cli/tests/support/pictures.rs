//! The player tests' common ground: running the binary on files in a folder, and (with the
//! `players` feature) judging the pictures players drew against a reference, every
//! difference named at the end.

use std::path::Path;
use std::process::Command;

use gmotion_export_raster::Pixmap;
#[cfg(feature = "players")]
use gmotion_export_raster::compare;

#[cfg(feature = "players")]
use super::players::{Player, chromium, frame_path, play};

/// A pixel is off when a premultiplied channel differs by more than this (of 255).
#[cfg(feature = "players")]
pub const OFF: u8 = 32;

/// Runs the `gmotion` binary in `dir`, asserting success, and returns its standard error.
pub fn gmotion(dir: &Path, args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_gmotion"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "gmotion {args:?} failed:\n{err}");
    err
}

/// The PNG at `path`.
pub fn load(path: &Path) -> Pixmap {
    Pixmap::load_png(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Collects the pictures that are more than `max_off` (a fraction of the pixels) off their
/// reference, so that one run reports every player and frame that differs.
#[cfg(feature = "players")]
pub struct Judge {
    max_off: f64,
    failures: Vec<String>,
}

#[cfg(feature = "players")]
impl Judge {
    /// A judge allowing `max_off` of a picture's pixels to be off.
    pub fn new(max_off: f64) -> Judge {
        Judge {
            max_off,
            failures: Vec::new(),
        }
    }

    /// Records a failure, named `what`, when `got` is not close to `want`.
    pub fn close(&mut self, what: &str, want: &Pixmap, got: &Pixmap) {
        if (want.width(), want.height()) != (got.width(), got.height()) {
            self.failures
                .push(format!("{what}: {}x{} px", got.width(), got.height()));
            return;
        }
        let off = compare(want, got, OFF);
        if off > self.max_off {
            self.failures
                .push(format!("{what}: {:.2}% off", off * 100.0));
        }
    }

    /// Fails the test when anything was recorded, pointing at the files in `dir`.
    pub fn assert_all_close(self, dir: &Path) {
        assert!(
            self.failures.is_empty(),
            "files in {}:\n{}",
            dir.display(),
            self.failures.join("\n")
        );
    }
}

/// Animates `art.svg` with `art.gm` in `dir` to Lottie, SMIL and PNG frames (`width` px
/// wide, the grammar at `fps`), plays the Lottie in `players` and the SMIL in Chromium at
/// `frames`, and judges both against gmotion's own frames, which it returns (for the
/// caller to check that something moved). `case` names the players' folder.
#[cfg(feature = "players")]
pub fn animate_and_play(
    case: &str,
    dir: &Path,
    width: u32,
    fps: f64,
    frames: &[f64],
    players: &[Player],
    judge: &mut Judge,
) -> Vec<Pixmap> {
    let w = width.to_string();
    gmotion(
        dir,
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
            &w,
        ],
    );
    let ours: Vec<Pixmap> = frames
        .iter()
        .map(|f| load(&dir.join(format!("frames/frame_{:05}.png", *f as usize))))
        .collect();
    let json = std::fs::read_to_string(dir.join("anim.json")).unwrap();
    let played = play(case, &json, frames, width, players);
    let times: Vec<f64> = frames.iter().map(|f| f / fps).collect();
    let smil = chromium(&dir.join("anim.svg"), width, &times);
    for (k, f) in frames.iter().enumerate() {
        for &p in players {
            let got = load(&frame_path(&played, p, *f));
            judge.close(&format!("{p:?} frame {f}"), &ours[k], &got);
        }
        judge.close(&format!("SMIL frame {f}"), &ours[k], &smil[k]);
    }
    ours
}
