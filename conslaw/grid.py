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

    def mirror_cells(self, centre: float) -> NDArray[np.intp] | None:
        """For each primary cell, the index of its mirror image about ``x = centre`` (-1 where
        that image is not on the grid); ``None`` if ``centre`` is neither a cell face nor a cell
        centre (to round-off), so that the cells do not pair up.

        Cell ``j`` covers ``[j, j + 1]`` in units of ``dx`` from ``x_min``; with
        ``s = 2 (centre - x_min) / dx`` an integer its image is cell ``s - 1 - j``.
        """
        doubled = 2.0 * (centre - self.x_min) / self.dx
        if not np.isfinite(doubled) or abs(doubled) > 4.0 * self.n_cells + 4.0:
            return None  # not a number, or so far off that no cell has its image on the grid
        # A face or a centre to round-off only: a centre genuinely off a face is left alone.
        if abs(doubled - round(doubled)) > 64.0 * np.finfo(float).eps * max(1.0, abs(doubled)):
            return None
        partner = round(doubled) - 1 - np.arange(self.n_cells, dtype=np.intp)
        partner[(partner < 0) | (partner >= self.n_cells)] = -1
        return partner

    def mirror_symmetric(
        self, values: NDArray[np.float64], centre: float, odd: tuple[int, ...] = ()
    ) -> NDArray[np.float64]:
        """Cell averages of data that is mirror-symmetric about ``x = centre`` (rows in ``odd``
        antisymmetric, such as a momentum), made so bit for bit: each pair of mirror cells
        takes ``(a + b) / 2`` (``(a - b) / 2`` and its negative for an odd row), a change within
        the round-off of the averages. Unchanged where the cells do not pair up
        (:meth:`mirror_cells`).

        Why: with ``phi > delta`` the Savage–Hutter earth pressure switches on the sign of a
        velocity difference, which turns a round-off asymmetry of the initial averages into an
        asymmetry of the solution of the size of the truncation error (docs/design.md,
        "Earth pressure"); the update itself is mirror-exact.
        """
        partner = self.mirror_cells(centre)
        if partner is None:
            return values
        paired = np.flatnonzero(partner >= 0)
        result = np.array(values, dtype=np.float64, copy=True)
        rows = result.reshape(-1, self.n_cells)
        for row in range(rows.shape[0]):
            mine, theirs = rows[row, paired], rows[row, partner[paired]]
            rows[row, paired] = 0.5 * (mine - theirs) if row in odd else 0.5 * (mine + theirs)
        return result

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
