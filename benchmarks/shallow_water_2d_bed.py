"""2D shallow water over a bed: the compiled Jiang–Tadmor kernels over a bed against the numpy
reference steps, interleaved (docs/performance.md, "Two dimensions over a bed").

    python benchmarks/shallow_water_2d_bed.py [--sizes 100,400] [--reference 100] [--json PATH]

The problem is the scene ``sw2d-thacker`` (Thacker's planar oscillation in a paraboloid bowl:
a moving shoreline, dry land over most of the domain, walls), ``mc``, Courant number 0.45 per
direction, to ``t = 40 / N`` (38 steps at every N). Measured, each the median of
``REPEATS`` solves after a warm-up (compiling), the solvers one after the other at each size
(A B A B): cell updates per second (cells times steps over the solve time) of the compiled
kernels on one and on two threads, and of the reference at the ``--reference`` sizes (numpy, a
few seconds per solve at 100^2). The flat kernel on the same grid and steps (the bowl's water
over a flat bed, so the same number of cells but no bed terms) is timed alongside for the cost
of the bed. A child process compiles the kernels into the cache first.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from typing import Any

from shallow_water_2d import interleaved

from conslaw import registry
from conslaw.grid2d import Grid2D
from conslaw.model import Model
from conslaw.scene2d import Scene2D, load_scene_2d
from conslaw.schemes.jiang_tadmor import JiangTadmor, JiangTadmorReference
from conslaw_models.shallow_water_2d import ShallowWater2D

SCENE = "sw2d-thacker"


def problem(n: int) -> tuple[Scene2D, Model, Grid2D]:
    """The scene at ``n x n`` cells, its model and grid."""
    scene = load_scene_2d(SCENE, {"n_cells": [n, n]})
    model = registry.models.get(scene.model)(**scene.parameters)
    grid = Grid2D.from_bounds(scene.x_min, scene.x_max, n, scene.y_min, scene.y_max, n)
    return scene, model, grid


def solve(n: int, threads: int | None, bed: bool = True) -> tuple[float, int]:
    """One solve of the problem to ``t = 40 / n``: the kernels on ``threads`` threads, or the
    reference (``threads`` None); over a flat bed if not ``bed``.

    Returns
    -------
    seconds : float
        Solve time (the scheme made before the clock starts).
    steps : int
        Time steps taken.
    """
    scene, model, grid = problem(n)
    q = model.initial_cell_averages_2d(scene.initial.kind, scene.initial.options, grid)
    if not bed:
        model = ShallowWater2D(g=model.params.g)
    limiter = registry.reconstructors.get("mc")
    scheme: Any = (
        JiangTadmorReference(model, limiter, grid, scene.boundaries)
        if threads is None
        else JiangTadmor(model, limiter, grid, scene.boundaries, threads=threads)
    )
    started = time.perf_counter()
    _, _, steps = scheme.advance(q, 0.0, 40.0 / n)
    return time.perf_counter() - started, steps


def main() -> None:
    """Measure and print the table of docs/performance.md; with ``--json PATH``, write every
    number to ``PATH``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="100,400")
    parser.add_argument("--reference", default="100")
    parser.add_argument("--json")
    parser.add_argument("--warm-kernels", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.warm_kernels:
        solve(16, 1)
        solve(16, 1, bed=False)
        return
    subprocess.run([sys.executable, __file__, "--warm-kernels"], check=True)
    reference_sizes = [int(s) for s in args.reference.split(",")] if args.reference else []
    report: dict[str, Any] = {"problem": SCENE, "rows": []}
    print("| N^2 | steps | bed, 1 thread | bed, 2 threads | 2 / 1 | flat bed, 1 thread "
          "| bed / flat | numpy reference | kernel / reference |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|")
    for n in (int(s) for s in args.sizes.split(",")):
        solvers: dict[str, Any] = {
            "bed_1_thread": lambda n=n: solve(n, 1),
            "bed_2_threads": lambda n=n: solve(n, 2),
            "flat_1_thread": lambda n=n: solve(n, 1, bed=False),
        }
        if n in reference_sizes:
            solvers["reference"] = lambda n=n: solve(n, None)
        rates = interleaved(n, solvers)
        report["rows"].append({"n": n, **rates})
        one, two = rates["bed_1_thread"], rates["bed_2_threads"]
        flat = rates["flat_1_thread"]
        reference = rates.get("reference")
        rate = "cell_updates_per_s"
        print(
            f"| {n}^2 | {one['steps']} | {one[rate]:.3e} | {two[rate]:.3e} | "
            f"{two[rate] / one[rate]:.2f} | {flat[rate]:.3e} | {one[rate] / flat[rate]:.2f} | "
            f"{f'{reference[rate]:.3e}' if reference else '-'} | "
            f"{f'{one[rate] / reference[rate]:.1f}' if reference else '-'} |",
            flush=True,
        )
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(report, handle, indent=2)


if __name__ == "__main__":
    main()
