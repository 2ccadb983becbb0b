"""The result of a 2D run: the states at the output times and their comparison with the exact
solution (:func:`conslaw.simulation2d.simulate_2d`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from conslaw.result import run_line

if TYPE_CHECKING:
    from conslaw.analysis import ErrorNorms
    from conslaw.exact2d import ExactSolution2D
    from conslaw.grid2d import Grid2D
    from conslaw.model import Model
    from conslaw.peak_fields import PeakFields
    from conslaw.scene2d import Scene2D
    from conslaw.stopping import StopRecord

Array = NDArray[np.float64]


@dataclass(frozen=True)
class State2D:
    """The cell averages ``q`` (``(n_vars, ny, nx)``) at time ``t``."""

    t: float
    q: Array


@dataclass(repr=False)
class RunResult2D:
    """What a 2D run produced: the states at the output times and their comparison with the
    exact solution (None where there is none).

    Attributes
    ----------
    states : list of State2D
        The cell averages at every output time (``state.t``), the last at ``t_end`` (at the
        stop time of a run that stopped at rest, :attr:`stop`).
    exact : list of ndarray or None
        Exact cell averages at the same times (None without an exact solution).
    errors : list of ErrorNorms or None
        Error norms of variable 0 against the exact cell averages at the same times
        (docs/equations.md, "Error norms", with the mean over cells in place of the sum times
        ``dx``).
    peaks : PeakFields or None
        The largest flow depth and speed of every cell over the run, updated after every step
        pair (None for a model without a depth; :mod:`conslaw.peak_fields`).
    scheme_notes : list of str
        What the scheme tells of the run so far (the tracked margins of ``jiang-tadmor-ft``
        lagging the material), one line each.
    stop : StopRecord or None
        How the run ended, with ``stop.at_rest`` (:mod:`conslaw.stopping`): stopped at rest
        (its last state at the stop time) or at ``t_end``; None without the rule.
    steps : int
        Time steps taken.
    solve_seconds, compile_seconds : float
        Wall time of the time loop, and of compiling the kernels (0 when they were cached).
    """

    scene: Scene2D
    model: Model
    grid: Grid2D
    initial: State2D
    states: list[State2D] = field(default_factory=list)
    exact: list[Array | None] = field(default_factory=list)
    errors: list[ErrorNorms | None] = field(default_factory=list)
    exact_solution: ExactSolution2D | None = None
    exact_note: str | None = None
    peaks: PeakFields | None = None
    scheme_notes: list[str] = field(default_factory=list)
    stop: StopRecord | None = None
    steps: int = 0
    solve_seconds: float = 0.0
    compile_seconds: float = 0.0

    def __repr__(self) -> str:
        """One line: the scene, where the run got to and its headline error (the arrays are
        in :attr:`states`)."""
        ny, nx = self.grid.shape
        return run_line(self, "RunResult2D", f"{nx} x {ny} cells")

    def headline_error(self) -> float | None:
        """L1 error of variable 0 at the last output time against the exact cell averages
        (None if there is no exact solution or no output yet)."""
        error = self.errors[-1] if self.errors else None
        return None if error is None else error.l1

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
