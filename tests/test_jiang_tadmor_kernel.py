"""The compiled Jiang–Tadmor kernel (:class:`conslaw.schemes.jiang_tadmor.scheme.JiangTadmor`)
against the numpy reference it is written from: the same steps and values for every
reconstructor (a plugin's too) and kind of side, wet and dry, in 2D shallow water and Burgers,
and over a bed (still water with dry land, moving water, a bowl); results that do not depend on
the threads or on how the rows are cut; conservation; one time loop; a blow-up stopped with the
time, step and cell."""

from __future__ import annotations

from dataclasses import replace
from itertools import pairwise

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import conslaw
from conslaw import registry
from conslaw.errors import ConfigError, SchemeBreakdownError
from conslaw.grid2d import Grid2D
from conslaw.scene2d import load_scene_2d
from conslaw.schemes.depth_rules import velocity_bounded_slope
from conslaw.schemes.jiang_tadmor import JiangTadmorReference
from conslaw.schemes.jiang_tadmor.reference import quarter_velocity_outside
from conslaw.schemes.jiang_tadmor.scheme import JiangTadmor, compiles, over_bed
from conslaw_models.burgers_2d import Burgers2D
from conslaw_models.shallow_water_2d import ShallowWater2D

RECONSTRUCTORS = registry.reconstructors.names()
KINDS = ("periodic", "outflow", "wall")
#: The kernel's sums are the reference's, operation for operation; numpy's einsum in the
#: reference's predictor may add a Jacobian's products in another order on another machine.
#: (The shallow-water runs below are equal bit for bit, and asserted so.)
TOLERANCE = 1e-12


def sides(x_kind: str, y_kind: str) -> dict[str, str]:
    return {"left": x_kind, "right": x_kind, "bottom": y_kind, "top": y_kind}


def column(grid: Grid2D, inside: float, outside: float, drift: float) -> np.ndarray:
    """A round column of depth ``inside`` (radius 0.5, centred off the grid's centre) on water
    of depth ``outside`` (0: a dry bed), moving at ``(drift, -drift / 2)``."""
    x, y = grid.centres()
    r2 = (x[None, :] - 0.1) ** 2 + (y[:, None] + 0.05) ** 2
    q = np.zeros((3, *grid.shape))
    q[0] = np.where(r2 < 0.25, inside, outside)
    q[1], q[2] = drift * q[0], -0.5 * drift * q[0]
    return q


@pytest.mark.parametrize("reconstructor", RECONSTRUCTORS)
@pytest.mark.parametrize(("x_kind", "y_kind"), [("wall", "outflow"), ("periodic", "wall")])
@pytest.mark.parametrize("outside", [0.1, 0.0], ids=["wet", "dry"])
def test_the_kernel_takes_the_reference_steps(
    reconstructor: str, x_kind: str, y_kind: str, outside: float
) -> None:
    """Shallow water, a column collapsing onto water or a dry bed: the compiled run equals the
    reference run (same number of steps, the same values bit for bit), every depth >= 0."""
    grid = Grid2D.from_bounds(-1.0, 1.0, 24, -1.0, 1.0, 20)
    limiter = registry.reconstructors.get(reconstructor)
    model = ShallowWater2D()
    q = column(grid, 1.0, outside, 0.3)
    compiled = JiangTadmor(model, limiter, grid, sides(x_kind, y_kind), threads=1, chunks=3)
    assert compiled.compiled
    reference = JiangTadmorReference(model, limiter, grid, sides(x_kind, y_kind))
    q_compiled, t_compiled, steps_compiled = compiled.advance(q, 0.0, 0.15)
    q_reference, t_reference, steps_reference = reference.advance(q, 0.0, 0.15)
    assert (t_compiled, steps_compiled) == (t_reference, steps_reference)
    np.testing.assert_array_equal(q_compiled, q_reference)
    assert np.min(q_compiled[0]) >= 0.0


