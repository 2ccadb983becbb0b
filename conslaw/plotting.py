"""Plots of runs: profiles at the output times against the exact solution."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

if TYPE_CHECKING:
    from conslaw.simulation import RunResult


def profiles_figure(result: RunResult) -> Any:
    """One panel per conserved variable: numerical cell averages (markers) at every output
    time, the exact solution (black line) where the model has one."""
    model = result.model
    n_vars = model.n_vars
    figure, axes = plt.subplots(n_vars, 1, figsize=(8, 3.2 * n_vars), sharex=True, squeeze=False)
    colours = plt.cm.viridis(np.linspace(0.0, 0.85, len(result.states)))
    fine = np.linspace(result.grid.x_min, result.grid.x_max, 4001)
    for v, name in enumerate(model.variables):
        axis = axes[v, 0]
        for state, colour in zip(result.states, colours, strict=True):
            axis.plot(
                state.x,
                state.q[v],
                "o",
                ms=2.5,
                color=colour,
                label=f"{result.scene.scheme}, t={state.t:g}",
            )
            if result.exact_solution is not None:
                axis.plot(
                    fine,
                    result.exact_solution.point_values(fine, state.t)[v],
                    "k-",
                    lw=0.9,
                    label="exact" if state is result.states[-1] else None,
                )
        axis.set_ylabel(name)
        axis.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=8, loc="best")
    axes[-1, 0].set_xlabel("x")
    error = result.headline_error()
    subtitle = f", L1 error {error:.3e}" if error is not None else ""
    axes[0, 0].set_title(
        f"{result.scene.name}: {model.name}, {result.scene.reconstructor}, "
        f"N={result.grid.n_cells}{subtitle}",
        fontsize=10,
    )
    figure.tight_layout()
    return figure


def _study_lines(study: Any) -> dict[str, list[Any]]:
    lines: dict[str, list[Any]] = {}
    for row in study.rows:
        lines.setdefault(f"{row.scheme}, {row.reconstructor}", []).append(row)
    return lines


def error_against_time_figure(study: Any) -> Any:
    """Work-precision plot: L1 error against the median solve time, one line per
    (scheme, reconstructor), each point labelled with its N (log-log)."""
    figure, axis = plt.subplots(figsize=(7, 5))
    for label, rows in _study_lines(study).items():
        times = [r.solve_median for r in rows]
        errors = [r.l1 for r in rows]
        axis.loglog(times, errors, "o-", label=label)
        for r in rows:
            axis.annotate(
                str(r.n_cells),
                (r.solve_median, r.l1),
                fontsize=7,
                xytext=(3, 3),
                textcoords="offset points",
            )
    axis.set_xlabel("solve wall time [s] (median; compilation excluded)")
    axis.set_ylabel("L1 error against exact cell averages")
    axis.set_title(f"{study.scene}: error against run time (t = {study.t_end:g})", fontsize=10)
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=8)
    figure.tight_layout()
    return figure


def error_against_cells_figure(study: Any) -> Any:
    """L1 error against N (log-log) with reference slopes 1 and 2."""
    figure, axis = plt.subplots(figsize=(7, 5))
    all_rows = study.rows
    for label, rows in _study_lines(study).items():
        axis.loglog([r.n_cells for r in rows], [r.l1 for r in rows], "o-", label=label)
    n = np.array(sorted({r.n_cells for r in all_rows}), dtype=float)
    top = max(r.l1 for r in all_rows)
    for slope, style in ((1, "k--"), (2, "k:")):
        axis.loglog(n, top * (n / n[0]) ** (-slope), style, lw=0.8, label=f"order {slope}")
    axis.set_xlabel("number of cells N")
    axis.set_ylabel("L1 error against exact cell averages")
    axis.set_title(f"{study.scene}: error against N (t = {study.t_end:g})", fontsize=10)
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=8)
    figure.tight_layout()
    return figure
