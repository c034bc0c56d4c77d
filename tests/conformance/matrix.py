"""The conformance matrix: generated cases that span the language, played in every player.

    python3 matrix.py list [--matrix sample|full]
        prints the cases (name and dimension values) without running anything.
    python3 matrix.py selftest
        checks the generator: coverage of every value and pair, determinism, and slice
        boundaries worked out by hand from docs/grammar.md.
    python3 matrix.py prepare OUT GMOTION [--matrix sample|full] [--only NAME,...]
        writes every case (scene, grammar or targets file) under OUT/cases/NAME/, exports it
        with gmotion to Lottie (.json), dotLottie (.lottie) and SMIL (.svg), renders gmotion's
        own reference frames (resvg, `--time`) and its frames of the Lottie as written
        (`convert --time`), validates the Lottie against the schema and writes the players'
        job lists (OUT/lottie_web_jobs.json with both renderers, rlottie_jobs.json,
        thorvg_jobs.json, dotlottie_web_jobs.json, smil_jobs.json).
    python3 matrix.py report OUT
        compares every player frame with its reference (conformance.off: a frame passes
        with at most 0.5% of its pixels off by more than 32/255; a Lottie player's pixel is
        off only where it is off both gmotion's frame and gmotion's render of the Lottie as
        written, see WRITTEN), writes
        OUT/matrix.md (per player: cases passed; per dimension value: the failures) and
        exits 1 on any failure.

Why Python, not a Rust example: the players' harness (job lists, off_fraction, the schema
check) is Python already, so the matrix reuses it directly and needs no build; the cases
are text (SVG + grammar / targets), which a generator in any language writes the same way.

Cases. Three families:
  gm-NNNN   a generated scene (200x150, 2-6 shapes with fills and strokes) and a timeslice
            grammar; dimensions GM_DIMS (operator and animate type, local/world, easing,
            lookup and grid, interp, offset, inverted twin placement, nesting, a second
            animation on the same slice, inherited motion, spatial rules feeding the
            timeslice rules, smoothing, loop, timing, scene);
  tr-NNNN   a generated scene and a `gmotion transitions` targets file; dimensions TR_DIMS
            (system kind, attribute, where the system is given, format, anchor, ...);
  ex-NAME   every grammars/NAME.gm with its scene, and every grammars/NAME.targets.json.
The generated cases follow a covering design (greedy, AETG-like, seeded): every value of
every dimension appears, and every pair of values of the "pair" dimensions appears in some
case, far fewer cases than the full product. The sample (CI) is a greedy cover of every
dimension value of both families, grown to SAMPLE_GENERATED cases by pairs, plus every
example. Everything is deterministic: the same code writes the same cases.

Frames. At least 12 per case: every slice boundary (computed from the grammar's fractions by
a small simulation of `timesplit`/`animate`, including where a delayed change starts) as
the frame at or just before it and the frame just after it, the first and last frame, and
evenly spaced frames to fill up.
"""

import concurrent.futures
import json
import math
import os
import random
import re
import subprocess
import sys
import zipfile

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

from conformance import OFF, off, off_mask, rgba  # noqa: E402  (same rule and comparison as the example grammars)

MAX_OFF = 0.005
MIN_FRAMES = 12
MAX_FRAMES = 24
W, H = 200, 150
SCALE = 2
GM_CASES = 230
TR_CASES = 140
SAMPLE_GENERATED = 36
# Examples in the sample: the grammar examples are played by the main run (conformance.py)
# in every player but lottie-web's canvas renderer; the transitions examples only here.
SAMPLE_EXAMPLES = {"ex-toy", "ex-histogram", "ex-permutation", "ex-revisions"}
SEED = 20261202
PLAYERS = ["lottie-web-svg", "lottie-web-canvas", "rlottie", "thorvg", "dotlottie-web", "chromium-smil"]
CHECKS = ["export", "schema"] + PLAYERS


class Dim:
    """One dimension of the design: its values, whether its pairs with other pair
    dimensions must be covered, and the weights used when a value is free to choose (a
    heavier default keeps most cases plain, e.g. no smoothing)."""

    def __init__(self, name, values, pair=True, weights=None):
        self.name, self.values, self.pair = name, values, pair
        self.weights = weights or [1] * len(values)


GM_DIMS = [
    Dim("type", ["translate", "rotate", "scale", "skew", "matrix", "product", "about",
                 "towards", "path", "fill", "border", "opacity", "stroke-width",
                 "keyed", "keyed-towards", "trim", "follow", "follow-orient",
                 "morph"]),
    Dim("ref", ["local", "world"]),
    Dim("ease", ["linear", "ease", "ease-in", "ease-out", "ease-in-out", "cubic",
                 "bspline", "poles", "poles-tau", "steps", "hold"]),
    Dim("lookup", ["nearest", "bilinear", "exact", "vertex"]),
    Dim("grid", ["1x1", "3x2", "4x4"]),
    Dim("interp", ["linear", "alexa"]),
    Dim("offset", ["zero", "inside", "stagger", "near-limit"]),
    Dim("inverted", ["none", "after", "before", "after-hold", "before-hold"]),
    Dim("nesting", ["1", "2", "3", "2-twin"]),
    Dim("second", ["none", "fill", "opacity", "stroke-width", "border", "local-rotate", "world-translate"]),
    Dim("inherit", ["none", "motion", "colour"]),
    Dim("scene", ["rects", "circles", "paths", "group", "strokes", "mixed", "filtered"]),
    Dim("spatial", ["none", "regularSplit", "dual-split", "outline", "regroup", "ungroup", "fill",
                    "invert", "perturb", "streamline", "place", "stipple", "letters", "words", "lines"],
        pair=False, weights=[24] + [1] * 14),
    Dim("smoothing", ["none", "spring", "msd", "fir", "lowpass", "spline", "series", "simple",
                      "parallel", "tustin"], pair=False, weights=[18] + [1] * 9),
    Dim("where", ["header", "rule"], pair=False),
    Dim("loop", ["true", "false"], pair=False, weights=[4, 1]),
    Dim("timing", ["2s@30", "2.4s@25", "1.5s@24"], pair=False),
]

TR_DIMS = [
    Dim("system", ["none", "simple", "spline", "fir", "arc", "spring", "msd", "lowpass", "zoh",
                   "impulse", "tustin", "matched", "series", "parallel"]),
    Dim("attr", ["x", "y", "dx", "dy", "scale", "sx-sy", "zx-zy", "rotate", "opacity", "fill"]),
    Dim("via", ["cli", "file", "channel", "tag-channel"]),
    Dim("format", ["json", "csv"]),
    Dim("retarget", ["once", "mid-flight"]),
    Dim("anchor", ["centre", "bottom"], pair=False),
    Dim("fps", ["file", "cli"], pair=False),
    Dim("scene", ["rects", "circles", "paths", "mixed"], pair=False),
]


# ---- covering design -------------------------------------------------------------------

def cover(dims, count, seed):
    """`count` cases (dicts dimension -> value) such that every value of every dimension
    and, as early as possible, every pair of values of two pair dimensions appears.

    Each new case starts from an uncovered pair (or single value), then fills the other
    dimensions one at a time, in a random order, with the value that covers the most new
    pairs with those already chosen (ties by weight, then at random); of a few such
    candidates the best is kept."""
    rng = random.Random(seed)
    pair_idx = [i for i, d in enumerate(dims) if d.pair]
    todo_pairs = {(i, a, j, b) for x, i in enumerate(pair_idx) for j in pair_idx[x + 1:]
                  for a in dims[i].values for b in dims[j].values}
    todo_single = {(i, a) for i, d in enumerate(dims) for a in d.values}
    cases = []

    def gain(case):
        g = 0
        for x, i in enumerate(pair_idx):
            for j in pair_idx[x + 1:]:
                g += (i, case[i], j, case[j]) in todo_pairs
        return g + 3 * sum((i, case[i]) in todo_single for i in range(len(dims)))

    for _ in range(count):
        best, best_gain = None, -1
        for _ in range(6):
            case = [None] * len(dims)
            if todo_pairs:
                i, a, j, b = rng.choice(sorted(todo_pairs))
                case[i], case[j] = a, b
            elif todo_single:
                i, a = rng.choice(sorted(todo_single))
                case[i] = a
            order = [k for k in range(len(dims)) if case[k] is None]
            rng.shuffle(order)
            for k in order:
                d = dims[k]
                single = [v for v in d.values if (k, v) in todo_single]
                if not d.pair:
                    # Free dimensions: an uncovered value first, else by weight.
                    case[k] = single[0] if single and rng.random() < 0.5 else rng.choices(d.values, d.weights)[0]
                    continue

                def score(v):
                    s = sum((min(k, m), v if k < m else case[m], max(k, m), case[m] if k < m else v) in todo_pairs
                            for m in pair_idx if m != k and case[m] is not None)
                    return (s + 3 * ((k, v) in todo_single), rng.random())
                case[k] = max(d.values, key=score)
            g = gain(case)
            if g > best_gain:
                best, best_gain = case, g
        for x, i in enumerate(pair_idx):
            for j in pair_idx[x + 1:]:
                todo_pairs.discard((i, best[i], j, best[j]))
        for i in range(len(dims)):
            todo_single.discard((i, best[i]))
        cases.append({d.name: v for d, v in zip(dims, best)})
    if todo_single:
        raise SystemExit(f"matrix: {len(todo_single)} dimension values never used; raise the case count")
    return cases, len(todo_pairs)


