"""The velocity bound of films (docs/design.md, "Films"): a new cell shallower than ``FILM`` times
the deepest cell of its source family carries the velocities of the cells around it and makes
none of its own."""

from __future__ import annotations

import numpy as np

from conslaw import registry
from conslaw.grid2d import Grid2D
from conslaw.schemes.jiang_tadmor import JiangTadmor
from conslaw.schemes.nessyahu_tadmor.constants import FILM
from conslaw_models.savage_hutter_terrain import SavageHutterTerrain

WALLS = dict.fromkeys(("left", "right", "bottom", "top"), "wall")


def test_a_pile_thinner_than_a_film_beside_a_deep_one_makes_no_velocity() -> None:
    """Two piles side by side on a 35-degree plane with 10-degree friction, one 400 times
    thinner (below ``FILM`` of the deepest): the deep one slides some 110 m in 8 s, the thin one,
    a film, no more than its own Riemann invariants move it (it spreads; its centre of mass moved
    7 m): the documented limit of the rule, a separate body thinner than ``FILM`` of the deepest
    does not slide by itself."""
    model = SavageHutterTerrain(phi=30.0, delta=10.0, terrain="plane", zeta=35.0)
    grid = Grid2D.from_bounds(0.0, 400.0, 80, -150.0, 150.0, 60)

    def pile(y: float, height: float) -> np.ndarray:
        options = {"centre": [60.0, y], "radii": [25.0, 25.0], "height": height}
        return model.initial_cell_averages_2d("pile", {**options, "thin_layer": 0.0}, grid)

    thin_height = 0.5 * FILM * 5.0
    q = pile(-80.0, 5.0) + pile(80.0, thin_height)
    x, y = grid.centres()
    xx, yy = np.meshgrid(x, y)
    thin = yy > 0.0
    scheme = JiangTadmor(model, registry.reconstructors.get("mc"), grid, WALLS)
    end, _, _ = scheme.advance(q.copy(), 0.0, 8.0)

    def centre(values: np.ndarray, where: np.ndarray) -> float:
        return float((values[0] * xx)[where].sum() / values[0][where].sum())

    deep_travel = centre(end, ~thin) - centre(q, ~thin)
    assert deep_travel > 100.0
    assert abs(centre(end, thin) - centre(q, thin)) < 0.1 * deep_travel
