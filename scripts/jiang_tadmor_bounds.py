"""How far the Jiang–Tadmor scheme leaves the range of its initial data, by reconstructor and
Courant number (docs/design.md, "The 2D time step and the maximum principle"): Burgers in 2D,
``u = 1`` inside the circle of radius 0.2 about the centre of the periodic unit square and 0
outside, 64 x 64 cells, to ``t = 0.3`` (the scene ``burgers2d-shock`` with a ``circle``
initial condition), through :func:`conslaw.run_2d`. Prints a markdown table of the largest and
smallest value reached at the end.

Usage: ``python scripts/jiang_tadmor_bounds.py``
"""

from __future__ import annotations

import numpy as np

import conslaw

RECONSTRUCTORS = ("none", "minmod", "mc", "weno5")
COURANT_NUMBERS = (0.45, 0.25, 0.2, 0.125)
CIRCLE = {"kind": "circle", "centre": [0.5, 0.5], "radius": 0.2, "inside": 1.0, "outside": 0.0}


def main() -> None:
    print("| reconstructor | " + " | ".join(f"cfl {c}: max, min" for c in COURANT_NUMBERS) + " |")
    print("|---|" + "---|" * len(COURANT_NUMBERS))
    for name in RECONSTRUCTORS:
        cells = []
        for cfl in COURANT_NUMBERS:
            result = conslaw.run_2d(
                "burgers2d-shock",
                initial=CIRCLE,
                n_cells=[64, 64],
                t_end=0.3,
                output_times=[],
                reconstructor=name,
                cfl=cfl,
            )
            u = result.final.q[0]
            cells.append(f"{np.max(u):.4f}, {np.min(u):.1e}")
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
