"""Ending a 2D run when its material is at rest (docs/terrain.md, "Stopping at rest").

Hazard tools do not run an avalanche to a fixed end time: they stop it once it has come to rest.
AvaFrame's com1DFA (its configuration ``stopCritType = kinEnergy``, ``stopCrit = 0.01``, and
the stop test of its time loop, ``com1DFA/DFAfunctionsCython.pyx``) ends the run when the total
kinetic energy falls to ``stopCrit`` times the largest total kinetic energy reached so far.
conslaw keeps that rule and adds the exact one its friction allows: a Coulomb bed stops a cell
with a momentum of exactly 0 (the stopping rule, docs/design.md, "Savage–Hutter specifics"), so
a run also ends when every momentum is 0.

The rule, with ``E(t) = 1/2 sum_cells H |u|^2 dx dy`` (``H`` the depth variable, the volume per
map area on terrain; ``|u|`` the speed of ``Model.flow_depth_and_speed``, in the surface on
terrain; the kinetic energy per unit density) and ``E_peak`` its largest value over every step
pair so far (and the start)::

    at an output time t > 0:  every momentum is exactly 0,  or  E(t) <= energy_fraction E_peak

The run ends at the first output time where it holds (that output is its last), so it ends
within one output interval of the time the material comes to rest; ``t_end`` is the cap. The
test is made at the output times only, so a run that stops holds the same states as the run
without the rule up to its stop (no time step changes). After every step pair the energy is
summed (numpy, from the depth and speed the peak fields compute anyway) for ``E_peak`` and for
the time since when ``E <= energy_fraction E_peak`` has held (``rest_since``), recorded with
the stop.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number, unknown_name_message
from conslaw.model import Model

Array = NDArray[np.float64]

#: AvaFrame com1DFA's ``stopCrit`` (its ``com1DFACfg.ini``, with ``stopCritType = kinEnergy``).
ENERGY_FRACTION = 0.01
#: The keys of a scene's ``[stop]`` table.
STOP_KEYS = ("at_rest", "energy_fraction")


@dataclass(frozen=True)
class StopRule:
    """When a 2D run ends before ``t_end``: the scene's ``[stop]`` table, validated.

    Parameters
    ----------
    at_rest : bool
        End the run at the first output time at which the material is at rest (the rule of the
        module docstring); False: run to ``t_end``.
    energy_fraction : float
        The fraction of the peak kinetic energy below which the material counts as at rest,
        in [0, 1) (AvaFrame's ``stopCrit``, 0.01); 0: only when every momentum is 0.
    """

    at_rest: bool = False
    energy_fraction: float = ENERGY_FRACTION

    def to_table(self) -> dict[str, Any]:
        """The ``[stop]`` table of the resolved scene."""
        return {"at_rest": self.at_rest, "energy_fraction": self.energy_fraction}

    def describe(self) -> str:
        """The rule in words, for the summary and the outputs."""
        return (
            f"kinetic energy <= {self.energy_fraction:g} of its peak, or every momentum 0, "
            "at an output time"
        )


def on_terrain(model: Model) -> bool:
    """Whether ``model`` is a model on terrain: it gives a terrain for hazard maps (it
    overrides :meth:`~conslaw.model.Model.scene_dem`)."""
    return type(model).scene_dem is not Model.scene_dem


def can_come_to_rest(model: Model) -> bool:
    """Whether ``model`` has a kinetic energy to watch: a depth and a momentum."""
    return model.depth_index is not None and model.momentum_index is not None


def stop_rule(value: Any, model: Model) -> StopRule:
    """Validate a scene's ``[stop]`` table for ``model``: ``at_rest`` (true or false; default
    true for a model on terrain, :func:`on_terrain`, false otherwise) and ``energy_fraction``
    (a number in [0, 1), default :data:`ENERGY_FRACTION`).

    Parameters
    ----------
    value : Any
        The ``stop`` entry of the raw scene.
    model : Model
        The scene's model.

    Returns
    -------
    StopRule

    Raises
    ------
    ConfigError
        Naming the key and what it takes; also ``at_rest = true`` for a model without a depth
        and a momentum.
    """
    if not isinstance(value, Mapping):
        raise ConfigError(f"scene key 'stop': expected a table, got {value!r}")
    for key in value:
        if key not in STOP_KEYS:
            raise ConfigError(unknown_name_message("key in [stop]", key, STOP_KEYS))
    at_rest = value.get("at_rest", on_terrain(model) and can_come_to_rest(model))
    if not isinstance(at_rest, bool):
        raise ConfigError(f"stop.at_rest: expected true or false, got {at_rest!r}")
    fraction = finite_number(value.get("energy_fraction", ENERGY_FRACTION), "stop.energy_fraction")
    if not 0.0 <= fraction < 1.0:
        raise ConfigError(f"stop.energy_fraction: must be in [0, 1), got {fraction:g}")
    if at_rest and not can_come_to_rest(model):
        raise ConfigError(
            f"stop.at_rest: model '{model.name}' has no depth and momentum, so no kinetic "
            "energy to come to rest; set stop.at_rest = false"
        )
    return StopRule(at_rest, fraction)


@dataclass(frozen=True)
class StopRecord:
    """How a 2D run ended, recorded in its outputs (``states.npz`` entry ``stop``,
    ``hazard.json`` entry ``stop``) and told in the summary of ``conslaw run``.

    Attributes
    ----------
    rule : StopRule
    t : float
        The time the run reached (its last output).
    t_end : float
        The scene's ``t_end``, the cap.
    stopped : bool
        The run ended before ``t_end`` because the material came to rest.
    at_rest : bool
        The rule holds at ``t``.
    held : bool
        Every momentum is exactly 0 at ``t``.
    energy, peak_energy : float
        ``E(t)`` and ``E_peak`` (m^5/s^2: times the density, joules).
    rest_since : float or None
        The time of the step pair since which ``E <= energy_fraction E_peak`` has held without
        a break (None if it does not hold at ``t``).
    """

    rule: StopRule
    t: float
    t_end: float
    stopped: bool
    at_rest: bool
    held: bool
    energy: float
    peak_energy: float
    rest_since: float | None

    @property
    def fraction(self) -> float:
        """``E(t) / E_peak`` (0 when nothing has moved)."""
        return self.energy / self.peak_energy if self.peak_energy > 0.0 else 0.0

    def summary(self) -> str:
        """One line: ``stopped at rest at t = ... (kinetic energy ... of its peak)``, or
        ``ran to t_end = ..., still moving (...)``."""
        energy = f"kinetic energy {self.fraction:.2g} of its peak"
        if self.held:
            energy += ", every momentum 0"
        since = "" if self.rest_since is None else f"; at rest from t = {self.rest_since:.6g}"
        rule = f"rule: {self.rule.describe()}"
        if self.stopped:
            return f"stopped at rest at t = {self.t:.6g} ({energy}{since}; {rule})"
        state = "at rest there" if self.at_rest else "still moving"
        return f"ran to t_end = {self.t:.6g}, {state} ({energy}{since}; {rule})"

    def to_dict(self) -> dict[str, Any]:
        """The record as JSON-ready entries."""
        return {
            "rule": self.rule.describe(),
            "energy_fraction": self.rule.energy_fraction,
            "stopped_at_rest": self.stopped,
            "t": self.t,
            "t_end": self.t_end,
            "at_rest": self.at_rest,
            "every_momentum_zero": self.held,
            "kinetic_energy": self.energy,
            "peak_kinetic_energy": self.peak_energy,
            "kinetic_energy_fraction": self.fraction,
            "rest_since": self.rest_since,
        }

    def to_json(self) -> str:
        """:meth:`to_dict` as one JSON object (the ``stop`` entry of ``states.npz``)."""
        return json.dumps(self.to_dict())


class RestWatch:
    """Applies a :class:`StopRule` during a run: :meth:`pair` after every step pair (the peak
    kinetic energy), :meth:`timed` with the pair's time, :meth:`at_output` at every output time
    (whether to end the run there).

    Parameters
    ----------
    rule : StopRule
    model : Model
        A model with a depth and a momentum (:func:`can_come_to_rest`).
    aux : numpy.ndarray or None
        The model's coefficients at the cells (for ``flow_depth_and_speed``; the peak fields'
        ``aux``).
    cell_area : float
    q0 : numpy.ndarray
        The initial values, ``(n_vars, ny, nx)``.
    t_end : float
    """

    def __init__(
        self, rule: StopRule, model: Model, aux: Array | None, cell_area: float, q0: Array,
        t_end: float,
    ) -> None:  # fmt: skip
        assert model.depth_index is not None
        self.rule = rule
        self.model = model
        self.aux = aux
        self.cell_area = cell_area
        self.t_end = t_end
        self.depth_row = model.depth_index
        self.momentum_rows = [
            v for v in (model.momentum_index, model.momentum_y_index) if v is not None
        ]
        self.latest = self.energy(q0)
        self.peak = self.latest
        self.rest_since: float | None = None

    def energy(self, q: Array) -> float:
        """``E = 1/2 sum H |u|^2 dx dy`` of cell values ``q``."""
        fields = self.model.flow_depth_and_speed(q, self.aux)
        assert fields is not None
        return self.energy_of(q, fields[1])

    def energy_of(self, q: Array, speed: Array) -> float:
        """``E`` from the speed of every cell."""
        depth = q[self.depth_row]
        return 0.5 * self.cell_area * float(np.sum(depth * speed * speed))

    def pair(self, q: Array, speed: Array) -> None:
        """After a step pair: its energy (from ``speed``, ``Model.flow_depth_and_speed``),
        and the peak so far."""
        self.latest = self.energy_of(q, speed)
        self.peak = max(self.peak, self.latest)

    def timed(self, t: float) -> None:
        """The time of the pair just passed to :meth:`pair`: since when the energy rule has
        held."""
        if self.latest <= self.rule.energy_fraction * self.peak:
            if self.rest_since is None:
                self.rest_since = t
        else:
            self.rest_since = None

    def at_output(self, t: float, q: Array) -> StopRecord:
        """The record at output time ``t`` (values ``q``); its ``stopped``: end the run here
        (the rule holds, ``0 < t < t_end``)."""
        energy = self.energy(q)
        self.peak = max(self.peak, energy)
        held = not any(np.any(q[v]) for v in self.momentum_rows)
        at_rest = t > 0.0 and (held or energy <= self.rule.energy_fraction * self.peak)
        if held and self.rest_since is None:
            self.rest_since = t
        return StopRecord(
            rule=self.rule, t=t, t_end=self.t_end, stopped=at_rest and t < self.t_end,
            at_rest=at_rest, held=held, energy=energy, peak_energy=self.peak,
            rest_since=self.rest_since if at_rest else None,
        )  # fmt: skip
