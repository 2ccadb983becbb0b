"""A model's coefficients at the centres and quarter points of one padded family of cells along
x (the 1D Nessyahu–Tadmor scheme, and the Jiang–Tadmor scheme for a 2D model whose
coefficients vary along x only, such as a chute's inclination and curvature)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from conslaw.grid import Grid
from conslaw.model import Model

Array = NDArray[np.float64]

#: How the ghost cells of a side take their coefficients: from the cell they copy (``wrap``,
#: periodic), the mirror image (``mirror``, a wall), or the edge cell's (``copy``).
GHOST_RULES = ("wrap", "mirror", "copy")


def padded_positions(grid: Grid, offset: float, periodic: bool, ghosts: int) -> Array:
    """Centres of the family with ``offset`` and ``ghosts`` ghost cells on each side,
    continuing the grid's spacing: ``x_min + dx (i - ghosts + 1/2)`` for the primary family,
    ``x_min + dx (i - ghosts)`` for the staggered one (Tai et al. 2001, Fig. 1).

    Parameters
    ----------
    grid : Grid
        The grid along x.
    offset : float
        0 for the primary family, 0.5 for the staggered one.
    periodic : bool
        Whether the grid is periodic (the staggered family then has as many cells).
    ghosts : int
        Ghost cells on each side.

    Returns
    -------
    numpy.ndarray
        The ``n + 2 ghosts`` centres.
    """
    shift = 0.5 if offset == 0.0 else 0.0
    n = grid.n_cells_at(offset, periodic)
    index = np.arange(n + 2 * ghosts, dtype=np.float64)
    return grid.x_min + grid.dx * (index - ghosts + shift)


def coefficient_family(
    model: Model,
    grid: Grid,
    offset: float,
    periodic: bool,
    rules: tuple[str, str],
    ghosts: int,
) -> tuple[Array, Array, Array]:
    """``model.aux`` at the centres, left and right quarter points of one padded family.

    Parameters
    ----------
    model : Model
        Its ``aux(x, width)`` gives the coefficients at the points ``x`` (averaged over cells of
        ``width``) and ``aux_reflect_signs`` their signs in a mirror image.
    grid : Grid
        The grid along x.
    offset : float
        0 for the primary family, 0.5 for the staggered one.
    periodic : bool
        Whether the grid is periodic.
    rules : tuple of str
        The :data:`GHOST_RULES` of the left and the right side.
    ghosts : int
        Ghost cells on each side.

    Returns
    -------
    tuple of numpy.ndarray
        ``(centre, left_quarter, right_quarter)``, each ``(n_aux, n + 2 ghosts)``. Ghost cells
        follow the rule of their side, so that a state the boundary condition reproduces (a
        lake at rest) sees consistent coefficients in its ghosts; a staggered cell centred on a
        wall gets those of its inner half (:func:`_symmetric_wall_cells`).
    """
    x = padded_positions(grid, offset, periodic, ghosts)
    n = grid.n_cells_at(offset, periodic)
    centre = x.copy()
    direction = np.ones_like(x)  # +1: left quarter at centre - dx/4; -1 for mirror images
    signs = np.ones((model.n_aux, x.size))
    odd = np.array(model.aux_reflect_signs or (1.0,) * model.n_aux, dtype=np.float64)
    sides = (
        (rules[0], slice(0, ghosts), grid.x_min, ghosts),
        (rules[1], slice(ghosts + n, x.size), grid.x_max, ghosts + n - 1),
    )
    for rule, cells, boundary, edge in sides:
        if rule == "wrap":
            # The ghost takes the position of the real cell it copies, by index: wrapping
            # positions by the period would put a staggered ghost that lands on the period's
            # end (x = x_max -+ round-off) on the wrong side of it, and a chute or bed that
            # is not periodic would then differ between the ghost and its cell (mass lost).
            index = np.arange(x.size)[cells]
            centre[cells] = x[ghosts + np.mod(index - ghosts, n)]
        elif rule == "mirror":
            centre[cells] = 2.0 * boundary - x[cells]
            direction[cells] = -1.0
            signs[:, cells] = odd[:, None]
        else:
            centre[cells] = x[edge]
    quarter = 0.25 * grid.dx
    result = []
    for points, width in (
        (centre, grid.dx),
        (centre - direction * quarter, 0.5 * grid.dx),
        (centre + direction * quarter, 0.5 * grid.dx),
    ):
        values = np.asarray(model.aux(points, width), dtype=np.float64) * signs
        result.append(np.ascontiguousarray(values))
    if offset != 0.0 and not periodic:
        _symmetric_wall_cells(model, grid, result, n, odd, rules, ghosts)
    return result[0], result[1], result[2]


def _symmetric_wall_cells(
    model: Model,
    grid: Grid,
    aux: list[Array],
    n: int,
    odd: Array,
    rules: tuple[str, str],
    ghosts: int,
) -> None:
    """Staggered cells centred on a wall are half outside the domain, where the state is the
    mirror image: their coefficients are those of the inner half cell (odd rows, slopes,
    vanish) and the outer quarter is the mirror of the inner one."""
    quarter = 0.25 * grid.dx
    half = 0.5 * grid.dx
    for rule, index, inward in ((rules[0], ghosts, 1.0), (rules[1], ghosts + n - 1, -1.0)):
        if rule != "mirror":
            continue
        wall = grid.x_min if inward > 0 else grid.x_max
        inner = np.asarray(model.aux(np.array([wall + inward * quarter]), half))[:, 0]
        centre, left_quarter, right_quarter = aux
        centre[:, index] = np.where(odd < 0, 0.0, inner)
        inner_quarter, outer_quarter = (
            (right_quarter, left_quarter) if inward > 0 else (left_quarter, right_quarter)
        )
        inner_quarter[:, index] = inner
        outer_quarter[:, index] = inner * odd
