"""The runner: builds a scene's objects, advances to every output time, collects results."""

from __future__ import annotations

import dataclasses
import signal
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from conslaw import registry
from conslaw.analysis import error_norms, total_mass
from conslaw.config import Scene, load_scene, validate
from conslaw.errors import (
    ConfigError,
    RunInterrupted,
    SchemeBreakdownError,
    StepLimitError,
    shown,
)
from conslaw.exact import ExactSolution, Unavailable
from conslaw.grid import Grid
from conslaw.memory import available_bytes, run_bytes
from conslaw.model import Model
from conslaw.result import RunResult
from conslaw.schemes.base import BoundarySpec, ProgressCallback, Scheme
from conslaw.state import State

Array = NDArray[np.float64]


def build(scene: Scene) -> tuple[Model, Grid, Scheme, State, ExactSolution | None]:
    """Instantiate the model, grid, scheme, initial state and exact solution of a scene."""
    model, grid, scheme, initial, exact, _ = _build(scene)
    return model, grid, scheme, initial, exact


def _build(
    scene: Scene,
) -> tuple[Model, Grid, Scheme, State, ExactSolution | None, str | None]:
    model = scene.model_instance()
    model.check_domain(scene.x_min, scene.x_max)
    check_memory(scene, model)
    grid = Grid(float(scene.x_min), float(scene.x_max), int(scene.n_cells))
    left = BoundarySpec(registry.boundaries.get(scene.left.kind), scene.left.options)
    right = BoundarySpec(registry.boundaries.get(scene.right.kind), scene.right.options)
    scheme_name = scene.scheme
    if scene.front_tracking and scheme_name == "nessyahu-tadmor":
        scheme_name = "front-tracking"  # a Scene built with the flag (dataclasses.replace)
    if scheme_name == "front-tracking" and not scene.front_tracking:
        raise ConfigError("scene: front_tracking = false contradicts scheme 'front-tracking'")
    scheme_class = registry.schemes.get(scheme_name)
    scheme = scheme_class(
        model,
        registry.reconstructors.get(scene.reconstructor),
        grid,
        left,
        right,
        float(scene.cfl),
        **scene.scheme_options,
    )
    q0 = scene.initial.cell_averages(grid, model)
    if not np.all(np.isfinite(q0)):
        raise ConfigError("initial: the initial data are not finite (NaN or inf)")
    initial = scheme.initial_state(State(0.0, grid.centres(), q0, 0.0), scene.initial)
    exact, note = exact_solution_for(scene, model, grid)
    return model, grid, scheme, initial, exact, note


def check_scene(scene: Scene) -> Scene:
    """The rules of a scene file for a Scene object too (one made or changed in Python, e.g. by
    ``dataclasses.replace``, skips :func:`conslaw.config.validate`): a ConfigError naming the key,
    as for the file. The output times must also be the increasing, distinct times validation
    makes of them (the outputs are labelled by them). Returns the scene with its model, built
    once (:meth:`~conslaw.config.Scene.model_instance`)."""
    model = scene.model_instance()
    validate(scene.name, _plain(scene.to_table()), model_object=model)
    times = [float(t) for t in scene.output_times]
    if times != sorted(set(times)) or not times or times[-1] != scene.t_end:
        raise ConfigError(
            f"scene key 'output_times': {times} must increase, without repeats, and end at "
            f"t_end={scene.t_end}"
        )
    return dataclasses.replace(scene, validated_model=(scene.parameters, model))


def _plain(value: Any) -> Any:
    """``value`` with numpy scalars as Python numbers (in nested tables and lists too)."""
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(item) for item in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def check_memory(scene: Scene, model: Model) -> None:
    """A ConfigError, before anything is allocated, if the run needs more memory than this
    process may still use (:mod:`conslaw.memory`; nothing is checked where that is unknown)."""
    needed = run_bytes(scene.n_cells, model.n_vars, model.n_aux, len(scene.output_times) + 1)
    room = available_bytes()
    if room is not None and needed > room:
        gib = 2.0**30
        raise ConfigError(
            f"n_cells = {scene.n_cells} with {len(scene.output_times)} output times needs about "
            f"{needed / gib:.1f} GiB, and this process may use about {max(room, 0) / gib:.1f} "
            "GiB more; use fewer cells or output times"
        )


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


#: Called after every output time with the result so far (its last state is the new one).
OutputCallback = Callable[["RunResult"], None]


