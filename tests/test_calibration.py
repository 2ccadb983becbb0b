"""Calibration (conslaw.ensemble.calibration, docs/calibration.md): a synthetic observation is
recovered, the uncertainty is the linearised one, the same inputs give the same fit, and bad
input is one line with exit code 2.

The synthetic observations come from a run of ``sh-runout-shock`` at ``n_cells = 200`` with
``parameters.delta = 25``; every calibration starts from the scene's ``delta = 30`` and runs on
one local worker process.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from conslaw.cli import main
from conslaw.ensemble.calibration import Calibration, calibrate, parse_fit
from conslaw.ensemble.fitting import Evaluation, FitKey, bracket
from conslaw.ensemble.member import MemberTask, run_member
from conslaw.ensemble.observations import (
    Deposit,
    Observation,
    deposit_agreement,
    read_deposit,
    residuals,
)
from conslaw.errors import ConfigError
from conslaw.grid2d import Grid2D
from conslaw.terrain.raster import write_geotiff

SCENE = "sh-runout-shock"
SETTINGS = {"n_cells": 200}
TRUE_DELTA = 25.0
FIT = ["parameters.delta=20:35"]
OPTIONS = {"workers": 1}


def quiet(line: str) -> None:
    """Progress lines are not checked here."""


@pytest.fixture(scope="module")
def truth() -> dict[str, Any]:
    """The synthetic observation: the summary and final depth of the run at delta = 25."""
    overrides = {**SETTINGS, "parameters.delta": TRUE_DELTA}
    outcome = run_member(MemberTask(0, SCENE, overrides, fields=True))
    assert outcome.status == "finished", outcome.message
    return {"summary": outcome.summary, "fields": outcome.fields}


@pytest.fixture(scope="module")
def fitted(truth: dict[str, Any], tmp_path_factory: pytest.TempPathFactory) -> Calibration:
    """The acceptance calibration: run-out length only, delta in 20:35 from 30."""
    observed = {"runout_length": truth["summary"]["runout_length"]}
    out = tmp_path_factory.mktemp("calibration")
    return calibrate(SCENE, observed, FIT, settings=SETTINGS, out=out, options=OPTIONS,
                     report=quiet)  # fmt: skip


def test_recovers_delta_from_the_run_out(fitted: Calibration) -> None:
    key = fitted.keys[0]
    assert (key.key, key.low, key.high, key.start) == ("parameters.delta", 20.0, 35.0, 30.0)
    assert fitted.evaluations[0].values == {"parameters.delta": 30.0}  # started at the scene's
    assert abs(fitted.fitted["parameters.delta"] - TRUE_DELTA) < 0.1
    # The fitted member reproduces the observation to well within its standard error.
    best = fitted.best
    assert best.values == fitted.fitted and best.misfit == fitted.misfit
    observation = fitted.observations[0]
    assert abs(best.figures["runout_length"] - observation.value) < 0.1 * observation.sigma
    assert fitted.misfit == min(e.misfit for e in fitted.evaluations)
    # Every evaluation stays in the bounds and is a distinct member (the cache).
    values = [e.values["parameters.delta"] for e in fitted.evaluations]
    assert all(20.0 <= v <= 35.0 for v in values)
    assert len(set(values)) == len(values)
    # Members with delta > phi = 30 are refused by the model and counted as failed.
    assert fitted.failed == sum(v > 30.0 for v in values) > 0


def test_uncertainty_is_finite_positive_and_linearised(fitted: Calibration) -> None:
    uncertainty = fitted.uncertainty
    error = fitted.standard_error["parameters.delta"]
    assert 0.0 < error < math.inf
    assert uncertainty.members == 4 and uncertainty.failed == 0
    # One key, one observation: sigma_delta = sigma_obs / |d runout / d delta|.
    slope = uncertainty.slopes["parameters.delta"]["runout_length"]
    assert slope < 0  # more bed friction, a shorter run-out
    sigma = fitted.observations[0].sigma
    assert error == pytest.approx(sigma / abs(slope), rel=1e-9)
    assert uncertainty.covariance[0, 0] == pytest.approx(error**2, rel=1e-12)


def test_files_hold_every_member(fitted: Calibration) -> None:
    names = sorted(path.name for path in fitted.files)
    assert names == ["calibration.json", "calibration.png"]
    folder = fitted.files[0].parent
    assert (folder / "calibration.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    document = json.loads((folder / "calibration.json").read_text())
    assert document["fitted"] == fitted.fitted
    assert document["misfit"] == fitted.misfit
    assert document["uncertainty"]["standard_error"] == fitted.standard_error
    assert len(document["evaluations"]) == len(fitted.evaluations) == document["members"]
    for row, evaluation in zip(document["evaluations"], fitted.evaluations, strict=True):
        assert row["values"] == evaluation.values
        assert row["status"] == evaluation.status
        assert (row["misfit"] is None) == (not evaluation.ok)
        if evaluation.ok:
            assert row["figures"]["runout_length"] == evaluation.figures["runout_length"]
    assert not list(folder.glob(".*.tmp"))  # written atomically: no temporary file left


def test_same_inputs_same_calibration(fitted: Calibration, truth: dict[str, Any]) -> None:
    observed = {"runout_length": truth["summary"]["runout_length"]}
    again = calibrate(SCENE, observed, FIT, settings=SETTINGS, options=OPTIONS, report=quiet)
    assert again.fitted == fitted.fitted
    assert again.misfit == fitted.misfit
    assert again.standard_error == fitted.standard_error
    assert [e.values for e in again.evaluations] == [e.values for e in fitted.evaluations]
    assert [e.digest for e in again.evaluations] == [e.digest for e in fitted.evaluations]
    assert again.files == []  # no folder, no files


def test_two_observations(truth: dict[str, Any]) -> None:
    summary = truth["summary"]
    observed = [f"runout_length={summary['runout_length']!r}",
                f"travel_angle={summary['travel_angle']!r}"]  # fmt: skip
    result = calibrate(SCENE, observed, FIT, settings=SETTINGS, options=OPTIONS, report=quiet)
    assert abs(result.fitted["parameters.delta"] - TRUE_DELTA) < 0.1
    assert [o.name for o in result.observations] == ["runout_length", "travel_angle"]
    assert result.best.residuals.shape == (2,)
    slopes = result.uncertainty.slopes["parameters.delta"]
    assert slopes["runout_length"] < 0 < slopes["travel_angle"]
    # Two figures: J^T J is the sum of both (slope / sigma)^2.
    information = sum((slopes[o.name] / o.sigma) ** 2 for o in result.observations)
    assert result.standard_error["parameters.delta"] == pytest.approx(information**-0.5)


def test_deposit_profile_from_the_command_line(
    truth: dict[str, Any], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    fields = truth["fields"]
    table = tmp_path / "deposit.csv"
    rows = "\n".join(
        f"{float(x)!r},{float(h)!r}"
        for x, h in zip(fields["_x"], fields["final_depth"], strict=True)
    )
    table.write_text(f"x,depth\n{rows}\n")
    out = tmp_path / "out"
    code = main(["calibrate", SCENE, "--observed", f"deposit={table}", "--fit", FIT[0], "--set",
                 "n_cells=200", "--workers", "1", "--out", str(out), "--no-plot"])  # fmt: skip
    printed = capsys.readouterr()
    assert code == 0, printed.err
    document = json.loads((out / "calibration.json").read_text())
    assert abs(document["fitted"]["parameters.delta"] - TRUE_DELTA) < 0.1
    assert not (out / "calibration.png").exists()
    assert (
        "parameters.delta = " in printed.out and f"wrote {out / 'calibration.json'}" in printed.out
    )
    best = document["evaluations"][document["optimum_member"]]
    sigma = document["observed"][0]["sigma"]
    assert sigma == pytest.approx(0.01 * float(np.max(fields["final_depth"])))
    assert best["figures"]["deposit_rms"] ** 2 / sigma**2 == pytest.approx(document["misfit"])


CASES = [
    (["--observed", "runout=33", "--fit", FIT[0]],
     ["--observed runout", "known: front, rear", "runout_length", "travel_angle"]),
    (["--fit", FIT[0]], ["--observed", "at least one"]),
    (["--observed", "runout_length=33.67"], ["--fit", "at least one"]),
    (["--observed", "runout_length=33.67", "--fit", "parameters.chute=20:35"],
     ["--fit parameters.chute", "not a number"]),
    (["--observed", "runout_length=33.67", "--fit", "parameters.foo=20:35"],
     ["parameters.foo", "unknown parameter"]),
    (["--observed", "runout_length=33.67", "--fit", "n_cells=100:300"], ["--fit n_cells"]),
    (["--observed", "runout_length=33.67", "--fit", "parameters.delta=35:20"],
     ["--fit parameters.delta", "LOW < HIGH"]),
    (["--observed", "runout_length=33.67", "--fit", "parameters.delta=25:25"], ["LOW < HIGH"]),
    (["--observed", "runout_length=33.67", "--fit", "parameters.delta=20:28"],
     ["parameters.delta", "start", "30", "outside the bounds"]),
    (["--observed", "runout_length=33.67", "--fit", "parameters.delta=20"], ["LOW:HIGH"]),
    (["--observed", "runout_length=far", "--fit", FIT[0]], ["--observed runout_length", "far"]),
    (["--observed", "runout_length=inf", "--fit", FIT[0]], ["--observed runout_length"]),
    (["--observed", "runout_length=33", "--fit", FIT[0], "--tolerance", "drop=1"],
     ["--tolerance drop", "no --observed drop"]),
    (["--observed", "drop=3", "--fit", FIT[0], "--tolerance", "drop=0"], ["--tolerance drop"]),
    (["--observed", "travel_angle=0", "--fit", FIT[0]], ["--tolerance travel_angle"]),
    (["--observed", "runout_length=1", "--observed", "runout_length=2", "--fit", FIT[0]],
     ["runout_length", "more than once"]),
    (["--observed", "deposit=missing.csv", "--fit", FIT[0]], ["deposit", "missing.csv"]),
    (["--observed", "runout_length=33", "--fit", FIT[0], "--coarse", "-1"], ["--coarse"]),
]  # fmt: skip


@pytest.mark.parametrize(("extra", "fragments"), CASES)
def test_bad_input_is_one_line(
    extra: list[str],
    fragments: list[str],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "out"
    arguments = ["calibrate", SCENE, "--set", "n_cells=200", "--workers", "1", "--out", str(out)]
    assert main([*arguments, *extra]) == 2
    printed = capsys.readouterr()
    lines = printed.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("conslaw: error: "), printed.err
    assert "Traceback" not in printed.err and printed.out == ""
    for fragment in fragments:
        assert fragment in lines[0]
    assert not out.exists()  # refused before anything is written


def test_every_member_failing_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """No member reaches the end (a step limit): no optimum, one line, exit code 2."""
    out = tmp_path / "out"
    code = main(["calibrate", SCENE, "--observed", "runout_length=33.67", "--fit", FIT[0],
                 "--set", "n_cells=200", "--set", "max_steps=5", "--coarse", "2",
                 "--workers", "1", "--out", str(out)])  # fmt: skip
    printed = capsys.readouterr()
    assert code == 2
    lines = printed.err.strip().splitlines()
    assert len(lines) == 1 and "every member of the coarse stage failed" in lines[0]
    assert "parameters.delta=30" in lines[0] and "step-limit" in lines[0]
    assert not out.exists()


def test_python_api_refuses_like_the_command() -> None:
    with pytest.raises(ConfigError, match="not a figure of a 1D scene"):
        calibrate(SCENE, {"area": 1.0}, FIT, settings=SETTINGS, report=quiet)
    with pytest.raises(ConfigError, match="unknown options"):
        calibrate(SCENE, {"drop": 1.0}, FIT, settings=SETTINGS, options={"cores": 2})
    with pytest.raises(ConfigError, match="LOW < HIGH"):
        parse_fit("parameters.delta=3:3")


# -- the parts, without runs -----------------------------------------------------------------


def _evaluation(index: int, value: float, residual: float) -> Evaluation:
    figures = {"runout_length": residual}
    return Evaluation(index, "coarse", {"k": value}, "finished", "", figures, residual**2, "",
                      0.0, np.array([residual]))  # fmt: skip


@settings(max_examples=80, deadline=None)
@given(
    edge=st.floats(0.05, 0.9),
    gap=st.floats(0.001, 0.1),
    slope=st.floats(0.5, 50.0),
    count=st.integers(3, 12),
)
def test_bracket_holds_the_root_past_a_plateau(
    edge: float, gap: float, slope: float, count: int
) -> None:
    """Residuals flat below ``edge`` (a run-out cut short at the end of the domain), then
    ``slope (root - x)`` with the root ``gap`` past the edge: the flat members come closest to
    the observation, yet the refined interval holds the root whenever an evaluated member lies
    on each side of it (the residual changes sign there)."""
    key = FitKey("k", 0.0, 1.0, 0.5)
    root = edge + gap
    xs = np.linspace(0.0, 1.0, count + 2)[1:-1]
    members = [_evaluation(i, float(x), slope * (root - max(float(x), edge)))
               for i, x in enumerate(xs)]  # fmt: skip
    assume(xs[0] < root < xs[-1])
    best = min(members, key=lambda e: (e.misfit, e.index))
    low, high = bracket(members, key, best)
    assert 0.0 <= low < high <= 1.0
    assert low <= root <= high


@settings(max_examples=50, deadline=None)
@given(
    depth=st.lists(st.floats(0.0, 3.0), min_size=4, max_size=40),
    shift=st.floats(-1.0, 1.0),
    sigma=st.floats(0.01, 1.0),
)
def test_profile_residuals_sum_to_the_rms_difference(
    depth: list[float], shift: float, sigma: float
) -> None:
    """A 1D deposit's residuals: their squares sum to ``(RMS(h - h_obs) / sigma)^2``."""
    x = np.arange(len(depth), dtype=float)
    observed = np.array(depth)
    model = np.clip(observed + shift, 0.0, None)
    deposit = Deposit(Path("d.csv"), x, None, observed)
    observation = Observation("deposit", math.nan, sigma, deposit)
    maps = {"_x": x, "final_depth": model}
    weighted = residuals([observation], {}, maps)
    rms = deposit_agreement(observation, maps)["deposit_rms"]
    assert weighted.shape == x.shape
    assert float(np.sum(weighted**2)) == pytest.approx((rms / sigma) ** 2, rel=1e-9, abs=1e-12)


