"""Figures drawn by a child process started before the solve.

Importing matplotlib takes about as long as loading the compiled kernels (about a third of a
second each on the reference machine, see docs/performance.md). ``conslaw run`` therefore forks
a child that imports matplotlib and warms up its renderer while the parent loads the kernels and
solves; the parent then hands the finished run to the child, which writes the PNGs (through the
same atomic writes as everything else) and reports the paths. With two figures or more the
child forks a helper from itself, already warmed up, and each draws half of them. Where
``fork`` is not the platform's way to start processes (macOS, Windows) or the child fails for
any reason, the figures are drawn in the parent as before: the worker changes when figures are
drawn, never what is drawn.
"""

from __future__ import annotations

import contextlib
import ctypes
import dataclasses
import json
import multiprocessing
import os
import signal
import sys
import threading
from collections.abc import Iterator
from multiprocessing.connection import Connection
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

from conslaw.signals import STOP_SIGNALS

if TYPE_CHECKING:
    from multiprocessing.process import BaseProcess

    from conslaw.result import RunResult

#: Seconds the parent waits for the child to exit once its work is done.
JOIN_SECONDS = 5.0
#: ``prctl`` option: the signal a process gets when its parent dies (linux/prctl.h).
_PR_SET_PDEATHSIG = 1


#: What a stop signal must clean up in this process: the folder the figures are written into
#: (None before a run arrives), the figures this process writes (None: any, the child's
#: clean-up after its helper), the helper drawing half of them (its process id; 0: none), and
#: the exit status of a stopped process (1 in the helper: a stopped helper failed).
_running: dict[str, Any] = {"folder": None, "figures": None, "helper": 0, "stopped_status": 0}


def _handle_stops(handler: Any) -> None:
    """``handler`` for every stop signal but SIGINT (Ctrl-C is the parent's to report)."""
    for number in STOP_SIGNALS:
        if number != signal.SIGINT:
            signal.signal(number, handler)


def _stop(signal_number: int, frame: Any) -> NoReturn:
    """End this process at the first stop signal (later ones are ignored): first the helper,
    if one is drawing, then every temporary file an interrupted figure write left in the
    folder (:func:`_remove_temporary_files`); exit status 0.

    The handler exits itself rather than raising: Python runs a signal handler between any two
    bytecodes, also inside a weakref callback, a finaliser or an at-fork hook, where an
    exception it raises is printed and dropped, and the child would draw on with its stop
    signals ignored (seen in the tests, until the parent killed it mid-write)."""
    _handle_stops(signal.SIG_IGN)
    _end_helper(_running["helper"])
    _remove_temporary_files(_running["folder"], _running["figures"])
    os._exit(_running["stopped_status"])


@contextlib.contextmanager
def _stops_held() -> Iterator[None]:
    """Block the stop signals (a stop that comes meanwhile is handled at the end): around the
    fork of the helper and the bookkeeping of its process id, so that :func:`_stop` never
    misses a helper that exists nor signals one already reaped."""
    held = {number for number in STOP_SIGNALS if number != signal.SIGINT}
    signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_UNBLOCK, held)


def _end_helper(helper: int) -> None:
    """Stop the helper ``helper`` (if not 0) and reap it; its own stop handler removes the
    temporary file of the figure it was writing."""
    if helper:
        with contextlib.suppress(OSError):
            os.kill(helper, signal.SIGTERM)
            os.waitpid(helper, 0)


def _warm_up() -> None:
    """Import pyplot and draw, to a buffer, a small figure with what the run figures use
    (shared axes, markers, lines, a fill, a legend, text, a grid, tight layout): the first
    draw of each loads fonts and sets up caches, which the run's figures (and the helper that
    draws half of them, forked after this) then find ready."""
    import io as _io

    import matplotlib.pyplot as plt

    import conslaw.plotting  # noqa: F401  (the import the parent would otherwise pay)

    figure, axes = plt.subplots(2, 1, figsize=(2, 2), sharex=True, squeeze=False)
    for axis in axes[:, 0]:
        axis.plot([0.0, 1.0], [0.0, 1.0], "o", ms=4.5, mfc="none", mew=0.9, label="a")
        axis.plot([0.0, 1.0], [1.0, 0.0], "k-", lw=0.9, label="b")
        axis.fill([0.0, 1.0, 1.0], [0.0, 0.0, 1.0], color="tab:orange", alpha=0.8, lw=0)
        axis.text(0.98, 0.85, "t = 1", transform=axis.transAxes, ha="right", fontsize=9)
        axis.grid(alpha=0.3)
        axis.set_ylabel("h")
    axes[0, 0].legend(fontsize=8, loc="best")
    axes[0, 0].set_title("warm-up", fontsize=10)
    axes[-1, 0].set_xlabel("x")
    figure.tight_layout()
    figure.savefig(_io.BytesIO(), format="png", dpi=30)
    plt.close(figure)


