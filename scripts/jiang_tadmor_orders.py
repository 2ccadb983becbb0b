"""Observed orders of the Jiang–Tadmor 2D reference step on the smooth 2D Burgers solution
(docs/design.md, "Toward two dimensions"): ``u0 = 0.3 + 0.5 sin(2 pi x) sin(2 pi y)`` on the
periodic unit square to t = 0.15 (it breaks at 0.318), mean |error| against the exact cell
averages, and the change of the total. Prints a markdown table.

Usage: ``python scripts/jiang_tadmor_orders.py``
"""

from __future__ import annotations

import numpy as np

from conslaw import registry
from conslaw.analysis import observed_orders
from conslaw.grid2d import Grid2D
from conslaw.schemes.jiang_tadmor import JiangTadmorReference
from conslaw_models.burgers_2d import Burgers2D, SmoothProductWave

SIDES = {"left": "periodic", "right": "periodic", "bottom": "periodic", "top": "periodic"}


def main() -> None:
    wave = SmoothProductWave(0.3, 0.5, 1.0)
    t_end = 0.15
    cells = [32, 64, 128, 256]
    print("| reconstructor | mean error N=32 | 64 | 128 | 256 | orders | largest total change |")
    print("|---|---|---|---|---|---|---|")
    for name in ("mc", "minmod", "weno5"):
        errors, drift = [], 0.0
        for n in cells:
            grid = Grid2D.from_bounds(0.0, 1.0, n, 0.0, 1.0, n)
            scheme = JiangTadmorReference(
                Burgers2D(), registry.reconstructors.get(name), grid, SIDES
            )
            edges = (grid.x.edges, grid.y.edges)
            start = wave.cell_averages(*edges, 0.0)
            q, _, _ = scheme.advance(start, 0.0, t_end)
            errors.append(float(np.mean(np.abs(q - wave.cell_averages(*edges, t_end)))))
            drift = max(drift, abs(q.sum() - start.sum()) / np.abs(start).sum())
        orders = ", ".join(f"{o:.2f}" for o in observed_orders(cells, errors))
        row = " | ".join(f"{e:.3e}" for e in errors)
        print(f"| {name} | {row} | {orders} | {drift:.1e} |")


if __name__ == "__main__":
    main()
