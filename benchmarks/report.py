"""Markdown tables from the JSON that ``benchmarks/run.py --json`` wrote.

    python benchmarks/report.py benchmarks/results.json

The tables of ``docs/performance.md`` are this script's output, unedited.
"""

from __future__ import annotations

import json
import sys
from typing import Any

SIZES = (1000, 10000, 100000, 1000000)


def _rate(value: float | None) -> str:
    return "-" if value is None else f"{value:.2e}"


def _seconds(value: float | None) -> str:
    return "not reached" if value is None else f"{value:.4f} s"


def throughput_table(report: dict[str, Any]) -> list[str]:
    lines = [
        "| model (scene, reconstructor) | N = 1e3 | 1e4 | 1e5 | 1e6 |",
        "|---|---|---|---|---|",
    ]
    rows: dict[tuple[str, str, str], dict[int, float]] = {}
    for r in report["throughput"]:
        rows.setdefault((r["model"], r["scene"], r["reconstructor"]), {})[r["n_cells"]] = r[
            "cell_updates_per_s"
        ]
    for (model, scene, reconstructor), by_n in rows.items():
        cells = " | ".join(_rate(by_n.get(n)) for n in SIZES)
        lines.append(f"| {model.split(',')[0]} ({scene}, {reconstructor}) | {cells} |")
    pyclaw = report.get("pyclaw") or {}
    for problem, prow in pyclaw.get("throughput", {}).items():
        by_n = {r["n_cells"]: r["cell_updates_per_s"] for r in prow}
        cells = " | ".join(_rate(by_n.get(n)) for n in SIZES)
        lines.append(f"| PyClaw classic ({problem}, MC) | {cells} |")
    for kind, what in (("rate", "wall time"), ("rate_cpu", "CPU time")):
        for label in ("shallow-water", "burgers"):
            ratios = {
                int(key.split("N=")[1]): value
                for key, value in (report.get("ratios") or {}).get(kind, {}).items()
                if key.startswith(label + " ")
            }
            if ratios:
                cells = " | ".join(f"{ratios[n]:.1f}" if n in ratios else "-" for n in SIZES)
                lines.append(f"| **conslaw / PyClaw, {label}, by {what}** | {cells} |")
    return lines


def linearity_table(report: dict[str, Any]) -> list[str]:
    lines = [
        "| model | N = 1e3 | 1e4 | 1e5 | 1e6 | largest / smallest |",
        "|---|---|---|---|---|---|",
    ]
    for label, relative in report["linearity"].items():
        values = {int(n): r for n, r in relative.items()}
        cells = " | ".join(f"{values[n]:.2f}" if n in values else "-" for n in SIZES)
        spread = max(values.values()) / min(values.values())
        lines.append(f"| {label} | {cells} | {spread:.2f} |")
    return lines


def work_precision_table(report: dict[str, Any]) -> list[str]:
    pyclaw = (report.get("pyclaw") or {}).get("work_precision", {})
    lines = [
        "| problem | conslaw to 1e-3 | PyClaw to 1e-3 | ratio | conslaw to 1e-4 | PyClaw to 1e-4 "
        "| ratio |",
        "|---|---|---|---|---|---|---|",
    ]
    for row in report["work_precision"]:
        theirs = pyclaw.get(row["scene"], {})
        cells = []
        for target in ("1e-03", "0.0001"):
            key = f"time_to_{float(target):g}"
            mine, other = row.get(key), theirs.get(key)
            ratio = f"{mine / other:.2f}" if mine and other else "-"
            cells += [_seconds(mine), _seconds(other) if theirs else "-", ratio]
        lines.append(f"| {row['scene']} | {' | '.join(cells)} |")
    for problem, reason in ((report.get("pyclaw") or {}).get("not_run") or {}).items():
        lines.append(f"\nPyClaw on {problem}: no work-precision row: {reason}.")
    return lines


