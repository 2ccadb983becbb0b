"""Cell-update rate of a kernel compiled in this process against one loaded from the cache.

    python benchmarks/fresh_compile.py [--cells N]

Compiles the shallow-water kernel (dam-break-wet, MC) into a new, empty cache folder in a child
process and times it there, then times it again in a second child process, which loads it from
that cache. Prints both rates (medians of 3 solves of 240 steps), their ratio and the time of the
first call (the compile, or the load from the cache); then the same with ``NUMBA_OPT=max``.
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
started = time.perf_counter()
scheme.advance(initial, t_end)
first = time.perf_counter() - started
times = []
for _ in range(3):
    started = time.perf_counter()
    result = scheme.advance(initial, t_end)
    times.append(time.perf_counter() - started)
print(first, n * result.steps / statistics.median(times))
"""


def rate(cells: int, cache: str, numba_opt: str | None) -> tuple[float, float]:
    """Time of the first call and cell updates per second, measured in a child process using
    the cache folder ``cache`` (and ``NUMBA_OPT=numba_opt`` if given)."""
    environment = {**os.environ, "CONSLAW_CACHE_DIR": cache}
    environment.pop("NUMBA_OPT", None)
    if numba_opt is not None:
        environment["NUMBA_OPT"] = numba_opt
    output = subprocess.run(
        [sys.executable, "-c", CHILD, str(cells)],
        env=environment,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    first, updates = output.split()[-2:]
    return float(first), float(updates)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100_000)
    args = parser.parse_args()
    print(f"dam-break-wet, N = {args.cells}, 240 steps, medians of 3 solves")
    for numba_opt in (None, "max"):
        with tempfile.TemporaryDirectory() as cache:
            fresh_first, fresh = rate(args.cells, cache, numba_opt)
            cached_first, cached = rate(args.cells, cache, numba_opt)
        print(f"NUMBA_OPT={numba_opt or 'unset (3)'}")
        print(f"  compiled in this process: {fresh:.3e} cell updates/s, compile {fresh_first:.1f}s")
        print(f"  loaded from the cache:    {cached:.3e} cell updates/s, load {cached_first:.2f}s")
        print(f"  ratio cached / fresh:     {cached / fresh:.2f}")


if __name__ == "__main__":
    main()
