//! Mutation fuzzing through the real binary (cargo-fuzz needs a nightly compiler, which
//! this project's toolchain is not): the bundled grammars, their scenes and Lottie files
//! of the corpus, mutated by a seeded generator — bytes flipped, ranges cut or repeated,
//! numbers swapped for hostile ones (`1e308`, `-1`, `0`, `NaN`, huge integers), brackets
//! inserted — and fed to `animate`, `convert` and `check`. Every run must end within a time
//! bound with status 0 or 1 (2 for usage), never a panic or a signal.
//!
//! `GMOTION_FUZZ_CASES=N` runs N cases instead of the default 96 (a longer session:
//! `GMOTION_FUZZ_CASES=3000 cargo test --profile quick --test gmotion fuzz::`);
//! `GMOTION_FUZZ_SEED=S` starts elsewhere.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use gmotion::tangle::noise::Rng;

use crate::support::{root, run_bounded};

/// How long one run may take (rejected input is rejected fast; accepted mutants are small
/// scenes with a bounded number of frames).
const BOUND: Duration = Duration::from_secs(30);

const BOLD: &[&str] = &["0.001", "1000", "37", "2", "0.5", "360", "1e6", "3.7"];

const HOSTILE: &[&str] = &[
    "1e308",
    "-1e308",
    "-1",
    "0",
    "NaN",
    "inf",
    "99999999999999999999",
    "1e-320",
    "(((((",
    "]",
    "{",
    "}",
    "\"",
    "<",
    "&amp;",
    "[all, all]",
    "-> [x, x]",
    "1x100000",
    "\u{0}",
    "\n\n",
];

/// One mutation of `text`: a few edits of the kinds above.
fn mutate(text: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut out = text.to_vec();
    for _ in 0..1 + usize::from(rng.index(4) == 0) {
        let len = out.len().max(1);
        let at = rng.index(len);
        // Mostly numbers swapped (the file stays readable and the values reach the engine
        // and the exporters), sometimes the bytes themselves.
        match [0, 1, 2, 3, 3, 3, 3, 5, 5, 4][rng.index(10)] {
            0 => {
                if let Some(b) = out.get_mut(at) {
                    *b ^= 1 << rng.index(8);
                }
            }
            1 => {
                let end = (at + 1 + rng.index(40)).min(out.len());
                out.drain(at.min(end)..end);
            }
            2 => {
                let end = (at + 1 + rng.index(200)).min(out.len());
                let piece = out[at.min(end)..end].to_vec();
                for _ in 0..1 + rng.index(3) {
                    out.splice(at..at, piece.iter().copied());
                }
            }
            3 | 5 => {
                // A number replaced by a bold or a hostile one.
                let digits: Vec<usize> = (0..out.len())
                    .filter(|&i| out[i].is_ascii_digit())
                    .collect();
                if let Some(&i) = digits.get(rng.index(digits.len())) {
                    let mut j = i;
                    while j < out.len() && (out[j].is_ascii_digit() || out[j] == b'.') {
                        j += 1;
                    }
                    let pool = if rng.index(2) == 0 { BOLD } else { HOSTILE };
                    let h = pool[rng.index(pool.len())];
                    out.splice(i..j, h.bytes());
                }
            }
            _ => {
                let h = HOSTILE[rng.index(HOSTILE.len())];
                let at = at.min(out.len());
                out.splice(at..at, h.bytes());
            }
        }
    }
    out
}

/// What one case runs on: the kind of input mutated and the files it starts from.
#[derive(Clone, Copy)]
enum Target {
    /// `animate SCENE MUTANT.gm -o out.json -o out.png`.
    Grammar,
    /// `convert MUTANT.svg -o out.png -o out.json`.
    Svg,
    /// `convert MUTANT.json -o out.png -o out.json`, then `check --shapes`.
    Lottie,
}

/// Runs `args` in `dir`, killing it past [`BOUND`]: `Some(problem)` when it crashed, hung
/// or panicked. Successful runs are counted in `accepted`.
fn run(dir: &Path, args: &[&str], accepted: &AtomicUsize) -> Option<String> {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_gmotion"));
    cmd.args(args).current_dir(dir);
    let (code, err, elapsed) = run_bounded(&mut cmd, BOUND);
    let tail: String = err.lines().rev().take(3).collect::<Vec<_>>().join(" | ");
    match code {
        _ if elapsed > BOUND => Some(format!("did not finish within {BOUND:?}")),
        None => Some(format!("killed by a signal: {tail}")),
        Some(c) if c > 2 || err.contains("panicked") => Some(format!("exit status {c}: {tail}")),
        Some(0) => {
            accepted.fetch_add(1, Ordering::Relaxed);
            None
        }
        _ => None,
    }
}

