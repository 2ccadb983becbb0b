"""Loops over cells of a 2D model's coefficient hooks, for the numpy steps of the Jiang–Tadmor
reference (:mod:`conslaw.schemes.jiang_tadmor.reference`): the model's pointwise function is an
argument (numba compiles one loop per function).

Not cached on disk: numba cannot reuse a cached loop whose argument is a function (each process
wrote a new cache entry and compiled anyway); a model's generated module
(:mod:`conslaw.kernelgen`) would cache them, at the price of a recompile of every model's module.
"""

from __future__ import annotations

from numba import njit


@njit
def coefficients_2d_cells(point, q, slopes_x, slopes_y, aux, params):
    """``point(q, slope_x, slope_y, aux, params)`` on every column, ``aux`` set in place.

    Parameters
    ----------
    point : numba dispatcher
        A model's ``coefficients_2d_point``.
    q, slopes_x, slopes_y : numpy.ndarray
        ``(n_vars, n)``: the cells' values and their limited slopes in x and in y.
    aux : numpy.ndarray
        ``(n_aux, n)``: the coefficients, set in place.
    params : numpy.ndarray
        The model's ``param_vector()``.
    """
    for i in range(q.shape[1]):
        point(q[:, i], slopes_x[:, i], slopes_y[:, i], aux[:, i], params)


@njit
def corner_coefficients_cells(point, a, b, c, d, aux, params):
    """``point(a, b, c, d, aux, params)`` on every column (the corners of one staggered cell
    each), ``aux`` set in place.

    Parameters
    ----------
    point : numba dispatcher
        A model's ``corner_coefficients_point``.
    a, b, c, d : numpy.ndarray
        ``(n_vars, n)``: the lower-left, lower-right, upper-left and upper-right corner states.
    aux : numpy.ndarray
        ``(n_aux, n)``: the coefficients, set in place.
    params : numpy.ndarray
        The model's ``param_vector()``.
    """
    for i in range(a.shape[1]):
        point(a[:, i], b[:, i], c[:, i], d[:, i], aux[:, i], params)
