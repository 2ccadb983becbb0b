"""Tracked margins in 2D (conslaw/schemes/jiang_tadmor/margins.py, scheme ``jiang-tadmor-ft``):
gathering keeps every total to round-off, leaves exactly nothing outside the region and no
negative depth, and mirrored data give mirrored results; the level set moves a plane exactly
and stays put at rest; the similarity solution's margins lie within 1.5 cells of the exact
ellipse with the depth converging at order >= 1; a pile at rest stays exactly at rest; walls
conserve mass for random states over the whole range of the friction angles."""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import conslaw
from conslaw import registry
from conslaw.analysis import observed_orders
from conslaw.errors import ConfigError
from conslaw.grid2d import Grid2D
from conslaw.schemes.jiang_tadmor import JiangTadmor, JiangTadmorTracked
from conslaw.schemes.jiang_tadmor.margins import (
    MarginTracker,
    advected,
    reinitialised,
    signed_distance,
)
from conslaw_models.burgers_2d import Burgers2D
from conslaw_models.savage_hutter_terrain import SavageHutterTerrain

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
from similarity_2d import margin_offset

WALLS = dict.fromkeys(("left", "right", "bottom", "top"), "wall")


def tracker_on(shape: tuple[int, int]) -> MarginTracker:
    ny, nx = shape
    return MarginTracker(Grid2D.from_bounds(0.0, float(nx), nx, 0.0, float(ny), ny), 0, 1, 2)


@settings(max_examples=40, deadline=None)
@given(
    ny=st.integers(4, 12),
    nx=st.integers(4, 12),
    seed=st.integers(0, 2**32 - 1),
    covered_share=st.floats(0.05, 0.95),
)
def test_gathering_keeps_totals_and_leaves_nothing_outside(
    ny: int, nx: int, seed: int, covered_share: float
) -> None:
    """Random depths (dry cells among them) and momenta, and a random non-empty region: after
    gathering, every total is the same to round-off, the region grew only by the cells of
    material lying more than three cells out, every value outside it is exactly 0, no depth is
    negative and no depth inside fell."""
    rng = np.random.default_rng(seed)
    h = np.abs(rng.normal(1.0, 1.0, (ny, nx))) * (rng.random((ny, nx)) > 0.3)
    q = np.stack([h, h * rng.normal(0.0, 2.0, (ny, nx)), h * rng.normal(0.0, 2.0, (ny, nx))])
    inside = rng.random((ny, nx)) < covered_share
    inside.flat[rng.integers(0, ny * nx)] = True
    tracker = tracker_on((ny, nx))
    tracker.level = np.where(inside, 1.0, -1.0)
    before = q.copy()
    tracker.gather(q)
    scale = np.sum(np.abs(before), axis=(1, 2))
    totals = before.sum(axis=(1, 2))
    np.testing.assert_allclose(q.sum(axis=(1, 2)), totals, atol=1e-13 * scale.max())
    region = tracker.level > 0.0
    assert np.all(region[inside])  # the region only grows, where material lay far out
    assert np.count_nonzero(region & ~inside) == tracker.joined
    assert np.all(q[:, ~region] == 0.0)
    assert np.all(q[0] >= 0.0)
    assert np.all(q[0][inside] >= before[0][inside])


@settings(max_examples=20, deadline=None)
@given(ny=st.integers(2, 8), nx=st.integers(4, 12), seed=st.integers(0, 2**32 - 1))
def test_mirrored_data_gather_to_mirrored_results(ny: int, nx: int, seed: int) -> None:
    """Data and a region symmetric about the middle row (the y momentum odd) gather to a
    symmetric result, bit for bit."""
    rng = np.random.default_rng(seed)
    half = np.abs(rng.normal(1.0, 1.0, (ny, nx))) * (rng.random((ny, nx)) > 0.3)
    h = np.concatenate([half, half[::-1]])
    u = np.concatenate([half * 0.5, half[::-1] * 0.5])
    v_half = half * rng.normal(0.0, 1.0, (ny, nx))
    v = np.concatenate([v_half, -v_half[::-1]])
    q = np.stack([h, u, v])
    region = rng.random((ny, nx)) < 0.4
    region[0, 0] = True
    inside = np.concatenate([region, region[::-1]])
    tracker = tracker_on((2 * ny, nx))
    tracker.level = np.where(inside, 1.0, -1.0)
    tracker.gather(q)
    np.testing.assert_array_equal(q[:2], q[:2, ::-1])
    np.testing.assert_array_equal(q[2], -q[2, ::-1])


