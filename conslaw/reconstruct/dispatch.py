"""Every built-in reconstructor behind one compiled function, chosen at run time by its code.

The compiled kernels hand :func:`builtin_slopes` a row of stencil values and the code of the
scene's reconstructor. The code is tested once per row, outside the loop over the cells, so each
branch is a plain loop over one limiter that compiles to SIMD code, and one compiled kernel
serves all seven built-in reconstructors: changing the reconstructor of a scene compiles nothing
(docs/design.md, "Compiled kernels"). A plugin's reconstructor has no code; its slope function is
bound into the kernel instead. The seven loops are written out: a compiled function that takes
another as an argument is not cached by numba, so one generic loop would compile in every run.
"""

from __future__ import annotations

from numba import njit

from conslaw.reconstruct.limiters import (
    slope_mc,
    slope_minmod,
    slope_none,
    slope_superbee,
    slope_vanleer,
)
from conslaw.reconstruct.weno import slope_weno3, slope_weno5

#: Codes of the built-in reconstructors (``Reconstructor.code``).
NONE = 0
MINMOD = 1
SUPERBEE = 2
VANLEER = 3
MC = 4
WENO3 = 5
WENO5 = 6


@njit(cache=True, error_model="numpy")
def builtin_slopes(code, values, count, out):
    """Slopes of ``count`` cells with the built-in reconstructor of ``code``.

    ``out[j] = slope(values[j], values[j + 1], values[j + 2], values[j + 3], values[j + 4])``
    for ``j < count``: the slope ``w'`` of the paper's eq. (11) for the cell whose average is
    ``values[j + 2]``, with the limiter or WENO slope of :mod:`conslaw.reconstruct.limiters`
    and :mod:`conslaw.reconstruct.weno`. An unknown code gives zero slopes (as ``none``).
    """
    if code == MINMOD:
        for j in range(count):
            out[j] = slope_minmod(
                values[j], values[j + 1], values[j + 2], values[j + 3], values[j + 4]
            )
    elif code == SUPERBEE:
        for j in range(count):
            out[j] = slope_superbee(
                values[j], values[j + 1], values[j + 2], values[j + 3], values[j + 4]
            )
    elif code == VANLEER:
        for j in range(count):
            out[j] = slope_vanleer(
                values[j], values[j + 1], values[j + 2], values[j + 3], values[j + 4]
            )
    elif code == MC:
        for j in range(count):
            out[j] = slope_mc(values[j], values[j + 1], values[j + 2], values[j + 3], values[j + 4])
    elif code == WENO3:
        for j in range(count):
            out[j] = slope_weno3(
                values[j], values[j + 1], values[j + 2], values[j + 3], values[j + 4]
            )
    elif code == WENO5:
        for j in range(count):
            out[j] = slope_weno5(
                values[j], values[j + 1], values[j + 2], values[j + 3], values[j + 4]
            )
    else:
        for j in range(count):
            out[j] = slope_none(
                values[j], values[j + 1], values[j + 2], values[j + 3], values[j + 4]
            )


@njit(cache=True, error_model="numpy")
def builtin_slopes_across(code, row_0, row_1, row_2, row_3, row_4, count, out):
    """Slopes of ``count`` cells across five rows with the built-in reconstructor of ``code``.

    ``out[j] = slope(row_0[j], row_1[j], row_2[j], row_3[j], row_4[j])`` for ``j < count``:
    :func:`builtin_slopes` across the rows (the slopes in y of a row of a 2D grid, whose stencil
    is the same column in the two rows below and the two above), so that each branch is again a
    plain loop over the cells of a row.
    """
    if code == MINMOD:
        for j in range(count):
            out[j] = slope_minmod(row_0[j], row_1[j], row_2[j], row_3[j], row_4[j])
    elif code == SUPERBEE:
        for j in range(count):
            out[j] = slope_superbee(row_0[j], row_1[j], row_2[j], row_3[j], row_4[j])
    elif code == VANLEER:
        for j in range(count):
            out[j] = slope_vanleer(row_0[j], row_1[j], row_2[j], row_3[j], row_4[j])
    elif code == MC:
        for j in range(count):
            out[j] = slope_mc(row_0[j], row_1[j], row_2[j], row_3[j], row_4[j])
    elif code == WENO3:
        for j in range(count):
            out[j] = slope_weno3(row_0[j], row_1[j], row_2[j], row_3[j], row_4[j])
    elif code == WENO5:
        for j in range(count):
            out[j] = slope_weno5(row_0[j], row_1[j], row_2[j], row_3[j], row_4[j])
    else:
        for j in range(count):
            out[j] = slope_none(row_0[j], row_1[j], row_2[j], row_3[j], row_4[j])
