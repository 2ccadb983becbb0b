"""Regenerate the run figures committed under docs/figures/ from the built-in scenes:

    python scripts/figures.py

(The paper's Figs. 3-5 under docs/figures/paper/ come from `conslaw reproduce paper --out
docs/figures/paper`.)

Each scene is run with its own settings; its PNGs are copied to docs/figures/<scene>-<name>.png.
(The Fig. 3-style comparison of NT and the Lagrangian scheme is part of `reproduce paper`.)
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import conslaw

ROOT = Path(__file__).resolve().parents[1]
#: (figure prefix, scene, overrides)
SCENES = [
    ("burgers-riemann", "burgers-riemann", {"n_cells": 1600}),
    ("dam-break-wet", "dam-break-wet", {"n_cells": 400}),
    ("dam-break-dry", "dam-break-dry", {"n_cells": 400}),
    ("sh-runout-shock-ft", "sh-runout-shock", {"front_tracking": True}),
]


def main() -> None:
    target = ROOT / "docs" / "figures"
    target.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:
        for prefix, scene, overrides in SCENES:
            result = conslaw.run(scene, out=Path(folder) / prefix, **overrides)
            for path in result.files:
                if path.suffix == ".png":
                    destination = target / f"{prefix}-{path.name}"
                    shutil.copyfile(path, destination)
                    print(f"wrote {destination}")


if __name__ == "__main__":
    main()