@pytest.mark.parametrize("reconstructor", ["mc", "weno5", "minmod"])
@pytest.mark.parametrize("kind", KINDS)
def test_burgers_takes_the_reference_steps(reconstructor: str, kind: str) -> None:
    """Burgers 2D past its shock: compiled and reference runs agree to 1e-12."""
    grid = Grid2D.from_bounds(-1.0, 1.0, 20, -1.0, 1.0, 16)
    x, y = grid.centres()
    q = (np.sin(np.pi * x)[None, :] * np.cos(np.pi * y)[:, None] + 0.2)[None]
    limiter = registry.reconstructors.get(reconstructor)
    compiled = JiangTadmor(Burgers2D(), limiter, grid, sides(kind, kind), threads=1)
    reference = JiangTadmorReference(Burgers2D(), limiter, grid, sides(kind, kind))
    q_compiled, _, steps_compiled = compiled.advance(q, 0.0, 0.6)
    q_reference, _, steps_reference = reference.advance(q, 0.0, 0.6)
    assert steps_compiled == steps_reference
    np.testing.assert_allclose(q_compiled, q_reference, rtol=0, atol=TOLERANCE)


@settings(max_examples=10, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    dry_fraction=st.floats(0.0, 0.6),
    speed=st.floats(0.0, 3.0),
    reconstructor=st.sampled_from(RECONSTRUCTORS),
    x_kind=st.sampled_from(KINDS),
    y_kind=st.sampled_from(KINDS),
    courant=st.floats(0.05, 0.45),
)
def test_a_step_pair_of_random_states_is_the_reference_pair(
    seed: int,
    dry_fraction: float,
    speed: float,
    reconstructor: str,
    x_kind: str,
    y_kind: str,
    courant: float,
) -> None:
    """Random depths (some dry), random velocities, any Courant number below the bound: one
    compiled step pair (through the staggered family and back) is the reference's to 1e-12."""
    rng = np.random.default_rng(seed)
    grid = Grid2D.from_bounds(0.0, 1.0, 9, 0.0, 2.0, 7)
    q = np.zeros((3, *grid.shape))
    q[0] = np.where(rng.random(grid.shape) < dry_fraction, 0.0, rng.uniform(1e-6, 2.0, grid.shape))
    q[1:] = q[0] * rng.uniform(-speed, speed, (2, *grid.shape))
    limiter = registry.reconstructors.get(reconstructor)
    model = ShallowWater2D()
    reference = JiangTadmorReference(model, limiter, grid, sides(x_kind, y_kind))
    compiled = JiangTadmor(model, limiter, grid, sides(x_kind, y_kind), threads=1, chunks=2)
    dt = courant / 0.45 * reference.stable_dt(q)
    middle = reference.step(q, False, dt)
    expected = (
        reference.step(middle, True, dt)
        if max(reference.courant_numbers(middle, dt)) < 0.5
        else None
    )
    np.testing.assert_allclose(compiled.step(q, False, dt), middle, rtol=0, atol=TOLERANCE)
    if expected is not None:
        np.testing.assert_allclose(
            compiled.step(middle, True, dt), expected, rtol=0, atol=TOLERANCE
        )


@pytest.mark.parametrize(("threads", "chunks"), [(1, 1), (1, 7), (2, None), (2, 32)])
def test_threads_and_chunks_do_not_change_the_result(threads: int, chunks: int | None) -> None:
    """The same run with one thread in one chunk and any other cut of the rows: bit for bit."""
    if threads > JiangTadmor.available_threads():
        pytest.skip("one core")
    grid = Grid2D.from_bounds(-1.0, 1.0, 30, -1.0, 1.0, 33)
    q = column(grid, 2.0, 0.0, 0.5)
    limiter = registry.reconstructors.get("weno5")
    boundaries = sides("wall", "outflow")
    single = JiangTadmor(ShallowWater2D(), limiter, grid, boundaries, threads=1, chunks=1)
    other = JiangTadmor(ShallowWater2D(), limiter, grid, boundaries, threads=threads, chunks=chunks)
    expected = single.advance(q, 0.0, 0.2)
    result = other.advance(q, 0.0, 0.2)
    assert result[1:] == expected[1:]
    np.testing.assert_array_equal(result[0], expected[0])


