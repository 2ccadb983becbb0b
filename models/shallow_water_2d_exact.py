"""Exact solutions of the 2D shallow-water equations: Thacker's planar oscillation in a
paraboloid bowl (Thacker 1981, J. Fluid Mech. 107, 499–508; SWASHES, Delestre et al. 2013,
Int. J. Numer. Meth. Fluids 72, section 4.2.2).

Over the bowl ``z = h0 (r^2/a^2 - 1)`` (``r`` the distance from the bowl's centre) the water
surface stays a plane that turns round the centre, and the velocity is uniform::

    w = eta h0 / a^2 (2 x' cos(omega t) + 2 y' sin(omega t) - eta),   h = max(w - z, 0)
    u = -eta omega sin(omega t),   v = eta omega cos(omega t),   omega = sqrt(2 g h0) / a

with ``(x', y')`` the position relative to the centre. The shoreline is the circle where the
plane meets the bowl; it moves, so the solution tests wet and dry cells at once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


@dataclass(frozen=True)
class ThackerPlanar:
    """Thacker's planar surface in the bowl of depth ``h0`` and radius ``a`` centred at
    ``(x0, y0)``, amplitude ``eta``, gravity ``g``."""

    h0: float
    a: float
    eta: float
    g: float
    x0: float = 0.0
    y0: float = 0.0

    @property
    def omega(self) -> float:
        """Angular frequency ``sqrt(2 g h0) / a``."""
        return math.sqrt(2.0 * self.g * self.h0) / self.a

    @property
    def period(self) -> float:
        """``2 pi / omega``."""
        return 2.0 * math.pi / self.omega

    def bed(self, x: Array, y: Array) -> Array:
        """``h0 (r^2/a^2 - 1)``."""
        radius_squared = (x - self.x0) ** 2 + (y - self.y0) ** 2
        return self.h0 * (radius_squared / self.a**2 - 1.0)

    def point_values(self, x: Array, y: Array, t: float) -> Array:
        """``(h, hu, hv)`` at the points ``(x, y)`` (broadcast), shape ``(3, ...)``."""
        phase = self.omega * t
        surface = (
            self.eta
            * self.h0
            / self.a**2
            * (
                2.0 * (x - self.x0) * math.cos(phase)
                + 2.0 * (y - self.y0) * math.sin(phase)
                - self.eta
            )
        )
        h = np.maximum(surface - self.bed(x, y), 0.0)
        u = -self.eta * self.omega * math.sin(phase)
        v = self.eta * self.omega * math.cos(phase)
        return np.stack(np.broadcast_arrays(h, h * u, h * v))

    def cell_averages(
        self, x_edges: Array, y_edges: Array, t: float, parts: int = 8, points: int = 4
    ) -> Array:
        """Averages of ``(h, hu, hv)`` over the cells of the edges, shape ``(3, ny, nx)``: each
        cell cut into ``parts`` x ``parts`` pieces with ``points`` x ``points`` Gauss–Legendre
        points each (the depth has a kink at the shoreline: the error there falls as
        ``1/parts^2``, about 1e-6 of ``h0`` at the defaults on the cells of the tests)."""
        nodes, weights = np.polynomial.legendre.leggauss(points)
        x_left, x_width = np.asarray(x_edges)[:-1], np.diff(x_edges)
        y_low, y_width = np.asarray(y_edges)[:-1], np.diff(y_edges)
        total = np.zeros((3, len(y_low), len(x_left)))
        offsets = (np.arange(parts)[:, None] + 0.5 * (nodes[None, :] + 1.0)).ravel() / parts
        shares = np.tile(0.5 * weights, parts) / parts
        for offset_y, share_y in zip(offsets, shares, strict=True):
            y = (y_low + offset_y * y_width)[:, None]
            for offset_x, share_x in zip(offsets, shares, strict=True):
                x = (x_left + offset_x * x_width)[None, :]
                total += (share_x * share_y) * self.point_values(x, y, t)
        return total
