"""An ensemble study from start to dataset: draw the members, check every one before anything
runs, run them on an engine, keep each as it finishes, write the labelled dataset
(docs/ensembles.md).

``conslaw ensemble`` and :func:`run_study` are the same study.
"""

from __future__ import annotations

import collections
import contextlib
import json
import math
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from conslaw import signals
from conslaw.config import plain_values
from conslaw.ensemble.dataset import build_dataset, check_format, write_dataset
from conslaw.ensemble.design import Variation, check_seed, draw, parse_variation
from conslaw.ensemble.engine import DaskEngine, LocalEngine, WorkerLostError, engine_for
from conslaw.ensemble.member import MemberOutcome, MemberTask
from conslaw.ensemble.store import StudyFolder, StudySpec
from conslaw.errors import ConfigError, ConslawError, OutputError
from conslaw.progress import CountProgress

if TYPE_CHECKING:
    import xarray

Array = NDArray[np.float64]

#: Scene keys that change the grid: members varying them have no common map.
GRID_KEYS = ("n_cells", "x_min", "x_max", "y_min", "y_max")
#: Times a local pool may be restarted after its workers died without any member finishing.
RESTARTS = 3
#: Wall time one batch of members should keep a worker busy (short members go in batches: one
#: message each way per batch instead of per member), and the largest batch.
BATCH_SECONDS = 0.2
MAX_BATCH = 64
#: Batches in flight per worker (one running, the next waiting in the queue).
IN_FLIGHT_PER_WORKER = 2
#: Deaths of its worker, running alone, after which a member is kept as failed.
DEATHS = 2
#: The dataset is rewritten from the members kept at most this often during a study (seconds);
#: the journal has every member as it arrives.
DATASET_SECONDS = 10.0


class StudyInterrupted(ConslawError):  # noqa: N818 (named like RunInterrupted)
    """A study stopped by a signal; every finished member is kept (``--resume`` finishes it)."""

    def __init__(self, kept: int, total: int, folder: Path, signal_number: int) -> None:
        self.signal_number = signal_number
        super().__init__(
            f"interrupted: {kept} of {total} members kept in '{folder}'; run the same "
            "command with --resume to finish the study"
        )


@dataclass
class StudyResult:
    """What a study produced.

    Attributes
    ----------
    dataset : xarray.Dataset
        The labelled dataset (:func:`conslaw.ensemble.dataset.build_dataset`).
    path : Path
        Where it was written.
    ran : int
        Members run by this call (not those a resumed study had already).
    wall_seconds : float
        This call's time from the first member submitted to the last received.
    workers : int
        Worker processes the engine had.
    files : list of Path
        The products written besides the dataset.
    """

    dataset: xarray.Dataset
    path: Path
    ran: int
    wall_seconds: float
    workers: int
    files: list[Path] = field(default_factory=list)


def _scene_value(variation: Variation, value: float) -> float | int:
    """A member's value as the scene takes it: a whole number listed by ``choice`` stays an
    integer (``max_steps=choice:1000,100000``), every other value is a float."""
    if variation.kind == "choice" and float(value).is_integer():
        return int(value)
    return float(value)


def member_tasks(spec: StudySpec, variations: Sequence[Variation], values: Array) -> list[Any]:
    """Every member's task, each checked as ``conslaw run`` checks its scene before it runs
    (the scene read and validated, its model, grid, scheme and initial state built); the first
    member that cannot run is a ConfigError naming it, its values and the key."""
    from conslaw.scene2d import Scene2D, load_any_scene
    from conslaw.simulation import build
    from conslaw.simulation2d import build_2d

    tasks, dimension = [], 0
    for index, row in enumerate(values):
        varied = {v.key: _scene_value(v, value) for v, value in zip(variations, row, strict=True)}
        overrides = {**spec.settings, **varied}
        try:
            scene = load_any_scene(spec.scene, overrides)
            build_2d(scene) if isinstance(scene, Scene2D) else build(scene)
        except ConfigError as error:
            shown = ", ".join(f"{key}={value:.6g}" for key, value in varied.items())
            raise ConfigError(f"member {index} ({shown}): {error}") from None
        dimension = 2 if isinstance(scene, Scene2D) else 1
        tasks.append(
            (MemberTask(index, spec.scene, overrides, spec.fields, spec.depth_threshold), scene)
        )
    spec.extra["dimension"] = dimension
    if tasks:
        names = tasks[0][1].model_instance().long_names
        spec.extra["axes"] = {axis: names.get(axis, axis) for axis in ("x", "y")}
    return tasks


