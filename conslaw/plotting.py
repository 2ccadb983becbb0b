"""Plots of runs and studies: profiles against the exact solution, the x–t diagram, margin
trajectories, the chute in elevation with the flowing mass, work-precision plots.

Figures are :class:`matplotlib.figure.Figure` objects made without pyplot: importing this module
leaves the matplotlib backend alone (a notebook's inline backend keeps working), and the figures
are written as PNG through the Agg renderer whatever the backend."""

from __future__ import annotations

from collections.abc import Callable, Collection, Sequence
from typing import TYPE_CHECKING, Any

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from conslaw.io import write_figure

if TYPE_CHECKING:
    from pathlib import Path

    from conslaw.result import RunResult


def _display_rows(model: Any, q: Any, film: float = 0.0) -> list[tuple[str, Any]]:
    """What to plot: the conserved variables, or depth and velocity for depth-averaged models.
    The velocity is left out (NaN) where the depth is below ``film`` times the largest depth:
    the thin film a flow leaves behind moves, but its velocity says nothing about the body."""
    d, m = model.depth_index, model.momentum_index
    if d is None or m is None:
        return [(name, q[v]) for v, name in enumerate(model.variables)]
    h = q[d]
    deepest = float(np.max(h)) if h.size else 0.0
    wet = h > max(model.dry_depth(), 1e-12, film * deepest)
    u = np.full_like(h, np.nan)
    u[wet] = q[m][wet] / h[wet]
    return [(model.variables[d], h), ("u", u)]


def axis_label(model: Any, name: str, lines: int = 1) -> str:
    """``name`` with what it is, from the model's long names (``h: depth ...``); with
    ``lines = 2`` (a y axis) the long name goes on a second line, without "(dimensionless)"
    (the x axis says it for the whole figure)."""
    long_name = model.long_names.get(name)
    if not long_name:
        return name
    if lines == 2:
        return f"{name}\n{long_name.replace(' (dimensionless)', '')}"
    return f"{name}: {long_name}"


#: Velocities are drawn where the depth is at least this fraction of the largest depth.
FILM_FRACTION = 1e-3
#: The colours of successive output times: a sequential map whose ends stay apart.
TIME_COLOURS = "plasma"


def time_colours(count: int) -> Any:
    """``count`` colours for output times in order, dark to light."""
    return matplotlib.colormaps[TIME_COLOURS](np.linspace(0.0, 0.88, count))


#: Output times from which ``conslaw run`` also draws the x–t diagram (``xt.png``).
XT_MIN_OUTPUTS = 10
#: Grids up to this many cells are drawn with open circles (one per cell), finer ones with dots.
COARSE_GRID = 200
#: Most profiles drawn in one figure (evenly chosen among the output times beyond that).
MAX_PROFILES = 6


def select_states(
    result: RunResult, times: Sequence[float] | None = None, at_most: int = MAX_PROFILES
) -> list[Any]:
    """The output states at ``times`` (the nearest output time to each), or, without
    ``times``, at most ``at_most`` of them evenly spread, the first and last included."""
    states = result.states
    if times is None:
        if len(states) <= at_most:
            return list(states)
        picks = np.unique(np.round(np.linspace(0, len(states) - 1, at_most)).astype(int))
        return [states[k] for k in picks]
    t = np.array([s.t for s in states])
    return [states[int(np.argmin(np.abs(t - wanted)))] for wanted in times]


