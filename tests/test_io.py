"""Output files: XDMF/HDF5, VTU and CSV read back exactly; only the formats asked for; every
output time written as it is reached, so an interrupted or failed run keeps what came before."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest
from test_cli import cli

import conslaw
from conslaw.errors import InadmissibleStateError, StepLimitError
from conslaw.schemes.nessyahu_tadmor.scheme import NessyahuTadmor

ALL_FORMATS = {"output.formats": ["npz", "xdmf", "vtu", "csv"]}


def expected_fields(result: conslaw.RunResult, k: int) -> dict[str, np.ndarray]:
    """The fields of output ``k``, built here from the solver's arrays and the model's
    parameters (not through conslaw.io)."""
    state, model = result.states[k], result.model
    fields = {name: state.q[v] for v, name in enumerate(model.variables)}
    if model.depth_index is not None:
        h, m = state.q
        wet = (h >= model.dry_depth()) & (h > 0.0)
        fields["u"] = np.where(wet, m / np.where(wet, h, 1.0), 0.0)
    coefficients = result.scheme.cell_coefficients(state)
    if model.name == "savage-hutter":
        zeta = model.chute.zeta(state.x)
        k_cells = coefficients[3]
        assert set(np.unique(k_cells)) <= {model.k_active, model.k_passive}
        fields.update(
            zeta=np.degrees(zeta),
            lambda_kappa=model.chute.curvature(state.x),
            K=k_cells,
            beta=model.params.epsilon * np.cos(zeta) * k_cells,
        )
    elif model.name == "shallow-water":
        fields.update(bed=coefficients[0], bed_slope=coefficients[1])
    if result.exact[k] is not None:
        for v, name in enumerate(model.variables):
            fields[f"{name}_exact"] = result.exact[k][v]
    return fields


def expected_field_data(state: conslaw.State) -> dict[str, float]:
    data = {"time": state.t}
    if state.margins is not None:
        for side in ("rear", "front"):
            margin = getattr(state.margins, side)
            if margin is not None:
                data[f"x_{side}"], data[f"u_{side}"] = margin.position, margin.velocity
    return data


SCENES = [
    # name, overrides: a curved chute where K switches (passive behind the shock), front tracking
    # with margins, shallow water with an exact solution, a scalar law on a periodic domain.
    ("sh-runout-shock", {"t_end": 12.0, "output_times": [0.0, 8.0]}),
    ("sh-similarity-ft", {"output_times": [0.0, 3.0]}),
    ("dam-break-wet", {"n_cells": 100, "output_times": [1.0]}),
    ("burgers-sine", {"n_cells": 64, "output_times": [0.1]}),
]


@pytest.mark.parametrize(("scene", "overrides"), SCENES, ids=[s for s, _ in SCENES])
def test_xdmf_vtu_and_csv_read_back_exactly(tmp_path: Path, scene: str, overrides: dict) -> None:
    result = conslaw.run(scene, out=tmp_path, **overrides, **ALL_FORMATS, **{"output.plot": False})
    edges = result.grid.edges
    n_out = len(result.states)
    with meshio.xdmf.TimeSeriesReader(tmp_path / "solution.xdmf") as reader:
        points, cells = reader.read_points_cells()
        np.testing.assert_array_equal(points[:, 0], edges)
        np.testing.assert_array_equal(points[:, 1:], 0.0)
        assert len(cells) == 1 and cells[0].type == "line"
        np.testing.assert_array_equal(cells[0].data[:, 1] - cells[0].data[:, 0], 1)
        assert reader.num_steps == n_out
        for k in range(n_out):
            t, point_data, cell_data = reader.read_data(k)
            assert t == result.states[k].t and point_data == {}
            expected = expected_fields(result, k)
            assert set(cell_data) == set(expected)
            for name, values in expected.items():
                np.testing.assert_array_equal(cell_data[name][0], values, err_msg=name)
    information = ET.parse(tmp_path / "solution.xdmf").getroot().iter("Information")
    names = [element.get("Name") for element in information]
    assert names.count("time") == n_out
    pvd = ET.parse(tmp_path / "solution.pvd").getroot()
    entries = [(float(d.get("timestep")), d.get("file")) for d in pvd.iter("DataSet")]
    assert [t for t, _ in entries] == [s.t for s in result.states]
    for k, (_, name) in enumerate(entries):
        mesh = meshio.read(tmp_path / name)
        np.testing.assert_array_equal(mesh.points[:, 0], edges)
        expected = expected_fields(result, k)
        assert set(mesh.cell_data) == set(expected)
        for field, values in expected.items():
            np.testing.assert_array_equal(mesh.cell_data[field][0], values, err_msg=field)
        data = expected_field_data(result.states[k])
        assert {key: float(value[0]) for key, value in mesh.field_data.items()} == data
        table = np.loadtxt(tmp_path / f"solution-{k:05d}.csv", delimiter=",", skiprows=1, ndmin=2)
        header = (tmp_path / f"solution-{k:05d}.csv").read_text().splitlines()[0].split(",")
        assert header == ["t", "x", *expected]
        np.testing.assert_array_equal(table[:, 0], result.states[k].t)
        np.testing.assert_array_equal(table[:, 1], result.states[k].x)
        for column, values in enumerate(expected.values(), start=2):
            np.testing.assert_array_equal(table[:, column], values)
    with np.load(tmp_path / "states.npz") as saved:
        np.testing.assert_array_equal(saved["q"], [s.q for s in result.states])


def test_the_runout_writes_passive_earth_pressure_behind_the_shock(tmp_path: Path) -> None:
    """K is the coefficient the scheme uses: passive where the deposit is compressed."""
    result = conslaw.run(
        "sh-runout-shock", out=tmp_path, t_end=16.0, output_times=[],
        **{"output.formats": ["vtu"], "output.plot": False},
    )  # fmt: skip
    mesh = meshio.read(tmp_path / "solution-00000.vtu")
    k_cells = mesh.cell_data["K"][0]
    assert np.any(k_cells == result.model.k_passive) and np.any(k_cells == result.model.k_active)


def test_only_the_formats_asked_for_are_written(tmp_path: Path) -> None:
    conslaw.run(
        "burgers-sine", out=tmp_path, n_cells=32, output_times=[0.1],
        **{"output.formats": ["xdmf"], "output.plot": False},
    )  # fmt: skip
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == [
        "scene.toml",
        "solution-00000.h5",
        "solution-00001.h5",
        "solution-mesh.h5",
        "solution.xdmf",
    ]


def test_a_shorter_rerun_removes_the_series_files_it_did_not_write(tmp_path: Path) -> None:
    keep = tmp_path / "notes.txt"
    keep.write_text("mine")
    common = {"n_cells": 32, "output.plot": False}
    conslaw.run("burgers-sine", out=tmp_path, output_times=[0.1, 0.2], **ALL_FORMATS, **common)
    assert (tmp_path / "solution-00002.vtu").exists()
    conslaw.run("burgers-sine", out=tmp_path, **{"output.formats": ["vtu"]}, **common)
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["notes.txt", "scene.toml", "solution-00000.vtu", "solution.pvd"]


def _load_everything(folder: Path) -> tuple[np.ndarray, np.ndarray]:
    """Every output of an (interrupted) run folder, checked for agreement between formats:
    returns the npz times and states."""
    with np.load(folder / "states.npz") as saved:
        times, q = saved["t"], saved["q"]
    with meshio.xdmf.TimeSeriesReader(folder / "solution.xdmf") as reader:
        reader.read_points_cells()
        assert reader.num_steps == len(times)
        for k in range(reader.num_steps):
            t, _, cell_data = reader.read_data(k)
            assert t == times[k]
            np.testing.assert_array_equal(cell_data["u"][0], q[k, 0])
    pvd = ET.parse(folder / "solution.pvd").getroot()
    files = [d.get("file") for d in pvd.iter("DataSet")]
    assert len(files) == len(times)
    for k, name in enumerate(files):
        mesh = meshio.read(folder / name)
        assert mesh.field_data["time"][0] == times[k]
        np.testing.assert_array_equal(mesh.cell_data["u"][0], q[k, 0])
    return times, q


#: A run long enough to be stopped mid-way (about 20 s of solving), with 100 output times.
LONG_RUN = {
    "n_cells": 50_000,
    "reconstructor": "mc",
    "output_times": [round(0.0025 * k, 4) for k in range(1, 100)],
    "output.plot": False,
}
LONG_RUN_ARGUMENTS = [
    *("--set", "n_cells=50000", "--set", "reconstructor=mc", "--set", "output.plot=false"),
    *("--set", f"output_times={LONG_RUN['output_times']}"),
    *("--set", 'output.formats=["npz", "xdmf", "vtu", "csv"]'),
]


SIGNALLED_RUN = """
import os, sys
from conslaw.cli import console_main
from conslaw.output.writer import RunWriter
from conslaw.progress import RunProgress

