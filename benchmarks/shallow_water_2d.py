"""2D shallow water: the compiled Jiang–Tadmor kernel against PyClaw classic, interleaved
(docs/performance.md, "Two dimensions: shallow water against PyClaw classic").

    python benchmarks/shallow_water_2d.py [--sizes 100,250,500,1000,2000] [--pyclaw 250,1000]
                                          [--updates 1e8] [--json PATH]

The problem is PyClaw's own radial dam break (``clawpack/pyclaw/examples/shallow_2d/
radial_dam_break.py``): depth 2 inside the circle of radius 0.5, 1 outside, at rest, g = 1, on
[-2.5, 2.5]^2, outflow on the left and bottom, walls on the right and top. conslaw: the
Jiang–Tadmor kernel, ``mc``, Courant number 0.45 per direction. PyClaw: ``ClawSolver2D`` with
``shallow_roe_with_efix_2D``, the MC limiter and the example's splitting (``dimensional_split =
1``), Fortran, its default Courant number (0.9 desired).

Both codes run to the end time of ``--updates`` cell updates (at least ``MIN_STEPS`` steps) at a
wave speed of 2.2 (:func:`end_time`); the largest speed of the dam at the start is sqrt(g h) =
sqrt(2), so a conslaw solve takes fewer updates than that, and PyClaw, at twice the Courant number,
about half as many (the JSON records the steps). Measured, each the median of ``REPEATS`` solves
after a warm-up (compiling), the two codes one after the other at each size (A B A B): cell updates
per second (cells times time steps over the solve time) on one thread, at every size for conslaw
(the cost per cell update from 100^2 to 2000^2) and at the ``--pyclaw`` sizes for both; conslaw on
one and on two threads at the largest PyClaw size, interleaved; the peak memory that numpy
allocates during two runs at 250^2 (``tracemalloc``), to the time of 10 and of 40 steps at a wave
speed of 2.3 (:func:`peak_memory`; fewer steps at the dam's speeds): flat in the number of steps
means no allocation per step. A child process compiles the kernel into the cache first.
Needs ``pip install clawpack`` (gfortran) for the PyClaw rows; ``--pyclaw ""`` leaves them out
(with small ``--sizes`` and ``--updates``, a quick check that the script runs).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
import tracemalloc
from typing import Any

import numpy as np

from conslaw import registry
from conslaw.grid2d import Grid2D
from conslaw.schemes.jiang_tadmor import JiangTadmor
from conslaw_models.shallow_water_2d import ShallowWater2D

REPEATS = 3
#: Cell updates per timed solve at the wave speed :func:`end_time` assumes (default of
#: ``--updates``); at least ``MIN_STEPS`` steps.
TARGET_UPDATES = 1.0e8
MIN_STEPS = 8
SIDES = {"left": "outflow", "bottom": "outflow", "right": "wall", "top": "wall"}
DOMAIN = (-2.5, 2.5)


def initial(n: int) -> tuple[Grid2D, np.ndarray]:
    """The radial dam at rest.

    Parameters
    ----------
    n : int
        Cells along each side.

    Returns
    -------
    grid : Grid2D
        ``n`` x ``n`` cells over ``DOMAIN`` squared.
    q : ndarray
        ``(h, hu, hv)``, shape ``(3, n, n)``: depth 2 inside the circle of radius 0.5, 1
        outside, at rest.
    """
    grid = Grid2D.from_bounds(*DOMAIN, n, *DOMAIN, n)
    x, y = grid.centres()
    r = np.sqrt(x[None, :] ** 2 + y[:, None] ** 2)
    q = np.zeros((3, n, n))
    q[0] = np.where(r <= 0.5, 2.0, 1.0)
    return grid, q


def end_time(n: int, courant: float, updates: float = TARGET_UPDATES) -> float:
    """The end time of ``updates`` cell updates if every step were ``courant dx / 2.2``.

    Parameters
    ----------
    n : int
        Cells along each side.
    courant : float
        Courant number per step.
    updates : float
        Cell updates (at least ``MIN_STEPS`` steps).

    Returns
    -------
    float
        ``max(MIN_STEPS, updates / n^2) courant dx / 2.2``. The dam's largest wave speed at the
        start is sqrt(g h) = sqrt(2), not 2.2, so a run takes fewer steps than that.
    """
    steps = max(MIN_STEPS, updates / n**2)
    return steps * courant * (DOMAIN[1] - DOMAIN[0]) / n / 2.2


def conslaw_solve(n: int, threads: int, t_end: float) -> tuple[float, int]:
    """The Jiang–Tadmor kernel on the radial dam break.

    Parameters
    ----------
    n : int
        Cells along each side.
    threads : int
        Threads of the kernel.
    t_end : float
        End time.

    Returns
    -------
    seconds : float
        Solve time (the scheme made before the clock starts).
    steps : int
        Time steps taken.
    """
    grid, q = initial(n)
    scheme = JiangTadmor(
        ShallowWater2D(g=1.0), registry.reconstructors.get("mc"), grid, SIDES, threads=threads
    )
    started = time.perf_counter()
    _, _, steps = scheme.advance(q, 0.0, t_end)
    return time.perf_counter() - started, steps


def pyclaw_solve(n: int, t_end: float) -> tuple[float, int]:
    """PyClaw classic on its radial dam break.

    Parameters
    ----------
    n : int
        Cells along each side.
    t_end : float
        End time.

    Returns
    -------
    seconds : float
        Solve time (``Controller.run``).
    steps : int
        Time steps taken.
    """
    from clawpack import pyclaw, riemann

    solver = pyclaw.ClawSolver2D(riemann.shallow_roe_with_efix_2D)
    solver.limiters = pyclaw.limiters.tvd.MC
    solver.dimensional_split = 1
    solver.kernel_language = "Fortran"
    solver.bc_lower[0] = solver.bc_lower[1] = pyclaw.BC.extrap
    solver.bc_upper[0] = solver.bc_upper[1] = pyclaw.BC.wall
    x = pyclaw.Dimension(*DOMAIN, n, name="x")
    y = pyclaw.Dimension(*DOMAIN, n, name="y")
    domain = pyclaw.Domain([x, y])
    state = pyclaw.State(domain, 3)
    state.problem_data["grav"] = 1.0
    _, q = initial(n)
    state.q[...] = q.transpose(0, 2, 1)  # PyClaw's arrays are (variable, x, y)
    controller = pyclaw.Controller()
    controller.solution = pyclaw.Solution(state, domain)
    controller.solver = solver
    controller.tfinal = t_end
    controller.num_output_times = 1
    controller.output_format = None
    controller.keep_copy = False
    controller.verbosity = 0
    started = time.perf_counter()
    controller.run()
    return time.perf_counter() - started, int(solver.status["numsteps"])


def median_rate(runs: list[tuple[float, int]], n: int) -> dict[str, Any]:
    """The median solve of repeated runs and its rate.

    Parameters
    ----------
    runs : list of (float, int)
        Solve time and steps of each run (the same steps in each).
    n : int
        Cells along each side.

    Returns
    -------
    dict
        ``seconds`` (the median), ``steps`` and ``cell_updates_per_s``, ``n^2 steps / seconds``.
    """
    seconds = statistics.median(r[0] for r in runs)
    steps = runs[0][1]
    return {"seconds": seconds, "steps": steps, "cell_updates_per_s": n * n * steps / seconds}


def interleaved(n: int, solvers: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Each solver once to warm up, then ``REPEATS`` rounds of all of them in turn (A B A B).

    Parameters
    ----------
    n : int
        Cells along each side.
    solvers : dict
        Name -> a function of no argument returning ``(seconds, steps)``.

    Returns
    -------
    dict
        Name -> :func:`median_rate` of its runs.
    """
    for solve in solvers.values():
        solve()
    runs: dict[str, list[tuple[float, int]]] = {name: [] for name in solvers}
    for _ in range(REPEATS):
        for name, solve in solvers.items():
            runs[name].append(solve())
    return {name: median_rate(taken, n) for name, taken in runs.items()}


