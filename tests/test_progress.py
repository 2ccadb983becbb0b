"""Progress output (conslaw.progress, docs/cli.md "Progress"): the lines written without a
terminal, the bar on one, the lines of studies and calibrations, ``--quiet``.

No test waits for or measures wall time: the interval is set to 0 s by
``CONSLAW_PROGRESS_SECONDS`` (every report writes a line) or the clock is a fake one.
"""

from __future__ import annotations

import io
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conslaw import progress
from conslaw.errors import ConfigError
from conslaw.progress import CountProgress, RunProgress

CONSLAW = shutil.which("conslaw") or ""
#: A 1D scene whose run takes about a second once its kernels are cached.
SMALL_RUN = ["sh-runout-shock", "--no-plot"]


class FakeClock:
    """Wall seconds that move only when a test says so."""

    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


class Terminal(io.StringIO):
    """A stream that says it is a terminal (a fake ``isatty``)."""

    def isatty(self) -> bool:
        return True


def test_without_a_terminal_a_line_every_interval(monkeypatch: pytest.MonkeyPatch) -> None:
    """Reports come every step pair; a line is written when the interval has passed since the
    last one (fake clock), with model time, percent, steps, dt and the estimate; the estimate
    says "estimating" until it means something."""
    monkeypatch.delenv(progress.SECONDS_VARIABLE, raising=False)
    clock, stream = FakeClock(), io.StringIO()
    bar = RunProgress(150.0, stream, clock=clock)
    assert not bar.terminal and bar.interval == progress.LINE_SECONDS
    bar(0.5, 2)  # the first report starts the clock
    clock.now += progress.LINE_SECONDS - 0.5
    bar(1.0, 4)
    assert stream.getvalue() == ""
    clock.now += 0.5
    bar(1.1, 6)
    clock.now += 1.0
    bar(1.2, 8)
    clock.now += progress.LINE_SECONDS
    bar(15.5, 100)
    lines = stream.getvalue().splitlines()
    assert lines == [
        "conslaw: t=1.1 of 150 (0.7%), 6 steps, dt=0.05, 10.0 s elapsed, estimating time left",
        "conslaw: t=15.5 of 150 (10.3%), 100 steps, dt=0.155, 21.0 s elapsed, "
        "about 3 min 08 s left",
    ]


