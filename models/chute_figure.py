"""The chute in elevation with the flowing mass on it: the figure ``chute.png`` of a
Savage–Hutter run (paper Fig. 3)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from conslaw.plotting import run_label, select_states, times_label

if TYPE_CHECKING:
    from conslaw.result import RunResult


def chute_figure(
    result: RunResult, times: Sequence[float] | None = None, exaggeration: float = 3.0
) -> Any:
    """Paper Fig. 3 style: one panel per output time (``times``, see :func:`select_states`),
    the chute drawn in elevation (not arc length) at equal aspect, so that its angles are the
    true ones, and the flowing mass on it, its depth laid off along the bed's upward normal
    ``(sin zeta, cos zeta)`` in the units of length (a depth ``h`` in units of ``H`` is
    ``epsilon h`` lengths ``L``), exaggerated by ``exaggeration`` so that it is visible. The
    point of arc length 0 is the origin when the domain holds it. Panels are laid out in up to
    three columns."""
    model = result.model
    chute = getattr(model, "chute")  # noqa: B009 (only models with a chute get this figure)
    x = result.grid.centres()
    horizontal, vertical = chute.elevation_profile(x)
    if x[0] <= 0.0 <= x[-1]:
        horizontal = horizontal - np.interp(0.0, x, horizontal)
        vertical = vertical - np.interp(0.0, x, vertical)
    angle = chute.zeta(x)
    scale = exaggeration * float(getattr(model.params, "epsilon", 1.0))
    shown = select_states(result, times)
    tops = []
    for state in shown:
        h = scale * state.q[model.depth_index]
        tops.append((horizontal + h * np.sin(angle), vertical + h * np.cos(angle)))
    left = min(horizontal.min(), *(top[0].min() for top in tops))
    right = max(horizontal.max(), *(top[0].max() for top in tops))
    bottom = min(vertical.min(), *(top[1].min() for top in tops))
    top_edge = max(vertical.max(), *(top[1].max() for top in tops))
    margin = 0.03 * max(right - left, top_edge - bottom)
    width, height = right - left + 2 * margin, top_edge - bottom + 2 * margin
    count = len(shown)
    columns = 1 if count == 1 else (2 if count <= 4 or height > 0.6 * width else 3)
    rows = -(-count // columns)
    figure_width = 10.0 if columns > 1 else 7.0
    panel_width = (figure_width - 1.0) / columns
    panel_height = min(max(panel_width * height / width, 0.9), 6.0)
    figure = Figure(figsize=(figure_width, rows * (panel_height + 0.6) + 0.6))
    axes = figure.subplots(rows, columns, sharex=True, sharey=True, squeeze=False)
    for axis in axes.flat[count:]:
        axis.set_visible(False)
    for axis, state, (top_x, top_z) in zip(axes.flat, shown, tops, strict=False):
        axis.plot(horizontal, vertical, "k-", lw=1.0)
        # The mass as a patch added without ``Axes.fill``'s data-limit update, which walks
        # every segment of the outline in Python (the limits are set below anyway).
        outline = np.column_stack(
            [np.concatenate([horizontal, top_x[::-1]]), np.concatenate([vertical, top_z[::-1]])]
        )
        axis.add_artist(Polygon(outline, closed=True, color="tab:orange", alpha=0.85, lw=0))
        axis.set_aspect("equal", adjustable="box")
        axis.set_xlim(left - margin, right + margin)
        axis.set_ylim(bottom - margin, top_edge + margin)
        axis.text(0.98, 0.9, f"t = {state.t:g}", transform=axis.transAxes, ha="right", fontsize=9)
    unit = " / L" if model.dimensionless else ""
    for axis in axes[:, 0]:
        axis.set_ylabel(f"elevation{unit}", fontsize=9)
    for axis in axes[-1, :]:
        axis.set_xlabel(f"horizontal position{unit}", fontsize=9)
    figure.suptitle(
        f"{result.scene.name}: {run_label(result)}\nequal scales; depth drawn "
        f"x{exaggeration:g}, normal to the bed{times_label(result, shown)}",
        fontsize=10,
    )
    figure.tight_layout()
    return figure
