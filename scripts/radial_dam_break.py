"""A radial dam break with the Jiang–Tadmor 2D reference step (docs/design.md, "Toward two
dimensions"): depth ``h_in`` inside the circle of radius 0.5 centred on the square [-1, 1]^2,
``h_out`` (0: a dry bed) outside, at rest, walls; to t = 0.25. Printed per grid: whether every
depth stayed >= 0 and finite, the L1 difference (per unit length of radius, over r < 0.95) of the
depth along the x axis and along the diagonal, and the L1 change of the depth along the x axis
from this grid to the next finer (an estimate of the first-order error there). Prints a markdown
table.

Usage: ``python scripts/radial_dam_break.py [--reconstructor mc] [--cells 50,100,200]
[--outside 0.1]``
"""

from __future__ import annotations

import argparse

import numpy as np

from conslaw import registry
from conslaw.grid2d import Grid2D
from conslaw.schemes.jiang_tadmor import JiangTadmor
from conslaw_models.shallow_water_2d import ShallowWater2D

SIDES = {"left": "wall", "right": "wall", "bottom": "wall", "top": "wall"}
T_END = 0.25
RADII = np.linspace(0.0, 0.95, 400)


def profiles(reconstructor: str, n: int, outside: float) -> tuple[np.ndarray, np.ndarray, bool]:
    """The depth along the x axis and along the diagonal at :data:`RADII` (linear
    interpolation), and whether every depth stayed finite and >= 0, on ``n`` x ``n`` cells
    (``n`` even: the centre is a cell corner)."""
    grid = Grid2D.from_bounds(-1.0, 1.0, n, -1.0, 1.0, n)
    limiter = registry.reconstructors.get(reconstructor)
    jt = JiangTadmor(ShallowWater2D(g=1.0), limiter, grid, SIDES)
    x, y = grid.centres()
    q = np.zeros((3, n, n))
    inside = x[None, :] ** 2 + y[:, None] ** 2 < 0.25
    q[0] = np.where(inside, 1.0, outside)
    t, admissible = 0.0, True
    while t < T_END:
        q, t, _ = jt.advance(q, t, min(t + 0.05, T_END))
        admissible &= bool(np.all(np.isfinite(q)) and np.min(q[0]) >= 0.0)
    half = n // 2
    # The two rows next to y = 0 (at y = -+dx/2), and the diagonal cells (k, k) for x > 0.
    axis_h = 0.5 * (q[0, half - 1, half:] + q[0, half, half:])
    axis_r = np.hypot(x[half:], 0.5 * grid.dy)
    diagonal_h = q[0, np.arange(half, n), np.arange(half, n)]
    diagonal_r = np.hypot(x[half:], y[half:])
    return np.interp(RADII, axis_r, axis_h), np.interp(RADII, diagonal_r, diagonal_h), admissible


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reconstructor", default="mc")
    parser.add_argument("--cells", default="50,100,200")
    parser.add_argument("--outside", type=float, default=0.1)
    args = parser.parse_args()
    cells = [int(c) for c in args.cells.split(",")]
    runs = [profiles(args.reconstructor, n, args.outside) for n in cells]
    step = RADII[1] - RADII[0]
    print(f"{args.reconstructor}, h = 1 inside r < 0.5, {args.outside:g} outside, t = {T_END:g}")
    print("| N | h >= 0, finite | L1 axis - diagonal | L1 axis: N - 2N |")
    print("|---|---|---|---|")
    for k, (n, (axis, diagonal, admissible)) in enumerate(zip(cells, runs, strict=True)):
        across = float(np.sum(np.abs(axis - diagonal)) * step)
        finer = "" if k + 1 == len(runs) else f"{np.sum(np.abs(axis - runs[k + 1][0])) * step:.2e}"
        print(f"| {n} | {admissible} | {across:.2e} | {finer} |", flush=True)


if __name__ == "__main__":
    main()