def simulate(
    scene: Scene,
    progress: ProgressCallback | None = None,
    on_output: OutputCallback | None = None,
    notice: Callable[[str], None] | None = None,
) -> RunResult:
    """Run a validated scene to every output time.

    ``on_output(result)`` is called as the run reaches each output time, with the result so far
    (:class:`conslaw.io.RunWriter` writes the files there, so a run that fails or is interrupted
    keeps every earlier output). A Ctrl-C (or a signal turned into a ``KeyboardInterrupt``)
    becomes :class:`~conslaw.errors.RunInterrupted` saying where the run stopped.
    ``notice(message)`` is told of a wait before it starts (a first run compiling its kernels).
    """
    scene = check_scene(scene)
    model, grid, scheme, initial, exact_solution, exact_note = _build(scene)
    scheme.check_admissible(initial, step=0)
    result = RunResult(
        scene, model, grid, scheme, initial, [], exact_solution, [], [], 0, 0.0,
        np.zeros(model.n_vars), 0.0, exact_note,
    )  # fmt: skip
    reached = [initial.t, 0.0]  # time and steps the solution has reached
    checked = [initial.t, 0.0]  # time and steps at the previous progress report
    target = [initial.t]  # the output time the scheme is advancing to
    last_output: float | None = None

    def report(t: float, n: int) -> None:
        steps = result.steps + n
        reached[:] = [t, steps]
        # Not at the output time itself: that state is recorded first (checked after it).
        if steps > scene.max_steps and t < target[0]:
            raise StepLimitError(step_limit_message(scene, initial.t, t, steps))
        if cannot_finish(scene, (checked[0], int(checked[1])), t, steps) and t < target[0]:
            raise StepLimitError(step_limit_message(scene, initial.t, t, steps, early=True))
        checked[:] = [t, steps]
        if progress is not None:
            progress(t, result.steps + n)

    try:
        # Compile the kernels (or load them from the cache) before the clock starts.
        if notice is not None and scheme.needs_compile():
            notice(
                f"compiling the {scene.scheme} kernels for {kernel_label(scene, model)} (the "
                "first run of this kind only, about 15 s; cached for later runs)"
            )
        started = time.perf_counter()
        scheme.compile(initial)
        result.compile_seconds = time.perf_counter() - started
        state = initial
        margin_rows: list[Array] = []
        for t_out in scene.output_times:
            if t_out > state.t:
                target[0] = t_out
                started = time.perf_counter()
                try:
                    advanced = scheme.advance(state, t_out, report)
                except SchemeBreakdownError as error:
                    error.completed_states = list(result.states)
                    raise
                result.solve_seconds += time.perf_counter() - started
                state = advanced.state
                result.steps += advanced.steps
                if advanced.margins is not None:
                    margin_rows.append(advanced.margins[1:] if margin_rows else advanced.margins)
            elif state.margins is not None and not margin_rows:
                margin_rows.append(np.array([state.margins.row(state.t)]))
            _record(result, state, margin_rows)
            if on_output is not None:
                on_output(result)
            last_output = state.t
            if result.steps > scene.max_steps and state.t < scene.t_end:
                stop = StepLimitError(step_limit_message(scene, initial.t, state.t, result.steps))
                stop.completed_states = list(result.states)
                raise stop
    except RunInterrupted:
        raise
    except KeyboardInterrupt as interrupt:
        number = getattr(interrupt, "signal_number", signal.SIGINT)
        raise RunInterrupted(reached[0], int(reached[1]), last_output, number) from None
    return result


#: A run stops early once, after this many steps, its step rate says that it would need more than
#: ``HOPELESS_FACTOR`` times ``max_steps`` to reach ``t_end`` (the rate changes along a run, so
#: only a clear excess counts).
HOPELESS_AFTER_STEPS = 10_000
HOPELESS_FACTOR = 10.0
#: After this many steps the rate is a firm estimate: a run needing more than
#: ``CONFIDENT_FACTOR`` times ``max_steps`` stops then.
CONFIDENT_AFTER_STEPS = 1_000_000
CONFIDENT_FACTOR = 2.0


def kernel_label(scene: Scene, model: Model) -> str:
    """The model and, where its parameters choose among its kernels, which one (``savage-hutter,
    phi > delta``)."""
    variant = model.kernel_variant()
    return f"{scene.model}, {variant}" if variant else scene.model


class StepBudget(Protocol):
    """What the step-limit rules read of a scene (1D or 2D): its end time and step limit."""

    @property
    def t_end(self) -> float: ...

    @property
    def max_steps(self) -> int: ...


def steps_needed(scene: StepBudget, since: tuple[float, int], t: float, steps: int) -> float:
    """The steps a run at ``t`` after ``steps`` steps needs to reach ``t_end``, at its rate since
    ``since`` = (time, steps) of the previous check (an early transient of tiny steps does not
    count against it once the steps grow)."""
    elapsed = t - since[0]
    if not elapsed > 0:
        return np.inf
    return steps + (steps - since[1]) * (scene.t_end - t) / elapsed


def hopeless_factor(steps: int) -> float:
    """How many times ``max_steps`` a run may need before it is stopped, after ``steps`` steps:
    ``HOPELESS_FACTOR``, or ``CONFIDENT_FACTOR`` once the rate is firm."""
    return HOPELESS_FACTOR if steps < CONFIDENT_AFTER_STEPS else CONFIDENT_FACTOR