def _check_fields(spec: StudySpec, variations: Sequence[Variation]) -> None:
    grid = [v.key for v in variations if v.key in GRID_KEYS]
    if spec.fields and grid:
        raise ConfigError(
            f"--fields: the members' maps need one grid, but {', '.join(grid)} varies"
        )


def _warm(scenes: Sequence[Any], report: Callable[[str], None]) -> None:
    """Compile in this process the kernels the members need that are not cached yet, one
    member per kernel family, so that the workers load them from the cache instead of each
    compiling them."""
    from conslaw.scene2d import Scene2D
    from conslaw.simulation import kernel_label
    from conslaw.warm import compile_kernels

    families: dict[str, Any] = {}
    for scene in scenes:
        if isinstance(scene, Scene2D):
            label = scene.model
        else:
            label = kernel_label(scene, scene.model_instance())
        families.setdefault(f"{scene.scheme}/{label}", scene)
    for scene in families.values():
        compile_kernels(
            scene, only_missing=True,
            announce=lambda label: report(f"compiling the {label} (first run of them only)"),
        )  # fmt: skip


class _Batches:
    """The members not yet sent, in batches sized so that one batch keeps a worker busy for
    about :data:`BATCH_SECONDS` (from the members' times so far; one member per batch until the
    first come back). Members that were in flight when a local worker died are *suspects*:
    each is sent alone with nothing else in flight, so that a member that kills its worker is
    found, and failed after :data:`DEATHS` deaths, without taking others with it."""

    def __init__(self, tasks: Sequence[MemberTask]) -> None:
        self.queue: collections.deque[MemberTask] = collections.deque(tasks)
        self.suspects: set[int] = set()
        self.deaths: collections.Counter[int] = collections.Counter()
        self.seconds: list[float] = []

    def size(self) -> int:
        if not self.seconds:
            return 1
        typical = float(np.median(self.seconds[-200:]))
        return int(min(max(BATCH_SECONDS / max(typical, 1e-6), 1), MAX_BATCH))

    def take(self, in_flight: int) -> list[MemberTask] | None:
        """The next batch to send with ``in_flight`` batches out, or None to wait: a suspect
        goes alone when nothing else is out; a batch stops before a suspect."""
        if self.queue[0].index in self.suspects:
            return [self.queue.popleft()] if in_flight == 0 else None
        batch = [self.queue.popleft()]
        while self.queue and len(batch) < self.size() and self.queue[0].index not in self.suspects:
            batch.append(self.queue.popleft())
        return batch

    def put_back(self, batch: Sequence[MemberTask], suspect: bool) -> None:
        """Members to send again (first), as suspects if ``suspect``."""
        if suspect:
            self.suspects.update(task.index for task in batch)
        self.queue.extendleft(reversed(batch))


def _failed(batch: Sequence[MemberTask], message: str) -> list[MemberOutcome]:
    return [MemberOutcome(task.index, "failed", message, {}, "", math.nan, "") for task in batch]


def _execute(
    engine: LocalEngine | DaskEngine,
    tasks: Sequence[MemberTask],
    keep: Callable[[MemberOutcome], None],
) -> None:
    """Run ``tasks`` on ``engine`` in batches, a few per worker in flight at a time, ``keep``
    each outcome once as it arrives. A member whose worker dies is sent again (alone); one that
    kills its worker :data:`DEATHS` times, or whose batch fails otherwise, is kept as failed
    with the reason, and the study goes on."""
    batches = _Batches(tasks)
    flying: dict[Any, list[MemberTask]] = {}
    kept: set[int] = set()
    stalls = 0
    while batches.queue or flying:
        window = IN_FLIGHT_PER_WORKER * max(engine.capacity(), 1)
        while batches.queue and len(flying) < window:
            batch = batches.take(len(flying))
            if batch is None:
                break
            flying[engine.submit_batch(batch)] = batch
        lost: list[MemberTask] = []
        broken = False
        for future in engine.wait_any(flying):
            batch = flying.pop(future)
            try:
                outcomes = engine.outcome(future)
            except WorkerLostError as error:
                broken = isinstance(engine, LocalEngine)
                outcomes = _lost(engine, batches, batch, lost, str(error))
            except Exception as error:  # the batch's own failure (not picklable, ...)
                outcomes = _failed(batch, f"{type(error).__name__}: {error}")
            for outcome in outcomes:
                if math.isfinite(outcome.wall_seconds):
                    batches.seconds.append(outcome.wall_seconds)
                if outcome.index not in kept:  # a member is kept once
                    kept.add(outcome.index)
                    keep(outcome)
                    stalls = 0 if outcome.status == "finished" else stalls
        if broken:
            stalls = _restart(engine, batches, flying, lost, stalls)


