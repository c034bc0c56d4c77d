"""The 600-file check: real colour SVGs drawn by gmotion as Chromium draws them.

    python3 tests/conformance/icons.py GMOTION OUT_DIR [--per-set N] [--python-lottie]

150 files from each of four sets published on npm (pinned in icons/package.json, installed
into icons/node_modules on first use): Fluent emoji (flat), Noto emoji (the iconify
package's bodies in their own viewBox), Twemoji, Tabler (filled). Files are taken evenly
from each set's sorted names, so the choice is the same on every run.

Each file is drawn 128 px wide by Chromium (tests/conformance/smil.mjs, the reference) and
by gmotion twice: its own render (`gmotion convert X.svg -o X.png`) and its Lottie export
played in lottie-web's svg renderer (`gmotion convert X.svg -o X.json`, lottie_web.mjs).
With --python-lottie, python-lottie's conversion (parse_svg_file) is played the same way,
for comparison. A drawing passes when at most 1% of its pixels differ from Chromium's by
more than 32/255 in a premultiplied channel (the corpus check's bar).

Prints a table per set and converter, then the failing files with how far off they are.
Exits 1 when a file that KNOWN does not name fails with gmotion (its PNG or its Lottie), or
when a named one passes (its entry would hide it failing again). All renderers here are
deterministic: the last run's passing files were within 0.91% (Lottie) and 0.98% (PNG).
"""

import argparse
import glob
import json
import os
import signal
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

# The files gmotion does not draw as Chromium does, by converter, each with why.
_EDGES = "edge pixels: resvg anti-aliases curved edges and thin strokes unlike Chromium's Skia"
KNOWN = {
    "gmotion PNG": {
        "noto-copyright": _EDGES + " (1.1%)",
        "noto-goal-net": _EDGES + " (the net's hairlines, 3%)",
        "twemoji-1f506": _EDGES + " (1.2%)",
    },
    "gmotion Lottie": {},
}

from conformance import CORPUS_MAX, off_fraction  # noqa: E402

WIDTH = 128
MODULES = os.path.join(HERE, "icons", "node_modules")


def install():
    if not os.path.isdir(os.path.join(MODULES, "fluentui-emoji")):
        subprocess.run(["npm", "ci", "--no-audit", "--no-fund", "--loglevel=error"],
                       cwd=os.path.join(HERE, "icons"), check=True)


