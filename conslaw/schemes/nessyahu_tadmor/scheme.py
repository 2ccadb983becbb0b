"""The Nessyahu–Tadmor non-oscillatory central (NOC) staggered scheme.

Tai, Noelle, Gray & Hutter (2001), eqs. (10)–(18); Nessyahu & Tadmor (1990). The default path is a
fused, compiled kernel (:mod:`~conslaw.schemes.nessyahu_tadmor.kernel_template`) that advances
many step pairs per call;
:meth:`NessyahuTadmor.reference_step` is an independent numpy implementation used to test it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, InadmissibleStateError, SchemeBreakdownError
from conslaw.grid import Grid
from conslaw.kernelgen import compile_lock, compiled_before
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor
from conslaw.reconstruct.base import STENCIL_HALF_WIDTH
from conslaw.schemes.base import (
    DT_FLOOR_RELATIVE,
    AdvanceResult,
    BoundarySpec,
    ProgressCallback,
    Scheme,
)
from conslaw.schemes.coefficient_families import coefficient_family, padded_positions
from conslaw.schemes.depth_rules import velocity_bounded_slope
from conslaw.schemes.nessyahu_tadmor.constants import DEPTH_SLOPE_LIMIT, FILM
from conslaw.schemes.nessyahu_tadmor.kernels import kernel_parameters, nt_kernels
from conslaw.state import State

Array = NDArray[np.float64]

#: Ghost cells each side: one for the staggered flux, two for the widest slope stencil.
GHOSTS = 1 + STENCIL_HALF_WIDTH
#: Cell updates per call of the compiled kernel between progress reports (0.01-0.1 s at the
#: measured 4e7-4e8 cell updates per second; a call itself costs about 10 microseconds).
CELL_UPDATES_PER_CALL = 4_000_000


def _resist(momentum: Array, impulse: Array) -> Array:
    """numpy version of the kernel's ``resist``: stop if ``|m| <= impulse``, never reverse."""
    reduced = momentum - np.sign(momentum) * impulse
    return np.where(np.abs(momentum) <= impulse, 0.0, reduced)


class SubcellHooks:
    """Points where a variant of the numpy NT update may replace the reconstruction in chosen
    cells (all no-ops here; front tracking overrides them in the margin cells). Arrays are
    ``(n_vars, n)`` over the source cells of the update, ``x_cells`` their centres."""

    def adjust_source_depths(
        self,
        values: Array,
        slopes: Array,
        transported: Array,
        quarter_left: Array,
        quarter_right: Array,
    ) -> None:
        """Replace the quarter-point states of every staggered cell once its transported
        (flux-updated, source-free) average is known."""

    def stencil_values(self, w: Array, x_padded: Array) -> Array:
        """The padded values the slope stencils read (``w`` itself here)."""
        return w

    def adjust_slopes(self, values: Array, slopes: Array, x_cells: Array) -> None:
        """Replace slopes in place (they define the half-cell integrals of eq. 10)."""

    def adjust_predicted(self, values: Array, predicted: Array, x_cells: Array, dt: float) -> None:
        """Replace the mid-step point values at the cell centres (eq. 15) in place."""

    def adjust_quarters(
        self, values: Array, slopes: Array, quarter_left: Array, quarter_right: Array
    ) -> None:
        """Replace the quarter-point states of the source integration (eqs. 13-14) in place."""


