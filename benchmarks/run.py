"""Benchmarks: throughput, error against run time, paper scenes, and PyClaw side by side.

    python benchmarks/run.py [--quick] [--json PATH]

Prints markdown tables; ``--json`` also writes every number. Medians of 3 runs with min-max; the
compiled kernels are warmed up first (compilation is not timed). PyClaw (``pip install clawpack``,
built with gfortran) is measured in the same run when it can be imported, and skipped with a
message otherwise. Quote ratios from one run: the machine is noisy.

(a) cell updates per second (cells x time steps / solve time) for each model and N
(b) work-precision: the solve time needed to reach L1 = 1e-3 and 1e-4, interpolated (log-log)
    between the N of a convergence study
(c) the 90-cell paper scene: solve time, and wall time of the whole ``conslaw run`` process
(d) PyClaw classic (MC limiter, Roe) on the same dam break: (a) and (b) for it, and the ratios
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import conslaw
from conslaw.analysis import error_norms
from conslaw.convergence import convergence_study
from conslaw.simulation import build

REPEATS = 3
THROUGHPUT_SCENES = {
    "burgers": "burgers-sine",
    "shallow-water": "dam-break-wet",
    "savage-hutter": "sh-similarity",
}


def timed(function: Callable[[], Any], repeats: int = REPEATS) -> tuple[float, float, float, Any]:
    """Median, min and max wall time of ``function()`` and its last result."""
    times = []
    result = None
    for _ in range(repeats):
        started = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - started)
    return statistics.median(times), min(times), max(times), result


def throughput(sizes: list[int], target_updates: float) -> list[dict[str, Any]]:
    """Cell updates per second of the fused NT kernel for each model at each N."""
    rows = []
    for model_name, scene in THROUGHPUT_SCENES.items():
        for n in sizes:
            sc = conslaw.load_scene(scene, {"n_cells": n, "output_times": []})
            _, _, scheme, initial, _ = build(sc)
            steps_wanted = max(20, int(target_updates / n))
            # Never past the scene's own end time (the flow must stay the scene's flow).
            t_end = min(sc.t_end, scheme.stable_dt(initial) * steps_wanted)
            scheme.advance(initial, initial.t)  # compile or load from cache
            median, low, high, result = timed(lambda s=scheme, i=initial, t=t_end: s.advance(i, t))
            rate = n * result.steps / median
            rows.append(
                {"model": model_name, "scene": scene, "n_cells": n, "steps": result.steps,
                 "seconds": median, "min": low, "max": high, "cell_updates_per_s": rate}
            )  # fmt: skip
            print(
                f"  {model_name:14s} N={n:>8d} steps={result.steps:>5d} {median:.4f} s  "
                f"{rate:.3e} cell updates/s"
            )
    return rows


def time_to_reach(
    cells: list[int], seconds: list[float], errors: list[float], target: float
) -> float | None:
    """Solve time at which L1 reaches ``target``, log-log interpolated (None if never)."""
    for k in range(len(cells) - 1):
        if errors[k] >= target >= errors[k + 1]:
            fraction = math.log(errors[k] / target) / math.log(errors[k] / errors[k + 1])
            return math.exp(math.log(seconds[k]) + fraction * math.log(seconds[k + 1] / seconds[k]))
    return None


def work_precision(scene: str, cells: list[int], reconstructor: str) -> dict[str, Any]:
    study = convergence_study(scene, cells, [reconstructor], repeats=REPEATS, measure_import=False)
    seconds = [r.solve_median for r in study.rows]
    errors = [r.l1 for r in study.rows]
    return {
        "scene": scene, "reconstructor": reconstructor, "cells": cells, "seconds": seconds,
        "l1": errors, "time_to_1e-3": time_to_reach(cells, seconds, errors, 1e-3),
        "time_to_1e-4": time_to_reach(cells, seconds, errors, 1e-4),
    }  # fmt: skip


def paper_scene() -> dict[str, Any]:
    """sh-similarity (90 cells, t = 6): solve time, and the whole `conslaw run` process."""
    result = conslaw.run("sh-similarity")  # warm the cache
    solve = [conslaw.run("sh-similarity").solve_seconds for _ in range(REPEATS)]
    with tempfile.TemporaryDirectory() as folder:
        command = [
            sys.executable,
            "-m",
            "conslaw.cli",
            "run",
            "sh-similarity",
            "--no-plot",
            "--out",
            folder,
        ]
        median, low, high, _ = timed(
            lambda: subprocess.run(command, check=True, capture_output=True)
        )
    return {
        "scene": "sh-similarity", "n_cells": result.grid.n_cells, "steps": result.steps,
        "solve_median": statistics.median(solve), "solve_min": min(solve), "solve_max": max(solve),
        "process_median": median, "process_min": low, "process_max": high,
    }  # fmt: skip


# --------------------------------------------------------------------------- PyClaw
def pyclaw_available() -> bool:
    try:
        import clawpack.pyclaw
        import clawpack.riemann  # noqa: F401
    except ImportError:
        return False
    return True


def pyclaw_dam_break(n: int, t_final: float = 2.0) -> tuple[float, int, np.ndarray]:
    """PyClaw classic, MC limiter, Roe with entropy fix: the dam-break-wet scene. Returns the solve
    time, the number of time steps and the depth at ``t_final``."""
    from clawpack import pyclaw, riemann

    solver = pyclaw.ClawSolver1D(riemann.shallow_roe_with_efix_1D)
    solver.limiters = pyclaw.limiters.tvd.MC
    solver.kernel_language = "Fortran"
    solver.bc_lower[0] = pyclaw.BC.extrap
    solver.bc_upper[0] = pyclaw.BC.extrap
    x = pyclaw.Dimension(-5.0, 5.0, n, name="x")
    domain = pyclaw.Domain(x)
    state = pyclaw.State(domain, 2)
    state.problem_data["grav"] = 1.0
    state.problem_data["dry_tolerance"] = 1e-3
    state.problem_data["sea_level"] = 0.0
    centres = state.grid.x.centers
    state.q[0, :] = np.where(centres < 0.0, 3.0, 1.0)
    state.q[1, :] = 0.0
    controller = pyclaw.Controller()
    controller.solution = pyclaw.Solution(state, domain)
    controller.solver = solver
    controller.tfinal = t_final
    controller.num_output_times = 1
    controller.output_format = None
    controller.keep_copy = True
    controller.verbosity = 0
    started = time.perf_counter()
    controller.run()
    elapsed = time.perf_counter() - started
    return elapsed, int(solver.status["numsteps"]), np.array(controller.frames[-1].q[0])


def pyclaw_rows(sizes: list[int], cells: list[int], target_updates: float) -> dict[str, Any]:
    exact = build(conslaw.load_scene("dam-break-wet"))[4]
    assert exact is not None
    throughput_rows = []
    for n in sizes:
        # About target_updates cell updates (PyClaw's default Courant number is 0.9, wave speed
        # up to about 3.4 here), not the whole t = 2 run, which would take minutes at N = 1e5.
        t_final = min(2.0, max(20.0, target_updates / n) * 0.9 * (10.0 / n) / 3.4)
        pyclaw_dam_break(n, t_final)
        times = [pyclaw_dam_break(n, t_final) for _ in range(REPEATS)]
        median = statistics.median(t for t, _, _ in times)
        steps = times[0][1]
        throughput_rows.append(
            {
                "n_cells": n,
                "steps": steps,
                "seconds": median,
                "cell_updates_per_s": n * steps / median,
            }
        )
        print(
            f"  pyclaw         N={n:>8d} steps={steps:>5d} {median:.4f} s  "
            f"{n * steps / median:.3e} cell updates/s"
        )
    seconds, errors = [], []
    for n in cells:
        runs = [pyclaw_dam_break(n) for _ in range(REPEATS)]
        seconds.append(statistics.median(t for t, _, _ in runs))
        edges = np.linspace(-5.0, 5.0, n + 1)
        errors.append(
            error_norms(runs[-1][2], exact.cell_averages(edges, 2.0)[0], 10.0 / n, 10.0).l1
        )
    return {
        "throughput": throughput_rows,
        "work_precision": {
            "cells": cells, "seconds": seconds, "l1": errors,
            "time_to_1e-3": time_to_reach(cells, seconds, errors, 1e-3),
            "time_to_1e-4": time_to_reach(cells, seconds, errors, 1e-4),
        },
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description="conslaw benchmarks")
    parser.add_argument("--quick", action="store_true", help="smaller sizes (a smoke test)")
    parser.add_argument("--json", help="write all numbers to this JSON file")
    args = parser.parse_args()
    sizes = [1000, 10000] if args.quick else [1000, 10000, 100000, 1000000]
    cells = [100, 200, 400] if args.quick else [100, 200, 400, 800, 1600, 3200, 6400]
    target = 2e6 if args.quick else 2e7
    report: dict[str, Any] = {}
    print("(a) throughput of the fused NT kernel")
    report["throughput"] = throughput(sizes, target)
    print("(b) work-precision (mc)")
    report["work_precision"] = [
        work_precision(scene, cells, "mc")
        for scene in ("dam-break-wet", "dam-break-dry", "burgers-riemann")
    ]
    for row in report["work_precision"]:
        print(
            f"  {row['scene']:16s} time to L1=1e-3: {row['time_to_1e-3']}  "
            f"to 1e-4: {row['time_to_1e-4']}"
        )
    print("(c) paper scene")
    report["paper_scene"] = paper_scene()
    print(f"  {report['paper_scene']}")
    print("(d) PyClaw")
    if pyclaw_available():
        report["pyclaw"] = pyclaw_rows(sizes[:3], cells, target)
        ours = {
            r["n_cells"]: r["cell_updates_per_s"]
            for r in report["throughput"]
            if r["model"] == "shallow-water"
        }
        for row in report["pyclaw"]["throughput"]:
            print(
                f"  N={row['n_cells']}: conslaw / PyClaw cell-update rate = "
                f"{ours[row['n_cells']] / row['cell_updates_per_s']:.2f}"
            )
        mine = report["work_precision"][0]
        for key in ("time_to_1e-3", "time_to_1e-4"):
            theirs = report["pyclaw"]["work_precision"][key]
            if mine[key] and theirs:
                print(
                    f"  dam-break-wet {key}: conslaw {mine[key]:.4f} s, "
                    f"PyClaw {theirs:.4f} s, ratio {mine[key] / theirs:.2f}"
                )
    else:
        print("  skipped: clawpack is not installed (pip install clawpack, needs gfortran)")
        report["pyclaw"] = None
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(report, handle, indent=2)


if __name__ == "__main__":
    main()
