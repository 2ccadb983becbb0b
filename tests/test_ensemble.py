"""Ensembles (conslaw.ensemble, docs/ensembles.md): designs, members equal to single runs bit for
bit, nothing lost or duplicated when workers die or the study is interrupted, products."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import threading
from collections.abc import Iterator
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import conslaw
from conslaw.cli import main
from conslaw.ensemble import run_study
from conslaw.ensemble.dataset import read_dataset
from conslaw.ensemble.design import draw, parse_variation, unit_points
from conslaw.ensemble.engine import DaskEngine, LocalEngine, WorkerLostError
from conslaw.ensemble.member import MemberOutcome, MemberTask, run_member, state_digest
from conslaw.ensemble.products import exceedance, rank_correlations
from conslaw.ensemble.store import StudyFolder
from conslaw.ensemble.study import _execute
from conslaw.ensemble.summary import margins, member_summary
from conslaw.errors import ConfigError

SCENE = "sh-runout-shock"
VARY = [
    "parameters.delta=uniform:22:28",
    "parameters.phi=uniform:30:36",
    "initial.height=normal:2.2:0.1",
]
SMALL = {"n_cells": 100}


def _study(out: Path, samples: int = 8, **options: object) -> conslaw.ensemble.StudyResult:
    options.setdefault("workers", 2)
    return run_study(SCENE, VARY, samples, out, settings=SMALL, options=options, report=print)


def _member_overrides(dataset, index: int) -> dict[str, float]:
    varied = {
        dataset[name].attrs["scene_key"]: float(dataset[name][index])
        for name in dataset.data_vars
        if "scene_key" in dataset[name].attrs
    }
    return {**SMALL, **varied}


@pytest.fixture(autouse=True)
def _no_threads_left() -> Iterator[None]:
    """A study's local pool ends its threads in the background: wait for them, so that a later
    test in this process (the figure child forks only a single-threaded process) sees none."""
    before = set(threading.enumerate())
    yield
    for thread in set(threading.enumerate()) - before:
        with contextlib.suppress(RuntimeError):  # one still starting cannot be joined yet
            thread.join(2 if thread.daemon else 30)


# -- designs -----------------------------------------------------------------------------------


@settings(max_examples=40, deadline=None)
@given(
    samples=st.integers(1, 300),
    dimensions=st.integers(1, 5),
    seed=st.integers(0, 2**32 - 1),
)
def test_a_latin_hypercube_puts_one_member_in_every_bin_of_every_parameter(
    samples: int, dimensions: int, seed: int
) -> None:
    points = unit_points("lhs", samples, dimensions, seed)
    assert points.shape == (samples, dimensions)
    assert np.all((points > 0) & (points < 1))
    for column in points.T:
        bins = np.floor(column * samples).astype(int)
        assert sorted(bins) == list(range(samples))


@settings(max_examples=30, deadline=None)
@given(
    low=st.floats(-1e6, 1e6),
    width=st.floats(1e-6, 1e6),
    seed=st.integers(0, 1000),
    design=st.sampled_from(["lhs", "random", "sobol"]),
)
def test_uniform_members_stay_in_their_range_and_a_seed_repeats_them(
    low: float, width: float, seed: int, design: str
) -> None:
    variation = parse_variation(f"parameters.delta=uniform:{low!r}:{low + width!r}")
    first = draw([variation], design, 64, seed)
    assert np.array_equal(first, draw([variation], design, 64, seed))
    assert np.all((first >= low) & (first <= low + width))


def test_a_grid_takes_every_combination_of_bin_midpoints() -> None:
    values = draw(
        [parse_variation("a.b=uniform:0:3"), parse_variation("a.c=choice:1,2")], "grid", 4, 0
    )
    with pytest.raises(ConfigError, match="k\\^2 members"):
        draw([parse_variation("a.b=uniform:0:3"), parse_variation("a.c=uniform:0:1")], "grid", 5, 0)
    assert sorted(map(tuple, values)) == [(0.75, 1.0), (0.75, 2.0), (2.25, 1.0), (2.25, 2.0)]


def test_normal_members_have_the_asked_mean_and_spread() -> None:
    values = draw([parse_variation("initial.height=normal:2:0.1")], "lhs", 4000, 3)[:, 0]
    assert abs(values.mean() - 2.0) < 1e-3
    assert abs(values.std() - 0.1) < 1e-3


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("parameters.delta", "KEY=DISTRIBUTION:ARGS"),
        ("parameters.delta=gauss:1:2", "unknown distribution 'gauss'"),
        ("parameters.delta=uniform:30:20", "LOW < HIGH"),
        ("parameters.delta=uniform:1", "got 1 numbers"),
        ("parameters.delta=normal:1:0", "STD > 0"),
        ("parameters.delta=loguniform:0:2", "LOW = 0"),
        ("parameters.delta=uniform:a:b", "as numbers"),
        ("parameters.delta=uniform:1:inf", "finite"),
        ("parameters.delta=triangular:1:5:3", "LOW <= MODE <= HIGH"),
    ],
)
def test_a_bad_variation_is_one_line_naming_it(text: str, words: str) -> None:
    with pytest.raises(ConfigError, match=words.replace("^", "\\^").replace("(", "\\(")):
        parse_variation(text)


def test_a_sobol_design_needs_a_power_of_two() -> None:
    with pytest.raises(ConfigError, match=r"power of 2.*64 or 128"):
        unit_points("sobol", 100, 2, 0)


# -- summary figures ---------------------------------------------------------------------------


def test_margins_are_the_interpolated_crossings_of_the_covered_depth() -> None:
    x = np.arange(6.0)
    h = np.array([0.0, 1.0, 3.0, 3.0, 2.0, 0.0])
    front, rear = margins(x, h, 1.0)
    assert front == 4.5  # 2 at x = 4, 0 at x = 5: 1 is crossed halfway
    assert rear == 1.0  # 1 at x = 1 is not above 1; 3 at x = 2 falls to 1 at x = 1
    assert margins(x, np.ones(6), 0.5) == (5.0, 0.0)  # covered to both ends


def test_the_travel_angle_is_measured_on_the_chute() -> None:
    from scipy.integrate import quad

    result = conslaw.run(SCENE, n_cells=100)
    summary = member_summary(result)
    chute = result.model.chute
    top = margins(result.grid.centres(), result.initial.q[0], 1e-3 * result.initial.q[0].max())[1]
    # Along the bed: dX = cos(zeta) dx, dZ = -sin(zeta) dx (the transition's ends as breaks).
    breaks = [21.5, 25.5]
    length = quad(lambda x: np.cos(chute.zeta(np.array([x]))[0]), top, summary["front"],
                  points=breaks, limit=200)[0]  # fmt: skip
    drop = quad(lambda x: np.sin(chute.zeta(np.array([x]))[0]), top, summary["front"],
                points=breaks, limit=200)[0]  # fmt: skip
    assert summary["runout_length"] == pytest.approx(length, rel=1e-6)
    assert summary["drop"] == pytest.approx(drop, rel=1e-6)
    assert summary["travel_angle"] == pytest.approx(np.degrees(np.arctan2(drop, length)), rel=1e-6)
    assert summary["mass_drift"] == float(result.mass_drift[0])


# -- members equal single runs; failures recorded --------------------------------------------


def test_members_equal_the_same_scenes_run_one_by_one(tmp_path: Path) -> None:
    study = _study(tmp_path / "study")
    dataset = study.dataset
    assert list(dataset.status.values) == ["finished"] * 8
    for index in (0, 5):
        overrides = _member_overrides(dataset, index)
        single = conslaw.run(SCENE, **{k.replace(".", "__"): v for k, v in overrides.items()})
        assert state_digest(single.states[-1].q) == dataset.digest.values[index]
        summary = member_summary(single)
        for name, value in summary.items():
            if name != "solve_seconds":
                np.testing.assert_equal(float(dataset[name][index]), value)
    stored = read_dataset(study.path)
    assert stored.drop_vars("wall_seconds").equals(dataset.drop_vars("wall_seconds"))


def test_a_member_through_conslaw_run_has_the_same_final_state(tmp_path: Path) -> None:
    task = MemberTask(0, SCENE, {"n_cells": 100, "parameters.delta": 25.123456789012345})
    outcome = run_member(task)
    code = main(
        [
            "run", SCENE, "--set", "n_cells=100", "--set", "parameters.delta=25.123456789012345",
            "--out", str(tmp_path / "run"), "--no-plot",
        ]
    )  # fmt: skip
    assert code == 0
    with np.load(tmp_path / "run" / "states.npz") as states:
        final = states["q"][-1]
    assert state_digest(final) == outcome.digest


def test_a_failed_member_is_recorded_and_the_study_goes_on(tmp_path: Path) -> None:
    study = run_study(
        SCENE, ["max_steps=choice:5,100000"], 4, tmp_path / "s", settings=SMALL,
        options={"workers": 2}, report=print,
    )  # fmt: skip
    dataset = study.dataset
    limited = dataset.max_steps.values == 5
    assert limited.any() and (~limited).any()
    assert set(dataset.status.values[limited]) == {"step-limit"}
    assert all("max_steps" in text for text in dataset.message.values[limited])
    assert set(dataset.status.values[~limited]) == {"finished"}
    assert np.all(np.isnan(dataset.front.values[limited]))


def test_a_member_that_cannot_run_is_refused_before_anything_runs(tmp_path: Path) -> None:
    out = tmp_path / "s"
    with pytest.raises(ConfigError, match=r"member \d+ \(parameters\.delta=.*must be <= .*phi"):
        run_study(SCENE, ["parameters.delta=uniform:25:40"], 8, out, report=print)
    assert not out.exists()


def test_the_command_line_refuses_a_bad_member_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["ensemble", SCENE, "--vary", "parameters.delta=uniform:25:40", "--samples", "4"]
    code = main([*argv, "--out", str(tmp_path / "s")])
    lines = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "member" in lines[0] and "phi" in lines[0]
    code = main(["ensemble", SCENE, "--vary", "nope=uniform:1:2", "--samples", "2"])
    lines = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "nope" in lines[0]


# -- the folder: one study, resumed only as itself ---------------------------------------------


def test_a_folder_holds_one_study(tmp_path: Path) -> None:
    out = tmp_path / "s"
    _study(out, samples=2)
    with pytest.raises(ConfigError, match="holds a study already: add --resume"):
        _study(out, samples=2)
    with pytest.raises(ConfigError, match="asked differently \\(samples: 2 there, 3 now\\)"):
        _study(out, samples=3, resume=True)
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "notes.txt").write_text("mine")
    with pytest.raises(ConfigError, match="not empty and holds no study"):
        _study(tmp_path / "other", samples=2)
    with pytest.raises(ConfigError, match="no study in"):
        _study(tmp_path / "empty", samples=2, resume=True)


def test_a_study_being_written_is_not_entered_by_another(tmp_path: Path) -> None:
    from conslaw.ensemble.store import StudyFolder, StudySpec

    spec = StudySpec(SCENE, {}, [], "lhs", 2, 0)
    first = StudyFolder(tmp_path / "s")
    first.open(spec, resume=False)
    try:
        with pytest.raises(ConfigError, match="being written by another conslaw study"):
            StudyFolder(tmp_path / "s").open(spec, resume=True)
    finally:
        first.close()


def test_a_journal_line_cut_short_is_dropped_and_the_member_run_again(tmp_path: Path) -> None:
    out = tmp_path / "s"
    whole = _study(out, samples=4)
    journal = out / "members.jsonl"
    lines = journal.read_bytes().splitlines(keepends=True)
    journal.write_bytes(b"".join(lines[:2]) + lines[2][:25])  # a process killed mid-line
    resumed = _study(out, samples=4, resume=True)
    assert resumed.ran == 2
    kept = [json.loads(line)["member"] for line in journal.read_text().splitlines()]
    assert sorted(kept) == [0, 1, 2, 3]
    columns = ["digest", "status", "front", "travel_angle"]
    assert resumed.dataset[columns].equals(whole.dataset[columns])


# -- interruptions and dead workers ------------------------------------------------------------


def _journal_lines(path: Path) -> int:
    return path.read_bytes().count(b"\n") if path.exists() else 0


INTERRUPTED_STUDY = """
import os, signal, sys
from conslaw.cli import console_main
from conslaw.ensemble.store import StudyFolder

