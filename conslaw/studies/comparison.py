"""Several schemes on one scene: one figure, one table (``conslaw compare``).

Every variant is the scene with another scheme (and its options, ``lagrangian:viscosity=0.02``),
everything else equal; all are validated before the first run. A variant that breaks down
(:class:`~conslaw.errors.SchemeBreakdownError`) does not stop the comparison: its row says where it
broke down, and the figure shows the states it reached, the last one marked. The table holds, per
variant, the errors (docs/equations.md, "Error norms") of ``h`` at ``t_end`` against the exact cell
averages (where the
scene has an exact solution), the steps, the solve time and the mass drift.

:func:`runout_comparison` builds the Fig. 3-style comparison of the paper (sh-runout-shock with
Nessyahu–Tadmor, the Lagrangian scheme without and with artificial viscosity).
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from conslaw.config import Scene, scheme_variants
from conslaw.errors import SchemeBreakdownError
from conslaw.exact import ExactSolution
from conslaw.simulation import RunResult, exact_solution_for, simulate
from conslaw.state import State

#: The schemes of the Fig. 3-style comparison (Tai et al. 2001: NT; Lagrangian without and with
#: artificial viscosity, Savage & Hutter's mu = 0.01-0.03).
RUNOUT_SCHEMES = (
    "nessyahu-tadmor",
    "lagrangian:viscosity=0.0",
    "lagrangian:viscosity=0.02",
    "lagrangian:viscosity=0.02:pressure=flux",
)


@dataclass
class VariantRun:
    """One scheme's run: the states it reached (at the output times; after a breakdown the last
    good state is appended) and its result if it finished."""

    scene: Scene
    states: list[State]
    result: RunResult | None
    seconds: float
    breakdown: str | None = None

    @property
    def label(self) -> str:
        """Scheme, options and (if used) reconstructor."""
        reconstructor = self.scene.reconstructor_label
        return self.scene.scheme_label + ("" if reconstructor == "-" else f", {reconstructor}")


@dataclass
class Comparison:
    """The runs of :func:`compare`."""

    scene: Scene
    runs: list[VariantRun] = field(default_factory=list)
    exact_solution: ExactSolution | None = None
    exact_note: str | None = None

    def table(self) -> str:
        """Markdown table: errors of h at t_end, steps, solve time, mass drift, outcome."""
        lines = [
            "| scheme | N | steps | L1(h) | L2(h) | Linf(h) | solve s | mass drift | outcome |",
            "|---|---|---|---|---|---|---|---|---|",
        ]
        for run in self.runs:
            result = run.result
            if result is None:
                steps, norms, seconds, drift = "-", "- | - | -", f"({run.seconds:.3f})", "-"
                outcome = f"breakdown: {run.breakdown}"
            else:
                error = result.errors[-1]
                norms = (
                    "- | - | -"
                    if error is None
                    else f"{error.l1:.3e} | {error.l2:.3e} | {error.linf:.3e}"
                )
                steps, seconds = str(result.steps), f"{result.solve_seconds:.3f}"
                drift = f"{result.mass_drift[result.model.depth_index or 0]:+.1e}"
                outcome = f"reached t = {result.final.t:g}"
            lines.append(
                f"| {run.label} | {run.scene.n_cells} | {steps} | {norms} | {seconds} | {drift} "
                f"| {outcome} |"
            )
        return "\n".join(lines)

    def notes(self) -> str:
        """What the errors are measured against."""
        if self.exact_solution is None:
            return f"no exact solution: {self.exact_note}"
        return (
            f"errors of h at t = {self.scene.t_end:g} against the exact cell averages on the "
            f"scene's grid ({self.scene.n_cells} cells; the L1 norm of docs/equations.md); "
            "solve time without compilation, in parentheses the wall time to the breakdown"
        )


def compare(
    scene: str | Path,
    schemes: Sequence[str],
    overrides: Mapping[str, Any] | None = None,
    progress: Any = None,
) -> Comparison:
    """Run ``scene`` with every scheme spec in ``schemes`` (see the module docstring)."""
    variants = scheme_variants(scene, list(schemes), overrides)
    first = variants[0]
    from conslaw import registry
    from conslaw.grid import Grid

    model = registry.models.get(first.model)(**first.parameters)
    exact, note = exact_solution_for(first, model, Grid(first.x_min, first.x_max, first.n_cells))
    comparison = Comparison(first, exact_solution=exact, exact_note=note)
    for variant in variants:
        started = time.perf_counter()
        try:
            result = simulate(variant, progress)
        except SchemeBreakdownError as error:
            states = list(error.completed_states)
            if error.state is not None:
                states.append(error.state)
            comparison.runs.append(
                VariantRun(variant, states, None, time.perf_counter() - started, str(error))
            )
            continue
        comparison.runs.append(
            VariantRun(variant, result.states, result, time.perf_counter() - started)
        )
    return comparison


def _profile(state: State) -> tuple[Any, Any, Any]:
    """Positions, depths and velocities to draw: a Lagrangian state on its own elements (centres,
    depths, mean node velocities), any other on the grid (NaN velocity where dry)."""
    if state.nodes is not None:
        x = state.nodes.positions
        u = 0.5 * (state.nodes.velocities[:-1] + state.nodes.velocities[1:])
        return 0.5 * (x[:-1] + x[1:]), state.nodes.depths, u
    h = state.q[0]
    wet = h > 1e-6
    u = np.full_like(h, np.nan)
    u[wet] = state.q[1, wet] / h[wet]
    return state.x, h, u


def _state_at(run: VariantRun, t: float) -> State | None:
    """The run's state at output time t, or its last state before t if it broke down earlier."""
    reached = [s for s in run.states if s.t <= t]
    return reached[-1] if reached else None