#[test]
fn mutated_inputs_never_crash_or_hang() {
    let cases: usize = std::env::var("GMOTION_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(96);
    let seed: u64 = std::env::var("GMOTION_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    let grammars = root().join("grammars");
    let examples: Vec<(PathBuf, PathBuf)> = ["toy", "abstract", "leaf", "regroup", "cube"]
        .iter()
        .map(|n| {
            (
                grammars.join(format!("{n}.gm")),
                grammars.join(format!("{n}.svg")),
            )
        })
        .collect();
    // The Lottie seeds come from the corpus `tests/conformance/install.sh` fetches, so
    // only with the `players` feature; without it their quarter of the cases mutates
    // the SVG scenes instead.
    #[cfg(feature = "players")]
    let lotties: Vec<PathBuf> = lottie_seeds();
    #[cfg(not(feature = "players"))]
    let lotties: Vec<PathBuf> = Vec::new();
    let base = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz");
    let _ = std::fs::remove_dir_all(&base);
    let failures = std::sync::Mutex::new(Vec::new());
    let next = AtomicUsize::new(0);
    let accepted = AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= cases {
                        break;
                    }
                    let mut rng = Rng::new(seed.wrapping_mul(0x1000_0000_01B3) ^ i as u64);
                    let dir = base.join(format!("case-{i}"));
                    std::fs::create_dir_all(&dir).expect("case folder");
                    let target = [
                        Target::Grammar,
                        Target::Grammar,
                        Target::Svg,
                        Target::Lottie,
                    ][i % 4];
                    let target = match target {
                        Target::Lottie if lotties.is_empty() => Target::Svg,
                        t => t,
                    };
                    let (gm, svg) = &examples[rng.index(examples.len())];
                    let problems: Vec<String> = match target {
                        Target::Grammar => {
                            let text = std::fs::read(gm).expect("example grammar");
                            std::fs::write(dir.join("g.gm"), mutate(&text, &mut rng)).unwrap();
                            let svg = svg.display().to_string();
                            let args = [
                                "animate",
                                svg.as_str(),
                                "g.gm",
                                "-o",
                                "out.json",
                                "-o",
                                "out.png",
                                "--limit",
                                "frames=400",
                            ];
                            run(&dir, &args, &accepted).into_iter().collect()
                        }
                        Target::Svg => {
                            let text = std::fs::read(svg).expect("example scene");
                            std::fs::write(dir.join("s.svg"), mutate(&text, &mut rng)).unwrap();
                            run(
                                &dir,
                                &["convert", "s.svg", "-o", "out.png", "-o", "out.json"],
                                &accepted,
                            )
                            .into_iter()
                            .collect()
                        }
                        Target::Lottie => {
                            let text = std::fs::read(&lotties[rng.index(lotties.len())])
                                .expect("corpus file");
                            std::fs::write(dir.join("a.json"), mutate(&text, &mut rng)).unwrap();
                            let a = run(
                                &dir,
                                &["convert", "a.json", "-o", "out.png", "-o", "out.json"],
                                &accepted,
                            );
                            let b = run(&dir, &["check", "--shapes", "a.json"], &accepted);
                            a.into_iter().chain(b).collect()
                        }
                    };
                    if problems.is_empty() {
                        let _ = std::fs::remove_dir_all(&dir);
                    } else {
                        failures.lock().unwrap().push(format!(
                            "{} ({}): {}",
                            dir.display(),
                            i,
                            problems.join("; ")
                        ));
                    }
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    // Mutants the binary accepts reach the engine and the exporters, not only the parsers:
    // a generator whose every mutant is refused at the first byte would test little.
    let accepted = accepted.into_inner();
    eprintln!("fuzz: {cases} cases, {accepted} runs accepted");
    assert!(
        accepted * 5 >= cases,
        "only {accepted} of {cases} mutants were accepted"
    );
    assert!(
        failures.is_empty(),
        "{} of {cases} mutants crashed or hung (inputs kept):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The Lottie seeds of [`mutated_inputs_never_crash_or_hang`]: three files of the Lottie
/// corpus.
#[cfg(feature = "players")]
fn lottie_seeds() -> Vec<PathBuf> {
    let lottie_dir = root().join("tests/conformance/lottie-corpus");
    let lotties: Vec<PathBuf> = [
        "rlottie-python__StickAndBall.json",
        "rlottie-python__3d.json",
        "lottie-web__ripple.json",
    ]
    .iter()
    .map(|n| lottie_dir.join(n))
    .filter(|p| p.is_file())
    .collect();
    assert!(
        !lotties.is_empty(),
        "run tests/conformance/install.sh for the Lottie corpus"
    );
    lotties
}