@pytest.mark.parametrize("reconstructor", ["mc", "weno5"])
def test_a_periodic_run_conserves_every_variable(reconstructor: str) -> None:
    """Periodic sides: the totals of h, hu and hv after 40 compiled steps are the start's to
    round-off."""
    grid = Grid2D.from_bounds(-1.0, 1.0, 25, -1.0, 1.0, 25)
    q = column(grid, 1.5, 0.2, 0.7)
    jt = JiangTadmor(
        ShallowWater2D(),
        registry.reconstructors.get(reconstructor),
        grid,
        sides("periodic", "periodic"),
    )
    end, _, steps = jt.advance(q, 0.0, 0.3)
    assert steps >= 20
    totals, start = end.sum(axis=(1, 2)), q.sum(axis=(1, 2))
    np.testing.assert_allclose(totals, start, rtol=0, atol=1e-13 * np.abs(q).sum())


@pytest.mark.parametrize("along_y", [False, True], ids=["along-x", "along-y"])
@pytest.mark.parametrize(
    ("scene", "overrides"),
    [
        ("dam-break-dry", {"n_cells": 200}),
        ("dam-break-wet", {"n_cells": 200, "reconstructor": "weno5"}),
    ],
)
def test_a_1d_scene_run_in_2d_by_the_kernel_is_the_1d_run(
    scene: str, overrides: dict[str, object], along_y: bool
) -> None:
    """A flat-bed 1D scene turned along x (or y) in the compiled 2D scheme: every row (column)
    is the compiled 1D run to 1e-13 (bit for bit here), with the same number of steps."""
    result = conslaw.run(scene, **overrides)  # type: ignore[arg-type]
    line, across = result.grid, 4
    left, right = result.scheme.left.condition.name, result.scheme.right.condition.name
    n = line.n_cells
    model = ShallowWater2D(g=result.model.params.g, dry_tolerance=result.model.params.dry_tolerance)
    if along_y:
        grid = Grid2D.from_bounds(0.0, 1.0, across, line.x_min, line.x_max, n)
        boundaries = {"left": "periodic", "right": "periodic", "bottom": left, "top": right}
        q = np.zeros((3, n, across))
        q[0], q[2] = result.initial.q[0][:, None], result.initial.q[1][:, None]
    else:
        grid = Grid2D.from_bounds(line.x_min, line.x_max, n, 0.0, 1.0, across)
        boundaries = {"left": left, "right": right, "bottom": "periodic", "top": "periodic"}
        q = np.zeros((3, across, n))
        q[0], q[1] = result.initial.q[0][None, :], result.initial.q[1][None, :]
    limiter = registry.reconstructors.get(result.scene.reconstructor)
    jt = JiangTadmor(model, limiter, grid, boundaries, result.scheme.cfl)
    t, steps = 0.0, 0
    for state in result.states:
        q, t, taken = jt.advance(q, t, state.t)
        steps += taken
    assert steps == result.steps
    for index in range(across):
        cut = q[[0, 2]][:, :, index] if along_y else q[[0, 1]][:, index, :]
        np.testing.assert_allclose(cut, result.final.q, rtol=0, atol=1e-13)


BEDS = pytest.mark.parametrize("bump", [0.0, 0.2], ids=["flat", "over-a-bed"])


@BEDS
@pytest.mark.parametrize(
    ("variable", "value"),
    [(0, np.nan), (2, np.nan), (1, np.inf)],
    ids=["nan-depth", "nan-momentum", "infinite-momentum"],
)
def test_a_value_that_is_not_finite_stops_the_run_with_its_cell(
    bump: float, variable: int, value: float
) -> None:
    """A NaN or an infinity in the start stops the run with the time, the step and the cell, in
    a dry cell too (whose wave speeds are 0 whatever its momenta), with or without a bed."""
    grid = Grid2D.from_bounds(0.0, 1.0, 8, 0.0, 1.0, 6)
    q = np.ones((3, *grid.shape))
    q[1:] = 0.0
    q[0, 4, 2] = 0.0  # dry
    q[variable, 4, 2] = value
    jt = JiangTadmor(
        ShallowWater2D(bump_height=bump),
        registry.reconstructors.get("mc"),
        grid,
        sides("wall", "wall"),
    )
    with pytest.raises(
        SchemeBreakdownError,
        match=r"^t=0, step 0: cell \(row 4, column 2\) of the primary family is not finite$",
    ):
        jt.advance(q, 0.0, 1.0)


