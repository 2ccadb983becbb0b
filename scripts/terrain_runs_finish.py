"""Avalanches on AvaFrame's generated topographies run to their end with the defaults: the
table of docs/validation.md, "Runs that finish".

The inputs come from AvaFrame's own generators (``scripts/avaframe_topographies.py``, in
AvaFrame's environment); this script runs in the project's::

    /tmp/avaenv/bin/python scripts/avaframe_topographies.py --out /tmp/avatopo
    python scripts/terrain_runs_finish.py --topographies /tmp/avatopo --out /tmp/finish \\
        --table /tmp/finish/table.md

Every case is ``savage-hutter-terrain`` on the whole DEM's extent (x 1000 to 6000, y -5000 to
-3500), outflow sides, the release file of the topography at 1 m normal to the slope, t_end =
150 s with outputs every 30 s, no ``dem_smoothing``, every other setting at its default
(``mc``, ``cfl = 0.45``, ``delta = 25``, ``phi = 35``, Savage–Hutter earth pressure) unless the
case says otherwise: on the hockey stick at 20 m cells every combination of ``cfl`` in {0.25,
0.45}, ``delta`` in {20, 25, 30}, ``phi`` in {delta, 35} and both earth-pressure rules, and the
default at 10 m and at 5 m (AvaFrame's own cells); on the inclined plane, the parabolic slope and
the bowl the default at 20 m.

After every step (both steps of every accepted pair, the staggered family included) it measures
the speed in the surface of every cell, the largest of the cells at least 1 cm deep (thickness
normal to the slope) so far in the run, and the largest ratio of any cell's speed to that; the
table gives per case: whether it reached t_end, the steps, the smallest step, the fastest cell
at least 1 cm deep and the fastest cell anywhere over the run, that largest ratio, the most
times a pair was redone, the relative change of the volume (what left through the outflow
sides) and the wall time. ``--cases`` picks cases by name (comma-separated).
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import dataclass
from itertools import product
from pathlib import Path
from typing import Any

import numpy as np

#: Depth (m, normal to the slope) from which a cell counts as flow for the speed comparison.
DEEP = 0.01
T_END = 150.0
OUTPUT_TIMES = [30.0, 60.0, 90.0, 120.0]


@dataclass(frozen=True)
class Case:
    """One run: a name, the topography (``HS``, ``IP``, ``PF``, ``BL``), the cell size and the
    scene keys that differ from the defaults."""

    name: str
    topography: str
    cell: float
    settings: dict[str, Any]


def cases() -> list[Case]:
    """The cases of the table, in its order."""
    found = []
    for cfl, delta, same, earth in product(
        (0.25, 0.45), (20.0, 25.0, 30.0), (True, False), ("savage-hutter", "isotropic")
    ):
        phi = delta if same else 35.0
        settings = {
            "cfl": cfl,
            "parameters.delta": delta,
            "parameters.phi": phi,
            "parameters.earth_pressure": earth,
        }
        name = f"HS-20-cfl{cfl:g}-d{delta:g}-p{phi:g}-{'sh' if earth == 'savage-hutter' else 'iso'}"
        found.append(Case(name, "HS", 20.0, settings))
    found.append(Case("HS-10-default", "HS", 10.0, {}))
    found.append(Case("HS-5-default", "HS", 5.0, {}))
    for topography in ("IP", "PF", "BL"):
        found.append(Case(f"{topography}-20-default", topography, 20.0, {}))
    return found


def scene_table(case: Case, topographies: Path) -> dict[str, Any]:
    """The scene of ``case`` as a table (the built-in scene keys)."""
    folder = topographies / case.topography
    nx, ny = round(5000.0 / case.cell), round(1500.0 / case.cell)
    table: dict[str, Any] = {
        "model": "savage-hutter-terrain",
        "n_cells": [nx, ny],
        "x_min": 1000.0,
        "x_max": 6000.0,
        "y_min": -5000.0,
        "y_max": -3500.0,
        "t_end": T_END,
        "output_times": OUTPUT_TIMES,
        "exact": False,
        "parameters": {
            "terrain": "dem",
            "dem_file": str(folder / f"DEM_{case.topography}_Topo.asc"),
        },
        "boundary": dict.fromkeys(("left", "right", "bottom", "top"), "outflow"),
        "initial": {
            "kind": "release",
            "thickness": 1.0,
            "release_file": str(folder / f"release1{case.topography}.shp"),
        },
    }
    for key, value in case.settings.items():
        if key.startswith("parameters."):
            table["parameters"][key.split(".", 1)[1]] = value
        else:
            table[key] = value
    return table


class Watch:
    """The speeds of every family a scheme accepts (wrapped around ``JiangTadmor._pair``)."""

    def __init__(self, scheme: Any) -> None:
        self.scheme = scheme
        self.deep_max = 0.0
        self.any_max = 0.0
        self.worst = 0.0
        self.smallest_dt = np.inf
        reference = scheme.reference
        self.aux = {s: reference.family_aux(s) for s in (False, True)}
        pair = scheme._pair

        def watched(dt: float) -> tuple[bool, float]:
            accepted, next_dt = pair(dt)
            if accepted:
                self.smallest_dt = min(self.smallest_dt, dt)
                self.look(scheme._values(1), True)
                self.look(scheme._values(2), False)
            return accepted, next_dt

        scheme._pair = watched

    def look(self, values: np.ndarray, staggered: bool) -> None:
        """Update the maxima with one family's values."""
        model, aux = self.scheme.model, self.aux[staggered]
        depth, speed = model.flow_depth_and_speed(values, aux)
        deep = depth >= DEEP
        if deep.any():
            self.deep_max = max(self.deep_max, float(speed[deep].max()))
        fastest = float(speed.max())
        self.any_max = max(self.any_max, fastest)
        if self.deep_max > 0.0:
            self.worst = max(self.worst, fastest / self.deep_max)


