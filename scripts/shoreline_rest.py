"""How still a lake with dry land stays: the table of docs/design.md, "Well-balanced bed".

    python scripts/shoreline_rest.py [--surfaces 0.1,0.3,0.45] [--cells 100,200,400,800]

The `lake-at-rest` scene (walls, Gaussian bump of height 0.5) with the still surface below the
top of the bump, so that the bump is a dry island. Printed per surface and grid: the largest
``|hu|`` at t = 5 and t = 25, the largest surface deviation ``|h + b - surface|`` over the cells
at least 1e-2 deep, and the observed order of ``max |hu|`` at t = 5 between successive grids.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

import conslaw


def stillness(
    surface: float, n_cells: int, t_end: float, reconstructor: str
) -> tuple[float, float]:
    """Largest ``|hu|`` and largest surface deviation in cells of depth >= 1e-2 at ``t_end``."""
    overrides: dict[str, Any] = {
        "n_cells": n_cells, "t_end": t_end, "reconstructor": reconstructor,
        "initial.surface": surface,
    }  # fmt: skip
    result = conslaw.run("lake-at-rest", **overrides)
    depth, momentum = result.final.q
    bed = result.model.aux(result.grid.centres(), result.grid.dx)[0]
    deep = depth >= 1e-2
    return float(np.abs(momentum).max()), float(np.abs(depth + bed - surface)[deep].max())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--surfaces", default="0.1,0.3,0.45")
    parser.add_argument("--cells", default="100,200,400,800")
    parser.add_argument("--reconstructor", default="mc")
    args = parser.parse_args()
    print(
        "| surface | N | max \\|hu\\| t=5 | order | max \\|hu\\| t=25 "
        "| max \\|h+b-surface\\| t=25 (h >= 1e-2) |"
    )
    print("|---|---|---|---|---|---|")
    for surface in (float(s) for s in args.surfaces.split(",")):
        previous: tuple[int, float] | None = None
        for n_cells in (int(n) for n in args.cells.split(",")):
            early, _ = stillness(surface, n_cells, 5.0, args.reconstructor)
            late, deviation = stillness(surface, n_cells, 25.0, args.reconstructor)
            order = (
                f"{math.log(previous[1] / early) / math.log(n_cells / previous[0]):.2f}"
                if previous else ""
            )  # fmt: skip
            print(
                f"| {surface:g} | {n_cells} | {early:.2e} | {order} | {late:.2e} "
                f"| {deviation:.2e} |"
            )
            previous = (n_cells, early)


if __name__ == "__main__":
    main()
