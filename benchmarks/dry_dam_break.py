"""The dry dam break against PyClaw's augmented solver, interleaved (docs/performance.md, "The
dry dam break against PyClaw's augmented solver").

    python benchmarks/dry_dam_break.py [--cells 400,800,1600,3200,6400] [--json PATH]

``dam-break-dry`` (h = 1 | 0 at rest, g = 1, t = 2) with conslaw's NT kernel (``mc``) and with
PyClaw classic using George's augmented Riemann solver ``sw_aug_1D`` (the solver of GeoClaw; MC
limiter, a flat bed of depth 0, dry tolerance 1e-3), per N one after the other (conslaw, PyClaw),
each the median of ``REPEATS`` solves after a warm-up: the L1 error of the depth against Ritter's
solution, the solve times, and the time to reach L1 = 1e-3 and 1e-4 (log-log interpolated).
Needs ``pip install clawpack`` (gfortran).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).parent))

import run as bench


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", default="400,800,1600,3200,6400")
    parser.add_argument("--json")
    args = parser.parse_args()
    if not bench.pyclaw_available():
        raise SystemExit("clawpack is not installed (pip install clawpack)")
    cells = [int(c) for c in args.cells.split(",")]
    ours: dict[str, list[float]] = {"seconds": [], "l1": [], "steps": []}
    theirs: dict[str, list[float]] = {"seconds": [], "l1": [], "steps": []}
    for n in cells:
        for side, measure in (
            (ours, lambda n=n: bench.work_precision("dam-break-dry", [n])),
            (theirs, lambda n=n: bench.pyclaw_work_precision("dam-break-dry", [n])),
        ):
            row = measure()
            for key in side:
                side[key].append(row[key][0])
    report: dict[str, Any] = {"cells": cells, "conslaw": ours, "pyclaw_sw_aug_1D": theirs}
    print("| N | conslaw steps | conslaw solve s | conslaw L1 | PyClaw steps | PyClaw solve s "
          "| PyClaw L1 |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    for k, n in enumerate(cells):
        print(
            f"| {n} | {ours['steps'][k]} | {ours['seconds'][k]:.4f} | {ours['l1'][k]:.3e} "
            f"| {theirs['steps'][k]} | {theirs['seconds'][k]:.4f} | {theirs['l1'][k]:.3e} |"
        )
    for target in bench.TARGETS:
        mine = bench.time_to_reach(cells, ours["seconds"], ours["l1"], target)
        other = bench.time_to_reach(cells, theirs["seconds"], theirs["l1"], target)
        report[f"time_to_{target:g}"] = {"conslaw": mine, "pyclaw": other}
        ratio = f"{mine / other:.3f}" if mine and other else "-"
        print(f"time to L1 = {target:g}: conslaw {mine}, PyClaw {other}, ratio {ratio}")
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
