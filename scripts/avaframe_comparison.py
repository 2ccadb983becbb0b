"""AvaFrame's com1DFA and conslaw's ``savage-hutter-terrain`` side by side on one hockey stick.

The same terrain (AvaFrame's generated hockey stick: a plane turning through a circular arc into
a flat run-out), the same release polygon, 1 m thick normal to the slope, and the same Coulomb
friction ``mu = tan(30 deg)`` (AvaFrame's ``frictModel = Coulomb``, ``mucoulomb``; conslaw's
``delta = phi = 30`` with ``earth_pressure = "isotropic"``, K = 1 like AvaFrame's hydrostatic
pressure), no entrainment, no resistance. Both runs are measured the same way from their peak
flow-thickness rasters (:func:`runout_metrics`).

Two steps from a clean checkout, each in its own environment (AvaFrame brings numpy 1.26,
geopandas and more, which stay out of the project's virtual environment)::

    # 1. AvaFrame (PyPI) in a separate venv: terrain, release, com1DFA run (about 10 s)
    python3 -m venv /tmp/avaenv
    /tmp/avaenv/bin/pip install avaframe            # measured with avaframe 2.1
    /tmp/avaenv/bin/python scripts/avaframe_comparison.py avaframe --dir /tmp/ava_hockey

    # 2. conslaw (the project's venv) on the DEM and release of step 1, then the table
    #    (about 2 minutes on 2 cores)
    python3 -m venv .venv && . .venv/bin/activate && pip install .
    python scripts/avaframe_comparison.py compare --dir /tmp/ava_hockey \\
        --out /tmp/ava_hockey/conslaw --table /tmp/ava_hockey/table.md

Step 1 fills ``DIR`` with AvaFrame's folder layout: ``Inputs/DEM_HS_Topo.asc`` (from
``in3Utils.generateTopo`` with :data:`TOPO`), ``Inputs/REL/release.shp`` (:data:`RELEASE`, no
``.prj``: the generated DEM has no CRS), ``Outputs/com1DFA/peakFiles/*_pft.*`` (peak flow
thickness) and ``*_FT.*`` (thickness at the stop), and ``avaframe_run.json`` (version, wall-clock
seconds, simulated end time, stop reason). Step 2 writes ``conslaw_scene.toml`` into ``DIR``
(``dem_file`` and ``release_file`` point at step 1's inputs), runs it into ``--out`` (its report
in ``OUT.log``, its wall clock in ``OUT.seconds``) and prints the markdown table (also to
``--table``).

The timing of docs/validation.md ("The hockey stick at AvaFrame's HS defaults, timed"), in the
project's venv, on a topography of ``scripts/avaframe_topographies.py`` (:func:`timing`)::

    python scripts/avaframe_comparison.py timing --topography /tmp/avatopo/HS \\
        --dir /tmp/avatime/run --rounds 2 --table /tmp/avatime/table.md

conslaw at twice the DEM's cell size first (it warms the kernel cache and is the
grid-independence run), then A B rounds: com1DFA (``avaframe-topography`` through
``--avaframe-python``, default ``/tmp/avaenv/bin/python``) and ``conslaw run`` on the DEM's own
cells, both stopping at rest (1 % of the peak kinetic energy; conslaw's outputs every
``--interval`` = 5 s), with the load averages before and after each run.

Only the standard library and numpy are imported at the top, so the file runs in both
environments; ``avaframe`` is imported by step 1 only, ``conslaw``, ``rasterio`` and
``shapely`` by step 2 only.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

#: Bed friction angle (degrees) of both runs: AvaFrame's ``mucoulomb = tan(DELTA)``.
DELTA = 30.0
#: Release thickness normal to the slope (m), AvaFrame's ``relTh``, conslaw's ``thickness``.
THICKNESS = 1.0
#: Bulk density (kg/m^3): AvaFrame's default ``rho``; conslaw's only for the peak pressure.
DENSITY = 200.0
#: ``in3Utils/generateTopoCfg.ini`` overrides, ``[TOPO]``: a 34-degree plane from z0 = 1000 m
#: turning through an arc of 200 m into a flat run-out at z = 0 (x1 = z0 / tan 34 = 1483 m from
#: the top), 2200 m x 800 m, 5 m cells, no channel.
TOPO = {
    "demType": "HS",
    "dx": "5.",
    "xEnd": "2200",
    "yEnd": "800",
    "meanAlpha": "34",
    "z0": "1000",
    "rCirc": "200",
    "channel": "False",
}
#: ``[DEMDATA]`` of generateTopo (its defaults): the lower-left cell centre of the DEM (m).
DEM_ORIGIN = (1000.0, -5000.0)
#: The release polygon in map coordinates: 200 m along x (generator x 200..400, on the plane,
#: z = 865..730 m) by 200 m across the centre line, on cell edges (centres at 1000 + 5 k),
#: clockwise (a shapefile's outer ring).
RELEASE = ((1197.5, -4602.5), (1197.5, -4402.5), (1397.5, -4402.5), (1397.5, -4602.5))
#: Peak flow thickness (m) from which a cell counts as reached (conslaw's ``REACHED_DEPTH``) and
#: a stricter one, to show how much the margins weigh.
THRESHOLDS = (0.01, 0.1)
#: conslaw's simulated time (s), with an output every 10 s: longer than AvaFrame's stop (73.6 s
#: with avaframe 2.1); conslaw's flow is at rest by 80 s (:func:`conslaw_stop_time`).
CONSLAW_T_END = 90.0
#: com1DFA's default ``tEnd`` (s): the cap of a run that stops at rest.
AVAFRAME_T_END = 400.0


def _avaframe_inputs(folder: Path) -> None:
    """AvaFrame's folder layout, its hockey-stick DEM and the release shapefile in ``folder``."""
    import shapefile  # pyshp, an AvaFrame dependency
    from avaframe.in3Utils import cfgUtils, generateTopo, initializeProject

    initializeProject.initializeFolderStruct(str(folder), removeExisting=True)
    topo = cfgUtils.getModuleConfig(generateTopo, onlyDefault=True, toPrint=False)
    for key, value in TOPO.items():
        topo["TOPO"][key] = value
    topo["DEMDATA"]["xl"], topo["DEMDATA"]["yl"] = (str(v) for v in DEM_ORIGIN)
    generateTopo.generateTopo(topo, folder)
    with shapefile.Writer(str(folder / "Inputs" / "REL" / "release")) as writer:
        writer.field("name", "C", 40)
        writer.field("thickness", "N", decimal=4)
        writer.poly([[*RELEASE, RELEASE[0]]])
        writer.record("release", THICKNESS)


