#!/usr/bin/env python3
"""Builds a frame strip (a grid of PNG frames) for the README from a frames directory.

usage: strip.py FRAMES_DIR OUT.png [COLUMNS]
"""
import sys
from pathlib import Path

from PIL import Image

frames = sorted(Path(sys.argv[1]).glob("frame_*.png"))
cols = int(sys.argv[3]) if len(sys.argv) > 3 else 6
if not frames:
    sys.exit(f"no frame_*.png in {sys.argv[1]}")
imgs = [Image.open(f).convert("RGBA") for f in frames]
w, h = imgs[0].size
rows = (len(imgs) + cols - 1) // cols
sheet = Image.new("RGBA", (cols * (w + 4), rows * (h + 4)), (255, 255, 255, 255))
for i, im in enumerate(imgs):
    sheet.alpha_composite(im, ((i % cols) * (w + 4), (i // cols) * (h + 4)))
sheet.save(sys.argv[2])
