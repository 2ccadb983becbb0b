"""The two-dimensional similarity solution of the Savage–Hutter equations on an inclined plane:
a cap shaped as an elliptic paraboloid that keeps its shape while it spreads and slides
(Savage & Hutter 1991, Acta Mech. 86, 201–223; Hutter, Siegel, Savage & Nohguchi 1993, Acta
Mech. 100, 37–68).

With ``xi = (x - x_c(t)) / a(t)`` and ``eta = (y - y_c) / b(t)``::

    h = h_0(t) (1 - xi^2 - eta^2)_+,   h_0 a b = const   (the volume pi h_0 a b / 2)
    u = x_c' + xi a',   v = eta b'
    x_c'' = s,   a'' = 2 beta_x h_0 / a,   b'' = 2 beta_y h_0 / b

where ``s = sin zeta - tan delta cos zeta`` is the driving acceleration and ``beta_x = eps
cos zeta K_x``, ``beta_y = eps cos zeta K_y``. Substituting the fields into ``u_t + u u_x +
v u_y = s - beta_x h_x`` and ``v_t + u v_x + v v_y = -beta_y h_y`` gives the three ordinary
differential equations; the depth equation holds because the volume is constant. A cap
released at rest spreads in both directions for all time (``a'', b'' > 0``), so the earth
pressure stays active in both. The friction term is ``tan delta cos zeta`` along x: exact for
the model only without bed friction (``delta = 0``), where the friction along the velocity of
the model and the friction along x coincide.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from conslaw.exact import Unavailable
from conslaw.exact2d import gauss_average

Array = NDArray[np.float64]

#: Relative and absolute tolerance of the integration of the ordinary differential equations.
ODE_TOLERANCE = 1e-12
#: Times, besides the integrator's own steps, at which :meth:`EllipticCap.extent` looks for
#: the margin's extremes.
EXTENT_SAMPLES = 1025


@dataclass(frozen=True)
class EllipticCap:
    """The similarity solution released at rest at ``t = 0`` with centre ``(x0, y0)``, axes
    ``(a0, b0)`` and height ``height``; ``beta_x``, ``beta_y`` and the acceleration ``slope``
    as in the module docstring. The equations are integrated up to ``t_end`` when the cap is
    made.

    Raises
    ------
    Unavailable
        If the integration fails (its message says why).
    """

    x0: float
    y0: float
    a0: float
    b0: float
    height: float
    beta_x: float
    beta_y: float
    slope: float
    t_end: float
    _solution: object = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.t_end <= 0.0:
            object.__setattr__(self, "_solution", None)
            return
        volume = self.height * self.a0 * self.b0

        def rates(t: float, y: Array) -> list[float]:
            a, a_dot, b, b_dot = y
            h0 = volume / (a * b)
            return [a_dot, 2.0 * self.beta_x * h0 / a, b_dot, 2.0 * self.beta_y * h0 / b]

        # A failed integration (overflow on absurd axes) is reported below, not warned.
        with np.errstate(all="ignore"):
            from scipy.integrate import solve_ivp  # on first use: every run loads this module

            solution = solve_ivp(
                rates,
                (0.0, self.t_end),
                [self.a0, 0.0, self.b0, 0.0],
                method="DOP853",
                rtol=ODE_TOLERANCE,
                atol=ODE_TOLERANCE * min(self.a0, self.b0),
                dense_output=True,
            )
        if not solution.success:
            raise Unavailable(
                f"the axes of the similarity solution could not be integrated to "
                f"t={self.t_end:g}: {solution.message}"
            )
        object.__setattr__(self, "_solution", solution)

    def axes(self, t: float) -> tuple[float, float, float, float]:
        """``(a, a', b, b')`` at time ``t`` in ``[0, t_end]``."""
        if t == 0.0 or self._solution is None:
            return self.a0, 0.0, self.b0, 0.0
        a, a_dot, b, b_dot = self._solution.sol(t)  # type: ignore[attr-defined]
        return float(a), float(a_dot), float(b), float(b_dot)

    def centre(self, t: float) -> tuple[float, float]:
        """``(x_c, y_c)`` at time ``t``: ``x_c = x0 + s t^2 / 2``."""
        return self.x0 + 0.5 * self.slope * t * t, self.y0

    def point_values(self, x: Array, y: Array, t: float) -> Array:
        """``(h, h u, h v)`` at the points ``(x, y)`` (broadcast), shape ``(3, ...)``."""
        a, a_dot, b, b_dot = self.axes(t)
        x_c, y_c = self.centre(t)
        xi, eta = (np.asarray(x) - x_c) / a, (np.asarray(y) - y_c) / b
        h0 = self.height * self.a0 * self.b0 / (a * b)
        h = h0 * np.maximum(1.0 - xi * xi - eta * eta, 0.0)
        u = self.slope * t + xi * a_dot
        v = eta * b_dot
        return np.stack(np.broadcast_arrays(h, h * u, h * v))

    def cell_averages(self, x_edges: Array, y_edges: Array, t: float) -> Array:
        """Averages over the cells of the edges, shape ``(3, ny, nx)``
        (:func:`~conslaw.exact2d.gauss_average`: the depth has a kink at the margin)."""
        return gauss_average(lambda x, y: self.point_values(x, y, t), x_edges, y_edges)

    def margin(self, t: float) -> tuple[float, float, float, float]:
        """``(x_c, y_c, a, b)``: the ellipse where the depth vanishes at time ``t``."""
        a, _, b, _ = self.axes(t)
        x_c, y_c = self.centre(t)
        return x_c, y_c, a, b

    def extent(self) -> tuple[float, float, float, float]:
        """``(x_low, x_high, y_low, y_high)``: the box that the margin stays in over ``[0,
        t_end]``.

        The rear ``x_c - a`` is not monotone (the cap spreads back before gravity carries it
        down): the extremes are taken over the integrator's steps and :data:`EXTENT_SAMPLES`
        equally spaced times.

        Returns
        -------
        tuple of float
        """
        if self._solution is None:
            return self.x0 - self.a0, self.x0 + self.a0, self.y0 - self.b0, self.y0 + self.b0
        times = np.union1d(
            self._solution.t,  # type: ignore[attr-defined]
            np.linspace(0.0, self.t_end, EXTENT_SAMPLES),
        )
        a, _, b, _ = self._solution.sol(times)  # type: ignore[attr-defined]
        x_c = self.x0 + 0.5 * self.slope * times * times
        return (
            float(np.min(x_c - a)),
            float(np.max(x_c + a)),
            float(self.y0 - np.max(b)),
            float(self.y0 + np.max(b)),
        )
