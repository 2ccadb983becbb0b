"""How smoothly the run-out of ``sh-runout-shock`` follows the bed friction angle: the
run-out length (:func:`conslaw.ensemble.summary.member_summary`, the calibration's
``runout_length``) at delta = 24.80, 24.81, ..., 25.20 degrees, for several numbers of cells,
its straight-line fit, the scatter about the line (rms and largest) and that scatter as an
angle (rms / |slope|): the sharpest a calibration of delta on the run-out can be
(docs/calibration.md, "How sharp a fit can be").

Usage: ``python scripts/runout_jitter.py [N ...] [--set KEY=VALUE ...]`` (default 300 600
1200, on the domain ``x_max = 60``, 41 runs each; ``--set`` changes every run, e.g.
``--set cfl=0.2``); the table also gives the scatter of the deposit's centre of mass.
``python scripts/runout_jitter.py --history`` prints instead, for 300 cells and delta = 25,
25.005 and 25.01, the front (depth 1e-3 of the largest initial depth) and the centre of mass at
t = 0, 1, ..., 20: where the runs part.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np

import conslaw
from conslaw.config import parse_value
from conslaw.ensemble.summary import RELATIVE_THRESHOLD, margins, member_summary

DELTAS = np.round(np.arange(24.80, 25.2001, 0.01), 4)
X_MAX = 60.0


def scatter(values: np.ndarray) -> tuple[float, float, float]:
    """Slope of the straight-line fit over :data:`DELTAS`, rms and largest scatter about it."""
    slope, intercept = np.polyfit(DELTAS, values, 1)
    about = values - (slope * DELTAS + intercept)
    return float(slope), float(np.sqrt(np.mean(about**2))), float(np.abs(about).max())


def jitter(n_cells: int, changes: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """The run-out length and the deposit's centre of mass at every angle of :data:`DELTAS`."""
    lengths, centres = [], []
    for delta in DELTAS:
        overrides = {"n_cells": n_cells, "x_max": X_MAX, **changes}
        overrides |= {"parameters.delta": float(delta), "output_times": [0.0]}
        summary = member_summary(conslaw.simulate(conslaw.load_scene("sh-runout-shock", overrides)))
        lengths.append(summary["runout_length"])
        centres.append(summary["deposit_centre"])
    return np.array(lengths), np.array(centres)


def history() -> None:
    """Front and centre of mass against time for three nearby angles, and their differences
    from the first."""
    times = [float(t) for t in range(21)]
    fronts, centres = [], []
    for delta in (25.0, 25.005, 25.01):
        overrides = {"n_cells": 300, "x_max": X_MAX, "parameters.delta": delta}
        result = conslaw.simulate(
            conslaw.load_scene("sh-runout-shock", {**overrides, "output_times": times})
        )
        x = result.grid.centres()
        threshold = RELATIVE_THRESHOLD * float(result.initial.q[0].max())
        fronts.append([margins(x, state.q[0], threshold)[0] for state in result.states])
        centres.append([float(np.sum(state.q[0] * x) / np.sum(state.q[0]))
                        for state in result.states])  # fmt: skip
    print("| t | front (25) | front: 25.005 - 25 | 25.01 - 25 | centre: 25.005 - 25 | 25.01 - 25 |")
    print("|---|---|---|---|---|---|")
    for k, t in enumerate(times):
        print(f"| {t:g} | {fronts[0][k]:.4f} | {fronts[1][k] - fronts[0][k]:+.4f} | "
              f"{fronts[2][k] - fronts[0][k]:+.4f} | {centres[1][k] - centres[0][k]:+.5f} | "
              f"{centres[2][k] - centres[0][k]:+.5f} |")  # fmt: skip


def main() -> None:
    arguments = sys.argv[1:]
    if arguments == ["--history"]:
        history()
        return
    changes: dict[str, Any] = {}
    while "--set" in arguments:
        at = arguments.index("--set")
        key, _, value = arguments[at + 1].partition("=")
        changes[key] = parse_value(value)
        del arguments[at : at + 2]
    counts = [int(word) for word in arguments] or [300, 600, 1200]
    print("| N | dx | slope (per degree) | rms scatter | largest | rms as an angle (degree) "
          "| centre of mass: rms scatter | largest |")  # fmt: skip
    print("|---" * 8 + "|")
    for n_cells in counts:
        lengths, centres = jitter(n_cells, changes)
        slope, rms, largest = scatter(lengths)
        _, centre_rms, centre_largest = scatter(centres)
        dx = (X_MAX + 10.0) / n_cells
        print(f"| {n_cells} | {dx:.3f} | {slope:.3f} | {rms:.3f} | {largest:.3f} | "
              f"{rms / abs(slope):.3f} | {centre_rms:.4f} | {centre_largest:.4f} |")  # fmt: skip


if __name__ == "__main__":
    main()
