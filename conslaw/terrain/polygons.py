"""Release polygons from a vector file (GeoJSON, shapefile, GeoPackage), read with pyogrio and
checked feature by feature with shapely.

Features are named by their position in the file, counted from 1 (``feature 2 of 3``), and
places by their map coordinates.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from conslaw.errors import ConfigError
from conslaw.terrain.raster import check_input_file, library_message, map_location

#: Vector file suffix (lower case) -> what it is called in messages.
POLYGON_FORMATS = {
    ".geojson": "GeoJSON",
    ".json": "GeoJSON",
    ".shp": "shapefile",
    ".gpkg": "GeoPackage",
}
#: shapely type ids of the geometries a release area may have.
POLYGON_TYPES = (shapely.GeometryType.POLYGON, shapely.GeometryType.MULTIPOLYGON)
_REASON_AT = re.compile(r"^(.*)\[(\S+) (\S+)\]$")


@dataclass(frozen=True)
class Polygons:
    """The union of the polygons of a vector file.

    Attributes
    ----------
    area : shapely.Geometry
        The union of every feature (a Polygon or MultiPolygon, valid, not empty).
    crs : str or None
        The file's CRS as pyogrio reports it (``'EPSG:n'`` or a WKT), ``None`` if it has none.
    count : int
        Features in the file.
    """

    area: shapely.Geometry
    crs: str | None
    count: int


def read_polygons(path: Path, where: str) -> Polygons:
    """The polygons of the vector file ``path`` (``.geojson``/``.json``, ``.shp``, ``.gpkg``).

    Raises
    ------
    ConfigError
        One line starting with ``where``: a missing file, a file that cannot be read, more than
        one layer, no features, a feature without geometry, not a Polygon or MultiPolygon,
        empty, or invalid (with shapely's reason and its place).
    """
    path = Path(path)
    kind = POLYGON_FORMATS[path.suffix.lower()]
    check_input_file(path, where)
    try:
        # pyogrio (and the pandas it imports) only when a polygon file is read: every run
        # loads this module with the terrain model.
        import pyogrio
        import pyogrio.raw

        layers = pyogrio.list_layers(path)
        if len(layers) == 1:
            meta, _, wkb, _ = pyogrio.raw.read(path, force_2d=True)
    except Exception as error:  # pyogrio's DataSourceError, GDAL's own classes
        raise ConfigError(
            f"{where}: cannot be read as a {kind}: {library_message(error, path)}"
        ) from None
    if len(layers) != 1:
        names = ", ".join(str(row[0]) for row in layers)
        raise ConfigError(
            f"{where}: has {len(layers)} layers ({names}); keep the release in exactly one"
        )
    count = len(wkb)
    if count == 0:
        raise ConfigError(f"{where}: has no features")
    wkb = np.asarray(wkb, dtype=object)
    null = np.array([item is None for item in wkb], dtype=bool)  # one per feature
    _refuse_first(null, count, "has no geometry", where)
    geometries = shapely.from_wkb(wkb, on_invalid="ignore")
    _refuse_first(shapely.is_missing(geometries), count, "has a malformed geometry", where)
    type_ids = shapely.get_type_id(geometries)
    wrong = ~np.isin(type_ids, [int(kind_id) for kind_id in POLYGON_TYPES])
    if wrong.any():
        first = int(np.flatnonzero(wrong)[0])
        raise ConfigError(
            f"{where}: feature {first + 1} of {count} is a {geometries[first].geom_type}; a "
            "release area must be a Polygon or MultiPolygon"
        )
    _refuse_first(shapely.is_empty(geometries), count, "is an empty polygon", where)
    invalid = ~shapely.is_valid(geometries)
    if invalid.any():
        first = int(np.flatnonzero(invalid)[0])
        reason = _reason(str(shapely.is_valid_reason(geometries[first])))
        raise ConfigError(
            f"{where}: feature {first + 1} of {count} is not a valid polygon: {reason}"
        )
    crs = meta.get("crs")
    return Polygons(area=shapely.union_all(geometries), crs=crs or None, count=count)


def _refuse_first(flags: np.ndarray, count: int, what: str, where: str) -> None:
    """A ConfigError naming the first feature with ``flags`` set."""
    if flags.any():
        first = int(np.flatnonzero(flags)[0])
        raise ConfigError(f"{where}: feature {first + 1} of {count} {what}")


def _reason(text: str) -> str:
    """shapely's ``"Self-intersection[5 5]"`` as ``"self-intersection at x=5, y=5"``."""
    match = _REASON_AT.match(text.strip())
    if match is None:
        return text
    try:
        place = map_location(float(match.group(2)), float(match.group(3)))
    except ValueError:
        return text
    return f"{match.group(1).lower()} at {place}"