@settings(max_examples=30, deadline=None)
@given(
    slope_x=st.floats(-2.0, 2.0),
    slope_y=st.floats(-2.0, 2.0),
    shift_x=st.floats(-0.9, 0.9),
    shift_y=st.floats(-0.9, 0.9),
)
def test_a_plane_level_moves_exactly_and_stays_at_rest(
    slope_x: float, slope_y: float, shift_x: float, shift_y: float
) -> None:
    """A plane level moved by a uniform shift is the plane shifted (away from the edges, where
    the values are the edge's), to round-off; with no shift the level is kept bit for bit."""
    rows, columns = np.indices((12, 16), dtype=np.float64)
    level = slope_x * columns + slope_y * rows + 0.3
    still = advected(level, np.zeros_like(level), np.zeros_like(level))
    np.testing.assert_array_equal(still, level)
    moved = advected(level, np.full_like(level, shift_x), np.full_like(level, shift_y))
    expected = slope_x * (columns - shift_x) + slope_y * (rows - shift_y) + 0.3
    np.testing.assert_allclose(moved[1:-1, 1:-1], expected[1:-1, 1:-1], atol=1e-12)


def test_reinitialising_a_signed_distance_keeps_its_margin() -> None:
    """The signed distance of a disc, scaled by 5 and made a distance again, has its zero
    contour where it was (within a hundredth of a cell along the axes) and unit slope near it."""
    rows, columns = np.indices((41, 41), dtype=np.float64)
    radius = np.hypot(columns - 20.0, rows - 20.0)
    level = 5.0 * (10.3 - radius)
    again = reinitialised(level, (1.0, 1.0))
    row = again[20]
    inner, outer = row[30], row[31]  # the zero lies between columns 30 and 31
    crossing = 30.0 + inner / (inner - outer)
    assert abs(crossing - 30.3) < 1e-2
    assert np.all(np.sign(again) == np.sign(level))
    np.testing.assert_allclose(row[28:34], 10.3 - np.abs(np.arange(28, 34) - 20.0), atol=0.05)


def test_signed_distance_is_half_way_between_covered_and_bare_centres() -> None:
    covered = np.zeros((5, 9), dtype=bool)
    covered[:, :4] = True
    level = signed_distance(covered, (1.0, 1.0))
    np.testing.assert_array_equal(level[2], [3.5, 2.5, 1.5, 0.5, -0.5, -1.5, -2.5, -3.5, -4.5])


def similarity(reconstructor: str, cells: tuple[int, int]) -> tuple[float, float, object]:
    result = conslaw.run_2d(
        "sh2d-similarity-ft", n_cells=list(cells), output_times=[], reconstructor=reconstructor
    )
    error = result.headline_error()
    assert error is not None
    return error, margin_offset(result), result


@pytest.mark.parametrize("reconstructor", ["mc", "weno5"])
def test_the_similarity_margins_lie_within_one_and_a_half_cells(reconstructor: str) -> None:
    """The elliptic cap of ``sh2d-similarity-ft`` at 48 x 30 and 96 x 60 cells: every cell
    centre on the wrong side of the exact ellipse (covered above 1e-6 outside, or bare inside)
    within 1.5 cells of it, the depth's L1 error falling at order >= 1, the volume kept to
    round-off, no negative depth, and exactly 0 two cells beyond the ellipse."""
    errors, offsets = [], []
    for cells in ((48, 30), (96, 60)):
        error, offset, result = similarity(reconstructor, cells)
        errors.append(error)
        offsets.append(offset)
        h0, h = result.initial.q[0], result.final.q[0]  # type: ignore[attr-defined]
        assert abs(h.sum() - h0.sum()) <= 1e-13 * h0.sum()
        assert np.min(h) >= 0.0
        cap = result.exact_solution  # type: ignore[attr-defined]
        x_c, y_c, a, b = cap.margin(result.final.t)  # type: ignore[attr-defined]
        x, y = result.grid.centres()  # type: ignore[attr-defined]
        xx, yy = np.meshgrid(x, y)
        beyond = np.hypot(
            (xx - x_c) / (a + 2 * result.grid.dx), (yy - y_c) / (b + 2 * result.grid.dy)
        )  # type: ignore[attr-defined]
        assert np.all(h[beyond > 1.0] == 0.0)
    assert max(offsets) <= 1.5, offsets
    assert observed_orders([48, 96], errors)[0] >= 1.0, errors


