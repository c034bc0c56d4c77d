"""Renders Lottie frames with rlottie (PyPI rlottie-python) to transparent PNGs.

    python3 rlottie_render.py JOBS.json

JOBS.json is the job list lottie_web.mjs reads:
[{"json": "a.json", "width": 300, "frames": [0, 5], "out": ["a-0.png", "a-5.png"]}, ...].
A job that fails is reported on stderr and its PNGs are not written.
"""

import json
import sys

import numpy as np
from PIL import Image
from rlottie_python import LottieAnimation


def render(job):
    anim = LottieAnimation.from_file(job["json"])
    try:
        w0, h0 = anim.lottie_animation_get_size()
        width = int(job["width"])
        height = max(1, round(width * h0 / w0))
        for frame, out in zip(job["frames"], job["out"]):
            buf = anim.lottie_animation_render(frame_num=int(frame), width=width, height=height)
            # rlottie writes premultiplied BGRA; PNG wants straight RGBA.
            px = np.frombuffer(bytes(buf), dtype=np.uint8).reshape(height, width, 4)[..., [2, 1, 0, 3]].astype(np.float64)
            a = px[..., 3:4]
            rgb = np.where(a > 0, np.clip(px[..., :3] * 255.0 / np.maximum(a, 1), 0, 255), 0)
            img = np.concatenate([rgb, a], axis=2).round().astype(np.uint8)
            Image.fromarray(img, "RGBA").save(out)
    finally:
        anim.lottie_animation_destroy()


def main(argv):
    with open(argv[1], encoding="utf-8") as f:
        jobs = json.load(f)
    failed = 0
    for job in jobs:
        try:
            render(job)
        except Exception as e:  # noqa: BLE001 - any player failure is reported per file
            failed += 1
            print(f"rlottie: {job['json']}: {e}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
