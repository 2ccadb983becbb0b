"""Template: compiled loops over cells of a model's pointwise functions.

Generated per model by :meth:`conslaw.model.Model._compiled_arrays`; do not import directly.
The per-cell vectors are stack arrays of the compile-time sizes ``NV`` and ``NAUX`` (see
:mod:`conslaw.kernelgen.stack`).
"""

from numba import njit  # noqa: I001 (the binding block below is replaced when generated)

from conslaw.kernelgen.stack import local_matrix, local_vector

# --- bindings ---
from conslaw.pointwise import (
    admissible_point as _admissible_point,
    balanced_source_point as _balanced_source_point,
    coefficients_point as _coefficients_point,
    correct_point as _correct_point,
    flux_point as _flux_point,
    interface_coefficients_point as _interface_coefficients_point,
    rest_coefficients_point as _rest_coefficients_point,
    jacobian_point as _jacobian_point,
    max_speed_point as _max_speed_point,
    resistance_point as _resistance_point,
    source_point as _source_point,
)

NV = 1
NAUX = 0
HAS_SOURCE = False
HAS_BALANCED_SOURCE = False
HAS_CORRECTION = False
HAS_RESISTANCE = False
HAS_DYNAMIC_COEFFICIENTS = False
HAS_INTERFACE_COEFFICIENTS = False
HAS_REST_COEFFICIENTS = False
# --- end bindings ---


@njit(cache=True)
def load_column(q, aux, i, state, coefficients):
    """Copy column i of the state and of the coefficients into the scratch vectors."""
    for v in range(NV):
        state[v] = q[v, i]
    for k in range(NAUX):
        coefficients[k] = aux[k, i]


@njit(cache=True)
def flux_cells(q, aux, params, out):
    state = local_vector(NV)
    result = local_vector(NV)
    coefficients = local_vector(NAUX)
    for i in range(q.shape[1]):
        load_column(q, aux, i, state, coefficients)
        _flux_point(state, coefficients, params, result)
        for v in range(NV):
            out[v, i] = result[v]


@njit(cache=True)
def jacobian_cells(q, aux, params, out):
    state = local_vector(NV)
    matrix = local_matrix(NV)
    coefficients = local_vector(NAUX)
    for i in range(q.shape[1]):
        load_column(q, aux, i, state, coefficients)
        _jacobian_point(state, coefficients, params, matrix)
        for r in range(NV):
            for c in range(NV):
                out[r, c, i] = matrix[r, c]


@njit(cache=True)
def max_speed_cells(q, aux, params, out):
    state = local_vector(NV)
    coefficients = local_vector(NAUX)
    for i in range(q.shape[1]):
        load_column(q, aux, i, state, coefficients)
        out[i] = _max_speed_point(state, coefficients, params)


@njit(cache=True)
def source_cells(q, aux, params, out):
    state = local_vector(NV)
    result = local_vector(NV)
    for v in range(NV):
        result[v] = 0.0
    coefficients = local_vector(NAUX)
    for i in range(q.shape[1]):
        load_column(q, aux, i, state, coefficients)
        if HAS_SOURCE:
            _source_point(state, coefficients, params, result)
        for v in range(NV):
            out[v, i] = result[v]


@njit(cache=True)
def admissible_cells(q, aux, params, out):
    state = local_vector(NV)
    coefficients = local_vector(NAUX)
    for i in range(q.shape[1]):
        load_column(q, aux, i, state, coefficients)
        out[i] = _admissible_point(state, coefficients, params)


@njit(cache=True)
def balanced_source_cells(q, aux, dx, params, out):
    left = local_vector(NV)
    right = local_vector(NV)
    result = local_vector(NV)
    for v in range(NV):
        result[v] = 0.0
    aux_left = local_vector(NAUX)
    aux_right = local_vector(NAUX)
    for i in range(q.shape[1] - 1):
        for v in range(NV):
            left[v] = q[v, i]
            right[v] = q[v, i + 1]
        for k in range(NAUX):
            aux_left[k] = aux[k, i]
            aux_right[k] = aux[k, i + 1]
        if HAS_BALANCED_SOURCE:
            _balanced_source_point(left, right, aux_left, aux_right, dx, params, result)
        for v in range(NV):
            out[v, i] = result[v]


@njit(cache=True)
def correct_cells(q, aux, params, dt):
    state = local_vector(NV)
    coefficients = local_vector(NAUX)
    for i in range(q.shape[1]):
        load_column(q, aux, i, state, coefficients)
        if HAS_CORRECTION:
            _correct_point(state, coefficients, params, dt)
        for v in range(NV):
            q[v, i] = state[v]


@njit(cache=True)
def resistance_cells(q, aux, params, out):
    state = local_vector(NV)
    coefficients = local_vector(NAUX)
    for i in range(q.shape[1]):
        load_column(q, aux, i, state, coefficients)
        if HAS_RESISTANCE:
            out[i] = _resistance_point(state, coefficients, params)


@njit(cache=True)
def coefficients_cells(q, slopes, aux, params):
    state = local_vector(NV)
    slope = local_vector(NV)
    coefficients = local_vector(NAUX)
    for i in range(q.shape[1]):
        for v in range(NV):
            state[v] = q[v, i]
            slope[v] = slopes[v, i]
        for k in range(NAUX):
            coefficients[k] = aux[k, i]
        if HAS_DYNAMIC_COEFFICIENTS:
            _coefficients_point(state, slope, coefficients, params)
        for k in range(NAUX):
            aux[k, i] = coefficients[k]


@njit(cache=True)
def interface_coefficients_cells(left, right, aux_left, aux_right, params):
    state_left = local_vector(NV)
    state_right = local_vector(NV)
    coefficients_left = local_vector(NAUX)
    coefficients_right = local_vector(NAUX)
    for i in range(left.shape[1]):
        load_column(left, aux_left, i, state_left, coefficients_left)
        load_column(right, aux_right, i, state_right, coefficients_right)
        if HAS_INTERFACE_COEFFICIENTS:
            _interface_coefficients_point(
                state_left, state_right, coefficients_left, coefficients_right, params
            )
        for k in range(NAUX):
            aux_left[k, i] = coefficients_left[k]
            aux_right[k, i] = coefficients_right[k]


@njit(cache=True)
def rest_coefficients_cells(low, high, params):
    coefficients_low = local_vector(NAUX)
    coefficients_high = local_vector(NAUX)
    for i in range(low.shape[1]):
        for k in range(NAUX):
            coefficients_low[k] = low[k, i]
            coefficients_high[k] = high[k, i]
        if HAS_REST_COEFFICIENTS:
            _rest_coefficients_point(coefficients_low, coefficients_high, params)
        for k in range(NAUX):
            low[k, i] = coefficients_low[k]
            high[k, i] = coefficients_high[k]
