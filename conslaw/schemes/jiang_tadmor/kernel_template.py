"""Template: the compiled Jiang–Tadmor step (Jiang & Tadmor 1998, SIAM J. Sci. Comput. 19), the
formula of :mod:`conslaw.schemes.jiang_tadmor.reference`, for models without a bed.

Generated per model (and plugin reconstructor) by
:func:`~conslaw.schemes.jiang_tadmor.kernels.jt_kernels`; do not import directly. Layout: padded
arrays ``w[v, NG + k, NG + j]`` for the real cells ``(k, j)`` (row ``k`` along y, column ``j``
along x) of one family.

One step maps family A to family B, whose cell ``(k, j)`` is centred on the common corner of the
A-cells ``a = (first + k, first + j)``, ``b`` to its right, ``c`` above ``a`` and ``d`` above
``b`` (``first = NG - 1`` primary -> staggered, ``NG`` back). How it is made fast without a second
copy of the physics (docs/design.md, "Toward two dimensions"):

- **Rows in parallel, one pass over memory.** The new rows are cut into as many chunks as the
  work array has (``work.shape[0]``), run with numba's ``prange``. A chunk computes each source
  row once (:func:`predict_row`: slopes in x and y, the depth rules, the predictor and the fluxes
  of the predicted values, into one of two work rows that take turns), then the new row between
  the last two (:func:`average_row`), the velocity bound of its films (:func:`bound_films`) and its
  largest wave speeds and smallest depth (:func:`row_statistics`), which is all the time loop
  needs from the new state. A source row is computed twice only where two chunks meet.
- **Registers, not arrays, per cell.** The model's pointwise functions fill stack arrays of a
  compile-time size (:mod:`conslaw.kernelgen.stack`), as in the 1D template.
- **Slopes row by row.** The built-in reconstructor is chosen once per row
  (:func:`~conslaw.reconstruct.dispatch.builtin_slopes` along a row,
  :func:`~conslaw.reconstruct.dispatch.builtin_slopes_across` across five rows), so its loop is
  a plain loop over the cells.
- **Compile-time switches** (constants of the generated module): ``NV``, ``NAUX``; ``DEPTH``,
  ``MOMENTUM``, ``MOMENTUM_Y`` (rows of the depth and of its two momenta, or -1) and
  ``DRY_DEPTH``; ``HAS_CORRECTION``; ``CUSTOM_SLOPES`` (a plugin's reconstructor).

The arithmetic of every cell is that of :meth:`JiangTadmorReference.step`, operation for
operation (no fast-math), so the two agree to round-off.
"""

from typing import NamedTuple  # noqa: I001 (the binding block below is replaced when generated)

import math

import numpy as np
from numba import njit, prange

from conslaw.kernelgen.stack import local_matrix, local_vector
from conslaw.reconstruct.dispatch import builtin_slopes, builtin_slopes_across
from conslaw.schemes.jiang_tadmor.constants import (
    DEEPEST,
    LOWEST,
    QUARTER_MARGIN,
    SPEED_MARGIN,
    SPEED_X,
    SPEED_Y,
    TINY,
)
from conslaw.schemes.nessyahu_tadmor.constants import DEPTH_SLOPE_LIMIT, FILM

# --- bindings ---
from conslaw.pointwise import (
    correct_point as _correct_point,
    flux_point as _flux_point,
    flux_y_point as _flux_y_point,
    jacobian_point as _jacobian_point,
    jacobian_y_point as _jacobian_y_point,
    max_speed_point as _max_speed_point,
    max_speed_y_point as _max_speed_y_point,
    resistance_point as _resistance_point,
    slope_point as _slope_point,
    source_point as _source_point,
)

NV = 1
NAUX = 0
NPARAMS = 1
HAS_CORRECTION = False
DEPTH = -1
MOMENTUM = -1
MOMENTUM_Y = -1
DRY_DEPTH = 0.0
CUSTOM_SLOPES = False
HAS_RESISTANCE = False
SURFACE_METRIC = False
SKIP_EMPTY = False
# --- end bindings ---

#: Ghost cells per side: the slope stencil's half width and the staggered shift.
NG = 3
#: Rows of a work row: limited slopes in x, in y, then the x and y fluxes of the predicted values.
SLOPE_X = 0
SLOPE_Y = NV
FLUX_X = 2 * NV
FLUX_Y = 3 * NV
#: Then the velocities of each momentum (x first) in the row below, the row and the row above.
VELOCITY = 4 * NV
MOMENTA = (MOMENTUM >= 0) + (MOMENTUM_Y >= 0)
#: Row of the first of them: the x momentum, or the y momentum of a model with no x momentum.
FIRST_MOMENTUM = MOMENTUM if MOMENTUM >= 0 else MOMENTUM_Y
WORK_ROWS = 4 * NV + 3 * MOMENTA
#: Kinds of side (the ``kinds`` array of :func:`fill_ghosts`).
PERIODIC = 0
OUTFLOW = 1
WALL = 2
INFLOW = 3
# The per-row statistics (:func:`row_statistics`) are in the columns SPEED_X, SPEED_Y, LOWEST,
# DEEPEST of conslaw.schemes.jiang_tadmor.constants (shared with the scheme's time loop).
#: Index of the reconstructor's code in the parameter vector.
SLOPE_CODE = NPARAMS