def test_raster_deposit_overlap(tmp_path: Path) -> None:
    """A 2D deposit raster: the overlap of the covered areas, 1 for the same area; a raster on
    coarser cells is sampled at the scene's cell centres."""
    grid = Grid2D.from_bounds(0.0, 100.0, 20, 0.0, 50.0, 10)
    x, y = grid.centres()
    inside = (np.abs(x[None, :] - 50.0) < 20.0) & (np.abs(y[:, None] - 25.0) < 15.0)
    model = np.where(inside, 1.0, 0.0)
    coarse = model.reshape(5, 2, 10, 2).max(axis=(1, 3))  # 10 m cells, same area
    path = write_geotiff(tmp_path / "deposit.tif", coarse, (0.0, 0.0), 10.0, None,
                         name="deposit", units="m")  # fmt: skip
    deposit = read_deposit(path, 2, grid)
    observation = Observation("deposit", math.nan, 0.05, deposit)
    maps = {"_x": x, "_y": y, "deposit": model}
    assert deposit_agreement(observation, maps)["deposit_overlap"] == 1.0
    assert residuals([observation], {}, maps).tolist() == [0.0]
    shifted = {**maps, "deposit": np.roll(model, 2, axis=1)}  # 2 of its 8 columns downstream
    overlap = deposit_agreement(observation, shifted)["deposit_overlap"]
    assert overlap == pytest.approx(36 / 60)
    assert residuals([observation], {}, shifted).tolist() == pytest.approx([(1 - overlap) / 0.05])
    with pytest.raises(ConfigError, match="no cell of the scene is covered"):
        read_deposit(path, 2, Grid2D.from_bounds(500.0, 600.0, 4, 0.0, 50.0, 4))