@pytest.mark.slow
@pytest.mark.parametrize("reconstructor", ["mc", "minmod", "weno5"])
def test_the_similarity_margins_at_192_cells(reconstructor: str) -> None:
    """The test above at 96 x 60 and 192 x 120 cells."""
    (coarse, _, _), (fine, offset, _) = (
        similarity(reconstructor, cells) for cells in ((96, 60), (192, 120))
    )
    assert offset <= 1.5
    assert observed_orders([96, 192], [coarse, fine])[0] >= 1.0


@settings(max_examples=6, deadline=None)
@given(
    delta=st.floats(25.0, 80.0),
    share_phi=st.floats(0.0, 1.0),
    earth_pressure=st.sampled_from(["savage-hutter", "isotropic"]),
    reconstructor=st.sampled_from(registry.reconstructors.names()),
)
def test_a_pile_below_the_coulomb_threshold_stays_exactly_at_rest(
    delta: float, share_phi: float, earth_pressure: str, reconstructor: str
) -> None:
    """A pile in a bowl whose slopes and earth pressure stay below half the Coulomb threshold
    (``tan 11.4 + 2 K height / radius <= tan(delta) / 2``, as in
    tests/test_savage_hutter_terrain.py) keeps every momentum exactly 0 and every depth bit
    for bit over 100 steps with its margins tracked."""
    phi = delta + share_phi * (89.9 - delta)
    model = SavageHutterTerrain(
        phi=phi, delta=delta, terrain="bowl", bowl_radius=100.0, earth_pressure=earth_pressure
    )
    k_max = max(model.k_passive, model.k_y_max)
    height = (0.5 * math.tan(math.radians(delta)) - 0.2) * 20.0 / (2.0 * k_max)
    assert height > 0.0
    grid = Grid2D.from_bounds(-30.0, 30.0, 20, -30.0, 30.0, 20)
    scheme = JiangTadmorTracked(model, registry.reconstructors.get(reconstructor), grid, WALLS)
    # The pile of radius 20 m of that test, its slopes within the bound above.
    options = {"centre": [0.0, 0.0], "radii": [20.0, 20.0], "height": height, "thin_layer": 0.0}
    q = model.initial_cell_averages_2d("pile", options, grid)
    dt = scheme.reference.stable_dt(q)
    end, _, steps = scheme.advance(q, 0.0, 101 * dt)
    assert steps >= 100
    np.testing.assert_array_equal(end[1:], 0.0)
    np.testing.assert_array_equal(end[0], q[0])


@settings(max_examples=8, deadline=None)
@given(
    phi=st.floats(0.0, 89.9),
    share=st.floats(0.0, 1.0),
    zeta=st.floats(-60.0, 60.0),
    reconstructor=st.sampled_from(["none", "mc", "weno5"]),
    seed=st.integers(0, 2**32 - 1),
)
def test_walls_conserve_mass_and_keep_h_nonnegative_with_tracked_margins(
    phi: float, share: float, zeta: float, reconstructor: str, seed: int
) -> None:
    """Random depths (dry cells included) and velocities between four walls on a plane: the
    volume is kept to round-off, no depth is negative or NaN, and nothing lies outside the
    tracked region after 20 steps."""
    rng = np.random.default_rng(seed)
    shape = (10, 14)
    h = np.abs(rng.normal(2.0, 2.0, shape)) * (rng.random(shape) > 0.3)
    q = np.stack([h, h * rng.normal(0, 3, shape), h * rng.normal(0, 3, shape)])
    model = SavageHutterTerrain(phi=phi, delta=phi * share, terrain="plane", zeta=zeta)
    grid = Grid2D.from_bounds(-35.0, 35.0, 14, -25.0, 25.0, 10)
    scheme = JiangTadmorTracked(model, registry.reconstructors.get(reconstructor), grid, WALLS)
    end, _, _ = scheme.advance(q, 0.0, 10.0 * scheme.reference.stable_dt(q))
    assert np.all(np.isfinite(end)) and np.min(end[0]) >= 0.0
    np.testing.assert_allclose(end[0].sum(), h.sum(), rtol=1e-13)
    assert scheme.tracker.level is not None
    assert np.all(end[:, scheme.tracker.level <= 0.0] == 0.0)


