"""The two discretisations of the Savage–Hutter pressure with phi > delta, side by side
(docs/design.md, "Earth pressure"): ``K`` chosen per source cell inside the conservative flux
(the paper's eq. 2 form), and one ``K`` per staggered cell for both of its fluxes (conslaw's,
eq. 4). Prints

- the largest ``|h - 1|`` of a uniform layer (h = 1, u = 1, periodic 30-degree plane, phi = 35,
  delta = 30, 100 cells) at t = 10, started with random perturbations of relative size 1e-14,
  1e-10 and 1e-6;
- the total momentum of two piles colliding on a frictionless flat bed (delta = 0, phi = 35,
  400 cells), whose exact total does not change, at t = 0, 1, 2, 4.

Usage: ``python scripts/earth_pressure_forms.py`` (about a minute, most of it compiling).
"""

from __future__ import annotations

import sys

import numpy as np

from conslaw import registry
from conslaw.grid import Grid
from conslaw.initial import piecewise_constant_averages
from conslaw.schemes.base import BoundarySpec
from conslaw.schemes.nessyahu_tadmor.scheme import NessyahuTadmor
from conslaw.state import State
from conslaw_models.savage_hutter import SavageHutter


class PerCellPressure(SavageHutter):
    """The paper's form: each source cell's flux with its own K (no interface coefficients)."""

    def capabilities(self) -> dict[str, bool]:
        uses = super().capabilities()
        uses["interface_coefficients"] = False
        return uses


def scheme_for(model: SavageHutter, reconstructor: str, grid: Grid, boundary: str):  # type: ignore[no-untyped-def]
    side = BoundarySpec(registry.boundaries.get(boundary))
    return NessyahuTadmor(model, registry.reconstructors.get(reconstructor), grid, side, side, 0.45)


def noisy_layer(model: SavageHutter, reconstructor: str, noise: float) -> float:
    scheme = scheme_for(model, reconstructor, Grid(0.0, 10.0, 100), "periodic")
    h = 1.0 + noise * np.random.default_rng(1).standard_normal(100)
    state = State(0.0, scheme.grid.centres(), np.vstack([h, h]), 0.0)
    return float(np.abs(scheme.advance(state, 10.0).state.q[0] - 1.0).max())


def collision(model: SavageHutter, reconstructor: str) -> list[float]:
    """Total momentum at t = 1, 2, 4 less the initial one (2.0): a pile of depth 1 on
    [-4, -1] moving right at 1 meets one of depth 2 on [1, 2] moving left at 0.5."""
    grid = Grid(-10.0, 10.0, 400)
    scheme = scheme_for(model, reconstructor, grid, "outflow")
    states = np.array([[0.0, 1.0, 0.0, 2.0, 0.0], [0.0, 1.0, 0.0, -1.0, 0.0]])
    q = piecewise_constant_averages(grid.edges, np.array([-4.0, -1.0, 1.0, 2.0]), states)
    state = State(0.0, grid.centres(), q, 0.0)
    start = float(q[1].sum()) * grid.dx
    changes = []
    for t in (1.0, 2.0, 4.0):
        state = scheme.advance(state, t).state
        changes.append(float(state.q[1].sum()) * grid.dx - start)
    return changes


def main() -> None:
    forms = {"K per source cell (eq. 2)": PerCellPressure, "K per staggered cell": SavageHutter}
    parameters = {"phi": 35.0, "delta": 30.0, "zeta": 30.0, "epsilon": 1.0}
    print("| form | reconstructor | noise 1e-14 | 1e-10 | 1e-6 |")
    print("|---|---|---|---|---|")
    for name, model_class in forms.items():
        for reconstructor in ("mc", "weno5"):
            row = [noisy_layer(model_class(**parameters), reconstructor, e)
                   for e in (1e-14, 1e-10, 1e-6)]  # fmt: skip
            print(f"| {name} | {reconstructor} | " + " | ".join(f"{v:.1e}" for v in row) + " |")
    print()
    print("| form | reconstructor | total momentum - initial (2.0) at t = 1, 2, 4 |")
    print("|---|---|---|")
    frictionless = {"phi": 35.0, "delta": 0.0, "zeta": 0.0, "epsilon": 1.0}
    for name, model_class in forms.items():
        for reconstructor in ("mc", "weno5"):
            changes = collision(model_class(**frictionless), reconstructor)
            print(f"| {name} | {reconstructor} | " + ", ".join(f"{c:+.4f}" for c in changes) + " |")


if __name__ == "__main__":
    sys.exit(main())
