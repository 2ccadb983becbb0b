"""The interface of exact solutions: exact cell averages and point values."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


class ExactSolution(ABC):
    """An exact solution of a model for one initial condition."""

    @abstractmethod
    def cell_averages(self, edges: Array, t: float) -> Array:
        """Exact averages over the cells ``[edges[i], edges[i+1]]``, shape ``(n_vars, n)``.

        Integrated exactly, splitting at the kinks of the solution (reference §6 error norm).
        """

    @abstractmethod
    def point_values(self, x: Array, t: float) -> Array:
        """Exact values at the points ``x``, shape ``(n_vars, n)``."""
