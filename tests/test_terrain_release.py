"""Release areas (polygons and raster masks) on a DEM, the slope-normal release thickness, and
the bad-input catalogue of release files."""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pyogrio.raw
import pytest
import rasterio
import shapely
from affine import Affine
from hypothesis import given, settings, strategies as st

from conslaw.errors import ConfigError
from conslaw.terrain import (
    DigitalElevationModel,
    release_mask,
    release_thickness,
    slope_cosine,
    write_field_geotiff,
)

UTM = "EPSG:32632"
X0, Y0, CELL = 500000.0, 5000000.0, 10.0  # 12 columns x 10 rows of 10 m cells


def make_dem(crs: str | None = UTM) -> DigitalElevationModel:
    """A 10 x 12 DEM of 10 m cells, a plane falling to the east."""
    x = X0 + (np.arange(12) + 0.5) * CELL
    return DigitalElevationModel(np.tile(2000.0 - 0.5 * (x - X0), (10, 1)), X0, Y0, CELL, crs)


def box(x0: float, y0: float, x1: float, y1: float) -> shapely.Geometry:
    """A rectangle in metres from the DEM's south-west corner."""
    return shapely.box(X0 + x0, Y0 + y0, X0 + x1, Y0 + y1)


#: Faces at x = 20..60 and y = 30..70: the centres of columns 2..5 and rows 3..6 inside.
RECTANGLE = box(20.0, 30.0, 60.0, 70.0)


def expected_rectangle_mask() -> np.ndarray:
    mask = np.zeros((10, 12), dtype=bool)
    mask[3:7, 2:6] = True
    return mask


def geojson_text(geometries: list[Any], crs: str | None = UTM) -> str:
    """A FeatureCollection of ``geometries`` (shapely geometries, GeoJSON dicts or None), with
    the old-style ``crs`` member unless ``crs`` is None."""
    features = [
        {
            "type": "Feature",
            "properties": {},
            "geometry": json.loads(shapely.to_geojson(g)) if isinstance(g, shapely.Geometry) else g,
        }
        for g in geometries
    ]
    document: dict[str, Any] = {"type": "FeatureCollection", "features": features}
    if crs is not None:
        code = crs.split(":")[1]
        document["crs"] = {"type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{code}"}}
    return json.dumps(document)


def write_vector(
    path: Path, geometries: list[shapely.Geometry], crs: str | None = UTM, layer: str | None = None
) -> Path:
    """A shapefile or GeoPackage through pyogrio (a GeoJSON through :func:`geojson_text`)."""
    if path.suffix == ".geojson":
        path.write_text(geojson_text(geometries, crs))
        return path
    driver = {".shp": "ESRI Shapefile", ".gpkg": "GPKG"}[path.suffix]
    wkb = np.array([shapely.to_wkb(g) for g in geometries], dtype=object)
    kind = geometries[0].geom_type
    with warnings.catch_warnings(action="ignore"):  # "'crs' was not provided"
        pyogrio.raw.write(
            path, wkb, [], [], layer=layer, driver=driver, geometry_type=kind, crs=crs
        )
    return path


def write_mask(path: Path, north_up: np.ndarray, transform: Affine, crs: str | None = UTM) -> Path:
    """A raster mask written with plain rasterio (``(bands, rows, columns)`` or 2D)."""
    values = north_up if north_up.ndim == 3 else north_up[np.newaxis]
    with rasterio.open(
        path, "w", driver="GTiff", width=values.shape[2], height=values.shape[1],
        count=values.shape[0], dtype="float64", crs=crs, transform=transform,
    ) as dataset:  # fmt: skip
        dataset.write(values)
    return path


DEM_TRANSFORM = Affine(CELL, 0.0, X0, 0.0, -CELL, Y0 + 10 * CELL)


# --- masks ------------------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", [".geojson", ".shp", ".gpkg"])
def test_rectangle_covers_exactly_the_cell_centres_inside(tmp_path: Path, suffix: str) -> None:
    path = write_vector(tmp_path / f"release{suffix}", [RECTANGLE])
    mask = release_mask(make_dem(), path)
    assert mask.dtype == np.bool_ and mask.shape == (10, 12)
    assert np.array_equal(mask, expected_rectangle_mask())


