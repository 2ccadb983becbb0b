"""Thacker's planar oscillation in a paraboloid with the Jiang–Tadmor 2D scheme (over the bowl its
numpy reference steps; docs/design.md, "Toward two dimensions"): SWASHES' case (h0 = 0.1, a = 1,
eta = 0.5, g = 9.81, centre of the square [0, 4]^2, walls), exact cell averages at t = 0, the L1
error of the depth at the end against the exact cell averages, the observed order between
successive grids and the smallest depth seen (checked after every 0.05 of time). Prints a
markdown table.

Usage: ``python scripts/thacker_planar.py [--reconstructor mc] [--periods 1] [--cells 25,50,100]``
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from conslaw import registry
from conslaw.grid2d import Grid2D
from conslaw.schemes.jiang_tadmor import JiangTadmor
from conslaw_models.shallow_water_2d import ShallowWater2D
from conslaw_models.shallow_water_2d_exact import ThackerPlanar

SIDES = {"left": "wall", "right": "wall", "bottom": "wall", "top": "wall"}


def run(reconstructor: str, n: int, t_end: float) -> tuple[int, float, float]:
    """Steps, L1 error of the depth at ``t_end`` and the smallest depth on ``n`` x ``n``."""
    exact = ThackerPlanar(h0=0.1, a=1.0, eta=0.5, g=9.81, x0=2.0, y0=2.0)
    model = ShallowWater2D(
        g=9.81, bowl_depth=0.1, bowl_radius=1.0, bowl_centre_x=2.0, bowl_centre_y=2.0
    )
    grid = Grid2D.from_bounds(0.0, 4.0, n, 0.0, 4.0, n)
    jt = JiangTadmor(model, registry.reconstructors.get(reconstructor), grid, SIDES)
    q = exact.cell_averages(grid.x.edges, grid.y.edges, 0.0)
    t, steps, smallest = 0.0, 0, math.inf
    while t < t_end:
        q, t, taken = jt.advance(q, t, min(t + 0.05, t_end))
        steps += taken
        smallest = min(smallest, float(np.min(q[0])))
    reference = exact.cell_averages(grid.x.edges, grid.y.edges, t_end)[0]
    return steps, float(np.abs(q[0] - reference).sum() * grid.cell_area), smallest


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reconstructor", default="mc")
    parser.add_argument("--periods", type=float, default=1.0)
    parser.add_argument("--cells", default="25,50,100")
    args = parser.parse_args()
    period = ThackerPlanar(h0=0.1, a=1.0, eta=0.5, g=9.81).period
    t_end = args.periods * period
    print(f"{args.reconstructor}, t = {t_end:.4f} ({args.periods:g} periods)")
    print("| N | steps | L1(h) | order | smallest depth |")
    print("|---|---|---|---|---|")
    previous = None
    for n in (int(c) for c in args.cells.split(",")):
        steps, error, smallest = run(args.reconstructor, n, t_end)
        order = "" if previous is None else f"{math.log2(previous / error):.2f}"
        print(f"| {n} | {steps} | {error:.2e} | {order} | {smallest:.1e} |", flush=True)
        previous = error


if __name__ == "__main__":
    main()