@BEDS
def test_a_runaway_wave_speed_stops_the_run_before_its_step(bump: float) -> None:
    """A momentum of 1e200 (finite; its flux is not): its stable step, 5.6e-202, is below
    ``DT_FLOOR dx``, so the run stops at t = 0, step 0, naming that cell, its map point and its
    values (before, the first step made the staggered cells around it infinite and the run
    stopped at step 1 naming the first of them)."""
    grid = Grid2D.from_bounds(0.0, 1.0, 8, 0.0, 1.0, 6)
    q = np.ones((3, *grid.shape))
    q[1:] = 0.0
    q[1, 2, 3] = 1e200
    jt = JiangTadmor(
        ShallowWater2D(bump_height=bump),
        registry.reconstructors.get("mc"),
        grid,
        sides("wall", "wall"),
    )
    message = (
        r"^t=0, step 0: the time step fell to 5.63e-202, below 1e-14 dx; the fastest cell "
        r"\(column 3, row 2\) at x=0.4375, y=0.416667: h=1, hu=1e\+200, hv=0 "
    )
    with (
        np.errstate(over="ignore", invalid="ignore"),
        pytest.raises(SchemeBreakdownError, match=message),
    ):
        jt.advance(q, 0.0, 1.0)


@BEDS
def test_both_paths_run_the_reference_time_loop_and_report_progress(bump: float) -> None:
    """Flat or over a bed (the bed's kernels): ``advance`` is the reference's ``advance`` bit
    for bit, and reports the time and the step count after every pair."""
    grid = Grid2D.from_bounds(-1.0, 1.0, 12, -1.0, 1.0, 10)
    model = ShallowWater2D(bump_height=bump)
    limiter = registry.reconstructors.get("weno5")
    boundaries = sides("wall", "outflow")
    q = column(grid, 1.0, 0.1, 0.3)
    jt = JiangTadmor(model, limiter, grid, boundaries, threads=1, chunks=2)
    assert jt.compiled and over_bed(model) == (bump != 0.0)
    reports: list[tuple[float, int]] = []
    values, t, steps = jt.advance(q, 0.0, 0.2, lambda t, steps: reports.append((t, steps)))
    expected, t_expected, steps_expected = JiangTadmorReference(
        model, limiter, grid, boundaries
    ).advance(q, 0.0, 0.2)
    assert (t, steps) == (t_expected, steps_expected)
    np.testing.assert_array_equal(values, expected)
    assert [n for _, n in reports] == list(range(2, steps + 1, 2))
    assert reports[-1][0] == 0.2 and all(a < b for (a, _), (b, _) in pairwise(reports))


@BEDS
def test_a_step_past_the_courant_bound_is_refused(bump: float) -> None:
    """``step`` with a ``dt`` that makes a Courant number reach 1/2: refused on both paths."""
    grid = Grid2D.from_bounds(-1.0, 1.0, 10, -1.0, 1.0, 10)
    q = column(grid, 1.0, 0.1, 0.3)
    jt = JiangTadmor(
        ShallowWater2D(bump_height=bump),
        registry.reconstructors.get("mc"),
        grid,
        sides("wall", "wall"),
    )
    dt = jt.reference.stable_dt(q)
    assert jt.step(q, False, dt).shape == (3, 11, 11)
    with pytest.raises(SchemeBreakdownError, match=r"makes a Courant number reach 0\.5"):
        jt.step(q, False, 0.5 / 0.45 * dt)


