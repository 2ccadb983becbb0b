"""Calibration: the scene keys that make a scene's members match observations, and how well
they are determined (docs/calibration.md).

Every evaluation of the misfit ``sum_i ((m_i - o_i) / sigma_i)^2`` is a member of the scene run
on an ensemble engine (:mod:`conslaw.ensemble.engine`); the stages of the fit are
:mod:`conslaw.ensemble.fitting`, the observations and residuals
:mod:`conslaw.ensemble.observations`. ``conslaw calibrate`` and :func:`calibrate` are the same
calibration: it writes ``calibration.json`` (every member's values and figures) and
``calibration.png`` (the misfit against each key).
"""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any

from conslaw.config import MAX_NESTING, plain_values
from conslaw.ensemble.design import MAX_SAMPLES, check_seed
from conslaw.ensemble.engine import LocalEngine, engine_for
from conslaw.ensemble.fitting import (
    COARSE_PER_KEY,
    MAX_EVALUATIONS,
    STAGES,
    STEP,
    XTOL,
    Evaluation,
    FitKey,
    Members,
    Uncertainty,
    best_of,
    coarse_stage,
    json_ready,
    refine,
    uncertainty_stage,
)
from conslaw.ensemble.observations import Observation, parse_number, read_observations, split_pair
from conslaw.ensemble.study import plain_settings, scene_source
from conslaw.errors import ConfigError, shown
from conslaw.output.files import (
    atomic_write_bytes,
    check_output_dir,
    hold_folder,
    prepare_output_dir,
    write_figure,
)
from conslaw.progress import CountProgress


@dataclass
class Calibration:
    """What :func:`calibrate` found.

    Attributes
    ----------
    scene : str
    fitted : dict of str to float
        The fitted keys' values: the member with the smallest misfit.
    misfit : float
        Its misfit.
    uncertainty : Uncertainty
    evaluations : list of Evaluation
        Every member run, in order.
    keys : list of FitKey
    observations : list of Observation
    settings : dict
        The scene keys set for every member (``--set``).
    seed : int
    optimiser : dict
        The refinement's method, message and member count.
    notes : list of str
        What a reader of the fit should know (the best member at a bound, cut short, ...).
    wall_seconds : float
    files : list of Path
        The files written (none without ``out``).
    """

    scene: str
    fitted: dict[str, float]
    misfit: float
    uncertainty: Uncertainty
    evaluations: list[Evaluation]
    keys: list[FitKey]
    observations: list[Observation]
    settings: dict[str, Any]
    seed: int
    optimiser: dict[str, Any]
    notes: list[str]
    wall_seconds: float
    files: list[Path] = field(default_factory=list)

    @property
    def standard_error(self) -> dict[str, float]:
        """The standard error of each fitted key (:class:`Uncertainty`)."""
        return self.uncertainty.standard_error

    @property
    def failed(self) -> int:
        """Members without a misfit, over every stage."""
        return sum(not evaluation.ok for evaluation in self.evaluations)

    @property
    def best(self) -> Evaluation:
        """The member at the optimum."""
        return min((e for e in self.evaluations if e.ok), key=lambda e: (e.misfit, e.index))

    def to_json(self) -> dict[str, Any]:
        """The calibration as a JSON object (``calibration.json``)."""
        return {
            "scene": self.scene,
            "settings": json_ready(dict(self.settings)),
            "fit": {k.key: {"low": k.low, "high": k.high, "start": k.start} for k in self.keys},
            "observed": [_observation_json(o) for o in self.observations],
            "seed": self.seed,
            "fitted": self.fitted,
            "misfit": json_ready(self.misfit),
            "optimum_member": self.best.index,
            "uncertainty": self.uncertainty.to_json(),
            "optimiser": json_ready(self.optimiser),
            "members": len(self.evaluations),
            "failed": self.failed,
            "notes": self.notes,
            "wall_seconds": self.wall_seconds,
            "evaluations": [evaluation.to_json() for evaluation in self.evaluations],
        }


def _observation_json(observation: Observation) -> dict[str, Any]:
    deposit = observation.deposit
    return {
        "name": observation.name,
        "value": json_ready(observation.value),
        "sigma": observation.sigma,
        "file": None if deposit is None else str(deposit.path),
    }


