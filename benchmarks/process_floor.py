"""The whole `conslaw run` process against the floor of any Python program that draws with the
same libraries (docs/performance.md, "The whole conslaw run process").

    python benchmarks/process_floor.py [--scene sh-similarity] [--pairs 3] [--json FILE]

Each round runs, one after the other (A B C, interleaved so that the machine's load falls on
all three): A = ``conslaw run SCENE --out TMP`` (its kernels already cached: one warm-up run
first), B = the same with ``--no-plot`` (no figure child, no matplotlib), C = a bare
``python -c`` that imports numpy, scipy, numba and matplotlib and saves one figure. Prints the
wall times, their medians and the ratios A / C (the goal in the performance notes: 1.2) and
B / C (what the run costs without drawing its figures).

``--baseline CHECKOUT`` adds D = the same ``conslaw run`` from the ``conslaw`` and ``models``
folders of another checkout (``git worktree add /tmp/base COMMIT``), interleaved, and the ratio
A / D: what a change of the code did, measured in one run.
"""

from __future__ import annotations

import argparse
import json
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

FLOOR = (
    "import numpy, scipy, numba, matplotlib\n"
    "from matplotlib.figure import Figure\n"
    "figure = Figure()\n"
    "figure.add_subplot().plot([0.0, 1.0])\n"
    "figure.savefig({path!r})\n"
)


#: Runs ``conslaw`` from another checkout: its packages replace the installed ones (the entry
#: points, which name modules, stay those installed).
FROM_CHECKOUT = (
    "import importlib.util, sys\n"
    "root = sys.argv.pop(1)\n"
    "for name, folder in (('conslaw', 'conslaw'), ('conslaw_models', 'models')):\n"
    "    path = f'{root}/{folder}'\n"
    "    spec = importlib.util.spec_from_file_location(\n"
    "        name, f'{path}/__init__.py', submodule_search_locations=[path]\n"
    "    )\n"
    "    module = importlib.util.module_from_spec(spec)\n"
    "    sys.modules[name] = module\n"
    "    spec.loader.exec_module(module)\n"
    "from conslaw.cli import console_main\n"
    "sys.argv[0] = 'conslaw'\n"
    "raise SystemExit(console_main())\n"
)


def wall(command: list[str]) -> float:
    """Seconds one process takes, start to exit (it must succeed)."""
    started = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True)
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="sh-similarity")
    parser.add_argument("--pairs", type=int, default=3, help="rounds (A B C each)")
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--baseline", type=Path, help="another checkout to compare with")
    args = parser.parse_args()
    conslaw = shutil.which("conslaw") or "conslaw"
    folder = Path(tempfile.mkdtemp(prefix="conslaw-floor-"))
    run = [conslaw, "run", args.scene, "--out", str(folder / "run")]
    no_plot = [conslaw, "run", args.scene, "--no-plot", "--out", str(folder / "no-plot")]
    floor = [sys.executable, "-c", FLOOR.format(path=str(folder / "floor.png"))]
    commands = {"run": run, "no_plot": no_plot, "floor": floor}
    if args.baseline is not None:
        commands["baseline"] = [
            sys.executable, "-c", FROM_CHECKOUT, str(args.baseline.resolve()),
            "run", args.scene, "--out", str(folder / "baseline"),
        ]  # fmt: skip
        wall(commands["baseline"])
    wall(run)  # the kernels into the cache, the files into the folder
    times: dict[str, list[float]] = {key: [] for key in commands}
    for _ in range(args.pairs):
        for key, command in commands.items():
            times[key].append(wall(command))
    shutil.rmtree(folder, ignore_errors=True)
    medians = {key: statistics.median(values) for key, values in times.items()}
    heads = {"run": f"conslaw run {args.scene} (s)", "no_plot": "with --no-plot (s)"}
    heads |= {"floor": "floor (s)", "baseline": f"the same from {args.baseline} (s)"}
    print("| round | " + " | ".join(heads[key] for key in commands) + " |")
    print("|---" * (len(commands) + 1) + "|")
    for k, row in enumerate(zip(*times.values(), strict=True), 1):
        print(f"| {k} | " + " | ".join(f"{value:.2f}" for value in row) + " |")
    print("| median | " + " | ".join(f"{medians[key]:.2f}" for key in commands) + " |")
    ratios = {"ratio": medians["run"] / medians["floor"]}
    ratios["ratio_no_plot"] = medians["no_plot"] / medians["floor"]
    line = f"ratio of the medians: {ratios['ratio']:.2f} (with --no-plot: "
    line += f"{ratios['ratio_no_plot']:.2f})"
    if "baseline" in medians:
        ratios["ratio_to_baseline"] = medians["run"] / medians["baseline"]
        line += f"; against the baseline: {ratios['ratio_to_baseline']:.2f}"
    print(line)
    if args.json is not None:
        args.json.write_text(json.dumps({"scene": args.scene, **times, **ratios}) + "\n")


if __name__ == "__main__":
    main()
