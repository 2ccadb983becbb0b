"""Shallow-water equations in two dimensions with a bed ``b(x, y)`` and dry states.

    h_t + (h u)_x + (h v)_y = 0
    (h u)_t + (h u^2 + g h^2 / 2)_x + (h u v)_y = -g h b_x
    (h v)_t + (h u v)_x + (h v^2 + g h^2 / 2)_y = -g h b_y

The 2D form of :mod:`conslaw_models.shallow_water` (the same dry-state rules: where
``h < dry_tolerance`` both velocities are 0 in every formula and a cell holds no momentum; the same
well-balanced source, paired with the pressure flux along each direction, docs/design.md,
"Well-balanced bed"). The bed is a sum of a Gaussian bump (round, or a ridge that varies along
one axis only) and a paraboloid bowl (Thacker 1981, J. Fluid Mech. 107, the bowl of the planar
oscillation). The scheme reads the bed as exact averages over the quarter cells that the primary
and the staggered cells share (``quarter_bed``; docs/design.md, "Toward two dimensions").
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numba import njit
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number
from conslaw.exact import ExactSolution, Unavailable
from conslaw.exact2d import ExactSolution2D, dam_break_along_normal, gauss_average
from conslaw.grid2d import Grid2D
from conslaw.model import InitialData, parameter
from conslaw_models.depth_averaged import (
    DRY,
    TwoDimensionalRows,
    momentum_jacobian_x,
    momentum_jacobian_y,
    velocity,
)
from conslaw_models.shallow_water import (
    WaterOverBed,
    balanced_step,
    check_water_parameters,
    max_speed_point,
)
from conslaw_models.shallow_water_2d_exact import ThackerPlanar
from conslaw_models.shallow_water_exact import DamBreak

Array = NDArray[np.float64]

#: Gauss–Legendre points per direction over each quarter cell (exact for polynomial beds of
#: degree 11, to round-off for the Gaussian bump on any grid that resolves it).
QUADRATURE_POINTS = 6
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(QUADRATURE_POINTS)

# Positions of the parameters in the packed vector.
G = 0
# Rows of the coefficient array: cell average of the bed, its slopes in x and y (``2 (right half
# - left half) / dx`` and the same in y), and its twist ``(ll - lr) + (ur - ul)`` of the quarter
# averages (lower left, lower right, upper left, upper right), in units of height.
BED, BED_X, BED_Y, BED_TWIST = 0, 1, 2, 3
BUMP_AXES = ("xy", "x", "y")


@njit(cache=True)
def flux_point(q, aux, params, out):
    """``f = (h u, h u^2 + g h^2 / 2, h u v)``."""
    h = q[0]
    u = velocity(h, q[1], params[DRY])
    out[0] = q[1]
    out[1] = q[1] * u + 0.5 * params[G] * h * h
    out[2] = q[2] * u


@njit(cache=True)
def flux_y_point(q, aux, params, out):
    """``g = (h v, h u v, h v^2 + g h^2 / 2)``."""
    h = q[0]
    v = velocity(h, q[2], params[DRY])
    out[0] = q[2]
    out[1] = q[1] * v
    out[2] = q[2] * v + 0.5 * params[G] * h * h


@njit(cache=True)
def jacobian_point(q, aux, params, out):
    """``A = [[0, 1, 0], [g h - u^2, 2 u, 0], [-u v, v, u]]``."""
    u = velocity(q[0], q[1], params[DRY])
    v = velocity(q[0], q[2], params[DRY])
    momentum_jacobian_x(u, v, params[G] * q[0], out)


@njit(cache=True)
def jacobian_y_point(q, aux, params, out):
    """``B = [[0, 0, 1], [-u v, v, u], [g h - v^2, 0, 2 v]]``."""
    u = velocity(q[0], q[1], params[DRY])
    v = velocity(q[0], q[2], params[DRY])
    momentum_jacobian_y(u, v, params[G] * q[0], out)


@njit(cache=True)
def max_speed_y_point(q, aux, params):
    """``|v| + sqrt(g h)``."""
    v = velocity(q[0], q[2], params[DRY])
    return abs(v) + math.sqrt(params[G] * max(q[0], 0.0))


@njit(cache=True)
def source_point(q, aux, params, out):
    """``s = (0, -g h b_x, -g h b_y)`` (in the predictor)."""
    out[0] = 0.0
    out[1] = -params[G] * q[0] * aux[BED_X]
    out[2] = -params[G] * q[0] * aux[BED_Y]


@njit(cache=True)
def balanced_source_point(q_left, q_right, aux_left, aux_right, dx, params, out):
    """``(0, balanced_step, 0)`` between two centres along x (the 1D well-balanced source of
    :func:`conslaw_models.shallow_water.balanced_step`)."""
    out[0] = 0.0
    out[1] = balanced_step(q_left[0], q_right[0], aux_left[BED], aux_right[BED], dx, params[G])
    out[2] = 0.0


@njit(cache=True)
def balanced_source_y_point(q_low, q_high, aux_low, aux_high, dy, params, out):
    """``(0, 0, balanced_step)`` between two centres along y."""
    out[0] = 0.0
    out[1] = 0.0
    out[2] = balanced_step(q_low[0], q_high[0], aux_low[BED], aux_high[BED], dy, params[G])


@dataclass(frozen=True)
class ShallowWater2DParameters:
    """Gravity, dry tolerance, and the bed: a Gaussian bump plus a paraboloid bowl."""

    g: float = parameter(1.0, "gravitational acceleration $g$, > 0, in the scene's units")
    dry_tolerance: float = parameter(
        1e-10, "depth below which a cell counts as dry (velocities 0), in [0, 1e-3)"
    )
    bump_height: float = parameter(
        0.0,
        "height $b_0$ of the bump $b_0 \\exp(-(r/w)^2)$ of the bed ($r$ the distance from "
        "the bump's centre, along the axes of `bump_along`); 0: no bump, negative: a hollow",
    )
    bump_centre_x: float = parameter(0.0, "x of the bump's centre")
    bump_centre_y: float = parameter(0.0, "y of the bump's centre")
    bump_width: float = parameter(1.0, "width $w$ of the bump, > 0")
    bump_along: str = parameter(
        "xy", "`xy`: a round bump; `x` (or `y`): a ridge whose height varies along x (y) only"
    )
    bowl_depth: float = parameter(
        0.0,
        "depth $h_0 \\ge 0$ of the paraboloid bowl $h_0 (r^2/a^2 - 1)$ added to the bed "
        "(Thacker's bowl; $r$ the distance from the bowl's centre); 0: no bowl",
    )
    bowl_radius: float = parameter(1.0, "radius $a > 0$ at which the bowl reaches height 0")
    bowl_centre_x: float = parameter(0.0, "x of the bowl's centre")
    bowl_centre_y: float = parameter(0.0, "y of the bowl's centre")

    def __post_init__(self) -> None:
        check_water_parameters(
            self,
            (
                "g", "dry_tolerance", "bump_height", "bump_centre_x", "bump_centre_y",
                "bump_width", "bowl_depth", "bowl_radius", "bowl_centre_x", "bowl_centre_y",
            ),
        )  # fmt: skip
        if self.bump_along not in BUMP_AXES:
            raise ConfigError(
                f"parameters.bump_along: '{self.bump_along}' is not one of {', '.join(BUMP_AXES)}"
            )
        if not self.bowl_depth >= 0:
            raise ConfigError(f"parameters.bowl_depth: must be >= 0, got {self.bowl_depth}")
        if not self.bowl_radius > 0:
            raise ConfigError(f"parameters.bowl_radius: must be > 0, got {self.bowl_radius}")


class ShallowWater2D(TwoDimensionalRows, WaterOverBed):
    """Shallow-water equations in 2D, ``q = (h, hu, hv)``, with gravity ``g`` and a bed
    ``b(x, y)`` (flat unless ``bump_height`` or ``bowl_depth`` is set)."""

    name = "shallow-water-2d"
    description = "shallow-water equations in 2D (h, hu, hv), bed b(x, y), dry states"
    long_names: ClassVar[dict[str, str]] = {
        "x": "position x",
        "y": "position y",
        "t": "time",
        "h": "depth",
        "hu": "depth times depth-averaged x velocity",
        "hv": "depth times depth-averaged y velocity",
        "u": "depth-averaged x velocity",
        "v": "depth-averaged y velocity",
    }
    aux_names = ("bed", "bed_x", "bed_y", "bed_twist")
    aux_reflect_signs = (1.0, -1.0, 1.0, -1.0)
    aux_reflect_signs_y: ClassVar[tuple[float, ...] | None] = (1.0, 1.0, -1.0, -1.0)
    has_source = True
    surface_aux = (BED, BED_X)
    surface_aux_y: ClassVar[tuple[int, int] | None] = (BED_Y, BED_TWIST)
    empty_stays_empty: ClassVar[bool] = True
    aux_layout_2d = "bed"
    Parameters = ShallowWater2DParameters
    initial_kinds: ClassVar[dict[str, tuple[tuple[str, ...], dict[str, Any], str]]] = {
        "still-water": (
            ("surface",),
            {},
            "water at rest up to the level `surface` over the bed, dry land above it",
        ),
        "thacker": (
            ("amplitude",),
            {},
            "Thacker's planar surface in the bowl (needs bowl_depth > 0), amplitude eta",
        ),
    }
    flux_point = staticmethod(flux_point)
    jacobian_point = staticmethod(jacobian_point)
    max_speed_point = staticmethod(max_speed_point)
    flux_y_point = staticmethod(flux_y_point)
    jacobian_y_point = staticmethod(jacobian_y_point)
    max_speed_y_point = staticmethod(max_speed_y_point)
    source_point = staticmethod(source_point)
    balanced_source_point = staticmethod(balanced_source_point)
    balanced_source_y_point = staticmethod(balanced_source_y_point)

    @property
    def has_bed(self) -> bool:
        """Whether the bed is not flat."""
        return self.params.bump_height != 0.0 or self.params.bowl_depth != 0.0

    def param_vector(self) -> Array:
        """``(g, dry_tolerance)``: the bed enters through the coefficients only."""
        return np.array([self.params.g, self.params.dry_tolerance], dtype=np.float64)

    def bed(self, x: Array, y: Array) -> Array:
        """Bed elevation at the points ``(x, y)`` (broadcast): the bump plus the bowl."""
        p = self.params
        x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
        shape = np.broadcast(x, y).shape
        bed = np.zeros(shape)
        if p.bump_height != 0.0:
            along_x = ((x - p.bump_centre_x) / p.bump_width) ** 2
            along_y = ((y - p.bump_centre_y) / p.bump_width) ** 2
            exponent = {"xy": along_x + along_y, "x": along_x, "y": along_y}[p.bump_along]
            bed = bed + p.bump_height * np.exp(-np.broadcast_to(exponent, shape))
        if p.bowl_depth != 0.0:
            radius_squared = (x - p.bowl_centre_x) ** 2 + (y - p.bowl_centre_y) ** 2
            bed = bed + p.bowl_depth * (radius_squared / p.bowl_radius**2 - 1.0)
        return bed

    def quarter_bed(self, x_edges: Array, y_edges: Array) -> Array:
        """Averages of the bed over the rectangles ``[x_edges[j], x_edges[j+1]] x [y_edges[k],
        y_edges[k+1]]``, shape ``(len(y_edges) - 1, len(x_edges) - 1)``, by a product
        Gauss–Legendre rule of :data:`QUADRATURE_POINTS` per direction. A bed that varies along
        x only gets equal averages in every row, bit for bit (the same sums in the same order)."""
        x_low, x_half = np.asarray(x_edges)[:-1], 0.5 * np.diff(x_edges)
        y_low, y_half = np.asarray(y_edges)[:-1], 0.5 * np.diff(y_edges)
        total = np.zeros((len(y_low), len(x_low)))
        if not self.has_bed:
            return total
        with np.errstate(over="ignore", invalid="ignore"):
            for node_y, weight_y in zip(_NODES, _WEIGHTS, strict=True):
                y = (y_low + y_half * (node_y + 1.0))[:, None]
                for node_x, weight_x in zip(_NODES, _WEIGHTS, strict=True):
                    x = (x_low + x_half * (node_x + 1.0))[None, :]
                    total += (0.25 * weight_x * weight_y) * self.bed(x, y)
        if not np.all(np.isfinite(total)):
            raise ConfigError(
                "parameters.bump_height, bump_width, bowl_depth, bowl_radius: the bed overflows "
                "on this grid"
            )
        return total

    def thacker(self, amplitude: float) -> ThackerPlanar:
        """Thacker's planar oscillation of amplitude ``amplitude`` in the model's bowl."""
        p = self.params
        if p.bowl_depth <= 0.0 or p.bump_height != 0.0:
            raise ConfigError(
                "initial.kind 'thacker' needs the bowl alone: parameters.bowl_depth > 0 and "
                "bump_height = 0"
            )
        return ThackerPlanar(
            p.bowl_depth, p.bowl_radius, amplitude, p.g, p.bowl_centre_x, p.bowl_centre_y
        )

    def initial_cell_averages_2d(
        self, kind: str, options: Mapping[str, Any], grid: Grid2D
    ) -> Array:
        """``still-water``: ``h = max(surface - b, 0)`` of the cell-average bed ``b`` (a scheme
        that reads the bed by quarters may replace it by its own still water); ``thacker``:
        the cell averages of Thacker's planar surface at ``t = 0``
        (:class:`~conslaw_models.shallow_water_2d_exact.ThackerPlanar`)."""
        x_edges, y_edges = grid.x.edges, grid.y.edges
        if kind == "still-water":
            surface = finite_number(options["surface"], "initial.surface")
            h = np.maximum(surface - self.quarter_bed(x_edges, y_edges), 0.0)
            return np.stack([h, np.zeros_like(h), np.zeros_like(h)])
        if kind == "thacker":
            amplitude = finite_number(options["amplitude"], "initial.amplitude")
            return self.thacker(amplitude).cell_averages(x_edges, y_edges, 0.0)
        return super().initial_cell_averages_2d(kind, options, grid)

    def exact_solution_2d(
        self, initial: InitialData, grid: Grid2D, context: Mapping[str, Any]
    ) -> ExactSolution2D | None:
        """Stoker/Ritter along the normal of a dam break on a flat bed between states at rest
        (:func:`conslaw.exact2d.dam_break_along_normal`), Thacker's planar surface while it
        stays inside the domain, still water at rest between walls; else None or
        :class:`~conslaw.exact.Unavailable`."""
        p = self.params
        if initial.kind == "thacker":
            thacker = self.thacker(float(initial.options["amplitude"]))
            reach = p.bowl_radius + abs(thacker.eta)
            if (
                p.bowl_centre_x - reach < grid.x.x_min
                or p.bowl_centre_x + reach > grid.x.x_max
                or p.bowl_centre_y - reach < grid.y.x_min
                or p.bowl_centre_y + reach > grid.y.x_max
            ):
                raise Unavailable("the water of Thacker's solution reaches the boundary")
            return thacker
        if initial.kind == "still-water":
            if any(context[side] != "wall" for side in ("left", "right", "bottom", "top")):
                raise Unavailable("still water stays still between walls only")
            return StillWater2D(self, float(initial.options["surface"]))
        if initial.kind != "dam-break" or self.has_bed:
            return None

        def solve(low: Array, high: Array, x0: float) -> ExactSolution | None:
            if low[1] != 0.0 or low[2] != 0.0 or high[1] != 0.0 or high[2] != 0.0:
                return None
            if low[0] == high[0]:
                return None
            return DamBreak(x0, float(low[0]), float(high[0]), p.g)

        def extent(piece: ExactSolution, t: float) -> tuple[float, float]:
            assert isinstance(piece, DamBreak)
            return piece.wave_extent(t)

        return dam_break_along_normal(initial.options, grid, context, solve, extent, 1)


@dataclass(frozen=True)
class StillWater2D:
    """Water at rest: ``h = max(surface - b, 0)`` with the model's bed, no momentum (cell
    averages of the depth by :func:`conslaw.exact2d.gauss_average`)."""

    model: ShallowWater2D
    surface: float

    def point_values(self, x: Array, y: Array, t: float) -> Array:
        """``(h, 0, 0)`` at the points."""
        h = np.maximum(self.surface - self.model.bed(x, y), 0.0)
        return np.stack([h, np.zeros_like(h), np.zeros_like(h)])

    def cell_averages(self, x_edges: Array, y_edges: Array, t: float) -> Array:
        """Averages over the cells (Gauss points on sub-cells: the shoreline is a kink)."""
        return gauss_average(lambda x, y: self.point_values(x, y, t), x_edges, y_edges)
