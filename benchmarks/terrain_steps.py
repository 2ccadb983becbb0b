"""The numpy steps of the Savage–Hutter terrain model, timed, optionally against an older
checkout interleaved (A B A B) (docs/performance.md, "Savage–Hutter on terrain").

    python benchmarks/terrain_steps.py [--rounds 3] [--cells 200,100] [--t-end 10]
        [--baseline-tree /path/to/old/checkout | --tracked] [--json PATH]

Each sample is a child process that runs ``terrain-plane-to-flat`` once small (the kernels
from the cache) and then times one solve at ``--cells`` to ``--t-end`` seconds of flow (no
output files). With ``--baseline-tree`` the baseline's children import ``conslaw`` from that
tree (``PYTHONPATH``; the plugins ``conslaw_models`` stay the installed ones, so the two may
differ only in ``conslaw/``), alternating with the current ones; with ``--tracked`` the
baseline is the same tree on ``jiang-tadmor`` and the current side runs ``jiang-tadmor-ft``
(the margins tracked, docs/design.md, "Margins in two dimensions"). The table gives the medians
and the ratio current / baseline.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

CHILD = """
import json, time, conslaw
conslaw.run_2d("terrain-plane-to-flat", n_cells=[40, 20], output_times=[5.0])
started = time.perf_counter()
result = conslaw.run_2d(
    "terrain-plane-to-flat", n_cells={cells}, t_end={t_end}, output_times=[{t_end}],
    scheme={scheme!r},
)
print(json.dumps({{"seconds": time.perf_counter() - started, "steps": result.steps}}))
"""


def sample(
    cells: list[int], t_end: float, tree: str | None, scheme: str = "jiang-tadmor"
) -> dict[str, float]:
    """One timed solve on ``scheme`` in a child process (``tree``: the baseline's checkout)."""
    environment = dict(os.environ)
    if tree is not None:
        environment["PYTHONPATH"] = tree
    done = subprocess.run(
        [sys.executable, "-c", CHILD.format(cells=cells, t_end=t_end, scheme=scheme)],
        capture_output=True,
        text=True,
        check=True,
        env=environment,
    )
    return dict(json.loads(done.stdout.strip().splitlines()[-1]))


def main() -> None:
    """Print the table (and write JSON with every sample if asked)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--cells", default="200,100")
    parser.add_argument("--t-end", type=float, default=10.0)
    parser.add_argument("--baseline-tree", default=None)
    parser.add_argument("--tracked", action="store_true")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    if args.tracked and args.baseline_tree is not None:
        parser.error("--tracked compares schemes on this tree: drop --baseline-tree")
    cells = [int(v) for v in args.cells.split(",")]
    compared = args.baseline_tree is not None or args.tracked
    sides = ["baseline", "current"] if compared else ["current"]
    samples: dict[str, list[dict[str, float]]] = {side: [] for side in sides}
    for _ in range(args.rounds):
        for side in sides:
            tree = args.baseline_tree if side == "baseline" else None
            tracked = args.tracked and side == "current"
            scheme = "jiang-tadmor-ft" if tracked else "jiang-tadmor"
            samples[side].append(sample(cells, args.t_end, tree, scheme))
    print("| side | steps | seconds per solve (each round) | median | cell updates / s |")
    print("|---|---|---|---|---|")
    medians = {}
    for side in sides:
        seconds = [s["seconds"] for s in samples[side]]
        steps = int(samples[side][0]["steps"])
        medians[side] = statistics.median(seconds)
        rate = cells[0] * cells[1] * steps / medians[side]
        listed = ", ".join(f"{v:.3f}" for v in seconds)
        print(f"| {side} | {steps} | {listed} | {medians[side]:.3f} | {rate:.3g} |")
    if "baseline" in medians:
        print(f"\ncurrent / baseline: {medians['current'] / medians['baseline']:.2f}")
    if args.json:
        with open(args.json, "w") as out:
            json.dump({"cells": cells, "t_end": args.t_end, "samples": samples}, out, indent=2)


if __name__ == "__main__":
    main()
