"""Renders Lottie frames with rlottie (PyPI rlottie-python) to transparent PNGs.

    python3 rlottie_render.py JOBS.json | --serve   (player_jobs.py: the jobs and the modes)
"""

import sys

import numpy as np
from PIL import Image
from rlottie_python import LottieAnimation

import player_jobs


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


if __name__ == "__main__":
    sys.exit(player_jobs.main("rlottie", render, sys.argv))
