"""DEMs: reading and writing (GeoTIFF, ESRI ASCII grid) bit for bit and the right way up, the
bad-input catalogue of DEM files, slopes, and the DEMs made from formulas."""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import rasterio
from affine import Affine
from hypothesis import given, settings, strategies as st
from rasterio.crs import CRS

from conslaw.errors import ConfigError
from conslaw.terrain import (
    DigitalElevationModel,
    bowl,
    bowl_radius,
    channelled_slope,
    dem_from_function,
    elevation_gradient,
    inclined_plane_to_flat,
    plane_to_flat_profile,
    read_dem,
    slope_angle,
    slope_cosine,
    write_dem,
)

UTM = "EPSG:32632"


def write_raster(
    path: Path,
    north_up: np.ndarray,
    transform: Affine | None = None,
    crs: str | None = UTM,
    nodata: float | None = None,
) -> Path:
    """A GeoTIFF written with plain rasterio: ``north_up`` is ``(bands, rows, columns)`` or
    ``(rows, columns)``, row 0 north."""
    values = north_up if north_up.ndim == 3 else north_up[np.newaxis]
    count, rows, columns = values.shape
    options = {} if transform is None else {"transform": transform}
    with warnings.catch_warnings(action="ignore"), rasterio.open(
        path, "w", driver="GTiff", width=columns, height=rows, count=count,
        dtype=values.dtype, crs=crs, nodata=nodata, **options,
    ) as dataset:  # fmt: skip
        dataset.write(values)
    return path


def ascii_grid(path: Path, north_up: np.ndarray, corner: tuple[float, float], cell: float) -> Path:
    """An ESRI ASCII grid of ``north_up`` (row 0 north), values in full precision."""
    rows, columns = north_up.shape
    header = f"ncols {columns}\nnrows {rows}\nxllcorner {corner[0]!r}\nyllcorner {corner[1]!r}\n"
    body = "\n".join(" ".join(repr(float(v)) for v in row) for row in north_up)
    path.write_text(header + f"cellsize {cell!r}\n" + body + "\n")
    return path


def sample_dem(crs: str | None = UTM) -> DigitalElevationModel:
    """A 6 x 7 DEM with irregular float64 elevations at a UTM-like place."""
    values = 1500.0 + np.random.default_rng(7).normal(0.0, 30.0, (6, 7))
    return DigitalElevationModel(values, 412345.5, 5123456.25, 2.5, crs)


# --- reading and writing ------------------------------------------------------------------------


@pytest.mark.parametrize("crs", [UTM, None])
def test_write_then_read_is_bit_for_bit(tmp_path: Path, crs: str | None) -> None:
    dem = sample_dem(crs)
    path = write_dem(dem, tmp_path / "dem.tif")
    back = read_dem(path)
    assert back.elevation.tobytes() == dem.elevation.tobytes()
    assert (back.x_min, back.y_min, back.cell_size, back.crs) == (
        dem.x_min, dem.y_min, dem.cell_size, dem.crs,
    )  # fmt: skip
    assert back.transform == dem.transform
    with rasterio.open(path) as dataset:
        assert dataset.transform == dem.transform
        assert dataset.dtypes == ("float64",)
        assert dataset.descriptions == ("elevation",)


def test_read_keeps_an_awkward_transform_bit_for_bit(tmp_path: Path) -> None:
    """A north edge that y_min + ny c does not reproduce from the naive y_min = top - ny c."""
    transform = Affine(0.1, 0.0, 0.1, 0.0, -0.1, 0.7)
    path = write_raster(tmp_path / "dem.tif", np.arange(42.0).reshape(7, 6), transform)
    dem = read_dem(path)
    assert dem.transform == transform
    back = read_dem(write_dem(dem, tmp_path / "again.tif"))
    assert back.transform == transform and back.y_min == dem.y_min


def test_ascii_grid_reads_as_the_geotiff(tmp_path: Path) -> None:
    dem = sample_dem()
    tif = write_dem(dem, tmp_path / "dem.tif")
    asc = ascii_grid(tmp_path / "dem.asc", dem.elevation[::-1], (dem.x_min, dem.y_min), 2.5)
    (tmp_path / "dem.prj").write_text(CRS.from_string(UTM).to_wkt())
    from_tif, from_asc = read_dem(tif), read_dem(asc)
    assert from_asc.elevation.tobytes() == from_tif.elevation.tobytes()
    assert from_asc.transform == from_tif.transform
    assert from_asc.crs == from_tif.crs == UTM