def _die_with_the_parent() -> None:
    """Ask Linux to send SIGTERM to this child when the parent dies (``prctl``
    ``PR_SET_PDEATHSIG``): a parent killed outright leaves no orphan drawing on."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
    except (OSError, AttributeError):
        pass  # not essential: the child also stops when its pipe closes


def _remove_temporary_files(folder: Path | None, figures: list[str] | None = None) -> None:
    """Remove the temporary files of figure writes a stop interrupted (:func:`_stop` ends the
    process anywhere, also between the temporary file's creation and its rename in
    :func:`conslaw.io.atomic_write_bytes`): those of ``figures`` (names such as
    ``profiles.png``), or of any figure. Their names are ``.<figure>.<random>.tmp``, and only
    this child and its helper write PNGs into the folder."""
    if folder is None:
        return
    patterns = [f".{name}.*.tmp" for name in figures] if figures is not None else [".*.png.*.tmp"]
    with contextlib.suppress(OSError):  # a folder removed meanwhile
        for pattern in patterns:
            for leftover in folder.glob(pattern):
                leftover.unlink(missing_ok=True)


def _draw_shared(result: RunResult, folder: Path) -> list[Path]:
    """Write ``result``'s figures (:func:`conslaw.plotting.draw_figures`) from two processes
    when there are two figures or more and two cores: a helper forked from this warmed-up child
    draws every second figure while this one draws the others (the run waits for the slower
    half, not the sum). Returns the paths in :func:`conslaw.plotting.figures_for` order; a
    RuntimeError if the helper fails (the parent then draws them all)."""
    from conslaw import plotting

    names = [name for name, _ in plotting.figures_for(result)]
    if len(names) < 2 or len(os.sched_getaffinity(0)) < 2:
        return plotting.draw_figures(result, folder)
    child = os.getpid()
    with _stops_held():
        reader, writer = os.pipe()
        try:
            helper = os.fork()
        except OSError:  # no process to spare: this one draws them all
            os.close(reader)
            os.close(writer)
            helper = -1
        if helper == 0:  # the helper: never returns
            os.close(reader)
            _help(result, folder, names[1::2], writer, child)
        _running["helper"] = max(helper, 0)  # a stop in this process ends the helper too
    if helper < 0:
        return plotting.draw_figures(result, folder)
    os.close(writer)
    reply = b""
    try:
        ours = plotting.draw_figures(result, folder, names[0::2])
        with os.fdopen(reader, "rb") as stream:
            reader = -1
            reply = stream.read()  # until the helper's end of the pipe closes: it is exiting
    finally:
        if reader >= 0:
            os.close(reader)
        with _stops_held():
            if reply:
                status = os.waitpid(helper, 0)[1]
            else:  # a failure here, or a helper that ended without its paths
                _end_helper(helper)
                status = 1
            _running["helper"] = 0
    if not reply or os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError("the second figure process failed")
    by_name = {path.name: path for path in [*ours, *(Path(p) for p in json.loads(reply))]}
    return [by_name[name] for name in names]


def _help(result: RunResult, folder: Path, names: list[str], writer: int, child: int) -> NoReturn:
    """The helper of :func:`_draw_shared`: draw the figures ``names``, write their paths (JSON)
    to the pipe ``writer`` and exit at once (``os._exit``: nothing of the child's state is
    finalised twice); exit status 1 on any failure. A stop signal (the child's handler,
    :func:`_stop`) removes the temporary file of this helper's interrupted write and exits with
    status 1."""
    code = 1
    try:
        # Still with the stop signals held (_draw_shared): a stop from here on removes this
        # helper's own temporary files only, and says the helper failed.
        _running.update(figures=names, stopped_status=1)
        _die_with_the_parent()
        signal.pthread_sigmask(signal.SIG_UNBLOCK, set(STOP_SIGNALS) - {signal.SIGINT})
        if os.getppid() == child:  # not orphaned before prctl took effect
            from conslaw import plotting

            written = plotting.draw_figures(result, folder, names)
            with os.fdopen(writer, "w") as stream:
                stream.write(json.dumps([str(path) for path in written]))
            code = 0
    except BaseException:  # reported by the exit status
        pass
    finally:
        os._exit(code)


def _serve(connection: Connection, parent_end: Connection) -> None:
    """The child: warm up, wait for one run, write its figures, report ``("ok", paths)`` or
    ``("error", message)``. Ctrl-C is the parent's to report; SIGTERM and SIGHUP end the child
    at once and remove an interrupted write's temporary file (:func:`_stop`)."""
    parent_end.close()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _handle_stops(_stop)
    try:
        _die_with_the_parent()
        _warm_up()
        job = connection.recv()
        if job is None:
            return
        result, folder_name = job
        _running["folder"] = Path(folder_name)
        connection.send(("ok", _draw_shared(result, _running["folder"])))
    except (EOFError, BrokenPipeError):
        pass  # the parent is gone: nothing to report
    except Exception as error:  # reported to the parent, which draws in-process instead
        with contextlib.suppress(BrokenPipeError, OSError):
            connection.send(("error", f"{type(error).__name__}: {error}"))
    finally:
        connection.close()