def peak_memory(n: int, steps: int) -> dict[str, int]:
    """Peak bytes numpy allocates during a run of the kernel (after the scheme is made and a
    first run), to the time ``steps`` steps would reach at a wave speed of 2.3.

    Parameters
    ----------
    n : int
        Cells along each side.
    steps : int
        Steps at a wave speed of 2.3; the dam's speeds are lower, so the run takes fewer.

    Returns
    -------
    dict
        ``steps`` (the steps taken) and ``peak_bytes`` (``tracemalloc``'s peak).
    """
    grid, q = initial(n)
    scheme = JiangTadmor(
        ShallowWater2D(), registry.reconstructors.get("mc"), grid, SIDES, threads=1
    )
    t_end = 0.5 * steps * 0.45 * (DOMAIN[1] - DOMAIN[0]) / n / 2.3
    scheme.advance(q, 0.0, t_end)  # compiled, buffers made
    tracemalloc.start()
    _, _, taken = scheme.advance(q, 0.0, 2.0 * t_end)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    print(f"  memory: {taken} steps at {n}^2, peak {peak / 1e6:.2f} MB allocated by numpy")
    return {"steps": taken, "peak_bytes": peak}


def warm_kernels() -> None:
    """Compile the kernel into the cache. Run in a child process before anything is timed: a
    kernel compiled in the timing process itself runs slower than one loaded from the cache
    (docs/performance.md, "A kernel compiled in the running process is slower")."""
    conslaw_solve(16, 1, 0.01)


