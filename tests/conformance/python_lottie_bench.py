"""python-lottie's load and export of the Lottie corpus, timed for the README's comparison
with `cargo bench --bench lottie` (the same files, the same work: JSON text in, JSON text
out).

    python3 python_lottie_bench.py FOLDER [--repeat N]

Prints the best of N passes over every file (seconds) and the files python-lottie could
not take.
"""

import argparse
import json
import os
import sys
import time

from lottie.objects import Animation


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("folder")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    texts = []
    for f in sorted(os.listdir(args.folder)):
        if f.endswith(".json"):
            with open(os.path.join(args.folder, f)) as fh:
                texts.append((f, fh.read()))
    failed = set()
    best = float("inf")
    for _ in range(args.repeat):
        start = time.perf_counter()
        for name, text in texts:
            try:
                json.dumps(Animation.load(json.loads(text)).to_dict())
            except Exception:  # noqa: BLE001 - a file it cannot take is counted, not fatal
                failed.add(name)
        best = min(best, time.perf_counter() - start)
    print(f"python-lottie load + export of {len(texts)} files: best of {args.repeat}: {best:.3f} s")
    print(f"failed: {len(failed)} {sorted(failed)}")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
