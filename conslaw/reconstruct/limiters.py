"""TVD slope limiters (Sweby 1984; Yee 1989), written once for numba and numpy.

Every function takes the five cell averages ``w[j-2], ..., w[j+2]`` and returns the limited slope
``w'_j`` (the cell-mean derivative times ``dx``) used in the paper's eq. (11). The bodies use only
ufuncs (``np.sign``, ``np.minimum``, ...), so the same code runs compiled on scalars inside the
fused kernel and, through ``.py_func``, vectorised on whole numpy arrays in the reference path.
"""

from __future__ import annotations

import numpy as np
from numba import njit

# Smallest denominator of the van Leer limiter; only reached when both differences are zero.
_TINY = 1e-300


@njit(cache=True)
def minmod2(a, b):
    """``minmod(a, b)``: the smaller in magnitude if the signs agree, else 0."""
    return 0.5 * (np.sign(a) + np.sign(b)) * np.minimum(np.abs(a), np.abs(b))


@njit(cache=True)
def minmod3(a, b, c):
    """``minmod(a, b, c)``: the smallest in magnitude if all signs agree, else 0."""
    sa = np.sign(a)
    return (
        0.25
        * (sa + np.sign(b))
        * np.abs(sa + np.sign(c))
        * np.minimum(np.minimum(np.abs(a), np.abs(b)), np.abs(c))
    )


@njit(cache=True)
def slope_none(wm2, wm1, w0, wp1, wp2):
    """Zero slope: piecewise-constant data, the staggered Lax–Friedrichs scheme."""
    return 0.0 * w0


@njit(cache=True)
def slope_minmod(wm2, wm1, w0, wp1, wp2):
    """Minmod limiter, ``w' = minmod(Δ-, Δ+)`` (Nessyahu & Tadmor 1990, eq. 2.12)."""
    return minmod2(w0 - wm1, wp1 - w0)


@njit(cache=True)
def slope_superbee(wm2, wm1, w0, wp1, wp2):
    """Superbee (Roe), ``w' = maxmod(minmod(2Δ-, Δ+), minmod(Δ-, 2Δ+))`` (Yee 1989)."""
    dm = w0 - wm1
    dp = wp1 - w0
    a = minmod2(2.0 * dm, dp)
    b = minmod2(dm, 2.0 * dp)
    # a and b share the sign of the data (or vanish), so maxmod reduces to this.
    return np.sign(a + b) * np.maximum(np.abs(a), np.abs(b))


@njit(cache=True, error_model="numpy")  # no zero-division branch: the kernel stays SIMD
def slope_vanleer(wm2, wm1, w0, wp1, wp2):
    """Van Leer (harmonic) limiter, ``w' = (Δ+|Δ-| + Δ-|Δ+|)/(|Δ-| + |Δ+|)`` (van Leer 1974)."""
    dm = w0 - wm1
    dp = wp1 - w0
    denominator = np.maximum(np.abs(dm) + np.abs(dp), _TINY)
    return (dp * np.abs(dm) + dm * np.abs(dp)) / denominator


@njit(cache=True)
def slope_mc(wm2, wm1, w0, wp1, wp2):
    """Monotonised-central limiter, ``w' = minmod(2Δ-, (Δ- + Δ+)/2, 2Δ+)`` (van Leer 1977)."""
    dm = w0 - wm1
    dp = wp1 - w0
    return minmod3(2.0 * dm, 0.5 * (dm + dp), 2.0 * dp)