# ---- scenes ------------------------------------------------------------------------------

SCENES = {
    "rects": [
        '<rect data-tag="s" x="30" y="40" width="40" height="30" fill="#e4572e" stroke="#1d3557" stroke-width="2"/>',
        '<rect data-tag="s" x="110" y="80" width="36" height="36" fill="#17bebb" stroke="#1d3557" stroke-width="2"/>',
        '<rect data-tag="c" x="150" y="20" width="30" height="20" fill="#ffc914" stroke="#2e282a" stroke-width="1.5"/>',
    ],
    "circles": [
        '<circle data-tag="s" cx="50" cy="50" r="18" fill="#e4572e" stroke="#1d3557" stroke-width="2"/>',
        '<circle data-tag="s" cx="100" cy="90" r="14" fill="#76b041" stroke="#1d3557" stroke-width="2"/>',
        '<circle data-tag="s" cx="150" cy="60" r="16" fill="#17bebb" stroke="#1d3557" stroke-width="2"/>',
        '<ellipse data-tag="c" cx="100" cy="125" rx="40" ry="12" fill="#ffc914" stroke="#2e282a" stroke-width="1.5"/>',
    ],
    "paths": [
        '<path data-tag="s" d="M 50 20 L 59 42 L 82 42 L 64 56 L 71 78 L 50 65 L 29 78 L 36 56 L 18 42 L 41 42 Z" fill="#e4572e" stroke="#1d3557" stroke-width="2"/>',
        '<path data-tag="s" d="M 110 100 C 110 70 160 70 160 100 L 135 125 Z" fill="#17bebb" stroke="#1d3557" stroke-width="2"/>',
        '<path data-tag="c" d="M 120 30 L 140 50 L 160 30 L 180 50" fill="none" stroke="#2e282a" stroke-width="3"/>',
    ],
    "group": [
        '<g data-tag="s"><rect x="30" y="40" width="36" height="36" fill="#e4572e" stroke="#1d3557" stroke-width="2"/>'
        '<circle cx="48" cy="58" r="10" fill="#ffc914"/></g>',
        '<g data-tag="s"><path d="M 110 70 L 150 70 L 130 110 Z" fill="#17bebb" stroke="#1d3557" stroke-width="2"/>'
        '<rect x="124" y="76" width="12" height="12" fill="#2e282a"/></g>',
        '<circle data-tag="c" cx="165" cy="120" r="12" fill="#76b041" stroke="#2e282a" stroke-width="1.5"/>',
    ],
    "strokes": [
        '<rect data-tag="s" x="30" y="40" width="50" height="40" fill="none" stroke="#e4572e" stroke-width="4"/>',
        '<circle data-tag="s" cx="130" cy="80" r="22" fill="none" stroke="#17bebb" stroke-width="4"/>',
        '<line data-tag="c" x1="20" y1="130" x2="180" y2="120" stroke="#2e282a" stroke-width="3"/>',
    ],
    "mixed": [
        '<rect data-tag="s" x="20" y="20" width="30" height="30" fill="#e4572e" stroke="#1d3557" stroke-width="2"/>',
        '<circle data-tag="s" cx="90" cy="40" r="16" fill="#17bebb" stroke="#1d3557" stroke-width="2"/>',
        '<ellipse data-tag="s" cx="150" cy="40" rx="22" ry="12" fill="#76b041" stroke="#1d3557" stroke-width="2"/>',
        '<path data-tag="s" d="M 40 90 L 80 90 L 60 125 Z" fill="#ffc914" stroke="#1d3557" stroke-width="2"/>',
        '<rect data-tag="c" x="110" y="90" width="60" height="14" rx="4" fill="#6a4c93" stroke="#2e282a" stroke-width="1.5"/>',
        '<circle data-tag="c" cx="140" cy="125" r="8" fill="#d1495b"/>',
    ],
    # Blurs and drop shadows, as hand-written SVG and Figma write them: Lottie effects.
    "filtered": [
        '<defs><filter id="shadow" x="-50%" y="-50%" width="200%" height="200%">'
        '<feDropShadow dx="3" dy="4" stdDeviation="2" flood-color="#1d3557" flood-opacity="0.5"/></filter>'
        '<filter id="soft" x="-50%" y="-50%" width="200%" height="200%"><feGaussianBlur stdDeviation="3"/></filter>'
        '<filter id="figma" x="90" y="60" width="80" height="80" filterUnits="userSpaceOnUse" color-interpolation-filters="sRGB">'
        '<feFlood flood-opacity="0" result="BackgroundImageFix"/>'
        '<feColorMatrix in="SourceAlpha" type="matrix" values="0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 127 0" result="hardAlpha"/>'
        '<feOffset dy="4"/><feGaussianBlur stdDeviation="3"/><feComposite in2="hardAlpha" operator="out"/>'
        '<feColorMatrix type="matrix" values="0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0.35 0"/>'
        '<feBlend mode="normal" in2="BackgroundImageFix" result="effect1"/>'
        '<feBlend mode="normal" in="SourceGraphic" in2="effect1" result="shape"/></filter></defs>',
        '<rect data-tag="s" x="30" y="40" width="40" height="30" fill="#e4572e" filter="url(#shadow)"/>',
        '<rect data-tag="s" x="110" y="80" width="36" height="36" rx="6" fill="#17bebb" filter="url(#figma)"/>',
        '<circle data-tag="c" cx="165" cy="30" r="14" fill="#ffc914" filter="url(#soft)"/>',
    ],
}


# Two lines of type tagged like the scene's shapes, added to the scene of the text operators'
# cases: the text is cut, the scene's other `s` shapes pass through whole (with a warning).
# Drawn with the fonts vendored in tests/fonts (given with --font-file), ligatures and all.
TEXT = ('<text data-tag="s" font-family="Noto Sans" font-size="15" fill="#3a86ff" stroke="#1d3557" '
        'stroke-width="0.4"><tspan x="10" y="122">Kinetic type</tspan><tspan x="10" dy="18">first flow</tspan></text>')
TEXT_OPS = {"letters", "words", "lines"}
FONTS = ["NotoSans-Regular.ttf", "NotoSansHebrew-Regular.ttf"]


def font_args():
    """The command-line arguments that give gmotion the vendored fonts."""
    return [a for f in FONTS for a in ("--font-file", os.path.join(root(), "tests", "fonts", f))]


def scene_svg(kind, text=False):
    body = "\n".join(SCENES[kind] + ([TEXT] if text else []))
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}">\n'
            f'<rect data-tag="bg" width="{W}" height="{H}" fill="#f4f1ea"/>\n{body}\n</svg>\n')


# ---- timeslice grammars ------------------------------------------------------------------

EASES = {"linear": None, "ease": "ease", "ease-in": "ease-in", "ease-out": "ease-out",
         "ease-in-out": "ease-in-out", "cubic": "cubic(0.3, -0.3, 0.7, 1.3)",
         "bspline": "bspline(3)", "poles": "poles(4)", "poles-tau": "poles(3, 0.15)",
         "steps": "steps(3)", "hold": "hold"}
