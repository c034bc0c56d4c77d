"""The conformance run's two halves around the players (see run.sh):

    python3 conformance.py prepare OUT GMOTION CORPUS GRAMMARS
        converts the corpus with gmotion (timed per file, one process per file) and with
        python-lottie (timed in process), exports every example grammar to Lottie, dotLottie,
        SMIL and gmotion's own PNG frames, and writes the players' job lists into OUT.
    python3 conformance.py report OUT
        compares every player frame with its reference, prints the figures and exits 1
        when a threshold is missed.

Pixels are compared premultiplied (what shows over black, alpha included): a pixel is off
when some channel differs by more than 32/255. Thresholds: example frames at most 0.5%
off in every player (lottie-web, rlottie, ThorVG, dotlottie-web, Chromium's SMIL); corpus
files at most 1% off in lottie-web, but for the named known failures (CORPUS_KNOWN).
"""

import glob
import json
import os
import re
import signal
import statistics
import subprocess
import sys
import time

import numpy as np
from PIL import Image

WIDTH = 300
EXAMPLE_FRAMES = 12
# Frames played of an example whose Lottie is over PER_FRAME_MAX_BYTES.
EXAMPLE_FRAMES_LARGE = 6
OFF = 32
EXAMPLE_MAX = 0.005
# Largest Lottie export whose size is compared with keying every frame (see prepare).
PER_FRAME_MAX_BYTES = 4_000_000
# Largest SMIL export played in Chromium (`SMIL_MAX_BYTES=0` in the environment plays every
# one). Chromium loads the document again for every frame it draws: intersections' 13 MB
# (8216 animated shapes, its nested groups merged) takes it about 45 s a frame here, so a
# SMIL export over SMIL_FEW_FRAMES_BYTES is played at SMIL_FRAMES_LARGE of its example's
# frames, spread over the animation. (Its 18 MB before the merge took ten minutes to draw
# its first frame, and the next page would not load.)
SMIL_MAX_BYTES = int(os.environ.get("SMIL_MAX_BYTES", "16000000")) or None
SMIL_FEW_FRAMES_BYTES = 4_000_000
SMIL_FRAMES_LARGE = 2
CORPUS_MAX = 0.01
# The resvg corpus files whose gmotion Lottie lottie-web does not draw as resvg's reference
# (each with why). Any other file failing fails the run by name, and so does a listed file
# that passes, whose entry would otherwise hide it failing again. (The last run's passing
# files were all within 0.75% of their reference, these at least 1.4% off.)
# Examples a player draws otherwise for a reason of its own, by (example, player), each with
# why. An entry whose example passes in that player fails the run (take it off), as for the
# corpus.
EXAMPLE_KNOWN = {
    ("follow", "rlottie"): "rlottie lays the dashes of a dashed stroke along a curve by its own "
                           "measure of the length: on the example's dashed S-curve track they drift "
                           "by a dash edge (0.52% of pixels at every frame, frame 0 included, before "
                           "anything moves); lottie-web, ThorVG, dotlottie-web and SMIL pass",
}

_PATTERN = "resvg draws pattern tiles as pictures, gmotion's Lottie as vector copies of the tile: their edges differ"
CORPUS_KNOWN = {
    "paint-servers__pattern__invalid-patternUnits-and-patternContentUnits": _PATTERN,
    "paint-servers__pattern__pattern-on-child": _PATTERN,
    "paint-servers__pattern__patternContentUnits-with-viewBox": _PATTERN,
    "paint-servers__pattern__patternContentUnits=objectBoundingBox": _PATTERN,
    "paint-servers__pattern__patternUnits=objectBoundingBox-with-percent": _PATTERN,
    "paint-servers__pattern__patternUnits=objectBoundingBox": _PATTERN,
    "paint-servers__pattern__patternUnits=userSpaceOnUse-with-percent": _PATTERN,
    "paint-servers__pattern__recursive-on-child": _PATTERN,
    "paint-servers__pattern__self-recursive-on-child": _PATTERN,
    "paint-servers__pattern__text-child": _PATTERN + " (the tile holds text)",
    "painting__marker__with-an-image-child": "the marker's picture is `../../../resources/image.svg`, outside the vendored corpus: not drawn (warned)",
    "structure__svg__no-size": "no width, height or viewBox: usvg sizes the canvas to the drawing (199 x 199) where the reference is 200 x 200, so every edge lands a little off",
    "structure__svg__not-UTF-8-encoding": "not UTF-8: refused with the byte's line and column",
}


