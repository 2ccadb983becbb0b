"""Regenerate the figures committed under docs/figures/ from the built-in scenes:

    python scripts/figures.py

Each scene is run with its own settings; its PNGs are copied to docs/figures/<scene>-<name>.png.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import conslaw

ROOT = Path(__file__).resolve().parents[1]
SCENES = {
    "burgers-riemann": {"n_cells": 1600},
    "dam-break-wet": {"n_cells": 400},
    "dam-break-dry": {"n_cells": 400},
    "sh-similarity": {},
    "sh-runout-shock": {},
}


def main() -> None:
    target = ROOT / "docs" / "figures"
    target.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:
        for scene, overrides in SCENES.items():
            result = conslaw.run(scene, out=Path(folder) / scene, **overrides)
            for path in result.files:
                if path.suffix == ".png":
                    destination = target / f"{scene}-{path.name}"
                    shutil.copyfile(path, destination)
                    print(f"wrote {destination}")


if __name__ == "__main__":
    main()
