"""Savage–Hutter on terrain as a user runs it: a scene on a generated terrain or on a DEM file
with a release area, and its hazard maps (GeoTIFFs with the terrain's georeference, PNGs,
hazard.json; docs/output.md, "Hazard maps"), with the run's invariants: volume conserved to
round-off, depth >= 0, the peaks at least every depth the run passed through."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import rasterio
from affine import Affine

import conslaw
from conslaw.peak_fields import REACHED_DEPTH
from conslaw.result2d import RunResult2D
from conslaw.terrain import dem_from_function, write_dem
from conslaw.terrain.hazard_maps import hazard_maps
from conslaw_models.sliding_point import energy_line_stop, sliding_stop
from conslaw_models.terrain_surface import PlaneToFlat

UTM = "EPSG:32632"
X0, Y0 = 500000.0, 5200000.0


def test_the_plane_to_flat_scene_writes_its_hazard_maps(tmp_path: Path) -> None:
    """``terrain-plane-to-flat`` at 25 m cells: the run keeps its volume to round-off and its
    depths >= 0; every hazard GeoTIFF opens with rasterio on the scene's cells (north-up, the
    transform of the grid); the peak depth (its float32 values where the flow reached, no data
    elsewhere: docs/output.md, "Hazard maps") is at least the release and the deposit in every
    cell it holds; the travel angle of a mass with delta = 30 lies near 30 degrees (the energy
    line of a point; docs/validation.md, "Savage–Hutter on terrain")."""
    out = tmp_path / "run"
    result = conslaw.run_2d(
        "terrain-plane-to-flat", out=out, n_cells=[40, 20], output_times=[20.0, 60.0]
    )
    grid = result.grid
    volumes = [np.sum(state.q[0]) for state in (result.initial, *result.states)]
    np.testing.assert_allclose(volumes, volumes[0], rtol=1e-13)
    assert all(np.min(state.q[0]) >= 0.0 for state in result.states)
    summary = json.loads((out / "hazard.json").read_text())
    assert summary["volume_final_m3"] == pytest.approx(summary["volume_initial_m3"], rel=1e-13)
    assert 25.0 <= summary["travel_angle_deg"] <= 35.0
    fields = {}
    for stem in ("peak_depth", "peak_speed", "peak_pressure", "deposit"):
        with rasterio.open(out / f"{stem}.tif") as dataset:
            assert dataset.crs is None
            assert dataset.transform == Affine(
                grid.dx, 0.0, grid.x.x_min, 0.0, -grid.dy, grid.y.x_max
            )
            fields[stem] = dataset.read(1, masked=True)[::-1]  # north-up in the file
        assert (out / f"{stem}.png").stat().st_size > 0
    assert result.peaks is not None
    reached = ~np.ma.getmaskarray(fields["peak_depth"])
    np.testing.assert_array_equal(reached, result.peaks.depth >= REACHED_DEPTH)  # no layer
    peak = fields["peak_depth"].compressed()
    np.testing.assert_array_equal(peak, result.peaks.depth[reached].astype(np.float32))
    cos = result.model.aux_2d(*np.meshgrid(*grid.centres()))[2]
    for state in (result.initial, *result.states):
        assert np.all(peak >= (cos * state.q[0])[reached].astype(np.float32))
    np.testing.assert_allclose(
        fields["peak_pressure"].compressed(),
        0.2 * fields["peak_speed"].compressed() ** 2,
        rtol=1e-6,
    )
    for stem in ("peak_speed", "peak_pressure"):
        np.testing.assert_array_equal(~np.ma.getmaskarray(fields[stem]), reached)
    assert np.all(result.peaks.speed[result.peaks.depth < REACHED_DEPTH] == 0.0)


def tilted_plane_dem(tmp_path: Path, angle: float) -> Path:
    """A 400 m x 200 m DEM of 10 m cells in UTM 32N descending at ``angle`` toward the east."""
    slope = math.tan(math.radians(angle))
    dem = dem_from_function(
        lambda x, y: 1000.0 - slope * (x - X0) + 0.0 * y,
        (X0, X0 + 400.0),
        (Y0, Y0 + 200.0),
        10.0,
        UTM,
    )
    return write_dem(dem, tmp_path / "slope.tif")


def dem_scene(tmp_path: Path, angle: float, earth_pressure: str, formats: str) -> Path:
    """A scene on ``slope.tif`` with a square release from a GeoJSON file in the DEM's CRS."""
    tilted_plane_dem(tmp_path, angle)
    square = [[X0 + 50, Y0 + 70], [X0 + 110, Y0 + 70], [X0 + 110, Y0 + 130], [X0 + 50, Y0 + 130]]
    release = {
        "type": "FeatureCollection",
        "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32632"}},
        "features": [
            {
                "type": "Feature",
                "properties": {},
                "geometry": {"type": "Polygon", "coordinates": [[*square, square[0]]]},
            }
        ],
    }
    (tmp_path / "release.geojson").write_text(json.dumps(release))
    scene = tmp_path / "scene.toml"
    scene.write_text(
        f"""model = "savage-hutter-terrain"
n_cells = [40, 20]
x_min = {X0}
x_max = {X0 + 400.0}
y_min = {Y0}
y_max = {Y0 + 200.0}
t_end = 6.0
output_times = [6.0]
exact = false

[parameters]
phi = 35.0
delta = 25.0
terrain = "dem"
dem_file = "slope.tif"
earth_pressure = "{earth_pressure}"

[boundary]
left = "outflow"
right = "outflow"
bottom = "outflow"
top = "outflow"

[initial]
kind = "release"
thickness = 2.0
release_file = "release.geojson"

[output]
formats = {formats}
"""
    )
    return scene


