"""Terrain inputs and hazard-map outputs of 2D avalanche runs on a DEM (docs/terrain.md).

Inputs: a DEM (:mod:`~conslaw.terrain.dem`, GeoTIFF or ESRI ASCII grid), its slope
(:mod:`~conslaw.terrain.slope`), a release area and the slope-normal release thickness
(:mod:`~conslaw.terrain.release`), DEMs from formulas (:mod:`~conslaw.terrain.generated`).
Outputs: a field on the DEM's cells as a GeoTIFF (:mod:`~conslaw.terrain.hazard_geotiff`) and as
a map over a hillshade (:mod:`~conslaw.terrain.hazard_figure`). Arrays are ``(ny, nx)`` with row
0 at the south edge; files are north-up.
"""

from __future__ import annotations

from conslaw.lazy_exports import lazy_exports

#: Where each name of the package lives; a submodule is imported on first use of one of its
#: names (PEP 562), so that importing one of them (the terrain model imports the DEM reader at
#: every run) does not import matplotlib or pyogrio with the others.
_HOMES = {
    "DigitalElevationModel": "dem",
    "dem_from_function": "dem",
    "read_dem": "dem",
    "write_dem": "dem",
    "bowl": "generated",
    "bowl_radius": "generated",
    "channelled_slope": "generated",
    "inclined_plane_to_flat": "generated",
    "plane_to_flat_profile": "generated",
    "hazard_map_figure": "hazard_figure",
    "hillshade": "hazard_figure",
    "nice_contour_interval": "hazard_figure",
    "write_field_geotiff": "hazard_geotiff",
    "release_mask": "release",
    "release_polygon_mask": "release",
    "release_thickness": "release",
    "elevation_gradient": "slope",
    "slope_angle": "slope",
    "slope_cosine": "slope",
}

__all__ = sorted(_HOMES)


__getattr__ = lazy_exports(__name__, _HOMES)
