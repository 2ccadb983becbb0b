"""Root of a monotone scalar function, for the implicit equations of the exact solutions.

Plain bisection in pure Python: it halves the bracket until its ends are neighbouring floating
point numbers, so the root is found to the last bit (a tolerance of one unit in the last place).
It replaces ``scipy.optimize.brentq`` here because importing ``scipy.optimize`` takes about 0.3 s,
a large part of a short ``conslaw run``; about 60 evaluations per root cost microseconds.
"""

from __future__ import annotations

from collections.abc import Callable


def increasing_root(function: Callable[[float], float], low: float, high: float) -> float:
    """The root of ``function`` in ``[low, high]``, with ``function(low) <= 0 <= function(high)``
    and ``function`` increasing: of the last bracket's two ends, the one nearer zero.

    Raises
    ------
    ValueError
        If the bracket does not straddle the root.
    """
    f_low, f_high = function(low), function(high)
    if not (f_low <= 0.0 <= f_high):
        raise ValueError(f"no sign change in [{low!r}, {high!r}]: f = {f_low!r}, {f_high!r}")
    while True:
        middle = 0.5 * (low + high)
        if not low < middle < high:
            return low if -f_low <= f_high else high
        f_middle = function(middle)
        if f_middle == 0.0:
            return middle
        if f_middle < 0.0:
            low, f_low = middle, f_middle
        else:
            high, f_high = middle, f_middle
