"""The source at the quarter points and the Coulomb resistance of the Jiang–Tadmor step, for a
2D model whose coefficients vary along x (a chute) or over the plane (a terrain): the 1D rule
of Tai et al. (2001, eqs. 13–14) on the quarters of the four source cells of a new cell.

The new cell centred on the common corner of ``a`` (lower left), ``b`` (lower right), ``c``
(upper left) and ``d`` (upper right) holds one quarter of each; their mid-step values at the
quarters' centres are ``p_a + w'_a/4 + w*_a/4``, ``p_b - w'_b/4 + w*_b/4``, ``p_c + w'_c/4 -
w*_c/4`` and ``p_d - w'_d/4 - w*_d/4`` (``p`` the predicted values, ``w'`` and ``w*`` the
undivided slopes in x and y), with the coefficients at the same points (along a chute: at ``x +
dx/4`` for ``a`` and ``c`` and at ``x - dx/4`` for ``b`` and ``d``). Then::

    w_new += dt/4 ((s_a + s_b) + (s_c + s_d))
    impulse = dt/4 ((R_a + R_b) + (R_c + R_d))

and the momentum ``(m_x, m_y)`` is stopped if ``|m| <= impulse``, else shortened by the impulse
along itself (:func:`resist`). Data that do not depend on y give the 1D values bit for bit
(``(s + s)/4 = s/2`` exactly; a momentum along x alone keeps its direction exactly).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from conslaw.model import Model

Array = NDArray[np.float64]


#: The source cells ``a``, ``b``, ``c``, ``d`` of every new cell within the last two axes of an
#: array of source cells (rows and columns).
CORNERS = (
    (Ellipsis, slice(None, -1), slice(None, -1)),
    (Ellipsis, slice(None, -1), slice(1, None)),
    (Ellipsis, slice(1, None), slice(None, -1)),
    (Ellipsis, slice(1, None), slice(1, None)),
)


def corners(array: Array) -> tuple[Array, Array, Array, Array]:
    """The lower-left, lower-right, upper-left and upper-right source cells of every new cell.

    Parameters
    ----------
    array : numpy.ndarray
        ``(..., rows, columns)`` values of the source cells.

    Returns
    -------
    tuple of numpy.ndarray
        Four views ``(..., rows - 1, columns - 1)``.
    """
    a, b, c, d = (array[corner] for corner in CORNERS)
    return a, b, c, d


def resist(
    momentum_x: Array,
    momentum_y: Array,
    impulse: Array,
    slopes: tuple[Array, Array] | None = None,
) -> None:
    """Coulomb's stopping rule in place: ``m = 0`` where ``|m| <= impulse``, else ``m - impulse
    m / |m|``: friction never reverses the momentum (docs/equations.md; the 1D scheme's rule
    along x).

    Parameters
    ----------
    momentum_x, momentum_y : numpy.ndarray
        The momentum components, changed in place.
    impulse : numpy.ndarray
        The friction's impulse over the step, ``>= 0``, of the same shape.
    slopes : tuple of numpy.ndarray, optional
        A surface gradient ``(b_x, b_y)`` of the same shape: ``m`` is then the map projection
        of a momentum tangent to the surface, whose length is ``|m|_G = (|m|^2 + (b_x m_x + b_y
        m_y)^2)^(1/2)``, and the rule applies in that length (docs/design.md, "Savage–Hutter on
        terrain").
    """
    size = np.hypot(momentum_x, momentum_y)
    if slopes is not None:
        size = np.hypot(size, slopes[0] * momentum_x + slopes[1] * momentum_y)
    stopped = size <= impulse
    safe = np.where(stopped, 1.0, size)
    for momentum in (momentum_x, momentum_y):
        reduced = momentum - impulse * (momentum / safe)
        momentum[...] = np.where(stopped, 0.0, reduced)


def _quarter_values(predicted: Array, slopes_x: Array, slopes_y: Array) -> list[Array]:
    """The mid-step values at the centres of the quarters of ``a``, ``b``, ``c``, ``d`` that
    lie in the new cell (module docstring)."""
    values = []
    for (p, sx, sy), (along_x, along_y) in zip(
        zip(corners(predicted), corners(slopes_x), corners(slopes_y), strict=True),
        ((0.25, 0.25), (-0.25, 0.25), (0.25, -0.25), (-0.25, -0.25)),
        strict=True,
    ):
        values.append(p + along_x * sx + along_y * sy)
    return values


def add_quarter_terms(
    model: Model,
    new: Array,
    parts: tuple[Array, Array, Array],
    quarter_aux: tuple[Array, Array, Array, Array],
    dt: float,
    resistance: bool,
    slopes: tuple[Array, Array] | None = None,
) -> None:
    """Add the source at the quarter points to the new cells ``new`` and apply the resistance,
    in place.

    Parameters
    ----------
    model : Model
        A 2D model with a source and, if ``resistance``, a ``resistance_point``.
    new : numpy.ndarray
        ``(n_vars, rows, columns)`` new cells (one fewer row and column than the sources).
    parts : tuple of numpy.ndarray
        The predicted values and the slopes in x and in y of the source cells.
    quarter_aux : tuple of numpy.ndarray
        The coefficients at the centres of the quarters in the new cells: the upper-right
        quarter of ``a``, the upper-left of ``b``, the lower-right of ``c`` and the lower-left
        of ``d`` (:data:`CORNERS` of the source cells' arrays), each ``(n_aux, rows,
        columns)`` like ``new``.
    dt : float
        The time step.
    resistance : bool
        Whether to apply the Coulomb resistance.
    slopes : tuple of numpy.ndarray, optional
        The surface gradient at the new cells, for a resistance in the surface metric
        (:func:`resist`).
    """
    quarters = _quarter_values(*parts)
    aux = quarter_aux
    shape = new.shape
    flat = [
        (q.reshape(shape[0], -1), a.reshape(a.shape[0], q[0].size))
        for q, a in zip(quarters, aux, strict=True)
    ]
    s = [model.source(q, a).reshape(shape) for q, a in flat]
    new += (0.25 * dt) * ((s[0] + s[1]) + (s[2] + s[3]))
    if not resistance:
        return
    r = [model.resistance(q, a).reshape(shape[1:]) for q, a in flat]
    impulse = (0.25 * dt) * ((r[0] + r[1]) + (r[2] + r[3]))
    m_x, m_y = model.momentum_index, model.momentum_y_index
    assert m_x is not None and m_y is not None
    resist(new[m_x], new[m_y], impulse, slopes)
