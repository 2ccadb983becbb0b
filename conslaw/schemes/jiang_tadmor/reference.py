"""The Jiang–Tadmor staggered central step in numpy (Jiang & Tadmor 1998, SIAM J. Sci. Comput.
19, 1892–1917, the 2D form of the Nessyahu–Tadmor scheme of Tai et al. 2001, eqs. 10–15).

Cell averages alternate between the primary cells and the cells staggered by half a cell in both
directions (:class:`~conslaw.grid2d.Grid2D`). A new cell is centred on the common corner of four
source cells ``a`` (lower left), ``b`` (lower right), ``c`` (upper left), ``d`` (upper right),
with undivided slopes ``w'`` in x and ``w*`` in y (``w(x, y) = w + w' (x - x_j)/dx + w* (y -
y_k)/dy`` in each source cell)::

    w_new = (a + b + c + d)/4 + ((w'_a - w'_b) + (w'_c - w'_d))/16
            + ((w*_a - w*_c) + (w*_b - w*_d))/16
            - dt/(2 dx) ((f(p_b) - f(p_a)) + (f(p_d) - f(p_c)))
            - dt/(2 dy) ((g(p_c) - g(p_a)) + (g(p_d) - g(p_b)))
    p = w + dt/2 (-A(w) w'/dx - B(w) w*/dy)                   (the predictor at t + dt/2)

the fluxes through each half edge taken by the midpoint rule in time and along the edge. The sums
are grouped so that data that do not depend on y give the 1D Nessyahu–Tadmor step bit for bit
(``(a + b + a + b)/4 = (a + b)/2``, the y terms cancel exactly). The time step keeps the Courant
number below 1/2 in each direction, ``dt max|a_x| / dx`` and ``dt max|a_y| / dy``: then no wave
from the corner cells reaches the edges of the new cell, whose flux integrals use the corner
values only (Jiang & Tadmor 1998, section 2).

The reference is written for testing the compiled 2D kernel, not for speed. Boundaries per side:
periodic (on both sides of a direction), outflow (zero gradient) or wall (the mirror image, with
the signs ``Model.reflect_signs`` across an x wall and ``Model.reflect_signs_y`` across a y wall,
as the 1D ``wall`` condition: a primary family mirrors about the cell face, a staggered one about
the centre of its end cell, which straddles the wall).

A depth-averaged model (``depth_index``, ``momentum_index``, ``momentum_y_index``) gets the 1D
depth rules in both directions (docs/design.md, "Depth-averaged models: dry states and
positivity"): the depth reconstructed through the surface ``depth + bed`` with the bed's quarter
averages (:mod:`conslaw.schemes.jiang_tadmor.bed`, the twist term added to the new depth), the
depth's slopes and twist scaled down together until every quarter keeps at least half the depth
(a slope alone is clipped to ``2 h`` as in 1D), each momentum slope bounded by the velocities of
the cell and its two neighbours along that direction, the source ``s(w)`` in the predictor, the
well-balanced source
of each pair of centres along x (``balanced_source_point``) and along y
(``balanced_source_y_point``) averaged over the two pairs of the new cell::

    + dt/2 (S_x(p_a, p_b) + S_x(p_c, p_d)) + dt/2 (S_y(p_a, p_c) + S_y(p_b, p_d))

then the model's correction, and the velocity bound of thin tails over the 4 x 4 cells a new
cell reads. :meth:`JiangTadmorReference.advance` redoes a step pair with half the time step while
a depth would become negative (no clipping). Data that do not depend on y take the 1D steps of
``NessyahuTadmor.reference_step`` bit for bit here too.

Still water against dry land stays still to round-off (docs/design.md, "Toward two
dimensions"): a still cell (every velocity below ``STILL`` times its wave speed) that is partly
flooded is read as still water over flat quarters (:meth:`JiangTadmorReference._effective_bed`),
dry land beside water sets no surface gradient (:meth:`JiangTadmorReference._surface_data`), and
a still cell's quarters may be empty where the predicted fluxes drain nothing
(:meth:`JiangTadmorReference._drain_floors`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from conslaw.boundary import builtin_boundary_conditions
from conslaw.errors import ConfigError, SchemeBreakdownError
from conslaw.grid import Grid
from conslaw.grid2d import Grid2D
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor
from conslaw.reconstruct.base import STENCIL_HALF_WIDTH
from conslaw.schemes.coefficient_families import coefficient_family, padded_positions
from conslaw.schemes.depth_rules import velocity_bounded_slope
from conslaw.schemes.jiang_tadmor.bed import (
    QUARTER_SIGNS,
    family_bed,
    flooded_level,
    quarter_averages,
    quarters_of_rows,
    rows_of_quarters,
    still_water_depth,
)
from conslaw.schemes.jiang_tadmor.constants import QUARTER_MARGIN, SPEED_MARGIN, STILL, TINY
from conslaw.schemes.jiang_tadmor.quarter_sources import (
    CORNERS,
    add_quarter_terms,
    corners,
    resist,
)
from conslaw.schemes.nessyahu_tadmor.constants import (
    DEPTH_SLOPE_LIMIT,
    FILM,
    MAX_RETRIES,
    ROUND_OFF,
)

Array = NDArray[np.float64]

#: Ghost cells per side: the slope stencil's half width and the staggered shift.
GHOSTS = STENCIL_HALF_WIDTH + 1
#: Courant number per direction that a step must stay below.
CFL_LIMIT = 0.5
SIDES = ("left", "right", "bottom", "top")
KINDS = ("periodic", "outflow", "wall", "inflow")
#: Smallest time step, in units of ``dx``, before a run whose depths stay negative stops.
DT_FLOOR = 1e-14


def _columns(array: Array) -> Array:
    """``array`` with every axis after the first flattened into one (rows of cells, in C
    order; an array of no rows too)."""
    return array.reshape(array.shape[0], int(np.prod(array.shape[1:])))


def _window_extreme(values: Array, take_max: bool, width: int = 4) -> Array:
    """The largest (or smallest) value over every ``width`` x ``width`` block of ``values``
    (last two axes): the running extreme along the columns, then along the rows (the same
    values as a reduction over each block, in ``2 (width - 1)`` whole-array operations)."""
    pick = np.maximum if take_max else np.minimum
    rows = values.shape[-2] - width + 1
    columns = values.shape[-1] - width + 1
    along = values[..., :, :columns]
    for k in range(1, width):
        along = pick(along, values[..., :, k : k + columns])
    result = along[..., :rows, :]
    for k in range(1, width):
        result = pick(result, along[..., k : k + rows, :])
    return result


def _neighbour_range(u: Array, rows: slice, columns: slice, axis: int) -> tuple[Array, Array]:
    """Smallest and largest ``u`` of each cell ``u[rows, columns]`` and its two neighbours along
    ``axis`` (0: y, 1: x)."""
    shifted = []
    for shift in (-1, 0, 1):
        r = slice(rows.start + shift, rows.stop + shift) if axis == 0 else rows
        c = slice(columns.start + shift, columns.stop + shift) if axis == 1 else columns
        shifted.append(u[r, c])
    low = np.minimum(np.minimum(shifted[0], shifted[1]), shifted[2])
    high = np.maximum(np.maximum(shifted[0], shifted[1]), shifted[2])
    return low, high


def quarter_velocity_outside(
    h: Array,
    momentum: Array,
    depth_slopes: tuple[Array, Array, Array],
    momentum_slopes: tuple[Array, Array],
    low: Array,
    high: Array,
) -> Array:
    """Whether the velocity of a wet quarter cell, ``(m + (sx m' + sy m*)/4) / (h + (sx h' + sy
    h* + sx sy t)/4)``, falls outside ``[low, high]`` in any of the four quarters of each cell
    (``t`` the depth's twist), compared as momenta: outside by more than ``QUARTER_MARGIN`` times
    the depth and the largest velocity of the range, plus the smallest normal number (below it a
    momentum has lost its relative precision: velocities of 1e-308 in a depth of 1e-9).

    The 1D bound along each direction keeps the velocities at the quarter points *along* it in
    range, not those of the corner quarters that a staggered 2D cell takes: with independent WENO
    slopes of depth and momentum in a thin film a corner quarter can hold a velocity far outside
    (a column collapsing onto a dry bed with ``weno3`` grew velocities of 20 in films of 1e-8,
    docs/design.md, "Toward two dimensions"). Data that vary along one axis never trip it.
    """
    along_x, along_y, twist = depth_slopes
    momentum_x, momentum_y = momentum_slopes
    largest = QUARTER_MARGIN * np.maximum(np.abs(low), np.abs(high))
    outside = np.zeros(h.shape, dtype=bool)
    for sx, sy in QUARTER_SIGNS:
        depth = h + 0.25 * (sx * along_x + sy * along_y + (sx * sy) * twist)
        moment = momentum + 0.25 * (sx * momentum_x + sy * momentum_y)
        slack = largest * depth + TINY
        outside |= (depth > 0.0) & (
            (moment < low * depth - slack) | (moment > high * depth + slack)
        )
    return outside


def metric_speed(u: Array, v: Array, slopes: tuple[Array, Array] | None) -> Array:
    """The speed of map velocity ``(u, v)``: ``(u^2 + v^2)^(1/2)``, or with a surface gradient
    ``slopes = (b_x, b_y)`` the speed in the surface, ``(u^2 + v^2 + (b_x u + b_y v)^2)^(1/2)``
    (``Model.tangent_slope_rows``; docs/design.md, "Savage–Hutter on terrain")."""
    squared = u * u + v * v
    if slopes is not None:
        along = slopes[0] * u + slopes[1] * v
        squared = squared + along * along
    return np.sqrt(squared)


def _pair_of(velocities: list[Array]) -> tuple[Array, Array]:
    """The x and y velocities of a model with one or two momenta (a missing one 0)."""
    if len(velocities) == 1:
        return velocities[0], np.zeros_like(velocities[0])
    return velocities[0], velocities[1]


def inflow_states(
    model: Model, boundaries: Mapping[str, str], given: Mapping[str, Sequence[float]]
) -> dict[str, Array]:
    """The state of every inflow side (``boundary.SIDE = { kind = "inflow", state = [...] }``),
    checked: one finite number per variable, admissible for ``model``; a state for a side that
    is not an inflow, or an inflow side without one, is a ConfigError naming the side."""
    states = {}
    for side, kind in boundaries.items():
        if (kind == "inflow") != (side in given):
            raise ConfigError(
                f"boundary.{side}: an inflow side needs state = [...] with one number per "
                f"variable ({', '.join(model.variables)}), and only an inflow side has one"
            )
        if kind != "inflow":
            continue
        state = np.asarray(given[side], dtype=np.float64).reshape(-1)
        if state.shape != (model.n_vars,) or not np.all(np.isfinite(state)):
            raise ConfigError(
                f"boundary.{side}: the inflow state must be {model.n_vars} finite numbers "
                f"({', '.join(model.variables)}), got {list(given[side])!r}"
            )
        if not model.is_admissible(state[:, None]).all():
            raise ConfigError(
                f"boundary.{side}: the inflow state {state.tolist()} is not admissible for "
                f"'{model.name}' ({model.admissible_rule})"
            )
        states[side] = state
    return states


def _padded_points(
    axis: Grid, offset: float, periodic: bool, low: str, high: str, shift: float
) -> tuple[Array, NDArray[np.bool_], NDArray[np.bool_]]:
    """The points ``shift`` cell widths from the centres of a padded family along one axis, by
    the rules of :func:`~conslaw.schemes.coefficient_families.coefficient_family`: a periodic
    ghost takes the point of the cell it copies (by index), an outflow or inflow ghost its edge
    cell's, a wall ghost the mirror image of its point. A staggered cell centred on a wall has
    its point beyond the wall mirrored too.

    Returns
    -------
    points : numpy.ndarray
    mirrored : numpy.ndarray of bool
        The points that are mirror images (their coefficients take the mirror signs).
    on_wall : numpy.ndarray of bool
        The staggered cells centred on a wall (their odd coefficients vanish at the centre).
    """
    x = padded_positions(axis, offset, periodic, GHOSTS)
    n = axis.n_cells_at(offset, periodic)
    centre = x.copy()
    direction = np.ones_like(x)
    mirrored = np.zeros(x.shape, dtype=bool)
    on_wall = np.zeros(x.shape, dtype=bool)
    sides = (
        (low, slice(0, GHOSTS), axis.x_min, GHOSTS),
        (high, slice(GHOSTS + n, x.size), axis.x_max, GHOSTS + n - 1),
    )
    for kind, cells, boundary, edge in sides:
        if periodic:
            index = np.arange(x.size)[cells]
            centre[cells] = x[GHOSTS + np.mod(index - GHOSTS, n)]
        elif kind == "wall":
            centre[cells] = 2.0 * boundary - x[cells]
            direction[cells] = -1.0
            mirrored[cells] = True
        else:
            centre[cells] = x[edge]
    points = centre + direction * (shift * axis.dx)
    if offset != 0.0 and not periodic:
        for kind, (_, _, boundary, edge), outward in zip(
            (low, high), sides, (-1.0, 1.0), strict=True
        ):
            if kind != "wall":
                continue
            on_wall[edge] = True
            points[edge] = boundary + shift * axis.dx
            if shift * outward > 0.0:
                points[edge] = boundary - shift * axis.dx
                mirrored[edge] = True
    return points, mirrored, on_wall


def _coefficient_layout_error(model: Model) -> str:
    """What the 2D scheme cannot serve in how ``model`` lays out its coefficients and terms
    (``Model.aux_layout_2d``), as the end of a sentence naming it, or ``""``."""
    uses = model.capabilities()
    if uses["resistance"] and (model.momentum_index is None or model.momentum_y_index is None):
        return "has a resistance but not both momenta (momentum_index, momentum_y_index)"
    if model.n_aux == 0:
        return ""
    if model.aux_layout_2d == "bed":
        if model.surface_aux is None or model.surface_aux_y is None:
            return "lays out a bed but names no bed rows (surface_aux, surface_aux_y)"
        if uses["source"] and not uses["balanced_source"]:
            return "has a bed and a source that is not the well-balanced one (balanced_source)"
        return ""
    if model.aux_layout_2d in ("along-x", "field"):
        return ""
    return (
        f"has coefficients but aux_layout_2d = {model.aux_layout_2d!r}: it must be 'bed', "
        "'along-x' or 'field'"
    )


class JiangTadmorReference:
    """The Jiang–Tadmor step for a two-dimensional model (``Model.n_dims == 2``).

    Parameters
    ----------
    model : Model
        With x and y fluxes, Jacobians and wave speeds; its coefficients, if any, a bed
        (``surface_aux`` and ``surface_aux_y``, the rows of
        :func:`~conslaw.schemes.jiang_tadmor.bed.bed_rows`) from ``quarter_bed``.
    reconstructor : Reconstructor
        Limits the slopes in x and in y separately (any of the registry's).
    grid : Grid2D
    boundaries : mapping
        ``left``, ``right``, ``bottom``, ``top`` -> ``"periodic"``, ``"outflow"``, ``"wall"``
        or ``"inflow"``.
    cfl : float
        Courant number per direction, in (0, 1/2).
    inflow : mapping, optional
        The state of every inflow side (its ghost cells hold it; :func:`inflow_states`).
    """

    def __init__(
        self,
        model: Model,
        reconstructor: Reconstructor,
        grid: Grid2D,
        boundaries: Mapping[str, str],
        cfl: float = 0.45,
        inflow: Mapping[str, Sequence[float]] | None = None,
    ) -> None:
        if model.n_dims != 2:
            raise ConfigError(f"jiang-tadmor needs a 2D model; '{model.name}' is 1D")
        uses = model.capabilities()
        hooks = {
            "dynamic_coefficients": model.coefficients_2d_point,
            "interface_coefficients": model.corner_coefficients_point,
            "rest_coefficients": None,
        }
        unsupported = [key for key, hook in hooks.items() if uses[key] and hook is None]
        if unsupported:
            raise ConfigError(
                f"jiang-tadmor (reference): '{model.name}' needs {', '.join(unsupported)} "
                "(the 2D forms: coefficients_2d_point, corner_coefficients_point)"
            )
        layout_error = _coefficient_layout_error(model)
        if layout_error:
            raise ConfigError(f"jiang-tadmor (reference): '{model.name}' {layout_error}")
        if set(boundaries) != set(SIDES):
            raise ConfigError(f"boundaries: need {', '.join(SIDES)}, got {sorted(boundaries)}")
        for side, kind in boundaries.items():
            if kind not in KINDS:
                raise ConfigError(f"boundary.{side}: '{kind}' is not one of {', '.join(KINDS)}")
        for low, high in (("left", "right"), ("bottom", "top")):
            if (boundaries[low] == "periodic") != (boundaries[high] == "periodic"):
                raise ConfigError(f"boundary.{low} and boundary.{high}: periodic on both or none")
        if not 0.0 < cfl < CFL_LIMIT:
            raise ConfigError(f"cfl must be in (0, {CFL_LIMIT}), got {cfl!r}")
        self.inflow = inflow_states(model, boundaries, inflow or {})
        self.model = model
        self.reconstructor = reconstructor
        self.grid = grid
        self.boundaries = dict(boundaries)
        self.cfl = float(cfl)
        self.uses = uses
        self.periodic_x = boundaries["left"] == "periodic"
        self.periodic_y = boundaries["bottom"] == "periodic"
        #: The coefficients at the centres of the upper-right, upper-left, lower-right and
        #: lower-left quarters of every padded cell of each family (:meth:`_family_aux`), for
        #: the source at the quarter points.
        self._quarters: dict[bool, tuple[Array, Array, Array, Array]] = {}
        self._aux = {staggered: self._family_aux(staggered) for staggered in (False, True)}

    def family_shape(self, staggered: bool) -> tuple[int, int]:
        """``(rows, columns)`` of the primary or the staggered family."""
        return self.grid.shape_at(0.5 if staggered else 0.0, self.periodic_x, self.periodic_y)

    def _family_aux(self, staggered: bool) -> Array:
        """The coefficients of one family, padded as the state is (with the coefficients'
        own mirror signs): ``(n_aux, rows + 2 GHOSTS, columns + 2 GHOSTS)``."""
        model = self.model
        rows, columns = self.family_shape(staggered)
        if model.n_aux == 0:
            empty = np.zeros((0, rows + 2 * GHOSTS, columns + 2 * GHOSTS))
            self._quarters[staggered] = (empty, empty, empty, empty)
            return empty
        if model.aux_layout_2d == "along-x":
            return self._along_x_aux(staggered)
        if model.aux_layout_2d == "field":
            return self._field_aux(staggered)
        quarters = quarter_averages(model, self.grid, self.boundaries)
        periodic = (self.periodic_x, self.periodic_y)
        aux = family_bed(quarters, self.grid, staggered, periodic)
        ones = (1.0,) * model.n_aux
        return self.padded(
            aux,
            staggered,
            model.aux_reflect_signs or ones,
            model.aux_reflect_signs_y or model.aux_reflect_signs or ones,
            states=False,
        )

    def _along_x_aux(self, staggered: bool) -> Array:
        """The coefficients of a model whose coefficients vary along x only (``Model.aux(x,
        dx)``, a chute), padded: those of the 1D scheme at every column
        (:func:`~conslaw.schemes.coefficient_families.coefficient_family`: ghost columns by
        the rule of their side), the same in every row. Keeps those at the quarter points in
        ``self._quarters[staggered]``."""
        rows = self.family_shape(staggered)[0] + 2 * GHOSTS
        rule = {
            condition.name: condition.ghost_coefficients
            for condition in builtin_boundary_conditions()
        }
        rules = (rule[self.boundaries["left"]], rule[self.boundaries["right"]])
        offset = 0.5 if staggered else 0.0
        family = coefficient_family(self.model, self.grid.x, offset, self.periodic_x, rules, GHOSTS)
        centre, left, right = (
            np.ascontiguousarray(
                np.broadcast_to(aux[:, None, :], (aux.shape[0], rows, aux.shape[1]))
            )
            for aux in family
        )
        self._quarters[staggered] = (right, left, right, left)
        return centre

    def _field_aux(self, staggered: bool) -> Array:
        """The coefficients of a model whose coefficients vary over the plane (``Model.aux_2d``
        at map points, a terrain), padded: at the centres of the family's cells and, in
        ``self._quarters[staggered]``, at the centres of their upper-right, upper-left,
        lower-right and lower-left quarters. A ghost cell of an outflow or inflow side takes
        the points of its edge cell; a point beyond a wall takes the coefficients of its mirror
        image (with ``aux_reflect_signs``, ``aux_reflect_signs_y``); periodic sides wrap."""
        model = self.model
        grid = self.grid
        ones = (1.0,) * model.n_aux
        signs_x = np.asarray(model.aux_reflect_signs or ones)[:, None, None]
        signs_y = np.asarray(model.aux_reflect_signs_y or model.aux_reflect_signs or ones)[
            :, None, None
        ]
        offset = 0.5 if staggered else 0.0
        families = []
        shifts = ((0.0, 0.0), (0.25, 0.25), (-0.25, 0.25), (0.25, -0.25), (-0.25, -0.25))
        sides_x = (self.boundaries["left"], self.boundaries["right"])
        sides_y = (self.boundaries["bottom"], self.boundaries["top"])
        for shift_x, shift_y in shifts:
            x, flip_x, wall_x = _padded_points(grid.x, offset, self.periodic_x, *sides_x, shift_x)
            y, flip_y, wall_y = _padded_points(grid.y, offset, self.periodic_y, *sides_y, shift_y)
            aux = model.aux_2d(x[None, :], y[:, None])
            aux = np.where(flip_x[None, None, :], signs_x * aux, aux)
            aux = np.where(flip_y[None, :, None], signs_y * aux, aux)
            if shift_x == 0.0:
                # A staggered cell centred on a wall: the mirror-symmetric coefficients there.
                aux = np.where(wall_x[None, None, :] & (signs_x < 0.0), 0.0, aux)
                aux = np.where(wall_y[None, :, None] & (signs_y < 0.0), 0.0, aux)
            families.append(np.ascontiguousarray(aux))
        self._quarters[staggered] = (families[1], families[2], families[3], families[4])
        return families[0]

    def still_water(self, surface: float) -> Array:
        """Primary-family values of still water at ``surface`` over the model's bed
        (:func:`~conslaw.schemes.jiang_tadmor.bed.still_water_depth`), all momenta 0."""
        model = self.model
        assert model.depth_index is not None
        q = np.zeros((model.n_vars, *self.family_shape(False)))
        if model.n_aux == 0:
            q[model.depth_index] = max(surface, 0.0)
            return q
        assert model.surface_aux is not None and model.surface_aux_y is not None
        rows = [*model.surface_aux, *model.surface_aux_y]
        quarters = quarters_of_rows(self.family_aux(False)[rows], self.grid.dx, self.grid.dy)
        q[model.depth_index] = still_water_depth(quarters, surface)
        return q

    def family_aux_padded(self, staggered: bool) -> Array:
        """The coefficients of one family padded as its states, ``(n_aux, rows + 2 GHOSTS,
        columns + 2 GHOSTS)`` (each ghost cell's by the rule of its side)."""
        return self._aux[staggered]

    def quarter_aux_padded(self, staggered: bool) -> tuple[Array, Array, Array, Array]:
        """The coefficients at the centres of the upper-right, upper-left, lower-right and
        lower-left quarters of every cell of one family, padded as its states (a model with
        coefficients along x or over the field; the source of the quarter points)."""
        return self._quarters[staggered]

    def family_aux(self, staggered: bool) -> Array:
        """The coefficients of the cells of one family (not padded)."""
        rows, columns = self.family_shape(staggered)
        return self._aux[staggered][:, GHOSTS : GHOSTS + rows, GHOSTS : GHOSTS + columns]

    def padded(
        self,
        q: Array,
        staggered: bool,
        signs_x: tuple[float, ...] | None = None,
        signs_y: tuple[float, ...] | None = None,
        states: bool = True,
    ) -> Array:
        """``q`` (one family, ``(n_vars, rows, columns)``) with GHOSTS ghost cells on every
        side: a periodic copy, the edge cell repeated (outflow), the mirror image (wall), with
        ``signs_x`` across x walls and ``signs_y`` across y walls (default: the model's
        ``reflect_signs`` and ``reflect_signs_y``), or the side's inflow state (inflow; with
        ``states = False``, for coefficients, the edge cell as at an outflow)."""
        model = self.model
        across_x = np.asarray(signs_x or model.reflect_signs, dtype=np.float64)
        across_y = np.asarray(
            signs_y or model.reflect_signs_y or model.reflect_signs, dtype=np.float64
        )
        w = q
        directions = ((2, "left", "right", across_x), (1, "bottom", "top", across_y))
        for axis, low, high, signs in directions:
            width = [(0, 0)] * 3
            if self.boundaries[low] == "periodic":  # both ends at once: each copies the other
                width[axis] = (GHOSTS, GHOSTS)
                w = np.pad(w, width, mode="wrap")
                continue
            for end, side in ((0, low), (1, high)):
                width[axis] = (GHOSTS, 0) if end == 0 else (0, GHOSTS)
                kind = self.boundaries[side]
                # A wall mirrors about the face, or about the centre of a staggered end cell.
                mode = (
                    "edge"
                    if kind in ("outflow", "inflow")
                    else "reflect"
                    if staggered
                    else "symmetric"
                )
                w = np.pad(w, width, mode=mode)  # type: ignore[call-overload]
                if kind == "inflow" and states:
                    ghosts = [slice(None)] * 3
                    ghosts[axis] = slice(0, GHOSTS) if end == 0 else slice(-GHOSTS, None)
                    w[tuple(ghosts)] = self.inflow[side].reshape(-1, 1, 1)
                if kind == "wall":
                    ghosts = [slice(None)] * 3
                    ghosts[axis] = slice(0, GHOSTS) if end == 0 else slice(-GHOSTS, None)
                    w[tuple(ghosts)] *= signs.reshape(-1, 1, 1)
        return w

    def courant_numbers(self, q: Array, dt: float, staggered: bool = False) -> tuple[float, float]:
        """``dt max|a_x| / dx`` and ``dt max|a_y| / dy`` of the cells of ``q`` (of the
        primary family, or the staggered one)."""
        speed_x, speed_y = self.max_speeds(q, staggered)
        return dt * speed_x / self.grid.dx, dt * speed_y / self.grid.dy

    def max_speeds(self, q: Array, staggered: bool = False) -> tuple[float, float]:
        """The largest wave speeds in x and in y of the cells of ``q`` (of the primary
        family, or the staggered one: the wave speeds read the family's coefficients)."""
        flat = q.reshape(q.shape[0], -1)
        aux = _columns(self.family_aux(staggered)) if self.model.n_aux else None
        speed_x = float(np.max(self.model.max_wave_speed(flat, aux)))
        speed_y = float(np.max(self.model.max_wave_speed(flat, aux, direction="y")))
        return speed_x, speed_y

    def stable_dt(self, q: Array, staggered: bool = False) -> float:
        """The largest ``dt`` with both Courant numbers at most ``cfl``, ``min(cfl dx / max|a_x|,
        cfl dy / max|a_y|)`` (inf at rest; the 1D kernel's ``cfl dx / a_max`` in a direction
        along which nothing moves), for ``q`` of the primary family or the staggered one."""
        speed_x, speed_y = self.max_speeds(q, staggered)
        dt_x = self.cfl * self.grid.dx / speed_x if speed_x > 0.0 else np.inf
        dt_y = self.cfl * self.grid.dy / speed_y if speed_y > 0.0 else np.inf
        return min(dt_x, dt_y)

    def source_step_limit(self, q: Array, staggered: bool = False) -> float:
        """The largest step with which the source, from rest, builds up a velocity that meets
        the Courant condition in each direction: ``min(sqrt(cfl dx / (2 a_x)), sqrt(cfl dy / (2
        a_y)))``, ``a_x = max |s_x| / h`` and ``a_y = max |s_y| / h`` over the wet cells of ``q``
        (the 1D ``NessyahuTadmor.source_step_limit`` along each direction: the wave speed of a
        thin layer on a slope, ``(g h)^(1/2) -> 0``, does not see the velocity gravity gives it);
        inf for a model without a source, a depth or momenta.

        Parameters
        ----------
        q : numpy.ndarray
            Values of the primary family, or the staggered one (``staggered``).
        staggered : bool

        Returns
        -------
        float
        """
        model = self.model
        depth = model.depth_index
        if depth is None or not self.uses["source"]:
            return np.inf
        h = q[depth]
        wet = h > 0.0
        if not wet.any():
            return np.inf
        aux = self.family_aux(staggered)[:, wet] if model.n_aux else None
        source = model.source(q[:, wet], aux)
        limit = np.inf
        for m, spacing in (
            (model.momentum_index, self.grid.dx),
            (model.momentum_y_index, self.grid.dy),
        ):
            if m is None:
                continue
            largest = float(np.max(np.abs(source[m]) / h[wet]))
            if largest > 0.0:
                limit = min(limit, float(np.sqrt(self.cfl * spacing / (2.0 * largest))))
        return limit

    def _still_cells(self, w: Array) -> Array:
        """Whether each padded cell is still: every velocity below ``STILL`` times the cell's
        wave speed along it (round-off of a lake at rest is far below; any flow far above)."""
        model = self.model
        d = model.depth_index
        assert d is not None
        flat = _columns(w)
        h = w[d]
        wet = (h >= model.dry_depth()) & (h > 0.0)
        safe = np.where(wet, h, 1.0)
        still = np.ones(h.shape, dtype=bool)
        for m, direction in ((model.momentum_index, "x"), (model.momentum_y_index, "y")):
            if m is None:
                continue
            speed = model.max_wave_speed(flat, direction=direction).reshape(h.shape)
            still &= np.abs(np.where(wet, w[m] / safe, 0.0)) <= STILL * speed
        return still

    def _effective_bed(self, w: Array, aux: Array, still: Array) -> Array:
        """``aux`` with the bed of every still, partly flooded cell (its still-water level below
        the top of a quarter) replaced by the bed under its water, ``min(quarter, level)``
        (:func:`~conslaw.schemes.jiang_tadmor.bed.flooded_level`): the cell is then a fully wet
        cell over that bed, whose depth in the dry quarters is 0 when the surface is flat. A
        moving cell keeps its bed: the flat quarters under a moving shoreline slow its run-down
        (Thacker's planar oscillation: 4x the L1 error of the depth at N = 50)."""
        model = self.model
        assert model.surface_aux is not None and model.surface_aux_y is not None
        assert model.depth_index is not None
        rows = (*model.surface_aux, *model.surface_aux_y)
        dx, dy = self.grid.dx, self.grid.dy
        h = w[model.depth_index]
        quarters = quarters_of_rows(aux[list(rows)], dx, dy)
        partial = still & (h > 0.0) & (h + aux[rows[0]] < np.max(quarters, axis=0))
        if not np.any(partial):
            return aux
        under_water = rows_of_quarters(np.minimum(quarters, flooded_level(h, quarters)), dx, dy)
        effective = aux.copy()
        for k, row in enumerate(rows):
            effective[row] = np.where(partial, under_water[k], aux[row])
        return effective

    def _surface_data(self, w: Array, aux: Array) -> Array:
        """``w`` with the depth replaced by the surface ``depth + bed``; a dry cell takes the
        highest surface of the wet cells within two cells (5 x 5) where its bed is higher
        (dry land sets no surface gradient for the water beside it: still water stays still
        with every reconstructor, WENO's wider stencil included)."""
        model = self.model
        assert model.surface_aux is not None and model.depth_index is not None
        d = model.depth_index
        data = w.copy()
        surface = w[d] + aux[model.surface_aux[0]]
        dry = (w[d] <= 0.0) | (w[d] < model.dry_depth())
        wet_surface = np.pad(
            np.where(dry, -np.inf, surface), 2, mode="constant", constant_values=-np.inf
        )
        nearby = _window_extreme(wet_surface, True, width=5)
        dry_land = dry & (nearby > -np.inf)
        data[d] = np.where(dry_land, np.minimum(surface, nearby), surface)
        return data

    def _raw_slopes(
        self, w: Array, aux: Array, rows: slice, columns: slice
    ) -> tuple[Array, Array, Array | None]:
        """Slopes in x and in y of the padded cells ``w[:, rows, columns]`` as the reconstructor
        gives them, the depth's from the surface less the bed's (with its twist, None without a
        bed)."""
        model = self.model
        half = STENCIL_HALF_WIDTH
        surface = self.uses["surface"] and model.surface_aux is not None
        data = self._surface_data(w, aux) if surface else w
        wide_x = data[:, rows, columns.start - half : columns.stop + half]
        slopes_x = self.reconstructor.slopes(wide_x)
        wide_y = data[:, rows.start - half : rows.stop + half, columns]
        slopes_y = self.reconstructor.slopes(wide_y.swapaxes(1, 2)).swapaxes(1, 2)
        if not surface:
            return slopes_x, slopes_y, None
        depth = model.depth_index
        assert model.surface_aux is not None and model.surface_aux_y is not None
        assert depth is not None
        slopes_x[depth] -= self.grid.dx * aux[model.surface_aux[1], rows, columns]
        slopes_y[depth] -= self.grid.dy * aux[model.surface_aux_y[0], rows, columns]
        return slopes_x, slopes_y, -aux[model.surface_aux_y[1], rows, columns]

    def _limited_slopes(
        self,
        w: Array,
        rows: slice,
        columns: slice,
        raw: tuple[Array, Array, Array | None],
        floors: Array | None,
    ) -> tuple[Array, Array, Array | None]:
        """Copies of the ``raw`` slopes with the depth rules: every quarter of the depth at least
        its floor (``floors``, ``(4, rows, columns)`` in the order of
        :data:`~conslaw.schemes.jiang_tadmor.bed.QUARTER_SIGNS`; None: half the depth), then
        the momentum slopes bounded by the velocities. Returns the slopes and the depth's
        twist."""
        slopes_x, slopes_y, twist = raw[0].copy(), raw[1].copy(), raw[2]
        if self.model.depth_index is None:
            return slopes_x, slopes_y, twist
        h = w[self.model.depth_index, rows, columns]
        twist = self._limit_depth_slopes(h, slopes_x, slopes_y, twist, floors)
        self._bound_momentum_slopes(w, rows, columns, slopes_x, slopes_y, twist)
        return slopes_x, slopes_y, twist

    def _limit_depth_slopes(
        self,
        h: Array,
        slopes_x: Array,
        slopes_y: Array,
        twist: Array | None,
        floors: Array | None,
    ) -> Array | None:
        """Scale the depth's slopes and twist (in place; the twist returned) by the largest
        factor <= 1 that keeps every quarter ``h + (sx h' + sy h* + sx sy twist)/4`` at or above
        its floor; without floors, half the depth, where a slope alone is clipped to
        ``DEPTH_SLOPE_LIMIT h`` as in 1D (the same limit, bit for bit). Nothing is
        reconstructed in a dry cell."""
        depth = self.model.depth_index
        assert depth is not None
        along_x, along_y = slopes_x[depth], slopes_y[depth]
        bent = np.zeros_like(h) if twist is None else twist
        ratio = np.ones_like(h)
        for k, (sx, sy) in enumerate(QUARTER_SIGNS):
            floor = 0.5 * h if floors is None else floors[k]
            deviation = 0.25 * (sx * along_x + sy * along_y + (sx * sy) * bent)
            short = h + deviation < floor
            ratio = np.where(
                short, np.minimum(ratio, (h - floor) / np.where(short, -deviation, 1.0)), ratio
            )
        if floors is None:
            limit = DEPTH_SLOPE_LIMIT * h
            only_x = (along_y == 0.0) & (bent == 0.0)
            only_y = (along_x == 0.0) & (bent == 0.0)
            slopes_x[depth] = np.where(only_x, np.clip(along_x, -limit, limit), along_x * ratio)
            slopes_y[depth] = np.where(only_y, np.clip(along_y, -limit, limit), along_y * ratio)
        else:
            slopes_x[depth] = along_x * ratio
            slopes_y[depth] = along_y * ratio
        dry = h <= 0.0
        slopes_x[:, dry] = 0.0
        slopes_y[:, dry] = 0.0
        if twist is None:
            return None
        return np.where(dry, 0.0, twist * ratio)

    def _drain_floors(self, h: Array, predicted: Array, aux: Array, dt: float) -> Array:
        """The floor of each quarter of the depth over a bed: ``min(h/2, 2 D)`` with ``D = 2 dt
        (max(-sx F, 0)/dx + max(-sy G, 0)/dy)`` the depth that the two half edges at the cell's
        centre take out of the new cell holding that quarter (``F``, ``G`` the depth fluxes of
        the predicted values). Still water drains nothing, so its quarters may be empty (dry
        land); a quarter that is drained keeps at least twice what it loses. ``D`` falls with
        ``dt``, so a small enough step keeps every new depth >= 0."""
        model = self.model
        assert model.depth_index is not None
        flat, flat_aux = _columns(predicted), _columns(aux)
        along_x = model.flux(flat, flat_aux)[model.depth_index].reshape(h.shape)
        along_y = model.flux(flat, flat_aux, direction="y")[model.depth_index].reshape(h.shape)
        floors = []
        for sx, sy in QUARTER_SIGNS:
            drain = (
                2.0
                * dt
                * (
                    np.maximum(-sx * along_x, 0.0) / self.grid.dx
                    + np.maximum(-sy * along_y, 0.0) / self.grid.dy
                )
            )
            floors.append(np.minimum(0.5 * h, 2.0 * drain))
        return np.stack(floors)

    def _bound_momentum_slopes(
        self,
        w: Array,
        rows: slice,
        columns: slice,
        slopes_x: Array,
        slopes_y: Array,
        twist: Array | None,
    ) -> None:
        """Each momentum's slope along each direction bounded so that the velocities at the two
        quarter points along it (depths ``h +- h'/4``) stay between the smallest and largest
        velocity of the cell and its two neighbours along it (the 1D
        ``NessyahuTadmor._bound_momentum_slopes``); then, where the velocity of a quarter cell
        (:func:`quarter_velocity_outside`) still falls outside the range of the cell and its four
        neighbours, both slopes of that momentum carry the cell's velocity, ``u h'`` and ``u
        h*`` (docs/design.md, "Toward two dimensions")."""
        model = self.model
        d = model.depth_index
        assert d is not None
        dry = model.dry_depth()
        depth_all = w[d]
        wet = (depth_all >= dry) & (depth_all > 0.0)
        safe = np.where(wet, depth_all, 1.0)
        h = depth_all[rows, columns]
        bent = np.zeros_like(h) if twist is None else twist
        for m in (model.momentum_index, model.momentum_y_index):
            if m is None:
                continue
            u = np.where(wet, w[m] / safe, 0.0)
            q = w[m, rows, columns]
            ranges = []
            for axis, slopes in ((1, slopes_x), (0, slopes_y)):
                u_min, u_max = _neighbour_range(u, rows, columns, axis)
                ranges.append((u_min, u_max))
                transverse = (m == model.momentum_index) == (axis == 0)
                slopes[m] = velocity_bounded_slope(
                    h, q, slopes[d], slopes[m], u_min, u_max, transverse
                )
            low = np.minimum(ranges[0][0], ranges[1][0])
            high = np.maximum(ranges[0][1], ranges[1][1])
            outside = quarter_velocity_outside(
                h, q, (slopes_x[d], slopes_y[d], bent), (slopes_x[m], slopes_y[m]), low, high
            )
            u_here = u[rows, columns]
            slopes_x[m] = np.where(outside, u_here * slopes_x[d], slopes_x[m])
            slopes_y[m] = np.where(outside, u_here * slopes_y[d], slopes_y[m])

    def _reconstruct(
        self, w: Array, rows: slice, columns: slice, staggered: bool, dt: float
    ) -> tuple[Array, Array, Array, Array | None, Array]:
        """The coefficients, limited slopes, depth twist and predicted values of the padded
        cells ``w[:, rows, columns]``: over a bed, still cells read as still water, their
        quarters free to be empty for the predictor and then limited by what its fluxes drain
        (:meth:`_drain_floors`; the averages take these slopes, the predictor keeps the first),
        moving ones with half the depth in every quarter."""
        aux_all = self._aux[staggered]
        surface = self.uses["surface"]
        still = self._still_cells(w) if surface else None
        if still is not None:
            aux_all = self._effective_bed(w, aux_all, still)
        values = w[:, rows, columns]
        aux = aux_all[:, rows, columns]
        raw = self._raw_slopes(w, aux_all, rows, columns)
        floors = None
        if still is not None:
            assert self.model.depth_index is not None
            h = values[self.model.depth_index]
            still_here = still[rows, columns]
            floors = np.where(still_here, 0.0, 0.5 * h) * np.ones((4, 1, 1))
        slopes_x, slopes_y, twist = self._limited_slopes(w, rows, columns, raw, floors)
        aux = self._cell_coefficients(values, slopes_x, slopes_y, aux)
        predicted = self._predictor(values, slopes_x, slopes_y, aux, dt)
        if self.uses["resistance"]:
            self._resist_predicted(values, aux, predicted, dt)
        if still is not None and np.any(still_here):
            # The quarters are limited again by what the predicted fluxes drain; the predictor
            # keeps the first slopes, so that what drains a quarter is what was measured.
            floors = np.where(still_here, self._drain_floors(h, predicted, aux, dt), 0.5 * h)
            slopes_x, slopes_y, twist = self._limited_slopes(w, rows, columns, raw, floors)
        return aux, slopes_x, slopes_y, twist, predicted

    def step(self, q: Array, staggered: bool, dt: float) -> Array:
        """One step from the family of ``q`` (``staggered`` or primary) to the other, ``dt``
        given; the new family's values, shape ``(n_vars, rows, columns)``.

        Raises
        ------
        SchemeBreakdownError
            If a Courant number of ``q`` reaches 1/2 with this ``dt``.
        """
        if max(self.courant_numbers(q, dt, staggered)) >= CFL_LIMIT:
            raise SchemeBreakdownError(
                f"dt={dt:g} makes a Courant number reach {CFL_LIMIT} (Jiang & Tadmor 1998)"
            )
        n_rows, n_columns = self.family_shape(not staggered)
        w = self.padded(q, staggered)
        first = GHOSTS + (0 if staggered else -1)
        rows = slice(first, first + n_rows + 1)
        columns = slice(first, first + n_columns + 1)
        values = w[:, rows, columns]
        aux, slopes_x, slopes_y, twist, predicted = self._reconstruct(
            w, rows, columns, staggered, dt
        )
        a, b, c, d_ = corners(values)
        xa, xb, xc, xd = corners(slopes_x)
        ya, yb, yc, yd = corners(slopes_y)
        (fa, fb, fc, fd), (ga, gb, gc, gd) = self._corner_fluxes(
            predicted, aux, self._aux[staggered][:, rows, columns]
        )
        new = (
            0.25 * ((a + b) + (c + d_))
            + 0.0625 * ((xa - xb) + (xc - xd))
            + 0.0625 * ((ya - yc) + (yb - yd))
            - 0.5 * (dt / self.grid.dx) * ((fb - fa) + (fd - fc))
            - 0.5 * (dt / self.grid.dy) * ((gc - ga) + (gd - gb))
        )
        if twist is not None:
            d = self.model.depth_index
            assert d is not None
            ta, tb, tc, td = corners(twist)
            new[d] += 0.0625 * ((ta - tb) + (td - tc))
            # An empty quarter is a sum of terms that cancel: a new depth within round-off of
            # its terms of 0 is 0 (the cell was emptied exactly).
            size = (
                0.25 * (np.abs(a[d]) + np.abs(b[d]) + np.abs(c[d]) + np.abs(d_[d]))
                + 0.0625 * sum(np.abs(term[d]) for term in (xa, xb, xc, xd, ya, yb, yc, yd))
                + 0.0625 * (np.abs(ta) + np.abs(tb) + np.abs(tc) + np.abs(td))
                + 0.5 * (dt / self.grid.dx) * sum(np.abs(term[d]) for term in (fa, fb, fc, fd))
                + 0.5 * (dt / self.grid.dy) * sum(np.abs(term[d]) for term in (ga, gb, gc, gd))
            )
            # (Below the smallest normal number the relative precision is gone: such a depth
            # is round-off too; a subnormal depth of 6e-310 gave -5e-324 at any time step.)
            emptied = np.abs(new[d]) <= ROUND_OFF * size + np.finfo(np.float64).tiny
            new[d] = np.where(emptied, 0.0, new[d])
        if self.uses["balanced_source"]:
            new += dt * self._balanced_sources(predicted, aux)
        elif self.uses["source"]:
            upper_right, upper_left, lower_right, lower_left = (
                self._with_cell_coefficients(quarter[:, rows, columns][corner], aux[corner])
                for quarter, corner in zip(self._quarters[staggered], CORNERS, strict=True)
            )
            quarter_aux = (upper_right, upper_left, lower_right, lower_left)
            parts = (predicted, slopes_x, slopes_y)
            add_quarter_terms(
                self.model,
                new,
                parts,
                quarter_aux,
                dt,
                self.uses["resistance"],
                self._tangent_slopes(self.family_aux(not staggered)),
            )
        return self._finish(new, w, first, staggered, dt, self.film_depth(q))

    def _with_cell_coefficients(self, quarter: Array, cells: Array) -> Array:
        """A contiguous copy of the static coefficients ``quarter`` of source cells at one of
        their quarter points, with the rows ``varying_aux_rows`` those ``cells`` took for the
        predictor: the source of a quarter uses its cell's earth pressure (the terrain's
        pressure geometry), not the static active one."""
        mixed = np.array(quarter, dtype=np.float64, order="C", copy=True)
        rows = list(self.model.varying_aux_rows)
        if rows and self.uses["dynamic_coefficients"]:
            mixed[rows] = cells[rows]
        return mixed

    def _cell_coefficients(
        self, values: Array, slopes_x: Array, slopes_y: Array, aux: Array
    ) -> Array:
        """The coefficients of every source cell for its predictor: ``aux`` with the model's
        ``coefficients_2d_point`` applied (the earth pressure from the slopes), or ``aux``."""
        if not self.uses["dynamic_coefficients"]:
            return aux
        cells = self.model.coefficients_2d(
            _columns(values), _columns(slopes_x), _columns(slopes_y), _columns(aux)
        )
        return cells.reshape(aux.shape)

    def _resist_predicted(self, values: Array, aux: Array, predicted: Array, dt: float) -> None:
        """The resistance over half a step applied to the predicted momenta (in place), by
        the stopping rule of :func:`~conslaw.schemes.jiang_tadmor.quarter_sources.resist`
        (the 1D predictor's)."""
        model = self.model
        m_x, m_y = model.momentum_index, model.momentum_y_index
        assert m_x is not None and m_y is not None
        rate = model.resistance(_columns(values), _columns(aux)).reshape(values.shape[1:])
        resist(predicted[m_x], predicted[m_y], 0.5 * dt * rate, self._tangent_slopes(aux))

    def _tangent_slopes(self, aux: Array) -> tuple[Array, Array] | None:
        """The surface gradient rows of ``aux`` (``Model.tangent_slope_rows``), or None."""
        rows = self.model.tangent_slope_rows
        return None if rows is None else (aux[rows[0]], aux[rows[1]])

    def _corner_fluxes(
        self, predicted: Array, aux: Array, static: Array
    ) -> tuple[tuple[Array, ...], tuple[Array, ...]]:
        """The x and y fluxes of the predicted values of the corner cells ``a``, ``b``, ``c``,
        ``d`` of every new cell: with the coefficients ``aux`` of each source cell, or, for a
        model with corner coefficients, with the static coefficients ``static`` of each source
        cell whose rows ``varying_aux_rows`` are those the model chooses for the new cell
        (``corner_coefficients_point``; one earth pressure for every flux of the cell)."""
        model = self.model
        if not self.uses["interface_coefficients"]:
            flat, flat_aux = _columns(predicted), _columns(aux)
            f = model.flux(flat, flat_aux).reshape(predicted.shape)
            g = model.flux(flat, flat_aux, direction="y").reshape(predicted.shape)
            return corners(f), corners(g)
        states = corners(predicted)
        shape = states[0].shape
        flat_states = [_columns(q) for q in states]
        statics = corners(static)
        a, b, c, d = flat_states
        chosen = model.corner_coefficients(a, b, c, d, _columns(statics[0]))
        fluxes_x, fluxes_y = [], []
        for q, own in zip(flat_states, statics, strict=True):
            corner_aux = _columns(np.array(own, dtype=np.float64, order="C", copy=True))
            rows = list(model.varying_aux_rows)
            corner_aux[rows] = chosen[rows]
            fluxes_x.append(model.flux(q, corner_aux).reshape(shape))
            fluxes_y.append(model.flux(q, corner_aux, direction="y").reshape(shape))
        return tuple(fluxes_x), tuple(fluxes_y)

    def film_depth(self, q: Array) -> float:
        """``FILM`` times the deepest cell of the family ``q`` (0 for a model without a depth): a
        new cell shallower than this is a film, a source cell at least this deep is flow
        (docs/design.md, "Films")."""
        depth = self.model.depth_index
        if depth is None:
            return 0.0
        return FILM * float(np.max(q[depth], initial=0.0))

    def _finish(
        self, new: Array, w: Array, first: int, staggered: bool, dt: float, film: float
    ) -> Array:
        """The model's correction of the new cells, then the velocity bound of films."""
        model = self.model
        if self.uses["correction"]:
            aux_new = self.family_aux(not staggered)
            flat_aux = _columns(aux_new)
            new = model.correct(_columns(new), flat_aux, dt).reshape(new.shape)
        if model.depth_index is not None and model.momentum_index is not None:
            self._bound_velocities(w, first, staggered, dt, new, film)
        return new

    def _predictor(
        self, values: Array, slopes_x: Array, slopes_y: Array, aux: Array, dt: float
    ) -> Array:
        """``w + dt/2 (-A(w) w'/dx - B(w) w*/dy + s(w))`` at every source cell."""
        flat = _columns(values)
        flat_aux = _columns(aux)
        model = self.model
        along_x = np.einsum(
            "rcm,cm->rm", model.flux_jacobian(flat, flat_aux), _columns(slopes_x)
        ) * (1.0 / self.grid.dx)
        along_y = np.einsum(
            "rcm,cm->rm",
            model.flux_jacobian(flat, flat_aux, direction="y"),
            _columns(slopes_y),
        ) * (1.0 / self.grid.dy)
        rate = -(along_x + along_y)
        if self.uses["source"]:
            rate += model.source(flat, flat_aux)
        return (flat + 0.5 * dt * rate).reshape(values.shape)

    def _pair_sources(
        self, first: Array, second: Array, aux: tuple[Array, Array], y: bool
    ) -> Array:
        """``balanced_source_point`` (``_y_point`` if ``y``) of every pair of cells ``(first,
        second)`` (arrays of the same shape), interleaved so that one call handles all pairs."""
        nv, n_aux = first.shape[0], aux[0].shape[0]
        pairs = np.empty((nv, 2 * first[0].size))
        pairs[:, 0::2] = _columns(first)
        pairs[:, 1::2] = _columns(second)
        pair_aux = np.empty((n_aux, pairs.shape[1]))
        pair_aux[:, 0::2] = _columns(aux[0])
        pair_aux[:, 1::2] = _columns(aux[1])
        spacing = self.grid.dy if y else self.grid.dx
        sources = self.model.balanced_source(pairs, pair_aux, spacing, direction="y" if y else "x")
        return sources[:, 0::2].reshape(first.shape)

    def _balanced_sources(self, predicted: Array, aux: Array) -> Array:
        """The well-balanced source over each new cell: the mean of the x pairs (a, b), (c, d)
        and of the y pairs (a, c), (b, d) of its corner cells' predicted values."""
        along_x = self._pair_sources(
            predicted[..., :, :-1],
            predicted[..., :, 1:],
            (aux[..., :, :-1], aux[..., :, 1:]),
            False,
        )
        along_y = self._pair_sources(
            predicted[..., :-1, :], predicted[..., 1:, :], (aux[..., :-1, :], aux[..., 1:, :]), True
        )
        return 0.5 * (along_x[..., :-1, :] + along_x[..., 1:, :]) + 0.5 * (
            along_y[..., :, :-1] + along_y[..., :, 1:]
        )

    def _bound_velocities(
        self, w: Array, first: int, staggered: bool, dt: float, new: Array, film: float
    ) -> None:
        """The velocity bound of films (docs/design.md, "Films"), in place: a new wet cell
        shallower than ``film`` keeps, along each momentum's direction, its Riemann invariants
        ``u -+ 2c`` within the smallest ``u - 2c`` and the largest ``u + 2c`` of the 4 x 4 cells
        its update reads (``c`` the wave speed less ``|u|`` along that direction), those of the
        flow (at least ``film`` deep) widened by what their forces do in one step
        (:meth:`_flow_changes`), and its velocity between rest and that range (the 1D
        ``NessyahuTadmor._bound_velocities`` per momentum); then its speed is bounded likewise
        (:meth:`_cap_film_speeds`)."""
        model = self.model
        d = model.depth_index
        assert d is not None
        h_new = new[d]
        films = (h_new >= model.dry_depth()) & (h_new > 0.0) & (h_new < film)
        if not np.any(films):
            return
        n_rows, n_columns = new.shape[1:]
        window = (
            slice(None),
            slice(first - 1, first + n_rows + 2),
            slice(first - 1, first + n_columns + 2),
        )
        block, aux = w[window], self._aux[staggered][window]
        flat, flat_aux = _columns(block), _columns(aux)
        new_aux = _columns(self.family_aux(not staggered))
        h = block[d]
        wet = (h >= model.dry_depth()) & (h > 0.0)
        changes, gain = self._flow_changes(block, aux, (h >= film) & (h > 0.0), dt)
        safe_new = np.where(films, h_new, 1.0)
        momenta = [
            (m, direction)
            for m, direction in ((model.momentum_index, "x"), (model.momentum_y_index, "y"))
            if m is not None
        ]
        celerities = []
        for m, direction in momenta:  # of the new cells, before the bound
            with np.errstate(invalid="ignore"):
                speed = model.max_wave_speed(_columns(new), new_aux, direction=direction)
                celerity = speed.reshape(h_new.shape) - np.abs(new[m] / safe_new)
            celerities.append(np.where(films & (celerity > 0.0), celerity, 0.0))
        twices, velocities = [], []
        for (m, direction), celerity_new, change in zip(momenta, celerities, changes, strict=True):
            u = np.where(wet, block[m] / np.where(wet, h, 1.0), 0.0)
            speed = model.max_wave_speed(flat, flat_aux, direction=direction).reshape(h.shape)
            twice = 2.0 * np.maximum(speed - np.abs(u), 0.0)
            low = _window_extreme(u - twice + np.minimum(change, 0.0), False)
            high = _window_extreme(u + twice + np.maximum(change, 0.0), True)
            lo = np.minimum(low + 2.0 * celerity_new, 0.0)
            hi = np.maximum(high - 2.0 * celerity_new, 0.0)
            u_new = np.where(films, new[m] / safe_new, 0.0)
            new[m] = np.where(
                films & (u_new < lo),
                lo * h_new,
                np.where(films & (u_new > hi), hi * h_new, new[m]),
            )
            twices.append(twice)
            velocities.append(u)
        widest = np.maximum.reduce(twices) + gain
        reach = metric_speed(*_pair_of(velocities), self._tangent_slopes(aux)) + widest
        cap = np.maximum(_window_extreme(reach, True) - 2.0 * np.maximum.reduce(celerities), 0.0)
        self._cap_film_speeds(new, staggered, films, cap)

    def _flow_changes(
        self, block: Array, aux: Array, flow: NDArray[np.bool_], dt: float
    ) -> tuple[list[Array], Array]:
        """What an explicit step of their source and resistance does to the cells ``block`` (with
        coefficients ``aux``) that are ``flow``: the change of each velocity (an array per
        momentum) and the rise of the speed in the model's metric (:func:`metric_speed`), 0
        elsewhere; the resistance by the stopping rule (:func:`resist`), so friction slows and
        never speeds up."""
        model = self.model
        assert model.depth_index is not None
        rows = [m for m in (model.momentum_index, model.momentum_y_index) if m is not None]
        flat, flat_aux = _columns(block), _columns(aux)
        source = model.source(flat, flat_aux).reshape(block.shape)
        momenta = [block[m] for m in rows]
        driven = [momentum + dt * source[m] for m, momentum in zip(rows, momenta, strict=True)]
        slopes = self._tangent_slopes(aux)
        if self.uses["resistance"]:
            impulse = dt * model.resistance(flat, flat_aux).reshape(block.shape[1:])
            resist(driven[0], driven[1], impulse, slopes)
        safe = np.where(flow, block[model.depth_index], 1.0)
        changes = [
            np.where(flow, (after - before) / safe, 0.0)
            for after, before in zip(driven, momenta, strict=True)
        ]
        rise = metric_speed(*_pair_of(driven), slopes) - metric_speed(*_pair_of(momenta), slopes)
        return changes, np.where(flow, np.maximum(rise, 0.0) / safe, 0.0)

    def _cap_film_speeds(
        self, new: Array, staggered: bool, films: NDArray[np.bool_], cap: Array
    ) -> None:
        """The momentum of every film among the new cells ``new`` shortened along itself where
        its speed in the model's metric (:func:`metric_speed`) is above ``cap`` (the largest
        speed of the cells its update reads, widened as its velocities are, less twice its own
        celerity) by more than round-off (``SPEED_MARGIN``), in place."""
        model = self.model
        assert model.depth_index is not None
        rows = [m for m in (model.momentum_index, model.momentum_y_index) if m is not None]
        safe = np.where(films, new[model.depth_index], 1.0)
        moving = [np.where(films, new[m] / safe, 0.0) for m in rows]
        speed = metric_speed(
            *_pair_of(moving), self._tangent_slopes(self.family_aux(not staggered))
        )
        over = films & (speed > cap * (1.0 + SPEED_MARGIN))
        if np.any(over):
            scale = np.where(over, cap / np.where(over, speed, 1.0), 1.0)
            for m in rows:
                new[m] = np.where(over, new[m] * scale, new[m])

    def _pair(self, q: Array, dt: float) -> tuple[Array | None, float]:
        """A step pair of ``dt`` each from the primary family, as the 1D kernel's
        ``step_pair``: ``(None, dt / 2)`` if a depth would become negative, ``(None, the stable
        dt of the staggered values)`` if their Courant number reaches 1/2, else ``(values,
        dt)``."""
        depth = self.model.depth_index
        middle = self.step(q, False, dt)
        if depth is not None and np.min(middle[depth]) < 0.0:
            return None, 0.5 * dt
        if max(self.courant_numbers(middle, dt, True)) >= CFL_LIMIT:
            return None, self.stable_dt(middle, True)
        end = self.step(middle, True, dt)
        if depth is not None and np.min(end[depth]) < 0.0:
            return None, 0.5 * dt
        return (q.copy() if self.held_at_rest(q, middle, end) else end), dt

    def held_at_rest(self, start: Array, middle: Array, end: Array) -> bool:
        """Whether a step pair from ``start`` through ``middle`` (staggered values) to ``end``
        (primary values) left everything at rest.

        A model with a resistance (Coulomb friction) whose every momentum is exactly 0 at all
        three: nothing has moved (``h_t = -div(h u) = 0`` in both steps), and the pair's end
        is its start, bit for bit; the staggered averaging would otherwise smear a pile at rest
        (the 1D rule, docs/design.md, "Savage–Hutter specifics").

        Parameters
        ----------
        start, middle, end : numpy.ndarray
            ``(n_vars, rows, columns)`` values of the pair's start, middle and end.

        Returns
        -------
        bool
        """
        model = self.model
        if not self.uses["resistance"]:
            return False
        rows = [m for m in (model.momentum_index, model.momentum_y_index) if m is not None]
        return all(bool(np.all(values[rows] == 0.0)) for values in (start, middle, end))

    def advance(self, q: Array, t: float, t_end: float) -> tuple[Array, float, int]:
        """Advance primary-family values ``q`` from ``t`` to exactly ``t_end`` by step pairs of
        one ``dt`` each (:meth:`stable_dt`; the last pair shortened to land on ``t_end``); a pair
        is redone with half its ``dt`` while a depth would become negative, and with the stable
        ``dt`` of the staggered values if their Courant number would reach 1/2 (the 1D kernel's
        rules). Returns the values, the time and the number of steps.

        Raises
        ------
        SchemeBreakdownError
            If the time step falls below ``DT_FLOOR dx`` (but to land on ``t_end``) or a pair
            fails ``MAX_RETRIES`` times (the scheme's time loop).
        """
        steps = 0
        while t < t_end:
            remaining = t_end - t
            dt = min(self.stable_dt(q), self.source_step_limit(q))
            last = 2.0 * dt >= remaining
            if last:
                dt = 0.5 * remaining
            end = None
            for _ in range(MAX_RETRIES):
                if dt < DT_FLOOR * self.grid.dx and not last:
                    break
                end, next_dt = self._pair(q, dt)
                if end is not None:
                    break
                dt, last = next_dt, False
            if end is None:
                raise SchemeBreakdownError(
                    f"t={t:g}, step {steps}: the time step fell to {dt:.3g} (below "
                    f"{DT_FLOOR:g} dx) or a step pair failed {MAX_RETRIES} times"
                )
            q = end
            t = t_end if last else t + 2.0 * dt
            steps += 2
        return q, t, steps
