"""What a 2D output holds (docs/output.md, "2D runs"): the quadrilateral mesh of the grid, the
cell fields at an output time, and ``states.npz``."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from conslaw.output.npz import exact_arrays, npz_bytes, variable_meanings
from conslaw.provenance import as_json

if TYPE_CHECKING:
    from conslaw.result2d import RunResult2D

Array = NDArray[np.float64]


def quad_mesh(x_edges: Array, y_edges: Array) -> tuple[Array, NDArray[np.int64]]:
    """Points ``(x, y, 0)`` at the cell corners (x fastest) and one quadrilateral per cell,
    corners counter-clockwise, cells in the order of ``q[v].ravel()`` (y rows, x columns)."""
    nx, ny = len(x_edges) - 1, len(y_edges) - 1
    x, y = np.meshgrid(np.asarray(x_edges), np.asarray(y_edges))
    points = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    corner = (np.arange(ny)[:, None] * (nx + 1) + np.arange(nx)[None, :]).ravel()
    cells = np.column_stack([corner, corner + 1, corner + nx + 2, corner + nx + 1])
    return points, cells.astype(np.int64)


def cell_fields_2d(result: RunResult2D, index: int) -> dict[str, Array]:
    """The cell fields of output ``index``, each flat in cell order: the conserved variables,
    the primitive ones (``Model.primitive_fields``), the bed where the model has one
    (``quarter_bed``: its cell averages) and the exact cell averages (``h_exact``, ...)."""
    model, state = result.model, result.states[index]
    fields = {name: state.q[v].ravel() for v, name in enumerate(model.variables)}
    for name, values in model.primitive_fields(state.q).items():
        fields.setdefault(name, np.asarray(values).ravel())
    quarter_bed = getattr(model, "quarter_bed", None)
    if quarter_bed is not None:
        fields["bed"] = quarter_bed(result.grid.x.edges, result.grid.y.edges).ravel()
    exact = result.exact[index]
    if exact is not None:
        for v, name in enumerate(model.variables):
            fields[f"{name}_exact"] = exact[v].ravel()
    return {name: np.ascontiguousarray(values, dtype=np.float64) for name, values in fields.items()}


def states_bytes_2d(
    result: RunResult2D, provenance: dict[str, str], compressed: bool = True
) -> bytes:
    """``states.npz`` of the outputs so far. Keys: ``t`` (n_out,), ``x`` (nx,), ``y`` (ny,),
    ``x_edges``, ``y_edges``, ``q`` (n_out, n_vars, ny, nx), ``q_exact`` (only for a scene with
    an exact solution; NaN at an output time without one), ``variables``,
    ``variable_meanings`` (what each variable is: on terrain ``h`` is the volume per map area
    ``H``, not the slope-normal thickness), ``provenance`` (a JSON string) and, for a run with
    ``stop.at_rest``, ``stop`` (a JSON string: how the run ended so far,
    :meth:`conslaw.stopping.StopRecord.to_dict`)."""
    grid = result.grid
    x, y = grid.centres()
    q = np.array([state.q for state in result.states])
    exact = exact_arrays(result.exact, [state.q for state in result.states])
    stop = {} if result.stop is None else {"stop": np.array(result.stop.to_json())}
    return npz_bytes(
        compressed,
        t=np.array([state.t for state in result.states]),
        x=x,
        y=y,
        x_edges=grid.x.edges,
        y_edges=grid.y.edges,
        q=q,
        **exact,
        variables=np.array(result.model.variables),
        variable_meanings=variable_meanings(result.model),
        provenance=np.array(as_json(provenance)),
        **stop,
    )
