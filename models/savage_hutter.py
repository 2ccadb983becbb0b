"""Savage–Hutter avalanche equations in conservative form (Tai et al. 2001, eqs. 1–8).

    h_t + m_x = 0
    m_t + (m^2/h + beta h^2/2)_x = h s_x,     beta = eps cos(zeta) K,
    s_x = sin zeta - sgn(u) tan delta (cos zeta + lambda kappa u^2)

with ``K = K_act`` where the flow extends (``du/dx > 0``) and ``K_pass`` where it contracts
(eqs. 5–6). Coulomb friction is set-valued at ``u = 0``: it can hold material at rest but never
accelerate or reverse it (docs/design.md, "Savage–Hutter specifics"). The NT kernel integrates the
driving force ``h sin zeta``
and the friction magnitude ``h tan delta (cos zeta + lambda kappa u^2)`` at the same quarter points
(eqs. 13–14) and applies the friction with the stopping rule
``m = 0 if |m*| <= dt F else m* - sgn(m*) dt F``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numba import njit
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number
from conslaw.exact import ExactSolution, Unavailable, piecewise_cell_averages
from conslaw.grid import Grid
from conslaw.model import InitialData, parameter
from conslaw_models.chute import CHUTE_KINDS, Chute, PlaneChute, make_chute
from conslaw_models.depth_averaged import DRY, DepthAveragedModel, velocity
from conslaw_models.savage_hutter_exact import InclinedDamBreak, SimilaritySolution
from conslaw_models.shallow_water_exact import DamBreak

Array = NDArray[np.float64]

# Packed parameters (see SavageHutter.param_vector); DRY = 1 is shared with shallow water.
EPSILON, K_ACTIVE, K_PASSIVE, TAN_DELTA = 0, 2, 3, 4
# Rows of the coefficients: sin zeta, cos zeta, lambda kappa, and the earth-pressure coefficient K
# (set per cell by coefficients_point; K_active in the static coefficients).
SIN, COS, CURVATURE, K = 0, 1, 2, 3


def earth_pressure_coefficients(phi: float, delta: float) -> tuple[float, float]:
    """``(K_act, K_pass) = 2 sec^2 phi (1 -+ sqrt(1 - cos^2 phi sec^2 delta)) - 1`` (eq. 6).

    Angles in radians, ``0 <= delta <= phi < pi/2``. For ``delta = phi`` both equal
    ``2 sec^2 phi - 1``.

    Evaluated without cancellation (docs/design.md, "Earth pressure"): with
    ``w = sqrt(sin(phi + delta) sin(phi - delta))`` (``= cos(delta) sqrt(1 - cos^2 phi
    sec^2 delta)``, since ``cos^2 delta - cos^2 phi = sin(phi + delta) sin(phi - delta)``),

    ``K_act = (4 sin^2 delta + cos^2 delta cos^2 phi) / ((1 + sin^2 delta + w cos delta)
    cos delta (cos delta + w))`` and ``K_pass = 2 (cos delta + w) / (cos delta cos^2 phi) - 1``.

    The textbook form subtracts nearly equal numbers as ``phi -> 90`` (``K_act`` came out
    0.46 instead of ``tan^2 delta``, 0 for ``delta = 0``, at ``phi = 90 - 1e-6`` degrees) and
    as ``phi -> delta``.
    """
    if delta > phi:
        raise ValueError(f"delta ({delta}) must not exceed phi ({phi}): K_act/pass are not real")
    if phi == delta:
        # One coefficient; the same floating-point expression as always for this case.
        k = 2.0 / math.cos(phi) ** 2 - 1.0
        return k, k
    cos_delta, sin_delta = math.cos(delta), math.sin(delta)
    cos_phi, sin_phi = math.cos(phi), math.sin(phi)
    cos_phi2 = cos_phi**2
    # sin(phi + delta) by its sum formula (all terms >= 0): accurate also for phi + delta near pi.
    sin_sum = sin_phi * cos_delta + cos_phi * sin_delta
    w = math.sqrt(max(0.0, sin_sum * math.sin(phi - delta)))
    k_active = (4.0 * sin_delta**2 + cos_delta**2 * cos_phi2) / (
        (1.0 + sin_delta**2 + w * cos_delta) * cos_delta * (cos_delta + w)
    )
    k_passive = 2.0 * (cos_delta + w) / (cos_delta * cos_phi2) - 1.0
    return k_active, k_passive


@njit(cache=True)
def flux_point(q, aux, params, out):
    """``f = (m, m u + beta h^2 / 2)``, ``beta = eps cos zeta K`` (eq. 8)."""
    h = q[0]
    u = velocity(h, q[1], params[DRY])
    beta = params[EPSILON] * aux[COS] * aux[K]
    out[0] = q[1]
    out[1] = q[1] * u + 0.5 * beta * h * h


@njit(cache=True)
def jacobian_point(q, aux, params, out):
    """``A = [[0, 1], [beta h - u^2, 2 u]]``."""
    u = velocity(q[0], q[1], params[DRY])
    out[0, 0] = 0.0
    out[0, 1] = 1.0
    out[1, 0] = params[EPSILON] * aux[COS] * aux[K] * q[0] - u * u
    out[1, 1] = 2.0 * u


@njit(cache=True)
def max_speed_point(q, aux, params):
    """``|u| + sqrt(beta_max h)`` with the larger of K_act, K_pass (eq. 18, on the safe side)."""
    u = velocity(q[0], q[1], params[DRY])
    k_max = max(params[K_ACTIVE], params[K_PASSIVE], aux[K])
    return abs(u) + math.sqrt(max(params[EPSILON] * aux[COS] * k_max * q[0], 0.0))


@njit(cache=True)
def source_point(q, aux, params, out):
    """Driving part of the source, ``(0, h sin zeta)``."""
    out[0] = 0.0
    out[1] = q[0] * aux[SIN]


@njit(cache=True)
def resistance_point(q, aux, params):
    """Coulomb friction magnitude ``h tan delta (cos zeta + lambda kappa u^2)`` (eq. 3), and 0
    where the normal pressure vanishes (``cos zeta + lambda kappa u^2 < 0``)."""
    h = max(q[0], 0.0)
    u = velocity(q[0], q[1], params[DRY])
    normal = aux[COS] + aux[CURVATURE] * u * u
    return params[TAN_DELTA] * h * normal if normal > 0.0 else 0.0


@njit(cache=True)
def earth_pressure(stretching, params):
    """The earth-pressure coefficient for a velocity change ``stretching`` along the flow across
    a cell (eq. 5; docs/design.md, "Earth pressure"): ``K_pass`` where the material contracts
    (``< 0``), ``K_act`` where it extends and where it does neither (``= 0``: uniform flow,
    next to a dry cell). Material that ends a step at rest takes any value between the two
    instead (:func:`rest_coefficients_point`)."""
    return params[K_PASSIVE] if stretching < 0.0 else params[K_ACTIVE]


#: A velocity change within this many units of round-off of the values it is taken from
#: counts as none: the material neither extends nor contracts, and takes the active coefficient
#: (:func:`earth_pressure`) rather than the one the sign of its rounding error would pick
#: (docs/design.md, "Earth pressure").
SWITCH_ROUND_OFF = 16.0 * 2.220446049250313e-16


@njit(cache=True)
def beyond_round_off(change, scale):
    """``change``, or 0 where ``|change| <= SWITCH_ROUND_OFF |scale|`` (``scale`` the size of
    the values ``change`` is the difference of)."""
    return change if abs(change) > SWITCH_ROUND_OFF * abs(scale) else 0.0


@njit(cache=True)
def velocity_change(low, high, row, dry):
    """``high[row]/high[0] - low[row]/low[0]``, the velocity change from state ``low`` to state
    ``high``: 0 if either is dry (the pressure ``~ h^2`` vanishes there) or if it is round-off of
    the two velocities (:func:`beyond_round_off`)."""
    if low[0] >= dry and low[0] > 0.0 and high[0] >= dry and high[0] > 0.0:
        low_velocity = low[row] / low[0]
        high_velocity = high[row] / high[0]
        return beyond_round_off(
            high_velocity - low_velocity, abs(low_velocity) + abs(high_velocity)
        )
    return 0.0


@njit(cache=True)
def coefficients_point(q, slope, aux, params):
    """Earth-pressure coefficient of a cell for its predictor, by :func:`earth_pressure` from
    the velocity change across the cell, the reconstructed ``u' = (m' - u h') / h`` (0 in a dry
    cell)."""
    h = q[0]
    stretching = 0.0
    if h >= params[DRY] and h > 0.0:
        stretching = beyond_round_off(slope[1] - (q[1] / h) * slope[0], q[1])
    aux[K] = earth_pressure(stretching, params)


@njit(cache=True)
def interface_coefficients_point(left, right, aux_left, aux_right, params):
    """One earth-pressure coefficient for both fluxes of a staggered cell, by
    :func:`earth_pressure` from the velocity change ``u_right - u_left`` across it (0 if a side
    is dry, where the pressure ``~ h^2`` vanishes). The pressure flux difference in the cell,
    ``eps K (cos zeta_R h_R^2 - cos zeta_L h_L^2) / 2`` with one ``K``, then approximates
    ``beta h dh/dx`` of the momentum equation (paper eq. 4), and the conservative
    ``d(beta h^2/2)/dx`` wherever ``K`` is uniform (shocks), without the spurious force
    ``(h^2/2) dK/dx`` that a ``K`` chosen per cell exerts where it switches between neighbours
    (docs/design.md, "Earth pressure")."""
    k = earth_pressure(velocity_change(left, right, 1, params[DRY]), params)
    aux_left[K] = k
    aux_right[K] = k


@njit(cache=True)
def rest_coefficients_point(low, high, params):
    """Material at rest is not yielding: its earth-pressure coefficient may be anything between
    ``K_act`` (``low``) and ``K_pass`` (``high``) (Mohr–Coulomb: the stress lies inside the
    yield surface), as the basal friction of a mass at rest may be anything up to the Coulomb
    limit (docs/design.md, "Earth pressure")."""
    low[K] = params[K_ACTIVE]
    high[K] = params[K_PASSIVE]


EARTH_PRESSURE = ("savage-hutter", "isotropic")


@dataclass(frozen=True)
class SavageHutterParameters:
    """Parameters (angles in degrees). ``chute`` selects the geometry (see :mod:`chute`)."""

    epsilon: float = parameter(
        1.0, "aspect ratio $\\varepsilon = H/L$ of the depth and length scales; > 0"
    )
    phi: float = parameter(
        30.0,
        "internal friction angle $\\phi$ in degrees, $\\delta \\le \\phi < 90$; with $\\phi > "
        "\\delta$ the earth pressure switches between $K_{act}$ and $K_{pass}$ "
        "([equations](equations.md))",
    )
    delta: float = parameter(
        30.0, "bed friction angle $\\delta$ in degrees, $0 \\le \\delta \\le \\phi$"
    )
    earth_pressure: str = parameter(
        "savage-hutter",
        "`savage-hutter`: $K_{act}$ where the flow stretches ($u_x \\ge 0$), $K_{pass}$ where it "
        "is compressed; `isotropic`: $K = 1$",
    )
    chute: str = parameter(
        "plane",
        "the bed: `plane` (inclination `zeta`), `paper` (Tai et al. 2001 Fig. 3: `zeta`, then "
        "turning linearly to `zeta_end` between `transition_start` and `transition_end`), "
        "`table` (`chute_file`)",
    )
    zeta: float = parameter(
        40.0,
        "inclination $\\zeta$ of a `plane` chute, or of the top of a `paper` one, in degrees, "
        "in (-90, 90); positive where the bed descends in +x",
    )
    transition_start: float = parameter(
        21.5, "`paper` chute: arc length $x$ where the inclination starts to fall"
    )
    transition_end: float = parameter(
        25.5, "`paper` chute: arc length $x$ where it reaches `zeta_end`; > `transition_start`"
    )
    zeta_end: float = parameter(
        0.0, "`paper` chute: inclination of the run-out in degrees, in (-90, 90)"
    )
    chute_file: str = parameter(
        "",
        "`table` chute: a CSV with the header `x,zeta` (arc length, degrees) or `x,z` (a "
        "terrain profile, smoothed by a spline); relative to the scene file",
    )
    chute_extend: bool = parameter(
        False,
        "`table` chute: let the domain reach past the table, the chute continuing as planes at "
        "the angles of its ends (else such a domain is refused)",
    )
    dry_tolerance: float = parameter(
        1e-10, "depth below which a cell counts as dry (velocity 0), in [0, 1e-3)"
    )

    def __post_init__(self) -> None:
        for name in ("epsilon", "phi", "delta", "dry_tolerance"):
            finite_number(getattr(self, name), f"parameters.{name}")
        if not self.epsilon > 0:
            raise ConfigError(f"parameters.epsilon: must be > 0, got {self.epsilon}")
        check_friction(self.phi, self.delta, self.earth_pressure)
        if self.chute not in CHUTE_KINDS:
            raise ConfigError(
                f"parameters.chute: unknown '{self.chute}'; allowed: {', '.join(CHUTE_KINDS)}"
            )
        if not isinstance(self.chute_file, str):
            raise ConfigError(
                f"parameters.chute_file: expected a file name, got {self.chute_file!r}"
            )
        if not isinstance(self.chute_extend, bool):
            raise ConfigError(
                f"parameters.chute_extend: expected true or false, got {self.chute_extend!r}"
            )
        if not 0 <= self.dry_tolerance < 1e-3:
            raise ConfigError(
                f"parameters.dry_tolerance: must be in [0, 1e-3), got {self.dry_tolerance}"
            )


def check_friction(phi: float, delta: float, earth_pressure: str) -> None:
    """The friction angles and the earth-pressure rule of every Savage–Hutter model: ``0 <=
    delta <= phi < 90`` degrees (``K_act`` and ``K_pass`` of eq. 6 are real only then), and a
    rule of :data:`EARTH_PRESSURE`.

    Parameters
    ----------
    phi, delta : float
        Finite angles in degrees.
    earth_pressure : str

    Raises
    ------
    ConfigError
        Naming ``parameters.phi``, ``parameters.delta`` or ``parameters.earth_pressure``.
    """
    if not 0 <= phi < 90:
        raise ConfigError(f"parameters.phi: must be in [0, 90) degrees, got {phi}")
    if not 0 <= delta < 90:
        raise ConfigError(f"parameters.delta: must be in [0, 90) degrees, got {delta}")
    if delta > phi:
        raise ConfigError(
            f"parameters.delta: bed friction angle delta={delta} must be <= internal "
            f"friction angle phi={phi} (K_act/pass are not real otherwise)"
        )
    if earth_pressure not in EARTH_PRESSURE:
        raise ConfigError(
            f"parameters.earth_pressure: unknown '{earth_pressure}'; allowed: "
            f"{', '.join(EARTH_PRESSURE)}"
        )


def active_and_passive(phi: float, delta: float, earth_pressure: str) -> tuple[float, float]:
    """``(K_act, K_pass)`` of eq. 6 for angles in degrees (:func:`earth_pressure_coefficients`),
    both 1 for ``earth_pressure = "isotropic"``.

    Parameters
    ----------
    phi, delta : float
    earth_pressure : str

    Returns
    -------
    tuple of float
    """
    if earth_pressure == "isotropic":
        return 1.0, 1.0
    return earth_pressure_coefficients(math.radians(phi), math.radians(delta))


def chute_and_pressures(p: SavageHutterParameters) -> tuple[Chute, float, float]:
    """The chute of the parameters ``p`` and ``(K_act, K_pass)`` (Tai et al. 2001, eq. 6;
    both 1 for ``earth_pressure = "isotropic"``), shared by the 1D and the 2D model.

    Parameters
    ----------
    p : SavageHutterParameters

    Returns
    -------
    chute : Chute
    k_active, k_passive : float
        ``2 (1 -+ sqrt(1 - cos^2 phi / cos^2 delta)) / cos^2 phi - 1``.
    """
    chute = make_chute(
        p.chute, p.zeta, p.transition_start, p.transition_end, p.zeta_end, p.chute_file
    )
    return chute, *active_and_passive(p.phi, p.delta, p.earth_pressure)


def check_chute_covers(chute: Chute, p: SavageHutterParameters, x_min: float, x_max: float) -> None:
    """A chute table must cover the domain ``[x_min, x_max]``, unless ``chute_extend`` says to
    continue it as planes at the angles of its ends (a domain in other coordinates than the
    table's would otherwise run down an endless plane unnoticed).

    Parameters
    ----------
    chute : Chute
    p : SavageHutterParameters
        Its ``chute_extend``.
    x_min, x_max : float
        The domain along x.

    Raises
    ------
    ConfigError
        Naming ``parameters.chute_file``, the uncovered part and the ways out.
    """
    problem = chute.uncovered(x_min, x_max)
    if problem is not None and not p.chute_extend:
        raise ConfigError(
            f"parameters.chute_file: {problem}; move x_min/x_max inside the table, extend "
            "the table, or set parameters.chute_extend = true to continue the chute as "
            "planes at the angles of its ends"
        )


class SavageHutter(DepthAveragedModel):
    """Savage–Hutter granular avalanche, ``q = (h, m = h u)``, on a curved chute.

    The earth-pressure coefficient is decided per cell, every step, from the sign of the
    velocity slope ``u' = (m' - u h')/h`` computed from the reconstructed slopes of the conserved
    variables (:func:`coefficients_point`): active if ``u' >= 0``, passive if ``u' < 0``. With
    ``earth_pressure = "isotropic"``, ``K = 1`` everywhere.
    """

    name = "savage-hutter"
    description = "Savage–Hutter avalanche (h, hu): earth pressure, Coulomb friction, curved chute"
    # The scaled equations (docs/equations.md): lengths along the bed by L, depths by H,
    # velocities by (g L)^(1/2), time by (L/g)^(1/2).
    dimensionless = True
    long_names: ClassVar[Mapping[str, str]] = {
        "x": "arc length along the bed / L (dimensionless)",
        "t": "time / (L/g)^(1/2) (dimensionless)",
        "h": "depth normal to the bed / H (dimensionless)",
        "hu": "depth times depth-averaged velocity / (H (g L)^(1/2)) (dimensionless)",
        "u": "depth-averaged velocity / (g L)^(1/2) (dimensionless)",
    }
    aux_names = ("sin_zeta", "cos_zeta", "lambda_kappa", "K")
    aux_reflect_signs = (-1.0, 1.0, 1.0, 1.0)
    has_source = True
    Parameters = SavageHutterParameters
    initial_kinds: ClassVar[dict[str, tuple[tuple[str, ...], dict[str, Any], str]]] = {
        "parabolic-cap": (
            ("centre", "radius", "height"),
            {"thin_layer": 0.0},
            "h = height (1 - ((x - centre)/radius)^2) inside, plus thin_layer everywhere, at rest",
        ),
    }
    flux_point = staticmethod(flux_point)
    jacobian_point = staticmethod(jacobian_point)
    max_speed_point = staticmethod(max_speed_point)
    source_point = staticmethod(source_point)
    resistance_point = staticmethod(resistance_point)
    coefficients_point = staticmethod(coefficients_point)
    interface_coefficients_point = staticmethod(interface_coefficients_point)
    rest_coefficients_point = staticmethod(rest_coefficients_point)

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        self.chute, self.k_active, self.k_passive = chute_and_pressures(self.params)

    def check_domain(self, x_min: float, x_max: float) -> None:
        """A chute table must cover the domain (:func:`check_chute_covers`)."""
        check_chute_covers(self.chute, self.params, x_min, x_max)

    def param_vector(self) -> Array:
        """``(eps, dry_tolerance, K_act, K_pass, tan delta)`` (indices EPSILON, DRY, ...)."""
        p = self.params
        values = [0.0] * 5
        values[EPSILON] = p.epsilon
        values[DRY] = p.dry_tolerance
        values[K_ACTIVE] = self.k_active
        values[K_PASSIVE] = self.k_passive
        values[TAN_DELTA] = math.tan(math.radians(p.delta))
        return np.array(values)

    def figures(self) -> dict[str, Callable[..., Any]]:
        """``chute.png``: the chute in elevation with the flowing mass on it."""
        from conslaw_models.chute_figure import chute_figure

        return {"chute.png": chute_figure}

    def kernel_variant(self) -> str:
        """phi = delta (one earth-pressure coefficient) or phi > delta (the active/passive
        switch), and whether there is bed friction."""
        switch = "phi > delta" if self.k_active != self.k_passive else "phi = delta"
        return switch if self.params.delta > 0.0 else f"{switch}, no bed friction"

    def capabilities(self) -> dict[str, bool]:
        """Driving source and friction always; the K switch only if K_act != K_pass."""
        return {
            "source": True,
            "balanced_source": False,
            "surface": False,
            "correction": True,
            "resistance": self.params.delta > 0.0,
            "dynamic_coefficients": self.k_active != self.k_passive,
            "interface_coefficients": self.k_active != self.k_passive,
            "rest_coefficients": self.k_active != self.k_passive,
        }

    def uniform_aux(self) -> bool:
        """On a plane chute the coefficients are the same everywhere."""
        return isinstance(self.chute, PlaneChute)

    def aux(self, x: Array, dx: float) -> Array:
        """``sin zeta``, ``cos zeta``, ``lambda kappa`` at x, and ``K = K_act``."""
        x = np.asarray(x, dtype=np.float64)
        angle = self.chute.zeta(x)
        return np.ascontiguousarray(
            np.vstack(
                [
                    np.sin(angle),
                    np.cos(angle),
                    self.chute.curvature(x),
                    np.full(x.shape, self.k_active),
                ]
            )
        )

    def coefficient_fields(self, x: Array, coefficients: Array) -> dict[str, Array]:
        """``zeta`` (the local inclination in degrees), ``lambda_kappa`` (curvature term of
        eq. 3), ``K`` (earth-pressure coefficient chosen by eq. 5) and
        ``beta = eps cos zeta K`` (eq. 2)."""
        return {
            "zeta": np.degrees(self.chute.zeta(np.asarray(x, dtype=np.float64))),
            "lambda_kappa": np.asarray(coefficients[CURVATURE]),
            "K": np.asarray(coefficients[K]),
            "beta": self.params.epsilon * coefficients[COS] * coefficients[K],
        }

    def initial_cell_averages(self, kind: str, options: Mapping[str, Any], grid: Grid) -> Array:
        """``parabolic-cap``: exact cell averages of the cap plus the thin layer, at rest."""
        values = {}
        for key in ("centre", "radius", "height", "thin_layer"):
            values[key] = finite_number(options[key], f"initial.{key}")
        if values["radius"] <= 0 or values["height"] < 0 or values["thin_layer"] < 0:
            raise ConfigError("initial: need radius > 0, height >= 0 and thin_layer >= 0")
        cap = cap_profile(values["centre"], values["radius"], values["height"])
        h = piecewise_cell_averages(grid.edges, *cap)[0]
        # The cap is symmetric about its centre: so are its averages, bit for bit.
        h = grid.mirror_symmetric(h, values["centre"]) + values["thin_layer"]
        return np.ascontiguousarray(np.vstack([h, np.zeros_like(h)]))

    def exact_solution(
        self, initial: InitialData, grid: Grid, context: Mapping[str, Any]
    ) -> ExactSolution | None:
        """The parabolic similarity solution for a cap released at rest on a plane chute, and
        the dam break down a plane onto a dry bed (:meth:`dam_break_solution`).

        The similarity solution is unavailable when its parameters are invalid (the rear margin
        would move upslope), when the thin layer is thicker than 1e-3 of the cap height (the
        comparison is then not with the same problem; at 1e-4, as in the paper, it floors the
        error at about 1e-4), or when a margin leaves the domain before ``t_end``.
        """
        if initial.kind == "piecewise-constant":
            return self.dam_break_solution(initial, grid, context)
        if initial.kind != "parabolic-cap":
            return None
        if not isinstance(self.chute, PlaneChute):
            raise Unavailable("the similarity solution needs a plane chute (chute = 'plane')")
        p = self.params
        options = initial.options
        height, radius = float(options["height"]), float(options["radius"])
        if float(options["thin_layer"]) > 1e-3 * height:
            raise Unavailable("the thin layer is thicker than 1e-3 of the cap height")
        zeta = self.chute.angle
        slope = math.sin(zeta) - math.tan(math.radians(p.delta)) * math.cos(zeta)
        beta = p.epsilon * math.cos(zeta) * self.k_active
        try:
            solution = SimilaritySolution.create(
                slope, beta, height, radius, float(options["centre"])
            )
        except ConfigError as why:
            raise Unavailable(str(why)) from None
        rear, front = solution.margins(float(context["t_end"]))
        if rear < grid.x_min or front > grid.x_max:
            raise Unavailable(f"a margin leaves the domain before t={context['t_end']:g}")
        return solution

    def dam_break_solution(
        self, initial: InitialData, grid: Grid, context: Mapping[str, Any]
    ) -> ExactSolution | None:
        """:class:`~conslaw_models.savage_hutter_exact.InclinedDamBreak` for one jump between a
        reservoir at rest (left, upslope) and a dry bed, on a plane chute on which the material
        slides (``tan delta <= tan zeta``), with outflow boundaries that no wave reaches by
        ``t_end``; None for other piecewise-constant data that are not a dam break."""
        if not isinstance(self.chute, PlaneChute):
            raise Unavailable("the dam-break solution needs a plane chute (chute = 'plane')")
        zeta = self.chute.angle
        beta = self.params.epsilon * math.cos(zeta) * self.k_active
        dam = DamBreak.from_initial(initial, beta)
        if dam is None:
            return None
        if dam.h_right != 0.0:
            raise Unavailable(
                "the dam-break solution needs the material upslope (left) of a dry bed"
            )
        slope = math.sin(zeta) - math.tan(math.radians(self.params.delta)) * math.cos(zeta)
        if slope < 0.0:
            raise Unavailable(
                "the dam-break solution needs the material to slide (delta <= zeta); "
                f"here tan(delta) > tan(zeta), s = {slope:.4g}"
            )
        if (context["left"], context["right"]) != ("outflow", "outflow"):
            raise Unavailable("the exact dam-break solution assumes outflow boundaries")
        solution = InclinedDamBreak(dam, slope)
        low, high = solution.wave_extent(float(context["t_end"]))
        if low < grid.x_min or high > grid.x_max:
            raise Unavailable(f"a wave reaches the boundary before t={context['t_end']:g}")
        return solution


def cap_profile(centre: float, radius: float, height: float) -> tuple[Array, list[Any]]:
    """Breakpoints and pieces of ``h = height (1 - ((x-c)/r)^2)`` inside ``|x-c| <= r``, else 0."""

    def zero(x: Array) -> Array:
        return np.zeros((1, x.size))

    def parabola(x: Array) -> Array:
        return (height * (1.0 - ((x - centre) / radius) ** 2))[None, :]

    return np.array([centre - radius, centre + radius]), [zero, parabola, zero]