write, report = RunWriter.__call__, RunProgress.__call__
outputs = []

def write_and_count(self, result):
    write(self, result)
    outputs.append(result.states[-1].t)

def report_then_signal(self, t, steps):
    if len(outputs) == 3:  # the first progress report after the third output: mid-run
        outputs.append("signalled")
        os.kill(os.getpid(), {signal_number})
    report(self, t, steps)

RunWriter.__call__ = write_and_count
RunProgress.__call__ = report_then_signal
sys.argv = ["conslaw", *{argv!r}]
sys.exit(console_main())
"""


@pytest.mark.skipif(not hasattr(signal, "SIGTERM"), reason="needs POSIX signals")
@pytest.mark.parametrize("signal_number", [signal.SIGINT, signal.SIGTERM], ids=["INT", "TERM"])
def test_a_run_stopped_by_a_signal_keeps_every_earlier_output(
    tmp_path: Path, signal_number: int
) -> None:
    """The signal comes from the run's own process at its first progress report after the third
    output is written, between two calls of the compiled kernel (counted, not timed: a run that
    is fast, or a parent that is slow to look, cannot let it finish first); it is handled as
    one from outside would be."""
    out = tmp_path / "out"
    argv = ["run", "burgers-sine", "--out", str(out), *LONG_RUN_ARGUMENTS]
    script = SIGNALLED_RUN.format(signal_number=int(signal_number), argv=argv)
    process = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    stderr = process.stderr
    assert process.returncode == 128 + signal_number, stderr
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    name = signal.Signals(signal_number).name
    assert lines[0].startswith(f"conslaw: interrupted ({name}) at t="), lines[0]
    assert ", step " in lines[0] and f"are complete in {out}" in lines[0], lines[0]
    stopped_at = float(lines[0].split("at t=")[1].split(",")[0])
    times, q = _load_everything(out)
    assert len(times) >= 3 and times[-1] < 0.25
    assert stopped_at > times[-1]
    # The outputs are those of an uninterrupted run (same output times up to there).
    kept = [t for t in LONG_RUN["output_times"] if t <= times[-1]]
    reference = conslaw.run(
        "burgers-sine", **{**LONG_RUN, "output_times": kept, "t_end": float(times[-1])}
    )
    np.testing.assert_array_equal(q, [s.q for s in reference.states])


def fail_at_third_output(monkeypatch: pytest.MonkeyPatch) -> object:
    """Make the NT scheme's advance to the third output time raise an InadmissibleStateError
    (an injected blow-up); returns the original advance."""
    advance = NessyahuTadmor.advance
    calls = []

    def failing_advance(self, state, t_end, progress=None):  # type: ignore[no-untyped-def]
        if t_end > state.t:
            calls.append(t_end)
            if len(calls) == 3:
                raise InadmissibleStateError(f"inadmissible state at t={state.t:.6g}, step 7")
        return advance(self, state, t_end, progress)

    monkeypatch.setattr(NessyahuTadmor, "advance", failing_advance)
    return advance


def test_a_failure_mid_run_keeps_every_earlier_output_and_says_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """An injected blow-up at the third output time: the CLI reports it in one line (exit 2)
    and the two outputs before it load intact in every format."""
    advance = fail_at_third_output(monkeypatch)
    from conslaw.cli import main

    out = tmp_path / "out"
    arguments = ["run", "burgers-sine", "--set", "n_cells=64", "--set", "output_times=[0.05, 0.1]"]
    arguments += ["--set", 'output.formats=["npz", "xdmf", "vtu", "csv"]', "--out", str(out)]
    assert main(arguments) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and "inadmissible state at t=0.1, step 7" in error[0]
    assert f"outputs up to t=0.1 are complete in {out}" in error[0]
    times, q = _load_everything(out)
    np.testing.assert_array_equal(times, [0.05, 0.1])
    monkeypatch.setattr(NessyahuTadmor, "advance", advance)
    reference = conslaw.run("burgers-sine", n_cells=64, output_times=[0.05], t_end=0.1)
    np.testing.assert_array_equal(q, [s.q for s in reference.states])
    assert not (out / "profiles.png").exists()


def test_an_interrupt_swallowed_mid_run_still_stops_the_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A Ctrl-C whose KeyboardInterrupt is swallowed where it lands (code that catches or
    clears errors can do that; a SIGINT was once lost under the test suite and its run went on
    to the end) still stops the run at its next progress report or output time: exit 130, the
    one-line message, and the outputs before it intact; the SIGINT handler of before the run is
    back (the default one, or SIG_IGN in a process started in the background by a shell without
    job control, as POSIX shells start such jobs)."""
    advance = NessyahuTadmor.advance
    calls = []
    swallowed = []
    handler_before = signal.getsignal(signal.SIGINT)

    def swallowing_advance(self, state, t_end, progress=None):  # type: ignore[no-untyped-def]
        if t_end > state.t:
            calls.append(t_end)
            if len(calls) == 3:
                try:
                    os.kill(os.getpid(), signal.SIGINT)
                    time.sleep(1.0)  # the handler runs here; its exception goes nowhere
                except KeyboardInterrupt:
                    swallowed.append(t_end)
        return advance(self, state, t_end, progress)

    monkeypatch.setattr(NessyahuTadmor, "advance", swallowing_advance)
    from conslaw.cli import main

    out = tmp_path / "out"
    arguments = ["run", "burgers-sine", "--set", "n_cells=64", "--set"]
    arguments += ["output_times=[0.05, 0.1, 0.15, 0.2]", "--set", "output.plot=false"]
    arguments += ["--set", 'output.formats=["npz", "xdmf", "vtu", "csv"]', "--out", str(out)]
    assert main(arguments) == 130
    assert swallowed == [0.15]
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and error[0].startswith("conslaw: interrupted (SIGINT) at t="), error
    # The advance to 0.15 reports its progress as it ends, and the run stops there: the outputs
    # before it are kept and 0.15 is not written.
    times, _ = _load_everything(out)
    np.testing.assert_array_equal(times, [0.05, 0.1])
    assert signal.getsignal(signal.SIGINT) is handler_before


