"""The 2D Savage–Hutter similarity solution (scene ``sh2d-similarity``: an elliptic-paraboloid
cap on a 40 degree plane without bed friction, docs/validation.md, "Savage–Hutter in two
dimensions") at four resolutions, through :func:`conslaw.run_2d`: the L1 error of the depth at
``t = 4`` against the exact cell averages, its observed order, the largest distance (in cells)
between the margin of the computed cap (the ``h = 1e-6`` contour: cells deeper than that) and
the exact ellipse, the relative change of the total depth and the smallest depth.

Usage: ``python scripts/similarity_2d.py [--scene NAME] [reconstructor ...]`` (default
``sh2d-similarity`` and ``mc``; ``--scene sh2d-similarity-ft`` tracks the margins,
docs/design.md, "Margins in two dimensions")
"""

from __future__ import annotations

import math
import sys

import numpy as np

import conslaw
from conslaw.analysis import observed_orders
from conslaw.result2d import RunResult2D

RESOLUTIONS = ((24, 15), (48, 30), (96, 60), (192, 120))
#: Depth above which a cell counts as covered by the cap.
MARGIN_DEPTH = 1e-6


def margin_offset(result: RunResult2D) -> float:
    """The largest distance, in cells, from the exact ellipse of a cell centre on the wrong
    side of it (covered outside, or bare inside); the distance measured along the ray from the
    ellipse's centre."""
    cap = result.exact_solution
    t = result.final.t
    x_c, y_c, a, b = cap.margin(t)  # type: ignore[union-attr]
    x, y = result.grid.centres()
    xx, yy = np.meshgrid(x, y)
    radius = np.hypot((xx - x_c) / a, (yy - y_c) / b)
    covered = result.final.q[0] > MARGIN_DEPTH
    wrong = covered != (radius < 1.0)
    if not np.any(wrong):
        return 0.0
    # Distance along the ray: |r - 1| times the ellipse's radius in that direction.
    angle = np.arctan2((yy - y_c) / b, (xx - x_c) / a)
    reach = np.hypot(a * np.cos(angle), b * np.sin(angle))
    distance = np.abs(radius - 1.0) * reach
    return float(np.max(distance[wrong]) / result.grid.dx)


def main() -> None:
    arguments = sys.argv[1:]
    scene = "sh2d-similarity"
    if arguments[:1] == ["--scene"]:
        scene, arguments = arguments[1], arguments[2:]
    names = arguments or ["mc"]
    print("| reconstructor | cells | L1(h) | order | margin offset (cells) | mass change | min h |")
    print("|---|---|---|---|---|---|---|")
    for name in names:
        errors, cells = [], []
        rows = []
        for nx, ny in RESOLUTIONS:
            result = conslaw.run_2d(scene, n_cells=[nx, ny], output_times=[], reconstructor=name)
            error = result.headline_error()
            assert error is not None
            errors.append(error)
            cells.append(nx)
            total = result.initial.q[0].sum()
            change = (result.final.q[0].sum() - total) / total
            rows.append((nx, ny, error, margin_offset(result), change, result.final.q[0].min()))
        orders = [math.nan, *observed_orders(cells, errors)]
        for (nx, ny, error, offset, change, low), order in zip(rows, orders, strict=True):
            print(
                f"| {name} | {nx} x {ny} | {error:.3e} | {order:.2f} | {offset:.2f} | "
                f"{change:.1e} | {low:.1e} |"
            )


if __name__ == "__main__":
    main()
