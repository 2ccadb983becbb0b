"""Savage–Hutter avalanche equations in two dimensions on a chute (Savage & Hutter 1991, Acta
Mech. 86, 201–223; Gray, Wieland & Hutter 1999, Proc. R. Soc. Lond. A 455, 1841–1874), in
conservative form as the 1D model of Tai et al. (2001)::

    h_t + (h u)_x + (h v)_y = 0
    (h u)_t + (h u^2 + beta_x h^2 / 2)_x + (h u v)_y = h (sin zeta - F u/|(u, v)|)
    (h v)_t + (h u v)_x + (h v^2 + beta_y h^2 / 2)_y = -h F v/|(u, v)|

with x the arc length down the chute (inclination ``zeta(x)``, curvature ``kappa``), y across
it, ``beta_x = eps cos zeta K_x``, ``beta_y = eps cos zeta K_y`` and the Coulomb friction
``F = tan delta (cos zeta + lambda kappa u^2)`` along the velocity ``(u, v)``, which can stop
the material but never reverses it (docs/design.md, "Savage–Hutter in two dimensions").

The earth-pressure coefficients (Hutter et al. 1993; Gray, Wieland & Hutter 1999): ``K_x =
K_act`` or ``K_pass`` of the 1D model by the sign of ``du/dx`` (active where it is >= 0), and

    K_y = (K_x + 1 -+ sqrt((K_x - 1)^2 + 4 tan^2 delta)) / 2

active (minus) where ``dv/dy >= 0``, passive where the material is compressed across the
chute. As in 1D the predictor takes them from the reconstructed slopes of each cell, and the
fluxes of a staggered cell take one pair for the cell, from the velocity changes across it
(:func:`corner_coefficients_point`). With ``earth_pressure = "isotropic"`` both are 1.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np
from numba import njit
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number
from conslaw.exact import Unavailable
from conslaw.exact2d import ExactSolution2D
from conslaw.grid2d import Grid2D
from conslaw.model import InitialData
from conslaw_models.chute import PlaneChute
from conslaw_models.depth_averaged import (
    DRY,
    DepthAveragedModel,
    TwoDimensionalRows,
    momentum_jacobian_x,
    momentum_jacobian_y,
    velocity,
)
from conslaw_models.savage_hutter import (
    SavageHutterParameters,
    beyond_round_off,
    check_chute_covers,
    chute_and_pressures,
    earth_pressure,
    velocity_change,
)
from conslaw_models.savage_hutter_2d_exact import EllipticCap

Array = NDArray[np.float64]

# Packed parameters; DRY = 1 is shared with the other depth-averaged models.
EPSILON, K_ACTIVE, K_PASSIVE, TAN_DELTA, K_Y_MAX = 0, 2, 3, 4, 5
# Rows of the coefficients: sin zeta, cos zeta, lambda kappa, and the earth-pressure
# coefficients K_x and K_y (set per cell and per staggered cell; active in the static ones).
SIN, COS, CURVATURE, KX, KY = 0, 1, 2, 3, 4


@njit(cache=True)
def lateral_coefficient(k_x, stretching, tan_delta):
    """``K_y`` for ``K_x`` (Gray, Wieland & Hutter 1999; Hutter et al. 1993): ``(K_x + 1 -
    sqrt((K_x - 1)^2 + 4 tan^2 delta)) / 2`` where the material spreads across the chute or
    does neither (``stretching >= 0``), with ``+`` where it is compressed."""
    root = math.sqrt((k_x - 1.0) ** 2 + 4.0 * tan_delta * tan_delta)
    if stretching < 0.0:
        return 0.5 * (k_x + 1.0 + root)
    return 0.5 * (k_x + 1.0 - root)


@njit(cache=True)
def flux_point(q, aux, params, out):
    """``f = (h u, h u^2 + beta_x h^2 / 2, h u v)``."""
    h = q[0]
    u = velocity(h, q[1], params[DRY])
    out[0] = q[1]
    out[1] = q[1] * u + 0.5 * params[EPSILON] * aux[COS] * aux[KX] * h * h
    out[2] = q[2] * u


@njit(cache=True)
def flux_y_point(q, aux, params, out):
    """``g = (h v, h u v, h v^2 + beta_y h^2 / 2)``."""
    h = q[0]
    v = velocity(h, q[2], params[DRY])
    out[0] = q[2]
    out[1] = q[1] * v
    out[2] = q[2] * v + 0.5 * params[EPSILON] * aux[COS] * aux[KY] * h * h


@njit(cache=True)
def jacobian_point(q, aux, params, out):
    """``A = [[0, 1, 0], [beta_x h - u^2, 2 u, 0], [-u v, v, u]]``."""
    u = velocity(q[0], q[1], params[DRY])
    v = velocity(q[0], q[2], params[DRY])
    momentum_jacobian_x(u, v, params[EPSILON] * aux[COS] * aux[KX] * q[0], out)


@njit(cache=True)
def jacobian_y_point(q, aux, params, out):
    """``B = [[0, 0, 1], [-u v, v, u], [beta_y h - v^2, 0, 2 v]]``."""
    u = velocity(q[0], q[1], params[DRY])
    v = velocity(q[0], q[2], params[DRY])
    momentum_jacobian_y(u, v, params[EPSILON] * aux[COS] * aux[KY] * q[0], out)


@njit(cache=True)
def max_speed_point(q, aux, params):
    """``|u| + sqrt(beta_x h)`` with the larger of ``K_act``, ``K_pass`` (on the safe side, as
    in 1D)."""
    u = velocity(q[0], q[1], params[DRY])
    k_max = max(params[K_ACTIVE], params[K_PASSIVE], aux[KX])
    return abs(u) + math.sqrt(max(params[EPSILON] * aux[COS] * k_max * q[0], 0.0))


@njit(cache=True)
def max_speed_y_point(q, aux, params):
    """``|v| + sqrt(beta_y h)`` with the largest ``K_y`` (the passive one of ``K_pass``)."""
    v = velocity(q[0], q[2], params[DRY])
    k_max = max(params[K_Y_MAX], aux[KY])
    return abs(v) + math.sqrt(max(params[EPSILON] * aux[COS] * k_max * q[0], 0.0))


@njit(cache=True)
def source_point(q, aux, params, out):
    """Driving part of the source, ``(0, h sin zeta, 0)``."""
    out[0] = 0.0
    out[1] = q[0] * aux[SIN]
    out[2] = 0.0


@njit(cache=True)
def resistance_point(q, aux, params):
    """Coulomb friction magnitude ``h tan delta (cos zeta + lambda kappa u^2)`` (the
    curvature of the chute along x presses with the downslope velocity ``u``), 0 where the
    normal pressure vanishes; the scheme applies it against the momentum ``(h u, h v)``."""
    h = max(q[0], 0.0)
    u = velocity(q[0], q[1], params[DRY])
    normal = aux[COS] + aux[CURVATURE] * u * u
    return params[TAN_DELTA] * h * normal if normal > 0.0 else 0.0


@njit(cache=True)
def coefficients_2d_point(q, slope_x, slope_y, aux, params):
    """``K_x`` and ``K_y`` of a cell for its predictor, from the velocity changes across it,
    ``u' = (m' - u h') / h`` along x and ``v* = (n* - v h*) / h`` along y from the
    reconstructed slopes (0 in a dry cell)."""
    h = q[0]
    along_x = 0.0
    along_y = 0.0
    if h >= params[DRY] and h > 0.0:
        along_x = beyond_round_off(slope_x[1] - (q[1] / h) * slope_x[0], q[1])
        along_y = beyond_round_off(slope_y[2] - (q[2] / h) * slope_y[0], q[2])
    k_x = earth_pressure(along_x, params)
    aux[KX] = k_x
    aux[KY] = lateral_coefficient(k_x, along_y, params[TAN_DELTA])


@njit(cache=True)
def corner_coefficients_point(a, b, c, d, aux, params):
    """One ``K_x`` and ``K_y`` for every flux of a staggered cell, from the mid-step states of
    its corner cells ``a`` (lower left), ``b`` (lower right), ``c`` (upper left), ``d`` (upper
    right): the signs of ``(u_b - u_a) + (u_d - u_c)`` and ``(v_c - v_a) + (v_d - v_b)``
    (a pair with a dry side counts 0). The 1D rule of
    :func:`conslaw_models.savage_hutter.interface_coefficients_point` along each direction."""
    dry = params[DRY]
    along_x = velocity_change(a, b, 1, dry) + velocity_change(c, d, 1, dry)
    along_y = velocity_change(a, c, 2, dry) + velocity_change(b, d, 2, dry)
    k_x = earth_pressure(along_x, params)
    aux[KX] = k_x
    aux[KY] = lateral_coefficient(k_x, along_y, params[TAN_DELTA])


def cap_options(
    options: Mapping[str, Any],
) -> tuple[tuple[float, float], tuple[float, float], float, float]:
    """``(centre, radii, height, thin_layer)`` of an elliptic cap's initial options, checked:
    two finite numbers each for ``centre`` and ``radii`` (radii > 0), ``height`` and
    ``thin_layer`` finite and >= 0 (the ``cap`` of this model, the ``pile`` of the terrain
    model).

    Parameters
    ----------
    options : mapping

    Returns
    -------
    tuple

    Raises
    ------
    ConfigError
        Naming the option.
    """
    pairs = []
    for key in ("centre", "radii"):
        pair = options[key]
        if not isinstance(pair, list) or len(pair) != 2:
            raise ConfigError(f"initial.{key}: expected a list of two numbers, got {pair!r}")
        pairs.append(
            (finite_number(pair[0], f"initial.{key}"), finite_number(pair[1], f"initial.{key}"))
        )
    height = finite_number(options["height"], "initial.height")
    thin = finite_number(options["thin_layer"], "initial.thin_layer")
    if min(pairs[1]) <= 0:
        raise ConfigError(f"initial.radii: both must be > 0, got {options['radii']!r}")
    for key, value in (("height", height), ("thin_layer", thin)):
        if value < 0:
            raise ConfigError(f"initial.{key}: must be >= 0, got {value!r}")
    return pairs[0], pairs[1], height, thin


def check_cap_resolved(cap: EllipticCap, grid: Grid2D) -> None:
    """Refuse a cap narrower than a cell in either direction: its cell averages (Gauss points on
    sub-cells) would lose or distort its volume, silently.

    Parameters
    ----------
    cap : EllipticCap
    grid : Grid2D

    Raises
    ------
    ConfigError
        Naming ``initial.radii``, the radii and the cell widths.
    """
    if cap.a0 < grid.dx or cap.b0 < grid.dy:
        raise ConfigError(
            f"initial.radii: [{cap.a0:g}, {cap.b0:g}] is narrower than a cell (dx = "
            f"{grid.dx:g}, dy = {grid.dy:g}): refine the grid or widen the cap"
        )


class TwoEarthPressures:
    """``K_x`` and ``K_y`` of a 2D Savage–Hutter model, and what follows from them (a mixin,
    listed before :class:`~conslaw_models.depth_averaged.DepthAveragedModel`): the packed
    parameters, the kernel variant and the capabilities. The model calls
    :meth:`set_earth_pressures` and gives :meth:`pressure_scale`."""

    params: Any
    k_active: float
    k_passive: float
    k_y_active: float
    k_y_max: float

    def set_earth_pressures(self, k_active: float, k_passive: float) -> None:
        """``K_act``, ``K_pass`` and from them the active and the largest ``K_y`` (both 1 for
        ``earth_pressure = "isotropic"``; :func:`lateral_coefficient`)."""
        self.k_active, self.k_passive = k_active, k_passive
        tan_delta = math.tan(math.radians(self.params.delta))
        if self.params.earth_pressure == "isotropic":
            self.k_y_active = self.k_y_max = 1.0
        else:
            self.k_y_active = lateral_coefficient(k_active, 0.0, tan_delta)
            self.k_y_max = lateral_coefficient(k_passive, -1.0, tan_delta)

    def pressure_scale(self) -> float:
        """The first packed parameter (``epsilon`` of the chute, ``g`` of the terrain)."""
        raise NotImplementedError

    def param_vector(self) -> Array:
        """``(pressure scale, dry_tolerance, K_act, K_pass, tan delta, largest K_y)``."""
        p = self.params
        values = [0.0] * 6
        values[EPSILON] = self.pressure_scale()
        values[DRY] = p.dry_tolerance
        values[K_ACTIVE] = self.k_active
        values[K_PASSIVE] = self.k_passive
        values[TAN_DELTA] = math.tan(math.radians(p.delta))
        values[K_Y_MAX] = self.k_y_max
        return np.array(values)

    def kernel_variant(self) -> str:
        """Whether the earth-pressure coefficients switch, and whether there is bed friction."""
        switch = "earth pressure switches" if self._switches() else "one earth pressure"
        return switch if self.params.delta > 0.0 else f"{switch}, no bed friction"

    def _switches(self) -> bool:
        """Whether ``K_x`` or ``K_y`` takes more than one value."""
        return self.k_active != self.k_passive or self.k_y_active != self.k_y_max

    def capabilities(self) -> dict[str, bool]:
        """The driving source and the correction always; friction if ``delta > 0``; the
        per-cell and per-staggered-cell coefficients if an earth pressure switches; no rest
        range of the coefficients (docs/design.md, "Savage–Hutter in two dimensions")."""
        switches = self._switches()
        return {
            "source": True,
            "balanced_source": False,
            "surface": False,
            "correction": True,
            "resistance": self.params.delta > 0.0,
            "dynamic_coefficients": switches,
            "interface_coefficients": switches,
            "rest_coefficients": False,
        }


class SavageHutter2D(TwoEarthPressures, TwoDimensionalRows, DepthAveragedModel):
    """Savage–Hutter granular avalanche in 2D, ``q = (h, h u, h v)``, on a chute that curves
    along x (the parameters and chutes of the 1D model, :mod:`conslaw_models.savage_hutter`)."""

    name = "savage-hutter-2d"
    description = (
        "Savage–Hutter avalanche in 2D (h, hu, hv) on a chute: earth pressure in x and y, "
        "Coulomb friction along the velocity"
    )
    dimensionless = True
    long_names: ClassVar[Mapping[str, str]] = {
        "x": "arc length down the chute / L (dimensionless)",
        "y": "distance across the chute / L (dimensionless)",
        "t": "time / (L/g)^(1/2) (dimensionless)",
        "h": "depth normal to the bed / H (dimensionless)",
        "hu": "depth times downslope velocity / (H (g L)^(1/2)) (dimensionless)",
        "hv": "depth times cross-slope velocity / (H (g L)^(1/2)) (dimensionless)",
        "u": "downslope velocity / (g L)^(1/2) (dimensionless)",
        "v": "cross-slope velocity / (g L)^(1/2) (dimensionless)",
    }
    parameter_meanings: ClassVar[Mapping[str, str]] = {
        "phi": (
            r"internal friction angle $\phi$ in degrees, $\delta \le \phi < 90$; $K_x$ switches "
            r"between $K_{act}$ and $K_{pass}$ where $\phi > \delta$, and $K_y$ between its two "
            r"roots wherever $\delta > 0$ ([design](design.md), Savage–Hutter in two dimensions)"
        ),
        "delta": (
            r"bed friction angle $\delta$ in degrees, $0 \le \delta \le \phi$; the Coulomb "
            r"friction opposes the velocity vector $(u, v)$ and can stop it, never reverse it"
        ),
        "earth_pressure": (
            r"`savage-hutter`: $K_x = K_{act}$ where $u_x \ge 0$, else $K_{pass}$; $K_y = (K_x + "
            r"1 \mp \sqrt{(K_x - 1)^2 + 4 \tan^2\delta})/2$, the minus (active) root where $v_y "
            r"\ge 0$; `isotropic`: $K_x = K_y = 1$"
        ),
        "chute": (
            "the bed along x, the same across y: `plane` (inclination `zeta`), `paper` (Tai et "
            "al. 2001 Fig. 3: `zeta`, then turning linearly to `zeta_end` between "
            "`transition_start` and `transition_end`), `table` (`chute_file`)"
        ),
    }
    aux_names = ("sin_zeta", "cos_zeta", "lambda_kappa", "K_x", "K_y")
    aux_reflect_signs = (-1.0, 1.0, 1.0, 1.0, 1.0)
    varying_aux_rows: ClassVar[tuple[int, ...]] = (KX, KY)
    empty_stays_empty: ClassVar[bool] = True
    aux_layout_2d = "along-x"
    has_source = True
    Parameters = SavageHutterParameters
    initial_kinds: ClassVar[dict[str, tuple[tuple[str, ...], dict[str, Any], str]]] = {
        "cap": (
            ("centre", "radii", "height"),
            {"thin_layer": 0.0},
            "an elliptic paraboloid h = height (1 - (x'/a)^2 - (y'/b)^2) at rest, centre = "
            "[x, y], radii = [a, b], plus thin_layer everywhere",
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
        self.chute, k_active, k_passive = chute_and_pressures(self.params)
        self.set_earth_pressures(k_active, k_passive)

    def pressure_scale(self) -> float:
        """``epsilon``, the first entry of the packed parameters."""
        return float(self.params.epsilon)

    def check_domain(self, x_min: float, x_max: float) -> None:
        """As the 1D model: a chute table must cover the domain along x."""
        check_chute_covers(self.chute, self.params, x_min, x_max)

    def uniform_aux(self) -> bool:
        """On a plane chute the static coefficients are the same everywhere."""
        return isinstance(self.chute, PlaneChute)

    def aux(self, x: Array, dx: float) -> Array:
        """``sin zeta``, ``cos zeta``, ``lambda kappa`` at the arc lengths ``x``, and the active
        ``K_x`` and ``K_y``: the coefficients vary along x only."""
        x = np.asarray(x, dtype=np.float64)
        angle = self.chute.zeta(x)
        return np.ascontiguousarray(
            np.vstack(
                [
                    np.sin(angle),
                    np.cos(angle),
                    self.chute.curvature(x),
                    np.full(x.shape, self.k_active),
                    np.full(x.shape, self.k_y_active),
                ]
            )
        )

    def initial_cell_averages_2d(
        self, kind: str, options: Mapping[str, Any], grid: Grid2D
    ) -> Array:
        """``cap``: the cell averages of the elliptic paraboloid (Gauss points on sub-cells,
        :func:`~conslaw.exact2d.gauss_average`) plus the thin layer, at rest."""
        if kind != "cap":
            return super().initial_cell_averages_2d(kind, options, grid)
        cap = self._cap(options, 0.0)
        check_cap_resolved(cap, grid)
        h = cap.cell_averages(grid.x.edges, grid.y.edges, 0.0)[0] + float(options["thin_layer"])
        return np.stack([h, np.zeros_like(h), np.zeros_like(h)])

    def _cap(self, options: Mapping[str, Any], t_end: float) -> EllipticCap:
        """The similarity solution of the ``cap`` options (its axes integrated to ``t_end``)."""
        centre, radii, height, _ = cap_options(options)
        zeta = self.chute.angle if isinstance(self.chute, PlaneChute) else 0.0
        tan_delta = math.tan(math.radians(self.params.delta))
        slope = math.sin(zeta) - tan_delta * math.cos(zeta)
        scale = self.params.epsilon * math.cos(zeta)
        return EllipticCap(
            *centre, *radii, height,
            scale * self.k_active, scale * self.k_y_active, slope, t_end,
        )  # fmt: skip

    def exact_solution_2d(
        self, initial: InitialData, grid: Grid2D, context: Mapping[str, Any]
    ) -> ExactSolution2D | None:
        """The similarity solution of a ``cap`` on a plane chute without bed friction
        (:class:`~conslaw_models.savage_hutter_2d_exact.EllipticCap`), while its margin stays
        inside the domain; :class:`~conslaw.exact.Unavailable` with the reason otherwise."""
        if initial.kind != "cap":
            return None
        if not isinstance(self.chute, PlaneChute):
            raise Unavailable("the similarity solution needs a plane chute (chute = 'plane')")
        if self.params.delta != 0.0:
            raise Unavailable(
                "the similarity solution holds without bed friction (delta = 0): it takes the "
                "friction along x, the model along the velocity"
            )
        options = initial.options
        if float(options["thin_layer"]) > 1e-3 * float(options["height"]):
            raise Unavailable("the thin layer is thicker than 1e-3 of the cap height")
        t_end = float(context["t_end"])
        cap = self._cap(options, t_end)
        x_low, x_high, y_low, y_high = cap.extent()
        if (
            x_low < grid.x.x_min
            or x_high > grid.x.x_max
            or y_low < grid.y.x_min
            or y_high > grid.y.x_max
        ):
            raise Unavailable(f"the margin leaves the domain before t={t_end:g}")
        return cap