#: A thin film (h = 5.96e-8) with momentum -0.514 on 13 periodic cells (g = 1): every wave
#: moves at 8.6e6, so the honest CFL step is 1e-9 and t_end = 0.5 needs about 5e8 steps.
FAST_FILM = [
    "run", "dam-break-wet", "--set", "n_cells=13", "--set", "cfl=0.11", "--set", "t_end=0.5",
    "--set", "x_min=0.0", "--set", "x_max=1.0", "--set", "output_times=[1e-5]",
    "--set", 'boundary={left="periodic", right="periodic"}',
    "--set", 'initial={kind="piecewise-constant", breakpoints=[], states=[[5.96e-8, -0.514]]}',
    "--set", "output.plot=false",
]  # fmt: skip
FILM_SPEED = 0.514 / 5.96e-8 + np.sqrt(5.96e-8)


@pytest.mark.parametrize(
    ("max_steps", "reached", "t_end"),
    [
        # stops between two progress reports, after the output at 1e-5 (t_end 2e-3 needs about
        # 2e6 steps, not more than ten times the limit: the run is not stopped earlier)
        (300_000, 0.00031, 2e-3),
        # over the limit when it reaches the output at 1e-5: written, then stop
        (5_000, 1e-5, 0.5),
    ],
)
def test_a_run_past_max_steps_stops_with_one_line_and_keeps_its_outputs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], max_steps: int, reached: float, t_end: float
) -> None:
    """``max_steps`` turns a run that would take hours (an honest CFL step of 1e-9) into one
    error line naming the key, the time reached and the mean step (that of the fastest wave);
    every output time reached is written, including one reached past the limit."""
    from conslaw.cli import main

    out = tmp_path / "out"
    limit = ["--set", f"max_steps={max_steps}", "--set", f"t_end={t_end}"]
    assert main([*FAST_FILM, *limit, "--out", str(out)]) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and f"scene key 'max_steps' = {max_steps} reached" in error[0], error
    assert f"outputs up to t=1e-05 are complete in {out}" in error[0]
    stopped = float(error[0].split("stopped at t=")[1].split(" ")[0])
    assert stopped == pytest.approx(reached, rel=0.05)
    mean_dt = float(error[0].split("mean time step ")[1].split(")")[0])
    assert mean_dt == pytest.approx(0.11 * (1.0 / 13) / FILM_SPEED, rel=1e-2)
    with np.load(out / "states.npz") as saved:
        np.testing.assert_array_equal(saved["t"], [1e-5])
        np.testing.assert_allclose(saved["q"][0], [[5.96e-8] * 13, [-0.514] * 13], rtol=1e-14)