def _lost(
    engine: LocalEngine | DaskEngine,
    batches: _Batches,
    batch: list[MemberTask],
    lost: list[MemberTask],
    reason: str,
) -> list[MemberOutcome]:
    """A batch whose worker died: the failed outcome of a suspect that died :data:`DEATHS`
    times alone (or, on Dask, a member the scheduler gave up on), else [] and the batch to send
    again (``lost``: a local pool is restarted; on Dask, each member alone)."""
    alone = len(batch) == 1 and batch[0].index in batches.suspects
    if isinstance(engine, DaskEngine) and len(batch) == 1:
        return _failed(batch, reason)
    if alone:
        batches.deaths[batch[0].index] += 1
        if batches.deaths[batch[0].index] >= DEATHS:
            return _failed(batch, f"its worker process died {DEATHS} times running it "
                                  "(killed, or out of memory)")  # fmt: skip
    if isinstance(engine, DaskEngine):
        batches.put_back(batch, suspect=True)
    else:
        lost.extend(batch)
    return []


def _restart(
    engine: LocalEngine | DaskEngine,
    batches: _Batches,
    flying: dict[Any, list[MemberTask]],
    lost: list[MemberTask],
    stalls: int,
) -> int:
    """After a local worker died: every batch in flight is lost with the pool; send them (and
    ``lost``) again, as suspects, on a new pool (an error after :data:`RESTARTS` deaths in a
    row without a member finishing: workers that cannot run anything)."""
    if stalls >= RESTARTS:
        raise ConfigError(
            f"worker processes died {RESTARTS + 1} times without finishing a member "
            "(out of memory, or a script that starts a study outside `if __name__ == "
            "'__main__':`, docs/ensembles.md); the finished members are kept: "
            "--resume continues"
        )
    for batch in [lost, *flying.values()]:
        batches.put_back(batch, suspect=True)
    flying.clear()
    engine.restart()
    return stalls + 1


def plain_settings(settings: Mapping[str, Any]) -> dict[str, Any]:
    """The keys set for every member (of a study or a calibration) as plain JSON values (numpy
    numbers and arrays as Python ones, :func:`conslaw.config.plain_values`), as ``study.json``
    and ``calibration.json`` keep them; a value JSON cannot hold is a ConfigError naming its
    key."""
    chosen = {}
    for key, value in settings.items():
        try:
            chosen[str(key)] = json.loads(json.dumps(plain_values(value)))
        except (TypeError, ValueError) as error:
            raise ConfigError(f"--set {key}: {value!r} is not a scene value ({error})") from None
    return chosen


def scene_source(scene: str | Path) -> tuple[str, str]:
    """A study's scene as its members load it, resolved as ``conslaw run`` resolves it (a
    built-in name stays a name, a ``.toml`` file becomes its absolute path), and the SHA-256
    of the scene file's bytes; a ConfigError naming the scene otherwise."""
    import hashlib

    from conslaw import registry
    from conslaw.config import scene_path

    name, path = scene_path(scene)
    source = name if str(scene) in registry.scenes else str(Path(path).resolve())
    try:
        digest = hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError as error:
        raise ConfigError(f"cannot read scene file '{path}': {error.strerror}") from None
    return source, digest


def _options(options: Mapping[str, Any] | None) -> tuple[dict[str, Any], str]:
    """The options of :func:`run_study`, checked, and the dataset format."""
    chosen = dict(options or {})
    known = {"fields", "depth_threshold", "format", "scheduler", "workers", "resume"}
    unknown = set(chosen) - known
    if unknown:
        raise ConfigError(f"run_study: unknown options {', '.join(sorted(unknown))}")
    file_format = str(chosen.get("format", "netcdf"))
    check_format(file_format)
    threshold = chosen.get("depth_threshold")
    if threshold is not None and not (math.isfinite(float(threshold)) and threshold >= 0):
        raise ConfigError(f"--depth-threshold: expected a number >= 0, got {threshold}")
    return chosen, file_format


