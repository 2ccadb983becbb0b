"""Initial conditions: exact cell averages of the initial data on a grid.

Kinds (scene table ``[initial]``, key ``kind``):

``piecewise-constant``
    ``breakpoints`` (increasing list), ``states`` (one more entry than breakpoints; a number for a
    scalar model, else a list with one number per conserved variable).
``sine``
    ``u0 = mean + amplitude sin(2 pi wavenumber (x - x_min) / L)``, scalar models only.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number, shown, unknown_name_message
from conslaw.grid import Grid

#: Largest sine wavenumber (every integer up to it is exact as a float).
MAX_WAVENUMBER = 2**53

if TYPE_CHECKING:
    from conslaw.model import Model

Array = NDArray[np.float64]

#: kind -> (required keys, optional keys with defaults, one-line description)
INITIAL_KINDS: dict[str, tuple[tuple[str, ...], dict[str, Any], str]] = {
    "piecewise-constant": (
        ("breakpoints", "states"),
        {},
        "constant states separated at breakpoints (Riemann problems, dam breaks)",
    ),
    "sine": (
        ("mean", "amplitude"),
        {"wavenumber": 1},
        "u0 = mean + amplitude*sin(2*pi*wavenumber*(x - x_min)/L), scalar models",
    ),
}


def _number(value: Any, key: str) -> float:
    return finite_number(value, f"initial.{key}")


def checked_options(
    table: Any, kinds: Mapping[str, tuple[tuple[str, ...], dict[str, Any], str]]
) -> tuple[str, dict[str, Any]]:
    """The kind of an ``[initial]`` table and its options with the defaults filled in; unknown
    kinds and keys and missing required keys are ConfigErrors naming them. ``kinds``: kind ->
    (required keys, optional keys with defaults, description)."""
    if not isinstance(table, Mapping):
        raise ConfigError(f"initial: expected a table, got {table!r}")
    kind = table.get("kind")
    if kind is None:
        raise ConfigError(f"initial.kind is required; allowed: {', '.join(sorted(kinds))}")
    if not isinstance(kind, str) or kind not in kinds:
        raise ConfigError(unknown_name_message("initial.kind", str(kind), kinds))
    required, defaults, _ = kinds[kind]
    allowed = {"kind", *required, *defaults}
    for key in table:
        if key not in allowed:
            raise ConfigError(unknown_name_message(f"key in [initial] ({kind})", key, allowed))
    for key in required:
        if key not in table:
            raise ConfigError(f"initial.{key} is required for kind '{kind}'")
    return kind, {**defaults, **{k: v for k, v in table.items() if k != "kind"}}


@dataclass(frozen=True)
class InitialCondition:
    """A validated initial condition: ``kind`` and its options."""

    kind: str
    options: Mapping[str, Any] = field(default_factory=dict)

    @classmethod
    def from_table(
        cls, table: Mapping[str, Any], model_class: type[Model] | None = None
    ) -> InitialCondition:
        """Validate a scene's ``[initial]`` table (unknown kinds and keys are errors).

        The allowed kinds are the generic ones and those the model adds (``initial_kinds``).
        """
        kinds = {**INITIAL_KINDS, **(model_class.initial_kinds if model_class else {})}
        kind, options = checked_options(table, kinds)
        return cls(kind, options)

    def cell_averages(self, grid: Grid, model: Model) -> Array:
        """Exact cell averages of the initial data on the primary grid, shape (n_vars, n)."""
        if self.kind == "piecewise-constant":
            return self._piecewise_constant(grid, model)
        if self.kind == "sine":
            return self._sine(grid, model)
        return model.initial_cell_averages(self.kind, self.options, grid)

    def _piecewise_constant(self, grid: Grid, model: Model) -> Array:
        breakpoints_raw = self.options["breakpoints"]
        states_raw = self.options["states"]
        if not isinstance(breakpoints_raw, list) or not isinstance(states_raw, list):
            raise ConfigError("initial.breakpoints and initial.states must be lists")
        breakpoints = np.array([_number(b, "breakpoints") for b in breakpoints_raw])
        if breakpoints.size and np.any(np.diff(breakpoints) <= 0):
            raise ConfigError(f"initial.breakpoints must be increasing, got {breakpoints_raw}")
        if len(states_raw) != breakpoints.size + 1:
            raise ConfigError(
                f"initial.states needs {breakpoints.size + 1} entries (one more than "
                f"breakpoints), got {len(states_raw)}"
            )
        states = np.empty((model.n_vars, len(states_raw)))
        for k, entry in enumerate(states_raw):
            values = entry if isinstance(entry, list) else [entry]
            if len(values) != model.n_vars:
                raise ConfigError(
                    f"initial.states[{k}]: expected {model.n_vars} numbers "
                    f"({', '.join(model.variables)}), got {entry!r}"
                )
            states[:, k] = [_number(v, f"states[{k}]") for v in values]
        admissible = model.is_admissible(states)
        if not admissible.all():
            k = int((~admissible).nonzero()[0][0])
            raise ConfigError(
                f"initial.states[{k}] = {states_raw[k]!r} is not an admissible state of "
                f"'{model.name}'"
            )
        averages = piecewise_constant_averages(grid.edges, breakpoints, states)
        if model.capabilities()["correction"]:
            # Admissible states need not average to an admissible one: 60 % of a moving film of
            # 1e-10 (wet if the dry tolerance is below it) and 40 % of a dry bed make a cell
            # below the tolerance that holds momentum. Such a cell gets the rule the scheme
            # applies after every step (model.correct: a dry cell holds no momentum).
            averages = model.correct(averages, model.aux(grid.centres(), grid.dx), 0.0)
        return averages

    def _sine(self, grid: Grid, model: Model) -> Array:
        if model.n_vars != 1:
            raise ConfigError(f"initial.kind 'sine' needs a scalar model; '{model.name}' is not")
        mean = _number(self.options["mean"], "mean")
        amplitude = _number(self.options["amplitude"], "amplitude")
        wavenumber = self.options["wavenumber"]
        if (
            isinstance(wavenumber, bool)
            or not isinstance(wavenumber, int)
            or not 1 <= wavenumber <= MAX_WAVENUMBER
        ):
            raise ConfigError(
                "initial.wavenumber: expected an integer >= 1 and <= 2**53, "
                f"got {shown(wavenumber)}"
            )
        k = 2.0 * np.pi * wavenumber / grid.length
        edges = grid.edges
        antiderivative = mean * edges - amplitude / k * np.cos(k * (edges - grid.x_min))
        return (np.diff(antiderivative) / grid.dx)[None, :]


def piecewise_constant_averages(edges: Array, breakpoints: Array, states: Array) -> Array:
    """Exact cell averages of constant ``states[:, k]`` between increasing ``breakpoints``.

    A cell inside one piece gets that piece's state bit for bit (a uniform layer starts exactly
    uniform); a cell with breakpoints inside gets the difference of the antiderivative
    ``F(x) = integral from breakpoints[0] to x`` at its edges over its width. Memory and time are
    linear in the number of cells plus pieces (no cells-by-pieces matrix).
    """
    left, right = edges[:-1], edges[1:]
    piece_left = np.searchsorted(breakpoints, left, side="right")
    piece_right = np.searchsorted(breakpoints, right, side="left")
    averages = np.ascontiguousarray(states[:, piece_left])
    split = np.nonzero(piece_left != piece_right)[0]
    if split.size:
        lengths = np.diff(breakpoints)
        # F at every breakpoint: the integral over the pieces between breakpoints[0] and it.
        at_breakpoints = np.concatenate(
            [np.zeros((states.shape[0], 1)), np.cumsum(states[:, 1:-1] * lengths, axis=1)], axis=1
        )

        def antiderivative(x: Array) -> Array:
            piece = np.searchsorted(breakpoints, x, side="right")
            start = np.maximum(piece - 1, 0)
            return at_breakpoints[:, start] + states[:, piece] * (x - breakpoints[start])

        width = right[split] - left[split]
        averages[:, split] = (antiderivative(right[split]) - antiderivative(left[split])) / width
    return averages