def _avaframe_config() -> Any:
    """com1DFA's default configuration with Coulomb friction, the release thickness from the
    configuration, no entrainment, resistance, secondary release or dam."""
    from avaframe.com1DFA import com1DFA
    from avaframe.in3Utils import cfgUtils

    cfg = cfgUtils.getModuleConfig(com1DFA, onlyDefault=True, toPrint=False)
    general = cfg["GENERAL"]
    general["simTypeList"] = "null"
    general["frictModel"] = "Coulomb"
    general["mucoulomb"] = repr(math.tan(math.radians(DELTA)))
    general["relThFromFile"] = "False"
    general["relTh"] = repr(THICKNESS)
    general["rho"] = repr(DENSITY)
    general["secRelArea"] = "False"
    general["dam"] = "False"
    general["resType"] = "ppr|pft|pfv|FT"
    return cfg


def run_avaframe(folder: Path) -> dict[str, Any]:
    """Generate the inputs and run com1DFA in ``folder``; write ``avaframe_run.json``.

    Parameters
    ----------
    folder : Path
        The avalanche directory (emptied first).

    Returns
    -------
    dict
        ``version``, ``seconds`` (wall clock of ``com1DFAMain``, plots and report off),
        ``t_end_s`` (simulated time at the stop) and ``stop`` (AvaFrame's reason).
    """
    _avaframe_inputs(folder)
    run = _com1dfa(folder)
    run.update({"topo": TOPO, "release": RELEASE})
    (folder / "avaframe_run.json").write_text(json.dumps(run, indent=2) + "\n")
    return run


def _com1dfa(folder: Path) -> dict[str, Any]:
    """com1DFA with :func:`_avaframe_config` on the inputs in ``folder``, timed; the keys of
    ``avaframe_run.json`` but the inputs'."""
    from importlib.metadata import version

    from avaframe.com1DFA import com1DFA
    from avaframe.in3Utils import cfgUtils

    main = cfgUtils.getGeneralConfig()
    main["MAIN"]["avalancheDir"] = str(folder)
    main["FLAGS"]["savePlot"] = "False"
    main["FLAGS"]["createReport"] = "False"
    started = time.perf_counter()
    _, _, reports, _ = com1DFA.com1DFAMain(main, cfgInfo=_avaframe_config())
    seconds = time.perf_counter() - started
    parameters = reports[0]["Simulation Parameters"]
    run = {
        "version": version("avaframe"),
        "seconds": seconds,
        "t_end_s": float(parameters["Process run time [s]"]),
        "stop": parameters["Stop criterion"],
        "compute_seconds": float(parameters["Computation time [s]"]),
        "mucoulomb": math.tan(math.radians(DELTA)),
    }
    return run


def run_avaframe_topography(folder: Path, topography: Path) -> dict[str, Any]:
    """com1DFA (:func:`_avaframe_config`) on a topography of ``scripts/avaframe_topographies.py``
    (its ``DEM_*_Topo.asc`` and ``release1*.shp``, copied into AvaFrame's folder layout in
    ``folder``, emptied first); write ``avaframe_run.json``.

    Parameters
    ----------
    folder : Path
        The avalanche directory.
    topography : Path
        One topography's folder, e.g. ``/tmp/avatopo/HS``.

    Returns
    -------
    dict
        As :func:`run_avaframe`, with ``dem_file`` and ``release_file`` instead of the
        generator's settings.
    """
    import shutil

    from avaframe.in3Utils import initializeProject

    initializeProject.initializeFolderStruct(str(folder), removeExisting=True)
    dem = _one(topography, "DEM_*_Topo.asc")
    shutil.copyfile(dem, folder / "Inputs" / dem.name)
    release = _one(topography, "release1*.shp")
    for suffix in (".shp", ".shx", ".dbf"):
        shutil.copyfile(release.with_suffix(suffix), folder / "Inputs" / "REL" / f"release{suffix}")
    run = _com1dfa(folder)
    run.update({"dem_file": str(dem), "release_file": str(release)})
    (folder / "avaframe_run.json").write_text(json.dumps(run, indent=2) + "\n")
    return run


@dataclass(frozen=True)
class Raster:
    """A single-band raster read north-up: ``values[row, col]`` at the cell centres ``x[col]``,
    ``y[row]``; ``cell`` the (square) cell size in m."""

    values: Array
    x: Array
    y: Array
    cell: float


