"""Default pointwise functions for models that do not provide their own."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def finite_point(q, aux, params):  # type: ignore[no-untyped-def]
    """Admissible means every component is finite."""
    # A plain loop: numba compiles it, not a generator inside all().
    for v in range(q.shape[0]):  # noqa: SIM110
        if not np.isfinite(q[v]):
            return False
    return True