def parse_fit(text: str) -> tuple[str, float, float]:
    """``(key, low, high)`` of ``KEY=LOW:HIGH``; a ConfigError naming the key otherwise.

    Examples
    --------
    >>> parse_fit("parameters.delta=20:35")
    ('parameters.delta', 20.0, 35.0)
    """
    key, bounds = split_pair(text, "--fit", "KEY=LOW:HIGH")
    if key.count(".") >= MAX_NESTING:
        raise ConfigError(
            f"--fit {shown(key, 40)}: {key.count('.') + 1} parts; at most {MAX_NESTING}"
        )
    parts = bounds.split(":")
    if len(parts) != 2:
        raise ConfigError(f"--fit {key}: expected LOW:HIGH, got '{bounds}'")
    low = parse_number(parts[0], f"--fit {key}: LOW")
    high = parse_number(parts[1], f"--fit {key}: HIGH")
    if not low < high:
        raise ConfigError(f"--fit {key}: expected LOW < HIGH, got {low:g} and {high:g}")
    return key, low, high


def _pairs(given: Mapping[str, Any] | Sequence[str], option: str, form: str) -> dict[str, Any]:
    """A mapping from ``NAME=VALUE`` texts (or a mapping as it is); a name given twice is a
    ConfigError."""
    if isinstance(given, Mapping):
        return dict(given)
    chosen: dict[str, Any] = {}
    for text in given:
        name, value = split_pair(text, option, form)
        if name in chosen:
            raise ConfigError(f"{option} {name}: given more than once")
        chosen[name] = value
    return chosen


def _fits(fit: Mapping[str, Sequence[float]] | Sequence[str]) -> list[tuple[str, float, float]]:
    if isinstance(fit, Mapping):
        texts = [f"{key}={':'.join(str(v) for v in bounds)}" for key, bounds in fit.items()]
    else:
        texts = list(fit)
    fits = [parse_fit(text) for text in texts]
    keys = [key for key, _, _ in fits]
    if not fits:
        raise ConfigError("--fit: at least one fitted key is needed, KEY=LOW:HIGH")
    repeated = sorted({key for key in keys if keys.count(key) > 1})
    if repeated:
        raise ConfigError(f"--fit {repeated[0]}: given more than once")
    return fits


_MISSING = object()


def _scene_value(scene: Any, key: str) -> Any:
    """The value of the dotted scene ``key`` in ``scene`` (a model parameter left at its
    default included); :data:`_MISSING` if the scene has no such key."""
    node: Any = scene.to_table()
    for part in key.split("."):
        if not isinstance(node, Mapping) or part not in node:
            node = _MISSING
            break
        node = node[part]
    head, _, name = key.partition(".")
    if node is _MISSING and head == "parameters" and name:
        node = getattr(scene.model_instance().params, name, _MISSING)
    return node


def fit_keys(
    source: str, settings: Mapping[str, Any], fits: Sequence[tuple[str, float, float]]
) -> list[FitKey]:
    """Each fitted key with its start, the scene's value after ``settings``.

    Parameters
    ----------
    source : str
        A built-in scene name or a scene file.
    settings : mapping
        Scene keys set for every member (``--set``).
    fits : sequence of (key, low, high)
        From :func:`parse_fit`.

    Returns
    -------
    list of FitKey

    Raises
    ------
    ConfigError
        Naming the key: the scene has no such key, it is not a number there, it takes no
        real values (``n_cells``), or its start lies outside the bounds.
    """
    from conslaw.scene2d import load_any_scene

    scene = load_any_scene(source, dict(settings))
    keys = []
    for key, low, high in fits:
        value = _scene_value(scene, key)
        if value is _MISSING:
            try:  # the scene's own message names what is wrong with the key
                load_any_scene(source, {**settings, key: 0.5 * (low + high)})
            except ConfigError as error:
                text = str(error)
                raise ConfigError(
                    f"--fit {text if text.startswith(key) else f'{key}: {text}'}"
                ) from None
            raise ConfigError(f"--fit {key}: not a key of scene '{scene.name}'")
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(f"--fit {key}: not a number in the scene (it is {shown(value)})")
        try:
            load_any_scene(source, {**settings, key: float(value)})
        except ConfigError as error:
            raise ConfigError(f"--fit {key}: not a real-valued key ({error})") from None
        if not low <= value <= high:
            raise ConfigError(
                f"--fit {key}={low:g}:{high:g}: the start, the scene's value {value:g}, is "
                f"outside the bounds (widen them, or --set {key}=VALUE inside them)"
            )
        keys.append(FitKey(key, low, high, float(value)))
    return keys


def _shown_values(values: Mapping[str, float]) -> str:
    return ", ".join(f"{key}={value:.6g}" for key, value in values.items())


OPTIONS = ("scheduler", "workers", "coarse", "step", "max_evaluations", "plot")


