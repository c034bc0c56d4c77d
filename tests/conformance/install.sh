#!/usr/bin/env bash
# Installs what the conformance run needs, idempotently: Debian chromium and fonts (Noto
# Sans, which the corpus references use), npm
# lottie-web and playwright-core (into tests/conformance/node_modules), PyPI rlottie-python,
# thorvg-python (ctypes bindings bundling libthorvg),
# lottie-specs (the official schema), jsonschema-rs (validates it fast), lottie (python-lottie, the comparison converter),
# numpy and Pillow (pixel comparisons). Each step is skipped when already satisfied.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

# Noto Sans is the font the resvg corpus references were drawn with (its text tests).
if [ ! -x /usr/bin/chromium ] || ! fc-list 2>/dev/null | grep -q "Noto Sans"; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends chromium fonts-dejavu-core fonts-liberation fonts-noto-core fontconfig >/dev/null
fi

if [ ! -d "$here/node_modules/lottie-web" ] || [ ! -d "$here/node_modules/playwright-core" ]; then
    (cd "$here" && if [ -f package-lock.json ]; then npm ci --no-audit --no-fund --loglevel=error; else npm install --no-audit --no-fund --loglevel=error; fi)
fi

if ! python3 -c "import rlottie_python, thorvg_python, lottie_specs, jsonschema_rs, lottie, numpy, PIL" 2>/dev/null; then
    python3 -m pip install -q --disable-pip-version-check -r "$here/requirements.txt"
fi
echo "conformance tools ready: $(/usr/bin/chromium --version 2>/dev/null | head -1)"
