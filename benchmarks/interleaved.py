"""Two versions of conslaw timed against each other, interleaved (A B A B ...), in one run.

The machines here are shared and noisy: a comparison is only worth something when both sides are
measured in the same minutes. This script takes the Python of another checkout (or virtual
environment) as the baseline, and alternates between it and the current one:

- section (a) of ``benchmarks/run.py``: cell updates per second of the fused NT kernel for each
  model (the same scenes, reconstructors and step counts) at each N, a child process per side and
  round (kernels loaded from each side's cache, compiled first in a warm-up child);
- the whole process ``conslaw run sh-similarity`` (import, kernels from the cache, the run, the
  output files and figures), wall time per run.

It prints a table of medians and the ratio current / baseline of every row, and writes JSON with
every sample if asked.

Usage::

    python benchmarks/interleaved.py --baseline /path/to/other/.venv/bin/python [--rounds 5]
        [--sizes 10000,100000,1000000] [--json out.json]
    python benchmarks/interleaved.py --baseline-tree /path/to/old/checkout ...

Every child runs in its side's cache folder (``python -m`` puts the working folder first on the
import path, so a child started in a checkout would import that checkout's conslaw). Both sides
need their own kernel cache (``CONSLAW_CACHE_DIR`` is set per side to
``<cache>/baseline`` and ``<cache>/current``, default under the system's temporary folder).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

#: Model -> (scene, reconstructor): the rows of section (a) of benchmarks/run.py.
THROUGHPUT = {
    "burgers": ("burgers-sine", "mc"),
    "burgers, weno5": ("burgers-sine", "weno5"),
    "shallow-water": ("dam-break-wet", "mc"),
    "savage-hutter": ("sh-similarity", "superbee"),
}
TARGET_UPDATES = 2e7


def child(sizes: list[int]) -> None:
    """Print the throughput of every row as JSON (runs under either side's Python)."""
    import conslaw
    from conslaw.simulation import build

    rows = []
    for label, (scene, reconstructor) in THROUGHPUT.items():
        for n in sizes:
            loaded = conslaw.load_scene(
                scene, {"n_cells": n, "output_times": [], "reconstructor": reconstructor}
            )
            _, _, scheme, initial, _ = build(loaded)
            steps_wanted = max(20, int(TARGET_UPDATES / n))
            t_end = min(loaded.t_end, scheme.stable_dt(initial) * steps_wanted)
            scheme.advance(initial, initial.t)  # compile or load from the cache
            samples = []
            for _ in range(3):
                started = time.perf_counter()
                result = scheme.advance(initial, t_end)
                samples.append(time.perf_counter() - started)
            seconds = statistics.median(samples)
            rows.append({"model": label, "n_cells": n, "rate": n * result.steps / seconds})
    print(json.dumps(rows))


#: Extra environment of each side (``PYTHONPATH`` of a baseline source tree, see main).
SIDE_ENVIRONMENT: dict[str, dict[str, str]] = {}


def side_environment(cache: Path) -> dict[str, str]:
    """The environment of the side whose kernel cache is ``cache``."""
    return {**os.environ, **SIDE_ENVIRONMENT.get(cache.name, {}), "CONSLAW_CACHE_DIR": str(cache)}


def run_child(python: str, cache: Path, sizes: list[int]) -> list[dict[str, Any]]:
    environment = side_environment(cache)
    output = subprocess.run(
        [python, __file__, "--child", "--sizes", ",".join(map(str, sizes))],
        capture_output=True, text=True, check=True, env=environment, cwd=cache,
    ).stdout  # fmt: skip
    rows: list[dict[str, Any]] = json.loads(output.strip().splitlines()[-1])
    return rows


def whole_process(python: str, cache: Path, folder: Path) -> float:
    """Wall time of ``conslaw run sh-similarity --out folder`` with ``python``'s conslaw."""
    environment = side_environment(cache)
    started = time.perf_counter()
    subprocess.run(
        [python, "-m", "conslaw.cli", "run", "sh-similarity", "--out", str(folder)],
        capture_output=True, check=True, env=environment, cwd=cache,
    )  # fmt: skip
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--baseline", help="the Python executable of the baseline version")
    parser.add_argument(
        "--baseline-tree",
        help="a source checkout of the baseline, run with this Python (its conslaw and models "
        "folders first on PYTHONPATH)",
    )
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--sizes", default="10000,100000,1000000")
    parser.add_argument("--cache", help="folder for the two kernel caches")
    parser.add_argument("--json", help="write every sample to this JSON file")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    if args.child:
        child(sizes)
        return
    if not args.baseline and not args.baseline_tree:
        parser.error("--baseline or --baseline-tree is required")
    root = Path(args.cache) if args.cache else Path(tempfile.gettempdir()) / "conslaw-interleaved"
    sides = {"baseline": args.baseline or sys.executable, "current": sys.executable}
    if args.baseline_tree:
        shim = root / "baseline-packages"
        shim.mkdir(parents=True, exist_ok=True)
        for name, folder in (("conslaw", "conslaw"), ("conslaw_models", "models")):
            link = shim / name
            if link.is_symlink():
                link.unlink()
            link.symlink_to(Path(args.baseline_tree).resolve() / folder)
        SIDE_ENVIRONMENT["baseline"] = {"PYTHONPATH": str(shim)}
    caches = {side: root / side for side in sides}
    for cache in caches.values():
        cache.mkdir(parents=True, exist_ok=True)
    for side, python in sides.items():  # compile every kernel once, outside the timing
        run_child(python, caches[side], sizes)
        with tempfile.TemporaryDirectory() as folder:
            whole_process(python, caches[side], Path(folder) / "out")
    samples: dict[str, dict[str, list[float]]] = {side: {} for side in sides}
    for round_ in range(args.rounds):
        for side, python in sides.items():  # A B, A B, ...
            for row in run_child(python, caches[side], sizes):
                key = f"{row['model']} N={row['n_cells']}"
                samples[side].setdefault(key, []).append(row["rate"])
            with tempfile.TemporaryDirectory() as folder:
                seconds = whole_process(python, caches[side], Path(folder) / "out")
            samples[side].setdefault("conslaw run sh-similarity (s)", []).append(seconds)
        print(f"round {round_ + 1} of {args.rounds} done", file=sys.stderr)
    print("| row | baseline (median) | current (median) | current / baseline |")
    print("|---|---|---|---|")
    for key in samples["baseline"]:
        base = statistics.median(samples["baseline"][key])
        current = statistics.median(samples["current"][key])
        print(f"| {key} | {base:.4g} | {current:.4g} | {current / base:.3f} |")
    if args.json:
        Path(args.json).write_text(json.dumps(samples, indent=2))


if __name__ == "__main__":
    main()