# (local value, world value) of each animate type; world transforms are about the canvas
# origin, so they are kept small enough to leave the shapes on the canvas.
VALUES = {
    "translate": ("translate(40, -20)", "translate(40, -20)"),
    "rotate": ("rotate(75)", "rotate(12)"),
    "scale": ("scale(0.6)", "scale(0.85)"),
    "skew": ("skewX(25)", "skew(15, 8)"),
    "matrix": ("matrix(0.9, 0.25, -0.2, 0.8, 12, -6)", "matrix(0.95, 0.1, -0.05, 0.9, 12, 4)"),
    "product": ("translate(30, 0) rotate(40) scale(0.7)", "translate(30, 10) rotate(10)"),
    "about": ("rotate(60, 10, 5)", "rotate(30, 100, 75)"),
    "towards": ("(W / 2, H / 2)",) * 2,
    "path": ('"M 20 130 C 60 10 140 10 180 130"',) * 2,
    "fill": ("#d1495b",) * 2,
    "border": ("steelblue",) * 2,
    "opacity": ("0.3",) * 2,
    "stroke-width": ("5",) * 2,
    # The strokes' visible part: 10 % to 60 % of each path, moved a quarter turn.
    "trim": ("(0.1, 0.6, 0.25)",) * 2,
    # n×m×p grids: the value at 5 keyframes in time (`u` = 0, 1/4, …, 1).
    "keyed": ("rotate(120 * u) scale(1 - 0.4 * sin(pi * u))",
              "translate(60 * u, -30 * sin(pi * u))"),
    "keyed-towards": ("(lerp(cx, W / 2, u), lerp(cy, H / 2, u) - 40 * sin(pi * u))",) * 2,
    # Motion along a path: `local` from the centroid, `world` on the path as written.
    "follow": ('"M 0 0 C 30 -60 90 -60 120 0 S 150 40 170 20"', '"M 30 120 C 60 20 140 20 170 110"'),
    "follow-orient": ('"M 0 0 C 30 -60 90 -60 120 0 S 150 40 170 20"', '"M 30 120 C 60 20 140 20 170 110"'),
    # A five-pointed star (ten vertices: another point count than any scene's shape), as
    # path data; `local` centres it on each shape, `world` takes it where it is drawn.
    "morph": ('"M 0 -30 L 7 -10 L 29 -9 L 12 4 L 18 24 L 0 12 L -18 24 L -12 4 L -29 -9 L -7 -10 Z"',
              '"M 100 45 L 107 65 L 129 66 L 112 79 L 118 99 L 100 87 L 82 99 L 88 79 L 71 66 L 93 65 Z"'),
}
ANIM = {"translate": "affine", "rotate": "affine", "scale": "affine", "skew": "affine",
        "matrix": "affine", "product": "affine", "about": "affine", "towards": "towards",
        "path": "path", "fill": "fill", "border": "border", "opacity": "opacity",
        "stroke-width": "stroke-width", "keyed": "affine", "keyed-towards": "towards",
        "trim": "trim",
        "follow": "follow", "follow-orient": "follow",
        "morph": "morph"}
OFFSETS = {"zero": "0", "inside": "0.25 * d", "stagger": "0.3 * d * id / n", "near-limit": "0.9 * d"}
SECOND = {"fill": "fill, local, 0, #00798c", "opacity": "opacity, local, 0, 0.5",
          "stroke-width": "stroke-width, local, 0, 1", "border": "border, local, 0, #edae49",
          "local-rotate": "affine, local, 0, rotate(-30)",
          "world-translate": "affine, world, 0, translate(-20, 15)"}
INHERIT = {"motion": "affine, world, 0, translate(25, 10)", "colour": "fill, local, 0, #5d2e8c"}
FIRST_SPLIT = {"none": ("0.4, 0.6", "a, rest"), "after": ("0.5, 0.5", "a, inv_a"),
               "before": ("0.5, 0.5", "inv_a, a"), "after-hold": ("0.3, 0.4, 0.3", "a, hold, inv_a"),
               "before-hold": ("0.3, 0.4, 0.3", "inv_a, hold, a")}
SPATIAL = {
    "none": ([], "s"),
    "regularSplit": (["regularSplit(line, 14) : s -> [p]"], "p"),
    "dual-split": (["regularSplit(line, 14, 1, angle=30) : s -> [p]"], "p"),
    "outline": (["outline(5) : s -> [q, p]"], "p, q"),
    "regroup": (["regularSplit(line, 12, 1) : s -> [k]", "regroup(2, chessboard) : k -> [p, q]"], "p, q"),
    "ungroup": (["regularSplit(line, 16) : s -> [k]", "ungroup() : k -> [p]"], "p"),
    "fill": (["fill(#6a4c93) : s -> [p]"], "p"),
    "invert": (["invert() : s -> [p]"], "p"),
    "perturb": (["regularSplit(line, 16, 1) : s -> [k]", "perturb(2, 20) : k -> [p]"], "p"),
    "streamline": (["streamlineSplit(strip, 8) : s -> [p]"], "p"),
    "place": (["place(circle, 8, 11) : s -> [p, q]"], "q, p"),
    "stipple": (["stipple(dots, 3, 1.5) : s -> [q, p]"], "q, p"),
    "letters": (["letters() : s -> [p]"], "p"),
    "words": (["words() : s -> [p]"], "p"),
    "lines": (["lines() : s -> [p]"], "p"),
}
SMOOTHING = {"none": None, "spring": "spring(0.3, 0.1)", "msd": "msd(1, 150, 14)",
             "fir": "fir(bspline(3), 0.25)", "lowpass": "lowpass(2, 0.06)", "spline": "spline(0.25)",
             "series": "series(lowpass(1, 0.04), spring(0.3, 0))", "simple": "simple(ease-in-out, 0.25)",
             "parallel": "parallel(0.5, spring(0.3, 0), 0.5, fir(linear, 0.2))",
             "tustin": "tustin(spring(0.3, 0.2))"}
TIMING = {"2s@30": (2, 30), "2.4s@25": (2.4, 25), "1.5s@24": (1.5, 24)}


def grammar(c):
    """The grammar text of a generated timeslice case."""
    dur, fps = TIMING[c["timing"]]
    spatial, pieces = SPATIAL[c["spatial"]]
    shapes = f"({pieces}, c)"
    motion = [f"# case dimensions: {json.dumps(c, sort_keys=True)}", f"duration {dur}s", f"fps {fps}", "seed 3"]
    grid = c["grid"] + ("x5" if c["type"].startswith("keyed") else "")
    if c["where"] == "header":
        motion += [f"grid {grid}", f"lookup {c['lookup']}", f"interp {c['interp']}"]
    if SMOOTHING[c["smoothing"]]:
        motion.append(f"smoothing {SMOOTHING[c['smoothing']]}")
    if c["loop"] == "false":
        motion.append("loop false")
    motion.append("")
    motion += spatial
    top = "all"
    if c["inherit"] != "none":
        motion.append(f"animate({INHERIT[c['inherit']]}) : [all, {shapes}] -> [moving]")
        top = "moving"
    fr, outs = FIRST_SPLIT[c["inverted"]]
    motion.append(f"timesplit({fr}) : [{top}, {shapes}] -> [{outs}]")
    m = "a"
    if c["nesting"] == "2":
        motion.append(f"timesplit(0.4, 0.6) : [a, {shapes}] -> [m, e]")
        m = "m"
    elif c["nesting"] == "3":
        motion.append(f"timesplit(0.4, 0.6) : [a, {shapes}] -> [b, e]")
        motion.append(f"timesplit(0.5, 0.5) : [b, {shapes}] -> [m, f]")
        m = "m"
    elif c["nesting"] == "2-twin":
        motion.append(f"timesplit(0.5, 0.5) : [a, {shapes}] -> [m, inv_m]")
        m = "m"
    value = VALUES[c["type"]][c["ref"] == "world"]
    extra = ""
    if EASES[c["ease"]]:
        extra += f", ease={EASES[c['ease']]}"
    if c["type"] == "follow-orient":
        extra += ", orient=auto"
    if c["where"] == "rule":
        extra += f", grid={grid}, lookup={c['lookup']}, interp={c['interp']}"
    # A morph's target is one path: units of several paths (the group scene's, and pieces
    # a spatial rule makes) would be an error saying the counts, so only `c` (one path in
    # every scene, never split) morphs there.
    target = shapes
    if c["type"] == "morph" and (c["scene"] == "group" or c["spatial"] != "none"):
        target = "c"
    motion.append(f"animate({ANIM[c['type']]}, {c['ref']}, {OFFSETS[c['offset']]}, {value}{extra}) : [{m}, {target}] -> [m1]")
    if c["second"] != "none":
        motion.append(f"animate({SECOND[c['second']]}) : [m1, {target}] -> [m2]")
    return "\n".join(motion) + "\n"


# ---- transitions targets ---------------------------------------------------------------

SYSTEMS = {"none": "none", "simple": "simple(ease-in-out, 0.3)", "spline": "spline(0.3)",
           "fir": "fir(bspline(3), 0.3)", "arc": "arc(0.6, 0.5)", "spring": "spring(0.4, 0.1)",
           "msd": "msd(1, 120, 12)", "lowpass": "lowpass(2, 0.08)", "zoh": "zoh(spring(0.4, 0))",
           "impulse": "impulse(spring(0.4, 0.2))", "tustin": "tustin(spring(0.4, 0))",
           "matched": "matched(spring(0.4, 0.1))", "series": "series(lowpass(1, 0.05), spring(0.35, 0))",
           "parallel": "parallel(0.5, spring(0.4, 0), 0.5, fir(linear, 0.2))"}
