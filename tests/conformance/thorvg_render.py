"""Renders Lottie frames with ThorVG (PyPI thorvg-python, which bundles libthorvg) to
transparent PNGs.

    python3 thorvg_render.py JOBS.json | --serve   (player_jobs.py: the jobs and the modes)
"""

import os
import sys

import thorvg_python as tvg

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
            player_jobs.save_premultiplied(canvas.buffer_arr, width, height, "RGBa", out)
    finally:
        if canvas is not None:
            canvas.destroy()
        anim._del()


if __name__ == "__main__":
    engine = tvg.Engine(threads=0)
    sys.exit(player_jobs.main("thorvg", lambda job: render(engine, job), sys.argv))
