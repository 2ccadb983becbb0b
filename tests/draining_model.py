"""A test model whose depth drains at a fixed rate everywhere: a dry cell would become negative
at any time step, so no halving can make a step pair work and the 2D time loop must stop (the
Savage–Hutter chute model in 2D with the source ``(-1, s_x, s_y)``)."""

from __future__ import annotations

from numba import njit

from conslaw_models.savage_hutter_2d import SavageHutter2D, source_point as chute_source


@njit(cache=True)
def draining_source_point(q, aux, params, out):  # type: ignore[no-untyped-def]
    """The chute's source with a depth source of -1."""
    chute_source(q, aux, params, out)
    out[0] = -1.0


class Draining2D(SavageHutter2D):
    """Savage–Hutter on a 2D chute whose depth drains at rate 1 (test model, not registered)."""

    name = "draining-2d"
    description = "2D chute with a depth sink (test model)"
    source_point = staticmethod(draining_source_point)
    empty_stays_empty = False  # its sink acts on empty cells too
