"""One member of an ensemble: its scene run to the end in a worker process, and what the study
keeps of it (docs/ensembles.md, "What a member keeps").

A member is the scene with its varied keys set, run exactly as ``conslaw run SCENE --set
KEY=VALUE ...`` runs it (:func:`conslaw.simulation.simulate` or
:func:`conslaw.simulation2d.simulate_2d`, no output files); the final state's SHA-256 digest
lets anyone check that (``scripts/ensemble_check.py``). A member that fails (a blow-up, the step
limit, a state without meaning) is recorded with its one-line message and does not stop the
study.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import socket
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.ensemble.summary import FIELD_NAMES, member_fields, member_summary
from conslaw.errors import (
    ConslawError,
    InadmissibleStateError,
    SchemeBreakdownError,
    StepLimitError,
)

Array = NDArray[np.float64]

#: Status of a member: finished; stopped by the step limit; stopped by a blow-up (a state
#: without meaning, a time step that collapsed); refused or failed otherwise; not yet run.
STATUSES = ("finished", "step-limit", "blow-up", "failed", "pending")


@dataclass(frozen=True)
class MemberTask:
    """What a worker needs to run one member.

    Attributes
    ----------
    index : int
        The member's number in the study (0-based).
    scene : str
        A built-in scene name or a scene file's absolute path.
    overrides : dict
        Scene keys set for every member (``--set``) and this member's varied keys, as
        ``conslaw run --set`` takes them.
    fields : bool
        Keep the member's maps (:data:`~conslaw.ensemble.summary.FIELD_NAMES`).
    depth_threshold : float or None
        Depth above which a cell counts as covered (None: the default of
        :func:`~conslaw.ensemble.summary.member_summary`).
    """

    index: int
    scene: str
    overrides: Mapping[str, Any]
    fields: bool = False
    depth_threshold: float | None = None


@dataclass
class MemberOutcome:
    """What the study keeps of one member (written to the journal as it arrives).

    Attributes
    ----------
    index : int
    status : str
        One of :data:`STATUSES`.
    message : str
        Empty when finished; the one-line reason otherwise.
    summary : dict of str to float
        The summary figures (:func:`~conslaw.ensemble.summary.member_summary`; NaN where a
        figure has no value).
    digest : str
        SHA-256 of the final state's cell averages (C order, float64), empty if it failed.
    wall_seconds : float
        The member's time in the worker, from reading the scene to its summary.
    worker : str
        ``host:pid`` of the process that ran it.
    fields : dict of str to ndarray
        The maps, if asked for.
    """

    index: int
    status: str
    message: str
    summary: dict[str, float]
    digest: str
    wall_seconds: float
    worker: str
    fields: dict[str, Array] = field(default_factory=dict)


def state_digest(q: Array) -> str:
    """SHA-256 of cell averages as C-ordered float64 bytes (the same for a member and for the
    last state of the ``states.npz`` that ``conslaw run`` writes)."""
    return hashlib.sha256(np.ascontiguousarray(q, dtype=np.float64).tobytes()).hexdigest()


def _status_of(error: BaseException) -> str:
    if isinstance(error, StepLimitError):
        return "step-limit"
    if isinstance(error, SchemeBreakdownError | InadmissibleStateError):
        return "blow-up"
    return "failed"


def run_member(task: MemberTask) -> MemberOutcome:
    """Run one member to its end in this process; never raises for the member's own failure.

    Parameters
    ----------
    task : MemberTask

    Returns
    -------
    MemberOutcome
        Its status, summary figures, final-state digest and (on request) maps.
    """
    from conslaw.scene2d import Scene2D, load_any_scene
    from conslaw.simulation import simulate
    from conslaw.simulation2d import simulate_2d

    started = time.perf_counter()
    worker = f"{socket.gethostname()}:{os.getpid()}"

    def failed(status: str, message: str) -> MemberOutcome:
        seconds = time.perf_counter() - started
        return MemberOutcome(task.index, status, message, {}, "", seconds, worker)

    try:
        scene = load_any_scene(task.scene, dict(task.overrides))
        result: Any = simulate_2d(scene) if isinstance(scene, Scene2D) else simulate(scene)
    except ConslawError as error:
        return failed(_status_of(error), str(error))
    except Exception as error:  # any other failure is this member's, not the study's
        return failed("failed", f"{type(error).__name__}: {error}")
    try:
        summary = member_summary(result, task.depth_threshold)
        maps = member_fields(result) if task.fields else {}
        digest = state_digest(result.states[-1].q)
    except Exception as error:
        return failed("failed", f"summary: {type(error).__name__}: {error}")
    seconds = time.perf_counter() - started
    return MemberOutcome(task.index, "finished", "", summary, digest, seconds, worker, maps)


def run_members(tasks: list[MemberTask]) -> list[MemberOutcome]:
    """:func:`run_member` for each of ``tasks`` in turn (a batch of short members sent to a
    worker at once: one message each way instead of one per member)."""
    return [run_member(task) for task in tasks]


def prepare_member(task: MemberTask) -> None:
    """Load (or compile) in this worker the kernels ``task`` needs, without running it, so that
    the worker's first member does not wait for them (sent to each local worker as the study
    starts, while its own process still checks the members). A member that cannot be built
    is left to :func:`run_member` to report."""
    from conslaw.scene2d import load_any_scene
    from conslaw.warm import compile_kernels

    with contextlib.suppress(ConslawError, ArithmeticError, ValueError):
        compile_kernels(load_any_scene(task.scene, dict(task.overrides)))


__all__ = [
    "FIELD_NAMES",
    "STATUSES",
    "MemberOutcome",
    "MemberTask",
    "prepare_member",
    "run_member",
    "run_members",
    "state_digest",
]
