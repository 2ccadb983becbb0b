"""Template: the fused Nessyahu–Tadmor (NOC) kernels, Tai et al. (2001) eqs. (10)–(18).

Generated per (model, reconstructor, boundary pair) by :func:`conslaw.kernels.codegen.nt_kernels`;
do not import directly. Layout: padded arrays ``w[v, NG + i]`` for the ``n`` real cells ``i``.

One step maps cell family A to family B, whose cell ``k`` spans the centres of A-cells
``L = NG + shift + k`` and ``R = L + 1`` (``shift = -1`` primary -> staggered, ``0`` back):

    w_B[k] = (w_L + w_R)/2 + (w'_L - w'_R)/8                      (eq. 10 with eq. 11)
             - dt/dx (f(w_R^{n+1/2}) - f(w_L^{n+1/2}))            (eq. 12)
             + dt/2 (s(w_L^{n+1/2} + w'_L/4) + s(w_R^{n+1/2} - w'_R/4))   (eqs. 13-14)
    w^{n+1/2} = w + dt/2 (-A(w) w'/dx + s(w))                    (eq. 15)

Compile-time switches (constants of the generated module; unused branches are removed):

- ``HAS_SOURCE``: quarter-point sources.
- ``HAS_BALANCED_SOURCE``: the model's staggered-cell source replaces the quarter-point pair.
- ``HAS_RESISTANCE``: a Coulomb-type resistance of magnitude ``resistance_point`` opposing the
  momentum, integrated at the quarter points like the sources and applied with the stopping rule
  ``m = 0 if |m*| <= dt R else m* - sgn(m*) dt R`` (never reverses the flow).
- ``HAS_DYNAMIC_COEFFICIENTS``: the model sets per-cell coefficients from the cell's slopes (the
  earth-pressure coefficient) before the Jacobian and the flux are evaluated.
- ``HAS_CORRECTION``: pointwise correction of every new cell (dry cells).
- ``DEPTH``: row of a depth variable kept >= 0 (or -1); ``MOMENTUM``: row of depth * velocity,
  whose slope is bounded by the neighbouring velocities; ``DRY_DEPTH``: velocity 0 below it.
- ``SURFACE_BED``/``SURFACE_SLOPE``: aux rows of the bed average and slope; the depth is then
  reconstructed as depth + bed.
"""

import numpy as np
from numba import njit

# --- bindings ---
from conslaw.kernels.placeholders import (
    admissible_point as _admissible_point,
    balanced_source_point as _balanced_source_point,
    coefficients_point as _coefficients_point,
    correct_point as _correct_point,
    fill_left as _fill_left,
    fill_right as _fill_right,
    flux_point as _flux_point,
    jacobian_point as _jacobian_point,
    max_speed_point as _max_speed_point,
    resistance_point as _resistance_point,
    slope_point as _slope_point,
    source_point as _source_point,
)

HAS_SOURCE = False
HAS_BALANCED_SOURCE = False
HAS_CORRECTION = False
HAS_RESISTANCE = False
HAS_DYNAMIC_COEFFICIENTS = False
DEPTH = -1
MOMENTUM = -1
DRY_DEPTH = 0.0
SURFACE_BED = -1
SURFACE_SLOPE = -1
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
MAX_RETRIES = 60
# |depth slope| <= DEPTH_SLOPE_LIMIT * depth: the half-cell averages depth -+ slope/4 keep at least
# half the depth, so a wet cell always has mass on both sides of its centre and a small enough
# time step keeps every new depth >= 0 (with the limit 4 a half cell can be empty while the
# flux at the centre still drains it, and no time step helps).
DEPTH_SLOPE_LIMIT = 2.0


@njit(cache=True)
def fill_ghosts(w, n, staggered, bc_left, bc_right):  # type: ignore[no-untyped-def]
    _fill_left(w, n, NG, staggered, bc_left)
    _fill_right(w, n, NG, staggered, bc_right)


@njit(cache=True)
def max_speed(w, n, aux, params):  # type: ignore[no-untyped-def]
    """Largest wave speed over the real cells; ``(-1, i)`` at the first inadmissible cell i,
    ``(-2, i)`` at the first cell whose wave speed is not finite (an overflow)."""
    nv = w.shape[0]
    state = np.empty(nv)
    coefficients = np.empty(aux.shape[0])
    largest = 0.0
    for i in range(NG, NG + n):
        for v in range(nv):
            state[v] = w[v, i]
        for k in range(aux.shape[0]):
            coefficients[k] = aux[k, i]
        if not _admissible_point(state, coefficients, params):
            return -1.0, i - NG
        speed = _max_speed_point(state, coefficients, params)
        if not (speed >= 0.0 and speed < np.inf):
            return -2.0, i - NG
        if speed > largest:
            largest = speed
    return largest, -1


