"""A dam break along the diagonal with the Jiang–Tadmor 2D reference step (docs/design.md,
"Toward two dimensions"): on the periodic square [0, 4]^2 the depth is ``h_deep`` where
``(x + y) mod 4 < 2`` and ``h_shallow`` elsewhere, at rest; until the waves of the two dams (at
``x + y = 0`` and ``x + y = 2``) meet, the exact solution is the 1D dam break
(:class:`conslaw_models.shallow_water_exact.DamBreak`) along the normal ``xi = (x + y)/sqrt 2``
of each dam, with the velocity along the normal. Printed: the L1 error of the depth against the
exact cell averages, the observed orders, and how far the depth is from its mirror image about
the diagonal (``max |h - h^T|``). Prints a markdown table.

Usage: ``python scripts/diagonal_dam_break.py [--reconstructor mc] [--cells 25,50,100,200]
[--shallow 0.5]``
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from conslaw import registry
from conslaw.grid2d import Grid2D
from conslaw.schemes.jiang_tadmor import JiangTadmor
from conslaw_models.shallow_water_2d import ShallowWater2D
from conslaw_models.shallow_water_exact import DamBreak

SIDES = {"left": "periodic", "right": "periodic", "bottom": "periodic", "top": "periodic"}
PERIOD = 4.0
T_END = 0.5


def exact_points(x: np.ndarray, y: np.ndarray, t: float, deep: float, shallow: float) -> np.ndarray:
    """``(h, hu, hv)`` of the two diagonal dam breaks at the points (before their waves meet)."""
    s = np.mod(x + y, PERIOD)
    near_second = (s >= 1.0) & (s < 3.0)
    xi = np.where(near_second, s, np.where(s < 1.0, s, s - PERIOD)) / math.sqrt(2.0)
    second = DamBreak(2.0 / math.sqrt(2.0), deep, shallow, 1.0).point_values(xi.ravel(), t)
    first = DamBreak(0.0, shallow, deep, 1.0).point_values(xi.ravel(), t)
    h_and_flux = np.where(near_second.ravel(), second, first).reshape(2, *s.shape)
    along = h_and_flux[1] / math.sqrt(2.0)
    return np.stack([h_and_flux[0], along, along])


def exact_averages(
    grid: Grid2D, t: float, deep: float, shallow: float, parts: int = 8
) -> np.ndarray:
    """Cell averages of :func:`exact_points`: ``parts`` x ``parts`` pieces per cell with 4 x 4
    Gauss–Legendre points each."""
    nodes, weights = np.polynomial.legendre.leggauss(4)
    offsets = (np.arange(parts)[:, None] + 0.5 * (nodes[None, :] + 1.0)).ravel() / parts
    shares = np.tile(0.5 * weights, parts) / parts
    x_left, y_low = grid.x.edges[:-1], grid.y.edges[:-1]
    total = np.zeros((3, *grid.shape))
    for offset_y, share_y in zip(offsets, shares, strict=True):
        y = (y_low + offset_y * grid.dy)[:, None]
        for offset_x, share_x in zip(offsets, shares, strict=True):
            x = (x_left + offset_x * grid.dx)[None, :]
            total += (share_x * share_y) * exact_points(x + 0 * y, y + 0 * x, t, deep, shallow)
    return total


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reconstructor", default="mc")
    parser.add_argument("--cells", default="25,50,100,200")
    parser.add_argument("--shallow", type=float, default=0.5)
    args = parser.parse_args()
    deep, shallow = 1.0, args.shallow
    low, high = DamBreak(0.0, deep, shallow, 1.0).wave_extent(T_END)
    # The dams are sqrt(2) apart along the normal: each one's waves must stay within half that.
    if max(-low, high) >= 1.0 / math.sqrt(2.0):
        raise SystemExit(f"the waves of the two dams meet before t = {T_END}")
    print(f"{args.reconstructor}, h = {deep:g} | {shallow:g}, g = 1, t = {T_END:g}")
    print("| N | steps | L1(h) | order | max abs(h - h^T) |")
    print("|---|---|---|---|---|")
    previous = None
    model = ShallowWater2D(g=1.0)
    for n in (int(c) for c in args.cells.split(",")):
        grid = Grid2D.from_bounds(0.0, PERIOD, n, 0.0, PERIOD, n)
        limiter = registry.reconstructors.get(args.reconstructor)
        jt = JiangTadmor(model, limiter, grid, SIDES)
        q = exact_averages(grid, 0.0, deep, shallow)
        q, _, steps = jt.advance(q, 0.0, T_END)
        error = float(np.abs(q[0] - exact_averages(grid, T_END, deep, shallow)[0]).sum())
        error *= grid.cell_area
        order = "" if previous is None else f"{math.log2(previous / error):.2f}"
        mirror = float(np.max(np.abs(q[0] - q[0].T)))
        print(f"| {n} | {steps} | {error:.3e} | {order} | {mirror:.1e} |", flush=True)
        previous = error


if __name__ == "__main__":
    main()
