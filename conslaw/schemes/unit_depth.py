"""The forces on material of unit depth, asked from a depth-averaged model.

Schemes that move material points (the margins of front tracking, the nodes of the Lagrangian
scheme) integrate the momentum equation in its Lagrangian, per-unit-mass form
``du/dt = s_x - beta dh/dx`` (docs/design.md, "Savage–Hutter specifics"; Tai et al. 2001, eq. 19 at
a margin). They never
re-implement the physics: ``beta``, the driving force and the Coulomb friction come from the
model's own array methods, evaluated for unit depth:

- ``beta`` is the Jacobian entry ``A[1, 0] = beta h - u^2`` at ``h = 1, u = 0``, after the model's
  ``dynamic_coefficients`` has chosen its per-point coefficients (Savage–Hutter: ``K_act`` where
  ``du/dx >= 0``, ``K_pass`` where ``du/dx < 0``) from the velocity gradient;
- the drive is the momentum row of the model's source at ``h = 1`` (``sin zeta``);
- the friction is the model's resistance at ``h = 1`` (``tan delta (cos zeta + lambda kappa u^2)``),
  a magnitude that the caller applies with the stopping rule (docs/design.md, "Savage–Hutter
  specifics") (it may stop the
  material but never accelerate or reverse it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from conslaw.model import Model

Array = NDArray[np.float64]


@dataclass(frozen=True)
class UnitDepthForces:
    """Per point: the pressure coefficient ``beta``, the driving acceleration and the friction
    magnitude (both per unit depth, i.e. accelerations)."""

    beta: Array
    drive: Array
    friction: Array


def unit_depth_state(model: Model, velocity: Array) -> Array:
    """States ``(h, hu) = (1, u)`` in the model's rows, shape ``(n_vars, n)``."""
    assert model.depth_index is not None and model.momentum_index is not None
    velocity = np.asarray(velocity, dtype=np.float64)
    q = np.zeros((model.n_vars, velocity.size))
    q[model.depth_index] = 1.0
    q[model.momentum_index] = velocity
    return q


def unit_depth_forces(
    model: Model,
    x: Array,
    velocity: Array,
    velocity_change: Array,
    width: float,
    aux: Array | None = None,
) -> UnitDepthForces:
    """``beta``, drive and friction at the points ``x`` moving with ``velocity``.

    Parameters
    ----------
    model : Model
        A depth-averaged model (``depth_index`` and ``momentum_index`` set).
    x : ndarray
        Positions of the points.
    velocity : ndarray
        Their velocities.
    velocity_change : ndarray
        A velocity difference across each point in the direction of increasing x (only its sign
        matters: it decides the earth-pressure state, active for >= 0, passive for < 0).
    width : float
        Width handed to :meth:`Model.aux` (the coefficients may be averages over it).
    aux : ndarray, optional
        ``model.aux(x, width)`` if the caller already has it.
    """
    d, m = model.depth_index, model.momentum_index
    assert d is not None and m is not None
    x = np.asarray(x, dtype=np.float64)
    aux = model.aux(x, width) if aux is None else aux
    moving = unit_depth_state(model, velocity)
    slopes = np.zeros_like(moving)
    slopes[m] = velocity_change
    aux = model.dynamic_coefficients(moving, slopes, aux)
    at_rest = unit_depth_state(model, np.zeros(x.size))
    beta = model.flux_jacobian(at_rest, aux)[m, d]
    drive = model.source(moving, aux)[m]
    friction = model.resistance(moving, aux)
    return UnitDepthForces(beta, drive, friction)
