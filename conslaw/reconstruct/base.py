"""The Reconstructor interface and the seven built-in reconstructors."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.reconstruct import dispatch, limiters, weno

# Every reconstructor reads at most two neighbours on each side.
STENCIL_HALF_WIDTH = 2


@dataclass(frozen=True)
class Reconstructor:
    """Slopes ``w'_j`` (cell-mean derivative times dx) from cell averages.

    ``slope_point(w[j-2], w[j-1], w[j], w[j+1], w[j+2])`` is a module-level numba function built
    from ufuncs only: the fused kernel calls it on scalars, :meth:`slopes` on whole arrays.
    """

    name: str
    description: str
    slope_point: Callable[..., Any]
    formal_order: int
    #: Code of a built-in reconstructor in :mod:`conslaw.reconstruct.dispatch` (the compiled
    #: kernels choose it at run time); None for a plugin's, whose ``slope_point`` is compiled in.
    code: int | None = None

    def slopes(self, w: NDArray[np.float64]) -> NDArray[np.float64]:
        """Slopes of the interior cells of ``w`` (last axis), which has 2 extra cells each side.

        Returns an array with the last axis shorter by ``2 * STENCIL_HALF_WIDTH``.
        """
        w = np.asarray(w, dtype=np.float64)
        n = w.shape[-1]
        if n <= 2 * STENCIL_HALF_WIDTH:
            raise ValueError("need at least 5 cells to compute a slope")
        pieces = [w[..., k : n - 2 * STENCIL_HALF_WIDTH + k] for k in range(5)]
        result = getattr(self.slope_point, "py_func")(*pieces)  # noqa: B009
        return np.broadcast_to(result, pieces[2].shape).astype(np.float64)


def builtin_reconstructors() -> list[Reconstructor]:
    """The reconstructors that ship with conslaw."""
    return [
        Reconstructor(
            "none",
            "zero slope: first-order staggered Lax–Friedrichs",
            limiters.slope_none,
            1,
            dispatch.NONE,
        ),
        Reconstructor(
            "minmod",
            "minmod TVD limiter (most diffusive)",
            limiters.slope_minmod,
            2,
            dispatch.MINMOD,
        ),
        Reconstructor(
            "superbee",
            "superbee TVD limiter (most compressive; paper Fig. 4)",
            limiters.slope_superbee,
            2,
            dispatch.SUPERBEE,
        ),
        Reconstructor(
            "vanleer",
            "van Leer harmonic TVD limiter",
            limiters.slope_vanleer,
            2,
            dispatch.VANLEER,
        ),
        Reconstructor("mc", "monotonised-central TVD limiter", limiters.slope_mc, 2, dispatch.MC),
        Reconstructor(
            "weno3",
            "WENO r=2 slopes, Jiang & Shu 1996 (third-order face values)",
            weno.slope_weno3,
            3,
            dispatch.WENO3,
        ),
        Reconstructor(
            "weno5",
            "WENO r=3 piecewise quadratic, Jiang & Shu 1996 (paper Fig. 5)",
            weno.slope_weno5,
            5,
            dispatch.WENO5,
        ),
    ]
