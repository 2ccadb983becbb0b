"""Inviscid Burgers equation ``u_t + (u^2/2)_x = 0`` and its exact solutions."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from numba import njit

from conslaw.exact import ExactSolution
from conslaw.grid import Grid
from conslaw.initial import InitialCondition
from conslaw.model import Model
from conslaw_models.burgers_exact import BurgersRiemannFans, BurgersSmoothSine


@njit(cache=True)
def flux_point(q, aux, params, out):  # type: ignore[no-untyped-def]
    """``f(u) = u^2 / 2``."""
    out[0] = 0.5 * q[0] * q[0]


@njit(cache=True)
def jacobian_point(q, aux, params, out):  # type: ignore[no-untyped-def]
    """``f'(u) = u``."""
    out[0, 0] = q[0]


@njit(cache=True)
def max_speed_point(q, aux, params):  # type: ignore[no-untyped-def]
    """``|f'(u)| = |u|``."""
    return abs(q[0])


class Burgers(Model):
    """Inviscid Burgers equation, ``u_t + (u^2/2)_x = 0`` (one conserved variable ``u``).

    Exact solutions: separated Riemann problems (shock, rarefaction, transonic rarefaction) for
    piecewise-constant data, and the smooth solution of ``u0 = a + b sin(2 pi k x / L)`` before it
    breaks (reference §5).
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
        self, initial: InitialCondition, grid: Grid, boundary: Mapping[str, Any]
    ) -> ExactSolution | None:
        """Exact solution for ``piecewise-constant`` or ``sine`` data, else None."""
        if initial.kind == "piecewise-constant":
            return BurgersRiemannFans.from_initial(initial, grid)
        if initial.kind == "sine":
            if boundary.get("left") != "periodic":
                return None
            return BurgersSmoothSine.from_initial(initial, grid)
        return None
