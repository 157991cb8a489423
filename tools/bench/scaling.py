#!/usr/bin/env python3
"""Draws docs/rigid-scaling.svg, disc set-up and frame time against vertices (log-log), from the
criterion output of `cargo bench --bench rigid -- rigid-scaling`, and prints the table.

Usage: python3 tools/bench/scaling.py [target/criterion] [docs/rigid-scaling.svg]

Plain SVG written by hand, so the plot needs nothing beyond Python's standard library.
"""

import math
import sys
from pathlib import Path

from criterion import medians


def sizes(root: Path, what: str) -> list[tuple[int, float]]:
    """(vertices, median seconds) for every size criterion measured of `what`."""
    return sorted((int(n), t) for n, t in medians(root / "rigid-scaling" / what) if n.isdigit())


def nice(seconds: float) -> str:
    if seconds >= 1:
        return f"{seconds:.2f} s"
    if seconds >= 1e-3:
        return f"{seconds * 1e3:.3g} ms"
    return f"{seconds * 1e6:.3g} µs"


def main() -> None:
    root = Path(sys.argv[1] if len(sys.argv) > 1 else "target/criterion")
    dest = Path(sys.argv[2] if len(sys.argv) > 2 else "docs/rigid-scaling.svg")
    series = {
        "frame": sizes(root, "frame"),
        "frames8": [(n, t / 8) for n, t in sizes(root, "frames8")],
        "set-up": sizes(root, "setup"),
    }
    if not series["frame"]:
        sys.exit(f"no rigid-scaling results under {root}: run the bench first")

    # Table for the docs.
    setup, eight = dict(series["set-up"]), dict(series["frames8"])
    print(
        "| vertices | disc per frame | per frame and vertex "
        "| per frame, eight at a time | disc set-up |"
    )
    print("|---:|---:|---:|---:|---:|")
    for n, f in series["frame"]:
        s = nice(setup[n]) if n in setup else ""
        e = nice(eight[n]) if n in eight else ""
        print(f"| {n:,} | {nice(f)} | {f / n * 1e9:.0f} ns | {e} | {s} |")

    # Log-log axes: decades of vertices and of seconds spanning the data.
    w, h, left, right, top, bottom = 640, 420, 70, 40, 30, 50
    ns = [n for s in series.values() for n, _ in s]
    ts = [t for s in series.values() for _, t in s]
    x0, x1 = math.floor(math.log10(min(ns))), math.ceil(math.log10(max(ns)))
    y0, y1 = math.floor(math.log10(min(ts))), math.ceil(math.log10(max(ts)))

    def x(n: float) -> float:
        return left + (math.log10(n) - x0) / (x1 - x0) * (w - left - right)

    def y(t: float) -> float:
        return h - bottom - (math.log10(t) - y0) / (y1 - y0) * (h - top - bottom)

    def label(t: float) -> str:
        return nice(t).replace(".00 ", " ")

    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
        f'viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">',
        f'<rect width="{w}" height="{h}" fill="white"/>',
        f'<text x="{w / 2}" y="18" text-anchor="middle" font-size="14">'
        "Disc interpolation on grids: time against vertices (log-log)</text>",
    ]
    for e in range(x0, x1 + 1):
        parts.append(
            f'<line x1="{x(10**e):.1f}" y1="{top}" x2="{x(10**e):.1f}" y2="{h - bottom}" '
            'stroke="#ddd"/>'
        )
        parts.append(
            f'<text x="{x(10**e):.1f}" y="{h - bottom + 16}" text-anchor="middle">'
            f"{10**e:,}</text>"
        )
    for e in range(y0, y1 + 1):
        parts.append(
            f'<line x1="{left}" y1="{y(10.0**e):.1f}" x2="{w - right}" y2="{y(10.0**e):.1f}" '
            'stroke="#ddd"/>'
        )
        parts.append(
            f'<text x="{left - 6}" y="{y(10.0**e) + 4:.1f}" text-anchor="end">'
            f"{label(10.0**e)}</text>"
        )
    parts.append(
        f'<text x="{(left + w - right) / 2}" y="{h - 12}" text-anchor="middle">vertices</text>'
    )
    colours = {"frame": "#1565c0", "frames8": "#2e7d32", "set-up": "#c62828"}
    names = {
        "frame": "one frame",
        "frames8": "per frame, eight at a time (one pass over the factor)",
        "set-up": "set-up (factor once)",
    }
    for k, (name, pts) in enumerate(series.items()):
        if not pts:
            continue
        path = " ".join(f"{'M' if i == 0 else 'L'}{x(n):.1f} {y(t):.1f}" for i, (n, t) in enumerate(pts))
        c = colours[name]
        parts.append(f'<path d="{path}" fill="none" stroke="{c}" stroke-width="2"/>')
        for n, t in pts:
            parts.append(f'<circle cx="{x(n):.1f}" cy="{y(t):.1f}" r="3" fill="{c}"/>')
        parts.append(
            f'<text x="{left + 12}" y="{top + 16 + 16 * k}" fill="{c}">'
            f"{names[name]}</text>"
        )
    parts.append("</svg>")
    dest.write_text("\n".join(parts) + "\n")
    print(f"wrote {dest}")


if __name__ == "__main__":
    main()
