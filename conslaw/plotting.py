"""Plots of runs: profiles at the output times against the exact solution."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

if TYPE_CHECKING:
    from conslaw.simulation import RunResult


def profiles_figure(result: RunResult) -> Any:
    """One panel per conserved variable: numerical cell averages (markers) at every output
    time, the exact solution (black line) where the model has one."""
    model = result.model
    n_vars = model.n_vars
    figure, axes = plt.subplots(n_vars, 1, figsize=(8, 3.2 * n_vars), sharex=True, squeeze=False)
    colours = plt.cm.viridis(np.linspace(0.0, 0.85, len(result.states)))
    fine = np.linspace(result.grid.x_min, result.grid.x_max, 4001)
    for v, name in enumerate(model.variables):
        axis = axes[v, 0]
        for state, colour in zip(result.states, colours, strict=True):
            axis.plot(
                state.x,
                state.q[v],
                "o",
                ms=2.5,
                color=colour,
                label=f"{result.scene.scheme}, t={state.t:g}",
            )
            if result.exact_solution is not None:
                axis.plot(
                    fine,
                    result.exact_solution.point_values(fine, state.t)[v],
                    "k-",
                    lw=0.9,
                    label="exact" if state is result.states[-1] else None,
                )
        axis.set_ylabel(name)
        axis.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=8, loc="best")
    axes[-1, 0].set_xlabel("x")
    error = result.headline_error()
    subtitle = f", L1 error {error:.3e}" if error is not None else ""
    axes[0, 0].set_title(
        f"{result.scene.name}: {model.name}, {result.scene.reconstructor}, "
        f"N={result.grid.n_cells}{subtitle}",
        fontsize=10,
    )
    figure.tight_layout()
    return figure
