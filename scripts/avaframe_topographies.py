"""AvaFrame's generated test topographies with their default releases, as inputs for conslaw.

Runs in AvaFrame's own environment (it imports ``avaframe`` and its dependency ``pyshp``)::

    python3 -m venv /tmp/avaenv && /tmp/avaenv/bin/pip install avaframe   # measured: 2.1
    /tmp/avaenv/bin/python scripts/avaframe_topographies.py --out /tmp/avatopo

For each of the inclined plane (``IP``), the hockey stick (``HS``), the parabolic slope
(``PF``) and the bowl (``BL``) it writes ``OUT/<type>/DEM_<type>_Topo.asc`` from
``in3Utils.generateTopo`` with the package's defaults (``generateTopoCfg.ini``: 5 m cells,
5000 m x 1500 m, lower-left cell centre (1000, -5000); only ``demType`` set) and
``OUT/<type>/release1<type>.shp`` from ``in3Utils.getReleaseArea`` with its defaults
(``getReleaseAreaCfg.ini``: 200 m of drop, 100 000 m^3, 1 m thick), and ``OUT/topographies.json``
with the DEMs' extents and the release polygons.

``getReleaseArea`` has no release for the bowl (it logs "no release area available for demType:
BL"); the bowl gets :data:`BOWL_RELEASE`, a 200 m x 200 m square of 1 m on the bowl's wall
(from 350 to 150 m west of its centre, where the wall is 45 to 17 degrees steep), so that
the material runs down through the centre and up the far wall.
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path
from typing import Any

#: The topographies of ``generateTopo`` measured (``demType``).
TYPES = ("IP", "HS", "PF", "BL")
#: The bowl's release in coordinates relative to its centre (m), clockwise, 1 m thick.
BOWL_RELEASE = ((-350.0, -100.0), (-350.0, 100.0), (-150.0, 100.0), (-150.0, -100.0))


def _configs(dem_type: str) -> tuple[Any, Any]:
    """``generateTopo``'s and ``getReleaseArea``'s default configurations, ``demType`` set."""
    from avaframe.in3Utils import cfgUtils, generateTopo, getReleaseArea

    topo = cfgUtils.getModuleConfig(generateTopo, onlyDefault=True, toPrint=False)
    topo["TOPO"]["demType"] = dem_type
    release = cfgUtils.getModuleConfig(getReleaseArea, onlyDefault=True, toPrint=False)
    return topo, release


def _bowl_release(topo: Any, folder: Path) -> list[list[float]]:
    """:data:`BOWL_RELEASE` about the bowl's centre, written as ``release1BL.shp``."""
    import shapefile  # pyshp, an AvaFrame dependency

    x_end, y_end = float(topo["TOPO"]["xEnd"]), float(topo["TOPO"]["yEnd"])
    x_centre = float(topo["DEMDATA"]["xl"]) + 0.5 * x_end
    y_centre = float(topo["DEMDATA"]["yl"]) + 0.5 * y_end
    corners = [[x_centre + x, y_centre + y] for x, y in BOWL_RELEASE]
    with shapefile.Writer(str(folder / "release1BL")) as writer:
        writer.field("ID", "C", 40)
        writer.field("thickness", "N", decimal=4)
        writer.poly([[*corners, corners[0]]])
        writer.record("1", 1.0)
    return corners


def generate(out: Path) -> dict[str, Any]:
    """Every topography of :data:`TYPES` and its release into ``out/<type>``.

    Returns
    -------
    dict
        Per type: the DEM file, its lower-left corner and cell size, the release file and its
        corners.
    """
    import numpy as np
    from avaframe.in3Utils import generateTopo, getReleaseArea, initializeProject

    summary: dict[str, Any] = {}
    for dem_type in TYPES:
        folder = out / dem_type
        work = out / f"_{dem_type}_avalanche"
        initializeProject.initializeFolderStruct(str(work), removeExisting=True)
        topo, release = _configs(dem_type)
        generateTopo.generateTopo(topo, work)
        folder.mkdir(parents=True, exist_ok=True)
        dem = folder / f"DEM_{dem_type}_Topo.asc"
        shutil.copyfile(work / "Inputs" / dem.name, dem)
        if dem_type == "BL":
            corners = _bowl_release(topo, folder)
        else:
            _, _, points = getReleaseArea.getReleaseArea(topo, release, work)
            corners = np.asarray(points).tolist()
            for suffix in (".shp", ".shx", ".dbf"):
                name = f"release1{dem_type}{suffix}"
                shutil.copyfile(work / "Inputs" / "REL" / name, folder / name)
        shutil.rmtree(work)
        header = dict(line.split()[:2] for line in dem.read_text().splitlines()[:6])
        summary[dem_type] = {
            "dem_file": str(dem),
            "xllcorner": float(header.get("xllcorner", header.get("xllcenter", 0.0))),
            "yllcorner": float(header.get("yllcorner", header.get("yllcenter", 0.0))),
            "cellsize": float(header["cellsize"]),
            "ncols": int(header["ncols"]),
            "nrows": int(header["nrows"]),
            "release_file": str(folder / f"release1{dem_type}.shp"),
            "release": corners,
        }
    (out / "topographies.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="folder for the inputs")
    arguments = parser.parse_args()
    summary = generate(arguments.out)
    for dem_type, item in summary.items():
        print(dem_type, item["dem_file"], item["release_file"])


if __name__ == "__main__":
    main()
