"""Front tracking (NOC-FT): the Nessyahu–Tadmor scheme with sharp avalanche margins.

Tai, Noelle, Gray & Hutter (2001), section "Front-tracking", Fig. 2 and eq. (19); the full method
is in Tai, Noelle, Gray & Hutter, J. Comput. Phys. 175 (2002). The body occupies
``[x_rear, x_front]``; outside it ``h = 0`` exactly (no thin layer).

- **Margin cells.** The cell holding a margin is reconstructed linearly from ``h = 0`` at the
  margin, with the cell average unchanged (front margin in ``[a, b]``:
  ``h(a) = 2 hbar dx / (x_F - a)``, paper Fig. 2), and ``h = 0`` beyond it; the velocity in it is
  linear with the inner cells' gradient and the cell's mean. The NT update (eqs. 10-14)
  integrates this reconstruction exactly over the half cells and takes the mid-step point value
  at the cell centre from the triangle carried to the margin's mid-step position.
- **Inner cells.** Their slope stencils read the smooth continuation of the body across the
  margin (the fit below), not the kink to ``h = 0``, which would make their slopes one-sided.
- **Sources.** Depth-proportional sources act on the mid-step mass of each staggered cell (see
  :meth:`MarginCellHooks.adjust_source_depths`), a departure from the plain quarter-point
  depths of eqs. (13-14) that keeps a uniformly accelerated body at uniform velocity.
- **Point values.** The mid-step fluxes of the body's cells start from third-order point values
  ``w - D2 w / 24`` (limited), not the cell averages of eq. (12): near a margin, where the depth
  is ``O(dx)``, the averages' ``O(dx^2)`` error is ``O(dx)`` relative and biased the margin slope
  (see :meth:`MarginCellHooks._point_values`).
- **Margin motion.** ``dx_M/dt = u_M`` with ``du_M/dt = s_x - beta dh/dx`` (eq. 19, the
  ``h -> 0`` limit of the momentum equation). ``beta``, the driving force and the Coulomb
  friction come from the model (Jacobian entry ``A[1,0]`` at ``h = 1, u = 0``, source and
  resistance per unit depth), the friction with the stopping rule (docs/design.md, "Savage–Hutter
  specifics"). ``dh/dx`` at
  the margin is the slope of the quadratic ``h = S d - C d^2`` (``d`` the distance from the
  margin) that holds the masses of the margin cell and its two inner neighbours.
- **Crossing a cell face.** After each step, whatever the update left in cells wholly outside
  the new margins (at most ``O(dt^2)``) is moved into the new margin cell, so mass is conserved to
  round-off and ``h = 0`` outside the body exactly.

One body only; a body touching the domain boundary has no margin on that side. A margin reaching
the boundary stops the run with a clear message.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, InadmissibleStateError, SchemeBreakdownError
from conslaw.grid import Grid
from conslaw.initial import InitialCondition
from conslaw.kernelgen import compiled_before
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor
from conslaw.schemes.base import AdvanceResult, BoundarySpec, ProgressCallback
from conslaw.schemes.front_tracking.kernels import ft_kernels
from conslaw.schemes.nessyahu_tadmor.constants import MAX_RETRIES
from conslaw.schemes.nessyahu_tadmor.scheme import (
    DT_FLOOR_RELATIVE,
    GHOSTS,
    NessyahuTadmor,
    SubcellHooks,
    _resist,
)
from conslaw.schemes.unit_depth import unit_depth_forces
from conslaw.state import Margin, Margins, State

Array = NDArray[np.float64]

#: Held while a compiled front-tracking kernel runs with a scheme's call back set (see advance).
_CALLBACK_LOCK = threading.Lock()
#: Cell updates per call of the compiled front-tracking kernel between progress reports.
FT_CELL_UPDATES_PER_CALL = 1_000_000
#: Rows of the margin history the compiled kernel fills before it pauses to hand them over.
HISTORY_ROWS = 8192
#: Cells kept between a margin and the domain boundary (the widest slope stencil).
BOUNDARY_CLEARANCE = GHOSTS
#: Cells from the margin cell outward whose stencil values are the body's continuation.
STENCIL_REACH = 3
#: An initial edge cell holding at least 1/STEP_RATIO of its inner neighbour's depth is a step,
#: not a margin (a linear edge on a cell face holds 1/3, a flat body cut off at a face 1/1).
STEP_RATIO = 2.0


class _RetryStepError(Exception):
    """A step made a depth negative or the second step of a pair would break the CFL
    condition: the step pair is redone with half the time step."""


def front_cell(left_edges: Array, position: float) -> int:
    """Index of the cell ``[e, e + dx)`` with ``e < position <= e + dx`` (a front margin)."""
    return int(np.searchsorted(left_edges, position, side="left")) - 1


def rear_cell(left_edges: Array, position: float) -> int:
    """Index of the cell with ``e <= position < e + dx`` (a rear margin)."""
    return int(np.searchsorted(left_edges, position, side="right")) - 1


def margin_fit(masses: Array, inner_length: float, dx: float) -> tuple[float, float]:
    """``(S, C)`` of the depth ``h = S d - C d^2`` near a margin, ``d`` the distance from it.

    ``masses`` are the masses ``h dx`` of the margin cell and its inner neighbours, outward
    first; ``inner_length`` is the part of the margin cell inside the body. With three cells the
    quadratic holding the masses of the first two and of all three cells is solved; with fewer,
    the line ``h = S d`` (``C = 0``). ``S = -dh/dx`` at a front margin (``+dh/dx`` at a rear
    one); a negative ``S`` (depth growing towards the margin) is taken as the line through the
    mass instead.
    """
    lengths = inner_length + dx * np.arange(masses.size)
    cumulative = np.cumsum(masses)
    linear = 2.0 * cumulative[-1] / lengths[-1] ** 2
    if masses.size < 3:
        return float(linear), 0.0
    l1, l2 = lengths[1], lengths[2]
    m1, m2 = cumulative[1], cumulative[2]
    a11, a12, a21, a22 = 0.5 * l1 * l1, -(l1**3) / 3.0, 0.5 * l2 * l2, -(l2**3) / 3.0
    determinant = a11 * a22 - a12 * a21
    slope = (m1 * a22 - a12 * m2) / determinant
    curvature = (a11 * m2 - a21 * m1) / determinant
    if slope < 0.0:
        return float(linear), 0.0
    return float(slope), float(curvature)


@dataclass(frozen=True)
class MarginProfile:
    """What the step needs to know about one margin at the start of a step."""

    sign: float  # +1 front margin, -1 rear margin
    margin: Margin
    slope: float  # S = |dh/dx| at the margin
    curvature: float  # C of h = S d - C d^2
    inner_velocity: float  # mean velocity of the inner neighbour cell
    velocity_gradient: float  # du/dd from the two inner neighbours (d: distance inside)


class MarginCellHooks(SubcellHooks):
    """The margin-cell reconstruction of front tracking inside the numpy NT update."""

    def __init__(
        self, profiles: list[MarginProfile], moved: Margins, dx: float, dry_depth: float
    ) -> None:
        self.profiles = profiles
        self.dx = dx
        # The margins at mid-step: means of the margins before and after the step.
        ends = {-1.0: moved.rear, 1.0: moved.front}
        self.middle = []
        for p in profiles:
            end = ends[p.sign]
            assert end is not None
            self.middle.append(
                Margin(
                    0.5 * (p.margin.position + end.position),
                    0.5 * (p.margin.velocity + end.velocity),
                )
            )
        self.dry_depth = dry_depth
        self._cells: list[tuple[int, float, float]] = []

    def stencil_values(self, w: Array, x_padded: Array) -> Array:
        """Slope stencils of the inner cells read the smooth continuation of the body across
        the margin (cell averages of ``h = S d - C d^2``, negative beyond the margin, and of
        ``h u`` with ``u`` extrapolated linearly), not the kink to ``h = 0``; otherwise the cells
        next to the margin get one-sided, diffusive slopes."""
        data = w.copy()
        left_edges = x_padded - 0.5 * self.dx
        for p in self.profiles:
            position = p.margin.position
            if p.sign > 0:
                k = front_cell(left_edges, position)
                cells = np.arange(k, min(k + STENCIL_REACH, w.shape[1]))
            else:
                k = rear_cell(left_edges, position)
                cells = np.arange(max(k - STENCIL_REACH + 1, 0), k + 1)
            # Distances inside the body of the cell ends (d decreases outward).
            d_inner = p.sign * (position - (left_edges[cells] + (p.sign < 0) * self.dx))
            d_outer = d_inner - self.dx
            integral = 0.5 * p.slope * (d_inner**2 - d_outer**2) - p.curvature / 3.0 * (
                d_inner**3 - d_outer**3
            )
            depth = integral / self.dx
            d_centre = d_inner - 0.5 * self.dx
            velocity = p.margin.velocity + p.velocity_gradient * d_centre
            data[0, cells] = depth
            data[1, cells] = depth * velocity
        self._stencil = data
        self._x_padded = x_padded
        return data

    def adjust_slopes(self, values: Array, slopes: Array, x_cells: Array) -> None:
        """Effective slopes whose half-cell integrals are those of the triangle (Fig. 2)."""
        dx = self.dx
        left_edges = x_cells - 0.5 * dx
        self._cells = []
        for p in self.profiles:
            position, sign = p.margin.position, p.sign
            k = front_cell(left_edges, position) if sign > 0 else rear_cell(left_edges, position)
            depth, momentum = values[0, k], values[1, k]
            # Length of the cell inside the body and the triangle's slope magnitude.
            inside = position - left_edges[k] if sign > 0 else left_edges[k] + dx - position
            inside = min(max(inside, 1e-9 * dx), dx)
            triangle = 2.0 * depth * dx / (inside * inside)
            # Mass in the outer half cell (towards the margin).
            reach = sign * (position - x_cells[k])
            outer = 0.5 * triangle * reach * reach if reach > 0.0 else 0.0
            outer_average = min(2.0 * outer / dx, 2.0 * depth)
            # Right half average = depth + slope/4 (eq. 11); the outer half is the right one at
            # a front margin, the left one at a rear margin.
            slopes[0, k] = 4.0 * sign * (outer_average - depth)
            # Velocity u(d) = ubar + G (d - 2L/3) inside the triangle (d: distance from the
            # margin, G from the inner cells): linear like the depth, and its mass-weighted mean
            # is the cell's ubar, so the momentum average is unchanged.
            u = momentum / depth if depth >= self.dry_depth and depth > 0.0 else 0.0
            if reach > 0.0 and outer_average < 2.0 * depth:
                gradient = p.velocity_gradient
                outer_momentum = triangle * (
                    0.5 * u * reach**2 + gradient * (reach**3 / 3.0 - inside * reach**2 / 3.0)
                )
                outer_momentum_average = 2.0 * outer_momentum / dx
            else:
                outer_momentum_average = u * outer_average
            slopes[1, k] = 4.0 * sign * (outer_momentum_average - momentum)
            self._cells.append((k, triangle, x_cells[k]))

    def adjust_predicted(self, values: Array, predicted: Array, x_cells: Array, dt: float) -> None:
        """Mid-step value at the centre: the triangle carried with the margin, with the velocity
        of the margin extrapolated inward by the inner cells' velocity gradient."""
        for (k, triangle, centre), p, middle in zip(
            self._cells, self.profiles, self.middle, strict=True
        ):
            reach = p.sign * (middle.position - centre)
            depth = triangle * reach if reach > 0.0 else 0.0
            velocity = middle.velocity + p.velocity_gradient * max(reach, 0.0)
            predicted[0, k] = depth
            predicted[1, k] = velocity * depth
        self._point_values(values, predicted, x_cells)

    def _point_values(self, values: Array, predicted: Array, x_cells: Array) -> None:
        """Point values at the centres of the body's cells, ``w - D2 w / 24``, in place of the
        cell averages the mid-step values of eq. (12) start from.

        ``D2 w`` is the second difference of the stencil values (the body continued across the
        margins), limited as the minmod of those of the cell and its two neighbours: exact for
        a quadratic, zero at a discontinuity or a change of curvature. Why: the cell average
        differs from the centre value by ``w'' dx^2 / 24``; where the depth vanishes linearly
        at a margin that is an ``O(dx)`` relative error on depths of ``O(dx)``, which left the
        three cells next to the margin 20/10/3 % too shallow and made the fitted margin slope
        (eq. 19) lag by an ``O(dx)`` error (``python scripts/front_tracking_check.py``).
        """
        data, x_padded = self._stencil, self._x_padded
        second = data[:, :-2] - 2.0 * data[:, 1:-1] + data[:, 2:]
        limited = np.zeros_like(second)
        middle = second[:, 1:-1]
        same_sign = (np.sign(second[:, :-2]) == np.sign(middle)) & (
            np.sign(second[:, 2:]) == np.sign(middle)
        )
        magnitude = np.minimum(
            np.minimum(np.abs(second[:, :-2]), np.abs(middle)), np.abs(second[:, 2:])
        )
        limited[:, 1:-1] = np.where(same_sign, np.sign(middle) * magnitude, 0.0)
        # limited[:, i - 1] belongs to padded cell i; the update's cells are padded
        # first .. first + n, found by position.
        start = int(np.searchsorted(x_padded, x_cells[0] - 0.25 * self.dx))
        correction = limited[:, start - 1 : start - 1 + x_cells.size]
        body = values[0] > 0.0
        for k, _, _ in self._cells:
            body[k] = False
        predicted[:, body] -= correction[:, body] / 24.0

    def adjust_source_depths(
        self,
        values: Array,
        slopes: Array,
        transported: Array,
        quarter_left: Array,
        quarter_right: Array,
    ) -> None:
        """Sources act on the mid-step mass of every staggered cell: the two quarter-point
        depths of a cell are scaled (velocities kept) so that their mean is the mean of the
        cell's depth before and after transport. For sources proportional to the depth (gravity,
        Coulomb friction) a body under uniform acceleration then keeps a uniform velocity; with
        the plain quarter-point depths of eqs. (13-14) the thin margins gained or lost velocity
        (front margin lag at t = 6: 0.36 dx -> 0.03 dx at 90 cells;
        ``python scripts/front_tracking_check.py``)."""
        start = 0.5 * (values[0, :-1] + values[0, 1:]) + 0.125 * (slopes[0, :-1] - slopes[0, 1:])
        target = 0.5 * (start + transported[0])
        current = 0.5 * (quarter_right[0, :-1] + quarter_left[0, 1:])
        factor = np.where(current > 0.0, target / np.where(current > 0.0, current, 1.0), 0.0)
        quarter_right[:, :-1] *= factor
        quarter_left[:, 1:] *= factor

    def adjust_quarters(
        self, values: Array, slopes: Array, quarter_left: Array, quarter_right: Array
    ) -> None:
        """Sources of a margin cell at mid-step: on its half cells, with the triangle moved to
        the margin's mid-step position (the material that crosses the cell centre during the
        step feels the driving force and friction of the staggered cell it moves into)."""
        for (k, triangle, centre), p, middle in zip(
            self._cells, self.profiles, self.middle, strict=True
        ):
            depth, momentum = values[0, k], values[1, k]
            u = momentum / depth if depth >= self.dry_depth and depth > 0.0 else 0.0
            reach = p.sign * (middle.position - centre)
            outer = 0.5 * triangle * reach * reach if reach > 0.0 else 0.0
            outer = min(outer, depth * self.dx)
            outer_average = 2.0 * outer / self.dx
            inner_average = 2.0 * depth - outer_average
            outer_side, inner_side = (
                (quarter_right, quarter_left) if p.sign > 0 else (quarter_left, quarter_right)
            )
            outer_side[0, k], outer_side[1, k] = outer_average, u * outer_average
            inner_side[0, k], inner_side[1, k] = inner_average, u * inner_average


