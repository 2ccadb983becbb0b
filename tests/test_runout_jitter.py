"""The run-out of ``sh-runout-shock`` against the bed friction angle (docs/calibration.md, "How
sharp a fit can be"): smooth to round-off of the stopping at ``cfl = 0.2``; at the default
``cfl = 0.45`` it scatters by about 0.05 lengths whatever the grid (a known defect, marked so
that a fix shows)."""

from __future__ import annotations

import numpy as np
import pytest

import conslaw
from conslaw.ensemble.summary import member_summary

#: 21 angles 0.01 degrees apart around the calibration tests' true value.
DELTAS = np.round(np.arange(24.90, 25.1001, 0.01), 4)


def scatter_about_the_line(cfl: float, n_cells: int) -> float:
    """The rms scatter of the run-out length about its straight-line fit over :data:`DELTAS`
    (domain to x = 60, as in scripts/runout_jitter.py)."""
    lengths = []
    for delta in DELTAS:
        overrides = {"n_cells": n_cells, "x_max": 60.0, "cfl": cfl, "output_times": [0.0]}
        scene = conslaw.load_scene("sh-runout-shock", {**overrides, "parameters.delta": delta})
        lengths.append(member_summary(conslaw.simulate(scene))["runout_length"])
    values = np.array(lengths)
    slope, intercept = np.polyfit(DELTAS, values, 1)
    assert slope < 0.0  # more bed friction, a shorter run-out
    return float(np.sqrt(np.mean((values - (slope * DELTAS + intercept)) ** 2)))


def test_the_run_out_follows_the_friction_angle_smoothly_at_a_small_time_step() -> None:
    """At cfl = 0.2 the run-out scatters about its line by less than a tenth of a cell at 600
    cells (0.006 lengths measured; dx = 0.117)."""
    assert scatter_about_the_line(0.2, 600) < 0.012


@pytest.mark.xfail(strict=True, reason="the stop at cfl 0.45 jitters (docs/calibration.md)")
def test_the_run_out_follows_the_friction_angle_smoothly_at_the_default_time_step() -> None:
    """The same at the default cfl = 0.45: 0.05 lengths measured, not converging with the grid."""
    assert scatter_about_the_line(0.45, 600) < 0.012
