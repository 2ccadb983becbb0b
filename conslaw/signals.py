"""The signals that stop a run (SIGINT, SIGTERM, SIGHUP) and what conslaw does with them, in one
place: a run turns them into an interruption (:class:`SignalLatch`), writing an output time holds
them until the files are in place (:func:`held`), and the figure process stops on them quietly
(:mod:`conslaw.figure_worker`). docs/output.md, "Nothing lost"."""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

#: The signals that stop a run, as far as the platform has them.
STOP_SIGNALS: tuple[int, ...] = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)


@contextmanager
def handled(
    handler: Callable[[int, Any], Any], numbers: tuple[int, ...] = STOP_SIGNALS
) -> Iterator[dict[int, Any]]:
    """``handler`` for the signals ``numbers`` inside the block, the previous handlers (given to
    the block) back on leaving it."""
    previous = {number: signal.signal(number, handler) for number in numbers}
    try:
        yield previous
    finally:
        for number, old in previous.items():
            signal.signal(number, old)


class SignalInterrupt(KeyboardInterrupt):
    """SIGINT, SIGTERM or SIGHUP turned into a KeyboardInterrupt, so a run stops as on Ctrl-C."""

    def __init__(self, signal_number: int) -> None:
        super().__init__(signal_number)
        self.signal_number = signal_number


class SignalLatch:
    """The signal handler of a run: it raises :class:`SignalInterrupt` at once, as Ctrl-C does,
    and also remembers the signal, so that :meth:`check` raises it again at the run's next
    progress report or output time if the first exception was swallowed. An exception raised by
    a signal handler lands wherever Python happens to be, and code that catches or clears errors
    there can drop it. A SIGINT was once lost in a run under the test suite (``python -m
    conslaw.cli``, cold kernel cache): the run went on to its end; where it was lost is not
    known."""

    def __init__(self) -> None:
        self.received: int | None = None

    def __call__(self, signal_number: int, frame: Any) -> None:
        if self.received is None:
            self.received = signal_number
        raise SignalInterrupt(signal_number)

    def check(self) -> None:
        """Raise :class:`SignalInterrupt` if a signal came."""
        if self.received is not None:
            raise SignalInterrupt(self.received)


@contextmanager
def held() -> Iterator[None]:
    """Hold the stop signals while one output time is written, so that an interruption lands
    between output times and every format holds the same ones; a signal that came meanwhile is
    handed to its previous handler on leaving (only in the main thread, where Python runs
    signal handlers)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending: list[int] = []

    def hold(number: int, frame: Any) -> None:
        pending.append(number)

    with handled(hold) as previous:
        yield
    for number in pending[:1]:
        handler = previous[number]
        if callable(handler):
            handler(number, None)
        elif handler == signal.SIG_DFL:
            signal.raise_signal(number)
