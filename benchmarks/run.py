"""Benchmarks: throughput, error against run time, the paper scene, and PyClaw side by side.

    python benchmarks/run.py [--quick] [--json PATH] [--plot PATH]

Prints every number as it is measured, then the summary tables; ``--json`` writes all numbers,
``--plot`` the work-precision figure. Times are wall-clock medians of ``REPEATS`` runs with their
min and max; the compiled kernels are loaded or compiled before anything is timed. PyClaw
(``pip install clawpack``, which builds its Fortran with gfortran) is measured in the same run
when it can be imported, and skipped with a message otherwise. Quote ratios from one run: the
machine may be shared, so the load average before and after each section is recorded too.

(a) cell updates per second (cells x time steps / solve time) of every model at N = 1e3 .. 1e6,
    and the cost per cell update relative to N = 1e4 (linear cost: all ratios near 1)
(b) work-precision: solve time against the L1 error on dam-break-wet, dam-break-dry and
    burgers-riemann (MC limiter), and the time to reach L1 = 1e-3 and 1e-4 (log-log interpolated
    between the N of the study)
(c) the 90-cell paper scene sh-similarity: solve time, and the wall time of the whole
    ``conslaw run sh-similarity`` process (default options, and with ``--no-plot``)
(d) PyClaw classic (Fortran, MC limiter; Roe with entropy fix for shallow water, George's
    augmented solver ``sw_aug_1D`` for the dry dam break) on the same problems: its rates, its
    work-precision, and the ratios
(e) memory: resident size and numba allocations after 100 and after 10000 step pairs
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

import conslaw
from conslaw.analysis import error_norms
from conslaw.simulation import build, simulate
from conslaw.studies.convergence import convergence_study

REPEATS = 3
PROCESS_REPEATS = 5
# Model -> (scene, reconstructor) of the throughput rows.
THROUGHPUT = {
    "burgers": ("burgers-sine", "mc"),
    "burgers, weno5": ("burgers-sine", "weno5"),
    "shallow-water": ("dam-break-wet", "mc"),
    "savage-hutter": ("sh-similarity", "superbee"),
}
WORK_PRECISION_SCENES = ("dam-break-wet", "dam-break-dry", "burgers-riemann")
TARGETS = (1e-3, 1e-4)


def load() -> float:
    """The one-minute load average (other processes competing for the 2 cores)."""
    return os.getloadavg()[0]


def timed(function: Callable[[], Any], repeats: int = REPEATS) -> tuple[float, float, float, Any]:
    """Median, min and max wall time of ``function()`` and its last result."""
    times = []
    result = None
    for _ in range(repeats):
        started = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - started)
    return statistics.median(times), min(times), max(times), result


def cpu_timed(function: Callable[[], Any], repeats: int = REPEATS) -> float:
    """Median CPU time of this process during ``function()``: unlike the wall time it leaves out
    the time the process waited for a core that another process held."""
    times = []
    for _ in range(repeats):
        started = time.process_time()
        function()
        times.append(time.process_time() - started)
    return statistics.median(times)


def time_to_reach(
    cells: list[int], seconds: list[float], errors: list[float], target: float
) -> float | None:
    """Solve time at which L1 reaches ``target``, log-log interpolated (None if never)."""
    for k in range(len(cells) - 1):
        if errors[k] >= target >= errors[k + 1]:
            fraction = math.log(errors[k] / target) / math.log(errors[k] / errors[k + 1])
            return math.exp(math.log(seconds[k]) + fraction * math.log(seconds[k + 1] / seconds[k]))
    return None


# --------------------------------------------------------------------------- (a) throughput
def throughput(sizes: list[int], target_updates: float) -> list[dict[str, Any]]:
    """Cell updates per second of the fused NT kernel for each model at each N."""
    rows = []
    for label, (scene, reconstructor) in THROUGHPUT.items():
        for n in sizes:
            sc = conslaw.load_scene(
                scene, {"n_cells": n, "output_times": [], "reconstructor": reconstructor}
            )
            _, _, scheme, initial, _ = build(sc)
            steps_wanted = max(20, int(target_updates / n))
            # Never past the scene's own end time (the flow must stay the scene's flow).
            t_end = min(sc.t_end, scheme.stable_dt(initial) * steps_wanted)
            scheme.advance(initial, initial.t)  # compile or load from the cache
            solve = lambda s=scheme, i=initial, t=t_end: s.advance(i, t)  # noqa: E731
            median, low, high, result = timed(solve)
            cpu = cpu_timed(solve)
            rate = n * result.steps / median
            rows.append(
                {"model": label, "scene": scene, "reconstructor": reconstructor, "n_cells": n,
                 "steps": result.steps, "seconds": median, "min": low, "max": high,
                 "cpu_seconds": cpu, "cell_updates_per_s": rate,
                 "cell_updates_per_cpu_s": n * result.steps / cpu,
                 "ns_per_cell_update": 1e9 / rate}
            )  # fmt: skip
            print(
                f"  {label:15s} N={n:>8d} steps={result.steps:>5d} {median:.4f} s "
                f"({low:.4f}-{high:.4f})  {rate:.3e} cell updates/s (per CPU second "
                f"{n * result.steps / cpu:.3e})"
            )
    return rows


def linearity(rows: list[dict[str, Any]], reference_n: int = 10_000) -> dict[str, dict[int, float]]:
    """Cost per cell update at each N relative to N = reference_n, for every model."""
    result: dict[str, dict[int, float]] = {}
    for label in THROUGHPUT:
        own = {r["n_cells"]: r["ns_per_cell_update"] for r in rows if r["model"] == label}
        if reference_n in own:
            result[label] = {n: cost / own[reference_n] for n, cost in sorted(own.items())}
    return result


# --------------------------------------------------------------------------- (b) work-precision
def work_precision(scene: str, cells: list[int], reconstructor: str = "mc") -> dict[str, Any]:
    study = convergence_study(scene, cells, [reconstructor], repeats=REPEATS, measure_import=False)
    seconds = [r.solve_median for r in study.rows]
    errors = [r.l1 for r in study.rows]
    for r in study.rows:
        print(
            f"  {scene:16s} N={r.n_cells:>6d} steps={r.steps:>6d} {r.solve_median:.4f} s "
            f"({r.solve_min:.4f}-{r.solve_max:.4f})  L1={r.l1:.3e}"
        )
    row: dict[str, Any] = {
        "scene": scene, "reconstructor": reconstructor, "cells": cells, "seconds": seconds,
        "min": [r.solve_min for r in study.rows], "max": [r.solve_max for r in study.rows],
        "steps": [r.steps for r in study.rows], "l1": errors,
    }  # fmt: skip
    for target in TARGETS:
        row[f"time_to_{target:g}"] = time_to_reach(cells, seconds, errors, target)
    return row


# --------------------------------------------------------------------------- (c) paper scene
def conslaw_command() -> list[str]:
    """The ``conslaw`` console script of this environment (else ``python -m conslaw.cli``)."""
    script = Path(sys.executable).with_name("conslaw")
    if script.exists():
        return [str(script)]
    found = shutil.which("conslaw")
    return [found] if found else [sys.executable, "-m", "conslaw.cli"]


def paper_scene() -> dict[str, Any]:
    """sh-similarity (90 cells, t = 6): solve time, and the whole ``conslaw run`` process."""
    scene = conslaw.load_scene("sh-similarity")
    warm = simulate(scene)  # compile or load the kernels
    solve = [simulate(scene).solve_seconds for _ in range(2 * REPEATS + 1)]
    front = conslaw.load_scene("sh-similarity-ft")
    simulate(front)
    front_solve = [simulate(front).solve_seconds for _ in range(REPEATS)]
    result: dict[str, Any] = {
        "scene": "sh-similarity", "n_cells": warm.grid.n_cells, "steps": warm.steps,
        "solve_median": statistics.median(solve), "solve_min": min(solve),
        "solve_max": max(solve),
        "front_tracking_solve_median": statistics.median(front_solve),
        "front_tracking_solve_min": min(front_solve), "front_tracking_solve_max": max(front_solve),
    }  # fmt: skip
    base = conslaw_command()
    with tempfile.TemporaryDirectory() as folder:
        runs = iter(range(100 * PROCESS_REPEATS))  # a fresh output folder for every run
        for label, extra in (("process", []), ("process_no_plot", ["--no-plot"])):
            cpu: list[float] = []

            def once(extra: list[str] = extra, cpu: list[float] = cpu) -> None:
                out = Path(folder) / f"run{next(runs)}"
                command = [*base, "run", "sh-similarity", *extra, "--out", str(out)]
                before = resource.getrusage(resource.RUSAGE_CHILDREN)
                subprocess.run(command, check=True, capture_output=True)
                after = resource.getrusage(resource.RUSAGE_CHILDREN)
                cpu.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)

            once()  # the compile cache is warm after this
            cpu.clear()
            median, low, high, _ = timed(once, PROCESS_REPEATS)
            result[f"{label}_median"] = median
            result[f"{label}_min"] = low
            result[f"{label}_max"] = high
            result[f"{label}_cpu_median"] = statistics.median(cpu)
    result["process_command"] = " ".join(
        [Path(base[0]).name, *base[1:], "run", "sh-similarity", "--out", "DIR"]
    )
    print(
        f"  sh-similarity: {warm.steps} steps, solve {result['solve_median'] * 1e3:.2f} ms; "
        f"front tracking (compiled) {result['front_tracking_solve_median'] * 1e3:.1f} ms; whole "
        f"process {result['process_median']:.2f} s ({result['process_min']:.2f}-"
        f"{result['process_max']:.2f}; CPU {result['process_cpu_median']:.2f} s), with "
        f"--no-plot {result['process_no_plot_median']:.2f} s ({result['process_no_plot_min']:.2f}"
        f"-{result['process_no_plot_max']:.2f}; CPU {result['process_no_plot_cpu_median']:.2f} s)"
    )
    return result


# --------------------------------------------------------------------------- (d) PyClaw
def pyclaw_available() -> bool:
    try:
        import clawpack.pyclaw
        import clawpack.riemann  # noqa: F401
    except ImportError:
        return False
    return True


def _dam_break(x: np.ndarray) -> list[np.ndarray]:
    return [np.where(x < 0.0, 3.0, 1.0), np.zeros_like(x)]


def _dry_dam_break(x: np.ndarray) -> list[np.ndarray]:
    return [np.where(x < 0.0, 1.0, 0.0), np.zeros_like(x)]


def _burgers_riemann(x: np.ndarray) -> list[np.ndarray]:
    return [np.where(x < 0.0, -0.5, np.where(x < 1.0, 1.0, 0.0))]


def _burgers_sine(x: np.ndarray) -> list[np.ndarray]:
    return [0.25 + 0.5 * np.sin(2.0 * np.pi * x)]


# The same problems as the conslaw scenes of the same name (domain, data, end time, boundaries).
# Jumps sit on cell faces for the N used, so point values are the exact cell averages.
PYCLAW_PROBLEMS: dict[str, dict[str, Any]] = {
    "dam-break-wet": {"solver": "shallow_roe_with_efix_1D", "domain": (-5.0, 5.0),
                      "t_end": 2.0, "periodic": False, "initial": _dam_break},
    # George's augmented solver (GeoClaw's, f-waves) with a flat bed (aux 0): a dry bed of
    # depth 0 at its default dry tolerance.
    "dam-break-dry": {"solver": "sw_aug_1D", "domain": (-5.0, 5.0), "t_end": 2.0,
                      "periodic": False, "initial": _dry_dam_break, "num_aux": 1,
                      "fwave": True, "dry_tolerance": 1e-3},
    "burgers-riemann": {"solver": "burgers_1D", "domain": (-1.0, 3.0), "t_end": 1.0,
                        "periodic": False, "initial": _burgers_riemann},
    "burgers-sine": {"solver": "burgers_1D", "domain": (0.0, 1.0), "t_end": 0.25,
                     "periodic": True, "initial": _burgers_sine},
}  # fmt: skip


def pyclaw_solve(
    problem: str, n: int, t_final: float | None = None, spec: dict[str, Any] | None = None
) -> tuple[float, int, Any, float]:
    """PyClaw classic (Fortran, MC limiter) on ``problem`` with N cells (or on the problem
    ``spec``, with the keys of PYCLAW_PROBLEMS, optionally ``num_aux`` (a flat bed) and
    ``dry_tolerance``). Returns the solve time (``Controller.run``), the number of time steps,
    variable 0 at the end, and the CPU time."""
    from clawpack import pyclaw, riemann

    spec = PYCLAW_PROBLEMS[problem] if spec is None else spec
    solver = pyclaw.ClawSolver1D(getattr(riemann, spec["solver"]))
    solver.limiters = pyclaw.limiters.tvd.MC
    solver.kernel_language = "Fortran"
    if "fwave" in spec:  # a solver that PyClaw's table does not describe (sw_aug_1D)
        solver.fwave = spec["fwave"]
    boundary = pyclaw.BC.periodic if spec["periodic"] else pyclaw.BC.extrap
    solver.bc_lower[0] = solver.bc_upper[0] = boundary
    solver.aux_bc_lower[0] = solver.aux_bc_upper[0] = boundary
    x = pyclaw.Dimension(*spec["domain"], n, name="x")
    domain = pyclaw.Domain(x)
    initial = spec["initial"](x.centers)
    state = pyclaw.State(domain, len(initial), spec.get("num_aux", 0))
    if spec.get("num_aux", 0):
        state.aux[:, :] = 0.0  # a flat bed
    dry_tolerance = spec.get("dry_tolerance", 1e-3)
    state.problem_data.update(
        {"grav": 1.0, "dry_tolerance": dry_tolerance, "sea_level": 0.0, "efix": True}
    )
    for v, values in enumerate(initial):
        state.q[v, :] = values
    controller = pyclaw.Controller()
    controller.solution = pyclaw.Solution(state, domain)
    controller.solver = solver
    controller.tfinal = spec["t_end"] if t_final is None else t_final
    controller.num_output_times = 1
    controller.output_format = None
    controller.keep_copy = True
    controller.verbosity = 0
    started, cpu_started = time.perf_counter(), time.process_time()
    controller.run()
    elapsed, cpu = time.perf_counter() - started, time.process_time() - cpu_started
    return elapsed, int(solver.status["numsteps"]), np.array(controller.frames[-1].q[0]), cpu


def pyclaw_throughput(
    problem: str, sizes: list[int], target_updates: float
) -> list[dict[str, Any]]:
    rows = []
    low_x, high_x = PYCLAW_PROBLEMS[problem]["domain"]
    for n in sizes:
        # About target_updates cell updates (Courant number 0.9, wave speeds up to about 3.4
        # for the dam break, 0.75 for the sine), never past the problem's end time.
        speed = 3.4 if problem == "dam-break-wet" else 0.75
        t_final = min(
            PYCLAW_PROBLEMS[problem]["t_end"],
            max(20.0, target_updates / n) * 0.9 * (high_x - low_x) / n / speed,
        )
        pyclaw_solve(problem, n, t_final)
        runs = [pyclaw_solve(problem, n, t_final) for _ in range(REPEATS)]
        wall = [r[0] for r in runs]
        median, low, high = statistics.median(wall), min(wall), max(wall)
        cpu = statistics.median(r[3] for r in runs)
        steps = runs[0][1]
        rate = n * steps / median
        rows.append(
            {"problem": problem, "n_cells": n, "steps": steps, "seconds": median, "min": low,
             "max": high, "cpu_seconds": cpu, "cell_updates_per_s": rate,
             "cell_updates_per_cpu_s": n * steps / cpu}
        )  # fmt: skip
        print(
            f"  pyclaw {problem:15s} N={n:>8d} steps={steps:>5d} {median:.4f} s "
            f"({low:.4f}-{high:.4f})  {rate:.3e} cell updates/s (per CPU second "
            f"{n * steps / cpu:.3e})"
        )
    return rows


def pyclaw_work_precision(problem: str, cells: list[int]) -> dict[str, Any]:
    exact = build(conslaw.load_scene(problem))[4]
    assert exact is not None
    low_x, high_x = PYCLAW_PROBLEMS[problem]["domain"]
    t_end = PYCLAW_PROBLEMS[problem]["t_end"]
    seconds, minima, maxima, errors, steps = [], [], [], [], []
    for n in cells:
        pyclaw_solve(problem, n)
        runs = [pyclaw_solve(problem, n) for _ in range(REPEATS)]
        wall = [r[0] for r in runs]
        median, low, high = statistics.median(wall), min(wall), max(wall)
        _, count, q0, _ = runs[-1]
        edges = np.linspace(low_x, high_x, n + 1)
        reference = exact.cell_averages(edges, t_end)[0]
        error = error_norms(q0, reference, (high_x - low_x) / n, high_x - low_x).l1
        seconds.append(median)
        minima.append(low)
        maxima.append(high)
        errors.append(error)
        steps.append(count)
        print(
            f"  pyclaw {problem:15s} N={n:>6d} steps={count:>6d} {median:.4f} s "
            f"({low:.4f}-{high:.4f})  L1={error:.3e}"
        )
    row: dict[str, Any] = {
        "scene": problem, "cells": cells, "seconds": seconds, "min": minima, "max": maxima,
        "steps": steps, "l1": errors,
    }  # fmt: skip
    for target in TARGETS:
        row[f"time_to_{target:g}"] = time_to_reach(cells, seconds, errors, target)
    return row


def pyclaw_dry_dam_break() -> list[dict[str, Any]]:
    """PyClaw's shallow-water solvers on dam-break-dry (h = 1|b, the "dry" bed of depth b) for a
    few beds, tolerances and N: which of them run it. Each row gives the L1 error against the
    exact dry-bed solution, or None for NaN. Only the augmented solver ``sw_aug_1D`` (George
    2008, the solver of GeoClaw) runs it on a bed of depth 0; it is the PyClaw row of the
    work-precision table."""
    from clawpack import riemann

    exact = build(conslaw.load_scene("dam-break-dry"))[4]
    assert exact is not None
    trials = [
        (solver, bed, 1e-3, 400)
        for solver in ("shallow_roe_with_efix_1D", "shallow_hlle_1D")
        for bed in (0.0, 1e-12, 1e-8)
    ]
    fwave = "shallow_bathymetry_fwave_1D"
    trials += [(fwave, 0.0, 1e-3, 400)]
    trials += [(fwave, 1e-12, 1e-3, n) for n in (400, 800, 1600, 3200)]
    trials += [(fwave, 1e-12, tolerance, 400) for tolerance in (1e-8, 1e-14)]
    trials += [("sw_aug_1D", 0.0, 1e-3, n) for n in (400, 3200)]
    rows = []
    for solver, bed, tolerance, n in trials:
        if not hasattr(riemann, solver):
            continue
        spec = {
            "solver": solver, "domain": (-5.0, 5.0), "t_end": 2.0, "periodic": False,
            "initial": lambda x, bed=bed: [np.where(x < 0.0, 1.0, bed), np.zeros_like(x)],
            "num_aux": 1 if solver in (fwave, "sw_aug_1D") else 0, "dry_tolerance": tolerance,
            "fwave": solver in (fwave, "sw_aug_1D"),
        }  # fmt: skip
        with np.errstate(all="ignore"):
            _, steps, h, _ = pyclaw_solve("dam-break-dry", n, spec=spec)
            edges = np.linspace(-5.0, 5.0, n + 1)
            reference = exact.cell_averages(edges, 2.0)[0]
            l1 = error_norms(h, reference, 10.0 / n, 10.0).l1
        rows.append(
            {"solver": solver, "bed": bed, "dry_tolerance": tolerance, "n_cells": n,
             "steps": steps, "l1": l1 if math.isfinite(l1) else None}
        )  # fmt: skip
        print(
            f"  pyclaw dam-break-dry {solver:28s} bed={bed:<6g} dry_tolerance={tolerance:<6g} "
            f"N={n:>5d} steps={steps:>5d} L1={l1:.3e}"
        )
    return rows


def resident_megabytes() -> float:
    """Current resident set size of this process (Linux /proc; NaN elsewhere)."""
    try:
        pages = int(Path("/proc/self/statm").read_text().split()[1])
    except (OSError, IndexError, ValueError):
        return float("nan")
    return pages * os.sysconf("SC_PAGE_SIZE") / 2**20


def memory(n: int = 1000) -> dict[str, Any]:
    """Resident size and numba (NRT) allocations after advancing 100 and 10000 step pairs."""
    from numba.core.runtime import _nrt_python, rtsys

    sc = conslaw.load_scene("dam-break-wet", {"n_cells": n, "output_times": [], "x_min": -50.0,
                                              "x_max": 50.0})  # fmt: skip
    _, _, scheme, initial, _ = build(sc)
    dt = scheme.stable_dt(initial)
    scheme.advance(initial, 2 * dt)
    _nrt_python.memsys_enable_stats()
    result: dict[str, Any] = {"n_cells": n, "rss_mb_before": resident_megabytes()}
    for pairs in (100, 10_000):
        calls: list[float] = []  # the progress callback runs once per call of the kernel
        before = rtsys.get_allocation_stats().alloc
        advanced = scheme.advance(initial, 2 * pairs * dt, lambda t, _, c=calls: c.append(t))
        allocations = rtsys.get_allocation_stats().alloc - before
        result[f"steps_{pairs}"] = advanced.steps
        result[f"kernel_calls_{pairs}"] = len(calls)
        result[f"allocations_{pairs}"] = allocations
        result[f"rss_mb_{pairs}"] = resident_megabytes()
        print(
            f"  N={n}, {advanced.steps} steps in {len(calls)} kernel calls: RSS "
            f"{result[f'rss_mb_{pairs}']:.1f} MB, {allocations} numba allocations "
            f"({allocations / len(calls):.0f} per call, {allocations / advanced.steps:.4f} per "
            "step)"
        )
    return result


# --------------------------------------------------------------------------- summary, plot
def ratios(report: dict[str, Any]) -> dict[str, Any]:
    """conslaw / PyClaw: rate ratios (higher is better for conslaw) and time ratios (lower)."""
    pyclaw = report.get("pyclaw")
    if not pyclaw:
        return {}
    ours = {(r["model"], r["n_cells"]): r for r in report["throughput"]}
    result: dict[str, Any] = {"rate": {}, "rate_cpu": {}, "time_to": {}}
    for label, problem in (("shallow-water", "dam-break-wet"), ("burgers", "burgers-sine")):
        for row in pyclaw["throughput"][problem]:
            key = (label, row["n_cells"])
            if key in ours:
                ratio = ours[key]["cell_updates_per_s"] / row["cell_updates_per_s"]
                cpu_ratio = ours[key]["cell_updates_per_cpu_s"] / row["cell_updates_per_cpu_s"]
                result["rate"][f"{label} N={row['n_cells']}"] = ratio
                result["rate_cpu"][f"{label} N={row['n_cells']}"] = cpu_ratio
                print(
                    f"  {label} N={row['n_cells']}: conslaw / PyClaw rate {ratio:.2f} "
                    f"(per CPU second {cpu_ratio:.2f})"
                )
    mine = {row["scene"]: row for row in report["work_precision"]}
    for problem, theirs in pyclaw["work_precision"].items():
        for target in TARGETS:
            key = f"time_to_{target:g}"
            if mine[problem][key] and theirs[key]:
                ratio = mine[problem][key] / theirs[key]
                result["time_to"][f"{problem} {key}"] = ratio
                print(
                    f"  {problem} time to L1 = {target:g}: conslaw {mine[problem][key]:.4f} s, "
                    f"PyClaw {theirs[key]:.4f} s, ratio {ratio:.3f}"
                )
    return result


def plot_work_precision(report: dict[str, Any], path: str) -> None:
    """Error against solve time, conslaw and PyClaw, log-log."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axis = plt.subplots(figsize=(7.0, 4.6))
    colours = {"dam-break-wet": "C0", "dam-break-dry": "C1", "burgers-riemann": "C2"}
    for row in report["work_precision"]:
        axis.loglog(row["seconds"], row["l1"], "o-", color=colours[row["scene"]],
                    label=f"conslaw NT, {row['scene']}")  # fmt: skip
    for problem, row in (report.get("pyclaw") or {}).get("work_precision", {}).items():
        axis.loglog(row["seconds"], row["l1"], "s--", color=colours[problem],
                    label=f"PyClaw classic, {problem}")  # fmt: skip
    for target in TARGETS:
        axis.axhline(target, color="0.6", lw=0.8, ls=":")
    axis.set_xlabel("solve time [s] (median of 3)")
    axis.set_ylabel("L1 error of the depth / u against the exact cell averages")
    axis.set_title("Work-precision, MC limiter, N = 100 ... 12800")
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)
    print(f"  wrote {path}")