def read_raster(path: Path) -> Raster:
    """The first band of a GeoTIFF or ESRI ASCII grid (AvaFrame's peak files, conslaw's
    hazard maps, the DEM), nodata as 0.

    Parameters
    ----------
    path : Path

    Returns
    -------
    Raster
    """
    import rasterio

    with rasterio.open(path) as source:
        values = source.read(1, masked=True).filled(0.0).astype(np.float64)
        t = source.transform
    if abs(t.a) != abs(t.e) or t.b != 0.0 or t.d != 0.0:
        raise ValueError(f"{path}: cells not square and north-up ({t})")
    x = t.c + (np.arange(values.shape[1]) + 0.5) * t.a
    y = t.f + (np.arange(values.shape[0]) + 0.5) * t.e
    return Raster(values, x, y, abs(t.a))


def release_mask(polygon_file: Path, dem: Raster) -> NDArray[np.bool_]:
    """The DEM cells whose centres lie inside the polygons of ``polygon_file`` (the rule both
    codes use to seed a release).

    Parameters
    ----------
    polygon_file : Path
        A shapefile, GeoPackage or GeoJSON in the DEM's coordinates.
    dem : Raster

    Returns
    -------
    numpy.ndarray of bool
        ``(ny, nx)``.
    """
    import pyogrio.raw
    import shapely

    _, _, wkb, _ = pyogrio.raw.read(polygon_file, force_2d=True)
    area = shapely.union_all(shapely.from_wkb(wkb))
    xx, yy = np.meshgrid(dem.x, dem.y)
    return np.asarray(shapely.contains_xy(area, xx, yy), dtype=bool)


def runout_metrics(
    peak_depth: Raster,
    dem: Raster,
    release: NDArray[np.bool_],
    threshold: float = 0.01,
    direction: tuple[float, float] = (1.0, 0.0),
) -> dict[str, float]:
    """Run-out and travel angle of one run from its peak flow thickness, measured the same
    way for every code.

    The top is the centroid of the highest released cells; the end is the reached cell (peak
    thickness at least ``threshold``) farthest from the top along ``direction``, of several
    equally far the one nearest the line through the top; ``length`` is the horizontal distance
    from the top to the end, ``drop`` the elevation of the top above the end, ``alpha =
    atan(drop / length)`` (Heim's Fahrböschung).

    Parameters
    ----------
    peak_depth : Raster
        Peak flow thickness (m) on the DEM's cells.
    dem : Raster
        Elevation (m).
    release : numpy.ndarray of bool
        The released cells.
    threshold : float
        Peak thickness (m) from which a cell counts as reached.
    direction : tuple of float
        The main direction of travel in map coordinates (+x for the hockey stick).

    Returns
    -------
    dict
        ``top_x``, ``top_y``, ``end_x``, ``end_y``, ``length_m``, ``drop_m``, ``alpha_deg``,
        ``area_ha`` (area of the reached cells, map projection).
    """
    if peak_depth.values.shape != dem.values.shape or not np.allclose(peak_depth.x, dem.x):
        raise ValueError("the peak raster is not on the DEM's cells")
    xx, yy = np.meshgrid(dem.x, dem.y)
    z = dem.values
    highest = z[release].max()
    tops = release & (z >= highest - 1e-9 * max(abs(highest), 1.0))
    top = np.array([xx[tops].mean(), yy[tops].mean()])
    heading = np.asarray(direction, dtype=np.float64) / math.hypot(*direction)
    along = (xx - top[0]) * heading[0] + (yy - top[1]) * heading[1]
    across = np.abs((yy - top[1]) * heading[0] - (xx - top[0]) * heading[1])
    reached = peak_depth.values >= threshold
    farthest = along[reached].max()
    ends = reached & (along >= farthest - 1e-9 * max(abs(farthest), 1.0))
    end = np.unravel_index(np.argmin(np.where(ends, across, np.inf)), z.shape)
    length = math.hypot(xx[end] - top[0], yy[end] - top[1])
    drop = float(z[tops].mean() - z[end])
    return {
        "top_x": float(top[0]),
        "top_y": float(top[1]),
        "end_x": float(xx[end]),
        "end_y": float(yy[end]),
        "length_m": length,
        "drop_m": drop,
        "alpha_deg": math.degrees(math.atan2(drop, length)),
        "area_ha": float(reached.sum()) * dem.cell**2 / 1e4,
    }


def overlap(a: Raster, b: Raster, threshold: float) -> float:
    """Intersection over union of the cells where each peak thickness is at least
    ``threshold``.

    Parameters
    ----------
    a, b : Raster
        Peak flow thickness on the same cells.
    threshold : float

    Returns
    -------
    float
    """
    first, second = a.values >= threshold, b.values >= threshold
    return float(np.sum(first & second) / np.sum(first | second))


def centre_of_mass(thickness: Raster, dem: Raster) -> tuple[float, float, float]:
    """``(x, y, z)`` of the centre of mass of a layer of slope-normal ``thickness`` (weighted
    by the volume per map area, thickness over the cosine of the DEM's slope).

    Parameters
    ----------
    thickness : Raster
    dem : Raster

    Returns
    -------
    tuple of float
    """
    z_y, z_x = np.gradient(dem.values, dem.y, dem.x)
    weight = thickness.values * np.sqrt(1.0 + z_x**2 + z_y**2)
    xx, yy = np.meshgrid(dem.x, dem.y)
    total = weight.sum()
    return (
        float((weight * xx).sum() / total),
        float((weight * yy).sum() / total),
        float((weight * dem.values).sum() / total),
    )