def transportable(result: RunResult) -> RunResult:
    """``result`` without its scheme (compiled kernels, not needed by any figure)."""
    return dataclasses.replace(result, scheme=None)  # type: ignore[arg-type]


class FigureWorker:
    """A child process that draws one run's figures (see the module docstring).

    Use :meth:`start` (None where it cannot run), then :meth:`draw` once, and :meth:`close` in
    every case (a ``finally``): it stops a child that was not given a run.
    """

    def __init__(self, process: BaseProcess, connection: Connection) -> None:
        self.process = process
        self.connection = connection
        self.sent = False  # whether the child was given a run

    @classmethod
    def start(cls) -> FigureWorker | None:
        """Fork the child now; None on other platforms than Linux, in a process running other
        threads (a fork copies locks they may hold), and if the fork fails."""
        if not sys.platform.startswith("linux") or threading.active_count() > 1:
            return None
        context = multiprocessing.get_context("fork")
        parent_end, child_end = context.Pipe()
        process = context.Process(
            target=_serve, args=(child_end, parent_end), name="conslaw-figures", daemon=True
        )
        try:
            process.start()
        except OSError:
            parent_end.close()
            child_end.close()
            return None
        child_end.close()
        return cls(process, parent_end)

    def draw(self, result: RunResult, folder: Path) -> list[Path] | None:
        """Have the child write ``result``'s figures into ``folder``; the paths written, or None
        if the child could not (the caller then draws them itself)."""
        try:
            self.connection.send((transportable(result), str(folder)))
            status, payload = self.connection.recv()
        except Exception:  # a result that does not pickle, a child that died: draw here
            self.stop()
            return None
        except BaseException:  # Ctrl-C while waiting: stop the child at once
            self.stop()
            raise
        self.sent = True
        self.close()
        return [Path(p) for p in payload] if status == "ok" else None

    def close(self) -> None:
        """End the child: wait for one that finished its run, terminate one that got none
        (a run that failed or was stopped should not wait for matplotlib's import)."""
        if not self.sent:
            self.stop()
            return
        self.connection.close()
        self.process.join(JOIN_SECONDS)
        if self.process.is_alive():
            self.stop()

    def stop(self) -> None:
        """Terminate the child (SIGTERM: an atomic write in progress removes its temporary
        file) and wait for it."""
        self.connection.close()
        self.process.terminate()
        self.process.join(JOIN_SECONDS)
        if self.process.is_alive():  # it ignores a second SIGTERM while it unwinds
            self.process.kill()
            self.process.join()


def write_figures(
    result: RunResult, folder: Path, worker: FigureWorker | None = None
) -> list[Path]:
    """``profiles.png``; with front tracking ``margins.png``; on a chute ``chute.png``; with at
    least :data:`conslaw.plotting.XT_MIN_OUTPUTS` output times ``xt.png`` (x–t diagram).

    Drawn by ``worker`` if one is given and it succeeds, else in this process
    (:func:`conslaw.plotting.draw_figures`)."""
    if worker is not None:
        written = worker.draw(result, folder)
        if written is not None:
            return written
    from conslaw import plotting

    return plotting.draw_figures(result, folder)