def convergence_table(report: dict[str, Any]) -> list[str]:
    pyclaw = (report.get("pyclaw") or {}).get("work_precision", {})
    lines = [
        "| problem | N | conslaw steps | conslaw solve s (min-max) | conslaw L1 | PyClaw steps "
        "| PyClaw solve s (min-max) | PyClaw L1 |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for row in report["work_precision"]:
        theirs = pyclaw.get(row["scene"])
        for k, n in enumerate(row["cells"]):
            mine = (
                f"{row['steps'][k]} | {row['seconds'][k]:.4f} ({row['min'][k]:.4f}-"
                f"{row['max'][k]:.4f}) | {row['l1'][k]:.3e}"
            )
            other = (
                f"{theirs['steps'][k]} | {theirs['seconds'][k]:.4f} ({theirs['min'][k]:.4f}-"
                f"{theirs['max'][k]:.4f}) | {theirs['l1'][k]:.3e}"
                if theirs
                else "- | - | -"
            )
            lines.append(f"| {row['scene']} | {n} | {mine} | {other} |")
    return lines


def paper_table(report: dict[str, Any]) -> list[str]:
    p = report["paper_scene"]
    return [
        "| what | median | min-max |",
        "|---|---|---|",
        f"| sh-similarity solve ({p['n_cells']} cells, {p['steps']} steps, compiled NT) | "
        f"{p['solve_median'] * 1e3:.2f} ms | {p['solve_min'] * 1e3:.2f}-"
        f"{p['solve_max'] * 1e3:.2f} ms |",
        f"| sh-similarity-ft solve (front tracking, compiled) | "
        f"{p['front_tracking_solve_median'] * 1e3:.1f} ms | "
        f"{p['front_tracking_solve_min'] * 1e3:.1f}-{p['front_tracking_solve_max'] * 1e3:.1f} ms |",
        f"| `conslaw run sh-similarity` whole process (default: npz + 2 PNG figures) | "
        f"{p['process_median']:.2f} s (CPU {p['process_cpu_median']:.2f} s) | "
        f"{p['process_min']:.2f}-{p['process_max']:.2f} s |",
        f"| `conslaw run sh-similarity --no-plot` whole process | "
        f"{p['process_no_plot_median']:.2f} s (CPU {p['process_no_plot_cpu_median']:.2f} s) | "
        f"{p['process_no_plot_min']:.2f}-{p['process_no_plot_max']:.2f} s |",
    ]


def pyclaw_dry_table(report: dict[str, Any]) -> list[str]:
    rows = (report.get("pyclaw") or {}).get("dry_dam_break") or []
    lines = [
        "| PyClaw solver | bed depth | dry_tolerance | N | steps | L1 |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        l1 = "NaN" if r["l1"] is None else f"{r['l1']:.3e}"
        lines.append(
            f"| {r['solver']} | {r['bed']:g} | {r['dry_tolerance']:g} | {r['n_cells']} | "
            f"{r['steps']} | {l1} |"
        )
    return lines if rows else ["(not measured in this run)"]


def memory_table(report: dict[str, Any]) -> list[str]:
    m = report["memory"]
    lines = [
        "| step pairs asked | steps taken | kernel calls | resident size | numba allocations |",
        "|---|---|---|---|---|",
    ]
    for pairs in (100, 10000):
        lines.append(
            f"| {pairs} | {m[f'steps_{pairs}']} | {m[f'kernel_calls_{pairs}']} | "
            f"{m[f'rss_mb_{pairs}']:.1f} MB | {m[f'allocations_{pairs}']} |"
        )
    return lines


def main() -> None:
    with open(sys.argv[1]) as handle:
        report = json.load(handle)
    env = report["environment"]
    loads = ", ".join(f"{k} {a:.1f}-{b:.1f}" for k, (a, b) in report["load"].items())
    print(
        f"Run of {env['date']} at commit {env['commit']}: {env['cpu']}, {env['cores']} cores, "
        f"Python {env['python']}, numpy {env['numpy']}, numba {env['numba']}; load average "
        f"per section {loads}.\n"
    )
    for title, table in (
        ("(a) cell updates per second", throughput_table),
        ("cost per cell update relative to N = 1e4", linearity_table),
        ("(b) time to reach an L1 error", work_precision_table),
        ("(b) the runs behind it", convergence_table),
        ("(b) PyClaw on the dry dam break", pyclaw_dry_table),
        ("(c) the paper scene", paper_table),
        ("(e) memory", memory_table),
    ):
        print(f"#### {title}\n")
        print("\n".join(table(report)))
        print()


if __name__ == "__main__":
    main()
