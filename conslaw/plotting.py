"""Plots of runs: profiles at the output times against the exact solution."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

if TYPE_CHECKING:
    from conslaw.simulation import RunResult


def _display_rows(model: Any, q: Any) -> list[tuple[str, Any]]:
    """What to plot: the conserved variables, or depth and velocity for depth-averaged models."""
    d, m = model.depth_index, model.momentum_index
    if d is None or m is None:
        return [(name, q[v]) for v, name in enumerate(model.variables)]
    h = q[d]
    wet = h > max(model.dry_depth(), 1e-12)
    u = np.full_like(h, np.nan)
    u[wet] = q[m][wet] / h[wet]
    return [(model.variables[d], h), ("u", u)]


def profiles_figure(result: RunResult) -> Any:
    """Profiles at every output time (markers) against the exact solution (black line):
    the conserved variables, or depth and velocity for a depth-averaged model (paper Fig. 4)."""
    model = result.model
    rows = len(_display_rows(model, result.states[0].q))
    figure, axes = plt.subplots(rows, 1, figsize=(8, 3.2 * rows), sharex=True, squeeze=False)
    colours = plt.cm.viridis(np.linspace(0.0, 0.85, len(result.states)))
    fine = np.linspace(result.grid.x_min, result.grid.x_max, 4001)
    for state, colour in zip(result.states, colours, strict=True):
        label = f"{result.scene.scheme}, t={state.t:g}"
        for axis, (name, values) in zip(axes[:, 0], _display_rows(model, state.q), strict=True):
            axis.plot(state.x, values, "o", ms=2.5, color=colour, label=label)
            axis.set_ylabel(name)
        if result.exact_solution is not None:
            exact = result.exact_solution.point_values(fine, state.t)
            with np.errstate(invalid="ignore", divide="ignore"):
                exact_rows = _display_rows(model, exact)
            for axis, (_, values) in zip(axes[:, 0], exact_rows, strict=True):
                axis.plot(
                    fine,
                    values,
                    "k-",
                    lw=0.9,
                    label="exact" if state is result.states[-1] else None,
                )
    for axis in axes[:, 0]:
        axis.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=8, loc="best")
    axes[-1, 0].set_xlabel("x")
    error = result.headline_error()
    subtitle = f", L1 error {error:.3e}" if error is not None else ""
    axes[0, 0].set_title(
        f"{result.scene.name}: {model.name}, {result.scene.reconstructor_label}"
        f"{' + front tracking' if result.scene.front_tracking else ''}, "
        f"N={result.grid.n_cells}{subtitle}",
        fontsize=10,
    )
    figure.tight_layout()
    return figure


def chute_figure(result: RunResult, exaggeration: float = 3.0) -> Any:
    """Paper Fig. 3 style: one panel per output time, the chute drawn in elevation (not arc
    length) and the flowing mass on it, its depth laid off normal to the bed and exaggerated by
    ``exaggeration`` so that it is visible against the chute."""
    model = result.model
    chute = getattr(model, "chute")  # noqa: B009 (only models with a chute get this figure)
    x = result.grid.centres()
    horizontal, vertical = chute.elevation_profile(x)
    angle = chute.zeta(x)
    count = len(result.states)
    figure, axes = plt.subplots(count, 1, figsize=(9, 1.6 * count), sharex=True, squeeze=False)
    for axis, state in zip(axes[:, 0], result.states, strict=True):
        h = exaggeration * state.q[model.depth_index]
        top_x = horizontal - h * np.sin(angle)
        top_z = vertical + h * np.cos(angle)
        axis.plot(horizontal, vertical, "k-", lw=1.0)
        axis.fill(
            np.concatenate([horizontal, top_x[::-1]]),
            np.concatenate([vertical, top_z[::-1]]),
            color="tab:orange", alpha=0.8, lw=0,
        )  # fmt: skip
        axis.set_ylabel("z")
        axis.text(0.98, 0.85, f"t = {state.t:g}", transform=axis.transAxes, ha="right", fontsize=9)
    axes[-1, 0].set_xlabel("horizontal position")
    axes[0, 0].set_title(
        f"{result.scene.name}: {model.name}, {result.scene.reconstructor_label}, "
        f"N={result.grid.n_cells} (depth drawn x{exaggeration:g}, normal to the bed)",
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


def margins_figure(result: RunResult) -> Any:
    """Margin positions and velocities against time (front tracking), with the exact margins
    where the exact solution provides them."""
    margins = result.margins
    assert margins is not None
    figure, (position_axis, velocity_axis) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    exact_margins = getattr(result.exact_solution, "margins", None)
    for column, name, colour in ((1, "rear", "tab:blue"), (3, "front", "tab:red")):
        if np.all(np.isnan(margins[:, column])):
            continue
        position_axis.plot(margins[:, 0], margins[:, column], "-", color=colour, label=name)
        velocity_axis.plot(margins[:, 0], margins[:, column + 1], "-", color=colour, label=name)
    if exact_margins is not None:
        times = np.linspace(margins[0, 0], margins[-1, 0], 200)
        exact = np.array([exact_margins(t) for t in times])
        position_axis.plot(times, exact[:, 0], "k--", lw=0.9, label="exact")
        position_axis.plot(times, exact[:, 1], "k--", lw=0.9)
    position_axis.set_ylabel("margin position x")
    velocity_axis.set_ylabel("margin velocity u")
    velocity_axis.set_xlabel("t")
    for axis in (position_axis, velocity_axis):
        axis.grid(alpha=0.3)
        axis.legend(fontsize=8, loc="best")
    position_axis.set_title(f"{result.scene.name}: tracked margins")
    figure.tight_layout()
    return figure
