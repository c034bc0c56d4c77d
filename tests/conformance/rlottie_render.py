"""Renders Lottie frames with rlottie (PyPI rlottie-python) to transparent PNGs.

    python3 rlottie_render.py JOBS.json | --serve   (player_jobs.py: the jobs and the modes)
"""

import sys

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
            player_jobs.save_premultiplied(buf, width, height, "BGRa", out)
    finally:
        anim.lottie_animation_destroy()


if __name__ == "__main__":
    sys.exit(player_jobs.main("rlottie", render, sys.argv))
