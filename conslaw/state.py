"""Immutable solution state."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class Margin:
    """An avalanche margin tracked inside its cell: position and velocity (front tracking)."""

    position: float
    velocity: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.position) and math.isfinite(self.velocity)):
            raise ValueError(f"margin must be finite, got {self.position!r}, {self.velocity!r}")


@dataclass(frozen=True)
class Margins:
    """The rear (upslope, smaller x) and front margins of one body; None where the body
    touches the boundary on that side."""

    rear: Margin | None
    front: Margin | None

    def row(self, t: float) -> tuple[float, float, float, float, float]:
        """``(t, x_rear, u_rear, x_front, u_front)``, NaN for a missing margin."""
        nan = math.nan
        rear = (self.rear.position, self.rear.velocity) if self.rear else (nan, nan)
        front = (self.front.position, self.front.velocity) if self.front else (nan, nan)
        return (t, *rear, *front)


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
    margins : Margins or None
        The tracked margins (front tracking only).
    """

    t: float
    x: NDArray[np.float64]
    q: NDArray[np.float64]
    offset: float = 0.0
    margins: Margins | None = None

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
