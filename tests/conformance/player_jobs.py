"""The job loop both Python players share (rlottie_render.py, thorvg_render.py).

    python3 PLAYER.py JOBS.json   plays the jobs of one file and exits;
    python3 PLAYER.py --each JOBS.json
                                  the same, each job in a process of its own, so that a
                                  player crashing on one file (ThorVG's SIGFPE on some
                                  text) loses only that file's frames;
    python3 PLAYER.py --serve     reads one JSON job list per line on stdin, plays it, and
                                  answers one line {"errors": [...]} on stdout; it exits at
                                  the end of stdin. The Rust tests keep one such player
                                  running for the whole test binary, so that each test does
                                  not pay the player's start-up (testkit/src/players.rs).

A job list is what lottie_web.mjs reads:
[{"json": "a.json", "width": 300, "frames": [0, 5], "out": ["a-0.png", "a-5.png"]}, ...].
A job that fails is reported (stderr, or the answer's errors) and its PNGs are not written.
"""

import json
import os
import subprocess
import sys
import tempfile

from PIL import Image


def save_premultiplied(data, width, height, order, out):
    """Writes the premultiplied pixels `data` (bytes in `order`: "BGRa" for rlottie, "RGBa"
    for ThorVG's ABGR8888) to the PNG `out` with straight alpha, as PNG wants. Pillow
    unpremultiplies in C (within one level of exact rounding) and zlib's fastest level
    loses nothing: a frame costs a fifth of unpremultiplying in floats and compressing
    hard, which was most of a test's wait for these players."""
    img = Image.frombuffer("RGBa", (width, height), bytes(data), "raw", order, 0, 1)
    img.convert("RGBA").save(out, compress_level=1)


def play_all(name, render, jobs):
    """Plays every job with `render(job)`; returns the failures as messages."""
    errors = []
    for job in jobs:
        try:
            render(job)
        except Exception as e:  # noqa: BLE001 - any player failure is reported per file
            errors.append(f"{name}: {job.get('json')}: {e}")
    return errors


def main(name, render, argv):
    """The command line of a player script: a jobs file, or --serve."""
    if len(argv) == 2 and argv[1] == "--serve":
        for line in sys.stdin:
            if line.strip():
                errors = play_all(name, render, json.loads(line))
                print(json.dumps({"errors": errors}), flush=True)
        return 0
    if len(argv) == 3 and argv[1] == "--each":
        with open(argv[2], encoding="utf-8") as f:
            jobs = json.load(f)
        for job in jobs:
            with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as one:
                json.dump([job], one)
            r = subprocess.run([sys.executable, argv[0], one.name], check=False)
            os.unlink(one.name)
            if r.returncode != 0:
                print(f"{name}: {job.get('json')}: the player exited with {r.returncode}", file=sys.stderr)
        return 0
    if len(argv) != 2:
        print(f"usage: {argv[0]} JOBS.json | --each JOBS.json | --serve", file=sys.stderr)
        return 2
    with open(argv[1], encoding="utf-8") as f:
        jobs = json.load(f)
    for e in play_all(name, render, jobs):
        print(e, file=sys.stderr)
    return 0
