"""gmotion's own render of Lottie files against the players (issue 15's "own render").

    python3 lottie_own_render.py GMOTION OUT FOLDER... [--max-files N] [--grammar [--groups]]

Plays every `*.json` of FOLDER at 5 evenly spaced frames (ip + k·(op − ip)/5) in lottie-web
(svg renderer), rlottie and `gmotion convert X.json -o f.png --time T`, and compares each
frame as conformance.py does (a pixel is off when a premultiplied channel differs by more
than OFF; a frame matches when at most 1% of its pixels are off). The players are the
oracle only where they agree with each other: a file counts when lottie-web and rlottie
match at all 5 frames, and gmotion passes it when it matches lottie-web at all 5. rlottie
draws no text layers, so for a file with text the second player is ThorVG.

With --grammar, every file gets motion on top first, as a user adds it (issue 15's "a
grammar on top"): every unit turns 90° over the composition's length, the first unit's tag
fades to half, the last unit's turns blue and its strokes three times as wide; the players play the
Lottie `gmotion animate` writes (the source with gmotion's null layers on top) and gmotion draws `animate … -o f.png --time T` itself.
With --groups as well, the grammar says `units groups`: the units are the top-level groups
of shape layers, whose motion gmotion writes as new groups around them.

Writes OUT/report.json and prints, per file, the worst frame. Exits 1 when a counted file
fails that KNOWN_FAILURES does not name (each with why), so that no new failure hides behind
a pass rate, and when a named file passes: its entry must come off the list, or it would
hide the file failing again.
"""

import argparse
import json
import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

from conformance import off_fraction

HERE = os.path.dirname(os.path.abspath(__file__))
FRAMES = 5
MATCH = 0.01

# Files where lottie-web and rlottie agree but gmotion's own render does not match them.
KNOWN_FAILURES = {
    "rlottie-python__file_transfer.json": "1.1-1.7% of pixels: 1 px strokes anti-aliased differently at mid-motion frames",
}

# The same with a grammar on top (--grammar). (like.json and mask.json left this list when
# a solid layer whose colour changes became a shape layer.)
KNOWN_GRAMMAR_FAILURES = dict(KNOWN_FAILURES)

# The same with the top-level groups of shape layers as units (--grammar --groups).
KNOWN_GROUPS_FAILURES = dict(KNOWN_GRAMMAR_FAILURES)