def comparison_figure(comparison: Comparison) -> Any:
    """All variants in one figure: ``h`` at every output time (one panel each; with a single
    output time also ``u``), the Lagrangian runs on their own elements (lines), the others on
    the grid (dots), the exact solution in grey. A run that broke down shows the states it
    reached and, in the panels after the breakdown, its last good state (dashed, labelled with
    its time); a peak far above the other runs is cut and its height written in the panel."""
    import matplotlib.pyplot as plt

    times = list(comparison.scene.output_times)
    show_velocity = len(times) == 1
    rows = len(times) + (1 if show_velocity else 0)
    figure, axes = plt.subplots(rows, 1, figsize=(9, 2.3 * rows + 0.6), sharex=True, squeeze=False)
    colours = plt.cm.tab10(np.arange(len(comparison.runs)) % 10)
    fine = np.linspace(comparison.scene.x_min, comparison.scene.x_max, 4001)
    for row, t in enumerate(times):
        axis = axes[row, 0]
        tops: list[float] = []
        stale_peaks: list[tuple[float, float]] = []
        if comparison.exact_solution is not None:
            exact = comparison.exact_solution.point_values(fine, t)
            axis.plot(fine, exact[0], "k-", lw=1.6, alpha=0.5, zorder=0, label="exact")
            tops.append(float(exact[0].max()))
            if show_velocity:
                with np.errstate(invalid="ignore", divide="ignore"):
                    u = np.where(exact[0] > 0, exact[1] / exact[0], np.nan)
                axes[-1, 0].plot(fine, u, "k-", lw=1.6, alpha=0.5, zorder=0)
        for run, colour in zip(comparison.runs, colours, strict=True):
            state = _state_at(run, t)
            if state is None:
                continue
            x, h, u = _profile(state)
            stale = state.t < t
            label = f"{run.label}: broke down, last state t={state.t:.4g}" if stale else run.label
            if state.nodes is not None:
                style = "--" if stale else "-"
                axis.plot(x, h, style, color=colour, lw=0.9, marker=".", ms=2.5, label=label)
            else:
                axis.plot(x, h, "x" if stale else "o", ms=2.2, color=colour, label=label)
            if show_velocity:
                axes[-1, 0].plot(x, u, ".", ms=2.5, color=colour)
            if stale:
                stale_peaks.append((float(h.max()), float(x[h.argmax()])))
            else:
                tops.append(float(h.max()))
        _cut_off_scale_peaks(axis, tops, stale_peaks)
        axis.set_ylabel("h")
        axis.text(0.99, 0.85, f"t = {t:g}", transform=axis.transAxes, ha="right", fontsize=9)
        axis.grid(alpha=0.3)
        if row == 0 or stale_peaks:
            axis.legend(fontsize=7, loc="upper left")
    if show_velocity:
        axes[-1, 0].set_ylabel("u")
        axes[-1, 0].grid(alpha=0.3)
    axes[-1, 0].set_xlabel("x")
    axes[0, 0].set_title(
        f"{comparison.scene.name}, N = {comparison.scene.n_cells} (cells or Lagrangian elements)",
        fontsize=10,
    )
    figure.tight_layout()
    return figure


def _cut_off_scale_peaks(
    axis: Any, tops: list[float], stale_peaks: list[tuple[float, float]]
) -> None:
    """Limit the h axis to 1.3 times the highest of the finished runs (and the exact solution)
    when a broken-down run peaks far above them, and write that peak into the panel."""
    if not tops or not stale_peaks:
        return
    limit = 1.3 * max(tops)
    high = [(h, x) for h, x in stale_peaks if h > limit]
    if not high:
        return
    axis.set_ylim(-0.05 * limit, limit)
    text = "; ".join(f"off scale: h = {h:.3g} at x = {x:.4g}" for h, x in high)
    axis.text(0.99, 0.65, text, transform=axis.transAxes, ha="right", fontsize=8, color="tab:red")


def write_comparison(comparison: Comparison, folder: Path) -> list[Path]:
    """``compare-SCENE.md`` (the table and notes) and ``compare-SCENE.png``; atomic writes."""
    import matplotlib.pyplot as plt

    from conslaw.io import atomic_write_bytes, prepare_output_dir, write_figure

    folder = prepare_output_dir(folder)
    stem = f"compare-{comparison.scene.name}"
    text = comparison.table() + "\n\n" + comparison.notes() + "\n"
    written = [atomic_write_bytes(folder / f"{stem}.md", text.encode())]
    figure = comparison_figure(comparison)
    written.append(write_figure(folder / f"{stem}.png", figure))
    plt.close(figure)
    return written


def runout_comparison(folder: Path, overrides: Mapping[str, Any] | None = None) -> list[Path]:
    """The Fig. 3-style comparison: ``sh-runout-shock`` with Nessyahu–Tadmor and the Lagrangian
    scheme with ``mu = 0`` and ``mu = 0.02`` (:data:`RUNOUT_SCHEMES`), written to ``folder`` as
    ``compare-sh-runout-shock.{md,png}``. The same as ``conslaw compare sh-runout-shock
    --scheme nessyahu-tadmor,lagrangian,lagrangian:viscosity=0.02``.
    """
    return write_comparison(compare("sh-runout-shock", RUNOUT_SCHEMES, overrides), folder)