def test_numpy_inputs_run_and_write(truth: dict[str, Any], tmp_path: Path) -> None:
    """Observations, bounds, settings and tolerances given as numpy numbers and arrays (from
    Python) are taken as Python values: the calibration runs and its JSON file is written
    (a numpy setting used to fail there, after every member had run)."""
    observed = {"runout_length": np.float32(truth["summary"]["runout_length"])}
    result = calibrate(
        SCENE, observed, {"parameters.delta": np.array([20.0, 35.0])},
        settings={"n_cells": np.int64(200)}, tolerance={"runout_length": np.float64(0.3)},
        out=tmp_path / "calibration", options=OPTIONS, report=quiet,
    )  # fmt: skip
    assert abs(result.fitted["parameters.delta"] - TRUE_DELTA) < 0.1
    document = json.loads((tmp_path / "calibration" / "calibration.json").read_text())
    assert document["fitted"] == result.fitted
    assert result.observations[0].sigma == 0.3


def test_a_fit_that_cannot_reach_its_observation_says_so(tmp_path: Path) -> None:
    """A run-out of 5 (every member of delta in 20:30 runs out about 28): the best member sits
    against the bound 30 and misses by hundreds of standard errors; the notes say both (it
    exited 0 with ``success: true`` and no note)."""
    fit = calibrate(SCENE, {"runout_length": 5.0}, ["parameters.delta=20:30"],
                    settings={"n_cells": 100}, options={**OPTIONS, "plot": False},
                    out=tmp_path, report=quiet)  # fmt: skip
    notes = " | ".join(fit.notes)
    assert "sits against its bound 30" in notes or "at its bound 30" in notes, notes
    assert "misses the observations by" in notes and "standard errors" in notes, notes
    miss = float(notes.split("misses the observations by ")[1].split()[0])
    assert miss > 100, notes
    written = json.loads((tmp_path / "calibration.json").read_text())
    assert written["notes"] == fit.notes


def test_an_information_matrix_that_underflows_gives_infinite_errors() -> None:
    """Slopes of 1e-200 (a --tolerance of 1e308 makes them so): J^T J underflows to 0 and was
    a numpy LinAlgError traceback; the keys are then undetermined, with infinite errors."""
    from conslaw.ensemble.fitting import _covariance

    covariance = _covariance(np.array([[1e-200], [2e-200]]))
    assert np.isinf(covariance[0, 0])
    regular = _covariance(np.array([[1.0], [1.0]]))
    assert regular[0, 0] == pytest.approx(0.5)
