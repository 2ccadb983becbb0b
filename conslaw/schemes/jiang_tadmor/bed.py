"""The bed of a 2D depth-averaged model as the Jiang–Tadmor cells see it: quarter-cell averages.

A primary cell and the four staggered cells that overlap it share its four quarters, so the
exact bed averages over the quarter cells (``Model.quarter_bed``) describe the bed of both cell
families at once. Each cell holds four numbers that give back its quarter averages exactly::

    bed   = (ll + lr + ul + ur) / 4
    bed_x = 2 (right - left) / dx,   right = (lr + ur)/2, left = (ll + ul)/2
    bed_y = 2 (upper - lower) / dy,  upper = (ul + ur)/2, lower = (ll + lr)/2
    twist = (ll - lr) + (ur - ul)

so that the quarter ``(sx, sy)`` (signs of its offset from the centre) has the average
``bed + sx dx bed_x/4 + sy dy bed_y/4 + sx sy twist/4``. The depth of a lake at rest, ``surface -
bed``, has these quarter averages too (the surface is flat), and the staggered average of four
quarters from four cells (what the scheme forms) is then the depth of the new cell exactly: the
twist term is what a linear reconstruction ``bed +- slope/4`` would miss (docs/design.md,
"Toward two dimensions"). With the 1D conventions of ``NessyahuTadmor._aux_family``: the
quarters beyond a wall mirror those inside (a staggered cell centred on a wall sees a symmetric
bed), a periodic side wraps, an outflow side evaluates the bed beyond the domain; ghost cells of a
family then take the family's values by the rule of their side.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from conslaw.grid2d import Grid2D
from conslaw.model import Model

Array = NDArray[np.float64]


#: The quarters of a cell, lower left, lower right, upper left, upper right, by the signs
#: ``(sx, sy)`` of their offsets from the centre.
QUARTER_SIGNS = ((-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0))


def rows_of_quarters(quarters: Array, dx: float, dy: float) -> Array:
    """``(bed, bed_x, bed_y, twist)`` of cells from their four quarter averages ``(4, ...)``
    in the order of :data:`QUARTER_SIGNS`.

    A bed that varies along x only (equal quarter averages up and down, bit for bit) has
    ``twist = 0`` and ``bed_y = 0`` exactly, and ``bed``, ``bed_x`` by the 1D formulas
    (``NessyahuTadmor._aux_family``).
    """
    lower_left, lower_right, upper_left, upper_right = quarters
    left = 0.5 * (lower_left + upper_left)
    right = 0.5 * (lower_right + upper_right)
    lower = 0.5 * (lower_left + lower_right)
    upper = 0.5 * (upper_left + upper_right)
    return np.stack(
        [
            0.5 * (left + right),
            2.0 * (right - left) / dx,
            2.0 * (upper - lower) / dy,
            (lower_left - lower_right) + (upper_right - upper_left),
        ]
    )


def quarters_of_rows(rows: Array, dx: float, dy: float) -> Array:
    """The four quarter averages ``(4, ...)`` that ``rows`` (``bed, bed_x, bed_y, twist``)
    describe, ``bed + sx dx bed_x/4 + sy dy bed_y/4 + sx sy twist/4``."""
    bed, bed_x, bed_y, twist = rows
    return np.stack(
        [
            bed + sx * (0.25 * dx) * bed_x + sy * (0.25 * dy) * bed_y + (0.25 * sx * sy) * twist
            for sx, sy in QUARTER_SIGNS
        ]
    )


def bed_rows(quarters: Array, dx: float, dy: float) -> Array:
    """:func:`rows_of_quarters` of the cells made of 2 x 2 blocks of ``quarters`` (``(2 rows,
    2 columns)`` -> ``(4, rows, columns)``)."""
    blocks = (
        quarters[0::2, 0::2],
        quarters[0::2, 1::2],
        quarters[1::2, 0::2],
        quarters[1::2, 1::2],
    )
    return rows_of_quarters(np.stack(blocks), dx, dy)


def flooded_level(depth: Array, quarters: Array) -> Array:
    """The water level ``w`` whose still water over a cell's four flat quarters (bed averages
    ``quarters``, ``(4, ...)``) has the cell's ``depth``: ``mean(max(w - quarter, 0)) = depth``.
    With the ``k`` lowest quarters under water, ``w = (4 depth + their sum) / k``; ``depth +
    bed`` if all are. (A partly flooded cell: Bollermann, Chen, Kurganov & Noelle 2013, J. Sci.
    Comput. 56, for the central-upwind scheme.)"""
    low_first = np.sort(quarters, axis=0)
    totals = np.cumsum(low_first, axis=0)
    level = (4.0 * depth + totals[3]) / 4.0
    for k in (3, 2, 1):  # the fewest quarters under water that hold the depth win
        candidate = (4.0 * depth + totals[k - 1]) / k
        level = np.where(candidate <= low_first[k], candidate, level)
    return level


def quarter_averages(model: Model, grid: Grid2D, boundaries: Mapping[str, str]) -> Array:
    """The bed averages over the quarter cells of ``grid`` and one layer of quarters beyond each
    side, ``(2 ny + 2, 2 nx + 2)``: mirrored beyond a wall, wrapped beyond a periodic side, the
    bed's own beyond an outflow."""
    nx, ny = grid.x.n_cells, grid.y.n_cells
    x_edges = grid.x.x_min + 0.5 * grid.dx * np.arange(-1, 2 * nx + 2, dtype=np.float64)
    y_edges = grid.y.x_min + 0.5 * grid.dy * np.arange(-1, 2 * ny + 2, dtype=np.float64)
    quarters = model.quarter_bed(x_edges, y_edges)  # type: ignore[attr-defined]
    for axis, low, high in ((1, "left", "right"), (0, "bottom", "top")):
        moved = np.moveaxis(quarters, axis, 0)  # a view: writes land in ``quarters``
        if boundaries[low] == "periodic":
            moved[0] = moved[-2]
            moved[-1] = moved[1]
            continue
        if boundaries[low] == "wall":
            moved[0] = moved[1]
        if boundaries[high] == "wall":
            moved[-1] = moved[-2]
    return quarters


def family_bed(
    quarters: Array, grid: Grid2D, staggered: bool, periodic: tuple[bool, bool]
) -> Array:
    """``bed_rows`` of the primary or the staggered family's cells (``periodic`` in x, in y)."""
    nx, ny = grid.x.n_cells, grid.y.n_cells
    if staggered:
        columns = slice(0, 2 * nx + (0 if periodic[0] else 2))
        rows = slice(0, 2 * ny + (0 if periodic[1] else 2))
    else:
        columns, rows = slice(1, 2 * nx + 1), slice(1, 2 * ny + 1)
    return bed_rows(quarters[rows, columns], grid.dx, grid.dy)


def still_water_depth(quarters: Array, surface: float) -> Array:
    """The depth of still water at ``surface`` over cells of four flat quarters (``(4, ...)``),
    ``mean(max(surface - quarter, 0))``: the state the scheme keeps at rest, dry land included
    (a cell average of ``max(surface - bed, 0)`` differs from it where the shoreline crosses a
    cell)."""
    return np.mean(np.maximum(surface - quarters, 0.0), axis=0)
