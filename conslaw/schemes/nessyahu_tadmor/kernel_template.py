"""Template: the fused Nessyahu–Tadmor (NOC) kernels, Tai et al. (2001) eqs. (10)–(18).

Generated per model and boundary pair (and plugin reconstructor) by
:func:`~conslaw.schemes.nessyahu_tadmor.kernels.nt_kernels`; do not import directly. Layout:
padded arrays ``w[v, NG + i]`` for the ``n`` real cells ``i``.

One step maps cell family A to family B, whose cell ``k`` spans the centres of A-cells
``L = NG + shift + k`` and ``R = L + 1`` (``shift = -1`` primary -> staggered, ``0`` back):

    w_B[k] = (w_L + w_R)/2 + (w'_L - w'_R)/8                      (eq. 10 with eq. 11)
             - dt/dx (f(w_R^{n+1/2}) - f(w_L^{n+1/2}))            (eq. 12)
             + dt/2 (s(w_L^{n+1/2} + w'_L/4) + s(w_R^{n+1/2} - w'_R/4))   (eqs. 13-14)
    w^{n+1/2} = w + dt/2 (-A(w) w'/dx + s(w))                    (eq. 15)

How the kernel is made fast without a second copy of the physics:

- **One pass over memory per step.** The cells are processed in blocks of ``BLOCK``: first the
  slopes, predictor, fluxes and quarter-point sources of the block's ``BLOCK + 1`` source cells
  (:func:`predict_cells`), then the block's new averages (:func:`average_cells`), which also
  evaluate everything the time loop needs from the new state: its largest wave speed, its
  admissibility, whether a depth is negative and whether anything moves. The per-block work rows
  (``work``, about 20 kB) stay in the L1 cache; the only traffic to memory is reading the old
  state and writing the new one. The time loop needs no extra pass for the CFL bound, the
  positivity check or the static-equilibrium test, and no copy of an accepted step: the three
  state buffers are rotated.
- **Registers, not arrays, per cell.** The model's pointwise functions fill small arrays; here
  those are stack arrays of a compile-time size (:mod:`conslaw.kernelgen.stack`). After inlining,
  LLVM keeps them in registers, and the loops over the cells of a block compile to SIMD code.
- **Rare work out of the per-cell loops.** The velocity bound of films acts in a few cells,
  so :func:`average_cells` only counts them and :func:`bound_film_velocities` bounds them in a
  second pass over the block (a branch in the loop kept it from vectorising; docs/performance.md,
  "How the kernel is fast").
- **Unsigned column indices** (:func:`col`): numba wraps negative indices around, a select per
  access that would turn every load into a gather; the kernel's indices are never negative.
- **Compile-time switches** (constants of the generated module; unused branches are removed):

  - ``NV``, ``NAUX``: number of variables and of coefficient rows (sizes of the stack arrays).
  - ``HAS_SOURCE``: quarter-point sources.
  - ``HAS_BALANCED_SOURCE``: the model's staggered-cell source replaces the quarter-point pair.
  - ``HAS_RESISTANCE``: a Coulomb-type resistance of magnitude ``resistance_point`` opposing the
    momentum, integrated at the quarter points like the sources and applied with the stopping
    rule ``m = 0 if |m*| <= dt R else m* - sgn(m*) dt R`` (never reverses the flow).
  - ``HAS_DYNAMIC_COEFFICIENTS``: the model sets per-cell coefficients from the cell's slopes
    (the earth-pressure coefficient) before the Jacobian of the predictor is evaluated.
  - ``HAS_INTERFACE_COEFFICIENTS``: the two fluxes of a new cell (at the centres of its source
    cells) are evaluated with one set of coefficients that the model chooses from the two
    mid-step states (the earth pressure of the new cell). The FLUX rows then hold the mid-step
    states, and :func:`average_cells` evaluates the fluxes (twice per source cell).
  - ``HAS_CORRECTION``: pointwise correction of every new cell (dry cells).
  - ``DEPTH``: row of a depth variable kept >= 0 (or -1); ``MOMENTUM``: row of depth * velocity,
    whose slope is bounded by the neighbouring velocities; ``DRY_DEPTH``: velocity 0 below it.
  - ``SURFACE_BED``/``SURFACE_SLOPE``: aux rows of the bed average and slope; the depth is then
    reconstructed as depth + bed.
  - ``CUSTOM_SLOPES``: the reconstructor is a plugin's, whose ``_slope_point`` is compiled in.
    Otherwise the built-in reconstructor is a run-time choice: its code follows the model's
    parameters in the parameter vector (index ``SLOPE_CODE``), and :func:`stencil_slopes` hands
    it to :func:`~conslaw.reconstruct.dispatch.builtin_slopes`, so one kernel serves them all.

The arithmetic of every cell is that of :meth:`NessyahuTadmor.reference_step`, operation for
operation (no fast-math), so the two agree to round-off.
"""

from typing import NamedTuple  # noqa: I001 (the binding block below is replaced when generated)

import numpy as np
from numba import njit

from conslaw.schemes.nessyahu_tadmor.constants import (
    DEPTH_SLOPE_LIMIT,
    FILM,
    MAX_RETRIES,
    ROUND_OFF,
)
from conslaw.kernelgen.stack import local_matrix, local_vector
from conslaw.reconstruct.dispatch import builtin_slopes

# --- bindings ---
from conslaw.pointwise import (
    admissible_point as _admissible_point,
    balanced_source_point as _balanced_source_point,
    coefficients_point as _coefficients_point,
    correct_point as _correct_point,
    fill_left as _fill_left,
    fill_right as _fill_right,
    flux_point as _flux_point,
    interface_coefficients_point as _interface_coefficients_point,
    jacobian_point as _jacobian_point,
    max_speed_point as _max_speed_point,
    resistance_point as _resistance_point,
    rest_coefficients_point as _rest_coefficients_point,
    slope_point as _slope_point,
    source_point as _source_point,
)

NV = 1
NAUX = 0
NPARAMS = 1
HAS_SOURCE = False
HAS_BALANCED_SOURCE = False
HAS_CORRECTION = False
HAS_RESISTANCE = False
HAS_DYNAMIC_COEFFICIENTS = False
HAS_INTERFACE_COEFFICIENTS = False
HAS_REST_COEFFICIENTS = False
DEPTH = -1
MOMENTUM = -1
DRY_DEPTH = 0.0
SURFACE_BED = -1
SURFACE_SLOPE = -1
CUSTOM_SLOPES = False
# --- end bindings ---

NG = 3
STATUS_DONE = 0
STATUS_PAUSED = 1
STATUS_INADMISSIBLE = 2
STATUS_DT_FLOOR = 3
STATUS_CFL_UNREACHABLE = 4
STATUS_SPEED_NOT_FINITE = 5
# Courant number that the second half of a step pair must stay below (eq. 17: strictly < 1/2).
CFL_LIMIT = 0.5

# New cells per block, and the row length of the work array (BLOCK + 1 source cells, padded).
BLOCK = 256
STRIDE = BLOCK + 8
# Rows of the work array: slopes, fluxes at t^{n+1/2}, the sources at the left and right quarter
# points (with a balanced source: the predicted states), the resistance at both quarter points,
# the wave speed of each new cell (NaN where it is inadmissible) and the velocities of the source
# cells (column j + 1 for source cell j, for the momentum-slope bound).
SLOPE = 0
FLUX = NV
SOURCE_LEFT = 2 * NV
SOURCE_RIGHT = 3 * NV
RESIST_LEFT = 4 * NV
RESIST_RIGHT = 4 * NV + 1
SPEED = 4 * NV + 2
VELOCITY = 4 * NV + 3
# With rest coefficients: the momentum row of each source cell's flux with the low end of the
# model's rest range, and dt/dx times its change from the low to the high end.
FLUX_LOW = 4 * NV + 4
FLUX_SPAN = 4 * NV + 5
WORK_ROWS = 4 * NV + (6 if HAS_REST_COEFFICIENTS else 4)
# The stencil values of one variable (see stencil_slopes) use the first flux row, which
# predict_cells fills only after the slopes: the work rows stay as small as the L1 cache wants.
STENCIL = FLUX
WORK_SIZE = WORK_ROWS * STRIDE
# With rest coefficients, the work array continues with three rows over every new cell of a
# step (see work_size, hold_static_runs): a new cell's momentum before the stopping rule with the
# low end of the rest range at both ends, its resistive impulse, and FLUX_SPAN at each source
# cell (the left end of new cell g is source cell g).
REST_MOMENTUM = 0
REST_IMPULSE = 1
REST_SPAN = 2
# Stretches pending in hold_static_runs (two entries each).
STACK_SIZE = 64
# Lanes of the partial maxima of the wave speed (one SIMD register of doubles).
LANES = 8
# Index of the built-in reconstructor's code in the kernel's parameter vector.
SLOPE_CODE = NPARAMS


