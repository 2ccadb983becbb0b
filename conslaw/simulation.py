"""The runner: builds a scene's objects, advances to every output time, collects results."""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw import registry
from conslaw.analysis import ErrorNorms, error_norms, total_mass
from conslaw.config import Scene, load_scene
from conslaw.errors import ConfigError, SchemeBreakdownError
from conslaw.exact import ExactSolution, Unavailable
from conslaw.grid import Grid
from conslaw.model import Model
from conslaw.schemes.base import BoundarySpec, ProgressCallback, Scheme
from conslaw.state import State

Array = NDArray[np.float64]


@dataclass
class RunResult:
    """Everything a run produced.

    Attributes
    ----------
    states : list of State
        The solution at every output time (primary grid).
    exact : list of ndarray or None
        Exact cell averages at the same times (None without an exact solution).
    errors : list of ErrorNorms or None
        Reference §6 norms of variable 0 against the exact cell averages.
    steps : int
        Time steps taken.
    solve_seconds : float
        Wall time of the time loop (set-up, compilation and output excluded).
    mass_drift : ndarray
        Relative change of the total of every conserved variable from t=0 to the end.
    margins : ndarray or None
        With front tracking: rows ``t, x_rear, u_rear, x_front, u_front`` after every step.
    """

    scene: Scene
    model: Model
    grid: Grid
    scheme: Scheme
    initial: State
    states: list[State]
    exact_solution: ExactSolution | None
    exact: list[Array | None]
    errors: list[ErrorNorms | None]
    steps: int
    solve_seconds: float
    mass_drift: Array
    compile_seconds: float = 0.0
    exact_note: str | None = None
    margins: Array | None = None
    files: list[Path] = field(default_factory=list)

    @property
    def final(self) -> State:
        """The state at ``t_end``."""
        return self.states[-1]

    def headline_error(self) -> float | None:
        """L1 error of variable 0 at ``t_end`` against the exact cell averages (None if unknown)."""
        error = self.errors[-1]
        return None if error is None else error.l1


def build(scene: Scene) -> tuple[Model, Grid, Scheme, State, ExactSolution | None]:
    """Instantiate the model, grid, scheme, initial state and exact solution of a scene."""
    model, grid, scheme, initial, exact, _ = _build(scene)
    return model, grid, scheme, initial, exact


def _build(
    scene: Scene,
) -> tuple[Model, Grid, Scheme, State, ExactSolution | None, str | None]:
    model_class = registry.models.get(scene.model)
    model = model_class(**scene.parameters)
    grid = Grid(scene.x_min, scene.x_max, scene.n_cells)
    left = BoundarySpec(registry.boundaries.get(scene.left.kind), scene.left.options)
    right = BoundarySpec(registry.boundaries.get(scene.right.kind), scene.right.options)
    scheme_class = registry.schemes.get(scene.scheme)
    if scene.front_tracking:
        from conslaw.schemes.front_tracking import FrontTrackingNT

        scheme_class = FrontTrackingNT
    scheme = scheme_class(
        model,
        registry.reconstructors.get(scene.reconstructor),
        grid,
        left,
        right,
        scene.cfl,
        **scene.scheme_options,
    )
    q0 = scene.initial.cell_averages(grid, model)
    if not np.all(np.isfinite(q0)):
        raise ConfigError("initial: the initial data are not finite (NaN or inf)")
    initial = scheme.initial_state(State(0.0, grid.centres(), q0, 0.0), scene.initial)
    exact, note = exact_solution_for(scene, model, grid)
    return model, grid, scheme, initial, exact, note


def exact_solution_for(
    scene: Scene, model: Model, grid: Grid
) -> tuple[ExactSolution | None, str | None]:
    """The exact solution the scene is compared with, or None and the reason why there is none.

    Checked before the run (up to the last output time), so that a comparison that cannot be
    made never costs a run.
    """
    if not scene.exact:
        return None, "exact = false in the scene"
    context = {"left": scene.left.kind, "right": scene.right.kind, "t_end": scene.t_end}
    try:
        exact = model.exact_solution(scene.initial, grid, context)
        if exact is not None:
            exact.cell_averages(grid.edges, scene.t_end)
    except (Unavailable, ConfigError) as why:
        return None, str(why)
    except (ValueError, ArithmeticError) as why:  # e.g. a root finder meeting an overflow
        return None, f"the exact solution could not be evaluated ({why})"
    if exact is None:
        return None, (
            f"model '{model.name}' has no exact solution for initial condition "
            f"'{scene.initial.kind}'"
        )
    return exact, None