def _checked_options(options: Mapping[str, Any] | None, keys: int) -> dict[str, Any]:
    """The options with their defaults; a ConfigError naming a bad one."""
    chosen = dict(options or {})
    unknown = sorted(set(chosen) - set(OPTIONS))
    if unknown:
        raise ConfigError(f"calibrate: unknown options {', '.join(unknown)}; known: {OPTIONS}")
    coarse = chosen.get("coarse")
    chosen["coarse"] = COARSE_PER_KEY * keys if coarse is None else coarse
    chosen.setdefault("step", STEP)
    chosen.setdefault("max_evaluations", MAX_EVALUATIONS)
    chosen.setdefault("plot", True)
    if isinstance(chosen["coarse"], bool) or not isinstance(chosen["coarse"], int):
        raise ConfigError(f"--coarse: expected an integer >= 0, got {shown(chosen['coarse'])}")
    if not 0 <= chosen["coarse"] <= MAX_SAMPLES:
        raise ConfigError(
            f"--coarse: expected an integer from 0 to {MAX_SAMPLES}, got {shown(chosen['coarse'])}"
        )
    step = parse_number(chosen["step"], "--step")
    if not 0 < step <= 0.1:
        raise ConfigError(f"--step: expected a fraction of the bounds in (0, 0.1], got {step:g}")
    chosen["step"] = step
    evaluations = chosen["max_evaluations"]
    if isinstance(evaluations, bool) or not isinstance(evaluations, int) or evaluations < 1:
        raise ConfigError(f"max_evaluations: expected an integer >= 1, got {shown(evaluations)}")
    return chosen


def calibrate(
    scene: str | Path,
    observed: Mapping[str, Any] | Sequence[str],
    fit: Mapping[str, Sequence[float]] | Sequence[str],
    *,
    settings: Mapping[str, Any] | None = None,
    tolerance: Mapping[str, Any] | Sequence[str] | None = None,
    seed: int = 0,
    out: str | Path | None = None,
    options: Mapping[str, Any] | None = None,
    report: Callable[[str], None] = print,
) -> Calibration:
    """Fit scene keys to observations: the bounded minimum of the misfit
    ``sum_i ((m_i - o_i) / sigma_i)^2`` over members of the scene, and its linearised
    standard errors (docs/calibration.md).

    Parameters
    ----------
    scene : str or Path
        A built-in scene name or a scene file.
    observed : mapping or sequence of str
        ``{"runout_length": 33.67, "deposit": "deposit.csv"}`` or ``["runout_length=33.67"]``:
        summary figures (:data:`conslaw.ensemble.observations.OBSERVABLE`) and a deposit file.
    fit : mapping or sequence of str
        ``{"parameters.delta": (20, 35)}`` or ``["parameters.delta=20:35"]``: the fitted keys
        and their bounds. Each starts from the scene's value (after ``settings``).
    settings : mapping, optional
        Scene keys set for every member, as ``--set``. Here and in ``observed``, ``fit`` and
        ``tolerance``, numpy numbers and arrays are taken as the Python values they hold.
    tolerance : mapping or sequence of str, optional
        The standard error ``sigma_i`` of an observation, in its units (default:
        :data:`~conslaw.ensemble.observations.RELATIVE_ERROR` of its magnitude).
    seed : int
        The coarse stage's Latin hypercube; the same inputs give the same calibration.
    out : str or Path, optional
        A folder for ``calibration.json`` and ``calibration.png`` (None: no files).
    options : mapping, optional
        ``scheduler`` (a Dask scheduler address, client or cluster), ``workers`` (local
        processes), ``coarse`` (members of the coarse stage, default :data:`COARSE_PER_KEY` per
        key), ``step`` (the uncertainty members' step, a fraction of the bounds, default
        :data:`STEP`), ``max_evaluations`` (of the refinement, default
        :data:`MAX_EVALUATIONS`), ``plot`` (draw ``calibration.png``, default True).
    report : callable
        Gets the progress lines.

    Returns
    -------
    Calibration

    Raises
    ------
    ConfigError
        Bad input (before any member runs), or no member of the coarse stage finished.
    """
    seed = check_seed(seed)
    source = scene_source(scene)[0]
    chosen_settings = plain_settings(settings or {})
    observed, fit = plain_values(observed), plain_values(fit)
    tolerance = plain_values(tolerance)
    keys = fit_keys(source, chosen_settings, _fits(fit))
    observations = _observations(source, chosen_settings, observed, tolerance)
    chosen = _checked_options(options, len(keys))
    folder = None if out is None else check_output_dir(Path(out))
    started = time.perf_counter()
    members = partial(Members, source=source, settings=chosen_settings, keys=keys,
                      observations=observations)  # fmt: skip
    evaluations, optimiser, uncertainty = _on_engine(members, chosen, int(seed), report)
    best = best_of(evaluations)
    calibration = Calibration(
        str(scene), dict(best.values), best.misfit, uncertainty, evaluations, keys,
        observations, chosen_settings, int(seed), optimiser, [],
        time.perf_counter() - started,
    )  # fmt: skip
    calibration.notes.extend(_notes(calibration))
    if folder is not None:
        calibration.files = write_calibration(calibration, folder, bool(chosen["plot"]))
    return calibration


