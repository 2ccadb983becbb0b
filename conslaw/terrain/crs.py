"""Coordinate reference systems of terrain inputs: parsed, checked to be in metres, compared.

A CRS is carried as the string rasterio's ``CRS.to_string()`` gives (``'EPSG:32632'`` when the
CRS has an EPSG code, its WKT otherwise) or ``None`` when a file has none. The terrain is in
metres (docs/design.md, "Terrain"), so a geographic CRS (degrees) or a projected one in feet is
refused: its cells are not metres in x and y, and the slopes computed from them would be wrong.
"""

from __future__ import annotations

import re

from rasterio.crs import CRS

from conslaw.errors import ConfigError

#: Longest CRS text quoted in a message (a WKT is cut to its name).
SHOWN_LENGTH = 60


def parse_crs(text: str, where: str) -> CRS:
    """The CRS of ``text`` (an ``'EPSG:n'`` code, a WKT, a PROJ string); a ConfigError
    ``"<where>: CRS ... cannot be parsed"`` if rasterio cannot read it."""
    try:
        return CRS.from_user_input(text)
    except Exception:  # rasterio raises CRSError, GDAL's own classes for odd strings
        raise ConfigError(f"{where}: CRS {crs_name(text)} cannot be parsed") from None


def normalise_crs(text: str | None, where: str) -> str | None:
    """``text`` as ``CRS.to_string()`` writes it, after checking that its unit is the metre;
    ``None`` stays ``None``.

    Raises
    ------
    ConfigError
        The CRS cannot be parsed, is geographic (degrees) or projected in another unit.
    """
    if text is None:
        return None
    crs = parse_crs(text, where)
    name = crs_name(crs.to_string())
    if crs.is_geographic:
        raise ConfigError(
            f"{where}: CRS {name} is geographic (degrees); reproject to a projected CRS in metres "
            "(e.g. UTM)"
        )
    unit = crs.linear_units
    if unit not in ("metre", "meter", "m"):
        raise ConfigError(f"{where}: CRS {name} has unit '{unit}'; terrain must be in metres")
    return str(crs.to_string())


def same_crs(first: str, second: str) -> bool:
    """Whether two CRS strings name the same system (rasterio's comparison, so an EPSG code
    equals its WKT)."""
    try:
        return bool(CRS.from_user_input(first) == CRS.from_user_input(second))
    except Exception:  # an unparsable string equals only itself
        return first == second


def crs_name(text: str | None) -> str:
    """A short one-line name of a CRS for messages: ``EPSG:n`` as it is, a WKT by the name in
    its first quotes (``'WGS 84 / UTM zone 32N'``), ``none`` for ``None``."""
    if text is None:
        return "none"
    one_line = " ".join(text.split())
    if re.fullmatch(r"[A-Za-z]+:\d+", one_line):
        return one_line
    quoted = re.search(r'"([^"]*)"', one_line)
    name = f"'{quoted.group(1)}'" if quoted else one_line
    return name if len(name) <= SHOWN_LENGTH else name[: SHOWN_LENGTH - 3] + "..."


def check_same_crs(file_crs: str | None, dem_crs: str | None, where: str, note: str = "") -> None:
    """A ConfigError unless a file's CRS agrees with the DEM's.

    Two known CRSs must name the same system. A CRS on one side only is refused as well: the
    file's coordinates cannot be checked to be the DEM's, and a release placed by guess is the
    worst kind of wrong; only when neither has a CRS are the coordinates taken as the same.
    ``note`` ends the message when the file has a CRS (a hint where that CRS came from).
    """
    if file_crs is None and dem_crs is None:
        return
    if file_crs is None:
        raise ConfigError(
            f"{where}: has no CRS while the DEM's is {crs_name(dem_crs)}; give the file a CRS "
            "(for a shapefile or an ASCII grid: a .prj file beside it)"
        )
    if dem_crs is None:
        raise ConfigError(
            f"{where}: has CRS {crs_name(file_crs)} while the DEM has none; give the DEM a "
            f"CRS{note}"
        )
    if not same_crs(file_crs, dem_crs):
        raise ConfigError(
            f"{where}: CRS {crs_name(file_crs)} differs from the DEM's {crs_name(dem_crs)}{note}"
        )