# (attribute, first target, retarget) per attribute value; sx-sy and zx-zy move two.
TARGETS = {"x": [("x", 150, 60)], "y": [("y", 110, 40)], "dx": [("dx", 40, -20)], "dy": [("dy", -30, 20)],
           "scale": [("scale", 1.6, 0.6)], "sx-sy": [("sx", 1.8, 0.7), ("sy", 0.5, 1.3)],
           "zx-zy": [("zx", 0.5, 1.2), ("zy", 1.4, 0.8)], "rotate": [("rotate", 90, -45)],
           "opacity": [("opacity", 0.2, 0.8)], "fill": [("fill", "#d1495b", "#00798c")]}
TR_DURATION, TR_FPS = 2, 30


def targets(c):
    """(file name, file text, extra command-line arguments, target times) of a transitions
    case: tag `s` ids 0 and 1 get the attribute's targets; with `mid-flight` the target
    changes again before the system has settled."""
    times = [0.2, 0.5] if c["retarget"] == "mid-flight" else [0.2, 1.2]
    rows = []
    for attr, first, again in TARGETS[c["attr"]]:
        for sid in (0, 1):
            rows.append((times[0], "s", sid, attr, first))
            rows.append((times[1], "s", sid, attr, again))
    # The tag `c` always gets a plain move too, so every case has a second channel.
    rows.append((0.3, "c", 0, "dx", -25))
    system = SYSTEMS[c["system"]]
    meta = {"duration": TR_DURATION}
    args = []
    if c["fps"] == "file":
        meta["fps"] = TR_FPS
    else:
        args += ["--fps", str(TR_FPS)]
    attr0 = TARGETS[c["attr"]][0][0]
    channel = {"x": "xy", "y": "xy", "dx": "xy", "dy": "xy"}.get(attr0, attr0)
    if c["via"] == "cli":
        args += ["--system", system]
        meta["system"] = "spring(0.6, 0)"  # overridden by --system
    elif c["via"] == "file":
        meta["system"] = system
    elif c["via"] == "channel":
        meta["system"] = "spring(0.6, 0)"
        meta["systems"] = {channel: system}
    else:
        meta["system"] = "spring(0.6, 0)"
        meta["systems"] = {f"s.{channel}": system}
    if c["anchor"] == "bottom":
        meta["anchors"] = {"s": [0.5, 1]}
    if c["format"] == "json":
        doc = dict(meta)
        doc["targets"] = [{"time": t, "tag": tag, "id": i, "attr": a, "value": v} for t, tag, i, a, v in rows]
        return "targets.json", json.dumps(doc, indent=1) + "\n", args, times
    lines = [f"# {k}: {v}" for k, v in meta.items() if k in ("duration", "fps", "system")]
    lines += [f"# system.{k}: {v}" for k, v in meta.get("systems", {}).items()]
    lines += [f"# anchor.{k}: {v[0]} {v[1]}" for k, v in meta.get("anchors", {}).items()]
    lines.append("time,tag,id,attr,value")
    lines += [f"{t},{tag},{i},{a},{v}" for t, tag, i, a, v in rows]
    return "targets.csv", "\n".join(lines) + "\n", args, times


# ---- slice boundaries --------------------------------------------------------------------

def strip_comment(line):
    """A line without its comment (`//`, or `#` not starting a colour; docs/grammar.md)."""
    out, i, quote = [], 0, False
    while i < len(line):
        ch = line[i]
        if ch == '"':
            quote = not quote
        elif not quote and line.startswith("//", i):
            break
        elif not quote and ch == "#" and not re.match(r"#([0-9a-fA-F]{8}|[0-9a-fA-F]{6}|[0-9a-fA-F]{3})(?![A-Za-z0-9_])", line[i:]):
            break
        out.append(ch)
        i += 1
    return "".join(out)


def statements(text):
    """The grammar's statements, continuation lines joined (open brackets, or a next line
    that starts, indented, with `:`, `->`, `→`, `priority=` or `weight=`)."""
    stmts, cur, depth = [], "", 0
    for raw in text.splitlines():
        line = strip_comment(raw)
        cont = re.match(r"\s+(:|->|→|priority|weight)", line) or (depth > 0 and not re.match(r"[A-Za-z_]", line))
        if cur and not cont:
            stmts.append(cur)
            cur, depth = "", 0
        cur += " " + line.strip()
        depth = max(0, depth + line.count("(") + line.count("[") - line.count(")") - line.count("]"))
    if cur.strip():
        stmts.append(cur)
    return [s.strip() for s in stmts if s.strip()]


def split_top(s):
    parts, depth, cur, quote = [], 0, "", False
    for ch in s:
        if ch == '"':
            quote = not quote
        if not quote and ch in "([":
            depth += 1
        elif not quote and ch in ")]":
            depth -= 1
        if ch == "," and depth == 0 and not quote:
            parts.append(cur.strip())
            cur = ""
        else:
            cur += ch
    if cur.strip():
        parts.append(cur.strip())
    return parts


def tag_list(s):
    s = s.strip()
    if s.startswith("("):
        s = s[1:-1]
    return [t.strip().strip('"') for t in s.split(",") if t.strip()]


def number(expr, env):
    """A numeric expression of the grammar language evaluated in Python, or None."""
    e = re.sub(r"(\d(?:\.\d*)?)ms\b", r"(\1/1000)", expr)
    e = re.sub(r"(\d(?:\.\d*)?)s\b", r"(\1)", e)
    e = re.sub(r"(\d(?:\.\d*)?)%(?![\d(A-Za-z.])", r"(\1/100)", e).replace("^", "**")
    if not re.fullmatch(r"[\d.\s+\-*/()%a-z_0-9]*", e):
        return None
    try:
        return float(eval(e, {"__builtins__": {}}, env))  # noqa: S307 - checked characters, no builtins
    except Exception:  # noqa: BLE001 - anything not a plain number is skipped
        return None


def boundaries(text):
    """Slice boundaries and change starts (seconds) of a grammar, union over its shape tags:
    a simulation of `timesplit` (mirrored on inverted slices) and `animate` (renames; an
    offset delays the change, mirrored on inverted slices). Rules whose fractions are not
    plain numbers are skipped; among several matching rules the first of the highest
    priority stands for all."""
    duration = 5.0
    rules = []
    for st in statements(text):
        m = re.match(r"duration\s+(\S+)", st)
        if m:
            duration = number(m.group(1), {}) or duration
        m = re.match(r"(timesplit|animate)\s*\((.*)\)\s*:\s*\[(.*)\]\s*(?:->|→)\s*(.*)$", st)
        if not m:
            continue
        op, args, match, rest = m.groups()
        mt = split_top(match)
        if len(mt) != 2:
            continue
        out = re.match(r"\[([^\]]*)\]|(\S+)", rest.strip())
        outs = tag_list(out.group(1) if out.group(1) is not None else out.group(2))
        pr = re.search(r"priority\s*=\s*(-?\d+)", rest)
        rules.append({"op": op, "args": split_top(args), "slices": tag_list(mt[0]), "shapes": tag_list(mt[1]),
                      "outs": outs, "priority": int(pr.group(1)) if pr else 0})
    times = {0.0, duration}
    shape_tags = sorted({t for r in rules for t in r["shapes"] if t != "all"}) or ["all"]

    def inv(tag, flip):
        if not flip:
            return tag
        return tag[4:] if tag.startswith("inv_") else "inv_" + tag

    for shape in shape_tags:
        slices = [("all", 0.0, duration)]
        done = []
        for _ in range(4000):
            if not slices:
                break
            tag, t0, d = slices.pop(0)
            base, flipped = (tag[4:], True) if tag.startswith("inv_") else (tag, False)
            cands = [r for r in rules if base in r["slices"] and (shape in r["shapes"] or "all" in r["shapes"])]
            if not cands:
                done.append((tag, t0, d))
                continue
            top = max(r["priority"] for r in cands)
            r = next(r for r in cands if r["priority"] == top)
            env = {"d": d, "t0": t0, "id": 1, "n": 2, "pi": math.pi}
            if r["op"] == "timesplit":
                fr = [number(a, env) for a in r["args"]]
                if None in fr or len(fr) != len(r["outs"]):
                    done.append((tag, t0, d))
                    continue
                pieces = list(zip(fr, r["outs"]))
                if flipped:
                    pieces = pieces[::-1]
                t = t0
                for f, o in pieces:
                    slices.append((inv(o, flipped), t, d * f))
                    times.add(t)
                    t += d * f
                times.add(t0 + d)
            else:
                off = number(r["args"][2], env) if len(r["args"]) > 2 else 0.0
                if off:
                    times.add(t0 + d - off if flipped else t0 + off)
                if r["outs"]:
                    slices.append((inv(r["outs"][0], flipped), t0, d))
        for _, t0, d in done:
            times.update((t0, t0 + d))
    return sorted(t for t in times if 0 <= t <= duration + 1e-9)


