#!/usr/bin/env python3
"""Median, 90th and 99th percentile and maximum of the automatic-mode set-up over the corpus
sample, from the criterion output of `cargo bench --bench auto` (criterion's median per pair).

Usage: python3 tools/bench/auto-setup.py [target/criterion]
"""

import sys
from pathlib import Path

from criterion import medians


def main() -> None:
    root = Path(sys.argv[1] if len(sys.argv) > 1 else "target/criterion") / "auto-setup"
    times = sorted((t * 1e3, name) for name, t in medians(root))
    if not times:
        sys.exit(f"no auto-setup results under {root}: run `cargo bench --bench auto` first")
    ms = [t for t, _ in times]

    def pct(p: float) -> float:
        # nearest rank
        k = max(0, min(len(ms) - 1, int(round(p / 100 * len(ms) + 0.5)) - 1))
        return ms[k]

    print(f"{len(ms)} pairs: median {pct(50):.2f} ms, p90 {pct(90):.2f} ms, "
          f"p99 {pct(99):.2f} ms, max {ms[-1]:.2f} ms ({times[-1][1]})")
    print("slowest:", ", ".join(f"{n} {t:.1f} ms" for t, n in times[-5:][::-1]))


if __name__ == "__main__":
    main()
