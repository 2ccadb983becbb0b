"""Run the stability catalogue of docs/stability.md and print the table of ``docs/stability.md``.

    python scripts/stability_table.py [--case KEY[,KEY...]]

Every case of ``tests/stability_cases.py`` (the same functions ``tests/test_stability.py``
asserts) is run; each row gives the set-up, the expected outcome, what was observed (outcome,
measured numbers, and any expectation that failed) and the command that reproduces the row. The
whole table takes about 15 s (plus the compilation of the kernels on a cold cache).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from stability_cases import CASES, Case  # noqa: E402


def number(value: object) -> str:
    """A compact rendering of a measured value."""
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return f"{value:.3g}"
    if isinstance(value, list | tuple):
        return "/".join(number(v) for v in value)
    try:
        return f"{float(value):.3g}"  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return str(value)


def row(case: Case) -> str:
    """The markdown row of one case (runs it)."""
    started = time.perf_counter()
    observation = case.run()
    seconds = time.perf_counter() - started
    facts = "; ".join(f"{name} {number(value)}" for name, value in observation.facts.items())
    failed = observation.failed()
    verdict = "as expected" if observation.outcome == case.expected and not failed else "FAILED"
    observed = f"**{observation.outcome}** ({verdict}; {seconds:.1f} s): {facts}"
    if failed:
        observed += f"; failed: {', '.join(failed)}"
    command = f"`python scripts/stability_table.py --case {case.key}`"
    cells = [f"`{case.key}`", case.item, case.setup, case.expected, observed, command]
    return "| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", help="comma-separated case keys (default: all)")
    args = parser.parse_args()
    keys = args.case.split(",") if args.case else [c.key for c in CASES]
    unknown = sorted(set(keys) - {c.key for c in CASES})
    if unknown:
        parser.error(
            f"unknown case(s) {', '.join(unknown)}; allowed: {', '.join(c.key for c in CASES)}"
        )
    print("| case | catalogue item | set-up | expected | observed | command |")
    print("|---|---|---|---|---|---|")
    failures = 0
    for case in CASES:
        if case.key in keys:
            line = row(case)
            failures += "(FAILED;" in line
            print(line, flush=True)
    if not args.case:
        failures += reconstructor_table()
    return 1 if failures else 0


def reconstructor_table() -> int:
    """The dry-bed and thin-layer cases with every reconstructor; returns the failures."""
    from stability_cases import dam_break

    from conslaw import registry

    print()
    header = ["reconstructor", "bed", "outcome", "steps", "max \\|u\\|", "max u+2c", "L1(h)"]
    print("| " + " | ".join([*header, "L1(h), none"]) + " |")
    print("|---|---|---|---|---|---|---|---|")
    failures = 0
    for name in registry.reconstructors.names():
        for label, h_right in (("dry", 0.0), ("1e-12", 1e-12)):
            observation = dam_break(h_right, name)
            failed = observation.failed()
            failures += bool(failed)
            f = observation.facts
            outcome = observation.outcome + (f" (failed: {', '.join(failed)})" if failed else "")
            values = [f["steps"], f["max |u|"], f["max u+2c"], f["L1(h)"], f["L1(h), none"]]
            cells = [name, label, outcome, *(number(v) for v in values)]
            print("| " + " | ".join(cells) + " |", flush=True)
    return failures


if __name__ == "__main__":
    raise SystemExit(main())