def pick_frames(n, fps, times):
    """Frame numbers: at or just before and just after every boundary, first and last, and
    evenly spaced ones up to MIN_FRAMES; at most MAX_FRAMES (boundaries first)."""
    must = {0, n - 1}
    for t in times:
        f = t * fps
        lo = math.floor(f + 1e-6)
        must.update((lo, lo + 1) if abs(f - round(f)) < 1e-6 else (lo, math.ceil(f - 1e-6)))
    must = sorted(f for f in must if 0 <= f < n)
    if len(must) > MAX_FRAMES:
        keep = {0, n - 1}
        step = len(must) / (MAX_FRAMES - 2)
        keep.update(must[int(i * step)] for i in range(MAX_FRAMES - 2))
        must = sorted(keep)
    frames = set(must)
    k = MIN_FRAMES
    while len(frames) < min(MIN_FRAMES, n):
        frames.update(round(i * (n - 1) / (k - 1)) for i in range(k))
        k += 1
    return sorted(frames)


# ---- cases -------------------------------------------------------------------------------

def root():
    return os.path.abspath(os.path.join(here, "..", ".."))


def all_cases():
    """Every case of the full matrix, in a fixed order, and the number of pairs left
    uncovered per family."""
    gm, gm_left = cover(GM_DIMS, GM_CASES, SEED)
    tr, tr_left = cover(TR_DIMS, TR_CASES, SEED + 1)
    cases = []
    for i, c in enumerate(gm):
        # One case in four is exported with `--pack` (runs of plain shape layers as one
        # layer of groups), so that the players judge that path across the language too.
        # Set after the covering design, which it leaves as it was.
        c["pack"] = "yes" if i % 4 == 3 else "no"
        cases.append({"name": f"gm-{i:04d}", "family": "gm", "dims": c})
    for i, c in enumerate(tr):
        cases.append({"name": f"tr-{i:04d}", "family": "tr", "dims": c})
    g = os.path.join(root(), "grammars")
    for f in sorted(os.listdir(g)):
        name, ext = os.path.splitext(f)
        if ext == ".gm" and os.path.exists(os.path.join(g, name + ".svg")):
            cases.append({"name": f"ex-{name}", "family": "ex", "dims": {"example": name}})
        if f.endswith(".targets.json") and os.path.exists(os.path.join(g, f[: -len(".targets.json")] + ".svg")):
            name = f[: -len(".targets.json")]
            cases.append({"name": f"ex-{name}", "family": "ex", "dims": {"transitions example": name}})
    return cases, {"gm": gm_left, "tr": tr_left}


def sample(cases):
    """The CI sample: SAMPLE_EXAMPLES, a greedy cover of every (family, dimension, value),
    then the cases that add the most uncovered value pairs, up to SAMPLE_GENERATED."""
    gen = [c for c in cases if c["family"] != "ex"]
    singles = {(c["family"], k, v) for c in gen for k, v in c["dims"].items()}
    pairs = {(c["family"], a, b) for c in gen for a in c["dims"].items() for b in c["dims"].items() if a < b}
    chosen = []
    while singles or (pairs and len(chosen) < SAMPLE_GENERATED):
        def gain(c):
            s = {(c["family"], k, v) for k, v in c["dims"].items()}
            p = {(c["family"], a, b) for a in c["dims"].items() for b in c["dims"].items() if a < b}
            return (len(s & singles), len(p & pairs))
        best = max((c for c in gen if c not in chosen), key=gain)
        chosen.append(best)
        singles -= {(best["family"], k, v) for k, v in best["dims"].items()}
        pairs -= {(best["family"], a, b) for a in best["dims"].items() for b in best["dims"].items() if a < b}
    names = {c["name"] for c in chosen}
    return [c for c in cases if c["name"] in names or c["name"] in SAMPLE_EXAMPLES]


def select(argv):
    kind = "sample"
    only = None
    rest = []
    i = 0
    while i < len(argv):
        if argv[i] == "--matrix":
            kind = argv[i + 1]
            i += 2
        elif argv[i] == "--only":
            only = set(argv[i + 1].split(","))
            i += 2
        else:
            rest.append(argv[i])
            i += 1
    if kind not in ("sample", "full"):
        raise SystemExit(f"matrix: --matrix is `sample` or `full`, not `{kind}`")
    cases, left = all_cases()
    chosen = cases if kind == "full" else sample(cases)
    if only is not None:
        chosen = [c for c in cases if c["name"] in only]
        kind = f"{len(chosen)} chosen"
    return kind, chosen, left, rest


# ---- prepare ------------------------------------------------------------------------------

def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    return r.returncode, r.stderr.strip()


def expected_error(case):
    """The message gmotion must refuse a case with, or None. `arc` moves a point along a
    2-D path (docs/transitions.md), so on any other channel it is an error; those cases check
    the error instead of playing."""
    d = case["dims"]
    if case["family"] == "tr" and d["system"] == "arc" and d["attr"] not in ("x", "y", "dx", "dy"):
        return "`arc` moves along a 2-D path"
    return None


def export(case, out, gm):
    """Writes a case's inputs, exports it and renders its reference frames; fills in the
    case's files, frames and any error."""
    d = os.path.join(out, "cases", case["name"])
    os.makedirs(d, exist_ok=True)
    g = os.path.join(root(), "grammars")
    lj, sj = os.path.join(d, "case.json"), os.path.join(d, "case.svg")
    # The same export as a dotLottie package, for dotlottie-web (its animation is the JSON
    # above, byte for byte: written by the same run).
    dl = os.path.join(d, "case.lottie")
    dims = case["dims"]
    if case["family"] == "gm":
        scene = os.path.join(d, "scene.svg")
        src = os.path.join(d, "case.gm")
        text = dims["spatial"] in TEXT_OPS
        with open(scene, "w", encoding="utf-8") as f:
            f.write(scene_svg(dims["scene"], text))
        with open(src, "w", encoding="utf-8") as f:
            f.write(grammar(dims))
        pre = [gm] + (font_args() if text else [])
        base = pre + ["animate", scene, src] + (["--pack"] if dims.get("pack") == "yes" else [])
    elif case["family"] == "tr":
        scene = os.path.join(d, "scene.svg")
        with open(scene, "w", encoding="utf-8") as f:
            f.write(scene_svg(dims["scene"]))
        fname, text, args, _ = targets(dims)
        src = os.path.join(d, fname)
        with open(src, "w", encoding="utf-8") as f:
            f.write(text)
        pre = [gm]
        base = pre + ["transitions", scene, src] + args
    elif "example" in dims:
        scene, src = os.path.join(g, dims["example"] + ".svg"), os.path.join(g, dims["example"] + ".gm")
        # An example drawn in the vendored fonts gets them, as its grammar says.
        with open(scene, encoding="utf-8") as f:
            vendored = "Noto Sans" in f.read()
        pre = [gm] + (font_args() if vendored else [])
        base = pre + ["animate", scene, src]
    else:
        name = dims["transitions example"]
        scene, src = os.path.join(g, name + ".svg"), os.path.join(g, name + ".targets.json")
        pre = [gm]
        base = pre + ["transitions", scene, src]
    case["source"] = src
    # Baked motion is exported at a tenth of a pixel's error here instead of the default
    # quarter: at 2x a 0.25 px bake error moves whole edges by half a pixel, which alone puts
    # thin shapes over the 0.5% bar though the motion is right. The matrix judges what the
    # motion means; the error bound itself is checked geometrically in exporters/lottie/tests/lottie.rs.
    rc, err = run(base + ["-o", lj, "-o", sj, "-o", dl, "--tolerance", TOLERANCE])
    expect = expected_error(case)
    if expect is not None:
        case["expected_error"] = expect
        if rc == 0 or expect not in err:
            case["error"] = f"expected the error `{expect}`, got " + (f"exit status {rc}: {err[-300:]}" if rc else "success")
        return case
    if rc != 0 or not os.path.exists(lj):
        case["error"] = err[-600:] or f"exit status {rc}"
        return case
    case["warnings"] = [line for line in err.splitlines() if "warning" in line.lower()][:5]
    # dotlottie-web plays the package, the other players the .json: the same animation, or
    # the column would judge something else.
    try:
        with zipfile.ZipFile(dl) as z, open(lj, "rb") as f:
            inside = [n for n in z.namelist() if n.startswith("a/")]
            if len(inside) != 1 or z.read(inside[0]) != f.read():
                case["dotlottie_error"] = f"the package's animations {inside} are not the .json"
    except (OSError, zipfile.BadZipFile) as e:
        case["dotlottie_error"] = f"no package: {e}"
    with open(lj, encoding="utf-8") as f:
        doc = json.load(f)
    case["per_paint_opacity"] = translucent_paint_overlap(doc, layers=True)
    case["per_paint_group_opacity"] = translucent_paint_overlap(doc, layers=False)
    case["stroke_under_nonuniform_scale"] = stroke_under_nonuniform_scale(doc)
    case["effects"] = any(layer.get("ef") for layer in doc.get("layers", []) +
                          [l for a in doc.get("assets", []) for l in a.get("layers", [])])
    n, fps = int(round(doc["op"] - doc["ip"])), float(doc["fr"])
    if case["family"] == "tr":
        times = targets(dims)[3] + [0.3]
    elif src.endswith(".gm"):
        with open(src, encoding="utf-8") as f:
            times = boundaries(f.read())
    else:
        times = []
    case["boundaries"] = [round(t, 6) for t in times]
    case["frames"] = pick_frames(n, fps, times)
    case["fps"] = fps
    # Exactly 2x, so the height is whole too and every player scales both axes alike
    # (revisions.svg is 829x110: at conformance.exact_width's 1000 px the height would
    # be 132.7, rounded, and the players stretch the text by 0.2%: 1.3% of pixels off).
    width = SCALE * int(round(doc["w"]))
    case["width"] = width
    for fr in case["frames"]:
        rc, err = run(base + ["-o", os.path.join(d, f"ref-{fr}.png"), "--time", repr(fr / fps), "--width", str(width)])
        if rc != 0:
            case["error"] = "reference render: " + err[-600:]
            return case
        # The Lottie as written, drawn by gmotion's own Lottie player: the second reference
        # of the Lottie players (see WRITTEN in judge).
        rc, err = run(pre + ["convert", lj, "-o", os.path.join(d, f"wref-{fr}.png"), "--time", repr(fr / fps),
                             "--width", str(width)])
        if rc != 0:
            case["error"] = "reference render of the written Lottie: " + err[-600:]
            return case
    # dotlottie-web draws into a canvas of the size it is given: the reference's own.
    with Image.open(os.path.join(d, f"ref-{case['frames'][0]}.png")) as im:
        case["height"] = im.size[1]
    case["lottie"], case["smil"], case["dotlottie"] = lj, sj, dl
    return case


