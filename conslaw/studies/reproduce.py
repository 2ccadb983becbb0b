"""``conslaw reproduce paper``: the figures of Tai, Noelle, Gray & Hutter (2001) and a report.

Each entry of :data:`PAPER_FIGURES` names a built-in scene, the settings the paper states, the
figures drawn from the run and the numbers that check what the paper's figure shows. To add a
figure of one run, append a :class:`PaperFigure`; the comparison of Fig. 3 with the Lagrangian
moving grid (several runs) is its own section. The report
(``report.md``) holds, per figure, the paper's caption, the measured facts and the pictures, and
the error table of the similarity solution with and without front tracking at 90, 180 and 360
cells (``errors.json`` has the same numbers).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from conslaw.analysis import observed_orders
from conslaw.config import load_scene
from conslaw.simulation import RunResult, simulate
from conslaw.studies.convergence import margin_error

FigureBuilder = Callable[[RunResult], Any]


@dataclass(frozen=True)
class PaperFigure:
    """One figure of the paper, reproduced from one run.

    Attributes
    ----------
    key : str
        File-name prefix (``fig3``).
    title : str
        One line for the report.
    caption : str
        What the paper's figure shows (its caption, shortened).
    scene : str
        Built-in scene with the paper's settings.
    overrides : dict
        Scene keys changed for the reproduction (e.g. denser output times).
    figures : sequence of (name, builder)
        PNGs written as ``<key>-<name>.png`` from the run.
    facts : callable
        Lines of measured facts for the report.
    """

    key: str
    title: str
    caption: str
    scene: str
    overrides: dict[str, Any] = field(default_factory=dict)
    figures: Sequence[tuple[str, FigureBuilder]] = ()
    facts: Callable[[RunResult], list[str]] = lambda result: []


# ---------------------------------------------------------------------- Fig. 3
FIG3_TIMES = (0.0, 4.0, 8.0, 12.0, 16.0, 20.0)


def _state_at(result: RunResult, t: float) -> Any:
    return min(result.states, key=lambda s: abs(s.t - t))


def largest_jump(state: Any) -> float:
    """Position of the largest jump in ``h`` between neighbouring cells (the shock)."""
    h = state.q[0]
    k = int(np.argmax(np.abs(np.diff(h))))
    return float(0.5 * (state.x[k] + state.x[k + 1]))


def _fig3_facts(result: RunResult) -> list[str]:
    later = [_state_at(result, t) for t in (12.0, 16.0, 20.0)]
    shocks = [largest_jump(s) for s in later]
    fronts = [float(s.x[np.nonzero(s.q[0] > 1e-6)[0][-1]]) for s in later]
    last = later[-1]
    flat = last.x >= 25.5
    moving = int(np.count_nonzero(last.q[1][flat]))
    mass = abs(result.mass_drift[0])
    return [
        "largest jump in h (the shock) at x = "
        + ", ".join(f"{x:.2f}" for x in shocks)
        + " for t = 12, 16, 20: "
        + ("moving upslope" if shocks[0] > shocks[1] > shocks[2] else "NOT moving upslope"),
        "front (last cell with h > 1e-6) at x = "
        + ", ".join(f"{x:.2f}" for x in fronts)
        + " for t = 12, 16, 20: "
        + ("at rest from t = 16" if fronts[1] == fronts[2] else "still moving"),
        f"cells on the flat run-out (x >= 25.5) with non-zero momentum at t = 20: {moving}",
        f"relative change of the total mass: {mass:.1e}",
    ]


def _fig3_chute(result: RunResult) -> Any:

    return result.model.figures()["chute.png"](result, FIG3_TIMES)


def _fig3_profiles(result: RunResult) -> Any:
    from conslaw.plotting import profiles_figure

    return profiles_figure(result, FIG3_TIMES[2:])


def _xt(result: RunResult) -> Any:
    from conslaw.plotting import xt_figure

    return xt_figure(result)


# ---------------------------------------------------------------------- Figs. 4 and 5
def _profiles(result: RunResult) -> Any:
    from conslaw.plotting import profiles_figure

    return profiles_figure(result, (result.scene.t_end,))


def _margins(result: RunResult) -> Any:
    from conslaw.plotting import margins_figure

    return margins_figure(result)


def _velocity_gradient_signs(result: RunResult) -> tuple[int, int]:
    """Cells of the body (h > 1e-3) and how many of them have du/dx < 0 between neighbours."""
    h, m = result.final.q
    body = np.nonzero(h > 1e-3)[0]
    u = m[body] / h[body]
    return body.size, int(np.count_nonzero(np.diff(u) < 0.0))


def _similarity_facts(result: RunResult) -> list[str]:
    norms = result.errors[-1]
    assert norms is not None
    cells, decreasing = _velocity_gradient_signs(result)
    lines = [
        f"error of h at t = {result.final.t:g} against the exact cell averages: "
        f"L1 = {norms.l1:.3e}, L2 = {norms.l2:.3e}, Linf = {norms.linf:.3e}",
        f"du/dx < 0 between {decreasing} of the {cells - 1} neighbouring pairs of body cells "
        "(h > 1e-3)",
    ]
    distance = margin_error(result)
    if distance is not None:
        lines.append(
            f"largest margin distance from the exact margins at t = 6: {distance:.3e} "
            f"({distance / result.grid.dx:.2f} dx)"
        )
    return lines


PAPER_FIGURES: list[PaperFigure] = [
    PaperFigure(
        "fig3",
        "Fig. 3: avalanche on the chute, at rest in the run-out, a shock moving upslope",
        "NOC scheme at t = 0, 4, 8, 12, 16, 20: the front reaches the run-out and comes to rest, "
        "the tail accelerates further and the body contracts; a shock forms (t = 12) and moves "
        "upslope.",
        "sh-runout-shock",
        {"output_times": [round(0.2 * k, 1) for k in range(101)]},
        (("chute", _fig3_chute), ("xt", _xt), ("profiles", _fig3_profiles)),
        _fig3_facts,
    ),
    PaperFigure(
        "fig4",
        "Fig. 4: similarity solution, NOC + superbee, thin layer 1e-4, 90 cells",
        "Depth (upper) and velocity (lower) at t = 6, circles computed, lines exact; the depth "
        "follows the parabola, the velocity is smeared across the margins (du/dx < 0 there).",
        "sh-similarity",
        {},
        (("profiles", _profiles),),
        _similarity_facts,
    ),
    PaperFigure(
        "fig5",
        "Fig. 5: similarity solution, NOC + WENO (r = 3) with front tracking, 90 cells, CFL 0.3",
        "Depth and velocity at t = 6: parabola and margins well described, no clipping, "
        "du/dx > 0 in the whole body.",
        "sh-similarity-ft",
        {},
        (("profiles", _profiles), ("margins", _margins)),
        _similarity_facts,
    ),
]

#: Scenes of the error table and the numbers of cells.
ERROR_TABLE_SCENES = ("sh-similarity", "sh-similarity-ft")
ERROR_TABLE_CELLS = (90, 180, 360)


def error_table() -> list[dict[str, Any]]:
    """Errors of h at t_end against the exact cell averages (and margin errors with front
    tracking) for :data:`ERROR_TABLE_SCENES` at :data:`ERROR_TABLE_CELLS`."""
    rows: list[dict[str, Any]] = []
    for name in ERROR_TABLE_SCENES:
        base = load_scene(name)
        errors: list[float] = []
        for n in ERROR_TABLE_CELLS:
            result = simulate(replace(base, n_cells=n, output_times=(base.t_end,)))
            norms = result.errors[-1]
            assert norms is not None
            errors.append(norms.l1)
            order = observed_orders(ERROR_TABLE_CELLS[: len(errors)][-2:], errors[-2:])
            rows.append(
                {
                    "scene": name,
                    "method": f"{base.reconstructor}{' + FT' if base.front_tracking else ''}",
                    "n_cells": n,
                    "l1": norms.l1,
                    "l2": norms.l2,
                    "linf": norms.linf,
                    "order_l1": order[0] if len(errors) > 1 else None,
                    "margin_error": margin_error(result),
                    "steps": result.steps,
                }
            )
    return rows


def _table_markdown(rows: list[dict[str, Any]]) -> str:
    lines = [
        "| scene | method | N | L1(h) | L2(h) | Linf(h) | order L1 | margin error | steps |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        order = "-" if r["order_l1"] is None else f"{r['order_l1']:.2f}"
        margin = "-" if r["margin_error"] is None else f"{r['margin_error']:.3e}"
        lines.append(
            f"| {r['scene']} | {r['method']} | {r['n_cells']} | {r['l1']:.3e} | {r['l2']:.3e} "
            f"| {r['linf']:.3e} | {order} | {margin} | {r['steps']} |"
        )
    return "\n".join(lines)


def _lagrangian_section(folder: Path, overrides: dict[str, Any] | None) -> tuple[str, list[Path]]:
    """The paper's Fig. 3 comparison with the Lagrangian moving grid of Savage & Hutter (1989):
    ``sh-runout-shock`` with NT and the Lagrangian scheme without and with artificial viscosity
    (:func:`conslaw.studies.comparison.runout_comparison`), as a report section."""
    from conslaw.studies.comparison import RUNOUT_SCHEMES, compare, write_comparison

    comparison = compare("sh-runout-shock", RUNOUT_SCHEMES, overrides)
    files = write_comparison(comparison, folder)
    picture = next(p for p in files if p.suffix == ".png")
    section = (
        "## Fig. 3, lowest panel: the Lagrangian moving grid at the shock\n\n"
        "*Paper:* for the Lagrangian moving-grid method without artificial viscosity, "
        "oscillations take place when the shock occurs, which may let an element boundary "
        "overtake another and destroy the scheme; Savage & Hutter damp them with mu = 0.01-0.03."
        "\n\n*Run:* `conslaw compare sh-runout-shock --scheme "
        f"{','.join(RUNOUT_SCHEMES)}`.\n\n*Measured:*\n\n{comparison.table()}\n\n"
        f"![lagrangian comparison]({picture.name})\n"
    )
    return section, files


def reproduce_paper(
    folder: Path,
    figures: Sequence[PaperFigure] | None = None,
    with_error_table: bool = True,
    overrides: dict[str, Any] | None = None,
    log: Callable[[str], None] = print,
    with_lagrangian: bool = True,
) -> list[Path]:
    """Run every figure of :data:`PAPER_FIGURES` (or ``figures``), write its PNGs, the
    comparison with the Lagrangian scheme (``with_lagrangian``), the error table and
    ``report.md`` into ``folder``; returns the files written. ``overrides`` change every scene
    (a quick test with fewer cells)."""
    import matplotlib.pyplot as plt

    from conslaw.io import atomic_write_bytes, prepare_output_dir, write_figure

    folder = prepare_output_dir(Path(folder))
    written: list[Path] = []
    sections: list[str] = []
    started = time.perf_counter()
    for entry in PAPER_FIGURES if figures is None else figures:
        began = time.perf_counter()
        scene = load_scene(entry.scene, {**entry.overrides, **(overrides or {})})
        result = simulate(scene)
        pictures = []
        for name, build in entry.figures:
            figure = build(result)
            path = write_figure(folder / f"{entry.key}-{name}.png", figure)
            plt.close(figure)
            written.append(path)
            pictures.append(f"![{entry.key} {name}]({path.name})")
        seconds = time.perf_counter() - began
        settings = (
            f"`conslaw run {entry.scene}`"
            + "".join(f" `--set {k}=...`" for k in entry.overrides)
            + f": {scene.model}, {scene.reconstructor}"
            + (" + front tracking" if scene.front_tracking else "")
            + f", N = {scene.n_cells}, CFL {scene.cfl:g}, t_end = {scene.t_end:g}, "
            f"{result.steps} steps"
        )
        facts = "\n".join(f"- {line}" for line in entry.facts(result))
        sections.append(
            f"## {entry.title}\n\n*Paper:* {entry.caption}\n\n*Run:* {settings} "
            f"({seconds:.1f} s with compilation).\n\n*Measured:*\n\n{facts}\n\n"
            + "\n".join(pictures)
            + "\n"
        )
        names = ", ".join(p.name for p in written[-len(pictures) :])
        log(f"{entry.key}: {seconds:.1f} s, wrote {names}")
    if with_lagrangian:
        began = time.perf_counter()
        section, files = _lagrangian_section(folder, overrides)
        sections.append(section)
        written.extend(files)
        names = ", ".join(p.name for p in files)
        log(f"lagrangian comparison: {time.perf_counter() - began:.1f} s, wrote {names}")
    table = ""
    if with_error_table:
        began = time.perf_counter()
        rows = error_table()
        written.append(
            atomic_write_bytes(folder / "errors.json", json.dumps(rows, indent=2).encode())
        )
        table = (
            "## Error table: the similarity solution at t = 6\n\n"
            "Errors of h against the exact cell averages (the norms of docs/equations.md), "
            "largest distance of a tracked margin from the exact one.\n\n"
            + _table_markdown(rows)
            + "\n"
        )
        log(f"error table: {time.perf_counter() - began:.1f} s")
    total = time.perf_counter() - started
    report = (
        "# Tai, Noelle, Gray & Hutter (2001), reproduced\n\n"
        f"Written by `conslaw reproduce paper` in {total:.0f} s.\n\n"
        + "\n".join(sections)
        + ("\n" + table if table else "")
    )
    written.append(atomic_write_bytes(folder / "report.md", report.encode()))
    return written
