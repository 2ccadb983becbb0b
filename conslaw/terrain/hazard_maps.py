"""Hazard maps of a 2D run on terrain (docs/output.md, "Hazard maps"): the peak flow depth,
peak speed and peak pressure of every cell over the run (:mod:`conslaw.peak_fields`, updated
after every step pair), the deposit (the flow depth at the end), the run-out and travel angle;
as GeoTIFFs with the terrain's georeference, PNG maps over a hillshade, and ``hazard.json``.

The GeoTIFFs are float32 and hold a value only where the flow reached (the ``reached`` cells of
:func:`hazard_maps`; the deposit where flow is left at the end), :data:`NODATA` elsewhere,
declared as the band's no-data value.

A run has hazard maps when its model gives a terrain on the run's cells
(``Model.scene_dem``) and a flow depth (``Model.flow_depth_and_speed``).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.grid2d import Grid2D
from conslaw.peak_fields import REACHED_DEPTH
from conslaw.terrain.animation import flow_depth_gif
from conslaw.terrain.dem import DigitalElevationModel
from conslaw.terrain.raster import geotiff_bytes

Array = NDArray[np.float64]


#: The no-data value of the hazard GeoTIFFs, where the flow did not reach: a finite sentinel
#: (the form of declared no-data GIS tools honour most widely; NaN is not taken as no-data by
#: every GIS), exact in float32, and below every value a map can hold (they are all >= 0).
NODATA = -9999.0

#: Speed (m/s) above which a cell of flow at least REACHED_DEPTH deep counts as moving at the
#: end of a run (``moving_cells_at_end`` of hazard.json).
MOVING_SPEED = 1e-3


@dataclass(frozen=True)
class RunOut:
    """Where the flow went, on a straight line from the top of the release.

        ``top``: the centroid of the highest released cells; ``end``: the reached cell (peak depth
        at least :data:`~conslaw.peak_fields.REACHED_DEPTH` above the initial layer) farthest from
        ``top`` along the direction from ``top`` to the deposit's centre of mass (of several equally
    far, the one nearest that line); ``length``: the
        horizontal distance from ``top`` to ``end``; ``drop``: the elevation of ``top`` above
        ``end``; ``alpha``: the travel angle ``atan(drop / length)`` in degrees (Heim's
        Fahrböschung; Lied & Bakkehøi 1980).
    """

    top: tuple[float, float]
    end: tuple[float, float]
    length: float
    drop: float
    alpha: float


def run_out(
    grid: Grid2D,
    elevation: Array,
    released: NDArray[np.bool_],
    reached: NDArray[np.bool_],
    deposit: Array,
) -> RunOut | None:
    """The run-out and travel angle of a run (:class:`RunOut`), or None if nothing was
    released or reached or nothing is left.

    Parameters
    ----------
    grid : Grid2D
    elevation : numpy.ndarray
        ``(ny, nx)`` terrain elevation at the cell centres, m.
    released, reached : numpy.ndarray of bool
        The released cells, and those the flow reached.
    deposit : numpy.ndarray
        ``(ny, nx)`` flow depth at the end, for the direction of travel.

    Returns
    -------
    RunOut or None
    """
    if not released.any() or not reached.any() or not np.sum(deposit) > 0.0:
        return None
    x, y = grid.centres()
    x_cells, y_cells = np.meshgrid(x, y)
    highest = np.max(elevation[released])
    tops = released & (elevation >= highest - 1e-9 * max(abs(highest), 1.0))
    top = np.array([x_cells[tops].mean(), y_cells[tops].mean()])
    z_top = float(np.mean(elevation[tops]))
    weight = deposit / np.sum(deposit)
    heading = np.array([np.sum(weight * x_cells), np.sum(weight * y_cells)]) - top
    size = float(np.hypot(*heading))
    if size == 0.0:
        return None
    heading /= size
    along = (x_cells - top[0]) * heading[0] + (y_cells - top[1]) * heading[1]
    across = np.abs((y_cells - top[1]) * heading[0] - (x_cells - top[0]) * heading[1])
    farthest = np.max(along[reached])
    # Of the reached cells equally far along, the one nearest the line of travel.
    ends = reached & (along >= farthest - 1e-9 * max(abs(farthest), 1.0))
    far = np.unravel_index(np.argmin(np.where(ends, across, np.inf)), along.shape)
    end = (float(x_cells[far]), float(y_cells[far]))
    length = float(np.hypot(end[0] - top[0], end[1] - top[1]))
    drop = z_top - float(elevation[far])
    alpha = math.degrees(math.atan2(drop, length)) if length > 0.0 else 90.0
    return RunOut((float(top[0]), float(top[1])), end, length, drop, alpha)


@dataclass(frozen=True)
class HazardField:
    """One map: its file stem, its values on the run's cells, its name and units, and the
    cells where it has a value in its GeoTIFF (``valid``; :data:`NODATA` elsewhere)."""

    stem: str
    values: Array
    name: str
    units: str
    valid: NDArray[np.bool_]

    def geotiff_values(self) -> NDArray[np.float32]:
        """The values as the GeoTIFF holds them: float32, :data:`NODATA` outside ``valid``.

        Returns
        -------
        numpy.ndarray of float32
            ``(ny, nx)``.
        """
        return np.where(self.valid, self.values, NODATA).astype(np.float32)


@dataclass(frozen=True)
class HazardMaps:
    """The maps of a run, its terrain on the run's cells, its released cells and the cells the
    flow reached (peak flow depth at least
    :data:`~conslaw.peak_fields.REACHED_DEPTH` above any layer that covered the whole domain at
    the start)."""

    dem: DigitalElevationModel
    released: NDArray[np.bool_]
    reached: NDArray[np.bool_]
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
    # A layer everywhere at the start (a thin layer) is neither release nor reach.
    layer = float(np.min(initial_fields[0]))
    released = initial_fields[0] >= layer + REACHED_DEPTH
    reached = peaks.depth >= layer + REACHED_DEPTH
    left = final_fields[0] >= layer + REACHED_DEPTH
    fields = [
        HazardField(
            "peak_depth", peaks.depth, "peak flow depth (normal to the slope)", "m", reached
        ),
        HazardField("peak_speed", peaks.speed, "peak speed", "m/s", reached),
    ]
    density = getattr(model.params, "density", None)
    if density is not None:
        fields.append(
            HazardField(
                "peak_pressure", peaks.pressure(density), f"peak pressure rho |U|^2, rho = "
                f"{density:g} kg/m^3", "kPa", reached,
            )
        )  # fmt: skip
    fields.append(
        HazardField("deposit", final_fields[0], f"flow depth at t = {final.t:g} s", "m", left)
    )
    elevation = np.asarray(dem.elevation)
    reach = run_out(grid, elevation, released, reached, final_fields[0] - layer)
    area = grid.cell_area
    moving = left & (final_fields[1] > MOVING_SPEED)
    summary: dict[str, Any] = {
        "t_end": float(final.t),
        "reached_depth_m": REACHED_DEPTH,
        "reached_cells": int(np.count_nonzero(reached)),
        "crs": dem.crs,
        "geotiff_nodata": NODATA,
        "runout_length_m": None if reach is None else reach.length,
        "drop_m": None if reach is None else reach.drop,
        "travel_angle_deg": None if reach is None else reach.alpha,
        "runout_end_xy_m": None if reach is None else list(reach.end),
        "release_top_xy_m": None if reach is None else list(reach.top),
        "volume_initial_m3": float(np.sum(result.initial.q[0]) * area),
        "volume_final_m3": float(np.sum(final.q[0]) * area),
        "moving_cells_at_end": int(np.count_nonzero(moving)),
        "moving_speed_m_s": MOVING_SPEED,
        **{f"max_{field.stem}": float(np.max(field.values)) for field in fields},
    }
    if result.stop is not None:
        summary["stop"] = result.stop.to_dict()
    return HazardMaps(dem, released, reached, tuple(fields), summary)


def hazard_files(maps: HazardMaps, folder: Path, geotiff: bool) -> dict[Path, bytes]:
    """The files of the maps: ``hazard.json`` and, with ``geotiff``, ``<stem>.tif`` for each
    map: float32, the terrain's transform and CRS, :data:`NODATA` (declared) outside the
    map's ``valid`` cells (:meth:`HazardField.geotiff_values`).

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
                field.geotiff_values(), (dem.x_min, dem.y_min), dem.cell_size, dem.crs,
                name=field.name, units=field.units, nodata=NODATA, where=f"GeoTIFF '{path}'",
            )  # fmt: skip
    text = json.dumps(maps.summary, indent=2, sort_keys=True) + "\n"
    files[folder / "hazard.json"] = text.encode()
    return files