def stroke_under_nonuniform_scale(doc):
    """Whether some stroke is drawn under a group transform that scales its axes unequally
    (a scale with unequal or animated components, or a skew): rlottie widens such a stroke
    by one averaged factor where the others draw it anisotropically; see KNOWN."""
    def nonuniform(tr):
        s, sk = tr.get("s", {}), tr.get("sk", {})
        skewed = bool(sk.get("a")) or (isinstance(sk.get("k"), (int, float)) and sk["k"] != 0)
        if s.get("a"):
            return True
        k = s.get("k")
        return skewed or (isinstance(k, list) and len(k) >= 2 and abs(k[0] - k[1]) > 1e-9)

    def walk(items, scaled):
        tr = next((x for x in items if x.get("ty") == "tr"), {})
        scaled = scaled or nonuniform(tr)
        for it in items:
            if it.get("ty") in ("st", "gs") and scaled:
                return True
            if it.get("ty") == "gr" and walk(it.get("it", []), scaled):
                return True
        return False

    layers = list(doc.get("layers", [])) + [l for a in doc.get("assets", []) for l in a.get("layers", [])]
    return any(walk(layer.get("shapes", []), nonuniform(layer.get("ks", {}))) for layer in layers)


def translucent_paint_overlap(doc, layers):
    """Whether some shape group or layer below 100% opacity (fixed or animated) holds more
    than one paint (a fill and a stroke, or several drawn paths). lottie-web's canvas
    renderer applies such opacity to each paint in it, so it draws where one paint overlaps
    another darker than a group composited whole (resvg, lottie-web svg, ThorVG, rlottie,
    browsers); see KNOWN."""
    def paints(items):
        n = 0
        for it in items:
            if it.get("ty") in ("fl", "gf", "st", "gs"):
                n += 1
            elif it.get("ty") == "gr":
                n += paints(it.get("it", []))
        return n

    def translucent(o):
        if not isinstance(o, dict):
            return False
        return bool(o.get("a")) or (isinstance(o.get("k"), (int, float)) and o["k"] < 100)

    def walk(items):
        for it in items:
            if it.get("ty") != "gr":
                continue
            inner = it.get("it", [])
            tr = next((x for x in inner if x.get("ty") == "tr"), {})
            if translucent(tr.get("o")) and paints(inner) > 1:
                return True
            if walk(inner):
                return True
        return False

    assets = {a.get("id"): a.get("layers", []) for a in doc.get("assets", [])}

    def layer_paints(layer):
        if "refId" in layer:
            return sum(layer_paints(sub) for sub in assets.get(layer["refId"], []))
        return paints(layer.get("shapes", []))

    every = [layer for layers in [doc.get("layers", [])] + list(assets.values()) for layer in layers]
    return any(walk(layer.get("shapes", [])) or
               (layers and translucent(layer.get("ks", {}).get("o")) and layer_paints(layer) > 1)
               for layer in every)


def schema_validator():
    """A function from a Lottie document to None (valid) or its first schema error
    (schema_check.checker: the schema and validators of the corpus check)."""
    import schema_check
    return schema_check.checker()


def prepare(argv):
    kind, cases, left, rest = select(argv)
    if len(rest) != 2:
        raise SystemExit(__doc__)
    out, gm = os.path.abspath(rest[0]), os.path.abspath(rest[1])
    os.makedirs(out, exist_ok=True)
    workers = int(os.environ.get("MATRIX_JOBS", "2"))
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        cases = list(pool.map(lambda c: export(c, out, gm), cases))

    valid = schema_validator()
    lw, rl, tv, dlw, smil = [], [], [], [], []
    for c in cases:
        if "lottie" not in c:  # failed, or refused as it must be
            continue
        d = os.path.dirname(c["lottie"])
        with open(c["lottie"], encoding="utf-8") as f:
            err = valid(json.load(f))
        if err is not None:
            c["schema_error"] = err
        fr = c["frames"]
        lw.append({"json": c["lottie"], "width": c["width"], "frames": fr, "out": [os.path.join(d, f"lws-{i}.png") for i in fr]})
        lw.append({"json": c["lottie"], "width": c["width"], "frames": fr, "renderer": "canvas",
                   "out": [os.path.join(d, f"lwc-{i}.png") for i in fr]})
        rl.append({"json": c["lottie"], "width": c["width"], "frames": fr, "out": [os.path.join(d, f"rl-{i}.png") for i in fr]})
        tv.append({"json": c["lottie"], "width": c["width"], "frames": fr, "out": [os.path.join(d, f"tv-{i}.png") for i in fr]})
        dlw.append({"lottie": c["dotlottie"], "width": c["width"], "height": c["height"], "frames": fr,
                    "out": [os.path.join(d, f"dl-{i}.png") for i in fr]})
        if os.path.exists(c["smil"]):
            smil.append({"svg": c["smil"], "width": c["width"], "out_prefix": os.path.join(d, "smil"),
                         "times": [i / c["fps"] for i in fr]})

    def dump(name, obj):
        with open(os.path.join(out, name), "w", encoding="utf-8") as f:
            json.dump(obj, f, indent=1)

    dump("cases.json", {"matrix": kind, "uncovered_pairs": left, "cases": cases})
    dump("lottie_web_jobs.json", lw)
    dump("rlottie_jobs.json", rl)
    dump("thorvg_jobs.json", tv)
    dump("dotlottie_web_jobs.json", dlw)
    dump("smil_jobs.json", smil)
    failed = sum("error" in c for c in cases)
    refused = sum("expected_error" in c and "error" not in c for c in cases)
    print(f"matrix ({kind}): {len(cases)} cases, {failed} failed to export, {refused} refused as they must be, "
          f"{sum(len(c.get('frames', [])) for c in cases)} reference frames")
    return 0


# ---- report -------------------------------------------------------------------------------

def player_pngs(c, player):
    d = os.path.dirname(c["lottie"])
    prefix = {"lottie-web-svg": "lws", "lottie-web-canvas": "lwc", "rlottie": "rl", "thorvg": "tv",
              "dotlottie-web": "dl"}
    if player == "chromium-smil":
        return [os.path.join(d, f"smil-{k}.png") for k in range(len(c["frames"]))]
    return [os.path.join(d, f"{prefix[player]}-{i}.png") for i in c["frames"]]