def test_a_plugin_reconstructor_is_compiled_into_the_kernel() -> None:
    """A reconstructor without a built-in code (as a plugin registers one) has its slope
    function compiled into the kernel: its run is the reference's run with it, and the run of
    the built-in reconstructor with the same slope function, bit for bit."""
    grid = Grid2D.from_bounds(-1.0, 1.0, 14, -1.0, 1.0, 12)
    x, y = grid.centres()
    q = (np.sin(np.pi * x)[None, :] * np.cos(0.5 * np.pi * y)[:, None] + 0.3 * y[:, None])[None]
    built_in = registry.reconstructors.get("weno5")
    plugin = replace(built_in, name="plugin-weno5", code=None)
    boundaries = sides("wall", "outflow")
    compiled = JiangTadmor(Burgers2D(), plugin, grid, boundaries, threads=1)
    assert compiled.compiled and compiled.kernels.CUSTOM_SLOPES
    result = compiled.advance(q, 0.0, 0.5)
    expected = JiangTadmorReference(Burgers2D(), plugin, grid, boundaries).advance(q, 0.0, 0.5)
    same_slopes = JiangTadmor(Burgers2D(), built_in, grid, boundaries, threads=1)
    assert not same_slopes.kernels.CUSTOM_SLOPES
    assert result[1:] == expected[1:] == same_slopes.advance(q, 0.0, 0.5)[1:]
    np.testing.assert_allclose(result[0], expected[0], rtol=0, atol=TOLERANCE)
    np.testing.assert_array_equal(result[0], same_slopes.advance(q, 0.0, 0.5)[0])


class _ShallowWaterWithoutXMomentum(ShallowWater2D):
    """2D shallow water whose x momentum is not declared a momentum: a depth model with a y
    momentum only (its x momentum gets no depth rules, and no cell a thin-tail bound)."""

    momentum_index = None


def test_a_depth_model_with_a_y_momentum_only_takes_the_reference_steps() -> None:
    """The kernel's depth rules take the momenta a model declares, the y momentum alone too:
    a step pair of a column onto a dry bed is the reference's."""
    grid = Grid2D.from_bounds(-1.0, 1.0, 10, -1.0, 1.0, 8)
    model = _ShallowWaterWithoutXMomentum()
    limiter = registry.reconstructors.get("mc")
    boundaries = sides("wall", "outflow")
    q = column(grid, 1.0, 0.0, 0.3)
    compiled = JiangTadmor(model, limiter, grid, boundaries, threads=1)
    assert compiled.compiled and compiled.kernels.MOMENTA == 1
    reference = JiangTadmorReference(model, limiter, grid, boundaries)
    dt = reference.stable_dt(q)
    middle = reference.step(q, False, dt)
    np.testing.assert_allclose(compiled.step(q, False, dt), middle, rtol=0, atol=TOLERANCE)
    np.testing.assert_allclose(
        compiled.step(middle, True, dt), reference.step(middle, True, dt), rtol=0, atol=TOLERANCE
    )


def test_what_the_kernel_covers_and_refuses() -> None:
    """Flat models and shallow water over a bed are compiled; a depth model over a bed without
    both momenta goes to the reference steps; a thread or chunk count out of range is refused
    with or without a bed."""
    assert compiles(ShallowWater2D()) and compiles(Burgers2D())
    assert compiles(ShallowWater2D(bump_height=0.2)) and over_bed(ShallowWater2D(bowl_depth=0.1))
    assert not over_bed(ShallowWater2D()) and not over_bed(Burgers2D())
    limiter = registry.reconstructors.get("mc")
    walls = sides("wall", "wall")
    grid = Grid2D.from_bounds(0, 1, 8, 0, 1, 8)
    one_momentum = _ShallowWaterWithoutXMomentum(bump_height=0.2)
    assert not compiles(one_momentum)
    assert not JiangTadmor(one_momentum, limiter, grid, walls).compiled
    too_many = JiangTadmor.available_threads() + 1
    for model in (ShallowWater2D(), ShallowWater2D(bump_height=0.2)):
        for threads in (0, too_many):
            with pytest.raises(ConfigError, match="threads must be in"):
                JiangTadmor(model, limiter, grid, walls, threads=threads)
        rows = min(grid.shape_at(offset, False, False)[0] for offset in (0.0, 0.5))
        for chunks in (0, rows + 1, 10**6):
            with pytest.raises(
                ConfigError, match=rf"scheme_options.chunks must be in \[1, {rows}\]"
            ):
                JiangTadmor(model, limiter, grid, walls, threads=1, chunks=chunks)
        assert JiangTadmor(model, limiter, grid, walls, threads=1, chunks=rows).chunks == rows