def test_a_run_that_cannot_finish_stops_early(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The fast film needs about 5e8 steps; with max_steps = 1e6 the run stops as soon as its
    step rate shows that (a progress report after 1e4 steps), not after 1e6 steps, with one
    line giving the estimate."""
    from conslaw.cli import main

    out = tmp_path / "out"
    assert main([*FAST_FILM, "--set", "max_steps=1000000", "--out", str(out)]) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1, error
    assert "more than 10 times scene key 'max_steps' = 1000000" in error[0], error[0]
    assert "needs about 5" in error[0] and "e+08 steps" in error[0], error[0]
    stopped = float(error[0].split("stopped at t=")[1].split(" ")[0])
    steps = int(error[0].split(" after ")[1].split(" steps")[0])
    # At the first progress report past 1e4 steps (13 cells: the kernel reports every ~3e5).
    assert 10_000 <= steps < 1_000_000 and stopped < 1e-3


def test_a_firm_step_rate_stops_a_run_needing_over_twice_max_steps() -> None:
    """After 1e4 steps a run stops only if it needs more than 10 x max_steps (the rate may
    still change); after 1e6 steps, more than 2 x (phi = 89.99999 needs 2.8e8 steps against
    the default 1e8: stopped after 1e6 steps, in 15 s, not after 1e8)."""
    from dataclasses import replace

    from conslaw.config import load_scene
    from conslaw.simulation import cannot_finish

    scene = replace(load_scene("sh-similarity"), max_steps=1_000_000, t_end=1.0)
    # Three times max_steps at the rate seen: 1.5e5 steps to t = 0.05 since the last check.
    assert not cannot_finish(scene, (0.0, 0), 0.05, 150_000)
    assert cannot_finish(scene, (0.0, 1_000_000), 0.05, 1_150_000)
    # Just under twice: runs on.
    assert not cannot_finish(scene, (0.0, 1_000_000), 0.5, 1_400_000)  # needs 1.8e6


def test_max_steps_stops_a_run_only_before_t_end_and_after_recording_an_output_time() -> None:
    """burgers-riemann takes 112 steps to its output at t = 0.5 and 224 to t_end = 1, each
    stretch in one kernel call: with ``max_steps = 1`` and no output time before t_end the run
    is complete; with the output at 0.5 it stops there, after recording that state."""
    whole = conslaw.run("burgers-riemann", output_times=[])
    limited = conslaw.run("burgers-riemann", max_steps=1, output_times=[])
    assert limited.steps == whole.steps > 1 and limited.final.t == limited.scene.t_end
    np.testing.assert_array_equal(limited.final.q, whole.final.q)
    with pytest.raises(StepLimitError) as stop:
        conslaw.run("burgers-riemann", max_steps=1)
    assert "stopped at t=0.5 of t_end=1 after 112 steps" in str(stop.value)
    assert stop.value.completed_states[-1].t == 0.5


def test_nothing_is_written_when_the_first_step_fails(tmp_path: Path) -> None:
    """A run that fails before its first output time creates no folder."""
    process = cli(
        "run", "dam-break-wet", "--set", "parameters.g=1e308", "--out", str(tmp_path / "o")
    )
    assert process.returncode == 2 and "wave speed is not finite" in process.stderr
    assert "complete in" not in process.stderr
    assert not (tmp_path / "o").exists()


def test_interrupted_message_names_time_step_and_outputs() -> None:
    from conslaw.errors import RunInterrupted

    message = str(RunInterrupted(1.25, 40, 1.0, signal.SIGTERM))
    assert message == "interrupted (SIGTERM) at t=1.25, step 40; outputs up to t=1 are complete"
    none = RunInterrupted(0.5, 3, None, signal.SIGINT)
    assert isinstance(none, KeyboardInterrupt) and "no output time was reached" in str(none)
    assert (none.t, none.steps, none.last_output) == (0.5, 3, None)


def test_output_files_get_the_permissions_of_open(tmp_path: Path) -> None:
    """Atomic writes go through a temporary file made owner-only (``mkstemp``); the file left
    in place has the mode ``open`` would give it (0o666 less the umask)."""
    import os

    from conslaw.output import files

    previous = os.umask(0o022)
    try:
        files._FILE_MODE = None  # the umask is read once per process
        path = files.atomic_write_bytes(tmp_path / "a.bin", b"x")
        assert path.stat().st_mode & 0o777 == 0o644
        os.umask(0o077)
        files._FILE_MODE = None
        assert files.atomic_write_bytes(tmp_path / "b.bin", b"x").stat().st_mode & 0o777 == 0o600
    finally:
        os.umask(previous)
        files._FILE_MODE = None


def test_a_folder_being_written_is_refused_to_a_second_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """An output folder belongs to one run at a time: while another process holds it (as a run
    does from its first output to its end), ``conslaw run`` into it stops in one line naming the
    folder, exit 2, and leaves every file as it was; once it is free, the run writes."""
    from test_bad_input import run_in_process, snapshot

    shared = tmp_path / "shared"
    shared.mkdir()
    (shared / "states.npz").write_bytes(b"the other run's output")
    holder = subprocess.Popen(
        [sys.executable, "-c", "import fcntl, os, sys, time\n"
         f"fd = os.open({str(shared)!r}, os.O_RDONLY)\n"
         "fcntl.flock(fd, fcntl.LOCK_EX)\nprint('held', flush=True)\nsys.stdin.read()\n"],
        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == "held"
        before = snapshot(tmp_path)
        args = ["run", "burgers-riemann", "--set", "n_cells=20", "--no-plot", "--out", str(shared)]
        code, _, err = run_in_process(args, capsys)
        lines = err.strip().splitlines()
        assert code == 2 and len(lines) == 1, err
        assert str(shared) in lines[0] and "another conslaw run" in lines[0], lines[0]
        assert snapshot(tmp_path) == before
    finally:
        holder.communicate("")
    code, _, err = run_in_process(args, capsys)
    assert code == 0, err
    assert (shared / "scene.toml").exists()


def test_two_writers_in_one_process_do_not_share_a_folder(tmp_path: Path) -> None:
    """The claim holds between threads and writers of one process too: the second writer's
    first output is refused before it writes, and the folder is free after the first ends."""
    from conslaw.errors import ConfigError
    from conslaw.io import RunWriter

    result = conslaw.run("burgers-riemann", n_cells=20)
    first = RunWriter(tmp_path / "out", result.scene)
    second = RunWriter(tmp_path / "out", result.scene)
    first(result)
    with pytest.raises(ConfigError, match="another conslaw run"):
        second(result)
    assert second.files == []
    first.finish(result)
    second(result)
    assert second.files and second.finish(result)


ALL_FOUR = 'output.formats=["npz", "xdmf", "vtu", "csv"]'


@pytest.mark.skipif(sys.platform == "win32", reason="needs RLIMIT_FSIZE")
def test_a_full_disk_mid_run_stops_in_one_line_with_every_format_consistent(
    tmp_path: Path,
) -> None:
    """A file-size limit (``RLIMIT_FSIZE``, as a full disk: writes fail with EFBIG) reached at
    a later output time: one line naming the cause and the last complete output, exit 2, and
    every format lists the same output times, each readable."""
    out = tmp_path / "out"
    times = [round(0.02 * k, 2) for k in range(1, 12)]
    script = (
        "import resource, sys\nimport conslaw\nfrom conslaw.cli import main\n"
        "conslaw.run('burgers-sine', n_cells=3000)  # kernels loaded before the limit\n"
        "resource.setrlimit(resource.RLIMIT_FSIZE, (400_000, 400_000))\n"
        f"sys.exit(main(['run', 'burgers-sine', '--set', 'n_cells=3000', '--set', {ALL_FOUR!r},"
        f" '--set', 'output_times={times}', '--no-plot', '--out', {str(out)!r}]))\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2 and len(lines) == 1, done.stderr
    assert "File too large" in lines[0] and "outputs up to t=" in lines[0], lines[0]
    assert "states.npz" in lines[0] or ".h5" in lines[0] or ".vtu" in lines[0], lines[0]
    last = float(lines[0].split("outputs up to t=")[1].split(" ")[0])
    saved, _ = _load_everything(out)
    assert 2 <= len(saved) < len(times) and saved[-1] == last
    assert not list(out.glob(".*.tmp")), "a temporary file was left"
    csv_times = sorted(
        float(p.read_text().splitlines()[1].split(",")[0]) for p in out.glob("solution-*.csv")
    )
    assert csv_times == list(saved)


def test_a_failed_run_over_an_earlier_one_leaves_no_mixture(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A run that fails mid-way in a folder holding an earlier, longer run: the folder then
    holds the new run's outputs so far and nothing of the earlier run."""
    from conslaw.cli import main

    out = tmp_path / "out"
    earlier = ["run", "burgers-sine", "--set", "n_cells=64", "--set", ALL_FOUR, "--no-plot"]
    earlier += ["--set", "output_times=[0.05, 0.1, 0.15, 0.2]", "--out", str(out)]
    assert main(earlier) == 0
    assert (out / "solution-00004.vtu").exists()
    fail_at_third_output(monkeypatch)
    later = ["run", "burgers-sine", "--set", "n_cells=32", "--set", ALL_FOUR, "--no-plot"]
    later += ["--set", "output_times=[0.05, 0.1, 0.15, 0.2]", "--out", str(out)]
    assert main(later) == 2
    capsys.readouterr()
    names = sorted(p.name for p in out.iterdir())
    assert "solution-00003.vtu" not in names and "solution-00004.h5" not in names, names
    times, q = _load_everything(out)
    np.testing.assert_array_equal(times, [0.05, 0.1])
    assert q.shape[-1] == 32
    assert "n_cells = 32" in (out / "scene.toml").read_text()


def test_a_failure_writing_the_first_output_leaves_an_earlier_run_intact(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A write error at the first output (a full disk): one line, exit 2, and the earlier run in
    the folder byte for byte as it was, with no temporary file left."""
    from test_bad_input import snapshot

    from conslaw import io as output
    from conslaw.cli import main

    out = tmp_path / "out"
    common = ["--set", ALL_FOUR, "--no-plot", "--out", str(out)]
    assert main(["run", "burgers-sine", "--set", "n_cells=64", *common]) == 0
    before = snapshot(out)

    def full(self: output.OutputCommit) -> None:
        raise OSError(28, "No space left on device", str(out / "solution.xdmf"))

    monkeypatch.setattr(output.OutputCommit, "apply", full)
    assert main(["run", "burgers-sine", "--set", "n_cells=32", *common]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "No space left on device (solution.xdmf)" in lines[0], lines
    assert "the output at t=0.25" in lines[0] and str(out) in lines[0]
    assert snapshot(out) == before


def test_a_result_as_a_labelled_dataset_round_trips_through_netcdf(tmp_path: Path) -> None:
    """``RunResult.to_xarray``: the states over (t, x) with long names, units and the exact
    cell averages; written to netCDF and read back, the same values, names and attributes."""
    import xarray as xr

    result = conslaw.run("sh-similarity", n_cells=60)
    dataset = result.to_xarray()
    assert dataset["h"].dims == ("t", "x") and dataset.sizes["x"] == 60
    np.testing.assert_array_equal(dataset["hu"].values[-1], result.final.q[1])
    np.testing.assert_array_equal(dataset["t"].values, [s.t for s in result.states])
    assert "H (g L)^(1/2)" in dataset["hu"].attrs["long_name"]
    assert dataset["h"].attrs["units"] == "1" and "h_exact" in dataset
    assert dataset.attrs["scene"] == "sh-similarity" and dataset.attrs["steps"] == result.steps
    path = tmp_path / "run.nc"
    dataset.to_netcdf(path, engine="scipy")
    with xr.open_dataset(path, engine="scipy") as back:
        xr.testing.assert_identical(back.load(), dataset)


def test_the_steps_needed_follow_the_recent_rate() -> None:
    """A run that began with 1e4 tiny steps (1e-7) and then took 1e3 steps of 1e-4 needs about
    1.1e5 steps for t_end = 10 at its recent rate, not the 1e8 of its mean rate: it is not
    stopped as hopeless with max_steps = 2e5."""
    from dataclasses import replace

    from conslaw.config import load_scene
    from conslaw.simulation import cannot_finish, steps_needed

    scene = replace(load_scene("burgers-riemann"), t_end=10.0, max_steps=200_000)
    since = (1e-3, 10_000)
    needed = steps_needed(scene, since, 1e-3 + 0.1, 11_000)
    assert needed == pytest.approx(11_000 + 1_000 * (10.0 - 0.101) / 0.1)
    assert not cannot_finish(scene, since, 0.101, 11_000)
    assert cannot_finish(scene, (0.0, 0), 1e-3, 10_000)  # 1e8 at the tiny rate
