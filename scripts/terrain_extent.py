"""How far the values of a terrain run reach: after each of a few times, the rows and columns of
the grid holding any value other than 0, and the rows holding material at least 1e-6 m deep
(docs/design.md, "Cost that follows the flow").

    python scripts/terrain_extent.py --topographies /tmp/avatopo [--case HS-10-default]

The cases are those of ``scripts/terrain_runs_finish.py`` (AvaFrame's generated topographies,
made by ``scripts/avaframe_topographies.py``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

TIMES = (0.5, 2.0, 5.0, 10.0, 20.0, 40.0, 80.0, 150.0)


def main() -> None:
    """Print one line per time."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--topographies", type=Path, required=True)
    parser.add_argument("--case", default="HS-10-default")
    arguments = parser.parse_args()
    sys.path.insert(0, str(Path(__file__).parent))
    import terrain_runs_finish as finish
    import tomli_w

    from conslaw.scene2d import load_scene_2d
    from conslaw.simulation2d import build_2d

    case = next(c for c in finish.cases() if c.name == arguments.case)
    path = Path("/tmp") / f"extent-{case.name}.toml"
    path.write_text(tomli_w.dumps(finish.scene_table(case, arguments.topographies)))
    _, _, scheme, q = build_2d(load_scene_2d(path))
    t = 0.0
    for target in TIMES:
        q, t, _ = scheme.advance(q, t, target)
        rows = np.flatnonzero(np.any(q != 0.0, axis=(0, 2)))
        columns = np.flatnonzero(np.any(q != 0.0, axis=(0, 1)))
        deep = np.flatnonzero(np.any(q[0] >= 1e-6, axis=1))
        print(
            f"t = {t:5.1f}: rows {rows.min()}..{rows.max()} and columns {columns.min()}.."
            f"{columns.max()} of {q.shape[1]} x {q.shape[2]} hold values; rows with material "
            f">= 1e-6 m: {deep.min()}..{deep.max()}"
        )


if __name__ == "__main__":
    main()