class Sides(NamedTuple):
    """The kinds of the four sides (``left, right, bottom, top``; :data:`PERIODIC`,
    :data:`OUTFLOW`, :data:`WALL`, :data:`INFLOW`), the signs of every variable mirrored across
    an x wall and across a y wall, and the state of every inflow side (``(4, NV)``, a row per
    side, unused for the other kinds)."""

    kinds: np.ndarray
    signs_x: np.ndarray
    signs_y: np.ndarray
    inflow: np.ndarray


class Step(NamedTuple):
    """What one step reads besides the states: the first padded source row and column
    (``NG - 1`` from the primary family, ``NG`` from the staggered), the new family's rows and
    columns, the time step, the cell widths and the largest depth of the source family (a new
    cell shallower than ``FILM`` times it is a film, :func:`bound_films`)."""

    first: int
    rows: int
    columns: int
    dt: float
    dx: float
    dy: float
    deepest: float


def work_shape(chunks, columns):
    """Shape of the work array for steps into families of up to ``columns`` columns (plain
    Python): per chunk, two work rows of ``WORK_ROWS`` rows over the ``columns + 1`` source
    cells and their two neighbours."""
    return (chunks, 2, WORK_ROWS, columns + 3)


@njit(cache=True)
def ghost_source(i, n, kind, staggered, low):
    """The real index (padded) whose value the ghost index ``i`` of a direction of ``n`` real
    cells takes, on its low (``low``) or high end: a periodic copy, the end cell (outflow), or
    the mirror image about the face (a wall of the primary family) or about the end cell's centre
    (a wall of the staggered family, whose end cell straddles the wall)."""
    if kind == PERIODIC:
        return NG + (i - NG + n * NG) % n
    if kind == OUTFLOW:
        return NG if low else NG + n - 1
    shift = 1 if staggered else 0
    if low:
        return NG + (NG - 1 - i) + shift
    return NG + n - 1 - (i - NG - n) - shift


@njit(cache=True)
def fill_ghosts(w, rows, columns, staggered, sides):
    """The ghost cells of a padded family: along x for the real rows, then along y for every
    column (the corners take the x ghosts' images), as :meth:`JiangTadmorReference.padded`."""
    kinds = sides.kinds
    for k in range(NG, NG + rows):
        for g in range(NG):
            for end in range(2):
                i = NG - 1 - g if end == 0 else NG + columns + g
                kind = kinds[end]
                source = ghost_source(i, columns, kind, staggered, end == 0)
                for v in range(NV):
                    value = w[v, k, source]
                    if kind == INFLOW:
                        value = sides.inflow[end, v]
                    w[v, k, i] = value * sides.signs_x[v] if kind == WALL else value
    for g in range(NG):
        for end in range(2):
            i = NG - 1 - g if end == 0 else NG + rows + g
            kind = kinds[2 + end]
            source = ghost_source(i, rows, kind, staggered, end == 0)
            for v in range(NV):
                if kind == INFLOW:
                    for j in range(columns + 2 * NG):
                        w[v, i, j] = sides.inflow[2 + end, v]
                    continue
                sign = sides.signs_y[v] if kind == WALL else 1.0
                for j in range(columns + 2 * NG):
                    w[v, i, j] = w[v, source, j] * sign if kind == WALL else w[v, source, j]


@njit(cache=True)
def col(i):
    """An index as an unsigned integer (numba then skips its negative-index wrap-around, a
    select per access that keeps a loop from vectorising)."""
    return np.uintp(i)


@njit(cache=True, error_model="numpy", inline="always")
def velocity_at(w, m, k, j):
    """``m / h`` of padded cell ``(k, j)``, 0 if dry (the reference's ``np.where(wet, m / safe,
    0)``), without a branch around the division."""
    depth = w[DEPTH, col(k), col(j)]
    wet = depth >= DRY_DEPTH and depth > 0.0
    velocity = w[m, col(k), col(j)] / (depth if wet else 1.0)
    return velocity if wet else 0.0


@njit(cache=True, inline="always")
def limited_depth_slope(along, across, ratio, depth):
    """The depth's slope ``along`` one direction: clipped to ``DEPTH_SLOPE_LIMIT depth`` where
    the slope ``across`` is 0 (the 1D rule, bit for bit), else scaled by the quarters' ratio."""
    limit = DEPTH_SLOPE_LIMIT * depth
    clipped = min(max(along, -limit), limit)
    return clipped if across == 0.0 else along * ratio


@njit(cache=True, inline="always")
def bounded_momentum_slope(depth, momentum, depth_slope, slope, u_min, u_max, transverse):
    """The momentum slope clamped so that the velocities at both quarter points along its
    direction stay in ``[u_min, u_max]``; a ``transverse`` one the mean of crossed ends
    (:func:`conslaw.schemes.depth_rules.velocity_bounded_slope`)."""
    plus = depth + 0.25 * depth_slope
    minus = depth - 0.25 * depth_slope
    low = max(4.0 * (plus * u_min - momentum), 4.0 * (momentum - minus * u_max))
    high = min(4.0 * (plus * u_max - momentum), 4.0 * (momentum - minus * u_min))
    if transverse and low > high:
        return 0.5 * (low + high)
    return min(max(slope, low), high)


