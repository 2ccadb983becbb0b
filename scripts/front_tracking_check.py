"""Print the numbers quoted in docs/design.md, section "Front tracking (NOC-FT)":

    python scripts/front_tracking_check.py

A body sliding on the 40° plane with (almost) no earth pressure (eps = 1e-6) accelerates
uniformly, u = s t everywhere; the spread of the cell velocities measures how well the sources are
integrated near the margins. Then the margin errors of the paper's Fig. 5 set-up.
"""

from __future__ import annotations

import math

import conslaw
from conslaw.schemes.front_tracking.scheme import FrontTrackingNT, MarginCellHooks
from conslaw.schemes.nessyahu_tadmor.scheme import SubcellHooks


def report(label: str) -> None:
    slope = math.sin(math.radians(40.0)) - math.tan(math.radians(30.0)) * math.cos(
        math.radians(40.0)
    )
    sliding = conslaw.run("sh-similarity-ft", exact=False, **{"parameters.epsilon": 1e-6})
    h, m = sliding.final.q
    body = h > 0.0
    u = m[body] / h[body]
    print(
        f"{label}: uniform slide, t = 6: u in [{u.min():.4f}, {u.max():.4f}], exact {6 * slope:.4f}"
    )
    result = conslaw.run("sh-similarity-ft")
    _, x_rear, _, x_front, _ = result.margins[-1]
    rear, front = result.exact_solution.margins(6.0)
    dx = result.grid.dx
    print(
        f"{label}: sh-similarity-ft, 90 cells: rear margin {(x_rear - rear) / dx:+.3f} dx, "
        f"front margin {(x_front - front) / dx:+.3f} dx, L1(h) {result.headline_error():.3e}"
    )


def main() -> None:
    report("mid-step mass sources")
    # The paper's plain quarter-point depths (eqs. 13-14): switch the rescaling off, in the numpy
    # reference path (the compiled kernel has no hooks to switch).
    MarginCellHooks.adjust_source_depths = SubcellHooks.adjust_source_depths
    FrontTrackingNT.advance = FrontTrackingNT.reference_advance  # type: ignore[method-assign]
    report("plain quarter points")


if __name__ == "__main__":
    main()