# Argument bundles of the entry points (numba types a named tuple field by field, caches
# functions taking them, and reads a field at no cost): what belongs together travels together.
class Family(NamedTuple):
    """One cell family (primary or staggered) as a step reads or writes it: its number of real
    cells and the model's coefficient rows (padded columns like the state) at the cell centres
    and at the left and right quarter points."""

    cells: int
    aux: np.ndarray
    aux_left: np.ndarray
    aux_right: np.ndarray


class Buffers(NamedTuple):
    """The three padded state buffers of a step pair (the state is in ``w0``, the half step goes
    to ``w1``, the full step to ``w2``) and the work array."""

    w0: np.ndarray
    w1: np.ndarray
    w2: np.ndarray
    work: np.ndarray


class Controls(NamedTuple):
    """What an advance aims at and may do: the end time, the Courant number, the cell width,
    the smallest time step before a breakdown, and the step pairs before it pauses."""

    t_end: float
    cfl: float
    dx: float
    dt_floor: float
    max_pairs: int


class Boundary(NamedTuple):
    """The data of the left and right boundary conditions (the fill functions' arrays)."""

    left: np.ndarray
    right: np.ndarray


def work_size(n_cells):
    """Length of the work array for steps of up to ``n_cells`` new cells (plain Python)."""
    return WORK_SIZE + (3 * (n_cells + 2) if HAS_REST_COEFFICIENTS else 0)


@njit(cache=True)
def rest_slot(work, row, g):
    """Index of entry ``g`` of rest row ``row`` in the work array."""
    stride = (work.size - WORK_SIZE) // 3
    return np.uintp(WORK_SIZE + row * stride + g)


@njit(cache=True)
def col(i):
    """A column index as an unsigned integer (numba then skips its negative-index wrap-around)."""
    return np.uintp(i)


@njit(cache=True)
def slot(row, j):
    """Index of column j of a work row."""
    return np.uintp(row * STRIDE + j)


@njit(cache=True)
def load_params(params, local):
    """Copy the model's parameters into a stack array: the compiler then knows that no store to
    the state changes them, keeps them in registers and hoists them out of the loops. The copy
    ends before the reconstructor's code (``SLOPE_CODE``): whatever takes slopes is handed the
    kernel's own parameter vector."""
    for k in range(NPARAMS):
        local[k] = params[k]


@njit(cache=True)
def fill_ghosts(w, n, staggered, bc_left, bc_right):
    _fill_left(w, n, NG, staggered, bc_left)
    _fill_right(w, n, NG, staggered, bc_right)


@njit(cache=True, error_model="numpy")
def max_speed(w, n, aux, params):
    """Largest wave speed over the real cells; ``(-1, i)`` at the first inadmissible cell i,
    ``(-2, i)`` at the first cell whose wave speed is not finite (an overflow)."""
    state = local_vector(NV)
    coefficients = local_vector(NAUX)
    largest = 0.0
    for i in range(NG, NG + n):
        c = col(i)
        for v in range(NV):
            state[v] = w[v, c]
        for k in range(NAUX):
            coefficients[k] = aux[k, c]
        if not _admissible_point(state, coefficients, params):
            return -1.0, i - NG
        speed = _max_speed_point(state, coefficients, params)
        if not (speed >= 0.0 and speed < np.inf):
            return -2.0, i - NG
        if speed > largest:
            largest = speed
    return largest, -1


@njit(cache=True, error_model="numpy")
def source_step_limit(w, n, aux, parameters, cfl, dx):
    """``sqrt(cfl dx / (2 a))``, ``a = max |s_m| / h`` over the wet real cells: over a step pair
    from rest the source builds up the velocity ``2 a dt``, which must itself meet the CFL
    condition (``2 a dt^2 / dx <= cfl``). inf without a source or a depth (see
    ``NessyahuTadmor.source_step_limit``)."""
    if not HAS_SOURCE or DEPTH < 0 or MOMENTUM < 0:
        return np.inf
    state = local_vector(NV)
    out = local_vector(NV)
    coefficients = local_vector(NAUX)
    params = local_vector(NPARAMS)
    load_params(parameters, params)
    largest = 0.0
    for i in range(NG, NG + n):
        c = col(i)
        h = w[DEPTH, c]
        if not h > 0.0:
            continue
        for v in range(NV):
            state[v] = w[v, c]
        for k in range(NAUX):
            coefficients[k] = aux[k, c]
        _source_point(state, coefficients, params, out)
        acceleration = abs(out[MOMENTUM]) / h
        if acceleration > largest:
            largest = acceleration
    if not largest > 0.0:
        return np.inf
    return np.sqrt(cfl * dx / (2.0 * largest))


@njit(cache=True)
def failure(code):
    """Status for a failed ``max_speed`` (its negative speed is the reason code)."""
    return STATUS_SPEED_NOT_FINITE if code == -2.0 else STATUS_INADMISSIBLE


@njit(cache=True)
def count_moving(w, n):
    """Number of real cells with a non-zero momentum (0 without a momentum row)."""
    moving = 0
    if MOMENTUM >= 0:
        for i in range(NG, NG + n):
            if w[MOMENTUM, col(i)] != 0.0:
                moving += 1
    return moving


@njit(cache=True)
def copy_cells(src, dst, n):
    for v in range(NV):
        for i in range(NG, NG + n):
            dst[v, col(i)] = src[v, col(i)]


@njit(cache=True, error_model="numpy")
def stencil_slopes(data, first, count, dx, aux_centre, code, values, slopes):
    """Slopes ``slopes[v, j]`` of padded cells ``first + j``, ``j < count`` (eq. 11), before
    the rules of :func:`finished_slope`.

    The reconstructor (the built-in one of ``code``, or the bound plugin slope) acts on the
    stencil values read from ``data`` (front tracking continues the body across a margin in
    ``data``), chosen outside the loop over the cells. ``values`` is a scratch row of
    ``count + 4`` entries for the surface ``depth + bed`` of the surface gradient method;
    otherwise the reconstructor reads ``data``'s row itself.
    """
    for v in range(NV):
        if SURFACE_BED >= 0 and v == DEPTH:
            for j in range(count + 4):
                c = col(first - 2 + j)
                values[j] = data[v, c] + aux_centre[SURFACE_BED, c]
            stencil = values
        else:
            stencil = data[v, first - 2 : first + count + 2]
        row = slopes[v]
        if CUSTOM_SLOPES:
            for j in range(count):
                row[j] = _slope_point(
                    stencil[j], stencil[j + 1], stencil[j + 2], stencil[j + 3], stencil[j + 4]
                )
        else:
            builtin_slopes(code, stencil, count, row)


@njit(cache=True, error_model="numpy", inline="always")
def finished_slope(raw, v, src, c, dx, aux_centre):
    """The slope of variable v in the cell of column ``c`` from the reconstructor's ``raw``
    one: with the surface gradient method the bed slope removed, then the depth rules of
    :func:`depth_limited` with the cell's depth in ``src``."""
    slope = raw
    if SURFACE_BED >= 0 and v == DEPTH:
        slope = slope - dx * aux_centre[SURFACE_SLOPE, c]
    if DEPTH >= 0:
        slope = depth_limited(slope, src[DEPTH, c], v)
    return slope


