"""The whole `conslaw run` process against the floor of any Python program that draws with the
same libraries (docs/performance.md, "The whole conslaw run process").

    python benchmarks/process_floor.py [--scene sh-similarity] [--pairs 3] [--json FILE]

Each pair runs, one after the other (A B, interleaved so that the machine's load falls on both):
A = ``conslaw run SCENE --out TMP`` (its kernels already cached: one warm-up run first), B = a
bare ``python -c`` that imports numpy, scipy, numba and matplotlib and saves one figure. Prints
the wall times, their medians and the ratio A / B (the goal in the performance notes: 1.2).
"""

from __future__ import annotations

import argparse
import json
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

FLOOR = (
    "import numpy, scipy, numba, matplotlib\n"
    "from matplotlib.figure import Figure\n"
    "figure = Figure()\n"
    "figure.add_subplot().plot([0.0, 1.0])\n"
    "figure.savefig({path!r})\n"
)


def wall(command: list[str]) -> float:
    """Seconds one process takes, start to exit (it must succeed)."""
    started = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True)
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="sh-similarity")
    parser.add_argument("--pairs", type=int, default=3)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args()
    conslaw = shutil.which("conslaw") or "conslaw"
    folder = Path(tempfile.mkdtemp(prefix="conslaw-floor-"))
    run = [conslaw, "run", args.scene, "--out", str(folder / "run")]
    floor = [sys.executable, "-c", FLOOR.format(path=str(folder / "floor.png"))]
    wall(run)  # the kernels into the cache, the files into the folder
    runs, floors = [], []
    for _ in range(args.pairs):
        runs.append(wall(run))
        floors.append(wall(floor))
    shutil.rmtree(folder, ignore_errors=True)
    ratio = statistics.median(runs) / statistics.median(floors)
    print(f"| pair | conslaw run {args.scene} (s) | floor (s) |")
    print("|---|---|---|")
    for k, (a, b) in enumerate(zip(runs, floors, strict=True), 1):
        print(f"| {k} | {a:.2f} | {b:.2f} |")
    print(f"| median | {statistics.median(runs):.2f} | {statistics.median(floors):.2f} |")
    print(f"ratio of the medians: {ratio:.2f}")
    if args.json is not None:
        args.json.write_text(
            json.dumps({"scene": args.scene, "run": runs, "floor": floors, "ratio": ratio}) + "\n"
        )


if __name__ == "__main__":
    main()
