"""``conslaw reproduce paper`` (with a coarser Fig. 3 to stay fast) and the run figures."""

from __future__ import annotations

import json
import re
from dataclasses import replace
from pathlib import Path

import pytest
from test_cli import cli

import conslaw
from conslaw.plotting import XT_MIN_OUTPUTS, figures_for
from conslaw.studies.reproduce import PAPER_FIGURES, reproduce_paper

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def reproduced(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[Path]]:
    folder = tmp_path_factory.mktemp("paper")
    fig3, fig4, fig5 = PAPER_FIGURES
    coarse3 = replace(
        fig3, overrides={"n_cells": 200, "output_times": [float(t) for t in range(21)]}
    )
    return folder, reproduce_paper(
        folder, [coarse3, fig4, fig5], log=lambda line: None, with_lagrangian=False
    )


def test_every_figure_of_the_report_is_written(reproduced: tuple[Path, list[Path]]) -> None:
    folder, files = reproduced
    report = (folder / "report.md").read_text()
    pictures = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", report)
    assert pictures == [
        "fig3-chute.png",
        "fig3-xt.png",
        "fig3-profiles.png",
        "fig4-profiles.png",
        "fig5-profiles.png",
        "fig5-margins.png",
    ]
    for name in pictures:
        assert (folder / name).read_bytes()[:8] == PNG
        assert folder / name in files
    for title in ("## Fig. 3", "## Fig. 4", "## Fig. 5", "## Error table"):
        assert title in report


def test_the_report_states_what_the_paper_shows(reproduced: tuple[Path, list[Path]]) -> None:
    """Fig. 4 (thin layer) has du/dx < 0 next to the margins, Fig. 5 (front tracking) nowhere;
    the shock moves upslope and the front rests in Fig. 3; the table matches fresh runs."""
    folder, _ = reproduced
    report = (folder / "report.md").read_text()
    fig4 = report.split("## Fig. 4")[1].split("## Fig. 5")[0]
    fig5 = report.split("## Fig. 5")[1].split("## Error table")[0]
    assert int(re.search(r"du/dx < 0 between (\d+) of", fig4).group(1)) > 0
    assert int(re.search(r"du/dx < 0 between (\d+) of", fig5).group(1)) == 0
    assert "moving upslope" in report and "NOT moving" not in report
    rows = json.loads((folder / "errors.json").read_text())
    assert [(r["scene"], r["n_cells"]) for r in rows] == [
        (scene, n) for scene in ("sh-similarity", "sh-similarity-ft") for n in (90, 180, 360)
    ]
    fresh = conslaw.run("sh-similarity-ft")
    assert rows[3]["l1"] == fresh.headline_error()
    assert f"L1 = {fresh.headline_error():.3e}" in fig5
    for thin, tracked in zip(rows[:3], rows[3:], strict=True):
        assert tracked["l1"] < thin["l1"]


def test_the_report_has_the_lagrangian_comparison(tmp_path: Path) -> None:
    """The lowest panel of Fig. 3: NT and the Lagrangian scheme with mu = 0 and 0.02 on the
    run-out (coarse here; `conslaw reproduce paper` runs the scene's 500 cells)."""
    files = reproduce_paper(
        tmp_path, [], with_error_table=False, overrides={"n_cells": 100}, log=lambda line: None
    )
    report = (tmp_path / "report.md").read_text()
    section = report.split("## Fig. 3, lowest panel")[1]
    assert "![lagrangian comparison](compare-sh-runout-shock.png)" in section
    assert (tmp_path / "compare-sh-runout-shock.png").read_bytes()[:8] == PNG
    assert tmp_path / "compare-sh-runout-shock.png" in files
    rows = [line for line in section.splitlines() if line.startswith("| ")][1:]
    assert [row.split("|")[1].strip() for row in rows] == [
        "nessyahu-tadmor, mc",
        "lagrangian(viscosity=0.0)",
        "lagrangian(viscosity=0.02)",
        "lagrangian(viscosity=0.02, pressure='flux')",
    ]
    assert "reached t = 20" in rows[0] and "reached t = 20" in rows[2]


def test_reproduce_refuses_an_unknown_target(tmp_path: Path) -> None:
    process = cli("reproduce", "papers", "--out", str(tmp_path / "o"))
    assert process.returncode == 2 and "invalid choice" in process.stderr
    assert not (tmp_path / "o").exists()


def test_a_run_with_many_output_times_draws_the_xt_diagram(tmp_path: Path) -> None:
    times = [0.1 * k for k in range(1, XT_MIN_OUTPUTS)]
    result = conslaw.run("burgers-riemann", n_cells=100, output_times=times, out=tmp_path)
    assert len(result.states) == XT_MIN_OUTPUTS
    assert [name for name, _ in figures_for(result)] == ["profiles.png", "xt.png"]
    assert (tmp_path / "xt.png").read_bytes()[:8] == PNG
    few = conslaw.run("burgers-riemann", n_cells=100)
    assert [name for name, _ in figures_for(few)] == ["profiles.png"]
