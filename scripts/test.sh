#!/usr/bin/env bash
# The whole test suite, as CI runs it: installs the players (idempotent), checks style and
# docs, runs the Rust tests of every crate and the library's examples, then plays the
# exports in lottie-web, rlottie, ThorVG and Chromium against gmotion's own renders.
#
# Everything builds with the `quick` profile (release optimisation without whole-program
# LTO): the tests need optimised code (the corpus test renders 504 files) but not the
# shipped binary's last 15 %, and one profile means every crate is compiled once.
set -euo pipefail
cd "$(dirname "$0")/.."
# A clean checkout gains nothing from incremental caches; writing them costs build time.
export CARGO_INCREMENTAL=0
# Every step reports its duration, so a slow CI run shows where its time went.
step() { local s=$SECONDS; "$@"; echo "[test.sh] $((SECONDS - s)) s: $*"; }
step bash tests/conformance/install.sh
step cargo fmt --all -- --check
# The `players` feature of each crate whose tests play exports in the real players or read
# the Lottie corpus (a plain `cargo test` leaves them out): always on here, so a player that
# is missing fails its tests instead of going unnoticed.
features=(--features gmotion-cli/players,gmotion-export-lottie/players)
step cargo clippy --profile quick --workspace --all-targets "${features[@]}" -- -D warnings
# Without it too, so that a plain `cargo test` stays free of warnings: only the crates
# the feature touches are checked again (a dozen seconds; `-p` would unify the
# dependencies' features differently and check some of them again).
step cargo clippy --profile quick --workspace --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" step cargo doc --workspace --no-deps --quiet
step cargo test --profile quick --workspace "${features[@]}"
# Every example of the library's front door builds and runs (they write into target/);
# with the same crates' features on as the tests, they reuse what the tests built.
ex_start=$SECONDS
for ex in examples/*.rs; do
    cargo run --profile quick --quiet --features gmotion-output/players,gmotion-export-lottie/players \
        --example "$(basename "$ex" .rs)"
done
echo "[test.sh] $((SECONDS - ex_start)) s: examples"
# The conformance run plays the binary the tests built: building it again with
# `-p gmotion-cli` would unify features differently and recompile half the tree.
# The fuzz targets build (one job, niced) while the conformance run plays: its players
# leave a core idle much of the time. Each target then runs for 5 s (a smoke run that
# also replays fuzz/regressions; the long runs are `bash scripts/fuzz.sh 900`).
fuzz_start=$SECONDS
CARGO_BUILD_JOBS=1 nice -n 10 bash scripts/fuzz.sh build >target/fuzz-build.log 2>&1 &
fuzz_build=$!
GMOTION=target/quick/gmotion PROFILE=quick step bash tests/conformance/run.sh
if ! wait $fuzz_build; then
    tail -n 30 target/fuzz-build.log
    exit 1
fi
echo "[test.sh] $((SECONDS - fuzz_start)) s: fuzz targets built"
step bash scripts/fuzz.sh 5