@njit(cache=True, inline="always")
def quarter_outside(depth, momentum, low, high, largest):
    """Whether a wet quarter of ``depth`` and ``momentum`` has a velocity outside ``[low, high]``
    by more than ``largest`` times its depth plus ``TINY`` (as momenta)."""
    slack = largest * depth + TINY
    return depth > 0.0 and (momentum < low * depth - slack or momentum > high * depth + slack)


@njit(cache=True, inline="always")
def quarter_velocity_outside(depth, momentum, along_x, along_y, slope_x, slope_y, low, high):
    """:func:`conslaw.schemes.jiang_tadmor.reference.quarter_velocity_outside` of one cell
    without a bed: whether a wet quarter cell's velocity falls outside ``[low, high]``."""
    largest = QUARTER_MARGIN * max(abs(low), abs(high))
    lower_left = quarter_outside(
        depth + 0.25 * (-along_x + -along_y), momentum + 0.25 * (-slope_x + -slope_y), low, high,
        largest,
    )  # fmt: skip
    lower_right = quarter_outside(
        depth + 0.25 * (along_x + -along_y), momentum + 0.25 * (slope_x + -slope_y), low, high,
        largest,
    )  # fmt: skip
    upper_left = quarter_outside(
        depth + 0.25 * (-along_x + along_y), momentum + 0.25 * (-slope_x + slope_y), low, high,
        largest,
    )  # fmt: skip
    upper_right = quarter_outside(
        depth + 0.25 * (along_x + along_y), momentum + 0.25 * (slope_x + slope_y), low, high,
        largest,
    )  # fmt: skip
    return lower_left or lower_right or upper_left or upper_right


@njit(cache=True, error_model="numpy")
def depth_rules(w, k, first, count, slots):
    """The depth rules of :meth:`JiangTadmorReference._limited_slopes` without a bed, on the
    slopes of the ``count`` padded cells ``(k, first + j)`` in ``slots``: the depth's slopes
    scaled down together until every quarter keeps half the depth (a slope alone clipped as in
    1D), each momentum's slopes bounded by the velocities of the cell and its two neighbours
    along each direction (the VELOCITY rows), and both of them ``u`` times the depth's where a
    quarter cell's velocity is still outside the range of the cell and its four neighbours,
    every slope 0 in a dry cell. A loop over the row per rule, each of which vectorises.

    The reference lowers the ratio quarter by quarter, ``min((h - h/2) / -deviation)`` over the
    short quarters; division is monotone, so that is the quotient of the lowest quarter alone,
    bit for bit (one division instead of four)."""
    depths = w[DEPTH, k, first : first + count]
    along_x, along_y = slots[SLOPE_X + DEPTH], slots[SLOPE_Y + DEPTH]
    for j in range(count):
        depth, slope_x, slope_y = depths[j], along_x[j], along_y[j]
        lowest = min(
            min(0.25 * (-slope_x + -slope_y), 0.25 * (slope_x + -slope_y)),
            min(0.25 * (-slope_x + slope_y), 0.25 * (slope_x + slope_y)),
        )
        floor = 0.5 * depth
        ratio = min(1.0, (depth - floor) / -lowest) if depth + lowest < floor else 1.0
        along_x[j] = limited_depth_slope(slope_x, slope_y, ratio, depth)
        along_y[j] = limited_depth_slope(slope_y, slope_x, ratio, depth)
    for n in range(MOMENTA):
        m = FIRST_MOMENTUM if n == 0 else MOMENTUM_Y
        momenta = w[m, k, first : first + count]
        momentum_x, momentum_y = slots[SLOPE_X + m], slots[SLOPE_Y + m]
        below, here = slots[VELOCITY + 3 * n], slots[VELOCITY + 3 * n + 1]
        above = slots[VELOCITY + 3 * n + 2]
        for j in range(count):
            depth, momentum = depths[j], momenta[j]
            u_c, u_l, u_r = here[j + 1], here[j], here[j + 2]
            low_x, high_x = min(min(u_l, u_c), u_r), max(max(u_l, u_c), u_r)
            slope_x = bounded_momentum_slope(
                depth, momentum, along_x[j], momentum_x[j], low_x, high_x, m == MOMENTUM_Y
            )
            u_l, u_r = below[j + 1], above[j + 1]
            low_y, high_y = min(min(u_l, u_c), u_r), max(max(u_l, u_c), u_r)
            slope_y = bounded_momentum_slope(
                depth, momentum, along_y[j], momentum_y[j], low_y, high_y, m == MOMENTUM
            )
            outside = quarter_velocity_outside(
                depth, momentum, along_x[j], along_y[j], slope_x, slope_y,
                min(low_x, low_y), max(high_x, high_y),
            )  # fmt: skip
            momentum_x[j] = u_c * along_x[j] if outside else slope_x
            momentum_y[j] = u_c * along_y[j] if outside else slope_y
    for v in range(2 * NV):
        slopes = slots[SLOPE_X + v]
        for j in range(count):
            slopes[j] = 0.0 if depths[j] <= 0.0 else slopes[j]