def test_a_model_without_a_depth_and_an_open_side_are_refused() -> None:
    grid = Grid2D.from_bounds(0.0, 1.0, 8, 0.0, 1.0, 8)
    limiter = registry.reconstructors.get("mc")
    with pytest.raises(ConfigError, match="model 'burgers-2d' has no depth"):
        JiangTadmorTracked(Burgers2D(), limiter, grid, WALLS)
    model = SavageHutterTerrain(phi=30.0, delta=20.0, terrain="plane", zeta=20.0)
    with pytest.raises(ConfigError, match=r"boundary\.top = 'periodic'"):
        JiangTadmorTracked(model, limiter, grid, {**WALLS, "top": "periodic"})


@pytest.mark.parametrize("reconstructor", ["minmod", "mc", "weno5"])
@settings(max_examples=4, deadline=None)
@given(phi=st.floats(0.0, 89.9), share=st.floats(0.0, 1.0))
def test_a_sliding_pile_symmetric_about_y_stays_symmetric_bit_for_bit(
    reconstructor: str, phi: float, share: float
) -> None:
    """A pile released off-centre in a bowl, symmetric about y = 0 on a grid whose centres
    mirror exactly, slides with its margins tracked and stays symmetric bit for bit (H and H u
    even in y, H v odd)."""
    delta = min(phi, 25.0) * share
    model = SavageHutterTerrain(phi=phi, delta=delta, terrain="bowl", bowl_radius=20.0)
    grid = Grid2D.from_bounds(-40.0, 40.0, 20, -30.0, 30.0, 16)
    scheme = JiangTadmorTracked(model, registry.reconstructors.get(reconstructor), grid, WALLS)
    options = {"centre": [12.0, 0.0], "radii": [10.0, 8.0], "height": 2.0, "thin_layer": 0.0}
    q = model.initial_cell_averages_2d("pile", options, grid)
    q = 0.5 * (q + q[:, ::-1, :])
    end, _, _ = scheme.advance(q, 0.0, 12.0 * scheme.reference.stable_dt(q))
    np.testing.assert_array_equal(end[:2], end[:2, ::-1, :])
    np.testing.assert_array_equal(end[2], -end[2, ::-1, :])
    assert np.any(end[1] != 0.0)


def test_a_release_at_rest_from_a_scene_stays_exactly_at_rest() -> None:
    """A block released in the bowl below its Coulomb threshold, its edge half a metre past the
    cell centres (the finer grid's start reads some covered cells as outside): nothing moves,
    bit for bit, as on the untracked scheme."""
    polygon = [[200.0, -40.0], [284.5, -40.0], [284.5, 40.0], [200.0, 40.0]]
    for scheme in ("jiang-tadmor", "jiang-tadmor-ft"):
        result = conslaw.run_2d(
            "terrain-bowl",
            scheme=scheme,
            t_end=2.0,
            output_times=[],
            parameters__phi=45.0,
            parameters__delta=40.0,
            initial__polygon=polygon,
            initial__thickness=0.5,
        )
        np.testing.assert_array_equal(result.final.q[0], result.initial.q[0])
        np.testing.assert_array_equal(result.final.q[1:], 0.0)
        assert result.steps > 0


def test_a_thin_pile_slides_beside_a_deep_one() -> None:
    """Two piles side by side on a plane, one 20 times thinner: the thin one slides as on the
    untracked scheme (its centre of mass within 1 m after 8 s of some 110 m of travel), and with
    the margins tracked no material crosses between them. (A pile thinner than ``FILM`` of the
    deepest is a film, which carries velocities and makes none: ``test_a_film_pile_...``.)"""
    model = SavageHutterTerrain(phi=30.0, delta=10.0, terrain="plane", zeta=35.0)
    grid = Grid2D.from_bounds(0.0, 400.0, 80, -150.0, 150.0, 60)
    limiter = registry.reconstructors.get("mc")

    def pile(y: float) -> np.ndarray:
        options = {"centre": [60.0, y], "radii": [25.0, 25.0], "height": 5.0, "thin_layer": 0.0}
        return model.initial_cell_averages_2d("pile", options, grid)

    q = pile(-80.0) + 5e-2 * pile(80.0)
    x, y = grid.centres()
    xx, yy = np.meshgrid(x, y)
    thin = yy > 0.0
    centres = []
    for scheme in (
        JiangTadmor(model, limiter, grid, WALLS),
        JiangTadmorTracked(model, limiter, grid, WALLS),
    ):
        end, _, _ = scheme.advance(q.copy(), 0.0, 8.0)
        h = end[0]
        centres.append(float((h * xx)[thin].sum() / h[thin].sum()))
    # The untracked film crosses between the halves (2e-5 of the thin pile); tracked, none.
    assert abs(h[thin].sum() - q[0][thin].sum()) <= 1e-12 * q[0][thin].sum()
    assert centres[0] > 160.0
    assert abs(centres[1] - centres[0]) < 1.0, centres


