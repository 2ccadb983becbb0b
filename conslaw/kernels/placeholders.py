"""Stand-ins for the functions a template binds; the generator replaces these imports.

They let the templates be valid, lintable Python modules. Calling one is a bug.
"""

from __future__ import annotations

from numba import njit


@njit
def unbound(*args):  # type: ignore[no-untyped-def]
    raise RuntimeError("template placeholder called: the kernel was not generated")


flux_point = jacobian_point = max_speed_point = source_point = admissible_point = unbound
balanced_source_point = correct_point = resistance_point = coefficients_point = unbound
interface_coefficients_point = rest_coefficients_point = unbound
slope_point = fill_left = fill_right = unbound
