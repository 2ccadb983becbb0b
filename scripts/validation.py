"""Regenerate docs/validation.md and its figures in one command:

    python scripts/validation.py

Runs the convergence tool on the scenes with exact solutions and writes the tables and the
work-precision plots (error against run time, error against N) under docs/.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from conslaw.studies.convergence import convergence_study, write_study

ROOT = Path(__file__).resolve().parents[1]
STUDIES = [
    ("dam-break-wet", [100, 200, 400, 800, 1600], ["minmod", "mc", "weno5"]),
    ("dam-break-dry", [100, 200, 400, 800, 1600], ["minmod", "mc", "weno5"]),
    ("burgers-riemann", [100, 200, 400, 800, 1600], ["minmod", "mc", "weno5"]),
    (
        "burgers-sine",
        [100, 200, 400, 800],
        ["none", "minmod", "superbee", "vanleer", "mc", "weno3", "weno5"],
    ),
]


def main() -> None:
    figures = ROOT / "docs" / "figures"
    sections = []
    for scene, cells, reconstructors in STUDIES:
        study = convergence_study(scene, cells, reconstructors, repeats=3)
        write_study(study, figures)
        command = (
            f"conslaw convergence {scene} --cells {','.join(map(str, cells))} "
            f"--reconstructor {','.join(reconstructors)}"
        )
        sections.append(
            f"## {scene}\n\nCommand: `{command}`\n\n{study.table()}\n\n"
            f"```\n{study.summary()}\n```\n\n"
            f"![error against run time](figures/convergence-{scene}-error-vs-time.png)\n"
            f"![error against N](figures/convergence-{scene}-error-vs-cells.png)\n"
        )
    orders = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "orders.py")],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    page = (ROOT / "docs" / "validation_intro.md").read_text()
    page += "\n## Observed orders on the smooth Burgers solution\n\n"
    page += "Command: `python scripts/orders.py`\n\n" + orders + "\n" + "\n".join(sections)
    (ROOT / "docs" / "validation.md").write_text(page)
    print(f"wrote {ROOT / 'docs' / 'validation.md'}")


if __name__ == "__main__":
    main()
