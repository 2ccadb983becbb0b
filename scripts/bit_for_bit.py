"""Bit-for-bit comparison of every built-in scene between two versions of conslaw.

Runs each built-in scene at its own resolution and at twice it (``--set n_cells=2N``) with two
Python interpreters (or one interpreter and two source trees), then compares every array of the
``states.npz`` files exactly (``numpy.array_equal`` with NaN equal to NaN, same dtype and shape).
Used to show that a restructuring changes no number (docs/design.md, "Kernel toolkit").

Usage::

    python scripts/bit_for_bit.py --before /path/to/old/checkout --out /tmp/b4b
    python scripts/bit_for_bit.py --before-python /old/venv/bin/python --out /tmp/b4b

``--before DIR`` runs the current interpreter with the old tree's ``conslaw`` and ``models``
folders first on ``PYTHONPATH`` (as ``conslaw`` and ``conslaw_models``, through symbolic links in
``OUT/before-packages``); ``--before-python`` runs another environment.
Exit code 0 if every scene is identical, 1 otherwise.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np

SCENE_FOLDER = Path(__file__).resolve().parents[1] / "conslaw" / "scenes"


def scene_names() -> list[str]:
    """Every built-in scene (the TOML files shipped in conslaw/scenes)."""
    return sorted(path.stem for path in SCENE_FOLDER.glob("*.toml"))


def default_cells(name: str) -> int:
    """The scene's own ``n_cells`` (its TOML, else 200)."""
    scene = tomllib.loads((SCENE_FOLDER / f"{name}.toml").read_text())
    return int(scene.get("n_cells", 200))


def run(python: str, pythonpath: str | None, scene: str, cells: int, out: Path) -> None:
    """One scene run into ``out`` (no figures); raises on a non-zero exit."""
    environment = dict(os.environ)
    if pythonpath is not None:
        environment["PYTHONPATH"] = pythonpath
    command = [python, "-m", "conslaw.cli", "run", scene, "--no-plot"]
    command += ["--set", f"n_cells={cells}", "--out", str(out)]
    done = subprocess.run(command, env=environment, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed: {done.stderr.strip()[-500:]}")


def identical(before: Path, after: Path) -> tuple[bool, str]:
    """Whether two npz files hold the same arrays bit for bit, and the first difference."""
    old, new = np.load(before), np.load(after)
    # The provenance (versions, commit, input paths) differs between two checkouts by design.
    keys = sorted(set(old.files) - {"provenance"})
    if keys != sorted(set(new.files) - {"provenance"}):
        return False, f"arrays {sorted(old.files)} vs {sorted(new.files)}"
    for key in keys:
        a, b = old[key], new[key]
        if a.dtype != b.dtype or a.shape != b.shape:
            return False, f"{key}: {a.dtype}{a.shape} vs {b.dtype}{b.shape}"
        if a.dtype.kind in "fc":
            same = np.array_equal(a.view(np.uint8), b.view(np.uint8))
        else:
            same = np.array_equal(a, b)
        if not same:
            return False, f"{key} differs"
    return True, ""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", help="old source tree (put first on PYTHONPATH)")
    parser.add_argument("--before-python", help="interpreter of the old version")
    parser.add_argument("--out", type=Path, required=True, help="folder for both runs")
    parser.add_argument("--scenes", help="comma-separated subset (default: every built-in scene)")
    arguments = parser.parse_args()
    if not arguments.before and not arguments.before_python:
        parser.error("give --before DIR or --before-python PYTHON")
    before_python = arguments.before_python or sys.executable
    before_path = None
    if arguments.before:
        shim = arguments.out / "before-packages"
        shim.mkdir(parents=True, exist_ok=True)
        for name, folder in (("conslaw", "conslaw"), ("conslaw_models", "models")):
            link = shim / name
            if link.is_symlink():
                link.unlink()
            link.symlink_to(Path(arguments.before).resolve() / folder)
        before_path = str(shim)
    scenes = arguments.scenes.split(",") if arguments.scenes else scene_names()
    failures = 0
    print(f"{'scene':28s} {'n_cells':>8s}  result")
    for scene in scenes:
        base = default_cells(scene)
        for cells in (base, 2 * base):
            folder = arguments.out / f"{scene}-{cells}"
            run(before_python, before_path, scene, cells, folder / "before")
            run(sys.executable, None, scene, cells, folder / "after")
            same, why = identical(folder / "before" / "states.npz", folder / "after" / "states.npz")
            failures += not same
            print(f"{scene:28s} {cells:8d}  {'identical' if same else 'DIFFERENT: ' + why}")
    print(f"{failures} of {2 * len(scenes)} runs differ")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