def test_a_scene_on_a_dem_file_writes_geotiffs_with_the_dems_transform_and_crs(
    tmp_path: Path,
) -> None:
    """A DEM file in UTM 32N with a release from a GeoJSON file next to the scene: the hazard
    GeoTIFFs carry the DEM's transform and CRS, and the release covers the 6 x 6 cells whose
    centres lie inside the square."""
    scene = dem_scene(tmp_path, 35.0, "savage-hutter", '["npz", "geotiff"]')
    result = conslaw.run_2d(scene, out=tmp_path / "run")
    assert np.count_nonzero(result.initial.q[0]) == 36
    with (
        rasterio.open(tmp_path / "slope.tif") as dem,
        rasterio.open(tmp_path / "run" / "peak_depth.tif") as peak,
    ):
        assert peak.crs == dem.crs and peak.crs.to_string() == UTM
        assert peak.transform == dem.transform
        assert peak.shape == dem.shape


def plane_runs(tmp_path: Path, earth_pressure: str) -> tuple[RunResult2D, RunResult2D]:
    """The scene of :func:`dem_scene` on the DEM file of a plane and on the formula plane."""
    scene = dem_scene(tmp_path, 35.0, earth_pressure, '["npz"]')
    on_dem = conslaw.run_2d(scene)
    on_plane = conslaw.run_2d(
        scene,
        parameters__terrain="plane",
        parameters__zeta=35.0,
        parameters__dem_file="",
        initial__release_file="",
        initial__polygon=[
            [X0 + 50, Y0 + 70], [X0 + 110, Y0 + 70], [X0 + 110, Y0 + 130], [X0 + 50, Y0 + 130]
        ],
    )  # fmt: skip
    return on_dem, on_plane


def test_a_dem_of_a_tilted_plane_gives_the_run_on_the_plane(tmp_path: Path) -> None:
    """The same scene on a DEM file of a plane and on the formula plane (``terrain =
    "plane"``), isotropic pressure: the spline through the DEM's cell centres is the plane to
    round-off (its coefficients within 1.5e-13), and the runs agree to 1e-11 of the largest
    value of each variable after 6 s (measured 3e-13); the formula plane is the chute model's
    plane to round-off (tests/test_savage_hutter_terrain.py)."""
    on_dem, on_plane = plane_runs(tmp_path, "isotropic")
    q_dem, q_plane = on_dem.states[-1].q, on_plane.states[-1].q
    for row in range(3):
        scale = np.max(np.abs(q_plane[row]))
        np.testing.assert_allclose(q_dem[row], q_plane[row], rtol=0, atol=1e-11 * scale)


def test_with_the_earth_pressure_switch_the_dem_plane_differs_by_the_switch(
    tmp_path: Path,
) -> None:
    """With the Savage–Hutter switch the same two runs differ by more than round-off: where the
    flow neither spreads nor contracts, the spline's 1e-13 in the slopes decides between
    ``K_act`` and ``K_pass`` (docs/design.md, "Earth pressure"). The centres of mass agree to
    5e-3 of the distance travelled along x (measured 1.9e-3) and to 0.05 m across (measured
    9e-3 m: the DEM's noise breaks the mirror symmetry that the formula plane keeps exactly)."""
    on_dem, on_plane = plane_runs(tmp_path, "savage-hutter")
    x, y = on_plane.grid.centres()
    start = on_plane.initial.q[0]
    x_start = float(np.sum(start.sum(axis=0) * x) / start.sum())
    centres = []
    for run in (on_dem, on_plane):
        depth = run.states[-1].q[0]
        centres.append(
            (
                float(np.sum(depth.sum(axis=0) * x) / depth.sum()),
                float(np.sum(depth.sum(axis=1) * y) / depth.sum()),
            )
        )
    (x_dem, y_dem), (x_plane, y_plane) = centres
    assert abs(x_dem - x_plane) <= 5e-3 * (x_plane - x_start)
    assert abs(y_dem - y_plane) <= 0.05


