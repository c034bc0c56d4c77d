"""Same output: runs a gmotion binary over every example (Lottie, SMIL, PNG, GIF, one HTML
page, a frame at t = 0.7 s), every generated case of the full conformance matrix, and the
Lottie corpus (converted, and under a small grammar to Lottie, SMIL and a PNG frame), writing
every output and a status line per run (exit status and the end of its messages) under OUT.
Run it with the binary before and after a change that must not change behaviour (a
refactoring), then compare the two folders:

    python3 scripts/same_output.py OLD_GMOTION target/same-old
    python3 scripts/same_output.py target/quick/gmotion target/same-new
    diff -rq target/same-old target/same-new && echo identical

The Lottie corpus is fetched by tests/conformance/install.sh. About 700 runs, 40 s on two
cores.
"""

import concurrent.futures
import glob
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "conformance"))
import matrix  # noqa: E402  (the conformance matrix's case generator)

# A grammar any Lottie scene takes: every unit turns and shrinks, staggered by id, and back.
LOTTIE_GRAMMAR = (
    "duration 2s\nfps 30\n"
    "timesplit(0.5, 0.5) : [all, all] -> [a, inv_a]\n"
    "animate(affine, local, 0.1 * id, rotate(20) scale(0.9)) : [a, all] -> [m]\n"
)


def outputs(out, name, exts):
    """`-o OUT/NAME.EXT` for each extension."""
    return [arg for e in exts for arg in ("-o", f"{out}/{name}{e}")]


def jobs(gm, out):
    """(name, command) of every run."""
    runs = []
    g = os.path.join(ROOT, "grammars")
    for path in sorted(glob.glob(g + "/*.gm")):
        name = os.path.basename(path)[:-3]
        # The two largest examples' pictures take most of the time and add no code path.
        big = name in ("intersections", "statue")
        exts = [".json", ".svg"] if big else [".json", ".svg", ".png", ".gif"]
        runs.append((f"ex-{name}", [gm, "animate", path] + outputs(out, f"ex-{name}", exts)))
        if name == "toy":
            runs.append(("html-toy", [gm, "animate", path, "-o", f"{out}/toy.html"]))
        runs.append((f"exf-{name}", [gm, "animate", path, "--time", "0.7", "-o", f"{out}/exf-{name}.png"]))
    for path in sorted(glob.glob(g + "/*.targets.json")):
        name = os.path.basename(path)[: -len(".targets.json")]
        runs.append((f"tr-{name}", [gm, "transitions", f"{g}/{name}.svg", path] + outputs(out, f"tr-{name}", [".json", ".svg"])))
    _, cases, _, _ = matrix.select(["--matrix", "full"])
    cases_dir = os.path.join(out, "cases")
    os.makedirs(cases_dir, exist_ok=True)
    for case in cases:
        dims, name = case["dims"], case["name"]
        if case["family"] not in ("gm", "tr"):
            continue  # the examples, run above
        scene = f"{cases_dir}/{name}.scene.svg"
        with open(scene, "w", encoding="utf-8") as f:
            f.write(matrix.scene_svg(dims["scene"]))
        if case["family"] == "gm":
            src, text, args, command = f"{cases_dir}/{name}.gm", matrix.grammar(dims), [], "animate"
        else:
            fname, text, args, _ = matrix.targets(dims)
            src, command = f"{cases_dir}/{name}.{fname}", "transitions"
        with open(src, "w", encoding="utf-8") as f:
            f.write(text)
        cmd = [gm, command, scene, src] + args + outputs(out, name, [".json", ".svg"])
        runs.append((name, cmd + ["--tolerance", matrix.TOLERANCE]))
    grammar = os.path.join(out, "units.gm")
    with open(grammar, "w", encoding="utf-8") as f:
        f.write(LOTTIE_GRAMMAR)
    corpus = os.path.join(ROOT, "tests", "conformance", "lottie-corpus")
    for path in sorted(glob.glob(corpus + "/**/*.json", recursive=True)):
        name = "lc-" + os.path.basename(path)[:-5]
        runs.append((name, [gm, "convert", path] + outputs(out, name, [".json", ".svg"])))
        runs.append((name + "-g", [gm, "animate", path, grammar] + outputs(out, name + "-g", [".json", ".svg"])))
        runs.append((name + "-f", [gm, "animate", path, grammar, "--time", "0.5", "-o", f"{out}/{name}-f.png"]))
    return runs


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    gm, out = os.path.abspath(argv[1]), os.path.abspath(argv[2])
    os.makedirs(out, exist_ok=True)

    def run(job):
        name, cmd = job
        r = subprocess.run(cmd, capture_output=True, text=True, cwd=out)
        # Messages name the output folder: written as OUT so two folders compare equal.
        return name, r.returncode, r.stderr.replace(out, "OUT").strip()[-200:]

    runs = jobs(gm, out)
    with open(os.path.join(out, "status.txt"), "w", encoding="utf-8") as status:
        with concurrent.futures.ThreadPoolExecutor(2) as pool:
            for name, code, err in pool.map(run, runs):
                status.write(f"{name} {code} {err!r}\n")
    print(f"{len(runs)} runs written to {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
