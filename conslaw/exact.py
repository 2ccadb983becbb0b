"""The interface of exact solutions: exact cell averages and point values."""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


class Unavailable(Exception):  # noqa: N818 (a reason, not a failure)
    """Raised by ``Model.exact_solution`` when the model has exact solutions but none applies to
    this set-up; the message says why (waves reach a boundary, wave interaction, ...)."""


class ExactSolution(ABC):
    """An exact solution of a model for one initial condition."""

    @abstractmethod
    def cell_averages(self, edges: Array, t: float) -> Array:
        """Exact averages over the cells ``[edges[i], edges[i+1]]``, shape ``(n_vars, n)``.

        Integrated exactly, splitting at the kinks of the solution (docs/equations.md, "Error
        norms").
        """

    @abstractmethod
    def point_values(self, x: Array, t: float) -> Array:
        """Exact values at the points ``x``, shape ``(n_vars, n)``."""


#: Gauss–Legendre nodes per smooth piece and cell: exact for polynomials up to degree 15.
_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(8)


def piecewise_cell_averages(
    edges: Array,
    breakpoints: Array,
    pieces: list[Callable[[Array], Array]],
) -> Array:
    """Cell averages of a function that is smooth between ``breakpoints``.

    ``pieces[p](x)`` evaluates the solution on piece p (between ``breakpoints[p-1]`` and
    ``breakpoints[p]``), returning shape ``(n_vars, len(x))``. Each cell is split at the
    breakpoints inside it and every part is integrated by 8-point Gauss–Legendre quadrature, exact
    to round-off for the polynomial pieces of the Riemann solutions here (degree <= 3).
    """
    edges = np.asarray(edges, dtype=np.float64)
    bounds = np.concatenate([[-np.inf], np.asarray(breakpoints, dtype=np.float64), [np.inf]])
    total: Array | None = None
    for p, piece in enumerate(pieces):
        a = np.clip(edges[:-1], bounds[p], bounds[p + 1])
        b = np.clip(edges[1:], bounds[p], bounds[p + 1])
        half = 0.5 * (b - a)
        points = (0.5 * (a + b))[:, None] + half[:, None] * _GAUSS_NODES[None, :]
        values = piece(points.ravel())
        values = values.reshape(values.shape[0], *points.shape)
        integral = np.einsum("vcg,g->vc", values, _GAUSS_WEIGHTS) * half[None, :]
        total = integral if total is None else total + integral
    assert total is not None
    return total / np.diff(edges)[None, :]
