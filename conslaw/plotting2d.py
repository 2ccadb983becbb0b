"""Figures of a 2D run (docs/output.md, "2D runs"): ``map.png``, the first variable (the depth
of shallow water) at the last output as a colour map with contours, beside its error against
the exact cell averages where there is an exact solution; ``cuts.png``, the first variable along
the middle row and the middle column at the output times, with the exact cuts dashed.

Made without pyplot, like :mod:`conslaw.plotting`: the backend is left alone."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

from conslaw.io import write_figure
from conslaw.peak_fields import REACHED_DEPTH
from conslaw.plotting import MAX_PROFILES, axis_label, time_colours
from conslaw.terrain.hazard_figure import hazard_map_figure
from conslaw.terrain.hazard_maps import hazard_maps

if TYPE_CHECKING:
    from conslaw.result2d import RunResult2D

#: Contour lines on a map.
CONTOURS = 10


def map_figure(result: RunResult2D) -> Figure:
    """The first variable at the last output, colour and contours, equal aspect; and the error
    map against the exact cell averages, if there is an exact solution."""
    model, grid, state = result.model, result.grid, result.final
    exact = result.exact[-1] if result.exact else None
    panels = 1 if exact is None else 2
    figure = Figure(figsize=(6.0 * panels, 5.2), layout="constrained")
    axes = figure.subplots(1, panels, squeeze=False)[0]
    x_edges, y_edges = grid.x.edges, grid.y.edges
    x, y = grid.centres()
    name = model.variables[0]
    values = state.q[0]
    mesh = axes[0].pcolormesh(x_edges, y_edges, values, cmap="viridis", shading="flat")
    if np.ptp(values) > 0.0:
        axes[0].contour(x, y, values, levels=CONTOURS, colors="white", linewidths=0.5)
    figure.colorbar(mesh, ax=axes[0], label=axis_label(model, name))
    axes[0].set_title(f"{name} at t={state.t:.4g}")
    if exact is not None:
        error = values - exact[0]
        bound = float(np.max(np.abs(error))) or 1.0
        error_mesh = axes[1].pcolormesh(
            x_edges, y_edges, error, cmap="RdBu_r", vmin=-bound, vmax=bound, shading="flat"
        )
        figure.colorbar(error_mesh, ax=axes[1], label=f"{name} - exact cell average")
        axes[1].set_title(f"error at t={state.t:.4g}")
    for axis in axes:
        axis.set_aspect("equal")
        axis.set_xlabel("x")
        axis.set_ylabel("y")
    figure.suptitle(
        f"{result.scene.name}: {result.scene.model}, {result.scene.scheme}, "
        f"{result.scene.reconstructor}, {grid.x.n_cells} x {grid.y.n_cells}"
    )
    return figure


def cuts_figure(result: RunResult2D) -> Figure:
    """The first variable along the middle row (against x) and the middle column (against y)
    at up to :data:`~conslaw.plotting.MAX_PROFILES` output times; exact cuts dashed."""
    model, grid = result.model, result.grid
    count = len(result.states)
    chosen = sorted({round(k) for k in np.linspace(0, count - 1, min(count, MAX_PROFILES))})
    figure = Figure(figsize=(10, 4), layout="constrained")
    along_x, along_y = figure.subplots(1, 2)
    x, y = grid.centres()
    row, column = grid.y.n_cells // 2, grid.x.n_cells // 2
    name = model.variables[0]
    for colour, index in zip(time_colours(len(chosen)), chosen, strict=True):
        state, exact = result.states[index], result.exact[index]
        label = f"t={state.t:.4g}"
        along_x.plot(x, state.q[0, row, :], color=colour, label=label)
        along_y.plot(y, state.q[0, :, column], color=colour, label=label)
        if exact is not None:
            along_x.plot(x, exact[0, row, :], color=colour, linestyle="--", linewidth=0.8)
            along_y.plot(y, exact[0, :, column], color=colour, linestyle="--", linewidth=0.8)
    along_x.set_xlabel(f"x (row at y={y[row]:.4g})")
    along_y.set_xlabel(f"y (column at x={x[column]:.4g})")
    along_x.set_ylabel(axis_label(model, name))
    along_x.legend(fontsize="small")
    if any(e is not None for e in result.exact):
        along_y.set_title("dashed: exact cell averages", fontsize="small")
    return figure


def write_figures_2d(result: RunResult2D, folder: Path) -> list[Path]:
    """Write ``map.png`` and ``cuts.png`` into ``folder`` (atomically), and for a run on
    terrain the hazard maps ``peak_depth.png``, ``peak_speed.png``, ``peak_pressure.png`` and
    ``deposit.png`` over a hillshade with the release outline
    (:func:`conslaw.terrain.hazard_figure.hazard_map_figure`); returns their paths."""
    folder = Path(folder)
    paths = [
        write_figure(folder / "map.png", map_figure(result)),
        write_figure(folder / "cuts.png", cuts_figure(result)),
    ]
    maps = hazard_maps(result)
    if maps is not None:
        # Drawn on the cells the GeoTIFFs hold (those the flow reached, the deposit's where
        # flow is left: the run-out's depth threshold above any initial layer).
        for field in maps.fields:
            figure = hazard_map_figure(
                maps.dem,
                np.where(field.valid, field.values, 0.0),
                label=f"{field.name} ({field.units})",
                release_mask=maps.released,
                threshold=0.0,
            )
            where = "is" if field.stem == "deposit" else "was"
            figure.axes[0].set_title(
                f"{result.scene.name}: where the flow {where} at least {REACHED_DEPTH:g} m deep",
                fontsize="medium",
            )
            paths.append(write_figure(folder / f"{field.stem}.png", figure))
    return paths
