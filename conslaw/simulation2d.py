"""The runner of 2D scenes: builds the grid, model and scheme, advances to every output time and
collects the states, with their errors against the exact solution where one applies."""

from __future__ import annotations

import signal
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw import registry
from conslaw.analysis import ErrorNorms
from conslaw.errors import ConfigError, RunInterrupted, SchemeBreakdownError, StepLimitError
from conslaw.exact import Unavailable
from conslaw.exact2d import ExactSolution2D
from conslaw.grid2d import Grid2D
from conslaw.memory import available_bytes, run_bytes
from conslaw.model import Model
from conslaw.peak_fields import PeakFields
from conslaw.progress import RunProgress
from conslaw.result2d import RunResult2D, State2D
from conslaw.scene2d import Scene2D
from conslaw.simulation import cannot_finish, check_run_arguments, step_limit_message
from conslaw.stopping import RestWatch, stop_rule

Array = NDArray[np.float64]

#: Called with ``(t, steps)`` as the run advances.
Progress2D = Callable[[float, int], None]


def error_norms_2d(numerical: Array, exact: Array) -> ErrorNorms:
    """``L1 = mean |q - qbar|``, ``L2 = sqrt(mean (q - qbar)^2)``, ``Linf = max |q - qbar|`` over
    the cells of a uniform grid (the 1D norms of docs/equations.md, "Error norms", per unit
    area)."""
    difference = np.asarray(numerical, dtype=np.float64) - exact
    return ErrorNorms(
        l1=float(np.mean(np.abs(difference))),
        l2=float(np.sqrt(np.mean(difference * difference))),
        linf=float(np.max(np.abs(difference))),
    )


def build_2d(scene: Scene2D) -> tuple[Model, Grid2D, Any, Array]:
    """The model, grid, scheme and initial cell averages of a 2D scene."""
    grid = Grid2D.from_bounds(
        scene.x_min, scene.x_max, scene.nx, scene.y_min, scene.y_max, scene.ny
    )
    model = scene.model_instance().on_grid_2d(grid)
    needed = run_bytes(scene.n_cells, model.n_vars, model.n_aux, len(scene.output_times) + 4)
    room = available_bytes()
    if room is not None and needed > room:
        raise ConfigError(
            f"n_cells = [{scene.nx}, {scene.ny}] with {len(scene.output_times)} output times "
            f"needs about {needed / 2**30:.1f} GiB, and this process may use about "
            f"{max(room, 0) / 2**30:.1f} GiB more; use fewer cells or output times"
        )
    scheme_class = registry.schemes_2d.get(scene.scheme)
    scheme = scheme_class(
        model,
        registry.reconstructors.get(scene.reconstructor),
        grid,
        scene.boundaries,
        scene.cfl,
        inflow=scene.inflow,
        **scene.scheme_options,
    )
    q0 = scheme.initial_values(scene.initial)
    if q0 is None:
        q0 = scene.initial.cell_averages(grid, model)
    q0 = np.ascontiguousarray(q0, dtype=np.float64)
    if not np.all(np.isfinite(q0)):
        raise ConfigError("initial: the initial data are not finite (NaN or inf)")
    admissible = model.is_admissible(q0.reshape(model.n_vars, -1))
    if not admissible.all():
        cell = int(np.flatnonzero(~admissible)[0])
        row, column = divmod(cell, scene.nx)
        raise ConfigError(
            f"initial: cell (x index {column}, y index {row}) is not admissible for "
            f"'{model.name}' ({model.admissible_rule})"
        )
    return model, grid, scheme, q0


def exact_solution_2d(
    scene: Scene2D, model: Model, grid: Grid2D
) -> tuple[ExactSolution2D | None, str | None]:
    """The exact solution the scene is compared with, or None and the reason why there is none
    (checked up to ``t_end`` before the run)."""
    if not scene.exact:
        return None, "exact = false in the scene"
    context = {**scene.boundaries, "t_end": scene.t_end}
    try:
        exact = model.exact_solution_2d(scene.initial, grid, context)
    except (Unavailable, ConfigError) as why:
        return None, str(why)
    if exact is None:
        return None, (
            f"model '{model.name}' has no exact solution for initial condition "
            f"'{scene.initial.kind}'"
        )
    return exact, None