@njit(cache=True, inline="always")
def depth_limited(slope, depth, v):
    """A slope in a cell of depth ``depth``: 0 in a dry cell; the depth's own slope bounded so
    that both half-cell averages depth +- slope/4 keep at least half the depth."""
    if depth <= 0.0:
        return 0.0
    if v == DEPTH:
        limit = DEPTH_SLOPE_LIMIT * depth
        if slope > limit:
            return limit
        if slope < -limit:
            return -limit
    return slope


@njit(cache=True, error_model="numpy")
def cell_velocity(src, i):
    """``m / h`` of padded cell i, 0 if dry. Written without a branch around the division, so
    that the loads of h and m stay unconditional (a load in a branch cannot be vectorised)."""
    depth = src[DEPTH, col(i)]
    wet = depth >= DRY_DEPTH and depth > 0.0
    velocity = src[MOMENTUM, col(i)] / (depth if wet else 1.0)
    return velocity if wet else 0.0


@njit(cache=True)
def bound_momentum_slope(depth, momentum, slope, u_left, u_centre, u_right):
    """Clamp the momentum slope so that the velocities at both quarter points,
    ``(m +- m'/4) / (h +- h'/4)``, lie between the smallest and largest velocity of the cell
    and its two neighbours. The interval always contains ``m' = u h'``, so it is never empty."""
    u_min = min(u_left, u_centre, u_right)
    u_max = max(u_left, u_centre, u_right)
    plus = depth + 0.25 * slope[DEPTH]
    minus = depth - 0.25 * slope[DEPTH]
    low = max(4.0 * (plus * u_min - momentum), 4.0 * (momentum - minus * u_max))
    high = min(4.0 * (plus * u_max - momentum), 4.0 * (momentum - minus * u_min))
    value = slope[MOMENTUM]
    if value < low:
        value = low
    if value > high:
        value = high
    slope[MOMENTUM] = value


@njit(cache=True)
def resist(momentum, impulse):
    """Apply a resistive impulse ``impulse >= 0`` against ``momentum``: it stops the flow
    exactly (returns 0.0) when it is at least as large, and never reverses it."""
    if abs(momentum) <= impulse:
        return 0.0
    return momentum - impulse if momentum > 0.0 else momentum + impulse


@njit(cache=True, error_model="numpy", inline="always")
def velocity_range(src, i, dt, aux_centre, params, state, coefficients, out, film):
    """The Riemann invariants ``(u - 2c, u + 2c)`` of padded cell i (``c`` the wave speed less
    ``|u|``), widened, if the cell is flow (at least ``film`` deep), by the change of its
    velocity its source and resistance make in one step, the lower end by a decrease and the
    upper by an increase (an explicit step of both with the stopping rule: friction slows, it
    never speeds up).

    In the exact solution the Riemann invariants ``u -+ 2c`` obey a maximum principle, so a new
    film whose invariants leave the range of those of the cells its update reads is an artefact.
    It appears where the staggered average of a draining cell is a small difference of large
    terms (the tail a sliding body leaves behind), whose momentum and depth do not cancel alike:
    a tail of depth 3e-5 behind a body sliding down an 89-degree chute at 0.4 got u = -1.9
    (upslope). Only the flow widens the range by its forces: a film's own source (on terrain its
    curvature term, quadratic in its velocity) widened it step by step (docs/design.md,
    "Films")."""
    c = col(i)
    u = cell_velocity(src, i)
    for v in range(NV):
        state[v] = src[v, c]
    for k in range(NAUX):
        coefficients[k] = aux_centre[k, c]
    celerity = max(_max_speed_point(state, coefficients, params) - abs(u), 0.0)
    h = src[DEPTH, c]
    change = 0.0
    if h >= film and h > 0.0:
        momentum = src[MOMENTUM, c]
        driven = momentum
        if HAS_SOURCE:
            _source_point(state, coefficients, params, out)
            driven = momentum + dt * out[MOMENTUM]
        if HAS_RESISTANCE:
            driven = resist(driven, dt * _resistance_point(state, coefficients, params))
        change = (driven - momentum) / h
    return u - 2.0 * celerity + min(change, 0.0), u + 2.0 * celerity + max(change, 0.0)


@njit(cache=True, error_model="numpy", inline="always")
def predict_point(
    state, slope, coefficients, params, half_dt, inverse_dx, matrix, rate, result, predicted
):
    """The predictor of one cell, eq. (15): ``predicted = w + dt/2 (-A(w) w'/dx + s(w))``, then
    the resistance over dt/2 with the stopping rule. ``coefficients`` are the cell's (a model
    with dynamic coefficients sets them here from the slopes); ``matrix``, ``rate`` and
    ``result`` are scratch."""
    if HAS_DYNAMIC_COEFFICIENTS:
        _coefficients_point(state, slope, coefficients, params)
    _jacobian_point(state, coefficients, params, matrix)
    for r in range(NV):
        acc = 0.0
        for k in range(NV):
            acc += matrix[r, k] * slope[k]
        rate[r] = -acc * inverse_dx
    if HAS_SOURCE:
        _source_point(state, coefficients, params, result)
        for v in range(NV):
            rate[v] += result[v]
    for v in range(NV):
        predicted[v] = state[v] + half_dt * rate[v]
    if HAS_RESISTANCE:
        predicted[MOMENTUM] = resist(
            predicted[MOMENTUM], half_dt * _resistance_point(state, coefficients, params)
        )


@njit(cache=True, error_model="numpy", inline="always")
def film_velocity_range(src, i, dt, aux_centre, params, state, coefficients, out, film):
    """The smallest lower and the largest upper end of :func:`velocity_range` over padded cells
    ``i .. i + 3`` (the four source cells of a new cell). ``state``, ``coefficients`` and ``out``
    are scratch."""
    low, high = np.inf, -np.inf
    for other in range(i, i + 4):
        other_low, other_high = velocity_range(
            src, other, dt, aux_centre, params, state, coefficients, out, film
        )
        low = min(low, other_low)
        high = max(high, other_high)
    return low, high


@njit(cache=True, error_model="numpy", inline="always")
def rest_flux_bounds(predicted, coefficients, aux_centre, c, params, ratio):
    """``(low, span)``: the momentum flux of source cell ``c``'s mid-step state ``predicted``
    with the low end of the model's rest range, and ``ratio`` (``dt/dx``) times its change to
    the high end; ``coefficients`` is scratch."""
    high = local_vector(NAUX)
    flux = local_vector(NV)
    for k in range(NAUX):
        coefficients[k] = aux_centre[k, c]
        high[k] = aux_centre[k, c]
    _rest_coefficients_point(coefficients, high, params)
    _flux_point(predicted, coefficients, params, flux)
    low = flux[MOMENTUM]
    _flux_point(predicted, high, params, flux)
    return low, ratio * (flux[MOMENTUM] - low)


@njit(cache=True, error_model="numpy", inline="always")
def rest_flux_span(predicted, coefficients, aux_centre, c, params, ratio, work, j):
    """The FLUX_LOW and FLUX_SPAN rows of source cell ``c`` (work column ``j``) from its
    mid-step state (:func:`rest_flux_bounds`); ``coefficients`` is scratch."""
    low, span = rest_flux_bounds(predicted, coefficients, aux_centre, c, params, ratio)
    work[slot(FLUX_LOW, j)] = low
    work[slot(FLUX_SPAN, j)] = span


