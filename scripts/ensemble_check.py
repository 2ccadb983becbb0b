"""An ensemble's members against the same scenes run one by one (docs/ensembles.md, "Members
are single runs"): a study of ``sh-runout-shock`` with the bed friction angle, the internal
friction angle and the release height varied, on the local default engine; then every member
again through :func:`conslaw.run` in this process, and some through the ``conslaw run`` command
(a new process each, its ``states.npz``), each final state compared by its SHA-256 digest.

Usage: ``python scripts/ensemble_check.py [--samples 1000] [--cells 200] [--cli 10]
[--out DIR]``
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import conslaw
from conslaw.ensemble import run_study
from conslaw.ensemble.member import state_digest

SCENE = "sh-runout-shock"
VARY = [
    "parameters.delta=uniform:20:28",
    "parameters.phi=uniform:30:38",
    "initial.height=normal:2.2:0.15",
]


def member_settings(dataset: object, index: int, cells: int) -> dict[str, float]:
    """The scene keys of member ``index`` (as ``--set`` takes them)."""
    varied = {
        dataset[name].attrs["scene_key"]: float(dataset[name][index])  # type: ignore[index]
        for name in dataset.data_vars  # type: ignore[attr-defined]
        if "scene_key" in dataset[name].attrs  # type: ignore[index]
    }
    return {"n_cells": cells, **varied}


def through_command(settings: dict[str, float], folder: Path) -> str:
    """The digest of the final state ``conslaw run`` writes for these settings."""
    pairs = [item for key, value in settings.items() for item in ("--set", f"{key}={value!r}")]
    command = [sys.executable, "-m", "conslaw", "run", SCENE, *pairs, "--no-plot"]
    subprocess.run([*command, "--out", str(folder)], check=True, capture_output=True)
    with np.load(folder / "states.npz") as states:
        return state_digest(states["q"][-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=1000)
    parser.add_argument("--cells", type=int, default=200)
    parser.add_argument("--cli", type=int, default=10, help="members checked via conslaw run")
    parser.add_argument("--out", help="study folder (default: a temporary one)")
    args = parser.parse_args()
    out = Path(args.out or tempfile.mkdtemp(prefix="ensemble-check-")) / "study"
    started = time.perf_counter()
    study = run_study(SCENE, VARY, args.samples, out, settings={"n_cells": args.cells})
    whole = time.perf_counter() - started
    dataset = study.dataset
    finished = int((dataset.status.values == "finished").sum())
    print(f"{args.samples} members, {finished} finished, {study.workers} workers, {whole:.1f} s")
    equal = 0
    for index in range(args.samples):
        settings = member_settings(dataset, index, args.cells)
        single = conslaw.run(SCENE, **{k.replace(".", "__"): v for k, v in settings.items()})
        equal += state_digest(single.states[-1].q) == dataset.digest.values[index]
    print(f"conslaw.run one by one: {equal} of {args.samples} final states equal bit for bit")
    chosen = np.linspace(0, args.samples - 1, min(args.cli, args.samples)).astype(int)
    equal_cli = 0
    with tempfile.TemporaryDirectory() as scratch:
        for index in chosen:
            digest = through_command(
                member_settings(dataset, index, args.cells), Path(scratch) / str(index)
            )
            equal_cli += digest == dataset.digest.values[index]
    print(f"conslaw run (command): {equal_cli} of {len(chosen)} final states equal bit for bit")
    if equal != args.samples or equal_cli != len(chosen):
        raise SystemExit(1)


if __name__ == "__main__":
    main()