@njit(cache=True, error_model="numpy")
def raw_slopes(w, k, first, count, params, slots):
    """The reconstructor's slopes in x and in y of the ``count`` padded cells ``(k, first + j)``
    into the slope rows of ``slots``."""
    code = int(params[SLOPE_CODE])
    for v in range(NV):
        along, across = slots[SLOPE_X + v], slots[SLOPE_Y + v]
        if CUSTOM_SLOPES:
            for j in range(count):
                c = col(first + j)
                along[col(j)] = _slope_point(
                    w[v, k, c - 2], w[v, k, c - 1], w[v, k, c], w[v, k, c + 1], w[v, k, c + 2]
                )
                across[col(j)] = _slope_point(
                    w[v, k - 2, c], w[v, k - 1, c], w[v, k, c], w[v, k + 1, c], w[v, k + 2, c]
                )
        else:
            builtin_slopes(code, w[v, k, first - 2 : first + count + 2], count, along)
            stop = first + count
            builtin_slopes_across(
                code, w[v, k - 2, first:stop], w[v, k - 1, first:stop], w[v, k, first:stop],
                w[v, k + 1, first:stop], w[v, k + 2, first:stop], count, across,
            )  # fmt: skip


@njit(cache=True, error_model="numpy")
def row_velocities(w, k, first, count, slots):
    """The velocities of each momentum in padded rows ``k - 1``, ``k``, ``k + 1`` over columns
    ``first - 1 .. first + count`` into the VELOCITY rows of ``slots`` (each division in a loop
    of its own, which vectorises)."""
    for n in range(MOMENTA):
        m = FIRST_MOMENTUM if n == 0 else MOMENTUM_Y
        for r in range(3):
            row = slots[VELOCITY + 3 * n + r]
            for j in range(count + 2):
                row[col(j)] = velocity_at(w, m, k - 1 + r, first - 1 + j)


@njit(cache=True, error_model="numpy")
def predict_row(w, k, first, count, step, params, slots):
    """Slopes, predicted values ``w + dt/2 (-A w'/dx - B w*/dy)`` and their x and y fluxes of
    the ``count`` padded cells ``(k, first + j)``, into ``slots``."""
    local = local_vector(NPARAMS)
    for p in range(NPARAMS):
        local[p] = params[p]
    raw_slopes(w, k, first, count, params, slots)
    if DEPTH >= 0:
        row_velocities(w, k, first, count, slots)
        depth_rules(w, k, first, count, slots)
    q, aux = local_vector(NV), local_vector(NAUX)
    slope_x, slope_y = local_vector(NV), local_vector(NV)
    jacobian, predicted, out = local_matrix(NV), local_vector(NV), local_vector(NV)
    for a in range(NAUX):
        aux[a] = 0.0
    inverse_dx, inverse_dy, half_dt = 1.0 / step.dx, 1.0 / step.dy, 0.5 * step.dt
    row = col(k)
    for j in range(count):
        c, jj = col(first + j), col(j)
        for v in range(NV):
            q[v] = w[v, row, c]
            slope_x[v] = slots[SLOPE_X + v, jj]
            slope_y[v] = slots[SLOPE_Y + v, jj]
        _jacobian_point(q, aux, local, jacobian)
        for r in range(NV):
            total = 0.0
            for c2 in range(NV):
                total += jacobian[r, c2] * slope_x[c2]
            predicted[r] = total * inverse_dx
        _jacobian_y_point(q, aux, local, jacobian)
        for r in range(NV):
            total = 0.0
            for c2 in range(NV):
                total += jacobian[r, c2] * slope_y[c2]
            predicted[r] = q[r] + half_dt * -(predicted[r] + total * inverse_dy)
        store_fluxes(predicted, aux, local, out, slots, jj)


@njit(cache=True, error_model="numpy", inline="always")
def store_fluxes(predicted, aux, local, out, slots, jj):
    """The x and y fluxes of the ``predicted`` values into column ``jj`` of the flux rows of
    ``slots`` (``out`` a scratch vector)."""
    _flux_point(predicted, aux, local, out)
    for v in range(NV):
        slots[FLUX_X + v, jj] = out[v]
    _flux_y_point(predicted, aux, local, out)
    for v in range(NV):
        slots[FLUX_Y + v, jj] = out[v]


