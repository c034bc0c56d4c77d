#!/usr/bin/env python3
"""`gmotion learn` over a folder of Lottie files (docs/learn.md, "After Effects files").

For each file: learn it, animate the learned grammar back to Lottie, draw both at ten
frames spread over the composition and count a file as reproduced when no frame has more
than 1 % of its pixels off (a channel past 32 of 255). Also prints the grammar's size
against the keyframe data it replaces (the JSON text of every animated property of the
file), and whether the file's motion is only what issue 45's corpus measure covers:
transforms (of layers and of shape groups), opacity and colour, keyframed (no
expressions, effects, masks or time remapping).

The frames are drawn by lottie-web (`--player lottie-web`, the default: svg renderer, in
headless Chromium through tests/conformance/lottie_web.mjs, whose node_modules must be
installed) or by gmotion's own renderer (`--player own`, to debug).

Usage: scripts/learn_corpus.py [--player lottie-web|own] GMOTION OUT_DIR FILE.json…
(needs Pillow and NumPy)
"""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
from PIL import Image

HERE = Path(__file__).resolve().parent
LOTTIE_WEB = HERE.parent / "tests" / "conformance" / "lottie_web.mjs"

# The properties whose animation the corpus measure covers, by the key that holds them
# (`ks` is also a path's key under `sh`, told apart by its parent's `ty`).
TRANSFORM_KEYS = {"a", "p", "s", "r", "o", "sk", "sa", "px", "py", "pz", "rx", "ry", "rz", "or"}


def keyframe_bytes(node):
    """Bytes of JSON text of the animated properties (`"a": 1`) under `node`."""
    if isinstance(node, dict):
        if node.get("a") == 1 and "k" in node:
            return len(json.dumps(node["k"], separators=(",", ":")))
        return sum(keyframe_bytes(v) for v in node.values())
    if isinstance(node, list):
        return sum(keyframe_bytes(v) for v in node)
    return 0


def uncovered(node, key=None):
    """Names of the animated properties that are not transforms, opacity or colour (and
    of the expressions, effects, masks and time remapping, which learn does not model)."""
    found = []
    if isinstance(node, list):
        for v in node:
            found += uncovered(v, key)
        return found
    if not isinstance(node, dict):
        return found
    kind = node.get("ty")
    if isinstance(kind, int) and (node.get("ef") or node.get("masksProperties") or "tm" in node):
        found.append(f"layer {node.get('nm', '')!r}: effects, masks or time remapping")
    # A layer's `ks` and a shape group's `tr` are transforms; a split position's x and y too.
    transform = (key == "ks" and "ty" not in node) or kind == "tr" or (key == "p" and node.get("s") is True)
    for k, v in node.items():
        if isinstance(v, dict) and "k" in v and isinstance(v.get("x"), str):
            # lottie-web runs expressions; learn samples the keyframes under them.
            found.append(f"{kind if kind is not None else key}.{k}: expression")
        if isinstance(v, dict) and v.get("a") == 1 and "k" in v:
            covered = (transform and k in TRANSFORM_KEYS | {"x", "y", "z"}) or (
                kind in ("fl", "st") and k in ("c", "o")
            )
            if not covered:
                found.append(f"{kind if kind is not None else key}.{k}")
        else:
            found += uncovered(v, k)
    return found


def off(a, b):
    x = np.array(Image.open(a).convert("RGBA")).astype(int)
    y = np.array(Image.open(b).convert("RGBA")).astype(int)
    if x.shape != y.shape:
        return 1.0
    return float((np.abs(x - y).max(axis=2) > 32).mean())


def frames_of(doc):
    """Ten frames spread over the composition, counted from its first frame."""
    ip, op = doc["ip"], doc["op"]
    return [round((op - 1 - ip) * k / 9) for k in range(10)]


