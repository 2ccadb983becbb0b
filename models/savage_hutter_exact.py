"""Exact solutions of the Savage–Hutter equations: the parabolic similarity solution (Savage &
Hutter 1989) and the dam break down an inclined plane (Mangeney et al. 2000).

The similarity solution:

On a plane (``zeta`` constant) with ``u > 0`` everywhere (docs/equations.md, "Exact solutions"):

    s = sin zeta - tan delta cos zeta,   xi = x - x0 - s t^2 / 2,
    h = (H0 g0 / g) (1 - xi^2 / g^2)  for |xi| <= g,   u = s t + xi g'/g,
    g'' = 2 beta H0 g0 / g^2,  g(0) = g0,  g'(0) = 0,  beta = eps cos zeta K_act.

With ``G = g / g0`` the ODE integrates to
``sqrt(G (G-1)) + ln(sqrt G + sqrt(G-1)) = 2 sqrt(beta H0 / g0^2) t`` and
``g' = 2 sqrt(beta H0) sqrt(1 - 1/G)``. The solution needs the rear margin to move downslope,
``s t - g'(t) >= 0`` for all t, i.e. ``2 beta H0 / g0 <= s``; other parameters are refused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError
from conslaw.exact import ExactSolution, piecewise_cell_averages
from conslaw_models.roots import increasing_root
from conslaw_models.shallow_water_exact import DamBreak

Array = NDArray[np.float64]


@dataclass(frozen=True)
class SimilaritySolution(ExactSolution):
    """Parabolic cap of height ``H0`` and half-length ``g0`` centred at ``x0`` at t = 0, at rest."""

    slope: float
    beta: float
    height: float
    half_length: float
    centre: float

    @classmethod
    def create(
        cls, slope: float, beta: float, height: float, half_length: float, centre: float
    ) -> SimilaritySolution:
        """Check validity (``2 beta H0 / g0 <= s``) and build the solution."""
        if not (beta > 0 and height > 0 and half_length > 0):
            raise ConfigError("similarity solution: needs beta > 0, height > 0 and radius > 0")
        limit = 2.0 * beta * height / half_length
        if limit > slope:
            raise ConfigError(
                f"similarity solution invalid: the rear margin would move upslope "
                f"(2 beta H0 / g0 = {limit:.4g} > s = sin zeta - tan delta cos zeta = {slope:.4g})"
            )
        return cls(slope, beta, height, half_length, centre)

    def spread(self, t: float) -> tuple[float, float]:
        """``(g(t), g'(t))``, solving the implicit form for ``G = g / g0`` (to the last bit)."""
        if t <= 0.0:
            return self.half_length, 0.0
        target = 2.0 * math.sqrt(self.beta * self.height / self.half_length**2) * t

        def mismatch(G: float) -> float:
            return math.sqrt(G * (G - 1.0)) + math.log(math.sqrt(G) + math.sqrt(G - 1.0)) - target

        upper = 2.0
        while mismatch(upper) < 0.0:
            upper *= 2.0
        G = increasing_root(mismatch, 1.0, upper)
        rate = 2.0 * math.sqrt(self.beta * self.height) * math.sqrt(1.0 - 1.0 / G)
        return G * self.half_length, rate

    def margins(self, t: float) -> tuple[float, float]:
        """Rear and front margin positions."""
        g, _ = self.spread(t)
        middle = self.centre + 0.5 * self.slope * t * t
        return middle - g, middle + g

    def _pieces(self, t: float) -> tuple[Array, list]:
        g, rate = self.spread(t)
        middle = self.centre + 0.5 * self.slope * t * t
        scale = self.height * self.half_length / g

        def outside(x: Array) -> Array:
            return np.zeros((2, x.size))

        def inside(x: Array) -> Array:
            xi = x - middle
            h = scale * (1.0 - (xi / g) ** 2)
            return np.vstack([h, h * (self.slope * t + xi * rate / g)])

        return np.array([middle - g, middle + g]), [outside, inside, outside]

    def cell_averages(self, edges: Array, t: float) -> Array:
        """Exact cell averages of (h, hu) (the parabola and cubic integrated exactly)."""
        points, pieces = self._pieces(t)
        return piecewise_cell_averages(edges, points, pieces)

    def point_values(self, x: Array, t: float) -> Array:
        """Exact (h, hu) at x (zero outside the margins)."""
        points, pieces = self._pieces(t)
        x = np.asarray(x, dtype=np.float64)
        inside = (x >= points[0]) & (x <= points[1])
        result = np.zeros((2, x.size))
        result[:, inside] = pieces[1](x[inside])
        return result

    def velocity(self, x: Array, t: float) -> Array:
        """Exact u inside the body (the linear profile ``s t + xi g'/g``; NaN outside)."""
        points, _ = self._pieces(t)
        g, rate = self.spread(t)
        x = np.asarray(x, dtype=np.float64)
        middle = self.centre + 0.5 * self.slope * t * t
        u = self.slope * t + (x - middle) * rate / g
        return np.where((x >= points[0]) & (x <= points[1]), u, np.nan)


@dataclass(frozen=True)
class InclinedDamBreak(ExactSolution):
    """Dam break down an inclined plane with Coulomb friction onto a dry bed (Mangeney et al.,
    Pure Appl. Geophys. 157, 2000; Faccanoni & Mangeney 2012, in the Savage–Hutter form): a
    reservoir at rest upslope of ``x0`` (the left), dry beyond, on a plane of inclination
    ``zeta`` with the net acceleration ``s = sin zeta - tan delta cos zeta >= 0``.

    Every velocity is >= 0, so the friction keeps its sign and ``s`` is uniform. In the frame
    ``x' = x - s t^2 / 2`` that moves with it, ``u' = u - s t``, the equations are those of
    shallow water with gravity ``beta = eps cos zeta K_act`` and no source (the fan extends,
    ``du/dx = 2 / (3t) > 0``: active; the reservoir slides as a block, ``du/dx = 0``), so the
    solution is Ritter's fan (:class:`conslaw_models.shallow_water_exact.DamBreak` with
    ``g = beta``, ``fan``) carried along: ``c0 = sqrt(beta h0)``,

        h = (2 c0 - (x' - x0)/t)^2 / (9 beta),  u = s t + 2/3 (c0 + (x' - x0)/t)

    for ``-c0 t < x' - x0 < 2 c0 t``, ``(h0, s t)`` behind it and dry ahead.
    """

    fan: DamBreak
    slope: float

    def _shift(self, t: float) -> float:
        return 0.5 * self.slope * t * t

    def _carried(self, values: Array, t: float) -> Array:
        carried = values.copy()
        carried[1] += self.slope * t * values[0]
        return carried

    def cell_averages(self, edges: Array, t: float) -> Array:
        """Exact cell averages of (h, hu), each cell split at the kinks."""
        shifted = np.asarray(edges, dtype=np.float64) - self._shift(t)
        return self._carried(self.fan.cell_averages(shifted, t), t)

    def point_values(self, x: Array, t: float) -> Array:
        """Exact (h, hu) at the points x."""
        shifted = np.asarray(x, dtype=np.float64) - self._shift(t)
        return self._carried(self.fan.point_values(shifted, t), t)

    def wave_extent(self, t: float) -> tuple[float, float]:
        """The tail of the fan and the dry front at time t."""
        low, high = self.fan.wave_extent(t)
        return low + self._shift(t), high + self._shift(t)
