"""Renders Lottie frames with ThorVG (PyPI thorvg-python, which bundles libthorvg) to
transparent PNGs.

    python3 thorvg_render.py JOBS.json | --serve   (player_jobs.py: the jobs and the modes)
"""

import os
import sys

import numpy as np
import thorvg_python as tvg
from PIL import Image

import player_jobs


def check(result, what):
    if result != tvg.Result.SUCCESS:
        raise RuntimeError(f"{what}: {result.name}")


def render(engine, job):
    anim = tvg.Animation(engine)
    canvas = None
    try:
        pic = anim.get_picture()
        check(pic.load(os.path.abspath(job["json"])), "load")
        _, w0, h0 = pic.get_size()
        width = int(job["width"])
        height = max(1, round(width * h0 / w0))
        check(pic.set_size(width, height), "set_size")
        canvas = tvg.SwCanvas(engine)
        # ABGR8888 is premultiplied, laid out as the bytes R, G, B, A (little-endian).
        check(canvas.set_target(width, height, cs=tvg.Colorspace.ABGR8888), "set_target")
        check(canvas.add(pic), "add")
        for frame, out in zip(job["frames"], job["out"]):
            anim.set_frame(float(frame))  # INSUFFICIENT_CONDITION when already at this frame
            check(canvas.update(), "update")
            check(canvas.draw(True), "draw")
            check(canvas.sync(), "sync")
            px = np.frombuffer(bytes(canvas.buffer_arr), dtype=np.uint8).reshape(height, width, 4).astype(np.float64)
            a = px[..., 3:4]
            rgb = np.where(a > 0, np.clip(px[..., :3] * 255.0 / np.maximum(a, 1), 0, 255), 0)
            Image.fromarray(np.concatenate([rgb, a], axis=2).round().astype(np.uint8), "RGBA").save(out)
    finally:
        if canvas is not None:
            canvas.destroy()
        anim._del()


if __name__ == "__main__":
    engine = tvg.Engine(threads=0)
    sys.exit(player_jobs.main("thorvg", lambda job: render(engine, job), sys.argv))