def draw_own(gm, pairs, out):
    """Draws each (original, learned) pair with gmotion's renderer; yields the PNG pairs."""
    for orig, back, doc in pairs:
        shots = []
        for k, f in enumerate(frames_of(doc)):
            t = f / doc["fr"]
            a, b = out / f"{orig.stem}-{k}.a.png", out / f"{orig.stem}-{k}.b.png"
            subprocess.run([gm, "convert", str(orig), "--time", str(t), "-o", str(a)], capture_output=True)
            subprocess.run([gm, "convert", str(back), "--time", str(t), "-o", str(b)], capture_output=True)
            shots.append((a, b))
        yield shots


def draw_lottie_web(pairs, out):
    """Draws every pair in one lottie-web run (svg renderer); yields the PNG pairs."""
    jobs, shots = [], []
    for orig, back, doc in pairs:
        back_doc = json.loads(back.read_text())
        width = int(min(512, max(1, round(doc["w"]))))
        frames = frames_of(doc)
        # The learned file counts frames from 0 at its own rate.
        back_frames = [f / doc["fr"] * back_doc["fr"] for f in frames]
        a = [str(out / f"{orig.stem}-{k}.a.png") for k in range(10)]
        b = [str(out / f"{orig.stem}-{k}.b.png") for k in range(10)]
        jobs.append({"json": str(orig), "width": width, "frames": frames, "out": a})
        jobs.append({"json": str(back), "width": width, "frames": back_frames, "out": b})
        shots.append(list(zip(a, b)))
    listing = out / "jobs.json"
    listing.write_text(json.dumps(jobs))
    r = subprocess.run(["node", str(LOTTIE_WEB), str(listing)], capture_output=True, text=True)
    if r.stderr.strip():
        print(r.stderr.strip(), file=sys.stderr)
    yield from shots


def main():
    args = sys.argv[1:]
    player = "lottie-web"
    if args[:1] == ["--player"]:
        player, args = args[1], args[2:]
    if player not in ("lottie-web", "own"):
        sys.exit(f"unknown player {player!r} (lottie-web or own)")
    gm, out, files = args[0], Path(args[1]).resolve(), args[2:]
    out.mkdir(parents=True, exist_ok=True)
    learned = []  # (original, learned animation, document, grammar, report, covered)
    for f in files:
        orig = Path(f).resolve()
        doc = json.loads(orig.read_text())
        grammar = out / f"{orig.stem}.gm"
        r = subprocess.run([gm, "learn", str(orig), "-o", str(grammar)], capture_output=True, text=True)
        if r.returncode != 0:
            print(f"{orig.stem} | refused: {r.stderr.strip().splitlines()[-1][:120]}")
            continue
        back = out / f"{orig.stem}.back.json"
        a = subprocess.run([gm, "animate", str(grammar), "-o", str(back)], capture_output=True, text=True)
        if a.returncode != 0:
            print(f"{orig.stem} | learned grammar fails: {a.stderr.strip()[:120]}")
            continue
        learned.append((orig, back, doc, grammar, r.stdout, not uncovered(doc)))
    pairs = [(o, b, d) for o, b, d, *_ in learned]
    drawn = draw_lottie_web(pairs, out) if player == "lottie-web" else draw_own(gm, pairs, out)
    good = covered = covered_good = 0
    for (orig, _, doc, grammar, report, cov), shots in zip(learned, drawn):
        worst = max((off(a, b) if Path(a).exists() and Path(b).exists() else 1.0) for a, b in shots)
        ok = worst <= 0.01
        good += ok
        covered += cov
        covered_good += cov and ok
        rules = sum(1 for l in grammar.read_text().splitlines() if l.startswith(("timesplit", "animate")))
        print(
            f"{orig.stem} | {'covered' if cov else 'other'} | {rules} rules | grammar "
            f"{grammar.stat().st_size} B, keyframes {keyframe_bytes(doc)} B | worst {worst * 100:.2f}%"
            f" | {report.count('NOT EXPLAINED')} not explained"
        )
    print(f"player: {player}")
    print(f"reproduced within 1%: {good} of {len(learned)} learned ({len(files)} files)")
    print(f"covered (transforms, opacity, colour only): {covered_good} of {covered} reproduced")


main()
