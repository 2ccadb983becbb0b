"""Accuracy against exact solutions (docs/equations.md, "Error norms") and observed orders."""

from __future__ import annotations

import pytest

import conslaw
from conslaw.analysis import observed_orders


def test_burgers_riemann_mc_1600_meets_the_reference_bound() -> None:
    """L1(u) <= 6e-4 at N=1600 with mc (PyClaw's MC gives 3.7e-4 on the same problem)."""
    result = conslaw.run("burgers-riemann", n_cells=1600, reconstructor="mc")
    error = result.headline_error()
    print(f"burgers-riemann N=1600 mc: L1 = {error:.4e}")
    assert error is not None and error <= 6e-4


@pytest.mark.parametrize("reconstructor", ["vanleer", "mc", "weno3", "weno5"])
def test_burgers_sine_observed_order(reconstructor: str) -> None:
    """Observed L1 order between N = 200 and 800 is at least 1.8 (second-order NT)."""
    cells = [200, 400, 800]
    errors = [
        conslaw.run("burgers-sine", n_cells=n, reconstructor=reconstructor).headline_error()
        for n in cells
    ]
    orders = observed_orders(cells, errors)
    overall = observed_orders([200, 800], [errors[0], errors[-1]])[0]
    print(f"{reconstructor}: errors {errors}, orders {orders}, 200->800 {overall:.3f}")
    assert overall >= 1.8


def test_first_order_scheme_converges_at_first_order() -> None:
    cells = [200, 800]
    errors = [
        conslaw.run("burgers-sine", n_cells=n, reconstructor="none").headline_error() for n in cells
    ]
    order = observed_orders(cells, errors)[0]
    assert 0.85 <= order <= 1.15
