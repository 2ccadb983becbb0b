"""Hazard-map outputs: GeoTIFFs of fields on a DEM (north-up, atomic) and the map figure."""

from __future__ import annotations

import errno
import io
import math
import os
from pathlib import Path

import numpy as np
import pytest
import rasterio
from hypothesis import given, settings, strategies as st
from matplotlib.contour import ContourSet
from matplotlib.figure import Figure

from conslaw.errors import ConfigError, OutputError
from conslaw.terrain import (
    DigitalElevationModel,
    dem_from_function,
    hazard_map_figure,
    hillshade,
    nice_contour_interval,
    write_dem,
    write_field_geotiff,
)
from conslaw.terrain.hazard_figure import contour_levels

UTM = "EPSG:32632"
ROOT = Path(__file__).resolve().parents[1]


def small_dem(crs: str | None = UTM) -> DigitalElevationModel:
    """8 x 10 cells of 10 m: a slope falling to the east, 200 m to 110 m."""
    return dem_from_function(
        lambda x, y: 200.0 - (x - 600000.0) * 0.9 + 0.0 * y,
        (600000.0, 600100.0), (4800000.0, 4800080.0), 10.0, crs,
    )  # fmt: skip


# --- GeoTIFFs ---------------------------------------------------------------------------------


def test_field_geotiff_is_north_up_with_the_dem_transform_and_crs(tmp_path: Path) -> None:
    """The field y: the file's first row holds the largest y (the north)."""
    dem = small_dem()
    _, y = np.meshgrid(*dem.centres())
    path = write_field_geotiff(dem, y, tmp_path / "northing.tif", name="northing", units="m")
    with rasterio.open(path) as dataset:
        values = dataset.read(1)
        assert dataset.transform == dem.transform
        assert dataset.crs.to_string() == UTM
        assert dataset.dtypes == ("float64",)
        assert dataset.descriptions == ("northing",)
        assert dataset.units == ("m",)
        assert dataset.tags(1)["name"] == "northing" and dataset.tags(1)["units"] == "m"
        assert dataset.nodata is None
        north_y = dataset.xy(0, 0)[1]
    assert np.all(values[0] == y[-1]) and np.all(values[-1] == y[0])
    assert np.all(values[0] > values[-1])
    assert north_y == y[-1, 0]  # rasterio's own centre of row 0 is the north row


@pytest.mark.parametrize("dtype", [np.float32, np.float64, np.int16, np.bool_])
def test_field_values_come_back_bit_for_bit(tmp_path: Path, dtype: type) -> None:
    dem = small_dem()
    field = (np.random.default_rng(3).random(dem.shape) * 50).astype(dtype)
    path = write_field_geotiff(dem, field, tmp_path / "f.tif", name="f", units="1", nodata=-1.0)
    with rasterio.open(path) as dataset:
        back = dataset.read(1)[::-1]
        assert dataset.nodata == -1.0
    assert back.dtype == (np.float32 if dtype is np.float32 else np.float64)
    assert np.array_equal(back, field.astype(back.dtype))


def test_a_write_into_a_missing_folder_fails_in_one_line(tmp_path: Path) -> None:
    path = tmp_path / "no such folder" / "peak.tif"
    with pytest.raises(OutputError) as info:
        write_field_geotiff(small_dem(), np.zeros((8, 10)), path, name="h", units="m")
    message = str(info.value)
    assert "\n" not in message and str(path) in message and "No such file or directory" in message
    assert not path.exists()


@pytest.mark.parametrize("writer", ["field", "dem"])
def test_a_failing_write_leaves_no_file_under_the_final_name(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, writer: str
) -> None:
    """A full disk at the rename: no new file, an old one untouched, no temporary left."""

    def full_disk(source: object, destination: object) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    dem = small_dem()
    new, old = tmp_path / "new.tif", tmp_path / "old.tif"
    old.write_bytes(b"the previous map")
    monkeypatch.setattr(os, "replace", full_disk)
    for path in (new, old):
        with pytest.raises(OutputError, match="No space left on device") as info:
            if writer == "field":
                write_field_geotiff(dem, dem.elevation, path, name="z", units="m")
            else:
                write_dem(dem, path)
        assert "\n" not in str(info.value) and path.name in str(info.value)
    monkeypatch.undo()
    assert not new.exists()
    assert old.read_bytes() == b"the previous map"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.tif"]


@pytest.mark.parametrize(
    ("field", "name", "cause"),
    [
        (np.zeros((10, 8)), "peak.tif", "field 'h' has shape (10, 8), the DEM (8, 10)"),
        (np.zeros((8, 10), dtype=complex), "peak.tif", "is not numeric"),
        (np.zeros((8, 10)), "peak.png", "a GeoTIFF must be named .tif or .tiff, got '.png'"),
    ],
)
def test_field_geotiff_refuses_bad_fields(
    tmp_path: Path, field: np.ndarray, name: str, cause: str
) -> None:
    with pytest.raises(ConfigError) as info:
        write_field_geotiff(small_dem(), field, tmp_path / name, name="h", units="m")
    assert cause in str(info.value) and "\n" not in str(info.value)
    assert list(tmp_path.iterdir()) == []


# --- hillshade and contours -------------------------------------------------------------------