def test_the_sliding_point_stops_before_the_energy_line() -> None:
    """On the plane-to-flat profile the curvature friction only takes energy: a point released
    anywhere on the plane stops short of the classical energy line (by about 100 m: the
    ``kappa U^2`` friction of the 40-degree turn), on the run-out or on the arc where the slope
    is below delta; a point on a slope friction holds does not move."""
    surface = PlaneToFlat(40.0, 200.0, 700.0)
    mu = math.tan(math.radians(30.0))
    for x0 in (50.0, 150.0, 300.0, 500.0):
        stop = sliding_stop(surface, x0, mu, 9.81)
        line = energy_line_stop(surface, x0, mu)
        assert x0 < stop < line
        slope = -float(surface.derivatives(np.array([stop]), np.zeros(1))[1][0])
        assert slope <= mu + 1e-6
    assert sliding_stop(surface, 150.0, math.tan(math.radians(41.0)), 9.81) == 150.0


def test_a_thinner_release_stops_nearer_the_sliding_point() -> None:
    """The energy line on ``terrain-plane-to-flat`` (20 m cells, t = 90 s): the deposit's centre
    of mass lies within 3 m of where points sliding from the release stop with the curvature
    friction for a release 1 m thick, closer than for 4 m (the earth pressure's work falls with
    the aspect ratio; measured 0.6 m and 6.3 m, ``python scripts/energy_line.py --cells 50``),
    and about 100 m short of the classical energy line."""
    surface = PlaneToFlat(40.0, 200.0, 700.0)
    mu = math.tan(math.radians(30.0))
    starts = np.linspace(100.0, 200.0, 41)[:-1] + 1.25
    sliding = float(np.mean([sliding_stop(surface, x0, mu, 9.81) for x0 in starts]))
    line = float(np.mean([energy_line_stop(surface, x0, mu) for x0 in starts]))
    misfits = []
    for thickness in (1.0, 4.0):
        result = conslaw.run_2d(
            "terrain-plane-to-flat",
            n_cells=[50, 25],
            t_end=90.0,
            output_times=[90.0],
            initial__thickness=thickness,
        )
        x, _ = result.grid.centres()
        depth = result.states[-1].q[0]
        misfits.append(float(np.sum(depth.sum(axis=0) * x) / depth.sum()) - sliding)
    assert abs(misfits[0]) <= 3.0 and abs(misfits[0]) < abs(misfits[1])
    assert 90.0 <= line - sliding <= 110.0


def test_an_animation_of_the_flow_depth_on_request(tmp_path: Path) -> None:
    """``output.formats = [..., "gif"]``: ``flow_depth.gif``, one frame at the start and one
    per output time, all of one size; a model without terrain refuses the format."""
    from PIL import Image

    conslaw.run_2d(
        "terrain-bowl",
        out=tmp_path,
        n_cells=[20, 20],
        t_end=20.0,
        output_times=[10.0, 20.0],
        output__formats=["npz", "gif"],
    )
    with Image.open(tmp_path / "flow_depth.gif") as animation:
        assert animation.n_frames == 3
    with pytest.raises(conslaw.ConfigError, match=r"output\.formats: 'gif'"):
        conslaw.run_2d("sh2d-similarity", output__formats=["gif"])


def test_a_thin_layer_is_neither_release_nor_reach(tmp_path: Path) -> None:
    """A thin layer of 2 cm everywhere under the release: the run-out and travel angle are
    those of the release (within a cell and half a degree of the run without the layer), not
    of the whole domain."""
    angles = []
    for layer in (0.0, 0.02):
        result = conslaw.run_2d(
            "terrain-plane-to-flat",
            n_cells=[50, 25],
            output_times=[60.0],
            initial__thin_layer=layer,
        )
        maps = hazard_maps(result)
        assert maps is not None
        angles.append((maps.summary["travel_angle_deg"], maps.summary["runout_length_m"]))
    assert abs(angles[1][0] - angles[0][0]) <= 0.5
    assert abs(angles[1][1] - angles[0][1]) <= 20.0


def test_the_sliding_point_refuses_a_slope_it_never_leaves() -> None:
    """On a plane steeper than delta a point never stops, and the energy line never meets
    the profile: both say so instead of returning a place."""
    plane = PlaneToFlat(40.0, 200.0, 1e9)
    with pytest.raises(ValueError, match="does not stop"):
        sliding_stop(plane, 0.0, math.tan(math.radians(30.0)), 9.81, max_time=60.0)
    with pytest.raises(ValueError, match="does not meet the profile"):
        energy_line_stop(plane, 0.0, math.tan(math.radians(30.0)))
