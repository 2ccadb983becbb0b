"""Loops over cells of a 2D model's coefficient hooks, for the numpy steps of the Jiang–Tadmor
reference (:mod:`conslaw.schemes.jiang_tadmor.reference`): the model's pointwise function is an
argument (numba compiles one loop per function)."""

from __future__ import annotations

from numba import njit


@njit
def coefficients_2d_cells(point, q, slopes_x, slopes_y, aux, params):
    """``point(q, slope_x, slope_y, aux, params)`` on every column, ``aux`` set in place."""
    for i in range(q.shape[1]):
        point(q[:, i], slopes_x[:, i], slopes_y[:, i], aux[:, i], params)


@njit
def corner_coefficients_cells(point, a, b, c, d, aux, params):
    """``point(a, b, c, d, aux, params)`` on every column (the corners of one staggered cell
    each), ``aux`` set in place."""
    for i in range(a.shape[1]):
        point(a[:, i], b[:, i], c[:, i], d[:, i], aux[:, i], params)
