"""A point sliding down a terrain profile with Coulomb friction: the limit of the Savage–Hutter
terrain model for a thin release (no earth pressure), and the energy line it refines
(docs/validation.md, "Savage–Hutter on terrain").

Along the fall line of a profile ``z = b(x)`` (the same across y), with ``theta`` the slope
angle, ``kappa = b'' cos^3(theta)`` the curvature and ``U`` the speed along the bed::

    dU/dt = g sin(theta) - tan(delta) (g cos(theta) + kappa U^2),   dx/dt = U cos(theta)

from rest until ``U`` returns to 0. The classical energy line (Heim's Fahrböschung; Lied &
Bakkehøi 1980) leaves out the ``kappa U^2`` part: ``z(x0) - z(x) = tan(delta) (x - x0)``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from conslaw_models.terrain_surface import TerrainSurface

#: Longest time step of the integration, s (the transition arcs are resolved).
MAX_STEP = 0.1
#: Longest time a point may slide, s.
MAX_TIME = 1e4
#: Farthest an energy line is followed from its release, m.
MAX_DISTANCE = 1e7


def _profile(surface: TerrainSurface, x: float) -> tuple[float, float, float]:
    """``(b, b_x, b_xx)`` of the surface at ``(x, 0)``."""
    values = surface.derivatives(np.array([x]), np.zeros(1))
    return float(values[0][0]), float(values[1][0]), float(values[3][0])


def sliding_stop(
    surface: TerrainSurface,
    x0: float,
    tan_delta: float,
    gravity: float,
    max_time: float = MAX_TIME,
) -> float:
    """Where a point released at rest at ``x0`` on a profile descending toward +x stops.

    Parameters
    ----------
    surface : TerrainSurface
        Its profile along y = 0.
    x0 : float
        The release, m.
    tan_delta : float
        The Coulomb friction coefficient.
    gravity : float
        m/s^2.
    max_time : float
        The longest slide followed, s.

    Returns
    -------
    float
        The x where the speed returns to 0 (or the release, if friction holds it there).

    Raises
    ------
    ValueError
        If the point does not stop within ``max_time``.
    """
    _, slope, _ = _profile(surface, x0)
    if -slope <= tan_delta:
        return x0

    def rates(t: float, state: np.ndarray) -> list[float]:
        _, slope, bend = _profile(surface, float(state[0]))
        c = 1.0 / math.sqrt(1.0 + slope * slope)
        normal = max(gravity * c + bend * c**3 * state[1] ** 2, 0.0)
        return [state[1] * c, -gravity * slope * c - tan_delta * normal]

    def stopped(t: float, state: np.ndarray) -> float:
        return float(state[1])

    stopped.terminal = True  # type: ignore[attr-defined]
    stopped.direction = -1  # type: ignore[attr-defined]
    solution = solve_ivp(
        rates, (0.0, max_time), [x0, 0.0], events=stopped, rtol=1e-10, atol=1e-10, max_step=MAX_STEP
    )
    if solution.status != 1:
        raise ValueError(
            f"the point released at x = {x0:g} does not stop within {max_time:g} s (a slope "
            "steeper than delta without end?)"
        )
    return float(solution.y[0, -1])


def energy_line_stop(surface: TerrainSurface, x0: float, tan_delta: float) -> float:
    """Where the energy line from ``x0`` meets the profile: the first ``x > x0`` with ``b(x0) -
    b(x) = tan(delta) (x - x0)`` (bisection between ``x0`` and a point beyond it).

    Parameters
    ----------
    surface : TerrainSurface
    x0 : float
    tan_delta : float

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If the line does not meet the profile within :data:`MAX_DISTANCE`.
    """
    z0 = _profile(surface, x0)[0]

    def above(x: float) -> float:
        return z0 - _profile(surface, x)[0] - tan_delta * (x - x0)

    step = 1.0
    low, high = x0, x0 + step
    while above(high) > 0.0:
        if high - x0 > MAX_DISTANCE:
            raise ValueError(
                f"the energy line from x = {x0:g} does not meet the profile within "
                f"{MAX_DISTANCE:g} m (a slope steeper than delta without end?)"
            )
        low, high = high, high + step
        step *= 2.0
    for _ in range(200):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if above(middle) > 0.0 else (low, middle)
    return 0.5 * (low + high)
