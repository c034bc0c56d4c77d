#!/usr/bin/env bash
# Conformance: what gmotion exports plays the same in real players.
#
#   bash tests/conformance/run.sh        (exit status 0 when every check passes)
#
# 1. installs the players (install.sh, idempotent) and builds gmotion (release);
# 2. converts the resvg corpus with `gmotion convert` and with python-lottie, and exports
#    every grammars/NAME.gm (with NAME.svg) to Lottie, SMIL and gmotion's own PNG frames;
# 3. validates every Lottie gmotion wrote against the official schema;
# 4. plays the Lottie files in lottie-web (headless Chromium), rlottie and ThorVG, the SMIL
#    files in Chromium (smil.mjs), and compares every frame (conformance.py report).
# Work files go to $CONFORMANCE_OUT (default target/conformance).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
corpus="${CORPUS:-$root/tests/corpus/resvg}"
out="${CONFORMANCE_OUT:-$root/target/conformance}"
start=$SECONDS

bash "$here/install.sh"
(cd "$root" && cargo build --release --quiet)
gm="${CARGO_TARGET_DIR:-$root/target}/release/gmotion"
[ -d "$corpus" ] || { echo "conformance: corpus not found at $corpus" >&2; exit 1; }

rm -rf "$out"
mkdir -p "$out"
echo "== exporting (corpus with gmotion and python-lottie, example grammars)"
python3 "$here/conformance.py" prepare "$out" "$gm" "$corpus" "$root/grammars"

status=0
echo "== schema (lottie-specs)"
python3 "$here/schema_check.py" --list "$out/gmotion_lottie_files.txt" || status=1

echo "== in-process conversion time (tests/lottie.rs)"
(cd "$root" && cargo test --release --quiet --test lottie corpus_converts_in_process -- --nocapture 2>&1) \
    | grep "lottie corpus conversion" > "$out/in_process.txt" || status=1

echo "== playing: lottie-web"
node "$here/lottie_web.mjs" "$out/lottie_web_jobs.json"
echo "== playing: rlottie"
python3 "$here/rlottie_render.py" "$out/rlottie_jobs.json"
echo "== playing: ThorVG"
python3 "$here/thorvg_render.py" "$out/thorvg_jobs.json"
if [ -f "$here/smil.mjs" ]; then
    echo "== playing: SMIL in Chromium"
    node "$here/smil.mjs" --jobs "$out/smil_jobs.json" >/dev/null
    touch "$out/smil.ran"
fi

python3 "$here/conformance.py" report "$out" || status=1
echo "conformance: $((SECONDS - start)) s"
exit $status
