"""The Nessyahu–Tadmor scheme: staggering, exact output times, boundaries, errors."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import make_scheme

from conslaw.errors import ConfigError, InadmissibleStateError
from conslaw.state import State


def sine_state(scheme, t: float = 0.0) -> State:  # type: ignore[no-untyped-def]
    x = scheme.grid.centres()
    return State(t, x, (0.3 + 0.5 * np.sin(2 * np.pi * x))[None, :], 0.0)


def test_step_staggers_and_two_steps_return() -> None:
    scheme = make_scheme(boundary="outflow", n_cells=16)
    state = sine_state(scheme)
    dt = 0.5 * scheme.stable_dt(state)
    half = scheme.step(state, dt)
    assert half.offset == 0.5 and half.n_cells == 17
    np.testing.assert_allclose(half.x, np.linspace(0.0, 1.0, 17))
    back = scheme.step(half, dt)
    assert back.offset == 0.0 and back.n_cells == 16
    np.testing.assert_array_equal(back.x, state.x)
    assert back.t == pytest.approx(2 * dt)


def test_periodic_staggered_family_has_n_cells() -> None:
    scheme = make_scheme(boundary="periodic", n_cells=16)
    half = scheme.step(sine_state(scheme), 1e-3)
    assert half.n_cells == 16 and half.x[0] == 0.0


@pytest.mark.parametrize("t_end", [0.1, 0.123456789, 0.3])
def test_advance_hits_the_output_time_exactly(t_end: float) -> None:
    scheme = make_scheme()
    result = scheme.advance(sine_state(scheme), t_end)
    assert result.state.t == t_end
    assert result.state.offset == 0.0
    assert result.steps % 2 == 0 and result.steps > 0


def test_advance_equals_repeated_compiled_steps() -> None:
    """The fused loop and the one-step interface take the same steps (same dt per pair)."""
    scheme = make_scheme(reconstructor="weno5", n_cells=40)
    state = sine_state(scheme)
    fused = scheme.advance(state, 0.05)
    current = state
    for _ in range(fused.steps // 2):
        dt = min(scheme.stable_dt(current), 0.5 * (0.05 - current.t))
        if 2 * dt >= 0.05 - current.t:
            dt = 0.5 * (0.05 - current.t)
        current = scheme.step(scheme.step(current, dt), dt)
    np.testing.assert_allclose(current.q, fused.state.q, atol=1e-13)


def test_stable_dt_is_cfl_dx_over_speed() -> None:
    scheme = make_scheme(cfl=0.3, n_cells=20)
    state = sine_state(scheme)
    assert scheme.stable_dt(state) == pytest.approx(
        0.3 * (1 / 20) / np.abs(state.q).max(), rel=1e-15
    )


def test_step_refuses_dt_beyond_cfl_half() -> None:
    scheme = make_scheme(n_cells=20)
    state = sine_state(scheme)
    dt = scheme.stable_dt(state, cfl=0.45) / 0.45 * 0.5001
    with pytest.raises(ConfigError, match="CFL"):
        scheme.step(state, dt)


@pytest.mark.parametrize("cfl", [0.5, 0.7, 0.0, -0.1, float("nan")])
def test_cfl_at_or_above_half_is_a_config_error(cfl: float) -> None:
    with pytest.raises(ConfigError, match="cfl"):
        make_scheme(cfl=cfl)


def test_nan_in_state_stops_with_time_step_and_cell() -> None:
    scheme = make_scheme(n_cells=10)
    q = np.zeros((1, 10))
    q[0, 7] = np.nan
    with pytest.raises(InadmissibleStateError, match=r"t=0, step 0, cell 7"):
        scheme.advance(State(0.0, scheme.grid.centres(), q), 0.1)


def test_wall_keeps_mirror_symmetry_and_mass() -> None:
    """Symmetric Burgers data u(-x) = -u(x) about each wall; totals conserved to round-off."""
    scheme = make_scheme(boundary="wall", n_cells=50, reconstructor="mc")
    x = scheme.grid.centres()
    q = (np.sin(2 * np.pi * x) + 0.2 * np.sin(6 * np.pi * x))[None, :]
    state = State(0.0, x, q)
    result = scheme.advance(state, 0.4).state
    # The data is odd about x=0.5 as well, so the solution stays odd about x=0.5.
    np.testing.assert_allclose(result.q[0], -result.q[0, ::-1], atol=1e-13)
    assert abs(result.q.sum() - q.sum()) <= 1e-13 * np.abs(q).sum()


def test_inflow_boundary_feeds_its_state() -> None:
    scheme = make_scheme(boundary="inflow", n_cells=40, state=[1.0])
    state = State(0.0, scheme.grid.centres(), np.full((1, 40), 1.0))
    result = scheme.advance(state, 0.5).state
    np.testing.assert_array_equal(result.q, 1.0)


def test_first_order_scheme_is_staggered_lax_friedrichs() -> None:
    """reconstructor 'none': w_{j+1/2} = (w_j + w_{j+1})/2 - dt/dx (f(w_{j+1}) - f(w_j))."""
    scheme = make_scheme(reconstructor="none", boundary="periodic", n_cells=12)
    state = sine_state(scheme)
    dt = 0.01
    half = scheme.step(state, dt)
    u = state.q[0]
    left = np.roll(u, 1)  # staggered cell k spans the centres of cells k-1 and k
    expected = 0.5 * (left + u) - dt / scheme.grid.dx * (0.5 * u**2 - 0.5 * left**2)
    np.testing.assert_allclose(half.q[0], expected, atol=1e-15)
