"""A test model whose solution blows up in finite time: ``u_t = u^2`` (no transport).

``u(t) = u0 / (1 - u0 t)`` reaches infinity at ``t = 1 / u0``; the wave speed is fixed at 1, so
the time step does not shrink as it does, and the NaN/inf appears in the middle of a run, in the
cell with the largest ``u0``. Used to test that every run path reports it with time, step, cell
and values.
"""

from __future__ import annotations

from numba import njit

from conslaw.model import Model


@njit(cache=True)
def flux_point(q, aux, params, out):  # type: ignore[no-untyped-def]
    """No transport."""
    out[0] = 0.0


@njit(cache=True)
def jacobian_point(q, aux, params, out):  # type: ignore[no-untyped-def]
    out[0, 0] = 0.0


@njit(cache=True)
def max_speed_point(q, aux, params):  # type: ignore[no-untyped-def]
    """A fixed speed of 1 (a step of ``cfl dx``)."""
    return 1.0


@njit(cache=True)
def source_point(q, aux, params, out):  # type: ignore[no-untyped-def]
    """``u^2``: finite-time blow-up."""
    out[0] = q[0] * q[0]


class Blowup(Model):
    """``u_t = u^2`` on a grid (test model, not registered)."""

    name = "blowup"
    description = "u_t = u^2 (test model)"
    variables = ("u",)
    reflect_signs = (1.0,)
    has_source = True
    flux_point = staticmethod(flux_point)
    jacobian_point = staticmethod(jacobian_point)
    max_speed_point = staticmethod(max_speed_point)
    source_point = staticmethod(source_point)
