"""Immutable solution state."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class State:
    """The conserved variables at one time on one cell family.

    Attributes
    ----------
    t : float
        Time.
    x : ndarray, shape (n_cells,)
        Cell centres.
    q : ndarray, shape (n_vars, n_cells)
        Conserved cell averages (float64, C-contiguous, read-only).
    offset : float
        0.0 on the primary grid, 0.5 on the staggered grid of the Nessyahu–Tadmor scheme.
    """

    t: float
    x: NDArray[np.float64]
    q: NDArray[np.float64]
    offset: float = 0.0

    def __post_init__(self) -> None:
        q = np.array(self.q, dtype=np.float64, order="C", copy=True, ndmin=2)
        x = np.array(self.x, dtype=np.float64, copy=True)
        if x.ndim != 1 or q.shape[1] != x.shape[0]:
            raise ValueError(f"q must have shape (n_vars, {x.shape[0]}), got {q.shape}")
        q.flags.writeable = False
        x.flags.writeable = False
        object.__setattr__(self, "q", q)
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "t", float(self.t))
        object.__setattr__(self, "offset", float(self.offset))

    @property
    def n_vars(self) -> int:
        """Number of conserved variables."""
        return int(self.q.shape[0])

    @property
    def n_cells(self) -> int:
        """Number of cells."""
        return int(self.q.shape[1])
