"""Immutable solution state."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class Margin:
    """An avalanche margin tracked inside its cell: position and velocity (front tracking)."""

    position: float
    velocity: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.position) and math.isfinite(self.velocity)):
            raise ValueError(f"margin must be finite, got {self.position!r}, {self.velocity!r}")


@dataclass(frozen=True)
class Margins:
    """The rear (upslope, smaller x) and front margins of one body; None where the body
    touches the boundary on that side."""

    rear: Margin | None
    front: Margin | None

    def row(self, t: float) -> tuple[float, float, float, float, float]:
        """``(t, x_rear, u_rear, x_front, u_front)``, NaN for a missing margin."""
        nan = math.nan
        rear = (self.rear.position, self.rear.velocity) if self.rear else (nan, nan)
        front = (self.front.position, self.front.velocity) if self.front else (nan, nan)
        return (t, *rear, *front)


@dataclass(frozen=True)
class LagrangianNodes:
    """The moving mesh of the Lagrangian scheme: ``n + 1`` nodes carried by the material and the
    fixed volume (mass per unit width) of each of the ``n`` elements between them.

    Attributes
    ----------
    positions : ndarray, shape (n + 1,)
        Node positions, strictly increasing.
    velocities : ndarray, shape (n + 1,)
        Node velocities.
    volumes : ndarray, shape (n,)
        Element volumes ``V_i``; the element depth is ``V_i / (x_{i+1} - x_i)``.
    ends : (str, str)
        What the first and last node are: ``"free"`` (a margin, ``h = 0`` beyond it),
        ``"wall"`` (held at a wall) or ``"open"`` (at an outflow boundary).
    """

    positions: NDArray[np.float64]
    velocities: NDArray[np.float64]
    volumes: NDArray[np.float64]
    ends: tuple[str, str] = ("free", "free")

    def __post_init__(self) -> None:
        arrays = {}
        for name in ("positions", "velocities", "volumes"):
            values = np.array(getattr(self, name), dtype=np.float64, copy=True)
            values.flags.writeable = False
            arrays[name] = values
            object.__setattr__(self, name, values)
        n = arrays["volumes"].shape
        if (
            len(n) != 1
            or arrays["positions"].shape != (n[0] + 1,)
            or arrays["velocities"].shape != (n[0] + 1,)
        ):
            raise ValueError("LagrangianNodes needs n + 1 positions and velocities for n volumes")

    @property
    def n_elements(self) -> int:
        """Number of elements."""
        return int(self.volumes.size)

    @property
    def depths(self) -> NDArray[np.float64]:
        """Element depths ``h_i = V_i / (x_{i+1} - x_i)``."""
        return np.asarray(self.volumes / np.diff(self.positions))


def node_arrays(states: list[State]) -> dict[str, NDArray[np.float64]]:
    """The Lagrangian meshes of ``states`` for ``states.npz``: ``nodes`` (positions),
    ``node_velocities`` (both ``(n_out, n + 1)``) and ``element_depths`` (``(n_out, n)``); empty
    when the states carry none (or meshes of different sizes)."""
    meshes = [s.nodes for s in states]
    if not meshes or any(m is None for m in meshes):
        return {}
    sizes = {m.n_elements for m in meshes if m is not None}
    if len(sizes) != 1:
        return {}
    return {
        "nodes": np.array([m.positions for m in meshes if m is not None]),
        "node_velocities": np.array([m.velocities for m in meshes if m is not None]),
        "element_depths": np.array([m.depths for m in meshes if m is not None]),
    }


@dataclass(frozen=True)
class State:
    """The conserved variables at one time on one cell family.

    Attributes
    ----------
    t : float
        Time.
    x : ndarray, shape (n_cells,)
        Cell centres.
    q : ndarray, shape (n_vars, n_cells)
        Conserved cell averages (float64, C-contiguous, read-only).
    offset : float
        0.0 on the primary grid, 0.5 on the staggered grid of the Nessyahu–Tadmor scheme.
    margins : Margins or None
        The tracked margins (front tracking; the free end nodes of the Lagrangian scheme).
    nodes : LagrangianNodes or None
        The moving mesh of the Lagrangian scheme (``q`` is then its projection on the grid).
    """

    t: float
    x: NDArray[np.float64]
    q: NDArray[np.float64]
    offset: float = 0.0
    margins: Margins | None = None
    nodes: LagrangianNodes | None = None

    def __post_init__(self) -> None:
        q = np.array(self.q, dtype=np.float64, order="C", copy=True, ndmin=2)
        x = np.array(self.x, dtype=np.float64, copy=True)
        if x.ndim != 1 or q.shape[1] != x.shape[0]:
            raise ValueError(f"q must have shape (n_vars, {x.shape[0]}), got {q.shape}")
        q.flags.writeable = False
        x.flags.writeable = False
        object.__setattr__(self, "q", q)
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "t", float(self.t))
        object.__setattr__(self, "offset", float(self.offset))

    @property
    def n_vars(self) -> int:
        """Number of conserved variables."""
        return int(self.q.shape[0])

    @property
    def n_cells(self) -> int:
        """Number of cells."""
        return int(self.q.shape[1])
