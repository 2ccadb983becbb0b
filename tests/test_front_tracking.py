"""Front tracking (NOC-FT): paper Fig. 5 acceptance, run-out deposit, margins in the output,
and clear refusals."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

import conslaw
from conslaw.errors import ConfigError, SchemeBreakdownError
from conslaw.schemes.front_tracking.scheme import front_cell, margin_fit, rear_cell
from conslaw.studies.convergence import convergence_study


@pytest.fixture(scope="module")
def similarity_ft() -> conslaw.RunResult:
    return conslaw.run("sh-similarity-ft")


def body_velocity(result: conslaw.RunResult) -> np.ndarray:
    h, m = result.final.q
    body = h > 0.0
    return m[body] / h[body]


def test_similarity_margins_within_half_a_cell(similarity_ft: conslaw.RunResult) -> None:
    """Paper Fig. 5 set-up (weno5, 90 cells, CFL 0.3, t = 6): both margins within 0.5 dx."""
    result = similarity_ft
    t, x_rear, _, x_front, _ = result.margins[-1]
    assert t == 6.0
    rear, front = result.exact_solution.margins(6.0)
    dx = result.grid.dx
    print(
        f"margin errors / dx: rear {(x_rear - rear) / dx:+.3f}, front {(x_front - front) / dx:+.3f}"
    )
    assert abs(x_rear - rear) <= 0.5 * dx
    assert abs(x_front - front) <= 0.5 * dx


def test_similarity_beats_thin_layer_and_stays_active(similarity_ft: conslaw.RunResult) -> None:
    """L1(h) at least 2x below the thin-layer run; du/dx > 0 in every cell of the body (the
    active state the similarity solution presumes); h = 0 exactly outside the margins; mass
    to round-off."""
    thin_layer = conslaw.run("sh-similarity")
    ft_error, thin_error = similarity_ft.headline_error(), thin_layer.headline_error()
    print(f"L1(h): front tracking {ft_error:.3e}, thin layer {thin_error:.3e}")
    assert ft_error * 2.0 <= thin_error
    assert np.all(np.diff(body_velocity(similarity_ft)) > 0.0)
    _, x_rear, _, x_front, _ = similarity_ft.margins[-1]
    x, dx = similarity_ft.final.x, similarity_ft.grid.dx
    outside = (x + 0.5 * dx <= x_rear) | (x - 0.5 * dx >= x_front)
    assert outside.sum() > 40
    assert np.all(similarity_ft.final.q[:, outside] == 0.0)
    assert abs(similarity_ft.mass_drift[0]) <= 1e-12


def test_margin_error_converges_and_is_printed(capsys: pytest.CaptureFixture[str]) -> None:
    """The convergence tool reports the margin error at t = 6 and its observed order for
    90/180/360 cells: at least 1 (measured 1.67 and 1.71), and the margins stay within
    a tenth of a cell at every N."""
    study = convergence_study("sh-similarity-ft", [90, 180, 360], repeats=1, measure_import=False)
    table = study.table()
    print(table)
    assert "margin error" in table and "order margin" in table
    errors = [row.margin_error for row in study.rows]
    assert all(e is not None for e in errors)
    for row in study.rows:
        assert row.margin_error <= 0.1 * 18.0 / row.n_cells
    orders = [row.order_margin for row in study.rows[1:]]
    assert all(order is not None and order >= 1.0 for order in orders), orders
    assert f"{orders[0]:.2f}" in table and f"{orders[1]:.2f}" in table


def test_runout_front_stops_and_stays(tmp_path: Path) -> None:
    """sh-runout-shock with front tracking: the front comes to rest in the run-out and stays
    there to t = 20; mass to round-off; margins written to npz, CSV and a plot."""
    result = conslaw.run(
        "sh-runout-shock", front_tracking=True, out=tmp_path, **{"output.formats": ["npz", "csv"]}
    )
    margins = result.margins
    assert margins[-1, 0] == 20.0
    stopped = np.flatnonzero(margins[:, 4] == 0.0)
    moving = np.flatnonzero(margins[:, 4] != 0.0)
    first_rest = moving[-1] + 1
    assert margins[first_rest, 0] < 16.0  # at rest well before the end
    assert np.all(margins[first_rest:, 3] == margins[first_rest, 3])
    assert stopped[-1] == len(margins) - 1
    assert 25.5 < margins[-1, 3] < 40.0  # in the flat run-out
    assert abs(result.mass_drift[0]) <= 1e-12
    with np.load(tmp_path / "states.npz") as saved:
        np.testing.assert_array_equal(saved["margins"], margins)
    with open(tmp_path / "margins.csv", newline="") as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == ["t", "x_rear", "u_rear", "x_front", "u_front"]
    assert len(rows) == len(margins) + 1
    assert float(rows[-1][3]) == margins[-1, 3]
    assert (tmp_path / "margins.png").stat().st_size > 0


def test_dry_stays_exactly_zero_and_h_nonnegative() -> None:
    """Every step of a short run keeps h >= 0 and zero outside the tracked body."""
    scene = conslaw.load_scene("sh-similarity-ft", {"t_end": 1.0, "n_cells": 60})
    _, grid, scheme, initial, _ = conslaw.simulation.build(scene)
    state = scheme.initial_margins(initial)
    for _ in range(40):
        dt = scheme.stable_dt(state)
        state = scheme.step(state, dt)
        assert np.all(state.q[0] >= 0.0)
        left = state.x - 0.5 * grid.dx
        k_rear = rear_cell(left, state.margins.rear.position)
        k_front = front_cell(left, state.margins.front.position)
        assert np.all(state.q[:, :k_rear] == 0.0) and np.all(state.q[:, k_front + 1 :] == 0.0)


def test_margin_fit_is_exact_for_a_quadratic() -> None:
    """The margin slope fit recovers S and C of h = S d - C d^2 from cell masses."""
    slope, curvature, dx, inside = 0.7, 0.05, 0.2, 0.13
    edges = np.array([0.0, inside, inside + dx, inside + 2 * dx])

    def primitive(d: np.ndarray) -> np.ndarray:
        return 0.5 * slope * d**2 - curvature * d**3 / 3.0

    masses = np.diff(primitive(edges))
    fitted = margin_fit(masses, inside, dx)
    assert fitted == pytest.approx((slope, curvature), rel=1e-12)


@pytest.mark.parametrize(
    ("scene", "overrides", "fragment"),
    [
        ("burgers-riemann", {"front_tracking": True}, "needs a model with a depth variable"),
        ("sh-similarity-ft", {"initial.thin_layer": 1e-4}, "fills the whole domain"),
        ("sh-similarity-ft", {"scheme": "nessyahu-tadmor", "front_tracking": 1}, "true or false"),
        # A dam break's edge is a step: eq. (19) cannot start from it (unbounded acceleration;
        # the front overshot by 14 dx at N = 400 before this refusal).
        ("dam-break-dry", {"front_tracking": True}, "front margin starts as a step"),
    ],
)
def test_refused_at_set_up(scene: str, overrides: dict, fragment: str) -> None:
    with pytest.raises(ConfigError, match=fragment):
        conslaw.run(scene, **overrides)


def test_two_bodies_refused(tmp_path: Path) -> None:
    scene = conslaw.load_scene("dam-break-dry", {"front_tracking": True})
    model, grid, scheme, initial, _ = conslaw.simulation.build(conslaw.load_scene("dam-break-dry"))
    q = initial.q.copy()
    q[0, : grid.n_cells // 4] = 0.0
    q[0, grid.n_cells // 4 + 5 : grid.n_cells // 4 + 8] = 0.0
    from conslaw.schemes.front_tracking.scheme import FrontTrackingNT
    from conslaw.state import State

    tracker = FrontTrackingNT(
        model, scheme.reconstructor, grid, scheme.left, scheme.right, scene.cfl
    )
    with pytest.raises(ConfigError, match="separate bodies"):
        tracker.initial_margins(State(0.0, initial.x, q))


def test_margin_reaching_the_boundary_stops_clearly() -> None:
    with pytest.raises(SchemeBreakdownError, match="front margin reached the right boundary"):
        conslaw.run("sh-similarity-ft", t_end=12.0)