@njit(cache=True, error_model="numpy")
def predict_cells(
    src, first, count, dt, dx, aux_centre, aux_left_quarter, aux_right_quarter, parameters, work
):
    """For source cells ``first .. first + count - 1`` (work columns ``0 .. count - 1``): slope,
    predictor (eq. 15), flux at t^{n+1/2} (eq. 12; the mid-step state itself with interface
    coefficients), and the sources and resistance at the two quarter points (eqs. 13-14)."""
    state = local_vector(NV)
    slope = local_vector(NV)
    rate = local_vector(NV)
    result = local_vector(NV)
    predicted = local_vector(NV)
    coefficients = local_vector(NAUX)
    matrix = local_matrix(NV)
    params = local_vector(NPARAMS)
    load_params(parameters, params)
    half_dt = 0.5 * dt
    # A multiplication instead of NV divisions per cell (the reference path does the same).
    inverse_dx = 1.0 / dx
    if MOMENTUM >= 0:
        # Each velocity once (three cells use it), in its own loop (one division per cell).
        for j in range(count + 2):
            work[slot(VELOCITY, j)] = cell_velocity(src, first - 1 + j)
    rows = work[:WORK_SIZE].reshape((WORK_ROWS, STRIDE))
    stencil_slopes(
        src, first, count, dx, aux_centre, int(parameters[SLOPE_CODE]), rows[STENCIL],
        rows[SLOPE : SLOPE + NV],
    )  # fmt: skip
    for j in range(count):
        i = first + j
        c = col(i)
        for v in range(NV):
            state[v] = src[v, c]
            slope[v] = finished_slope(work[slot(SLOPE + v, j)], v, src, c, dx, aux_centre)
        if MOMENTUM >= 0 and state[DEPTH] > 0.0:
            bound_momentum_slope(
                state[DEPTH], state[MOMENTUM], slope, work[slot(VELOCITY, j)],
                work[slot(VELOCITY, j + 1)], work[slot(VELOCITY, j + 2)],
            )  # fmt: skip
        for v in range(NV):
            work[slot(SLOPE + v, j)] = slope[v]
        for k in range(NAUX):
            coefficients[k] = aux_centre[k, c]
        predict_point(
            state, slope, coefficients, params, half_dt, inverse_dx, matrix, rate, result,
            predicted,
        )  # fmt: skip
        if HAS_INTERFACE_COEFFICIENTS:
            # The flux depends on coefficients of the new cell: average_cells evaluates it.
            for v in range(NV):
                work[slot(FLUX + v, j)] = predicted[v]
        else:
            _flux_point(predicted, coefficients, params, result)
            for v in range(NV):
                work[slot(FLUX + v, j)] = result[v]
        if HAS_REST_COEFFICIENTS:
            rest_flux_span(predicted, coefficients, aux_centre, c, params, dt * inverse_dx, work, j)
        if HAS_BALANCED_SOURCE:
            for v in range(NV):
                work[slot(SOURCE_LEFT + v, j)] = predicted[v]
        elif HAS_SOURCE or HAS_RESISTANCE:
            for v in range(NV):
                state[v] = predicted[v] + 0.25 * slope[v]
            for k in range(NAUX):
                coefficients[k] = aux_right_quarter[k, c]
            if HAS_SOURCE:
                _source_point(state, coefficients, params, result)
                for v in range(NV):
                    work[slot(SOURCE_RIGHT + v, j)] = result[v]
            if HAS_RESISTANCE:
                work[slot(RESIST_RIGHT, j)] = _resistance_point(state, coefficients, params)
            for v in range(NV):
                state[v] = predicted[v] - 0.25 * slope[v]
            for k in range(NAUX):
                coefficients[k] = aux_left_quarter[k, c]
            if HAS_SOURCE:
                _source_point(state, coefficients, params, result)
                for v in range(NV):
                    work[slot(SOURCE_LEFT + v, j)] = result[v]
            if HAS_RESISTANCE:
                work[slot(RESIST_LEFT, j)] = _resistance_point(state, coefficients, params)


@njit(cache=True, error_model="numpy", inline="always")
def new_cell_speed(state, coefficients, params):
    """Largest wave speed of a new cell, NaN if it is inadmissible (the SPEED row)."""
    speed = np.nan
    if _admissible_point(state, coefficients, params):
        speed = _max_speed_point(state, coefficients, params)
    return speed


@njit(cache=True, inline="always")
def no_finite_speed(speed):
    """Whether a SPEED-row value is not a finite wave speed >= 0 (inadmissible, or overflow)."""
    return not (speed >= 0.0 and speed < np.inf)


@njit(cache=True, error_model="numpy", inline="always")
def film_celerity(speed, velocity):
    """The celerity ``c`` of a new film: its wave speed ``speed`` less ``|velocity|``, 0 if that
    is not a positive number (a velocity that overflows, an inadmissible state)."""
    celerity = speed - abs(velocity)
    return celerity if celerity > 0.0 else 0.0


@njit(cache=True, inline="always")
def in_film(depth, film):
    """Whether a new cell of depth ``depth`` is a film: wet, and shallower than ``film`` (``FILM``
    times the deepest cell of its source family; where :func:`bound_film_velocities` acts)."""
    return depth >= DRY_DEPTH and depth > 0.0 and depth < film


@njit(cache=True)
def film_depth(src, n):
    """``FILM`` times the deepest of the ``n`` real cells of ``src``: a new cell shallower than
    this is a film, a source cell at least this deep is flow."""
    deepest = 0.0
    for i in range(NG, NG + n):
        deepest = max(deepest, src[DEPTH, col(i)])
    return FILM * deepest


@njit(cache=True, error_model="numpy", inline="always")
def bounded_film_momentum(
    src, left, depth, momentum, dt, aux_centre, params, state, coefficients, out, film, speed
):
    """``(momentum, changed)`` of a new cell of depth ``depth`` and wave speed ``speed`` over
    source cells ``left``, ``left + 1`` after the bound of films: in a film (:func:`in_film`) a
    velocity whose Riemann invariants leave the range of those of the four source cells
    (:func:`film_velocity_range`), or that lies beyond rest and that range, is moved to the
    nearer end. ``state``, ``coefficients`` and ``out`` are scratch."""
    if not in_film(depth, film):
        return momentum, False
    low, high = film_velocity_range(
        src, left - 1, dt, aux_centre, params, state, coefficients, out, film
    )
    velocity = momentum / depth
    celerity = film_celerity(speed, velocity)
    low = min(low + 2.0 * celerity, 0.0)
    high = max(high - 2.0 * celerity, 0.0)
    if velocity < low:
        return low * depth, True
    if velocity > high:
        return high * depth, True
    return momentum, False


@njit(cache=True, error_model="numpy")
def bound_film_velocities(
    src, dst, first, dst_first, count, dt, aux_centre, aux_dst, params, work, film
):
    """In each film (:func:`in_film`) among the new cells ``dst_first .. dst_first + count -
    1``, clamp the velocity to the range of its four source cells (:func:`film_velocity_range`),
    and redo its wave speed in the SPEED row.

    A second pass over a block in which :func:`average_cells` counted a film (rare), with
    the same arithmetic as a clamp inside that loop. Returns the change in its counts of moving
    cells and of cells without a finite wave speed (the depth, and so the count of negative
    depths, is not changed).
    """
    state = local_vector(NV)
    coefficients = local_vector(NAUX)
    probe = local_vector(NV)
    probe_coefficients = local_vector(NAUX)
    result = local_vector(NV)
    moving_change = 0
    bad_change = 0
    for j in range(count):
        new = col(dst_first + j)
        momentum = dst[MOMENTUM, new]
        for v in range(NV):
            state[v] = dst[v, new]
        for k in range(NAUX):
            coefficients[k] = aux_dst[k, new]
        bounded, changed = bounded_film_momentum(
            src, first + j, dst[DEPTH, new], momentum, dt, aux_centre, params, probe,
            probe_coefficients, result, film, _max_speed_point(state, coefficients, params),
        )  # fmt: skip
        if not changed:
            continue
        dst[MOMENTUM, new] = bounded
        moving_change += int(bounded != 0.0) - int(momentum != 0.0)
        state[MOMENTUM] = bounded
        speed = new_cell_speed(state, coefficients, params)
        bad_change += int(no_finite_speed(speed)) - int(no_finite_speed(work[slot(SPEED, j)]))
        work[slot(SPEED, j)] = speed
    return moving_change, bad_change


