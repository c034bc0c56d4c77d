#!/usr/bin/env bash
# Coverage-guided fuzzing of gmotion's six fuzz targets (fuzz/fuzz_targets/) with libFuzzer.
#
#   bash scripts/fuzz.sh [SECONDS] [TARGET ...]
#   bash scripts/fuzz.sh build          # only build the targets
#
# runs each TARGET (default: all six) for SECONDS (default 60) after seeding its corpus
# (fuzz/seed.sh) with the bundled examples, the resvg test SVGs, the Lottie corpus and every
# regression case. A crash, a timeout (10 s, or FUZZ_TIMEOUT seconds) or more than 2 GB of
# memory stops a target, writes the input to fuzz/artifacts/TARGET/ and makes this script
# fail. The timeout is wall-clock time: a long run niced beside other work wants a larger
# one (FUZZ_TIMEOUT=60), or an input that takes 0.5 s alone is reported as a hang. CI
# builds the targets beside the conformance run (`build`, on the core the players leave
# idle) and then runs each for 5 s.
#
# It builds what `cargo fuzz build --sanitizer none -O` builds (the same coverage flags, on
# the stable toolchain: gmotion has no unsafe code, so AddressSanitizer, which needs a
# nightly compiler, would add little), without needing cargo-fuzz installed;
# `cargo fuzz run --sanitizer none -O TARGET` works as well where it is.
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-60}
shift || true
build_only=0
if [ "$secs" = build ]; then
    build_only=1
fi
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(grammar svg targets lottie export studio)
triple=$(rustc -vV | sed -n 's/^host: //p')
export CARGO_TARGET_DIR=fuzz/target
export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares -Cllvm-args=-simplifycfg-branch-fold-threshold=0 \
-Cllvm-args=-sanitizer-coverage-stack-depth --cfg fuzzing -Ccodegen-units=1"
cargo build --release --manifest-path fuzz/Cargo.toml --target "$triple" \
    $(printf -- '--bin %s ' "${targets[@]}")
[ "$build_only" = 0 ] || exit 0
bash fuzz/seed.sh
status=0
for t in "${targets[@]}"; do
    mkdir -p "fuzz/artifacts/$t"
    echo "== fuzz $t for ${secs}s"
    if ! "fuzz/target/$triple/release/$t" "fuzz/corpus/$t" \
        -max_total_time="$secs" -timeout="${FUZZ_TIMEOUT:-10}" -rss_limit_mb=2048 -max_len=65536 \
        -artifact_prefix="fuzz/artifacts/$t/" -print_final_stats=1 2>"fuzz/artifacts/$t.log"; then
        status=1
        grep -E "panicked|ERROR|SUMMARY|Test unit written" "fuzz/artifacts/$t.log" | head -20
    fi
    grep -E "^stat::number_of_executed_units|^stat::average_exec_per_sec|^stat::peak_rss_mb|DONE" \
        "fuzz/artifacts/$t.log" | tr '\n' ' '
    echo
done
exit $status