NA = "n/a"
# Players that draw where one paint of a translucent group or layer overlaps another darker
# (opacity applied per paint; see translucent_paint_overlap). Their frames of such cases are
# reported as "known", not failed; every other player still judges those cases.
# lottie-web 5.13's canvas renderer multiplies the context's globalAlpha by a layer's opacity
# (CVBaseElement renderFrame: ctxOpacity(finalTransform.localOpacity)) and by each shape
# group's (renderStyledShapes: ctxOpacity(coOp)), then fills and strokes straight onto the
# canvas, with no offscreen buffer. Minimal reproducer: one 100x100 shape layer holding a
# rectangle (20..80) with a blue fill over a green (0, 0.6, 0) stroke 8 wide, at opacity 50
# either on the layer's ks.o or on the group's tr.o. At 2x, pixel (44, 44), where the fill
# covers the stroke, is premultiplied (0, 38, 128, 192) in the canvas renderer both ways
# (the stroke shows through: two paints composited one after the other), and plain
# half-blue, (0, 0, 125..128, 125..128), in lottie-web svg, ThorVG and rlottie for the layer.
# rlottie applies a group's opacity per paint too (0, 38, 127, 190), but not a layer's; the
# exporter still keeps a single-path shape's opacity on its group, because each translucent
# layer in rlottie dims everything beneath it by about 1/255 and that adds up (the cube
# example's background fell to alpha 215 with opacity on ~50 layers). So rlottie's frames
# of cases with a translucent group holding several paints are known too.
# rlottie also widens a stroke under a group or layer transform that scales the axes
# unequally (the exporter's skews are rotate·scale·rotate) by one averaged factor, where
# lottie-web (both renderers), ThorVG, resvg and browsers stroke anisotropically. Minimal
# reproducer: a 200x200 layer, one group holding a 60x60 rectangle stroked 10 wide (lc 2,
# lj 2) under tr.p (100, 100), tr.s (50, 200): rlottie's frame differs from lottie-web's on
# 7.65% of the pixels, ThorVG's on 0.00%, static width or animated. A held width under such a
# transform is exported as the stroke's outline (for ThorVG, which widens along the canvas
# axes), which every player draws alike; an animated width stays a stroke (gm-0103: 0.71%).
# Player -> the case flags that make its frames known, with what they mean.
# Neither lottie-web's canvas renderer nor rlottie draws Lottie effects (blurs, drop
# shadows): the export says so in a warning, and README's format table.
KNOWN = {
    "lottie-web-canvas": [("per_paint_opacity", "opacity applied per paint"),
                          ("effects", "effects not drawn")],
    "rlottie": [("per_paint_group_opacity", "opacity applied per paint"),
                ("stroke_under_nonuniform_scale", "stroke under non-uniform scale"),
                ("effects", "effects not drawn")],
}
KNOWN_NOTE = "known ("
# Bake error bound (canvas px) for the exports. Compared at 2x, an edge the exporter moves by
# its full bound changes an antialiased pixel by up to 2·bound of coverage, and a frame fails
# on pixels off by more than 32/255: so the bound must stay well under 32/255/2 ≈ 0.063 px.
# At 0.1 the exports of gm-0126 and gm-0007 sat within their bound (0.08 px off) and still
# failed. At 0.05 gm-0189, tr-0048, tr-0137 (lottie-web) and tr-0078 (SMIL) failed single
# frames by 0.5-0.65%: resvg, Skia and lottie-web's canvas quantise an edge's vertical
# coverage to quarter pixels, so an edge moved by less than the bound but across a quarter
# boundary changes whole rows by ~54/255 (gm-0189 frame 4 exported at 1e-4 matches lottie-web
# to 12/255). That the bake stays within its bound is the Rust tests' job (exporters/lottie/tests/lottie.rs,
# exporters/svg/tests/smil.rs: max_error); the matrix judges whether players draw what was written.
TOLERANCE = "0.01"


# Players judged against two references: a pixel of theirs is off only where it is off both
# gmotion's own frame (the motion as the engine means it) and gmotion's own render of the
# Lottie as written (`gmotion convert case.json --time T`, wref-N.png). The matrix judges
# whether the players draw what was written; that the bake stays within its bound
# (TOLERANCE) is the Rust tests' job. Without the second reference an edge the bake moved
# by far less than its bound still failed frames: resvg and Skia (lottie-web, both
# renderers) sample an edge's vertical coverage on four sub-scanlines per pixel, at 1/8,
# 3/8, 5/8 and 7/8, so an edge that lies within a hair of one flips a quarter of the
# coverage of its whole row. gm-0010 frame 29: every shape is moved down by 15.186882 px
# (the model) and 15.188326 (the export, 0.0014 px off, within its 0.01 bound); at 2x the
# square's top edge lies at 68.3738 and 68.3767, on either side of the sub-scanline at
# 68.375, and so do the other edges of the scene (integer and quarter coordinates), so
# whole rows differ by ~38/255: lottie-web 0.52% off gmotion's frame, 0.0075% off gmotion's
# render of the file (rlottie and ThorVG, with analytic coverage, draw partial rows between
# the two). Chromium's SMIL has no such second reference (gmotion does not play SMIL), nor
# has a case whose Lottie carries effects: gmotion's frame of a blurred group under a turn
# is itself off (resvg redraws the blurred source's edges, see README), and its render of
# the Lottie, blurred by another path, agrees with the players there (gm-0005, gm-0009,
# gm-0015: 0.2-0.48% of pixels off at every frame, under the bar, would vanish).
WRITTEN = ("lottie-web-svg", "lottie-web-canvas", "rlottie", "thorvg", "dotlottie-web")


# The second reference counts only while the Lottie as written is itself within twice the
# bar of gmotion's frame: an export that is wrong by more is judged against the frame alone,
# whatever the players agree on.
WRITTEN_MAX_OFF = 2 * MAX_OFF


def off_both(ref, written, got):
    """The fraction of pixels of the decoded player frame `got` off both the decoded
    reference `ref` and `written` (see WRITTEN), or None when `got` or `ref` is missing or
    of another size; without `written`, or with a `written` more than WRITTEN_MAX_OFF off
    `ref`, off `ref` alone."""
    mask = off_mask(ref, got)
    if mask is None:
        return None
    export = off_mask(ref, written)
    if export is None or export.mean() > WRITTEN_MAX_OFF:
        return float(mask.mean())
    return float((mask & off_mask(written, got)).mean())


def judge(c):
    """Per check: None when it passes, else a short reason (worst off fraction, frames)."""
    res = {}
    if "expected_error" in c and "error" not in c:
        # Refused as it must be: nothing to play.
        return {k: (None if k == "export" else NA) for k in CHECKS}, {}
    if "error" in c:
        res = {k: "export failed" for k in CHECKS}
        res["export"] = c["error"].splitlines()[-1][:200] if c["error"] else "export failed"
        return res, {}
    res["export"] = None
    res["schema"] = c.get("schema_error")
    worst = {}
    d = os.path.dirname(c["lottie"])
    refs = [rgba(os.path.join(d, f"ref-{i}.png")) for i in c["frames"]]
    written = [rgba(os.path.join(d, f"wref-{i}.png")) for i in c["frames"]]
    for player in PLAYERS:
        if player in WRITTEN and not c.get("effects"):
            offs = [off_both(r, w, rgba(p)) for r, w, p in zip(refs, written, player_pngs(c, player))]
        else:
            offs = [off(r, p) for r, p in zip(refs, player_pngs(c, player))]
        bad = [(f, x) for f, x in zip(c["frames"], offs) if x is None or x > MAX_OFF]
        worst[player] = max((1.0 if x is None else x) for x in offs)
        if bad:
            missing = [f for f, x in bad if x is None]
            shown = ", ".join(f"{f}:{'none' if x is None else f'{x * 100:.2f}%'}" for f, x in bad[:6])
            res[player] = (f"no picture at {len(missing)} frame(s); " if missing else "") + \
                f"{len(bad)}/{len(offs)} frames off, worst {worst[player] * 100:.2f}% ({shown})"
        else:
            res[player] = None
        if player == "dotlottie-web" and c.get("dotlottie_error"):
            res[player] = c["dotlottie_error"]
        why = [note for flag, note in KNOWN.get(player, []) if c.get(flag)]
        if res[player] is not None and why:
            res[player] = KNOWN_NOTE + "; ".join(why) + "): " + res[player]
    return res, worst


