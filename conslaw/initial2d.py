"""Initial conditions of 2D scenes: cell averages of the initial data on a :class:`Grid2D`.

Kinds (scene table ``[initial]``, key ``kind``; docs/scenes.md, "Two-dimensional scenes"):

``dam-break``
    ``states`` (two entries, each a number for a scalar model or a list of one number per
    variable), ``normal = [a, b]`` (default ``[1, 0]``), ``position`` (default 0) and ``period``
    (default 0). With ``s = a x + b y``: ``states[0]`` where ``s < position`` and ``states[1]``
    elsewhere; with ``period = P > 0`` the pattern repeats along ``s``, ``states[0]`` where
    ``(s - position) mod P`` is below ``P/2`` (stripes, for a periodic domain). Exact cell
    averages (the area of a cell on each side of a line, below).
``circle``
    ``centre = [x, y]``, ``radius``, ``inside`` and ``outside`` states. Cells the circle cuts are
    averaged over :data:`CIRCLE_PARTS` x :data:`CIRCLE_PARTS` sub-cell midpoints (the others
    are exact).

A model adds its own kinds through ``Model.initial_kinds`` and ``Model.initial_cell_averages``
(shallow water in 2D: ``still-water`` and ``thacker``; Burgers in 2D: ``product-wave``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number
from conslaw.initial import checked_options

if TYPE_CHECKING:
    from conslaw.grid2d import Grid2D
    from conslaw.model import Model

Array = NDArray[np.float64]

#: Sub-cells per direction over which a cell cut by a ``circle`` is averaged.
CIRCLE_PARTS = 32

#: kind -> (required keys, optional keys with defaults, one-line description)
INITIAL_KINDS_2D: dict[str, tuple[tuple[str, ...], dict[str, Any], str]] = {
    "dam-break": (
        ("states",),
        {"normal": [1.0, 0.0], "position": 0.0, "period": 0.0},
        "states[0] where a x + b y < position (normal = [a, b]), states[1] beyond; with "
        "period P > 0, stripes: states[0] where (a x + b y - position) mod P < P/2",
    ),
    "circle": (
        ("centre", "radius", "inside", "outside"),
        {},
        "one state inside a circle, another outside (a radial dam break)",
    ),
}


def _number(value: Any, key: str) -> float:
    return finite_number(value, f"initial.{key}")


def _pair(value: Any, key: str) -> tuple[float, float]:
    if not isinstance(value, list) or len(value) != 2:
        raise ConfigError(f"initial.{key}: expected a list of two numbers, got {value!r}")
    return _number(value[0], key), _number(value[1], key)


def state_vector(value: Any, key: str, model: Model) -> Array:
    """One state of the scene (a number for a scalar model, else a list with one number per
    variable), checked admissible for ``model``."""
    values = value if isinstance(value, list) else [value]
    if len(values) != model.n_vars:
        raise ConfigError(
            f"initial.{key}: expected {model.n_vars} numbers ({', '.join(model.variables)}), "
            f"got {value!r}"
        )
    state = np.array([_number(v, key) for v in values], dtype=np.float64)
    if not model.is_admissible(state[:, None]).all():
        raise ConfigError(
            f"initial.{key} = {value!r} is not an admissible state of '{model.name}' "
            f"({model.admissible_rule})"
        )
    return state


def area_below(a: float, b: float, level: Array | float, x_edges: Array, y_edges: Array) -> Array:
    """The fraction of every cell ``[x_edges[j], x_edges[j+1]] x [y_edges[k], y_edges[k+1]]``
    where ``a x + b y < level``, shape ``(ny, nx)``, exact up to round-off.

    With ``R(z) = max(z, 0)^2`` the area is the mixed second difference over the cell's corners
    ``[R(c - a x0 - b y0) - R(c - a x1 - b y0) - R(c - a x0 - b y1) + R(c - a x1 - b y1)]
    / (2 a b)`` (integrate the step ``H(c - a x - b y)`` once in y, once in x); with ``b = 0``
    (or ``a = 0``) the 1D fraction of the cell's width. Cells the line does not cross are 0 or 1
    exactly, and the result is clipped to [0, 1] (the difference loses digits for a line nearly
    along an axis).
    """
    x0, x1 = np.asarray(x_edges)[None, :-1], np.asarray(x_edges)[None, 1:]
    y0, y1 = np.asarray(y_edges)[:-1, None], np.asarray(y_edges)[1:, None]
    level = np.asarray(level, dtype=np.float64)
    corners = [a * x + b * y for x in (x0, x1) for y in (y0, y1)]
    lowest = np.minimum.reduce(np.broadcast_arrays(*corners))
    highest = np.maximum.reduce(np.broadcast_arrays(*corners))
    with np.errstate(divide="ignore", invalid="ignore"):
        if a != 0.0 and b != 0.0:
            ramp = [np.maximum(level - c, 0.0) ** 2 for c in corners]
            # corners: (x0, y0), (x0, y1), (x1, y0), (x1, y1)
            inside = (ramp[0] - ramp[1] - ramp[2] + ramp[3]) / (2.0 * a * b)
            fraction = inside / ((x1 - x0) * (y1 - y0))
        elif a != 0.0:
            fraction = np.broadcast_to((level - a * x0) / (a * (x1 - x0)), lowest.shape)
            fraction = fraction if a > 0.0 else 1.0 - fraction
        else:
            fraction = np.broadcast_to((level - b * y0) / (b * (y1 - y0)), lowest.shape)
            fraction = fraction if b > 0.0 else 1.0 - fraction
    fraction = np.clip(fraction, 0.0, 1.0)
    return np.where(level <= lowest, 0.0, np.where(level >= highest, 1.0, fraction))


def sub_cell_average(
    values: Callable[[Array, Array], Array], x_edges: Array, y_edges: Array, parts: int
) -> Array:
    """Average of ``values(x, y)`` (broadcast, any leading axes) over every cell by the midpoints
    of ``parts`` x ``parts`` sub-cells."""
    x_left, x_width = np.asarray(x_edges)[:-1], np.diff(x_edges)
    y_low, y_width = np.asarray(y_edges)[:-1], np.diff(y_edges)
    total: Array | None = None
    for j in range(parts):
        y = (y_low + (j + 0.5) / parts * y_width)[:, None]
        for i in range(parts):
            x = (x_left + (i + 0.5) / parts * x_width)[None, :]
            sample = values(x, y)
            total = sample if total is None else total + sample
    assert total is not None
    return total / parts**2


@dataclass(frozen=True)
class InitialCondition2D:
    """A validated 2D initial condition: ``kind`` and its options."""

    kind: str
    options: Mapping[str, Any] = field(default_factory=dict)

    @classmethod
    def from_table(cls, table: Any, model_class: type[Model]) -> InitialCondition2D:
        """Validate a 2D scene's ``[initial]`` table (unknown kinds and keys are errors); the
        kinds are those of :data:`INITIAL_KINDS_2D` and the model's ``initial_kinds``."""
        kind, options = checked_options(table, {**INITIAL_KINDS_2D, **model_class.initial_kinds})
        return cls(kind, options)

    def to_table(self) -> dict[str, Any]:
        """The ``[initial]`` table of the resolved scene."""
        return {"kind": self.kind, **self.options}

    def dam_break(self, model: Model) -> tuple[Array, Array, tuple[float, float], float, float]:
        """``(state 0, state 1, (a, b), position, period)`` of a ``dam-break``, checked."""
        states = self.options["states"]
        if not isinstance(states, list) or len(states) != 2:
            raise ConfigError(f"initial.states: expected two states, got {states!r}")
        first = state_vector(states[0], "states[0]", model)
        second = state_vector(states[1], "states[1]", model)
        a, b = _pair(self.options["normal"], "normal")
        if a == 0.0 and b == 0.0:
            raise ConfigError("initial.normal: must not be [0, 0]")
        position = _number(self.options["position"], "position")
        period = _number(self.options["period"], "period")
        if period < 0.0:
            raise ConfigError(f"initial.period: must be >= 0, got {period}")
        return first, second, (a, b), position, period

    def cell_averages(self, grid: Grid2D, model: Model) -> Array:
        """Cell averages on the primary grid, shape ``(n_vars, ny, nx)``."""
        x_edges, y_edges = grid.x.edges, grid.y.edges
        if self.kind == "dam-break":
            first, second, (a, b), position, period = self.dam_break(model)
            share = self._share_of_first(a, b, position, period, x_edges, y_edges)
            averages = share * first[:, None, None] + (1.0 - share) * second[:, None, None]
            # A cell wholly on one side gets that state bit for bit.
            averages = np.where(share == 1.0, first[:, None, None], averages)
            return np.where(share == 0.0, second[:, None, None], averages)
        if self.kind == "circle":
            return self._circle(grid, model)
        return model.initial_cell_averages_2d(self.kind, self.options, grid)

    @staticmethod
    def _share_of_first(
        a: float, b: float, position: float, period: float, x_edges: Array, y_edges: Array
    ) -> Array:
        if period == 0.0:
            return area_below(a, b, position, x_edges, y_edges)
        corners = [a * x + b * y for x in x_edges[[0, -1]] for y in y_edges[[0, -1]]]
        first = math.floor((min(corners) - position) / period) - 1
        last = math.ceil((max(corners) - position) / period) + 1
        if last - first > 100_000:
            raise ConfigError(f"initial.period: {period} gives too many stripes on the domain")
        share = np.zeros((len(y_edges) - 1, len(x_edges) - 1))
        for k in range(first, last + 1):
            start = position + k * period
            share += area_below(a, b, start + 0.5 * period, x_edges, y_edges)
            share -= area_below(a, b, start, x_edges, y_edges)
        return np.clip(share, 0.0, 1.0)

    def _circle(self, grid: Grid2D, model: Model) -> Array:
        centre_x, centre_y = _pair(self.options["centre"], "centre")
        radius = _number(self.options["radius"], "radius")
        if radius <= 0.0:
            raise ConfigError(f"initial.radius: must be > 0, got {radius}")
        inside = state_vector(self.options["inside"], "inside", model)
        outside = state_vector(self.options["outside"], "outside", model)
        x_edges, y_edges = grid.x.edges, grid.y.edges
        # Nearest and farthest distance of each cell from the centre.
        near_x = np.maximum(np.maximum(x_edges[:-1] - centre_x, centre_x - x_edges[1:]), 0.0)
        near_y = np.maximum(np.maximum(y_edges[:-1] - centre_y, centre_y - y_edges[1:]), 0.0)
        far_x = np.maximum(np.abs(x_edges[:-1] - centre_x), np.abs(x_edges[1:] - centre_x))
        far_y = np.maximum(np.abs(y_edges[:-1] - centre_y), np.abs(y_edges[1:] - centre_y))
        nearest = np.hypot(near_x[None, :], near_y[:, None])
        farthest = np.hypot(far_x[None, :], far_y[:, None])
        share = np.where(farthest <= radius, 1.0, 0.0)
        rows, columns = np.nonzero((nearest < radius) & (farthest > radius))
        if rows.size:
            x_low, width = x_edges[columns], grid.dx
            y_low, height = y_edges[rows], grid.dy
            offsets = (np.arange(CIRCLE_PARTS) + 0.5) / CIRCLE_PARTS
            x = x_low[:, None, None] + width * offsets[None, None, :]
            y = y_low[:, None, None] + height * offsets[None, :, None]
            within = (x - centre_x) ** 2 + (y - centre_y) ** 2 < radius**2
            share[rows, columns] = within.mean(axis=(1, 2))
        averages = share * inside[:, None, None] + (1.0 - share) * outside[:, None, None]
        averages = np.where(share == 1.0, inside[:, None, None], averages)
        return np.where(share == 0.0, outside[:, None, None], averages)
