"""What a 2D run that breaks down says, in one line: the time and the step, the cause, the cell
(its column and row and the map point of its centre: easting and northing on terrain), its values
and wave speeds, and what to try (docs/design.md, "Films", and docs/stability.md)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from conslaw.model import Model

Array = NDArray[np.float64]

#: What to try when a step pair cannot be made to work.
REMEDIES = (
    "likely remedies: a smaller cfl, reconstructor = 'minmod', and on a DEM a look for cliffs "
    "and steps in it (parameters.dem_smoothing)"
)


def _speeds(model: Model, values: Array, aux: Array | None) -> tuple[Array, Array]:
    """The wave speeds along x and along y of every cell of ``values`` ``(n_vars, rows,
    columns)``, NaN where they are not finite numbers."""
    flat = values.reshape(values.shape[0], -1)
    flat_aux = None if aux is None or aux.shape[0] == 0 else aux.reshape(aux.shape[0], -1)
    with np.errstate(invalid="ignore", over="ignore"):
        along_x = model.max_wave_speed(flat, flat_aux).reshape(values.shape[1:])
        along_y = model.max_wave_speed(flat, flat_aux, direction="y").reshape(values.shape[1:])
    return along_x, along_y


def fastest_cell(model: Model, values: Array, aux: Array | None) -> tuple[int, int]:
    """``(row, column)`` of the cell of ``values`` with the largest wave speed (the first with one
    that is not finite, if any).

    Parameters
    ----------
    model : Model
    values : numpy.ndarray
        ``(n_vars, rows, columns)``.
    aux : numpy.ndarray or None
        The coefficients at the same cells.

    Returns
    -------
    tuple of int
    """
    along_x, along_y = _speeds(model, values, aux)
    largest = np.fmax(along_x, along_y)
    bad = ~np.isfinite(largest) | ~np.all(np.isfinite(values), axis=0)
    index = int(np.argmax(bad)) if bad.any() else int(np.argmax(largest))
    row, column = divmod(index, values.shape[2])
    return row, column


def shallowest_cell(model: Model, values: Array) -> tuple[int, int]:
    """``(row, column)`` of the cell of ``values`` with the smallest depth.

    Parameters
    ----------
    model : Model
        A model with a depth row.
    values : numpy.ndarray
        ``(n_vars, rows, columns)``.

    Returns
    -------
    tuple of int
    """
    assert model.depth_index is not None
    row, column = divmod(int(np.argmin(values[model.depth_index])), values.shape[2])
    return row, column


def cell_report(
    model: Model,
    values: Array,
    aux: Array | None,
    centres: tuple[Array, Array],
    cell: tuple[int, int],
) -> str:
    """``cell (column j, row k) at x=..., y=...: h=..., hu=..., hv=... (wave speeds ... along x,
    ... along y)`` for the cell ``(row, column)`` of ``values``.

    Parameters
    ----------
    model : Model
    values : numpy.ndarray
        ``(n_vars, rows, columns)``.
    aux : numpy.ndarray or None
        The coefficients at the same cells.
    centres : tuple of numpy.ndarray
        The cell centres along x (columns) and along y (rows).
    cell : tuple of int
        ``(row, column)``.

    Returns
    -------
    str
    """
    row, column = cell
    state = ", ".join(
        f"{name}={float(values[v, row, column]):.3g}" for v, name in enumerate(model.variables)
    )
    one = (slice(None), slice(row, row + 1), slice(column, column + 1))
    along_x, along_y = _speeds(model, values[one], None if aux is None else aux[one])
    x, y = centres
    return (
        f"cell (column {column}, row {row}) at x={float(x[column]):.6g}, y={float(y[row]):.6g}: "
        f"{state} (wave speeds {float(along_x[0, 0]):.3g} along x, "
        f"{float(along_y[0, 0]):.3g} along y)"
    )