def run_case(case: Case, topographies: Path) -> dict[str, Any]:
    """Run one case to t_end (step pair by step pair through its output times, as ``conslaw run``
    does) and measure it."""
    from conslaw.errors import ConslawError
    from conslaw.scene2d import load_scene_2d
    from conslaw.simulation2d import build_2d

    folder = Path("/tmp") / "conslaw-finish-scenes"
    folder.mkdir(exist_ok=True)
    import tomli_w

    path = folder / f"{case.name}.toml"
    path.write_text(tomli_w.dumps(scene_table(case, topographies)))
    scene = load_scene_2d(path)
    _, grid, scheme, q = build_2d(scene)
    watch = Watch(scheme)
    volume = float(q[0].sum())
    started = time.perf_counter()
    t, steps, stop = 0.0, 0, "t_end"
    try:
        for target in [*scene.output_times, scene.t_end]:
            q, t, taken = scheme.advance(q, t, target)
            steps += taken
    except ConslawError as error:
        stop = f"stopped: {error}"
    return {
        "case": case.name,
        "cells": f"{grid.x.n_cells} x {grid.y.n_cells}",
        "finished": stop == "t_end",
        "stop": stop,
        "t": t,
        "steps": steps,
        "smallest_dt": watch.smallest_dt,
        "fastest_deep": watch.deep_max,
        "fastest_any": watch.any_max,
        "largest_ratio": watch.worst,
        "most_redone": scheme.most_retries,
        "volume_change": float(q[0].sum()) / volume - 1.0,
        "seconds": time.perf_counter() - started,
    }


def table(rows: list[dict[str, Any]]) -> str:
    """The markdown table of the measured cases."""
    lines = [
        "| case | cells | reached t_end | steps | smallest step (s) | fastest >= 1 cm (m/s) | "
        "fastest anywhere (m/s) | largest ratio | most redone | volume change | wall (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        lines.append(
            f"| {row['case']} | {row['cells']} | {'yes' if row['finished'] else row['stop']} "
            f"| {row['steps']} | {row['smallest_dt']:.3g} | {row['fastest_deep']:.1f} | "
            f"{row['fastest_any']:.1f} | {row['largest_ratio']:.3f} | {row['most_redone']} | "
            f"{row['volume_change']:+.2e} | {row['seconds']:.0f} |"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--topographies", type=Path, required=True)
    parser.add_argument("--out", type=Path, required=True, help="folder for results.json")
    parser.add_argument("--table", type=Path, help="also write the markdown table here")
    parser.add_argument("--cases", help="comma-separated case names (default: all)")
    arguments = parser.parse_args()
    chosen = cases()
    if arguments.cases:
        names = set(arguments.cases.split(","))
        chosen = [case for case in chosen if case.name in names]
    arguments.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for case in chosen:
        row = run_case(case, arguments.topographies)
        rows.append(row)
        print(json.dumps(row), flush=True)
        (arguments.out / "results.json").write_text(json.dumps(rows, indent=2) + "\n")
    text = table(rows)
    print(text)
    if arguments.table:
        arguments.table.write_text(text + "\n")


if __name__ == "__main__":
    main()