def fails(x):
    """Whether a check's result is a failure (not a pass, not applicable, not known)."""
    return x not in (None, NA) and not x.startswith(KNOWN_NOTE)


def report(argv):
    out = os.path.abspath(argv[0])
    with open(os.path.join(out, "cases.json"), encoding="utf-8") as f:
        data = json.load(f)
    cases = data["cases"]
    # Decoding ~5 PNGs per reference frame dominates; two processes, as the machine has.
    with concurrent.futures.ProcessPoolExecutor(max_workers=int(os.environ.get("MATRIX_JOBS", "2"))) as pool:
        rows = [(c, res, worst) for c, (res, worst) in zip(cases, pool.map(judge, cases, chunksize=4))]
    lines = [f"# Conformance matrix ({data['matrix']}: {len(cases)} cases)", "",
             "Each case is played in every player and compared with gmotion's own resvg render at every "
             f"chosen frame (at least {MIN_FRAMES}, every slice boundary and the frame after it), at {SCALE}x; a frame passes "
             f"with at most {MAX_OFF * 100:g}% of its pixels off by more than {OFF}/255. Generated by "
             "`tests/conformance/matrix.py` (see its header for the dimensions and the covering design).", "",
             "| check | " + " | ".join(["all"] + ["gm", "tr", "ex"]) + " |", "|---|---|---|---|---|"]
    fams = ["gm", "tr", "ex"]
    for k in CHECKS:
        cells = []
        for fam in [None] + fams:
            sel = [(c, r) for c, r, _ in rows if (fam is None or c["family"] == fam) and r[k] != NA]
            ok = sum(r[k] is None for _, r in sel)
            known = sum(r[k] is not None and not fails(r[k]) for _, r in sel)
            cells.append(f"{ok}/{len(sel)}" + (f" (+{known} known)" if known else ""))
        lines.append(f"| {k} | " + " | ".join(cells) + " |")
    refused = sum("expected_error" in c and "error" not in c for c in cases)
    lines += ["", "Families: gm = generated timeslice grammars, tr = generated `gmotion transitions` targets, "
              "ex = the bundled examples. Pairs of dimension values left uncovered by the full design: "
              f"{data['uncovered_pairs']}." + (f" {refused} case(s) must be refused with a located error "
                                                 "(`arc` on a channel that is not a position) and were; they "
                                                 "count under export only." if refused else ""),
              "", "`(+N known)`: frames of lottie-web's canvas renderer (a translucent group's or layer's "
              "opacity) and rlottie (a translucent group's) that differ only because they apply that opacity "
              "to each paint (a shape's stroke over its own fill draws darker), and rlottie's strokes under a "
              "non-uniform scale (widened by one averaged factor), and the Lottie effects (blurs, drop shadows) neither of them draws; the other players "
              "(lottie-web svg, ThorVG, dotlottie-web, Chromium SMIL) judge those cases in full. dotlottie-web (ThorVG in wasm) has no "
              "known limitation: it plays each case's `.lottie` package, the same animation as the `.json`. Baked motion is exported with "
              f"`--tolerance {TOLERANCE}`.", ""]
    # Failures per dimension value.
    fail_rows = []
    for fam in fams:
        values = {}
        for c, r, _ in rows:
            if c["family"] != fam:
                continue
            for k, v in c["dims"].items():
                values.setdefault((k, v), []).append(r)
        for (k, v), rs in sorted(values.items()):
            counts = [sum(fails(r[p]) for r in rs) for p in CHECKS]
            if any(counts):
                fail_rows.append(f"| {fam} | {k} = {v} | {len(rs)} | " + " | ".join(str(x) if x else "" for x in counts) + " |")
    if fail_rows:
        lines += ["## Failures per dimension value", "",
                  "| family | value | cases | " + " | ".join(CHECKS) + " |",
                  "|---|---|---|" + "---|" * len(CHECKS)] + fail_rows
        lines += ["", "Values not listed pass in every check.", ""]
    failing = [(c, r) for c, r, _ in rows if any(fails(x) for x in r.values())]
    if failing:
        lines += ["## Failing cases", ""]
        for c, r in failing:
            src = c.get("source", "")
            src = os.path.relpath(src, root()) if src.startswith(root() + os.sep) else src
            lines.append(f"- `{c['name']}` ({', '.join(f'{k}={v}' for k, v in c['dims'].items())}): `{src}`")
            for k in CHECKS:
                if fails(r[k]):
                    lines.append(f"  - {k}: {r[k]}")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out, "matrix.md"), "w", encoding="utf-8") as f:
        f.write(text)
    with open(os.path.join(out, "results.json"), "w", encoding="utf-8") as f:
        json.dump([{"name": c["name"], "family": c["family"], "dims": c["dims"], "result": r, "worst": w}
                   for c, r, w in rows], f, indent=1)
    head = text.split("## Failures")[0]
    print(head.strip())
    print(f"matrix: {len(failing)} of {len(cases)} cases fail some check; details in {os.path.join(out, 'matrix.md')}")
    return 1 if failing else 0


def selftest():
    """Checks the generator itself, against properties stated independently of its code:
    the design covers what it claims, generation is deterministic, and the boundary
    simulation gives the slices docs/grammar.md works out by hand. Exits 1 on a failure."""
    bad = []
    for dims, n, seed in ((GM_DIMS, GM_CASES, SEED), (TR_DIMS, TR_CASES, SEED + 1)):
        cases, _ = cover(dims, n, seed)
        if cases != cover(dims, n, seed)[0]:
            bad.append(f"{dims[0].name}: the design differs between two runs")
        for d in dims:
            missing = set(d.values) - {c[d.name] for c in cases}
            if missing:
                bad.append(f"{d.name}: values never used: {sorted(missing)}")
        pd = [d for d in dims if d.pair]
        seen = {(a.name, c[a.name], b.name, c[b.name]) for c in cases for a in pd for b in pd}
        for x, a in enumerate(pd):
            for b in pd[x + 1:]:
                for u in a.values:
                    for v in b.values:
                        if (a.name, u, b.name, v) not in seen:
                            bad.append(f"pair {a.name}={u}, {b.name}={v} not covered")
    # docs/grammar.md, timesplit: a 5 s timeline split (0.3, 0.4, 0.3) -> 1.5 s, 3.5 s; the
    # same split on an inverted slice is mirrored: inv_all of 5 s -> 1.5, 3.5 as well, so
    # an asymmetric split shows the mirror: (0.2, 0.8) on inv_a = [2.5, 5] -> 2.5 + 2.0.
    cases = [("duration 5s\ntimesplit(0.3, 0.4, 0.3) : [all, all] -> [in, hold, inv_in]\n", [0, 1.5, 3.5, 5]),
             ("duration 5s\ntimesplit(0.5, 0.5) : [all, s] -> [a, inv_a]\n"
              "timesplit(0.2, 0.8) : [a, s] -> [b, c]\n", [0, 0.5, 2.5, 4.5, 5]),
             ("duration 4s\ntimesplit(0.5, 0.5) : [all, s] -> [a, inv_a]\n"
              "animate(opacity, local, 0.5, 0.2) : [a, s] -> [f]\n", [0, 0.5, 2, 3.5, 4]),
             ("duration 2s\ntimesplit(0.5,\n    0.5)\n  : [all, (s, c)]\n  -> [a, b]  # 50%\n", [0, 1, 2])]
    for text, want in cases:
        got = boundaries(text)
        if len(got) != len(want) or any(abs(g - w) > 1e-9 for g, w in zip(got, want)):
            bad.append(f"boundaries of {text!r}: {got}, expected {want}")
    frames = pick_frames(60, 30, [1.0, 0.51])
    for f in (0, 15, 16, 30, 31, 59):
        if f not in frames:
            bad.append(f"frame {f} missing from {frames} (boundaries at 1.0 s and 0.51 s, 30 fps)")
    if len(frames) < MIN_FRAMES:
        bad.append(f"only {len(frames)} frames")
    for b in bad:
        print("matrix selftest: " + b)
    print(f"matrix selftest: {'FAILED' if bad else 'ok'}")
    return 1 if bad else 0


def main(argv):
    if len(argv) == 2 and argv[1] == "selftest":
        return selftest()
    if len(argv) >= 2 and argv[1] == "list":
        kind, cases, left, _ = select(argv[2:])
        for c in cases:
            print(c["name"], json.dumps(c["dims"], sort_keys=True))
        print(f"{len(cases)} cases ({kind}); uncovered pairs in the full design: {left}", file=sys.stderr)
        return 0
    if len(argv) >= 2 and argv[1] == "prepare":
        return prepare(argv[2:])
    if len(argv) == 3 and argv[1] == "report":
        return report(argv[2:])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
