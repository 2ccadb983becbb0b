"""The compiled field kernels of the Jiang–Tadmor scheme (Savage–Hutter on a chute with a
cross-slope direction and on terrain: coefficients at every point, a source at the quarter
points, Coulomb friction) against the numpy reference they are written from: the same step
pairs, bit for bit, over the whole admissible range of the parameters (``delta <= phi < 90``,
both earth-pressure rules, every terrain kind, a DEM averaged to a coarser grid), for every
reconstructor and kind of side, on beds that are dry, partly dry and covered by films; whole
runs with the same steps; results that do not depend on the threads.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st

from conslaw import registry
from conslaw.grid2d import Grid2D
from conslaw.schemes.jiang_tadmor import JiangTadmorReference
from conslaw.schemes.jiang_tadmor.reference import GHOSTS
from conslaw.schemes.jiang_tadmor.scheme import JiangTadmor, compiles, on_field, over_bed
from conslaw.terrain import dem_from_function, write_dem
from conslaw_models.savage_hutter_2d import SavageHutter2D
from conslaw_models.savage_hutter_terrain import SavageHutterTerrain

RECONSTRUCTORS = registry.reconstructors.names()
KINDS = ("periodic", "outflow", "wall", "inflow")
#: The state an inflow side feeds in (depth, both momenta).
INFLOW_STATE = (1.5, 6.0, -1.0)
#: Domain of the terrain grids (metres) and their cells (10 m along x, 12.3 m along y: a swap
#: of dx and dy does not pass).
X_RANGE, Y_RANGE, SHAPE = (-100.0, 100.0), (-80.0, 80.0), (13, 20)


def sides(x_kind: str, y_kind: str) -> dict[str, str]:
    return {"left": x_kind, "right": x_kind, "bottom": y_kind, "top": y_kind}


def inflow_of(boundaries: dict[str, str]) -> dict[str, tuple[float, ...]]:
    """The state of every inflow side of ``boundaries``."""
    return {side: INFLOW_STATE for side, kind in boundaries.items() if kind == "inflow"}


@pytest.fixture(scope="module")
def dem_path(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A 2 m DEM over the terrain domain: a 35-degree slope with a channel and rough noise,
    finer than the 10 m cells of the grids (so the model averages it to them)."""
    rng = np.random.default_rng(11)
    noise = rng.normal(0.0, 0.4, (90, 110))

    def elevation(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        channel = -8.0 * np.exp(-((y / 25.0) ** 2))
        return -np.tan(np.radians(35.0)) * x + channel + noise[: x.shape[0], : x.shape[1]]

    dem = dem_from_function(elevation, (-110.0, 110.0), (-90.0, 90.0), 2.0)
    return write_dem(dem, tmp_path_factory.mktemp("dem") / "slope.tif")


def terrain_model(kind: str, phi: float, delta: float, rule: str, dem: Path) -> SavageHutterTerrain:
    """A terrain model of ``kind`` with friction angles ``phi >= delta`` and ``rule``."""
    common = {"phi": phi, "delta": delta, "earth_pressure": rule}
    by_kind: dict[str, dict[str, object]] = {
        "plane": {"terrain": "plane", "zeta": 38.0},
        "bowl": {"terrain": "bowl", "bowl_radius": 150.0},
        "channel": {
            "terrain": "channel",
            "zeta": 35.0,
            "transition_radius": 100.0,
            "transition_end": 60.0,
            "channel_depth": 10.0,
            "channel_half_width": 30.0,
        },
        "dem": {"terrain": "dem", "dem_file": str(dem)},
    }
    return SavageHutterTerrain(**common, **by_kind[kind])


def random_flow(rng: np.random.Generator, shape: tuple[int, int], dry: float, films: float,
                speed: float) -> np.ndarray:  # fmt: skip
    """Depths up to 2 m, a fraction ``dry`` of cells empty and ``films`` of them 1e-6 of that;
    velocities up to ``speed`` in each direction."""
    h = rng.uniform(0.0, 2.0, shape) * (rng.random(shape) >= dry)
    h = np.where(rng.random(shape) < films, h * 1e-6, h)
    q = np.zeros((3, *shape))
    q[0] = h
    q[1:] = h * rng.uniform(-speed, speed, (2, *shape))
    return q


def assert_same_pair(model: object, reconstructor: str, grid: Grid2D, boundaries: dict[str, str],
                     q: np.ndarray, courant: float) -> None:  # fmt: skip
    """One step pair (through the staggered family and back) of the compiled kernels equals the
    reference's bit for bit (the second step only if the reference can take it)."""
    limiter = registry.reconstructors.get(reconstructor)
    inflow = inflow_of(boundaries)
    reference = JiangTadmorReference(model, limiter, grid, boundaries, inflow=inflow)  # type: ignore[arg-type]
    compiled = JiangTadmor(model, limiter, grid, boundaries, threads=1, chunks=2, inflow=inflow)  # type: ignore[arg-type]
    assert compiled.compiled and on_field(compiled.model)
    dt = courant / 0.45 * min(reference.stable_dt(q), reference.source_step_limit(q))
    middle = reference.step(q, False, dt)
    np.testing.assert_array_equal(compiled.step(q, False, dt), middle)
    if np.min(middle[0]) >= 0.0 and max(reference.courant_numbers(middle, dt)) < 0.5:
        expected = reference.step(middle, True, dt)
        np.testing.assert_array_equal(compiled.step(middle, True, dt), expected)


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    kind=st.sampled_from(["plane", "bowl", "channel", "dem"]),
    delta=st.floats(0.0, 60.0),
    phi_above=st.floats(0.0, 1.0),
    rule=st.sampled_from(["savage-hutter", "isotropic"]),
    dry=st.floats(0.0, 0.7),
    films=st.floats(0.0, 0.4),
    speed=st.floats(0.0, 40.0),
    reconstructor=st.sampled_from(RECONSTRUCTORS),
    side_kinds=st.tuples(st.sampled_from(KINDS), st.sampled_from(KINDS)),
    courant=st.floats(0.05, 0.45),
)
@example(
    seed=1, kind="dem", delta=0.0, phi_above=0.0, rule="savage-hutter", dry=0.3, films=0.2,
    speed=20.0, reconstructor="mc", side_kinds=("outflow", "wall"), courant=0.45,
)  # fmt: skip
def test_a_terrain_step_pair_is_the_reference_pair(
    dem_path: Path,
    seed: int,
    kind: str,
    delta: float,
    phi_above: float,
    rule: str,
    dry: float,
    films: float,
    speed: float,
    reconstructor: str,
    side_kinds: tuple[str, str],
    courant: float,
) -> None:
    """Savage–Hutter on every kind of terrain, ``0 <= delta <= phi < 90`` (``phi`` drawn from
    ``delta`` to 89.9 degrees), either earth-pressure rule, random depths with dry cells and
    films, random velocities up to 40 m/s, any Courant number below the bound: the compiled
    step pair is the reference's bit for bit."""
    phi = delta + phi_above * (89.9 - delta)
    rng = np.random.default_rng(seed)
    grid = Grid2D.from_bounds(*X_RANGE, SHAPE[1], *Y_RANGE, SHAPE[0])
    model = terrain_model(kind, phi, delta, rule, dem_path).on_grid_2d(grid)
    q = random_flow(rng, grid.shape, dry, films, speed)
    assert_same_pair(model, reconstructor, grid, sides(*side_kinds), q, courant)


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    chute=st.sampled_from(["plane", "paper"]),
    zeta=st.floats(0.0, 60.0),
    delta=st.floats(0.0, 50.0),
    phi_above=st.floats(0.0, 1.0),
    rule=st.sampled_from(["savage-hutter", "isotropic"]),
    dry=st.floats(0.0, 0.7),
    films=st.floats(0.0, 0.4),
    reconstructor=st.sampled_from(RECONSTRUCTORS),
    x_kind=st.sampled_from(KINDS),
    y_kind=st.sampled_from(KINDS),
    courant=st.floats(0.05, 0.45),
)
def test_a_chute_step_pair_is_the_reference_pair(
    seed: int,
    chute: str,
    zeta: float,
    delta: float,
    phi_above: float,
    rule: str,
    dry: float,
    films: float,
    reconstructor: str,
    x_kind: str,
    y_kind: str,
    courant: float,
) -> None:
    """Savage–Hutter on a chute (a plane, or the paper's curved one), dimensionless, over the
    admissible range of its angles: the compiled step pair is the reference's bit for bit."""
    phi = delta + phi_above * (89.9 - delta)
    rng = np.random.default_rng(seed)
    grid = Grid2D.from_bounds(0.0, 10.0, 20, -4.0, 4.0, 13)
    model = SavageHutter2D(chute=chute, zeta=zeta, phi=phi, delta=delta, earth_pressure=rule)
    q = random_flow(rng, grid.shape, dry, films, 3.0)
    assert_same_pair(model, reconstructor, grid, sides(x_kind, y_kind), q, courant)


