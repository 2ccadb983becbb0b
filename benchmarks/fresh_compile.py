"""Cell-update rate of a kernel compiled in this process against one loaded from the cache.

    python benchmarks/fresh_compile.py [--cells N]

Compiles the shallow-water kernel (dam-break-wet, MC) into a new, empty cache folder in a child
process and times it there, then times it again in a second child process, which loads it from
that cache. Prints both rates (medians of 3 solves of 240 steps) and their ratio.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile

CHILD = """
import statistics, sys, time
import conslaw
from conslaw.simulation import build
n = int(sys.argv[1])
options = {"n_cells": n, "output_times": [], "reconstructor": "mc"}
scene = conslaw.load_scene("dam-break-wet", options)
_, _, scheme, initial, _ = build(scene)
t_end = min(scene.t_end, scheme.stable_dt(initial) * 240)
scheme.advance(initial, t_end)
times = []
for _ in range(3):
    started = time.perf_counter()
    result = scheme.advance(initial, t_end)
    times.append(time.perf_counter() - started)
print(n * result.steps / statistics.median(times))
"""


def rate(cells: int, cache: str) -> float:
    """Cell updates per second measured in a child process using the cache folder ``cache``."""
    environment = {**os.environ, "CONSLAW_CACHE_DIR": cache}
    output = subprocess.run(
        [sys.executable, "-c", CHILD, str(cells)],
        env=environment,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return float(output.split()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100_000)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as cache:
        fresh = rate(args.cells, cache)
        cached = rate(args.cells, cache)
    print(f"dam-break-wet, N = {args.cells}, 240 steps, medians of 3 solves")
    print(f"  compiled in this process: {fresh:.3e} cell updates/s")
    print(f"  loaded from the cache:    {cached:.3e} cell updates/s")
    print(f"  ratio cached / fresh:     {cached / fresh:.2f}")


if __name__ == "__main__":
    main()
