"""Uniform 2D Cartesian grid: a 1D :class:`~conslaw.grid.Grid` per direction.

The staggered cell families of the Jiang–Tadmor scheme (docs/design.md, "Toward two
dimensions") are those of the 1D grid in each direction at once: the primary cells (offset 0 in
both) have centres ``(x_min + (j + 1/2) dx, y_min + (k + 1/2) dy)``, the staggered ones (offset
1/2 in both) are centred on the primary cell corners, one more per direction on a bounded domain
and as many on a periodic one. Arrays of cell values are ``(n_vars, ny, nx)``: y along the
rows, x along the columns, C order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError
from conslaw.grid import MAX_CELLS, Grid


@dataclass(frozen=True)
class Grid2D:
    """``x.n_cells`` by ``y.n_cells`` uniform cells on ``[x_min, x_max] x [y_min, y_max]``."""

    x: Grid
    y: Grid

    def __post_init__(self) -> None:
        if self.x.n_cells * self.y.n_cells > MAX_CELLS:
            raise ConfigError(
                f"nx * ny must be <= {MAX_CELLS}, got {self.x.n_cells} * {self.y.n_cells}"
            )

    @classmethod
    def from_bounds(
        cls, x_min: float, x_max: float, nx: int, y_min: float, y_max: float, ny: int
    ) -> Grid2D:
        """The grid of ``nx`` by ``ny`` cells on the rectangle (each side checked as a 1D grid,
        :class:`~conslaw.grid.Grid`)."""
        return cls(Grid(x_min, x_max, nx), Grid(y_min, y_max, ny))

    @property
    def shape(self) -> tuple[int, int]:
        """``(ny, nx)``: the shape of one variable's primary cell values."""
        return (self.y.n_cells, self.x.n_cells)

    @property
    def dx(self) -> float:
        """Cell width in x."""
        return self.x.dx

    @property
    def dy(self) -> float:
        """Cell width in y."""
        return self.y.dx

    @property
    def cell_area(self) -> float:
        """``dx dy``."""
        return self.dx * self.dy

    def shape_at(self, offset: float, periodic_x: bool, periodic_y: bool) -> tuple[int, int]:
        """``(rows, columns)`` of the family with ``offset`` (0 primary, 0.5 staggered)."""
        return (self.y.n_cells_at(offset, periodic_y), self.x.n_cells_at(offset, periodic_x))

    def centres(
        self, offset: float = 0.0, periodic_x: bool = False, periodic_y: bool = False
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The x centres (columns) and y centres (rows) of the family with ``offset``."""
        return self.x.centres(offset, periodic_x), self.y.centres(offset, periodic_y)