def _observations(
    source: str,
    settings: Mapping[str, Any],
    observed: Mapping[str, Any] | Sequence[str],
    tolerance: Mapping[str, Any] | Sequence[str] | None,
) -> list[Observation]:
    """The observations of the scene ``source`` (with ``settings``), each with its standard
    error (:func:`~conslaw.ensemble.observations.read_observations`)."""
    from conslaw.grid import Grid
    from conslaw.grid2d import Grid2D
    from conslaw.scene2d import Scene2D, load_any_scene

    given = _pairs(observed, "--observed", "NAME=VALUE")
    tolerances = _pairs(tolerance or {}, "--tolerance", "NAME=VALUE")
    scene = load_any_scene(source, dict(settings))
    if isinstance(scene, Scene2D):
        grid = Grid2D.from_bounds(
            scene.x_min, scene.x_max, scene.nx, scene.y_min, scene.y_max, scene.ny
        )
        return read_observations(given, tolerances, 2, grid)
    return read_observations(given, tolerances, 1, Grid(scene.x_min, scene.x_max, scene.n_cells))


def _on_engine(
    members: Callable[..., Members],
    chosen: Mapping[str, Any],
    seed: int,
    report: Callable[[str], None],
) -> tuple[list[Evaluation], dict[str, Any], Uncertainty]:
    """The stages (:func:`_stages`) on the engine ``chosen`` names, started for them and
    stopped after (at once on an interrupt); ``members(engine=...)`` makes the members."""
    engine = engine_for(chosen.get("scheduler"), chosen.get("workers"))
    if isinstance(engine, LocalEngine) and engine.note is not None:
        report(engine.note)
    engine.start()
    try:
        run = members(engine=engine)
        engine.boot(run.task(0, [key.start for key in run.keys]))  # load the kernels now
        optimiser, uncertainty = _stages(run, chosen, seed, report)
    except KeyboardInterrupt:
        engine.abandon()
        raise
    finally:
        engine.stop()
    return run.evaluations, optimiser, uncertainty


def _stages(
    members: Members, chosen: Mapping[str, Any], seed: int, report: Callable[[str], None]
) -> tuple[dict[str, Any], Uncertainty]:
    """The three stages (module docstring); the refinement's record and the uncertainty. Each
    stage reports its members as they finish (:class:`~conslaw.progress.CountProgress`; the
    refinement's are open-ended: its optimiser decides when it has enough), then its result."""
    members.progress = CountProgress(report, "coarse stage", int(chosen["coarse"]) + 1)
    coarse = coarse_stage(members, int(chosen["coarse"]), seed)
    best = best_of(members.evaluations)
    report(
        f"coarse stage: {len(coarse)} members, best {_shown_values(best.values)} "
        f"(misfit {best.misfit:.4g})"
    )
    members.progress = CountProgress(report, "refinement", None)
    optimiser = refine(members, best, int(chosen["max_evaluations"]))
    best = best_of(members.evaluations)
    report(
        f"refinement: {optimiser['members']} members, best {_shown_values(best.values)} "
        f"(misfit {best.misfit:.4g})"
    )
    members.progress = CountProgress(report, "uncertainty")
    uncertainty = uncertainty_stage(members, best, float(chosen["step"]))
    members.progress = None
    failed = f", {uncertainty.failed} failed" if uncertainty.failed else ""
    report(f"uncertainty: {uncertainty.members} members{failed}")
    return optimiser, uncertainty


#: A best member whose weighted residuals are this many standard errors (root mean square) is
#: not a fit: a note says so.
FAR_MISS = 5.0
#: A fitted value within this fraction of its range from a bound sits against it (with a
#: best member that misses the observations by :data:`FAR_MISS`).
NEAR_BOUND = 0.01