def _variations(vary: Sequence[str | Variation]) -> list[Variation]:
    return [v if isinstance(v, Variation) else parse_variation(v) for v in vary]


def _check_not_set(settings: Mapping[str, Any], variations: Sequence[Variation]) -> None:
    """A ConfigError for a varied key that ``--set`` sets too (the same key, a table holding it,
    or a key inside it): the members would run the varied values while the study recorded the
    ``--set`` one."""
    for variation in variations:
        for key, value in settings.items():
            inside = key.startswith(variation.key + ".")
            holds = variation.key.startswith(key + ".")
            node = value
            for part in variation.key[len(key) + 1 :].split(".") if holds else []:
                node = node.get(part, _ABSENT) if isinstance(node, Mapping) else _ABSENT
            if key == variation.key or inside or (holds and node is not _ABSENT):
                raise ConfigError(
                    f"--vary {variation.key}: --set {key} sets it too; a varied key takes its "
                    "values from --vary only: drop one of them"
                )


_ABSENT = object()


def _study_spec(
    scene: str | Path,
    vary: Sequence[str | Variation],
    drawn: tuple[str, int, int],
    settings: Mapping[str, Any] | None,
    chosen: Mapping[str, Any],
) -> tuple[StudySpec, list[Variation]]:
    """The study's spec and variations, each checked before anything runs: the seed, the
    scene, the keys set and varied (none both), the maps kept."""
    design, samples, seed = drawn
    source, digest = scene_source(scene)
    spec = StudySpec(
        source, plain_settings(settings or {}), [], design, int(samples), check_seed(seed),
        bool(chosen.get("fields", False)), chosen.get("depth_threshold"), digest,
    )  # fmt: skip
    variations = _variations(vary)
    _check_not_set(spec.settings, variations)
    spec.vary.extend(v.text for v in variations)
    _check_fields(spec, variations)
    return spec, variations


def run_study(
    scene: str | Path,
    vary: Sequence[str | Variation],
    samples: int,
    out: str | Path,
    *,
    design: str = "lhs",
    seed: int = 0,
    settings: Mapping[str, Any] | None = None,
    options: Mapping[str, Any] | None = None,
    report: Callable[[str], None] = print,
) -> StudyResult:
    """Run an ensemble of a scene and write its labelled dataset.

    Parameters
    ----------
    scene : str or Path
        A built-in scene name or a scene file.
    vary : sequence of str or Variation
        The varied keys, ``KEY=DISTRIBUTION:ARGS`` (:mod:`conslaw.ensemble.design`).
    samples : int
        Members.
    out : str or Path
        The study's folder (new or empty; or the same study's, with ``resume``).
    design : {"lhs", "sobol", "grid", "random"}
    seed : int
        The same seed draws the same members.
    settings : mapping, optional
        Scene keys set for every member, as ``--set``.
    options : mapping, optional
        ``fields`` (bool: keep each member's maps), ``depth_threshold`` (float),
        ``format`` (``netcdf`` or ``zarr``), ``scheduler`` (a Dask scheduler address, client or
        cluster; default: local processes), ``workers`` (local processes), ``resume`` (bool).
    report : callable
        Gets the progress lines.

    Returns
    -------
    StudyResult

    Raises
    ------
    ConfigError
        A bad variation, design or member (before anything runs), a folder in use.
    StudyInterrupted
        A signal stopped it; every finished member is kept.
    """
    chosen, file_format = _options(options)
    spec, variations = _study_spec(scene, vary, (design, samples, seed), settings, chosen)
    values = draw(variations, design, int(samples), spec.seed)
    engine = engine_for(chosen.get("scheduler"), chosen.get("workers"), int(samples))
    if isinstance(engine, LocalEngine) and engine.note is not None:
        report(engine.note)
    first = member_tasks(spec, variations, values[:1])[0][0]
    # The workers start (and load the first member's kernels) while the members are checked.
    engine.start()
    latch = signals.SignalLatch()
    try:
        with _handled_in_main_thread(latch):  # a stop signal ends the workers too
            engine.boot(first)
            checked = member_tasks(spec, variations, values)
            _warm([scene for _, scene in checked], report)
            folder = StudyFolder(Path(out))
            done = folder.open(spec, bool(chosen.get("resume", False)))
            note = folder.damage_note()
            if note is not None:
                report(note)
            try:
                return _run(spec, (variations, values), checked, done, folder, engine,
                            (file_format, latch), report)  # fmt: skip
            finally:
                folder.close()
    except BaseException:
        engine.abandon()  # a refused or failed study: its workers' current work is not needed
        raise
    finally:
        engine.stop(wait=False)


