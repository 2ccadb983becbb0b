"""Observed L1 orders of every reconstructor on burgers-sine (smooth solution, docs/equations.md,
"Exact solutions").

    python scripts/orders.py [--cells 100,200,400,800] [--json PATH]

Prints a markdown table of the errors and the observed orders between successive grids.
"""

from __future__ import annotations

import argparse
import itertools
import json

import conslaw
from conslaw import registry
from conslaw.analysis import observed_orders


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", default="100,200,400,800")
    parser.add_argument("--scene", default="burgers-sine")
    parser.add_argument("--json", help="also write the results to this JSON file")
    args = parser.parse_args()
    cells = [int(n) for n in args.cells.split(",")]
    rows = []
    header = " | ".join(f"L1 N={n}" for n in cells)
    pairs = " | ".join(f"{a}->{b}" for a, b in itertools.pairwise(cells))
    print(f"| reconstructor | {header} | order {pairs} |")
    print("|---" * (2 * len(cells)) + "|")
    for name in registry.reconstructors.names():
        errors = [
            conslaw.run(args.scene, n_cells=n, reconstructor=name).headline_error() for n in cells
        ]
        orders = observed_orders(cells, errors)
        rows.append({"reconstructor": name, "cells": cells, "l1": errors, "orders": orders})
        print(
            f"| {name} | "
            + " | ".join(f"{e:.3e}" for e in errors)
            + " | "
            + " | ".join(f"{o:.2f}" for o in orders)
            + " |"
        )
    if args.json:
        with open(args.json, "w") as handle:
            json.dump({"scene": args.scene, "results": rows}, handle, indent=2)


if __name__ == "__main__":
    main()
