#!/usr/bin/env bash
# The whole test suite, as CI runs it: installs the players (idempotent), checks style,
# runs the Rust tests of every crate (release build: the corpus test renders 504 files),
# the library examples, then plays the exports in lottie-web, rlottie, ThorVG and Chromium
# against gmotion's own renders.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tests/conformance/install.sh
cargo fmt --all -- --check
cargo clippy --release --workspace --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet
cargo test --release --workspace
# Every example of the library's front door builds and runs (they write into target/).
for ex in examples/*.rs; do
    cargo run --release --quiet --example "$(basename "$ex" .rs)"
done
bash tests/conformance/run.sh