def environment() -> dict[str, Any]:
    import numba

    try:
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True,
            cwd=Path(__file__).resolve().parent,
        ).stdout.strip()  # fmt: skip
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {
        "date": datetime.datetime.now().isoformat(timespec="seconds"), "commit": commit,
        "cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(),
        "numpy": np.__version__, "numba": numba.__version__,
    }  # fmt: skip


def warm_kernels() -> None:
    """Compile every kernel this benchmark times into the cache. Run in a child process before
    anything is timed: a kernel compiled in the timing process itself runs several times slower
    than one loaded from the cache (``benchmarks/fresh_compile.py``), so a cold cache would
    otherwise be measured as a slow kernel."""
    scenes = [(scene, {"reconstructor": r}) for scene, r in THROUGHPUT.values()]
    scenes += [(scene, {"reconstructor": "mc"}) for scene in WORK_PRECISION_SCENES]
    scenes += [("sh-similarity", {}), ("sh-similarity-ft", {})]
    for name, options in scenes:
        simulate(conslaw.load_scene(name, {"n_cells": 40, "output_times": [], **options}))


def main() -> None:
    parser = argparse.ArgumentParser(description="conslaw benchmarks")
    parser.add_argument("--quick", action="store_true", help="smaller sizes (a smoke test)")
    parser.add_argument("--json", help="write all numbers to this JSON file")
    parser.add_argument("--plot", help="write the work-precision figure (PNG) to this file")
    parser.add_argument("--warm-kernels", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.warm_kernels:
        warm_kernels()
        return
    subprocess.run([sys.executable, __file__, "--warm-kernels"], check=True)
    sizes = [1000, 10000] if args.quick else [1000, 10000, 100000, 1000000]
    cells = [100, 200, 400] if args.quick else [100, 200, 400, 800, 1600, 3200, 6400, 12800]
    target = 2e6 if args.quick else 2e7
    report: dict[str, Any] = {"environment": environment(), "load": {}}
    print(f"environment: {report['environment']}")

    def section(name: str, function: Callable[[], Any]) -> Any:
        print(f"{name} (load average {load():.2f})")
        started = load()
        value = function()
        report["load"][name.split()[0]] = [started, load()]
        return value

    report["throughput"] = section("(a) throughput of the fused NT kernel",
                                   lambda: throughput(sizes, target))  # fmt: skip
    report["linearity"] = linearity(report["throughput"])
    for label, relative in report["linearity"].items():
        values = ", ".join(f"N={n}: {r:.2f}" for n, r in relative.items())
        print(f"  cost per cell update relative to N=1e4, {label}: {values}")
    report["work_precision"] = section(
        "(b) work-precision (mc)",
        lambda: [work_precision(scene, cells) for scene in WORK_PRECISION_SCENES],
    )
    report["paper_scene"] = section("(c) paper scene", paper_scene)
    if pyclaw_available():

        def run_pyclaw() -> dict[str, Any]:
            dry = pyclaw_dry_dam_break()
            return {
                "throughput": {
                    problem: pyclaw_throughput(problem, sizes, target)
                    for problem in ("dam-break-wet", "burgers-sine")
                },
                "work_precision": {
                    problem: pyclaw_work_precision(problem, cells)
                    for problem in WORK_PRECISION_SCENES
                },
                "dry_dam_break": dry,
            }

        report["pyclaw"] = section("(d) PyClaw", run_pyclaw)
        print("ratios (same run)")
        report["ratios"] = ratios(report)
    else:
        print("(d) PyClaw skipped: clawpack is not installed (pip install clawpack)")
        report["pyclaw"] = None
    report["memory"] = section("(e) memory", memory)
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(report, handle, indent=2)
        print(f"  wrote {args.json}")
    if args.plot:
        plot_work_precision(report, args.plot)


if __name__ == "__main__":
    main()
