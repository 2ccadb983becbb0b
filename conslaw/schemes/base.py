"""The Scheme interface: ``stable_dt(state, cfl)`` and ``step(state, dt) -> state``."""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from conslaw.boundary import BoundaryCondition
from conslaw.errors import (
    ConfigError,
    InadmissibleStateError,
    SchemeBreakdownError,
    unknown_name_message,
)
from conslaw.grid import Grid
from conslaw.initial import InitialCondition
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor
from conslaw.state import State


@dataclass(frozen=True)
class BoundarySpec:
    """A boundary condition and its scene options for one side of the domain."""

    condition: BoundaryCondition
    options: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class AdvanceResult:
    """What :meth:`Scheme.advance` returns: the new state, how many time steps it took and,
    with front tracking, the margins after every step (rows ``t, x_rear, u_rear, x_front,
    u_front``)."""

    state: State
    steps: int
    margins: NDArray[np.float64] | None = None


ProgressCallback = Callable[[float, int], None]

#: Smallest accepted time step relative to dx (below it a run stops instead of hanging).
DT_FLOOR_RELATIVE = 1e-14


@dataclass(frozen=True)
class SchemeOption:
    """An option a scheme declares for the scene table ``[scheme_options]``.

    ``check(value, label)`` returns the validated value or raises a ConfigError naming ``label``.
    """

    default: Any
    description: str
    check: Callable[[Any, str], Any]
    #: Named in run labels even at its default (otherwise only when set to another value).
    always_shown: bool = False


class Scheme(ABC):
    """A time-stepping scheme for ``q_t + f(q)_x = s(q)`` on a :class:`~conslaw.grid.Grid`.

    The model, reconstructor and boundary conditions are injected; a scheme never branches on
    their names. A scheme refuses an incompatible model at construction with a ConfigError.
    """

    name: ClassVar[str]
    description: ClassVar[str]
    #: Options of the scene table ``[scheme_options]``, passed to the constructor as keywords.
    options: ClassVar[Mapping[str, SchemeOption]] = {}
    #: Whether the injected reconstructor shapes the solution (False: reports show "-", and the
    #: registry-wide property tests run the scheme with one reconstructor only).
    uses_reconstructor: ClassVar[bool] = True
    #: Whether the scheme needs the material in one body with dry cells around it (it tracks
    #: the body's margins); the property tests then draw such initial data.
    needs_single_body: ClassVar[bool] = False

    @classmethod
    def resolve_options(cls, given: Mapping[str, Any]) -> dict[str, Any]:
        """``given`` checked against :attr:`options`, with the defaults filled in.

        Unknown keys are a ConfigError naming the allowed ones (with a "did you mean").
        """
        for key in given:
            if key not in cls.options:
                raise ConfigError(
                    f"scheme_options.{key}: scheme '{cls.name}' "
                    + (
                        unknown_name_message("option", key, cls.options).replace(
                            "unknown option", "has no option"
                        )
                        if cls.options
                        else "takes no options"
                    )
                )
        return {
            key: option.check(given[key], f"scheme_options.{key}")
            if key in given
            else option.default
            for key, option in cls.options.items()
        }

    def __init__(
        self,
        model: Model,
        reconstructor: Reconstructor,
        grid: Grid,
        left: BoundarySpec,
        right: BoundarySpec,
        cfl: float,
    ) -> None:
        if model.n_dims != 1:
            raise ConfigError(
                f"model '{model.name}' is {model.n_dims}-dimensional: the 1D scheme "
                f"'{type(self).name}' cannot run it"
            )
        if left.condition.periodic != right.condition.periodic:
            raise ConfigError(
                "boundary: 'periodic' must be used on both sides (left and right), got "
                f"left='{left.condition.name}', right='{right.condition.name}'"
            )
        self.model = model
        self.reconstructor = reconstructor
        self.grid = grid
        self.left = left
        self.right = right
        self.periodic = left.condition.periodic
        self.cfl = cfl

    def initial_state(self, state: State, initial: InitialCondition | None = None) -> State:
        """The state a run starts from, given the initial cell averages on the grid and the
        initial condition they were computed from (a scheme with its own mesh may sample it
        there). The default is ``state`` itself."""
        return state

    @abstractmethod
    def stable_dt(self, state: State, cfl: float | None = None) -> float:
        """Largest time step allowed by the scheme's CFL condition at this state."""

    @abstractmethod
    def step(self, state: State, dt: float) -> State:
        """One time step of length ``dt``."""

    def kernel_identity(self) -> str | None:
        """A name shared by every scheme that runs the same compiled kernels (the generated
        module's), or None for a scheme without compiled code: ``conslaw warm`` compiles each
        once."""
        return None

    def needs_compile(self) -> bool:
        """Whether :meth:`compile` will compile code (not load it from a cache): a run announces
        the wait. The default (a scheme without compiled code) is False."""
        return False

    def compile(self, state: State) -> None:
        """Compile (or load from the cache) everything :meth:`advance` runs, for states like
        ``state``, without changing it, so that no compile falls inside a timed solve. The
        default advances ``state`` to its own time (no step)."""
        self.advance(state, state.t)

    def advance(
        self, state: State, t_end: float, progress: ProgressCallback | None = None
    ) -> AdvanceResult:
        """Advance to ``t_end`` (generic loop for plugin schemes; schemes may provide a faster
        one). The last step is shortened to reach ``t_end`` and the returned time is ``t_end``
        itself. A staggered scheme must override this to end on its primary grid.

        The run is monitored as the built-in schemes' runs are: a time step below
        ``DT_FLOOR_RELATIVE * dx`` (other than the last, which only closes the gap to ``t_end``)
        raises SchemeBreakdownError, and a NaN, inf or inadmissible state after any step raises
        InadmissibleStateError naming time, step, cell and values.
        """
        steps = 0
        floor = DT_FLOOR_RELATIVE * self.grid.dx
        while state.t < t_end:
            dt = min(self.stable_dt(state), t_end - state.t)
            last = dt >= t_end - state.t
            if not dt > 0.0 or (dt < floor and not last):
                raise SchemeBreakdownError(
                    f"time step {dt:.3g} fell below the floor {DT_FLOOR_RELATIVE:g}*dx at "
                    f"t={state.t:.6g}, step {steps}"
                )
            state = self.step(state, dt)
            if last:
                state = State(t_end, state.x, state.q, state.offset, state.margins)
            steps += 1
            self.check_admissible(state, steps)
            if progress is not None:
                progress(state.t, steps)
        return AdvanceResult(state, steps)

    def cell_coefficients(self, state: State) -> NDArray[np.float64]:
        """The model's coefficients in the cells of ``state`` as a step from it would use them,
        shape ``(n_aux, n_cells)`` (for output files). Default: the static ones of
        :meth:`Model.aux <conslaw.model.Model.aux>`."""
        return self.model.aux(state.x, self.grid.dx)

    def check_admissible(self, state: State, step: int) -> None:
        """Raise InadmissibleStateError naming time, step, cell and values if ``state`` is bad."""
        ok = self.model.is_admissible(state.q, self.model.aux(state.x, self.grid.dx))
        if not ok.all():
            cell = int((~ok).nonzero()[0][0])
            values = ", ".join(
                f"{name}={float(state.q[v, cell])!r}" for v, name in enumerate(self.model.variables)
            )
            raise InadmissibleStateError(
                f"inadmissible state at t={state.t:.6g}, step {step}, cell {cell} "
                f"(x={state.x[cell]:.6g}): {values} (need {self.model.admissible_rule})"
            )
