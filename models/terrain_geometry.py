"""The geometry of a terrain surface ``z = b(x, y)`` that the Savage–Hutter terrain model
carries in its coefficients (docs/design.md, "Savage–Hutter on terrain").

With ``s = 1 + |grad b|^2`` and ``c = cos(theta) = s^(-1/2)`` (the cosine of the slope angle):

- the projection ``P = G^-1 = I - c^2 grad b grad b^T``, the inverse of the surface metric ``G = I
  + grad b grad b^T``: a surface gradient seen in map coordinates is ``P grad_X``;
- the pressure geometry ``T_ij = d_j (P_ij / c)``; with ``g_j = b_x b_xj + b_y b_yj``::

      T_ij = delta_ij c g_j + c^3 g_j b_i b_j - c (b_ij b_j + b_i b_jj)

  (from ``P_ij / c = delta_ij / c - c b_i b_j``, ``d_j (1/c) = c g_j`` and ``d_j c = -c^3
  g_j``), the source that the divergence form of the pressure leaves; it vanishes on a plane.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def slope_cosine(b_x: Array, b_y: Array) -> Array:
    """``c = (1 + b_x^2 + b_y^2)^(-1/2)``, the cosine of the slope angle.

    Parameters
    ----------
    b_x, b_y : numpy.ndarray
        The surface gradient.

    Returns
    -------
    numpy.ndarray
    """
    return 1.0 / np.sqrt(1.0 + b_x * b_x + b_y * b_y)


def projection(b_x: Array, b_y: Array) -> tuple[Array, Array, Array]:
    """``(P_xx, P_xy, P_yy)`` of ``P = I - c^2 grad b grad b^T`` (symmetric).

    Parameters
    ----------
    b_x, b_y : numpy.ndarray
        The surface gradient.

    Returns
    -------
    tuple of numpy.ndarray
    """
    c2 = 1.0 / (1.0 + b_x * b_x + b_y * b_y)
    return 1.0 - c2 * b_x * b_x, -c2 * b_x * b_y, 1.0 - c2 * b_y * b_y


def pressure_geometry(
    b_x: Array, b_y: Array, b_xx: Array, b_xy: Array, b_yy: Array
) -> tuple[Array, Array, Array, Array]:
    """``(T_xx, T_xy, T_yx, T_yy)``, ``T_ij = d_j (P_ij / c)`` (module docstring).

    Parameters
    ----------
    b_x, b_y : numpy.ndarray
        The surface gradient.
    b_xx, b_xy, b_yy : numpy.ndarray
        The second derivatives.

    Returns
    -------
    tuple of numpy.ndarray
    """
    c = slope_cosine(b_x, b_y)
    c3 = c * c * c
    g_x = b_x * b_xx + b_y * b_xy
    g_y = b_x * b_xy + b_y * b_yy
    t_xx = c * g_x + c3 * g_x * b_x * b_x - 2.0 * c * b_x * b_xx
    t_xy = c3 * g_y * b_x * b_y - c * (b_xy * b_y + b_x * b_yy)
    t_yx = c3 * g_x * b_y * b_x - c * (b_xy * b_x + b_y * b_xx)
    t_yy = c * g_y + c3 * g_y * b_y * b_y - 2.0 * c * b_y * b_yy
    return t_xx, t_xy, t_yx, t_yy