def profiles_figure(result: RunResult, times: Sequence[float] | None = None) -> Any:
    """Profiles at the output times against the exact solution (black dashed line): the
    conserved variables, or depth and velocity for a depth-averaged model (paper Figs. 4 and
    5). ``times`` selects the output times drawn (see :func:`select_states`); the initial
    state is drawn in grey when it is not one of them. The axes say what each quantity is (the
    model's long names, with its scales), the chute's features (a curved transition) are
    shaded, and the title says which error is shown, or that there is no exact solution, and
    how many of the output times are drawn."""
    model = result.model
    rows = len(_display_rows(model, result.states[0].q))
    figure = Figure(figsize=(8, 3.2 * rows))
    axes = figure.subplots(rows, 1, sharex=True, squeeze=False)
    shown = select_states(result, times)
    fine = np.linspace(result.grid.x_min, result.grid.x_max, 4001)
    # Open circles as in the paper where the cells can be told apart, lines on fine grids.
    coarse = result.grid.n_cells <= COARSE_GRID
    style = ("o", {"ms": 4.5, "mfc": "none", "mew": 0.9}) if coarse else ("-", {"lw": 1.4})
    if all(state.t != result.initial.t for state in shown):
        rows_then = _display_rows(model, result.initial.q, FILM_FRACTION)
        for axis, (_, values) in zip(axes[:, 0], rows_then, strict=True):
            axis.plot(
                result.initial.x, values, "-", color="0.6", lw=1.0,
                label=f"t = {result.initial.t:g} (initial)",
            )  # fmt: skip
    for state, colour in zip(shown, time_colours(len(shown)), strict=True):
        rows_now = _display_rows(model, state.q, FILM_FRACTION)
        for axis, (name, values) in zip(axes[:, 0], rows_now, strict=True):
            axis.plot(state.x, values, style[0], color=colour, label=f"t = {state.t:g}", **style[1])
            axis.set_ylabel(axis_label(model, name, lines=2), fontsize=8.5)
        if result.exact_solution is not None:
            exact = result.exact_solution.point_values(fine, state.t)
            with np.errstate(invalid="ignore", divide="ignore"):
                exact_rows = _display_rows(model, exact)
            for axis, (_, values) in zip(axes[:, 0], exact_rows, strict=True):
                axis.plot(
                    fine, values, "k--", lw=0.9, zorder=3,
                    label="exact" if state is shown[-1] else None,
                )  # fmt: skip
    chute = getattr(model, "chute", None)
    for start, end, label in chute.features() if chute is not None else []:
        for axis in axes[:, 0]:
            axis.axvspan(start, end, color="0.85", zorder=0, lw=0)
        axes[0, 0].text(
            0.5 * (start + end), 0.98, label, transform=axes[0, 0].get_xaxis_transform(),
            ha="center", va="top", fontsize=8, color="0.35",
        )  # fmt: skip
    for axis in axes[:, 0]:
        axis.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=8, loc="best")
    axes[-1, 0].set_xlabel(axis_label(model, "x"), fontsize=9)
    if model.depth_index is not None and model.momentum_index is not None:
        axes[-1, 0].text(
            0.01, 0.02, f"u drawn where h >= {FILM_FRACTION:g} x the largest depth",
            transform=axes[-1, 0].transAxes, fontsize=7, color="0.4",
        )  # fmt: skip
    axes[0, 0].set_title(
        f"{result.scene.name}: {run_label(result)}\n{_error_label(result)}"
        f"{times_label(result, shown)}",
        fontsize=10,
    )
    figure.tight_layout()
    return figure


def run_label(result: RunResult) -> str:
    """Model, scheme (with its options), reconstructor where the scheme uses one, and grid."""
    scene = result.scene
    parts = [result.model.name, scene.scheme_label]
    if scene.reconstructor_label != "-":
        parts.append(scene.reconstructor_label)
    if scene.front_tracking and "front" not in scene.scheme:
        parts.append("front tracking")
    return ", ".join(parts) + f", N={result.grid.n_cells}"


def _error_label(result: RunResult) -> str:
    """What the title says about the exact solution."""
    if result.exact_solution is None:
        return "no exact solution for this scene"
    error = result.headline_error()
    if error is None:
        return "exact solution: dashed line"
    name = result.model.variables[0]
    return f"L1({name}) at t = {result.final.t:g}: {error:.3e}; exact: dashed line"


def times_label(result: RunResult, shown: Sequence[Any]) -> str:
    """``; 6 of 8 output times drawn`` when some are left out."""
    if len(shown) < len(result.states):
        return f"; {len(shown)} of {len(result.states)} output times drawn"
    return ""


def _study_lines(study: Any) -> dict[str, list[Any]]:
    lines: dict[str, list[Any]] = {}
    for row in study.rows:
        lines.setdefault(f"{row.scheme}, {row.reconstructor}", []).append(row)
    return lines