record = StudyFolder.record
kept = []

def record_then_interrupt(self, outcome):
    record(self, outcome)
    kept.append(outcome.index)
    if len(kept) == {at}:
        os.kill(os.getpid(), signal.SIGINT)  # as Ctrl-C would, once this many are kept

StudyFolder.record = record_then_interrupt
sys.argv = ["conslaw", *{argv!r}]
sys.exit(console_main())
"""


def test_an_interrupted_study_resumed_equals_an_uninterrupted_one(tmp_path: Path) -> None:
    """A SIGINT once half the members are kept (sent by the study's process to itself when it
    keeps that member: counted, not timed, so the study cannot finish first on a fast machine
    or a slow poller), then ``--resume``: the dataset of an uninterrupted study."""
    samples = 120
    argv = [
        "ensemble", SCENE, "--samples", str(samples),
        "--set", "n_cells=100", "--workers", "2", "--no-plot",
        *[item for text in VARY for item in ("--vary", text)],
    ]  # fmt: skip
    out = tmp_path / "interrupted"
    script = INTERRUPTED_STUDY.format(at=samples // 2, argv=[*argv, "--out", str(out)])
    child = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    error = child.stderr
    assert child.returncode == 130, error
    assert error.strip().startswith("conslaw: interrupted:") and len(error.splitlines()) == 1
    argv = [sys.executable, "-m", "conslaw", *argv]
    partial = read_dataset(out / "study.nc")
    kept = int((partial.status.values != "pending").sum())
    assert samples // 2 <= kept < samples, kept
    assert kept == _journal_lines(out / "members.jsonl")
    resumed = subprocess.run([*argv, "--out", str(out), "--resume"], capture_output=True)
    assert resumed.returncode == 0, resumed.stderr
    straight = subprocess.run([*argv, "--out", str(tmp_path / "straight")], capture_output=True)
    assert straight.returncode == 0, straight.stderr
    ignore = ["wall_seconds", "worker", "solve_seconds"]
    finished = read_dataset(out / "study.nc").drop_vars(ignore)
    assert finished.identical(read_dataset(tmp_path / "straight" / "study.nc").drop_vars(ignore))
    assert sorted(json.loads(x)["member"] for x in (out / "members.jsonl").open()) == list(
        range(samples)
    )


def _kill_a_worker_at(lines: int, killed: list[int]) -> None:
    """Make the study folder, once it has kept ``lines`` members, SIGKILL the worker process
    that ran the last (counted by the study's own journal writes, not timed: the study cannot
    finish first). For the test's duration, or a child process's."""
    record = StudyFolder.record
    kept: list[int] = []

    def record_then_kill(self: StudyFolder, outcome: MemberOutcome) -> None:
        record(self, outcome)
        kept.append(outcome.index)
        if len(kept) == lines:
            pid = int(outcome.worker.rsplit(":", 1)[1])
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    StudyFolder.record = record_then_kill  # type: ignore[method-assign]


def test_a_local_worker_killed_mid_study_loses_and_repeats_no_member(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    reference = _study(tmp_path / "reference", samples=60)
    out = tmp_path / "s"
    killed: list[int] = []
    monkeypatch.setattr(StudyFolder, "record", StudyFolder.record)  # put back after the test
    _kill_a_worker_at(10, killed)
    study = _study(out, samples=60)
    assert killed
    indices = [json.loads(line)["member"] for line in (out / "members.jsonl").open()]
    assert sorted(indices) == list(range(60))
    assert list(study.dataset.status.values) == ["finished"] * 60
    assert list(study.dataset.digest.values) == list(reference.dataset.digest.values)


DASK_STUDY = """
import sys
from pathlib import Path
import distributed
from conslaw.ensemble import run_study
sys.path.insert(0, {tests!r})
from test_ensemble import SCENE, SMALL, VARY, _kill_a_worker_at

