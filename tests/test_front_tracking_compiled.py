"""The compiled front tracking (``FrontTrackingNT.advance``) against its numpy reference
(``reference_advance``): the same states, margins, steps and failures, to round-off."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import conslaw
from conslaw.errors import InadmissibleStateError, SchemeBreakdownError
from conslaw.schemes.base import AdvanceResult
from conslaw.schemes.front_tracking import scheme as front_tracking
from conslaw.schemes.front_tracking.scheme import FrontTrackingNT
from conslaw.state import State

#: Agreement of the two paths, relative to the largest value of each row.
TOLERANCE = 1e-12


def tracker(scene_name: str, **overrides: Any) -> tuple[FrontTrackingNT, State, float]:
    scene = conslaw.load_scene(scene_name, overrides)
    _, _, scheme, initial, _ = conslaw.simulation.build(scene)
    assert isinstance(scheme, FrontTrackingNT)
    return scheme, scheme.initial_state(initial), scene.t_end


def reference_with_halvings(
    scheme: FrontTrackingNT, state: State, t_end: float, monkeypatch: pytest.MonkeyPatch
) -> tuple[AdvanceResult, int]:
    """The reference run and how many of its steps made a depth negative (and were redone)."""
    negative = [0]
    raw_step = FrontTrackingNT._raw_step

    def counting(self: FrontTrackingNT, source: State, dt: float, steps: int) -> State:
        try:
            return raw_step(self, source, dt, steps)
        except front_tracking._RetryStepError:
            negative[0] += 1
            raise

    with monkeypatch.context() as patch:
        patch.setattr(FrontTrackingNT, "_raw_step", counting)
        result = scheme.reference_advance(state, t_end)
    return result, negative[0]


def assert_same_run(compiled: AdvanceResult, reference: AdvanceResult) -> None:
    assert compiled.steps == reference.steps
    assert compiled.state.t == reference.state.t
    q_ref, q = reference.state.q, compiled.state.q
    scale = np.abs(q_ref).max(axis=1, keepdims=True)
    assert np.all(np.abs(q - q_ref) <= TOLERANCE * scale), np.abs(q - q_ref).max(axis=1)
    # h = 0 outside the body is exact in both.
    np.testing.assert_array_equal(q[0] == 0.0, q_ref[0] == 0.0)
    history, history_ref = compiled.margins, reference.margins
    assert history is not None and history_ref is not None
    assert history.shape == history_ref.shape
    np.testing.assert_array_equal(np.isnan(history), np.isnan(history_ref))
    tracked = ~np.isnan(history_ref[0])  # the columns of the margins the body has
    columns = np.abs(history_ref[:, tracked]).max(axis=0)
    error = np.abs(history[:, tracked] - history_ref[:, tracked]).max(axis=0)
    assert np.all(error <= TOLERANCE * columns), error / columns
    assert compiled.state.margins is not None and reference.state.margins is not None
    np.testing.assert_allclose(
        compiled.state.margins.row(0.0), reference.state.margins.row(0.0), rtol=0, atol=1e-12
    )


@pytest.mark.parametrize(
    ("scene", "overrides", "min_halvings"),
    [
        # Paper Fig. 5 set-up (weno5, plane chute, both margins): two steps of the reference
        # make a depth negative and are redone with half the time step.
        ("sh-similarity-ft", {}, 1),
        # Curved chute (paper Fig. 3, mc): the front slows down in the run-out and comes to
        # rest under Coulomb friction, then a shock runs upslope.
        ("sh-runout-shock", {"front_tracking": True, "n_cells": 200}, 1),
        # Body against the left boundary: a front margin only (mc).
        ("sh-runout-shock", {"front_tracking": True, "n_cells": 120, "t_end": 3.0,
                             "x_min": 0.0, "x_max": 30.0, "initial.centre": 0.5,
                             "output_times": [3.0]}, 0),
        # Body against the right boundary: a rear margin only (weno5, CFL 0.49).
        ("sh-similarity-ft", {"cfl": 0.49, "n_cells": 60, "t_end": 3.0,
                              "initial.centre": 17.0}, 0),
        # Friction stronger than the drive (zeta 25 < delta 30): the body spreads by its
        # pressure and slows down; delta < phi: the earth pressure switches between active and
        # passive (the model's dynamic coefficients, also at the margins).
        ("sh-similarity-ft", {"n_cells": 60, "t_end": 4.0, "parameters.zeta": 25.0,
                              "parameters.phi": 35.0}, 0),
        # A pile spreading on a level bed with phi >> delta: friction holds its top, where the
        # earth pressure may take any value of its rest range (rule 3 of docs/design.md, "Earth
        # pressure"). The compiled kernel lacked that rule: its margins ran off at 2.8 instead
        # of 0.75.
        ("sh-at-rest", {"scheme": "front-tracking", "n_cells": 101, "t_end": 0.3,
                        "output_times": [0.3], "parameters.phi": 45.0, "parameters.delta": 10.0,
                        "parameters.zeta": 0.0, "parameters.epsilon": 10.0,
                        "boundary.left": "wall", "boundary.right": "wall"}, 0),
    ],
)  # fmt: skip
def test_compiled_equals_reference(
    scene: str, overrides: dict[str, Any], min_halvings: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    scheme, state, t_end = tracker(scene, **overrides)
    reference, halvings = reference_with_halvings(scheme, state, t_end, monkeypatch)
    compiled = scheme.advance(state, t_end)
    print(f"{scene} {overrides}: {compiled.steps} steps, {halvings} halvings")
    assert halvings >= min_halvings
    assert_same_run(compiled, reference)


def test_compiled_pauses_and_resumes(monkeypatch: pytest.MonkeyPatch) -> None:
    """A run cut into kernel calls (progress reports, a full history table) is the same run."""
    scheme, state, t_end = tracker("sh-similarity-ft", n_cells=60, t_end=3.0)
    whole = scheme.advance(state, t_end)
    monkeypatch.setattr(front_tracking, "FT_CELL_UPDATES_PER_CALL", 1)
    reports: list[tuple[float, int]] = []
    pieces = scheme.advance(state, t_end, progress=lambda t, steps: reports.append((t, steps)))
    assert len(reports) == whole.steps // 2
    assert reports[-1] == (t_end, whole.steps)
    np.testing.assert_array_equal(pieces.state.q, whole.state.q)
    np.testing.assert_array_equal(pieces.margins, whole.margins)
    monkeypatch.undo()
    scheme._history = np.zeros((5, 5))  # room for two pairs per call
    table_full = scheme.advance(state, t_end)
    np.testing.assert_array_equal(table_full.state.q, whole.state.q)
    np.testing.assert_array_equal(table_full.margins, whole.margins)


def failure_text(call: Any) -> tuple[type[Exception], str]:
    with pytest.raises((SchemeBreakdownError, InadmissibleStateError)) as caught:
        call()
    return type(caught.value), str(caught.value)


def test_margin_at_the_boundary_fails_as_the_reference() -> None:
    """The front margin reaches the right boundary: the same error, time and step."""
    scheme, state, _ = tracker("sh-similarity-ft")
    compiled = failure_text(lambda: scheme.advance(state, 12.0))
    reference = failure_text(lambda: scheme.reference_advance(state, 12.0))
    assert compiled[0] is SchemeBreakdownError
    assert "front margin reached the right boundary" in compiled[1] and "step" in compiled[1]
    assert compiled == reference


def test_inadmissible_state_fails_as_the_reference() -> None:
    """NaN inside the body stops both paths with the same message (time, step, cell)."""
    scheme, state, _ = tracker("sh-similarity-ft")
    q = state.q.copy()
    q[1, 30] = np.nan
    bad = State(state.t, state.x, q, state.offset, state.margins)
    compiled = failure_text(lambda: scheme.advance(bad, 1.0))
    reference = failure_text(lambda: scheme.reference_advance(bad, 1.0))
    assert compiled[0] is InadmissibleStateError
    assert "cell 30" in compiled[1]
    assert compiled == reference


def test_a_body_shorter_than_two_cells_fails_as_the_reference() -> None:
    """Two margins running into each other (u = +-3 in a 6-cell body): the same error, time
    and step on both paths."""
    scheme, state, _ = tracker("sh-similarity-ft", n_cells=60)
    middle = scheme.n_primary // 2
    h, u = np.zeros_like(state.x), np.zeros_like(state.x)
    h[middle - 3 : middle + 3] = [0.3, 1.0, 1.0, 1.0, 1.0, 0.3]
    u[middle - 3 : middle + 3] = [3.0, 3.0, 3.0, -3.0, -3.0, -3.0]
    body = scheme.initial_margins(State(0.0, state.x, np.vstack([h, h * u])))
    compiled = failure_text(lambda: scheme.advance(body, 2.0))
    reference = failure_text(lambda: scheme.reference_advance(body, 2.0))
    assert compiled[0] is SchemeBreakdownError
    assert "the body became shorter than 2 cells at t=" in compiled[1] and "step" in compiled[1]
    assert compiled == reference


def test_a_time_step_below_the_floor_fails_as_the_reference(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A floor above every stable step (1 dx): both paths stop at once with the same line."""
    scheme, state, _ = tracker("sh-similarity-ft", n_cells=60)
    monkeypatch.setattr(front_tracking, "DT_FLOOR_RELATIVE", 1.0)
    compiled = failure_text(lambda: scheme.advance(state, 2.0))
    reference = failure_text(lambda: scheme.reference_advance(state, 2.0))
    assert compiled[0] is SchemeBreakdownError
    assert "fell below the floor 1*dx at t=0, step 0" in compiled[1]
    assert compiled == reference
