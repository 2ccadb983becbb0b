"""The project's exception hierarchy.

Library code raises these; only the command-line interface turns them into a one-line message and
exit code 2 (see :mod:`conslaw.cli`).
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterable
from typing import Any


class ConslawError(Exception):
    """Base class of every error conslaw raises on purpose."""


class ConfigError(ConslawError, ValueError):
    """Invalid input: an unknown name, a value out of range, a malformed scene file."""


class InadmissibleStateError(ConslawError, FloatingPointError):
    """The solution left the admissible set (NaN, inf, negative depth) during a run."""


class SchemeBreakdownError(ConslawError, ArithmeticError):
    """A scheme cannot continue (time step below its floor, crossing Lagrangian nodes, ...).

    ``state`` is the last good state when the scheme provides it; the runner adds
    ``completed_states``, the states it had reached at the output times before the breakdown.
    """

    def __init__(self, message: str, state: Any = None) -> None:
        super().__init__(message)
        self.state = state
        self.completed_states: list[Any] = []


class OutputError(ConslawError, OSError):
    """An output could not be written (a full disk, a file-size limit, the folder removed): the
    run stops, and the folder keeps every output committed before (docs/output.md)."""


class KernelCacheError(ConslawError):
    """The kernel cache folder cannot be used (``CONSLAW_CACHE_DIR`` not a writable folder, a
    full disk); the message names the folder and what to do."""


class StepLimitError(SchemeBreakdownError):
    """A run took more time steps than the scene's ``max_steps`` before reaching ``t_end``.

    Not a failure of the scheme: its CFL step is honest but tiny (a fast wave). The outputs
    reached before the limit are kept, as for every :class:`SchemeBreakdownError`.
    """


def unknown_name_message(kind: str, name: str, allowed: Iterable[str]) -> str:
    """One line naming the unknown ``name``, the allowed values and a close match if any."""
    allowed = sorted(allowed)
    close = difflib.get_close_matches(str(name), allowed, n=1)
    hint = f"; did you mean '{close[0]}'?" if close else ""
    return f"unknown {kind} '{name}'; allowed: {', '.join(allowed)}{hint}"


def shown(value: object, limit: int = 60) -> str:
    """``repr(value)`` for a one-line message: an integer too long to print whole (Python
    refuses beyond 4300 digits) by its number of digits, anything longer than ``limit``
    characters cut with ``...``."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 200:
        digits = len(str(abs(value))) if value.bit_length() < 14000 else "over 4000"
        return f"an integer of {digits} digits"
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def finite_number(value: object, label: str) -> float:
    """``value`` as a float if it is a finite int or float (not a bool); else a ConfigError
    ``"<label>: expected a finite number, got <value>"`` (an integer beyond the float range
    too)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ConfigError(f"{label}: expected a finite number, got {shown(value)}")
    try:
        number = float(value)
    except OverflowError:
        raise ConfigError(f"{label}: expected a finite number, got {shown(value)}") from None
    if not math.isfinite(number):
        raise ConfigError(f"{label}: expected a finite number, got {shown(value)}")
    return number


class RunInterrupted(KeyboardInterrupt):
    """A run stopped by a signal (Ctrl-C/SIGINT, SIGTERM) between two output times.

    A ``KeyboardInterrupt``, so code that handles Ctrl-C keeps doing so. The message says where
    the run stopped; the outputs written before (one file set per output time reached) are
    complete.

    Attributes
    ----------
    t : float
        Time the solution had reached when the signal came.
    steps : int
        Time steps taken until then.
    last_output : float or None
        The last output time written (None if none was reached).
    signal_number : int
        The signal (``signal.SIGINT`` for Ctrl-C).
    """

    def __init__(self, t: float, steps: int, last_output: float | None, signal_number: int) -> None:
        import signal

        self.t, self.steps, self.last_output = t, steps, last_output
        self.signal_number = signal_number
        name = signal.Signals(signal_number).name
        kept = (
            "no output time was reached"
            if last_output is None
            else f"outputs up to t={last_output:.6g} are complete"
        )
        super().__init__(f"interrupted ({name}) at t={t:.6g}, step {steps}; {kept}")