@njit(cache=True, error_model="numpy", inline="always")
def interface_fluxes(
    state_left, state_right, aux_centre, left, right, params, flux_left, flux_right
):
    """The fluxes at the two ends of a new cell, at the centres of its source cells ``left``,
    ``right`` with the mid-step states ``state_left``, ``state_right``, both evaluated with the
    coefficients that the model's ``interface_coefficients_point`` chooses for the cell."""
    coefficients_left = local_vector(NAUX)
    coefficients_right = local_vector(NAUX)
    for k in range(NAUX):
        coefficients_left[k] = aux_centre[k, left]
        coefficients_right[k] = aux_centre[k, right]
    _interface_coefficients_point(
        state_left, state_right, coefficients_left, coefficients_right, params
    )
    _flux_point(state_left, coefficients_left, params, flux_left)
    _flux_point(state_right, coefficients_right, params, flux_right)


@njit(cache=True, error_model="numpy", inline="always")
def centre_fluxes(
    work, j, aux_centre, left, right, params, predicted, neighbour, flux_left, flux_right
):
    """The fluxes at the two ends of new cell ``j`` (at the centres of its source cells ``left``
    and ``right``) into ``flux_left`` and ``flux_right``: the FLUX rows of work columns ``j``,
    ``j + 1``, or with interface coefficients the fluxes of the mid-step states those rows hold
    (:func:`interface_fluxes`; ``predicted`` and ``neighbour`` are scratch)."""
    if HAS_INTERFACE_COEFFICIENTS:
        for v in range(NV):
            predicted[v] = work[slot(FLUX + v, j)]
            neighbour[v] = work[slot(FLUX + v, j + 1)]
        interface_fluxes(
            predicted, neighbour, aux_centre, left, right, params, flux_left, flux_right
        )
    else:
        for v in range(NV):
            flux_left[v] = work[slot(FLUX + v, j)]
            flux_right[v] = work[slot(FLUX + v, j + 1)]


@njit(cache=True, error_model="numpy", inline="always")
def record_rest_terms(work, j, g, momentum, ratio, flux_left, flux_right):
    """For :func:`hold_static_runs`: new cell ``g``'s momentum with the low end of the rest
    range at both ends instead (``momentum`` is with the cell's own coefficients), its resistive
    impulse (0 until the resistance is known) and the FLUX_SPAN of its two source cells (work
    columns ``j``, ``j + 1``)."""
    low = (work[slot(FLUX_LOW, j + 1)] - work[slot(FLUX_LOW, j)]) - (
        flux_right[MOMENTUM] - flux_left[MOMENTUM]
    )
    work[rest_slot(work, REST_MOMENTUM, g)] = momentum - ratio * low
    work[rest_slot(work, REST_IMPULSE, g)] = 0.0
    work[rest_slot(work, REST_SPAN, g)] = work[slot(FLUX_SPAN, j)]
    work[rest_slot(work, REST_SPAN, g + 1)] = work[slot(FLUX_SPAN, j + 1)]


@njit(cache=True, error_model="numpy", inline="always")
def resisted(work, j, g, momentum, half_dt):
    """New cell ``g``'s ``momentum`` after the resistance at its two quarter points (eqs. 13-14,
    the RESIST rows of work columns ``j``, ``j + 1``), applied with the stopping rule
    (docs/design.md, "Savage–Hutter specifics"); with rest coefficients the impulse is kept for
    :func:`hold_static_runs`."""
    impulse = half_dt * (work[slot(RESIST_RIGHT, j)] + work[slot(RESIST_LEFT, j + 1)])
    if HAS_REST_COEFFICIENTS:
        work[rest_slot(work, REST_IMPULSE, g)] = impulse
    return resist(momentum, impulse)


@njit(cache=True, error_model="numpy")
def average_cells(
    src, dst, first, dst_first, count, dt, dx, aux_centre, aux_dst, parameters, work, film
):
    """The new cells ``dst_first ..`` (eq. 10) of ``count`` from source cells ``first ..`` and
    the work columns ``0 .. count``, films (shallower than ``film``) bounded; the wave speed of
    each new cell to the SPEED row (NaN if inadmissible). Returns how many new cells have a
    negative depth, a non-zero momentum, and no finite wave speed >= 0 (inadmissible, overflow)."""
    state = local_vector(NV)
    predicted = local_vector(NV)
    neighbour = local_vector(NV)
    result = local_vector(NV)
    flux_left = local_vector(NV)
    flux_right = local_vector(NV)
    coefficients = local_vector(NAUX)
    other = local_vector(NAUX)
    params = local_vector(NPARAMS)
    load_params(parameters, params)
    half_dt = 0.5 * dt
    ratio = dt / dx
    negative = 0
    moving = 0
    bad = 0
    films = 0
    for j in range(count):
        left = col(first + j)
        right = col(first + j + 1)
        centre_fluxes(
            work, j, aux_centre, left, right, params, predicted, neighbour, flux_left, flux_right
        )
        if HAS_BALANCED_SOURCE:
            for v in range(NV):
                predicted[v] = work[slot(SOURCE_LEFT + v, j)]
                neighbour[v] = work[slot(SOURCE_LEFT + v, j + 1)]
            for k in range(NAUX):
                coefficients[k] = aux_centre[k, left]
                other[k] = aux_centre[k, right]
            _balanced_source_point(predicted, neighbour, coefficients, other, dx, params, result)
        for v in range(NV):
            value = (
                0.5 * (src[v, left] + src[v, right])
                + 0.125 * (work[slot(SLOPE + v, j)] - work[slot(SLOPE + v, j + 1)])
                - ratio * (flux_right[v] - flux_left[v])
            )
            if HAS_BALANCED_SOURCE:
                value += dt * result[v]
            elif HAS_SOURCE:
                value += half_dt * (
                    work[slot(SOURCE_RIGHT + v, j)] + work[slot(SOURCE_LEFT + v, j + 1)]
                )
            state[v] = value
        if HAS_REST_COEFFICIENTS:
            record_rest_terms(
                work, j, dst_first - NG + j, state[MOMENTUM], ratio, flux_left, flux_right
            )
        if HAS_RESISTANCE:
            state[MOMENTUM] = resisted(work, j, dst_first - NG + j, state[MOMENTUM], half_dt)
        new = col(dst_first + j)
        for k in range(NAUX):
            coefficients[k] = aux_dst[k, new]
        if HAS_CORRECTION:
            _correct_point(state, coefficients, params, dt)
        if DEPTH >= 0 and MOMENTUM >= 0 and in_film(state[DEPTH], film):
            films += 1  # bounded after the loop, so that this one stays vectorised
        for v in range(NV):
            dst[v, new] = state[v]
        if DEPTH >= 0 and state[DEPTH] < 0.0:
            negative += 1
        if MOMENTUM >= 0 and state[MOMENTUM] != 0.0:
            moving += 1
        speed = new_cell_speed(state, coefficients, params)
        if no_finite_speed(speed):
            bad += 1
        work[slot(SPEED, j)] = speed
    if films > 0:
        moving_change, bad_change = bound_film_velocities(
            src, dst, first, dst_first, count, dt, aux_centre, aux_dst, params, work, film
        )
        moving += moving_change
        bad += bad_change
    return negative, moving, bad


@njit(cache=True, error_model="numpy", inline="always")
def holdable(work, g):
    """Whether new cell ``g`` could be brought to rest with both its ends free: its momentum
    with the low end of the rest range, changed by at most the spans at its two ends, within
    its impulse (a filter: the runs themselves fix the ends of each run)."""
    momentum = work[rest_slot(work, REST_MOMENTUM, g)]
    impulse = work[rest_slot(work, REST_IMPULSE, g)]
    reach_up = work[rest_slot(work, REST_SPAN, g)]
    reach_down = work[rest_slot(work, REST_SPAN, g + 1)]
    return momentum - impulse <= reach_up and momentum + impulse >= -reach_down