def simulate_2d(
    scene: Scene2D,
    progress: Progress2D | None = None,
    on_output: Callable[[RunResult2D], None] | None = None,
    notice: Callable[[str], None] | None = None,
) -> RunResult2D:
    """Run a validated 2D scene to every output time, or, with ``stop.at_rest``, to the first
    at which the material is at rest (:mod:`conslaw.stopping`; ``result.stop`` says how the run
    ended).

    ``progress(t, steps)`` after every step pair, ``on_output(result)`` at every output time
    (the result so far), ``notice(message)`` before a first compile. A Ctrl-C becomes
    :class:`~conslaw.errors.RunInterrupted`; more than ``max_steps`` steps a
    :class:`~conslaw.errors.StepLimitError`; a breakdown keeps the states reached before it.
    """
    model, grid, scheme, q = build_2d(scene)
    exact, note = exact_solution_2d(scene, model, grid)
    result = RunResult2D(scene, model, grid, State2D(0.0, q), exact_solution=exact, exact_note=note)
    result.peaks = PeakFields.start(model, grid, q)
    watch = None
    if scene.stop.at_rest:
        rule = stop_rule(scene.stop.to_table(), model)  # a Scene2D changed in Python
        if result.peaks is None:
            raise ConfigError(f"stop.at_rest: model '{model.name}' gives no flow depth and speed")
        watch = RestWatch(rule, model, result.peaks.aux, grid.cell_area, q, scene.t_end)
    observe = _observer(model, result.peaks, progress, watch)
    reached = [0.0, 0]
    checked = [0.0, 0]  # time and steps at the previous report
    last_output: float | None = None

    def report(t: float, steps: int) -> None:
        total = result.steps + steps
        reached[:] = [t, total]
        if watch is not None:
            watch.timed(t)
        if total > scene.max_steps and t < scene.t_end:
            raise StepLimitError(step_limit_message(scene, 0.0, t, total))
        # As the 1D runner: a run whose rate needs far more than max_steps stops now.
        if cannot_finish(scene, (checked[0], int(checked[1])), t, total) and t < scene.t_end:
            raise StepLimitError(step_limit_message(scene, 0.0, t, total, early=True))
        checked[:] = [t, total]
        if progress is not None:
            progress(t, total)

    try:
        if notice is not None and scheme.needs_compile():
            notice(
                f"compiling the {scene.scheme} kernels for {scene.model} (the first run of this "
                "kind only; cached for later runs)"
            )
        started = time.perf_counter()
        scheme.compile()
        result.compile_seconds = time.perf_counter() - started
        t = 0.0
        for t_out in scene.output_times:
            if t_out > t:
                started = time.perf_counter()
                try:
                    q, t, steps = scheme.advance(q, t, t_out, report, observe)
                except SchemeBreakdownError as error:
                    error.completed_states = list(result.states)
                    raise
                result.solve_seconds += time.perf_counter() - started
                result.steps += steps
            _record(result, State2D(t, q))
            result.scheme_notes = list(getattr(scheme, "notes", list)())
            if watch is not None:
                result.stop = watch.at_output(t, q)
            if on_output is not None:
                on_output(result)
            last_output = t
            if result.stop is not None and result.stop.stopped:
                break
    except KeyboardInterrupt as interrupt:
        number = getattr(interrupt, "signal_number", signal.SIGINT)
        raise RunInterrupted(reached[0], int(reached[1]), last_output, number) from None
    return result


def _observer(
    model: Model,
    peaks: PeakFields | None,
    progress: Progress2D | None,
    watch: RestWatch | None = None,
) -> Callable[[Array], object] | None:
    """What the scheme calls with the values after every step pair (None: nothing): the peak
    fields' update, the kinetic energy of ``watch`` (from the speed the peak fields computed),
    and for a :class:`~conslaw.progress.RunProgress` writing lines about a model
    with a momentum, a reference to the values from which its line counts the moving cells
    (cells with a nonzero momentum; counted only when a line is written, from the values of
    the pair just reported)."""
    update = _pair_update(peaks, watch)
    rows = [v for v in (model.momentum_index, model.momentum_y_index) if v is not None]
    if not (isinstance(progress, RunProgress) and progress.writes_lines and rows):
        return update
    latest: list[Array | None] = [None]

    def moving() -> int | None:
        values = latest[0]
        return None if values is None else int(np.count_nonzero(np.any(values[rows], axis=0)))

    progress.moving = moving

    def observe(values: Array) -> None:
        latest[0] = values
        if update is not None:
            update(values)

    return observe


def _pair_update(
    peaks: PeakFields | None, watch: RestWatch | None
) -> Callable[[Array], object] | None:
    """The peak fields' update after a step pair, with the kinetic energy of ``watch`` from
    the speed it computes (None without peak fields)."""
    if peaks is None:
        return None
    if watch is None:
        return peaks.update

    def update(values: Array) -> None:
        watch.pair(values, peaks.update(values)[1])

    return update


def _record(result: RunResult2D, state: State2D) -> None:
    """Append an output state with its exact cell averages and errors."""
    result.states.append(state)
    exact = None
    if result.exact_solution is not None:
        grid = result.grid
        exact = np.asarray(result.exact_solution.cell_averages(grid.x.edges, grid.y.edges, state.t))
    result.exact.append(exact)
    result.errors.append(None if exact is None else error_norms_2d(state.q[0], exact[0]))


def run_2d(
    scene: str | Path | Scene2D,
    out: str | Path | None = None,
    progress: Progress2D | None = None,
    **overrides: Any,
) -> RunResult2D:
    """Run a 2D scene from Python (as :func:`conslaw.run` for 1D scenes).

    Parameters
    ----------
    scene : str, Path or Scene2D
        A built-in 2D scene name (``conslaw list``), a path to a ``.toml`` file, or a Scene2D.
    out : path, optional
        Folder for the files the scene asks for (``output.formats``: npz, xdmf), the resolved
        scene and the figures; nothing is written without it.
    **overrides
        Scene keys to override, e.g. ``n_cells=[200, 200]``; nested keys as
        ``**{"boundary.left": "wall"}``.

    Examples
    --------
    >>> result = conslaw.run_2d("sw2d-thacker", n_cells=[50, 50])   # doctest: +SKIP
    >>> result.errors[-1].l1                                       # doctest: +SKIP
    """
    from conslaw.scene2d import load_scene_2d

    check_run_arguments(out, progress)
    if isinstance(scene, Scene2D):
        if overrides:
            raise ConfigError("overrides need a scene name or file, not a Scene2D object")
        resolved = scene
    else:
        flat = {key.replace("__", "."): value for key, value in overrides.items()}
        resolved = load_scene_2d(scene, flat)
    if out is None:
        return simulate_2d(resolved, progress)
    from conslaw.output.files import check_output_dir
    from conslaw.output.writer2d import RunWriter2D
    from conslaw.plotting2d import write_figures_2d
    from conslaw.terrain.hazard_maps import hazard_output_files

    check_output_dir(Path(out))
    writer = RunWriter2D(Path(out), resolved, write_figures_2d, hazard_output_files)
    try:
        writer.claim()
        result = simulate_2d(resolved, progress, writer)
        writer.finish(result)
    finally:
        writer.release()
    return result
