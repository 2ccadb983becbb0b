"""The largest flow depth and speed every cell sees during a 2D run, updated after every step
pair (not sampled from the output times), and the peak pressure (docs/output.md, "Hazard
maps").

The model says what its depth and speed are (``Model.flow_depth_and_speed``): for the terrain
model the thickness normal to the slope and the speed in the surface.
"""

from __future__ import annotations

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

    def update(self, q: Array) -> tuple[Array, Array]:
        """Raise every cell's peaks to those of ``q`` (primary cell values).

        Parameters
        ----------
        q : numpy.ndarray
            ``(n_vars, ny, nx)``.

        Returns
        -------
        depth, speed : numpy.ndarray
            The flow depth and speed of ``q`` (``Model.flow_depth_and_speed``), for other
            watchers of the same pair (the kinetic energy of :mod:`conslaw.stopping`).
        """
        fields = self.model.flow_depth_and_speed(q, self.aux)
        assert fields is not None
        depth, speed = fields
        np.maximum(self.depth, depth, out=self.depth)
        np.maximum(self.speed, np.where(depth >= REACHED_DEPTH, speed, 0.0), out=self.speed)
        return depth, speed

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