@njit(cache=True, error_model="numpy")
def longest_held_from(work, start, stop):
    """The largest ``end`` in ``start .. stop - 1`` such that some choice of the flux changes
    ``d_c`` in ``[0, REST_SPAN_c]`` at the interior centres of new cells ``start .. end``
    (``d = 0`` at both ends of the run) brings every one of them within its impulse of rest;
    ``start - 1`` if there is none. A chain of interval constraints: the set of ``d`` reachable
    at each centre is an interval, swept once."""
    low = 0.0
    high = 0.0
    end = start - 1
    for k in range(start, stop):
        momentum = work[rest_slot(work, REST_MOMENTUM, k)]
        impulse = work[rest_slot(work, REST_IMPULSE, k)]
        # d_{k+1} = d_k + x with x in [momentum - impulse, momentum + impulse].
        low, high = low + momentum - impulse, high + momentum + impulse
        if low <= 0.0 <= high:
            end = k
        if k + 1 < stop:
            low = max(low, 0.0)
            high = min(high, work[rest_slot(work, REST_SPAN, k + 1)])
            if low > high:
                break
    return end


@njit(cache=True)
def stop_cells(dst, start, stop):
    """Set the momentum of new cells ``start .. stop - 1`` to 0; returns how many moved."""
    stopped = 0
    for g in range(start, stop):
        c = col(NG + g)
        if dst[MOMENTUM, c] != 0.0:
            dst[MOMENTUM, c] = 0.0
            stopped += 1
    return stopped


@njit(cache=True, error_model="numpy")
def hold_static_runs(dst, n_dst, seam, work):
    """Stop the runs of new cells that friction and a statically admissible earth pressure
    bring to rest within the step; returns how many of them this stopped (their momentum is
    set to 0). The implicit treatment of the set-valued laws at rest: as the stopping rule
    lets Coulomb friction take any value up to its limit that stops a cell within the step,
    so material that ends the step at rest is not yielding, and its coefficients (the
    Savage–Hutter earth pressure) may lie anywhere in the model's rest range at every
    source-cell centre, as long as each centre's flux stays one value shared by its two new
    cells (a continuous pressure, which exerts no net force on the run).

    ``REST_MOMENTUM`` holds each new cell's momentum before the stopping rule with the low end
    of the range at both its ends; raising the flux at interior centre ``c`` of a run by ``d_c``
    in ``[0, REST_SPAN_c]`` changes new cell ``g``'s momentum by ``d_g - d_{g+1}``, and the cell
    is held iff the result is within its resistive impulse ``REST_IMPULSE``. The ends of a run
    share their centre with a cell that keeps moving (or a boundary): ``d = 0`` there.

    Within each maximal stretch of cells that could each be held alone (:func:`holdable`), the
    longest run that can be held as a whole (:func:`longest_held_from` from every start) is
    held, and the stretches on either side of it are treated the same way; a tie between
    overlapping runs holds neither. The result is the same read from either end (a mirror
    image is held as the mirror image) (docs/design.md, "Earth pressure"). On a periodic domain
    the staggered cell ``seam`` (-1: none) straddles the ends of the index range; it is left to
    friction alone, so that runs never wrap and the mirror image of a periodic state (which maps
    that cell onto itself) is treated the same way.
    """
    stopped = 0
    g = 0
    # Stretches still to treat, [start, stop) pairs (as floats: a stack array; each split
    # replaces one stretch by two, so the depth stays small; a stretch that does not fit is
    # left unheld).
    stack = local_vector(STACK_SIZE)
    while g < n_dst:
        if g == seam or not holdable(work, g):
            g += 1
            continue
        stop = g + 1
        while stop < n_dst and stop != seam and holdable(work, stop):
            stop += 1
        stack[0], stack[1] = g, stop
        depth = 2
        while depth > 0:
            depth -= 2
            start, end = int(stack[depth]), int(stack[depth + 1])
            best_start, best_stop, tied = start, start, False
            for first in range(start, end):
                last = longest_held_from(work, first, end)
                length = last + 1 - first
                if length > best_stop - best_start:
                    best_start, best_stop, tied = first, last + 1, False
                elif length > 0 and length == best_stop - best_start and first < best_stop:
                    tied = True  # an equally long run overlapping the best one
                if last + 1 >= end:
                    break  # a later start can only give a shorter run
            if best_stop == best_start or tied:
                continue
            stopped += stop_cells(dst, best_start, best_stop)
            if depth + 4 <= STACK_SIZE:
                stack[depth], stack[depth + 1] = start, best_start
                stack[depth + 2], stack[depth + 3] = best_stop, end
                depth += 4
        g = stop
    return stopped


@njit(cache=True)
def block_speed(work, count):
    """Largest value of the SPEED row (all finite and >= 0), as LANES partial maxima that the
    compiler turns into one SIMD maximum per LANES cells."""
    lanes = local_vector(LANES)
    for lane in range(LANES):
        lanes[lane] = 0.0
    padded = (count + LANES - 1) // LANES * LANES
    for j in range(count, padded):
        work[slot(SPEED, j)] = 0.0
    for start in range(0, padded, LANES):
        for lane in range(LANES):
            speed = work[slot(SPEED, start + lane)]
            if speed > lanes[lane]:
                lanes[lane] = speed
    largest = 0.0
    for lane in range(LANES):
        if lanes[lane] > largest:
            largest = lanes[lane]
    return largest


@njit(cache=True, error_model="numpy")
def nt_step(src, dst, source, target, shift, dt, dx, params, boundary, work):
    """One staggered step from ``src`` (cells of the :class:`Family` ``source``) into ``dst``
    (cells of ``target``), one pass; ``shift`` is -1 from the primary family, 0 from the
    staggered one.

    Returns ``(largest, bad, negative, moving)``: the largest wave speed of the new cells, the
    first of them that is inadmissible or has no finite speed (``(-1, i)``/``(-2, i)`` as in
    :func:`max_speed`, else ``(largest, -1)``), and how many have a negative depth and a
    non-zero momentum.
    """
    n_src, n_dst = source.cells, target.cells
    aux_centre, aux_dst = source.aux, target.aux
    src_staggered = shift >= 0
    fill_ghosts(src, n_src, src_staggered, boundary.left, boundary.right)
    first = NG + shift
    largest = 0.0
    bad = 0
    negative = 0
    moving = 0
    film = film_depth(src, n_src) if DEPTH >= 0 and MOMENTUM >= 0 else 0.0
    for start in range(0, n_dst, BLOCK):
        count = min(BLOCK, n_dst - start)
        predict_cells(
            src, first + start, count + 1, dt, dx, aux_centre, source.aux_left, source.aux_right,
            params, work,
        )  # fmt: skip
        block_negative, block_moving, block_bad = average_cells(
            src, dst, first + start, NG + start, count, dt, dx, aux_centre, aux_dst, params, work,
            film,
        )  # fmt: skip
        negative += block_negative
        moving += block_moving
        bad += block_bad
        if bad == 0:
            block_largest = block_speed(work, count)
            if block_largest > largest:
                largest = block_largest
    if HAS_REST_COEFFICIENTS:
        # On a periodic domain (as many staggered cells as primary ones) the staggered cell 0
        # is centred on the seam.
        seam = 0 if n_dst == n_src and shift < 0 else -1
        moving -= hold_static_runs(dst, n_dst, seam, work)
    if bad > 0:
        # Rare path: find the first bad cell and tell an inadmissible state from an overflowing
        # wave speed, as max_speed does.
        code, cell = max_speed(dst, n_dst, aux_dst, params)
        return code, cell, negative, moving
    return largest, -1, negative, moving