if __name__ == "__main__":
    out = Path({out!r})
    killed = []
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        _kill_a_worker_at(10, killed)
        run_study(
            SCENE, VARY, 50, out, settings=SMALL,
            options={{"scheduler": cluster.scheduler_address}}, report=print,
        )
    print("killed", killed)
"""


def test_a_dask_cluster_runs_the_study_and_a_killed_worker_loses_nothing(tmp_path: Path) -> None:
    """In a process of its own: Dask leaves threads running in the process that used it."""
    pytest.importorskip("distributed")
    reference = _study(tmp_path / "reference", samples=50)
    out = tmp_path / "dask"
    script = DASK_STUDY.format(tests=str(Path(__file__).parent), out=str(out))
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "killed [" in done.stdout and "killed []" not in done.stdout
    indices = [json.loads(line)["member"] for line in (out / "members.jsonl").open()]
    assert sorted(indices) == list(range(50))
    dataset = read_dataset(out / "study.nc")
    assert list(dataset.status.values) == ["finished"] * 50
    assert list(dataset.digest.values) == list(reference.dataset.digest.values)
    assert len(set(dataset.worker.values)) >= 2


# -- products ----------------------------------------------------------------------------------


def test_exceedance_and_rank_correlations(tmp_path: Path) -> None:
    study = _study(tmp_path / "s", samples=12, fields=True)
    dataset = study.dataset
    probability = exceedance(dataset, "max_depth", 0.5)
    expected = (dataset.max_depth.values > 0.5).mean(axis=0)
    np.testing.assert_array_equal(probability.values, expected)
    assert probability.attrs["members"] == 12
    correlations = rank_correlations(dataset)
    # Higher bed friction stops the mass earlier: the run-out falls, the travel angle rises.
    assert float(correlations.sel(figure="runout_length", parameter="delta")) < -0.8
    assert float(correlations.sel(figure="travel_angle", parameter="delta")) > 0.8
    with pytest.raises(ConfigError, match="not a map of this study"):
        exceedance(dataset, "peak_speed", 1.0)


ZARR_STUDY = """
import sys
import numpy as np
from conslaw.ensemble import run_study
from conslaw.ensemble.dataset import read_dataset

