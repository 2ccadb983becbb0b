"""The energy line on the plane-to-flat terrain (docs/validation.md, "Savage–Hutter on terrain").

python scripts/energy_line.py [--cells NX] [--thickness 4,2,1,0.5]

A mass released on the 40-degree plane of ``terrain-plane-to-flat`` with Coulomb friction
``mu = tan(delta)`` comes to rest on the run-out. Where does its centre of mass stop?

- the classical energy line of a point (:func:`conslaw_models.sliding_point.energy_line_stop`):
  the drop equals ``mu`` times the horizontal distance; it leaves out the friction of the
  curved transition (the centripetal ``kappa U^2`` presses the mass on the bed) and the work of
  the earth pressure;
- a point sliding along the profile with that curvature friction
  (:func:`conslaw_models.sliding_point.sliding_stop`), released at rest from every x of the
  release (the mean of the stopping points: each column of uniform thickness is one such point
  without pressure);
- the model, whose centre of mass at the end includes the pressure's work, which falls with
  the aspect ratio (thickness over the release's length).

Prints a markdown table: for each release thickness, the centre of mass of the deposit in the
model and the two predictions, and the misfits.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import conslaw
from conslaw_models.sliding_point import energy_line_stop, sliding_stop
from conslaw_models.terrain_surface import PlaneToFlat

G = 9.81
ANGLE, RADIUS, END, DELTA = 40.0, 200.0, 700.0, 30.0
RELEASE = (100.0, 200.0)


def main() -> None:
    """Print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=100, help="cells along x (default 100)")
    parser.add_argument("--thickness", default="4,2,1,0.5", help="release thicknesses, m")
    args = parser.parse_args()
    surface = PlaneToFlat(ANGLE, RADIUS, END)
    mu = math.tan(math.radians(DELTA))
    starts = np.linspace(*RELEASE, 41)[:-1] + 1.25  # column centres of a 2.5 m sampling
    classical = float(np.mean([energy_line_stop(surface, x0, mu) for x0 in starts]))
    sliding = float(np.mean([sliding_stop(surface, x0, mu, G) for x0 in starts]))
    print(
        "| release thickness (m) | aspect ratio | model x_c (m) | sliding point x_c (m) | "
        "model - sliding (m) | energy line x_c (m) | model - energy line (m) | "
        "cells with momentum at t_end | run time (s) |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for thickness in (float(v) for v in args.thickness.split(",")):
        started = time.perf_counter()
        result = conslaw.run_2d(
            "terrain-plane-to-flat",
            n_cells=[args.cells, args.cells // 2],
            t_end=90.0,
            output_times=[90.0],
            initial__thickness=thickness,
        )
        seconds = time.perf_counter() - started
        x, _ = result.grid.centres()
        depth = result.states[-1].q[0]
        centre = float(np.sum(depth.sum(axis=0) * x) / depth.sum())
        moving = int(np.count_nonzero(np.any(result.states[-1].q[1:] != 0.0, axis=0)))
        aspect = thickness / (RELEASE[1] - RELEASE[0])
        print(
            f"| {thickness:g} | {aspect:.3g} | {centre:.1f} | {sliding:.1f} | "
            f"{centre - sliding:+.1f} | {classical:.1f} | {centre - classical:+.1f} | {moving} | "
            f"{seconds:.0f} |"
        )


if __name__ == "__main__":
    main()
