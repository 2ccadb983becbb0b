"""The figure child of ``conslaw run`` (conslaw.figure_worker): same figures as drawn in the
parent, a fallback to the parent when the child fails, no litter when it is stopped, and models
that pickle (a run is handed to the child by pickling)."""

from __future__ import annotations

import os
import pickle
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

import conslaw
from conslaw import figure_worker, plotting
from conslaw.figure_worker import FigureWorker
from conslaw.simulation import simulate

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="the figure child is forked (Linux only)"
)


@pytest.fixture(scope="module")
def run() -> conslaw.simulation.RunResult:
    """sh-similarity: a profile figure against the exact solution and a chute figure."""
    return simulate(conslaw.load_scene("sh-similarity"))


@pytest.fixture(autouse=True)
def patient_parent(monkeypatch: pytest.MonkeyPatch) -> None:
    """The parent waits up to two minutes (not :data:`~conslaw.figure_worker.JOIN_SECONDS`)
    for a stopped child before it kills it: a child that is slow to be scheduled on a loaded
    machine is not killed mid-clean-up, so the tests' "ended by the stop itself" (exit status
    0, no temporary file) does not depend on how fast the machine is."""
    monkeypatch.setattr(figure_worker, "JOIN_SECONDS", 120.0)


def started() -> FigureWorker:
    worker = FigureWorker.start()
    assert worker is not None, "a single-threaded Linux process must be able to fork the child"
    return worker


def test_the_child_draws_the_figures_the_parent_would(run, tmp_path: Path) -> None:
    """Byte-identical PNGs from the child and from :func:`conslaw.plotting.draw_figures`, and the
    child reports the paths it wrote."""
    (tmp_path / "child").mkdir()
    (tmp_path / "parent").mkdir()
    worker = started()
    written = worker.draw(run, tmp_path / "child")
    assert written == [tmp_path / "child" / "profiles.png", tmp_path / "child" / "chute.png"]
    assert not worker.process.is_alive() and worker.process.exitcode == 0
    expected = plotting.draw_figures(run, tmp_path / "parent")
    for ours, theirs in zip(written, expected, strict=True):
        assert ours.name == theirs.name
        assert ours.read_bytes() == theirs.read_bytes()


@pytest.mark.parametrize("failing", ["child", "helper"])
def test_a_failing_child_leaves_the_figures_to_the_parent(
    run, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, failing: str
) -> None:
    """A child that raises (in its own half of the figures, or in the helper that draws every
    second one) reports the error; :func:`conslaw.figure_worker.write_figures` then draws them
    all in the parent, so the run still gets its figures."""
    parent = os.getpid()
    draw = plotting.draw_figures
    broken = None if failing == "child" else ["chute.png"]

    def fails_in_a_child(result, folder, names=None):  # type: ignore[no-untyped-def]
        if os.getpid() != parent and (broken is None or names == broken):
            raise RuntimeError("no figures here")
        return draw(result, folder, names)

    monkeypatch.setattr(plotting, "draw_figures", fails_in_a_child)
    assert started().draw(run, tmp_path) is None
    written = figure_worker.write_figures(run, tmp_path, started())
    assert [p.name for p in written] == ["profiles.png", "chute.png"]
    assert all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in written)


def _hang_after_mkstemp_in_children(monkeypatch: pytest.MonkeyPatch) -> None:
    """Make every figure write in a forked process (the child, its helper) hang for a minute
    once its temporary file exists."""
    parent = os.getpid()
    original = tempfile.mkstemp

    def hangs(*args, **kwargs):  # type: ignore[no-untyped-def]
        made = original(*args, **kwargs)
        if os.getpid() != parent:
            time.sleep(60)
        return made

    monkeypatch.setattr(tempfile, "mkstemp", hangs)