def simulate(scene: Scene, progress: ProgressCallback | None = None) -> RunResult:
    """Run a validated scene to every output time."""
    model, grid, scheme, initial, exact_solution, exact_note = _build(scene)
    scheme.check_admissible(initial, step=0)
    # Compile the kernels (or load them from the cache) before the clock starts.
    started = time.perf_counter()
    scheme.advance(initial, initial.t)
    compile_seconds = time.perf_counter() - started
    states: list[State] = []
    state = initial
    steps = 0
    margin_rows: list[Array] = []
    started = time.perf_counter()

    def report(t: float, n: int) -> None:
        if progress is not None:
            progress(t, steps + n)

    for t_out in scene.output_times:
        if t_out > state.t:
            try:
                advanced = scheme.advance(state, t_out, report)
            except SchemeBreakdownError as error:
                error.completed_states = list(states)
                raise
            state = advanced.state
            steps += advanced.steps
            if advanced.margins is not None:
                margin_rows.append(advanced.margins[1:] if margin_rows else advanced.margins)
        elif state.margins is not None and not margin_rows:
            margin_rows.append(np.array([state.margins.row(state.t)]))
        states.append(state)
    solve_seconds = time.perf_counter() - started
    exact: list[Array | None] = []
    errors: list[ErrorNorms | None] = []
    for s in states:
        if exact_solution is None:
            exact.append(None)
            errors.append(None)
            continue
        averages = exact_solution.cell_averages(grid.edges, s.t)
        exact.append(averages)
        errors.append(error_norms(s.q[0], averages[0], grid.dx, grid.length))
    mass0 = total_mass(initial.q, grid.dx)
    scale = np.maximum(np.abs(mass0), total_mass(np.abs(initial.q), grid.dx))
    drift = (total_mass(states[-1].q, grid.dx) - mass0) / np.where(scale > 0, scale, 1.0)
    return RunResult(
        scene,
        model,
        grid,
        scheme,
        initial,
        states,
        exact_solution,
        exact,
        errors,
        steps,
        solve_seconds,
        drift,
        compile_seconds,
        exact_note,
        np.concatenate(margin_rows) if margin_rows else None,
    )


def run(
    scene: str | Path | Scene,
    out: str | Path | None = None,
    progress: ProgressCallback | None = None,
    **overrides: Any,
) -> RunResult:
    """Run a scene from Python.

    Parameters
    ----------
    scene : str, Path or Scene
        A built-in scene name (``conslaw list``), a path to a ``.toml`` file, or a Scene.
    out : path, optional
        Folder for the npz states, the resolved scene and the plot. Nothing is written without it.
    **overrides
        Scene keys to override, e.g. ``n_cells=800, reconstructor="weno5"``; nested keys as
        ``**{"boundary.left": "wall"}``.

    Examples
    --------
    >>> result = conslaw.run("burgers-riemann", n_cells=400)   # doctest: +SKIP
    >>> result.headline_error()                                 # doctest: +SKIP
    """
    if isinstance(scene, Scene):
        if overrides:
            raise ConfigError("overrides need a scene name or file, not a Scene object")
        resolved = scene
    else:
        resolved = load_scene(scene, _flatten(overrides))
    if out is not None:
        from conslaw.io import check_output_dir

        check_output_dir(Path(out))
    result = simulate(resolved, progress)
    if out is not None:
        from conslaw.io import write_run

        result.files = write_run(result, Path(out))
    return result


def _flatten(overrides: Mapping[str, Any]) -> dict[str, Any]:
    return {key.replace("__", "."): value for key, value in overrides.items()}