def every(names, n):
    """n names spread evenly over the sorted list."""
    names = sorted(names)
    if len(names) <= n:
        return names
    return [names[i * len(names) // n] for i in range(n)]


def noto_files(out, n):
    """Noto's SVGs as the iconify package holds them: a body per icon, drawn in the set's
    viewBox (or the icon's own size)."""
    with open(os.path.join(MODULES, "@iconify-json", "noto", "icons.json"), encoding="utf-8") as f:
        data = json.load(f)
    w0, h0 = data.get("width", 16), data.get("height", 16)
    paths = []
    for name in every(data["icons"], n):
        icon = data["icons"][name]
        w, h = icon.get("width", w0), icon.get("height", h0)
        path = os.path.join(out, f"noto-{name}.svg")
        with open(path, "w", encoding="utf-8") as f:
            f.write(f'<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
                    f'width="{w}" height="{h}" viewBox="{icon.get("left", 0)} {icon.get("top", 0)} {w} {h}">'
                    f'{icon["body"]}</svg>')
        paths.append(path)
    return paths


def sets(out, n):
    src = os.path.join(out, "src")
    os.makedirs(src, exist_ok=True)

    def copied(prefix, files):
        paths = []
        for f in every(files, n):
            dst = os.path.join(src, f"{prefix}-{os.path.basename(f)}")
            with open(f, "rb") as a, open(dst, "wb") as b:
                b.write(a.read())
            paths.append(dst)
        return paths

    return {
        "fluent": copied("fluent", glob.glob(os.path.join(MODULES, "fluentui-emoji", "icons", "flat", "*.svg"))),
        "noto": noto_files(src, n),
        "twemoji": copied("twemoji", glob.glob(os.path.join(MODULES, "@twemoji", "svg", "*.svg"))),
        "tabler": copied("tabler", glob.glob(os.path.join(MODULES, "@tabler", "icons", "icons", "filled", "*.svg"))),
    }


def run_gmotion(gm, files, out):
    """gmotion's PNG and Lottie of every file, each a batch into its folder."""
    for fmt in ("png", "json"):
        d = os.path.join(out, "gm-" + fmt)
        os.makedirs(d, exist_ok=True)
        subprocess.run([gm, "-q", "--format", fmt, "convert", *files, "-o", d + "/", "--width", str(WIDTH)],
                       capture_output=True)


def run_python_lottie(files, out):
    from lottie.parsers.svg import parse_svg_file

    def alarm(_s, _f):
        raise TimeoutError()

    signal.signal(signal.SIGALRM, alarm)
    d = os.path.join(out, "pl-json")
    os.makedirs(d, exist_ok=True)
    for f in files:
        try:
            signal.alarm(40)
            text = json.dumps(parse_svg_file(f).to_dict())
            signal.alarm(0)
            with open(os.path.join(d, stem(f) + ".json"), "w", encoding="utf-8") as g:
                g.write(text)
        except BaseException as e:  # noqa: BLE001 - python-lottie may fail on any input
            signal.alarm(0)
            if isinstance(e, KeyboardInterrupt):
                raise


def stem(path):
    return os.path.splitext(os.path.basename(path))[0]


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("gmotion")
    ap.add_argument("out")
    ap.add_argument("--per-set", type=int, default=150)
    ap.add_argument("--python-lottie", action="store_true")
    args = ap.parse_args(argv)
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    install()
    by_set = sets(out, args.per_set)
    files = [f for fs in by_set.values() for f in fs]

    chrome_dir = os.path.join(out, "chromium")
    os.makedirs(chrome_dir, exist_ok=True)
    jobs = [{"svg": f, "width": WIDTH, "out_prefix": os.path.join(chrome_dir, stem(f)), "times": [0]} for f in files]
    with open(os.path.join(out, "smil_jobs.json"), "w") as f:
        json.dump(jobs, f)
    subprocess.run(["node", os.path.join(HERE, "smil.mjs"), "--jobs", os.path.join(out, "smil_jobs.json")],
                   capture_output=True)

    run_gmotion(args.gmotion, files, out)
    lw = []
    converters = [("gmotion PNG", None), ("gmotion Lottie", "gm-json")]
    if args.python_lottie:
        run_python_lottie(files, out)
        converters.append(("python-lottie Lottie", "pl-json"))
    for _, d in converters:
        if d is None:
            continue
        for f in files:
            j = os.path.join(out, d, stem(f) + ".json")
            if os.path.exists(j):
                lw.append({"json": j, "width": WIDTH, "frames": [0], "out": [os.path.join(out, d, stem(f) + ".lw.png")]})
    with open(os.path.join(out, "lw_jobs.json"), "w") as f:
        json.dump(lw, f)
    subprocess.run(["node", os.path.join(HERE, "lottie_web.mjs"), os.path.join(out, "lw_jobs.json")], capture_output=True)

    def drawn(conv, f):
        if conv == "gmotion PNG":
            return os.path.join(out, "gm-png", stem(f) + ".png")
        d = "gm-json" if conv == "gmotion Lottie" else "pl-json"
        return os.path.join(out, d, stem(f) + ".lw.png")

    failures = {}
    totals = {c: 0 for c, _ in converters}
    print(f"{'set':10s} " + " ".join(f"{c:>22s}" for c, _ in converters))
    for name, fs in by_set.items():
        row = []
        for conv, _ in converters:
            ok = 0
            for f in fs:
                off = off_fraction(os.path.join(chrome_dir, stem(f) + "-0.png"), drawn(conv, f))
                if off is not None and off <= CORPUS_MAX:
                    ok += 1
                else:
                    failures.setdefault(conv, []).append((stem(f), off))
            totals[conv] += ok
            row.append(f"{ok:4d}/{len(fs):<4d} {ok / len(fs) * 100:5.1f}%")
        print(f"{name:10s} " + " ".join(f"{r:>22s}" for r in row))
    n = len(files)
    print(f"{'all':10s} " + " ".join(f"{f'{totals[c]:4d}/{n:<4d} {totals[c] / n * 100:5.1f}%':>22s}" for c, _ in converters))
    for conv, fails in failures.items():
        if conv.startswith("gmotion"):
            for name, off in fails:
                how = "nothing drawn" if off is None else f"{off * 100:.2f}% off"
                print(f"  {conv} fails {name}: {how}")
    status = 0
    played = {stem(f) for f in files}
    for conv, known in KNOWN.items():
        failed = {name for name, _ in failures.get(conv, [])}
        for name in sorted(failed - known.keys()):
            print(f"icons: {conv} fails {name}, which is not a known failure")
            status = 1
        for name in sorted((known.keys() & played) - failed):
            print(f"icons: {conv} passes {name} now; take it off KNOWN")
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
