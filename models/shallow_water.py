"""Shallow-water equations with optional bed, dry states and a well-balanced NT discretisation.

    h_t + (h u)_x = 0
    (h u)_t + (h u^2 + g h^2 / 2)_x = -g h b_x

Dry states: where ``h < dry_tolerance`` the velocity is taken as 0 in every formula (no division
by zero anywhere) and the scheme sets the momentum of such cells to 0 after each step.

Well-balanced bed source (lake at rest ``h + b = const, u = 0`` is preserved to round-off):
the depth is reconstructed through the surface ``h + b`` (surface gradient method, Zhou, Causon,
Mingham & Ingram 2001, J. Comput. Phys. 168), and the source over each staggered cell is paired with
the pressure flux at the same two cell centres, ``-g (h_L + h_R)/2 (b_R - b_L)/dx`` with the cell
averages ``b`` of the bed, as in the well-balanced central schemes of Russo (2005, "Central schemes
for conservation laws with application to shallow water equations") and Kurganov & Levy (2002,
M2AN 36). At rest it cancels the flux difference ``g (h_R^2 - h_L^2)/(2 dx)`` exactly, and it is
second-order accurate in general. Where a bed step is higher than the water in front of it (a
shoreline) the step is clipped to that water's depth (hydrostatic reconstruction, Audusse et al.
2004), so still water against dry land feels no net force; the staggered averaging still moves
some water across a shoreline, and a lake with dry land stays at rest to O(dx), not to round-off
(docs/design.md, "Well-balanced bed").
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
from conslaw.grid import Grid
from conslaw.model import InitialData, parameter
from conslaw_models.depth_averaged import DRY, DepthAveragedModel, velocity
from conslaw_models.shallow_water_exact import DamBreak, StillWater

Array = NDArray[np.float64]

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(8)

# Positions of the parameters in the packed vector (field order of ShallowWaterParameters).
G = 0
# Rows of the coefficient array: cell average of the bed, and its slope.
BED, BED_SLOPE = 0, 1


@njit(cache=True)
def flux_point(q, aux, params, out):
    """``f = (h u, h u^2 + g h^2 / 2)``."""
    h = q[0]
    u = velocity(h, q[1], params[DRY])
    out[0] = q[1]
    out[1] = q[1] * u + 0.5 * params[G] * h * h


@njit(cache=True)
def jacobian_point(q, aux, params, out):
    """``A = [[0, 1], [g h - u^2, 2 u]]``."""
    u = velocity(q[0], q[1], params[DRY])
    out[0, 0] = 0.0
    out[0, 1] = 1.0
    out[1, 0] = params[G] * q[0] - u * u
    out[1, 1] = 2.0 * u


@njit(cache=True)
def max_speed_point(q, aux, params):
    """``|u| + sqrt(g h)``."""
    u = velocity(q[0], q[1], params[DRY])
    return abs(u) + math.sqrt(params[G] * max(q[0], 0.0))


@njit(cache=True)
def source_point(q, aux, params, out):
    """``s = (0, -g h b_x)`` (used in the predictor, paper eq. 15)."""
    out[0] = 0.0
    out[1] = -params[G] * q[0] * aux[BED_SLOPE]


@njit(cache=True)
def balanced_step(h_left, h_right, bed_left, bed_right, spacing, g):
    """``-g (h_L + h_R)/2 D / spacing``: the bed source averaged over the part of a staggered cell
    between two centres, ``D = b_R - b_L`` clipped to ``[-h_R, h_L]``.

    A bed step higher than the water in front of it pushes on that water only, as in the
    hydrostatic reconstruction of Audusse, Bouchut, Bristeau, Klein & Perthame (2004, SIAM J.
    Sci. Comput. 25). Still water against a dry bed higher than its surface (``h_R = 0``,
    ``D = h_L``) then feels ``-g h_L^2/2``, which cancels the pressure flux difference
    ``g (h_R^2 - h_L^2)/2`` exactly; with water on both sides the clip is inactive at rest
    (``|b_R - b_L| < h`` on the deeper side), so the centred second-order form of Russo (2005) is
    kept wherever the flow is wet (docs/design.md, "Well-balanced bed").
    """
    step = bed_right - bed_left
    if step > h_left:
        step = h_left
    elif step < -h_right:
        step = -h_right
    return -g * 0.5 * (h_left + h_right) * step / spacing


@njit(cache=True)
def balanced_source_point(q_left, q_right, aux_left, aux_right, dx, params, out):
    """Source averaged over the staggered cell, ``(0, balanced_step)``."""
    out[0] = 0.0
    out[1] = balanced_step(q_left[0], q_right[0], aux_left[BED], aux_right[BED], dx, params[G])


def check_water_parameters(params: Any, numbers: tuple[str, ...]) -> None:
    """The checks every shallow-water model's parameters share: the fields ``numbers`` finite,
    ``g > 0``, ``0 <= dry_tolerance < 1e-3`` and ``bump_width > 0``."""
    for name in numbers:
        finite_number(getattr(params, name), f"parameters.{name}")
    if not params.g > 0:
        raise ConfigError(f"parameters.g: gravity must be > 0, got {params.g}")
    if not 0 <= params.dry_tolerance < 1e-3:
        raise ConfigError(
            f"parameters.dry_tolerance: must be in [0, 1e-3), got {params.dry_tolerance}"
        )
    if not params.bump_width > 0:
        raise ConfigError(f"parameters.bump_width: must be > 0, got {params.bump_width}")


@dataclass(frozen=True)
class ShallowWaterParameters:
    """Gravity, dry tolerance and an optional Gaussian bump ``b = height exp(-((x-c)/w)^2)``."""

    g: float = parameter(1.0, "gravitational acceleration $g$, > 0, in the scene's units")
    dry_tolerance: float = parameter(
        1e-10, "depth below which a cell counts as dry (velocity 0), in [0, 1e-3)"
    )
    bump_height: float = parameter(
        0.0,
        "height of the bed $b = $ `bump_height` $\\exp(-((x - $ `bump_centre`$)/$ `bump_width`"
        "$)^2)$; 0 is a flat bed (no source compiled), negative a hollow",
    )
    bump_centre: float = parameter(0.0, "centre of the bed bump")
    bump_width: float = parameter(1.0, "width of the bed bump, > 0")

    def __post_init__(self) -> None:
        check_water_parameters(
            self, ("g", "dry_tolerance", "bump_height", "bump_centre", "bump_width")
        )


class WaterOverBed(DepthAveragedModel):
    """A shallow-water model over a bed that may be flat (:attr:`has_bed`): a flat bed costs
    nothing, the bed source and the surface reconstruction are compiled only for one that is
    not."""

    @property
    def has_bed(self) -> bool:
        """Whether the bed is not flat."""
        raise NotImplementedError

    def kernel_variant(self) -> str:
        """A flat bed or not (the bed source and surface reconstruction)."""
        return "with a bed" if self.has_bed else "flat bed"

    def uniform_aux(self) -> bool:
        """A flat bed has the same (zero) coefficients everywhere."""
        return not self.has_bed

    def capabilities(self) -> dict[str, bool]:
        """Without a bed, no source, no surface reconstruction (nothing compiled for them)."""
        return {
            "source": self.has_bed,
            "balanced_source": self.has_bed,
            "surface": self.has_bed,
            "correction": True,
            "resistance": False,
            "dynamic_coefficients": False,
            "interface_coefficients": False,
            "rest_coefficients": False,
        }


class ShallowWater(WaterOverBed):
    """Shallow-water equations, ``q = (h, hu)``, with gravity ``g`` and an optional bed ``b(x)``.

    Exact solutions (flat bed): the Stoker (wet) and Ritter (dry) dam breaks for a single jump at
    rest (docs/equations.md, "Exact solutions"). A flat bed costs nothing: the bed source and the
    surface reconstruction
    are compiled only when ``bump_height != 0``.
    """

    name = "shallow-water"
    description = "shallow-water equations (h, hu), optional bed, dry states, well-balanced"
    aux_names = ("bed", "bed_slope")
    aux_reflect_signs = (1.0, -1.0)
    has_source = True
    surface_aux = (BED, BED_SLOPE)
    Parameters = ShallowWaterParameters
    initial_kinds: ClassVar[dict[str, tuple[tuple[str, ...], dict[str, Any], str]]] = {
        "still-water": (
            ("surface",),
            {"velocity": 0.0},
            "h = max(surface - bed, 0), hu = h * velocity",
        ),
    }
    flux_point = staticmethod(flux_point)
    jacobian_point = staticmethod(jacobian_point)
    max_speed_point = staticmethod(max_speed_point)
    source_point = staticmethod(source_point)
    balanced_source_point = staticmethod(balanced_source_point)

    @property
    def has_bed(self) -> bool:
        """Whether the bed is not flat."""
        return self.params.bump_height != 0.0

    def bed(self, x: Array) -> Array:
        """Bed elevation ``b(x) = bump_height exp(-((x - bump_centre) / bump_width)^2)``."""
        p = self.params
        return p.bump_height * np.exp(-(((np.asarray(x) - p.bump_centre) / p.bump_width) ** 2))

    def _half_cell_averages(self, x: Array, dx: float) -> tuple[Array, Array]:
        # 8-point Gauss–Legendre over each half cell: exact to round-off for a smooth bed, and
        # free of the cancellation of differences of an antiderivative.
        quarter = 0.25 * dx
        left = np.zeros_like(x)
        right = np.zeros_like(x)
        for node, weight in zip(_NODES, _WEIGHTS, strict=True):
            left += 0.5 * weight * self.bed(x - quarter + quarter * node)
            right += 0.5 * weight * self.bed(x + quarter + quarter * node)
        return left, right

    def aux(self, x: Array, dx: float) -> Array:
        """Cell average of the bed over ``[x - dx/2, x + dx/2]`` and its slope
        ``2 (b_right half - b_left half) / dx``, so that ``b +- dx b_x / 4`` are the half-cell
        averages (what the surface reconstruction and the staggered averages need)."""
        x = np.asarray(x, dtype=np.float64)
        with np.errstate(over="ignore", invalid="ignore"):
            left, right = self._half_cell_averages(x, dx)
            aux = np.vstack([0.5 * (left + right), 2.0 * (right - left) / dx])
        if not np.all(np.isfinite(aux)):
            raise ConfigError(
                "parameters.bump_height, bump_width: the bed or its slope overflows on this grid "
                f"(height {self.params.bump_height:g}, width {self.params.bump_width:g})"
            )
        return np.ascontiguousarray(aux)

    def initial_cell_averages(self, kind: str, options: Mapping[str, Any], grid: Grid) -> Array:
        """``still-water``: ``h = max(surface - b, 0)``, ``b`` the cell average of the bed."""
        surface = options["surface"]
        velocity_value = options["velocity"]
        for key, value in (("surface", surface), ("velocity", velocity_value)):
            finite_number(value, f"initial.{key}")
        bed = self.aux(grid.centres(), grid.dx)[BED]
        h = np.maximum(float(surface) - bed, 0.0)
        return np.ascontiguousarray(np.vstack([h, h * float(velocity_value)]))

    def exact_solution(
        self, initial: InitialData, grid: Grid, context: Mapping[str, Any]
    ) -> ExactSolution | None:
        """Stoker/Ritter for one jump between two states at rest on a flat bed, with outflow
        boundaries that no wave reaches by ``t_end``; still water at rest over the bed between
        walls; else None or Unavailable."""
        if initial.kind == "still-water":
            if initial.options["velocity"] != 0.0:
                return None
            if (context["left"], context["right"]) != ("wall", "wall"):
                raise Unavailable("still water stays still between walls only")
            p = self.params
            return StillWater(
                float(initial.options["surface"]), p.bump_height, p.bump_centre, p.bump_width
            )
        if initial.kind != "piecewise-constant" or self.has_bed:
            return None
        dam = DamBreak.from_initial(initial, self.params.g)
        if dam is None:
            return None
        if (context["left"], context["right"]) != ("outflow", "outflow"):
            raise Unavailable("the exact dam-break solution assumes outflow boundaries")
        low, high = dam.wave_extent(float(context["t_end"]))
        if low < grid.x_min or high > grid.x_max:
            raise Unavailable(f"a wave reaches the boundary before t={context['t_end']:g}")
        return dam