@pytest.mark.parametrize("reconstructor", RECONSTRUCTORS)
@pytest.mark.parametrize(("x_kind", "y_kind"), [("wall", "outflow"), ("outflow", "outflow")])
def test_a_column_collapsing_onto_a_dry_bed_runs_out_through_open_sides(
    reconstructor: str, x_kind: str, y_kind: str
) -> None:
    """A column of depth 1 moving at (0, 0.3) on a dry bed, 50 x 50 cells, until t = 0.5 (its
    films leave through the open sides): every reconstructor finishes, every depth >= 0, in 38
    to 52 steps and at most 1.25 times the steps of ``mc`` (with ``weno3`` the time step used to
    collapse at t = 0.195, and ``weno5`` took 146 to 202 steps, before the quarter-velocity
    rule)."""
    grid = Grid2D.from_bounds(-1.0, 1.0, 50, -1.0, 1.0, 50)
    x, y = grid.centres()
    q = np.zeros((3, *grid.shape))
    q[0] = np.where(x[None, :] ** 2 + y[:, None] ** 2 < 0.25, 1.0, 0.0)
    q[2] = 0.3 * q[0]

    def run(name: str) -> tuple[np.ndarray, int]:
        jt = JiangTadmor(
            ShallowWater2D(), registry.reconstructors.get(name), grid, sides(x_kind, y_kind)
        )
        end, _, steps = jt.advance(q, 0.0, 0.5)
        return end, steps

    end, steps = run(reconstructor)
    assert np.min(end[0]) >= 0.0 and np.all(np.isfinite(end))
    assert 38 <= steps <= 52
    assert steps <= 1.25 * run("mc")[1]


def test_a_corner_quarter_outside_the_velocity_range_is_found() -> None:
    """Slopes that keep the quarter points along x and along y in range can still put a corner
    quarter outside it; the rule finds it, and data that vary along one axis never trip it."""
    one = np.ones(1)
    # h = 1, m = 0, range [-0.1, 0.1]: along x, (0 +- 0.2/4) / (1 +- 1/4) is in range; the upper
    # right quarter has (0.2 + 0.2)/4 = 0.1 over 1 - (1.9 + 1.9)/4 = 0.05: u = 2.
    depth_slopes = (-1.9 * one, -1.9 * one, 0.0 * one)
    assert quarter_velocity_outside(
        one, 0 * one, depth_slopes, (0.2 * one, 0.2 * one), -0.1 * one, 0.1 * one
    )[0]
    assert not quarter_velocity_outside(
        one, 0 * one, depth_slopes, (0.0 * one, 0.0 * one), -0.1 * one, 0.1 * one
    )[0]


@settings(max_examples=300, deadline=None)
@given(
    depth=st.floats(1e-9, 10.0),
    depth_slope=st.floats(-1.0, 1.0),
    velocities=st.lists(st.floats(-5.0, 5.0), min_size=3, max_size=3),
    momentum_slope=st.floats(-20.0, 20.0),
)
def test_the_1d_bound_never_trips_the_quarter_rule(
    depth: float, depth_slope: float, velocities: list[float], momentum_slope: float
) -> None:
    """A cell whose data vary along x only (y slopes 0), with its momentum slope bounded as in
    1D: no quarter velocity is outside the range (so 1D runs in 2D stay bit for bit)."""
    h = np.array([depth])
    h_slope = np.array([2.0 * depth * depth_slope])  # |h'| <= 2 h, the 1D depth rule
    u_centre = velocities[1]
    m = h * u_centre
    low = np.array([min(velocities)])
    high = np.array([max(velocities)])
    bounded = velocity_bounded_slope(h, m, h_slope, np.array([momentum_slope]), low, high)
    zero = np.zeros(1)
    assert not quarter_velocity_outside(h, m, (h_slope, zero, zero), (bounded, zero), low, high)[0]


# ------------------------------------------------------------------ over a bed
def bed_model(rng: np.random.Generator) -> ShallowWater2D:
    """A bump (or a hollow) of random height, place and width, in a bowl or not."""
    return ShallowWater2D(
        bump_height=rng.uniform(-0.6, 0.8),
        bump_centre_x=rng.uniform(0.0, 1.0),
        bump_centre_y=rng.uniform(0.0, 2.0),
        bump_width=rng.uniform(0.1, 0.6),
        bowl_depth=float(rng.choice([0.0, 0.3])),
        bowl_centre_x=0.5,
        bowl_centre_y=1.0,
    )