def hazard_output_files(result: Any, folder: Path, formats: tuple[str, ...]) -> dict[Path, bytes]:
    """The hazard files of a finished run for its run folder (empty without hazard maps):
    ``hazard.json``, the GeoTIFFs if ``"geotiff"`` is in ``formats`` (:func:`hazard_files`),
    and ``flow_depth.gif`` if ``"gif"`` is (:func:`~conslaw.terrain.animation.flow_depth_gif`).

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
    files = hazard_files(maps, folder, "geotiff" in formats)
    if "gif" in formats:
        files[folder / "flow_depth.gif"] = flow_depth_gif(result, maps.dem, maps.released)
    return files


def terrain_run_notes(result: Any, formats: tuple[str, ...]) -> list[str]:
    """What ``conslaw run`` tells of a finished run on terrain, one line each (none for a model
    without a terrain): which quantity the states hold, and, when GeoTIFFs are written from a
    terrain without a CRS (a formula, or a DEM file without one), that they carry none.

    Parameters
    ----------
    result : RunResult2D
    formats : tuple of str
        The scene's ``output.formats``.

    Returns
    -------
    list of str
    """
    model = result.model
    dem = model.scene_dem(result.grid)
    if dem is None:
        return []
    name = model.variables[0]
    notes = [
        f"the states' {name} (states.npz q[:, 0]) is the {model.long_names.get(name, name)}; "
        "the hazard maps' flow depth is the thickness normal to the slope"
    ]
    if "geotiff" in formats and dem.crs is None:
        dem_file = getattr(model.params, "dem_file", "")
        source = f"DEM file '{dem_file}' has none" if dem_file else "a terrain formula has none"
        notes.append(
            f"the hazard GeoTIFFs carry no CRS ({source}): a GIS takes their coordinates as "
            "metres in an unknown projection"
        )
    return notes
