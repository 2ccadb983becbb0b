"""The margins of a depth in 2D, tracked: a level set carried by the flow's velocity, and the thin
film a central scheme spreads beyond it gathered back inside (docs/design.md, "Margins in two
dimensions").

A staggered central scheme averages a covered cell with its bare neighbour at every step, so a
film of depth ``1e-6`` and less runs cells ahead of a margin that should move with the material
(a granular margin is material: it moves with the velocity of the flow there; Savage & Hutter
1991, Hutter et al. 1993). The tracker keeps the covered region as ``{level > 0}`` of a signed
distance ``level`` (positive inside, in length units), moved after every step pair by the
advection equation of a material surface (Osher & Sethian 1988; Osher & Fedkiw 2003, ch. 3)::

    d level / dt + u . grad level = 0,

in one semi-Lagrangian step (:func:`advected`) with the mean of the pair's start and end
velocity fields (:meth:`MarginTracker.velocity`: the flow's velocity trusted a few cells inside
the region and extrapolated out to it). Region cells no velocity reaches are dropped, the level
is made a signed distance again near its zero (:func:`reinitialised`), and material the step
put outside is moved, mass and momenta together, to the 4-neighbour nearer the region (split
equally between equally near ones), again until none is outside (:meth:`MarginTracker.gather`):
totals are kept to round-off, no depth becomes negative, and nothing moves more than
:data:`MAX_GATHER` cells.

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

from conslaw.errors import ConfigError, SchemeBreakdownError
from conslaw.grid2d import Grid2D

if TYPE_CHECKING:
    from conslaw.model import Model

Array = NDArray[np.float64]

#: Sub-cells per direction on which the initial data's covered region is found.
REFINE = 4
#: Most cells of that finer grid (beyond, the region starts from the cell averages).
MAX_REFINED_CELLS = 2**20
#: Share of the deepest depth within :data:`LOCAL_REACH` cells from which a cell's velocity
#: may move the level set (a cell deep enough to carry one).
VELOCITY_DEPTH_SHARE = 1e-3
#: Cells around a cell (each way) whose deepest depth decides whether it carries a velocity.
LOCAL_REACH = 8
#: Cells inside the region from which the flow's velocity is trusted to move the margin.
TRUSTED_DEPTH = 3.5
#: Layers of 4-neighbours beyond the trusted cells over which their velocity is extrapolated
#: linearly (zero further out): a layer count is a taxicab distance, so this reaches
#: 12/sqrt(2), about 8.5 cells, along a diagonal, past a margin :data:`TRUSTED_DEPTH` cells out.
EXTRAPOLATION_LAYERS = 12
#: Cells from the margin over which the level set is kept a signed distance after every pair.
BAND = 4
#: Cells from the region beyond which material is not gathered: its cells join the region.
MAX_GATHER = 3


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
    reached : ndarray of bool
        The cells the last :meth:`velocity` gave the flow's velocity (within
        :data:`EXTRAPOLATION_LAYERS` layers of trusted cells); after a pair the region keeps
        none that neither end of it reached.
    joined : int
        Cells that joined the region because material lay more than :data:`MAX_GATHER` cells
        outside it (the margin had lagged the material), over the tracker's life.
    largest_gathered : float
        The largest share of the total depth gathered back in one step pair so far.
    gathered_shift : float
        The distances the gathering moved the centre of mass of the depth, summed over the
        pairs so far (length units): a film gathered from all round a margin hardly moves it,
        material the margin lagged is pushed back against the flow.
    """

    def __init__(self, grid: Grid2D, depth: int, momentum_x: int, momentum_y: int) -> None:
        self.grid = grid
        self.depth, self.momenta = depth, (momentum_x, momentum_y)
        self.level: Array | None = None
        self.reached = np.zeros(grid.shape, dtype=bool)
        self.joined = 0
        self.largest_gathered = 0.0
        self.gathered_shift = 0.0

    def start_from_values(self, q: Array) -> None:
        """The region of the cells of ``q`` with a positive depth, its margin half-way between
        covered and bare cell centres.

        Parameters
        ----------
        q : ndarray
            Primary-family values, ``(n_vars, ny, nx)``.
        """
        self.level = signed_distance(q[self.depth] > 0.0, (self.grid.dy, self.grid.dx))

    def start_from_initial(self, initial: Any, model: Model, q: Array) -> None:
        """The region covered by the initial data, found from its cell averages on a grid
        :data:`REFINE` times finer in each direction and read at this grid's centres (each the
        corner of four fine cells: their mean); every cell ``q`` covers is inside. Where the
        finer grid would exceed :data:`MAX_REFINED_CELLS` cells or the initial data refuse it
        (a release too narrow for its cells), :meth:`start_from_values`.

        Parameters
        ----------
        initial : InitialCondition2D
            The scene's initial condition (its ``cell_averages``).
        model : Model
            The model it is built for.
        q : ndarray
            Its cell averages on this grid, ``(n_vars, ny, nx)``.
        """
        grid = self.grid
        covered = q[self.depth] > 0.0
        if REFINE**2 * covered.size > MAX_REFINED_CELLS:
            self.start_from_values(q)
            return
        fine = Grid2D.from_bounds(
            grid.x.x_min,
            grid.x.x_max,
            REFINE * grid.x.n_cells,
            grid.y.x_min,
            grid.y.x_max,
            REFINE * grid.y.n_cells,
        )
        try:
            fine_covered = initial.cell_averages(fine, model)[self.depth] > 0.0
        except ConfigError:
            self.start_from_values(q)
            return
        level = signed_distance(fine_covered, (fine.dy, fine.dx))
        half = REFINE // 2
        corners = [
            level[rows::REFINE, columns::REFINE]
            for rows in (half - 1, half)
            for columns in (half - 1, half)
        ]
        level = 0.25 * ((corners[0] + corners[3]) + (corners[1] + corners[2]))
        # A covered cell whose corners read outside (its material in a sliver) is inside, its
        # margin at the cell.
        smallest = np.finfo(np.float64).tiny
        self.level = np.where(covered & (level <= 0.0), smallest, level)

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
        reached = self.reached
        u_end, v_end = self.velocity(after)
        reached = reached | self.reached
        level = advected(
            self.level,
            0.5 * (u_start + u_end) * elapsed / self.grid.dx,
            0.5 * (v_start + v_end) * elapsed / self.grid.dy,
        )
        # The region keeps no cell the flow's velocity does not reach: material has left it.
        cell = max(self.grid.dx, self.grid.dy)
        level = np.where((level > 0.0) & ~reached, -cell, level)
        self.level = reinitialised(level, (self.grid.dy, self.grid.dx))
        return self.gather(after)

    def velocity(self, q: Array) -> tuple[Array, Array]:
        """The velocity that moves the level set: the flow's own, ``momentum / depth``, in the
        trusted cells (inside the region by at least :data:`TRUSTED_DEPTH` cells, among the
        cells carrying a velocity: at least :data:`VELOCITY_DEPTH_SHARE` of the deepest depth
        within :data:`LOCAL_REACH` cells), extrapolated linearly from them layer by layer over
        :data:`EXTRAPOLATION_LAYERS` layers of 4-neighbours (each cell of a layer the mean of
        its known neighbours' value plus their gradient times the step to it; gradients by
        central differences over trusted cells, one-sided at their edge), and zero beyond
        (cells so far out that one step pair does not reach the margin). Two more candidates
        are carried out unchanged, layer by layer: the trusted velocity, and the flow's own in
        every carrying cell, in the region or out of it; each cell takes the candidate fastest
        along the outward normal ``-grad level`` (a compressed front keeps the speed of the flow
        behind it, a spreading edge its own).

        The cells near a margin are not trusted because a central scheme's velocity there is
        smoothed to a plateau over its last cells (docs/design.md, "Margins in two
        dimensions"); in a body of material (8-connected carrying cells in the region) thinner
        than that, its farthest inside cells are. :attr:`reached` records the cells the
        trusted velocity reached. Mirrored data
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
        self.reached = np.zeros(h.shape, dtype=bool)
        if not deepest > 0.0:
            return still
        local = ndimage.maximum_filter(h, size=2 * LOCAL_REACH + 1, mode="constant")
        carrying = (h > 0.0) & (h >= VELOCITY_DEPTH_SHARE * local)
        moving = carrying if self.level is None else carrying & (self.level > 0.0)
        if not np.any(moving):
            return still
        # Only the cells within reach of the extrapolation are computed: those further out
        # are zero either way.
        window = _window(carrying, EXTRAPOLATION_LAYERS + 1)
        spacing = (self.grid.dy, self.grid.dx)
        near_moving = moving[window]
        inward = ndimage.distance_transform_edt(near_moving, sampling=spacing) / max(spacing)
        # Each body of material (8-connected) trusts its cells TRUSTED_DEPTH inside, or its
        # farthest inside where it is thinner: a small body beside a large one has its own.
        bodies, count = ndimage.label(near_moving, structure=np.ones((3, 3), dtype=bool))
        reach = np.zeros(count + 1)
        reach[1:] = np.minimum(
            TRUSTED_DEPTH, ndimage.maximum(inward, bodies, np.arange(1, count + 1))
        )
        trusted = near_moving & (inward >= reach[bodies])
        velocities = [
            np.where(trusted, q[row][window], 0.0) / np.where(trusted, h[window], 1.0)
            for row in self.momenta
        ]
        linear, constant, reached = _extrapolated(velocities, trusted)
        self.reached[window] = reached
        if self.level is None:
            chosen = linear
        else:
            # The flow's own velocity in every cell deep enough to carry one, in the region or
            # out, carried out unchanged: a margin that spreads fastest at its edge (a released
            # block) moves with its edge.
            near = carrying[window]
            own = [
                np.where(near, q[row][window], 0.0) / np.where(near, h[window], 1.0)
                for row in self.momenta
            ]
            _, edge_velocity, _ = _extrapolated(own, near)
            chosen = _fastest_outward(
                [linear, constant, edge_velocity], self.level[window], self.grid
            )
        u, v = still
        u[window], v[window] = chosen
        return u, v

    def _add_shift(self, before: Array, after: Array, total: float) -> None:
        """Add to :attr:`gathered_shift` how far gathering moved the centre of mass of the depth
        (``before`` to ``after``, ``total`` its sum)."""
        if not total > 0.0:
            return
        x, y = self.grid.centres()
        change = after - before
        along_x = float(np.sum(change.sum(axis=0) * x)) / total
        along_y = float(np.sum(change.sum(axis=1) * y)) / total
        self.gathered_shift += math.hypot(along_x, along_y)

    def gather(self, q: Array) -> bool:
        """Move, in place, the material of ``q`` outside the region into it: each outside cell
        holding any gives all of its values to the 4-neighbours nearest the region (equal
        shares to equally near ones), sweep after sweep until none is left outside. Material
        more than :data:`MAX_GATHER` cells out is not moved: its cells join the region (the
        margin lagged it; counted in :attr:`joined`), so nothing moves further than that.

        Parameters
        ----------
        q : ndarray
            Primary-family values, ``(n_vars, ny, nx)``, changed in place.

        Returns
        -------
        bool
            Whether anything was moved.
        """
        assert self.level is not None
        spacing = (self.grid.dy, self.grid.dx)
        holding = np.any(q != 0.0, axis=0)
        inside = self.level > 0.0
        if not np.any(holding & ~inside):
            return False
        distance = ndimage.distance_transform_edt(~inside, sampling=spacing)
        far = holding & (distance > MAX_GATHER * max(spacing))
        if np.any(far):
            self.joined += int(np.count_nonzero(far))
            self.level = np.where(far, 0.5 * min(spacing), self.level)
            inside = self.level > 0.0
            distance = ndimage.distance_transform_edt(~inside, sampling=spacing)
        padded = np.pad(distance, 1, constant_values=np.inf)
        # The neighbours' distances: west, east, south, north.
        around = np.stack(
            [padded[1:-1, :-2], padded[1:-1, 2:], padded[:-2, 1:-1], padded[2:, 1:-1]]
        )
        chosen = around == np.min(around, axis=0)
        shares = 1.0 / np.sum(chosen, axis=0)
        depth_before = q[self.depth].copy()
        total = float(np.sum(depth_before))
        if total > 0.0:
            share = float(np.sum(depth_before[~inside])) / total
            self.largest_gathered = max(self.largest_gathered, share)
        moved = False
        # Every outside cell has a 4-neighbour nearer the region: material within MAX_GATHER
        # of the larger cell size reaches it in fewer steps than this many.
        aspect = math.ceil(max(spacing) / min(spacing))
        for _ in range(2 * MAX_GATHER * aspect + 2):
            holding = ~inside & np.any(q != 0.0, axis=0)
            if not np.any(holding):
                self._add_shift(depth_before, q[self.depth], total)
                return moved
            moved = True
            given = np.where(holding, q * shares, 0.0)
            q[:, holding] = 0.0
            q += _received(given, chosen & holding)
        raise SchemeBreakdownError("material is left outside the tracked margins")


def _fastest_outward(candidates: list[list[Array]], level: Array, grid: Grid2D) -> list[Array]:
    """Per cell, the candidate velocity ``[u, v]`` with the largest speed along the outward
    normal ``-grad level`` (central differences; the first of equal ones)."""
    edge = np.pad(level, 1, mode="edge")
    outward_x = -(edge[1:-1, 2:] - edge[1:-1, :-2]) / grid.dx
    outward_y = -(edge[2:, 1:-1] - edge[:-2, 1:-1]) / grid.dy
    best = candidates[0]
    best_speed = best[0] * outward_x + best[1] * outward_y
    for candidate in candidates[1:]:
        speed = candidate[0] * outward_x + candidate[1] * outward_y
        faster = speed > best_speed
        best = [np.where(faster, c, b) for c, b in zip(candidate, best, strict=True)]
        best_speed = np.where(faster, speed, best_speed)
    return best


def _window(mask: NDArray[np.bool_], margin: int) -> tuple[slice, slice]:
    """The rows and columns of the smallest box holding every True cell of ``mask``, widened
    by ``margin`` cells on each side within the array."""
    rows = np.flatnonzero(np.any(mask, axis=1))
    columns = np.flatnonzero(np.any(mask, axis=0))
    return (
        slice(max(int(rows[0]) - margin, 0), int(rows[-1]) + margin + 1),
        slice(max(int(columns[0]) - margin, 0), int(columns[-1]) + margin + 1),
    )


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


def _extrapolated(
    velocities: list[Array], trusted: NDArray[np.bool_]
) -> tuple[list[Array], list[Array], NDArray[np.bool_]]:
    """Each of ``velocities`` at the ``trusted`` cells, extrapolated beyond them linearly and
    as a constant over :data:`EXTRAPOLATION_LAYERS` layers of 4-neighbours and zero further
    out (see :meth:`MarginTracker.velocity`): ``(linear, constant, reached)``, one array per
    velocity in each of the first two, and the cells the layers reached. All are carried
    through the layers together, as channels of one array (per velocity: the linear value, its
    gradient along x and y, the constant value); the neighbours' guesses are summed in mirror
    pairs."""
    channels = []
    for u in velocities:
        slope_x, slope_y = _trusted_differences(u, trusted)
        channels += [u, slope_x, slope_y, u]
    values = np.stack(channels)
    linear = np.arange(0, values.shape[0], 4)
    known = trusted.copy()
    for _ in range(EXTRAPOLATION_LAYERS):
        padded = np.pad(values, ((0, 0), (1, 1), (1, 1)))
        have = np.pad(known, 1)
        guesses = []
        # Each neighbour's guess of this cell: its channels, the linear value plus its
        # gradient times the step here (+1 column from the west, -1 from the east, ...).
        for rows, columns, slope, sign in (
            (slice(1, -1), slice(None, -2), 1, 1.0),  # from the west
            (slice(1, -1), slice(2, None), 1, -1.0),  # from the east
            (slice(None, -2), slice(1, -1), 2, 1.0),  # from the south
            (slice(2, None), slice(1, -1), 2, -1.0),  # from the north
        ):
            neighbour = padded[:, rows, columns].copy()
            neighbour[linear] += sign * neighbour[linear + slope]
            guesses.append(np.where(have[rows, columns], neighbour, 0.0))
        count = (
            have[1:-1, :-2].astype(np.float64) + have[1:-1, 2:] + have[:-2, 1:-1] + have[2:, 1:-1]
        )
        layer = ~known & (count > 0.0)
        if not np.any(layer):
            break
        total = (guesses[0] + guesses[1]) + (guesses[2] + guesses[3])
        values = np.where(layer, total / np.maximum(count, 1.0), values)
        known |= layer
    values = np.where(known, values, 0.0)
    return [values[k] for k in linear], [values[k + 3] for k in linear], known


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
    half-way between a covered and a bare centre: positive inside, negative outside,
    ``d(c) - s/2`` for a covered centre ``c`` whose nearest bare centre is ``d(c)`` away (and
    the mirror of it outside), ``s`` the smaller cell size; the Euclidean distances are
    scipy's exact transform (``scipy.ndimage.distance_transform_edt``).

    Parameters
    ----------
    covered : ndarray of bool
        ``(ny, nx)``.
    spacing : (float, float)
        The cell sizes ``(dy, dx)``.

    Returns
    -------
    ndarray
        ``(ny, nx)``; ``+-(BAND + 1)`` of the larger cell size everywhere if every cell is
        covered or none is.
    """
    if np.all(covered) or not np.any(covered):
        far = (BAND + 1) * max(spacing)
        return np.full(covered.shape, far if np.all(covered) else -far)
    half = 0.5 * min(spacing)
    inner = ndimage.distance_transform_edt(covered, sampling=spacing)
    outer = ndimage.distance_transform_edt(~covered, sampling=spacing)
    return np.where(covered, inner - half, half - outer)