@njit(cache=True, error_model="numpy")
def average_row(w, out, k, step, params, low, high):
    """New row ``k``: the staggered averages of the corner cells' reconstructions and the
    midpoint-rule fluxes through the half edges (the formula of
    :mod:`~conslaw.schemes.jiang_tadmor.reference`), a variable at a time over the row (the
    model's correction follows, :func:`correct_row`)."""
    lambda_x = 0.5 * (step.dt / step.dx)
    lambda_y = 0.5 * (step.dt / step.dy)
    first = col(step.first)
    for v in range(NV):
        below, above, target = w[v, step.first + k], w[v, step.first + k + 1], out[v, NG + k]
        slope_x_low, slope_x_high = low[SLOPE_X + v], high[SLOPE_X + v]
        slope_y_low, slope_y_high = low[SLOPE_Y + v], high[SLOPE_Y + v]
        flux_x_low, flux_x_high = low[FLUX_X + v], high[FLUX_X + v]
        flux_y_low, flux_y_high = low[FLUX_Y + v], high[FLUX_Y + v]
        for j in range(step.columns):
            a, b = below[first + j], below[first + j + 1]
            c, d = above[first + j], above[first + j + 1]
            xa, xb, xc, xd = (
                slope_x_low[j],
                slope_x_low[j + 1],
                slope_x_high[j],
                slope_x_high[j + 1],
            )
            ya, yb, yc, yd = (
                slope_y_low[j],
                slope_y_low[j + 1],
                slope_y_high[j],
                slope_y_high[j + 1],
            )
            fa, fb, fc, fd = flux_x_low[j], flux_x_low[j + 1], flux_x_high[j], flux_x_high[j + 1]
            ga, gb, gc, gd = flux_y_low[j], flux_y_low[j + 1], flux_y_high[j], flux_y_high[j + 1]
            target[col(NG) + j] = (
                0.25 * ((a + b) + (c + d))
                + 0.0625 * ((xa - xb) + (xc - xd))
                + 0.0625 * ((ya - yc) + (yb - yd))
                - lambda_x * ((fb - fa) + (fd - fc))
                - lambda_y * ((gc - ga) + (gd - gb))
            )


@njit(cache=True, error_model="numpy")
def correct_row(out, k, step, params):
    """The model's correction of every cell of new row ``k``."""
    local = local_vector(NPARAMS)
    for p in range(NPARAMS):
        local[p] = params[p]
    q, aux = local_vector(NV), local_vector(NAUX)
    for a in range(NAUX):
        aux[a] = 0.0
    for j in range(step.columns):
        correct_cell(out, NG + k, col(NG + j), q, aux, local, step.dt)


@njit(cache=True, error_model="numpy", inline="always")
def correct_cell(out, row, c, q, aux, local, dt):
    """The model's correction of padded cell ``(row, c)`` of ``out`` with coefficients ``aux``
    (``q`` a scratch vector)."""
    for v in range(NV):
        q[v] = out[v, row, c]
    _correct_point(q, aux, local, dt)
    for v in range(NV):
        out[v, row, c] = q[v]


@njit(cache=True, error_model="numpy", inline="always")
def widen_film_bounds(bounds, u, v, speeds, changes, slopes):
    """Take a source cell of velocity ``(u, v)``, wave speeds ``speeds`` along x and y and
    ``changes`` (what its source and resistance do to its velocities in one step and the rise
    of its speed, :func:`flow_changes`; 0 for a film or a dry cell) into a film's ``bounds``:
    the smallest ``u - 2c + min(change, 0)`` and largest ``u + 2c + max(change, 0)`` along x
    (``c = max(speed - |u|, 0)``), the same along y, and the largest speed
    (:func:`metric_speed` with the surface gradient ``slopes``, zeros in the plane) plus the
    larger ``2c`` and the rise (docs/design.md, "Films")."""
    twice_x = 2.0 * max(speeds[0] - abs(u), 0.0)
    twice_y = 2.0 * max(speeds[1] - abs(v), 0.0)
    bounds[0] = min(bounds[0], u - twice_x + min(changes[0], 0.0))
    bounds[1] = max(bounds[1], u + twice_x + max(changes[0], 0.0))
    bounds[2] = min(bounds[2], v - twice_y + min(changes[1], 0.0))
    bounds[3] = max(bounds[3], v + twice_y + max(changes[1], 0.0))
    bounds[4] = max(bounds[4], metric_speed(u, v, slopes) + (max(twice_x, twice_y) + changes[2]))


@njit(cache=True, error_model="numpy", inline="always")
def resist(momentum_x, momentum_y, impulse, slopes):
    """Coulomb's stopping rule (:func:`conslaw.schemes.jiang_tadmor.quarter_sources.resist`):
    ``(0, 0)`` where the momentum's length (in the surface metric of ``slopes`` for a model
    on a surface, ``SURFACE_METRIC``) is at most ``impulse``, else the momentum shortened by
    ``impulse`` along itself."""
    size = math.hypot(momentum_x, momentum_y)
    if SURFACE_METRIC:
        size = math.hypot(size, slopes[0] * momentum_x + slopes[1] * momentum_y)
    if size <= impulse:
        return 0.0, 0.0
    return momentum_x - impulse * (momentum_x / size), momentum_y - impulse * (momentum_y / size)


