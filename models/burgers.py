"""Inviscid Burgers equation ``u_t + (u^2/2)_x = 0`` and its exact solutions."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from numba import njit

from conslaw.exact import ExactSolution, Unavailable
from conslaw.grid import Grid
from conslaw.model import InitialData, Model
from conslaw_models.burgers_exact import BurgersRiemannFans, BurgersSmoothSine


@njit(cache=True)
def flux_point(q, aux, params, out):
    """``f(u) = u^2 / 2``."""
    out[0] = 0.5 * q[0] * q[0]


@njit(cache=True)
def jacobian_point(q, aux, params, out):
    """``f'(u) = u``."""
    out[0, 0] = q[0]


@njit(cache=True)
def max_speed_point(q, aux, params):
    """``|f'(u)| = |u|``."""
    return abs(q[0])


class Burgers(Model):
    """Inviscid Burgers equation, ``u_t + (u^2/2)_x = 0`` (one conserved variable ``u``).

    Exact solutions: separated Riemann problems (shock, rarefaction, transonic rarefaction) for
    piecewise-constant data, and the smooth solution of ``u0 = a + b sin(2 pi k x / L)`` before it
    breaks (docs/equations.md, "Exact solutions").
    """

    name = "burgers"
    description = "inviscid Burgers equation u_t + (u^2/2)_x = 0"
    variables = ("u",)
    # A mirror image of a Burgers solution, u(-x) = -u(x), is again a solution.
    reflect_signs = (-1.0,)
    flux_point = staticmethod(flux_point)
    jacobian_point = staticmethod(jacobian_point)
    max_speed_point = staticmethod(max_speed_point)

    def exact_solution(
        self, initial: InitialData, grid: Grid, context: Mapping[str, Any]
    ) -> ExactSolution | None:
        """Separated Riemann problems (open boundaries, no wave reaching them or each other by
        ``t_end``), or the sine wave before it breaks (periodic); else None or Unavailable."""
        t_end = float(context["t_end"])
        if initial.kind == "piecewise-constant":
            if (context["left"], context["right"]) != ("outflow", "outflow"):
                raise Unavailable("the exact Riemann solution assumes outflow boundaries")
            fans = BurgersRiemannFans.from_initial(initial, grid)
            if fans.valid_until() < t_end:
                raise Unavailable(f"the Riemann waves interact at t={fans.valid_until():g}")
            if not fans.breakpoints:  # one constant state: it stays as it is
                return fans
            lowest = fans._wave_extent(0, t_end)[0]
            highest = fans._wave_extent(len(fans.breakpoints) - 1, t_end)[1]
            if lowest < grid.x_min or highest > grid.x_max:
                raise Unavailable(f"a wave reaches the boundary before t={t_end:g}")
            return fans
        if initial.kind == "sine":
            if context["left"] != "periodic":
                raise Unavailable("the exact sine solution needs periodic boundaries")
            sine = BurgersSmoothSine.from_initial(initial, grid)
            if sine.breaking_time() <= t_end:
                raise Unavailable(f"the sine wave breaks at t={sine.breaking_time():g}")
            return sine
        return None
