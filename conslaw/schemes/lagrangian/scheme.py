"""The Lagrangian moving-grid scheme of Savage & Hutter (1989, 1991) (docs/design.md, "The
Lagrangian moving grid").

The body of material is cut into ``n`` elements between ``n + 1`` nodes that move with it:

    dx_k/dt = u_k,      h_i = V_i / (x_{i+1} - x_i)       (element volumes V_i fixed)
    du_k/dt = s_x - beta (h_i - h_{i-1}) / (xbar_i - xbar_{i-1}) + mu d2u/dx2

with ``xbar_i`` the element centres, ``h = 0`` at a free margin and one-sided differences there
(``dh/dx = 2 h_0 / (x_1 - x_0)`` at the rear margin, ``-2 h_{n-1} / (x_n - x_{n-1})`` at the
front), and the artificial viscosity ``mu`` (Savage & Hutter used 0.01-0.03; 0 shows the
instability at shocks, Tai et al. 2001, Fig. 3), applied at the interior nodes. Mass is
conserved exactly: it is carried by the fixed volumes. ``beta``, the driving force and the
Coulomb friction are the model's own, per unit depth (:mod:`conslaw.schemes.unit_depth`); the
friction is applied with the stopping rule (docs/design.md, "Savage–Hutter specifics"), so it can
hold a node at rest but
never reverse it.

**Time integration**: velocity Verlet (Störmer–Verlet, "kick-drift-kick"; Hairer, Lubich &
Wanner, Acta Numerica 12, 2003, "Geometric numerical integration illustrated by the
Störmer–Verlet method"), the explicit, second-order, symplectic integrator of classical
Lagrangian hydrodynamics (the leapfrog of von Neumann & Richtmyer, J. Appl. Phys. 21, 1950).
It adds no numerical dissipation, so what the scheme does at a shock without viscosity is the
scheme's own, not the integrator's. Each half kick applies the friction with the stopping rule;
terms that depend on the velocity (friction on a curved bed, the earth-pressure switch, the
viscosity) use the velocity at the start of their half kick (first order in time for those
terms; the driving force and the pressure gradient are second order).

**Time step**: ``dt = cfl / max_i [(c_i + max(u_i - u_{i+1}, 0)) / L_i + 2 mu / L_i^2]``, with
``L_i`` the element length and ``c_i = sqrt(beta h_i)`` the model's wave speed relative to the
material (its ``max_wave_speed`` at ``u = 0``): in one step no wave crosses an element, no
element closes, and the explicit viscous term stays within ``mu dt / L^2 <= 1/2``, the
forward-Euler limit of the heat equation (LeVeque, *Finite Difference Methods for Ordinary and
Partial Differential Equations*, 2007, ch. 9). Störmer–Verlet is stable for ``omega dt < 2``
(Hairer et al. 2003); the fastest element mode has ``omega = 2 c / L``, so ``cfl < 1/2`` keeps a
margin of two.

**Breakdown**: the run stops with :class:`~conslaw.errors.SchemeBreakdownError` naming the time,
the step and the element when an element's length becomes <= 0 (a node overtakes its
neighbour), when an element becomes :data:`GROWTH_LIMIT` times deeper than the deepest element
at the start (oscillations growing without bound), when a velocity is not finite, when a free
margin leaves the domain, or when the time step falls below ``1e-14`` of the mean element length.
The error carries the last good state (``error.state``).

**Output** on the scene's uniform grid: the elements are projected conservatively
(:mod:`conslaw.schemes.projection`); the states also carry the nodes
(:class:`~conslaw.state.LagrangianNodes`) and, for free end nodes, the margins.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, NoReturn

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, SchemeBreakdownError, finite_number, unknown_name_message
from conslaw.grid import Grid
from conslaw.initial import InitialCondition
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor
from conslaw.schemes.base import (
    AdvanceResult,
    BoundarySpec,
    ProgressCallback,
    Scheme,
    SchemeOption,
)
from conslaw.schemes.nessyahu_tadmor.scheme import DT_FLOOR_RELATIVE, _resist, validate_cfl
from conslaw.schemes.projection import project_onto_grid
from conslaw.schemes.unit_depth import unit_depth_forces
from conslaw.state import LagrangianNodes, Margin, Margins, State

Array = NDArray[np.float64]

#: How an end node behaves: a free margin (h = 0 beyond it), fixed at a wall, or open (the depth
#: continues unchanged beyond it, as at a zero-gradient outflow boundary).
FREE, WALL, OPEN = "free", "wall", "open"
#: Halvings of the search interval when locating an initial margin inside its cell (factor 4 each).
MARGIN_SEARCH_STEPS = 40
#: An element deeper than this many times the deepest element at the start stops the run: the
#: oscillations of a shock without artificial viscosity grow without bound (measured on
#: sh-runout-shock, mu = 0: 1000 elements reach 1e4 times with time steps of 1e-9, whereas the
#: physical deposit is about as deep as the initial cap).
GROWTH_LIMIT = 100.0
#: How a breakdown message says that a margin left the domain (no viscosity hint then).
DOMAIN_EXIT = "left the domain"
#: Depths below this fraction of the largest are round-off, not material.
ROUND_OFF = 64.0 * np.finfo(np.float64).eps
#: Steps between progress reports.
PROGRESS_EVERY = 200


def _check_viscosity(value: Any, label: str) -> float:
    mu = finite_number(value, label)
    if mu < 0.0:
        raise ConfigError(f"{label}: the artificial viscosity must be >= 0, got {mu}")
    return mu


def _wet(depth: Array, largest: float | None = None) -> NDArray[np.intp]:
    """Indices of the wet cells: depth above the round-off of the largest depth of the body
    (default: of ``depth``); cell averages of a body that ends on a cell face leave ~1e-30 in
    the next cell."""
    largest = float(np.max(depth, initial=0.0)) if largest is None else largest
    return np.flatnonzero(depth > ROUND_OFF * largest)


PRESSURE_FORMS = ("gradient", "flux")


def _check_pressure(value: Any, label: str) -> str:
    if value not in PRESSURE_FORMS:
        raise ConfigError(
            unknown_name_message(f"{label}: pressure form", str(value), PRESSURE_FORMS)
        )
    return str(value)


def _end_kind(side: BoundarySpec, model: Model, left: bool) -> str | None:
    """What the boundary's ghost cells do to a state next to it: copy it (an open end),
    mirror it (a wall), or anything else (None: not supported for a body touching it)."""
    condition = side.condition
    fill = condition.fill_left if left else condition.fill_right
    data = condition.data(model, side.options)
    signs = np.array(model.reflect_signs, dtype=np.float64)
    kinds = set()
    for inner in (np.array([2.0, 0.5]), np.array([5.0, -0.25])):
        w = np.zeros((model.n_vars, 4))
        w[:, 1] = w[:, 2] = inner
        fill(w, 2, 1, False, data)
        ghost = w[:, 0] if left else w[:, 3]
        if np.array_equal(ghost, inner):
            kinds.add(OPEN)
        elif np.array_equal(ghost, inner * signs):
            kinds.add(WALL)
        else:
            kinds.add("other")
    return kinds.pop() if len(kinds) == 1 and "other" not in kinds else None


@dataclass
class _Mesh:
    """Working copy of the nodes during a step (arrays replaced, never changed in place), with
    the model's static coefficients at the current node positions (computed once per
    position array: the time step and the first kick of a step share them)."""

    x: Array
    u: Array
    volumes: Array
    ends: tuple[str, str]
    _aux: tuple[Array, Array] | None = None

    def aux(self, model: Model, width: float) -> Array:
        if self._aux is None or self._aux[0] is not self.x:
            self._aux = (self.x, model.aux(self.x, width))
        return self._aux[1]

    @classmethod
    def of(cls, nodes: LagrangianNodes) -> _Mesh:
        return cls(nodes.positions, nodes.velocities, nodes.volumes, nodes.ends)

    def frozen(self) -> LagrangianNodes:
        return LagrangianNodes(self.x, self.u, self.volumes, self.ends)


class LagrangianScheme(Scheme):
    """Lagrangian moving grid of Savage & Hutter (1989): see the module docstring.

    Needs a depth-averaged model (``q = (h, hu)``) without a well-balanced bed source; refuses
    any other at construction. The reconstructor is not used. A body touching a boundary needs
    a wall (the end node stays there) or an outflow (open end, no depth gradient) on that side;
    a free margin reaching a boundary stops the run.

    Parameters
    ----------
    model, reconstructor, grid, left, right, cfl
        As for every :class:`~conslaw.schemes.base.Scheme`; ``cfl`` in (0, 1/2) scales the time
        step (module docstring).
    viscosity : float
        The artificial viscosity ``mu >= 0`` (scene: ``[scheme_options] viscosity``).
    pressure : {"gradient", "flux"}
        The pressure term at the interior nodes: ``beta (h_i - h_{i-1}) / (xbar_i - xbar_{i-1})``
        (docs/design.md, "The Lagrangian moving grid"; the default) or the difference of ``beta h^2
        / 2`` over the node's
        lumped mass (conservative in the mass coordinate).
    """

    name = "lagrangian"
    description = (
        "Lagrangian moving grid (Savage & Hutter 1989): nodes move with the material, "
        "artificial viscosity mu"
    )
    uses_reconstructor = False
    needs_single_body = True
    options: ClassVar[Mapping[str, SchemeOption]] = {
        "viscosity": SchemeOption(
            0.0,
            "artificial viscosity mu >= 0 of the term mu d2u/dx2 (Savage & Hutter: 0.01-0.03)",
            _check_viscosity,
            always_shown=True,
        ),
        "pressure": SchemeOption(
            "gradient",
            "gradient: beta dh/dx at the nodes (Savage & Hutter 1989); flux: the "
            "difference of beta h^2/2 over the node mass (conservative)",
            _check_pressure,
        ),
    }

    def __init__(
        self,
        model: Model,
        reconstructor: Reconstructor,
        grid: Grid,
        left: BoundarySpec,
        right: BoundarySpec,
        cfl: float = 0.45,
        viscosity: float = 0.0,
        pressure: str = "gradient",
    ) -> None:
        if model.depth_index is None or model.momentum_index is None or model.n_vars != 2:
            raise ConfigError(
                f"scheme 'lagrangian' needs a depth-averaged model with q = (h, hu); "
                f"'{model.name}' is not one (variables: {', '.join(model.variables)})"
            )
        if left.condition.periodic or right.condition.periodic:
            raise ConfigError("scheme 'lagrangian': not available on a periodic domain")
        super().__init__(model, reconstructor, grid, left, right, validate_cfl(cfl))
        if model.capabilities()["balanced_source"]:
            raise ConfigError(
                f"scheme 'lagrangian': not available for '{model.name}' with a bed source "
                "(well-balanced staggered-cell source); use a flat bed"
            )
        self.viscosity = _check_viscosity(viscosity, "scheme_options.viscosity")
        self.pressure = _check_pressure(pressure, "scheme_options.pressure")
        self._end_kinds = (_end_kind(left, model, True), _end_kind(right, model, False))
        self._grid_aux = model.aux(grid.centres(), grid.dx)
        self._momentum = model.momentum_index
        self._depth = model.depth_index
        self._start_depth: float | None = None
        # Steps of earlier advance() calls of this run, so that a breakdown names the step of
        # the run, not of the output interval.
        self._steps_before = 0

    # ------------------------------------------------------------------ set-up
    def _ends(self, touches: tuple[bool, bool]) -> tuple[str, str]:
        ends = []
        for touching, kind, side in zip(touches, self._end_kinds, ("left", "right"), strict=True):
            if not touching:
                ends.append(FREE)
                continue
            if kind is None:
                condition = (self.left if side == "left" else self.right).condition.name
                raise ConfigError(
                    f"scheme 'lagrangian': the body touches the {side} boundary, where "
                    f"'{condition}' is not supported (use wall or outflow there, or keep the "
                    "material inside the domain)"
                )
            ends.append(kind)
        return ends[0], ends[1]

    def _body_cells(self, depth: Array) -> tuple[int, int]:
        wet = _wet(depth)
        if wet.size == 0:
            raise ConfigError("scheme 'lagrangian': the initial depth is zero everywhere")
        gaps = np.flatnonzero(np.diff(wet) > 1)
        if gaps.size:
            raise ConfigError(
                f"scheme 'lagrangian' follows one body; the initial depth has {gaps.size + 1} "
                "separate bodies"
            )
        return int(wet[0]), int(wet[-1])

    def _locate_margin(
        self, initial: InitialCondition, low: float, high: float, front: bool, largest: float
    ) -> float:
        """The end of the material inside ``[low, high]`` (its outermost wet cell), found by
        repeated exact cell averages of the initial condition on 4 sub-cells (``largest``: the
        body's largest depth, the scale of the round-off)."""
        for _ in range(MARGIN_SEARCH_STEPS):
            if not high - low > 4.0 * np.spacing(max(abs(low), abs(high))):
                break
            depth = initial.cell_averages(Grid(low, high, 4), self.model)[self._depth]
            wet = _wet(depth, largest)
            if wet.size == 0:
                break
            k = int(wet[-1] if front else wet[0])
            width = (high - low) / 4.0
            low, high = low + k * width, low + (k + 1) * width
        return high if front else low

    def initial_state(self, state: State, initial: InitialCondition | None = None) -> State:
        """The nodes of the initial body, and ``state`` projected from them.

        The body spans the wet cells of ``state`` (one body; free margins located inside their
        cells from ``initial``). With ``initial``, the body is cut into ``n_cells`` equal
        elements whose volumes are exact integrals of the initial depth; without it, the
        elements are the wet cells themselves. Interior node velocities are the momentum over
        the depth of the two neighbouring elements; end nodes take their element's velocity.
        """
        if state.nodes is not None:
            return state
        d, m = self._depth, self._momentum
        assert d is not None and m is not None
        dx = self.grid.dx
        first, last = self._body_cells(state.q[d])
        ends = self._ends((first == 0, last == state.n_cells - 1))
        edges = self.grid.edges
        start, stop = float(edges[first]), float(edges[last + 1])
        if initial is None:
            positions = edges[first : last + 2].copy()
            depth, momentum = state.q[d, first : last + 1], state.q[m, first : last + 1]
        else:
            largest = float(np.max(state.q[d]))
            if ends[0] == FREE:
                start = self._locate_margin(initial, start, start + dx, False, largest)
            if ends[1] == FREE:
                stop = self._locate_margin(initial, stop - dx, stop, True, largest)
            elements = Grid(start, stop, self.grid.n_cells)
            averages = initial.cell_averages(elements, self.model)
            positions = elements.edges
            positions[-1] = stop
            depth, momentum = averages[d], averages[m]
            if np.any(depth <= 0.0):
                raise ConfigError(
                    "scheme 'lagrangian' follows one body; the initial depth vanishes inside it"
                )
        volumes = depth * np.diff(positions)
        velocities = np.empty(positions.size)
        velocities[1:-1] = (momentum[:-1] + momentum[1:]) / (depth[:-1] + depth[1:])
        velocities[0], velocities[-1] = momentum[0] / depth[0], momentum[-1] / depth[-1]
        self._hold_walls(velocities, ends)
        self._start_depth = float(depth.max())
        self._steps_before = 0
        return self._state(state.t, LagrangianNodes(positions, velocities, volumes, ends))

    # ------------------------------------------------------------------ pieces
    @staticmethod
    def _hold_walls(u: Array, ends: tuple[str, str]) -> None:
        if ends[0] == WALL:
            u[0] = 0.0
        if ends[1] == WALL:
            u[-1] = 0.0

    def _state(self, t: float, nodes: LagrangianNodes) -> State:
        """The state on the grid: the projection of ``nodes``, their margins and the nodes."""
        ends = nodes.ends
        q = project_onto_grid(
            nodes.positions,
            nodes.velocities,
            nodes.volumes,
            self.grid.edges,
            ends[0] == FREE,
            ends[1] == FREE,
        )
        q = self.model.correct(q, self._grid_aux, 0.0) if self.model.correct_point else q
        x, u = nodes.positions, nodes.velocities
        margins = Margins(
            Margin(float(x[0]), float(u[0])) if ends[0] == FREE else None,
            Margin(float(x[-1]), float(u[-1])) if ends[1] == FREE else None,
        )
        has_margin = margins.rear is not None or margins.front is not None
        return State(t, self.grid.centres(), q, 0.0, margins if has_margin else None, nodes)

    def _nodes(self, state: State) -> LagrangianNodes:
        if state.offset != 0.0 or state.n_cells != self.grid.n_cells:
            raise ValueError(f"state has shape {state.q.shape}; expected the scheme's grid")
        nodes = self.initial_state(state).nodes
        assert nodes is not None
        return nodes

    def _acceleration(self, mesh: _Mesh) -> tuple[Array, Array]:
        """Node accelerations without friction, and the friction magnitudes (per unit depth)."""
        x, u, ends = mesh.x, mesh.u, mesh.ends
        lengths = np.diff(x)
        depth = mesh.volumes / lengths
        gradient = np.empty(x.size)
        gradient[1:-1] = (depth[1:] - depth[:-1]) / (0.5 * (lengths[1:] + lengths[:-1]))
        gradient[0] = 2.0 * depth[0] / lengths[0] if ends[0] == FREE else 0.0
        gradient[-1] = -2.0 * depth[-1] / lengths[-1] if ends[1] == FREE else 0.0
        change = np.empty(x.size)
        change[1:-1] = u[2:] - u[:-2]
        change[0], change[-1] = u[1] - u[0], u[-1] - u[-2]
        aux = mesh.aux(self.model, self.grid.dx)
        forces = unit_depth_forces(self.model, x, u, change, self.grid.dx, aux)
        acceleration = forces.drive - forces.beta * gradient
        if self.pressure == "flux":
            # Interior nodes: minus the difference of the element pressures beta h^2/2 over the
            # node's mass (the lumped half volumes of its two elements); the free end nodes keep
            # the one-sided gradient, the right h -> 0 limit (lumping there halves it).
            beta = 0.5 * (forces.beta[:-1] + forces.beta[1:])
            pressure = 0.5 * beta * depth * depth
            mass = 0.5 * (mesh.volumes[:-1] + mesh.volumes[1:])
            acceleration[1:-1] = forces.drive[1:-1] - np.diff(pressure) / mass
        if self.viscosity > 0.0:
            shear = np.diff(u) / lengths
            acceleration[1:-1] += (
                self.viscosity * (shear[1:] - shear[:-1]) / (0.5 * (lengths[1:] + lengths[:-1]))
            )
        return acceleration, forces.friction

    def _kick(self, mesh: _Mesh, dt: float) -> None:
        """Half a Verlet kick: ``u += dt/2 a``, friction with the stopping rule."""
        acceleration, friction = self._acceleration(mesh)
        mesh.u = _resist(mesh.u + 0.5 * dt * acceleration, 0.5 * dt * friction)
        self._hold_walls(mesh.u, mesh.ends)

    def _element_dt(self, mesh: _Mesh, cfl: float) -> float:
        lengths = np.diff(mesh.x)
        depth = mesh.volumes / lengths
        q = np.zeros((2, depth.size))
        q[self._depth] = depth
        aux = mesh.aux(self.model, self.grid.dx)
        # The wave speed of each element with the coefficients of either of its nodes.
        speed = np.maximum(
            self.model.max_wave_speed(q, aux[:, :-1]), self.model.max_wave_speed(q, aux[:, 1:])
        )
        closing = np.maximum(mesh.u[:-1] - mesh.u[1:], 0.0)
        rate = (speed + closing) / lengths + 2.0 * self.viscosity / lengths**2
        largest = float(rate.max())
        return np.inf if largest == 0.0 else cfl / largest

    def _breakdown(self, message: str, t: float, steps: int, last: State | None) -> NoReturn:
        hint = (
            ""
            if DOMAIN_EXIT in message
            else f" (artificial viscosity is {self.viscosity:g}; a shock needs some, e.g. "
            "--set scheme_options.viscosity=0.02)"
        )
        raise SchemeBreakdownError(
            f"{message} at t={t:.6g}, step {steps}; the Lagrangian scheme cannot continue{hint}",
            state=last,
        )

    def _step(self, mesh: _Mesh, dt: float) -> None:
        """One velocity-Verlet step (replacing the mesh's arrays), with the breakdown checks."""
        self._kick(mesh, dt)
        mesh.x = mesh.x + dt * mesh.u
        lengths = np.diff(mesh.x)
        if not np.all(lengths > 0.0):
            bad = np.flatnonzero(~(lengths > 0.0))
            i = int(bad[0])
            raise _MeshBrokenError(
                f"element {i} collapsed (node {i + 1} overtook node {i}, length "
                f"{lengths[i]:.3g} near x={mesh.x[i]:.6g}; {bad.size} element(s) in all)"
            )
        depth = mesh.volumes / lengths
        i = int(np.argmax(depth))
        if depth[i] > GROWTH_LIMIT * self._reference_depth(mesh):
            raise _MeshBrokenError(
                f"element {i} (x={mesh.x[i]:.6g}) is {depth[i]:.3g} deep, over {GROWTH_LIMIT:g} "
                "times the deepest element at the start: the oscillations grow without bound"
            )
        self._kick(mesh, dt)
        if not np.all(np.isfinite(mesh.u)):
            k = int(np.flatnonzero(~np.isfinite(mesh.u))[0])
            element = min(k, mesh.volumes.size - 1)
            raise _MeshBrokenError(f"node {k} of element {element} has the velocity {mesh.u[k]!r}")
        self._check_inside(mesh)

    def _reference_depth(self, mesh: _Mesh) -> float:
        """The largest element depth when the run started (of the first mesh seen)."""
        if self._start_depth is None:
            self._start_depth = float(np.max(mesh.volumes / np.diff(mesh.x)))
        return self._start_depth

    def _check_inside(self, mesh: _Mesh) -> None:
        last = mesh.x.size - 1
        for position, side, beyond in (
            (
                mesh.x[0],
                "rear margin (node 0)",
                mesh.ends[0] == FREE and mesh.x[0] < self.grid.x_min,
            ),
            (
                mesh.x[-1],
                f"front margin (node {last})",
                mesh.ends[1] == FREE and mesh.x[-1] > self.grid.x_max,
            ),
        ):
            if beyond:
                raise _MeshBrokenError(
                    f"the {side} {DOMAIN_EXIT} (x={position:.6g}); enlarge it (x_min/x_max)"
                )

    # ------------------------------------------------------------------ Scheme interface
    def stable_dt(self, state: State, cfl: float | None = None) -> float:
        """The time step of the module docstring at ``state``."""
        cfl = self.cfl if cfl is None else validate_cfl(cfl)
        return self._element_dt(_Mesh.of(self._nodes(state)), cfl)

    def step(self, state: State, dt: float) -> State:
        """One velocity-Verlet step of length ``dt``."""
        if not (np.isfinite(dt) and dt > 0.0):
            raise ConfigError(f"dt must be a positive number, got {dt!r}")
        mesh = _Mesh.of(self._nodes(state))
        try:
            self._step(mesh, dt)
        except _MeshBrokenError as why:
            self._breakdown(str(why), state.t + dt, 1, state)
        return self._state(state.t + dt, mesh.frozen())

    def advance(
        self, state: State, t_end: float, progress: ProgressCallback | None = None
    ) -> AdvanceResult:
        """Advance to exactly ``t_end``; the result holds the margin history (rows
        ``t, x_rear, u_rear, x_front, u_front`` after every step) when an end node is free.

        Raises
        ------
        SchemeBreakdownError
            Crossing nodes, a non-finite value, a margin leaving the domain or a collapsed time
            step, with the time, step and element; ``error.state`` is the last good state.
        """
        if not t_end >= state.t:
            raise ConfigError(f"t_end={t_end} is before the state's time {state.t}")
        nodes = self._nodes(state)
        mesh = _Mesh.of(nodes)
        track = FREE in mesh.ends
        history = [self._margin_row(state.t, mesh)] if track else []
        dt_floor = DT_FLOOR_RELATIVE * float(np.mean(np.diff(nodes.positions)))
        t, steps = state.t, 0
        while t < t_end:
            dt = self._element_dt(mesh, self.cfl)
            last = dt >= t_end - t
            if last:
                dt = t_end - t
            elif dt < dt_floor:
                self._breakdown(
                    f"the time step {dt:.3g} fell below {DT_FLOOR_RELATIVE:g} of the initial "
                    "element length",
                    t,
                    self._steps_before + steps,
                    self._state(t, mesh.frozen()),
                )
            previous = _Mesh(mesh.x, mesh.u, mesh.volumes, mesh.ends)
            try:
                self._step(mesh, dt)
            except _MeshBrokenError as why:
                self._breakdown(
                    str(why),
                    t + dt,
                    self._steps_before + steps + 1,
                    self._state(t, previous.frozen()),
                )
            t = t_end if last else t + dt
            steps += 1
            if track:
                history.append(self._margin_row(t, mesh))
            if progress is not None and steps % PROGRESS_EVERY == 0:
                progress(t, steps)
        if progress is not None:
            progress(t, steps)
        margins = np.array(history, dtype=np.float64) if track else None
        self._steps_before += steps
        return AdvanceResult(self._state(t, mesh.frozen()), steps, margins)

    def _margin_row(self, t: float, mesh: _Mesh) -> tuple[float, ...]:
        ends = mesh.ends
        nan = np.nan
        rear = (mesh.x[0], mesh.u[0]) if ends[0] == FREE else (nan, nan)
        front = (mesh.x[-1], mesh.u[-1]) if ends[1] == FREE else (nan, nan)
        return (t, float(rear[0]), float(rear[1]), float(front[0]), float(front[1]))


class _MeshBrokenError(Exception):
    """A step broke the mesh; turned into a SchemeBreakdownError with the time and step."""
