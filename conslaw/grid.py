"""Uniform 1D grid and the two staggered cell families of the Nessyahu–Tadmor scheme."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError

MIN_CELLS = 4
#: Largest grid accepted (about 2 GB of work arrays for a two-variable model).
MAX_CELLS = 50_000_000


@dataclass(frozen=True)
class Grid:
    """A uniform grid of ``n_cells`` cells on ``[x_min, x_max]``.

    The *primary* cells (offset 0) have centres ``x_min + (j + 1/2) dx``. The staggered cells
    (offset 1/2) are centred on the primary cell faces, ``x_min + k dx``: ``n_cells + 1`` of them on
    a bounded domain (the two end cells straddle the boundary), ``n_cells`` on a periodic one.
    """

    x_min: float
    x_max: float
    n_cells: int

    def __post_init__(self) -> None:
        if isinstance(self.n_cells, bool) or not isinstance(self.n_cells, int | np.integer):
            raise ConfigError(f"n_cells must be an integer >= {MIN_CELLS}, got {self.n_cells!r}")
        if self.n_cells > MAX_CELLS:
            raise ConfigError(f"n_cells must be <= {MAX_CELLS}, got {self.n_cells}")
        if self.n_cells < MIN_CELLS:
            raise ConfigError(f"n_cells must be an integer >= {MIN_CELLS}, got {self.n_cells}")
        if not (np.isfinite(self.x_min) and np.isfinite(self.x_max)):
            raise ConfigError("x_min and x_max must be finite numbers")
        if not self.x_max > self.x_min:
            raise ConfigError(f"x_max must be > x_min, got x_min={self.x_min}, x_max={self.x_max}")
        length = self.x_max - self.x_min
        if not (np.isfinite(length) and length / self.n_cells > 0.0):
            raise ConfigError(
                f"x_max - x_min must be a finite length, got {self.x_min}..{self.x_max}"
            )

    @property
    def length(self) -> float:
        """Domain length ``x_max - x_min``."""
        return float(self.x_max - self.x_min)

    @property
    def dx(self) -> float:
        """Cell width."""
        return self.length / self.n_cells

    @property
    def edges(self) -> NDArray[np.float64]:
        """The ``n_cells + 1`` faces of the primary cells."""
        return self.x_min + self.dx * np.arange(self.n_cells + 1, dtype=np.float64)

    def n_cells_at(self, offset: float, periodic: bool) -> int:
        """Number of cells of the family with ``offset`` (0 or 0.5)."""
        if offset == 0.0 or periodic:
            return self.n_cells
        return self.n_cells + 1

    def centres(self, offset: float = 0.0, periodic: bool = False) -> NDArray[np.float64]:
        """Cell centres of the family with ``offset`` (0 primary, 0.5 staggered)."""
        n = self.n_cells_at(offset, periodic)
        shift = 0.5 if offset == 0.0 else 0.0
        return self.x_min + self.dx * (np.arange(n, dtype=np.float64) + shift)