@njit(cache=True, error_model="numpy", inline="always")
def flow_push(q, aux, params, dt, film, slopes, source, changes):
    """Into ``changes`` (:func:`flow_changes`): what an explicit step ``dt`` of its source and
    its resistance (with the stopping rule, :func:`resist`) does to the velocities of cell
    ``q`` with coefficients ``aux``, if it is flow (at least ``film`` deep and not dry); zeros
    otherwise. ``source`` is scratch space. The reference's ``_flow_changes``; docs/design.md,
    "Films"."""
    changes[0], changes[1], changes[2] = 0.0, 0.0, 0.0
    depth = q[DEPTH]
    if depth >= film and depth > 0.0:
        _source_point(q, aux, params, source)
        momentum_x, momentum_y = q[MOMENTUM], q[MOMENTUM_Y]
        driven_x = momentum_x + dt * source[MOMENTUM]
        driven_y = momentum_y + dt * source[MOMENTUM_Y]
        if HAS_RESISTANCE:
            impulse = dt * _resistance_point(q, aux, params)
            driven_x, driven_y = resist(driven_x, driven_y, impulse, slopes)
        flow_changes(momentum_x, momentum_y, driven_x, driven_y, depth, slopes, changes)


@njit(cache=True, error_model="numpy", inline="always")
def flow_changes(momentum_x, momentum_y, driven_x, driven_y, depth, slopes, changes):
    """Into ``changes``: the change of each velocity of a cell of the flow of ``depth`` from its
    momentum before to ``driven`` after an explicit step of its source and resistance, and the
    rise of its speed in the metric of ``slopes`` (0 if it falls), as the reference's
    ``_flow_changes``."""
    changes[0] = (driven_x - momentum_x) / depth
    changes[1] = (driven_y - momentum_y) / depth
    rise = metric_speed(driven_x, driven_y, slopes) - metric_speed(momentum_x, momentum_y, slopes)
    changes[2] = max(rise, 0.0) / depth


@njit(cache=True, error_model="numpy", inline="always")
def metric_speed(u, v, slopes):
    """The speed of map velocity ``(u, v)`` in a surface of gradient ``slopes``, ``(u^2 + v^2 +
    (b_x u + b_y v)^2)^(1/2)``; zero slopes give ``|(u, v)|`` bit for bit
    (:func:`conslaw.schemes.jiang_tadmor.reference.metric_speed`)."""
    along = slopes[0] * u + slopes[1] * v
    return math.sqrt(u * u + v * v + along * along)


@njit(cache=True, error_model="numpy", inline="always")
def start_film_bounds(bounds):
    """Bounds that hold nothing, before the source cells widen them."""
    for n in range(0, 4, 2):
        bounds[n] = np.inf
        bounds[n + 1] = -np.inf
    bounds[4] = -np.inf


@njit(cache=True, error_model="numpy")
def film_window(w, row, c, params, bounds):
    """The ``bounds`` (:func:`widen_film_bounds`) of a film over the 4 x 4 padded cells from
    ``(row, c)``, for a model without a source or a resistance (nothing changes a velocity)."""
    q, aux = local_vector(NV), local_vector(NAUX)
    speeds, changes = local_vector(2), local_vector(3)
    for a in range(NAUX):
        aux[a] = 0.0
    changes[0], changes[1], changes[2] = 0.0, 0.0, 0.0
    flat = local_vector(2)
    flat[0], flat[1] = 0.0, 0.0
    start_film_bounds(bounds)
    for r in range(row, row + 4):
        for i in range(c, c + 4):
            for v in range(NV):
                q[v] = w[v, r, i]
            u = velocity_at(w, MOMENTUM, r, i)
            speeds[0] = _max_speed_point(q, aux, params)
            v_y, speeds[1] = 0.0, 0.0
            if MOMENTUM_Y >= 0:
                v_y = velocity_at(w, MOMENTUM_Y, r, i)
                speeds[1] = _max_speed_y_point(q, aux, params)
            widen_film_bounds(bounds, u, v_y, speeds, changes, flat)


@njit(cache=True, error_model="numpy", inline="always")
def film_celerity(speed, velocity):
    """The celerity ``c`` of a new film along one direction: its wave speed ``speed`` less
    ``|velocity|``, 0 if that is not a positive number (a velocity that overflows)."""
    celerity = speed - abs(velocity)
    return celerity if celerity > 0.0 else 0.0


@njit(cache=True, error_model="numpy", inline="always")
def clamp_film(out, k, j, depth, bounds, speeds, slopes):
    """New cell ``(k, j)`` (of ``depth``, wave speeds ``speeds`` along x and y before the
    bound), a film: along each direction its Riemann invariants within ``bounds`` and its
    velocity between rest and them, then the momentum shortened along itself where its speed
    (:func:`metric_speed` with the surface gradient ``slopes`` at the cell) plus ``2c`` is above
    the largest of the bounds by more than round-off (``SPEED_MARGIN``; the reference's
    ``_bound_velocities``)."""
    celerity_x = film_celerity(speeds[0], out[MOMENTUM, NG + k, NG + j] / depth)
    celerity_y = 0.0
    if MOMENTUM_Y >= 0:
        celerity_y = film_celerity(speeds[1], out[MOMENTUM_Y, NG + k, NG + j] / depth)
    low = min(bounds[0] + 2.0 * celerity_x, 0.0)
    high = max(bounds[1] - 2.0 * celerity_x, 0.0)
    clamp_velocity(out, MOMENTUM, k, j, depth, low, high)
    v = 0.0
    if MOMENTUM_Y >= 0:
        low = min(bounds[2] + 2.0 * celerity_y, 0.0)
        high = max(bounds[3] - 2.0 * celerity_y, 0.0)
        clamp_velocity(out, MOMENTUM_Y, k, j, depth, low, high)
        v = out[MOMENTUM_Y, NG + k, NG + j] / depth
    u = out[MOMENTUM, NG + k, NG + j] / depth
    speed = metric_speed(u, v, slopes)
    cap = max(bounds[4] - 2.0 * max(celerity_x, celerity_y), 0.0)
    if speed > cap * (1.0 + SPEED_MARGIN):
        scale = cap / speed
        out[MOMENTUM, NG + k, NG + j] = out[MOMENTUM, NG + k, NG + j] * scale
        if MOMENTUM_Y >= 0:
            out[MOMENTUM_Y, NG + k, NG + j] = out[MOMENTUM_Y, NG + k, NG + j] * scale