def test_union_of_features_multipolygons_and_holes(tmp_path: Path) -> None:
    """Two overlapping rectangles, a MultiPolygon and a hole: the union, less the hole."""
    left = box(0.0, 0.0, 30.0, 30.0)
    overlapping = box(20.0, 0.0, 40.0, 20.0)
    multi = shapely.MultiPolygon([box(100.0, 80.0, 120.0, 100.0), box(60.0, 80.0, 70.0, 90.0)])
    ring = shapely.Polygon(
        box(50.0, 20.0, 90.0, 60.0).exterior.coords, [box(60.0, 30.0, 80.0, 50.0).exterior.coords]
    )
    path = write_vector(tmp_path / "release.geojson", [left, overlapping, multi, ring])
    mask = release_mask(make_dem(), path)
    expected = np.zeros((10, 12), dtype=bool)
    expected[0:3, 0:3] = True  # left
    expected[0:2, 2:4] = True  # overlapping
    expected[8:10, 10:12] = True  # first part of the MultiPolygon
    expected[8, 6] = True  # second part
    expected[2:6, 5:9] = True  # the ring ...
    expected[3:5, 6:8] = False  # ... less its hole
    assert np.array_equal(mask, expected)


def test_centres_on_the_outline_are_outside(tmp_path: Path) -> None:
    """Polygon edges through cell centres: the centres on the outline are not released."""
    path = write_vector(tmp_path / "release.geojson", [box(25.0, 35.0, 65.0, 75.0)])
    mask = release_mask(make_dem(), path)
    expected = np.zeros((10, 12), dtype=bool)
    expected[4:7, 3:6] = True
    assert np.array_equal(mask, expected)


def test_release_on_the_dem_edge_is_accepted(tmp_path: Path) -> None:
    path = write_vector(tmp_path / "release.geojson", [box(0.0, 0.0, 120.0, 100.0)])
    assert release_mask(make_dem(), path).all()


@pytest.mark.parametrize("suffix", [".tif", ".asc"])
def test_raster_mask_on_the_dem_cells(tmp_path: Path, suffix: str) -> None:
    dem = make_dem()
    mask = expected_rectangle_mask()
    values = np.where(mask, 3.0, 0.0)
    if suffix == ".tif":
        path = write_field_geotiff(dem, values, tmp_path / "mask.tif", name="release", units="1")
    else:
        header = f"ncols 12\nnrows 10\nxllcorner {X0}\nyllcorner {Y0}\ncellsize {CELL}\n"
        rows = "\n".join(" ".join(f"{v:g}" for v in row) for row in values[::-1])
        path = tmp_path / "mask.asc"
        path.write_text(header + rows + "\n")
        (tmp_path / "mask.prj").write_text(rasterio.crs.CRS.from_string(UTM).to_wkt())
    assert np.array_equal(release_mask(dem, path), mask)


def test_no_data_cells_of_a_raster_mask_are_not_released(tmp_path: Path) -> None:
    dem = make_dem()
    values = np.where(expected_rectangle_mask(), 1.0, -9999.0)
    path = write_field_geotiff(
        dem, values, tmp_path / "mask.tif", name="r", units="1", nodata=-9999
    )
    assert np.array_equal(release_mask(dem, path), expected_rectangle_mask())


def test_no_crs_on_either_side_is_accepted(tmp_path: Path) -> None:
    path = write_vector(tmp_path / "release.shp", [RECTANGLE], crs=None)
    assert np.array_equal(release_mask(make_dem(crs=None), path), expected_rectangle_mask())


def test_equal_crs_written_differently_is_accepted(tmp_path: Path) -> None:
    """The DEM's CRS as a WKT, the file's as an EPSG code: the same system."""
    wkt = rasterio.crs.CRS.from_string(UTM).to_wkt()
    dem = DigitalElevationModel(make_dem().elevation, X0, Y0, CELL, wkt)
    path = write_vector(tmp_path / "release.gpkg", [RECTANGLE])
    assert np.array_equal(release_mask(dem, path), expected_rectangle_mask())


# --- the bad-input catalogue of release files ------------------------------------------------


def _geojson(geometries: list[Any], crs: str | None = UTM) -> Callable[[Path], Path]:
    def build(path: Path) -> Path:
        path.write_text(geojson_text(geometries, crs))
        return path

    return build


def _text(text: str) -> Callable[[Path], Path]:
    def build(path: Path) -> Path:
        path.write_text(text)
        return path

    return build


def _vector(
    geometries: list[shapely.Geometry], crs: str | None = UTM, remove: str = ""
) -> Callable[[Path], Path]:
    def build(path: Path) -> Path:
        write_vector(path, geometries, crs)
        if remove:
            path.with_suffix(remove).unlink()
        return path

    return build


def _two_layers(path: Path) -> Path:
    write_vector(path, [RECTANGLE], layer="north")
    return write_vector(path, [RECTANGLE], layer="south")


def _mask(
    values: np.ndarray, transform: Affine = DEM_TRANSFORM, crs: str | None = UTM
) -> Callable[[Path], Path]:
    def build(path: Path) -> Path:
        return write_mask(path, values, transform, crs)

    return build


