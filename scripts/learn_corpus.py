#!/usr/bin/env python3
"""`gmotion learn` over a folder of Lottie files (docs/learn.md, "After Effects files").

For each file: learn it, animate the learned grammar back to Lottie, draw both with
gmotion's own renderer at ten frames spread over the composition and count a file as
reproduced when no frame has more than 1 % of its pixels off (a channel past 32 of 255).
Also prints the grammar's size against the keyframe data it replaces (the JSON text of
every animated property of the file).

Usage: scripts/learn_corpus.py GMOTION OUT_DIR FILE.json…   (needs Pillow and NumPy)
"""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
from PIL import Image


def keyframe_bytes(node):
    """Bytes of JSON text of the animated properties (`"a": 1`) under `node`."""
    if isinstance(node, dict):
        if node.get("a") == 1 and "k" in node:
            return len(json.dumps(node["k"], separators=(",", ":")))
        return sum(keyframe_bytes(v) for v in node.values())
    if isinstance(node, list):
        return sum(keyframe_bytes(v) for v in node)
    return 0


def off(a, b):
    x = np.array(Image.open(a).convert("RGBA")).astype(int)
    y = np.array(Image.open(b).convert("RGBA")).astype(int)
    if x.shape != y.shape:
        return 1.0
    return float((np.abs(x - y).max(axis=2) > 32).mean())


def main():
    gm, out = sys.argv[1], Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    done = good = 0
    for f in sys.argv[3:]:
        name = Path(f).stem
        doc = json.loads(Path(f).read_text())
        grammar = out / f"{name}.gm"
        r = subprocess.run([gm, "learn", f, "-o", str(grammar)], capture_output=True, text=True)
        if r.returncode != 0:
            print(f"{name} | refused: {r.stderr.strip().splitlines()[-1][:120]}")
            continue
        back = out / f"{name}.back.json"
        r = subprocess.run([gm, "animate", str(grammar), "-o", str(back)], capture_output=True, text=True)
        if r.returncode != 0:
            print(f"{name} | learned grammar fails: {r.stderr.strip()[:120]}")
            continue
        done += 1
        ip, op, fr = doc["ip"], doc["op"], doc["fr"]
        worst = 0.0
        for k in range(10):
            t = round((op - 1 - ip) * k / 9) / fr
            a, b = out / "a.png", out / "b.png"
            subprocess.run([gm, "convert", f, "--time", str(t), "-o", str(a)], capture_output=True)
            subprocess.run([gm, "convert", str(back), "--time", str(t), "-o", str(b)], capture_output=True)
            worst = max(worst, off(a, b))
        good += worst <= 0.01
        rules = sum(1 for l in grammar.read_text().splitlines() if l.startswith(("timesplit", "animate")))
        unexplained = r.stdout.count("NOT EXPLAINED")
        print(f"{name} | {rules} rules | grammar {grammar.stat().st_size} B, keyframes {keyframe_bytes(doc)} B | worst {worst * 100:.2f}%")
    print(f"reproduced within 1%: {good} of {done} learned ({len(sys.argv) - 3} files)")


main()
