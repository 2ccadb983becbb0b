"""The depth rules of the numpy reference steps, shared by the 1D and 2D schemes.

The compiled kernels have their own copies (``bound_momentum_slope`` of the NT template); these
are what the tests compare them with (docs/design.md, "Depth-averaged models: dry states and
positivity").
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def velocity_bounded_slope(
    h: Array, momentum: Array, depth_slope: Array, slope: Array, u_min: Array, u_max: Array
) -> Array:
    """The momentum slope ``slope`` clamped so that the velocities at both quarter points,
    ``(m +- m'/4) / (h +- h'/4)``, lie in ``[u_min, u_max]`` (the range of the cell and its two
    neighbours along the slope's direction); unchanged in a cell with ``h <= 0``. The range always
    contains ``m' = u h'``, so the clamp is never empty."""
    plus = h + 0.25 * depth_slope
    minus = h - 0.25 * depth_slope
    low = np.maximum(4.0 * (plus * u_min - momentum), 4.0 * (momentum - minus * u_max))
    high = np.minimum(4.0 * (plus * u_max - momentum), 4.0 * (momentum - minus * u_min))
    bounded = np.minimum(np.maximum(slope, low), high)
    return np.where(h > 0.0, bounded, slope)