def main() -> None:
    """Measure and print the table of docs/performance.md (the command line is in the module's
    docstring); with ``--json PATH``, write every number to ``PATH``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="100,250,500,1000,2000")
    parser.add_argument("--pyclaw", default="250,1000")
    parser.add_argument("--updates", type=float, default=TARGET_UPDATES)
    parser.add_argument("--json")
    parser.add_argument("--warm-kernels", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.warm_kernels:
        warm_kernels()
        return
    subprocess.run([sys.executable, __file__, "--warm-kernels"], check=True)
    sizes = [int(s) for s in args.sizes.split(",")]
    pyclaw_sizes = [int(s) for s in args.pyclaw.split(",")] if args.pyclaw else []
    report: dict[str, Any] = {"problem": "PyClaw's radial dam break", "rows": []}
    for n in sizes:
        t_end = end_time(n, 0.45, args.updates)
        solvers: dict[str, Any] = {"conslaw": lambda n=n, t=t_end: conslaw_solve(n, 1, t)}
        if n in pyclaw_sizes:
            solvers["pyclaw"] = lambda n=n, t=t_end: pyclaw_solve(n, t)
        if n == max(pyclaw_sizes, default=0):
            solvers["conslaw_2_threads"] = lambda n=n, t=t_end: conslaw_solve(n, 2, t)
        rates = interleaved(n, solvers)
        report["rows"].append({"n": n, "t_end": t_end, **rates})
        line = ", ".join(
            f"{name} {row['steps']} steps {row['seconds']:.3f} s {row['cell_updates_per_s']:.3e}/s"
            for name, row in rates.items()
        )
        print(f"{n}^2: {line}", flush=True)
    report["memory"] = [peak_memory(250, steps) for steps in (10, 40)]
    print_table(report)
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(report, handle, indent=2)


def print_table(report: dict[str, Any]) -> None:
    """Print the markdown table of docs/performance.md and the memory rows.

    Parameters
    ----------
    report : dict
        What :func:`main` measured (the JSON's content).
    """
    rows = report["rows"]
    base = rows[0]["conslaw"]["cell_updates_per_s"]
    print("\n| N^2 | conslaw cell updates/s (1 thread) | cost vs 100^2 | PyClaw cell updates/s "
          "| conslaw/PyClaw | conslaw 2 threads / 1 |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for row in rows:
        ours = row["conslaw"]["cell_updates_per_s"]
        theirs = row.get("pyclaw", {}).get("cell_updates_per_s")
        two = row.get("conslaw_2_threads", {}).get("cell_updates_per_s")
        print(
            f"| {row['n']}^2 | {ours:.3e} | {base / ours:.2f} | "
            f"{f'{theirs:.3e}' if theirs else '-'} | {f'{ours / theirs:.2f}' if theirs else '-'} "
            f"| {f'{two / ours:.2f}' if two else '-'} |"
        )
    for row in report["memory"]:
        print(f"peak numpy allocation during {row['steps']} steps at 250^2: {row['peak_bytes']} B")


if __name__ == "__main__":
    main()
