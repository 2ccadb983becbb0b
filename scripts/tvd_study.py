"""How often each reconstructor increases the total variation of Burgers data, per CFL number.

    python scripts/tvd_study.py [--trials 200] [--pairs 10] [--cells 64] [--seed 1990]
                                [--cfl 0.1,0.2,0.3,0.4,0.45,0.49] [--reconstructors a,b]
                                [--long] [--json PATH]

Burgers' equation on a periodic grid of [0, 1], random initial data (fixed seed), the
Nessyahu–Tadmor scheme advanced by step pairs exactly as ``NessyahuTadmor.advance`` takes them
(one ``dt = cfl dx / max|u|`` per pair, the pair redone with a smaller ``dt`` if the Courant number
of its second half would reach 1/2), but one compiled step at a time so that the staggered
half-step states are seen too. The total variation is the periodic one,
``sum_j |u_{j+1} - u_j|`` including the wrap-around difference.

Two data families, each with ``--trials`` trials per (reconstructor, CFL):

* ``noise``: ``u_j = m + U(-1, 1)`` independently per cell, with ``m ~ U(-1, 1)`` per trial;
* ``riemann``: piecewise constant, 2 to 6 pieces with values ``U(-1, 1)``, random breakpoints;
* ``waves``: cell averages of ``m + sum_k a_k sin(2 pi k x + phi_k)``, ``k = 1..4``, with
  ``a_k ~ U(-1, 1) / k``, ``phi_k ~ U(0, 2 pi)``, ``m ~ U(-1, 1)`` (smooth data that steepen into
  shocks within the run).

Measured per (data, reconstructor, CFL):

* ``step``: fraction of trials in which some single step (either cell family) increased the TV by
  more than round-off, ``TV_new > TV_old + 1e-12 (1 + TV_old)``;
* ``max``: the largest relative increase ``(TV_new - TV_old) / TV_old`` of one step;
* ``pair``: the same fraction as ``step``, comparing only primary-grid states after whole pairs;
* ``net``: fraction of trials whose TV after all pairs exceeds the initial TV beyond round-off.

The default output is one markdown table per data family (rows: reconstructors, columns: CFL,
cells ``step / pair / net (max)``, a dash where the TV never grew); ``--long`` prints one row per
setting instead.

Nessyahu & Tadmor (1990) prove the scheme with limited slopes TVD under a CFL restriction below
1/2; a sufficient bound for this implementation with minmod slopes and Burgers is
``c (1 + c)^2 <= 3/8``, i.e. ``c <= 0.2428`` (derived in
``tests/test_properties.py::test_minmod_burgers_advance_is_tvd``).
"""

from __future__ import annotations

import argparse
import json
from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import NDArray

from conslaw import registry
from conslaw.grid import Grid
from conslaw.schemes.base import BoundarySpec
from conslaw.schemes.nessyahu_tadmor.scheme import NessyahuTadmor
from conslaw.state import State

Array = NDArray[np.float64]

DATA_KINDS = ("noise", "riemann", "waves")
#: Courant number the second half of a pair must stay below (``step`` refuses 1/2 itself).
HALF = 0.4999999
#: Retries of a pair with a smaller dt (the fused kernel allows 60).
MAX_RETRIES = 60


@dataclass(frozen=True)
class Setting:
    """The outcome of all trials of one (data kind, reconstructor, CFL)."""

    data: str
    reconstructor: str
    cfl: float
    trials: int
    step_fraction: float
    max_relative_step_increase: float
    pair_fraction: float
    net_fraction: float


def periodic_total_variation(u: Array) -> float:
    """``sum_j |u_{j+1} - u_j|`` with the wrap-around difference."""
    return float(np.sum(np.abs(np.roll(u, -1, axis=-1) - u)))


def exceeds_round_off(new: float, old: float) -> bool:
    """Whether ``new`` is larger than ``old`` by more than round-off."""
    return new > old + 1e-12 * (1.0 + old)


def random_data(kind: str, n: int, rng: np.random.Generator) -> Array:
    """One random initial condition of the family ``kind``, shape ``(1, n)``."""
    if kind == "noise":
        return (rng.uniform(-1.0, 1.0) + rng.uniform(-1.0, 1.0, n))[None, :]
    if kind == "waves":
        edges = np.linspace(0.0, 1.0, n + 1)
        total = rng.uniform(-1.0, 1.0) * np.ones(n)
        for k in range(1, 5):
            amplitude, phase = rng.uniform(-1.0, 1.0) / k, rng.uniform(0.0, 2.0 * np.pi)
            # Exact cell averages of amplitude * sin(2 pi k x + phase).
            primitive = -amplitude * np.cos(2.0 * np.pi * k * edges + phase) / (2.0 * np.pi * k)
            total += np.diff(primitive) * n
        return total[None, :]
    pieces = int(rng.integers(2, 7))
    breaks = np.sort(rng.choice(np.arange(1, n), size=pieces - 1, replace=False))
    values = rng.uniform(-1.0, 1.0, pieces)
    return np.repeat(values, np.diff(np.concatenate([[0], breaks, [n]])))[None, :]


def step_pair(scheme: NessyahuTadmor, state: State) -> tuple[State, State]:
    """One step pair with one ``dt``, as ``NessyahuTadmor.advance`` takes it."""
    dx = scheme.grid.dx
    dt = scheme.stable_dt(state)
    if not np.isfinite(dt):
        dt = dx
    for _ in range(MAX_RETRIES):
        half = scheme.step(state, dt)
        speed = float(np.max(np.abs(half.q)))
        if speed * dt / dx < HALF:
            return half, scheme.step(half, dt)
        dt = scheme.cfl * dx / speed
    raise RuntimeError(f"could not meet the CFL condition at t={state.t}")


