"""The Jiang–Tadmor scheme on a 2D grid: compiled steps, and the time loop of step pairs.

Models without a bed (no source, no well-balanced source, no surface reconstruction: Burgers 2D,
shallow water over a flat bed) take the compiled kernel of
:mod:`~conslaw.schemes.jiang_tadmor.kernel_template`, multi-threaded across rows; shallow water
over a bed that of :mod:`~conslaw.schemes.jiang_tadmor.bed_kernel_template`, which continues it;
any other model the steps of :class:`~conslaw.schemes.jiang_tadmor.reference.JiangTadmorReference`
(docs/design.md, "Toward two dimensions"). The time loop is one for all, that of
:meth:`JiangTadmorReference.advance` (step pairs of one ``dt``, a pair
redone with half the step while a depth would become negative and with the staggered values'
stable step if their Courant number would reach 1/2), with a progress report after every pair
and a check of every new family for values and wave speeds that are not finite.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any, ClassVar

import numba
import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, SchemeBreakdownError
from conslaw.grid2d import Grid2D
from conslaw.kernelgen import compile_lock, compiled_before
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor
from conslaw.schemes.jiang_tadmor.breakdown import (
    REMEDIES,
    cell_report,
    fastest_cell,
    shallowest_cell,
)
from conslaw.schemes.jiang_tadmor.constants import (
    DEEPEST,
    LOWEST,
    SPEED_X,
    SPEED_Y,
    STATISTICS,
)
from conslaw.schemes.jiang_tadmor.kernels import (
    jt_bed_kernels,
    jt_field_kernels,
    jt_kernels,
    varying_rows,
)
from conslaw.schemes.jiang_tadmor.reference import (
    CFL_LIMIT,
    DT_FLOOR,
    GHOSTS,
    KINDS,
    SIDES,
    JiangTadmorReference,
)
from conslaw.schemes.nessyahu_tadmor.constants import MAX_RETRIES

Array = NDArray[np.float64]

#: Chunks of rows per thread (each chunk computes one source row twice).
CHUNKS_PER_THREAD = 2
#: The terms of a bed (``Model.capabilities``): a compiled model has all of them or none.
BED_TERMS = ("source", "balanced_source", "surface")


def compiles(model: Model) -> bool:
    """Whether the compiled kernels cover ``model``.

    Parameters
    ----------
    model : Model
        A 2D model.

    Returns
    -------
    bool
        True for a model with coefficients at every point and a source, with or without a resistance
        (:func:`on_field`); otherwise if it has no resistance and no coefficients of its own, and
        either no bed (no source, no well-balanced source, no surface reconstruction) or all three
        of a bed over which the depth is reconstructed from the surface (:func:`over_bed`).
    """
    if on_field(model):
        return True
    uses = model.capabilities()
    if any(
        uses[key]
        for key in (
            "resistance",
            "dynamic_coefficients",
            "interface_coefficients",
            "rest_coefficients",
        )
    ):
        return False
    return over_bed(model) or not any(uses[key] for key in BED_TERMS)


def on_field(model: Model) -> bool:
    """Whether ``model`` runs the compiled field kernels
    (:func:`~conslaw.schemes.jiang_tadmor.kernels.jt_field_kernels`: Savage–Hutter on a chute
    with a cross-slope direction or on terrain): a depth and both momenta, a source at the
    quarter points (no well-balanced source, no surface reconstruction, no range of
    coefficients at rest), coefficients laid out ``along-x`` or over the ``field``, the 2D hooks
    of the coefficients it sets per cell and per staggered cell (``coefficients_2d_point``,
    ``corner_coefficients_point``) if it sets any, and the rows it sets per cell consecutive. A
    resistance is optional.

    Parameters
    ----------
    model : Model
        A 2D model.

    Returns
    -------
    bool
    """
    uses = model.capabilities()
    hooks_2d = (not uses["dynamic_coefficients"] or model.coefficients_2d_point is not None) and (
        not uses["interface_coefficients"] or model.corner_coefficients_point is not None
    )
    return (
        hooks_2d
        and uses["source"]
        and not any(uses[key] for key in ("balanced_source", "surface", "rest_coefficients"))
        and model.n_aux > 0
        and model.aux_layout_2d in ("along-x", "field")
        and model.depth_index is not None
        and model.momentum_index is not None
        and model.momentum_y_index is not None
        and varying_rows(model) is not None
    )


def cell_major(table: Array) -> Array:
    """A coefficient table ``(n_aux, rows, columns)`` laid out ``(rows, columns, n_aux)``,
    contiguous: the kernel reads every coefficient of a cell at once, from one run of memory
    instead of ``n_aux`` planes.

    Parameters
    ----------
    table : ndarray
        ``(n_aux, rows, columns)``.

    Returns
    -------
    ndarray
        ``(rows, columns, n_aux)``, C-contiguous (a copy).
    """
    return np.ascontiguousarray(np.moveaxis(table, 0, -1))


def over_bed(model: Model) -> bool:
    """Whether ``model`` runs the compiled kernels over a bed
    (:func:`~conslaw.schemes.jiang_tadmor.kernels.jt_bed_kernels`): it has a depth, both
    momenta, a source, a well-balanced source and a surface reconstruction with the bed's rows
    in both directions (``surface_aux``, ``surface_aux_y``); ``model`` is any 2D model, and the
    answer a bool."""
    uses = model.capabilities()
    return (
        all(uses[key] for key in BED_TERMS)
        and model.depth_index is not None
        and model.momentum_index is not None
        and model.momentum_y_index is not None
        and model.surface_aux is not None
        and model.surface_aux_y is not None
    )


class JiangTadmor:
    """The Jiang–Tadmor (1998) staggered central scheme for a 2D model on ``grid``.

    Each step maps the cell averages of one family to those of the other, centred on the
    corners of the first (Jiang & Tadmor 1998, SIAM J. Sci. Comput. 19, 1892–1917; the formula
    and its predictor are in :mod:`~conslaw.schemes.jiang_tadmor.reference`)::

        w_new = (a + b + c + d)/4 + (slope terms)/16
                - dt/(2 dx) (x fluxes of the predicted values) - dt/(2 dy) (y fluxes)

    Parameters
    ----------
    model, reconstructor, grid, boundaries, cfl, inflow
        As :class:`~conslaw.schemes.jiang_tadmor.reference.JiangTadmorReference` (which checks
        them).
    threads : int, optional
        Threads of the compiled kernel, in ``[1, available_threads()]`` (default: numba's,
        every core).
    chunks : int, optional
        Chunks of rows a step is cut into, at least 1 (default ``2 threads``); the results do
        not depend on it, bit for bit.

    Raises
    ------
    ConfigError
        If ``threads`` or ``chunks`` is out of range (with or without a bed), or as
        :class:`JiangTadmorReference`.

    Notes
    -----
    Models without a bed take the compiled kernel, and so do depth-averaged models over a bed
    (:func:`compiles`, :func:`over_bed`: a pass that finds the still cells, the bed they are
    read with and the surface, then the rows); any other model's steps are
    :meth:`JiangTadmorReference.step`, run by numpy, and ``threads`` and ``chunks`` are checked
    but not used. Everything else is the same in both: the values (the kernels' arithmetic is
    the reference's, operation for operation), the time loop of :meth:`advance` with its
    progress reports and its check for values that are not finite, and :meth:`step` refusing a
    ``dt`` whose Courant number reaches 1/2.
    """

    #: The scheme's name in the registry of 2D schemes and in scene files.
    name: ClassVar[str] = "jiang-tadmor"
    description: ClassVar[str] = (
        "Jiang-Tadmor staggered central scheme in 2D (compiled, threads across rows)"
    )
    #: The options a scene's ``[scheme_options]`` may set (integers >= 1).
    options: ClassVar[dict[str, str]] = {
        "threads": "threads of the compiled kernel (default: every core)",
        "chunks": "chunks of rows a step is cut into (default: 2 per thread)",
    }
    #: Boundary conditions of every side.
    boundary_kinds: ClassVar[tuple[str, ...]] = KINDS

    def __init__(
        self,
        model: Model,
        reconstructor: Reconstructor,
        grid: Grid2D,
        boundaries: Mapping[str, str],
        cfl: float = 0.45,
        threads: int | None = None,
        chunks: int | None = None,
        inflow: Mapping[str, Sequence[float]] | None = None,
    ) -> None:
        self.reference = JiangTadmorReference(model, reconstructor, grid, boundaries, cfl, inflow)
        self.model, self.grid, self.cfl = model, grid, float(cfl)
        available = self.available_threads()
        self.threads = available if threads is None else int(threads)
        if not 1 <= self.threads <= available:
            raise ConfigError(
                f"scheme_options.threads must be in [1, {available}] (the cores this process "
                f"may use), got {threads!r}"
            )
        self.shapes = {
            staggered: self.reference.family_shape(staggered) for staggered in (False, True)
        }
        rows = min(shape[0] for shape in self.shapes.values())
        self.chunks = min(CHUNKS_PER_THREAD * self.threads, rows) if chunks is None else int(chunks)
        if not 1 <= self.chunks <= rows:
            raise ConfigError(
                f"scheme_options.chunks must be in [1, {rows}] (the rows of a step), got {chunks!r}"
            )
        self.compiled = compiles(model)
        #: The most times a step pair was redone in the run so far (``MAX_RETRIES`` stops it).
        self.most_retries = 0
        #: The state buffer whose depth went negative in the last pair tried, or None.
        self.negative_in: int | None = None
        # The families of a step pair (primary, staggered, primary) and their statistics: per
        # row, padded and reused by the kernel; the reference's values and one row over a bed.
        self.states = [np.zeros((model.n_vars, 0, 0)) for _ in range(3)]
        self.statistics = [np.zeros((1, STATISTICS)) for _ in range(3)]
        if self.compiled:
            self._prepare_kernel(reconstructor, boundaries)

    def _prepare_kernel(self, reconstructor: Reconstructor, boundaries: Mapping[str, str]) -> None:
        """The compiled kernel of the model, its parameters, padded buffers and sides."""
        model, shapes = self.model, self.shapes
        self.kernels = jt_kernels(model, reconstructor)
        code = -1.0 if reconstructor.code is None else float(reconstructor.code)
        self.params = np.append(model.param_vector(), code)
        columns = max(shape[1] for shape in shapes.values())
        self.work = np.zeros(self.kernels.work_shape(self.chunks, columns))
        nv = model.n_vars
        padded = {
            s: (nv, rows + 2 * GHOSTS, cols + 2 * GHOSTS) for s, (rows, cols) in shapes.items()
        }
        if over_bed(model):
            self._prepare_bed(reconstructor, padded, columns)
        if on_field(model):
            self._prepare_field(reconstructor, columns)
        self.states = [np.zeros(padded[False]), np.zeros(padded[True]), np.zeros(padded[False])]
        self.statistics = [np.zeros((shapes[s][0], STATISTICS)) for s in (False, True, False)]
        kinds = np.array([KINDS.index(boundaries[side]) for side in SIDES], dtype=np.int64)
        signs_x = np.asarray(model.reflect_signs, dtype=np.float64)
        signs_y = np.asarray(model.reflect_signs_y or model.reflect_signs, dtype=np.float64)
        inflow = np.zeros((len(SIDES), model.n_vars))
        for index, side in enumerate(SIDES):
            if side in self.reference.inflow:
                inflow[index] = self.reference.inflow[side]
        self.sides = self.kernels.Sides(kinds, signs_x, signs_y, inflow)
        if [KINDS.index(k) for k in KINDS] != [
            self.kernels.PERIODIC,
            self.kernels.OUTFLOW,
            self.kernels.WALL,
            self.kernels.INFLOW,
        ]:  # the kernel's codes of the kinds are the reference's order
            raise AssertionError("side kinds out of order")

    def _prepare_bed(
        self, reconstructor: Reconstructor, padded: dict[bool, tuple[int, int, int]], columns: int
    ) -> None:
        """The kernels over a bed, their work array, and a coefficient bundle per direction of
        a step (``self.beds[staggered]``: the source family's static coefficients, the new
        family's, and the arrays the kernel fills per step)."""
        self.bed_kernels = jt_bed_kernels(self.model, reconstructor)
        self.work = np.zeros(self.bed_kernels.bed_work_shape(self.chunks, columns))
        coefficients = {
            s: np.ascontiguousarray(self.reference.family_aux_padded(s)) for s in padded
        }
        self.beds = {
            s: self.bed_kernels.Bed(
                coefficients[s],
                coefficients[not s],
                np.zeros_like(coefficients[s]),
                np.zeros(padded[s][1:]),
                np.zeros(padded[s][1:]),
            )
            for s in padded
        }

    def _prepare_field(self, reconstructor: Reconstructor, columns: int) -> None:
        """The field kernels, their work array, and a coefficient bundle per direction of a
        step (``self.fields[staggered]``: the source family's coefficients at its centres and
        quarter points, the new family's at its centres, all padded as the states and laid out
        cell by cell, :func:`cell_major`)."""
        self.field_kernels = jt_field_kernels(self.model, reconstructor)
        self.work = np.zeros(self.field_kernels.field_work_shape(self.chunks, columns))
        reference = self.reference
        centres = {s: cell_major(reference.family_aux_padded(s)) for s in (False, True)}
        self.fields = {
            s: self.field_kernels.Field(
                centres[s],
                *(cell_major(quarter) for quarter in reference.quarter_aux_padded(s)),
                centres[not s],
            )
            for s in (False, True)
        }

    def _kernel_module(self) -> Any:
        """The generated module whose step this scheme runs (field, bed or flat)."""
        if on_field(self.model):
            return self.field_kernels
        return self.bed_kernels if over_bed(self.model) else self.kernels

    def initial_values(self, initial: Any) -> Array | None:
        """The scheme's own initial values of a scene's initial condition, or None for the
        cell averages: still water (``initial.kind == "still-water"``) is
        :meth:`JiangTadmorReference.still_water`, level over the scheme's quarter-cell bed, so
        that it stays at rest to round-off.

        Parameters
        ----------
        initial : InitialCondition2D
            Its ``kind`` and ``options``.

        Returns
        -------
        numpy.ndarray or None
            ``(n_vars, ny, nx)`` values, or None.
        """
        if initial.kind == "still-water" and self.model.depth_index is not None:
            return self.reference.still_water(float(initial.options["surface"]))
        return None

    def kernel_identity(self) -> str | None:
        """The name of the generated kernel module this scheme runs (runs that share it share
        one compile), or None for a model the kernels do not cover (numpy steps)."""
        if not self.compiled:
            return None
        return str(self._kernel_module().__name__)

    def needs_compile(self) -> bool:
        """Whether the first step compiles the kernel (it is not in numba's cache)."""
        if not self.compiled:
            return False
        if on_field(self.model):
            return not compiled_before(self.field_kernels, "step_family_field")
        if over_bed(self.model):
            return not compiled_before(self.bed_kernels, "step_family_bed")
        return not compiled_before(self.kernels, "step_family")

    def compile(self) -> None:
        """Compile (or load from the cache) the kernel's functions, with the kernel module's
        compile lock held (:func:`~conslaw.kernelgen.compile_lock`: of several processes that
        need the same kernel, one compiles it): one step of length 0 on still values."""
        if not self.compiled:
            return
        with compile_lock(self._kernel_module()):
            q = np.zeros((self.model.n_vars, *self.shapes[False]))
            if self.model.depth_index is not None:
                q[self.model.depth_index] = 1.0
            self.step(q, False, 0.0)

    @staticmethod
    def available_threads() -> int:
        """The most threads a kernel can run on.

        Returns
        -------
        int
            numba's thread count (``NUMBA_NUM_THREADS``, every core unless set).
        """
        return int(numba.config.NUMBA_NUM_THREADS)  # type: ignore[attr-defined]

    def step(self, q: Array, staggered: bool, dt: float) -> Array:
        """One step from the family of ``q`` to the other, as :meth:`JiangTadmorReference.step`.

        Parameters
        ----------
        q : ndarray
            Values of the primary family (``staggered`` False) or of the staggered one,
            ``(n_vars, rows, columns)``.
        staggered : bool
            Whether ``q`` is the staggered family.
        dt : float
            The time step.

        Returns
        -------
        ndarray
            The other family's values (a new array).

        Raises
        ------
        SchemeBreakdownError
            If a Courant number of ``q`` reaches 1/2 with this ``dt``.
        """
        if not self.compiled:
            return self.reference.step(q, staggered, dt)
        source, target = (1, 2) if staggered else (0, 1)
        self._load(q, source)
        if self._courant_reached(self.statistics[source], dt):
            raise SchemeBreakdownError(
                f"dt={dt:g} makes a Courant number reach {CFL_LIMIT} (Jiang & Tadmor 1998)"
            )
        self._step(source, target, staggered, dt)
        return self._values(target).copy()

    def stable_dt(self, statistics: Array) -> float:
        """The largest time step of a family with both Courant numbers at most ``cfl``, as
        :meth:`JiangTadmorReference.stable_dt`: ``min(cfl dx / max|a_x|, cfl dy / max|a_y|)``.

        Parameters
        ----------
        statistics : ndarray
            The family's statistics, one row per row of cells (or one for the whole family),
            columns ``SPEED_X``, ``SPEED_Y``, ``LOWEST``, ``DEEPEST`` of
            :mod:`~conslaw.schemes.jiang_tadmor.constants`.

        Returns
        -------
        float
            The time step; inf at rest.
        """
        speed_x = float(np.max(statistics[:, SPEED_X]))
        speed_y = float(np.max(statistics[:, SPEED_Y]))
        dt_x = self.cfl * self.grid.dx / speed_x if speed_x > 0.0 else np.inf
        dt_y = self.cfl * self.grid.dy / speed_y if speed_y > 0.0 else np.inf
        return min(dt_x, dt_y)

    def _courant_reached(self, statistics: Array, dt: float) -> bool:
        speed_x = float(np.max(statistics[:, SPEED_X]))
        speed_y = float(np.max(statistics[:, SPEED_Y]))
        return max(dt * speed_x / self.grid.dx, dt * speed_y / self.grid.dy) >= CFL_LIMIT

    def _negative_depth(self, statistics: Array) -> bool:
        return self.model.depth_index is not None and bool(np.min(statistics[:, LOWEST]) < 0.0)

    def _values(self, buffer: int) -> Array:
        """The cells of state buffer ``buffer`` (a view; buffer 1 holds a staggered family)."""
        if not self.compiled:
            return self.states[buffer]
        rows, columns = self.shapes[buffer == 1]
        return self.states[buffer][:, GHOSTS : GHOSTS + rows, GHOSTS : GHOSTS + columns]

    def _load(self, q: Array, buffer: int) -> None:
        """Values ``q`` into state buffer ``buffer`` (its ghosts filled for the kernel), with
        their statistics."""
        if not self.compiled:
            self.states[buffer] = np.asarray(q, dtype=np.float64)
            self.statistics[buffer] = self._reference_statistics(self.states[buffer], buffer == 1)
            return
        staggered = buffer == 1
        rows, columns = self.shapes[staggered]
        self._values(buffer)[...] = q
        self.kernels.fill_ghosts(self.states[buffer], rows, columns, staggered, self.sides)
        numba.set_num_threads(self.threads)
        if on_field(self.model):
            self.field_kernels.family_statistics_field(
                self.states[buffer], rows, columns, self.params, self.statistics[buffer],
                self.fields[staggered].aux,
            )  # fmt: skip
            return
        self.kernels.family_statistics(
            self.states[buffer], rows, columns, self.params, self.statistics[buffer]
        )

    def _reference_statistics(self, values: Array, staggered: bool) -> Array:
        """The statistics of a family (``staggered`` or primary) of the reference's steps as
        one row, as the kernel's
        ``row_statistics`` of all its cells: the speeds and the smallest depth NaN if a value
        or a wave speed is not finite."""
        statistics = np.array([[0.0, 0.0, np.inf, -np.inf]])
        with np.errstate(invalid="ignore", over="ignore"):
            speeds = self.reference.max_speeds(values, staggered)
        statistics[0, SPEED_X], statistics[0, SPEED_Y] = speeds
        depth = self.model.depth_index
        if depth is not None:
            statistics[0, LOWEST] = np.min(values[depth])
            statistics[0, DEEPEST] = np.max(values[depth])
        if not (np.all(np.isfinite(values)) and np.all(np.isfinite(speeds))):
            statistics[0, [SPEED_X, SPEED_Y, LOWEST]] = np.nan
        return statistics

    def _step(self, source: int, target: int, staggered: bool, dt: float) -> Array:
        """One step from state buffer ``source`` (a primary family unless ``staggered``) into
        buffer ``target`` (its ghosts filled for the kernel); the new family's statistics."""
        if not self.compiled:
            new = self.reference.step(self.states[source], staggered, dt)
            self.states[target] = new
            self.statistics[target] = self._reference_statistics(new, not staggered)
            return self.statistics[target]
        kernels = self.kernels
        rows, columns = self.shapes[not staggered]
        first = GHOSTS if staggered else GHOSTS - 1
        deepest = float(np.max(self.statistics[source][:, DEEPEST]))
        step = kernels.Step(first, rows, columns, dt, self.grid.dx, self.grid.dy, deepest)
        statistics = self.statistics[target]
        numba.set_num_threads(self.threads)
        if on_field(self.model):
            self.field_kernels.step_family_field(
                self.states[source], self.states[target], self.work, statistics, self.params,
                step, self.fields[staggered],
            )  # fmt: skip
        elif over_bed(self.model):
            bed = self.beds[staggered]
            w = self.states[source]
            self.bed_kernels.prepare_bed(w, bed, self.grid.dx, self.grid.dy, self.params)
            self.bed_kernels.step_family_bed(
                w, self.states[target], self.work, statistics, self.params, step, bed
            )
        else:
            kernels.step_family(
                self.states[source], self.states[target], self.work, statistics, self.params, step
            )
        kernels.fill_ghosts(self.states[target], rows, columns, not staggered, self.sides)
        return statistics

    def _pair(self, dt: float) -> tuple[bool, float]:
        """A step pair from buffer 0 (through 1) into buffer 2, as
        :meth:`JiangTadmorReference._pair`: ``(True, dt)`` or ``(False, the step to redo it
        with)``; the buffer whose depth went negative, if one did, in ``self.negative_in``."""
        self.negative_in = None
        middle = self._step(0, 1, False, dt)
        self._check_finite(1, 1, dt)
        if self._negative_depth(middle):
            self.negative_in = 1
            return False, 0.5 * dt
        if self._courant_reached(middle, dt):
            return False, self.stable_dt(middle)
        end = self._step(1, 2, True, dt)
        self._check_finite(2, 2, 2.0 * dt)
        if self._negative_depth(end):
            self.negative_in = 2
            return False, 0.5 * dt
        if self.reference.held_at_rest(self._values(0), self._values(1), self._values(2)):
            self.states[2] = self.states[0].copy()
            self.statistics[2] = self.statistics[0].copy()
        return True, dt

    def _check_finite(self, buffer: int, step: int, elapsed: float) -> None:
        """A :class:`_NotFiniteError` naming the first cell (in row order) of buffer ``buffer``
        with a value that is not finite, or a wave speed, if any: the family reached ``step``
        steps and ``elapsed`` time into the current pair."""
        statistics = self.statistics[buffer]
        if np.all(np.isfinite(statistics[:, [SPEED_X, SPEED_Y]])):
            return
        bad = np.argwhere(~np.all(np.isfinite(self._values(buffer)), axis=0))
        where = "a wave speed" if bad.size == 0 else f"cell (row {bad[0][0]}, column {bad[0][1]})"
        family = "staggered" if buffer == 1 else "primary"
        raise _NotFiniteError(f"{where} of the {family} family is not finite", step, elapsed)

    def advance(
        self,
        q: Array,
        t: float,
        t_end: float,
        progress: Callable[[float, int], Any] | None = None,
        observe: Callable[[Array], Any] | None = None,
    ) -> tuple[Array, float, int]:
        """Advance primary-family values from ``t`` to exactly ``t_end``, as
        :meth:`JiangTadmorReference.advance`: step pairs of one ``dt``, a pair redone with half
        its ``dt`` while a depth would become negative and with the staggered values' stable
        ``dt`` if their Courant number would reach 1/2.

        Parameters
        ----------
        q : ndarray
            Primary-family values, ``(n_vars, ny, nx)``.
        t, t_end : float
            The start and the end time.
        progress : callable, optional
            Called as ``progress(t, steps)`` after every step pair.
        observe : callable, optional
            Called as ``observe(values)`` with the primary-family values (a view, not to be
            kept) after every step pair (the peak fields of hazard maps).

        Returns
        -------
        values : ndarray
            The values at ``t_end`` (a new array).
        t : float
            ``t_end``.
        steps : int
            The number of steps taken.

        Raises
        ------
        SchemeBreakdownError
            If the time step falls below ``DT_FLOOR dx``, or a value or wave speed is not
            finite: the time and the step at which it became so (step 0: the start), the
            family and the first such cell, as ``t=0.25, step 7: cell (row 4, column 2) of the
            staggered family is not finite``.
        """
        steps = 0
        try:
            self._load(q, 0)
            self._check_finite(0, 0, 0.0)
            while t < t_end:
                t, steps = self._advance_pair(t, t_end, steps)
                if observe is not None:
                    observe(self._values(0))
                if progress is not None:
                    progress(t, steps)
        except _NotFiniteError as error:
            raise SchemeBreakdownError(
                f"t={t + error.elapsed:g}, step {steps + error.step}: {error}"
            ) from None
        return self._values(0).copy(), t, steps

    def _advance_pair(self, t: float, t_end: float, steps: int) -> tuple[float, int]:
        """One accepted step pair from ``t``; the new time and step count. A pair is tried at
        most ``MAX_RETRIES`` times (``self.most_retries`` keeps the most redone so far), and
        never with a step below ``DT_FLOOR dx`` but to land on ``t_end``: either stops the run
        (:meth:`_breakdown`), so no run is caught in ever smaller steps."""
        remaining = t_end - t
        dt = min(
            self.stable_dt(self.statistics[0]), self.reference.source_step_limit(self._values(0))
        )
        last = 2.0 * dt >= remaining
        if last:
            dt = 0.5 * remaining
        for tries in range(MAX_RETRIES):
            if dt < DT_FLOOR * self.grid.dx and not last:
                cause = f"the time step fell to {dt:.3g}, below {DT_FLOOR:g} dx"
                raise self._breakdown(t, steps, cause)
            accepted, next_dt = self._pair(dt)
            if accepted:
                self.most_retries = max(self.most_retries, tries)
                self.states[0], self.states[2] = self.states[2], self.states[0]
                self.statistics[0], self.statistics[2] = self.statistics[2], self.statistics[0]
                return (t_end if last else t + 2.0 * dt), steps + 2
            dt, last = next_dt, False
        cause = f"a step pair failed {MAX_RETRIES} times, the last with dt={dt:.3g}"
        raise self._breakdown(t, steps, cause)

    def _breakdown(self, t: float, steps: int, cause: str) -> SchemeBreakdownError:
        """The one-line error of a run that cannot take its next step pair from ``t``:
        ``cause``, then the cell of the family whose depth went negative with its smallest
        depth, or else the fastest cell of the state at ``t``
        (:mod:`~conslaw.schemes.jiang_tadmor.breakdown`), and what to try."""
        buffer = self.negative_in or 0
        staggered = buffer == 1
        values = self._values(buffer)
        aux = self.reference.family_aux(staggered) if self.model.n_aux else None
        if buffer:
            cell = shallowest_cell(self.model, values)
            what = "where a depth stays negative"
        else:
            cell = fastest_cell(self.model, values, aux)
            what = "the fastest"
        family = "staggered " if staggered else ""
        centres = self.grid.centres(
            0.5 if staggered else 0.0, self.reference.periodic_x, self.reference.periodic_y
        )
        report = cell_report(self.model, values, aux, centres, cell)
        return SchemeBreakdownError(
            f"t={t:g}, step {steps}: {cause}; {what} {family}{report}; {REMEDIES}"
        )


class _NotFiniteError(Exception):
    """A value or wave speed of a family is not finite, ``step`` steps and ``elapsed`` time into
    the current step pair (0 and 0: the start); :meth:`JiangTadmor.advance` makes it a
    SchemeBreakdownError with the time and the step."""

    def __init__(self, message: str, step: int, elapsed: float) -> None:
        super().__init__(message)
        self.step = step
        self.elapsed = elapsed
