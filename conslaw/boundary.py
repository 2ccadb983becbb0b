"""Boundary conditions: ghost-cell filling for both cell families of the staggered scheme.

A padded array ``w`` of shape ``(n_vars, n + 2 ng)`` holds ``n`` real cells at columns
``ng .. ng + n - 1``. On the primary family (``staggered = False``) the domain boundary is a cell
*face*; on the staggered family it is the *centre* of the first and last cell. The fill functions
are module-level numba functions, so the generated kernels can import them.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number, shown

if TYPE_CHECKING:
    from conslaw.model import Model


@njit(cache=True)
def periodic_left(w, n, ng, staggered, data):
    """Left ghosts copy the last cells (period n on either family)."""
    for g in range(1, ng + 1):
        for v in range(w.shape[0]):
            w[v, ng - g] = w[v, ng + n - g]


@njit(cache=True)
def periodic_right(w, n, ng, staggered, data):
    """Right ghosts copy the first cells."""
    for g in range(1, ng + 1):
        for v in range(w.shape[0]):
            w[v, ng + n - 1 + g] = w[v, ng + g - 1]


@njit(cache=True)
def outflow_left(w, n, ng, staggered, data):
    """Zero gradient: left ghosts copy the first cell."""
    for g in range(1, ng + 1):
        for v in range(w.shape[0]):
            w[v, ng - g] = w[v, ng]


@njit(cache=True)
def outflow_right(w, n, ng, staggered, data):
    """Zero gradient: right ghosts copy the last cell."""
    for g in range(1, ng + 1):
        for v in range(w.shape[0]):
            w[v, ng + n - 1 + g] = w[v, ng + n - 1]


@njit(cache=True)
def wall_left(w, n, ng, staggered, data):
    """Mirror image across the left boundary, ``data[v]`` = sign of variable v (momentum -1)."""
    for g in range(1, ng + 1):
        source = ng + g if staggered else ng + g - 1
        for v in range(w.shape[0]):
            w[v, ng - g] = data[v] * w[v, source]


@njit(cache=True)
def wall_right(w, n, ng, staggered, data):
    """Mirror image across the right boundary."""
    for g in range(1, ng + 1):
        source = ng + n - 1 - g if staggered else ng + n - g
        for v in range(w.shape[0]):
            w[v, ng + n - 1 + g] = data[v] * w[v, source]


@njit(cache=True)
def inflow_left(w, n, ng, staggered, data):
    """Left ghosts hold the fixed state ``data``."""
    for g in range(1, ng + 1):
        for v in range(w.shape[0]):
            w[v, ng - g] = data[v]


@njit(cache=True)
def inflow_right(w, n, ng, staggered, data):
    """Right ghosts hold the fixed state ``data``."""
    for g in range(1, ng + 1):
        for v in range(w.shape[0]):
            w[v, ng + n - 1 + g] = data[v]


# Kind codes of the built-in conditions: they share one pair of compiled fill functions, so a
# kernel compiled for one model and reconstructor serves every combination of built-in boundaries.
PERIODIC, OUTFLOW, WALL, INFLOW = 0, 1, 2, 3


@njit(cache=True)
def builtin_left(w, n, ng, staggered, data):
    """Left ghosts of a built-in condition: ``data[0]`` is its kind code, ``data[1:]`` its data."""
    kind = int(data[0])
    payload = data[1:]
    if kind == PERIODIC:
        periodic_left(w, n, ng, staggered, payload)
    elif kind == OUTFLOW:
        outflow_left(w, n, ng, staggered, payload)
    elif kind == WALL:
        wall_left(w, n, ng, staggered, payload)
    else:
        inflow_left(w, n, ng, staggered, payload)


@njit(cache=True)
def builtin_right(w, n, ng, staggered, data):
    """Right ghosts of a built-in condition (see :func:`builtin_left`)."""
    kind = int(data[0])
    payload = data[1:]
    if kind == PERIODIC:
        periodic_right(w, n, ng, staggered, payload)
    elif kind == OUTFLOW:
        outflow_right(w, n, ng, staggered, payload)
    elif kind == WALL:
        wall_right(w, n, ng, staggered, payload)
    else:
        inflow_right(w, n, ng, staggered, payload)


@dataclass(frozen=True)
class BoundaryCondition:
    """One kind of boundary condition.

    Attributes
    ----------
    name, description : str
        Registry name and one-line description.
    fill_left, fill_right : callable
        Numba functions ``fill(w, n, ng, staggered, data)`` writing the ghost cells in place.
    periodic : bool
        Periodic conditions must be used on both sides and change the staggered cell count.
    options : tuple of str
        Keys this condition accepts in a scene (``inflow``: ``state``).
    ghost_coefficients : str
        How the model's coefficients (bed, chute angle) are set in the ghost cells, matching
        what the fill functions do to the state: ``"mirror"`` (wall), ``"wrap"`` (periodic) or
        ``"copy"`` (the edge cell's coefficients).
    """

    name: str
    description: str
    fill_left: Callable[..., None]
    fill_right: Callable[..., None]
    periodic: bool = False
    options: tuple[str, ...] = ()
    ghost_coefficients: str = "copy"
    #: Kind code for the shared built-in fill functions (None for a plugin's own functions).
    code: int | None = None
    data_builder: Callable[[Model, Mapping[str, Any]], NDArray[np.float64]] | None = field(
        default=None, compare=False
    )

    def data(self, model: Model, options: Mapping[str, Any]) -> NDArray[np.float64]:
        """The float array handed to the fill functions (led by the kind code if built in)."""
        payload = (
            np.zeros(1, dtype=np.float64)
            if self.data_builder is None
            else self.data_builder(model, options)
        )
        if self.code is None:
            return payload
        return np.concatenate([[float(self.code)], payload])


def _wall_data(model: Model, options: Mapping[str, Any]) -> NDArray[np.float64]:
    return np.array(model.reflect_signs, dtype=np.float64)


def _inflow_data(model: Model, options: Mapping[str, Any]) -> NDArray[np.float64]:
    state = options.get("state")
    if not isinstance(state, Sequence) or isinstance(state, str) or len(state) != model.n_vars:
        raise ConfigError(
            f"boundary 'inflow' needs state = a list of {model.n_vars} numbers "
            f"({', '.join(model.variables)}), got {state!r}"
        )
    if any(isinstance(v, bool) or not isinstance(v, int | float) for v in state):
        raise ConfigError(
            f"boundary 'inflow' needs state = a list of {model.n_vars} numbers "
            f"({', '.join(model.variables)}), got {state!r}"
        )
    try:
        values = np.array([finite_number(v, "boundary 'inflow' state") for v in state])
    except ConfigError:
        raise ConfigError(f"boundary 'inflow' state must be finite, got {shown(state)}") from None
    if not bool(model.is_admissible(values[:, None])[0]):
        raise ConfigError(f"boundary 'inflow' state {state!r} is not admissible for '{model.name}'")
    return values


def builtin_boundary_conditions() -> list[BoundaryCondition]:
    """The boundary conditions that ship with conslaw (all served by one compiled kernel)."""
    return [
        BoundaryCondition(
            "periodic", "periodic (both sides)", builtin_left, builtin_right, True,
            ghost_coefficients="wrap", code=PERIODIC,
        ),
        BoundaryCondition(
            "outflow", "zero-gradient outflow", builtin_left, builtin_right, code=OUTFLOW
        ),
        BoundaryCondition(
            "wall", "reflective wall (momentum mirrored)", builtin_left, builtin_right,
            data_builder=_wall_data, ghost_coefficients="mirror", code=WALL,
        ),
        BoundaryCondition(
            "inflow", "fixed inflow state (option: state = [...])", builtin_left, builtin_right,
            options=("state",), data_builder=_inflow_data, code=INFLOW,
        ),
    ]  # fmt: skip