ONES = np.ones((10, 12))
WITH_NAN = np.where(np.arange(120).reshape(10, 12) == 13, math.nan, 1.0)  # file row 1, col 1
POINT = {"type": "Point", "coordinates": [X0 + 50.0, Y0 + 50.0]}
LINE = {"type": "LineString", "coordinates": [[X0, Y0], [X0 + 50.0, Y0 + 50.0]]}
BOW_TIE = shapely.Polygon([(X0 + 40, Y0 + 40), (X0 + 60, Y0 + 60), (X0 + 60, Y0 + 40),
                           (X0 + 40, Y0 + 60)])  # fmt: skip
TINY = shapely.Polygon([(X0 + 11, Y0 + 11), (X0 + 14, Y0 + 11), (X0 + 11, Y0 + 14)])

RELEASE_CASES: list[tuple[str, str, Callable[[Path], Path], str, str | None]] = [
    ("missing", "r.geojson", lambda path: path, "file not found", UTM),
    ("not json", "r.geojson", _text('{"type": "FeatureColl'), "cannot be read as a GeoJSON", UTM),
    ("empty file", "r.geojson", _text(""), "cannot be read as a GeoJSON", UTM),
    ("no features", "r.geojson", _geojson([]), "has no features", UTM),
    ("point", "r.geojson", _geojson([POINT]), "feature 1 of 1 is a Point", UTM),
    ("line", "r.geojson", _geojson([RECTANGLE, LINE]), "feature 2 of 2 is a LineString", UTM),
    (
        "collection",
        "r.geojson",
        _geojson([shapely.GeometryCollection([RECTANGLE])]),
        "is a GeometryCollection",
        UTM,
    ),
    ("null geometry", "r.geojson", _geojson([RECTANGLE, None]), "feature 2 of 2 has no geo", UTM),
    (
        "empty polygon",
        "r.geojson",
        _geojson([{"type": "Polygon", "coordinates": []}]),
        "feature 1 of 1 is an empty polygon",
        UTM,
    ),
    (
        "bow tie",
        "r.geojson",
        _geojson([BOW_TIE]),
        "is not a valid polygon: self-intersection at x=500050, y=5000050",
        UTM,
    ),
    (
        "other crs",
        "r.geojson",
        _geojson([RECTANGLE], "EPSG:32633"),
        "CRS EPSG:32633 differs from the DEM's EPSG:32632",
        UTM,
    ),
    ("geojson wgs84", "r.geojson", _geojson([RECTANGLE], None), "WGS 84 by RFC 7946", UTM),
    (
        "shapefile no prj",
        "r.shp",
        _vector([RECTANGLE], None),
        "has no CRS while the DEM's is EPSG:32632",
        UTM,
    ),
    ("dem no crs", "r.gpkg", _vector([RECTANGLE]), "EPSG:32632 while the DEM has none", None),
    (
        "outside",
        "r.geojson",
        _geojson([box(200.0, 0.0, 300.0, 50.0)]),
        "the release lies entirely outside the DEM (release x 500200..500300",
        UTM,
    ),
    (
        "partly outside",
        "r.geojson",
        _geojson([box(-20.0, 0.0, 20.0, 50.0)]),
        "50% of the release area lies outside the DEM",
        UTM,
    ),
    ("too small", "r.geojson", _geojson([TINY]), "covers no cell centre", UTM),
    ("raster shape", "r.tif", _mask(ONES[:, :11]), "has 10 x 11 cells", UTM),
    (
        "raster shifted",
        "r.tif",
        _mask(ONES, Affine.translation(5, 0) @ DEM_TRANSFORM),
        "not on the DEM's cells (south-west corner x=500005",
        UTM,
    ),
    (
        "raster cell size",
        "r.tif",
        _mask(ONES, DEM_TRANSFORM @ Affine.scale(1.001)),
        "not on the DEM's cells",
        UTM,
    ),
    ("raster crs", "r.tif", _mask(ONES, crs="EPSG:3035"), "CRS EPSG:3035 differs", UTM),
    ("raster no crs", "r.tif", _mask(ONES, crs=None), "has no CRS while the DEM's", UTM),
    ("raster zeros", "r.tif", _mask(0 * ONES), "releases no cell", UTM),
    (
        "raster nan",
        "r.tif",
        _mask(WITH_NAN),
        "1 NaN or infinite value, the first (from the south-west) at x=500015, y=5000085",
        UTM,
    ),
    ("raster two bands", "r.tif", _mask(np.stack([ONES, ONES])), "has 2 bands", UTM),
    (
        "raster truncated",
        "r.asc",
        _text("ncols 12\nnrows 10\nxllcorner 0\nyllcorner 0\ncellsize 10\n1 1 1\n"),
        "cannot be read as an ESRI ASCII grid",
        UTM,
    ),
    ("unsupported", "r.kml", _text("<kml/>"), "unsupported file type '.kml'", UTM),
    ("two layers", "r.gpkg", _two_layers, "has 2 layers (north, south)", UTM),
    (
        "shapefile no shx",
        "r.shp",
        _vector([RECTANGLE], remove=".shx"),
        "cannot be read as a shapefile",
        UTM,
    ),
    ("shapefile points", "r.shp", _vector([shapely.Point(X0, Y0)]), "is a Point", UTM),
]