class FrontTrackingNT(NessyahuTadmor):
    """Nessyahu–Tadmor with front tracking of the avalanche margins (NOC-FT).

    Chosen with ``scheme = "front-tracking"`` in a scene (``front_tracking = true`` with the
    nessyahu-tadmor scheme, the form of earlier scene files, means the same). Needs a model with
    a depth and a momentum variable (``q = (h, hu)``) and no staggered-cell (well-balanced) bed
    source; the states carry their :class:`~conslaw.state.Margins`. Steps go in pairs with one
    ``dt``, redone with half the
    time step if a depth would become negative. :meth:`advance` runs compiled
    (:mod:`~conslaw.schemes.front_tracking.kernel_template`, generated with the model's point
    functions);
    :meth:`reference_advance` and :meth:`step` are the numpy reference (the NT update with the
    margin-cell hooks of :class:`MarginCellHooks`), which the compiled path equals to round-off.
    """

    name = "front-tracking"
    description = (
        "Nessyahu–Tadmor with front tracking of the margins (NOC-FT), paper Fig. 2 and eq. (19)"
    )
    needs_single_body = True

    def __init__(
        self,
        model: Model,
        reconstructor: Reconstructor,
        grid: Grid,
        left: BoundarySpec,
        right: BoundarySpec,
        cfl: float = 0.45,
    ) -> None:
        if model.depth_index != 0 or model.momentum_index != 1 or model.n_vars != 2:
            raise ConfigError(
                f"front_tracking needs a model with a depth variable, q = (h, hu); "
                f"'{model.name}' has variables {', '.join(model.variables)}"
            )
        if left.condition.periodic:
            raise ConfigError("front_tracking: not available on a periodic domain")
        super().__init__(model, reconstructor, grid, left, right, cfl)
        if self.uses["balanced_source"]:
            raise ConfigError(
                f"front_tracking: not available for '{model.name}' with a bed source "
                "(well-balanced staggered-cell source); use a flat bed"
            )
        self._ft_kernels: Any = None
        n_pad = self.n_staggered + 2 * GHOSTS
        self._stencil = np.zeros((model.n_vars, n_pad))
        self._ft_margins = np.full((3, 4), np.nan)
        self._profiles_buffer = np.zeros((2, 16))
        self._margin_of = np.zeros(2, dtype=np.int64)
        self._history = np.zeros((HISTORY_ROWS, 5))
        self._padded = {offset: self._padded_positions(offset) for offset in (0.0, 0.5)}
        self._centres = {offset: self.grid.centres(offset, self.periodic) for offset in (0.0, 0.5)}

    def kernel_identity(self) -> str | None:
        """The generated front-tracking kernel module's name."""
        return str(self.ft_kernels.__name__)

    def needs_compile(self) -> bool:
        """Whether the front-tracking kernel's first call compiles (it is not in the cache)."""
        return not compiled_before(self.ft_kernels, "ft_advance")

    def _compiled_module(self) -> Any:
        """The generated module that :meth:`advance` runs."""
        return self.ft_kernels

    @property
    def ft_kernels(self) -> Any:
        """The generated compiled front-tracking kernels (built on first use)."""
        if self._ft_kernels is None:
            self._ft_kernels = ft_kernels(
                self.model,
                self.reconstructor,
                self.left.condition.fill_left,
                self.right.condition.fill_right,
            )
            columns = self.n_staggered + 2 * GHOSTS + 8
            self._ft_work = np.zeros((self._ft_kernels.ft_work_rows(columns), columns))
            # The call back to Python is compiled (object mode, about 50 ms) at its first call,
            # not loaded from the cache: done here, with the kernels, not inside a timed solve.
            self._ft_kernels.margin_aux_source = self._margin_aux
            self._ft_kernels.margin_aux(
                self.grid.x_min, np.zeros(max(self.model.n_aux, 1)), False, np.zeros(1)
            )
        return self._ft_kernels

    def _margin_aux(self, position: float) -> Array:
        """The model's coefficients at one margin position, ``Model.aux`` with the cell width
        (both paths ask here; the compiled kernel calls back once per margin and step)."""
        values = self.model.aux(np.array([position]), self.grid.dx)
        return np.ascontiguousarray(values[:, 0], dtype=np.float64)

    # ------------------------------------------------------------------ margins
    def initial_state(self, state: State, initial: InitialCondition | None = None) -> State:
        """``state`` with its margins (:meth:`initial_margins`)."""
        return state if state.margins is not None else self.initial_margins(state)

    def initial_margins(self, state: State) -> State:
        """``state`` with margins found from its depth: one body of wet cells, each margin in
        the outermost wet cell where a line from the margin, meeting the mean of that cell and
        its neighbour at the inner face, holds the cell's mass (at the outer face if the mass
        does not fit, as for a body whose edges are cell faces)."""
        depth = state.q[0]
        wet = np.flatnonzero(depth > 0.0)
        if wet.size == 0:
            raise ConfigError("front_tracking: the initial depth is zero everywhere")
        gaps = np.flatnonzero(np.diff(wet) > 1)
        if gaps.size:
            raise ConfigError(
                f"front_tracking follows one body; the initial depth has {gaps.size + 1} "
                "separate bodies"
            )
        n = state.n_cells
        if wet[0] == 0 and wet[-1] == n - 1:
            raise ConfigError(
                "front_tracking: the material fills the whole domain, so there is no margin to "
                "track (a thin layer? set thin_layer = 0)"
            )
        if wet.size < 3:
            raise ConfigError("front_tracking: the body must span at least 3 cells")
        dx = self.grid.dx
        left_edges = state.x - 0.5 * dx
        margins: dict[str, Margin | None] = {"rear": None, "front": None}
        for side, outer, inner, sign in (
            ("rear", wet[0], wet[1], -1.0),
            ("front", wet[-1], wet[-2], 1.0),
        ):
            if (sign < 0 and outer == 0) or (sign > 0 and outer == n - 1):
                continue
            if not BOUNDARY_CLEARANCE <= outer < n - BOUNDARY_CLEARANCE:
                raise ConfigError(
                    f"front_tracking: the {side} margin starts within {BOUNDARY_CLEARANCE} cells "
                    "of the boundary; enlarge the domain"
                )
            if STEP_RATIO * depth[outer] >= depth[inner]:
                raise ConfigError(
                    f"front_tracking: the {side} margin starts as a step (edge cell at "
                    f"x={state.x[outer]:.6g} with h={depth[outer]:.6g}, at least 1/{STEP_RATIO:g} "
                    f"of its neighbour's h={depth[inner]:.6g}); eq. (19) cannot start from a step "
                    "(the margin's acceleration is unbounded there and a dam-break front "
                    "overshoots for good): let the depth fall to zero over the edge cells, or "
                    "run without front tracking"
                )
            face_depth = 0.5 * (depth[outer] + depth[inner])
            inside = min(dx, 2.0 * depth[outer] * dx / face_depth)
            position = left_edges[outer] + (inside if sign > 0 else dx - inside)
            # Keep the margin in its cell under round-off (a body edge on a cell face).
            if sign > 0:
                position = min(position, left_edges[outer + 1])
            else:
                position = max(position, left_edges[outer])
            h, m = depth[outer], state.q[1, outer]
            velocity = m / h if h >= self.model.dry_depth() else 0.0
            margins[side] = Margin(float(position), float(velocity))
        return replace(state, margins=Margins(margins["rear"], margins["front"]))

    def _profiles(self, state: State) -> list[MarginProfile]:
        """The depth fit and velocities near every margin of ``state``."""
        assert state.margins is not None
        dx = self.grid.dx
        left_edges = state.x - 0.5 * dx
        depth, momentum = state.q[0], state.q[1]
        dry = self.model.dry_depth()
        profiles = []
        for margin, sign in ((state.margins.rear, -1.0), (state.margins.front, 1.0)):
            if margin is None:
                continue
            if sign > 0:
                k = front_cell(left_edges, margin.position)
                inside = margin.position - left_edges[k]
                cells = np.arange(k, max(k - 3, -1), -1)
            else:
                k = rear_cell(left_edges, margin.position)
                inside = left_edges[k] + dx - margin.position
                cells = np.arange(k, min(k + 3, state.n_cells))
            slope, curvature = margin_fit(depth[cells] * dx, inside, dx)
            wet = depth[cells[1:]] >= max(dry, np.finfo(float).tiny)
            u = np.where(wet, momentum[cells[1:]] / np.where(wet, depth[cells[1:]], 1.0), 0.0)
            inner_velocity = float(u[0]) if wet[0] else margin.velocity
            gradient = float(u[1] - u[0]) / dx if wet.size == 2 and wet.all() else 0.0
            profiles.append(MarginProfile(sign, margin, slope, curvature, inner_velocity, gradient))
        return profiles

    def _margin_acceleration(self, p: MarginProfile) -> tuple[float, float]:
        """Driving acceleration ``s - beta dh/dx`` (eq. 19) and friction per unit depth."""
        # The earth-pressure state follows the velocity difference across the margin cell.
        spread = p.sign * (p.margin.velocity - p.inner_velocity)
        forces = unit_depth_forces(
            self.model,
            np.array([p.margin.position]),
            np.array([p.margin.velocity]),
            np.array([spread]),
            self.grid.dx,
            aux=self._margin_aux(p.margin.position)[:, None],
        )
        depth_gradient = -p.sign * p.slope
        return float(forces.drive[0] - forces.beta[0] * depth_gradient), float(forces.friction[0])

    def _move_margins(self, profiles: list[MarginProfile], dt: float) -> Margins:
        """Integrate eq. (19) over one step for every margin (friction never reverses it)."""
        moved: dict[float, Margin] = {}
        for p in profiles:
            acceleration, friction = self._margin_acceleration(p)
            driven = np.array([p.margin.velocity + dt * acceleration])
            velocity = float(_resist(driven, np.array([dt * friction]))[0])
            position = p.margin.position + 0.5 * dt * (p.margin.velocity + velocity)
            moved[p.sign] = Margin(position, velocity)
        return Margins(moved.get(-1.0), moved.get(1.0))

    def _confine(self, q: Array, x: Array, margins: Margins) -> Array:
        """Move what lies in cells wholly outside the margins into the margin cells."""
        left_edges = x - 0.5 * self.grid.dx
        if margins.front is not None:
            k = front_cell(left_edges, margins.front.position)
            q[:, k] += q[:, k + 1 :].sum(axis=1)
            q[:, k + 1 :] = 0.0
        if margins.rear is not None:
            k = rear_cell(left_edges, margins.rear.position)
            q[:, k] += q[:, :k].sum(axis=1)
            q[:, :k] = 0.0
        return q

    def _check_margins(self, margins: Margins, t: float, steps: int) -> None:
        low = self.grid.x_min + BOUNDARY_CLEARANCE * self.grid.dx
        high = self.grid.x_max - BOUNDARY_CLEARANCE * self.grid.dx
        for side, margin, name in (
            ("rear", margins.rear, "left"),
            ("front", margins.front, "right"),
        ):
            if margin is not None and not low <= margin.position <= high:
                raise SchemeBreakdownError(
                    f"the {side} margin reached the {name} boundary (x={margin.position:.6g}) at "
                    f"t={t:.6g}, step {steps}: front tracking needs the body inside the domain; "
                    f"enlarge the domain (x_min/x_max)"
                )
        if (
            margins.rear is not None
            and margins.front is not None
            and margins.front.position - margins.rear.position < 2.0 * self.grid.dx
        ):
            raise SchemeBreakdownError(
                f"the body became shorter than 2 cells at t={t:.6g}, step {steps}"
            )

    # ------------------------------------------------------------------ Scheme interface
    def stable_dt(self, state: State, cfl: float | None = None) -> float:
        """The NT limit (eqs. 17-18), also bounding the margin velocities."""
        dt = super().stable_dt(state, cfl)
        if state.margins is None:
            return dt
        speeds = [abs(m.velocity) for m in (state.margins.rear, state.margins.front) if m]
        largest = max(speeds, default=0.0)
        if largest == 0.0:
            return dt
        limit = (self.cfl if cfl is None else cfl) * self.grid.dx / largest
        return min(dt, limit)

    def _hooks_at(self, state: State) -> SubcellHooks:
        """The margin-cell reconstruction of ``state`` (margins held where they are)."""
        if state.margins is None:
            return SubcellHooks()
        return MarginCellHooks(
            self._profiles(state), state.margins, self.grid.dx, self.model.dry_depth()
        )

    def _raw_step(self, state: State, dt: float, steps: int) -> State:
        _, staggered = self._family(state)
        profiles = self._profiles(state)
        try:
            moved = self._move_margins(profiles, dt)
        except ValueError as error:  # a Margin refuses a non-finite position or velocity
            raise InadmissibleStateError(
                f"a margin is not finite (overflow) at t={state.t + dt:.6g}, step {steps + 1}: "
                f"{error}; check the magnitudes of the parameters"
            ) from None
        hooks = MarginCellHooks(profiles, moved, self.grid.dx, self.model.dry_depth())
        new = self._numpy_update(state.q, staggered, dt, hooks)
        offset = 0.0 if staggered else 0.5
        x = self.grid.centres(offset, self.periodic)
        self._check_margins(moved, state.t + dt, steps + 1)
        new = self._confine(new, x, moved)
        if self.uses["correction"]:
            new = self.model.correct(new, self._aux[offset][0][:, GHOSTS : GHOSTS + x.size], dt)
        if np.any(new[0] < 0.0):
            raise _RetryStepError
        return State(state.t + dt, x, new, offset, moved)

    def step(self, state: State, dt: float) -> State:
        """One NOC-FT step to the other cell family (margins found first if the state has
        none)."""
        if state.margins is None:
            state = self.initial_margins(state)
        self._family(state)
        self._check_step(state, dt)
        try:
            return self._raw_step(state, dt, 0)
        except _RetryStepError:
            raise SchemeBreakdownError(
                f"dt={dt:g} makes a depth negative; take a smaller step"
            ) from None

    def advance(
        self, state: State, t_end: float, progress: ProgressCallback | None = None
    ) -> AdvanceResult:
        """Advance to exactly ``t_end`` in step pairs with the compiled kernel; the result holds
        the margin history (rows ``t, x_rear, u_rear, x_front, u_front`` after every step).

        The same steps, margins and failures as :meth:`reference_advance`, to round-off.

        Raises
        ------
        SchemeBreakdownError
            A margin reached the boundary, the body became shorter than 2 cells, or the time
            step fell below ``1e-14 dx``; with the time and step.
        InadmissibleStateError
            A state outside the model's admissible set, or a margin that is not finite.
        """
        state = self._start(state, t_end)
        assert state.margins is not None
        if not self._compiled:
            self.compile(state)
        kernels = self.ft_kernels
        n = self.n_primary
        self._w0[:, GHOSTS : GHOSTS + n] = state.q
        margins = self._ft_margins
        margins[:] = np.nan
        margins[0] = state.margins.row(state.t)[1:]
        history = [np.array([state.margins.row(state.t)])]
        dx = self.grid.dx
        pairs_per_call = max(1, FT_CELL_UPDATES_PER_CALL // (2 * n))
        # Coefficients the same everywhere (a plane chute): asked once, not at every margin.
        uniform = self.model.uniform_aux()
        uniform_values = self._margin_aux(self.grid.x_min) if uniform else np.zeros(1)
        bundles = self.kernels  # the NT kernels, whose argument bundles the FT kernels take
        buffers = bundles.Buffers(self._w0, self._w1, self._w2, self._ft_work)
        primary = self._front_family(kernels, 0.0)
        staggered = self._front_family(kernels, 0.5)
        controls = bundles.Controls(
            float(t_end), self.cfl, dx, DT_FLOOR_RELATIVE * dx, pairs_per_call
        )
        boundary = bundles.Boundary(self.bc_left, self.bc_right)
        tracking = kernels.Tracking(
            margins,
            self._profiles_buffer,
            self._margin_of,
            self._history,
            self._stencil,
            self.grid.x_min + BOUNDARY_CLEARANCE * dx,
            self.grid.x_max - BOUNDARY_CLEARANCE * dx,
            uniform,
            uniform_values,
        )
        t, steps = state.t, 0
        while True:
            # The kernel module is shared by every scheme with the same model class (and
            # plugin reconstructor or boundaries), and its call back (the coefficients at a
            # margin on a curved chute) is a module attribute: set for this scheme before every
            # call (a progress callback may have run another scheme's advance), under a lock.
            with _CALLBACK_LOCK:
                kernels.margin_aux_source = self._margin_aux
                t, pairs, rows, status, where, step, dt = kernels.ft_advance(
                    buffers, primary, staggered, t, controls, self.params, boundary, tracking
                )
            history.append(self._history[:rows].copy())
            if status not in (kernels.FT_DONE, kernels.FT_PAUSED):
                self._raise_compiled_failure(status, where, t, steps + step, dt)
            steps += 2 * pairs
            if progress is not None:
                progress(t, steps)
            if status == kernels.FT_DONE:
                break
        final = State(
            t,
            self._centres[0.0].copy(),
            self._w0[:, GHOSTS : GHOSTS + n].copy(),
            0.0,
            _margins_of_row(margins[0]),
        )
        return AdvanceResult(final, steps, np.concatenate(history))

    def _front_family(self, kernels: Any, offset: float) -> Any:
        """The FT kernels' ``FrontFamily`` bundle of the primary (``offset`` 0) or staggered
        (1/2) cells: their number, the coefficients at their centres and quarter points, and
        the centres of the real and of the padded cells."""
        count = self.n_primary if offset == 0.0 else self.n_staggered
        return kernels.FrontFamily(
            count, *self._aux[offset], self._centres[offset], self._padded[offset]
        )

    def _raise_compiled_failure(
        self, status: int, where: int, t: float, step: int, dt: float
    ) -> None:
        """Raise the error of the reference path for a failure of the compiled kernel."""
        kernels = self.ft_kernels
        if status == kernels.FT_DT_FLOOR:
            raise SchemeBreakdownError(
                f"time step {dt:.3g} fell below the floor {DT_FLOOR_RELATIVE:g}*dx at "
                f"t={t:.6g}, step {step}"
            )
        if status == kernels.FT_MARGIN_OUTSIDE:
            self._check_margins(_margins_of_row(self._ft_margins[where]), t, step)
        if status == kernels.FT_MARGIN_NOT_FINITE:
            for side in (0, 1):
                position, velocity = self._ft_margins[where, 2 * side : 2 * side + 2]
                if np.isnan(self._ft_margins[where - 1, 2 * side]):
                    continue
                try:
                    Margin(float(position), float(velocity))
                except ValueError as error:
                    raise InadmissibleStateError(
                        f"a margin is not finite (overflow) at t={t:.6g}, step {step}: "
                        f"{error}; check the magnitudes of the parameters"
                    ) from None
        if status in (kernels.FT_INADMISSIBLE, kernels.FT_SPEED_NOT_FINITE):
            offset = 0.5 if where == 1 else 0.0
            n = self.n_staggered if where == 1 else self.n_primary
            buffer = (self._w0, self._w1, self._w2)[where]
            failed = State(t, self._centres[offset], buffer[:, GHOSTS : GHOSTS + n].copy(), offset)
            self.check_admissible(failed, step)
            raise InadmissibleStateError(
                f"the wave speed is not finite (overflow) at t={t:.6g}, step {step}; check the "
                "magnitudes of the parameters"
            )
        raise SchemeBreakdownError(
            f"front tracking failed (status {status}) at t={t:.6g}, step {step}"
        )

    def _start(self, state: State, t_end: float) -> State:
        """The state an advance to ``t_end`` starts from: on the primary grid, not after
        ``t_end``, with its margins (located now if it has none)."""
        _, staggered = self._family(state)
        if staggered:
            raise ValueError("advance() starts from the primary grid (offset 0)")
        if not t_end >= state.t:
            raise ConfigError(f"t_end={t_end} is before the state's time {state.t}")
        return state if state.margins is not None else self.initial_margins(state)

    def reference_advance(
        self, state: State, t_end: float, progress: ProgressCallback | None = None
    ) -> AdvanceResult:
        """:meth:`advance` in numpy (the NT update with :class:`MarginCellHooks`, a Python loop
        over the steps): the reference the compiled path is tested against."""
        state = self._start(state, t_end)
        assert state.margins is not None
        history: list[Any] = [state.margins.row(state.t)]
        steps = 0
        dt_floor = DT_FLOOR_RELATIVE * self.grid.dx
        while state.t < t_end:
            dt = self.stable_dt(state)
            last = 2.0 * dt >= t_end - state.t
            if last:
                dt = 0.5 * (t_end - state.t)
            accepted = False
            for _ in range(MAX_RETRIES):
                if dt < dt_floor and not last:
                    break
                try:
                    middle = self._raw_step(state, dt, steps)
                    self.check_admissible(middle, steps + 1)
                    if dt > self.stable_dt(middle, cfl=0.4999999999999999):
                        raise _RetryStepError
                    end = self._raw_step(middle, dt, steps + 1)
                    accepted = True
                    break
                except _RetryStepError:
                    dt *= 0.5
                    last = False
            if not accepted:
                # The last pair of a run may be shorter than the floor: it only closes the
                # round-off gap to t_end (as in the compiled kernel).
                raise SchemeBreakdownError(
                    f"time step {dt:.3g} fell below the floor {DT_FLOOR_RELATIVE:g}*dx at "
                    f"t={state.t:.6g}, step {steps}"
                )
            if last:
                end = replace(end, t=t_end)
            self.check_admissible(end, steps + 2)
            if self.uses["resistance"] and all(
                _held(s, self.model.momentum_index) for s in (state, middle, end)
            ):
                # Friction held everything: the kernel's held_at_rest keeps the state.
                end = replace(state, t=end.t)
            assert middle.margins is not None and end.margins is not None
            history.append(middle.margins.row(middle.t))
            history.append(end.margins.row(end.t))
            steps += 2
            state = end
            if progress is not None:
                progress(state.t, steps)
        return AdvanceResult(state, steps, np.array(history, dtype=np.float64))


def _held(state: State, momentum: int | None) -> bool:
    """No momentum in any cell and no moving margin (the kernel's ``held_at_rest``)."""
    assert momentum is not None and state.margins is not None
    margins = [m for m in (state.margins.rear, state.margins.front) if m is not None]
    return not np.any(state.q[momentum]) and all(m.velocity == 0.0 for m in margins)


def _margins_of_row(row: Array) -> Margins:
    """Margins from ``(x_rear, u_rear, x_front, u_front)``, NaN for a missing margin."""
    rear = None if np.isnan(row[0]) else Margin(float(row[0]), float(row[1]))
    front = None if np.isnan(row[2]) else Margin(float(row[2]), float(row[3]))
    return Margins(rear, front)
