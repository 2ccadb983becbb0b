"""Single-band raster files (GeoTIFF, ESRI ASCII grid) read into and written from the project's
orientation, through rasterio.

A raster file is north-up: its first row is the northern edge. conslaw's cell arrays are
``(ny, nx)`` with row 0 at the SOUTH edge (y ascending, :class:`~conslaw.grid2d.Grid2D`), so the
rows are flipped on the way in and on the way out. Every rasterio/GDAL failure becomes one line
naming the file (a :class:`~conslaw.errors.ConfigError` when reading, an
:class:`~conslaw.errors.OutputError` when writing).
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import rasterio
from affine import Affine
from numpy.typing import NDArray
from rasterio.errors import NotGeoreferencedWarning
from rasterio.io import MemoryFile

from conslaw.errors import ConfigError, OutputError
from conslaw.output.files import atomic_write_bytes

#: GDAL driver of each raster file suffix read (lower case).
RASTER_DRIVERS = {".tif": "GTiff", ".tiff": "GTiff", ".asc": "AAIGrid"}
#: Suffixes a GeoTIFF is written under.
GEOTIFF_SUFFIXES = (".tif", ".tiff")
_KIND = {"GTiff": "a GeoTIFF", "AAIGrid": "an ESRI ASCII grid"}
#: Relative difference of the two cell widths still taken as square cells (a GeoTIFF written
#: by some tools carries 5.000000000001 beside 5).
SQUARE_TOLERANCE = 1e-9
# An ASCII grid's header lines (GDAL's AAIGrid keywords), and a value that is not a number: a
# token with a character no number has, other than the words nan and inf (GDAL reads such a
# token as 0 without a word).
_ASCII_HEADER = re.compile(
    rb"\A(?:[ \t]*(?:ncols|nrows|xllcorner|xllcenter|yllcorner|yllcenter|cellsize|dx|dy"
    rb"|nodata_value)[ \t]+\S+[ \t]*\r?\n)*",
    re.IGNORECASE,
)
_NOT_A_NUMBER = re.compile(
    rb"(?<!\S)(?![-+]?(?:nan|inf|infinity)(?!\S))\S*?[^\s0-9eE+\-.]", re.IGNORECASE
)


@dataclass(frozen=True, eq=False)
class RasterBand:
    """The one band of a raster file on the project's orientation.

    Attributes
    ----------
    values : ndarray of float64, shape (ny, nx)
        Cell values, row 0 at the south edge, column 0 at the west edge.
    missing : ndarray of bool, shape (ny, nx)
        The no-data cells (the file's no-data value or mask), same orientation.
    x_min, y_min : float
        South-west corner of the raster, in map coordinates.
    cell_size : float
        Width of the (square) cells.
    crs : str or None
        ``CRS.to_string()`` of the file's CRS, ``None`` if it has none.
    nodata : float or None
        The file's no-data value.
    """

    values: NDArray[np.float64]
    missing: NDArray[np.bool_]
    x_min: float
    y_min: float
    cell_size: float
    crs: str | None
    nodata: float | None

    @property
    def shape(self) -> tuple[int, int]:
        """``(ny, nx)``."""
        return (int(self.values.shape[0]), int(self.values.shape[1]))

    def centre(self, flat_index: int) -> tuple[float, float]:
        """Map coordinates of the centre of the cell at ``flat_index`` (C order of ``values``)."""
        row, column = divmod(int(flat_index), self.values.shape[1])
        return cell_centre(self.x_min, self.y_min, self.cell_size, row, column)


def cell_centre(
    x_min: float, y_min: float, cell_size: float, row: int, column: int
) -> tuple[float, float]:
    """``(x_min + (column + 1/2) cell_size, y_min + (row + 1/2) cell_size)``."""
    return (x_min + (column + 0.5) * cell_size, y_min + (row + 0.5) * cell_size)


def counted(number: int, noun: str) -> str:
    """``"1 cell"``, ``"3 cells"``: ``number`` and ``noun``, plural unless one."""
    return f"{number} {noun}" if number == 1 else f"{number} {noun}s"


def map_location(x: float, y: float) -> str:
    """``"x=..., y=..."`` with up to 12 significant digits (a UTM northing in full)."""
    return f"x={float(x):.12g}, y={float(y):.12g}"


def north_up_transform(x_min: float, y_min: float, cell_size: float, ny: int) -> Affine:
    """The affine transform of a north-up raster with its south-west corner at
    ``(x_min, y_min)``: ``x = x_min + column c``, ``y = y_max - row c`` with
    ``y_max = y_min + ny c``."""
    return Affine(cell_size, 0.0, x_min, 0.0, -cell_size, y_min + ny * cell_size)


def start_from_end(end: float, extent: float) -> float:
    """The float ``start`` nearest ``end - extent`` for which ``start + extent == end`` exactly,
    if one is within a few units in the last place (so that a raster read from a file and
    written again keeps the file's transform bit for bit)."""
    start = end - extent
    for direction in (math.inf, -math.inf):
        candidate = start
        for _ in range(4):
            if candidate + extent == end:
                return candidate
            candidate = math.nextafter(candidate, direction)
    return start


def raster_driver(path: Path, where: str) -> str:
    """The GDAL driver for ``path`` by its suffix, after checking that it is an existing file."""
    if "\0" in str(path):
        raise ConfigError(f"{where}: a file name cannot hold a NUL byte")
    if path.is_dir():  # not "unsupported file type ''" for a folder without a suffix
        raise ConfigError(f"{where}: a folder, not a file")
    driver = RASTER_DRIVERS.get(path.suffix.lower())
    if driver is None:
        allowed = ", ".join(sorted(RASTER_DRIVERS))
        raise ConfigError(f"{where}: unsupported file type '{path.suffix}'; allowed: {allowed}")
    check_input_file(path, where)
    return driver


def check_input_file(path: Path, where: str) -> None:
    """A ConfigError unless ``path`` is an existing file."""
    if not path.exists():
        raise ConfigError(f"{where}: file not found")
    if not path.is_file():
        raise ConfigError(f"{where}: not a file")


def library_message(error: BaseException, path: Path) -> str:
    """The gist of a GDAL/rasterio/pyogrio message in one line: the innermost cause, without
    the file name, the part after the last ``": "`` (with the part before it when that is only
    a value, as in ``"Invalid dataset dimensions : 0 x 6"``), up to the first ``"; "``."""
    cause = error
    while cause.__cause__ is not None:
        cause = cause.__cause__
    text = " ".join(str(cause).split())
    for form in (str(path), path.name):
        text = text.replace(f"'{form}'", "").replace(form, "")
    parts = [part.strip(" .,;:'") for part in text.split(": ")]
    parts = [part for part in parts if part]
    if len(parts) > 1 and parts[-1][:1].isdigit():
        parts[-2:] = [f"{parts[-2]}: {parts[-1]}"]
    gist = parts[-1].split("; ")[0].strip(" .") if parts else ""
    return gist or type(cause).__name__


def read_raster(path: Path, where: str) -> RasterBand:
    """The one band of the raster file ``path`` (GeoTIFF ``.tif``/``.tiff``, ESRI ASCII grid
    ``.asc``), on the project's orientation.

    A south-up or east-to-west file is flipped into place. ASCII grids are read in float64
    (GDAL's default is float32) and checked for values that are not numbers (GDAL reads them
    as 0). Refused, each with one line starting with ``where``: an unsupported suffix, a missing
    file, a file GDAL cannot read (not a raster, truncated, a bad header), no georeferencing,
    more than one band, a rotated or sheared transform, non-square cells.
    """
    path = Path(path)
    driver = raster_driver(path, where)
    try:
        with (
            warnings.catch_warnings(record=True, action="always") as caught,
            rasterio.Env(AAIGRID_DATATYPE="Float64"),
            rasterio.open(path, driver=driver) as dataset,
        ):
            count, transform, crs = dataset.count, dataset.transform, dataset.crs
            nodata = dataset.nodata
            band = dataset.read(1, masked=True)
    except Exception as error:  # GDAL errors are not all in rasterio.errors (rasterio._err)
        reason = library_message(error, path)
        raise ConfigError(f"{where}: cannot be read as {_KIND[driver]}: {reason}") from None
    if any(issubclass(w.category, NotGeoreferencedWarning) for w in caught):
        raise ConfigError(f"{where}: not georeferenced (no geotransform)")
    if count != 1:
        raise ConfigError(f"{where}: has {count} bands; a terrain raster has exactly one")
    values = np.asarray(band.data, dtype=np.float64)
    missing = np.ma.getmaskarray(band)
    x_min, y_min, cell_size, values, missing = _oriented(transform, values, missing, where)
    result = RasterBand(
        values=np.ascontiguousarray(values),
        missing=np.ascontiguousarray(missing),
        x_min=x_min,
        y_min=y_min,
        cell_size=cell_size,
        crs=None if not crs else str(crs.to_string()),
        nodata=None if nodata is None else float(nodata),
    )
    if driver == "AAIGrid":
        _check_ascii_numbers(path, where, result)
    return result


def _oriented(
    transform: Affine, values: NDArray[np.float64], missing: NDArray[np.bool_], where: str
) -> tuple[float, float, float, NDArray[np.float64], NDArray[np.bool_]]:
    """``(x_min, y_min, cell_size, values, missing)`` with rows south to north and columns
    west to east, from a file's transform and band."""
    a, b, c, d, e, f = (float(value) for value in transform[:6])
    if b != 0.0 or d != 0.0:
        raise ConfigError(
            f"{where}: rotated or sheared transform ({a:g}, {b:g}, {c:.12g}, {d:g}, {e:g}, "
            f"{f:.12g}); warp it to a north-up grid first (e.g. gdalwarp)"
        )
    if not (math.isfinite(a) and math.isfinite(e) and a != 0.0 and e != 0.0):
        raise ConfigError(f"{where}: degenerate transform (cell widths {a:g} and {e:g})")
    if not math.isclose(abs(a), abs(e), rel_tol=SQUARE_TOLERANCE):
        raise ConfigError(
            f"{where}: cells are not square (dx={abs(a):.15g}, dy={abs(e):.15g}); resample it to "
            "square cells"
        )
    cell_size = abs(a)
    ny, nx = values.shape
    if e < 0.0:  # north-up: the usual case
        values, missing = values[::-1], missing[::-1]
        y_min = start_from_end(f, ny * cell_size)
    else:
        y_min = f
    if a < 0.0:  # columns east to west
        values, missing = values[:, ::-1], missing[:, ::-1]
        x_min = start_from_end(c, nx * cell_size)
    else:
        x_min = c
    corners = (x_min, y_min, x_min + nx * cell_size, y_min + ny * cell_size)
    if not all(math.isfinite(value) for value in corners):  # was "y_min: ... got nan"
        raise ConfigError(
            f"{where}: its extent overflows ({nx} x {ny} cells of {cell_size:g} from "
            f"{c:.12g}, {f:.12g}); check its cell size and corner"
        )
    return x_min, y_min, cell_size, values, missing


def _check_ascii_numbers(path: Path, where: str, band: RasterBand) -> None:
    """A ConfigError naming the first value of an ASCII grid that is not a number (the words
    nan and inf are numbers here: they are refused later, with their location)."""
    try:
        text = path.read_bytes()
    except OSError as error:
        raise ConfigError(f"{where}: cannot be read: {error.strerror}") from None
    header = _ASCII_HEADER.match(text)
    body = text[header.end() if header else 0 :]
    bad = _NOT_A_NUMBER.search(body)
    if bad is None:
        return
    index = len(body[: bad.start()].split())
    token = body[bad.start() :].split(maxsplit=1)[0].decode(errors="replace")
    ny, nx = band.shape
    row_from_north, column = divmod(index, nx)
    if row_from_north >= ny:
        raise ConfigError(f"{where}: extra text after the {ny} x {nx} values: '{token[:20]}'")
    x, y = cell_centre(band.x_min, band.y_min, band.cell_size, ny - 1 - row_from_north, column)
    raise ConfigError(
        f"{where}: value '{token[:20]}' (row {row_from_north + 1}, column {column + 1}, at "
        f"{map_location(x, y)}) is not a number"
    )


def write_geotiff(
    path: Path,
    values: NDArray[np.floating],
    corner: tuple[float, float],
    cell_size: float,
    crs: str | None,
    *,
    name: str,
    units: str,
    nodata: float | None = None,
) -> Path:
    """Write ``values`` (``(ny, nx)``, row 0 south) as a one-band north-up GeoTIFF at ``path``,
    atomically (built in memory, written under a temporary name beside ``path``, renamed into
    place), with the south-west ``corner`` ``(x_min, y_min)``, ``cell_size`` and ``crs``.

    float32 values are written as float32, everything else as float64; deflate-compressed
    (lossless). The band's description is ``name``, its unit ``units``, and its tags
    ``name=`` and ``units=``.

    Raises
    ------
    OutputError
        The file cannot be written (a missing folder, a full disk, no permission).
    """
    path = Path(path)
    where = f"GeoTIFF '{path}'"
    data = geotiff_bytes(
        values, corner, cell_size, crs, name=name, units=units, nodata=nodata, where=where
    )
    try:
        atomic_write_bytes(path, data)
    except OSError as error:
        reason = error.strerror or type(error).__name__
        raise OutputError(f"{where}: could not be written: {reason}") from None
    return path


def geotiff_bytes(
    values: NDArray[np.floating],
    corner: tuple[float, float],
    cell_size: float,
    crs: str | None,
    *,
    name: str,
    units: str,
    nodata: float | None = None,
    where: str = "GeoTIFF",
) -> bytes:
    """The bytes of the GeoTIFF :func:`write_geotiff` writes (for a caller that puts them in
    place with others, all or nothing).

    Raises
    ------
    OutputError
        GDAL cannot build the file (``where`` names it).
    """
    values = np.asarray(values)
    dtype = np.float32 if values.dtype == np.float32 else np.float64
    north_up = np.ascontiguousarray(values[::-1], dtype=dtype)
    ny, nx = north_up.shape
    try:
        with MemoryFile() as memory:
            with memory.open(
                driver="GTiff", width=nx, height=ny, count=1, dtype=dtype, crs=crs,
                transform=north_up_transform(corner[0], corner[1], cell_size, ny),
                nodata=nodata, compress="deflate",
            ) as dataset:  # fmt: skip
                dataset.write(north_up, 1)
                dataset.set_band_description(1, name)
                dataset.units = (units,)
                dataset.update_tags(1, name=name, units=units)
            return bytes(memory.getbuffer())
    except Exception as error:  # GDAL errors are not all in rasterio.errors (rasterio._err)
        reason = library_message(error, Path(where))
        raise OutputError(f"{where}: could not be written: {reason}") from None


def check_geotiff_suffix(path: Path, where: str) -> None:
    """A ConfigError unless ``path`` ends in ``.tif`` or ``.tiff``."""
    if Path(path).suffix.lower() not in GEOTIFF_SUFFIXES:
        raise ConfigError(
            f"{where}: a GeoTIFF must be named .tif or .tiff, got '{Path(path).suffix}'"
        )
