"""Exact Burgers solutions: cell averages against quadrature, and the PDE itself."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from conslaw.errors import ConfigError
from conslaw.grid import Grid
from conslaw.initial import InitialCondition
from conslaw_models.burgers import Burgers
from conslaw_models.burgers_exact import BurgersRiemannFans, BurgersSmoothSine


def riemann(breakpoints: list[float], states: list[float]) -> BurgersRiemannFans:
    initial = InitialCondition.from_table(
        {"kind": "piecewise-constant", "breakpoints": breakpoints, "states": states}
    )
    return BurgersRiemannFans.from_initial(initial, Grid(-1.0, 3.0, 8))


def test_reference_scene_waves() -> None:
    """burgers-riemann: transonic fan between -t/2 and t, shock at 1 + t/2."""
    exact = riemann([0.0, 1.0], [-0.5, 1.0, 0.0])
    t = 1.0
    x = np.array([-0.75, -0.25, 0.5, 0.99, 1.49, 1.51, 2.5])
    expected = [-0.5, -0.25, 0.5, 0.99, 1.0, 0.0, 0.0]
    np.testing.assert_allclose(exact.point_values(x, t)[0], expected, atol=1e-15)
    assert exact.valid_until() == pytest.approx(2.0)  # fan head (speed 1) meets shock (1/2) at t=2


@pytest.mark.parametrize(
    ("breakpoints", "states", "t"),
    [
        ([0.0, 1.0], [-0.5, 1.0, 0.0], 1.0),  # transonic rarefaction + shock
        ([0.3], [2.0, -1.0], 0.2),  # shock moving right at 1/2
        ([0.3], [0.5, 1.5], 0.7),  # plain rarefaction
        ([0.0], [-1.0, -0.2], 0.5),  # rarefaction moving left
    ],
)
def test_riemann_cell_averages_match_quadrature(
    breakpoints: list[float], states: list[float], t: float
) -> None:
    exact = riemann(breakpoints, states)
    edges = np.linspace(-1.0, 3.0, 57)
    averages = exact.cell_averages(edges, t)[0]
    kinks = []
    for k, x0 in enumerate(breakpoints):
        kinks += [
            x0 + states[k] * t,
            x0 + states[k + 1] * t,
            x0 + 0.5 * (states[k] + states[k + 1]) * t,
        ]
    for i in range(edges.size - 1):
        inside = [p for p in kinks if edges[i] < p < edges[i + 1]]
        value, _ = quad(
            lambda x: exact.point_values(np.array([x]), t)[0, 0],
            edges[i],
            edges[i + 1],
            points=inside or None,
            epsabs=1e-14,
            epsrel=1e-13,
            limit=200,
        )
        assert averages[i] == pytest.approx(value / (edges[i + 1] - edges[i]), abs=1e-12)


def test_riemann_refuses_interacting_waves() -> None:
    exact = riemann([0.0, 1.0], [-0.5, 1.0, 0.0])
    with pytest.raises(ConfigError, match="interact"):
        exact.cell_averages(np.linspace(-1, 3, 9), 2.5)


def sine() -> BurgersSmoothSine:
    initial = InitialCondition.from_table({"kind": "sine", "mean": 0.25, "amplitude": 0.5})
    return BurgersSmoothSine.from_initial(initial, Grid(0.0, 1.0, 8))


def test_sine_solves_burgers_along_characteristics() -> None:
    """u(x, t) = u0(x - u t) at every point (the implicit solution) before breaking."""
    exact = sine()
    x = np.linspace(0.0, 1.0, 101)
    for t in (0.0, 0.1, 0.25, 0.3):
        u = exact.point_values(x, t)[0]
        u0 = exact.point_values(x - u * t, 0.0)[0]
        np.testing.assert_allclose(u, u0, atol=1e-13)
    assert exact.breaking_time() == pytest.approx(1.0 / np.pi)


def test_sine_cell_averages_match_quadrature() -> None:
    exact = sine()
    edges = np.linspace(0.0, 1.0, 41)
    t = 0.25
    averages = exact.cell_averages(edges, t)[0]
    for i in range(40):
        value, _ = quad(
            lambda x: exact.point_values(np.array([x]), t)[0, 0],
            edges[i],
            edges[i + 1],
            epsabs=1e-15,
        )
        assert averages[i] == pytest.approx(value / (edges[i + 1] - edges[i]), abs=1e-13)


def test_sine_refuses_after_breaking() -> None:
    with pytest.raises(ConfigError, match="breaks"):
        sine().point_values(np.array([0.5]), 0.4)


def test_initial_cell_averages_are_exact() -> None:
    """Piecewise-constant data split inside a cell average to the overlap-weighted mean."""
    grid = Grid(0.0, 1.0, 4)
    initial = InitialCondition.from_table(
        {"kind": "piecewise-constant", "breakpoints": [0.125, 0.5], "states": [1.0, 3.0, -2.0]}
    )
    q = initial.cell_averages(grid, Burgers())
    np.testing.assert_allclose(q[0], [2.0, 3.0, -2.0, -2.0], atol=1e-15)