def reinitialised(level: Array, spacing: tuple[float, float]) -> Array:
    """``level`` made a signed distance again near its zero contour, which it keeps: each cell
    with a 4-neighbour of the other sign takes ``|level| / |grad level|`` (central differences)
    or, where it is one cell thin (the other sign on both sides along an axis, where central
    differences see no slope), its distance to the line through the nearest zero crossings
    along x and along y (each interpolated linearly towards a neighbour of the other sign;
    ``a b / sqrt(a^2 + b^2)`` for crossings ``a`` and ``b``, the one alone where there is one);
    at most a cell, its sign kept (the sub-cell rule of Russo & Smereka 2000, which keeps the
    zero where it was). The cells within :data:`BAND` cells of those take the
    distance through 8-neighbours (a chamfer distance, exact along the axes and diagonals);
    cells further out take ``-+(BAND + 1)`` cells. The chamfer pass is written here because
    scipy's transforms start from a mask, not from the sub-cell distances of the cells at the
    margin (Borgefors 1986 for chamfer distances).

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
    far = (BAND + 1) * max(spacing)
    near, across = _margin_distances(level, inside, spacing)
    distance = np.where(across, near, far)
    dy, dx = spacing
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


def _margin_distances(
    level: Array, inside: NDArray[np.bool_], spacing: tuple[float, float]
) -> tuple[Array, NDArray[np.bool_]]:
    """The distance to the zero of ``level`` of every cell with a 4-neighbour of the other sign
    (see :func:`reinitialised`), and where those cells are."""
    dy, dx = spacing
    cell = max(spacing)
    # Where the zero crosses to each 4-neighbour of the other sign (linear interpolation): the
    # nearest crossing along x and along y, and whether both sides along one axis cross.
    size = np.abs(level)
    padded_size = np.pad(size, 1, constant_values=np.inf)
    padded_inside = np.pad(inside, 1, mode="edge")
    crossings, thin = [], np.zeros(level.shape, dtype=bool)
    for step, neighbours in (
        (dx, ((slice(1, -1), slice(None, -2)), (slice(1, -1), slice(2, None)))),
        (dy, ((slice(None, -2), slice(1, -1)), (slice(2, None), slice(1, -1)))),
    ):
        nearest = np.full(level.shape, np.inf)
        sides = np.zeros(level.shape, dtype=np.int64)
        for rows, columns in neighbours:
            other = padded_inside[rows, columns] != inside
            with np.errstate(invalid="ignore"):
                share = size / (size + padded_size[rows, columns])
            nearest = np.where(other, np.minimum(nearest, share * step), nearest)
            sides += other
        crossings.append(nearest)
        thin |= sides == 2
    along_x, along_y = crossings
    across = np.isfinite(along_x) | np.isfinite(along_y)
    # Across a smooth margin: |level| / |grad level| (central differences); across a feature
    # one cell thin, where central differences see no slope: the distance to the line through
    # the crossings, a b / sqrt(a^2 + b^2) (the one crossing alone where there is one).
    edge = np.pad(level, 1, mode="edge")
    gradient = np.hypot(
        0.5 * (edge[1:-1, 2:] - edge[1:-1, :-2]) / dx, 0.5 * (edge[2:, 1:-1] - edge[:-2, 1:-1]) / dy
    )
    steep = gradient * cell > size
    smooth = np.where(steep, size / np.where(steep, gradient, 1.0), cell)
    both = np.isfinite(along_x) & np.isfinite(along_y)
    with np.errstate(invalid="ignore"):
        oblique = along_x * along_y / np.hypot(along_x, along_y)
    lines = np.where(both, oblique, np.minimum(along_x, along_y))
    near = np.clip(np.where(thin, lines, smooth), np.finfo(np.float64).tiny, cell)
    return near, across


def advected(level: Array, shift_x: Array, shift_y: Array) -> Array:
    """``level`` moved by a semi-Lagrangian step of ``d level/dt + u . grad level = 0``:
    ``level_new(x) = level(x - u dt)``, its bilinear interpolant (scipy's
    ``ndimage.map_coordinates``, order 1) at the feet ``(column - shift_x, row - shift_y)`` of
    the characteristics (shifts ``u dt`` in cells; Staniforth & Côté 1991); values beyond the
    grid those of its nearest edge cell. Exact for a plane ``level``.

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
    rows, columns = np.indices(level.shape, dtype=np.float64)
    return ndimage.map_coordinates(
        level, [rows - shift_y, columns - shift_x], order=1, mode="nearest"
    )
