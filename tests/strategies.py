"""Hypothesis strategies over the plugin registries: admissible states, reconstructors, CFL numbers.

Everything here is driven by :mod:`conslaw.registry`, so a newly registered model or reconstructor
is drawn (or parametrised over) without editing the tests. States are drawn inside a per-model box
of values (``VALUE_BOXES``; by default ``[-10, 10]`` for every variable and ``[0, 10]`` for the
model's ``depth_index`` row), inadmissible cells of a model with a depth are brought to rest (dry
cells carry no momentum), and the result is filtered with ``Model.is_admissible``. A new model whose
admissible set is much smaller than this box should add a box here; until it does, Hypothesis
reports a ``filter_too_much`` health-check failure instead of silently testing nothing.
"""

from __future__ import annotations

from functools import cache

import numpy as np
from hypothesis import reject, strategies as st
from hypothesis.extra import numpy as hnp
from numpy.typing import NDArray

from conslaw import registry
from conslaw.grid import Grid
from conslaw.model import Model

Array = NDArray[np.float64]

#: Domain of every grid built by the property tests.
X_MIN, X_MAX = 0.0, 1.0
#: Smallest and largest number of cells drawn (small: the properties are local).
MIN_CELLS, MAX_CELLS = 8, 64
#: Value range of the default box, per conserved variable.
DEFAULT_BOX = (-10.0, 10.0)
#: Value range of the default box for a depth variable (``Model.depth_index``).
DEFAULT_DEPTH_BOX = (0.0, 10.0)
#: Per-model boxes ``((lo, hi) per variable)`` whose points are (almost all) admissible.
VALUE_BOXES: dict[str, tuple[tuple[float, float], ...]] = {
    "burgers": ((-10.0, 10.0),),
}

MODEL_NAMES: list[str] = registry.models.names()
RECONSTRUCTOR_NAMES: list[str] = registry.reconstructors.names()


@cache
def model_instance(name: str) -> Model:
    """The registered model ``name`` with its default parameters (one instance per name)."""
    return registry.models.get(name)()


def value_box(name: str, min_depth: float = 0.0) -> tuple[tuple[float, float], ...]:
    """Per-variable ``(lo, hi)`` ranges of the values drawn for model ``name``.

    ``min_depth`` raises the lower end of the depth variable's range (wet states only).
    """
    model = model_instance(name)
    box = list(VALUE_BOXES.get(name, (DEFAULT_BOX,) * model.n_vars))
    if name not in VALUE_BOXES and model.depth_index is not None:
        box[model.depth_index] = DEFAULT_DEPTH_BOX
    if model.depth_index is not None:
        lo, hi = box[model.depth_index]
        box[model.depth_index] = (max(lo, min_depth), hi)
    return tuple(box)


def cell_aux(model: Model, n: int) -> Array:
    """The model's coefficients of the primary cells of the test grid with ``n`` cells."""
    grid = Grid(X_MIN, X_MAX, n)
    return np.ascontiguousarray(model.aux(grid.centres(), grid.dx), dtype=np.float64)


def _admissible_columns(model: Model, q: Array) -> NDArray[np.bool_]:
    """Which columns of ``q`` are finite and admissible on the test grid."""
    ok = model.is_admissible(q, cell_aux(model, q.shape[1]))
    return np.asarray(ok & np.all(np.isfinite(q), axis=0))


def _dry_columns_at_rest(model: Model, q: Array) -> Array:
    """``q`` with every non-depth variable set to 0 in its inadmissible columns.

    For a model with a depth variable the usual reason for an inadmissible column is a dry (or
    nearly dry) cell that still carries momentum; such a cell at rest is the admissible dry state.
    """
    if model.depth_index is None:
        return q
    bad = ~_admissible_columns(model, q)
    if bad.any():
        q = q.copy()
        others = [v for v in range(model.n_vars) if v != model.depth_index]
        q[np.ix_(others, np.nonzero(bad)[0])] = 0.0
    return q


def grid_sizes(min_cells: int = MIN_CELLS, max_cells: int = MAX_CELLS) -> st.SearchStrategy[int]:
    """Numbers of grid cells."""
    return st.integers(min_value=min_cells, max_value=max_cells)


def _values(lo: float, hi: float) -> st.SearchStrategy[float]:
    """Finite floats in ``[lo, hi]``, zero included but no subnormals.

    Subnormal inputs carry fewer than 53 significant bits, so no relative round-off bound
    (``1e-13 * sum|q|`` and the like) can hold for them; they are a floating-point artefact, not
    a state of interest.
    """
    return st.floats(
        min_value=lo, max_value=hi, allow_nan=False, allow_infinity=False, allow_subnormal=False
    )


@st.composite
def admissible_states(
    draw: st.DrawFn,
    model_name: str,
    n_cells: st.SearchStrategy[int] | None = None,
    min_depth: float = 0.0,
) -> Array:
    """Arrays ``q`` of shape ``(n_vars, n)``, finite, admissible in every cell for ``model_name``.

    Hypothesis' array strategy repeats a "fill" value, so the draws mix rough data with long
    constant runs (Riemann-like data) and fully constant arrays. ``min_depth`` > 0 keeps a depth
    variable away from dry states (where a flux Jacobian may not exist).
    """
    model = model_instance(model_name)
    n = draw(n_cells if n_cells is not None else grid_sizes())
    rows = [
        draw(hnp.arrays(np.float64, (n,), elements=_values(lo, hi)))
        for lo, hi in value_box(model_name, min_depth)
    ]
    q = _dry_columns_at_rest(model, np.ascontiguousarray(np.stack(rows), dtype=np.float64))
    if not _admissible_columns(model, q).all():
        # Counted by Hypothesis' filter health check (the box does not fit the admissible set).
        reject()
    return q


@st.composite
def constant_states(
    draw: st.DrawFn,
    model_name: str,
    n_cells: st.SearchStrategy[int] | None = None,
) -> Array:
    """Spatially constant admissible arrays ``q`` (one admissible state repeated in every cell)."""
    model = model_instance(model_name)
    n = draw(n_cells if n_cells is not None else grid_sizes())
    column = np.array([draw(_values(lo, hi)) for lo, hi in value_box(model_name)], dtype=np.float64)
    q = _dry_columns_at_rest(model, np.ascontiguousarray(np.repeat(column[:, None], n, axis=1)))
    if not _admissible_columns(model, q).all():
        reject()
    return q


def model_names() -> st.SearchStrategy[str]:
    """Names of the registered models."""
    return st.sampled_from(MODEL_NAMES)


def reconstructor_names() -> st.SearchStrategy[str]:
    """Names of the registered reconstructors."""
    return st.sampled_from(RECONSTRUCTOR_NAMES)


def cfl_numbers(
    low: float = 0.01, high: float = 0.49, *, exclude_low: bool = True
) -> st.SearchStrategy[float]:
    """CFL numbers in ``(low, high]`` (``[low, high]`` with ``exclude_low=False``)."""
    return st.floats(
        min_value=low,
        max_value=high,
        exclude_min=exclude_low,
        allow_nan=False,
        allow_infinity=False,
    )