def rgba(path):
    """Straight RGBA bytes of a PNG, or None if it is missing."""
    if not os.path.exists(path):
        return None
    return np.asarray(Image.open(path).convert("RGBA"))


def off(ref, got_path):
    """The fraction of pixels whose premultiplied channels differ by more than OFF between
    the decoded reference `ref` (`rgba`) and the PNG at `got_path`, or None when either is
    missing or the player wrote a picture of another size."""
    mask = off_mask(ref, rgba(got_path))
    return None if mask is None else float(mask.mean())


def off_mask(ref, got):
    """Where the premultiplied channels of two decoded pictures (`rgba`) differ by more than
    OFF (a boolean array), or None when either is missing or their sizes differ.

    Where both pixels are opaque, premultiplied is straight, so the bytes are compared as
    they are; only the other pixels are premultiplied (rounding to nearest). Premultiplying
    every pixel in 32 bits made the report of the examples and the corpus take minutes.
    A pixel is off when any of its four channels is: the four booleans of a pixel are read
    as one 32-bit word, not reduced over the channel axis, which numpy does slowly on an
    axis of four (the matrix's report, over 3000 frames, took 2.4 times as long)."""
    if ref is None or got is None or got.shape != ref.shape:
        return None
    over = np.abs(ref.astype(np.int16) - got.astype(np.int16)) > OFF
    bad = over.view(np.uint32)[..., 0] != 0
    clear = (ref[..., 3] < 255) | (got[..., 3] < 255)
    if clear.any():
        def premul(a):
            x = a[clear].astype(np.int32)
            return np.concatenate([(x[:, :3] * x[:, 3:4] + 127) // 255, x[:, 3:4]], axis=1)
        bad[clear] = np.abs(premul(ref) - premul(got)).max(axis=1) > OFF
    return bad


def off_fraction(ref_path, got_path):
    """Fraction of pixels off, or None when the player wrote nothing / a wrong size."""
    return off(rgba(ref_path), got_path)


def exact_width(w, h):
    """The render width for an example: twice its own width (within 600..1000 px), nudged
    to one at which the height is a whole number of pixels, so every renderer scales by
    the same factor (players fit the canvas to the viewport).

    Twice, because the examples' 1-1.5 px outlines shrink with their shapes: below about a
    pixel each renderer anti-aliases by its own rule (rlottie and ThorVG give a thin stroke
    its full area, resvg draws it ~10% lighter), so at 1x growing_tangle's mid-scale frames
    differ by 1.3-1.5% in rlottie and ThorVG while the geometry is the same; at 2x the same
    frames differ by 0.01%. The comparison is meant to measure the animation, not hairline
    anti-aliasing.

    Among those widths, one that scales by a multiple of 1/4 is preferred: at 1000 px the
    2064 px intersections lattice (scale 0.4845) put its plazas' edges at arbitrary
    fractions of a pixel, and resvg and lottie-web quantise an edge's vertical coverage to
    quarter pixels each their own way, so whole rows of edges differed (1.7% of pixels at
    rest, none at 1032 px, scale 1/2)."""
    target = int(min(max(2 * w, 600), 1000))
    return min(range(target - 60, target + 61), key=lambda x: (abs(x * h / w - round(x * h / w)) > 1e-9, (4 * x) % w != 0, abs(x - target)))


class Timeout(Exception):
    pass


def _alarm(_sig, _frame):
    raise Timeout()


def prepare(out, gm, corpus, grammars):
    os.makedirs(out, exist_ok=True)
    svgs = sorted(glob.glob(os.path.join(corpus, "*.svg")))
    gm_dir, pl_dir = os.path.join(out, "corpus-gmotion"), os.path.join(out, "corpus-python-lottie")
    os.makedirs(gm_dir, exist_ok=True)
    os.makedirs(pl_dir, exist_ok=True)
    manifest = {"corpus": [], "examples": []}
    gm_lotties = []
    lw_jobs, rl_jobs, tv_jobs, dl_jobs, smil_jobs = [], [], [], [], []

    from lottie.parsers.svg import parse_svg_file  # python-lottie, the comparison converter

    signal.signal(signal.SIGALRM, _alarm)
    for svg in svgs:
        name = os.path.splitext(os.path.basename(svg))[0]
        entry = {"name": name, "ref": os.path.splitext(svg)[0] + ".png"}
        # gmotion: the command a user runs, process start-up included.
        gj = os.path.join(gm_dir, name + ".json")
        t = time.perf_counter()
        r = subprocess.run([gm, "convert", svg, "-o", gj], capture_output=True, text=True)
        entry["gm_time"] = time.perf_counter() - t
        entry["gm_ok"] = r.returncode == 0 and os.path.exists(gj)
        entry["gm_warnings"] = sum(1 for line in r.stderr.splitlines() if "warning" in line.lower())
        # A reference is 300 px wide, or drawn at the document's own size.
        width = Image.open(entry["ref"]).size[0]
        if entry["gm_ok"]:
            gm_lotties.append(gj)
            entry["gm_png"] = os.path.join(gm_dir, name + ".lw.png")
            entry["gm_rl_png"] = os.path.join(gm_dir, name + ".rl.png")
            entry["gm_tv_png"] = os.path.join(gm_dir, name + ".tv.png")
            lw_jobs.append({"json": gj, "width": width, "frames": [0], "out": [entry["gm_png"]]})
            rl_jobs.append({"json": gj, "width": width, "frames": [0], "out": [entry["gm_rl_png"]]})
            tv_jobs.append({"json": gj, "width": width, "frames": [0], "out": [entry["gm_tv_png"]]})
        else:
            entry["gm_error"] = (r.stderr.strip().splitlines() or ["no output"])[-1][:200]
        # python-lottie: parse and serialise in process (its own exporter's JSON), twice,
        # keeping the faster time, as gmotion's in-process figure does (exporters/lottie/tests/lottie.rs).
        pj = os.path.join(pl_dir, name + ".json")
        t = time.perf_counter()
        try:
            signal.alarm(40)
            an = parse_svg_file(svg)
            text = json.dumps(an.to_dict())
            first = time.perf_counter() - t
            t = time.perf_counter()
            json.dumps(parse_svg_file(svg).to_dict())
            signal.alarm(0)
            entry["pl_time"] = min(first, time.perf_counter() - t)
            with open(pj, "w", encoding="utf-8") as f:
                f.write(text)
            entry["pl_ok"] = True
            entry["pl_png"] = os.path.join(pl_dir, name + ".lw.png")
            lw_jobs.append({"json": pj, "width": width, "frames": [0], "out": [entry["pl_png"]]})
        except BaseException as e:  # noqa: BLE001 - python-lottie may fail on any input
            signal.alarm(0)
            if isinstance(e, KeyboardInterrupt):
                raise
            entry["pl_time"] = time.perf_counter() - t
            entry["pl_ok"] = False
        manifest["corpus"].append(entry)

    # The fixed cost of a gmotion process (start-up, argument parsing, writing), measured
    # on the smallest SVG, so per-file times can be compared with in-process ones.
    tiny = os.path.join(out, "tiny.svg")
    with open(tiny, "w", encoding="utf-8") as f:
        f.write('<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><rect width="5" height="5"/></svg>')
    base = []
    for _ in range(21):
        t = time.perf_counter()
        subprocess.run([gm, "convert", tiny, "-o", os.path.join(out, "tiny.json")], capture_output=True)
        base.append(time.perf_counter() - t)
    manifest["gm_process_baseline"] = statistics.median(base)

    for gmf in sorted(glob.glob(os.path.join(grammars, "*.gm"))):
        name = os.path.splitext(os.path.basename(gmf))[0]
        scene = os.path.join(grammars, name + ".svg")
        if not os.path.exists(scene):
            continue
        d = os.path.join(out, "examples", name)
        frames_dir = os.path.join(d, "frames")
        os.makedirs(frames_dir, exist_ok=True)
        lj, sj = os.path.join(d, name + ".json"), os.path.join(d, name + ".svg")
        # The same animation as a dotLottie package, for dotlottie-web.
        dl = os.path.join(d, name + ".lottie")
        r = subprocess.run([gm, "animate", scene, gmf, "-o", lj, "-o", sj, "-o", dl], capture_output=True, text=True)
        entry = {"name": name, "ok": r.returncode == 0, "stderr": r.stderr.strip()[-500:]}
        if entry["ok"]:
            with open(lj, encoding="utf-8") as f:
                doc = json.load(f)
            width = exact_width(doc["w"], doc["h"])
            entry["lottie_bytes"] = os.path.getsize(lj)
            entry["width"] = width
            n = int(doc["op"] - doc["ip"])
            # A Lottie over PER_FRAME_MAX_BYTES (intersections: 8216 shapes) is played at
            # fewer frames: Chromium took 22 s a frame for its 18 MB SMIL.
            count = EXAMPLE_FRAMES if entry["lottie_bytes"] <= PER_FRAME_MAX_BYTES else EXAMPLE_FRAMES_LARGE
            picks = sorted({round(i * (n - 1) / (count - 1)) for i in range(count)}) if n > count else list(range(n))
            # gmotion's own render of just the chosen frames (`-o x.png --time t`).
            refs = [os.path.join(frames_dir, f"frame_{i:05d}.png") for i in picks]
            for i, ref in zip(picks, refs):
                r = subprocess.run([gm, "animate", scene, gmf, "-o", ref, "--time", repr(i / doc["fr"]), "--width", str(width)], capture_output=True, text=True)
                if r.returncode != 0:
                    entry["ok"] = False
                    entry["stderr"] = r.stderr.strip()[-500:]
                    break
        if entry["ok"]:
            gm_lotties.append(lj)
            entry["frames"] = picks
            entry["fps"] = doc["fr"]
            entry["refs"] = refs
            entry["lw"] = [os.path.join(d, f"lw-{i}.png") for i in picks]
            entry["rl"] = [os.path.join(d, f"rl-{i}.png") for i in picks]
            entry["tv"] = [os.path.join(d, f"tv-{i}.png") for i in picks]
            entry["dl"] = [os.path.join(d, f"dl-{i}.png") for i in picks]
            # Indices into `picks` of the frames Chromium draws of the SMIL export.
            smil_idx = list(range(len(picks)))
            if os.path.exists(sj) and os.path.getsize(sj) > SMIL_FEW_FRAMES_BYTES:
                smil_idx = [len(picks) * (k + 1) // (SMIL_FRAMES_LARGE + 1)
                            for k in range(SMIL_FRAMES_LARGE)]
            entry["smil_idx"] = smil_idx
            entry["smil"] = [os.path.join(d, f"smil-{k}.png") for k in range(len(smil_idx))]
            # Keying every frame of a large export in Python takes gigabytes (intersections:
            # 24 MB of Lottie, 8216 shapes × 241 frames; over 4.6 GB before it was stopped),
            # so the size comparison is left out above PER_FRAME_MAX_BYTES.
            if entry["lottie_bytes"] <= PER_FRAME_MAX_BYTES:
                (entry["lottie_per_frame_bytes"], entry["keys_bytes"],
                 entry["keys_per_frame_bytes"]) = per_frame_size(doc)
            lw_jobs.append({"json": lj, "width": width, "frames": picks, "out": entry["lw"]})
            rl_jobs.append({"json": lj, "width": width, "frames": picks, "out": entry["rl"]})
            tv_jobs.append({"json": lj, "width": width, "frames": picks, "out": entry["tv"]})
            # dotlottie-web draws into a canvas of the size it is given: the reference's own.
            with Image.open(refs[0]) as im:
                height = im.size[1]
            dl_jobs.append({"lottie": dl, "width": width, "height": height, "frames": picks, "out": entry["dl"]})
            if os.path.exists(sj) and SMIL_MAX_BYTES and os.path.getsize(sj) > SMIL_MAX_BYTES:
                entry["smil_skipped"] = os.path.getsize(sj)
            elif os.path.exists(sj):
                smil_jobs.append({"svg": sj, "width": width, "out_prefix": os.path.join(d, "smil"),
                                  "times": [picks[i] / doc["fr"] for i in smil_idx]})
        manifest["examples"].append(entry)

    def dump(name, obj):
        with open(os.path.join(out, name), "w", encoding="utf-8") as f:
            json.dump(obj, f, indent=1)

    dump("manifest.json", manifest)
    dump("lottie_web_jobs.json", lw_jobs)
    dump("rlottie_jobs.json", rl_jobs)
    dump("thorvg_jobs.json", tv_jobs)
    dump("dotlottie_web_jobs.json", dl_jobs)
    dump("smil_jobs.json", smil_jobs)
    with open(os.path.join(out, "gmotion_lottie_files.txt"), "w", encoding="utf-8") as f:
        f.write("\n".join(gm_lotties) + "\n")
    return 0


# ---- per-frame baking, for the size comparison -------------------------------------------

def bezier_ease(x1, y1, x2, y2, x):
    """CSS cubic-bezier at x (bisection on the monotone x(s))."""
    def b(a, c, s):
        m = 1 - s
        return 3 * m * m * s * a + 3 * m * s * s * c + s * s * s
    lo, hi = 0.0, 1.0
    for _ in range(50):
        mid = (lo + hi) / 2
        if b(x1, x2, mid) < x:
            lo = mid
        else:
            hi = mid
    return b(y1, y2, (lo + hi) / 2)


def handle(h, key):
    v = h[key]
    return v[0] if isinstance(v, list) else v


def value_at(keys, f):
    """A keyframed value at frame f, as players compute it."""
    if f <= keys[0]["t"]:
        return keys[0]["s"]
    for k0, k1 in zip(keys, keys[1:]):
        if f < k1["t"]:
            if k0.get("h"):
                return k0["s"]
            u = (f - k0["t"]) / (k1["t"] - k0["t"])
            y = bezier_ease(handle(k0["o"], "x"), handle(k0["o"], "y"), handle(k0["i"], "x"), handle(k0["i"], "y"), u)
            return lerp(k0["s"], k1["s"], y)
    return keys[-1]["s"]


def lerp(a, b, y):
    if isinstance(a, list):
        return [lerp(p, q, y) for p, q in zip(a, b)]
    if isinstance(a, dict):
        return {k: (lerp(a[k], b[k], y) if k != "c" else a[k]) for k in a}
    return round(a + (b - a) * y, 3)


def per_frame_size(doc):
    """Sizes for the comparison with an exporter that bakes each frame: (the same document
    with every animated property keyed at every frame, the keyframes alone as written,
    the keyframes alone keyed at every frame). Static geometry is the same in both, so
    the keyframe sizes show the saving where it applies."""
    frames = int(doc["op"] - doc["ip"])
    keys_written = keys_baked = 0

    def compact(x):
        return len(json.dumps(x, separators=(",", ":")))

    def walk(o):
        nonlocal keys_written, keys_baked
        if isinstance(o, dict):
            if o.get("a") == 1 and isinstance(o.get("k"), list) and o["k"] and isinstance(o["k"][0], dict) and "t" in o["k"][0]:
                keys = o["k"]
                o["k"] = [{"t": f, "s": value_at(keys, f), "o": {"x": 0, "y": 0}, "i": {"x": 1, "y": 1}} for f in range(frames + 1)]
                keys_written += compact(keys)
                keys_baked += compact(o["k"])
                return
            for v in o.values():
                walk(v)
        elif isinstance(o, list):
            for v in o:
                walk(v)

    copy = json.loads(json.dumps(doc))
    walk(copy)
    return compact(copy), keys_written, keys_baked


# ---- report -------------------------------------------------------------------------------

def report(out):
    with open(os.path.join(out, "manifest.json"), encoding="utf-8") as f:
        manifest = json.load(f)
    failures = []
    smil_ran = os.path.exists(os.path.join(out, "smil.ran"))

    print("== example grammars: player frames vs gmotion's own render (≤ 0.5% of pixels off by > 32/255)")
    for ex in manifest["examples"]:
        if not ex.get("ok") or "frames" not in ex:
            failures.append(f"example {ex['name']}: gmotion animate failed: {ex.get('stderr', '')}")
            print(f"  {ex['name']}: EXPORT FAILED {ex.get('stderr', '')}")
            continue
        every = list(range(len(ex["frames"])))
        # Each reference is compared with five players: decoded once.
        refs = {}

        def ref(i):
            if i not in refs:
                refs[i] = rgba(ex["refs"][i])
            return refs[i]

        players = [("lottie-web", ex["lw"], every), ("rlottie", ex["rl"], every), ("thorvg", ex["tv"], every),
                   ("dotlottie-web", ex["dl"], every)]
        if smil_ran and "smil_skipped" in ex:
            print(f"  {ex['name']}: SMIL of {ex['smil_skipped']} B not played in Chromium (over SMIL_MAX_BYTES)")
        elif smil_ran:
            players.append(("chromium-smil", ex["smil"], ex["smil_idx"]))
        if "lottie_per_frame_bytes" in ex:
            ratio = ex["lottie_per_frame_bytes"] / max(1, ex["lottie_bytes"])
            keys = (f"; keyframes {ex['keys_bytes']} B, {ex['keys_per_frame_bytes']} B keyed every frame "
                    f"({ex['keys_per_frame_bytes'] / ex['keys_bytes']:.1f}x)") if ex["keys_bytes"] else "; static"
            size = f"{ex['lottie_per_frame_bytes']} B keyed every frame ({ratio:.1f}x){keys}"
        else:
            size = f"not compared with keying every frame (over {PER_FRAME_MAX_BYTES} B)"
        print(f"  {ex['name']}: frames {ex['frames']}; Lottie {ex['lottie_bytes']} B, {size}")
        for player, pngs, idx in players:
            fr = [off(ref(i), p) for i, p in zip(idx, pngs)]
            worst = max((x if x is not None else 1.0) for x in fr)
            bad = [ex["frames"][i] for i, x in zip(idx, fr) if x is None or x > EXAMPLE_MAX]
            known = EXAMPLE_KNOWN.get((ex["name"], player))
            status = "ok" if not bad else (f"known at frames {bad}: {known}" if known else f"FAIL at frames {bad}")
            some = "" if len(idx) == len(every) else f" (frames {[ex['frames'][i] for i in idx]})"
            print(f"    {player:14s} worst {worst * 100:6.3f}% off  {status}{some}")
            if bad and not known:
                failures.append(f"example {ex['name']} in {player}: frames {bad} differ (worst {worst * 100:.3f}%)")
            if known and not bad:
                failures.append(f"example {ex['name']} passes in {player} now; take it off EXAMPLE_KNOWN")

    print(f"== corpus: {len(manifest['corpus'])} files, 300 px wide vs the reference PNG (≤ 1% off by > 32/255)")
    gm_pass = pl_pass = rl_pass = tv_pass = 0
    gm_fail = []
    for e in manifest["corpus"]:
        ref = rgba(e["ref"])
        g = off(ref, e["gm_png"]) if e.get("gm_ok") else None
        r = off(ref, e["gm_rl_png"]) if e.get("gm_ok") else None
        t = off(ref, e["gm_tv_png"]) if e.get("gm_ok") else None
        p = off(ref, e["pl_png"]) if e.get("pl_ok") else None
        e["gm_off"], e["rl_off"], e["tv_off"], e["pl_off"] = g, r, t, p
        gm_pass += g is not None and g <= CORPUS_MAX
        rl_pass += r is not None and r <= CORPUS_MAX
        tv_pass += t is not None and t <= CORPUS_MAX
        pl_pass += p is not None and p <= CORPUS_MAX
        if g is None or g > CORPUS_MAX:
            gm_fail.append((e["name"], g, e.get("gm_error")))
    n = max(1, len(manifest["corpus"]))
    print(f"  {'converter':26s} {'player':11s} {'pass':>9s}  rate")
    print(f"  {'gmotion convert':26s} {'lottie-web':11s} {gm_pass:4d}/{n:<4d}  {gm_pass / n * 100:5.1f}%")
    print(f"  {'python-lottie parse_svg':26s} {'lottie-web':11s} {pl_pass:4d}/{n:<4d}  {pl_pass / n * 100:5.1f}%")
    print(f"  {'gmotion convert':26s} {'rlottie':11s} {rl_pass:4d}/{n:<4d}  {rl_pass / n * 100:5.1f}%  (information)")
    print(f"  {'gmotion convert':26s} {'thorvg':11s} {tv_pass:4d}/{n:<4d}  {tv_pass / n * 100:5.1f}%  (information)")
    for name, g, err in gm_fail:
        why = err if err else ("no picture" if g is None else f"{g * 100:.2f}% off")
        print(f"    gmotion fails {name}: {why}")
    failed = {name for name, _, _ in gm_fail}
    for name in sorted(failed - CORPUS_KNOWN.keys()):
        failures.append(f"corpus: {name} fails and is not a known failure")
    played = {e["name"] for e in manifest["corpus"]}
    for name in sorted((CORPUS_KNOWN.keys() & played) - failed):
        failures.append(f"corpus: {name} passes now; take it off CORPUS_KNOWN")

    gt = [e["gm_time"] for e in manifest["corpus"] if e.get("gm_ok")]
    pt = [e["pl_time"] for e in manifest["corpus"] if e.get("pl_ok")]
    if gt and pt:
        print("== conversion time per file (gmotion: whole `gmotion convert` process; python-lottie: in process)")
        print(f"  gmotion       median {statistics.median(gt) * 1000:7.2f} ms  mean {statistics.mean(gt) * 1000:7.2f} ms  total {sum(gt):6.2f} s")
        print(f"  python-lottie median {statistics.median(pt) * 1000:7.2f} ms  mean {statistics.mean(pt) * 1000:7.2f} ms  total {sum(pt):6.2f} s")
        print(f"  python-lottie / gmotion: {statistics.median(pt) / statistics.median(gt):.1f}x (median), {statistics.mean(pt) / statistics.mean(gt):.1f}x (mean)")
        base = manifest.get("gm_process_baseline", 0.0)
        print(f"  (a gmotion process converting a one-rectangle SVG takes {base * 1000:.2f} ms: start-up dominates)")
        path = os.path.join(out, "in_process.txt")
        line = open(path, encoding="utf-8").read().strip() if os.path.exists(path) else ""
        m = re.search(r"median ([0-9.]+) ms, mean ([0-9.]+) ms", line)
        if m:
            med, mean = float(m.group(1)) / 1000, float(m.group(2)) / 1000
            print(f"  gmotion in process (import + Lottie export, release build): median {med * 1000:.3f} ms, mean {mean * 1000:.3f} ms")
            print(f"  python-lottie / gmotion in process: {statistics.median(pt) / med:.1f}x (median), {statistics.mean(pt) / mean:.1f}x (mean)")
            print(f"  {line}")

    with open(os.path.join(out, "results.json"), "w", encoding="utf-8") as f:
        json.dump(manifest, f, indent=1)
    if failures:
        print("== FAILED")
        for x in failures:
            print("  " + x)
        return 1
    print("== all conformance checks passed")
    return 0


def main(argv):
    if len(argv) >= 6 and argv[1] == "prepare":
        return prepare(*argv[2:6])
    if len(argv) == 3 and argv[1] == "report":
        return report(argv[2])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
