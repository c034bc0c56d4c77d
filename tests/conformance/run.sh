#!/usr/bin/env bash
# Conformance: what gmotion exports plays the same in real players.
#
#   bash tests/conformance/run.sh                  (exit status 0 when every check passes)
#   bash tests/conformance/run.sh --matrix full    (the whole conformance matrix, ~350 cases;
#                                                   MATRIX=full does the same)
#   bash tests/conformance/run.sh --matrix-only    (skip the corpus and the example grammars)
#   bash tests/conformance/run.sh --matrix-only --only gm-0171,tr-0048
#                                                  (just those matrix cases, e.g. to re-check
#                                                   failures without replaying the whole matrix)
#   GMOTION=target/quick/gmotion bash tests/conformance/run.sh   (play that binary, no build)
#   PROFILE=quick bash tests/conformance/run.sh   (build and test with that cargo profile;
#                                                  default release)
#
# 1. installs the players (install.sh, idempotent) and builds gmotion (release);
# 2. converts the resvg corpus with `gmotion convert` and with python-lottie, and exports
#    every grammars/NAME.gm (with NAME.svg) to Lottie, dotLottie, SMIL and gmotion's own PNG
#    frames;
# 3. validates every Lottie gmotion wrote against the official schema;
# 4. plays the Lottie files in lottie-web (headless Chromium), rlottie and ThorVG, the
#    dotLottie packages in dotlottie-web (dotlottie_web.mjs, headless Chromium), the SMIL
#    files in Chromium (smil.mjs), and compares every frame (conformance.py report);
#    then plays the Lottie corpus (install.sh fetches it) with gmotion's own renderer
#    against lottie-web and rlottie (lottie_own_render.py), as it is and with a grammar
#    on top (units the layers, then the top-level groups), and draws 600 real colour
#    SVGs from npm (icons.py) with gmotion and Chromium;
# 5. the conformance matrix (matrix.py): generated scenes with grammars and transitions
#    targets spanning the language, plus every example, played in lottie-web (svg and canvas
#    renderers), rlottie, ThorVG, dotlottie-web and Chromium SMIL against gmotion's own
#    render; by default a fixed sample that covers every dimension value, with --matrix
#    full every case. Its table is written to $CONFORMANCE_OUT/matrix.md.
# Work files go to $CONFORMANCE_OUT (default target/conformance).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
corpus="${CORPUS:-$root/tests/corpus/resvg}"
out="${CONFORMANCE_OUT:-$root/target/conformance}"
matrix="${MATRIX:-sample}"
profile="${PROFILE:-release}"
main_run=1
only=()
while [ $# -gt 0 ]; do
    case "$1" in
        --matrix) matrix="${2:?--matrix takes sample or full}"; shift 2 ;;
        --matrix-only) main_run=0; shift ;;
        --only) only=(--only "${2:?--only takes case names, comma-separated}"); shift 2 ;;
        *) echo "conformance: unknown argument $1 (--matrix sample|full, --matrix-only, --only NAMES)" >&2; exit 2 ;;
    esac
done
case "$matrix" in sample|full) ;; *) echo "conformance: --matrix is sample or full, not $matrix" >&2; exit 2 ;; esac
start=$SECONDS
# Each phase header says when it began, so a slow CI run shows where its time went.
phase() { echo "== $* (at $((SECONDS - start)) s)"; }

bash "$here/install.sh"
if [ -n "${GMOTION:-}" ]; then
    gm="$(cd "$(dirname "$GMOTION")" && pwd)/$(basename "$GMOTION")"
else
    (cd "$root" && cargo build --profile "$profile" --quiet -p gmotion-cli)
    gm="${CARGO_TARGET_DIR:-$root/target}/$profile/gmotion"
fi
[ -d "$corpus" ] || { echo "conformance: corpus not found at $corpus" >&2; exit 1; }

rm -rf "$out"
mkdir -p "$out"
status=0
if [ "$main_run" = 1 ]; then
    phase "exporting (corpus with gmotion and python-lottie, example grammars)"
    python3 "$here/conformance.py" prepare "$out" "$gm" "$corpus" "$root/grammars"

    phase "schema (lottie-specs)"
    python3 "$here/schema_check.py" --list "$out/gmotion_lottie_files.txt" || status=1

    # `--workspace` and the `players` features, as scripts/test.sh builds the tests (the
    # players are installed above): the same features, so nothing is rebuilt.
    phase "in-process conversion time (exporters/lottie/tests/lottie.rs)"
    (cd "$root" && cargo test --profile "$profile" --quiet --workspace \
        --features gmotion-cli/players,gmotion-export-lottie/players \
        --test export_lottie lottie::corpus_converts_in_process -- --nocapture 2>&1) \
        | grep "lottie corpus conversion" > "$out/in_process.txt" || status=1

    # rlottie and ThorVG play beside lottie-web: Chromium leaves a core idle much of the
    # time, and the three write separate frames.
    phase "playing: lottie-web, with rlottie and ThorVG beside it"
    python3 "$here/rlottie_render.py" "$out/rlottie_jobs.json" &
    rl=$!
    python3 "$here/thorvg_render.py" "$out/thorvg_jobs.json" &
    tv=$!
    node "$here/lottie_web.mjs" "$out/lottie_web_jobs.json"
    wait $rl || true
    wait $tv || true
    # dotlottie-web (the examples' .lottie packages, one page) beside Chromium's SMIL, which
    # spends minutes on intersections' few frames with a core to spare.
    phase "playing: SMIL in Chromium, with dotlottie-web beside it"
    node "$here/dotlottie_web.mjs" "$out/dotlottie_web_jobs.json" >/dev/null &
    dl=$!
    if [ -f "$here/smil.mjs" ]; then
        node "$here/smil.mjs" --jobs "$out/smil_jobs.json" >/dev/null
        touch "$out/smil.ran"
    fi
    wait $dl || true

