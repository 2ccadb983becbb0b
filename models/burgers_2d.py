"""Inviscid Burgers equation in two dimensions, ``u_t + (u^2/2)_x + (u^2/2)_y = 0``, and its
smooth exact solution by characteristics (docs/design.md, "Toward two dimensions")."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number
from conslaw.exact import ExactSolution, Unavailable
from conslaw.exact2d import ExactSolution2D, dam_break_along_normal
from conslaw.grid2d import Grid2D
from conslaw.model import InitialData, Model
from conslaw_models.burgers import flux_point, jacobian_point, max_speed_point
from conslaw_models.burgers_exact import BurgersRiemannFans

Array = NDArray[np.float64]


class Burgers2D(Model):
    """``u_t + (u^2/2)_x + (u^2/2)_y = 0``: the same flux in both directions (the 1D Burgers
    pointwise functions, bound for x and for y), so every characteristic runs along ``(1, 1)``
    with speed ``u`` in each coordinate."""

    name = "burgers-2d"
    description = "inviscid Burgers equation in 2D, u_t + (u^2/2)_x + (u^2/2)_y = 0"
    variables = ("u",)
    reflect_signs = (-1.0,)
    # The y functions are the x ones (bound first: the x names are rebound below).
    flux_y_point = staticmethod(flux_point)
    jacobian_y_point = staticmethod(jacobian_point)
    max_speed_y_point = staticmethod(max_speed_point)
    flux_point = staticmethod(flux_point)
    jacobian_point = staticmethod(jacobian_point)
    max_speed_point = staticmethod(max_speed_point)
    initial_kinds: ClassVar[dict[str, tuple[tuple[str, ...], dict[str, Any], str]]] = {
        "product-wave": (
            ("mean", "amplitude"),
            {},
            "u0 = mean + amplitude sin(2 pi x / L) sin(2 pi y / L) on a square of side L",
        ),
    }

    @staticmethod
    def product_wave(options: Mapping[str, Any], grid: Grid2D) -> SmoothProductWave:
        """The :class:`SmoothProductWave` of a ``product-wave`` initial condition (the domain
        must be a square: its side is the period)."""
        if grid.x.length != grid.y.length:
            raise ConfigError(
                "initial.kind 'product-wave' needs a square domain (x_max - x_min = y_max - y_min)"
            )
        mean = finite_number(options["mean"], "initial.mean")
        amplitude = finite_number(options["amplitude"], "initial.amplitude")
        return SmoothProductWave(mean, amplitude, grid.x.length)

    def initial_cell_averages_2d(
        self, kind: str, options: Mapping[str, Any], grid: Grid2D
    ) -> Array:
        """``product-wave``: Gauss–Legendre cell averages of ``u0``
        (:meth:`SmoothProductWave.cell_averages`)."""
        if kind == "product-wave":
            wave = self.product_wave(options, grid)
            return wave.cell_averages(grid.x.edges, grid.y.edges, 0.0)
        return super().initial_cell_averages_2d(kind, options, grid)

    def exact_solution_2d(
        self, initial: InitialData, grid: Grid2D, context: Mapping[str, Any]
    ) -> ExactSolution2D | None:
        """The product wave before it breaks (periodic domain); a Riemann problem along an
        axis (:func:`conslaw.exact2d.dam_break_along_normal` with the 1D fans); else None or
        :class:`~conslaw.exact.Unavailable`."""
        t_end = float(context["t_end"])
        if initial.kind == "product-wave":
            if any(context[side] != "periodic" for side in ("left", "right", "bottom", "top")):
                raise Unavailable("the exact product wave needs a periodic domain")
            wave = self.product_wave(initial.options, grid)
            if wave.breaking_time() <= t_end:
                raise Unavailable(f"the wave breaks at t={wave.breaking_time():g}")
            return wave
        if initial.kind != "dam-break":
            return None
        if float(initial.options["period"]) != 0.0:
            raise Unavailable("stripes of Burgers data have no exact solution here")
        if any(float(v) < 0.0 for v in initial.options["normal"]):
            raise Unavailable("the exact Riemann solution needs a normal along +x or +y")

        def solve(low: Array, high: Array, x0: float) -> ExactSolution | None:
            return BurgersRiemannFans((x0,), (float(low[0]), float(high[0])))

        def extent(piece: ExactSolution, t: float) -> tuple[float, float]:
            assert isinstance(piece, BurgersRiemannFans)
            return piece._wave_extent(0, t)

        return dam_break_along_normal(initial.options, grid, context, solve, extent, None)


@dataclass(frozen=True)
class SmoothProductWave:
    """The exact solution of 2D Burgers from ``u0 = a + b sin(2 pi x / L) sin(2 pi y / L)``
    (periodic with period ``L`` in x and y) before it breaks.

    ``u`` is constant along the characteristics ``(x, y) = (x0, y0) + u0 (t, t)``, so
    ``u = u0(x - u t, y - u t)``, solved by Newton's method from ``u = a``; unique while
    ``1 + t (u0_x + u0_y) > 0`` everywhere, i.e. before ``t = L / (2 pi |b|)``
    (``u0_x + u0_y = b (2 pi / L) sin(2 pi (x + y) / L)``).
    """

    a: float
    b: float
    period: float

    def breaking_time(self) -> float:
        """When the first characteristics cross (inf for ``b = 0``)."""
        return math.inf if self.b == 0.0 else self.period / (2.0 * math.pi * abs(self.b))

    def initial(self, x: Array, y: Array) -> Array:
        """``u0`` at the points ``(x, y)``."""
        k = 2.0 * math.pi / self.period
        return self.a + self.b * np.sin(k * x) * np.sin(k * y)

    def point_values(self, x: Array, y: Array, t: float) -> Array:
        """``u(x, y, t)`` at the points, to round-off (Newton's method)."""
        if t >= self.breaking_time():
            raise ConfigError(f"the wave breaks at t={self.breaking_time():g}")
        k = 2.0 * math.pi / self.period
        u = np.full(np.broadcast(x, y).shape, self.a, dtype=np.float64)
        for _ in range(100):
            foot_x, foot_y = x - u * t, y - u * t
            residual = u - self.initial(foot_x, foot_y)
            slope = (
                self.b
                * k
                * (
                    np.cos(k * foot_x) * np.sin(k * foot_y)
                    + np.sin(k * foot_x) * np.cos(k * foot_y)
                )
            )
            step = residual / (1.0 + t * slope)
            u = u - step
            if np.max(np.abs(step)) <= 1e-15 * max(1.0, float(np.max(np.abs(u)))):
                break
        return u

    def cell_averages(self, x_edges: Array, y_edges: Array, t: float, points: int = 5) -> Array:
        """Averages over the cells ``[x_edges[j], x_edges[j+1]] x [y_edges[k], y_edges[k+1]]``,
        shape ``(1, ny, nx)``, by ``points`` x ``points`` Gauss–Legendre points per cell."""
        nodes, weights = np.polynomial.legendre.leggauss(points)
        x_left, x_width = x_edges[:-1], np.diff(x_edges)
        y_low, y_width = y_edges[:-1], np.diff(y_edges)
        total = np.zeros((len(y_low), len(x_left)))
        for node_y, weight_y in zip(nodes, weights, strict=True):
            y = y_low + 0.5 * (node_y + 1.0) * y_width
            for node_x, weight_x in zip(nodes, weights, strict=True):
                x = x_left + 0.5 * (node_x + 1.0) * x_width
                values = self.point_values(x[None, :], y[:, None], t)
                total += 0.25 * weight_x * weight_y * values
        return total[None, :, :]
