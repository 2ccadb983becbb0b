"""Pointwise functions a model need not write: the default admissibility, and stand-ins.

:func:`finite_point` is the admissibility of a model without its own. The stand-ins
(:func:`unbound` under every hook's name) let the kernel templates be valid, lintable Python
modules, and are bound for a hook a model does not have, where the template's ``HAS_*``
constant removes every call; calling one is a bug.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def finite_point(q, aux, params):
    """Admissible means every component is finite."""
    # A plain loop: numba compiles it, not a generator inside all().
    for v in range(q.shape[0]):  # noqa: SIM110
        if not np.isfinite(q[v]):
            return False
    return True


@njit
def unbound(*args):
    raise RuntimeError("template placeholder called: the kernel was not generated")


flux_point = jacobian_point = max_speed_point = source_point = admissible_point = unbound
balanced_source_point = balanced_source_y_point = correct_point = resistance_point = unbound
coefficients_point = coefficients_2d_point = corner_coefficients_point = unbound
interface_coefficients_point = rest_coefficients_point = unbound
slope_point = fill_left = fill_right = unbound
flux_y_point = jacobian_y_point = max_speed_y_point = unbound