@njit(cache=True)
def source_step_limit(w, n, aux, params, cfl, dx):  # type: ignore[no-untyped-def]
    """``sqrt(cfl dx / (2 a))``, ``a = max |s_m| / h`` over the wet real cells: over a step pair
    from rest the source builds up the velocity ``2 a dt``, which must itself meet the CFL
    condition (``2 a dt^2 / dx <= cfl``). inf without a source or a depth (see
    ``NessyahuTadmor.source_step_limit``)."""
    if not HAS_SOURCE or DEPTH < 0 or MOMENTUM < 0:
        return np.inf
    nv = w.shape[0]
    state = np.empty(nv)
    out = np.empty(nv)
    coefficients = np.empty(aux.shape[0])
    largest = 0.0
    for i in range(NG, NG + n):
        h = w[DEPTH, i]
        if not h > 0.0:
            continue
        for v in range(nv):
            state[v] = w[v, i]
        for k in range(aux.shape[0]):
            coefficients[k] = aux[k, i]
        _source_point(state, coefficients, params, out)
        acceleration = abs(out[MOMENTUM]) / h
        if acceleration > largest:
            largest = acceleration
    if not largest > 0.0:
        return np.inf
    return np.sqrt(cfl * dx / (2.0 * largest))


@njit(cache=True)
def failure(code):  # type: ignore[no-untyped-def]
    """Status for a failed ``max_speed`` (its negative speed is the reason code)."""
    return STATUS_SPEED_NOT_FINITE if code == -2.0 else STATUS_INADMISSIBLE


@njit(cache=True)
def depth_is_negative(w, n):  # type: ignore[no-untyped-def]
    """Whether any real cell has a negative depth (always False without a depth variable)."""
    if DEPTH < 0:
        return False
    for i in range(NG, NG + n):  # noqa: SIM110 (numba compiles loops, not generators)
        if w[DEPTH, i] < 0.0:
            return True
    return False


@njit(cache=True)
def at_rest(w, n):  # type: ignore[no-untyped-def]
    """Whether every real cell has exactly zero momentum (False without a momentum row)."""
    if MOMENTUM < 0:
        return False
    for i in range(NG, NG + n):  # noqa: SIM110 (numba compiles loops, not generators)
        if w[MOMENTUM, i] != 0.0:
            return False
    return True


@njit(cache=True)
def cell_slope(src, v, i, dx, aux_centre):  # type: ignore[no-untyped-def]
    """Slope of variable v in padded cell i, with the depth rules of the compile-time switches."""
    if SURFACE_BED >= 0 and v == DEPTH:
        # Surface gradient method: reconstruct depth + bed, then remove the bed slope.
        bed = aux_centre[SURFACE_BED]
        slope = (
            _slope_point(
                src[v, i - 2] + bed[i - 2],
                src[v, i - 1] + bed[i - 1],
                src[v, i] + bed[i],
                src[v, i + 1] + bed[i + 1],
                src[v, i + 2] + bed[i + 2],
            )
            - dx * aux_centre[SURFACE_SLOPE, i]
        )
    else:
        slope = _slope_point(src[v, i - 2], src[v, i - 1], src[v, i], src[v, i + 1], src[v, i + 2])
    if DEPTH >= 0:
        depth = src[DEPTH, i]
        if depth <= 0.0:
            return 0.0
        if v == DEPTH:
            # Both half-cell averages depth +- slope/4 keep at least half the depth.
            limit = DEPTH_SLOPE_LIMIT * depth
            if slope > limit:
                slope = limit
            elif slope < -limit:
                slope = -limit
    return slope


@njit(cache=True)
def cell_velocity(src, i):  # type: ignore[no-untyped-def]
    depth = src[DEPTH, i]
    return src[MOMENTUM, i] / depth if depth >= DRY_DEPTH and depth > 0.0 else 0.0