def release(grid: Grid2D, centre: tuple[float, float], radius: float, depth: float) -> np.ndarray:
    """A cap of ``depth`` at rest, ``radius`` m across, centred at ``centre``."""
    x, y = grid.centres()
    r2 = (x[None, :] - centre[0]) ** 2 + (y[:, None] - centre[1]) ** 2
    q = np.zeros((3, *grid.shape))
    q[0] = depth * np.clip(1.0 - r2 / radius**2, 0.0, None)
    return q


@pytest.mark.parametrize("reconstructor", ["mc", "weno5"])
@pytest.mark.parametrize("kind", ["bowl", "dem"])
def test_a_release_runs_the_reference_steps(dem_path: Path, reconstructor: str, kind: str) -> None:
    """A release sliding down a bowl or the noisy DEM, through its films and its stop: the
    compiled run and the reference run take the same steps to the same values, bit for bit."""
    grid = Grid2D.from_bounds(*X_RANGE, 30, *Y_RANGE, 24)
    model = terrain_model(kind, 32.0, 24.0, "savage-hutter", dem_path).on_grid_2d(grid)
    limiter = registry.reconstructors.get(reconstructor)
    boundaries = sides("outflow", "outflow")
    q = release(grid, (-50.0, 10.0), 30.0, 3.0)
    compiled = JiangTadmor(model, limiter, grid, boundaries, threads=1)
    reference = JiangTadmorReference(model, limiter, grid, boundaries)
    q_compiled, t_compiled, steps_compiled = compiled.advance(q, 0.0, 12.0)
    q_reference, t_reference, steps_reference = reference.advance(q, 0.0, 12.0)
    assert steps_compiled >= 20
    assert (t_compiled, steps_compiled) == (t_reference, steps_reference)
    np.testing.assert_array_equal(q_compiled, q_reference)
    assert np.min(q_compiled[0]) >= 0.0


