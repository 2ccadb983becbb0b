"""Hazard maps of a 2D run on terrain (docs/output.md, "Hazard maps"): the peak flow depth,
peak speed and peak pressure of every cell over the run (:mod:`conslaw.peak_fields`, updated
after every step pair), the deposit (the flow depth at the end), the run-out and travel angle;
as GeoTIFFs with the terrain's georeference, PNG maps over a hillshade, and ``hazard.json``.

A run has hazard maps when its model gives a terrain on the run's cells
(``Model.scene_dem``) and a flow depth (``Model.flow_depth_and_speed``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.peak_fields import REACHED_DEPTH, run_out
from conslaw.terrain.dem import DigitalElevationModel
from conslaw.terrain.raster import geotiff_bytes

Array = NDArray[np.float64]


@dataclass(frozen=True)
class HazardField:
    """One map: its file stem, its values on the run's cells, its name and units."""

    stem: str
    values: Array
    name: str
    units: str


@dataclass(frozen=True)
class HazardMaps:
    """The maps of a run, its terrain on the run's cells and its released cells."""

    dem: DigitalElevationModel
    released: NDArray[np.bool_]
    fields: tuple[HazardField, ...]
    summary: dict[str, Any]


def hazard_maps(result: Any) -> HazardMaps | None:
    """The hazard maps of a finished 2D run (a :class:`~conslaw.result2d.RunResult2D`), or
    None if its model has no terrain or no depth.

    Parameters
    ----------
    result : RunResult2D

    Returns
    -------
    HazardMaps or None
    """
    model, grid, peaks = result.model, result.grid, result.peaks
    if peaks is None:
        return None
    dem = model.scene_dem(grid)
    if dem is None:
        return None
    final = result.states[-1] if result.states else result.initial
    initial_fields = model.flow_depth_and_speed(result.initial.q, peaks.aux)
    final_fields = model.flow_depth_and_speed(final.q, peaks.aux)
    assert initial_fields is not None and final_fields is not None
    released = initial_fields[0] >= REACHED_DEPTH
    fields = [
        HazardField("peak_depth", peaks.depth, "peak flow depth (normal to the slope)", "m"),
        HazardField("peak_speed", peaks.speed, "peak speed", "m/s"),
    ]
    density = getattr(model.params, "density", None)
    if density is not None:
        fields.append(
            HazardField(
                "peak_pressure", peaks.pressure(density), f"peak pressure rho |U|^2, rho = "
                f"{density:g} kg/m^3", "kPa",
            )
        )  # fmt: skip
    fields.append(HazardField("deposit", final_fields[0], f"flow depth at t = {final.t:g} s", "m"))
    elevation = np.asarray(dem.elevation)
    reach = run_out(grid, elevation, released, peaks.depth)
    area = grid.cell_area
    summary: dict[str, Any] = {
        "t_end": float(final.t),
        "reached_depth_m": REACHED_DEPTH,
        "runout_length_m": None if reach is None else reach.length,
        "drop_m": None if reach is None else reach.drop,
        "travel_angle_deg": None if reach is None else reach.alpha,
        "runout_end_xy_m": None if reach is None else list(reach.end),
        "volume_initial_m3": float(np.sum(result.initial.q[0]) * area),
        "volume_final_m3": float(np.sum(final.q[0]) * area),
        "moving_cells_at_end": int(np.count_nonzero(final_fields[1])),
        **{f"max_{field.stem}": float(np.max(field.values)) for field in fields},
    }
    return HazardMaps(dem, released, tuple(fields), summary)


def hazard_files(maps: HazardMaps, folder: Path, geotiff: bool) -> dict[Path, bytes]:
    """The files of the maps: ``hazard.json`` and, with ``geotiff``, ``<stem>.tif`` for each
    map (the terrain's transform and CRS).

    Parameters
    ----------
    maps : HazardMaps
    folder : Path
    geotiff : bool

    Returns
    -------
    dict
        Path -> bytes, to be put in place together.
    """
    files: dict[Path, bytes] = {}
    dem = maps.dem
    if geotiff:
        for field in maps.fields:
            path = folder / f"{field.stem}.tif"
            files[path] = geotiff_bytes(
                field.values, (dem.x_min, dem.y_min), dem.cell_size, dem.crs,
                name=field.name, units=field.units, where=f"GeoTIFF '{path}'",
            )  # fmt: skip
    text = json.dumps(maps.summary, indent=2, sort_keys=True) + "\n"
    files[folder / "hazard.json"] = text.encode()
    return files


def hazard_output_files(result: Any, folder: Path, formats: tuple[str, ...]) -> dict[Path, bytes]:
    """The hazard files of a finished run for its run folder (empty without hazard maps):
    ``hazard.json``, and the GeoTIFFs if ``"geotiff"`` is in ``formats``
    (:func:`hazard_files`).

    Parameters
    ----------
    result : RunResult2D
    folder : Path
    formats : tuple of str
        The scene's ``output.formats``.

    Returns
    -------
    dict
        Path -> bytes.
    """
    maps = hazard_maps(result)
    if maps is None:
        return {}
    return hazard_files(maps, folder, "geotiff" in formats)
