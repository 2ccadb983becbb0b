"""Error norms, observed orders of accuracy and conserved totals."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


@dataclass(frozen=True)
class ErrorNorms:
    """Errors of a numerical solution against exact cell averages on a uniform grid."""

    l1: float
    l2: float
    linf: float


def error_norms(numerical: Array, exact: Array, dx: float, length: float) -> ErrorNorms:
    """The norms (docs/equations.md, "Error norms") of ``numerical - exact`` (both cell averages).

    ``L1 = (1/L) sum |q_i - qbar_i| dx``, ``L2 = sqrt((1/L) sum (q_i - qbar_i)^2 dx)``,
    ``Linf = max |q_i - qbar_i|``.
    """
    difference = np.asarray(numerical, dtype=np.float64) - np.asarray(exact, dtype=np.float64)
    return ErrorNorms(
        l1=float(np.sum(np.abs(difference)) * dx / length),
        l2=float(np.sqrt(np.sum(difference * difference) * dx / length)),
        linf=float(np.max(np.abs(difference))),
    )


def observed_orders(n_cells: Sequence[int], errors: Sequence[float]) -> list[float]:
    """Observed orders ``log(e_k / e_{k+1}) / log(N_{k+1} / N_k)`` between successive grids."""
    return [
        float(np.log(errors[k] / errors[k + 1]) / np.log(n_cells[k + 1] / n_cells[k]))
        for k in range(len(errors) - 1)
    ]


def total_mass(q: Array, dx: float) -> Array:
    """``sum q_i dx`` of every conserved variable."""
    return np.asarray(q, dtype=np.float64).sum(axis=-1) * dx