def test_orientation_z_equals_x_plus_2y(tmp_path: Path) -> None:
    """z = x + 2 y written and read: rises to the east (1) and to the north (2); the file
    holds the north row first."""
    dem = dem_from_function(lambda x, y: x + 2.0 * y, (100.0, 140.0), (200.0, 250.0), 5.0, UTM)
    path = write_dem(dem, tmp_path / "plane.tif")
    back = read_dem(path)
    dz_dx, dz_dy = elevation_gradient(back)
    np.testing.assert_allclose(dz_dx, 1.0, rtol=1e-12)
    np.testing.assert_allclose(dz_dy, 2.0, rtol=1e-12)
    x, y = back.centres()
    assert back.elevation[0, 0] == x[0] + 2.0 * y[0]  # south-west cell
    with rasterio.open(path) as dataset:
        first_row = dataset.read(1)[0]
    assert first_row[0] == x[0] + 2.0 * y[-1]  # the file's first row is the north one


@pytest.mark.parametrize("flip", ["south-up", "east-to-west"])
def test_flipped_files_are_read_into_place(tmp_path: Path, flip: str) -> None:
    dem = sample_dem()
    north_up = dem.elevation[::-1]
    if flip == "south-up":
        values = dem.elevation
        transform = Affine(2.5, 0.0, dem.x_min, 0.0, 2.5, dem.y_min)
    else:
        values = north_up[:, ::-1]
        transform = Affine(-2.5, 0.0, dem.x_max, 0.0, -2.5, dem.y_max)
    back = read_dem(write_raster(tmp_path / "dem.tif", np.ascontiguousarray(values), transform))
    assert np.array_equal(back.elevation, dem.elevation)
    assert (back.x_min, back.y_min) == (dem.x_min, dem.y_min)