@pytest.mark.parametrize(("threads", "chunks"), [(1, 1), (1, 5), (2, None), (2, 11)])
def test_threads_and_chunks_do_not_change_a_terrain_run(
    dem_path: Path, threads: int, chunks: int | None
) -> None:
    """The same terrain run with one thread in one chunk and any other cut of the rows: bit for
    bit."""
    if threads > JiangTadmor.available_threads():
        pytest.skip("one core")
    grid = Grid2D.from_bounds(*X_RANGE, 30, *Y_RANGE, 24)
    model = terrain_model("dem", 35.0, 25.0, "savage-hutter", dem_path).on_grid_2d(grid)
    limiter = registry.reconstructors.get("weno5")
    boundaries = sides("outflow", "wall")
    q = release(grid, (-50.0, 10.0), 30.0, 3.0)
    single = JiangTadmor(model, limiter, grid, boundaries, threads=1, chunks=1)
    other = JiangTadmor(model, limiter, grid, boundaries, threads=threads, chunks=chunks)
    expected = single.advance(q, 0.0, 6.0)
    result = other.advance(q, 0.0, 6.0)
    assert result[1:] == expected[1:]
    np.testing.assert_array_equal(result[0], expected[0])


def test_which_models_take_the_field_kernels(dem_path: Path) -> None:
    """Savage–Hutter on a chute and on every terrain is compiled by the field kernels; shallow
    water keeps its own kernels."""
    from conslaw_models.shallow_water_2d import ShallowWater2D

    for kind in ("plane", "bowl", "channel", "dem"):
        model = terrain_model(kind, 35.0, 25.0, "isotropic", dem_path)
        assert compiles(model) and on_field(model) and not over_bed(model)
    assert compiles(SavageHutter2D()) and on_field(SavageHutter2D())
    assert not on_field(ShallowWater2D()) and not on_field(ShallowWater2D(bump_height=0.2))


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    kind=st.sampled_from(["plane", "bowl", "dem"]),
    band=st.tuples(st.integers(0, 23), st.integers(1, 6)),
    reconstructor=st.sampled_from(RECONSTRUCTORS),
    side_kinds=st.tuples(st.sampled_from(KINDS), st.sampled_from(KINDS)),
)
def test_empty_rows_are_skipped_and_the_pair_is_the_reference_pair(
    dem_path: Path,
    seed: int,
    kind: str,
    band: tuple[int, int],
    reconstructor: str,
    side_kinds: tuple[str, str],
) -> None:
    """Material in a band of rows (at an edge, in the middle, wrapping a periodic side) and
    nothing elsewhere: the kernels compute only the rows a step can reach from it
    (``active_rows``: fewer than all for a narrow band away from an inflow side) and the step
    pair is still the reference's bit for bit (an empty cell of a model whose empty cells stay
    empty has no flux, source or resistance)."""
    rng = np.random.default_rng(seed)
    grid = Grid2D.from_bounds(*X_RANGE, 16, *Y_RANGE, 24)
    model = terrain_model(kind, 35.0, 25.0, "savage-hutter", dem_path).on_grid_2d(grid)
    q = random_flow(rng, grid.shape, 0.2, 0.2, 15.0)
    first, width = band
    rows = (first + np.arange(width)) % grid.shape[0]
    q[:, np.setdiff1d(np.arange(grid.shape[0]), rows)] = 0.0
    boundaries = sides(*side_kinds)
    limiter = registry.reconstructors.get(reconstructor)
    compiled = JiangTadmor(
        model, limiter, grid, boundaries, threads=1, inflow=inflow_of(boundaries)
    )
    compiled._load(q, 0)
    kernels = compiled.kernels
    step = kernels.Step(GHOSTS - 1, *compiled.shapes[True], 0.1, grid.dx, grid.dy, 1.0)
    start, stop = kernels.active_rows(compiled.states[0], step)
    assert 0 <= start <= stop <= step.rows
    inside = first + width <= grid.shape[0]  # the band does not wrap past the top row
    if (
        inside
        and side_kinds[1] not in ("inflow", "periodic")
        and side_kinds[0] != "inflow"
        and width <= 4
    ):
        assert stop - start < step.rows
    assert_same_pair(model, reconstructor, grid, boundaries, q, 0.45)


def test_a_model_whose_empty_cells_change_computes_every_row() -> None:
    """A model with a sink at the empty state (``empty_stays_empty`` False) steps every row,
    empty or not."""
    from draining_model import Draining2D

    assert not Draining2D.empty_stays_empty and SavageHutter2D.empty_stays_empty
    grid = Grid2D.from_bounds(0.0, 10.0, 20, -4.0, 4.0, 12)
    limiter = registry.reconstructors.get("mc")
    compiled = JiangTadmor(Draining2D(), limiter, grid, sides("outflow", "outflow"), threads=1)
    compiled._load(np.zeros((3, *grid.shape)), 0)
    kernels = compiled.kernels
    step = kernels.Step(GHOSTS - 1, *compiled.shapes[True], 0.1, grid.dx, grid.dy, 1.0)
    assert kernels.active_rows(compiled.states[0], step) == (0, step.rows)
