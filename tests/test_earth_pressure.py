"""The Savage–Hutter earth pressure with ``phi > delta`` (docs/design.md, "Earth pressure"):
uniform layers stay uniform, material at rest stays at rest (with and without front tracking),
the run-out comes to rest, the dam break down an incline converges to its exact solution, and
the similarity solution keeps its margins. The numbers of docs/validation.md, "Earth pressure",
come from ``python scripts/earth_pressure_check.py``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, example, given, settings, strategies as st

import conslaw
from conslaw import registry
from conslaw.analysis import observed_orders
from conslaw.config import load_scene
from conslaw.exact import Unavailable
from conslaw.grid import Grid
from conslaw.initial import InitialCondition
from conslaw.simulation import build
from conslaw.state import State
from conslaw_models.savage_hutter import SavageHutter, earth_pressure_coefficients
from conslaw_models.savage_hutter_exact import InclinedDamBreak

RECONSTRUCTORS = registry.reconstructors.names()

UNIFORM = """
model = "savage-hutter"
reconstructor = "{reconstructor}"
n_cells = {n}
x_min = 0.0
x_max = 10.0
t_end = 10.0
exact = false
[boundary]
left = "periodic"
right = "periodic"
[parameters]
epsilon = 1.0
phi = {phi}
delta = {delta}
chute = "plane"
zeta = 30.0
[initial]
kind = "piecewise-constant"
breakpoints = []
states = [[1.0, 1.0]]
"""


@pytest.mark.parametrize("reconstructor", RECONSTRUCTORS)
@pytest.mark.parametrize("n", [100, pytest.param(1600, marks=pytest.mark.slow)])
def test_a_uniform_layer_stays_uniform_whatever_phi(
    reconstructor: str, n: int, tmp_path: Path
) -> None:
    """h = 1, u = 1 on a periodic 30-degree plane: ``h`` stays 1 and ``u = 1 + s t`` to 1e-12
    at t = 10, for phi just above and well above delta (the earth pressure switching with the
    round-off of the velocity slope broke this layer up by 10 % with phi = 35 before)."""
    for phi in (30.0, 30.01, 35.0, 45.0):
        for delta in (29.99, 30.0):
            scene = tmp_path / f"uniform-{phi}-{delta}.toml"
            scene.write_text(UNIFORM.format(reconstructor=reconstructor, n=n, phi=phi, delta=delta))
            q = conslaw.run(scene).final.q
            zeta = math.radians(30.0)
            s = math.sin(zeta) - math.tan(math.radians(delta)) * math.cos(zeta)
            assert np.abs(q[0] - 1.0).max() <= 1e-12, (phi, delta)
            assert np.abs(q[1] / q[0] - (1.0 + s * 10.0)).max() <= 1e-12, (phi, delta)


def test_a_frictionless_uniform_layer_accelerates_freely_whatever_phi(tmp_path: Path) -> None:
    """delta = 0 < phi (no bed friction, earth pressure still switching): the uniform layer above
    stays uniform and ``u = 1 + sin(zeta) t`` to 1e-12 at t = 10."""
    for phi in (0.01, 30.0, 85.0):
        scene = tmp_path / f"frictionless-{phi}.toml"
        scene.write_text(UNIFORM.format(reconstructor="mc", n=100, phi=phi, delta=0.0))
        q = conslaw.run(scene).final.q
        assert np.abs(q[0] - 1.0).max() <= 1e-12, phi
        u_exact = 1.0 + math.sin(math.radians(30.0)) * 10.0
        assert np.abs(q[1] / q[0] - u_exact).max() <= 1e-12 * u_exact, phi


# ---------------------------------------------------------------------- material at rest
@st.composite
def held_caps(draw: st.DrawFn) -> dict[str, float]:
    """Parameters of a parabolic cap that friction holds at rest with the smallest earth
    pressure ``K_act`` (with half the friction to spare): ``delta > zeta`` and
    ``eps cos zeta K_act 2 H / R <= (tan delta cos zeta - sin zeta) / 2`` on its steepest
    face. phi anywhere from delta to delta + 20 degrees."""
    zeta = draw(st.floats(0.0, 35.0))
    delta = draw(st.floats(zeta + 3.0, 60.0))
    phi = min(delta + draw(st.floats(0.01, 20.0)), 89.0)
    epsilon = draw(st.floats(0.01, 1.0))
    radius = draw(st.floats(1.0, 3.0))
    k_active, _ = earth_pressure_coefficients(math.radians(phi), math.radians(delta))
    z, d = math.radians(zeta), math.radians(delta)
    spare = 0.5 * (math.tan(d) * math.cos(z) - math.sin(z))
    steepest = spare / (epsilon * math.cos(z) * k_active)
    height = draw(st.floats(0.05, 1.0)) * steepest * radius / 2.0
    return {"zeta": zeta, "delta": delta, "phi": phi, "epsilon": epsilon, "radius": radius,
            "height": height}  # fmt: skip


def run_cap(cap: dict[str, float], reconstructor: str, tracking: bool, t_end: float):  # type: ignore[no-untyped-def]
    return conslaw.run(
        "sh-at-rest", reconstructor=reconstructor, front_tracking=tracking, t_end=t_end,
        output_times=[0.0, t_end], boundary__left="wall", boundary__right="wall",
        parameters__zeta=cap["zeta"], parameters__delta=cap["delta"], parameters__phi=cap["phi"],
        parameters__epsilon=cap["epsilon"], initial__radius=cap["radius"],
        initial__height=cap["height"], n_cells=40,
    )  # fmt: skip


@pytest.mark.parametrize(("reconstructor", "tracking"), [("mc", False), ("weno5", True)])
@settings(max_examples=25, deadline=None)
@given(cap=held_caps(), pairs=st.integers(50, 400))
def test_material_at_rest_stays_at_rest_whatever_phi(
    reconstructor: str, tracking: bool, cap: dict[str, float], pairs: int
) -> None:
    """A cap that friction holds stays at rest: every momentum exactly 0, the depth (and the
    tracked margins) bit for bit, for phi from delta up (where the earth pressure of material
    at rest may lie anywhere between K_act and K_pass)."""
    first = run_cap(cap, reconstructor, tracking, 1e-9)
    start = first.final
    dt = first.scheme.stable_dt(start)
    result = run_cap(cap, reconstructor, tracking, 2.0 * pairs * dt)
    begin, end = result.states
    assert not np.any(end.q[1])
    np.testing.assert_array_equal(end.q[0], begin.q[0])
    assert end.margins == begin.margins


@settings(max_examples=20, deadline=None)
@given(
    phi_above=st.floats(0.0, 20.0),
    speed=st.floats(0.2, 2.0),
    height=st.floats(0.05, 0.5),
    reconstructor=st.sampled_from(RECONSTRUCTORS),
)
def test_material_at_rest_keeps_its_state_while_another_body_moves(
    phi_above: float, speed: float, height: float, reconstructor: str
) -> None:
    """A cap that friction holds (sh-at-rest's: 20-degree plane, delta = 30, phi from delta up,
    walls, 200 cells on [0, 20]) and a second cap released downslope at ``speed`` beside it: the
    cells within 1.5 of the held cap keep their state bit for bit while the other body moves and
    after it stops (rule 3 of docs/design.md, "Earth pressure": the staggered averaging moves no
    depth out of material at rest)."""
    scene = load_scene(
        "sh-at-rest",
        {"reconstructor": reconstructor, "n_cells": 200, "x_max": 20.0,
         "boundary.left": "wall", "boundary.right": "wall", "parameters.phi": 30.0 + phi_above},
    )  # fmt: skip
    _, grid, scheme, _, _ = build(scene)
    x = grid.centres()
    held = np.maximum(0.5 * (1.0 - ((x - 5.0) / 2.0) ** 2), 0.0)
    moving = np.maximum(height * (1.0 - ((x - 12.0) / 1.5) ** 2), 0.0)
    q0 = np.vstack([held + moving, speed * moving])
    near = x < 8.5
    state = State(0.0, x, q0)
    for t in (0.5, 1.0, 2.0, 4.0, 8.0):
        state = scheme.advance(state, t).state
        if t == 0.5:
            assert np.any(state.q[1][~near]), "the second body should still move"
        np.testing.assert_array_equal(state.q[:, near], q0[:, near])


@pytest.mark.slow
@pytest.mark.parametrize("reconstructor", RECONSTRUCTORS)
@pytest.mark.parametrize("tracking", [False, True])
def test_a_cap_at_rest_holds_for_ten_thousand_steps(reconstructor: str, tracking: bool) -> None:
    """sh-at-rest on a 25-degree plane (delta = 30, walls), phi = 30, 35, 45: after 10^4 steps
    every momentum is exactly 0 and the depth (and the margins) are the initial ones bit for bit
    (front tracking smeared this cap by up to 0.2 and moved its rear margin upslope before)."""
    for phi in (30.0, 35.0, 45.0):
        result = conslaw.run(
            "sh-at-rest", reconstructor=reconstructor, front_tracking=tracking,
            parameters__zeta=25.0, parameters__phi=phi, t_end=2000.0, output_times=[0.0, 2000.0],
            boundary__left="wall", boundary__right="wall",
        )  # fmt: skip
        assert result.steps >= 10_000
        begin, end = result.states
        assert not np.any(end.q[1])
        np.testing.assert_array_equal(end.q[0], begin.q[0])
        assert end.margins == begin.margins


# ---------------------------------------------------------------------- mirror symmetry
@settings(max_examples=25, deadline=None)
@example(delta=10.0, above=35.0 / 79.9, epsilon=10.0, n_cells=41, reconstructor="mc")
@given(
    delta=st.floats(0.0, 60.0),
    above=st.floats(0.0, 1.0),
    epsilon=st.floats(0.1, 10.0),
    n_cells=st.sampled_from([40, 41]),
    reconstructor=st.sampled_from(RECONSTRUCTORS),
)
def test_a_centred_pile_on_a_level_bed_stays_mirror_symmetric_bit_for_bit(
    delta: float, above: float, epsilon: float, n_cells: int, reconstructor: str
) -> None:
    """A cap centred in a walled domain on a level bed, for every ``delta <= phi < 90``: depth
    and momentum stay exact mirror images (``h(x) = h(-x)``, ``hu(x) = -hu(-x)``, bit for bit).

    The update is mirror-exact, and the cap's cell averages are made so
    (:meth:`conslaw.grid.Grid.mirror_symmetric`): before, the averages differed from their
    mirror images by 4e-16, which the earth-pressure switch grew to 1e-3 by t = 1 (phi = 45,
    delta = 10)."""
    phi = min(delta + above * (89.9 - delta), 89.9)
    # Only piles that move: the pressure gradient at the cap's edge (slope 2 height / radius =
    # 0.5) beats the friction (a pile at rest is symmetric whatever the scheme does).
    k_active = earth_pressure_coefficients(math.radians(phi), math.radians(delta))[0]
    assume(epsilon * k_active * 0.5 > 1.5 * math.tan(math.radians(delta)))
    result = conslaw.run(
        "sh-at-rest", n_cells=n_cells, reconstructor=reconstructor, t_end=0.2,
        output_times=[0.0, 0.2], parameters__phi=phi, parameters__delta=delta,
        parameters__zeta=0.0, parameters__epsilon=epsilon,
        **{"boundary.left": "wall", "boundary.right": "wall"},
    )  # fmt: skip
    for state in result.states:
        depth, momentum = state.q
        np.testing.assert_array_equal(depth, depth[::-1])
        np.testing.assert_array_equal(momentum, -momentum[::-1])
    assert np.any(result.states[-1].q[0] != result.states[0].q[0])  # it spread


def test_mirror_cells_pair_up_about_a_face_or_a_centre_only() -> None:
    grid = Grid(0.0, 1.0, 10)
    np.testing.assert_array_equal(grid.mirror_cells(0.5), np.arange(10)[::-1])
    np.testing.assert_array_equal(grid.mirror_cells(0.25)[:5], [4, 3, 2, 1, 0])
    assert np.all(grid.mirror_cells(0.25)[5:] == -1)
    assert grid.mirror_cells(0.33) is None
    assert grid.mirror_cells(0.5 + 1e-9 * grid.dx) is None  # off a face, not by round-off
    assert grid.mirror_cells(1e20) is None  # no image on the grid (was an OverflowError)
    assert grid.mirror_cells(0.1 + 0.2 + 0.2) is not None  # 0.5 to round-off
    values = np.linspace(0.0, 1.0, 10) ** 2
    symmetric = grid.mirror_symmetric(values + values[::-1], 0.5)
    np.testing.assert_array_equal(symmetric, symmetric[::-1])
    odd = grid.mirror_symmetric(np.vstack([values, values - values[::-1]]), 0.5, odd=(1,))
    np.testing.assert_array_equal(odd[1], -odd[1][::-1])
    np.testing.assert_array_equal(grid.mirror_symmetric(values, 0.33), values)


# ---------------------------------------------------------------------- the run-out
@pytest.mark.parametrize("phi", [32.0, 35.0, 40.0])
def test_the_run_out_comes_to_rest_and_stays(phi: float) -> None:
    """sh-runout-shock with phi > delta = 30: every momentum is exactly 0 by t = 100 (t = 50 for
    phi = 32 and 35; with phi = 40 a film on the 40-degree part, which carries the velocity of
    the flow it came from and makes none of its own (docs/design.md, "Films"), still creeps at
    3.5e-3 at t = 50), the deposit then stays bit for bit, and the mass is conserved to
    round-off (phi = 32 kept a rim cell moving for ever, and its deposit drifting, before the fix
    of docs/validation.md, "Earth pressure")."""
    times = [0.0, 4.0, 8.0, 12.0, 16.0, 20.0, 50.0, 100.0, 200.0]
    result = conslaw.run(
        "sh-runout-shock", parameters__phi=phi, output_times=times, t_end=times[-1]
    )
    at_rest = result.states[times.index(50.0 if phi < 40.0 else 100.0) :]
    for state in at_rest:
        assert not np.any(state.q[1]), f"moving at t = {state.t}"
        np.testing.assert_array_equal(state.q, at_rest[0].q)
    assert abs(result.mass_drift[0]) <= 1e-14


THIN_FILM_CYCLE = pytest.mark.xfail(
    strict=True,
    reason="a film on the 40-degree part feeds and drains the deposit's rear edge in a cycle "
    "(docs/validation.md, 'Earth pressure': not solved)",
)


@pytest.mark.parametrize(
    ("phi", "n_cells"),
    [(31.0, 500), (32.0, 250), (32.0, 400), (33.0, 500), (35.0, 250), (37.0, 500), (40.0, 400),
     (45.0, 400), (45.0, 500), (45.0, 250), pytest.param(45.0, 700, marks=THIN_FILM_CYCLE)],
)  # fmt: skip
def test_the_run_out_comes_to_rest_at_other_resolutions(phi: float, n_cells: int) -> None:
    """The run-out at resolutions where a film at the rear rim kept moving for ever before (11
    of the 28 runs of ``python scripts/earth_pressure_check.py run-out-sweep``; the film could
    not drain into a dry cell, and where its flux into the deposit exceeded its depth the whole
    hold of the resting cells was dropped for the step pair): every momentum is 0 by t = 200
    and the state then stays bit for bit to t = 400."""
    times = [0.0, 20.0, 50.0, 100.0, 200.0, 400.0]
    result = conslaw.run(
        "sh-runout-shock", parameters__phi=phi, n_cells=n_cells, output_times=times,
        t_end=times[-1],
    )  # fmt: skip
    at_rest = result.states[times.index(200.0) :]
    for state in at_rest:
        assert not np.any(state.q[1]), f"moving at t = {state.t}"
        np.testing.assert_array_equal(state.q, at_rest[0].q)


# ---------------------------------------------------------------------- the passive limit
PASSIVE_OVERSHOOT = pytest.mark.xfail(
    strict=True,
    reason="the passive pressure applied in full over a step throws the cap's foot forward "
    "(docs/validation.md, 'Wrong answers with phi well above delta': not solved)",
)


@PASSIVE_OVERSHOOT
@pytest.mark.parametrize(("phi", "delta"), [(45.0, 30.0), (85.0, 60.0)])
def test_a_slumping_cap_is_no_faster_than_the_lagrangian_baseline(phi: float, delta: float) -> None:
    """sh-at-rest (a parabolic cap on a 20-degree plane, walls, epsilon = 1) with phi well above
    delta: the largest speed at t = 0.2 at most 1.2 times that of the Lagrangian scheme (Savage
    & Hutter 1989), which slumps slowly. Fails today: 2.2 and 200 times."""
    speeds = []
    for scheme in ("nessyahu-tadmor", "lagrangian"):
        h, m = conslaw.run(
            "sh-at-rest", scheme=scheme, t_end=0.2, output_times=[0.0, 0.2],
            parameters__phi=phi, parameters__delta=delta, parameters__epsilon=1.0,
        ).final.q  # fmt: skip
        speeds.append(float(np.max(np.abs(np.where(h > 1e-8, m / np.maximum(h, 1e-300), 0.0)))))
    assert speeds[0] <= 1.2 * speeds[1], speeds


# ---------------------------------------------------------------------- dam break on an incline
def test_the_inclined_dam_break_is_the_ritter_fan_carried_along() -> None:
    """The exact solution: mass conserved, the reservoir sliding at ``s t``, the front at
    ``x0 + 2 c0 t + s t^2 / 2`` with ``u = s t + 2 c0`` there, and no solution where it does not
    apply."""
    model = SavageHutter(epsilon=1.0, phi=30.0, delta=25.0, zeta=35.0)
    grid = Grid(-5.0, 5.0, 200)
    initial = InitialCondition.from_table(
        {"kind": "piecewise-constant", "breakpoints": [0.0], "states": [[1.0, 0.0], [0.0, 0.0]]},
        SavageHutter,
    )
    context = {"left": "outflow", "right": "outflow", "t_end": 2.0}
    exact = model.exact_solution(initial, grid, context)
    assert isinstance(exact, InclinedDamBreak)
    zeta = math.radians(35.0)
    s = math.sin(zeta) - math.tan(math.radians(25.0)) * math.cos(zeta)
    beta = math.cos(zeta) * model.k_active
    c0 = math.sqrt(beta)
    t = 1.5
    front = 2 * c0 * t + 0.5 * s * t * t
    h, m = exact.point_values(np.array([-4.0, front - 1e-9, front + 1e-9]), t)
    assert h[0] == 1.0 and m[0] == pytest.approx(s * t, rel=1e-14)
    assert h[1] == pytest.approx(0.0, abs=1e-12) and h[2] == 0.0
    assert exact.wave_extent(t)[1] == pytest.approx(front, rel=1e-14)
    averages = exact.cell_averages(grid.edges, t)
    mass_in = 5.0 + s * t * t / 2.0  # the reservoir between x = -5 and 0, slid by s t^2/2
    assert averages[0].sum() * grid.dx == pytest.approx(mass_in, rel=1e-12)
    with pytest.raises(Unavailable, match="slide"):
        SavageHutter(phi=30.0, delta=25.0, zeta=20.0).exact_solution(initial, grid, context)
    with pytest.raises(Unavailable, match="outflow"):
        model.exact_solution(initial, grid, {**context, "left": "wall"})
    with pytest.raises(Unavailable, match="boundary"):
        model.exact_solution(initial, grid, {**context, "t_end": 4.0})


def dam_break_errors(reconstructor: str, cells: list[int], phi: float) -> tuple[list[float], float]:
    """L1(h) at t = 2 of sh-dam-break-incline, and the largest depth at 20 output times."""
    errors, highest = [], 0.0
    for n in cells:
        result = conslaw.run(
            "sh-dam-break-incline", n_cells=n, reconstructor=reconstructor,
            parameters__phi=phi, output_times=[0.1 * k for k in range(1, 21)],
        )  # fmt: skip
        error = result.headline_error()
        assert error is not None
        errors.append(error)
        highest = max(highest, max(float(s.q[0].max()) for s in result.states))
    return errors, highest


def check_dam_break(reconstructor: str, cells: list[int], order: float) -> None:
    """The observed order between successive grids at least ``order``, the error within 1.5
    times that of the same run with phi = delta at every N, and the depth never above 1.001 h0
    (weno5 grew it to 17.8 h0 at 800 cells before)."""
    errors, highest = dam_break_errors(reconstructor, cells, 30.0)
    reference, _ = dam_break_errors(reconstructor, cells, 25.0)
    orders = observed_orders(cells, errors)
    assert min(orders) >= order, orders
    assert all(e <= 1.5 * r for e, r in zip(errors, reference, strict=True)), (errors, reference)
    assert highest <= 1.001


@pytest.mark.parametrize("reconstructor", ["mc", "weno5"])
def test_the_inclined_dam_break_converges(reconstructor: str) -> None:
    check_dam_break(reconstructor, [200, 400, 800], 0.95)


@pytest.mark.slow
@pytest.mark.parametrize("reconstructor", RECONSTRUCTORS)
def test_the_inclined_dam_break_converges_with_every_reconstructor(reconstructor: str) -> None:
    """Order >= 0.8 from 200 to 1600 cells with every TVD and WENO reconstructor, except
    superbee, 0.79 from 800 to 1600 (1.03 over the whole range); 0.77 with the first-order
    scheme ``none``, the same as with phi = delta (its error ratio to that run stays at 1.1),
    the dx ln(1/dx) rate of a monotone scheme
    (:func:`test_the_first_order_dam_break_error_is_dx_log_dx`): measured, docs/validation.md,
    "Earth pressure"."""
    check_dam_break(
        reconstructor,
        [200, 400, 800, 1600],
        {"none": 0.75, "superbee": 0.75}.get(reconstructor, 0.8),
    )


def test_the_first_order_dam_break_error_is_dx_log_dx() -> None:
    """The first-order scheme (``none``: staggered Lax–Friedrichs, a monotone scheme) converges
    on the inclined dam break at the rate of monotone schemes at the corners of a rarefaction,
    ``L1 = C dx ln(1/dx)``: C stays within 8 % from 200 to 1600 cells while L1 / dx grows by
    half, so the observed order is 0.77-0.79 there and passes 0.8 only from 3200 cells on
    (``python scripts/earth_pressure_check.py dam-break-first-order``; docs/validation.md,
    "Earth pressure"). The same with phi = delta, within 1.15 times its error."""
    cells = [200, 400, 800, 1600]
    errors, _ = dam_break_errors("none", cells, 30.0)
    reference, _ = dam_break_errors("none", cells, 25.0)
    dx = [10.0 / n for n in cells]
    per_log = [e / (h * math.log(1.0 / h)) for e, h in zip(errors, dx, strict=True)]
    per_dx = [e / h for e, h in zip(errors, dx, strict=True)]
    assert max(per_log) <= 1.09 * min(per_log), per_log  # an error C dx would vary 1.7 times
    assert per_dx[-1] >= 1.5 * per_dx[0], per_dx
    assert all(e <= 1.15 * r for e, r in zip(errors, reference, strict=True)), (errors, reference)


# ---------------------------------------------------------------------- similarity solution
def test_the_similarity_solution_with_phi_35_keeps_its_margins() -> None:
    """sh-similarity-ft with phi = 35 (K_act = 1.01, a third of the phi = delta = 30 value):
    both margins within 0.05 dx of the exact ones at 90, 180 and 360 cells (the acceptance
    bound is 0.5 dx), and L1(h) falling at order >= 1. (The margin error itself, 5.3e-3,
    4.3e-3, 2.0e-3, does not yet fall at order 1 from 90 cells: at CFL 0.3 the fitted margin
    slope of front tracking lags by a few 1e-3 whatever the grid, with phi = delta as well;
    docs/validation.md, "Earth pressure".)"""
    errors = []
    for n in (90, 180, 360):
        result = conslaw.run("sh-similarity-ft", parameters__phi=35.0, n_cells=n)
        exact = result.exact_solution
        margins = result.final.margins
        assert exact is not None and margins is not None
        assert margins.rear is not None and margins.front is not None
        rear, front = exact.margins(result.final.t)  # type: ignore[attr-defined]
        error = max(abs(margins.rear.position - rear), abs(margins.front.position - front))
        assert error <= 0.05 * result.grid.dx, (n, error / result.grid.dx)
        l1 = result.headline_error()
        assert l1 is not None
        errors.append(l1)
    assert min(observed_orders([90, 180, 360], errors)) >= 1.0, errors