def _scene_extent(dem: Any, cell: float | None) -> dict[str, Any]:
    """The scene keys of the grid: the DEM's own cells, or cells of ``cell`` m over the extent
    of its cell centres."""
    if cell is None:
        half = 0.5 * dem.cell
        return {
            "n_cells": [dem.x.size, dem.y.size],
            "x_min": float(dem.x[0] - half),
            "x_max": float(dem.x[-1] + half),
            "y_min": float(dem.y[-1] - half),
            "y_max": float(dem.y[0] + half),
        }
    return {
        "n_cells": [round((dem.x[-1] - dem.x[0]) / cell), round((dem.y[0] - dem.y[-1]) / cell)],
        "x_min": float(dem.x[0]),
        "x_max": float(dem.x[-1]),
        "y_min": float(dem.y[-1]),
        "y_max": float(dem.y[0]),
    }


def _scene_timing(at_rest: float | None) -> dict[str, Any]:
    """The scene keys of time: :data:`CONSLAW_T_END` with an output every 10 s, or a stop at
    rest checked every ``at_rest`` seconds with AvaFrame's ``tEnd`` as the cap."""
    if at_rest is None:
        return {
            "t_end": CONSLAW_T_END,
            "output_times": [float(t) for t in np.arange(10.0, CONSLAW_T_END + 1.0, 10.0)],
        }
    return {
        "t_end": AVAFRAME_T_END,
        "output_interval": at_rest,
        "stop": {"at_rest": True, "energy_fraction": 0.01},
    }


def conslaw_scene(
    folder: Path,
    dem_file: Path,
    release_file: Path,
    cell: float | None = None,
    at_rest: float | None = None,
    name: str = "conslaw_scene",
) -> Path:
    """Write ``NAME.toml`` into ``folder``: ``savage-hutter-terrain`` on the DEM's own cells,
    ``delta = phi = DELTA``, isotropic pressure, the release polygon ``THICKNESS`` thick normal
    to the slope, outflow sides, :data:`CONSLAW_T_END` seconds with an output every 10 s.

    Parameters
    ----------
    folder : Path
    dem_file, release_file : Path
        AvaFrame's generated DEM and the release shapefile of step 1.
    cell : float, optional
        Cells of this size (m) over the extent of the DEM's cell centres (a multiple of the
        size) instead of the DEM's own cells.
    at_rest : float, optional
        Stop at rest (``[stop] at_rest``, kinetic energy 1 % of its peak at an output time) with
        an output every ``at_rest`` seconds and AvaFrame's ``tEnd`` (400 s) as the cap.
    name : str
        The scene file's stem.

    Returns
    -------
    Path
        The scene file.
    """
    import tomli_w

    dem = read_raster(dem_file)
    extent, timing = _scene_extent(dem, cell), _scene_timing(at_rest)
    scene = {
        "description": f"AvaFrame's {dem_file.stem} (scripts/avaframe_comparison.py), "
        f"Coulomb {DELTA:g} deg",
        "model": "savage-hutter-terrain",
        "scheme": "jiang-tadmor",
        "reconstructor": "mc",
        "cfl": 0.45,
        **extent,
        **timing,
        "exact": False,
        "parameters": {
            "phi": DELTA,
            "delta": DELTA,
            "earth_pressure": "isotropic",
            "density": DENSITY,
            "terrain": "dem",
            "dem_file": str(dem_file),
        },
        "boundary": dict.fromkeys(("left", "right", "bottom", "top"), "outflow"),
        "initial": {
            "kind": "release",
            "thickness": THICKNESS,
            "measured": "normal",
            "release_file": str(release_file),
        },
        "output": {"formats": ["npz", "geotiff"], "plot": False},
    }
    path = folder / f"{name}.toml"
    path.write_text(tomli_w.dumps(scene))
    return path


def run_conslaw(scene: Path, out: Path) -> float:
    """``python -m conslaw run scene --out out`` in this interpreter, its report in
    ``out.with_suffix(".log")``; its wall-clock seconds.

    Parameters
    ----------
    scene, out : Path

    Returns
    -------
    float
    """
    command = [sys.executable, "-m", "conslaw", "run", str(scene), "--out", str(out)]
    started = time.perf_counter()
    with out.with_suffix(".log").open("w") as log:
        subprocess.run(command, check=True, stdout=log)
    return time.perf_counter() - started


def conslaw_stop_time(states: Path) -> float:
    """The first output time at which no cell at least 0.01 m deep moves faster than 1 mm/s
    (hazard.json's ``moving_cells_at_end`` rule), ``inf`` if none.

    Parameters
    ----------
    states : Path
        The run's ``states.npz``.

    Returns
    -------
    float
    """
    with np.load(states) as saved:
        times, q = saved["t"], saved["q"]
    for t, (volume, hu, hv) in zip(times, q, strict=True):
        speed = np.hypot(hu, hv) / np.maximum(volume, 1e-12)
        if not np.any((volume >= 0.01) & (speed > 1e-3)):
            return float(t)
    return math.inf