@njit(cache=True)
def bound_momentum_slope(src, i, slope):  # type: ignore[no-untyped-def]
    """Clamp the momentum slope so that the velocities at both quarter points,
    ``(m +- m'/4) / (h +- h'/4)``, lie between the smallest and largest velocity of cells
    i-1, i, i+1. The interval always contains ``m' = u_i h'``, so it is never empty."""
    u_left = cell_velocity(src, i - 1)
    u_centre = cell_velocity(src, i)
    u_right = cell_velocity(src, i + 1)
    u_min = min(u_left, u_centre, u_right)
    u_max = max(u_left, u_centre, u_right)
    m = src[MOMENTUM, i]
    plus = src[DEPTH, i] + 0.25 * slope[DEPTH]
    minus = src[DEPTH, i] - 0.25 * slope[DEPTH]
    low = max(4.0 * (plus * u_min - m), 4.0 * (m - minus * u_max))
    high = min(4.0 * (plus * u_max - m), 4.0 * (m - minus * u_min))
    value = slope[MOMENTUM]
    if value < low:
        value = low
    if value > high:
        value = high
    slope[MOMENTUM] = value


@njit(cache=True)
def resist(momentum, impulse):  # type: ignore[no-untyped-def]
    """Apply a resistive impulse ``impulse >= 0`` against ``momentum``: it stops the flow
    exactly (returns 0.0) when it is at least as large, and never reverses it."""
    if abs(momentum) <= impulse:
        return 0.0
    return momentum - impulse if momentum > 0.0 else momentum + impulse


@njit(cache=True)
def velocity_range(src, i, dt, aux_centre, params, state, coefficients, out):  # type: ignore[no-untyped-def]
    """``(u - 2c - dt a, u + 2c + dt a)`` of padded cell i: its Riemann invariants (``c`` the
    wave speed less ``|u|``), widened by the velocity a source and a resistance can add or remove
    in one step (``a = (|s_m| + R) / h``)."""
    nv = src.shape[0]
    for v in range(nv):
        state[v] = src[v, i]
    for k in range(aux_centre.shape[0]):
        coefficients[k] = aux_centre[k, i]
    u = cell_velocity(src, i)
    c = max(_max_speed_point(state, coefficients, params) - abs(u), 0.0)
    h = src[DEPTH, i]
    change = 0.0
    if h > 0.0:
        if HAS_SOURCE:
            _source_point(state, coefficients, params, out)
            change += abs(out[MOMENTUM]) / h
        if HAS_RESISTANCE:
            change += _resistance_point(state, coefficients, params) / h
    return u - 2.0 * c - dt * change, u + 2.0 * c + dt * change


@njit(cache=True)
def bound_velocities(src, dst, n_dst, first, dt, aux_centre, params):  # type: ignore[no-untyped-def]
    """Keep the velocity of every new wet cell ``k`` within the range of its sources: between
    the smallest ``u - 2c`` and the largest ``u + 2c`` of the cells its update reads (``first + k
    - 1`` to ``first + k + 2``), widened by what a source or resistance adds in one step.

    In the exact solution the Riemann invariants ``u -+ 2c`` obey a maximum principle, so a
    velocity outside this range is an artefact; it appears where the staggered average of a
    draining cell is a small difference of large terms (the tail a sliding body leaves behind),
    whose momentum and depth do not cancel alike: a tail of depth 3e-5 behind a body sliding
    down an 89-degree chute at 0.4 got u = -1.9 (upslope). In wet cells the range is wider than
    the scheme's own deviation from the invariant region and the bound does not act."""
    nv = src.shape[0]
    state = np.empty(nv)
    out = np.empty(nv)
    coefficients = np.empty(aux_centre.shape[0])
    count = n_dst + 3
    low = np.empty(count)
    high = np.empty(count)
    for j in range(count):
        low[j], high[j] = velocity_range(
            src, first - 1 + j, dt, aux_centre, params, state, coefficients, out
        )
    for k in range(n_dst):
        h = dst[DEPTH, NG + k]
        if not (h >= DRY_DEPTH and h > 0.0):
            continue
        lo = min(min(low[k], low[k + 1]), min(low[k + 2], low[k + 3]))
        hi = max(max(high[k], high[k + 1]), max(high[k + 2], high[k + 3]))
        u = dst[MOMENTUM, NG + k] / h
        if u < lo:
            dst[MOMENTUM, NG + k] = lo * h
        elif u > hi:
            dst[MOMENTUM, NG + k] = hi * h


