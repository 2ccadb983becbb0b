"""Savage–Hutter on terrain (conslaw_models/savage_hutter_terrain.py) on the Jiang–Tadmor
reference: a plane tilted along x is the chute model under ``x = s cos(zeta)`` to round-off,
the pressure geometry is the derivative it claims to be, a pile in a bowl below the Coulomb
threshold stays exactly at rest, the mirror images across both axes are exact in a bowl, and
mass is conserved to round-off with h >= 0. Friction acts in the surface's metric: on a plane
it is the chute's friction against ``(U, V)``. Parameters over their whole admissible range:
0 <= delta <= phi < 90 degrees, both earth-pressure rules, planes from -60 to 60 degrees,
bowls."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from conslaw import registry
from conslaw.errors import ConfigError
from conslaw.grid2d import Grid2D
from conslaw.schemes.jiang_tadmor import JiangTadmorReference
from conslaw_models.savage_hutter_2d import SavageHutter2D
from conslaw_models.savage_hutter_terrain import SavageHutterTerrain
from conslaw_models.terrain_geometry import pressure_geometry, projection, slope_cosine
from conslaw_models.terrain_surface import GriddedSurface, InclinedPlane, ParaboloidBowl

SIDES = ("left", "right", "bottom", "top")
WALLS = dict.fromkeys(SIDES, "wall")
# WENO's smoothness weights add an absolute epsilon (not invariant under the scaling by cos zeta).
SCALE_INVARIANT = [name for name in registry.reconstructors.names() if not name.startswith("weno")]


@st.composite
def friction_angles(draw: st.DrawFn) -> tuple[float, float]:
    """``(phi, delta)``: ``phi`` in [0, 89.9], ``delta`` anywhere in [0, phi]."""
    phi = draw(st.floats(0.0, 89.9))
    return phi, phi * draw(st.sampled_from([0.0, 1.0]) | st.floats(0.0, 1.0))


@settings(max_examples=20, deadline=None)
@given(
    angles=friction_angles(),
    zeta=st.floats(-60.0, 60.0),
    earth_pressure=st.sampled_from(["savage-hutter", "isotropic"]),
    reconstructor=st.sampled_from(SCALE_INVARIANT),
    side=st.sampled_from(["wall", "periodic", "outflow"]),
    seed=st.integers(0, 2**32 - 1),
)
def test_a_plane_tilted_along_x_is_the_chute(
    angles: tuple[float, float],
    zeta: float,
    earth_pressure: str,
    reconstructor: str,
    side: str,
    seed: int,
) -> None:
    """Random depths (dry cells included) and velocities on a plane descending along x take
    the chute model's ten steps (``g = 1``, ``epsilon = 1``) under ``x = s cos zeta``, ``H =
    h / cos zeta``, ``H u = h U``, ``H v = h V / cos zeta``, to 1e-13 of each variable's
    largest value: the two formulations are one on a plane (docs/design.md, "Savage–Hutter on
    terrain")."""
    phi, delta = angles
    c = math.cos(math.radians(zeta))
    rng = np.random.default_rng(seed)
    shape = (8, 16)
    h = np.abs(rng.normal(1.0, 0.5, shape)) * (rng.random(shape) > 0.2)
    along, across = rng.normal(0.3, 1.0, shape), rng.normal(0.0, 1.0, shape)
    sides = dict.fromkeys(SIDES, side)
    limiter = registry.reconstructors.get(reconstructor)
    common = {"phi": phi, "delta": delta, "zeta": zeta, "earth_pressure": earth_pressure}
    chute = JiangTadmorReference(
        SavageHutter2D(epsilon=1.0, **common),
        limiter,
        Grid2D.from_bounds(0.0, 1.0, 16, 0.0, 0.5, 8),
        sides,
    )
    terrain = JiangTadmorReference(
        SavageHutterTerrain(gravity=1.0, **common),
        limiter,
        Grid2D.from_bounds(0.0, c, 16, 0.0, 0.5, 8),
        sides,
    )
    q_chute = np.stack([h, h * along, h * across])
    q_terrain = np.stack([h / c, h * along, h * across / c])
    dt = 0.5 * chute.stable_dt(q_chute)
    for step in range(10):
        q_chute = chute.step(q_chute, step % 2 == 1, dt)
        q_terrain = terrain.step(q_terrain, step % 2 == 1, dt)
    mapped = np.stack([q_terrain[0] * c, q_terrain[1], q_terrain[2] * c])
    for row in range(3):
        scale = max(np.max(np.abs(q_chute[row])), 1e-300)
        np.testing.assert_allclose(mapped[row], q_chute[row], rtol=0, atol=1e-13 * scale)


def test_the_pressure_geometry_is_the_derivative_of_the_projection() -> None:
    """``T_ij = d_j (P_ij / c)`` in closed form equals centred differences of ``P / c`` on a
    surface with every second derivative nonzero (to the differences' O(e^2) error)."""
    x, y = np.meshgrid(np.linspace(-1.0, 1.0, 7), np.linspace(-0.8, 0.9, 5))

    def derivatives(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, ...]:
        # b = sin(x) cos(2 y) + x^2 / 3 + x y / 2
        return (
            np.cos(x) * np.cos(2 * y) + 2 * x / 3 + y / 2,
            -2 * np.sin(x) * np.sin(2 * y) + x / 2,
            -np.sin(x) * np.cos(2 * y) + 2 / 3,
            -2 * np.cos(x) * np.sin(2 * y) + 0.5,
            -4 * np.sin(x) * np.cos(2 * y),
        )

    def over_c(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, ...]:
        b_x, b_y, *_ = derivatives(x, y)
        c = slope_cosine(b_x, b_y)
        return tuple(p / c for p in projection(b_x, b_y))

    step = 1e-5
    t_xx, t_xy, t_yx, t_yy = pressure_geometry(*derivatives(x, y))
    d_x = [
        (a - b) / (2 * step) for a, b in zip(over_c(x + step, y), over_c(x - step, y), strict=True)
    ]
    d_y = [
        (a - b) / (2 * step) for a, b in zip(over_c(x, y + step), over_c(x, y - step), strict=True)
    ]
    # P is (xx, xy, yy); T_xx = d_x P_xx, T_xy = d_y P_xy, T_yx = d_x P_yx, T_yy = d_y P_yy.
    for exact, difference in ((t_xx, d_x[0]), (t_xy, d_y[1]), (t_yx, d_x[1]), (t_yy, d_y[2])):
        np.testing.assert_allclose(exact, difference, rtol=0, atol=1e-8)


def bowl_pile(model: SavageHutterTerrain, grid: Grid2D, height: float) -> np.ndarray:
    """A pile of ``height`` m and radius 20 m at the bottom of the bowl, at rest, symmetric
    under both mirrors bit for bit."""
    options = {"centre": [0.0, 0.0], "radii": [20.0, 20.0], "height": height, "thin_layer": 0.0}
    q = model.initial_cell_averages_2d("pile", options, grid)
    q = 0.5 * (q + q[:, ::-1, :])
    return 0.5 * (q + q[:, :, ::-1])


@settings(max_examples=12, deadline=None)
@given(
    delta=st.floats(25.0, 80.0),
    share_phi=st.floats(0.0, 1.0),
    earth_pressure=st.sampled_from(["savage-hutter", "isotropic"]),
    reconstructor=st.sampled_from(registry.reconstructors.names()),
)
def test_a_pile_in_a_bowl_below_the_coulomb_threshold_stays_exactly_at_rest(
    delta: float, share_phi: float, earth_pressure: str, reconstructor: str
) -> None:
    """A pile in a bowl whose slopes under it stay below 11.4 degrees, low enough that gravity
    along the bed and the largest earth pressure of its slopes stay below half the Coulomb
    threshold (``tan 11.4 + 2 K height / radius <= tan(delta) / 2``), keeps every momentum
    exactly 0 and every depth bit for bit over 400 steps."""
    phi = delta + share_phi * (89.9 - delta)
    model = SavageHutterTerrain(
        phi=phi, delta=delta, terrain="bowl", bowl_radius=100.0, earth_pressure=earth_pressure
    )
    k_max = max(model.k_passive, model.k_y_max)
    height = (0.5 * math.tan(math.radians(delta)) - 0.2) * 20.0 / (2.0 * k_max)
    assert height > 0.0
    grid = Grid2D.from_bounds(-30.0, 30.0, 20, -30.0, 30.0, 20)
    jt = JiangTadmorReference(model, registry.reconstructors.get(reconstructor), grid, WALLS)
    q = bowl_pile(model, grid, height)
    dt = 0.45 * grid.dx / math.sqrt(9.81 * k_max * np.max(q[0]))
    state = q
    for _ in range(200):
        state, _ = jt._pair(state, dt)
        assert state is not None
        np.testing.assert_array_equal(state[1:], 0.0)
    np.testing.assert_array_equal(state[0], q[0])


@pytest.mark.slow
def test_a_pile_in_a_bowl_stays_at_rest_for_ten_thousand_steps() -> None:
    """The pile of the test above (delta = 30, phi = 35, mc) for 10^4 steps."""
    model = SavageHutterTerrain(phi=35.0, delta=30.0, terrain="bowl", bowl_radius=100.0)
    k_max = max(model.k_passive, model.k_y_max)
    height = (0.5 * math.tan(math.radians(30.0)) - 0.2) * 20.0 / (2.0 * k_max)
    grid = Grid2D.from_bounds(-30.0, 30.0, 20, -30.0, 30.0, 20)
    jt = JiangTadmorReference(model, registry.reconstructors.get("mc"), grid, WALLS)
    q = bowl_pile(model, grid, height)
    dt = 0.45 * grid.dx / math.sqrt(9.81 * k_max * np.max(q[0]))
    state = q
    for _ in range(5000):
        state, _ = jt._pair(state, dt)
        assert state is not None and not np.any(state[1:])
    np.testing.assert_array_equal(state[0], q[0])


@pytest.mark.parametrize("reconstructor", ["minmod", "mc", "weno5"])
@settings(max_examples=6, deadline=None)
@given(
    phi=st.floats(0.0, 89.9),
    share=st.floats(0.0, 1.0),
    earth_pressure=st.sampled_from(["savage-hutter", "isotropic"]),
)
def test_the_mirror_images_in_a_bowl_are_exact(
    reconstructor: str, phi: float, share: float, earth_pressure: str
) -> None:
    """A pile released off-centre in a bowl, symmetric about y = 0, stays symmetric bit for
    bit (H and H u even in y, H v odd), and the run of its mirror image across x = 0 is the
    mirror image of its run, bit for bit. The bowl (radius 20 m) is steeper than ``delta <=
    25`` degrees under most of the pile, which slides."""
    delta = min(phi, 25.0) * share
    model = SavageHutterTerrain(
        phi=phi, delta=delta, terrain="bowl", bowl_radius=20.0, earth_pressure=earth_pressure
    )
    # Cells of 4 m and 3.75 m: every centre and quarter point mirrors exactly.
    grid = Grid2D.from_bounds(-40.0, 40.0, 20, -30.0, 30.0, 16)
    limiter = registry.reconstructors.get(reconstructor)
    jt = JiangTadmorReference(model, limiter, grid, WALLS)
    options = {"centre": [12.0, 0.0], "radii": [10.0, 8.0], "height": 2.0, "thin_layer": 0.0}
    q = model.initial_cell_averages_2d("pile", options, grid)
    q = 0.5 * (q + q[:, ::-1, :])
    mirror = q[:, :, ::-1] * np.array([1.0, -1.0, 1.0])[:, None, None]
    dt = 0.25 * jt.stable_dt(q)
    for step in range(12):
        q = jt.step(q, step % 2 == 1, dt)
        mirror = jt.step(mirror, step % 2 == 1, dt)
    np.testing.assert_array_equal(q[:2], q[:2, ::-1, :])
    np.testing.assert_array_equal(q[2], -q[2, ::-1, :])
    np.testing.assert_array_equal(mirror, q[:, :, ::-1] * np.array([1.0, -1.0, 1.0])[:, None, None])
    assert np.any(q[1] != 0.0)


@pytest.mark.parametrize("reconstructor", ["none", "mc", "weno5"])
@settings(max_examples=6, deadline=None)
@given(
    angles=friction_angles(),
    terrain=st.sampled_from(["plane", "bowl"]),
    zeta=st.floats(-60.0, 60.0),
    seed=st.integers(0, 2**32 - 1),
)
def test_walls_conserve_mass_to_round_off_and_keep_h_nonnegative(
    reconstructor: str, angles: tuple[float, float], terrain: str, zeta: float, seed: int
) -> None:
    """Random depths (dry cells included) and velocities between four walls on a plane or in
    a bowl: the volume is conserved to round-off and no depth is negative or NaN after 20
    steps."""
    phi, delta = angles
    rng = np.random.default_rng(seed)
    shape = (10, 14)
    h = np.abs(rng.normal(2.0, 2.0, shape)) * (rng.random(shape) > 0.3)
    q = np.stack([h, h * rng.normal(0, 3, shape), h * rng.normal(0, 3, shape)])
    model = SavageHutterTerrain(phi=phi, delta=delta, terrain=terrain, zeta=zeta, bowl_radius=30.0)
    grid = Grid2D.from_bounds(-35.0, 35.0, 14, -25.0, 25.0, 10)
    jt = JiangTadmorReference(model, registry.reconstructors.get(reconstructor), grid, WALLS)
    end, _, _ = jt.advance(q, 0.0, 10.0 * jt.stable_dt(q))
    assert np.all(np.isfinite(end)) and np.min(end[0]) >= 0.0
    np.testing.assert_allclose(end[0].sum(), h.sum(), rtol=1e-13)


def test_gridded_terrain_reproduces_a_sampled_plane() -> None:
    """A bicubic spline through samples of a tilted plane is the plane: its slopes to 1e-12."""
    x = np.linspace(0.0, 50.0, 11)
    y = np.linspace(0.0, 30.0, 7)
    elevation = 100.0 - 0.7 * x[None, :] + 0.2 * y[:, None]
    surface = GriddedSurface(x, y, elevation)
    _, b_x, b_y, b_xx, b_xy, b_yy = surface.derivatives(
        np.array([3.3, 41.0]), np.array([2.0, 27.5])
    )
    np.testing.assert_allclose(b_x, -0.7, atol=1e-12)
    np.testing.assert_allclose(b_y, 0.2, atol=1e-12)
    np.testing.assert_allclose(np.stack([b_xx, b_xy, b_yy]), 0.0, atol=1e-11)
    assert surface.covers(-2.5, 52.5, -2.5, 32.5) is None
    # Beyond the outermost centres the spline continues the plane (linear padding).
    outside = surface.derivatives(np.array([-2.5, 52.5]), np.array([-2.5, 32.5]))
    np.testing.assert_allclose(outside[0], [100.0 + 1.75 - 0.5, 100.0 - 36.75 + 6.5], atol=1e-11)
    np.testing.assert_allclose(outside[1], -0.7, atol=1e-12)
    assert "leaves the terrain" in str(surface.covers(-10.0, 50.0, 0.0, 30.0))


def test_surfaces_in_closed_form() -> None:
    """The plane and the bowl give their slopes and curvatures exactly."""
    _, b_x, b_y, *_ = InclinedPlane(45.0).derivatives(np.zeros(2), np.ones(2))
    np.testing.assert_allclose(b_x, -1.0, rtol=1e-15)
    assert not np.any(b_y)
    _, b_x, b_y, b_xx, b_xy, b_yy = ParaboloidBowl(10.0).derivatives(
        np.array([5.0]), np.array([-2.0])
    )
    assert (b_x[0], b_y[0], b_xx[0], b_xy[0], b_yy[0]) == (0.5, -0.2, 0.1, 0.0, 0.1)


@pytest.mark.parametrize(
    ("params", "key"),
    [
        ({"gravity": 0.0}, "parameters.gravity"),
        ({"phi": 30.0, "delta": 31.0}, "parameters.delta"),
        ({"terrain": "hill"}, "parameters.terrain"),
        ({"zeta": 90.0}, "parameters.zeta"),
        ({"bowl_radius": -1.0}, "parameters.bowl_radius"),
        ({"earth_pressure": "rankine"}, "parameters.earth_pressure"),
    ],
)
def test_bad_parameters_name_their_key(params: dict[str, object], key: str) -> None:
    """Each bad parameter is one line naming its key."""
    with pytest.raises(ConfigError, match=key) as error:
        SavageHutterTerrain(**params)
    assert "\n" not in str(error.value)


def test_the_channelled_terrain_is_the_generated_one_with_its_derivatives() -> None:
    """The channel terrain in closed form equals the DEM generator's formula at its cell
    centres, and its first and second derivatives equal centred differences (to their O(e^2))
    on the plane, across the arc where the channel fades, and on the run-out."""
    from conslaw.terrain.generated import channelled_slope
    from conslaw_models.terrain_surface import ChannelledPlaneToFlat, PlaneToFlat

    surface = ChannelledPlaneToFlat(PlaneToFlat(40.0, 200.0, 700.0), 15.0, 50.0)
    dem = channelled_slope(length=1000.0, width=500.0, cell_size=25.0, runout_length=300.0)
    x, y = dem.centres()
    np.testing.assert_allclose(
        surface.derivatives(x[None, :], y[:, None])[0], dem.elevation, rtol=0, atol=1e-9
    )
    px, py = np.meshgrid(np.array([300.0, 600.0, 650.0, 690.0, 800.0]), np.array([-70.0, 10.0]))
    e = 1e-4
    values = surface.derivatives(px, py)
    right, left = surface.derivatives(px + e, py), surface.derivatives(px - e, py)
    up, down = surface.derivatives(px, py + e), surface.derivatives(px, py - e)
    for exact, difference in (
        (values[1], (right[0] - left[0]) / (2 * e)),
        (values[2], (up[0] - down[0]) / (2 * e)),
        (values[3], (right[1] - left[1]) / (2 * e)),
        (values[4], (up[1] - down[1]) / (2 * e)),
        (values[5], (up[2] - down[2]) / (2 * e)),
    ):
        np.testing.assert_allclose(exact, difference, rtol=0, atol=1e-6)


class TiltedSurface:
    """``b = s_x x + s_y y + a sin(x) cos(2 y) + k (x^2 / 30 + x y / 20)``, optionally
    mirrored across x = 0 or y = 0: with ``a`` and ``k`` not 0 a surface without symmetry, with
    both 0 a plane; every derivative in closed form."""

    def __init__(
        self,
        s_x: float,
        s_y: float,
        wave: float = 0.0,
        bend: float = 0.0,
        flip_x: bool = False,
        flip_y: bool = False,
    ) -> None:
        self.s_x, self.s_y, self.wave, self.bend = s_x, s_y, wave, bend
        self.sign_x = -1.0 if flip_x else 1.0
        self.sign_y = -1.0 if flip_y else 1.0

    def derivatives(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, ...]:
        x, y = np.broadcast_arrays(self.sign_x * np.asarray(x), self.sign_y * np.asarray(y))
        a, k = self.wave, self.bend
        b = self.s_x * x + self.s_y * y + a * np.sin(x) * np.cos(2 * y)
        b = b + k * (x * x / 30 + x * y / 20)
        b_x = self.s_x + a * np.cos(x) * np.cos(2 * y) + k * (x / 15 + y / 20)
        b_y = self.s_y - 2 * a * np.sin(x) * np.sin(2 * y) + k * x / 20
        b_xx = -a * np.sin(x) * np.cos(2 * y) + k / 15 + 0 * x
        b_xy = -2 * a * np.cos(x) * np.sin(2 * y) + k / 20
        b_yy = -4 * a * np.sin(x) * np.cos(2 * y)
        sx, sy = self.sign_x, self.sign_y
        return b, sx * b_x, sy * b_y, b_xx, sx * sy * b_xy, b_yy

    def covers(self, *bounds: float) -> None:
        return None


def test_the_mirror_signs_of_every_coefficient() -> None:
    """The coefficients of the mirror image of a surface without symmetry, at the mirror
    image of a point, are the surface's own with ``aux_reflect_signs`` (x -> -x) and
    ``aux_reflect_signs_y`` (y -> -y): the signs the scheme gives its ghost cells at walls."""
    model = SavageHutterTerrain(phi=35.0, delta=25.0)
    x, y = np.meshgrid(np.linspace(-2.0, 3.0, 7), np.linspace(-1.5, 2.5, 5))
    model.surface = TiltedSurface(-0.4, 0.25, wave=0.7, bend=1.0)
    own = model.aux_2d(x, y)
    for flip_x, signs in ((True, model.aux_reflect_signs), (False, model.aux_reflect_signs_y)):
        model.surface = TiltedSurface(
            -0.4, 0.25, wave=0.7, bend=1.0, flip_x=flip_x, flip_y=not flip_x
        )
        mirrored = model.aux_2d(-x, y) if flip_x else model.aux_2d(x, -y)
        assert signs is not None
        np.testing.assert_allclose(
            mirrored, np.asarray(signs)[:, None, None] * own, rtol=1e-14, atol=1e-15
        )


@settings(max_examples=20, deadline=None)
@given(
    s_x=st.floats(-1.5, 1.5),
    s_y=st.floats(-1.5, 1.5),
    delta=st.floats(0.0, 60.0),
    earth_pressure=st.sampled_from(["savage-hutter", "isotropic"]),
)
def test_a_layer_at_rest_on_an_oblique_plane_slides_down_its_fall_line_exactly(
    s_x: float, s_y: float, delta: float, earth_pressure: str
) -> None:
    """A uniform layer released at rest on a periodic plane ``b = s_x x + s_y y`` that is
    not along an axis: after ``n`` step pairs its speed in the surface is ``g (sin theta - tan
    delta cos theta) t`` (or 0 where friction holds it) and its velocity points down the fall
    line, ``-grad b``, to 1e-12: gravity, the projection ``P`` and the friction in the
    surface's metric together."""
    model = SavageHutterTerrain(phi=max(delta, 30.0), delta=delta, earth_pressure=earth_pressure)
    model.surface = TiltedSurface(s_x, s_y)
    model.surface.derivatives = (
        lambda x, y, s=model.surface: (  # type: ignore[method-assign]
            *(v for v in TiltedSurface.derivatives(s, x, y)[:3]),
            *(np.zeros(np.broadcast_shapes(np.shape(x), np.shape(y))) for _ in range(3)),
        )
    )
    grid = Grid2D.from_bounds(0.0, 40.0, 4, 0.0, 40.0, 4)
    jt = JiangTadmorReference(
        model, registry.reconstructors.get("mc"), grid, dict.fromkeys(SIDES, "periodic")
    )
    slope = math.hypot(s_x, s_y)
    theta = math.atan(slope)
    c = math.cos(theta)
    q = np.stack([np.full((4, 4), 1.0 / c), np.zeros((4, 4)), np.zeros((4, 4))])
    dt, t = 0.05, 0.0
    for _ in range(5):
        q = jt.step(jt.step(q, False, dt), True, dt)
        t += 2 * dt
    u, v = q[1, 0, 0] * c, q[2, 0, 0] * c
    speed = math.sqrt(u * u + v * v + (s_x * u + s_y * v) ** 2)
    expected = max(9.81 * (math.sin(theta) - math.tan(math.radians(delta)) * c) * t, 0.0)
    assert speed == pytest.approx(expected, rel=1e-12, abs=1e-12)
    np.testing.assert_allclose(q, np.broadcast_to(q[:, :1, :1], q.shape), rtol=1e-13, atol=1e-13)
    if expected > 0.0 and slope > 1e-6:
        assert abs(u * s_y - v * s_x) <= 1e-12 * speed * slope
        assert u * s_x + v * s_y < 0.0


@settings(max_examples=10, deadline=None)
@given(
    zeta=st.floats(-60.0, 60.0),
    angles=friction_angles(),
    reconstructor=st.sampled_from(registry.reconstructors.names()),
    seed=st.integers(0, 2**32 - 1),
)
def test_with_isotropic_pressure_a_plane_along_y_is_the_plane_along_x_turned(
    zeta: float, angles: tuple[float, float], reconstructor: str, seed: int
) -> None:
    """Random states (dry cells included) between walls on a plane descending along +x and,
    transposed (x and y, u and v swapped), on the same plane descending along +y: with
    isotropic pressure the runs are each other's transposes to 1e-12 of each variable's
    largest value after ten steps (the model is invariant under rotation; the scheme treats x
    and y alike)."""
    phi, delta = angles
    rng = np.random.default_rng(seed)
    h = np.abs(rng.normal(1.0, 0.5, (10, 10))) * (rng.random((10, 10)) > 0.2)
    q = np.stack([h, h * rng.normal(0, 1, h.shape), h * rng.normal(0, 1, h.shape)])
    limiter = registry.reconstructors.get(reconstructor)
    grid = Grid2D.from_bounds(0.0, 10.0, 10, 0.0, 10.0, 10)
    along_x = SavageHutterTerrain(phi=phi, delta=delta, zeta=zeta, earth_pressure="isotropic")
    along_y = SavageHutterTerrain(phi=phi, delta=delta, zeta=zeta, earth_pressure="isotropic")
    along_y.surface = TiltedSurface(0.0, -math.tan(math.radians(zeta)))
    runs = [JiangTadmorReference(model, limiter, grid, WALLS) for model in (along_x, along_y)]
    turned = np.stack([q[0].T, q[2].T, q[1].T])
    dt = 0.25 * runs[0].stable_dt(q)
    for step in range(10):
        q = runs[0].step(q, step % 2 == 1, dt)
        turned = runs[1].step(turned, step % 2 == 1, dt)
    back = np.stack([turned[0].T, turned[2].T, turned[1].T])
    for row in range(3):
        scale = max(np.max(np.abs(q[row])), 1e-300)
        np.testing.assert_allclose(back[row], q[row], rtol=0, atol=1e-12 * scale)


def test_smoothing_a_noisy_dem_quiets_its_curvature() -> None:
    """A plane with centimetre noise on 5 m cells reads as curved by noise / dx^2 (the normal
    reaction and the pressure geometry take it); a Gaussian filter of 2 cells cuts the largest
    curvature by more than 10x and keeps the mean slope; no filter keeps the samples."""
    from conslaw.terrain import DigitalElevationModel

    rng = np.random.default_rng(1)
    x = 2.5 + 5.0 * np.arange(60)
    elevation = 300.0 - 0.6 * x[None, :] + 0.01 * rng.standard_normal((40, 60))
    dem = DigitalElevationModel(elevation, 0.0, 0.0, 5.0)
    points = np.meshgrid(np.linspace(50.0, 250.0, 30), np.linspace(50.0, 150.0, 20))
    raw = GriddedSurface.from_dem(dem).derivatives(*points)
    smooth = GriddedSurface.from_dem(dem, 2.0).derivatives(*points)
    assert np.max(np.abs(smooth[3])) < 0.1 * np.max(np.abs(raw[3]))
    np.testing.assert_allclose(np.mean(smooth[1]), -0.6, atol=1e-3)
    np.testing.assert_array_equal(GriddedSurface.from_dem(dem, 0.0).elevation, dem.elevation)