def point_references(dem: Raster, release: NDArray[np.bool_]) -> dict[str, float]:
    """Where a point with Coulomb friction ``tan(DELTA)`` released at rest stops on the hockey
    stick's profile (conslaw's :class:`~conslaw_models.terrain_surface.PlaneToFlat` with
    :data:`TOPO`'s angle and radius is the same plane, arc and flat): from the top of the
    release, by the classical energy line (no curvature) and sliding with the arc's centripetal
    friction; and the mean stop of the released columns (the centre of mass of a deposit
    without pressure).

    Parameters
    ----------
    dem : Raster
    release : numpy.ndarray of bool

    Returns
    -------
    dict
        ``top_energy_line_x``, ``top_sliding_x``, ``columns_sliding_x`` (map x, m).
    """
    from conslaw_models.sliding_point import energy_line_stop, sliding_stop
    from conslaw_models.terrain_surface import PlaneToFlat

    angle, radius = float(TOPO["meanAlpha"]), float(TOPO["rCirc"])
    x1 = float(TOPO["z0"]) / math.tan(math.radians(angle))
    end = DEM_ORIGIN[0] + x1 + radius * math.tan(math.radians(angle / 2.0))
    surface = PlaneToFlat(angle, radius, end)
    mu = math.tan(math.radians(DELTA))
    columns = np.unique(np.meshgrid(dem.x, dem.y)[0][release])
    profile = surface.derivatives(dem.x, np.zeros_like(dem.x))[0]
    misfit = float(np.max(np.abs(profile - dem.values[dem.y.size // 2])))
    return {
        "top_energy_line_x": energy_line_stop(surface, float(columns[0]), mu),
        "top_sliding_x": sliding_stop(surface, float(columns[0]), mu, 9.81),
        "columns_sliding_x": float(np.mean([sliding_stop(surface, c, mu, 9.81) for c in columns])),
        "profile_misfit_m": misfit,
    }


def _rows(pair: dict[str, Any], ava: dict[str, Any], run: dict[str, Any]) -> list[str]:
    """The rows of the side-by-side table (``pair``: per code, the measures of :func:`measure`;
    ``run``: conslaw's ``seconds``, ``steps``, ``solve_seconds``, ``stop_s``, ``t_end``)."""
    a, c = pair["avaframe"], pair["conslaw"]

    def row(name: str, key: str, digits: int) -> str:
        diff = c[key] - a[key]
        return f"| {name} | {a[key]:.{digits}f} | {c[key]:.{digits}f} | {diff:+.{digits}f} |"

    rows = []
    centre = a[f"top_y@{THRESHOLDS[0]}"]
    for threshold in THRESHOLDS:
        t = f"{threshold:g} m"
        rows += [
            row(f"run-out end x, peak thickness >= {t} (m)", f"end_x@{threshold}", 1),
            row(f"run-out end y, >= {t} (centre line {centre:.1f}) (m)", f"end_y@{threshold}", 1),
            row(f"run-out length from the release top, >= {t} (m)", f"length_m@{threshold}", 1),
            row(f"travel angle alpha, >= {t} (deg)", f"alpha_deg@{threshold}", 2),
            row(f"affected area, >= {t} (ha)", f"area_ha@{threshold}", 2),
            f"| overlap of the areas >= {t} (intersection / union) | "
            f"{pair['iou'][threshold]:.3f} | | |",
        ]
    rows += [
        row("deposit centre of mass x (m)", "deposit_x", 1),
        row("centre-of-mass travel angle (deg)", "alpha_cm_deg", 2),
        row("largest peak flow thickness (m)", "max_peak", 2),
        f"| simulated time at the stop (s) | {ava['t_end_s']:.1f} ({ava['stop']}) | "
        f"<= {run['stop_s']:.0f} (first output at rest; run to {run['t_end']:.0f}) | |",
        f"| wall-clock run time (s) | {ava['seconds']:.1f} (com1DFAMain; its DFA loop "
        f"{ava['compute_seconds']:.1f}) | {run['seconds']:.1f} (conslaw run; solve "
        f"{run['solve_seconds']:.1f}, {run['steps']} steps) | |",
    ]
    return rows


def measure(
    peak: Raster, deposit: Raster, dem: Raster, release: NDArray[np.bool_]
) -> dict[str, float]:
    """The measures of one run: :func:`runout_metrics` at each of :data:`THRESHOLDS` (keys
    ``name@threshold``), the deposit's centre of mass and its travel angle from the release's
    centre of mass, the largest peak thickness.

    Parameters
    ----------
    peak, deposit : Raster
        Peak flow thickness and the thickness at the end (m).
    dem : Raster
    release : numpy.ndarray of bool

    Returns
    -------
    dict
    """
    found: dict[str, float] = {"max_peak": float(peak.values.max())}
    for threshold in THRESHOLDS:
        for key, value in runout_metrics(peak, dem, release, threshold).items():
            found[f"{key}@{threshold}"] = value
    layer = np.where(release, THICKNESS, 0.0)
    start = centre_of_mass(Raster(layer, dem.x, dem.y, dem.cell), dem)
    end = centre_of_mass(deposit, dem)
    found["deposit_x"] = end[0]
    length = math.hypot(end[0] - start[0], end[1] - start[1])
    found["alpha_cm_deg"] = math.degrees(math.atan2(start[2] - end[2], length))
    return found


def table(
    pair: dict[str, Any], ava: dict[str, Any], run: dict[str, Any], hazard: dict[str, Any]
) -> str:
    """The markdown of the comparison: the side-by-side table, conslaw's own ``hazard.json``,
    the point references.

    Parameters
    ----------
    pair : dict
        ``avaframe`` and ``conslaw`` (:func:`measure`), ``iou`` per threshold,
        ``references`` (:func:`point_references`).
    ava : dict
        ``avaframe_run.json``.
    run : dict
        conslaw's run: ``seconds`` (wall clock), ``steps``, ``solve_seconds``, ``stop_s``
        (:func:`conslaw_stop_time`), ``t_end``.
    hazard : dict
        conslaw's ``hazard.json``.

    Returns
    -------
    str
    """
    ref = pair["references"]
    top_x = pair["avaframe"][f"top_x@{THRESHOLDS[0]}"]
    lines = [
        f"AvaFrame {ava['version']} com1DFA (Coulomb, mu = {ava['mucoulomb']:.4f}) and conslaw "
        f"savage-hutter-terrain (delta = phi = {DELTA:g}, isotropic K = 1) on AvaFrame's "
        f"hockey stick (generateTopo {ava['topo']}), release {ava['release']} "
        f"{THICKNESS:g} m thick; scripts/avaframe_comparison.py.",
        "",
        "| measure (same function on both peak rasters) | AvaFrame com1DFA | conslaw | "
        "conslaw - AvaFrame |",
        "|---|---|---|---|",
        *_rows(pair, ava, run),
        "",
        "conslaw's own hazard.json (run-out toward the deposit's centre of mass, 0.01 m):",
        "",
        "| key | value |",
        "|---|---|",
        *(
            f"| {key} | {value:.6g} |" if isinstance(value, float) else f"| {key} | {value} |"
            for key, value in hazard.items()
        ),
        "",
        f"Point with Coulomb friction tan({DELTA:g} deg), released at rest (the release top at "
        f"x = {top_x:.1f} m; profile misfit to the DEM {ref['profile_misfit_m']:.2g} m):",
        "",
        "| reference | stop x (m) |",
        "|---|---|",
        f"| energy line from the release top (no curvature, alpha = {DELTA:g}) | "
        f"{ref['top_energy_line_x']:.1f} |",
        f"| sliding point from the release top, with the arc's centripetal friction | "
        f"{ref['top_sliding_x']:.1f} |",
        f"| sliding points from every released column, mean (centre of mass without pressure) | "
        f"{ref['columns_sliding_x']:.1f} |",
    ]
    return "\n".join(lines) + "\n"


def _one(folder: Path, pattern: str) -> Path:
    """The single file of ``folder`` matching ``pattern``."""
    found = sorted(folder.glob(pattern))
    if len(found) != 1:
        raise FileNotFoundError(f"expected one {pattern} in {folder}, found {len(found)}")
    return found[0]


def compare(folder: Path, out: Path, reuse: bool = False) -> str:
    """Run conslaw on step 1's inputs in ``folder`` (unless ``reuse`` and ``out`` holds a run),
    measure both runs and return the markdown of :func:`table`.

    Parameters
    ----------
    folder : Path
        The avalanche directory of step 1.
    out : Path
        conslaw's output folder.
    reuse : bool
        Take the run already in ``out`` (its wall clock in ``out.with_suffix(".seconds")``).

    Returns
    -------
    str
    """
    dem_file = _one(folder / "Inputs", "*.asc")
    release_file = folder / "Inputs" / "REL" / "release.shp"
    dem = read_raster(dem_file)
    release = release_mask(release_file, dem)
    clock = out.with_suffix(".seconds")
    if not (reuse and clock.exists()):
        seconds = run_conslaw(conslaw_scene(folder, dem_file, release_file), out)
        clock.write_text(f"{seconds:.3f}\n")
    report = re.search(r"(\d+) steps, solve ([\d.]+) s", out.with_suffix(".log").read_text())
    if report is None:
        raise ValueError(f"no step count in {out.with_suffix('.log')}")
    hazard = json.loads((out / "hazard.json").read_text())
    run = {
        "seconds": float(clock.read_text()),
        "steps": int(report[1]),
        "solve_seconds": float(report[2]),
        "stop_s": conslaw_stop_time(out / "states.npz"),
        "t_end": float(hazard["t_end"]),
    }
    peaks = folder / "Outputs" / "com1DFA" / "peakFiles"
    ava_peak, ours = read_raster(_one(peaks, "*_pft.*")), read_raster(out / "peak_depth.tif")
    pair = {
        "avaframe": measure(ava_peak, read_raster(_one(peaks, "*_FT.*")), dem, release),
        "conslaw": measure(ours, read_raster(out / "deposit.tif"), dem, release),
        "iou": {t: overlap(ava_peak, ours, t) for t in THRESHOLDS},
        "references": point_references(dem, release),
    }
    ava = json.loads((folder / "avaframe_run.json").read_text())
    return table(pair, ava, run, hazard)


def on_cells(dem: Raster, raster: Raster) -> Raster:
    """The DEM's values at the cell centres of ``raster`` (which must be DEM cell centres: a
    coarser grid whose centres fall on the DEM's).

    Parameters
    ----------
    dem, raster : Raster

    Returns
    -------
    Raster
        Elevation on ``raster``'s cells.
    """
    cols = np.rint((raster.x - dem.x[0]) / (dem.x[1] - dem.x[0])).astype(int)
    rows = np.rint((raster.y - dem.y[0]) / (dem.y[1] - dem.y[0])).astype(int)
    if not (np.allclose(dem.x[cols], raster.x) and np.allclose(dem.y[rows], raster.y)):
        raise ValueError("the raster's cell centres are not the DEM's")
    return Raster(dem.values[np.ix_(rows, cols)], raster.x, raster.y, raster.cell)


def _load() -> str:
    """The machine's load averages over 1, 5 and 15 minutes (``uptime``)."""
    return " ".join(f"{value:.2f}" for value in os.getloadavg())


def _conslaw_report(out: Path) -> dict[str, Any]:
    """Steps, solve seconds (the summary's, which include loading or compiling the kernels:
    ``load_seconds``), the stop time and whether the kernels were compiled, from the log of
    :func:`run_conslaw` and the run's ``hazard.json``."""
    log = out.with_suffix(".log").read_text()
    report = re.search(
        r"(\d+) steps, solve ([\d.]+) s(?: \(compile or cache load ([\d.]+) s)?", log
    )
    if report is None:
        raise ValueError(f"no step count in {out.with_suffix('.log')}")
    stop = json.loads((out / "hazard.json").read_text())["stop"]
    return {
        "steps": int(report[1]),
        "solve_seconds": float(report[2]),
        "load_seconds": float(report[3] or 0.0),
        "stop_t": float(stop["t"]),
        "rest_since": stop.get("rest_since"),
        "stopped_at_rest": bool(stop["stopped_at_rest"]),
        "compiled": "conslaw: compiling" in log,
    }


def timing(
    topography: Path,
    folder: Path,
    rounds: int,
    avaframe_python: Path,
    interval: float,
    reuse: bool = False,
) -> str:
    """AvaFrame's com1DFA and ``conslaw run`` on a generated topography at the DEM's own cells,
    timed interleaved (A B A B ...), and the run-out measures of both and of conslaw at twice
    the cell size; the markdown of the tables.

    conslaw's compiled kernels are warmed first by the run at twice the cell size (which is
    also its grid-independence run); every run is a fresh process. AvaFrame runs through
    ``avaframe_python`` (its own venv) with ``avaframe-topography``; its time is
    ``com1DFAMain``'s, as in :func:`run_avaframe`; conslaw's is the wall clock of the whole
    ``conslaw run`` process (start-up, DEM, solve, hazard maps and states written; no plots)
    and the solve time of its summary.

    Parameters
    ----------
    topography : Path
        One folder of ``scripts/avaframe_topographies.py``, e.g. ``/tmp/avatopo/HS``.
    folder : Path
        Work folder (scenes, runs, logs, ``timing.json``).
    rounds : int
        Rounds of one AvaFrame and one conslaw run.
    avaframe_python : Path
        The interpreter of AvaFrame's venv.
    interval : float
        conslaw's output interval (s), the resolution of its stop at rest.
    reuse : bool
        Only the tables, from the rounds in ``folder/timing.json`` (written after each round).

    Returns
    -------
    str
    """
    folder.mkdir(parents=True, exist_ok=True)
    dem_file = _one(topography, "DEM_*_Topo.asc")
    release_file = _one(topography, "release1*.shp")
    dem = read_raster(dem_file)
    fine = conslaw_scene(folder, dem_file, release_file, at_rest=interval, name="scene_fine")
    coarse = conslaw_scene(
        folder, dem_file, release_file, 2.0 * dem.cell, at_rest=interval, name="scene_coarse"
    )
    if reuse:
        saved = json.loads((folder / "timing.json").read_text())
        return _timing_tables(saved, folder, dem, release_file)
    record: dict[str, Any] = {"load_start": _load()}
    seconds = run_conslaw(coarse, folder / "conslaw_coarse")
    record["coarse"] = {"seconds": seconds, **_conslaw_report(folder / "conslaw_coarse")}
    record["rounds"] = []
    for index in range(rounds):
        row: dict[str, Any] = {"round": index + 1, "load_before_avaframe": _load()}
        ava_dir = folder / f"avaframe_{index + 1}"
        command = [str(avaframe_python), __file__, "avaframe-topography", "--dir", str(ava_dir)]
        started = time.perf_counter()
        with (folder / f"avaframe_{index + 1}.log").open("w") as log:
            subprocess.run(
                [*command, "--topography", str(topography)],
                check=True,
                stdout=log,
                stderr=subprocess.STDOUT,
            )
        row["avaframe_process_seconds"] = time.perf_counter() - started
        row["avaframe"] = json.loads((ava_dir / "avaframe_run.json").read_text())
        row["load_before_conslaw"] = _load()
        out = folder / f"conslaw_fine_{index + 1}"
        row["conslaw_seconds"] = run_conslaw(fine, out)
        row["conslaw"] = _conslaw_report(out)
        row["load_after"] = _load()
        record["rounds"].append(row)
        print(json.dumps(row), flush=True)
        (folder / "timing.json").write_text(json.dumps(record, indent=2) + "\n")
    return _timing_tables(record, folder, dem, release_file)


def _timing_round_lines(record: dict[str, Any], folder: Path) -> list[str]:
    """The markdown table of :func:`timing`'s rounds, one row each."""
    lines = [
        "| round | load before A (1, 5, 15 min) | A: com1DFAMain (s) | A: process (s) | "
        "A: stop (s) | load before B | B: conslaw run (s) | B: solve (s) | B: of it kernel "
        "load (s) | B: steps | B: stop (s) | load after B | B solve / A | B run / A |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in record["rounds"]:
        ava = row["avaframe"]
        ours = _conslaw_report(folder / f"conslaw_fine_{row['round']}")
        lines.append(
            f"| {row['round']} | {row['load_before_avaframe']} | {ava['seconds']:.1f} | "
            f"{row['avaframe_process_seconds']:.1f} | {ava['t_end_s']:.1f} | "
            f"{row['load_before_conslaw']} | {row['conslaw_seconds']:.1f} | "
            f"{ours['solve_seconds']:.1f} | {ours['load_seconds']:.1f}"
            f"{' (compiled)' if ours['compiled'] else ''} | {ours['steps']} | "
            f"{ours['stop_t']:g} | {row['load_after']} | "
            f"{ours['solve_seconds'] / ava['seconds']:.2f} | "
            f"{row['conslaw_seconds'] / ava['seconds']:.2f} |"
        )
    return lines


def _timing_tables(record: dict[str, Any], folder: Path, dem: Raster, release_file: Path) -> str:
    """The markdown of :func:`timing`: one row per round, then the measures."""
    lines = _timing_round_lines(record, folder)
    coarse = {
        "seconds": record["coarse"]["seconds"],
        **_conslaw_report(folder / "conslaw_coarse"),
    }
    last = record["rounds"][-1]
    ava_dir, out = folder / f"avaframe_{last['round']}", folder / f"conslaw_fine_{last['round']}"
    peaks = ava_dir / "Outputs" / "com1DFA" / "peakFiles"
    release = release_mask(release_file, dem)
    found = {
        "AvaFrame": measure(
            read_raster(_one(peaks, "*_pft.*")), read_raster(_one(peaks, "*_FT.*")), dem, release
        ),
        "conslaw fine": measure(
            read_raster(out / "peak_depth.tif"), read_raster(out / "deposit.tif"), dem, release
        ),
    }
    peak = read_raster(folder / "conslaw_coarse" / "peak_depth.tif")
    grid = on_cells(dem, peak)
    found["conslaw coarse"] = measure(
        peak,
        read_raster(folder / "conslaw_coarse" / "deposit.tif"),
        grid,
        release_mask(release_file, grid),
    )
    a, f, c = found["AvaFrame"], found["conslaw fine"], found["conslaw coarse"]
    lines += [
        "",
        f"conslaw at {2 * dem.cell:g} m (the warm-up run): run {coarse['seconds']:.1f} s, solve "
        f"{coarse['solve_seconds']:.1f} s (of it kernel "
        f"{'compile' if coarse['compiled'] else 'load'} {coarse['load_seconds']:.1f} s), "
        f"{coarse['steps']} steps, stop t = "
        f"{coarse['stop_t']:g} s; AvaFrame {last['avaframe']['version']}, "
        f"{last['avaframe']['stop']}; load at the start {record['load_start']}.",
        "",
        f"| measure (runout_metrics / measure) | AvaFrame | conslaw {dem.cell:g} m | conslaw "
        f"{2 * dem.cell:g} m | {dem.cell:g} m - AvaFrame | {2 * dem.cell:g} m - {dem.cell:g} m |",
        "|---|---|---|---|---|---|",
    ]
    keys = [
        (f"{name}@{threshold}", f"{label}, >= {threshold:g} m", digits)
        for threshold in THRESHOLDS
        for name, label, digits in (
            ("end_x", "run-out end x (m)", 1),
            ("end_y", "run-out end y (m)", 1),
            ("length_m", "run-out length from the release top (m)", 1),
            ("alpha_deg", "travel angle (deg)", 2),
            ("area_ha", "affected area (ha)", 2),
        )
    ]
    keys += [
        ("deposit_x", "deposit centre of mass x (m)", 1),
        ("alpha_cm_deg", "centre-of-mass travel angle (deg)", 2),
        ("max_peak", "largest peak flow thickness (m)", 2),
    ]
    for key, label, d in keys:
        lines.append(
            f"| {label} | {a[key]:.{d}f} | {f[key]:.{d}f} | {c[key]:.{d}f} | "
            f"{f[key] - a[key]:+.{d}f} | {c[key] - f[key]:+.{d}f} |"
        )
    return "\n".join(lines) + "\n"


def main() -> None:
    """Run the step named on the command line."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    steps = parser.add_subparsers(dest="step", required=True)
    first = steps.add_parser("avaframe", help="step 1, in AvaFrame's venv")
    first.add_argument("--dir", type=Path, required=True, help="avalanche directory (emptied)")
    topo = steps.add_parser(
        "avaframe-topography", help="com1DFA on a generated topography, in AvaFrame's venv"
    )
    topo.add_argument("--dir", type=Path, required=True, help="avalanche directory (emptied)")
    topo.add_argument("--topography", type=Path, required=True, help="e.g. /tmp/avatopo/HS")
    second = steps.add_parser("compare", help="step 2, in the project's venv")
    second.add_argument("--dir", type=Path, required=True, help="step 1's avalanche directory")
    second.add_argument("--out", type=Path, required=True, help="conslaw's output folder")
    second.add_argument("--table", type=Path, help="also write the markdown here")
    second.add_argument("--reuse", action="store_true", help="take the conslaw run in --out")
    timed = steps.add_parser(
        "timing", help="com1DFA and conslaw run interleaved, timed, in the project's venv"
    )
    timed.add_argument("--topography", type=Path, required=True, help="e.g. /tmp/avatopo/HS")
    timed.add_argument("--dir", type=Path, required=True, help="work folder")
    timed.add_argument("--rounds", type=int, default=2, help="A B rounds (default 2)")
    timed.add_argument(
        "--avaframe-python", type=Path, default=Path("/tmp/avaenv/bin/python"), help="its venv"
    )
    timed.add_argument("--interval", type=float, default=5.0, help="conslaw's output interval")
    timed.add_argument("--table", type=Path, help="also write the markdown here")
    timed.add_argument("--reuse", action="store_true", help="tables from DIR/timing.json")
    args = parser.parse_args()
    if args.step == "avaframe":
        print(json.dumps(run_avaframe(args.dir.resolve()), indent=2))
        return
    if args.step == "avaframe-topography":
        run = run_avaframe_topography(args.dir.resolve(), args.topography.resolve())
        print(json.dumps(run, indent=2))
        return
    if args.step == "timing":
        markdown = timing(
            args.topography.resolve(),
            args.dir.resolve(),
            args.rounds,
            args.avaframe_python,
            args.interval,
            args.reuse,
        )
    else:
        markdown = compare(args.dir.resolve(), args.out.resolve(), args.reuse)
    if args.table is not None:
        args.table.write_text(markdown)
    print(markdown, end="")


if __name__ == "__main__":
    main()