python3 "$here/conformance.py" report "$out" || status=1

    # The three passes run together: each waits on its players much of the time.
    phase "Lottie own render (gmotion convert X.json -o f.png --time T) and with a grammar on top (the layered export; units the layers, then the top-level groups), against lottie-web and rlottie (ThorVG for files with text)"
    python3 "$here/lottie_own_render.py" "$gm" "$out/own_render" "$here/lottie-corpus" > "$out/own_render.txt" &
    own=$!
    python3 "$here/lottie_own_render.py" "$gm" "$out/own_render_grammar" "$here/lottie-corpus" --grammar > "$out/own_render_grammar.txt" &
    own_grammar=$!
    python3 "$here/lottie_own_render.py" "$gm" "$out/own_render_groups" "$here/lottie-corpus" --grammar --groups > "$out/own_render_groups.txt" &
    own_groups=$!
    wait $own || status=1
    wait $own_grammar || status=1
    wait $own_groups || status=1
    tail -n 3 "$out/own_render.txt"
    tail -n 3 "$out/own_render_grammar.txt"
    tail -n 3 "$out/own_render_groups.txt"
    phase "600 real colour SVGs (Fluent, Noto, Twemoji, Tabler) against Chromium (icons.py)"
    python3 "$here/icons.py" "$gm" "$out/icons" > "$out/icons.txt" || status=1
    grep -E "^(set|all) |fails|below" "$out/icons.txt" || true
fi

m="$out/matrix"
mstart=$SECONDS
phase "matrix ($matrix): checking the generator, exporting, rendering gmotion's reference frames"
python3 "$here/matrix.py" selftest || status=1
python3 "$here/matrix.py" prepare "$m" "$gm" --matrix "$matrix" "${only[@]}"
phase "matrix: lottie-web (svg and canvas renderers), with rlottie and ThorVG beside it"
crashed() { echo "matrix: $1 exited with an error; its missing frames fail below"; }
(python3 "$here/rlottie_render.py" "$m/rlottie_jobs.json" || crashed rlottie) &
rl=$!
(python3 "$here/thorvg_render.py" "$m/thorvg_jobs.json" || crashed ThorVG) &
tv=$!
node "$here/lottie_web.mjs" "$m/lottie_web_jobs.json" || crashed lottie-web
wait $rl
wait $tv
# dotlottie-web (one browser, one page, every case's .lottie in turn) beside Chromium's SMIL,
# which loads a document for every frame and leaves a core idle much of the time.
phase "matrix: SMIL in Chromium, with dotlottie-web beside it"
(dl_start=$SECONDS
 node "$here/dotlottie_web.mjs" "$m/dotlottie_web_jobs.json" >/dev/null || crashed dotlottie-web
 echo "matrix: dotlottie-web took $((SECONDS - dl_start)) s") &
dl=$!
node "$here/smil.mjs" --jobs "$m/smil_jobs.json" >/dev/null || crashed "Chromium (SMIL)"
wait $dl
python3 "$here/matrix.py" report "$m" || status=1
cp "$m/matrix.md" "$out/matrix.md"
echo "matrix: $((SECONDS - mstart)) s"
phase "studio: the page in Chromium (tests/conformance/studio.mjs)"
node "$here/studio.mjs" "$gm" || status=1
phase "preview: the page animate -o preview.html writes (tests/conformance/preview.mjs)"
node "$here/preview.mjs" "$gm" || status=1
phase "studio: the editor in Chromium (tests/conformance/studio_editor.mjs)"
node "$here/studio_editor.mjs" "$gm" || status=1
phase "studio: the toy grammar recreated with the mouse and the form (tests/conformance/studio_toy.mjs)"
node "$here/studio_toy.mjs" "$gm" || status=1
phase "studio: the code editor and layer tree (tests/conformance/studio_code.mjs)"
node "$here/studio_code.mjs" "$gm" || status=1
phase "studio: started from an After Effects file by learn (tests/conformance/studio_learn.mjs)"
node "$here/studio_learn.mjs" "$gm" || status=1
echo "conformance: $((SECONDS - start)) s"
exit $status
