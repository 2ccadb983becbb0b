"""Exact dam-break solutions of the shallow-water equations (Stoker; Ritter) (docs/equations.md,
"Exact solutions")."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from conslaw.exact import ExactSolution, piecewise_cell_averages
from conslaw.model import InitialData
from conslaw_models.roots import increasing_root

Array = NDArray[np.float64]


@dataclass(frozen=True)
class DamBreak(ExactSolution):
    """Dam break on a flat bed: deep water ``h_deep`` at rest on one side of ``x0``, shallower
    water ``h_shallow >= 0`` at rest on the other.

    Deep side on the left (mirrored otherwise), ``c_L = sqrt(g h_L)``:

    - rarefaction ``-c_L t < x - x0 < (u_m - c_m) t``: ``h = (2 c_L - (x-x0)/t)^2 / (9 g)``,
      ``u = 2/3 (c_L + (x-x0)/t)``;
    - Stoker (``h_R > 0``): middle state ``(h_m, u_m)`` with ``u_m = 2 (c_L - c_m)`` (rarefaction)
      and ``u_m = (h_m - h_R) sqrt(g (h_m + h_R) / (2 h_m h_R))`` (shock), shock speed
      ``S = h_m u_m / (h_m - h_R)``;
    - Ritter (``h_R = 0``): the fan reaches the dry front ``x0 + 2 c_L t``.
    """

    x0: float
    h_left: float
    h_right: float
    g: float

    @classmethod
    def from_initial(cls, initial: InitialData, g: float) -> DamBreak | None:
        """From a piecewise-constant condition with one jump between states at rest."""
        breakpoints = initial.options["breakpoints"]
        states = initial.options["states"]
        if len(breakpoints) != 1 or len(states) != 2:
            return None
        (h_left, m_left), (h_right, m_right) = states
        if m_left != 0 or m_right != 0 or h_left == h_right:
            return None
        return cls(float(breakpoints[0]), float(h_left), float(h_right), float(g))

    @property
    def _mirrored(self) -> bool:
        return self.h_right > self.h_left

    def middle_state(self) -> tuple[float, float]:
        """``(h_m, u_m)`` behind the shock (deep side on the left); ``(0, 2 c_L)`` if dry."""
        h_deep = max(self.h_left, self.h_right)
        h_shallow = min(self.h_left, self.h_right)
        c_deep = math.sqrt(self.g * h_deep)
        if h_shallow == 0.0:
            return 0.0, 2.0 * c_deep

        def mismatch(h_m: float) -> float:
            rarefaction = 2.0 * (c_deep - math.sqrt(self.g * h_m))
            shock = (h_m - h_shallow) * math.sqrt(
                self.g * (h_m + h_shallow) / (2.0 * h_m * h_shallow)
            )
            return rarefaction - shock

        # The mismatch falls from > 0 at h_shallow to < 0 at h_deep.
        h_m = increasing_root(lambda h: -mismatch(h), h_shallow, h_deep)
        return h_m, 2.0 * (c_deep - math.sqrt(self.g * h_m))

    def _structure(self, t: float) -> tuple[Array, list]:
        """Breakpoints (deep side left, relative to x0) and piece functions of (h, hu)."""
        g = self.g
        h_deep = max(self.h_left, self.h_right)
        h_shallow = min(self.h_left, self.h_right)
        c_deep = math.sqrt(g * h_deep)
        h_m, u_m = self.middle_state()

        def constant(h: float, u: float):
            return lambda x: np.vstack([np.full_like(x, h), np.full_like(x, h * u)])

        def fan(x: Array) -> Array:
            xi = x / t
            h = (2.0 * c_deep - xi) ** 2 / (9.0 * g)
            return np.vstack([h, h * (2.0 / 3.0) * (c_deep + xi)])

        if h_shallow == 0.0:
            points = np.array([-c_deep * t, 2.0 * c_deep * t])
            pieces = [constant(h_deep, 0.0), fan, constant(0.0, 0.0)]
        else:
            c_m = math.sqrt(g * h_m)
            shock = h_m * u_m / (h_m - h_shallow)
            points = np.array([-c_deep * t, (u_m - c_m) * t, shock * t])
            pieces = [constant(h_deep, 0.0), fan, constant(h_m, u_m), constant(h_shallow, 0.0)]
        return points, pieces

    def _evaluate(self, x: Array, t: float, averages: bool) -> Array:
        x = np.asarray(x, dtype=np.float64)
        relative = x - self.x0
        if self._mirrored:
            relative = -relative[::-1]
        if t == 0.0:
            h_deep = max(self.h_left, self.h_right)
            h_shallow = min(self.h_left, self.h_right)
            pieces = [
                lambda s: np.vstack([np.full_like(s, h_deep), np.zeros_like(s)]),
                lambda s: np.vstack([np.full_like(s, h_shallow), np.zeros_like(s)]),
            ]
            points = np.array([0.0])
        else:
            points, pieces = self._structure(t)
        if averages:
            result = piecewise_cell_averages(relative, points, pieces)
        else:
            index = np.searchsorted(points, relative, side="right")
            result = np.empty((2, relative.size))
            for p, piece in enumerate(pieces):
                mask = index == p
                if mask.any():
                    result[:, mask] = piece(relative[mask])
        if self._mirrored:
            result = result[:, ::-1] * np.array([[1.0], [-1.0]])
        return result

    def cell_averages(self, edges: Array, t: float) -> Array:
        """Exact cell averages of (h, hu), each cell split at the kinks and shock."""
        return self._evaluate(edges, t, averages=True)

    def point_values(self, x: Array, t: float) -> Array:
        """Exact (h, hu) at the points x."""
        return self._evaluate(x, t, averages=False)

    def wave_extent(self, t: float) -> tuple[float, float]:
        """Leftmost and rightmost position reached by the waves at time t."""
        points, _ = self._structure(t) if t > 0 else (np.array([0.0, 0.0]), [])
        low, high = float(points[0]), float(points[-1])
        if self._mirrored:
            low, high = -high, -low
        return self.x0 + low, self.x0 + high


@dataclass(frozen=True)
class StillWater(ExactSolution):
    """Water at rest over the bed ``b(x) = height exp(-((x - centre)/width)^2)``: a flat surface
    where the bed is below it, dry land where it is above, ``h = max(surface - b, 0)``,
    ``u = 0``, for all time (docs/equations.md, "Exact solutions"). Cell averages split at the
    shorelines ``b(x) = surface``."""

    surface: float
    height: float
    centre: float
    width: float

    def bed(self, x: Array) -> Array:
        """The bed elevation."""
        return self.height * np.exp(-(((np.asarray(x) - self.centre) / self.width) ** 2))

    def shorelines(self) -> list[float]:
        """Where the bed meets the surface (none if it stays below or above it)."""
        ratio = self.height / self.surface if self.surface != 0.0 else math.inf
        if not ratio > 1.0:
            return []
        offset = self.width * math.sqrt(math.log(ratio))
        return [self.centre - offset, self.centre + offset]

    def _values(self, x: Array) -> Array:
        depth = np.maximum(self.surface - self.bed(x), 0.0)
        return np.vstack([depth, np.zeros_like(depth)])

    def cell_averages(self, edges: Array, t: float) -> Array:
        lines = self.shorelines()
        return piecewise_cell_averages(edges, np.array(lines), [self._values] * (len(lines) + 1))

    def point_values(self, x: Array, t: float) -> Array:
        return self._values(np.asarray(x, dtype=np.float64))
