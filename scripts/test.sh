#!/usr/bin/env bash
# The whole test suite, as CI runs it: installs the players (idempotent), checks style,
# runs the Rust tests (release build: the corpus test renders 504 files), then plays the
# exports in lottie-web, rlottie, ThorVG and Chromium against gmotion's own renders.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tests/conformance/install.sh
cargo fmt --all -- --check
cargo clippy --release --all-targets -- -D warnings
cargo test --release
bash tests/conformance/run.sh
