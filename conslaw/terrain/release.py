"""The release area of an avalanche on a DEM, and the thickness of the released layer.

A release area comes as polygons (GeoJSON, shapefile, GeoPackage: a cell is released when its
centre lies inside the union of the polygons, strictly; a centre on the outline is outside) or
as a raster mask on the DEM's cells (GeoTIFF or ESRI ASCII grid: a cell is released where the
value is nonzero and not no-data). The thickness of the released layer is measured normal to
the slope, as the depth of the Savage–Hutter equations is (docs/terrain.md).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import shapely
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number, unknown_name_message
from conslaw.terrain.crs import check_same_crs
from conslaw.terrain.dem import DigitalElevationModel
from conslaw.terrain.polygons import POLYGON_FORMATS, read_polygons
from conslaw.terrain.raster import (
    RASTER_DRIVERS,
    RasterBand,
    counted,
    map_location,
    read_raster,
)
from conslaw.terrain.slope import slope_cosine

#: Share of the release area allowed outside the DEM (round-off of an outline drawn on its edge).
OUTSIDE_TOLERANCE = 1e-9
#: Offset of a raster mask's corner from the DEM's still taken as the same cells, in cells.
ALIGNMENT_TOLERANCE = 1e-6
#: How a release thickness may be measured.
THICKNESS_MEASURES = ("normal", "vertical")
_GEOJSON_NOTE = " (a GeoJSON file without a 'crs' member is WGS 84 by RFC 7946)"


def release_mask(
    dem: DigitalElevationModel,
    path: str | Path,
    *,
    label: str = "release file",
    extent: str = "the DEM",
) -> NDArray[np.bool_]:
    """The released cells of ``dem``, ``(ny, nx)`` (y ascending), from a release file.

    Parameters
    ----------
    dem : DigitalElevationModel
        The terrain the release lies on.
    path : str or Path
        Polygons (``.geojson``/``.json``, ``.shp``, ``.gpkg``): a cell is released when its
        centre is strictly inside the union of the polygons (``shapely.contains_xy``). Or a
        raster mask (``.tif``/``.tiff``, ``.asc``) on the DEM's cells (same shape, corner, cell
        size and CRS): released where nonzero and not no-data.
    label : str
        How messages name the file: ``"<label> '<path>': <cause>"``.
    extent : str
        How messages name the rectangle of ``dem`` (``"the scene's domain"`` where ``dem`` is
        the terrain on a scene's cells).

    Returns
    -------
    ndarray of bool, shape (ny, nx)
        At least one cell is released.

    Raises
    ------
    ConfigError
        One line naming the file and the cause: an unsupported suffix, a missing or malformed
        file, no features, a feature that is not a polygon or is empty or invalid, a CRS that
        differs from the DEM's (or a CRS on one side only: see
        :func:`~conslaw.terrain.crs.check_same_crs`), a release entirely or partly outside the
        DEM, one that covers no cell centre, a raster mask not on the DEM's cells.
    """
    path = Path(path)
    where = f"{label} '{path}'"
    suffix = path.suffix.lower()
    if "\0" in str(path):
        raise ConfigError(f"{where}: a file name cannot hold a NUL byte")
    if path.is_dir():  # not "unsupported file type ''" for a folder without a suffix
        raise ConfigError(f"{where}: a folder, not a file")
    if suffix in RASTER_DRIVERS:
        return _raster_mask(dem, read_raster(path, where), where, extent)
    if suffix in POLYGON_FORMATS:
        return _polygon_mask(dem, path, where, extent)
    allowed = ", ".join(sorted({*POLYGON_FORMATS, *RASTER_DRIVERS}))
    raise ConfigError(f"{where}: unsupported file type '{path.suffix}'; allowed: {allowed}")


def _polygon_mask(
    dem: DigitalElevationModel, path: Path, where: str, extent: str
) -> NDArray[np.bool_]:
    """The cells whose centres lie inside the polygons of ``path``."""
    polygons = read_polygons(path, where)
    geojson = POLYGON_FORMATS[path.suffix.lower()] == "GeoJSON"
    note = _GEOJSON_NOTE if geojson and polygons.crs == "EPSG:4326" else ""
    check_same_crs(polygons.crs, dem.crs, where, note)
    area = polygons.area
    _check_inside_dem(area, dem, where, extent)
    mask = centres_inside(area, dem)
    if not mask.any():
        minx, miny, maxx, maxy = area.bounds
        raise ConfigError(
            f"{where}: covers no cell centre (release area {area.area:.4g} m² within x "
            f"{minx:.12g}..{maxx:.12g}, y {miny:.12g}..{maxy:.12g}); too small for the DEM's "
            f"{dem.cell_size:g} m cells"
        )
    return mask


def _extent(bounds: tuple[float, float, float, float]) -> str:
    """``"x a..b, y c..d"``."""
    minx, miny, maxx, maxy = bounds
    return f"x {minx:.12g}..{maxx:.12g}, y {miny:.12g}..{maxy:.12g}"


def _check_inside_dem(
    area: shapely.Geometry, dem: DigitalElevationModel, where: str, name: str = "the DEM"
) -> None:
    """A ConfigError if the release area is not entirely inside the rectangle of ``dem`` (named
    ``name`` in the message: the DEM, or the scene's domain), or so large that its area
    overflows (the share outside would be NaN and pass unseen)."""
    box = shapely.box(dem.x_min, dem.y_min, dem.x_max, dem.y_max)
    short = name.removeprefix("the ").removeprefix("scene's ")
    places = f"release {_extent(area.bounds)}; {short} {_extent(box.bounds)}"
    with np.errstate(all="ignore"):  # an overflow is what the checks below report
        if not math.isfinite(area.area):
            raise ConfigError(f"{where}: its area overflows ({places}); check its coordinates")
        if not shapely.intersects(area, box):
            raise ConfigError(f"{where}: the release lies entirely outside {name} ({places})")
        outside = shapely.difference(area, box).area / area.area
    if not outside <= OUTSIDE_TOLERANCE:
        raise ConfigError(
            f"{where}: {100.0 * outside:.3g}% of the release area lies outside {name} ({places})"
        )


def centres_inside(area: shapely.Geometry, dem: DigitalElevationModel) -> NDArray[np.bool_]:
    """Whether each cell centre of ``dem`` lies strictly inside ``area``, ``(ny, nx)``;
    tested only within the bounding box of ``area`` (vectorised, ``shapely.contains_xy``)."""
    x, y = dem.centres()
    minx, miny, maxx, maxy = area.bounds
    columns = slice(int(np.searchsorted(x, minx)), int(np.searchsorted(x, maxx, side="right")))
    rows = slice(int(np.searchsorted(y, miny)), int(np.searchsorted(y, maxy, side="right")))
    mask = np.zeros(dem.shape, dtype=bool)
    if columns.stop > columns.start and rows.stop > rows.start:
        shapely.prepare(area)
        x_window, y_window = np.meshgrid(x[columns], y[rows])
        mask[rows, columns] = shapely.contains_xy(area, x_window, y_window)
    return mask


def _raster_mask(
    dem: DigitalElevationModel, band: RasterBand, where: str, extent: str = "the DEM"
) -> NDArray[np.bool_]:
    """The cells of a raster mask on the cells of ``dem`` (named ``extent`` in messages) that
    are nonzero and not no-data."""
    owner = "the DEM" if extent == "the DEM" else "the scene"
    check_same_crs(band.crs, dem.crs, where)
    if band.shape != dem.shape:
        raise ConfigError(
            f"{where}: has {band.shape[0]} x {band.shape[1]} cells (rows x columns), {owner} "
            f"{dem.ny} x {dem.nx}; a release raster must be on {owner}'s cells"
        )
    tolerance = ALIGNMENT_TOLERANCE * dem.cell_size
    if (
        abs(band.x_min - dem.x_min) > tolerance
        or abs(band.y_min - dem.y_min) > tolerance
        or not math.isclose(band.cell_size, dem.cell_size, rel_tol=ALIGNMENT_TOLERANCE)
    ):
        raise ConfigError(
            f"{where}: not on {owner}'s cells (south-west corner "
            f"{map_location(band.x_min, band.y_min)}, cell size {band.cell_size:g}; {owner}'s "
            f"{map_location(dem.x_min, dem.y_min)}, {dem.cell_size:g})"
        )
    bad = ~np.isfinite(band.values) & ~band.missing
    if bad.any():
        x, y = band.centre(int(np.flatnonzero(bad)[0]))
        raise ConfigError(
            f"{where}: {counted(int(bad.sum()), 'NaN or infinite value')}, the first (from the "
            f"south-west) at {map_location(x, y)}; mark them no-data or 0"
        )
    mask = (band.values != 0.0) & ~band.missing
    if not mask.any():
        raise ConfigError(f"{where}: releases no cell (every value is 0 or no-data)")
    return mask


def release_thickness(
    dem: DigitalElevationModel,
    mask: NDArray[np.bool_],
    thickness: float,
    measured: str = "normal",
) -> NDArray[np.float64]:
    r"""The slope-normal thickness of the released layer on each cell, 0 outside ``mask``.

    A thickness ``d`` measured vertically (as a snow depth is often given) is the slope-normal
    thickness

    .. math:: h = d \cos\theta, \qquad \cos\theta = \frac{1}{\sqrt{1 + |\nabla z|^2}},

    on each cell (:func:`~conslaw.terrain.slope.slope_cosine`); one measured normal to the
    slope is taken as it is.

    Parameters
    ----------
    dem : DigitalElevationModel
        The terrain.
    mask : ndarray of bool, shape (ny, nx)
        The released cells (:func:`release_mask`).
    thickness : float
        The thickness d of the layer (m), finite and > 0.
    measured : {"normal", "vertical"}
        The direction ``thickness`` is measured in.

    Returns
    -------
    ndarray of float64, shape (ny, nx)
        ``h``, 0 outside the release.

    Raises
    ------
    ConfigError
        A thickness that is not a finite number > 0, an unknown ``measured``, a mask that is not
        a boolean array of the DEM's shape.
    """
    value = finite_number(thickness, "release thickness")
    if not value > 0.0:
        raise ConfigError(f"release thickness must be > 0 m, got {thickness!r}")
    if measured not in THICKNESS_MEASURES:
        raise ConfigError(unknown_name_message("thickness measure", measured, THICKNESS_MEASURES))
    mask = np.asarray(mask)
    if mask.dtype != np.bool_ or mask.shape != dem.shape:
        raise ConfigError(
            f"release mask: expected a boolean array of the DEM's shape {dem.shape}, got "
            f"{mask.dtype} of shape {mask.shape}"
        )
    if measured == "normal":
        return np.where(mask, value, 0.0)
    return np.where(mask, value * slope_cosine(dem), 0.0)


def release_polygon_mask(
    dem: DigitalElevationModel, corners: object, where: str, extent: str = "the DEM"
) -> NDArray[np.bool_]:
    """The released cells of ``dem`` inside the polygon with the vertices ``corners``, a list
    of ``[x, y]`` pairs in the DEM's map coordinates (at least three).

    Parameters
    ----------
    dem : DigitalElevationModel
    corners : list of [x, y]
    where : str
        How messages name the polygon (a scene key).
    extent : str
        How messages name the rectangle of ``dem`` (:func:`release_mask`).

    Returns
    -------
    ndarray of bool, shape (ny, nx)

    Raises
    ------
    ConfigError
        One line: not a list of at least three finite pairs, not a valid polygon (the reason
        shapely gives), outside the DEM or covering no cell centre.
    """
    if not isinstance(corners, list) or len(corners) < 3:
        raise ConfigError(f"{where}: expected a list of at least three [x, y] pairs")
    points = []
    for corner in corners:
        if not isinstance(corner, list) or len(corner) != 2:
            raise ConfigError(f"{where}: expected [x, y] pairs, got {corner!r}")
        points.append(tuple(finite_number(value, where) for value in corner))
    area = shapely.Polygon(points)
    if not area.is_valid or area.area <= 0.0:
        raise ConfigError(f"{where}: not a valid polygon ({shapely.is_valid_reason(area)})")
    _check_inside_dem(area, dem, where, extent)
    mask = centres_inside(area, dem)
    if not mask.any():
        raise ConfigError(
            f"{where}: covers no cell centre (area {area.area:.4g} m^2 within "
            f"{_extent(area.bounds)}); too small for the {dem.cell_size:g} m cells"
        )
    return mask