def test_a_still_margin_stays_put_on_cells_twice_as_wide_as_high() -> None:
    """A straight margin at x = 10.8 on cells of 2 x 1, made a distance again four times,
    keeps its zero where it was."""
    x = 2.0 * np.arange(12) + 1.0
    level = np.tile(10.8 - x, (6, 1))
    for _ in range(4):
        level = reinitialised(level, (1.0, 2.0))
        row = level[3]
        last = int(np.flatnonzero(row > 0.0).max())
        crossing = x[last] + 2.0 * row[last] / (row[last] - row[last + 1])
        assert abs(crossing - 10.8) < 1e-12


def test_material_far_outside_joins_the_region_instead_of_moving() -> None:
    """Material ten cells from the region is not carried there: its cells join the region and
    it stays where it is; the region's own film is gathered."""
    tracker = tracker_on((12, 20))
    level = np.full((12, 20), -1.0)
    level[5:7, 2:4] = 1.0
    tracker.level = level
    q = np.zeros((3, 12, 20))
    q[0, 5:7, 2:5] = 1.0  # one column of film next to the region
    q[0, 6, 15] = 0.25  # far out
    before = q.copy()
    assert tracker.gather(q)
    assert q[0, 6, 15] == 0.25 and tracker.joined == 1
    assert np.all(q[0, 5:7, 4] == 0.0)
    assert q[0].sum() == before[0].sum()


def test_an_everywhere_covered_start_has_a_finite_level_and_no_warnings() -> None:
    tracker = tracker_on((6, 8))
    q = np.stack([np.ones((6, 8)), np.full((6, 8), 0.5), np.zeros((6, 8))])
    tracker.start_from_values(q)
    assert tracker.level is not None and np.all(np.isfinite(tracker.level))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert not tracker.follow(q, q.copy(), 0.1)
    assert np.all(tracker.level > 0.0)


def test_a_run_is_told_when_its_margins_lagged_the_material() -> None:
    """The similarity cap gathers a film (well under 1 % a pair) and is told nothing; a block
    released in the bowl spreads faster at its edges than the margins follow, and the run says
    so."""
    cap = conslaw.run_2d("sh2d-similarity-ft", n_cells=[48, 30], output_times=[])
    assert cap.scheme_notes == []
    block = conslaw.run_2d(
        "terrain-bowl", scheme="jiang-tadmor-ft", t_end=8.0, output_times=[], n_cells=[50, 50]
    )
    assert len(block.scheme_notes) == 1
    assert "the tracked margins lagged the material" in block.scheme_notes[0]


def test_a_small_body_beside_a_large_one_keeps_its_own_margin() -> None:
    """A 2 x 2 cell blob 5 cm deep some 20 cells downslope of a 3 m pile: it trusts its own
    velocity, so its region neither is dropped nor grows like the untracked film (which covers
    20 cells and more after a second)."""
    grid = Grid2D.from_bounds(0.0, 200.0, 50, -60.0, 60.0, 30)
    model = SavageHutterTerrain(phi=30.0, delta=20.0, terrain="plane", zeta=25.0)
    limiter = registry.reconstructors.get("mc")
    options = {"centre": [40.0, 0.0], "radii": [24.0, 24.0], "height": 3.0, "thin_layer": 0.0}
    q = model.initial_cell_averages_2d("pile", options, grid)
    q[0, 14:16, 35:37] = 0.05
    plain, _, _ = JiangTadmor(model, limiter, grid, WALLS).advance(q.copy(), 0.0, 1.5)
    assert np.count_nonzero(plain[0][:, 28:]) >= 20
    scheme = JiangTadmorTracked(model, limiter, grid, WALLS)
    end, _, steps = scheme.advance(q.copy(), 0.0, 1.5)
    assert steps >= 6 and scheme.tracker.joined == 0
    assert scheme.tracker.level is not None
    assert 2 <= np.count_nonzero(scheme.tracker.level[:, 28:] > 0.0) <= 8
    assert 0 < np.count_nonzero(end[0][:, 28:]) <= 8