def run_setting(
    kind: str, reconstructor: str, cfl: float, trials: int, pairs: int, cells: int, seed: int
) -> Setting:
    """All trials of one setting (the same seed, hence the same data, for every setting)."""
    periodic = BoundarySpec(registry.boundaries.get("periodic"))
    grid = Grid(0.0, 1.0, cells)
    scheme = NessyahuTadmor(
        registry.models.get("burgers")(),
        registry.reconstructors.get(reconstructor),
        grid,
        periodic,
        periodic,
        cfl=cfl,
    )
    rng = np.random.default_rng([seed, DATA_KINDS.index(kind)])
    step_hits = pair_hits = net_hits = 0
    largest = 0.0
    for _ in range(trials):
        state = State(0.0, grid.centres(), random_data(kind, cells, rng), 0.0)
        tv_start = tv_primary = periodic_total_variation(state.q)
        step_increase = pair_increase = False
        for _ in range(pairs):
            half, full = step_pair(scheme, state)
            tv_previous = tv_primary
            for tv_old, new in ((tv_primary, half), (periodic_total_variation(half.q), full)):
                tv_new = periodic_total_variation(new.q)
                if exceeds_round_off(tv_new, tv_old):
                    step_increase = True
                    largest = max(largest, (tv_new - tv_old) / max(tv_old, 1e-300))
            tv_primary = periodic_total_variation(full.q)
            pair_increase |= exceeds_round_off(tv_primary, tv_previous)
            state = full
        step_hits += step_increase
        pair_hits += pair_increase
        net_hits += exceeds_round_off(tv_primary, tv_start)
    return Setting(
        kind,
        reconstructor,
        cfl,
        trials,
        step_hits / trials,
        largest,
        pair_hits / trials,
        net_hits / trials,
    )


def cell(r: Setting) -> str:
    """``step / pair / net (max)`` of one setting, or a dash if the TV never grew."""
    if r.step_fraction == 0.0:
        return "-"
    return (
        f"{r.step_fraction:.3f} / {r.pair_fraction:.3f} / {r.net_fraction:.3f} "
        f"({r.max_relative_step_increase:.1e})"
    )


def pivot_markdown(results: list[Setting]) -> str:
    """One table per data family: reconstructors x CFL numbers."""
    cfls = sorted({r.cfl for r in results})
    blocks = []
    for kind in dict.fromkeys(r.data for r in results):
        rows = [r for r in results if r.data == kind]
        lines = [
            f"**{kind}** (step / pair / net fraction of trials with a TV increase, "
            "(largest relative increase in one step))",
            "",
            "| reconstructor | " + " | ".join(f"CFL {c:g}" for c in cfls) + " |",
            "|---" * (1 + len(cfls)) + "|",
        ]
        for name in dict.fromkeys(r.reconstructor for r in rows):
            by_cfl = {r.cfl: r for r in rows if r.reconstructor == name}
            lines.append(
                f"| {name} | "
                + " | ".join(cell(by_cfl[c]) if c in by_cfl else "" for c in cfls)
                + " |"
            )
        blocks.append("\n".join(lines))
    return "\n\n".join(blocks)


def markdown(results: list[Setting]) -> str:
    """The results as a markdown table, one row per setting."""
    lines = [
        "| data | reconstructor | CFL | step | max rel. step | pair | net |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for r in results:
        lines.append(
            f"| {r.data} | {r.reconstructor} | {r.cfl:g} | {r.step_fraction:.3f} "
            f"| {r.max_relative_step_increase:.2e} | {r.pair_fraction:.3f} | {r.net_fraction:.3f} |"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=200)
    parser.add_argument("--pairs", type=int, default=10)
    parser.add_argument("--cells", type=int, default=64)
    parser.add_argument("--seed", type=int, default=1990)
    parser.add_argument("--cfl", default="0.1,0.2,0.3,0.4,0.45,0.49")
    parser.add_argument(
        "--reconstructors", default=None, help="comma-separated names (default: all registered)"
    )
    parser.add_argument("--long", action="store_true", help="one table row per setting")
    parser.add_argument("--json", help="also write the results to this JSON file")
    args = parser.parse_args()
    cfls = [float(c) for c in args.cfl.split(",")]
    names = (
        args.reconstructors.split(",") if args.reconstructors else registry.reconstructors.names()
    )
    results = [
        run_setting(kind, name, cfl, args.trials, args.pairs, args.cells, args.seed)
        for kind in DATA_KINDS
        for name in names
        for cfl in cfls
    ]
    print(
        f"Burgers, periodic, {args.cells} cells, {args.trials} trials per row, "
        f"{args.pairs} step pairs, seed {args.seed}\n"
    )
    print(markdown(results) if args.long else pivot_markdown(results))
    if args.json:
        parameters = {
            "model": "burgers",
            "boundary": "periodic",
            "cells": args.cells,
            "trials": args.trials,
            "pairs": args.pairs,
            "seed": args.seed,
            "round_off": "TV_new > TV_old + 1e-12 (1 + TV_old)",
        }
        with open(args.json, "w") as handle:
            json.dump(
                {"parameters": parameters, "results": [asdict(r) for r in results]},
                handle,
                indent=2,
            )


if __name__ == "__main__":
    main()