@njit(cache=True, error_model="numpy", inline="always")
def new_speeds(out, k, j, aux, params, speeds):
    """The wave speeds along x and y of new cell ``(k, j)`` with coefficients ``aux`` into
    ``speeds``."""
    q = local_vector(NV)
    for v in range(NV):
        q[v] = out[v, NG + k, NG + j]
    speeds[0] = _max_speed_point(q, aux, params)
    speeds[1] = _max_speed_y_point(q, aux, params) if MOMENTUM_Y >= 0 else 0.0


@njit(cache=True, error_model="numpy", inline="always")
def film_of(out, k, j, film):
    """The depth of new cell ``(k, j)`` if it is a film (wet and shallower than ``film``), else
    0."""
    depth = out[DEPTH, NG + k, NG + j]
    return depth if (depth >= DRY_DEPTH and depth > 0.0 and depth < film) else 0.0


@njit(cache=True, error_model="numpy", inline="always")
def clamp_velocity(out, m, k, j, depth, lowest, highest):
    """Momentum ``m`` of new cell ``(k, j)`` (of ``depth``) with its velocity clamped to
    ``[lowest, highest]``."""
    u = out[m, NG + k, NG + j] / depth
    if u < lowest:
        out[m, NG + k, NG + j] = lowest * depth
    elif u > highest:
        out[m, NG + k, NG + j] = highest * depth


@njit(cache=True, error_model="numpy")
def bound_films(w, out, k, step, params):
    """The velocity bound of the films of new row ``k`` (:meth:`JiangTadmorReference.
    _bound_velocities` without a source, docs/design.md, "Films"): a new cell shallower than
    ``FILM`` times the deepest source cell keeps its Riemann invariants within those of the 4 x 4
    cells its update reads and its velocity between rest and them, and its speed plus ``2c`` at
    most their largest."""
    film = FILM * step.deepest
    bounds = local_vector(5)
    speeds = local_vector(2)
    aux = local_vector(NAUX)
    for a in range(NAUX):
        aux[a] = 0.0
    flat = local_vector(2)
    flat[0], flat[1] = 0.0, 0.0
    for j in range(step.columns):
        depth = film_of(out, k, j, film)
        if depth > 0.0:
            film_window(w, step.first + k - 1, step.first + j - 1, params, bounds)
            new_speeds(out, k, j, aux, params, speeds)
            clamp_film(out, k, j, depth, bounds, speeds, flat)


#: The coefficient table of a model without coefficients at its cells (no rows, no cells):
#: :func:`row_statistics_with` then reads zeros.
NO_AUX_TABLE = np.zeros((0, 0, NAUX))


@njit(cache=True, error_model="numpy")
def row_statistics(out, k, columns, params, statistics):
    """:func:`row_statistics_with` of a model whose wave speeds read no coefficients."""
    row_statistics_with(out, k, columns, params, statistics, NO_AUX_TABLE)


@njit(cache=True, error_model="numpy")
def row_statistics_with(out, k, columns, params, statistics, aux_table):
    """Largest wave speeds in x and y, smallest and largest depth of padded row ``NG + k`` into
    ``statistics[k]``; the speeds and the smallest depth NaN if a value or a wave speed of the
    row is not finite (a NaN or infinite momentum of a dry cell too, whose wave speeds are 0).
    Each cell's coefficients come from ``aux_table`` (``(rows, columns, NAUX)``, padded as
    ``out``), or are 0 if it has no cells (:data:`NO_AUX_TABLE`)."""
    q, aux = local_vector(NV), local_vector(NAUX)
    for a in range(NAUX):
        aux[a] = 0.0
    tabled = aux_table.shape[0] > 0
    speed_x, speed_y, lowest, deepest, finite = 0.0, 0.0, np.inf, -np.inf, True
    for j in range(columns):
        if tabled:
            for a in range(NAUX):
                aux[a] = aux_table[NG + k, col(NG + j), a]
        # x - x is 0 for a finite x and NaN for a NaN or an infinity (no fast-math): the sum is
        # 0 only if every value and wave speed of the cell is finite.
        residue = 0.0
        for v in range(NV):
            q[v] = out[v, NG + k, NG + j]
            residue += q[v] - q[v]
        along_x = _max_speed_point(q, aux, params)
        along_y = _max_speed_y_point(q, aux, params)
        speed_x = max(speed_x, along_x)
        speed_y = max(speed_y, along_y)
        residue += (along_x - along_x) + (along_y - along_y)
        finite = finite and residue == 0.0
        if DEPTH >= 0:
            lowest = min(lowest, q[DEPTH])
            deepest = max(deepest, q[DEPTH])
    if not finite:
        speed_x, speed_y, lowest = np.nan, np.nan, np.nan
    statistics[k, SPEED_X] = speed_x
    statistics[k, SPEED_Y] = speed_y
    statistics[k, LOWEST] = lowest
    statistics[k, DEEPEST] = deepest