def test_hillshade_lights_slopes_facing_the_north_west() -> None:
    towards_north_west = dem_from_function(lambda x, y: x - y, (0, 50), (0, 50), 5.0)
    towards_south_east = dem_from_function(lambda x, y: y - x, (0, 50), (0, 50), 5.0)
    flat = dem_from_function(lambda x, y: 0.0 * x, (0, 50), (0, 50), 5.0)
    bright, dark = hillshade(towards_north_west), hillshade(towards_south_east)
    # n = (-1, 1, 1)/sqrt 3 and s = (-1/2, 1/2, 1/sqrt 2) (azimuth 315, altitude 45).
    np.testing.assert_allclose(bright, (1.0 + 1.0 / math.sqrt(2.0)) / math.sqrt(3.0), rtol=1e-12)
    np.testing.assert_allclose(dark, 0.0, atol=1e-12)  # n.s < 0: in shadow, clipped
    np.testing.assert_allclose(hillshade(flat), math.sin(math.radians(45.0)), rtol=1e-12)


@settings(deadline=None, max_examples=200)
@given(low=st.floats(-5000.0, 5000.0), span=st.floats(1e-3, 1e4))
def test_automatic_contour_interval_gives_10_to_20_lines(low: float, span: float) -> None:
    interval = nice_contour_interval(low, low + span)
    assert interval is not None
    assert 10 <= contour_levels(low, low + span, interval).size <= 20
    mantissa = interval / 10.0 ** math.floor(math.log10(interval))
    assert min(abs(mantissa - nice) for nice in (1.0, 2.0, 2.5, 4.0, 5.0)) < 1e-9


def test_flat_dem_has_no_contour_interval() -> None:
    assert nice_contour_interval(3.0, 3.0) is None


# --- the figure -------------------------------------------------------------------------------


def contour_sets(figure: Figure) -> list[ContourSet]:
    return [c for c in figure.axes[0].collections if isinstance(c, ContourSet)]


def test_hazard_map_figure(tmp_path: Path) -> None:
    dem = small_dem()
    field = np.zeros(dem.shape)
    field[2:6, 3:8] = np.linspace(0.5, 2.0, 5)
    release = np.zeros(dem.shape, dtype=bool)
    release[3:5, 0:2] = True
    figure = hazard_map_figure(dem, field, label="peak flow depth (m)", release_mask=release)
    assert isinstance(figure, Figure)
    axes, colourbar = figure.axes
    assert (axes.get_xlabel(), axes.get_ylabel()) == ("easting (m)", "northing (m)")
    assert axes.get_aspect() == 1.0
    assert colourbar.get_ylabel() == "peak flow depth (m)"
    assert axes.get_xlim() == (dem.x_min, dem.x_max) and axes.get_ylim() == (dem.y_min, dem.y_max)
    elevation, outline = contour_sets(figure)
    assert 10 <= len(elevation.levels) <= 20
    assert list(outline.levels) == [0.5]
    assert [t.get_text() for t in axes.get_legend().get_texts()] == ["release area"]
    shown = axes.images[1].get_array()
    assert np.array_equal(np.ma.getmaskarray(shown), field == 0.0)  # zero cells transparent
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=50)
    assert buffer.getvalue().startswith(b"\x89PNG")


def test_hazard_map_without_crs_interval_and_threshold() -> None:
    dem = small_dem(crs=None)
    field = np.linspace(0.0, 1.0, dem.nx * dem.ny).reshape(dem.shape)
    figure = hazard_map_figure(dem, field, label="h (m)", contour_interval=25.0, threshold=0.5)
    axes = figure.axes[0]
    assert (axes.get_xlabel(), axes.get_ylabel()) == ("x (m)", "y (m)")
    (elevation,) = contour_sets(figure)  # no release outline
    assert list(elevation.levels) == [125.0, 150.0, 175.0]
    assert np.array_equal(np.ma.getmaskarray(axes.images[1].get_array()), field <= 0.5)
    empty = hazard_map_figure(dem, np.zeros(dem.shape), label="h (m)")  # nothing to colour
    assert np.ma.getmaskarray(empty.axes[0].images[1].get_array()).all()


@pytest.mark.parametrize(
    ("field", "options", "cause"),
    [
        (np.zeros((3, 3)), {}, "field must be a numeric array of the DEM's shape (8, 10)"),
        (np.zeros((8, 10)), {"release_mask": np.ones(3)}, "release_mask must be a numeric"),
        (np.zeros((8, 10)), {"contour_interval": 0.0}, "contour_interval must be > 0 m"),
    ],
)
def test_hazard_map_refuses_bad_arguments(
    field: np.ndarray, options: dict[str, object], cause: str
) -> None:
    with pytest.raises(ConfigError) as info:
        hazard_map_figure(small_dem(), field, label="h (m)", **options)  # type: ignore[arg-type]
    assert cause in str(info.value) and "\n" not in str(info.value)


def test_terrain_leaves_the_matplotlib_backend_alone() -> None:
    """No pyplot and no matplotlib.use: the package is used in servers and notebooks alike."""
    for path in (ROOT / "conslaw" / "terrain").glob("*.py"):
        text = path.read_text()
        for banned in ("matplotlib.pyplot", "from matplotlib import pyplot", "matplotlib.use("):
            assert banned not in text, (path.name, banned)
