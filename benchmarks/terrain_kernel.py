"""Savage–Hutter on terrain: the compiled field kernels' cell-update rate, on one and on two
threads, against the numpy reference steps, interleaved (docs/performance.md, "Savage–Hutter on
terrain").

    python benchmarks/terrain_kernel.py [--cells 500] [--steps 40] [--rounds 3]
        [--reference-steps 4] [--json PATH]

The problem: ``--cells`` x ``--cells`` cells of 5 m on a 35-degree channelled slope turning into a
flat run-out (``terrain = "channel"``), every cell covered by material 2 m deep moving at 10 m/s
down the slope and 2 m/s across it (no cell is dry, held or a film: the film bound never acts, and
no row is skipped as empty), ``mc``, outflow sides, ``delta = 25``, ``phi = 35``, the Savage–Hutter
earth pressure. Each round times, one after the other (A B C A B C), ``--steps`` compiled steps on
one thread, the same on two threads, and ``--reference-steps`` numpy reference steps, all from the
same state with the same fixed time step (half the stable step). A cell update is one cell of one
step: the rate is cells times steps over the seconds. Medians over the rounds; the kernels are
compiled (or loaded from numba's cache) before the first round.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from typing import Any

import numpy as np

from conslaw import registry
from conslaw.grid2d import Grid2D
from conslaw.schemes.jiang_tadmor import JiangTadmor, JiangTadmorReference
from conslaw_models.savage_hutter_terrain import SavageHutterTerrain

CELL = 5.0
SIDES = dict.fromkeys(("left", "right", "bottom", "top"), "outflow")


def problem(cells: int) -> tuple[SavageHutterTerrain, Grid2D, np.ndarray]:
    """The model, the grid and the covered, moving state."""
    size = cells * CELL
    model = SavageHutterTerrain(
        terrain="channel",
        zeta=35.0,
        transition_radius=400.0,
        transition_end=0.75 * size,
        channel_depth=15.0,
        channel_half_width=60.0,
        phi=35.0,
        delta=25.0,
    )
    grid = Grid2D.from_bounds(0.0, size, cells, -size / 2, size / 2, cells)
    q = np.zeros((3, *grid.shape))
    q[0] = 2.0
    q[1] = 2.0 * 10.0
    q[2] = 2.0 * 2.0
    return model, grid, q


def time_steps(scheme: Any, q: np.ndarray, steps: int, dt: float) -> float:
    """Seconds for ``steps`` single steps from ``q``, alternating between the two families
    (each through ``scheme.step``: its values loaded and copied out, which a run's ``advance``
    does not do)."""
    started = time.perf_counter()
    values = q
    for k in range(steps):
        values = scheme.step(values, k % 2 == 1, dt)
    return time.perf_counter() - started


def main() -> None:
    """Print the table (and write JSON with every sample if asked)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=500)
    parser.add_argument("--steps", type=int, default=40)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--reference-steps", type=int, default=4)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    model, grid, q = problem(args.cells)
    limiter = registry.reconstructors.get("mc")
    reference = JiangTadmorReference(model, limiter, grid, SIDES)
    dt = 0.5 * reference.stable_dt(q)
    threads = min(2, JiangTadmor.available_threads())
    kernels = {n: JiangTadmor(model, limiter, grid, SIDES, threads=n) for n in sorted({1, threads})}
    for scheme in kernels.values():
        time_steps(scheme, q, 2, dt)
    rows: dict[str, tuple[int, list[float]]] = {
        **{f"compiled, {n} thread{'s' if n > 1 else ''}": (args.steps, []) for n in kernels},
        "numpy reference": (args.reference_steps, []),
    }
    schemes = [*kernels.values(), reference]
    for _ in range(args.rounds):
        for (steps, seconds), scheme in zip(rows.values(), schemes, strict=True):
            seconds.append(time_steps(scheme, q, steps, dt))
    cells = args.cells * args.cells
    print(f"{args.cells} x {args.cells} cells, all flowing; dt = {dt:.4g} s\n")
    print("| steps by | steps | seconds (each round) | median | cell updates / s |")
    print("|---|---|---|---|---|")
    rates = {}
    for name, (steps, seconds) in rows.items():
        median = statistics.median(seconds)
        rates[name] = cells * steps / median
        listed = ", ".join(f"{v:.3f}" for v in seconds)
        print(f"| {name} | {steps} | {listed} | {median:.3f} | {rates[name]:.3g} |")
    one = rates["compiled, 1 thread"]
    print(f"\none thread / numpy reference: {one / rates['numpy reference']:.1f}")
    if threads > 1:
        print(f"two threads / one thread: {rates['compiled, 2 threads'] / one:.2f}")
    if args.json:
        with open(args.json, "w") as out:
            json.dump(
                {"cells": args.cells, "dt": dt, "rows": {k: v[1] for k, v in rows.items()},
                 "steps": {k: v[0] for k, v in rows.items()}, "rates": rates},
                out, indent=2,
            )  # fmt: skip


if __name__ == "__main__":
    main()
