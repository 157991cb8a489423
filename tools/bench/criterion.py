"""Reading criterion's results: the scripts beside this one summarise benches from them."""

import json
from pathlib import Path


def medians(group: Path) -> list[tuple[str, float]]:
    """(benchmark id, median seconds) for every benchmark criterion measured under `group`
    (a folder such as target/criterion/auto-setup), sorted by id."""
    out = []
    for d in sorted(group.iterdir()) if group.is_dir() else []:
        est = d / "new" / "estimates.json"
        if est.is_file():
            ns = json.loads(est.read_text())["median"]["point_estimate"]
            out.append((d.name, ns * 1e-9))
    return out
