"""The largest flow depth and speed every cell sees during a 2D run, updated after every step
pair (not sampled from the output times), and what hazard maps take from them: peak pressure,
run-out and travel angle (docs/output.md, "Hazard maps").

The model says what its depth and speed are (``Model.flow_depth_and_speed``): for the terrain
model the thickness normal to the slope and the speed in the surface.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from conslaw.grid2d import Grid2D
from conslaw.model import Model

Array = NDArray[np.float64]

#: Depth (m) from which a cell counts as reached by the flow, for the run-out and the travel
#: angle (AvaFrame's and RAMMS' maps take thresholds of this order; docs/output.md).
REACHED_DEPTH = 0.01


@dataclass
class PeakFields:
    """``depth`` and ``speed``: the largest of every cell so far, ``(ny, nx)``; a cell's speed
    counts while its flow is at least :data:`REACHED_DEPTH` deep (a thin film at a margin can
    be fast, and it is no hazard).

    Parameters
    ----------
    model : Model
        A 2D model whose ``flow_depth_and_speed`` is not None.
    aux : numpy.ndarray or None
        The model's coefficients at the primary cells (for its depth and speed).
    depth, speed : numpy.ndarray
    """

    model: Model
    aux: Array | None
    depth: Array
    speed: Array

    @classmethod
    def start(cls, model: Model, grid: Grid2D, q: Array) -> PeakFields | None:
        """The peaks of the initial values ``q``, or None for a model without a depth.

        Parameters
        ----------
        model : Model
        grid : Grid2D
        q : numpy.ndarray
            ``(n_vars, ny, nx)`` primary cell values.

        Returns
        -------
        PeakFields or None
        """
        aux = None
        if model.aux_layout_2d == "field":
            x, y = grid.centres()
            aux = model.aux_2d(x[None, :], y[:, None])
        fields = model.flow_depth_and_speed(q, aux)
        if fields is None:
            return None
        depth, speed = fields
        return cls(model, aux, depth.copy(), np.where(depth >= REACHED_DEPTH, speed, 0.0))

    def update(self, q: Array) -> None:
        """Raise every cell's peaks to those of ``q`` (primary cell values).

        Parameters
        ----------
        q : numpy.ndarray
            ``(n_vars, ny, nx)``.
        """
        fields = self.model.flow_depth_and_speed(q, self.aux)
        assert fields is not None
        depth, speed = fields
        np.maximum(self.depth, depth, out=self.depth)
        np.maximum(self.speed, np.where(depth >= REACHED_DEPTH, speed, 0.0), out=self.speed)

    def pressure(self, density: float) -> Array:
        """The peak dynamic pressure ``density * speed^2`` in kPa (its largest value is that
        of the largest speed: the density is constant).

        Parameters
        ----------
        density : float
            kg/m^3.

        Returns
        -------
        numpy.ndarray
        """
        return 1e-3 * density * self.speed * self.speed


@dataclass(frozen=True)
class RunOut:
    """Where the flow went, on straight lines from the top of the release.

    ``length``: the largest horizontal distance from the highest released cell to a cell the
    flow reached (peak depth >= :data:`REACHED_DEPTH`); ``drop``: the elevation of that
    released cell above the reached one; ``alpha``: the travel angle ``atan(drop / length)`` in
    degrees (Heim's Fahrböschung; Lied & Bakkehøi 1980 for snow avalanches); ``end``: the map
    point of the reached cell.
    """

    length: float
    drop: float
    alpha: float
    end: tuple[float, float]


def run_out(
    grid: Grid2D, elevation: Array, released: NDArray[np.bool_], peak_depth: Array
) -> RunOut | None:
    """The run-out and travel angle of a run (:class:`RunOut`), or None if nothing was
    released or reached.

    Parameters
    ----------
    grid : Grid2D
    elevation : numpy.ndarray
        ``(ny, nx)`` terrain elevation at the cell centres, m.
    released : numpy.ndarray of bool
        The released cells.
    peak_depth : numpy.ndarray
        ``(ny, nx)`` peak flow depth, m.

    Returns
    -------
    RunOut or None
    """
    reached = peak_depth >= REACHED_DEPTH
    if not released.any() or not reached.any():
        return None
    x, y = grid.centres()
    top = np.unravel_index(np.argmax(np.where(released, elevation, -np.inf)), elevation.shape)
    distance = np.hypot(x[None, :] - x[top[1]], y[:, None] - y[top[0]])
    far = np.unravel_index(np.argmax(np.where(reached, distance, -1.0)), distance.shape)
    length = float(distance[far])
    drop = float(elevation[top] - elevation[far])
    alpha = math.degrees(math.atan2(drop, length)) if length > 0.0 else 90.0
    return RunOut(length, drop, alpha, (float(x[far[1]]), float(y[far[0]])))
