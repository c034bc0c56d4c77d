#!/usr/bin/env bash
# Installs what the conformance run needs, idempotently: Debian chromium, ffmpeg (the video
# tests) and fonts (Noto
# Sans, which the corpus references use), npm
# lottie-web, playwright-core, @lottiefiles/dotlottie-web and @dotlottie/dotlottie-js (into
# tests/conformance/node_modules), PyPI rlottie-python,
# thorvg-python (ctypes bindings bundling libthorvg),
# lottie-specs (the official schema), jsonschema-rs (validates it fast), lottie (python-lottie, the comparison converter),
# numpy and Pillow (pixel comparisons). Each step is skipped when already satisfied.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

# Noto Sans is the font the resvg corpus references were drawn with (its text tests).
if [ ! -x /usr/bin/chromium ] || [ ! -x /usr/bin/ffmpeg ] || ! fc-list 2>/dev/null | grep -q "Noto Sans"; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends chromium ffmpeg fonts-dejavu-core fonts-liberation fonts-noto-core fontconfig >/dev/null
fi

if [ ! -d "$here/node_modules/lottie-web" ] || [ ! -d "$here/node_modules/playwright-core" ] \
    || [ ! -d "$here/node_modules/@lottiefiles/dotlottie-web" ] || [ ! -d "$here/node_modules/@dotlottie/dotlottie-js" ]; then
    (cd "$here" && if [ -f package-lock.json ]; then npm ci --ignore-scripts --no-audit --no-fund --loglevel=error; else npm install --ignore-scripts --no-audit --no-fund --loglevel=error; fi)
fi

if ! python3 -c "import rlottie_python, thorvg_python, lottie_specs, jsonschema_rs, lottie, numpy, PIL" 2>/dev/null; then
    python3 -m pip install -q --disable-pip-version-check -r "$here/requirements.txt"
fi
# The Lottie corpus of the own-render check (lottie_own_render.py): lottie-web's test
# animations (from the npm package above) and rlottie's example animations (from the
# rlottie-python 1.3.8 source package on PyPI, pinned by its digest), both MIT, named as in
# the shared corpus (`lottie-web__X.json`, `rlottie-python__X.json`). The files stay out of
# git (see .gitignore); their sources are listed in lottie-corpus.md.
lc="$here/lottie-corpus"
if [ ! -f "$lc/.complete" ]; then
    sdist=rlottie_python-1.3.8.tar.gz
    sha=a8404bc5e8fa9b4e5c7dad2173930c11450c9a2d95091f4f6a213bc77c4d9288
    tmp="$(mktemp -d)"
    url="$(curl -fsS --max-time 60 https://pypi.org/simple/rlottie-python/ | grep -o "https://[^\"#]*/$sdist" | head -1)"
    curl -fsS --max-time 300 -o "$tmp/$sdist" "$url"
    echo "$sha  $tmp/$sdist" | sha256sum -c --quiet
    tar -xzf "$tmp/$sdist" -C "$tmp"
    rm -rf "$lc"
    python3 - "$tmp" "$here/node_modules/lottie-web/test/animations" "$lc" <<'PY'
import os, re, shutil, sys
tmp, web, out = sys.argv[1:]
os.makedirs(out)
def name(prefix, f):
    return prefix + re.sub(r"[^A-Za-z0-9_.-]", "-", f)
for f in os.listdir(web):
    if f.endswith(".json"):
        shutil.copy(os.path.join(web, f), os.path.join(out, name("lottie-web__", f)))
for root, _, files in os.walk(tmp):
    if root.replace(os.sep, "/").count("rlottie/example/resource"):
        for f in files:
            # repro_* are crash reproducers of rlottie's fuzzing, not animations.
            if f.endswith(".json") and not f.startswith("repro_"):
                shutil.copy(os.path.join(root, f), os.path.join(out, name("rlottie-python__", f)))
PY
    rm -rf "$tmp"
    touch "$lc/.complete"
fi
echo "conformance tools ready: $(/usr/bin/chromium --version 2>/dev/null | head -1)"
