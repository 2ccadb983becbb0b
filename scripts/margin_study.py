"""The front-tracking margin error of the similarity solution against the grid and the Courant
number (docs/validation.md, "Earth pressure"). Prints

- the front error at t = 6 in cells for phi = 35, and for phi = delta = 30 with ``eps`` scaled so
  that ``beta = eps cos(zeta) K_act`` is the same;
- the largest front error over the run and the error at t = 6 for CFL 0.3 and 0.1;
- the relative error of the fitted margin slope ``S`` of eq. (19) against the exact
  ``2 H0 g0 / g^2`` at t = 0.5, 1, 1.5, 2 (180 cells, numpy reference path).

Usage: ``python scripts/margin_study.py`` (a few minutes).
"""

from __future__ import annotations

import math

import numpy as np

import conslaw
import conslaw.schemes.front_tracking.scheme as front_tracking
from conslaw.config import load_scene
from conslaw.simulation import build
from conslaw_models.savage_hutter import earth_pressure_coefficients


def front_errors(result: conslaw.RunResult) -> np.ndarray:
    """The front margin's error after every step (the margin history against the exact)."""
    history = result.margins
    assert history is not None and result.exact_solution is not None
    exact = np.array([result.exact_solution.margins(t) for t in history[:, 0]])  # type: ignore[attr-defined]
    return history[:, 3] - exact[:, 1]


def main() -> None:
    k35 = earth_pressure_coefficients(math.radians(35.0), math.radians(30.0))[0]
    k30 = earth_pressure_coefficients(math.radians(30.0), math.radians(30.0))[0]
    cases = {
        "phi = 35": {"parameters__phi": 35.0},
        "phi = delta, same beta": {"parameters__epsilon": 0.1 * k35 / k30},
    }
    print("| case | front error / dx at t = 6, N = 90, 180, 360, 720 |")
    print("|---|---|")
    for name, overrides in cases.items():
        row = []
        for n in (90, 180, 360, 720):
            result = conslaw.run("sh-similarity-ft", n_cells=n, **overrides)
            row.append(front_errors(result)[-1] / result.grid.dx)
        print(f"| {name} | " + ", ".join(f"{e:+.3f}" for e in row) + " |")
    print()
    print("| phi | CFL | N | largest front error | front error at t = 6 |")
    print("|---|---|---|---|---|")
    for phi in (30.0, 35.0):
        for cfl in (0.3, 0.1):
            for n in (360, 1440):
                result = conslaw.run("sh-similarity-ft", n_cells=n, cfl=cfl, parameters__phi=phi)
                errors = front_errors(result)
                print(f"| {phi} | {cfl} | {n} | {np.abs(errors).max():.2e} | {errors[-1]:+.2e} |")
    print()
    print("| CFL | relative error of the fitted slope S at t = 0.5, 1, 1.5, 2 (180 cells) |")
    print("|---|---|")
    original = front_tracking.FrontTrackingNT._profiles
    for cfl in (0.3, 0.1):
        log: list[tuple[float, float]] = []

        def recording(self, state, log=log):  # type: ignore[no-untyped-def]
            profiles = original(self, state)
            log.extend((state.t, p.slope) for p in profiles if p.sign > 0)
            return profiles

        front_tracking.FrontTrackingNT._profiles = recording  # type: ignore[method-assign]
        _, _, scheme, initial, exact = build(
            load_scene("sh-similarity-ft", {"n_cells": 180, "cfl": cfl})
        )
        scheme.reference_advance(initial, 2.0)  # type: ignore[attr-defined]
        front_tracking.FrontTrackingNT._profiles = original  # type: ignore[method-assign]
        times, slopes = np.array(log).T
        row = []
        for t in (0.5, 1.0, 1.5, 2.0):
            i = min(int(np.searchsorted(times, t)), times.size - 1)
            g, _ = exact.spread(times[i])  # type: ignore[union-attr]
            row.append(slopes[i] / (2 * exact.height * exact.half_length / g**2) - 1)  # type: ignore[union-attr]
        print(f"| {cfl} | " + ", ".join(f"{e:+.1e}" for e in row) + " |")


if __name__ == "__main__":
    main()
