"""The figure child of ``conslaw run`` (conslaw.figure_worker): same figures as drawn in the
parent, a fallback to the parent when the child fails, no litter when it is stopped, and models
that pickle (a run is handed to the child by pickling)."""

from __future__ import annotations

import os
import pickle
import sys
from pathlib import Path

import numpy as np
import pytest

import conslaw
from conslaw import figure_worker, io
from conslaw.figure_worker import FigureWorker
from conslaw.simulation import simulate

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="the figure child is forked (Linux only)"
)


@pytest.fixture(scope="module")
def run() -> conslaw.simulation.RunResult:
    """sh-similarity: a profile figure against the exact solution and a chute figure."""
    return simulate(conslaw.load_scene("sh-similarity"))


def started() -> FigureWorker:
    worker = FigureWorker.start()
    assert worker is not None, "a single-threaded Linux process must be able to fork the child"
    return worker


def test_the_child_draws_the_figures_the_parent_would(run, tmp_path: Path) -> None:
    """Byte-identical PNGs from the child and from :func:`conslaw.io.draw_figures`, and the
    child reports the paths it wrote."""
    (tmp_path / "child").mkdir()
    (tmp_path / "parent").mkdir()
    worker = started()
    written = worker.draw(run, tmp_path / "child")
    assert written == [tmp_path / "child" / "profiles.png", tmp_path / "child" / "chute.png"]
    assert not worker.process.is_alive() and worker.process.exitcode == 0
    expected = io.draw_figures(run, tmp_path / "parent")
    for ours, theirs in zip(written, expected, strict=True):
        assert ours.name == theirs.name
        assert ours.read_bytes() == theirs.read_bytes()


def test_a_failing_child_leaves_the_figures_to_the_parent(
    run, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A child that raises reports the error; :func:`conslaw.io.write_figures` then draws in the
    parent, so the run still gets its figures."""
    parent = os.getpid()
    draw = io.draw_figures

    def fails_in_the_child(result, folder):  # type: ignore[no-untyped-def]
        if os.getpid() != parent:
            raise RuntimeError("no figures here")
        return draw(result, folder)

    monkeypatch.setattr(io, "draw_figures", fails_in_the_child)
    assert started().draw(run, tmp_path) is None
    written = io.write_figures(run, tmp_path, started())
    assert [p.name for p in written] == ["profiles.png", "chute.png"]
    assert all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in written)


def test_a_stopped_child_leaves_no_partial_or_temporary_file(run, tmp_path: Path) -> None:
    """``stop`` while the child draws (as on Ctrl-C): every PNG in the folder is complete, and
    no temporary file of an atomic write is left behind."""
    worker = started()
    worker.connection.send((figure_worker.transportable(run), str(tmp_path)))
    worker.stop()
    assert not worker.process.is_alive()
    for path in tmp_path.iterdir():
        assert path.suffix == ".png", f"left behind: {path.name}"
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_close_stops_a_child_that_got_no_run() -> None:
    """A run that fails before its figures: ``close`` ends the waiting child at once."""
    worker = started()
    worker.close()
    assert not worker.process.is_alive() and worker.process.exitcode == 0


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
