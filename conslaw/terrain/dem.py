"""A digital elevation model (DEM): elevations on square cells, with their place on the map.

The elevations are an ``(ny, nx)`` array with row 0 at the SOUTH edge and column 0 at the west
edge, cell ``(k, j)`` centred at ``(x_min + (j + 1/2) c, y_min + (k + 1/2) c)`` for the cell
size ``c``: the layout of :class:`~conslaw.grid2d.Grid2D`. Files are north-up (row 0 north);
:func:`read_dem` and :func:`write_dem` flip the rows. Coordinates and elevations are in metres
(docs/terrain.md).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from affine import Affine
from numpy.typing import ArrayLike, NDArray

from conslaw.errors import ConfigError, finite_number
from conslaw.grid import MIN_CELLS
from conslaw.grid2d import Grid2D
from conslaw.terrain.crs import normalise_crs
from conslaw.terrain.raster import (
    cell_centre,
    check_geotiff_suffix,
    counted,
    map_location,
    north_up_transform,
    read_raster,
    write_geotiff,
)

#: Relative mismatch tolerated between a range's length and a whole number of cells.
WHOLE_CELLS_TOLERANCE = 1e-9


@dataclass(frozen=True, eq=False)
class DigitalElevationModel:
    """Elevations on a grid of square cells.

    Validated on construction (a :class:`~conslaw.errors.ConfigError` otherwise): a 2D array of
    finite numbers of at least 4 x 4 cells, finite corner, positive cell size, a CRS in metres
    or none. ``elevation`` is stored as a read-only float64 copy; ``crs`` as
    ``CRS.to_string()`` writes it.

    Attributes
    ----------
    elevation : ndarray of float64, shape (ny, nx)
        Elevation z of each cell (m), y ascending: row 0 is the south edge.
    x_min, y_min : float
        South-west corner (m, map coordinates).
    cell_size : float
        Width of the square cells (m).
    crs : str or None
        ``'EPSG:n'`` or a WKT (rasterio's ``CRS.to_string()``), ``None`` if unknown.
    """

    elevation: NDArray[np.float64]
    x_min: float
    y_min: float
    cell_size: float
    crs: str | None = None

    def __post_init__(self) -> None:
        where = "DigitalElevationModel"
        elevation = checked_elevation(self.elevation, self.x_min, self.y_min, self.cell_size, where)
        object.__setattr__(self, "elevation", elevation)
        object.__setattr__(self, "x_min", float(self.x_min))
        object.__setattr__(self, "y_min", float(self.y_min))
        object.__setattr__(self, "cell_size", float(self.cell_size))
        object.__setattr__(self, "crs", normalise_crs(self.crs, where))

    @property
    def shape(self) -> tuple[int, int]:
        """``(ny, nx)``."""
        return (int(self.elevation.shape[0]), int(self.elevation.shape[1]))

    @property
    def nx(self) -> int:
        """Cells along x (columns)."""
        return self.shape[1]

    @property
    def ny(self) -> int:
        """Cells along y (rows)."""
        return self.shape[0]

    @property
    def x_max(self) -> float:
        """East edge, ``x_min + nx cell_size``."""
        return self.x_min + self.nx * self.cell_size

    @property
    def y_max(self) -> float:
        """North edge, ``y_min + ny cell_size``."""
        return self.y_min + self.ny * self.cell_size

    @property
    def grid(self) -> Grid2D:
        """The :class:`~conslaw.grid2d.Grid2D` of the same cells."""
        return Grid2D.from_bounds(self.x_min, self.x_max, self.nx, self.y_min, self.y_max, self.ny)

    @property
    def transform(self) -> Affine:
        """The north-up affine transform of the DEM as a file (rasterio's convention): column
        ``c`` and row ``r`` from the north-west corner map to
        ``(x_min + c cell_size, y_max - r cell_size)``."""
        return north_up_transform(self.x_min, self.y_min, self.cell_size, self.ny)

    def centres(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The cell centres along x (``nx``) and along y (``ny``, ascending)."""
        x = self.x_min + (np.arange(self.nx, dtype=np.float64) + 0.5) * self.cell_size
        y = self.y_min + (np.arange(self.ny, dtype=np.float64) + 0.5) * self.cell_size
        return x, y


def checked_elevation(
    elevation: ArrayLike, x_min: float, y_min: float, cell_size: float, where: str
) -> NDArray[np.float64]:
    """A read-only float64 copy of ``elevation`` after the checks of
    :class:`DigitalElevationModel`; each failure a one-line ConfigError starting with ``where``."""
    finite_number(x_min, f"{where}: x_min")
    finite_number(y_min, f"{where}: y_min")
    if not finite_number(cell_size, f"{where}: cell_size") > 0.0:
        raise ConfigError(f"{where}: cell_size must be > 0, got {cell_size!r}")
    try:
        values = np.array(elevation, dtype=np.float64, order="C")
    except (TypeError, ValueError):
        raise ConfigError(f"{where}: elevation is not an array of numbers") from None
    if values.ndim != 2:
        raise ConfigError(
            f"{where}: elevation must be a 2D array (ny, nx), got shape {values.shape}"
        )
    ny, nx = values.shape
    if ny < MIN_CELLS or nx < MIN_CELLS:
        raise ConfigError(
            f"{where}: {ny} x {nx} cells (rows x columns); a DEM needs at least "
            f"{MIN_CELLS} x {MIN_CELLS}"
        )
    bad = ~np.isfinite(values)
    if bad.any():
        row, column = divmod(int(np.flatnonzero(bad)[0]), nx)
        x, y = cell_centre(float(x_min), float(y_min), float(cell_size), row, column)
        raise ConfigError(
            f"{where}: {counted(int(bad.sum()), 'NaN or infinite elevation')}, the first (from "
            f"the south-west) at {map_location(x, y)}"
        )
    values.setflags(write=False)
    return values


def read_dem(path: str | Path, *, label: str = "DEM file") -> DigitalElevationModel:
    """The DEM in a GeoTIFF (``.tif``, ``.tiff``) or ESRI ASCII grid (``.asc``, with its CRS in
    a ``.prj`` beside it) file, read with rasterio.

    Parameters
    ----------
    path : str or Path
        The file.
    label : str
        How messages name the file: ``"<label> '<path>': <cause>"`` (a scene would pass its
        key, e.g. ``"terrain.dem"``).

    Returns
    -------
    DigitalElevationModel
        Rows flipped to y ascending; a south-up or east-to-west file is flipped into place.

    Raises
    ------
    ConfigError
        One line naming the file and the cause: a missing file, an unsupported suffix, a file
        that cannot be read (not a raster, truncated, a bad header, a value that is not a
        number), no georeferencing, more than one band, a rotated or sheared transform,
        non-square cells, no-data cells (how many and where the first is), NaN or infinite
        elevations, fewer than 4 x 4 cells, a CRS not in metres (geographic, feet). The full
        list is in docs/terrain.md.
    """
    path = Path(path)
    where = f"{label} '{path}'"
    band = read_raster(path, where)
    if band.missing.any():
        x, y = band.centre(int(np.flatnonzero(band.missing)[0]))
        value = "" if band.nodata is None else f" (value {band.nodata:g})"
        missing = counted(int(band.missing.sum()), "no-data cell")
        raise ConfigError(
            f"{where}: {missing}{value}, the first (from the south-west) at "
            f"{map_location(x, y)}; fill them (e.g. gdal_fillnodata) or crop the DEM"
        )
    elevation = checked_elevation(band.values, band.x_min, band.y_min, band.cell_size, where)
    crs = normalise_crs(band.crs, where)
    return DigitalElevationModel(elevation, band.x_min, band.y_min, band.cell_size, crs)


def write_dem(dem: DigitalElevationModel, path: str | Path) -> Path:
    """Write ``dem`` as a one-band float64 north-up GeoTIFF (``.tif``/``.tiff``) with its
    transform and CRS, atomically; :func:`read_dem` gives it back bit for bit.

    Raises
    ------
    ConfigError
        ``path`` does not end in ``.tif`` or ``.tiff``.
    OutputError
        The file cannot be written (a missing folder, a full disk); no file is left under
        ``path``.
    """
    path = Path(path)
    check_geotiff_suffix(path, f"DEM file '{path}'")
    corner = (dem.x_min, dem.y_min)
    return write_geotiff(
        path, dem.elevation, corner, dem.cell_size, dem.crs, name="elevation", units="m"
    )


def dem_from_function(
    function: Callable[[NDArray[np.float64], NDArray[np.float64]], Any],
    x_range: tuple[float, float],
    y_range: tuple[float, float],
    cell_size: float,
    crs: str | None = None,
) -> DigitalElevationModel:
    """The DEM with ``z = function(x, y)`` at the cell centres.

    Parameters
    ----------
    function : callable
        ``function(x, y)`` with ``x`` and ``y`` arrays of shape ``(ny, nx)`` (the centres,
        ``x`` along the columns, ``y`` ascending along the rows) returning the elevations,
        vectorised (numpy), in an array broadcastable to ``(ny, nx)``.
    x_range, y_range : tuple of float
        ``(x_min, x_max)`` and ``(y_min, y_max)`` of the DEM: each a whole number of cells.
    cell_size : float
        Width of the square cells.
    crs : str or None
        The CRS (e.g. ``"EPSG:32632"``), in metres.

    Raises
    ------
    ConfigError
        A range that is not a whole number of cells, an elevation array of another shape, or
        any check of :class:`DigitalElevationModel`.
    """
    where = "dem_from_function"
    cell = finite_number(cell_size, f"{where}: cell_size")
    if not cell > 0.0:
        raise ConfigError(f"{where}: cell_size must be > 0, got {cell_size!r}")
    nx = _whole_cells(x_range, cell, f"{where}: x_range")
    ny = _whole_cells(y_range, cell, f"{where}: y_range")
    x0, y0 = float(x_range[0]), float(y_range[0])
    x, y = np.meshgrid(x0 + (np.arange(nx) + 0.5) * cell, y0 + (np.arange(ny) + 0.5) * cell)
    values = np.asarray(function(x, y))
    try:
        values = np.broadcast_to(values, (ny, nx))
    except ValueError:
        raise ConfigError(
            f"{where}: function returned shape {values.shape}, expected {(ny, nx)}"
        ) from None
    elevation = checked_elevation(values, x0, y0, cell, where)
    return DigitalElevationModel(elevation, x0, y0, cell, normalise_crs(crs, where))


def _whole_cells(span: tuple[float, float], cell_size: float, where: str) -> int:
    """The number of cells of width ``cell_size`` in ``span``, which must be a whole number."""
    low, high = (finite_number(value, where) for value in span)
    if not high > low:
        raise ConfigError(f"{where}: expected (low, high) with high > low, got {span!r}")
    count = (high - low) / cell_size
    whole = round(count)
    if whole < 1 or abs(count - whole) > WHOLE_CELLS_TOLERANCE * max(1.0, count):
        raise ConfigError(
            f"{where}: the length {high - low:g} is not a whole number of {cell_size:g} cells"
        )
    return int(whole)