@pytest.mark.parametrize("where", ["after mkstemp", "before the rename"])
def test_a_child_stopped_in_a_write_leaves_no_file(
    run, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, where: str
) -> None:
    """``stop`` (as on Ctrl-C, or the parent's death) while the child writes a PNG: the child
    hangs in the write (patched in the child only) until the temporary file exists, then is
    stopped; nothing is left in the folder, neither a PNG nor the temporary file. "after
    mkstemp" is the window before the ``try`` of ``atomic_write_bytes`` (cleaned by the child's
    stop handler), "before the rename" the window inside it."""
    parent = os.getpid()
    if where == "after mkstemp":
        _hang_after_mkstemp_in_children(monkeypatch)
    else:
        rename = os.replace

        def hangs(source, target):  # type: ignore[no-untyped-def]
            if os.getpid() != parent:
                time.sleep(60)
            return rename(source, target)

        monkeypatch.setattr(os, "replace", hangs)
    worker = started()
    worker.connection.send((figure_worker.transportable(run), str(tmp_path)))
    deadline = time.monotonic() + 60
    while not list(tmp_path.glob(".*.tmp")):
        assert time.monotonic() < deadline, "the child never started its write"
        time.sleep(0.01)
    worker.stop()
    assert not worker.process.is_alive()
    assert list(tmp_path.iterdir()) == []


def test_a_result_that_does_not_pickle_is_drawn_in_the_parent(run, tmp_path: Path) -> None:
    """A plugin model with an attribute pickle refuses (a lambda): the figures are drawn in
    the parent, not lost."""
    import dataclasses

    model = pickle.loads(pickle.dumps(run.model))
    model.unpicklable = lambda: None  # type: ignore[attr-defined]
    result = dataclasses.replace(run, model=model)
    written = figure_worker.write_figures(result, tmp_path, started())
    assert [p.name for p in written] == ["profiles.png", "chute.png"]


def test_close_stops_a_child_that_got_no_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A run that fails before its figures: ``close`` ends the child at once, without waiting
    for its warm-up. The child is held in its warm-up (patched, in the child only) and says so;
    ``close`` stops it (SIGTERM) before it waits for it at all, the child ends by its stop
    handler (exit status 0), and it is not killed. Counted, not timed: a ``close`` that waited
    for the warm-up first would join before it terminates."""
    parent = os.getpid()
    warming = tmp_path / "warming"

    def warm_up_for_an_hour() -> None:
        if os.getpid() != parent:
            warming.write_text("")
            time.sleep(3600)

    monkeypatch.setattr(figure_worker, "_warm_up", warm_up_for_an_hour)
    worker = started()
    deadline = time.monotonic() + 60  # a generous wait for the fork, not a measurement
    while not warming.exists():
        assert time.monotonic() < deadline, "the child never started its warm-up"
        time.sleep(0.01)
    process, calls = worker.process, []
    for name in ("terminate", "join", "kill"):
        original = getattr(process, name)

        def recorded(*args: object, _name: str = name, _original: object = original) -> None:
            calls.append(_name)
            _original(*args)  # type: ignore[operator]

        monkeypatch.setattr(process, name, recorded)
    worker.close()
    assert calls == ["terminate", "join"], calls
    assert not process.is_alive() and process.exitcode == 0


def _stopped_inside_a_weakref_callback(folder: str) -> None:
    """A child with the figure worker's stop handler and a write in progress, whose stop signal
    is handled inside a weakref callback, where an exception raised by the handler would be
    printed and dropped."""
    import weakref

    figure_worker._handle_stops(figure_worker._stop)
    figure_worker._running["folder"] = Path(folder)
    (Path(folder) / ".profiles.png.interrupted.tmp").write_bytes(b"half a PNG")

    class Thing:
        pass

    def callback(_: object) -> None:
        os.kill(os.getpid(), signal.SIGTERM)
        for _ in range(100_000):  # the handler runs between two of these bytecodes
            pass

    thing = Thing()
    reference = weakref.ref(thing, callback)
    del thing
    (Path(folder) / "drew-on").write_text(f"the stop was lost ({reference})")


def test_a_stop_inside_a_weakref_callback_still_ends_the_child(tmp_path: Path) -> None:
    """Python runs a signal handler between any two bytecodes, also inside a weakref callback
    (or a finaliser, or an at-fork hook), where an exception it raises is dropped: the stop
    handler therefore ends the process itself. The child exits at once with status 0, the
    temporary file of its interrupted write is gone, and nothing after the stop ran."""
    import multiprocessing

    process = multiprocessing.get_context("fork").Process(
        target=_stopped_inside_a_weakref_callback, args=(str(tmp_path),)
    )
    process.start()
    process.join(30)
    assert process.exitcode == 0
    assert list(tmp_path.iterdir()) == []


def _children(pid: int) -> list[int]:
    """The process ids of ``pid``'s children (Linux ``/proc``)."""
    path = Path(f"/proc/{pid}/task/{pid}/children")
    return [int(word) for word in path.read_text().split()] if path.exists() else []


