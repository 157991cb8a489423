#!/usr/bin/env python3
"""A contact sheet of morphs: frames at t = 0, ¼, ½, ¾, 1 of each pair, one row per pair.

    python3 tools/sheet/sheet.py CRMORPH OUT.png PAIR...

PAIR is a folder holding source.svg and target.svg, or SOURCE.svg,TARGET.svg. Frames are rendered
by `CRMORPH frame --at T --size 120x120 --background white`. Needs Pillow (pip install pillow).
docs/icons-frames.png is `tools/sheet/sheet.py target/release/crmorph docs/icons-frames.png
fixtures/icons/*/`.
"""
import os
import subprocess
import sys
import tempfile

from PIL import Image, ImageDraw

TIMES = [0, 0.25, 0.5, 0.75, 1]
CELL = 120
LABEL = 170


def main():
    binary, out, pairs = sys.argv[1], sys.argv[2], sys.argv[3:]
    sheet = Image.new("RGB", (LABEL + CELL * len(TIMES), CELL * len(pairs)), "white")
    draw = ImageDraw.Draw(sheet)
    tmp = tempfile.mkdtemp()
    for row, pair in enumerate(pairs):
        if os.path.isdir(pair):
            src, tgt = os.path.join(pair, "source.svg"), os.path.join(pair, "target.svg")
            name = os.path.basename(pair.rstrip("/"))
        else:
            src, tgt = pair.split(",")
            name = os.path.basename(src)[:-4] + " → " + os.path.basename(tgt)[:-4]
        draw.text((5, row * CELL + CELL // 2 - 6), name[:28], fill="black")
        for col, t in enumerate(TIMES):
            png = os.path.join(tmp, f"{row}-{col}.png")
            run = subprocess.run(
                [binary, "frame", src, tgt, "--at", str(t), "-o", png,
                 "--size", f"{CELL}x{CELL}", "--background", "white", "--quiet"],
                capture_output=True, text=True)
            if run.returncode == 0:
                sheet.paste(Image.open(png).convert("RGB"), (LABEL + col * CELL, row * CELL))
            else:
                draw.text((LABEL + col * CELL + 5, row * CELL + 50), "failed", fill="red")
                print(f"{name} at t = {t}: {run.stderr.strip()}", file=sys.stderr)
    sheet.save(out)


if __name__ == "__main__":
    main()