def static_runs_held(momentum: Array, impulse: Array, span: Array, seam: int = -1) -> Array:
    """Which new cells friction and a statically admissible pressure bring to rest: the
    kernel's ``hold_static_runs`` (whose docstring gives the rule), in plain Python loops (the
    reference, not the kernel). ``momentum`` is every new cell's momentum before the stopping
    rule with the low end of the rest range, ``impulse`` its resistive impulse, ``span`` the
    largest flux change at every source cell (new cell ``g`` lies between source cells ``g``
    and ``g + 1``), ``seam`` the new cell left to friction alone (-1: none)."""
    n = momentum.size
    holdable = (momentum - impulse <= span[:n]) & (momentum + impulse >= -span[1 : n + 1])
    if seam >= 0:
        holdable[seam] = False

    def longest_from(start: int, stop: int) -> int:
        low = high = 0.0
        end = start - 1
        for k in range(start, stop):
            low, high = low + momentum[k] - impulse[k], high + momentum[k] + impulse[k]
            if low <= 0.0 <= high:
                end = k
            if k + 1 < stop:
                low, high = max(low, 0.0), min(high, span[k + 1])
                if low > high:
                    break
        return end

    held = np.zeros(n, dtype=bool)
    g = 0
    while g < n:
        if not holdable[g]:
            g += 1
            continue
        stop = g + 1
        while stop < n and holdable[stop]:
            stop += 1
        pending = [(g, stop)]
        while pending:
            start, end = pending.pop()
            best_start, best_stop, tied = start, start, False
            for first in range(start, end):
                last = longest_from(first, end)
                length = last + 1 - first
                if length > best_stop - best_start:
                    best_start, best_stop, tied = first, last + 1, False
                elif length > 0 and length == best_stop - best_start and first < best_stop:
                    tied = True
                if last + 1 >= end:
                    break
            if best_stop == best_start or tied:
                continue
            held[best_start:best_stop] = True
            pending += [(start, best_start), (best_stop, end)]
        g = stop
    return held


def validate_cfl(cfl: Any) -> float:
    """The CFL number as a float in (0, 1/2) (paper eq. 17), or a ConfigError."""
    if isinstance(cfl, bool) or not isinstance(cfl, int | float) or not np.isfinite(cfl):
        raise ConfigError(f"cfl must be a number in (0, 0.5), got {cfl!r}")
    if not 0.0 < cfl < 0.5:
        raise ConfigError(f"cfl must be in (0, 0.5) for the Nessyahu–Tadmor scheme, got {cfl}")
    return float(cfl)