@pytest.mark.parametrize("moment", ["helper forked", "0.03 s later", "both writing"])
def test_a_stop_while_drawing_ends_the_child_and_its_helper(
    run, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, moment: str
) -> None:
    """The child draws half the figures and a helper forked from it the other half. A stop
    as soon as the helper exists, a little later, or once both hang in their writes (patched in
    the children) ends both by the stop itself (the child's exit status 0, not the parent's
    kill after :data:`~conslaw.figure_worker.JOIN_SECONDS`), the helper is gone, and no
    temporary file is left."""
    _hang_after_mkstemp_in_children(monkeypatch)
    worker = started()
    worker.connection.send((figure_worker.transportable(run), str(tmp_path)))
    child = worker.process.pid
    assert child is not None
    deadline = time.monotonic() + 60
    while not _children(child) or (
        moment == "both writing" and len(list(tmp_path.glob(".*.tmp"))) < 2
    ):
        assert time.monotonic() < deadline, "the helper never started (or never wrote)"
        time.sleep(0.002)
    helpers = _children(child)
    if moment == "0.03 s later":
        time.sleep(0.03)
    worker.stop()
    assert not worker.process.is_alive() and worker.process.exitcode == 0
    for helper in helpers:
        with pytest.raises(ProcessLookupError):
            os.kill(helper, 0)  # reaped by the child before it exited
    assert [p for p in tmp_path.iterdir() if p.suffix == ".tmp"] == []


def test_no_child_where_a_fork_is_unsafe(monkeypatch: pytest.MonkeyPatch) -> None:
    """With other threads running (their locks would be copied) the figures stay in the
    parent."""
    monkeypatch.setattr(figure_worker.threading, "active_count", lambda: 2)
    assert FigureWorker.start() is None


def test_a_model_pickles_without_its_compiled_kernels(run) -> None:
    """The model goes to the child by pickle; the compiled array kernels (a module) are left
    out and rebuilt on first use, with the same results."""
    model = run.model
    q = run.final.q
    aux = model.aux(run.grid.centres(), run.grid.dx)
    expected = model.flux(q, aux)
    assert model._arrays is not None
    copy = pickle.loads(pickle.dumps(model))
    assert copy._arrays is None and copy.params == model.params
    np.testing.assert_array_equal(copy.flux(q, aux), expected)


def test_the_library_leaves_the_matplotlib_backend_alone(tmp_path: Path) -> None:
    """Importing conslaw and drawing a run's figures keeps the backend a user (or a notebook)
    chose, and the figures are still PNG files."""
    script = (
        "import pathlib, matplotlib\nmatplotlib.use('svg')\n"
        "import conslaw, conslaw.plotting\n"
        "result = conslaw.run('burgers-sine', n_cells=32)\n"
        f"paths = conslaw.plotting.draw_figures(result, pathlib.Path({str(tmp_path)!r}))\n"
        "print(matplotlib.get_backend(), len(paths))\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    backend, count = done.stdout.split()
    assert backend == "svg" and int(count) >= 1
    for png in tmp_path.glob("*.png"):
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
