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
    h: Array,
    momentum: Array,
    depth_slope: Array,
    slope: Array,
    u_min: Array,
    u_max: Array,
    transverse: bool = False,
) -> Array:
    """The momentum slope ``slope`` clamped so that the velocities at both quarter points,
    ``(m +- m'/4) / (h +- h'/4)``, lie in ``[u_min, u_max]`` (the range of the cell and its two
    neighbours along the slope's direction); unchanged in a cell with ``h <= 0``. The range
    contains ``m' = u h'``; where every velocity is one ``u`` it is that point alone, and rounding
    can cross its ends (``low > high`` by an ulp): the clamp then gives ``high``, and a
    ``transverse`` slope (a momentum's slope across its own direction in 2D, the x momentum's in
    y) the ends' mean. The mirror image across the slope's direction maps the ends of a
    transverse slope to minus each other's: the mean keeps the slope its mirror (the clamp would
    not), and a momentum that does not vary across its direction gets a transverse slope of 0."""
    plus = h + 0.25 * depth_slope
    minus = h - 0.25 * depth_slope
    low = np.maximum(4.0 * (plus * u_min - momentum), 4.0 * (momentum - minus * u_max))
    high = np.minimum(4.0 * (plus * u_max - momentum), 4.0 * (momentum - minus * u_min))
    bounded = np.minimum(np.maximum(slope, low), high)
    if transverse:
        bounded = np.where(low > high, 0.5 * (low + high), bounded)
    return np.where(h > 0.0, bounded, slope)