def _notes(calibration: Calibration) -> list[str]:
    """What a reader of the fit should know about it."""
    notes = []
    best = calibration.best
    count = len(best.residuals)
    miss = math.sqrt(best.misfit / count) if count else 0.0
    far = miss > FAR_MISS
    for key in calibration.keys:
        value = calibration.fitted[key.key]
        where = key.unit(value)
        bound = key.low if where < 0.5 else key.high
        if min(where, 1.0 - where) < 10 * XTOL:
            notes.append(f"{key.key} is at its bound {bound:g}: the best fit may lie beyond it")
        elif far and min(where, 1.0 - where) < NEAR_BOUND:
            notes.append(
                f"{key.key} = {value:.6g} sits against its bound {bound:g}: the best fit may "
                "lie beyond it"
            )
    if far:
        notes.append(
            f"the best member misses the observations by {miss:.3g} standard errors (root mean "
            "square of the weighted residuals): no member matches them; check the observed "
            "values and their --tolerance, and the bounds of --fit"
        )
    if best.figures.get("at_boundary") == 1.0:
        notes.append(
            "the best member reached an end of the domain: its run-out is cut short "
            "(widen the domain)"
        )
    errors = calibration.standard_error.values()
    if any(math.isinf(error) for error in errors):
        notes.append(
            f"the observations do not determine the {len(calibration.keys)} keys (the slopes "
            "of the residuals are linearly dependent): infinite standard errors"
        )
    if any(math.isnan(error) for error in errors):
        notes.append("a key has no standard error: its uncertainty members failed")
    return notes


def write_calibration(calibration: Calibration, folder: Path, plot: bool = True) -> list[Path]:
    """``calibration.json`` and (with ``plot``) ``calibration.png`` in ``folder``, each written
    atomically; the folder is held while they are written (``hold_folder``).

    Returns
    -------
    list of Path
    """
    folder = prepare_output_dir(Path(folder))
    handle = hold_folder(folder, "conslaw calibrate")
    try:
        paths = [folder / "calibration.json"]
        if plot:
            paths.append(folder / "calibration.png")
        body = json.dumps(calibration.to_json(), indent=2, allow_nan=False) + "\n"
        atomic_write_bytes(paths[0], body.encode())
        if plot:
            write_figure(paths[1], calibration_figure(calibration))
    finally:
        if handle is not None:
            os.close(handle)
    return paths


def calibration_figure(calibration: Calibration) -> Any:
    """The misfit of every member against each fitted key, one panel per key: the members by
    stage, the failed ones as crosses along the top, the start (dashed) and the optimum (a red
    star, its standard error as a bar)."""
    from matplotlib.figure import Figure

    keys = calibration.keys
    figure = Figure(figsize=(5.8 * len(keys), 3.6), layout="constrained")
    axes = figure.subplots(1, len(keys), squeeze=False)[0]
    done = [e for e in calibration.evaluations if e.ok]
    positive = [e.misfit for e in done if e.misfit > 0]
    top = max([e.misfit for e in done], default=1.0) or 1.0
    floor = 10.0 ** math.floor(math.log10(min(positive))) if positive else 1.0
    best = calibration.best
    for axis, key in zip(axes, keys, strict=True):
        for colour, stage in zip(("C0", "C1", "C2"), STAGES, strict=True):
            chosen = [e for e in done if e.stage == stage]
            axis.plot([e.values[key.key] for e in chosen], [e.misfit for e in chosen], "o",
                      ms=4, color=colour, alpha=0.7, label=f"{stage} ({len(chosen)})")  # fmt: skip
        failed = [e.values[key.key] for e in calibration.evaluations if not e.ok]
        if failed:
            label = f"failed ({len(failed)})"
            axis.plot(failed, [top] * len(failed), "x", color="0.4", label=label)
        error = calibration.standard_error[key.key]
        value = best.values[key.key]
        bar = [error] if math.isfinite(error) else None
        axis.errorbar([value], [best.misfit], xerr=bar, fmt="*", ms=12, color="C3", zorder=5,
                      label=f"optimum {value:.5g}")  # fmt: skip
        axis.axvline(key.start, color="0.5", ls="--", lw=0.8, label=f"start {key.start:g}")
        axis.set_xlim(key.low, key.high)
        axis.set_yscale("symlog", linthresh=floor)
        axis.set_ylim(0.0, 10.0 * top)
        axis.set_xlabel(key.key)
        axis.set_ylabel("misfit")
        axis.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    shown_fit = ", ".join(
        f"{k.key} = {calibration.fitted[k.key]:.5g} ± {calibration.standard_error[k.key]:.2g}"
        for k in keys
    )
    observed = ", ".join(o.shown for o in calibration.observations)
    figure.suptitle(f"{calibration.scene}: {shown_fit}\nobserved {observed}", fontsize=9)
    return figure