class NessyahuTadmor(Scheme):
    """Staggered central scheme of Nessyahu & Tadmor with quarter-point source integration.

    One :meth:`step` moves the solution from one cell family to the other (``State.offset``
    0 <-> 1/2); :meth:`advance` always takes steps in pairs with one ``dt`` per pair, so its result
    is on the primary grid at exactly the requested time.

    Parameters
    ----------
    model, reconstructor : Model, Reconstructor
        Physics and slopes (injected).
    grid : Grid
        The primary grid.
    left, right : BoundarySpec
        Boundary conditions.
    cfl : float
        Target Courant number, ``0 < cfl < 1/2`` (paper eq. 17).
    """

    name = "nessyahu-tadmor"
    description = "Nessyahu–Tadmor staggered central scheme (NOC), paper eqs. (10)-(18)"

    def __init__(
        self,
        model: Model,
        reconstructor: Reconstructor,
        grid: Grid,
        left: BoundarySpec,
        right: BoundarySpec,
        cfl: float = 0.45,
    ) -> None:
        super().__init__(model, reconstructor, grid, left, right, validate_cfl(cfl))
        self.n_primary = grid.n_cells
        self.n_staggered = grid.n_cells_at(0.5, self.periodic)
        self.params = kernel_parameters(model, reconstructor)
        self.bc_left = left.condition.data(model, left.options)
        self.bc_right = right.condition.data(model, right.options)
        self._aux = {offset: self._aux_family(offset) for offset in (0.0, 0.5)}
        self._kernels: Any = None
        self._compiled = False  # whether compile() ran (advance() runs it first otherwise)
        n_pad = self.n_staggered + 2 * GHOSTS
        nv = model.n_vars
        self._w0 = np.zeros((nv, n_pad))
        self._w1 = np.zeros((nv, n_pad))
        self._w2 = np.zeros((nv, n_pad))
        self._work = np.zeros(0)  # the kernel's per-block rows, sized when it is built
        self.uses = model.capabilities()

    # ------------------------------------------------------------------ set-up
    def _padded_positions(self, offset: float) -> Array:
        return padded_positions(self.grid, offset, self.periodic, GHOSTS)

    def _aux_family(self, offset: float) -> tuple[Array, Array, Array]:
        """Model coefficients at the centres and quarter points of one padded cell family
        (:func:`~conslaw.schemes.coefficient_families.coefficient_family`, ghost cells by the
        rule of their boundary condition)."""
        rules = (self.left.condition.ghost_coefficients, self.right.condition.ghost_coefficients)
        return coefficient_family(self.model, self.grid, offset, self.periodic, rules, GHOSTS)

    @property
    def kernels(self) -> Any:
        """The generated compiled kernels (built on first use)."""
        if self._kernels is None:
            self._kernels = nt_kernels(
                self.model,
                self.reconstructor,
                self.left.condition.fill_left,
                self.right.condition.fill_right,
            )
            self._work = np.zeros(self._kernels.work_size(self.n_staggered))
        return self._kernels

    def kernel_identity(self) -> str | None:
        """The generated kernel module's name."""
        return str(self.kernels.__name__)

    def needs_compile(self) -> bool:
        """Whether the fused kernel's first call compiles (it is not in the kernel cache)."""
        return not compiled_before(self.kernels, "advance")

    def _compiled_module(self) -> Any:
        """The generated module that :meth:`advance` runs."""
        return self.kernels

    def compile(self, state: State) -> None:
        """As :meth:`Scheme.compile` (a zero-length advance), with the kernel module's compile
        lock held (:func:`~conslaw.kernelgen.compile_lock`): of several processes that need the
        same kernels, one compiles them and the others load them from the cache. The first
        :meth:`advance` of a scheme compiles this way if nothing did before."""
        self._compiled = True
        with compile_lock(self._compiled_module()):
            super().compile(state)

    def _family(self, state: State) -> tuple[int, bool]:
        staggered = state.offset != 0.0
        n = self.n_staggered if staggered else self.n_primary
        if state.n_cells != n or state.n_vars != self.model.n_vars:
            raise ValueError(
                f"state has shape {state.q.shape}, expected ({self.model.n_vars}, {n}) "
                f"for offset {state.offset}"
            )
        return n, staggered

    # ------------------------------------------------------------------ Scheme interface
    def stable_dt(self, state: State, cfl: float | None = None) -> float:
        """The time step :meth:`advance` takes from ``state``: ``cfl * dx / a_max`` (paper eqs.
        17-18), and at most :meth:`source_step_limit`; infinite for a state at rest without a
        source."""
        cfl = self.cfl if cfl is None else validate_cfl(cfl)
        return min(self._wave_dt(state, cfl), self.source_step_limit(state, cfl))

    def _wave_dt(self, state: State, cfl: float) -> float:
        """``cfl * dx / a_max`` (paper eqs. 17-18); infinite for a state at rest."""
        n, staggered = self._family(state)
        aux = self._aux[0.5 if staggered else 0.0][0][:, GHOSTS : GHOSTS + n]
        speed = self.model.max_wave_speed(state.q, aux)
        if not np.all(np.isfinite(speed)):
            self.check_admissible(state, step=0)
        largest = float(speed.max()) if speed.size else 0.0
        return np.inf if largest == 0.0 else cfl * self.grid.dx / largest

    def source_step_limit(self, state: State, cfl: float | None = None) -> float:
        """``sqrt(cfl dx / (2 a))`` with ``a = max |s_m| / h`` the largest acceleration the source
        gives a wet cell (``g |b_x|``, ``sin zeta``); infinite for a model without a driving
        source or without a depth.

        Over a step pair from rest the source builds up the velocity ``2 a dt``, which must
        itself meet the CFL condition: ``2 a dt^2 / dx <= cfl``. The wave speed alone does not see
        this: for a thin layer on a slope it is ``sqrt(g h) -> 0`` and gives an enormous step,
        whose predicted momentum ``dt a h / 2`` then drains more than the cell holds (a layer of
        1e-12 on a bed slope needed about 500 halvings of the step to stay >= 0, and the run
        stopped). The kernel's ``source_step_limit`` is the same bound.
        """
        cfl = self.cfl if cfl is None else validate_cfl(cfl)
        depth, momentum = self.model.depth_index, self.model.momentum_index
        if depth is None or momentum is None or not self.uses["source"]:
            return np.inf
        n, staggered = self._family(state)
        aux = self._aux[0.5 if staggered else 0.0][0][:, GHOSTS : GHOSTS + n]
        h = state.q[depth]
        wet = h > 0.0
        if not wet.any():
            return np.inf
        source = self.model.source(state.q[:, wet], aux[:, wet])[momentum]
        largest = float(np.max(np.abs(source) / h[wet]))
        return np.inf if not largest > 0.0 else float(np.sqrt(cfl * self.grid.dx / (2 * largest)))

    def step(self, state: State, dt: float) -> State:
        """One compiled NT step to the other cell family (offset 0 <-> 1/2)."""
        n_src, staggered = self._family(state)
        self._check_step(state, dt)
        n_dst = self.n_primary if staggered else self.n_staggered
        src = self._w0
        src[:, GHOSTS : GHOSTS + n_src] = state.q
        kernels = self.kernels
        kernels.nt_step(
            src,
            self._w1,
            self._cell_family(kernels, 0.5 if staggered else 0.0),
            self._cell_family(kernels, 0.0 if staggered else 0.5),
            0 if staggered else -1,
            float(dt),
            self.grid.dx,
            self.params,
            kernels.Boundary(self.bc_left, self.bc_right),
            self._work,
        )
        offset = 0.0 if staggered else 0.5
        return State(
            state.t + dt,
            self.grid.centres(offset, self.periodic),
            self._w1[:, GHOSTS : GHOSTS + n_dst].copy(),
            offset,
        )

    def _check_step(self, state: State, dt: float) -> None:
        if not (np.isfinite(dt) and dt > 0.0):
            raise ConfigError(f"dt must be a positive number, got {dt!r}")
        if dt > self._wave_dt(state, 0.4999999999999999):
            raise ConfigError(
                f"dt={dt:g} violates the CFL condition dt*a_max/dx < 1/2 (paper eq. 17)"
            )

    def reference_step(self, state: State, dt: float) -> State:
        """The same step as :meth:`step`, written with numpy array operations (for testing)."""
        _, staggered = self._family(state)
        self._check_step(state, dt)
        new = self._numpy_update(state.q, staggered, dt, SubcellHooks())
        offset = 0.0 if staggered else 0.5
        return State(state.t + dt, self.grid.centres(offset, self.periodic), new, offset)

    def _numpy_update(self, q: Array, staggered: bool, dt: float, hooks: SubcellHooks) -> Array:
        """The NT update of ``q`` (one cell family) in numpy; ``hooks`` may replace the
        reconstruction of chosen cells (front tracking does so in the margin cells)."""
        n_src = q.shape[1]
        n_dst = self.n_primary if staggered else self.n_staggered
        centre, left_quarter, right_quarter = self._aux[0.5 if staggered else 0.0]
        nv = self.model.n_vars
        w = np.zeros((nv, n_src + 2 * GHOSTS))
        w[:, GHOSTS : GHOSTS + n_src] = q
        self.left.condition.fill_left(w, n_src, GHOSTS, staggered, self.bc_left)
        self.right.condition.fill_right(w, n_src, GHOSTS, staggered, self.bc_right)
        first = GHOSTS + (0 if staggered else -1)
        cells = slice(first, first + n_dst + 1)
        stencil = slice(first - STENCIL_HALF_WIDTH, first + n_dst + 1 + STENCIL_HALF_WIDTH)
        x_padded = self._padded_positions(0.5 if staggered else 0.0)
        slopes = self._reference_slopes(
            w, centre, stencil, cells, hooks.stencil_values(w, x_padded)
        )
        values = w[:, cells]
        x_cells = x_padded[cells]
        hooks.adjust_slopes(values, slopes, x_cells)
        model = self.model
        coefficients = model.dynamic_coefficients(values, slopes, centre[:, cells])
        momentum = model.momentum_index
        predicted = self._predictor(values, slopes, coefficients, dt)
        if self.uses["resistance"]:
            assert momentum is not None
            predicted[momentum] = _resist(
                predicted[momentum], 0.5 * dt * model.resistance(values, coefficients)
            )
        hooks.adjust_predicted(values, predicted, x_cells, dt)
        rest_difference, span = None, None
        if self.uses["interface_coefficients"]:
            difference, rest_difference, span = self._interface_flux_difference(
                predicted, centre[:, cells], dt
            )
        else:
            flux = model.flux(predicted, coefficients)
            difference = flux[:, 1:] - flux[:, :-1]
        new = (
            0.5 * (values[:, :-1] + values[:, 1:])
            + 0.125 * (slopes[:, :-1] - slopes[:, 1:])
            - dt / self.grid.dx * difference
        )
        quarter_left, quarter_right = predicted - 0.25 * slopes, predicted + 0.25 * slopes
        hooks.adjust_quarters(values, slopes, quarter_left, quarter_right)
        hooks.adjust_source_depths(values, slopes, new, quarter_left, quarter_right)
        if self.uses["balanced_source"]:
            new += dt * model.balanced_source(predicted, centre[:, cells], self.grid.dx)
        elif self.uses["source"]:
            source_right = model.source(quarter_right, right_quarter[:, cells])
            source_left = model.source(quarter_left, left_quarter[:, cells])
            new += 0.5 * dt * (source_right[:, :-1] + source_left[:, 1:])
        before_resistance = None if momentum is None else new[momentum].copy()
        impulse = np.zeros(n_dst)
        if self.uses["resistance"]:
            assert momentum is not None
            resistance_right = model.resistance(quarter_right, right_quarter[:, cells])
            resistance_left = model.resistance(quarter_left, left_quarter[:, cells])
            impulse = 0.5 * dt * (resistance_right[:-1] + resistance_left[1:])
            new[momentum] = _resist(new[momentum], impulse)
        if self.uses["correction"]:
            aux_dst = self._aux[0.0 if staggered else 0.5][0][:, GHOSTS : GHOSTS + n_dst]
            new = model.correct(new, aux_dst, dt)
        if model.depth_index is not None and momentum is not None:
            film = FILM * float(np.max(q[model.depth_index], initial=0.0))
            aux_new = self._aux[0.0 if staggered else 0.5][0][:, GHOSTS : GHOSTS + n_dst]
            self._bound_velocities(w, (centre, aux_new), first, dt, new, film)
        if rest_difference is not None and span is not None:
            assert momentum is not None and before_resistance is not None
            ratio = dt / self.grid.dx
            low = before_resistance - ratio * (rest_difference - difference[momentum])
            seam = 0 if self.periodic and not staggered else -1
            held = static_runs_held(low, impulse, span, seam)
            new[momentum] = np.where(held, 0.0, new[momentum])
        return new

    def _predictor(self, values: Array, slopes: Array, coefficients: Array, dt: float) -> Array:
        """``w + dt/2 (-A(w) w'/dx + s(w))`` (eq. 15) with the given coefficients."""
        model = self.model
        jacobian = model.flux_jacobian(values, coefficients)
        rate = -np.einsum("rcm,cm->rm", jacobian, slopes) * (1.0 / self.grid.dx)
        rate += model.source(values, coefficients)
        return values + 0.5 * dt * rate

    def _interface_flux_difference(
        self, predicted: Array, static: Array, dt: float
    ) -> tuple[Array, Array | None, Array | None]:
        """``f(w_R) - f(w_L)`` of every new cell with the coefficients the model chooses for it
        (the kernel's interface_fluxes). With rest coefficients also the momentum row of that
        difference with the low end of the rest range (the kernel's FLUX_LOW), and per source
        cell ``dt/dx`` times its flux's change from the low to the high end (FLUX_SPAN)."""
        model = self.model
        left, right = predicted[:, :-1], predicted[:, 1:]
        aux_left, aux_right = model.interface_coefficients(
            left, right, static[:, :-1], static[:, 1:]
        )
        difference = model.flux(right, aux_right) - model.flux(left, aux_left)
        if not self.uses["rest_coefficients"]:
            return difference, None, None
        momentum = model.momentum_index
        assert momentum is not None
        low, high = model.rest_coefficients(static)
        flux_low = model.flux(predicted, low)[momentum]
        span = dt / self.grid.dx * (model.flux(predicted, high)[momentum] - flux_low)
        return difference, flux_low[1:] - flux_low[:-1], span

    def _bound_velocities(
        self, w: Array, centres: tuple[Array, Array], first: int, dt: float, new: Array, film: float
    ) -> None:
        """numpy version of the kernel's velocity bound of films (``bounded_film_momentum``): a
        new wet cell shallower than ``film`` (``FILM`` times the deepest source cell) keeps its
        Riemann invariants ``u -+ 2c`` within the smallest ``u - 2c`` and the largest ``u + 2c``
        of the four cells its update reads, those of the flow (at least ``film`` deep) widened by
        the change of their velocity an explicit step of their source and resistance makes (the
        kernel's ``velocity_range``), and its velocity between rest and that range
        (docs/design.md, "Films"). ``centres``: the coefficients at the padded source cells'
        centres and at the new cells'."""
        model = self.model
        centre, aux_new = centres
        d, m = model.depth_index, model.momentum_index
        assert d is not None and m is not None
        n_dst = new.shape[1]
        cells = slice(first - 1, first + n_dst + 2)
        q, aux = w[:, cells], centre[:, cells]
        h = q[d]
        wet = (h >= model.dry_depth()) & (h > 0.0)
        u = np.where(wet, q[m] / np.where(wet, h, 1.0), 0.0)
        c = np.maximum(model.max_wave_speed(q, aux) - np.abs(u), 0.0)
        driven = _resist(q[m] + dt * model.source(q, aux)[m], dt * model.resistance(q, aux))
        flow = (h >= film) & (h > 0.0)
        change = np.where(flow, (driven - q[m]) / np.where(flow, h, 1.0), 0.0)
        low = u - 2.0 * c + np.minimum(change, 0.0)
        high = u + 2.0 * c + np.maximum(change, 0.0)
        lo = np.minimum(np.minimum(low[:-3], low[1:-2]), np.minimum(low[2:-1], low[3:]))
        hi = np.maximum(np.maximum(high[:-3], high[1:-2]), np.maximum(high[2:-1], high[3:]))
        h_new = new[d]
        films = (h_new >= model.dry_depth()) & (h_new > 0.0) & (h_new < film)
        u_new = np.where(films, new[m] / np.where(films, h_new, 1.0), 0.0)
        with np.errstate(invalid="ignore"):
            celerity = model.max_wave_speed(new, aux_new) - np.abs(u_new)
        celerity = np.where(celerity > 0.0, celerity, 0.0)
        lo = np.minimum(lo + 2.0 * celerity, 0.0)
        hi = np.maximum(hi - 2.0 * celerity, 0.0)
        new[m] = np.where(
            films & (u_new < lo), lo * h_new, np.where(films & (u_new > hi), hi * h_new, new[m])
        )

    def _reference_slopes(
        self, w: Array, centre: Array, stencil: slice, cells: slice, data_w: Array | None = None
    ) -> Array:
        """Slopes with the depth rules of the kernel (surface reconstruction, depth limit).

        ``data_w`` (default ``w``) are the values the slope stencils read."""
        model = self.model
        data = (w if data_w is None else data_w)[:, stencil].copy()
        surface_rows = model.surface_aux if self.uses["surface"] else None
        if surface_rows is not None and model.depth_index is not None:
            data[model.depth_index] += centre[surface_rows[0], stencil]
        slopes = self.reconstructor.slopes(data)
        if model.depth_index is None:
            return slopes
        depth = w[model.depth_index, cells]
        if surface_rows is not None:
            slopes[model.depth_index] -= self.grid.dx * centre[surface_rows[1], cells]
        limit = DEPTH_SLOPE_LIMIT * depth
        slopes[model.depth_index] = np.clip(slopes[model.depth_index], -limit, limit)
        slopes[:, depth <= 0.0] = 0.0
        if model.momentum_index is not None:
            self._bound_momentum_slopes(w, cells, slopes)
        return slopes

    def cell_coefficients(self, state: State) -> Array:
        """The coefficients of the primary cells of ``state`` as the next step uses them: the
        static ones, with the dynamic ones (``Model.coefficients_point``; the Savage–Hutter
        earth-pressure coefficient, eq. 5) set from the state's reconstructed slopes."""
        n, staggered = self._family(state)
        if staggered:
            raise ValueError("cell_coefficients() needs a state on the primary grid (offset 0)")
        centre = self._aux[0.0][0]
        cells = slice(GHOSTS, GHOSTS + n)
        static = np.ascontiguousarray(centre[:, cells])
        if not self.uses["dynamic_coefficients"]:
            return static
        w = np.zeros((self.model.n_vars, n + 2 * GHOSTS))
        w[:, cells] = state.q
        self.left.condition.fill_left(w, n, GHOSTS, False, self.bc_left)
        self.right.condition.fill_right(w, n, GHOSTS, False, self.bc_right)
        hooks = self._hooks_at(state)
        x_padded = self._padded_positions(0.0)
        stencil = slice(GHOSTS - STENCIL_HALF_WIDTH, GHOSTS + n + STENCIL_HALF_WIDTH)
        slopes = self._reference_slopes(
            w, centre, stencil, cells, hooks.stencil_values(w, x_padded)
        )
        values = w[:, cells]
        hooks.adjust_slopes(values, slopes, x_padded[cells])
        return self.model.dynamic_coefficients(values, slopes, static)

    def _hooks_at(self, state: State) -> SubcellHooks:
        """The sub-cell reconstruction used in the cells of ``state`` (none here)."""
        return SubcellHooks()

    def _bound_momentum_slopes(self, w: Array, cells: slice, slopes: Array) -> None:
        """numpy version of the kernel's ``bound_momentum_slope``."""
        model = self.model
        d, m = model.depth_index, model.momentum_index
        assert d is not None and m is not None
        dry = model.dry_depth()
        depth_all, momentum_all = w[d], w[m]
        safe = np.where((depth_all >= dry) & (depth_all > 0.0), depth_all, 1.0)
        u = np.where((depth_all >= dry) & (depth_all > 0.0), momentum_all / safe, 0.0)
        start, stop = cells.start, cells.stop
        u_min = np.minimum(
            np.minimum(u[start - 1 : stop - 1], u[start:stop]), u[start + 1 : stop + 1]
        )
        u_max = np.maximum(
            np.maximum(u[start - 1 : stop - 1], u[start:stop]), u[start + 1 : stop + 1]
        )
        h, q = depth_all[cells], momentum_all[cells]
        slopes[m] = velocity_bounded_slope(h, q, slopes[d], slopes[m], u_min, u_max)

    def advance(
        self, state: State, t_end: float, progress: ProgressCallback | None = None
    ) -> AdvanceResult:
        """Advance a primary-grid state to exactly ``t_end`` with the fused compiled kernel.

        Raises
        ------
        InadmissibleStateError
            NaN, inf or a state outside the model's admissible set, with time, step and cell.
        SchemeBreakdownError
            The time step fell below ``1e-14 dx`` or the CFL condition could not be met.
        """
        n, staggered = self._family(state)
        if staggered:
            raise ValueError("advance() starts from the primary grid (offset 0)")
        if not t_end >= state.t:
            raise ConfigError(f"t_end={t_end} is before the state's time {state.t}")
        if not self._compiled:
            self.compile(state)
        w0 = self._w0
        w0[:, GHOSTS : GHOSTS + n] = state.q
        t = state.t
        steps = 0
        dt_floor = DT_FLOOR_RELATIVE * self.grid.dx
        pairs_per_call = max(1, CELL_UPDATES_PER_CALL // (2 * self.n_primary))
        kernels = self.kernels
        buffers = kernels.Buffers(w0, self._w1, self._w2, self._work)
        primary = self._cell_family(kernels, 0.0)
        staggered = self._cell_family(kernels, 0.5)
        controls = kernels.Controls(float(t_end), self.cfl, self.grid.dx, dt_floor, pairs_per_call)
        boundary = kernels.Boundary(self.bc_left, self.bc_right)
        while True:
            t, pairs, status, family, cell, dt = kernels.advance(
                buffers, primary, staggered, t, controls, self.params, boundary
            )
            steps += 2 * pairs
            if status == kernels.STATUS_PAUSED:
                if progress is not None:
                    progress(t, steps)
                continue
            if status == kernels.STATUS_DONE:
                break
            self._raise_failure(status, family, cell, t, steps, dt)
        result = State(t, state.x, w0[:, GHOSTS : GHOSTS + n].copy(), 0.0)
        if progress is not None:
            progress(t, steps)
        return AdvanceResult(result, steps)

    def _cell_family(self, kernels: Any, offset: float) -> Any:
        """The kernels' ``Family`` bundle of the primary (``offset`` 0) or staggered (1/2) cells:
        their number and the model's coefficients at their centres and quarter points."""
        count = self.n_primary if offset == 0.0 else self.n_staggered
        return kernels.Family(count, *self._aux[offset])

    def _fastest_cell(self) -> str:
        """``the fastest cell i (x=...): h=..., hu=... (wave speed ...)`` of the primary state
        in the kernel's first buffer (the start of the pair that failed)."""
        n = self.n_primary
        values = self._w0[:, GHOSTS : GHOSTS + n]
        aux = self._aux[0.0][0][:, GHOSTS : GHOSTS + n]
        with np.errstate(invalid="ignore", over="ignore"):
            speeds = self.model.max_wave_speed(values, aux)
        bad = ~np.isfinite(speeds) | ~np.all(np.isfinite(values), axis=0)
        cell = int(np.argmax(bad)) if bad.any() else int(np.argmax(speeds))
        x = self.grid.centres(0.0, self.periodic)[cell]
        state = ", ".join(
            f"{name}={float(values[v, cell]):.3g}" for v, name in enumerate(self.model.variables)
        )
        return f"the fastest cell {cell} (x={x:.6g}): {state} (wave speed {speeds[cell]:.3g})"

    def _raise_failure(
        self, status: int, family: int, cell: int, t: float, steps: int, dt: float
    ) -> None:
        k = self.kernels
        if status in (k.STATUS_INADMISSIBLE, k.STATUS_SPEED_NOT_FINITE):
            buffer = self._w0 if family == 0 else self._w1
            x = self.grid.centres(0.5 * family, self.periodic)[cell]
            values = ", ".join(
                f"{name}={float(buffer[v, GHOSTS + cell])!r}"
                for v, name in enumerate(self.model.variables)
            )
            kind = "staggered cell" if family else "cell"
            where = f"t={t:.6g}, step {steps + family}, {kind} {cell} (x={x:.6g})"
            if status == k.STATUS_SPEED_NOT_FINITE:
                raise InadmissibleStateError(
                    f"the wave speed is not finite (overflow) at {where}: {values}; "
                    "check the magnitudes of the parameters"
                )
            raise InadmissibleStateError(
                f"inadmissible state at {where}: {values} (need {self.model.admissible_rule})"
            )
        if status == k.STATUS_DT_FLOOR:
            raise SchemeBreakdownError(
                f"time step {dt:.3g} fell below the floor {DT_FLOOR_RELATIVE:g}*dx at t={t:.6g}, "
                f"step {steps}; {self._fastest_cell()}; likely remedies: a smaller cfl, "
                "reconstructor = 'minmod'"
            )
        raise SchemeBreakdownError(
            f"could not meet the CFL condition (< 1/2) at t={t:.6g}, step {steps}"
        )