def test_moving_cells_are_counted_when_a_line_is_written(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(progress.SECONDS_VARIABLE, "0")
    clock, stream = FakeClock(), io.StringIO()
    counted = []
    bar = RunProgress(2.0, stream, clock=clock)
    bar(0.5, 10)
    bar.moving = lambda: counted.append(1) or 42
    bar(1.0, 20)
    lines = stream.getvalue().splitlines()
    assert "moving" not in lines[0] and ", 42 moving cells, " in lines[1], lines
    assert counted == [1]


@pytest.mark.parametrize(("text", "ok"), [("0", True), ("2.5", True), ("-1", False), ("x", False)])
def test_the_interval_variable(monkeypatch: pytest.MonkeyPatch, text: str, ok: bool) -> None:
    monkeypatch.setenv(progress.SECONDS_VARIABLE, text)
    if ok:
        assert progress.line_seconds() == float(text)
    else:
        with pytest.raises(ConfigError, match="CONSLAW_PROGRESS_SECONDS"):
            progress.line_seconds()


def test_on_a_terminal_a_bar_with_the_time_left(monkeypatch: pytest.MonkeyPatch) -> None:
    """A fake ``isatty``: the bar is drawn at the first report, then at most every
    BAR_SECONDS and always at t_end; it says the time left and is ended by a new line."""
    monkeypatch.setenv(progress.SECONDS_VARIABLE, "0")  # lines only: the bar keeps its pace
    clock, stream = FakeClock(), Terminal()
    bar = RunProgress(10.0, stream, clock=clock)
    assert bar.terminal and bar.interval == progress.BAR_SECONDS
    bar(0.1, 2)
    clock.now += progress.BAR_SECONDS / 2
    bar(0.2, 4)  # not due
    clock.now += 3.0
    bar(5.0, 100)
    bar(10.0, 200)  # the end: drawn although not due
    bar.close()
    drawn = stream.getvalue()
    assert drawn.startswith("\r") and drawn.endswith("\n") and "conslaw:" not in drawn
    frames = [frame.rstrip() for frame in drawn[1:-1].split("\r")]
    assert frames == [
        "[..............................] t=0.1 steps=2, estimating time left",
        "[###############...............] t=5 steps=100, about 3.1 s left",
        "[##############################] t=10 steps=200, done",
    ]
    padded = drawn[1:-1].split("\r")
    assert len(padded[2]) >= len(frames[1])  # a shorter bar covers the longer one before it


def test_quiet_writes_nothing_but_still_checks(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(progress.SECONDS_VARIABLE, "not read when quiet")
    checks = []
    for stream in (io.StringIO(), Terminal()):
        bar = RunProgress(1.0, stream, show=False, check=lambda: checks.append(1))
        bar(0.5, 2)
        bar(1.0, 4)
        bar.close()
        assert stream.getvalue() == ""
    assert len(checks) == 4


def test_durations_and_estimates() -> None:
    assert progress.duration(4.24) == "4.2 s"
    assert progress.duration(185.0) == "3 min 05 s"
    assert progress.duration(7620.0) == "2 h 07 min"
    assert progress.time_left(1.0, 1.0, 1.0) == "estimating time left"  # too early
    assert progress.time_left(0.001, 1.0, 60.0) == "estimating time left"  # too little done
    assert progress.time_left(1.0, 3.0, 10.0) == "about 30.0 s left"
    assert progress.time_left(1.0, 0.0, 10.0) == "done"


def test_count_lines_of_a_study(monkeypatch: pytest.MonkeyPatch) -> None:
    """At most one line per interval (fake clock), the last member's always; members that did
    not finish are counted; a resumed study's members are in the count, not in the rate."""
    monkeypatch.delenv(progress.SECONDS_VARIABLE, raising=False)
    monkeypatch.setattr(sys, "stdout", io.StringIO())  # not a terminal
    clock, lines = FakeClock(), []
    count = CountProgress(lines.append, "study", 10, 2, final=True, clock=clock)
    clock.now += 4.0
    count(True)
    assert lines == []
    clock.now += progress.LINE_SECONDS
    count(False)
    for _ in range(6):
        count(True)
    assert lines == [
        "study: 4 of 10 members done, 1 did not finish, 14.0 s elapsed, about 42.0 s left",
        "study: 10 of 10 members done, 1 did not finish, 14.0 s elapsed",
    ]


def test_count_lines_of_a_calibration_stage(monkeypatch: pytest.MonkeyPatch) -> None:
    """A stage's total grows as its members are sent (:meth:`expect`); an open-ended stage
    says how many are done without an estimate; on a terminal the lines are every
    TERMINAL_LINE_SECONDS."""
    monkeypatch.setenv(progress.SECONDS_VARIABLE, "0")
    monkeypatch.setattr(sys, "stdout", io.StringIO())
    clock, lines = FakeClock(), []
    stage = CountProgress(lines.append, "uncertainty", clock=clock)
    stage.expect(1)
    stage(True)
    stage.expect(3)
    stage(True)
    refine = CountProgress(lines.append, "refinement", None, clock=clock)
    refine.expect(1)
    refine(True)
    assert lines == [
        "uncertainty: 1 of 1 members done, 0.0 s elapsed",
        "uncertainty: 2 of 4 members done, 0.0 s elapsed, estimating time left",
        "refinement: 1 member done, 0.0 s elapsed",
    ]
    monkeypatch.setattr(sys, "stdout", Terminal())
    assert CountProgress(lines.append, "study").interval == progress.TERMINAL_LINE_SECONDS


def _run_to_log(tmp_path: Path, *arguments: str) -> str:
    """``conslaw run ... > log 2>&1`` in a process of its own, every report due
    (``CONSLAW_PROGRESS_SECONDS=0``); the log's text."""
    command = [CONSLAW] if CONSLAW else [sys.executable, "-m", "conslaw.cli"]
    log = tmp_path / "log"
    with log.open("w") as handle:
        done = subprocess.run(
            [*command, "run", *arguments, "--out", str(tmp_path / "out")],
            stdout=handle, stderr=subprocess.STDOUT, timeout=600,
            env={**os.environ, progress.SECONDS_VARIABLE: "0"},
        )  # fmt: skip
    text = log.read_text()
    assert done.returncode == 0, text
    return text


def test_a_run_into_a_log_file_writes_progress_lines(tmp_path: Path) -> None:
    text = _run_to_log(tmp_path, *SMALL_RUN)
    lines = [line for line in text.splitlines() if line.startswith("conslaw: t=")]
    assert lines, text
    assert all(" steps, dt=" in line and " elapsed, " in line for line in lines), lines
    assert "\r" not in text and lines[-1].startswith("conslaw: t=20 of 20 (100.0%)"), lines
    assert "sh-runout-shock: savage-hutter" in text  # the summary after them


def test_quiet_writes_no_progress_line_and_keeps_the_summary(tmp_path: Path) -> None:
    for where in (["--quiet"], ["-q"]):
        text = _run_to_log(tmp_path, *SMALL_RUN, *where)
        assert "conslaw: t=" not in text and "compiling" not in text, text
        assert text.startswith("sh-runout-shock: savage-hutter"), text
        assert "  wrote " in text


def test_quiet_before_the_command() -> None:
    from conslaw.cli import build_parser

    parser = build_parser()
    assert parser.parse_args(["--quiet", "run", "x"]).quiet
    assert parser.parse_args(["run", "x", "-q"]).quiet
    assert not parser.parse_args(["run", "x"]).quiet
    assert parser.parse_args(["-q", "calibrate", "x"]).quiet
    assert parser.parse_args(["warm", "--quiet"]).quiet


def test_a_2d_run_counts_its_moving_cells(monkeypatch: pytest.MonkeyPatch) -> None:
    """A 2D run of a model with a momentum: each line has the cells with a nonzero momentum
    (the avalanche at rest at t=0 has none, then it moves)."""
    from conslaw.scene2d import load_scene_2d
    from conslaw.simulation2d import simulate_2d

    monkeypatch.setenv(progress.SECONDS_VARIABLE, "0")
    scene = load_scene_2d("sh2d-runout", {"n_cells": [30, 10], "t_end": 2.0, "output_times": [1.0]})
    stream = io.StringIO()
    simulate_2d(scene, RunProgress(scene.t_end, stream, clock=FakeClock()))
    lines = stream.getvalue().splitlines()
    assert lines and all(" moving cells, " in line for line in lines), lines
    moving = [int(line.split(" moving cells")[0].rsplit(", ", 1)[1]) for line in lines]
    assert max(moving) > 0 and max(moving) <= 300, moving


def test_a_study_writes_its_lines_and_quiet_silences_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """``conslaw ensemble`` writes its members' lines (the last one always), which end as a
    run's do; with ``--quiet`` only the summary."""
    from conslaw.cli import main

    monkeypatch.setenv(progress.SECONDS_VARIABLE, "0")
    argv = ["ensemble", "sh-runout-shock", "--vary", "parameters.delta=uniform:24:26"]
    argv += ["--samples", "2", "--set", "n_cells=100", "--workers", "1", "--no-plot"]
    assert main([*argv, "--out", str(tmp_path / "loud")]) == 0
    out = capsys.readouterr().out
    assert "conslaw: study: 1 of 2 members done, " in out, out
    assert "conslaw: study: 2 of 2 members done, " in out and " elapsed\n" in out, out
    assert main([*argv, "--out", str(tmp_path / "quiet"), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "conslaw:" not in out and out.startswith("2 finished\n"), out


def test_a_bad_interval_is_one_line_before_anything_is_made(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from conslaw.cli import main

    monkeypatch.setenv(progress.SECONDS_VARIABLE, "ten")
    out = tmp_path / "out"
    assert main(["run", *SMALL_RUN, "--out", str(out)]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "CONSLAW_PROGRESS_SECONDS='ten'" in lines[0], lines
    assert not out.exists()
    assert main(["run", *SMALL_RUN, "--out", str(out), "--quiet"]) == 0  # not read