@njit(cache=True, error_model="numpy")
def depth_share(w, i, side, dt, dx, aux, parameters):
    """The part of the depth of padded cell i that a step hands to the new cell on its ``side``
    (+1: right, -1: left), as :func:`average_cells` forms it (eq. 10):
    ``h/2 + side (h'/8 + dt/dx f_h(w^{n+1/2}))``, with the slope, predictor and flux of
    :func:`predict_cells`."""
    state = local_vector(NV)
    slope = local_vector(NV)
    rate = local_vector(NV)
    result = local_vector(NV)
    predicted = local_vector(NV)
    coefficients = local_vector(NAUX)
    matrix = local_matrix(NV)
    params = local_vector(NPARAMS)
    load_params(parameters, params)
    values = local_vector(5)
    slopes = local_matrix(NV)
    stencil_slopes(w, i, 1, dx, aux, int(parameters[SLOPE_CODE]), values, slopes)
    c = col(i)
    for v in range(NV):
        state[v] = w[v, c]
        slope[v] = finished_slope(slopes[v, 0], v, w, c, dx, aux)
    if state[DEPTH] > 0.0:
        bound_momentum_slope(
            state[DEPTH], state[MOMENTUM], slope, cell_velocity(w, i - 1), cell_velocity(w, i),
            cell_velocity(w, i + 1),
        )  # fmt: skip
    for k in range(NAUX):
        coefficients[k] = aux[k, c]
    predict_point(
        state, slope, coefficients, params, 0.5 * dt, 1.0 / dx, matrix, rate, result, predicted
    )
    _flux_point(predicted, coefficients, params, result)
    return 0.5 * state[DEPTH] + side * (0.125 * slope[DEPTH] + dt / dx * result[DEPTH])


@njit(cache=True)
def at_rest(w0, w2, j):
    """Whether primary cell ``j`` was at rest through a step pair: dry at its start, or holding
    no momentum before (``w0``) and after (``w2``) it (friction held it)."""
    c = col(NG + j)
    depth = w0[DEPTH, c]
    dry = not (depth >= DRY_DEPTH and depth > 0.0)
    return dry or (w0[MOMENTUM, c] == 0.0 and w2[MOMENTUM, c] == 0.0)


@njit(cache=True, error_model="numpy")
def face_transfer(w0, w1, face, dt, dx, aux0, aux1, params):
    """The depth a step pair moved rightwards across primary face ``face`` (between primary
    cells ``face - 1`` and ``face``; ghost cells at the boundaries): what the first step handed
    from cell ``face - 1`` to the staggered cell centred on the face less what the second step
    handed back from that staggered cell to it, which equals what cell ``face`` got back from
    that staggered cell less what it handed to it. Both, averaged: the same value to the last
    bit, with its sign flipped, for the mirror image of the data."""
    from_left = depth_share(w0, NG + face - 1, 1.0, dt, dx, aux0, params) - depth_share(
        w1, NG + face, -1.0, dt, dx, aux1, params
    )
    to_right = depth_share(w1, NG + face, 1.0, dt, dx, aux1, params) - depth_share(
        w0, NG + face, -1.0, dt, dx, aux0, params
    )
    return 0.5 * (from_left - (-to_right))


@njit(cache=True, error_model="numpy")
def face_correction(w0, w1, w2, face, rest_left, dt, dx, aux0, aux1, params):
    """``(moved, returned)`` at an interior face with exactly one side at rest (the left one if
    ``rest_left``): the depth the pair moved across it rightwards, and the part of it that is
    taken back. Depth crosses only if the material of the moving side moves towards the face
    (the sign of its momentum before plus after the pair): the larger of what the pair moved
    from it into the other cell (at rest or dry) and its donor-cell flux, ``dt/dx`` times that
    momentum, the flux at most the moving cell's depth at the start of the pair (its momentum
    after the pair may belong to depth that the averaging moved in from the material at rest,
    which goes back). So nothing leaves material at rest, a moving cell spreads nothing against
    its motion, and a moving film drains in its direction of motion (without the flux into a
    dry cell, a film at the dry depth on a slope too steep to hold it kept its place and its
    velocity for ever)."""
    moved = face_transfer(w0, w1, face, dt, dx, aux0, aux1, params)
    moving = col(NG + face) if rest_left else col(NG + face - 1)
    momentum = w0[MOMENTUM, moving] + w2[MOMENTUM, moving]
    towards = momentum < 0.0 if rest_left else momentum > 0.0
    allowed = 0.0
    if towards:
        # Rightwards is positive: at least the donor-cell flux.
        donor = min(dt / dx * abs(momentum), w0[DEPTH, moving])
        allowed = min(moved, -donor) if rest_left else max(moved, donor)
    return moved, moved - allowed


@njit(cache=True, error_model="numpy")
def hold_resting_cells(w0, w1, w2, n0, dt, dx, aux0, aux1, params, work):
    """Give back, in ``w2`` (the state after a step pair from ``w0`` through ``w1``), every depth
    that the pair moved out of a cell at rest (:func:`at_rest`): material held by friction
    stays where it is (``h_t = -m_x = 0`` there). Without this, the staggered averaging moves
    depth out of cells at rest as numerical diffusion: a deposit would keep smearing while
    anything else moves, and its faces would feed margins that never stop. Depth may still
    flow into a cell at rest (:func:`face_correction`).

    A cell at rest gets its old depth less what crosses its faces (nothing where both sides
    are at rest: such a cell keeps its state bit for bit); a moving cell gets the pair's result
    with what it received from a cell at rest taken back, and what it gives to one by its
    donor-cell flux beyond what the pair moved. Conservative to round-off: what one cell of a
    face gets back, the other gives (a moving cell emptied to within ``ROUND_OFF`` of its terms
    is set to 0). A moving cell that gives depth back keeps its momentum, but is made no faster
    than it was at the start or end of the pair. Nothing changes anywhere if a depth would
    become negative beyond round-off (checked in a first pass; ``work``, free after the pair,
    keeps the face transfers for the second): rarer since the donor-cell flux is at most the
    moving cell's start depth, but still possible where a moving cell also loses depth across
    its other face. A changed cell gets the model's correction (a cell left below the dry depth
    holds no momentum). Returns the largest wave speed of the changed wet cells (0 if none) and
    how many changed cells stopped moving.
    """
    state = local_vector(NV)
    coefficients = local_vector(NAUX)
    local = local_vector(NPARAMS)
    load_params(params, local)
    largest = 0.0
    stopped = 0
    capacity = work.size // 2
    stored = 0
    for apply in range(2):
        used = 0
        # The right face of the previous cell is the left face of this one.
        rest_right = at_rest(w0, w2, 0)
        moved_right, returned_right = 0.0, 0.0
        if rest_right:
            moved_right = face_transfer(w0, w1, 0, dt, dx, aux0, aux1, params)
        for j in range(n0):
            rest = rest_right
            moved_left, returned_left = moved_right, returned_right
            moved_right, returned_right = 0.0, 0.0
            if j + 1 < n0:
                rest_right = at_rest(w0, w2, j + 1)
                if rest != rest_right:
                    if apply == 1 and used < stored:
                        moved_right, returned_right = work[2 * used], work[2 * used + 1]
                    else:
                        moved_right, returned_right = face_correction(
                            w0, w1, w2, j + 1, rest, dt, dx, aux0, aux1, params
                        )
                        if apply == 0 and used < capacity:
                            work[2 * used], work[2 * used + 1] = moved_right, returned_right
                            stored = used + 1
                    used += 1
            elif rest:
                moved_right = face_transfer(w0, w1, n0, dt, dx, aux0, aux1, params)
            c = col(NG + j)
            if rest:
                # What still crosses each face (nothing between two cells at rest). Sums
                # grouped so that the mirror image of the data gives the same bits.
                depth = w0[DEPTH, c] + (
                    (moved_left - returned_left) - (moved_right - returned_right)
                )
            elif returned_left == 0.0 and returned_right == 0.0:
                continue  # no face at rest: the pair's own result
            else:
                depth = w2[DEPTH, c] + (returned_right - returned_left)
                if depth < 0.0 and depth >= -ROUND_OFF * (
                    w2[DEPTH, c] + (abs(returned_right) + abs(returned_left))
                ):
                    depth = 0.0  # a moving cell emptied into material at rest, to round-off
            if depth < 0.0:
                return 0.0, 0
            if apply == 0 or depth == w2[DEPTH, c]:
                continue
            speed, stops = give_depth(w0, w2, j, rest, depth, dt, aux0, local, state, coefficients)
            stopped += stops
            if speed > largest:
                largest = speed
    return largest, stopped


