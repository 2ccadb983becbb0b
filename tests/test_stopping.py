"""Ending a 2D run when its material is at rest (conslaw.stopping; docs/terrain.md, "Stopping at
rest"): a release that comes to rest ends within one output interval of the time it does, with
the states of the run without the rule up to there; a flow that never rests runs to t_end; the
CLI summary and the outputs say which."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conslaw.cli import main
from conslaw.result2d import RunResult2D
from conslaw.scene2d import load_scene_2d
from conslaw.simulation2d import run_2d

#: terrain-plane-to-flat, coarse and shortened: the release runs onto the flat and stops
#: (at rest after about 31 s at these cells; the scene's own t_end is 60 s).
PLANE_TO_FLAT: dict[str, Any] = {"n_cells": [50, 25], "t_end": 40.0, "output_times": []}

#: A release on a 35-degree plane with delta = 20 degrees, periodic on every side: gravity
#: outweighs friction everywhere, so it speeds up for ever.
NEVER_RESTS: dict[str, Any] = {
    "n_cells": [40, 20], "x_min": 0.0, "x_max": 400.0, "y_min": -100.0, "y_max": 100.0,
    "t_end": 20.0, "output_times": [], "output_interval": 5.0,
    "parameters.terrain": "plane", "parameters.zeta": 35.0, "parameters.delta": 20.0,
    "boundary.left": "periodic", "boundary.right": "periodic",
    "boundary.bottom": "periodic", "boundary.top": "periodic",
    "initial.polygon": [[50.0, -30.0], [110.0, -30.0], [110.0, 30.0], [50.0, 30.0]],
}  # fmt: skip


def kinetic_energies(result: RunResult2D) -> list[float]:
    """``1/2 sum H |u|^2 dx dy`` at every output time, from the model's depth and speed."""
    assert result.peaks is not None
    energies = []
    for state in result.states:
        fields = result.model.flow_depth_and_speed(state.q, result.peaks.aux)
        assert fields is not None
        energies.append(0.5 * float(np.sum(state.q[0] * fields[1] ** 2)) * result.grid.cell_area)
    return energies


def first_rest(result: RunResult2D, fraction: float) -> float:
    """The first output time t > 0 of a run without the rule at which every momentum is 0 or
    the kinetic energy is at most ``fraction`` of the largest at the outputs so far."""
    peak = 0.0
    for state, energy in zip(result.states, kinetic_energies(result), strict=True):
        peak = max(peak, energy)
        if state.t > 0.0 and (not np.any(state.q[1:]) or energy <= fraction * peak):
            return state.t
    raise AssertionError("the material never came to rest")


def test_terrain_scenes_stop_at_rest_by_default_and_others_do_not() -> None:
    for name in ("terrain-plane-to-flat", "terrain-bowl", "terrain-channel"):
        rule = load_scene_2d(name).stop
        assert rule.at_rest and rule.energy_fraction == 0.01, name
    for name in ("sw2d-dam-break-x", "sh2d-runout", "burgers2d-shock"):
        assert not load_scene_2d(name).stop.at_rest, name
    assert load_scene_2d("sh2d-runout", {"stop.at_rest": True}).stop.at_rest
    assert not load_scene_2d("terrain-bowl", {"stop.at_rest": False}).stop.at_rest


def test_a_release_stops_within_one_output_interval_of_rest() -> None:
    """The rest time measured independently on the run without the rule, every 0.5 s (first
    output at which the energy rule holds); the run with the rule, every 4 s, ends at the
    first output of its own at or after that time (up to the 0.5 s sampling of the measure),
    less than one output interval later, with the states of the run without the rule."""
    fine = run_2d("terrain-plane-to-flat", **PLANE_TO_FLAT, output_interval=0.5,
                  **{"stop.at_rest": False})  # fmt: skip
    assert fine.stop is None and fine.final.t == 40.0
    rest = first_rest(fine, 0.01)
    interval = 4.0
    coarse = {**PLANE_TO_FLAT, "output_interval": interval}
    stopped = run_2d("terrain-plane-to-flat", **coarse)
    record = stopped.stop
    assert record is not None and record.stopped and record.at_rest
    assert record.t == stopped.final.t < 40.0
    assert rest - 0.5 <= record.t < rest + interval, (rest, record.t)
    assert record.rest_since is not None and record.rest_since <= record.t
    assert record.fraction <= 0.01
    # the rule changes no time step: the states up to the stop are the full run's, bit for bit
    full = run_2d("terrain-plane-to-flat", **coarse, **{"stop.at_rest": False})
    assert full.final.t == 40.0 and len(full.states) > len(stopped.states)
    for mine, theirs in zip(stopped.states, full.states, strict=False):
        assert mine.t == theirs.t and np.array_equal(mine.q, theirs.q)
    # and its peak fields are those of the full run up to then (hazard maps at the stop)
    assert stopped.peaks is not None and full.peaks is not None
    assert np.all(stopped.peaks.depth <= full.peaks.depth)


