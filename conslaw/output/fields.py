"""What an output holds on its mesh: the 1D mesh of the cell faces, the cell fields (conserved,
primitive, coefficients, exact) and the field data of one output time."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from conslaw.result import RunResult

Array = NDArray[np.float64]


#: File stem of the time-series files (``solution.xdmf``, ``solution-00003.vtu``, ...).
SERIES = "solution"
#: Field-data names of the margins (one value per output time), as in ``margins.csv``.
MARGIN_FIELDS = ("x_rear", "u_rear", "x_front", "u_front")


def mesh_points_cells(edges: Array) -> tuple[Array, NDArray[np.int64]]:
    """The 1D mesh: the cell faces as points ``(x, 0, 0)``, shape ``(n + 1, 3)``, and one line
    cell per grid cell, ``(n, 2)`` point indices."""
    edges = np.asarray(edges, dtype=np.float64)
    points = np.zeros((edges.size, 3))
    points[:, 0] = edges
    first = np.arange(edges.size - 1, dtype=np.int64)
    return points, np.ascontiguousarray(np.stack([first, first + 1], axis=1))


def cell_fields(result: RunResult, index: int) -> dict[str, Array]:
    """Every cell field of output ``index``: conserved variables, primitive variables, model
    coefficients (as the scheme uses them in that state) and exact cell averages
    (``<variable>_exact``, only where an exact solution applies). A primitive or coefficient
    field named like a conserved variable is the same quantity and is not repeated."""
    state = result.states[index]
    model = result.model
    fields: dict[str, Array] = {name: state.q[v] for v, name in enumerate(model.variables)}
    for name, values in model.primitive_fields(state.q).items():
        fields.setdefault(name, values)
    coefficients = result.coefficients[index]
    for name, values in model.coefficient_fields(state.x, coefficients).items():
        fields.setdefault(name, values)
    exact = result.exact[index]
    if exact is not None:
        for v, name in enumerate(model.variables):
            fields[f"{name}_exact"] = exact[v]
    return {name: np.ascontiguousarray(values, dtype=np.float64) for name, values in fields.items()}


def output_field_data(result: RunResult, index: int) -> dict[str, float]:
    """One value per output: ``time`` and, with front tracking, the margins that exist
    (:data:`MARGIN_FIELDS`)."""
    state = result.states[index]
    data = {"time": state.t}
    if state.margins is not None:
        row = state.margins.row(state.t)[1:]
        data.update({n: v for n, v in zip(MARGIN_FIELDS, row, strict=True) if v == v})
    return data