def test_properties_and_grid() -> None:
    dem = sample_dem()
    assert (dem.ny, dem.nx, dem.shape) == (6, 7, (6, 7))
    assert dem.x_max == 412345.5 + 7 * 2.5 and dem.y_max == 5123456.25 + 6 * 2.5
    x, y = dem.centres()
    grid_x, grid_y = dem.grid.centres()
    np.testing.assert_allclose(grid_x, x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(grid_y, y, rtol=0, atol=1e-9)
    assert dem.grid.shape == dem.shape
    assert dem.transform == Affine(2.5, 0.0, dem.x_min, 0.0, -2.5, dem.y_max)


def test_the_dem_is_immutable_and_owns_its_elevations() -> None:
    values = np.zeros((4, 5))
    dem = DigitalElevationModel(values, 0.0, 0.0, 1.0)
    values[0, 0] = 9.0
    assert dem.elevation[0, 0] == 0.0
    with pytest.raises(ValueError, match="read-only"):
        dem.elevation[0, 0] = 1.0


def test_dem_from_function_samples_cell_centres() -> None:
    dem = dem_from_function(lambda x, y: 10.0 * x - y, (0.0, 8.0), (-2.0, 6.0), 2.0, "epsg:32632")
    assert dem.shape == (4, 4)
    assert dem.elevation[0, 0] == 10.0 * 1.0 - (-1.0)
    assert dem.crs == UTM  # normalised by rasterio
    flat = dem_from_function(lambda x, y: 5.0, (0.0, 8.0), (0.0, 8.0), 2.0)
    assert np.all(flat.elevation == 5.0)


@pytest.mark.parametrize(
    ("call", "cause"),
    [
        (lambda: dem_from_function(lambda x, y: x, (0.0, 9.0), (0.0, 8.0), 2.0), "whole number"),
        (lambda: dem_from_function(lambda x, y: x, (0.0, 8.0), (0.0, 8.0), 0.0), "cell_size"),
        (lambda: dem_from_function(lambda x, y: x[:2], (0.0, 8.0), (0.0, 8.0), 2.0), "shape"),
        (lambda: dem_from_function(lambda x, y: x / 0.0, (0.0, 8.0), (0.0, 8.0), 2.0), "NaN"),
        (lambda: dem_from_function(lambda x, y: x, (0.0, 8.0), (0.0, 8.0), 2.0, "x"), "parsed"),
        (lambda: DigitalElevationModel(np.zeros(16), 0.0, 0.0, 1.0), "2D array"),
        (lambda: DigitalElevationModel(np.zeros((4, 4)), math.nan, 0.0, 1.0), "x_min"),
        (lambda: DigitalElevationModel(np.zeros((4, 4)), 0.0, 0.0, -1.0), "cell_size"),
        (lambda: DigitalElevationModel(np.zeros((4, 4)), 0, 0, 1, "EPSG:4326"), "geographic"),
    ],
)
def test_constructors_refuse_bad_values(call: Callable[[], object], cause: str) -> None:
    with np.errstate(divide="ignore", invalid="ignore"), pytest.raises(ConfigError) as info:
        call()
    assert cause in str(info.value) and "\n" not in str(info.value)


# --- the bad-input catalogue of DEM files -----------------------------------------------------

PLANE = np.add.outer(np.arange(6.0), np.arange(5.0)) * 10.0  # 6 rows x 5 columns
NORTH_UP = Affine(10.0, 0.0, 500000.0, 0.0, -10.0, 5000060.0)
HEADER = "ncols 5\nnrows 6\nxllcorner 500000\nyllcorner 5000000\ncellsize 10\n"
ROWS = "".join("1 2 3 4 5\n" for _ in range(6))


def _with(values: np.ndarray, **changes: object) -> Callable[[Path], Path]:
    def build(path: Path) -> Path:
        options: dict[str, object] = {"transform": NORTH_UP} | changes
        return write_raster(path, values, **options)  # type: ignore[arg-type]

    return build


def _text(text: str | bytes) -> Callable[[Path], Path]:
    def build(path: Path) -> Path:
        path.write_bytes(text if isinstance(text, bytes) else text.encode())
        return path

    return build


def _truncated_geotiff(path: Path) -> Path:
    whole = write_raster(path, PLANE, NORTH_UP).read_bytes()
    path.write_bytes(whole[: len(whole) // 3])
    return path


def _folder(path: Path) -> Path:
    path.mkdir()
    return path


def _no_data(path: Path) -> Path:
    values = PLANE.copy()
    values[0, 0] = values[2, 3] = values[5, 4] = -9999.0
    return write_raster(path, values, NORTH_UP, nodata=-9999.0)


def _with_value(value: float) -> Callable[[Path], Path]:
    def build(path: Path) -> Path:
        values = PLANE.copy()
        values[1, 2] = value
        return write_raster(path, values, NORTH_UP)

    return build


DEM_CASES: list[tuple[str, str, Callable[[Path], Path], str]] = [
    ("missing", "dem.tif", lambda path: path, "file not found"),
    ("folder", "dem.tif", _folder, "not a file"),
    ("text named tif", "dem.tif", _text("elevations: 1 2 3\n"), "cannot be read as a GeoTIFF"),
    ("truncated tif", "dem.tif", _truncated_geotiff, "cannot be read as a GeoTIFF"),
    ("empty tif", "dem.tif", _text(b""), "cannot be read as a GeoTIFF"),
    ("unsupported suffix", "dem.png", _text(b"\x89PNG"), "unsupported file type '.png'"),
    ("asc bad header", "dem.asc", _text("ncols five\nnrows 6\n" + ROWS), "cannot be read as an"),
    ("asc truncated", "dem.asc", _text(HEADER + ROWS[:30]), "File short"),
    ("asc empty", "dem.asc", _text(""), "cannot be read as an ESRI ASCII grid"),
    ("asc not a number", "dem.asc", _text(HEADER + ROWS[:-2] + "x5\n"), "'x5' (row 6, column 5"),
    ("asc decimal comma", "dem.asc", _text(HEADER + "1,5" + ROWS[1:]), "'1,5'"),
    ("asc dx dy", "dem.asc", _text(HEADER.replace("cellsize 10", "dx 10\ndy 20") + ROWS), "square"),
    ("asc no-data", "dem.asc", _text(HEADER + "NODATA_value -1\n" + ROWS[:-2] + "-1\n"), "1 no-da"),
    ("asc nan", "dem.asc", _text(HEADER + "nan" + ROWS[1:]), "1 NaN or infinite elevation,"),
    ("two bands", "dem.tif", _with(np.stack([PLANE, PLANE])), "has 2 bands"),
    ("rotated", "dem.tif", _with(PLANE, transform=NORTH_UP @ Affine.rotation(10)), "rotated"),
    ("sheared", "dem.tif", _with(PLANE, transform=NORTH_UP @ Affine.shear(5)), "sheared"),
    ("non-square", "dem.tif", _with(PLANE, transform=Affine.scale(1, 2) @ NORTH_UP), "not square"),
    ("no-data", "dem.tif", _no_data, "3 no-data cells (value -9999)"),
    ("nan", "dem.tif", _with_value(math.nan), "1 NaN or infinite elevation"),
    ("inf", "dem.tif", _with_value(-math.inf), "1 NaN or infinite elevation"),
    ("3 x 3", "dem.tif", _with(PLANE[:3, :3]), "3 x 3 cells"),
    ("one row", "dem.tif", _with(PLANE[:1]), "1 x 5 cells"),
    ("geographic", "dem.tif", _with(PLANE, crs="EPSG:4326"), "geographic (degrees)"),
    ("feet", "dem.tif", _with(PLANE, crs="EPSG:2227"), "unit 'US survey foot'"),
    ("no georeferencing", "dem.tif", _with(PLANE, transform=None), "not georeferenced"),
]


@pytest.mark.parametrize(
    ("name", "build", "cause"),
    [case[1:] for case in DEM_CASES],
    ids=[case[0] for case in DEM_CASES],
)
def test_bad_dem_file_is_refused_in_one_line(
    tmp_path: Path, name: str, build: Callable[[Path], Path], cause: str
) -> None:
    path = build(tmp_path / name)
    with pytest.raises(ConfigError) as info:
        read_dem(path)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"DEM file '{path}': ")
    assert cause in message


def refusal(path: Path) -> str:
    """The message of the ConfigError that reading ``path`` raises."""
    with pytest.raises(ConfigError) as info:
        read_dem(path)
    return str(info.value)


def test_no_data_and_bad_values_are_located_in_map_coordinates(tmp_path: Path) -> None:
    """The first no-data cell from the south-west: file row 5 (the south row), column 4."""
    message = refusal(_no_data(tmp_path / "dem.tif"))
    assert "the first (from the south-west) at x=500045, y=5000005" in message
    message = refusal(_with_value(math.inf)(tmp_path / "inf.tif"))  # file row 1, column 2
    assert "at x=500025, y=5000045" in message
    message = refusal(_text(HEADER + ROWS[:-2] + "x5\n")(tmp_path / "bad.asc"))
    assert "at x=500045, y=5000005" in message


def test_label_names_the_scene_key(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=r"^terrain\.dem '.*nowhere\.tif': file not found$"):
        read_dem(tmp_path / "nowhere.tif", label="terrain.dem")


# --- slopes ---------------------------------------------------------------------------------


@settings(deadline=None, max_examples=60)
@given(
    angle=st.floats(0.0, 80.0),
    azimuth=st.floats(0.0, 360.0),
    cell=st.floats(0.5, 20.0),
    origin=st.tuples(st.floats(-100.0, 100.0), st.floats(-100.0, 100.0)),
)
def test_slope_of_a_tilted_plane(
    angle: float, azimuth: float, cell: float, origin: tuple[float, float]
) -> None:
    """On a plane of slope angle theta (any aspect) every cell, the edges included, has
    cos(theta) and theta."""
    tangent = math.tan(math.radians(angle))
    a, b = tangent * math.sin(math.radians(azimuth)), tangent * math.cos(math.radians(azimuth))
    dem = DigitalElevationModel(np.zeros((5, 6)), origin[0], origin[1], cell)
    x, y = np.meshgrid(*dem.centres())
    dem = DigitalElevationModel(a * x + b * y, origin[0], origin[1], cell)
    np.testing.assert_allclose(slope_cosine(dem), math.cos(math.radians(angle)), rtol=1e-11)
    np.testing.assert_allclose(slope_angle(dem), angle, rtol=0, atol=1e-8)


# --- DEMs from formulas -----------------------------------------------------------------------


def test_inclined_plane_to_flat_has_its_slope_angles() -> None:
    dem = inclined_plane_to_flat(cell_size=25.0)  # 1000 m x 500 m: 40 x 20 cells
    start = 1000.0 - 300.0 - 200.0 * math.sin(math.radians(40.0))
    x, _ = dem.centres()
    angles = slope_angle(dem)
    on_plane = x < start - 2 * 25.0  # the differences reach one cell either side
    on_flat = x > 700.0 + 2 * 25.0
    np.testing.assert_allclose(angles[:, on_plane], 40.0, rtol=1e-12)
    assert np.all(angles[:, on_flat] == 0.0) and np.all(dem.elevation[:, on_flat] == 0.0)
    arc = (x > start) & (x < 700.0)
    _, slope = plane_to_flat_profile(
        x[arc], slope_angle=40.0, transition_radius=200.0, transition_end=700.0
    )
    np.testing.assert_allclose(angles[0, arc], np.degrees(np.arctan(-slope)), atol=0.5)
    assert np.all(np.diff(dem.elevation, axis=1) <= 0.0)  # downhill all the way
    assert np.all(dem.elevation == dem.elevation[:1])  # uniform across y


@pytest.mark.parametrize(("angle", "radius"), [(40.0, 200.0), (30.0, 50.0), (60.0, 1.0)])
def test_profile_is_c1_at_both_ends_of_the_arc(angle: float, radius: float) -> None:
    end = 700.0
    start = end - radius * math.sin(math.radians(angle))
    for joint in (start, end):
        x = np.array([joint - 1e-7, joint, joint + 1e-7])
        z, slope = plane_to_flat_profile(
            x, slope_angle=angle, transition_radius=radius, transition_end=end
        )
        assert abs(z[2] - z[0]) < 3e-7 * math.tan(math.radians(angle)) + 1e-9
        assert abs(slope[2] - slope[0]) < 1e-5 * (1.0 + 1.0 / radius)
    z, slope = plane_to_flat_profile(
        np.array([0.0, end + 5.0]), slope_angle=angle, transition_radius=radius, transition_end=end
    )
    assert slope[0] == -math.tan(math.radians(angle)) and slope[1] == 0.0 and z[1] == 0.0
    assert z[0] == pytest.approx(
        start * math.tan(math.radians(angle)) + radius * (1.0 - math.cos(math.radians(angle)))
    )


def test_channelled_slope_cross_slope_and_run_out() -> None:
    dem = channelled_slope(cell_size=10.0, channel_depth=15.0, channel_half_width=50.0)
    x, y = dem.centres()
    start = 1000.0 - 300.0 - 200.0 * math.sin(math.radians(40.0))
    assert np.array_equal(dem.elevation, dem.elevation[::-1])  # symmetric about y = 0
    assert np.all(dem.elevation[:, x > 700.0] == 0.0)  # the channel has faded out
    plain = inclined_plane_to_flat(cell_size=10.0)
    on_plane = x < start - 50.0
    depth = plain.elevation[:, on_plane] - dem.elevation[:, on_plane]
    expected = np.broadcast_to(15.0 * np.exp(-((y[:, None] / 50.0) ** 2)), depth.shape)
    np.testing.assert_allclose(depth, expected, rtol=0, atol=1e-9)
    _, dz_dy = elevation_gradient(dem)
    exact = 2.0 * 15.0 * y / 50.0**2 * np.exp(-((y / 50.0) ** 2))
    # Second-order differences: error below (c^2/6) max|z_yyy| = (100/6) 3.3 D/b^3 = 0.007.
    np.testing.assert_allclose(dz_dy[:, 0], exact, rtol=0, atol=0.01)


def test_bowl_slope_is_the_formula_everywhere() -> None:
    dem = bowl(size=400.0, cell_size=20.0, max_slope_angle=35.0)
    radius = bowl_radius(400.0, 35.0)
    x, y = np.meshgrid(*dem.centres())
    expected = np.degrees(np.arctan(np.hypot(x, y) / radius))
    np.testing.assert_allclose(slope_angle(dem), expected, rtol=0, atol=1e-9)
    assert slope_angle(dem).max() < 35.0
    corner = math.degrees(math.atan(math.hypot(190.0, 190.0) / radius))
    assert slope_angle(dem)[0, 0] == pytest.approx(corner, abs=1e-9)
    assert dem.elevation.min() == pytest.approx(2 * 10.0**2 / (2 * radius))


@pytest.mark.parametrize(
    ("call", "cause"),
    [
        (lambda: inclined_plane_to_flat(slope_angle=90.0), "slope_angle must be in (0, 90)"),
        (lambda: inclined_plane_to_flat(length=300.0), "leaves no inclined plane"),
        (lambda: inclined_plane_to_flat(transition_radius=0.0), "transition_radius"),
        (lambda: channelled_slope(channel_half_width=-1.0), "channel_half_width"),
        (lambda: bowl(max_slope_angle=0.0), "max_slope_angle"),
        (lambda: bowl(size=1003.0), "whole number"),
    ],
)
def test_generated_dems_refuse_bad_parameters(call: Callable[[], object], cause: str) -> None:
    with pytest.raises(ConfigError) as info:
        call()
    assert cause in str(info.value) and "\n" not in str(info.value)


@settings(max_examples=25, deadline=None)
@given(
    ratio=st.floats(1.2, 6.0),
    shift=st.tuples(st.floats(0.0, 1.0), st.floats(0.0, 1.0)),
    gradient=st.tuples(st.floats(-2.0, 2.0), st.floats(-2.0, 2.0)),
)
def test_averaging_onto_coarser_cells_keeps_a_plane_exactly(
    ratio: float, shift: tuple[float, float], gradient: tuple[float, float]
) -> None:
    """A plane averaged over the cells of any coarser grid, shifted against the DEM's cells by
    any fraction of a cell, is the plane's value at their centres (the means of a linear
    function), to round-off of the elevations."""
    from conslaw.grid2d import Grid2D
    from conslaw_models.terrain_surface import GriddedSurface

    dem = dem_from_function(
        lambda x, y: 1500.0 + gradient[0] * x + gradient[1] * y, (0.0, 500.0), (0.0, 300.0), 5.0
    )
    cell = 5.0 * ratio
    nx, ny = int(400.0 // cell), int(250.0 // cell)
    x0, y0 = 10.0 + 5.0 * shift[0], 10.0 + 5.0 * shift[1]
    grid = Grid2D.from_bounds(x0, x0 + nx * cell, nx, y0, y0 + ny * cell, ny)
    surface = GriddedSurface.from_dem(dem, 0.0, grid)
    x, y = grid.centres()
    plane = 1500.0 + gradient[0] * x[None, :] + gradient[1] * y[:, None]
    np.testing.assert_array_equal(surface.x_centres, x)
    np.testing.assert_array_equal(surface.y_centres, y)
    np.testing.assert_allclose(surface.elevation, plane, rtol=0, atol=1e-9)


def test_a_terrain_model_reads_a_finer_dem_at_its_grid(tmp_path: Path) -> None:
    """On a grid of the DEM's own cells the terrain model is itself; on coarser cells a copy
    whose surface passes through the means of the DEM's spline over the grid's cells (checked
    against scipy's own integral of the spline, cell by cell), so a 30 m step between two 5 m
    cells reads as a slope of the order of the drop over a 20 m cell, not over a 5 m one."""
    from conslaw.grid2d import Grid2D
    from conslaw_models.savage_hutter_terrain import SavageHutterTerrain

    step = dem_from_function(
        lambda x, y: np.where(x < 200.0, 30.0, 0.0) + 0.0 * y, (0, 400), (0, 200), 5.0
    )
    model = SavageHutterTerrain(terrain="dem", dem_file=str(write_dem(step, tmp_path / "s.tif")))
    same = Grid2D.from_bounds(0.0, 400.0, 80, 0.0, 200.0, 40)
    assert model.on_grid_2d(same) is model
    coarse = Grid2D.from_bounds(0.0, 400.0, 20, 0.0, 200.0, 10)
    resolved = model.on_grid_2d(coarse)
    assert resolved is not model and resolved.surface is not model.surface
    x, y = coarse.centres()
    z = resolved.surface.derivatives(x[None, :], y[:, None])[0]
    spline = model.surface._spline  # rows y, columns x
    edges_x, edges_y = coarse.x.edges, coarse.y.edges
    for k, j in ((0, 0), (4, 9), (4, 10), (9, 19)):
        area = 400.0
        mean = spline.integral(edges_y[k], edges_y[k + 1], edges_x[j], edges_x[j + 1]) / area
        assert z[k, j] == pytest.approx(mean, abs=1e-9)
    at_step = (np.array([200.0]), np.array([100.0]))
    coarse_slope = abs(float(resolved.surface.derivatives(*at_step)[1][0]))
    fine_slope = abs(float(model.surface.derivatives(*at_step)[1][0]))
    assert 30.0 / 20.0 < coarse_slope < 2.0 * 30.0 / 20.0 < 30.0 / 5.0 < fine_slope