def test_energy_fraction_zero_waits_for_every_cell_held() -> None:
    """With energy_fraction = 0 only the exact rest counts: friction holds every cell (at
    these finer cells by about 38 s; at 50 x 25 cells a few creep on past 80 s)."""
    result = run_2d("terrain-plane-to-flat", n_cells=[100, 50], output_times=[],
                    output_interval=4.0, **{"stop.energy_fraction": 0.0})  # fmt: skip
    record = result.stop
    assert record is not None and record.stopped and record.held and record.t < 60.0
    assert record.energy == 0.0 and not np.any(result.final.q[1:])
    assert np.any(result.states[-2].q[1:])  # it stops at the first output that is held
    assert record.rest_since is not None and record.t - 4.0 < record.rest_since <= record.t
    assert "every momentum 0" in record.summary()


def test_a_flow_that_never_rests_runs_to_t_end() -> None:
    result = run_2d("terrain-plane-to-flat", **NEVER_RESTS)
    record = result.stop
    assert record is not None and not record.stopped and not record.at_rest
    assert record.t == result.final.t == 20.0 and record.rest_since is None
    energies = kinetic_energies(result)
    assert energies[-1] == max(energies) > 0.0  # speeding up to the end
    assert record.summary().startswith("ran to t_end = 20, still moving")


def run_cli(args: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """``conslaw run`` in process; its standard output (exit code 0)."""
    code = main(["run", *args, "--quiet"])
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


def settings(overrides: dict[str, Any]) -> list[str]:
    """``--set key=value`` arguments (values as TOML)."""
    args = []
    for key, value in overrides.items():
        args += ["--set", f"{key}={json.dumps(value)}"]
    return args


def test_the_cli_and_the_outputs_say_how_the_run_ended(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "stopped"
    overrides = {**PLANE_TO_FLAT, "output_interval": 4.0, "output.plot": False}
    text = run_cli(["terrain-plane-to-flat", *settings(overrides), "--out", str(out)], capsys)
    line = next(line for line in text.splitlines() if "stopped at rest" in line)
    assert "stopped at rest at t = 32 (kinetic energy" in line and "of its peak" in line
    with np.load(out / "states.npz") as data:
        record = json.loads(str(data["stop"]))
        assert data["t"][-1] == record["t"] == 32.0
    assert record["stopped_at_rest"] and record["t_end"] == 40.0
    assert record["kinetic_energy_fraction"] <= record["energy_fraction"] == 0.01
    hazard = json.loads((out / "hazard.json").read_text())
    assert hazard["stop"] == record and hazard["t_end"] == 32.0
    assert (out / "deposit.tif").exists() and (out / "peak_speed.tif").exists()
    assert "[stop]\nat_rest = true\nenergy_fraction = 0.01" in (out / "scene.toml").read_text()

    moving = tmp_path / "moving"
    overrides = {**NEVER_RESTS, "output.plot": False}
    text = run_cli(["terrain-plane-to-flat", *settings(overrides), "--out", str(moving)], capsys)
    assert "  ran to t_end = 20, still moving (kinetic energy 1 of its peak" in text
    with np.load(moving / "states.npz") as data:
        record = json.loads(str(data["stop"]))
    assert not record["stopped_at_rest"] and record["t"] == 20.0
    assert json.loads((moving / "hazard.json").read_text())["stop"] == record


def test_a_run_without_the_rule_records_none(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    overrides = {**PLANE_TO_FLAT, "t_end": 4.0, "stop.at_rest": False, "output.plot": False}
    text = run_cli(["terrain-plane-to-flat", *settings(overrides), "--out", str(tmp_path)], capsys)
    assert "stopped at rest" not in text and "ran to t_end" not in text
    with np.load(tmp_path / "states.npz") as data:
        assert "stop" not in data.files
    assert "stop" not in json.loads((tmp_path / "hazard.json").read_text())
