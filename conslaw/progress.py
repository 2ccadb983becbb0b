"""Progress of a run and of a study, as ``conslaw run``, ``ensemble`` and ``calibrate`` print it
(docs/cli.md, "Progress").

On a terminal a run redraws a one-line bar; otherwise (a log file, a pipe, a batch scheduler)
it writes a plain line every :data:`LINE_SECONDS` of wall time, flushed at once so that
``tail -f`` shows it. A study or a calibration writes lines of the members done, at most one
per :data:`LINE_SECONDS` as well (every :data:`TERMINAL_LINE_SECONDS` on a terminal). Every
line ends alike: the wall time elapsed and an estimate of the time left
(:func:`progress_line`).

The interval of the lines can be set with the environment variable ``CONSLAW_PROGRESS_SECONDS``
(:func:`line_seconds`; 0: a line at every report, which the tests use instead of waiting).
Checking the clock at a report costs well under a microsecond; the line itself is made only
when one is due.
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Callable, Sequence
from typing import TextIO

from conslaw.errors import ConfigError

#: Wall seconds between two progress lines when the output is not a terminal.
LINE_SECONDS = 10.0
#: Wall seconds between two lines of a study's members on a terminal.
TERMINAL_LINE_SECONDS = 5.0
#: Wall seconds between two redraws of a run's bar on a terminal.
BAR_SECONDS = 0.1
#: The environment variable that sets :data:`LINE_SECONDS` (seconds, a number >= 0).
SECONDS_VARIABLE = "CONSLAW_PROGRESS_SECONDS"
#: The time left is estimated once this many wall seconds and this fraction of the work are
#: behind (before, the rate is mostly start-up: "estimating time left").
ESTIMATE_SECONDS = 2.0
ESTIMATE_FRACTION = 0.01
#: Characters of a run's bar.
BAR_WIDTH = 30


def line_seconds() -> float:
    """The wall seconds between two progress lines: ``$CONSLAW_PROGRESS_SECONDS`` if set, else
    :data:`LINE_SECONDS`.

    Returns
    -------
    float

    Raises
    ------
    ConfigError
        The variable is not a finite number >= 0.
    """
    text = os.environ.get(SECONDS_VARIABLE, "").strip()
    if not text:
        return LINE_SECONDS
    try:
        seconds = float(text)
    except ValueError:
        seconds = math.nan
    if not (math.isfinite(seconds) and seconds >= 0.0):
        raise ConfigError(
            f"{SECONDS_VARIABLE}='{text}': expected the seconds between two progress lines, "
            "a number >= 0"
        )
    return seconds


def is_terminal(stream: TextIO) -> bool:
    """Whether ``stream`` is a terminal (False for a stream without ``isatty`` or closed)."""
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):
        return False


def duration(seconds: float) -> str:
    """Wall time as a person reads it: ``4.2 s``, ``3 min 05 s``, ``2 h 07 min``."""
    if seconds < 60.0:
        return f"{seconds:.1f} s"
    whole = round(seconds)
    if whole < 3600:
        return f"{whole // 60} min {whole % 60:02d} s"
    return f"{whole // 3600} h {whole % 3600 // 60:02d} min"


def time_left(done: float, left: float, elapsed: float) -> str:
    """The estimate of the time left: the work ``left`` at the rate ``done`` per ``elapsed``
    wall seconds, as ``about 3 min 05 s left``; ``estimating time left`` while fewer than
    :data:`ESTIMATE_SECONDS` and :data:`ESTIMATE_FRACTION` of the work are behind.

    Parameters
    ----------
    done : float
        Work done since the clock started (model time, members).
    left : float
        Work still to do, in the same unit.
    elapsed : float
        Wall seconds since the clock started.

    Returns
    -------
    str
    """
    if left <= 0.0:
        return "done"
    if elapsed < ESTIMATE_SECONDS or done <= ESTIMATE_FRACTION * (done + left):
        return "estimating time left"
    return f"about {duration(elapsed * left / done)} left"


def progress_line(parts: Sequence[str], elapsed: float, left: str | None) -> str:
    """One progress line: ``parts``, the wall time ``elapsed`` and the estimate ``left`` (from
    :func:`time_left`; None: none), separated by commas. Runs, studies and calibrations all
    write their lines with it."""
    tail = [f"{duration(elapsed)} elapsed", *([left] if left else [])]
    return ", ".join([*parts, *tail])


class RunProgress:
    """The progress of one run, a ``progress(t, steps)`` callback of
    :func:`conslaw.simulation.simulate` and :func:`conslaw.simulation2d.simulate_2d`.

    On a terminal, a bar redrawn at most every :data:`BAR_SECONDS`; otherwise a line every
    :func:`line_seconds`, as ``conslaw: t=12.5 of 150 (8.3%), 4120 steps, dt=0.00305,
    1234 moving cells, 10.0 s elapsed, about 1 min 50 s left``. ``dt`` is the mean step size
    since the previous report (one step pair, or one call of a compiled kernel); the moving
    cells are counted when a line is written, by :attr:`moving` if the run set it (2D runs of
    a model with a momentum: cells with a nonzero momentum). The wall time counts from the first
    report (the first steps; a compile before them is not in the rate).

    Parameters
    ----------
    t_end : float
        The run's end time.
    stream : file, optional
        Where to write (default: ``sys.stdout`` when made).
    show : bool
        False: write nothing (``--quiet``); ``check`` is still called.
    check : callable, optional
        Called at every report before anything else (the command line's signal latch).
    terminal : bool, optional
        Whether ``stream`` is a terminal (default: its ``isatty()``).
    clock : callable
        Wall seconds (:func:`time.monotonic`; tests give a fake clock).
    """

    def __init__(
        self,
        t_end: float,
        stream: TextIO | None = None,
        *,
        show: bool = True,
        check: Callable[[], None] | None = None,
        terminal: bool | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.t_end = float(t_end)
        self.stream = sys.stdout if stream is None else stream
        self.terminal = is_terminal(self.stream) if terminal is None else terminal
        self.show = show
        self.check = check
        self.clock = clock
        self.interval = math.inf
        if show:
            self.interval = BAR_SECONDS if self.terminal else line_seconds()
        #: Counts the moving cells when a line is written (None: not known).
        self.moving: Callable[[], int | None] | None = None
        self.started: float | None = None
        self.first_t = 0.0
        self.last = 0.0  # when the last line or bar was written
        self.previous = (0.0, 0)  # time and steps at the previous report
        self.dt = math.nan
        self.drawn = 0  # characters of the bar on the terminal (0: none)

    @property
    def writes_lines(self) -> bool:
        """Whether it writes lines (shown, not on a terminal): only they count moving cells."""
        return self.show and not self.terminal

    def __call__(self, t: float, steps: int) -> None:
        if self.check is not None:
            self.check()
        if steps > self.previous[1]:
            self.dt = (t - self.previous[0]) / (steps - self.previous[1])
        self.previous = (t, steps)
        if not self.show:
            return
        now = self.clock()
        first = self.started is None
        if first:
            self.started, self.last, self.first_t = now, now, t
        due = now - self.last >= self.interval
        if self.terminal:
            if first or due or t >= self.t_end:
                self.last = now
                self._draw_bar(t, steps, now)
        elif due:
            self.last = now
            self.stream.write(f"conslaw: {self.line(t, steps, now)}\n")
            self.stream.flush()

    def _estimate(self, t: float, now: float) -> str:
        assert self.started is not None
        return time_left(t - self.first_t, self.t_end - t, now - self.started)

    def line(self, t: float, steps: int, now: float) -> str:
        """The text of a line at time ``t`` after ``steps`` steps, wall clock ``now``."""
        assert self.started is not None
        percent = 100.0 * min(t / self.t_end, 1.0) if self.t_end > 0 else 100.0
        parts = [f"t={t:.6g} of {self.t_end:g} ({percent:.1f}%)", f"{steps} steps"]
        if math.isfinite(self.dt):
            parts.append(f"dt={self.dt:.3g}")
        moving = self.moving() if self.moving is not None else None
        if moving is not None:
            parts.append(f"{moving} moving cells")
        return progress_line(parts, now - self.started, self._estimate(t, now))

    def _draw_bar(self, t: float, steps: int, now: float) -> None:
        fraction = min(t / self.t_end, 1.0) if self.t_end > 0 else 1.0
        filled = int(BAR_WIDTH * fraction)
        text = (
            f"[{'#' * filled}{'.' * (BAR_WIDTH - filled)}] t={t:.4g} steps={steps}, "
            f"{self._estimate(t, now)}"
        )
        self.stream.write(f"\r{text}{' ' * max(self.drawn - len(text), 0)}")
        self.stream.flush()
        self.drawn = len(text)

    def close(self) -> None:
        """End the bar's line (on a terminal, if a bar was drawn)."""
        if self.drawn:
            self.stream.write("\n")
            self.stream.flush()
            self.drawn = 0


class CountProgress:
    """Lines saying how many members of a study or of a calibration's stage are done, as
    ``study: 5 of 10 members done, 1 did not finish, 10.0 s elapsed, about 10 s left``; at most
    one per :func:`line_seconds` (per :data:`TERMINAL_LINE_SECONDS` when stdout is a terminal).

    Parameters
    ----------
    report : callable
        Gets each line.
    label : str
        What is counted, the start of each line (``study``, ``coarse stage``).
    total : int or None
        Members planned (raised by :meth:`expect`); None: open-ended (the lines say how many
        are done, without an estimate).
    done : int
        Members done before (a resumed study's), not in the rate.
    final : bool
        Whether the line of the last planned member is always written.
    clock : callable
        Wall seconds (:func:`time.monotonic`; tests give a fake clock).
    """

    def __init__(
        self,
        report: Callable[[str], None],
        label: str,
        total: int | None = 0,
        done: int = 0,
        *,
        final: bool = False,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.report, self.label, self.total, self.done = report, label, total, done
        self.final, self.clock = final, clock
        self.interval = TERMINAL_LINE_SECONDS if is_terminal(sys.stdout) else line_seconds()
        self.failed = 0
        self.ran = 0
        self.started = clock()
        self.last = self.started

    def expect(self, members: int) -> None:
        """``members`` more members were sent: the total is at least those done and these (an
        open-ended count stays open)."""
        if self.total is not None:
            self.total = max(self.total, self.done + members)

    def __call__(self, finished: bool) -> None:
        """One member done (``finished``: it ran to its end)."""
        self.done += 1
        self.ran += 1
        self.failed += not finished
        now = self.clock()
        last_one = self.total is not None and self.done >= self.total
        if now - self.last < self.interval and not (self.final and last_one):
            return
        self.last = now
        elapsed = now - self.started
        counted = f"{self.done} {'member' if self.done == 1 else 'members'} done"
        if self.total is not None:
            counted = f"{self.done} of {self.total} members done"
        parts = [f"{self.label}: {counted}"]
        if self.failed:
            parts.append(f"{self.failed} did not finish")
        left = None
        if self.total is not None and not last_one:
            left = time_left(self.ran, self.total - self.done, elapsed)
        self.report(progress_line(parts, elapsed, left))