@njit(cache=True, error_model="numpy")
def give_depth(w0, w2, j, rest, depth, dt, aux0, params, state, coefficients):
    """Set real cell ``j`` of ``w2`` (the state after a pair from ``w0``) to the depth ``depth``
    that :func:`hold_resting_cells` found: a cell at rest keeps its velocity, a moving cell that
    gives depth back its momentum but no more speed than at either end of the pair; then the
    model's correction. Returns the cell's wave speed (0 if dry) and 1 if it stopped moving."""
    c = col(NG + j)
    for v in range(NV):
        state[v] = w2[v, c]
    if rest and state[MOMENTUM] != 0.0:
        # A cell dry at the start keeps the velocity of what it may still receive.
        state[MOMENTUM] *= depth / state[DEPTH]
    elif depth < state[DEPTH]:
        # A moving cell that gives depth back is no faster than it was at the start or end of
        # the pair (the depth it gives back carried no momentum of its own).
        fastest = max(abs(cell_velocity(w0, NG + j)), abs(cell_velocity(w2, NG + j)))
        if abs(state[MOMENTUM]) > depth * fastest:
            state[MOMENTUM] = np.copysign(depth * fastest, state[MOMENTUM])
    state[DEPTH] = depth
    for k in range(NAUX):
        coefficients[k] = aux0[k, c]
    if HAS_CORRECTION:
        _correct_point(state, coefficients, params, dt)
    stops = int(state[MOMENTUM] == 0.0 and w2[MOMENTUM, c] != 0.0)
    for v in range(NV):
        w2[v, c] = state[v]
    if depth >= DRY_DEPTH:  # a dry cell's wave speed cannot matter
        return _max_speed_point(state, coefficients, params), stops
    return 0.0, stops


@njit(cache=True)
def finish(buffers, now, n0, t, pairs, status, family, cell, dt):
    """Leave the primary state in ``buffers[0]`` and return the result of :func:`advance`."""
    if now != 0:
        copy_cells(buffers[now], buffers[0], n0)
    return t, pairs, status, family, cell, dt


@njit(cache=True, error_model="numpy")
def step_pair(src, mid, dst, primary, staggered, dt, last, controls, params, boundary, work):
    """The two steps of a pair, ``src`` -> ``mid`` (staggered) -> ``dst`` (primary), with one
    ``dt``: the pair is redone with half the ``dt`` while a depth would become negative, and
    with the ``dt`` of the Courant bound if the second step's would reach 1/2 (``last`` then
    becomes False: the pair no longer lands on the end time).

    Returns ``(status, family, cell, dt, last, speed, bad, moving_mid, moving_end)``:
    ``STATUS_DONE`` with the largest wave speed, first bad cell and number of moving cells of
    ``dst`` (and the moving cells of ``mid``), or a failure status with the family and cell
    that :func:`advance` reports.
    """
    dx = controls.dx
    # The shifts as run-time values: constants would be typed as literals and compile nt_step
    # once per family, on top of the one-step interface.
    shift_up, shift_down = 0 * primary.cells - 1, 0 * primary.cells
    for _ in range(MAX_RETRIES):
        if dt < controls.dt_floor and not last:
            return STATUS_DT_FLOOR, 0, -1, dt, last, 0.0, -1, 0, 0
        speed1, bad1, negative1, moving1 = nt_step(
            src, mid, primary, staggered, shift_up, dt, dx, params, boundary, work
        )
        if negative1 > 0:
            dt *= 0.5
            last = False
            continue
        if bad1 >= 0:
            return failure(speed1), 1, bad1, dt, last, 0.0, -1, 0, 0
        if speed1 * dt / dx >= CFL_LIMIT:
            dt = controls.cfl * dx / speed1
            last = False
            continue
        speed2, bad2, negative2, moving2 = nt_step(
            mid, dst, staggered, primary, shift_down, dt, dx, params, boundary, work
        )
        if negative2 > 0:
            dt *= 0.5
            last = False
            continue
        return STATUS_DONE, 0, -1, dt, last, speed2, bad2, moving1, moving2
    if dt < controls.dt_floor:
        return STATUS_DT_FLOOR, 0, -1, dt, last, 0.0, -1, 0, 0
    return STATUS_CFL_UNREACHABLE, 1, -1, dt, last, 0.0, -1, 0, 0


@njit(cache=True, error_model="numpy")
def advance(buffers, primary, staggered, t, controls, params, boundary):
    """Advance ``buffers.w0`` (cells of the :class:`Family` ``primary``) by pairs of steps
    towards ``controls.t_end``.

    Each pair uses one ``dt = cfl dx / a_max`` (at most ``source_step_limit``) for both half
    steps, so the state is back on the primary family after every pair; the last pair is
    shortened to land on ``t_end`` exactly. A pair is redone with a smaller ``dt`` (the state is
    untouched until the pair is accepted) if the Courant number of its second half would reach
    1/2, or if a depth would become negative (:func:`step_pair`).
    With a resistance, a pair that starts and ends with every momentum exactly zero leaves the
    state unchanged (static equilibrium under Coulomb friction).

    The half step goes to ``w1``; the full step to whichever of ``w0``/``w2`` does not hold the
    state, and accepting a pair swaps the two (no copy); on return the state is in ``w0``, and
    after a failure in the staggered family (``family = 1``) that state is in ``w1``.

    Returns ``(t, pairs, status, family, cell, dt)``.
    """
    # The state is in states[now]; the half step always goes to w1, the full step to
    # states[full]; accepting a pair swaps now and full.
    states = (buffers.w0, buffers.w1, buffers.w2)
    now, full = 0, 2
    n0, dx, cfl = primary.cells, controls.dx, controls.cfl
    pairs = 0
    dt = 0.0
    speed, bad = max_speed(states[0], n0, primary.aux, params)
    moving = count_moving(states[0], n0)
    while t < controls.t_end:
        if pairs >= controls.max_pairs:
            return finish(states, now, n0, t, pairs, STATUS_PAUSED, 0, -1, dt)
        if bad >= 0:
            return finish(states, now, n0, t, pairs, failure(speed), 0, bad, dt)
        remaining = controls.t_end - t
        dt = cfl * dx / speed if speed > 0.0 else remaining
        dt = min(dt, source_step_limit(states[now], n0, primary.aux, params, cfl, dx))
        last = False
        if 2.0 * dt >= remaining:
            dt = 0.5 * remaining
            last = True
        status, family, cell, dt, last, speed2, bad2, moving1, moving2 = step_pair(
            states[now], buffers.w1, states[full], primary, staggered, dt, last, controls, params,
            boundary, buffers.work,
        )  # fmt: skip
        if status != STATUS_DONE:
            return finish(states, now, n0, t, pairs, status, family, cell, dt)
        static = HAS_RESISTANCE and moving == 0 and moving1 == 0 and moving2 == 0
        if HAS_RESISTANCE and DEPTH >= 0 and MOMENTUM >= 0 and not static and moving < n0:
            # Cells that friction held at rest give no depth away.
            held_speed, stopped = hold_resting_cells(
                states[now], buffers.w1, states[full], n0, dt, dx, primary.aux, staggered.aux,
                params, buffers.work,
            )  # fmt: skip
            speed2 = max(speed2, held_speed)
            moving2 -= stopped
        if not static:
            # Otherwise friction held every cell at rest through both half steps: nothing moved,
            # so the depth cannot change either (h_t = -m_x = 0). The state is kept bit for bit
            # instead of the staggered re-projection, which would smear a pile at rest.
            now, full = full, now
            speed, bad, moving = speed2, bad2, moving2
        t = controls.t_end if last else t + 2.0 * dt
        pairs += 1
    status = failure(speed) if bad >= 0 else STATUS_DONE
    return finish(states, now, n0, t, pairs, status, 0, bad, dt)
