"""The margins of a depth in 2D, tracked: a level set carried by the flow's velocity, and the thin
film a central scheme spreads beyond it gathered back inside (docs/design.md, "Margins in two
dimensions").

A staggered central scheme averages a covered cell with its bare neighbour at every step, so a
film of depth ``1e-6`` and less runs cells ahead of a margin that should move with the material
(a granular margin is material: it moves with the velocity of the flow there; Savage & Hutter
1991, Hutter et al. 1993). The tracker keeps the covered region as ``{level > 0}`` of a signed
distance ``level`` (positive inside, in length units), moved after every step pair by the
advection equation of a material surface (Osher & Sethian 1988)::

    d level / dt + u . grad level = 0,

with ``u`` the flow's velocity where the depth is at least :data:`VELOCITY_DEPTH_SHARE` of the
deepest cell and that of the nearest such cell elsewhere, taken as the mean of the pair's start
and end (a semi-Lagrangian step: ``level`` at the foot of the characteristic, interpolated
bilinearly, exact for a plane level). Material the step put outside is then moved, mass and
momenta together, to the 4-neighbour nearer the covered region (split equally between equally
near ones), again until none is outside: totals are kept to round-off and no depth becomes
negative.

The region starts as the initial data's covered region resolved on a grid :data:`REFINE` times
finer (:meth:`MarginTracker.start_from_initial`), so the margin starts within an eighth of a cell
of the data's, or, for values alone, half-way between covered and bare cell centres.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from conslaw.grid2d import Grid2D

if TYPE_CHECKING:
    from conslaw.model import Model

Array = NDArray[np.float64]

#: Sub-cells per direction on which the initial data's covered region is found.
REFINE = 4
#: Share of the deepest cell's depth from which a cell's velocity may move the level set.
VELOCITY_DEPTH_SHARE = 1e-3
#: Cells inside the region from which the flow's velocity is trusted to move the margin.
TRUSTED_DEPTH = 3.5
#: Layers of 4-neighbours beyond the trusted cells over which their velocity is extrapolated
#: linearly (zero further out): a layer count is a taxicab distance, so this reaches
#: 12/sqrt(2), about 8.5 cells, along a diagonal, past a margin :data:`TRUSTED_DEPTH` cells out.
EXTRAPOLATION_LAYERS = 12
#: Cells from the margin over which the level set is kept a signed distance after every pair.
BAND = 4
#: Most sweeps of gathering: material further out than this many cells is a tracker failure.
MAX_SWEEPS = 64


class MarginTracker:
    """The covered region of a 2D depth, ``{level > 0}``, moved with the flow; material outside
    it gathered back in.

    Parameters
    ----------
    grid : Grid2D
        The primary grid of the scheme.
    depth, momentum_x, momentum_y : int
        The rows of the depth and of the two momenta (the velocity is momentum / depth).

    Attributes
    ----------
    level : ndarray or None
        The signed distance to the margin (positive inside, length units) at the cell centres,
        ``(ny, nx)``; None before a start.
    """

    def __init__(self, grid: Grid2D, depth: int, momentum_x: int, momentum_y: int) -> None:
        self.grid = grid
        self.depth, self.momenta = depth, (momentum_x, momentum_y)
        self.level: Array | None = None

    def start_from_values(self, q: Array) -> None:
        """The region of the cells of ``q`` with a positive depth, its margin half-way between
        covered and bare cell centres.

        Parameters
        ----------
        q : ndarray
            Primary-family values, ``(n_vars, ny, nx)``.
        """
        self.level = signed_distance(q[self.depth] > 0.0, (self.grid.dy, self.grid.dx))

    def start_from_initial(self, initial: Any, model: Model) -> None:
        """The region covered by the initial data, found from its cell averages on a grid
        :data:`REFINE` times finer in each direction and read at this grid's centres (each the
        corner of four fine cells: their mean).

        Parameters
        ----------
        initial : InitialCondition2D
            The scene's initial condition (its ``cell_averages``).
        model : Model
            The model it is built for.
        """
        grid = self.grid
        fine = Grid2D.from_bounds(
            grid.x.x_min,
            grid.x.x_max,
            REFINE * grid.x.n_cells,
            grid.y.x_min,
            grid.y.x_max,
            REFINE * grid.y.n_cells,
        )
        covered = initial.cell_averages(fine, model)[self.depth] > 0.0
        level = signed_distance(covered, (fine.dy, fine.dx))
        half = REFINE // 2
        corners = [
            level[rows::REFINE, columns::REFINE]
            for rows in (half - 1, half)
            for columns in (half - 1, half)
        ]
        self.level = 0.25 * ((corners[0] + corners[3]) + (corners[1] + corners[2]))

    def follow(self, before: Array, after: Array, elapsed: float) -> bool:
        """Move the region over a step pair of length ``elapsed`` from ``before`` to ``after``,
        then gather into it, in place, the material of ``after`` outside it.

        Parameters
        ----------
        before, after : ndarray
            The primary-family values at the start and at the end of the pair.
        elapsed : float
            The pair's length of time.

        Returns
        -------
        bool
            Whether any material was moved (``after`` changed).
        """
        if self.level is None:
            self.start_from_values(before)
        assert self.level is not None
        u_start, v_start = self.velocity(before)
        u_end, v_end = self.velocity(after)
        self.level = reinitialised(
            advected(
                self.level,
                0.5 * (u_start + u_end) * elapsed / self.grid.dx,
                0.5 * (v_start + v_end) * elapsed / self.grid.dy,
            ),
            (self.grid.dy, self.grid.dx),
        )
        return self.gather(after)

    def velocity(self, q: Array) -> tuple[Array, Array]:
        """The velocity that moves the level set: the flow's own, ``momentum / depth``, in the
        trusted cells (inside the region by at least :data:`TRUSTED_DEPTH` cells and at least
        :data:`VELOCITY_DEPTH_SHARE` of the deepest cell's depth), extrapolated linearly from
        them layer by layer over :data:`EXTRAPOLATION_LAYERS` layers of 4-neighbours (each cell
        of a layer the mean of its known neighbours' value plus their gradient times the step to
        it; gradients by central differences over trusted cells, one-sided at their edge), and
        zero beyond (cells so far out that one step pair does not reach the margin). Where the
        linear extrapolation is slower along the outward normal (``-grad level``) than the
        trusted velocity carried out unchanged, as behind a compressed front or a bore, the
        unchanged one is taken: a margin never lags the flow behind it.

        The cells near a margin are not trusted because a central scheme's velocity there is
        smoothed to a plateau over its last cells (docs/design.md, "Margins in two
        dimensions"); where no cell is that far inside, the farthest inside are. Mirrored data
        give mirrored velocities bit for bit.

        Parameters
        ----------
        q : ndarray
            Primary-family values, ``(n_vars, ny, nx)``.

        Returns
        -------
        u, v : ndarray
            The two components, ``(ny, nx)`` each.
        """
        h = q[self.depth]
        deepest = float(np.max(h))
        still = np.zeros_like(h), np.zeros_like(h)
        if not deepest > 0.0:
            return still
        spacing = (self.grid.dy, self.grid.dx)
        moving = h >= VELOCITY_DEPTH_SHARE * deepest
        if self.level is not None:
            moving &= self.level > 0.0
        if not np.any(moving):
            return still
        inward = ndimage.distance_transform_edt(moving, sampling=spacing) / max(spacing)
        trusted = inward >= min(TRUSTED_DEPTH, float(np.max(inward)))
        linear, constant = [], []
        for row in self.momenta:
            u = np.where(trusted, q[row], 0.0) / np.where(trusted, h, 1.0)
            linear.append(_extrapolated(u, trusted, sloped=True))
            constant.append(_extrapolated(u, trusted, sloped=False))
        if self.level is None:
            return linear[0], linear[1]
        # Outward normal speeds: a margin the extrapolation would slow (a compressed front, a
        # bore) keeps the speed of the flow behind it instead.
        edge = np.pad(self.level, 1, mode="edge")
        outward_x = -(edge[1:-1, 2:] - edge[1:-1, :-2]) / self.grid.dx
        outward_y = -(edge[2:, 1:-1] - edge[:-2, 1:-1]) / self.grid.dy
        faster = (linear[0] - constant[0]) * outward_x + (linear[1] - constant[1]) * outward_y
        take = faster >= 0.0
        return np.where(take, linear[0], constant[0]), np.where(take, linear[1], constant[1])

    def gather(self, q: Array) -> bool:
        """Move, in place, the material of ``q`` outside the region into it: each outside cell
        holding any gives all of its values to the 4-neighbours nearest the region (equal
        shares to equally near ones), sweep after sweep until none is left outside.

        Parameters
        ----------
        q : ndarray
            Primary-family values, ``(n_vars, ny, nx)``, changed in place.

        Returns
        -------
        bool
            Whether anything was moved.

        Raises
        ------
        RuntimeError
            If material is left outside after :data:`MAX_SWEEPS` sweeps (cannot happen while
            the region is not empty: every outside cell has a neighbour nearer it).
        """
        assert self.level is not None
        inside = self.level > 0.0
        if not np.any(inside):
            return False
        distance = ndimage.distance_transform_edt(~inside, sampling=(self.grid.dy, self.grid.dx))
        padded = np.pad(distance, 1, constant_values=np.inf)
        # The neighbours' distances: west, east, south, north.
        around = np.stack(
            [padded[1:-1, :-2], padded[1:-1, 2:], padded[:-2, 1:-1], padded[2:, 1:-1]]
        )
        nearest = np.min(around, axis=0)
        chosen = around == nearest
        shares = 1.0 / np.sum(chosen, axis=0)
        moved = False
        for _ in range(MAX_SWEEPS):
            holding = ~inside & np.any(q != 0.0, axis=0)
            if not np.any(holding):
                return moved
            moved = True
            given = np.where(holding, q * shares, 0.0)
            q[:, holding] = 0.0
            q += _received(given, chosen & holding)
        raise RuntimeError("material is left outside the tracked margins")


def _trusted_differences(u: Array, trusted: NDArray[np.bool_]) -> tuple[Array, Array]:
    """The changes of ``u`` per cell along x and along y at the trusted cells: central
    differences where both neighbours are trusted, one-sided where one is, 0 where none is (and
    outside the trusted cells)."""
    padded, known = np.pad(u, 1), np.pad(trusted, 1)
    differences = []
    for lower, upper, lower_known, upper_known in (
        (padded[1:-1, :-2], padded[1:-1, 2:], known[1:-1, :-2], known[1:-1, 2:]),
        (padded[:-2, 1:-1], padded[2:, 1:-1], known[:-2, 1:-1], known[2:, 1:-1]),
    ):
        central = 0.5 * (upper - lower)
        one_sided = np.where(upper_known, upper - u, np.where(lower_known, u - lower, 0.0))
        change = np.where(lower_known & upper_known, central, one_sided)
        differences.append(np.where(trusted, change, 0.0))
    return differences[0], differences[1]


def _extrapolated(u: Array, trusted: NDArray[np.bool_], sloped: bool) -> Array:
    """``u`` at the ``trusted`` cells, extrapolated beyond them (linearly if ``sloped``, else
    as a constant) over :data:`EXTRAPOLATION_LAYERS` layers of 4-neighbours and zero further
    out (see :meth:`MarginTracker.velocity`); the neighbours' contributions are summed in
    mirror pairs."""
    if sloped:
        slope_x, slope_y = _trusted_differences(u, trusted)
    else:
        slope_x, slope_y = np.zeros_like(u), np.zeros_like(u)
    values, known = u.copy(), trusted.copy()
    for _ in range(EXTRAPOLATION_LAYERS):
        if np.all(known):
            break
        padded = [np.pad(array, 1) for array in (values, slope_x, slope_y)]
        have = np.pad(known, 1)
        value, gx, gy = padded
        # Each neighbour's guess of this cell: its value plus its gradient times the step here.
        guesses = (
            (have[1:-1, :-2], value[1:-1, :-2] + gx[1:-1, :-2], 1),  # from the west
            (have[1:-1, 2:], value[1:-1, 2:] - gx[1:-1, 2:], 1),  # from the east
            (have[:-2, 1:-1], value[:-2, 1:-1] + gy[:-2, 1:-1], 2),  # from the south
            (have[2:, 1:-1], value[2:, 1:-1] - gy[2:, 1:-1], 2),  # from the north
        )
        neighbours = [
            (
                np.where(mask, guess, 0.0),
                np.where(mask, source_x, 0.0),
                np.where(mask, source_y, 0.0),
            )
            for (mask, guess, _), source_x, source_y in zip(
                guesses,
                (gx[1:-1, :-2], gx[1:-1, 2:], gx[:-2, 1:-1], gx[2:, 1:-1]),
                (gy[1:-1, :-2], gy[1:-1, 2:], gy[:-2, 1:-1], gy[2:, 1:-1]),
                strict=True,
            )
        ]
        count = sum(mask.astype(np.float64) for mask, _, _ in guesses)
        layer = ~known & (count > 0.0)
        if not np.any(layer):
            break
        totals = [
            (neighbours[0][k] + neighbours[1][k]) + (neighbours[2][k] + neighbours[3][k])
            for k in range(3)
        ]
        share = np.where(layer, 1.0 / np.maximum(count, 1.0), 0.0)
        values = np.where(layer, totals[0] * share, values)
        slope_x = np.where(layer, totals[1] * share, slope_x)
        slope_y = np.where(layer, totals[2] * share, slope_y)
        known |= layer
    return np.where(known, values, 0.0)


def _received(given: Array, chosen: NDArray[np.bool_]) -> Array:
    """What every cell receives from its 4-neighbours' ``given`` values where they chose it
    (``chosen[k]``: the giving cell chose its neighbour k = west, east, south, north), summed in
    mirror pairs so that mirrored data receive mirrored sums bit for bit."""
    parts = [np.where(chosen[k], given, 0.0) for k in range(4)]
    received = [np.zeros_like(given) for _ in range(4)]
    # A cell's west neighbour gives to its east (k = 1), and so on.
    received[0][..., :, 1:] = parts[1][..., :, :-1]  # from the west
    received[1][..., :, :-1] = parts[0][..., :, 1:]  # from the east
    received[2][..., 1:, :] = parts[3][..., :-1, :]  # from the south
    received[3][..., :-1, :] = parts[2][..., 1:, :]  # from the north
    return (received[0] + received[1]) + (received[2] + received[3])


def signed_distance(covered: NDArray[np.bool_], spacing: tuple[float, float]) -> Array:
    """The signed distance of cell centres to the boundary of the ``covered`` cells, taken
    half-way between a covered and a bare centre: positive inside, negative outside.

    Parameters
    ----------
    covered : ndarray of bool
        ``(ny, nx)``.
    spacing : (float, float)
        The cell sizes ``(dy, dx)``.

    Returns
    -------
    ndarray
        ``(ny, nx)``; all ``+inf`` if every cell is covered, ``-inf`` if none is.
    """
    if np.all(covered):
        return np.full(covered.shape, np.inf)
    if not np.any(covered):
        return np.full(covered.shape, -np.inf)
    half = 0.5 * min(spacing)
    inner = ndimage.distance_transform_edt(covered, sampling=spacing)
    outer = ndimage.distance_transform_edt(~covered, sampling=spacing)
    return np.where(covered, inner - half, half - outer)


def reinitialised(level: Array, spacing: tuple[float, float]) -> Array:
    """``level`` made a signed distance again near its zero contour, which it keeps: each cell
    with a 4-neighbour of the other sign takes ``level / |grad level|`` (central differences,
    at most one cell in size, its sign kept), and the cells within :data:`BAND` cells of those
    the distance through 8-neighbours (a chamfer distance, exact along the axes and
    diagonals); cells further out take ``-+(BAND + 1)`` cells.

    Parameters
    ----------
    level : ndarray
        ``(ny, nx)``.
    spacing : (float, float)
        The cell sizes ``(dy, dx)``.

    Returns
    -------
    ndarray
        The new level, ``(ny, nx)``; ``level`` itself if it has no zero contour.
    """
    inside = level > 0.0
    if np.all(inside) or not np.any(inside):
        return level
    dy, dx = spacing
    cell = min(spacing)
    padded_inside = np.pad(inside, 1, mode="edge")
    across = (
        (padded_inside[1:-1, :-2] != inside)
        | (padded_inside[1:-1, 2:] != inside)
        | (padded_inside[:-2, 1:-1] != inside)
        | (padded_inside[2:, 1:-1] != inside)
    )
    edge = np.pad(level, 1, mode="edge")
    gradient = np.hypot(
        0.5 * (edge[1:-1, 2:] - edge[1:-1, :-2]) / dx, 0.5 * (edge[2:, 1:-1] - edge[:-2, 1:-1]) / dy
    )
    far = (BAND + 1) * cell
    steep = gradient * cell > np.abs(level)
    near = np.where(steep, np.abs(level) / np.where(steep, gradient, 1.0), cell)
    near = np.maximum(near, np.finfo(np.float64).tiny)
    distance = np.where(across, near, far)
    steps = [
        (rows, columns, math.hypot(rows * dy, columns * dx))
        for rows in (-1, 0, 1)
        for columns in (-1, 0, 1)
        if rows or columns
    ]
    for _ in range(BAND):
        padded = np.pad(distance, 1, constant_values=far)
        shorter = [
            padded[
                1 + rows : padded.shape[0] - 1 + rows, 1 + columns : padded.shape[1] - 1 + columns
            ]
            + step
            for rows, columns, step in steps
        ]
        distance = np.minimum(distance, np.minimum.reduce(shorter))
    return np.where(inside, distance, -distance)


def advected(level: Array, shift_x: Array, shift_y: Array) -> Array:
    """``level`` moved by a semi-Lagrangian step: its bilinear interpolant at the feet
    ``(column - shift_x, row - shift_y)`` of the characteristics (shifts in cells); values
    beyond the grid those of its nearest edge cell.

    Parameters
    ----------
    level : ndarray
        ``(ny, nx)``.
    shift_x, shift_y : ndarray
        The displacements over the step in cells, ``(ny, nx)`` each.

    Returns
    -------
    ndarray
        The new level, ``(ny, nx)``.
    """
    if not np.all(np.isfinite(level)):
        return level
    rows, columns = np.indices(level.shape, dtype=np.float64)
    return ndimage.map_coordinates(
        level, [rows - shift_y, columns - shift_x], order=1, mode="nearest"
    )
