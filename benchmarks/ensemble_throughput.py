"""The ensemble engine's cost per member and its scaling from one to two local workers
(docs/performance.md, "Ensembles"), interleaved (1 worker, 2 workers, 1, 2, ...).

    python benchmarks/ensemble_throughput.py [--members 1000] [--rounds 2] [--cells 200]
        [--json PATH]

Each sample is a whole study (``conslaw.ensemble.run_study``: drawing and checking every member,
starting the workers, running, keeping, writing the dataset) of ``sh-runout-shock`` with the
bed and internal friction angles and the release height varied, into a new folder. A small
study first loads the kernels into the cache. The overhead per member is the study's wall time
over its members minus one member's median solve time (the time loop alone), as asked of the
engine; with two workers the solve times overlap, so the table also gives the overhead per
member and worker (wall time x workers / members minus the solve time).
"""

from __future__ import annotations

import argparse
import json
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from conslaw.ensemble import run_study

SCENE = "sh-runout-shock"
VARY = [
    "parameters.delta=uniform:20:28",
    "parameters.phi=uniform:30:38",
    "initial.height=normal:2.2:0.15",
]


def sample(members: int, workers: int, cells: int, folder: Path) -> dict[str, float]:
    """One whole study: its wall time and its members' median solve and member times."""
    started = time.perf_counter()
    study = run_study(
        SCENE, VARY, members, folder, settings={"n_cells": cells},
        options={"workers": workers}, report=lambda line: None,
    )  # fmt: skip
    whole = time.perf_counter() - started
    dataset = study.dataset
    assert (dataset.status.values == "finished").all()
    return {
        "workers": workers,
        "whole_seconds": whole,
        "solve_seconds": float(np.median(dataset.solve_seconds.values)),
        "member_seconds": float(np.median(dataset.wall_seconds.values)),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--members", type=int, default=1000)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--cells", type=int, default=200)
    parser.add_argument("--json", help="write the samples and the summary here")
    args = parser.parse_args()
    samples: list[dict[str, float]] = []
    with tempfile.TemporaryDirectory() as scratch:
        sample(16, 2, args.cells, Path(scratch) / "warm")
        for round_number in range(args.rounds):
            for workers in (1, 2):
                folder = Path(scratch) / f"r{round_number}w{workers}"
                samples.append(sample(args.members, workers, args.cells, folder))
    rows = []
    medians = {}
    for workers in (1, 2):
        mine = [s for s in samples if s["workers"] == workers]
        whole = statistics.median(s["whole_seconds"] for s in mine)
        solve = statistics.median(s["solve_seconds"] for s in mine)
        member = statistics.median(s["member_seconds"] for s in mine)
        medians[workers] = whole
        per_member = whole / args.members - solve
        per_worker = whole * workers / args.members - solve
        rows.append((workers, whole, solve, member, per_member, per_worker))
    print(f"{args.members} members of {SCENE} (n_cells = {args.cells}), {args.rounds} rounds")
    print("| workers | study wall (s) | member solve (ms) | member in worker (ms) | "
          "overhead per member (ms) | per member and worker (ms) |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for workers, whole, solve, member, per_member, per_worker in rows:
        print(
            f"| {workers} | {whole:.2f} | {solve * 1e3:.2f} | {member * 1e3:.2f} | "
            f"{per_member * 1e3:.2f} | {per_worker * 1e3:.2f} |"
        )
    scaling = medians[1] / medians[2]
    print(f"scaling from 1 to 2 workers: {scaling:.2f}x")
    if args.json:
        summary = {"members": args.members, "cells": args.cells, "scaling": scaling, "rows": rows}
        Path(args.json).write_text(json.dumps({"samples": samples, "summary": summary}, indent=2))


if __name__ == "__main__":
    main()
