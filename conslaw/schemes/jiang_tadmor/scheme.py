"""The Jiang–Tadmor scheme on a 2D grid: compiled steps, and the time loop of step pairs.

Models without a bed (no source, no well-balanced source, no surface reconstruction: Burgers 2D,
shallow water over a flat bed) take the compiled kernel of
:mod:`~conslaw.schemes.jiang_tadmor.kernel_template`, multi-threaded across rows; over a bed the
steps are those of :class:`~conslaw.schemes.jiang_tadmor.reference.JiangTadmorReference` (its
still-water rules are not compiled yet; docs/design.md, "Toward two dimensions"). The time loop
is the reference's :meth:`~JiangTadmorReference.advance` in both: step pairs of one ``dt``, a
pair redone with half the step while a depth would become negative and with the staggered
values' stable step if their Courant number would reach 1/2.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, SchemeBreakdownError
from conslaw.grid2d import Grid2D
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor
from conslaw.schemes.jiang_tadmor.kernels import jt_kernels
from conslaw.schemes.jiang_tadmor.reference import (
    CFL_LIMIT,
    DT_FLOOR,
    GHOSTS,
    KINDS,
    SIDES,
    JiangTadmorReference,
)

Array = NDArray[np.float64]

#: Chunks of rows per thread (each chunk computes one source row twice).
CHUNKS_PER_THREAD = 2


def compiles(model: Model) -> bool:
    """Whether the compiled kernel covers ``model``: no bed (no source, no well-balanced
    source, no surface reconstruction), no resistance and no coefficients of its own."""
    uses = model.capabilities()
    return not any(
        uses[key]
        for key in (
            "source",
            "balanced_source",
            "surface",
            "resistance",
            "dynamic_coefficients",
            "interface_coefficients",
            "rest_coefficients",
        )
    )


class JiangTadmor:
    """The Jiang–Tadmor (1998) scheme for a 2D model on ``grid``.

    Parameters
    ----------
    model, reconstructor, grid, boundaries, cfl
        As :class:`~conslaw.schemes.jiang_tadmor.reference.JiangTadmorReference` (which checks
        them).
    threads : int, optional
        Threads of the compiled kernel (default: numba's, every core).
    chunks : int, optional
        Chunks of rows a step is cut into (default ``2 threads``); the results do not depend on
        it, bit for bit.
    """

    def __init__(
        self,
        model: Model,
        reconstructor: Reconstructor,
        grid: Grid2D,
        boundaries: Mapping[str, str],
        cfl: float = 0.45,
        threads: int | None = None,
        chunks: int | None = None,
    ) -> None:
        self.reference = JiangTadmorReference(model, reconstructor, grid, boundaries, cfl)
        self.model, self.grid, self.cfl = model, grid, float(cfl)
        self.compiled = compiles(model)
        if not self.compiled:
            return
        available = self.available_threads()
        self.threads = available if threads is None else int(threads)
        if not 1 <= self.threads <= available:
            raise ConfigError(f"threads must be in [1, {available}], got {threads!r}")
        self.kernels = jt_kernels(model, reconstructor)
        code = -1.0 if reconstructor.code is None else float(reconstructor.code)
        self.params = np.append(model.param_vector(), code)
        shapes = {staggered: self.reference.family_shape(staggered) for staggered in (False, True)}
        n_chunks = CHUNKS_PER_THREAD * self.threads if chunks is None else int(chunks)
        if n_chunks < 1:
            raise ConfigError(f"chunks must be >= 1, got {chunks!r}")
        columns = max(shape[1] for shape in shapes.values())
        self.work = np.zeros(self.kernels.work_shape(n_chunks, columns))
        self.shapes = shapes
        nv = model.n_vars
        padded = {
            s: (nv, rows + 2 * GHOSTS, cols + 2 * GHOSTS) for s, (rows, cols) in shapes.items()
        }
        self.states = [np.zeros(padded[False]), np.zeros(padded[True]), np.zeros(padded[False])]
        columns_of_statistics = self.kernels.STATISTICS
        self.statistics = [
            np.zeros((shapes[s][0], columns_of_statistics)) for s in (False, True, False)
        ]
        kinds = np.array([KINDS.index(boundaries[side]) for side in SIDES], dtype=np.int64)
        signs_x = np.asarray(model.reflect_signs, dtype=np.float64)
        signs_y = np.asarray(model.reflect_signs_y or model.reflect_signs, dtype=np.float64)
        self.sides = self.kernels.Sides(kinds, signs_x, signs_y)
        if [KINDS.index(k) for k in KINDS] != [
            self.kernels.PERIODIC,
            self.kernels.OUTFLOW,
            self.kernels.WALL,
        ]:  # the kernel's codes of the kinds are the reference's order
            raise AssertionError("side kinds out of order")

    @staticmethod
    def available_threads() -> int:
        """The most threads a kernel can run on (numba's, every core)."""
        return int(numba.config.NUMBA_NUM_THREADS)  # type: ignore[attr-defined]

    def step(self, q: Array, staggered: bool, dt: float) -> Array:
        """One step from the family of ``q`` (``staggered`` or primary) to the other with ``dt``
        (no Courant check), as :meth:`JiangTadmorReference.step`; the new values (a new array)."""
        if not self.compiled:
            return self.reference.step(q, staggered, dt)
        source, target = (1, 2) if staggered else (0, 1)
        rows, columns = self.shapes[staggered]
        self.states[source][:, GHOSTS : GHOSTS + rows, GHOSTS : GHOSTS + columns] = q
        self.kernels.fill_ghosts(self.states[source], rows, columns, staggered, self.sides)
        numba.set_num_threads(self.threads)
        self.kernels.family_statistics(
            self.states[source], rows, columns, self.params, self.statistics[source]
        )
        self._step(source, target, staggered, dt)
        rows, columns = self.shapes[not staggered]
        return self.states[target][:, GHOSTS : GHOSTS + rows, GHOSTS : GHOSTS + columns].copy()

    def stable_dt(self, statistics: Array) -> float:
        """``min(cfl dx / max|a_x|, cfl dy / max|a_y|)`` of a family's row statistics (inf at
        rest), as :meth:`JiangTadmorReference.stable_dt`."""
        speed_x = float(np.max(statistics[:, 0]))
        speed_y = float(np.max(statistics[:, 1]))
        dt_x = self.cfl * self.grid.dx / speed_x if speed_x > 0.0 else np.inf
        dt_y = self.cfl * self.grid.dy / speed_y if speed_y > 0.0 else np.inf
        return min(dt_x, dt_y)

    def _courant_reached(self, statistics: Array, dt: float) -> bool:
        speed_x = float(np.max(statistics[:, 0]))
        speed_y = float(np.max(statistics[:, 1]))
        return max(dt * speed_x / self.grid.dx, dt * speed_y / self.grid.dy) >= CFL_LIMIT

    def _step(self, source: int, target: int, staggered: bool, dt: float) -> Array:
        """One compiled step from state buffer ``source`` (a primary family unless
        ``staggered``) into buffer ``target``, its ghosts filled; the new rows' statistics."""
        kernels = self.kernels
        rows, columns = self.shapes[not staggered]
        first = GHOSTS if staggered else GHOSTS - 1
        deepest = float(np.max(self.statistics[source][:, kernels.DEEPEST]))
        step = kernels.Step(first, rows, columns, dt, self.grid.dx, self.grid.dy, deepest)
        statistics = self.statistics[target]
        numba.set_num_threads(self.threads)
        kernels.step_family(
            self.states[source], self.states[target], self.work, statistics, self.params, step
        )
        kernels.fill_ghosts(self.states[target], rows, columns, not staggered, self.sides)
        return statistics

    def _pair(self, dt: float) -> tuple[bool, float]:
        """A step pair from buffer 0 (through 1) into buffer 2, as
        :meth:`JiangTadmorReference._pair`: ``(True, dt)`` or ``(False, the step to redo it
        with)``."""
        middle = self._step(0, 1, False, dt)
        self._check_finite(middle, 1)
        if self.model.depth_index is not None and np.min(middle[:, 2]) < 0.0:
            return False, 0.5 * dt
        if self._courant_reached(middle, dt):
            return False, self.stable_dt(middle)
        end = self._step(1, 2, True, dt)
        self._check_finite(end, 2)
        if self.model.depth_index is not None and np.min(end[:, 2]) < 0.0:
            return False, 0.5 * dt
        return True, dt

    def _check_finite(self, statistics: Array, buffer: int) -> None:
        """A SchemeBreakdownError naming the first cell that is not finite, if any."""
        if np.all(np.isfinite(statistics[:, :2])) and not np.any(np.isnan(statistics[:, 2])):
            return
        rows, columns = self.shapes[buffer == 1]
        values = self.states[buffer][:, GHOSTS : GHOSTS + rows, GHOSTS : GHOSTS + columns]
        bad = np.argwhere(~np.isfinite(values))
        where = "a wave speed" if bad.size == 0 else f"cell (row {bad[0][1]}, column {bad[0][2]})"
        family = "staggered" if buffer == 1 else "primary"
        raise _NotFiniteError(f"{where} of the {family} family is not finite")

    def advance(
        self,
        q: Array,
        t: float,
        t_end: float,
        progress: Callable[[float, int], Any] | None = None,
    ) -> tuple[Array, float, int]:
        """Advance primary-family values ``q`` (``(n_vars, ny, nx)``) from ``t`` to exactly
        ``t_end``, as :meth:`JiangTadmorReference.advance`: returns the values (a new array),
        the time and the number of steps; ``progress(t, steps)`` after every pair.

        Raises
        ------
        SchemeBreakdownError
            If the time step falls below ``DT_FLOOR dx``, or a value or wave speed is not
            finite (with the time, step and cell).
        """
        if not self.compiled:
            return self.reference.advance(q, t, t_end)
        rows, columns = self.shapes[False]
        interior = (slice(None), slice(GHOSTS, GHOSTS + rows), slice(GHOSTS, GHOSTS + columns))
        self.states[0][interior] = q
        self.kernels.fill_ghosts(self.states[0], rows, columns, False, self.sides)
        statistics = self.statistics[0]
        numba.set_num_threads(self.threads)
        self.kernels.family_statistics(self.states[0], rows, columns, self.params, statistics)
        steps = 0
        try:
            self._check_finite(statistics, 0)
            while t < t_end:
                t, steps = self._advance_pair(t, t_end, steps)
                if progress is not None:
                    progress(t, steps)
        except _NotFiniteError as error:
            raise SchemeBreakdownError(f"t={t:g}, step {steps}: {error}") from None
        return self.states[0][interior].copy(), t, steps

    def _advance_pair(self, t: float, t_end: float, steps: int) -> tuple[float, int]:
        """One accepted step pair from ``t``; the new time and step count."""
        remaining = t_end - t
        dt = self.stable_dt(self.statistics[0])
        last = 2.0 * dt >= remaining
        if last:
            dt = 0.5 * remaining
        accepted, next_dt = self._pair(dt)
        while not accepted:
            dt, last = next_dt, False
            if dt < DT_FLOOR * self.grid.dx:
                raise SchemeBreakdownError(
                    f"t={t:g}, step {steps}: the time step fell below {DT_FLOOR:g} dx "
                    "(a depth stays negative)"
                )
            accepted, next_dt = self._pair(dt)
        self.states[0], self.states[2] = self.states[2], self.states[0]
        self.statistics[0], self.statistics[2] = self.statistics[2], self.statistics[0]
        return (t_end if last else t + 2.0 * dt), steps + 2


class _NotFiniteError(Exception):
    """A value or wave speed of a new family is not finite (becomes a SchemeBreakdownError with
    the time and step)."""