@settings(max_examples=15, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    level=st.floats(-0.2, 0.6),
    moving_fraction=st.floats(0.0, 0.8),
    reconstructor=st.sampled_from([*RECONSTRUCTORS, "plugin"]),
    x_kind=st.sampled_from(KINDS),
    y_kind=st.sampled_from(KINDS),
    courant=st.floats(0.05, 0.45),
)
def test_a_step_pair_over_a_bed_is_the_reference_pair(
    seed: int,
    level: float,
    moving_fraction: float,
    reconstructor: str,
    x_kind: str,
    y_kind: str,
    courant: float,
) -> None:
    """Still water at any level over a random bed (dry land, partly flooded cells) with some
    cells set moving or refilled at random: one step pair of the bed's kernels (through the
    staggered family and back) is the reference's, for every reconstructor (a plugin's too)
    and kind of side."""
    rng = np.random.default_rng(seed)
    grid = Grid2D.from_bounds(0.0, 1.0, 9, 0.0, 2.0, 7)
    model = bed_model(rng)
    limiter = registry.reconstructors.get("weno5" if reconstructor == "plugin" else reconstructor)
    if reconstructor == "plugin":
        limiter = replace(limiter, name="plugin-weno5", code=None)
    reference = JiangTadmorReference(model, limiter, grid, sides(x_kind, y_kind))
    q = reference.still_water(level)
    moving = rng.random(grid.shape) < moving_fraction
    refilled = moving & (rng.random(grid.shape) < 0.3)
    q[0] = np.where(refilled, rng.uniform(0.0, 1.0, grid.shape), q[0])
    q[1:] = np.where(moving, q[0] * rng.uniform(-1.0, 1.0, (2, *grid.shape)), 0.0)
    compiled = JiangTadmor(model, limiter, grid, sides(x_kind, y_kind), threads=1, chunks=2)
    assert compiled.compiled and over_bed(model)
    dt = courant / 0.45 * min(reference.stable_dt(q), 1.0)
    middle = reference.step(q, False, dt)
    np.testing.assert_allclose(compiled.step(q, False, dt), middle, rtol=0, atol=TOLERANCE)
    if np.min(middle[0]) >= 0.0 and max(reference.courant_numbers(middle, dt)) < 0.5:
        np.testing.assert_allclose(
            compiled.step(middle, True, dt),
            reference.step(middle, True, dt),
            rtol=0,
            atol=TOLERANCE,
        )


@pytest.mark.parametrize("reconstructor", RECONSTRUCTORS)
def test_thacker_and_the_lake_run_the_reference_steps_over_the_bed(reconstructor: str) -> None:
    """Thacker's oscillation (a moving shoreline in a bowl) and a lake with a dry island, by
    the bed's kernels and by the reference: the same steps and values, bit for bit; the lake
    stays at rest to round-off."""
    limiter = registry.reconstructors.get(reconstructor)
    for name, t_end in (("sw2d-thacker", 0.6), ("sw2d-lake-island", 0.3)):
        scene = load_scene_2d(name, {"n_cells": [16, 16]})
        model = registry.models.get(scene.model)(**scene.parameters)
        grid = Grid2D.from_bounds(scene.x_min, scene.x_max, 16, scene.y_min, scene.y_max, 16)
        compiled = JiangTadmor(model, limiter, grid, scene.boundaries, threads=1)
        reference = JiangTadmorReference(model, limiter, grid, scene.boundaries)
        start = compiled.initial_values(scene.initial)
        if start is None:
            start = model.initial_cell_averages_2d(scene.initial.kind, scene.initial.options, grid)
        q, t, steps = compiled.advance(start, 0.0, t_end)
        assert q[0].min() >= 0.0 and (t, steps) == reference.advance(start, 0.0, t_end)[1:]
        np.testing.assert_array_equal(q, reference.advance(start, 0.0, t_end)[0])
        if name == "sw2d-lake-island":
            assert np.max(np.abs(q - start)) <= 1e-12