@pytest.mark.parametrize(
    ("name", "build", "cause", "dem_crs"),
    [case[1:] for case in RELEASE_CASES],
    ids=[case[0] for case in RELEASE_CASES],
)
def test_bad_release_file_is_refused_in_one_line(
    tmp_path: Path, name: str, build: Callable[[Path], Path], cause: str, dem_crs: str | None
) -> None:
    path = build(tmp_path / name)
    with pytest.raises(ConfigError) as info:
        release_mask(make_dem(dem_crs), path)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"release file '{path}': ")
    assert cause in message


def test_label_names_the_scene_key(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=r"^release\.file '.*x\.geojson': file not found$"):
        release_mask(make_dem(), tmp_path / "x.geojson", label="release.file")


# --- thickness --------------------------------------------------------------------------------


def tilted_plane(a: float, b: float, cell: float = 1.0, shape: tuple[int, int] = (8, 9)) -> Any:
    """The DEM z = a x + b y on cells of ``cell`` from the origin."""
    x = (np.arange(shape[1]) + 0.5) * cell
    y = (np.arange(shape[0]) + 0.5) * cell
    return DigitalElevationModel(a * x[None, :] + b * y[:, None], 0.0, 0.0, cell)


def test_vertical_thickness_on_a_tilted_plane_is_d_cos_theta() -> None:
    dem = tilted_plane(0.5, -0.25)
    mask = np.zeros(dem.shape, dtype=bool)
    mask[2:6, 1:7] = True
    thickness = release_thickness(dem, mask, 2.0, measured="vertical")
    cos_theta = math.cos(math.atan(math.hypot(0.5, -0.25)))
    np.testing.assert_allclose(thickness[mask], 2.0 * cos_theta, rtol=1e-15, atol=0)
    assert np.all(thickness[~mask] == 0.0)
    normal = release_thickness(dem, mask, 2.0)
    assert np.array_equal(normal, np.where(mask, 2.0, 0.0))


@settings(deadline=None, max_examples=60)
@given(
    angle=st.floats(0.0, 80.0),
    azimuth=st.floats(0.0, 360.0),
    depth=st.floats(0.01, 10.0),
    seed=st.integers(0, 2**16),
)
def test_thickness_conversion_over_slopes(
    angle: float, azimuth: float, depth: float, seed: int
) -> None:
    """Vertical d becomes d cos(theta) on the released cells, never more than d; 0 elsewhere."""
    tangent = math.tan(math.radians(angle))
    dem = tilted_plane(tangent * math.sin(math.radians(azimuth)),
                       tangent * math.cos(math.radians(azimuth)), cell=5.0)  # fmt: skip
    mask = np.random.default_rng(seed).random(dem.shape) < 0.5
    vertical = release_thickness(dem, mask, depth, measured="vertical")
    assert np.array_equal(vertical, np.where(mask, depth * slope_cosine(dem), 0.0))
    np.testing.assert_allclose(vertical[mask], depth * math.cos(math.radians(angle)), rtol=1e-12)
    assert np.all(vertical <= depth)


@pytest.mark.parametrize(
    ("thickness", "measured", "mask", "cause"),
    [
        (0.0, "normal", None, "release thickness must be > 0 m, got 0.0"),
        (-1.0, "vertical", None, "must be > 0 m"),
        (math.nan, "normal", None, "release thickness: expected a finite number, got nan"),
        (math.inf, "normal", None, "expected a finite number"),
        ("1", "normal", None, "expected a finite number, got '1'"),
        (True, "normal", None, "expected a finite number, got True"),
        (1.0, "slope", None, "unknown thickness measure 'slope'; allowed: normal, vertical"),
        (1.0, "normal", np.ones((10, 12)), "release mask: expected a boolean array"),
        (1.0, "normal", np.ones((3, 3), dtype=bool), "of shape (3, 3)"),
    ],
)
def test_thickness_refuses_bad_values(
    thickness: Any, measured: str, mask: np.ndarray | None, cause: str
) -> None:
    dem = make_dem()
    chosen = expected_rectangle_mask() if mask is None else mask
    with pytest.raises(ConfigError) as info:
        release_thickness(dem, chosen, thickness, measured=measured)
    assert cause in str(info.value) and "\n" not in str(info.value)
