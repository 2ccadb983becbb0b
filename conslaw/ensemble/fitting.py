"""The stages of a calibration (docs/calibration.md, "How it fits"): members run on an ensemble
engine, each set of values once; the coarse stage, the bounded local refinement and the
uncertainty members around the optimum.

1. *coarse*: the scene's own values of the fitted keys and a Latin hypercube of members over
   the bounds (:func:`conslaw.ensemble.design.draw`), run in parallel;
2. *refine*: a bounded local minimisation from the best of them,
   :func:`scipy.optimize.minimize_scalar` (``method="bounded"``, Brent's method) for one key,
   :func:`scipy.optimize.minimize` (``method="Powell"``, with bounds) for several;
3. *uncertainty*: members at the optimum plus ``t`` steps of each key
   (``t`` in :data:`OFFSETS`), run in parallel, whose least-squares slopes give the Jacobian of
   the residuals and the linearised standard errors ``sqrt(diag((J^T J)^-1))``.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.ensemble.design import Variation, draw
from conslaw.ensemble.engine import DaskEngine, LocalEngine, WorkerLostError
from conslaw.ensemble.member import MemberOutcome, MemberTask
from conslaw.ensemble.observations import (
    DEPOSIT,
    Observation,
    deposit_agreement,
    folded_rows,
    residuals,
)
from conslaw.errors import ConfigError
from conslaw.progress import CountProgress

Array = NDArray[np.float64]

#: Members of the coarse stage per fitted key (besides the scene's own values).
COARSE_PER_KEY = 8
#: Tolerance of the refinement on the fitted keys, as a fraction of their bounds.
XTOL = 1e-4
#: Most members the refinement may run.
MAX_EVALUATIONS = 200
#: The step of the uncertainty members, as a fraction of each key's bounds.
STEP = 0.01
#: The uncertainty members of each key: the optimum plus these multiples of its step.
OFFSETS = (-2, -1, 1, 2)
#: What the optimiser sees for a failed member, besides 1000 times the largest misfit of the
#: coarse stage (it needs a finite value; the member is recorded with an infinite misfit).
FAILED_MISFIT = 1e12
#: Stages of a calibration, in order.
STAGES = ("coarse", "refine", "uncertainty")


@dataclass(frozen=True)
class FitKey:
    """A fitted scene key, its bounds and its start (the scene's own value)."""

    key: str
    low: float
    high: float
    start: float

    def value(self, unit: float) -> float:
        """The key's value at ``unit`` in [0, 1] of its bounds."""
        return self.low + float(unit) * (self.high - self.low)

    def unit(self, value: float) -> float:
        """Where ``value`` lies in the bounds, 0 at ``low`` and 1 at ``high``."""
        return (float(value) - self.low) / (self.high - self.low)


@dataclass
class Evaluation:
    """One member of a calibration.

    Attributes
    ----------
    index : int
        Its number, in the order run.
    stage : str
        One of :data:`STAGES`: the stage that ran it first.
    values : dict of str to float
        The fitted keys' values.
    status : str
        The member's status (:data:`conslaw.ensemble.member.STATUSES`).
    message : str
        Why it failed (empty if it has a misfit).
    figures : dict of str to float
        Its summary figures (and ``deposit_rms`` or ``deposit_overlap`` with a deposit).
    misfit : float
        The sum of the squared residuals; infinite for a member that failed or has no value
        of an observed figure.
    digest : str
        SHA-256 of its final state (:func:`conslaw.ensemble.member.state_digest`).
    wall_seconds : float
    residuals : ndarray
        The weighted residuals (:func:`conslaw.ensemble.observations.residuals`).
    """

    index: int
    stage: str
    values: dict[str, float]
    status: str
    message: str
    figures: dict[str, float]
    misfit: float
    digest: str
    wall_seconds: float
    residuals: Array = field(repr=False)

    @property
    def ok(self) -> bool:
        """It finished with a value of every observed figure."""
        return math.isfinite(self.misfit)

    def to_json(self) -> dict[str, Any]:
        """The member as a JSON object (without the residuals)."""
        return {
            "index": self.index, "stage": self.stage, "values": self.values,
            "status": self.status, "message": self.message, "misfit": json_ready(self.misfit),
            "figures": json_ready(self.figures), "digest": self.digest,
            "wall_seconds": json_ready(self.wall_seconds),
        }  # fmt: skip


@dataclass
class Uncertainty:
    """The linearised uncertainty of the fitted keys (docs/calibration.md, "Uncertainty").

    Attributes
    ----------
    standard_error : dict of str to float
        ``sqrt(C_jj)`` of each key, with ``C = (J^T J)^-1`` and ``J`` the slopes of the
        weighted residuals; infinite if the observations do not determine the keys, NaN if a
        key has no slope (its members failed).
    covariance : ndarray
        ``C``, keys in the order fitted.
    slopes : dict of str to dict of str to float
        ``d figure / d key`` of each observed summary figure, by key.
    step : dict of str to float
        The step of each key's members.
    members : int
        The uncertainty members (the optimum's neighbours).
    failed : int
        Those without a misfit (failed, or no value of an observed figure).
    """

    standard_error: dict[str, float]
    covariance: Array
    slopes: dict[str, dict[str, float]]
    step: dict[str, float]
    members: int
    failed: int

    def to_json(self) -> dict[str, Any]:
        """The uncertainty as a JSON object."""
        return {
            "standard_error": json_ready(self.standard_error),
            "covariance": json_ready(self.covariance.tolist()), "slopes": json_ready(self.slopes),
            "step": self.step, "members": self.members, "failed": self.failed,
            "offsets": list(OFFSETS),
        }  # fmt: skip


def json_ready(value: Any) -> Any:
    """``value`` for JSON: NaN and infinities as null (JSON has no such numbers)."""
    if isinstance(value, Mapping):
        return {str(k): json_ready(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [json_ready(v) for v in value]
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    return value


class Members:
    """The members of a calibration, run on ``engine``, each set of values once.

    Parameters
    ----------
    engine : LocalEngine or DaskEngine
        Started.
    source : str
        The scene.
    settings : mapping
        Scene keys set for every member.
    keys : list of FitKey
    observations : list of Observation
    """

    def __init__(
        self,
        engine: LocalEngine | DaskEngine,
        source: str,
        settings: Mapping[str, Any],
        keys: Sequence[FitKey],
        observations: Sequence[Observation],
    ) -> None:
        self.engine, self.source, self.settings = engine, source, dict(settings)
        self.keys, self.observations = list(keys), list(observations)
        self.fields = any(o.name == DEPOSIT for o in observations)
        self.evaluations: list[Evaluation] = []
        self._cache: dict[tuple[float, ...], Evaluation] = {}
        self.penalty = FAILED_MISFIT
        #: Told of every member run (its stage's lines; docs/cli.md, "Progress"), if set.
        self.progress: CountProgress | None = None

    def task(self, index: int, point: Sequence[float]) -> MemberTask:
        """The task of member ``index`` at ``point`` (values of the keys, in order)."""
        varied = {k.key: float(v) for k, v in zip(self.keys, point, strict=True)}
        return MemberTask(index, self.source, {**self.settings, **varied}, self.fields)

    def run(self, points: Sequence[Sequence[float]], stage: str) -> list[Evaluation]:
        """The members at ``points`` (values of the keys, in order), those not run before run
        in parallel; in the order of ``points``."""
        wanted = [tuple(float(v) for v in point) for point in points]
        new = list(dict.fromkeys(p for p in wanted if p not in self._cache))
        tasks: dict[int, tuple[MemberTask, tuple[float, ...]]] = {}
        for point in new:
            index = len(self.evaluations) + len(tasks)
            tasks[index] = (self.task(index, point), point)
        outcomes = self._outcomes([task for task, _ in tasks.values()])
        for index in sorted(tasks):
            evaluation = self._evaluation(outcomes[index], tasks[index][1], stage)
            self.evaluations.append(evaluation)
            self._cache[tasks[index][1]] = evaluation
        return [self._cache[point] for point in wanted]

    def _outcomes(self, tasks: Sequence[MemberTask]) -> dict[int, MemberOutcome]:
        futures = {self.engine.submit(task): task.index for task in tasks}
        outcomes, lost = {}, False
        if self.progress is not None:
            self.progress.expect(len(tasks))
        for future in self.engine.completed(futures):
            index = futures[future]
            try:
                outcomes[index] = self.engine.outcome(future)
            except WorkerLostError as error:
                outcomes[index] = MemberOutcome(index, "failed", str(error), {}, "", math.nan, "")
                lost = True
            if self.progress is not None:
                self.progress(outcomes[index].status == "finished")
        if lost:
            self.engine.restart()  # a local pool whose worker died refuses new members
        return outcomes

    def _evaluation(
        self, outcome: MemberOutcome, point: tuple[float, ...], stage: str
    ) -> Evaluation:
        values = {k.key: v for k, v in zip(self.keys, point, strict=True)}
        figures = dict(outcome.summary)
        weighted = np.array([math.nan])
        message = outcome.message
        if outcome.status == "finished":
            weighted = residuals(self.observations, outcome.summary, outcome.fields)
            for observation in self.observations:
                figures.update(deposit_agreement(observation, outcome.fields))
            missing = [o.name for o in self.observations if not _finite(figures, o)]
            if missing or not np.all(np.isfinite(weighted)):
                message = f"no value of {', '.join(missing) or 'the residuals'}"
        misfit = float(np.sum(weighted**2)) if not message else math.inf
        return Evaluation(
            outcome.index, stage, values, outcome.status, message, figures, misfit,
            outcome.digest, outcome.wall_seconds, weighted,
        )  # fmt: skip

    def misfit(self, point: Sequence[float]) -> float:
        """The misfit at ``point`` as the optimiser sees it (a failed member:
        :attr:`penalty`)."""
        evaluation = self.run([point], "refine")[0]
        return evaluation.misfit if evaluation.ok else self.penalty


def _finite(figures: Mapping[str, float], observation: Observation) -> bool:
    if observation.name == DEPOSIT:
        return True
    return math.isfinite(figures.get(observation.name, math.nan))


def coarse_stage(members: Members, samples: int, seed: int) -> list[Evaluation]:
    """The scene's own values, then ``samples`` members of a Latin hypercube over the bounds
    (McKay, Beckman & Conover 1979; :func:`conslaw.ensemble.design.draw` with ``seed``).
    The start runs first, alone.

    Parameters
    ----------
    members : Members
    samples : int
        Members of the Latin hypercube (0: the start only).
    seed : int

    Returns
    -------
    list of Evaluation
        The start first.

    Raises
    ------
    ConfigError
        No member has a misfit (each failed, or has no value of an observed figure): there is
        no optimum to refine.
    """
    keys = members.keys
    start = members.run([[k.start for k in keys]], "coarse")
    variations = [Variation(k.key, "uniform", (k.low, k.high)) for k in keys]
    spread = (
        members.run(draw(variations, "lhs", samples, seed).tolist(), "coarse") if samples else []
    )
    finished = [e for e in [*start, *spread] if e.ok]
    if not finished:
        failed = start[0]
        shown_values = ", ".join(f"{k}={v:.6g}" for k, v in failed.values.items())
        raise ConfigError(
            f"calibrate: every member of the coarse stage failed; the first ({shown_values}): "
            f"{failed.status}, {failed.message}"
        )
    members.penalty = FAILED_MISFIT + 1e3 * max(e.misfit for e in finished)
    return [*start, *spread]


def _segment_minimum(start: Array, end: Array) -> tuple[float, float]:
    """``(s, f)``: the minimum ``f`` of ``|r0 + s (r1 - r0)|^2`` over ``s`` in [0, 1], the
    sum of squares of the residuals interpolated on a straight line, and where it is."""
    change = end - start
    size = float(change @ change)
    where = float(np.clip(-(start @ change) / size, 0.0, 1.0)) if size > 0 else 0.0
    interpolated = start + where * change
    return where, float(interpolated @ interpolated)


def bracket(
    evaluations: Sequence[Evaluation], key: FitKey, best: Evaluation
) -> tuple[float, float]:
    """The interval of one fitted key the refinement searches.

    Between two adjacent evaluated members whose residuals, interpolated on a straight line,
    come closer to the observations inside the interval than ``best`` does (a residual that
    changes sign: the regula falsi bracket of a root), the one that comes closest; otherwise
    the interval between the evaluated values (or bounds) next to ``best``. A plateau of equal
    misfits (a run-out cut short at the end of the domain) thus does not hold the search.

    Parameters
    ----------
    evaluations : sequence of Evaluation
        The members run so far.
    key : FitKey
        The one fitted key.
    best : Evaluation
        The member with the smallest misfit.

    Returns
    -------
    (float, float)
        The interval, ``low < high``, inside the key's bounds.
    """
    by_value = {e.values[key.key]: e for e in evaluations}
    ordered = sorted(by_value)
    chosen, closest = None, best.misfit
    for low, high in itertools.pairwise(ordered):
        first, second = by_value[low], by_value[high]
        if first.ok and second.ok:
            where, value = _segment_minimum(first.residuals, second.residuals)
            if 0.0 < where < 1.0 and value < closest:
                chosen, closest = (low, high), value
    if chosen is not None:
        return chosen
    values = sorted({key.low, key.high, *ordered})
    at = values.index(best.values[key.key])
    return values[max(at - 1, 0)], values[min(at + 1, len(values) - 1)]


def refine(members: Members, best: Evaluation, max_evaluations: int) -> dict[str, Any]:
    """The bounded local minimisation from ``best``, in coordinates scaled to [0, 1] on each
    key's bounds, to :data:`XTOL`.

    One key: :func:`scipy.optimize.minimize_scalar` with ``method="bounded"`` (Brent's method,
    golden sections and parabolic steps; Brent 1973, ch. 5) between the evaluated values next to
    ``best``. Several: :func:`scipy.optimize.minimize` with ``method="Powell"`` (Powell 1964)
    and the bounds, from ``best``.

    Returns
    -------
    dict
        ``method``, ``message``, ``success`` and ``members`` (those it ran).
    """
    keys = members.keys
    before = len(members.evaluations)
    from scipy import optimize  # on first use: the command line imports this module

    if len(keys) == 1:
        key = keys[0]
        low, high = bracket(members.evaluations, key, best)
        result: Any = optimize.minimize_scalar(
            lambda u: members.misfit([key.value(u)]),
            bounds=(key.unit(low), key.unit(high)),
            method="bounded",
            options={"xatol": XTOL, "maxiter": max_evaluations},
        )
        method = "scipy.optimize.minimize_scalar(method='bounded')"
    else:
        result = optimize.minimize(
            lambda u: members.misfit([k.value(x) for k, x in zip(keys, u, strict=True)]),
            np.array([k.unit(best.values[k.key]) for k in keys]),
            method="Powell",
            bounds=[(0.0, 1.0)] * len(keys),
            options={"xtol": XTOL, "ftol": 1e-10, "maxfev": max_evaluations},
        )
        method = "scipy.optimize.minimize(method='Powell')"
    return {
        "method": method, "message": str(result.message), "success": bool(result.success),
        "members": len(members.evaluations) - before,
    }  # fmt: skip


def uncertainty_stage(members: Members, best: Evaluation, step: float) -> Uncertainty:
    """The linearised uncertainty at ``best`` (docs/calibration.md, "Uncertainty").

    For each key ``j``, members at ``x*_j + t h_j`` for ``t`` in :data:`OFFSETS` (those inside
    the bounds), ``h_j = step (high_j - low_j)``, the others at the optimum, all run in
    parallel. The column ``J_j`` is the least-squares slope of the weighted residuals against the
    key over these members and the optimum (a straight-line fit, robust to the small jumps of a
    figure on a grid). With residuals weighted by their standard errors, ``C = (J^T J)^-1`` is
    the covariance of the keys to first order (Gauss–Newton; e.g. Press et al. 2007, sec. 15.5;
    Tarantola 2005, ch. 3), and ``sqrt(C_jj)`` the standard error of key ``j``. A residual
    that is a distance (a 2D deposit's ``1 - overlap``, V-shaped at its minimum) counts as
    ``sign(t) (r(t) - r(0))``: its slope on each side.
    """
    keys = members.keys
    optimum = [best.values[k.key] for k in keys]
    steps = {k.key: step * (k.high - k.low) for k in keys}
    plan: list[tuple[int, float, list[float]]] = []
    for j, key in enumerate(keys):
        for t in OFFSETS:
            value = optimum[j] + t * steps[key.key]
            if key.low <= value <= key.high:
                plan.append((j, t * steps[key.key], [*optimum[:j], value, *optimum[j + 1 :]]))
    ran = members.run([point for _, _, point in plan], "uncertainty")
    folded = folded_rows(members.observations, best.residuals.size)
    jacobian = np.full((best.residuals.size, len(keys)), math.nan)
    for j in range(len(keys)):
        pairs = [(0.0, best.residuals)] + [
            (offset, e.residuals) for (i, offset, _), e in zip(plan, ran, strict=True)
            if i == j and e.ok
        ]  # fmt: skip
        if len(pairs) >= 2:
            shifts = np.array([offset for offset, _ in pairs])
            values = np.stack([r for _, r in pairs])
            # A distance (folded row) grows on both sides of its minimum: signed by the side.
            values[:, folded] = np.sign(shifts)[:, None] * (values[:, folded] - values[0, folded])
            centred = shifts - shifts.mean()
            jacobian[:, j] = centred @ (values - values.mean(axis=0)) / np.sum(centred**2)
    covariance = _covariance(jacobian)
    return Uncertainty(
        standard_error={
            k.key: float(np.sqrt(covariance[j, j])) if covariance[j, j] >= 0 else math.nan
            for j, k in enumerate(keys)
        },
        covariance=covariance,
        slopes=_figure_slopes(members.observations, keys, jacobian),
        step=steps,
        members=len(ran),
        failed=sum(not e.ok for e in ran),
    )


def _covariance(jacobian: Array) -> Array:
    """``(J^T J)^-1`` over the keys with a slope; NaN for a key without one, infinite on the
    diagonal if ``J^T J`` is singular (the observations do not determine the keys)."""
    n = jacobian.shape[1]
    covariance = np.full((n, n), math.nan)
    known = np.flatnonzero(np.all(np.isfinite(jacobian), axis=0))
    if known.size == 0:
        return covariance
    part = jacobian[:, known]
    information = part.T @ part
    if np.linalg.matrix_rank(part) < known.size:
        covariance[np.ix_(known, known)] = math.inf
        return covariance
    try:
        inverse = np.linalg.inv(information)
    except np.linalg.LinAlgError:  # J^T J underflowed (a --tolerance of 1e308): no information
        inverse = np.full(information.shape, math.inf)
    covariance[np.ix_(known, known)] = inverse
    return covariance


def _figure_slopes(
    observations: Sequence[Observation], keys: Sequence[FitKey], jacobian: Array
) -> dict[str, dict[str, float]]:
    """``d figure / d key`` of each observed summary figure: the Jacobian's row times its
    standard error."""
    slopes: dict[str, dict[str, float]] = {k.key: {} for k in keys}
    single = sum(observation.deposit is None or observation.folded for observation in observations)
    cells = jacobian.shape[0] - single  # a 1D deposit's rows: one per cell, no single figure
    row = 0
    for observation in observations:
        if observation.deposit is not None:
            row += 1 if observation.folded else cells
            continue
        for j, key in enumerate(keys):
            slopes[key.key][observation.name] = float(jacobian[row, j] * observation.sigma)
        row += 1
    return slopes


def best_of(evaluations: Sequence[Evaluation]) -> Evaluation:
    """The member with the smallest misfit (the first run among equals)."""
    return min((e for e in evaluations if e.ok), key=lambda e: (e.misfit, e.index))
