#!/usr/bin/env python3
"""Lottie export over the random icon corpus (tools/corpus, seed 2026): for every pair, crmorph
writes the animated SVG, Lottie JSON and the dotLottie archive (400 px on white); the JSON is
validated against the Lottie schema; lottie-web in headless Chromium shows frame t = 0.5, which is
compared with `crmorph frame --at 0.5` (the tolerance of cli/tests/external/lottie.rs). As a
control, crmorph's animated SVG paused at t = 0.5 in the same Chromium is compared with the same
frame and tolerance: what differs there is the renderers' antialiasing, not Lottie. Prints the
rates over the whole corpus and the sizes, and writes one JSON line per pair.

Usage: python3 tools/lottie/corpus.py CRMORPH [--pairs N] [--out report.jsonl]
Needs: the corpus (node tools/corpus/draw.js --seed 2026 --pairs 320 --out
tools/corpus/.cache/corpus), `npm ci --prefix tools/lottie`, chromium, node, Pillow.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

from PIL import Image, ImageChops

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "corpus", ".cache", "corpus")
SIZE = 400


def difference(a, b):
    """(mean, share > 32, share > 64) of the per-pixel max channel difference."""
    d = ImageChops.difference(a.convert("RGB"), b.convert("RGB"))
    r, g, bl = d.split()
    # The per-pixel maximum of the three channels, as one band.
    m = ImageChops.lighter(ImageChops.lighter(r, g), bl)
    hist = m.histogram()
    n = sum(hist)
    mean = sum(v * c for v, c in enumerate(hist)) / n
    return mean, sum(hist[33:]) / n, sum(hist[65:]) / n


def matches(diff):
    mean, o32, o64 = diff
    return mean <= 3.0 and o32 <= 0.01 and o64 <= 0.005


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("crmorph")
    ap.add_argument("--pairs", type=int, default=0, help="only the first N pairs")
    ap.add_argument("--out", default="lottie-corpus.jsonl")
    args = ap.parse_args()
    pairs = json.load(open(os.path.join(ROOT, "pairs.json")))["pairs"]
    if args.pairs:
        pairs = pairs[: args.pairs]
    work = tempfile.mkdtemp(prefix="lottie-corpus-")
    server = subprocess.Popen(
        ["node", os.path.join(HERE, "serve.mjs"), HERE, work], stdout=subprocess.PIPE, text=True
    )
    port = int(server.stdout.readline())
    rows = []
    try:
        for p in pairs:
            pid = p["id"]
            src, tgt = os.path.join(ROOT, p["source"]), os.path.join(ROOT, p["target"])
            common = ["--size", f"{SIZE}x{SIZE}", "--background", "white"]
            row = {"id": pid, "source": p["source"], "target": p["target"]}
            files = {k: os.path.join(work, f"{pid}.{k}") for k in ["svg", "lottie.json", "lottie"]}
            notes = ""
            ok = True
            for k, f in files.items():
                r = subprocess.run(
                    [args.crmorph, "morph", src, tgt, "-o", f, *common],
                    capture_output=True, text=True, timeout=600,
                )
                if r.returncode != 0:
                    ok = False
                    row["error"] = r.stderr.strip()
                    break
                if k == "lottie.json":
                    notes = r.stderr
                row[f"bytes_{k}"] = os.path.getsize(f)
            row["ok"] = ok
            row["notes"] = sorted(
                {l.split(": ", 2)[-1] for l in notes.splitlines() if ".lottie.json:" in l}
            )
            if ok:
                v = subprocess.run(
                    ["node", os.path.join(HERE, "validate.mjs"), files["lottie.json"]],
                    capture_output=True, text=True,
                )
                row["schema_ok"] = v.returncode == 0
                ref = os.path.join(work, f"{pid}-ref.png")
                subprocess.run(
                    [args.crmorph, "-q", "frame", src, tgt, "--at", "0.5", "-o", ref, *common],
                    check=True,
                )
                svg = open(files["svg"]).read()
                page = os.path.join(work, f"{pid}-svg.html")
                with open(page, "w") as f:
                    f.write(
                        "<!doctype html><html><head><style>html,body{margin:0;padding:0;"
                        "background:#fff;overflow:hidden}svg{display:block}</style></head><body>"
                        + svg
                        + "<script>const s=document.querySelector('svg');s.pauseAnimations();"
                        "s.setCurrentTime(1.0);</script></body></html>"
                    )
                urls = {
                    "lottie_web": f"player.html?player=lottie-web&src=/work/{pid}.lottie.json"
                    f"&frame=60&w={SIZE}&h={SIZE}",
                    "animated_svg": f"work/{pid}-svg.html",
                }
                for key, url in urls.items():
                    shot = os.path.join(work, f"{pid}-{key}.png")
                    profile = tempfile.mkdtemp(prefix="chromium-")
                    subprocess.run(
                        ["chromium", "--headless", "--no-sandbox", "--disable-gpu",
                         "--disable-background-networking", "--no-first-run",
                         "--hide-scrollbars", "--force-device-scale-factor=1",
                         f"--user-data-dir={profile}", f"--window-size={SIZE},{SIZE}",
                         "--virtual-time-budget=10000", f"--screenshot={shot}",
                         f"http://127.0.0.1:{port}/{url}"],
                        capture_output=True, timeout=120,
                    )
                    shutil.rmtree(profile, ignore_errors=True)
                    if os.path.exists(shot):
                        d = difference(Image.open(shot), Image.open(ref))
                        row[key] = [round(x, 5) for x in d]
                        row[f"{key}_ok"] = matches(d)
                    else:
                        row[f"{key}_ok"] = False
            rows.append(row)
            print(json.dumps(row), flush=True)
    finally:
        server.kill()
    with open(args.out, "w") as f:
        for r in rows:
            f.write(json.dumps(r) + "\n")
    n = len(rows)
    made = [r for r in rows if r["ok"]]
    print(f"pairs {n}; exported {len(made)} ({100 * len(made) / n:.1f} %)")
    print(f"schema: 0 errors in {sum(r.get('schema_ok', False) for r in rows)} of {n}")
    for key, what in [("lottie_web", "Lottie JSON in lottie-web"),
                      ("animated_svg", "animated SVG in Chromium (control)")]:
        ok = sum(r.get(f"{key}_ok", False) for r in rows)
        print(f"{what} at t = 0.5 within tolerance: {ok} of {n} ({100 * ok / n:.1f} %)")
    noted = {}
    for r in rows:
        for note in r["notes"]:
            noted[note] = noted.get(note, 0) + 1
    for note, c in sorted(noted.items(), key=lambda x: -x[1]):
        print(f"  note on {c} pairs: {note}")
    for k in ["svg", "lottie.json", "lottie"]:
        sizes = sorted(r[f"bytes_{k}"] for r in made)
        if sizes:
            print(f"{k}: median {statistics.median(sizes) / 1024:.1f} KiB, "
                  f"p90 {sizes[int(0.9 * (len(sizes) - 1))] / 1024:.1f} KiB, "
                  f"total {sum(sizes) / 1024 / 1024:.2f} MiB")
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
