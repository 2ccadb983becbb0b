"""Hazard maps as GeoTIFFs: a field on a DEM's cells (peak flow depth, peak velocity, ...)
written back on the DEM's grid, with its transform and CRS, for a GIS."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from conslaw.errors import ConfigError
from conslaw.terrain.dem import DigitalElevationModel
from conslaw.terrain.raster import check_geotiff_suffix, write_geotiff


def write_field_geotiff(
    dem: DigitalElevationModel,
    field: ArrayLike,
    path: str | Path,
    *,
    name: str,
    units: str,
    nodata: float | None = None,
) -> Path:
    """Write ``field`` (``(ny, nx)`` on the cells of ``dem``, y ascending) as a one-band
    GeoTIFF with the DEM's transform and CRS, north-up (the rows flipped back).

    The file is written atomically: built in memory, written under a temporary name in the
    same folder and renamed into place with ``os.replace``, so a crash or a full disk never
    leaves a partial file under ``path`` (a file already there stays as it was).

    Parameters
    ----------
    dem : DigitalElevationModel
        The terrain whose cells ``field`` is on.
    field : array_like, shape (ny, nx)
        Values; float32 is written as float32, everything else as float64.
    path : str or Path
        The file, ``.tif`` or ``.tiff``.
    name, units : str
        The band's description and unit (also band tags ``name`` and ``units``), e.g.
        ``"peak flow depth"``, ``"m"``.
    nodata : float or None
        The band's no-data value, if any.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ConfigError
        ``field`` is not of the DEM's shape, or ``path`` not a ``.tif``/``.tiff``.
    OutputError
        The file cannot be written (a missing folder, a full disk, no permission).
    """
    path = Path(path)
    where = f"GeoTIFF '{path}'"
    check_geotiff_suffix(path, where)
    values = np.asarray(field)
    if values.shape != dem.shape:
        raise ConfigError(
            f"{where}: field '{name}' has shape {values.shape}, the DEM {dem.shape} (ny, nx)"
        )
    if values.dtype.kind not in "biuf":  # booleans, integers, floats
        raise ConfigError(f"{where}: field '{name}' is not numeric (dtype {values.dtype})")
    if values.dtype != np.float32:
        values = values.astype(np.float64)
    corner = (dem.x_min, dem.y_min)
    return write_geotiff(
        path, values, corner, dem.cell_size, dem.crs, name=name, units=units, nodata=nodata
    )
