"""Exact solutions of the inviscid Burgers equation (docs/equations.md, "Exact solutions"), as exact
cell averages."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError
from conslaw.exact import ExactSolution
from conslaw.grid import Grid
from conslaw.model import InitialData

Array = NDArray[np.float64]


@dataclass(frozen=True)
class BurgersRiemannFans(ExactSolution):
    """Piecewise-constant data whose Riemann problems have not yet interacted.

    At each jump ``u_l | u_r`` at ``x_0``: a shock of speed ``(u_l + u_r)/2`` if ``u_l > u_r``,
    else the rarefaction ``u = (x - x_0)/t`` between ``x_0 + u_l t`` and ``x_0 + u_r t`` (a
    transonic one when ``u_l < 0 < u_r``). Valid while neighbouring waves stay apart, which
    :meth:`valid_until` gives; asking past it raises ConfigError.
    """

    breakpoints: tuple[float, ...]
    values: tuple[float, ...]

    @classmethod
    def from_initial(cls, initial: InitialData, grid: Grid) -> BurgersRiemannFans:
        """From a ``piecewise-constant`` initial condition with one variable."""
        states = initial.options["states"]
        return cls(
            tuple(float(b) for b in initial.options["breakpoints"]),
            tuple(float(s[0]) if isinstance(s, list | tuple) else float(s) for s in states),
        )

    def _wave_extent(self, k: int, t: float) -> tuple[float, float]:
        """Leftmost and rightmost position of the wave from jump k at time t."""
        x0 = self.breakpoints[k]
        left, right = self.values[k], self.values[k + 1]
        if left > right:
            position = x0 + 0.5 * (left + right) * t
            return position, position
        return x0 + left * t, x0 + right * t

    def valid_until(self) -> float:
        """Time at which two neighbouring waves first meet (inf if never)."""
        earliest = np.inf
        for k in range(len(self.breakpoints) - 1):
            gap = self.breakpoints[k + 1] - self.breakpoints[k]
            u_left, u_mid, u_right = self.values[k : k + 3]
            right_speed = 0.5 * (u_left + u_mid) if u_left > u_mid else u_mid
            left_speed = 0.5 * (u_mid + u_right) if u_mid > u_right else u_mid
            closing = right_speed - left_speed
            if closing > 0:
                earliest = min(earliest, gap / closing)
        return earliest

    def _pieces(self, t: float) -> tuple[Array, list[tuple[float, float]]]:
        """Breakpoints and (constant, slope) pairs of the solution u = c + s x on each piece."""
        if t > self.valid_until() * (1 + 1e-12):
            raise ConfigError(
                f"the Burgers Riemann waves interact at t={self.valid_until():g}; no exact "
                f"solution at t={t:g}"
            )
        points: list[float] = []
        pieces: list[tuple[float, float]] = [(self.values[0], 0.0)]
        for k in range(len(self.breakpoints)):
            start, end = self._wave_extent(k, t)
            left, right = self.values[k], self.values[k + 1]
            if left > right or t == 0.0:
                points.append(start)
            else:
                points.extend([start, end])
                x0 = self.breakpoints[k]
                pieces.append((-x0 / t, 1.0 / t))
            pieces.append((right, 0.0))
        return np.array(points), pieces

    def cell_averages(self, edges: Array, t: float) -> Array:
        """Exact averages of u over the cells ``[edges[i], edges[i+1]]``, shape (1, n)."""
        points, pieces = self._pieces(t)
        edges = np.asarray(edges, dtype=np.float64)
        # Integrate u = c + s x piece by piece from a reference point left of everything.
        reference = min(edges[0], points[0] if points.size else edges[0]) - 1.0
        far_right = max(edges[-1], points[-1] if points.size else edges[-1]) + 1.0
        bounds = np.concatenate([[reference], points, [far_right]])
        integral = np.zeros_like(edges)
        for (c, slope), lo, hi in zip(pieces, bounds[:-1], bounds[1:], strict=True):
            a = np.clip(edges, lo, hi)
            integral += c * (a - lo) + 0.5 * slope * (a * a - lo * lo)
        return (np.diff(integral) / np.diff(edges))[None, :]

    def point_values(self, x: Array, t: float) -> Array:
        """Exact u at the points x, shape (1, n)."""
        points, pieces = self._pieces(t)
        index = np.searchsorted(points, np.asarray(x, dtype=np.float64), side="right")
        c = np.array([p[0] for p in pieces])[index]
        s = np.array([p[1] for p in pieces])[index]
        return (c + s * np.asarray(x))[None, :]


@dataclass(frozen=True)
class BurgersSmoothSine(ExactSolution):
    """``u0(x) = a + b sin(2 pi k (x - x_min)/L)`` on a periodic domain, before breaking.

    ``u(x, t) = u0(xi)`` with the foot ``xi + u0(xi) t = x``. Cell averages are exact: with the
    change of variables ``x = xi + u0(xi) t``,
    ``int_a^b u dx = [U0(xi) + t u0(xi)^2 / 2]`` between the feet of a and b, ``U0`` being the
    antiderivative of ``u0``. Breaking time ``t_b = L / (2 pi k |b|)``.
    """

    mean: float
    amplitude: float
    wavenumber: int
    x_min: float
    length: float

    @classmethod
    def from_initial(cls, initial: InitialData, grid: Grid) -> BurgersSmoothSine:
        """From a ``sine`` initial condition."""
        o = initial.options
        return cls(
            float(o["mean"]), float(o["amplitude"]), int(o["wavenumber"]), grid.x_min, grid.length
        )

    @property
    def _k(self) -> float:
        return 2.0 * np.pi * self.wavenumber / self.length

    def breaking_time(self) -> float:
        """First time a characteristic crossing forms a shock."""
        return np.inf if self.amplitude == 0 else 1.0 / (self._k * abs(self.amplitude))

    def _u0(self, xi: Array) -> Array:
        return self.mean + self.amplitude * np.sin(self._k * (xi - self.x_min))

    def _feet(self, x: Array, t: float) -> Array:
        if t >= self.breaking_time():
            raise ConfigError(
                f"the sine solution breaks at t={self.breaking_time():g}; no smooth exact "
                f"solution at t={t:g}"
            )
        x = np.asarray(x, dtype=np.float64)
        lo = x - (self.mean + abs(self.amplitude)) * t
        hi = x - (self.mean - abs(self.amplitude)) * t
        # xi -> xi + u0(xi) t is strictly increasing before breaking: bisection brackets the
        # foot (vectorised over all points), then Newton polishes it to round-off.
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            above = mid + self._u0(mid) * t > x
            hi = np.where(above, mid, hi)
            lo = np.where(above, lo, mid)
        feet = 0.5 * (lo + hi)
        for _ in range(3):
            derivative = 1.0 + t * self.amplitude * self._k * np.cos(self._k * (feet - self.x_min))
            feet = feet - (feet + self._u0(feet) * t - x) / derivative
        return feet

    def point_values(self, x: Array, t: float) -> Array:
        """Exact u at the points x, shape (1, n)."""
        return self._u0(self._feet(x, t))[None, :]

    def cell_averages(self, edges: Array, t: float) -> Array:
        """Exact cell averages, shape (1, n)."""
        edges = np.asarray(edges, dtype=np.float64)
        xi = self._feet(edges, t)
        u0 = self._u0(xi)
        antiderivative = (
            self.mean * xi
            - self.amplitude / self._k * np.cos(self._k * (xi - self.x_min))
            + 0.5 * t * u0 * u0
        )
        return (np.diff(antiderivative) / np.diff(edges))[None, :]