@njit(cache=True, error_model="numpy", inline="always")
def chunk_rows(rows, chunks, chunk):
    """The first and one past the last of the ``rows`` new rows of chunk ``chunk`` of
    ``chunks`` (the last chunks may be shorter, or empty)."""
    per_chunk = (rows + chunks - 1) // chunks
    start = chunk * per_chunk
    return start, min(rows, start + per_chunk)


#: Source rows on each side of the two a new row averages that its value can read (the slopes
#: across rows reach two, the film window one; one more for safety).
READ_HALO = 3


@njit(cache=True, error_model="numpy")
def occupied_rows(w):
    """The first and the last padded row of ``w`` holding a value other than 0 (its ghost rows
    included), or ``(0, -1)`` if every value is 0."""
    rows = w.shape[1]
    low, high = rows, -1
    for r in range(rows):
        if np.any(w[:, r, :] != 0.0):
            low = r
            break
    for r in range(rows - 1, low - 1, -1):
        if np.any(w[:, r, :] != 0.0):
            high = r
            break
    return (0, -1) if high < 0 else (low, high)


@njit(cache=True, error_model="numpy")
def active_rows(w, step):
    """The range ``[low, high)`` of new rows a step from padded family ``w`` computes: for a
    model whose empty cells stay empty (``Model.empty_stays_empty``, ``SKIP_EMPTY``), those
    whose source rows (``step.first + k - READ_HALO`` to ``step.first + k + 1 + READ_HALO``)
    hold any value, every other new row being empty (docs/design.md, "Cost that follows the
    flow"); every row for any other model."""
    if not SKIP_EMPTY:
        return 0, step.rows
    low, high = occupied_rows(w)
    if high < low:
        return 0, 0
    start = max(0, low - step.first - 1 - READ_HALO)
    stop = min(step.rows, high - step.first + READ_HALO + 1)
    return start, max(start, stop)


@njit(cache=True, error_model="numpy")
def clear_rows(out, statistics, start, stop, columns):
    """New rows ``start`` to ``stop`` (exclusive) empty: their values 0 and their statistics
    those of a row of empty cells (no speed, depth 0)."""
    for k in range(start, stop):
        for v in range(NV):
            for j in range(columns):
                out[v, NG + k, NG + j] = 0.0
        statistics[k, SPEED_X] = 0.0
        statistics[k, SPEED_Y] = 0.0
        statistics[k, LOWEST] = 0.0
        statistics[k, DEEPEST] = 0.0


@njit(cache=True, error_model="numpy")
def chunk_span(step, chunks, chunk, low, high, out, statistics):
    """The rows of chunk ``chunk`` of ``chunks`` (:func:`chunk_rows`) within the active range
    ``[low, high)``, after clearing its rows outside it (:func:`clear_rows`)."""
    start, stop = chunk_rows(step.rows, chunks, chunk)
    first, last = max(start, low), min(stop, high)
    if last <= first:
        clear_rows(out, statistics, start, stop, step.columns)
        return first, first
    clear_rows(out, statistics, start, first, step.columns)
    clear_rows(out, statistics, last, stop, step.columns)
    return first, last


@njit(cache=True, parallel=True, error_model="numpy")
def step_family(w, out, work, statistics, params, step):
    """One Jiang–Tadmor step from the padded family ``w`` into the real cells of ``out`` (its
    ghosts are left to :func:`fill_ghosts`), with each new row's statistics
    (:func:`row_statistics`) in ``statistics``; the rows in ``work.shape[0]`` chunks across the
    threads."""
    active_start, active_stop = active_rows(w, step)
    for chunk in prange(work.shape[0]):
        start, stop = chunk_span(
            step, work.shape[0], chunk, active_start, active_stop, out, statistics
        )
        slots = work[chunk]
        if start < stop:
            predict_row(w, step.first + start, step.first, step.columns + 1, step, params, slots[0])
        for k in range(start, stop):
            low, high = slots[(k - start) % 2], slots[(k - start + 1) % 2]
            predict_row(w, step.first + k + 1, step.first, step.columns + 1, step, params, high)
            average_row(w, out, k, step, params, low, high)
            if HAS_CORRECTION:
                correct_row(out, k, step, params)
            if DEPTH >= 0 and MOMENTUM >= 0:
                bound_films(w, out, k, step, params)
            row_statistics(out, k, step.columns, params, statistics)


@njit(cache=True, parallel=True, error_model="numpy")
def family_statistics(w, rows, columns, params, statistics):
    """:func:`row_statistics` of every real row of the padded family ``w``."""
    for k in prange(rows):
        row_statistics(w, k, columns, params, statistics)
