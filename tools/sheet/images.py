#!/usr/bin/env python3
"""docs/images-frames.png: the image pairs of fixtures/images morphed, frames at t = 0, 1/4, 1/2,
3/4, 1 (the faces steered by their --controls files, the character by its traced outline).

    python3 tools/sheet/images.py target/release/crmorph docs/images-frames.png

Frames are rendered by `crmorph frame`; needs Pillow (pip install pillow).
"""
import os
import subprocess
import sys
import tempfile

from PIL import Image

ROOT = os.path.join(os.path.dirname(__file__), "..", "..", "fixtures", "images")
PAIRS = [
    ("faces", ["--controls", "faces/source-controls.svg", "faces/target-controls.svg"]),
    ("character", []),
]
CELL = (200, 240)
PAD = 6


def flat(path):
    im = Image.open(path).convert("RGBA")
    bg = Image.new("RGBA", im.size, "white")
    bg.alpha_composite(im)
    return bg.convert("RGB")


def main():
    binary, out = sys.argv[1], sys.argv[2]
    tmp = tempfile.mkdtemp()
    sheet = Image.new(
        "RGB", (5 * (CELL[0] + PAD) + PAD, len(PAIRS) * (CELL[1] + PAD) + PAD), "white"
    )
    for row, (name, extra) in enumerate(PAIRS):
        src = os.path.join(ROOT, name, "source.png")
        tgt = os.path.join(ROOT, name, "target.png")
        extra = [os.path.join(ROOT, e) if e.endswith(".svg") else e for e in extra]
        cells = [flat(src)]
        for t in (0.25, 0.5, 0.75):
            png = os.path.join(tmp, f"{name}-{t}.png")
            subprocess.run(
                [binary, "frame", src, tgt, *extra, "--at", str(t), "-o", png, "-q"],
                check=True,
            )
            cells.append(flat(png))
        cells.append(flat(tgt))
        for i, im in enumerate(cells):
            x = PAD + i * (CELL[0] + PAD) + (CELL[0] - im.size[0]) // 2
            y = PAD + row * (CELL[1] + PAD) + (CELL[1] - im.size[1]) // 2
            sheet.paste(im, (x, y))
    sheet.save(out, optimize=True)


if __name__ == "__main__":
    main()