@njit(cache=True)
def nt_step(  # type: ignore[no-untyped-def]
    src,
    dst,
    n_src,
    n_dst,
    shift,
    src_staggered,
    dt,
    dx,
    aux_centre,
    aux_left_quarter,
    aux_right_quarter,
    aux_dst,
    params,
    bc_left,
    bc_right,
    slopes,
    fluxes,
    source_left,
    source_right,
    resistance,
):
    """One staggered step from ``src`` (n_src cells) into ``dst`` (n_dst cells), in place.

    ``source_left`` holds the predicted states when the model has a balanced source;
    ``resistance[0/1, i]`` the resistance at the left/right quarter point of cell i.
    """
    nv = src.shape[0]
    fill_ghosts(src, n_src, src_staggered, bc_left, bc_right)
    state = np.empty(nv)
    slope = np.empty(nv)
    rate = np.empty(nv)
    result = np.empty(nv)
    predicted = np.empty(nv)
    neighbour = np.empty(nv)
    matrix = np.empty((nv, nv))
    coefficients = np.empty(aux_centre.shape[0])
    other = np.empty(aux_centre.shape[0])
    half_dt = 0.5 * dt
    first = NG + shift
    # Pass 1: per source cell, slope, predictor (eq. 15), flux at t^{n+1/2} (eq. 12), and the
    # sources at its two quarter points (eqs. 13-14).
    for i in range(first, first + n_dst + 1):
        for v in range(nv):
            state[v] = src[v, i]
            slope[v] = cell_slope(src, v, i, dx, aux_centre)
        if MOMENTUM >= 0 and src[DEPTH, i] > 0.0:
            bound_momentum_slope(src, i, slope)
        for v in range(nv):
            slopes[v, i] = slope[v]
        for k in range(aux_centre.shape[0]):
            coefficients[k] = aux_centre[k, i]
        if HAS_DYNAMIC_COEFFICIENTS:
            _coefficients_point(state, slope, coefficients, params)
        _jacobian_point(state, coefficients, params, matrix)
        for r in range(nv):
            acc = 0.0
            for c in range(nv):
                acc += matrix[r, c] * slope[c]
            rate[r] = -acc / dx
        if HAS_SOURCE:
            _source_point(state, coefficients, params, result)
            for v in range(nv):
                rate[v] += result[v]
        for v in range(nv):
            predicted[v] = src[v, i] + half_dt * rate[v]
        if HAS_RESISTANCE:
            predicted[MOMENTUM] = resist(
                predicted[MOMENTUM], half_dt * _resistance_point(state, coefficients, params)
            )
        _flux_point(predicted, coefficients, params, result)
        for v in range(nv):
            fluxes[v, i] = result[v]
        if HAS_BALANCED_SOURCE:
            for v in range(nv):
                source_left[v, i] = predicted[v]
        elif HAS_SOURCE or HAS_RESISTANCE:
            for v in range(nv):
                state[v] = predicted[v] + 0.25 * slope[v]
            for k in range(aux_centre.shape[0]):
                coefficients[k] = aux_right_quarter[k, i]
            if HAS_SOURCE:
                _source_point(state, coefficients, params, result)
                for v in range(nv):
                    source_right[v, i] = result[v]
            if HAS_RESISTANCE:
                resistance[1, i] = _resistance_point(state, coefficients, params)
            for v in range(nv):
                state[v] = predicted[v] - 0.25 * slope[v]
            for k in range(aux_centre.shape[0]):
                coefficients[k] = aux_left_quarter[k, i]
            if HAS_SOURCE:
                _source_point(state, coefficients, params, result)
                for v in range(nv):
                    source_left[v, i] = result[v]
            if HAS_RESISTANCE:
                resistance[0, i] = _resistance_point(state, coefficients, params)
    # Pass 2: the staggered cell averages (eq. 10).
    ratio = dt / dx
    for k in range(n_dst):
        left = first + k
        right = left + 1
        if HAS_BALANCED_SOURCE:
            for v in range(nv):
                predicted[v] = source_left[v, left]
                neighbour[v] = source_left[v, right]
            for c in range(aux_centre.shape[0]):
                coefficients[c] = aux_centre[c, left]
                other[c] = aux_centre[c, right]
            _balanced_source_point(predicted, neighbour, coefficients, other, dx, params, result)
        for v in range(nv):
            value = (
                0.5 * (src[v, left] + src[v, right])
                + 0.125 * (slopes[v, left] - slopes[v, right])
                - ratio * (fluxes[v, right] - fluxes[v, left])
            )
            if HAS_BALANCED_SOURCE:
                value += dt * result[v]
            elif HAS_SOURCE:
                value += half_dt * (source_right[v, left] + source_left[v, right])
            dst[v, NG + k] = value
        if HAS_RESISTANCE:
            # Eqs. (13)-(14) for the resistance, applied with the stopping rule (reference §1).
            impulse = half_dt * (resistance[1, left] + resistance[0, right])
            dst[MOMENTUM, NG + k] = resist(dst[MOMENTUM, NG + k], impulse)
        if HAS_CORRECTION:
            for v in range(nv):
                state[v] = dst[v, NG + k]
            for c in range(aux_dst.shape[0]):
                coefficients[c] = aux_dst[c, NG + k]
            _correct_point(state, coefficients, params, dt)
            for v in range(nv):
                dst[v, NG + k] = state[v]
    if DEPTH >= 0 and MOMENTUM >= 0:
        bound_velocities(src, dst, n_dst, first, dt, aux_centre, params)