def cannot_finish(scene: StepBudget, since: tuple[float, int], t: float, steps: int) -> bool:
    """Whether a run at ``t`` after ``steps`` steps would need more than ``HOPELESS_FACTOR *
    max_steps`` steps in all at its recent rate (:func:`steps_needed`; a domain far too small
    for its waves, say), or, once ``CONFIDENT_AFTER_STEPS`` steps make the rate a firm
    estimate, more than ``CONFIDENT_FACTOR * max_steps``: it is stopped then, not when it
    finally reaches ``max_steps``."""
    if steps < HOPELESS_AFTER_STEPS:
        return False
    factor = hopeless_factor(steps)
    return bool(steps_needed(scene, since, t, steps) > factor * scene.max_steps)


def step_limit_message(
    scene: StepBudget, t_start: float, t: float, steps: int, early: bool = False
) -> str:
    """The one line a run stopped by ``max_steps`` reports: where it stopped, its mean time step
    and how many steps the whole run would need at that rate (``early``: stopped before the
    limit, as :func:`cannot_finish`)."""
    elapsed = t - t_start
    mean_dt = elapsed / steps if steps else 0.0
    if elapsed > 0:
        need = steps * (scene.t_end - t_start) / elapsed
        need_text = f"about {need:.0f}" if need < 1e6 else f"about {need:.2g}"
    else:
        need_text = "unboundedly many"
    factor = hopeless_factor(steps)
    why = (
        f"more than {factor:g} times scene key 'max_steps' = {scene.max_steps}"
        if early
        else f"scene key 'max_steps' = {scene.max_steps} reached"
    )
    return (
        f"{why}: the run stopped at t={t:.6g} of "
        f"t_end={scene.t_end:g} after {steps} steps (mean time step {mean_dt:.3g}); at this "
        f"rate it needs {need_text} steps. Raise max_steps, or look for a fast wave in the "
        f"data (with a depth: a thin layer with a large momentum moves at momentum / depth)"
    )


def _record(result: RunResult, state: State, margin_rows: list[Array]) -> None:
    """Append an output state with its exact cell averages and errors; update the totals."""
    grid, initial = result.grid, result.initial
    exact = None
    if result.exact_solution is not None:
        exact = result.exact_solution.cell_averages(grid.edges, state.t)
    result.states.append(state)
    result.coefficients.append(result.scheme.cell_coefficients(state))
    result.exact.append(exact)
    result.errors.append(
        None if exact is None else error_norms(state.q[0], exact[0], grid.dx, grid.length)
    )
    result.margins = np.concatenate(margin_rows) if margin_rows else None
    mass0 = total_mass(initial.q, grid.dx)
    scale = np.maximum(np.abs(mass0), total_mass(np.abs(initial.q), grid.dx))
    result.mass_drift = (total_mass(state.q, grid.dx) - mass0) / np.where(scale > 0, scale, 1.0)


def check_run_arguments(out: object, progress: object) -> None:
    """A ConfigError, before anything runs, for an ``out`` that is not a path or a ``progress``
    that cannot be called (``out=123`` was a TypeError, ``progress="x"`` an error mid-run)."""
    import os

    if out is not None and not isinstance(out, str | os.PathLike):
        raise ConfigError(f"out: expected a folder (a str or Path), got {shown(out)}")
    if progress is not None and not callable(progress):
        raise ConfigError(
            f"progress: expected a callable progress(t, steps), got {shown(progress)}"
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
        Folder for the output files the scene asks for (``output.formats``: npz, xdmf, vtu,
        csv), the resolved scene and the plots; each output time is written as the run reaches
        it. Nothing is written without it.
    **overrides
        Scene keys to override, e.g. ``n_cells=800, reconstructor="weno5"``; nested keys as
        ``**{"boundary.left": "wall"}``. numpy numbers and arrays are taken as the Python
        numbers and lists they hold (:func:`conslaw.config.plain_values`).

    Examples
    --------
    >>> result = conslaw.run("burgers-riemann", n_cells=400)   # doctest: +SKIP
    >>> result.headline_error()                                 # doctest: +SKIP
    """
    check_run_arguments(out, progress)
    if isinstance(scene, Scene):
        if overrides:
            raise ConfigError("overrides need a scene name or file, not a Scene object")
        resolved = scene
    else:
        resolved = load_scene(scene, _flatten(overrides))
    if out is None:
        return simulate(resolved, progress)
    from conslaw.figure_worker import write_figures
    from conslaw.io import RunWriter, check_output_dir

    check_output_dir(Path(out))
    writer = RunWriter(Path(out), resolved, write_figures)
    try:
        writer.claim()
        result = simulate(resolved, progress, writer)
        result.files = writer.finish(result)
    finally:
        writer.release()
    return result


def _flatten(overrides: Mapping[str, Any]) -> dict[str, Any]:
    return {key.replace("__", "."): value for key, value in overrides.items()}