def _run(
    spec: StudySpec,
    design: tuple[Sequence[Variation], Array],
    checked: Sequence[Any],
    done: dict[int, MemberOutcome],
    folder: StudyFolder,
    engine: LocalEngine | DaskEngine,
    writing: tuple[str, signals.SignalLatch],
    report: Callable[[str], None],
) -> StudyResult:
    variations, values = design
    file_format, latch = writing
    missing = [task for task, _ in checked if task.index not in done]
    if done:
        report(f"resuming: {len(done)} of {len(checked)} members kept, {len(missing)} to run")
    # A line now and then (docs/cli.md, "Progress"), and one when the last member is in.
    progress = CountProgress(report, "study", len(checked), len(done), final=True)

    def keep(outcome: MemberOutcome) -> None:
        with signals.held():
            try:
                folder.record(outcome)
            except OSError as error:
                raise OutputError(
                    f"cannot write to the study folder '{folder.folder}': "
                    f"{error.strerror or error}; the members kept before are in "
                    f"{folder.journal_path.name}: make room and run again with --resume"
                ) from None
            done[outcome.index] = outcome
            refresh()
        progress(outcome.status == "finished")
        latch.check()

    last = [time.monotonic(), 0.0]  # when the dataset was last written, and how long it took

    def refresh() -> None:
        """Rewrite the dataset now and then as members arrive (at most every
        :data:`DATASET_SECONDS`, and never more than 5 % of the time)."""
        now = time.monotonic()
        if now - last[0] < max(DATASET_SECONDS, 20.0 * last[1]):
            return
        with contextlib.suppress(OSError):  # the journal has every member; the end retries
            write_dataset(build_dataset(spec, variations, values, done, folder),
                          folder.folder, file_format)  # fmt: skip
        last[:] = [time.monotonic(), time.monotonic() - now]

    started = time.perf_counter()
    try:
        _execute(engine, missing, keep)
    except KeyboardInterrupt as interrupt:
        number = getattr(interrupt, "signal_number", 2)
        _stop_after_interrupt(engine, report)
        write_dataset(build_dataset(spec, variations, values, done, folder),
                      folder.folder, file_format)  # fmt: skip
        raise StudyInterrupted(len(done), len(checked), folder.folder, number) from None
    except ConslawError:  # workers that keep dying, a full disk: keep what can be kept
        engine.abandon()
        with contextlib.suppress(OSError):
            write_dataset(build_dataset(spec, variations, values, done, folder),
                          folder.folder, file_format)  # fmt: skip
        raise
    wall = time.perf_counter() - started
    dataset = build_dataset(spec, variations, values, done, folder)
    try:
        path = write_dataset(dataset, folder.folder, file_format)
    except OSError as error:
        raise OutputError(
            f"cannot write the study's dataset in '{folder.folder}': {error.strerror or error}; "
            f"every member is in {folder.journal_path.name}: make room and run again with "
            "--resume"
        ) from None
    return StudyResult(dataset, path, progress.ran, wall, engine.workers)


def _handled_in_main_thread(latch: signals.SignalLatch) -> Any:
    """The stop signals raise through ``latch`` (only the main thread can set handlers; a
    study run from another thread is stopped by its caller)."""
    if threading.current_thread() is threading.main_thread():
        return signals.handled(latch)
    return contextlib.nullcontext()


def _stop_after_interrupt(engine: LocalEngine | DaskEngine, report: Callable[[str], None]) -> None:
    """After a signal: members not started are dropped; running ones are ended (their
    results would come after the study's dataset is written)."""
    report("stopping: ending the running members (finished members are kept)")
    engine.abandon()