@njit(cache=True)
def advance(  # type: ignore[no-untyped-def]
    w0,
    w1,
    w2,
    n0,
    n1,
    t,
    t_end,
    cfl,
    dx,
    dt_floor,
    max_pairs,
    aux0,
    aux0_left,
    aux0_right,
    aux1,
    aux1_left,
    aux1_right,
    params,
    bc_left,
    bc_right,
    slopes,
    fluxes,
    source_left,
    source_right,
    resistance,
):
    """Advance ``w0`` (primary family) by pairs of steps towards ``t_end``.

    Each pair uses one ``dt = cfl dx / a_max`` (at most ``source_step_limit``) for both half
    steps, so the state is back on the primary family after every pair; the last pair is
    shortened to land on ``t_end`` exactly. A pair is redone with a smaller ``dt`` (``w0`` is
    untouched until the pair is accepted) if the Courant number of its second half would reach
    1/2, or if a depth would become negative (with a depth variable the second half is written
    to ``w2`` and copied back when accepted). With a resistance, a pair that starts and ends with
    every momentum exactly zero leaves the state unchanged (static equilibrium under Coulomb
    friction).

    Returns ``(t, pairs, status, family, cell, dt)``.
    """
    pairs = 0
    dt = 0.0
    # The second half step goes to w2 when it may be rejected (negative depth) or discarded (rest).
    target = w2 if DEPTH >= 0 or HAS_RESISTANCE else w0
    while t < t_end:
        if pairs >= max_pairs:
            return t, pairs, STATUS_PAUSED, 0, -1, dt
        speed, bad = max_speed(w0, n0, aux0, params)
        if bad >= 0:
            return t, pairs, failure(speed), 0, bad, dt
        remaining = t_end - t
        dt = cfl * dx / speed if speed > 0.0 else remaining
        dt = min(dt, source_step_limit(w0, n0, aux0, params, cfl, dx))
        last = False
        if 2.0 * dt >= remaining:
            dt = 0.5 * remaining
            last = True
        resting = HAS_RESISTANCE and at_rest(w0, n0)
        accepted = False
        for _ in range(MAX_RETRIES):
            if dt < dt_floor and not last:
                return t, pairs, STATUS_DT_FLOOR, 0, -1, dt
            nt_step(
                w0, w1, n0, n1, -1, False, dt, dx, aux0, aux0_left, aux0_right, aux1, params,
                bc_left, bc_right, slopes, fluxes, source_left, source_right, resistance,
            )  # fmt: skip
            if depth_is_negative(w1, n1):
                dt *= 0.5
                last = False
                continue
            speed1, bad = max_speed(w1, n1, aux1, params)
            if bad >= 0:
                return t, pairs, failure(speed1), 1, bad, dt
            if speed1 * dt / dx >= CFL_LIMIT:
                dt = cfl * dx / speed1
                last = False
                continue
            nt_step(
                w1, target, n1, n0, 0, True, dt, dx, aux1, aux1_left, aux1_right, aux0, params,
                bc_left, bc_right, slopes, fluxes, source_left, source_right, resistance,
            )  # fmt: skip
            if depth_is_negative(target, n0):
                dt *= 0.5
                last = False
                continue
            accepted = True
            break
        if not accepted:
            if dt < dt_floor:
                return t, pairs, STATUS_DT_FLOOR, 0, -1, dt
            return t, pairs, STATUS_CFL_UNREACHABLE, 1, -1, dt
        if resting and at_rest(w1, n1) and at_rest(target, n0):
            # Friction held every cell at rest through both half steps: nothing moved, so the
            # depth cannot change either (h_t = -m_x = 0). Keep the state bit for bit instead of
            # the staggered re-projection, which would smear a pile at rest.
            pass
        elif DEPTH >= 0 or HAS_RESISTANCE:
            for v in range(w0.shape[0]):
                for i in range(NG, NG + n0):
                    w0[v, i] = target[v, i]
        t = t_end if last else t + 2.0 * dt
        pairs += 1
    speed, bad = max_speed(w0, n0, aux0, params)
    if bad >= 0:
        return t, pairs, failure(speed), 0, bad, dt
    return t, pairs, STATUS_DONE, 0, -1, dt
