"""Terrain inputs and hazard-map outputs of 2D avalanche runs on a DEM (docs/terrain.md).

Inputs: a DEM (:mod:`~conslaw.terrain.dem`, GeoTIFF or ESRI ASCII grid), its slope
(:mod:`~conslaw.terrain.slope`), a release area and the slope-normal release thickness
(:mod:`~conslaw.terrain.release`), DEMs from formulas (:mod:`~conslaw.terrain.generated`).
Outputs: a field on the DEM's cells as a GeoTIFF (:mod:`~conslaw.terrain.hazard_geotiff`) and as
a map over a hillshade (:mod:`~conslaw.terrain.hazard_figure`). Arrays are ``(ny, nx)`` with row
0 at the south edge; files are north-up.
"""

from __future__ import annotations

from conslaw.terrain.dem import DigitalElevationModel, dem_from_function, read_dem, write_dem
from conslaw.terrain.generated import (
    bowl,
    bowl_radius,
    channelled_slope,
    inclined_plane_to_flat,
    plane_to_flat_profile,
)
from conslaw.terrain.hazard_figure import hazard_map_figure, hillshade, nice_contour_interval
from conslaw.terrain.hazard_geotiff import write_field_geotiff
from conslaw.terrain.release import release_mask, release_polygon_mask, release_thickness
from conslaw.terrain.slope import elevation_gradient, slope_angle, slope_cosine

__all__ = [
    "DigitalElevationModel",
    "bowl",
    "bowl_radius",
    "channelled_slope",
    "dem_from_function",
    "elevation_gradient",
    "hazard_map_figure",
    "hillshade",
    "inclined_plane_to_flat",
    "nice_contour_interval",
    "plane_to_flat_profile",
    "read_dem",
    "release_mask",
    "release_polygon_mask",
    "release_thickness",
    "slope_angle",
    "slope_cosine",
    "write_dem",
    "write_field_geotiff",
]