def error_against_time_figure(study: Any) -> Any:
    """Work-precision plot: L1 error against the median solve time, one line per
    (scheme, reconstructor), each point labelled with its N (log-log)."""
    figure = Figure(figsize=(7, 5))
    axis = figure.subplots()
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
    figure = Figure(figsize=(7, 5))
    axis = figure.subplots()
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
    (dashed, on top) where the exact solution provides them; the exact velocities are the
    derivatives of the exact positions."""
    margins = result.margins
    assert margins is not None
    model = result.model
    figure = Figure(figsize=(8, 6))
    position_axis, velocity_axis = figure.subplots(2, 1, sharex=True)
    exact_margins = getattr(result.exact_solution, "margins", None)
    for column, name, colour in ((1, "rear", "tab:blue"), (3, "front", "tab:red")):
        if np.all(np.isnan(margins[:, column])):
            continue
        position_axis.plot(margins[:, 0], margins[:, column], "-", color=colour, label=name)
        velocity_axis.plot(margins[:, 0], margins[:, column + 1], "-", color=colour, label=name)
    if exact_margins is not None:
        times = np.linspace(margins[0, 0], margins[-1, 0], 400)
        exact = np.array([exact_margins(t) for t in times])
        for k in (0, 1):
            label = "exact" if k == 0 else None
            position_axis.plot(times, exact[:, k], "k--", lw=0.9, zorder=3, label=label)
            velocity = np.gradient(exact[:, k], times)
            velocity_axis.plot(times, velocity, "k--", lw=0.9, zorder=3, label=label)
    position_axis.set_ylabel(f"margin position\n{axis_label(model, 'x')}", fontsize=8.5)
    velocity_axis.set_ylabel(f"margin velocity\n{axis_label(model, 'u')}", fontsize=8.5)
    velocity_axis.set_xlabel(axis_label(model, "t"), fontsize=9)
    for axis in (position_axis, velocity_axis):
        axis.grid(alpha=0.3)
        axis.legend(fontsize=8, loc="best")
    position_axis.set_title(
        f"{result.scene.name}: tracked margins; {run_label(result)}", fontsize=10
    )
    figure.tight_layout()
    return figure


def xt_figure(result: RunResult) -> Any:
    """x–t diagram of the depth (or of the first variable): colour = value in every cell at
    every output time, so a shock shows as a line across which the colour jumps; tracked
    margins drawn on top. Needs enough output times to resolve the motion (``output_times``)."""
    model = result.model
    row = model.depth_index if model.depth_index is not None else 0
    t = np.array([s.t for s in result.states])
    values = np.array([s.q[row] for s in result.states])
    # Each output time owns the band up to half-way to its neighbours.
    if t.size < 2:
        raise ValueError("an x-t diagram needs at least two output times")
    middles = 0.5 * (t[1:] + t[:-1])
    t_edges = np.concatenate(
        [[t[0] - (middles[0] - t[0])], middles, [t[-1] + (t[-1] - middles[-1])]]
    )
    figure = Figure(figsize=(8, 5.5))
    axis = figure.subplots()
    mesh = axis.pcolormesh(result.grid.edges, t_edges, values, cmap="viridis", shading="flat")
    figure.colorbar(mesh, ax=axis, label=model.variables[row])
    if result.margins is not None:
        for column, name in ((1, "rear margin"), (3, "front margin")):
            if not np.all(np.isnan(result.margins[:, column])):
                axis.plot(result.margins[:, column], result.margins[:, 0], "w-", lw=1.0, label=name)
        axis.legend(fontsize=8, loc="upper left")
    axis.set_xlabel("x (along the bed)")
    axis.set_ylabel("t")
    axis.set_ylim(t[0], t[-1])
    axis.set_title(
        f"{result.scene.name}: {model.variables[row]}(x, t), {result.scene.reconstructor}, "
        f"N={result.grid.n_cells}, {len(t)} output times",
        fontsize=10,
    )
    figure.tight_layout()
    return figure


def figures_for(result: RunResult) -> list[tuple[str, Callable[[RunResult], Any]]]:
    """The figures of a run: ``profiles.png``; ``margins.png`` with front tracking; the model's
    own (:meth:`conslaw.model.Model.figures`, e.g. Savage–Hutter's ``chute.png``); ``xt.png``
    with at least :data:`XT_MIN_OUTPUTS` output times."""
    figures: list[tuple[str, Callable[[RunResult], Any]]] = [("profiles.png", profiles_figure)]
    if result.margins is not None:
        figures.append(("margins.png", margins_figure))
    figures.extend(result.model.figures().items())
    if len(result.states) >= XT_MIN_OUTPUTS:
        figures.append(("xt.png", xt_figure))
    return figures


def draw_figures(
    result: RunResult, folder: Path, names: Collection[str] | None = None
) -> list[Path]:
    """The figures of :func:`figures_for` (only those in ``names`` if given), drawn in this
    process and written atomically (:func:`conslaw.io.write_figure`); returns their paths."""
    written = []
    for name, build in figures_for(result):
        if names is None or name in names:
            written.append(write_figure(folder / name, build(result)))
    return written