def grammar_on_top(gm, src, doc, out, stem, groups):
    """Writes the grammar for `src` and its layered Lottie; returns (grammar, lottie) paths,
    or an error line."""
    units = ["--units", "groups"] if groups else []
    r = subprocess.run([gm, "check", "--shapes", *units, src], capture_output=True, text=True, timeout=300)
    # A unit's line is `  TAG:ID  box …`; the other indented lines (`measured at frame …`,
    # a package's animations) are not units.
    tags = [m.group(1) for m in (re.match(r"  (\S+):\d+\s", line) for line in r.stdout.splitlines()[1:]) if m]
    if r.returncode != 0 or not tags:
        return r.stderr.strip().splitlines()[-1:] or ["no units"]
    fr = float(doc["fr"])
    grammar = os.path.join(out, f"{stem}.gm")
    with open(grammar, "w") as f:
        f.write(("units groups\n" if groups else "") +
                f"duration {(doc['op'] - doc['ip']) / fr!r}s\nfps {fr!r}\n"
                "animate(affine, local, 0, rotate(90)) : [all, all] -> [turned]\n"
                f"animate(opacity, local, 0, 0.5) : [turned, {tags[0]}] -> [faded]\n"
                f"animate(fill, local, 0, #3366ff) : [turned, {tags[-1]}] -> [blue]\n"
                f"animate(stroke-width, local, 0, 3) : [blue, {tags[-1]}] -> [wide]\n")
    lottie = os.path.join(out, f"{stem}-layered.json")
    r = subprocess.run([gm, "animate", src, grammar, "-o", lottie], capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        return r.stderr.strip().splitlines()[-1:]
    return grammar, lottie


def render_width(w, h):
    """About 300 px wide, nudged so that the height is a whole number of pixels: every
    renderer then scales by the same factor."""
    return min(range(240, 361), key=lambda x: (abs(x * h / w - round(x * h / w)) > 1e-9, abs(x - 300)))


def frames_of(doc):
    span = doc["op"] - doc["ip"]
    return sorted({min(int(round(k * span / FRAMES)), max(int(span) - 1, 0)) for k in range(FRAMES)})


def has_text(doc):
    """Whether a text layer is anywhere in the document."""
    comps = [doc.get("layers") or []] + [a.get("layers") or [] for a in doc.get("assets") or []]
    return any(isinstance(l, dict) and l.get("ty") == 5 for layers in comps for l in layers)


def run_players(jobs, out):
    """Starts lottie-web and the second player (rlottie, or ThorVG for the jobs marked
    `text`) on `jobs` and answers them running (see `wait_players`)."""
    path = os.path.join(out, "jobs.json")
    with open(path, "w") as f:
        json.dump(jobs, f)

    def named(js, who):
        return [{k: v for k, v in dict(j, out=[p.replace("{player}", who) for p in j["out"]]).items() if k != "text"}
                for j in js]

    started = []
    for name, js, cmd in [
        ("lottie-web", named(jobs, "lottie-web"), ["node", os.path.join(HERE, "lottie_web.mjs")]),
        ("rlottie", named([j for j in jobs if not j["text"]], "second"),
         [sys.executable, os.path.join(HERE, "rlottie_render.py")]),
        ("thorvg", named([j for j in jobs if j["text"]], "second"),
         [sys.executable, os.path.join(HERE, "thorvg_render.py"), "--each"]),
    ]:
        if not js:
            continue
        p = os.path.join(out, f"jobs-{name}.json")
        with open(p, "w") as f:
            json.dump(js, f)
        # stderr to a file: a pipe nobody reads until the end could fill and stall a player.
        log = open(os.path.join(out, f"{name}.log"), "w+")
        started.append((subprocess.Popen(cmd + [p], stdout=subprocess.DEVNULL, stderr=log), log))
    return started


def wait_players(started):
    """Waits for the players `run_players` started, passing on what they said."""
    for proc, log in started:
        proc.wait(timeout=3600)
        log.seek(0)
        for line in log.read().splitlines():
            print(f"  {line}", file=sys.stderr)
        log.close()


def gmotion_frame(gm, src, grammar, fr, frame, width, png):
    t = frame / fr
    how = ["animate", src, grammar] if grammar else ["convert", src]
    r = subprocess.run(
        [gm, *how, "-o", png, "--time", repr(t), "--width", str(width)],
        capture_output=True, text=True, timeout=300,
    )
    return None if r.returncode == 0 else r.stderr.strip().splitlines()[-1:]


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("gmotion")
    ap.add_argument("out")
    ap.add_argument("folders", nargs="+")
    ap.add_argument("--max-files", type=int, default=0)
    ap.add_argument("--grammar", action="store_true")
    ap.add_argument("--groups", action="store_true")
    args = ap.parse_args(argv)
    known = (KNOWN_GROUPS_FAILURES if args.groups else KNOWN_GRAMMAR_FAILURES) if args.grammar else KNOWN_FAILURES
    os.makedirs(args.out, exist_ok=True)
    files = sorted((f, os.path.join(d, f)) for d in args.folders for f in os.listdir(d) if f.endswith(".json"))
    if args.max_files:
        files = files[: args.max_files]
    docs, jobs, gm_errors = {}, [], {}
    for name, path in files:
        try:
            with open(path) as f:
                doc = json.load(f)
            w, h, fr = float(doc["w"]), float(doc["h"]), float(doc["fr"])
            frames = frames_of(doc)
        except Exception as e:  # noqa: BLE001 - a file the players cannot take is skipped, said
            print(f"{name}: skipped ({e})")
            continue
        stem = name[:-5]
        width = render_width(w, h)
        grammar, played = None, path
        if args.grammar:
            made = grammar_on_top(args.gmotion, path, doc, args.out, stem, args.groups)
            if isinstance(made, list):
                print(f"{name}: gmotion animate failed: {made}")
                gm_errors[name] = made
                continue
            grammar, played = made
        docs[name] = (path, grammar, fr, frames, width, stem)
        jobs.append({"json": played, "width": width, "frames": frames, "text": has_text(doc),
                     "out": [os.path.join(args.out, f"{stem}-{f}-{{player}}.png") for f in frames]})
    # The players run while gmotion renders the same frames: lottie-web in Chromium leaves
    # a core idle much of the time.
    players = run_players(jobs, args.out)

    def gm_file(name):
        path, grammar, fr, frames, width, stem = docs[name]
        for f in frames:
            png = os.path.join(args.out, f"{stem}-{f}-gmotion.png")
            err = gmotion_frame(args.gmotion, path, grammar, fr, f, width, png)
            if err:
                gm_errors[name] = err
                return

    with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
        list(pool.map(gm_file, docs))
    wait_players(players)
    report, counted, passed = {}, 0, 0
    for name, (path, grammar, fr, frames, width, stem) in docs.items():
        png = lambda f, who: os.path.join(args.out, f"{stem}-{f}-{who}.png")  # noqa: E731
        players = [off_fraction(png(f, "lottie-web"), png(f, "second")) for f in frames]
        ours = [off_fraction(png(f, "lottie-web"), png(f, "gmotion")) for f in frames]
        agree = all(p is not None and p <= MATCH for p in players)
        ok = agree and all(o is not None and o <= MATCH for o in ours)
        counted += agree
        passed += ok
        report[name] = {"frames": frames, "players": players, "gmotion": ours, "agree": agree, "pass": ok,
                        "error": gm_errors.get(name)}
        worst = max((o if o is not None else 1.0) for o in ours)
        flag = "pass" if ok else ("FAIL" if agree else "(players disagree)")
        if has_text(json.load(open(path))):
            flag += " [text: ThorVG is the second player]"
        print(f"{name}: {flag}  worst frame off {worst:.2%}" + (f"  {gm_errors[name]}" if name in gm_errors else ""))
    with open(os.path.join(args.out, "report.json"), "w") as f:
        json.dump(report, f, indent=1)
    share = passed / counted if counted else 0.0
    print(f"\n{passed} of {counted} files where lottie-web and a second player agree pass ({share:.1%}); "
          f"{len(docs)} files played")
    new = [n for n, r in report.items() if r["agree"] and not r["pass"] and n not in known]
    fixed = [n for n in known if report.get(n, {}).get("pass")]
    for n in fixed:
        print(f"{n}: passes now; take it off the known failures")
    for n in new:
        print(f"{n}: FAILS and is not a known failure")
    # A grammar that could not be made or run on a file is a failure too: a check that plays
    # nothing passes nothing.
    unmade = [n for n in gm_errors if n not in docs and n not in known]
    for n in unmade:
        print(f"{n}: FAILS: no layered export to play")
    # An entry that outlives its reason would hide the file failing again: both fail the run.
    return 1 if new or fixed or unmade else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
