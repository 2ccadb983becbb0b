"""Exact solutions of 2D scenes: cell averages on a 2D grid (docs/scenes.md,
"Two-dimensional scenes").

:class:`AlongNormal` turns 1D exact solutions (:class:`conslaw.exact.ExactSolution`) into
solutions that vary along one direction only: a 1D problem along ``s = a x + b y`` is a 2D
solution whose velocity points along the normal ``(a, b)``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import NDArray

from conslaw.exact import ExactSolution, Unavailable

if TYPE_CHECKING:
    from conslaw.grid2d import Grid2D

Array = NDArray[np.float64]

#: Sub-cells per direction and Gauss–Legendre points per sub-cell of :func:`gauss_average`.
PARTS, POINTS = 8, 4


class ExactSolution2D(Protocol):
    """An exact solution of a 2D model for one initial condition."""

    def point_values(self, x: Array, y: Array, t: float) -> Array:
        """Values at the points ``(x, y)`` (broadcast), shape ``(n_vars, ...)``."""
        ...

    def cell_averages(self, x_edges: Array, y_edges: Array, t: float) -> Array:
        """Averages over the cells of the edges, shape ``(n_vars, ny, nx)``."""
        ...


def gauss_average(
    values: Callable[[Array, Array], Array],
    x_edges: Array,
    y_edges: Array,
    parts: int = PARTS,
    points: int = POINTS,
) -> Array:
    """Averages of ``values(x, y)`` (shape ``(n_vars, ...)``) over every cell: the cell cut into
    ``parts`` x ``parts`` pieces, ``points`` x ``points`` Gauss–Legendre points on each (a kink
    or a jump inside a cell costs an error falling as ``1/parts`` to ``1/parts^2``)."""
    nodes, weights = np.polynomial.legendre.leggauss(points)
    x_left, x_width = np.asarray(x_edges)[:-1], np.diff(x_edges)
    y_low, y_width = np.asarray(y_edges)[:-1], np.diff(y_edges)
    offsets = (np.arange(parts)[:, None] + 0.5 * (nodes[None, :] + 1.0)).ravel() / parts
    shares = np.tile(0.5 * weights, parts) / parts
    total: Array | None = None
    for offset_y, share_y in zip(offsets, shares, strict=True):
        y = (y_low + offset_y * y_width)[:, None]
        for offset_x, share_x in zip(offsets, shares, strict=True):
            x = (x_left + offset_x * x_width)[None, :]
            sample = (share_x * share_y) * values(x, y)
            total = sample if total is None else total + sample
    assert total is not None
    return total


@dataclass(frozen=True)
class AlongNormal:
    """1D solutions along ``xi = (a x + b y) / |(a, b)|``: ``pieces[k]`` holds for ``xi`` in
    ``[bounds[k], bounds[k + 1])`` (repeated with ``period`` along ``xi`` if it is > 0).

    ``momentum`` is the 1D variable that is the momentum along the normal (None for a scalar
    model, whose variable is copied): it becomes the x and y momenta ``m a / |n|`` and
    ``m b / |n|`` (the variables after the 1D ones). Along an axis the cell averages are the 1D
    solution's exact ones; otherwise :func:`gauss_average`.
    """

    pieces: Sequence[ExactSolution]
    bounds: Sequence[float]
    normal: tuple[float, float]
    momentum: int | None
    period: float = 0.0

    def _unit(self) -> tuple[float, float]:
        a, b = self.normal
        length = math.hypot(a, b)
        return a / length, b / length

    def _along(self, xi: Array, t: float) -> Array:
        """The 1D variables at the points ``xi`` (flat), shape ``(n_1d, len(xi))``."""
        if self.period > 0.0:
            start = self.bounds[0]
            xi = start + np.mod(xi - start, self.period)
        result: Array | None = None
        for k, piece in enumerate(self.pieces):
            values = piece.point_values(xi, t)
            if result is None:
                result = np.array(values, dtype=np.float64)
                continue
            mask = xi >= self.bounds[k]
            result[:, mask] = values[:, mask]
        assert result is not None
        return result

    def _to_2d(self, values: Array) -> Array:
        if self.momentum is None:
            return values
        unit_a, unit_b = self._unit()
        k, n = self.momentum, values.shape[0]
        m = values[k]
        stacked = np.concatenate([values, (m * unit_a)[None], (m * unit_b)[None]])
        return stacked[[*range(k), n, n + 1, *range(k + 1, n)]]

    def point_values(self, x: Array, y: Array, t: float) -> Array:
        """The values at the points ``(x, y)`` (broadcast)."""
        unit_a, unit_b = self._unit()
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), y)
        xi = (unit_a * x + unit_b * y).ravel()
        return self._to_2d(self._along(xi, t)).reshape(-1, *x.shape)

    def cell_averages(self, x_edges: Array, y_edges: Array, t: float) -> Array:
        """Exact 1D cell averages along an axis; :func:`gauss_average` otherwise."""
        unit_a, unit_b = self._unit()
        along_axis = (unit_a, unit_b) in ((1.0, 0.0), (0.0, 1.0))
        if self.period == 0.0 and len(self.pieces) == 1 and along_axis:
            edges = np.asarray(x_edges if unit_a == 1.0 else y_edges, dtype=np.float64)
            averages = self._to_2d(np.asarray(self.pieces[0].cell_averages(edges, t)))
            if unit_a == 1.0:
                return np.repeat(averages[:, None, :], len(y_edges) - 1, axis=1)
            return np.repeat(averages[:, :, None], len(x_edges) - 1, axis=2)
        return gauss_average(lambda x, y: self.point_values(x, y, t), x_edges, y_edges)


#: Builds the 1D exact solution of one dam: ``(state on the low side, state on the high side,
#: position along the unit normal)`` -> the solution, or None if there is none.
DamSolver = Callable[[Array, Array, float], ExactSolution | None]
#: The lowest and highest position along the normal the waves of a 1D solution reach by ``t``.
WaveExtent = Callable[[ExactSolution, float], tuple[float, float]]


def _dam_options(options: Mapping[str, Any]) -> tuple[Array, Array, float, float, float, float]:
    states = [np.atleast_1d(np.asarray(s, dtype=np.float64)) for s in options["states"]]
    a, b = (float(v) for v in options["normal"])
    return states[0], states[1], a, b, float(options["position"]), float(options["period"])


def dam_break_along_normal(
    options: Mapping[str, Any],
    grid: Grid2D,
    context: Mapping[str, Any],
    solve: DamSolver,
    extent: WaveExtent,
    momentum: int | None,
) -> AlongNormal | None:
    """The exact solution of a ``dam-break`` initial condition (:mod:`conslaw.initial2d`) from
    the 1D solutions of its dams, or None where ``solve`` has none.

    A single dam needs a normal along an axis and outflow on the two sides the normal crosses,
    and holds while its waves stay inside the domain; stripes (``period > 0``) need a periodic
    domain on which they repeat, and hold while the waves of each dam stay within a quarter
    period of it (they have not met the neighbouring dam's). Otherwise
    :class:`~conslaw.exact.Unavailable` says why.
    """
    try:
        return _dam_break_along_normal(options, grid, context, solve, extent, momentum)
    except (ValueError, ArithmeticError) as error:  # a Riemann solve that overflowed (g = 1e308)
        raise Unavailable(f"the exact dam break cannot be computed ({error})") from None


def _dam_break_along_normal(
    options: Mapping[str, Any],
    grid: Grid2D,
    context: Mapping[str, Any],
    solve: DamSolver,
    extent: WaveExtent,
    momentum: int | None,
) -> AlongNormal | None:
    first, second, a, b, position, period = _dam_options(options)
    length = math.hypot(a, b)
    unit = (a / length, b / length)
    t_end = float(context["t_end"])
    if period == 0.0:
        if 0.0 not in unit:
            raise Unavailable(
                "a dam break not along an axis meets the boundaries at once; use stripes "
                "(initial.period) on a periodic domain for an exact solution"
            )
        low_side, high_side = ("left", "right") if unit[1] == 0.0 else ("bottom", "top")
        if context[low_side] != "outflow" or context[high_side] != "outflow":
            raise Unavailable(f"the exact dam break assumes outflow at {low_side} and {high_side}")
        piece = solve(first, second, position / length)
        if piece is None:
            return None
        axis = grid.x if unit[1] == 0.0 else grid.y
        sign = unit[0] + unit[1]
        lowest, highest = sorted((sign * axis.x_min, sign * axis.x_max))
        low, high = extent(piece, t_end)
        if low < lowest or high > highest:
            raise Unavailable(f"a wave reaches the boundary before t={t_end:g}")
        return AlongNormal([piece], [-math.inf], unit, momentum)
    if any(context[side] != "periodic" for side in ("left", "right", "bottom", "top")):
        raise Unavailable(
            "stripes (initial.period > 0) have an exact solution on a periodic domain"
        )
    for along, width in ((a, grid.x.length), (b, grid.y.length)):
        turns = along * width / period
        if abs(turns - round(turns)) > 1e-9 * max(1.0, abs(turns)):
            raise Unavailable("the stripes do not repeat across the periodic domain")
    stripe = period / length  # the period along the unit normal
    dams = (position / length, position / length + 0.5 * stripe)
    rising, falling = solve(second, first, dams[0]), solve(first, second, dams[1])
    if rising is None or falling is None:
        return None
    pieces = [rising, falling]
    for dam, piece in zip(dams, pieces, strict=True):
        low, high = extent(piece, t_end)
        if low < dam - 0.25 * stripe or high > dam + 0.25 * stripe:
            raise Unavailable(f"the waves of neighbouring dams meet before t={t_end:g}")
    bounds = [dams[0] - 0.25 * stripe, dams[0] + 0.25 * stripe]
    return AlongNormal(pieces, bounds, unit, momentum, stripe)
