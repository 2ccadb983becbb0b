"""Pointwise pieces shared by the depth-averaged models (shallow water, Savage–Hutter).

They store ``q = (h, m = h u)`` (in 2D ``(h, h u, h v)``: every row after the depth a momentum)
and pack their dry tolerance at :data:`DRY` of the parameter vector. A cell with
``h < dry_tolerance`` is dry: its velocity is 0 in every formula (no division by zero anywhere)
and it holds no momentum.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import ClassVar

import numpy as np
from numba import njit
from numpy.typing import NDArray

from conslaw.model import Model

#: Index of the dry tolerance in the packed parameter vector of every depth-averaged model.
DRY = 1


@njit(cache=True)
def velocity(h, m, dry_tolerance):
    """``u = m / h``, and 0 in a dry cell (``h < dry_tolerance``)."""
    return m / h if h >= dry_tolerance and h > 0.0 else 0.0


@njit(cache=True)
def momentum_jacobian_x(u, v, celerity_squared, out):
    """The x-flux Jacobian of a 2D depth-averaged model, ``q = (h, h u, h v)`` with the
    pressure ``celerity_squared h / 2`` (``g h`` in shallow water, ``beta_x h`` in
    Savage–Hutter): ``A = [[0, 1, 0], [c^2 - u^2, 2 u, 0], [-u v, v, u]]`` (the derivative of
    ``F = (h u, h u^2 + c^2 h / 2, h u v)``; LeVeque 2002, sec. 18.8).

    Parameters
    ----------
    u, v : float
        The velocity.
    celerity_squared : float
        ``c^2``: the derivative of the pressure term with respect to ``h``.
    out : numpy.ndarray
        The ``3 x 3`` matrix, set in place.
    """
    out[0, 0] = 0.0
    out[0, 1] = 1.0
    out[0, 2] = 0.0
    out[1, 0] = celerity_squared - u * u
    out[1, 1] = 2.0 * u
    out[1, 2] = 0.0
    out[2, 0] = -u * v
    out[2, 1] = v
    out[2, 2] = u


@njit(cache=True)
def momentum_jacobian_y(u, v, celerity_squared, out):
    """The y-flux Jacobian of :func:`momentum_jacobian_x`'s models: ``B = [[0, 0, 1], [-u v,
    v, u], [c^2 - v^2, 0, 2 v]]``, the derivative of ``G = (h v, h u v, h v^2 + c^2 h / 2)``.

    Parameters
    ----------
    u, v : float
        The velocity.
    celerity_squared : float
        ``c^2``: the derivative of the y pressure term with respect to ``h``.
    out : numpy.ndarray
        The ``3 x 3`` matrix, set in place.
    """
    out[0, 0] = 0.0
    out[0, 1] = 0.0
    out[0, 2] = 1.0
    out[1, 0] = -u * v
    out[1, 1] = v
    out[1, 2] = u
    out[2, 0] = celerity_squared - v * v
    out[2, 1] = 0.0
    out[2, 2] = 2.0 * v


@njit(cache=True)
def correct_point(q, aux, params, dt):
    """A dry cell holds no momentum (every row after the depth)."""
    if q[0] < params[DRY]:
        for v in range(1, q.shape[0]):
            q[v] = 0.0


@njit(cache=True)
def admissible_point(q, aux, params):
    """Finite, ``h >= 0``, and no momentum (any row after the depth) in a dry cell."""
    for v in range(q.shape[0]):
        if not np.isfinite(q[v]):
            return False
    if q[0] < 0.0:
        return False
    if q[0] >= params[DRY]:
        return True
    # A plain loop: numba compiles it, not a generator inside all().
    for v in range(1, q.shape[0]):  # noqa: SIM110
        if q[v] != 0.0:
            return False
    return True


class DepthAveragedModel(Model):
    """Base of the models with ``q = (h, m = h u)``: the depth and momentum rows, the dry-state
    rules above, and the dry tolerance (a ``dry_tolerance`` field of the parameters)."""

    variables: ClassVar[tuple[str, ...]] = ("h", "hu")
    long_names: ClassVar[Mapping[str, str]] = {
        "x": "position",
        "t": "time",
        "h": "depth",
        "hu": "depth times depth-averaged velocity",
        "u": "depth-averaged velocity",
    }
    reflect_signs: ClassVar[tuple[float, ...]] = (1.0, -1.0)
    depth_index: ClassVar[int | None] = 0
    momentum_index: ClassVar[int | None] = 1
    admissible_rule: ClassVar[str] = "finite h >= 0, and hu = 0 where h < dry_tolerance"
    correct_point = staticmethod(correct_point)
    admissible_point = staticmethod(admissible_point)

    def dry_depth(self) -> float:
        """The ``dry_tolerance`` parameter."""
        return float(self.params.dry_tolerance)

    def primitive_fields(self, q: NDArray[np.float64]) -> dict[str, NDArray[np.float64]]:
        """Depth ``h`` and velocity ``u = hu / h`` (0 in a dry cell, as in every formula); in
        2D also ``v = hv / h``."""
        h = np.asarray(q[0])
        wet = (h >= self.dry_depth()) & (h > 0.0)
        safe = np.where(wet, h, 1.0)
        fields = {"h": h, "u": np.where(wet, np.asarray(q[1]) / safe, 0.0)}
        if self.momentum_y_index is not None:
            fields["v"] = np.where(wet, np.asarray(q[self.momentum_y_index]) / safe, 0.0)
        return fields


class TwoDimensionalRows:
    """The rows of a 2D depth-averaged model, ``q = (h, h u, h v)`` (a mixin, listed before the
    model's :class:`DepthAveragedModel` base): the mirror signs across x and y walls, the y
    momentum's row, and what is admissible."""

    variables: ClassVar[tuple[str, ...]] = ("h", "hu", "hv")
    reflect_signs: ClassVar[tuple[float, ...]] = (1.0, -1.0, 1.0)
    reflect_signs_y: ClassVar[tuple[float, ...] | None] = (1.0, 1.0, -1.0)
    momentum_y_index: ClassVar[int | None] = 2
    admissible_rule: ClassVar[str] = "finite h >= 0, and hu = hv = 0 where h < dry_tolerance"
