"""Savage–Hutter avalanche equations on a terrain surface ``z = b(x, y)``, in SI units, solved
over the horizontal map coordinates ``(x, y)`` (docs/design.md, "Savage–Hutter on terrain").

The thin-layer equations of Savage & Hutter (1991) and Gray, Wieland & Hutter (1999) hold in
the surface: thickness ``h`` normal to it, velocity ``U`` tangent to it, depth-averaged
pressure ``g c K h^2 / 2`` (``c = cos theta``), Coulomb friction ``tan delta`` times the
normal reaction. Written over the horizontal projection as Bouchut & Westdickenberg (2004) do
for arbitrary topography, with the unknowns the volume per map area ``H = h / c`` and the
horizontal velocity ``u = (u, v)`` (the map components of ``U = (u, v, grad b . u)``)::

    H_t + div(H u) = 0
    (H u_i)_t + div(H u_i u) + sum_j d_j (P_ij g K_j c^2 H^2 / 2)
        = -c N H b_i + sum_j g K_j c^3 T_ij H^2 / 2 - tan(delta) N H U_i / |U|

with ``P = I - c^2 grad b grad b^T`` and ``T_ij = d_j (P_ij / c)``
(:mod:`conslaw_models.terrain_geometry`), and the normal reaction per unit mass ``N = max(g c +
c u^T (grad grad b) u, 0)``: gravity's normal part plus the centripetal part of the curved
surface, 0 where the layer would leave the ground. Its horizontal part ``-c N grad b`` is the
driving force (``-g c^2 grad b``, the tangential gravity, at rest). The friction acts against
the tangential momentum ``H U``, whose length is ``|H u|_G = (|H u|^2 + (grad b . H u)^2)^(1/2)``:
the scheme stops or shortens it in that metric (``tangent_slope_rows``).

On a plane tilted along x these are the chute equations of
:mod:`conslaw_models.savage_hutter_2d` (with ``g = 1``, ``epsilon = 1``) under ``x = c s``, ``H
= h / c``, ``H u = h U``; a profile ``b(x)`` gives the curved-chute model with its ``kappa U^2``
friction. Earth pressure: ``K_x`` by the sign of ``du/dx``, ``K_y`` by the lateral rule and the
sign of ``dv/dy`` as in the chute model, along the map axes (exact where the fall line is along
x; ``earth_pressure = "isotropic"`` is invariant under rotation).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numba import njit
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number
from conslaw.exact2d import gauss_average
from conslaw.grid2d import Grid2D
from conslaw.model import parameter
from conslaw.terrain.dem import DigitalElevationModel, read_dem
from conslaw.terrain.release import release_mask, release_polygon_mask
from conslaw_models.depth_averaged import (
    DRY,
    DepthAveragedModel,
    TwoDimensionalRows,
    momentum_jacobian_x,
    momentum_jacobian_y,
    velocity,
)
from conslaw_models.savage_hutter import (
    active_and_passive,
    beyond_round_off,
    check_friction,
    earth_pressure,
    velocity_change,
)
from conslaw_models.savage_hutter_2d import TwoEarthPressures, cap_options, lateral_coefficient
from conslaw_models.terrain_geometry import pressure_geometry, projection, slope_cosine
from conslaw_models.terrain_surface import (
    ChannelledPlaneToFlat,
    GriddedSurface,
    InclinedPlane,
    ParaboloidBowl,
    PlaneToFlat,
    TerrainSurface,
    coarser,
)

Array = NDArray[np.float64]

# Packed parameters; DRY = 1 is shared with the other depth-averaged models, K_ACTIVE and
# K_PASSIVE with the chute models (conslaw_models.savage_hutter.earth_pressure reads them).
GRAVITY, K_ACTIVE, K_PASSIVE, TAN_DELTA, K_Y_MAX = 0, 2, 3, 4, 5
# Rows of the coefficients: the surface gradient, cos theta, c^2 P, c^3 T, the second
# derivatives, and the earth-pressure coefficients K_x, K_y (set per cell and staggered cell).
SLOPE_X, SLOPE_Y, COS = 0, 1, 2
PRESS_XX, PRESS_XY, PRESS_YY = 3, 4, 5
GEOMETRY_XX, GEOMETRY_XY, GEOMETRY_YX, GEOMETRY_YY = 6, 7, 8, 9
CURVE_XX, CURVE_XY, CURVE_YY = 10, 11, 12
KX, KY = 13, 14

TERRAIN_KINDS = ("plane", "bowl", "plane-to-flat", "channel", "dem")
#: The steepest slope, degrees, of a formula terrain and of a released cell: the thin-layer
#: equations hold for a layer much thinner than the slope is long, and the volume per map area
#: ``h / cos(theta)`` of a given thickness grows without bound toward a cliff
#: (docs/design.md, "Savage–Hutter on terrain").
MAX_SLOPE = 75.0


@njit(cache=True)
def flux_point(q, aux, params, out):
    """``f = (H u, H u^2 + P_xx p_x, H u v + P_yx p_x)``, ``p_x = g K_x c^2 H^2 / 2``."""
    depth = q[0]
    u = velocity(depth, q[1], params[DRY])
    pressure = 0.5 * params[GRAVITY] * aux[KX] * depth * depth
    out[0] = q[1]
    out[1] = q[1] * u + aux[PRESS_XX] * pressure
    out[2] = q[2] * u + aux[PRESS_XY] * pressure


@njit(cache=True)
def flux_y_point(q, aux, params, out):
    """``g = (H v, H u v + P_xy p_y, H v^2 + P_yy p_y)``, ``p_y = g K_y c^2 H^2 / 2``."""
    depth = q[0]
    v = velocity(depth, q[2], params[DRY])
    pressure = 0.5 * params[GRAVITY] * aux[KY] * depth * depth
    out[0] = q[2]
    out[1] = q[1] * v + aux[PRESS_XY] * pressure
    out[2] = q[2] * v + aux[PRESS_YY] * pressure


@njit(cache=True)
def jacobian_point(q, aux, params, out):
    """``A = [[0, 1, 0], [g K_x c^2 P_xx H - u^2, 2 u, 0], [g K_x c^2 P_yx H - u v, v, u]]``:
    eigenvalues ``u`` and ``u +- (g K_x c^2 P_xx H)^(1/2)``."""
    u = velocity(q[0], q[1], params[DRY])
    v = velocity(q[0], q[2], params[DRY])
    stiffness = params[GRAVITY] * aux[KX] * q[0]
    momentum_jacobian_x(u, v, stiffness * aux[PRESS_XX], out)
    out[2, 0] += stiffness * aux[PRESS_XY]


@njit(cache=True)
def jacobian_y_point(q, aux, params, out):
    """``B = [[0, 0, 1], [g K_y c^2 P_xy H - u v, v, u], [g K_y c^2 P_yy H - v^2, 0, 2 v]]``."""
    u = velocity(q[0], q[1], params[DRY])
    v = velocity(q[0], q[2], params[DRY])
    stiffness = params[GRAVITY] * aux[KY] * q[0]
    momentum_jacobian_y(u, v, stiffness * aux[PRESS_YY], out)
    out[1, 0] += stiffness * aux[PRESS_XY]


@njit(cache=True)
def max_speed_point(q, aux, params):
    """``|u| + (g K c^2 P_xx H)^(1/2)`` with the largest ``K_x`` (on the safe side)."""
    u = velocity(q[0], q[1], params[DRY])
    k_max = max(params[K_ACTIVE], params[K_PASSIVE], aux[KX])
    return abs(u) + math.sqrt(max(params[GRAVITY] * k_max * aux[PRESS_XX] * q[0], 0.0))


@njit(cache=True)
def max_speed_y_point(q, aux, params):
    """``|v| + (g K_y c^2 P_yy H)^(1/2)`` with the largest ``K_y``."""
    v = velocity(q[0], q[2], params[DRY])
    k_max = max(params[K_Y_MAX], aux[KY])
    return abs(v) + math.sqrt(max(params[GRAVITY] * k_max * aux[PRESS_YY] * q[0], 0.0))


@njit(cache=True)
def normal_reaction(q, aux, params):
    """``N = max(g c + c u^T (grad grad b) u, 0)``: the normal reaction per unit mass."""
    u = velocity(q[0], q[1], params[DRY])
    v = velocity(q[0], q[2], params[DRY])
    bend = aux[CURVE_XX] * u * u + 2.0 * aux[CURVE_XY] * u * v + aux[CURVE_YY] * v * v
    return max(aux[COS] * (params[GRAVITY] + bend), 0.0)


@njit(cache=True)
def source_point(q, aux, params, out):
    """``(0, -c N H b_x + g H^2 (K_x c^3 T_xx + K_y c^3 T_xy) / 2, -c N H b_y + g H^2 (K_x c^3
    T_yx + K_y c^3 T_yy) / 2)``: the driving force and what the divergence form of the
    pressure leaves."""
    depth = q[0]
    push = aux[COS] * normal_reaction(q, aux, params) * depth
    half = 0.5 * params[GRAVITY] * depth * depth
    out[0] = 0.0
    out[1] = -push * aux[SLOPE_X] + half * (aux[KX] * aux[GEOMETRY_XX] + aux[KY] * aux[GEOMETRY_XY])
    out[2] = -push * aux[SLOPE_Y] + half * (aux[KX] * aux[GEOMETRY_YX] + aux[KY] * aux[GEOMETRY_YY])


@njit(cache=True)
def resistance_point(q, aux, params):
    """Coulomb friction ``tan(delta) N H`` in the tangent plane (the scheme applies it against
    the tangential momentum, measured in the surface metric)."""
    return params[TAN_DELTA] * max(q[0], 0.0) * normal_reaction(q, aux, params)


@njit(cache=True)
def coefficients_2d_point(q, slope_x, slope_y, aux, params):
    """``K_x`` and ``K_y`` of a cell for its predictor, from the reconstructed velocity
    changes across it (:func:`conslaw_models.savage_hutter_2d.coefficients_2d_point`)."""
    depth = q[0]
    along_x = 0.0
    along_y = 0.0
    if depth >= params[DRY] and depth > 0.0:
        along_x = beyond_round_off(slope_x[1] - (q[1] / depth) * slope_x[0], q[1])
        along_y = beyond_round_off(slope_y[2] - (q[2] / depth) * slope_y[0], q[2])
    k_x = earth_pressure(along_x, params)
    aux[KX] = k_x
    aux[KY] = lateral_coefficient(k_x, along_y, params[TAN_DELTA])


@njit(cache=True)
def corner_coefficients_point(a, b, c, d, aux, params):
    """One ``K_x`` and ``K_y`` for the fluxes of a staggered cell from its corner cells
    (:func:`conslaw_models.savage_hutter_2d.corner_coefficients_point`)."""
    dry = params[DRY]
    along_x = velocity_change(a, b, 1, dry) + velocity_change(c, d, 1, dry)
    along_y = velocity_change(a, c, 2, dry) + velocity_change(b, d, 2, dry)
    k_x = earth_pressure(along_x, params)
    aux[KX] = k_x
    aux[KY] = lateral_coefficient(k_x, along_y, params[TAN_DELTA])


@dataclass(frozen=True)
class SavageHutterTerrainParameters:
    """Parameters in SI units (angles in degrees)."""

    gravity: float = parameter(9.81, "gravitational acceleration $g$ in m/s^2; > 0")
    phi: float = parameter(
        35.0,
        "internal friction angle $\\phi$ in degrees, $\\delta \\le \\phi < 90$; $K_x$ switches "
        "between $K_{act}$ and $K_{pass}$ where $\\phi > \\delta$, $K_y$ between its two roots "
        "wherever $\\delta > 0$",
    )
    delta: float = parameter(
        30.0,
        "bed friction angle $\\delta$ in degrees, $0 \\le \\delta \\le \\phi$; Coulomb friction "
        "$\\tan\\delta$ times the normal reaction, against the velocity in the surface",
    )
    earth_pressure: str = parameter(
        "savage-hutter",
        "`savage-hutter`: $K_x$, $K_y$ active or passive by the signs of $u_x$, $v_y$ along the "
        "map axes; `isotropic`: $K = 1$ (invariant under rotation)",
    )
    terrain: str = parameter(
        "plane",
        "the surface: `plane` (inclination `zeta`, descending toward +x), `bowl` (paraboloid "
        "$b = (x^2 + y^2) / (2 R)$, `bowl_radius`), `plane-to-flat` (a plane of inclination "
        "`zeta` turning through an arc of radius `transition_radius` into a flat run-out from "
        "`transition_end`; Gray, Wieland & Hutter 1999), `channel` (that terrain with a Gaussian "
        "channel along y = 0, `channel_depth` deep and `channel_half_width` wide, fading out "
        "through the arc), `dem` (`dem_file`, a GeoTIFF or ESRI "
        "ASCII grid, interpolated by a bicubic spline; [terrain](terrain.md))",
    )
    zeta: float = parameter(
        30.0,
        "`plane`, `plane-to-flat`, `channel`: inclination in degrees, in [-75, 75] (in (0, 75] "
        "for the last two); positive where it descends in +x",
    )
    bowl_radius: float = parameter(100.0, "`bowl`: radius of curvature $R$ at the bottom in m; > 0")
    transition_radius: float = parameter(
        200.0,
        "`plane-to-flat`, `channel`: radius of the arc between the plane and the run-out, m; > 0",
    )
    transition_end: float = parameter(
        700.0, "`plane-to-flat`, `channel`: x (m) where the arc meets the flat run-out"
    )
    channel_depth: float = parameter(
        15.0, "`channel`: depth of the channel on the plane in m; >= 0"
    )
    channel_half_width: float = parameter(
        50.0, "`channel`: half-width w of the channel, depth D exp(-(y/w)^2), in m; > 0"
    )
    dem_smoothing: float = parameter(
        0.0,
        "`dem`: standard deviation, in cells, of a Gaussian filter applied to the elevations "
        "before the spline (the curvature terms read a DEM's noise over the cell size "
        "squared); 0: none; in [0, 50]",
    )
    dem_file: str = parameter(
        "", "`dem`: the elevation model, GeoTIFF or ESRI ASCII grid; relative to the scene file"
    )
    density: float = parameter(
        200.0, "bulk density in kg/m^3, for the peak pressure $\\rho |U|^2$ of the hazard maps; > 0"
    )
    dry_tolerance: float = parameter(
        1e-10, "volume per map area (m) below which a cell counts as dry, in [0, 1e-3)"
    )

    def __post_init__(self) -> None:
        for name in (
            "gravity", "phi", "delta", "zeta", "bowl_radius", "transition_radius",
            "transition_end", "channel_depth", "channel_half_width", "density",
            "dem_smoothing", "dry_tolerance",
        ):  # fmt: skip
            finite_number(getattr(self, name), f"parameters.{name}")
        if not self.gravity > 0:
            raise ConfigError(f"parameters.gravity: must be > 0, got {self.gravity}")
        check_friction(self.phi, self.delta, self.earth_pressure)
        if self.terrain not in TERRAIN_KINDS:
            raise ConfigError(
                f"parameters.terrain: unknown '{self.terrain}'; allowed: {', '.join(TERRAIN_KINDS)}"
            )
        if not -MAX_SLOPE <= self.zeta <= MAX_SLOPE:
            raise ConfigError(
                f"parameters.zeta: must be in [-{MAX_SLOPE:g}, {MAX_SLOPE:g}] degrees (a thin "
                f"layer on a slope), got {self.zeta}"
            )
        if not self.bowl_radius > 0:
            raise ConfigError(f"parameters.bowl_radius: must be > 0, got {self.bowl_radius}")
        if not self.channel_depth >= 0:
            raise ConfigError(f"parameters.channel_depth: must be >= 0 m, got {self.channel_depth}")
        if not self.channel_half_width > 0:
            raise ConfigError(
                f"parameters.channel_half_width: must be > 0 m, got {self.channel_half_width}"
            )
        if not 0.0 <= self.dem_smoothing <= 50.0:
            raise ConfigError(
                f"parameters.dem_smoothing: must be in [0, 50] cells, got {self.dem_smoothing}"
            )
        if not self.density > 0:
            raise ConfigError(f"parameters.density: must be > 0 kg/m^3, got {self.density}")
        if not self.transition_radius > 0:
            raise ConfigError(
                f"parameters.transition_radius: must be > 0, got {self.transition_radius}"
            )
        if self.terrain in ("plane-to-flat", "channel") and not self.zeta > 0:
            raise ConfigError(
                f"parameters.zeta: a {self.terrain} terrain descends toward +x (zeta in (0, 90)), "
                f"got {self.zeta}"
            )
        if not isinstance(self.dem_file, str):
            raise ConfigError(f"parameters.dem_file: expected a file name, got {self.dem_file!r}")
        if self.terrain == "dem" and not self.dem_file:
            raise ConfigError("parameters.dem_file: terrain = 'dem' needs a GeoTIFF or .asc file")
        if not 0 <= self.dry_tolerance < 1e-3:
            raise ConfigError(
                f"parameters.dry_tolerance: must be in [0, 1e-3), got {self.dry_tolerance}"
            )


def check_release_slopes(released: NDArray[np.bool_], cosine: Array, x: Array, y: Array) -> None:
    """Refuse a release on a slope steeper than :data:`MAX_SLOPE`.

    Parameters
    ----------
    released : numpy.ndarray of bool
        ``(ny, nx)``.
    cosine : numpy.ndarray
        ``(ny, nx)`` cosine of the slope angle.
    x, y : numpy.ndarray
        The cell centres along x and y.

    Raises
    ------
    ConfigError
        Naming ``initial``, the steepest released cell and its slope.
    """
    steep = released & (cosine < math.cos(math.radians(MAX_SLOPE)))
    if steep.any():
        row, column = np.unravel_index(np.argmin(np.where(steep, cosine, np.inf)), steep.shape)
        angle = math.degrees(math.acos(float(cosine[row, column])))
        raise ConfigError(
            f"initial: {int(np.count_nonzero(steep))} released cells are steeper than "
            f"{MAX_SLOPE:g} degrees (the steepest {angle:.1f} at x={x[column]:g}, y={y[row]:g}): "
            "a thin layer cannot rest on a cliff; move the release"
        )


def make_surface(
    p: SavageHutterTerrainParameters,
) -> tuple[TerrainSurface, DigitalElevationModel | None]:
    """The terrain surface of the parameters ``p``, and the elevation model it was read from
    (None for a terrain from a formula).

    Parameters
    ----------
    p : SavageHutterTerrainParameters

    Returns
    -------
    surface : TerrainSurface
    dem : DigitalElevationModel or None

    Raises
    ------
    ConfigError
        For a DEM file that cannot be used, naming ``parameters.dem_file``
        (:func:`conslaw.terrain.dem.read_dem`).
    """
    if p.terrain == "bowl":
        return ParaboloidBowl(p.bowl_radius), None
    if p.terrain == "plane-to-flat":
        return PlaneToFlat(p.zeta, p.transition_radius, p.transition_end), None
    if p.terrain == "channel":
        profile = PlaneToFlat(p.zeta, p.transition_radius, p.transition_end)
        return ChannelledPlaneToFlat(profile, p.channel_depth, p.channel_half_width), None
    if p.terrain == "dem":
        dem = read_dem(p.dem_file, label="parameters.dem_file")
        return GriddedSurface.from_dem(dem, p.dem_smoothing), dem
    return InclinedPlane(p.zeta), None


class SavageHutterTerrain(TwoEarthPressures, TwoDimensionalRows, DepthAveragedModel):
    """Savage–Hutter granular avalanche on a terrain surface in SI units, ``q = (H, H u, H
    v)`` over the map coordinates: ``H`` the volume per map area (slope-normal thickness over
    the cosine of the slope), ``(u, v)`` the map components of the velocity."""

    name = "savage-hutter-terrain"
    description = (
        "Savage–Hutter avalanche on terrain z = b(x, y) in SI units (H, Hu, Hv over map "
        "coordinates): earth pressure, Coulomb friction in the surface, curvature"
    )
    long_names: ClassVar[Mapping[str, str]] = {
        "x": "easting or map x (m)",
        "y": "northing or map y (m)",
        "t": "time (s)",
        "h": "volume per map area H = slope-normal thickness / cos(slope) (m)",
        "hu": "H times the map x velocity (m^2/s)",
        "hv": "H times the map y velocity (m^2/s)",
        "u": "map x velocity (m/s)",
        "v": "map y velocity (m/s)",
    }
    aux_names = (
        "b_x", "b_y", "cos_theta", "c2_P_xx", "c2_P_xy", "c2_P_yy",
        "c3_T_xx", "c3_T_xy", "c3_T_yx", "c3_T_yy", "b_xx", "b_xy", "b_yy", "K_x", "K_y",
    )  # fmt: skip
    # Mirror images across an x wall (x -> -x) and a y wall (y -> -y).
    aux_reflect_signs = (
        -1.0, 1.0, 1.0, 1.0, -1.0, 1.0, -1.0, -1.0, 1.0, 1.0, 1.0, -1.0, 1.0, 1.0, 1.0,
    )  # fmt: skip
    aux_reflect_signs_y: ClassVar[tuple[float, ...] | None] = (
        1.0, -1.0, 1.0, 1.0, -1.0, 1.0, 1.0, 1.0, -1.0, -1.0, 1.0, -1.0, 1.0, 1.0, 1.0,
    )  # fmt: skip
    varying_aux_rows: ClassVar[tuple[int, ...]] = (KX, KY)
    empty_stays_empty: ClassVar[bool] = True
    aux_layout_2d = "field"
    tangent_slope_rows: ClassVar[tuple[int, int] | None] = (SLOPE_X, SLOPE_Y)
    has_source = True
    Parameters = SavageHutterTerrainParameters
    initial_kinds: ClassVar[dict[str, tuple[tuple[str, ...], dict[str, Any], str]]] = {
        "pile": (
            ("centre", "radii", "height"),
            {"thin_layer": 0.0},
            "a pile at rest, thickness normal to the slope h = height (1 - (x'/a)^2 - "
            "(y'/b)^2) in m over the map point centre = [x, y] with map radii = [a, b], plus "
            "thin_layer everywhere",
        ),
        "release": (
            ("thickness",),
            {"release_file": "", "polygon": [], "measured": "normal", "thin_layer": 0.0},
            "material at rest of thickness (m) in the cells whose centres lie inside a release "
            "area: release_file (GeoJSON, shapefile, GeoPackage, or a raster mask on the "
            "scene's cells) or polygon = [[x, y], ...] in map coordinates; measured = 'normal' "
            "(to the slope) or 'vertical'; square cells",
        ),
    }
    flux_point = staticmethod(flux_point)
    flux_y_point = staticmethod(flux_y_point)
    jacobian_point = staticmethod(jacobian_point)
    jacobian_y_point = staticmethod(jacobian_y_point)
    max_speed_point = staticmethod(max_speed_point)
    max_speed_y_point = staticmethod(max_speed_y_point)
    source_point = staticmethod(source_point)
    resistance_point = staticmethod(resistance_point)
    coefficients_2d_point = staticmethod(coefficients_2d_point)
    corner_coefficients_point = staticmethod(corner_coefficients_point)

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        p = self.params
        self.surface, self.dem = make_surface(p)
        self.set_earth_pressures(*active_and_passive(p.phi, p.delta, p.earth_pressure))

    def pressure_scale(self) -> float:
        """``g``, the first entry of the packed parameters."""
        return float(self.params.gravity)

    def flow_depth_and_speed(self, q: Array, aux: Array | None) -> tuple[Array, Array] | None:
        """The thickness normal to the slope ``c H`` and the speed in the surface ``|u|_G =
        (u^2 + v^2 + (b_x u + b_y v)^2)^(1/2)`` (0 in a dry cell), from the coefficients
        ``aux`` at the same cells.

        Parameters
        ----------
        q : numpy.ndarray
            ``(3, ny, nx)``.
        aux : numpy.ndarray
            ``(n_aux, ny, nx)`` (:meth:`aux_2d` at the cell centres).

        Returns
        -------
        tuple of numpy.ndarray
        """
        assert aux is not None
        depth = np.asarray(q[0], dtype=np.float64)
        wet = (depth >= self.dry_depth()) & (depth > 0.0)
        safe = np.where(wet, depth, 1.0)
        u = np.where(wet, q[1] / safe, 0.0)
        v = np.where(wet, q[2] / safe, 0.0)
        along = aux[SLOPE_X] * u + aux[SLOPE_Y] * v
        return aux[COS] * depth, np.sqrt(u * u + v * v + along * along)

    def check_boundaries_2d(self, kinds: Mapping[str, str]) -> None:
        """Periodic sides only on a plane: elsewhere the terrain does not repeat, and material
        leaving the run-out would come back at the top of the slope.

        Raises
        ------
        ConfigError
            Naming the periodic side.
        """
        periodic = [side for side, kind in kinds.items() if kind == "periodic"]
        if periodic and self.params.terrain != "plane":
            raise ConfigError(
                f"boundary.{periodic[0]}: periodic sides need a terrain that repeats (terrain = "
                f"'plane'); a '{self.params.terrain}' terrain does not"
            )

    def on_grid_2d(self, grid: Grid2D) -> SavageHutterTerrain:
        """On a grid of cells larger than the DEM's, a copy whose surface is the DEM averaged over
        the grid's cells (:meth:`GriddedSurface.from_dem`): sampled at the points of a coarser
        grid, a DEM's features smaller than a cell (a channel rim, a cliff) alias into slopes and
        curvatures that jump from cell to cell, and the curvature term, explicit in the
        velocity squared, is stable only for a curvature the grid resolves (docs/design.md,
        "Savage–Hutter on terrain"). Otherwise the model itself.

        Parameters
        ----------
        grid : Grid2D

        Returns
        -------
        SavageHutterTerrain
        """
        if self.dem is None or not coarser(grid, self.dem.cell_size):
            return self
        resolved = copy.copy(self)
        resolved.surface = GriddedSurface.from_dem(self.dem, self.params.dem_smoothing, grid)
        return resolved

    def check_domain_2d(self, grid: Grid2D) -> None:
        """The terrain must cover the domain, and the cells be square (for the release areas
        and the GeoTIFFs of the hazard maps, :meth:`scene_dem`).

        Raises
        ------
        ConfigError
            Naming ``parameters.terrain`` and what is missing, or ``n_cells``.
        """
        self.scene_dem(grid)
        problem = self.surface.covers(grid.x.x_min, grid.x.x_max, grid.y.x_min, grid.y.x_max)
        if problem is not None:
            raise ConfigError(f"parameters.terrain: {problem}")

    def aux_2d(self, x: Array, y: Array) -> Array:
        """The coefficients at the map points ``(x, y)`` (broadcast), ``(n_aux, *shape)``,
        with the active ``K_x`` and ``K_y``.

        Parameters
        ----------
        x, y : numpy.ndarray
            Map coordinates in m.

        Returns
        -------
        numpy.ndarray
        """
        _, b_x, b_y, b_xx, b_xy, b_yy = self.surface.derivatives(x, y)
        c = slope_cosine(b_x, b_y)
        c2 = c * c
        p_xx, p_xy, p_yy = projection(b_x, b_y)
        geometry = pressure_geometry(b_x, b_y, b_xx, b_xy, b_yy)
        rows = [
            b_x, b_y, c, c2 * p_xx, c2 * p_xy, c2 * p_yy,
            *(c2 * c * t for t in geometry),
            b_xx, b_xy, b_yy,
            np.full(c.shape, self.k_active), np.full(c.shape, self.k_y_active),
        ]  # fmt: skip
        return np.ascontiguousarray(np.stack(rows))

    def initial_cell_averages_2d(
        self, kind: str, options: Mapping[str, Any], grid: Grid2D
    ) -> Array:
        """``pile``: the cell averages of ``H = h / c`` of the pile (Gauss points on sub-cells,
        :func:`~conslaw.exact2d.gauss_average`) plus the thin layer, at rest."""
        if kind == "release":
            return self._release(options, grid)
        if kind != "pile":
            return super().initial_cell_averages_2d(kind, options, grid)
        (x0, y0), (a, b), height, thin = cap_options(options)
        if a < grid.dx or b < grid.dy:
            raise ConfigError(
                f"initial.radii: [{a:g}, {b:g}] is narrower than a cell (dx = {grid.dx:g}, dy = "
                f"{grid.dy:g}): refine the grid or widen the pile"
            )

        def volume_per_area(x: Array, y: Array) -> Array:
            _, b_x, b_y, *_ = self.surface.derivatives(x, y)
            xi, eta = (x - x0) / a, (y - y0) / b
            thickness = height * np.maximum(1.0 - xi * xi - eta * eta, 0.0) + thin
            return (thickness / slope_cosine(b_x, b_y))[None]

        h = gauss_average(volume_per_area, grid.x.edges, grid.y.edges)[0]
        x, y = grid.centres()
        _, b_x, b_y, *_ = self.surface.derivatives(x[None, :], y[:, None])
        piled = ((x[None, :] - x0) / a) ** 2 + ((y[:, None] - y0) / b) ** 2 < 1.0
        check_release_slopes(piled, slope_cosine(b_x, b_y), x, y)
        return np.stack([h, np.zeros_like(h), np.zeros_like(h)])

    def _release(self, options: Mapping[str, Any], grid: Grid2D) -> Array:
        """``release``: ``H = thickness / c`` (measured normal to the slope) or ``H =
        thickness`` (measured vertically: the volume per map area) in the released cells, at
        rest, plus the thin layer (normal to the slope)."""
        thickness = finite_number(options["thickness"], "initial.thickness")
        thin = finite_number(options["thin_layer"], "initial.thin_layer")
        if not thickness > 0.0:
            raise ConfigError(f"initial.thickness: must be > 0 m, got {thickness!r}")
        if thin < 0.0:
            raise ConfigError(f"initial.thin_layer: must be >= 0, got {thin!r}")
        measured = options["measured"]
        if measured not in ("normal", "vertical"):
            raise ConfigError(
                f"initial.measured: expected 'normal' or 'vertical', got {measured!r}"
            )
        mask = self.released_cells(options, grid)
        x, y = grid.centres()
        _, b_x, b_y, *_ = self.surface.derivatives(x[None, :], y[:, None])
        c = slope_cosine(b_x, b_y)
        check_release_slopes(mask, c, x, y)
        released = thickness if measured == "vertical" else thickness / c
        h = np.where(mask, released, 0.0) + thin / c
        return np.stack([h, np.zeros_like(h), np.zeros_like(h)])

    def scene_dem(self, grid: Grid2D) -> DigitalElevationModel:
        """The terrain sampled at the cell centres of ``grid`` as an elevation model, with the
        CRS of the DEM file if there is one (for release areas and hazard GeoTIFFs).

        Raises
        ------
        ConfigError
            If the cells are not square.
        """
        if not math.isclose(grid.dx, grid.dy, rel_tol=1e-9):
            raise ConfigError(
                f"n_cells: a terrain scene needs square cells for its release and maps, got "
                f"dx = {grid.dx:.15g}, dy = {grid.dy:.15g}"
            )
        x, y = grid.centres()
        elevation = self.surface.derivatives(x[None, :], y[:, None])[0]
        crs = None if self.dem is None else self.dem.crs
        return DigitalElevationModel(elevation, grid.x.x_min, grid.y.x_min, grid.dx, crs)

    def released_cells(self, options: Mapping[str, Any], grid: Grid2D) -> NDArray[np.bool_]:
        """The cells of ``grid`` released by ``release_file`` or ``polygon`` (exactly one).

        Raises
        ------
        ConfigError
            Naming ``initial.release_file`` or ``initial.polygon`` and the cause
            (:func:`conslaw.terrain.release.release_mask`).
        """
        path, corners = options["release_file"], options["polygon"]
        if bool(path) == bool(corners):
            raise ConfigError("initial: give exactly one of release_file and polygon")
        dem = self.scene_dem(grid)
        if path:
            if not isinstance(path, str):
                raise ConfigError(f"initial.release_file: expected a file name, got {path!r}")
            return release_mask(
                dem, path, label="initial.release_file", extent="the scene's domain"
            )
        return release_polygon_mask(dem, corners, "initial.polygon", "the scene's domain")
