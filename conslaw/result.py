"""What a run produced (:class:`RunResult`): handed by the runner to the output layer, the figures
and the studies, none of which calls back into the scheme."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    import xarray

    from conslaw.analysis import ErrorNorms
    from conslaw.config import Scene
    from conslaw.exact import ExactSolution
    from conslaw.grid import Grid
    from conslaw.model import Model
    from conslaw.schemes.base import Scheme
    from conslaw.state import State

Array = NDArray[np.float64]


@dataclass(repr=False)
class RunResult:
    """Everything a run produced.

    Attributes
    ----------
    states : list of State
        The solution at every output time (primary grid).
    exact : list of ndarray or None
        Exact cell averages at the same times (None without an exact solution).
    errors : list of ErrorNorms or None
        Error norms (docs/equations.md, "Error norms") of variable 0 against the exact cell
        averages.
    steps : int
        Time steps taken.
    solve_seconds : float
        Wall time of the time loop (set-up, compilation and output excluded).
    mass_drift : ndarray
        Relative change of the total of every conserved variable from t=0 to the end.
    margins : ndarray or None
        With front tracking: rows ``t, x_rear, u_rear, x_front, u_front`` after every step.
    coefficients : list of ndarray
        The model's coefficients in every cell at every output time, as the scheme used them
        in that state (``(n_aux, n)``, :meth:`conslaw.schemes.base.Scheme.cell_coefficients`):
        recorded by the runner, so that the output layer never calls back into the scheme.
    """

    scene: Scene
    model: Model
    grid: Grid
    scheme: Scheme
    initial: State
    states: list[State]
    exact_solution: ExactSolution | None
    exact: list[Array | None]
    errors: list[ErrorNorms | None]
    steps: int
    solve_seconds: float
    mass_drift: Array
    compile_seconds: float = 0.0
    exact_note: str | None = None
    margins: Array | None = None
    files: list[Path] = field(default_factory=list)
    coefficients: list[Array] = field(default_factory=list)

    def __repr__(self) -> str:
        """One line: the scene, where the run got to and its headline error (the arrays are
        in :attr:`states`; the whole record would fill a screen)."""
        if not self.states:
            return f"<RunResult {self.scene.name}: no output yet>"
        return run_line(self, "RunResult", f"N={self.grid.n_cells}")

    @property
    def final(self) -> State:
        """The state at ``t_end``."""
        return self.states[-1]

    def to_xarray(self) -> xarray.Dataset:
        """The run as a labelled dataset: every conserved variable (and, where an exact solution
        applies, its exact cell averages ``<name>_exact``) over ``t`` (the output times) and
        ``x`` (the cell centres), with long names and units, and the run's scene, model,
        scheme, reconstructor, steps and conslaw version as attributes. Write it with
        ``to_netcdf`` (scipy's netCDF3 writer needs nothing more) or ``to_zarr``.

        Units: ``units = "1"`` (dimensionless) for a model whose equations are scaled (the
        Savage–Hutter long names give the scales); otherwise the values are in the scene's own
        units, and no ``units`` attribute is claimed.
        """
        import xarray as xr

        from conslaw import __version__
        from conslaw.provenance import as_json, record

        names = self.model.long_names
        units = {"units": "1"} if self.model.dimensionless else {}
        t = np.array([state.t for state in self.states])
        q = np.array([state.q for state in self.states])
        variables: dict[str, tuple[tuple[str, str], Array, dict[str, str]]] = {}
        for v, name in enumerate(self.model.variables):
            attrs = {"long_name": names.get(name, name), **units}
            variables[name] = (("t", "x"), q[:, v, :], attrs)
            if any(e is not None for e in self.exact):
                exact = np.array(
                    [e[v] if e is not None else np.full(q.shape[-1], np.nan) for e in self.exact]
                )
                exact_attrs = {**attrs, "long_name": f"exact cell average of {attrs['long_name']}"}
                variables[f"{name}_exact"] = (("t", "x"), exact, exact_attrs)
        coordinates = {
            "t": ("t", t, {"long_name": names.get("t", "time"), **units}),
            "x": ("x", self.grid.centres(), {"long_name": names.get("x", "x"), **units}),
        }
        attributes = {
            "scene": self.scene.name,
            "model": self.scene.model,
            "scheme": self.scene.scheme,
            "reconstructor": self.scene.reconstructor_label,
            "n_cells": self.grid.n_cells,
            "steps": self.steps,
            "conslaw_version": __version__,
            "provenance": as_json(record(self.scene)),
        }
        return xr.Dataset(variables, coordinates, attributes)

    def outflow_fed_note(self, threshold: float = 1e-3) -> str | None:
        """A warning if the total depth grew by more than ``threshold`` (relative) in a run whose
        open boundaries are all ``outflow``: zero-gradient ghost cells let material moving
        towards the domain flow in, so an outflow boundary can feed mass (a release whose rear
        reaches the upper end of the domain). None otherwise, and None when the run is compared
        with an exact solution, which then judges the boundary (an exact solution with material
        beyond it, as an endless reservoir upstream, needs that inflow)."""
        depth = self.model.depth_index
        kinds = {self.scene.left.kind, self.scene.right.kind}
        if depth is None or "outflow" not in kinds or "inflow" in kinds:
            return None
        if self.exact_solution is not None:
            return None
        growth = float(self.mass_drift[depth])
        if not growth > threshold:
            return None
        return (
            f"the total {self.model.variables[depth]} grew by {100 * growth:.3g} % through an "
            "outflow boundary (its zero-gradient ghost cells let material that moves towards "
            "the domain flow in); a wall or a longer domain avoids it"
        )

    def headline_error(self) -> float | None:
        """L1 error of variable 0 at ``t_end`` against the exact cell averages (None if unknown)."""
        error = self.errors[-1]
        return None if error is None else error.l1


def run_line(result: Any, kind: str, cells: str) -> str:
    """``<kind scene: model, scheme, cells, outputs to t, steps, headline error>``: the one-line
    ``repr`` of a 1D or 2D run result (``result.scene``, ``.states``, ``.final``, ``.steps``,
    ``.headline_error()``)."""
    error = result.headline_error()
    shown = "no exact solution" if error is None else f"L1 error {error:.4g}"
    return (
        f"<{kind} {result.scene.name}: {result.scene.model}, {result.scene.scheme}, {cells}, "
        f"{len(result.states)} outputs to t={result.final.t:g}, {result.steps} steps, {shown}>"
    )
