"""The result of a 2D run: the states at the output times and their comparison with the exact
solution (:func:`conslaw.simulation2d.simulate_2d`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from conslaw.analysis import ErrorNorms
    from conslaw.exact2d import ExactSolution2D
    from conslaw.grid2d import Grid2D
    from conslaw.model import Model
    from conslaw.scene2d import Scene2D

Array = NDArray[np.float64]


@dataclass(frozen=True)
class State2D:
    """The cell averages ``q`` (``(n_vars, ny, nx)``) at time ``t``."""

    t: float
    q: Array


@dataclass
class RunResult2D:
    """What a 2D run produced: the states at the output times and their comparison with the
    exact solution (None where there is none)."""

    scene: Scene2D
    model: Model
    grid: Grid2D
    initial: State2D
    states: list[State2D] = field(default_factory=list)
    exact: list[Array | None] = field(default_factory=list)
    errors: list[ErrorNorms | None] = field(default_factory=list)
    exact_solution: ExactSolution2D | None = None
    exact_note: str | None = None
    steps: int = 0
    solve_seconds: float = 0.0
    compile_seconds: float = 0.0

    @property
    def final(self) -> State2D:
        """The last state reached."""
        return self.states[-1] if self.states else self.initial

    def totals(self, q: Array) -> Array:
        """``sum q dx dy`` of every variable."""
        return np.asarray(q).sum(axis=(1, 2)) * self.grid.cell_area

    @property
    def mass_drift(self) -> Array:
        """Change of every variable's total from ``t = 0``, relative to its size then (absolute
        for a total that is 0 at ``t = 0``)."""
        start, end = self.totals(self.initial.q), self.totals(self.final.q)
        scale = np.where(start != 0.0, np.abs(start), 1.0)
        return np.asarray((end - start) / scale)