if __name__ == "__main__":
    study = run_study(
        "sh-runout-shock", ["parameters.delta=uniform:22:28"], 6, sys.argv[1],
        settings={"n_cells": 100}, options={"workers": 2, "fields": True, "format": "zarr"},
    )
    stored = read_dataset(study.path)
    assert study.path.name == "study.zarr", study.path
    assert stored.drop_vars("wall_seconds").equals(study.dataset.drop_vars("wall_seconds"))
    assert stored.max_depth.shape == (6, 100)
    print("zarr round trip equal")
"""


def test_a_zarr_dataset_reads_back_equal(tmp_path: Path) -> None:
    """In a process of its own: zarr keeps I/O threads running in the process that used it."""
    pytest.importorskip("zarr")
    done = subprocess.run(
        [sys.executable, "-c", ZARR_STUDY, str(tmp_path / "s")], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert "zarr round trip equal" in done.stdout


def test_a_study_on_terrain_keeps_the_hazard_figures_and_maps(tmp_path: Path) -> None:
    settings = {"n_cells": [40, 20], "t_end": 20.0, "output_times": [20.0]}
    study = run_study(
        "terrain-plane-to-flat", ["parameters.delta=uniform:24:30"], 2, tmp_path / "s",
        settings=settings, options={"workers": 2, "fields": True}, report=print,
    )  # fmt: skip
    dataset = study.dataset
    assert list(dataset.status.values) == ["finished"] * 2
    assert dataset.peak_depth.dims == ("member", "y", "x")
    assert dataset.peak_depth.shape == (2, 20, 40)
    # The hazard figures are those of the same run's hazard maps.
    from conslaw.terrain.hazard_maps import hazard_maps

    overrides = {**settings, "parameters.delta": float(dataset.delta[1])}
    single = conslaw.run_2d(
        "terrain-plane-to-flat", **{k.replace(".", "__"): v for k, v in overrides.items()}
    )
    maps = hazard_maps(single)
    assert maps is not None
    assert float(dataset.travel_angle[1]) == maps.summary["travel_angle_deg"]
    np.testing.assert_array_equal(dataset.peak_depth.values[1], single.peaks.depth)
    probability = exceedance(dataset, "peak_depth", 0.5)
    assert probability.dims == ("y", "x")
    assert set(np.unique(probability.values)) <= {0.0, 0.5, 1.0}


def test_every_summary_figure_and_map_is_documented() -> None:
    from conslaw.ensemble.summary import FIELD_NAMES, SUMMARY_1D, SUMMARY_2D

    text = (Path(__file__).parents[1] / "docs" / "ensembles.md").read_text()
    names = [*SUMMARY_1D, *SUMMARY_2D, *FIELD_NAMES[1], *FIELD_NAMES[2]]
    assert [name for name in names if f"`{name}`" not in text] == []


# -- the scheduling of members, with engines that lose workers on purpose ----------------------


class _PoisonedPool(LocalEngine):
    """A local engine without processes: a batch holding ``poison`` kills "its worker", and
    with it every batch in flight, as a real process pool breaks."""

    def __init__(self, poison: int) -> None:
        super().__init__(2)
        self.poison = poison
        self.flying: list[tuple[Future[Any], list[MemberTask]]] = []
        self.restarts = 0

    def start(self) -> None:
        pass

    def submit_batch(self, tasks: list[MemberTask]) -> Future[Any]:
        future: Future[Any] = Future()
        self.flying.append((future, tasks))
        return future

    def wait_any(self, futures: Any) -> set[Any]:
        broken = any(self.poison in [t.index for t in tasks] for _, tasks in self.flying)
        for future, tasks in self.flying:
            if broken:
                future.set_exception(BrokenProcessPool("a worker died"))
            else:
                future.set_result([_fake_outcome(task) for task in tasks])
        self.flying = []
        return set(futures)

    def restart(self) -> None:
        self.restarts += 1


class _PoisonedCluster(DaskEngine):
    """A Dask engine without a cluster: the scheduler gives up on a task holding ``poison``."""

    def __init__(self, poison: int) -> None:
        super().__init__("tcp://nowhere:1")
        self.poison = poison

    def start(self) -> None:
        pass

    def capacity(self) -> int:
        return 2

    def submit_batch(self, tasks: list[MemberTask]) -> Any:
        future: Future[Any] = Future()
        if self.poison in [task.index for task in tasks]:
            future.set_exception(WorkerLostError("its workers died while running it"))
        else:
            future.set_result([_fake_outcome(task) for task in tasks])
        return future

    def wait_any(self, futures: Any) -> set[Any]:
        return set(futures)

    def outcome(self, future: Any) -> Any:
        return future.result()


def _fake_outcome(task: MemberTask) -> MemberOutcome:
    return MemberOutcome(task.index, "finished", "", {}, "d", 0.001, "fake:1")


@pytest.mark.parametrize("engine_class", [_PoisonedPool, _PoisonedCluster])
@pytest.mark.parametrize("poison", [0, 7, 39])
def test_a_member_that_kills_its_worker_is_failed_alone_and_the_rest_finish(
    engine_class: type, poison: int
) -> None:
    tasks = [MemberTask(index, SCENE, {}) for index in range(40)]
    kept: list[MemberOutcome] = []
    _execute(engine_class(poison), tasks, kept.append)
    assert sorted(outcome.index for outcome in kept) == list(range(40))
    failed = [outcome for outcome in kept if outcome.status != "finished"]
    assert [outcome.index for outcome in failed] == [poison]
    assert "died" in failed[0].message


def test_a_member_whose_initial_state_cannot_be_built_is_refused_first(tmp_path: Path) -> None:
    out = tmp_path / "s"
    with pytest.raises(ConfigError, match=r"member \d+ \(initial\.height=-.*height >= 0"):
        run_study(SCENE, ["initial.height=uniform:-0.5:2"], 8, out, settings=SMALL, report=print)
    assert not out.exists()


def test_an_unexpected_error_in_a_member_is_that_member_s_failure(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import conslaw.simulation

    def broken(*args: Any, **kwargs: Any) -> Any:
        raise RuntimeError("a bug")

    monkeypatch.setattr(conslaw.simulation, "simulate", broken)
    outcome = run_member(MemberTask(3, SCENE, SMALL))
    assert (outcome.index, outcome.status, outcome.message) == (3, "failed", "RuntimeError: a bug")


def test_a_release_against_the_boundary_is_not_a_run_out_cut_short() -> None:
    result = conslaw.run("sh-dam-break-incline")
    assert result.initial.q[0][0] > 0  # the reservoir fills the upslope end cell
    assert member_summary(result)["at_boundary"] == 0.0
    short = conslaw.run(SCENE, n_cells=100, x_max=20.0, parameters__zeta_end=40.0)
    assert member_summary(short)["at_boundary"] == 1.0


def test_a_resumed_study_whose_scene_file_changed_is_refused(tmp_path: Path) -> None:
    from conslaw import registry

    scene = tmp_path / "mine.toml"
    scene.write_text(registry.scenes.get(SCENE).read_text())
    out = tmp_path / "s"
    run_study(scene, VARY[:1], 2, out, settings=SMALL, options={"workers": 1}, report=print)
    scene.write_text(scene.read_text().replace("zeta = 40.0", "zeta = 35.0"))
    with pytest.raises(ConfigError, match="asked differently \\(scene_sha256"):
        run_study(scene, VARY[:1], 2, out, settings=SMALL, options={"resume": True}, report=print)


@pytest.mark.parametrize(
    ("arguments", "words"),
    [
        (["--threshold", "max_depth=1"], "add --fields"),
        (["--fields", "--threshold", "peak_depth=1"], "not a map of this scene's members"),
        (["--fields", "--threshold", "max_depth=nan"], "a finite number"),
        (["--fields", "--threshold", "max_depth=1", "--threshold", "max_depth=2"], "twice"),
        (["--depth-threshold", "-1"], "--depth-threshold: expected a number >= 0"),
    ],
)
def test_bad_study_options_are_refused_before_anything_runs(
    arguments: list[str], words: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "s"
    argv = ["ensemble", SCENE, "--vary", VARY[0], "--samples", "2", "--out", str(out)]
    assert main([*argv, *arguments]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], lines
    assert not out.exists()


def test_the_dataset_is_rewritten_as_members_arrive(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import conslaw.ensemble.study as study_module

    written: list[int] = []
    write = study_module.write_dataset

    def counted(dataset: Any, folder: Path, file_format: str) -> Path:
        written.append(int((dataset.status.values != "pending").sum()))
        return write(dataset, folder, file_format)

    monkeypatch.setattr(study_module, "DATASET_SECONDS", 0.0)
    monkeypatch.setattr(study_module, "write_dataset", counted)
    _study(tmp_path / "s", samples=6)
    # At least once before the end with fewer members (the first member kept writes it).
    assert written[-1] == 6 and len(written) >= 2
    assert written[0] < 6 and written == sorted(written)


def test_the_largest_seed_draws_runs_and_is_kept_exactly(tmp_path: Path) -> None:
    """A 64-bit seed runs, is written to ``study.nc`` (as text: netCDF 3 attributes hold 32
    bits; 2**31 crashed the writer after every member ran) and resumes."""
    seed = 2**64 - 1
    out = tmp_path / "s"
    study = run_study(SCENE, VARY[:1], 2, out, seed=seed, settings=SMALL,
                      options={"workers": 1}, report=print)  # fmt: skip
    assert read_dataset(out / "study.nc").attrs["seed"] == str(seed)
    assert list(study.dataset.status.values) == ["finished"] * 2
    again = run_study(SCENE, VARY[:1], 2, out, seed=seed, settings=SMALL,
                      options={"workers": 1, "resume": True}, report=print)  # fmt: skip
    assert again.ran == 0


def test_workers_are_capped_by_the_cores_and_the_members(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--workers 1000`` on a 2-member study started 227 processes in 147 s and finished no
    member: at most one worker per core and per member starts, and the study says so."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    assert LocalEngine(1000, members=4).workers == min(cores or 1, 4)
    assert LocalEngine(1000, members=1).workers == 1
    assert LocalEngine(1, members=100).note is None
    assert LocalEngine(members=1).workers == 1  # the default too, without a note
    for bad in ("2", 2.0, True, 0):
        with pytest.raises(ConfigError, match="--workers: expected an integer >= 1"):
            LocalEngine(bad)  # type: ignore[arg-type]
    out = tmp_path / "s"
    argv = ["ensemble", SCENE, "--vary", VARY[0], "--samples", "2", "--set", "n_cells=50"]
    assert main([*argv, "--workers", "1000", "--out", str(out), "--no-plot"]) == 0
    printed = capsys.readouterr().out
    started = min(cores or 1, 2)
    assert f"--workers 1000: starting {started}, at most one per core" in printed, printed
    assert "one per member (2)" in printed and f"on {started} workers" in printed, printed
