"""The convergence tool: study rows, refusal without an exact solution, files written."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_cli import assert_one_line_error, cli

from conslaw.errors import ConfigError
from conslaw.studies.convergence import convergence_study, write_study


def test_study_rows_orders_and_timings() -> None:
    study = convergence_study(
        "burgers-sine", [50, 100, 200], ["mc", "none"], repeats=2, measure_import=False
    )
    assert [(r.reconstructor, r.n_cells) for r in study.rows] == [
        ("mc", 50), ("mc", 100), ("mc", 200), ("none", 50), ("none", 100), ("none", 200),
    ]  # fmt: skip
    mc = [r for r in study.rows if r.reconstructor == "mc"]
    assert mc[0].order_l1 is None and mc[2].order_l1 is not None and mc[2].order_l1 > 1.8
    assert all(r.solve_min <= r.solve_median <= r.solve_max for r in study.rows)
    assert set(study.warmup_seconds) == {"nessyahu-tadmor/mc", "nessyahu-tadmor/none"}


def test_scene_without_exact_solution_is_refused() -> None:
    with pytest.raises(ConfigError, match="no exact solution"):
        convergence_study("sh-runout-shock", [20, 40], repeats=1, measure_import=False)


def test_write_study_files(tmp_path: Path) -> None:
    study = convergence_study("burgers-riemann", [50, 100], repeats=1, measure_import=False)
    written = write_study(study, tmp_path)
    names = sorted(p.name for p in written)
    assert names == sorted(
        [
            "convergence-burgers-riemann.md", "convergence-burgers-riemann.csv",
            "convergence-burgers-riemann.json", "convergence-burgers-riemann-error-vs-time.png",
            "convergence-burgers-riemann-error-vs-cells.png",
        ]
    )  # fmt: skip
    document = json.loads((tmp_path / "convergence-burgers-riemann.json").read_text())
    assert [row["n_cells"] for row in document["rows"]] == [50, 100]
    assert (tmp_path / "convergence-burgers-riemann-error-vs-time.png").read_bytes()[
        :4
    ] == b"\x89PNG"


def test_cli_convergence(tmp_path: Path) -> None:
    process = cli(
        "convergence", "dam-break-dry", "--cells", "50,100", "--reconstructor", "mc,minmod",
        "--repeats", "1", "--out", str(tmp_path),
    )  # fmt: skip
    assert process.returncode == 0, process.stderr
    assert "| nessyahu-tadmor | minmod | 100 |" in process.stdout
    assert (tmp_path / "convergence-dam-break-dry.csv").exists()


def test_cli_convergence_bad_input(tmp_path: Path) -> None:
    assert_one_line_error(cli("convergence", "dam-break-wet", "--cells", "10,abc"), "--cells")
    assert_one_line_error(
        cli("convergence", "dam-break-wet", "--cells", "50", "--reconstructor", "mc,wen05"),
        "did you mean 'weno5'",
    )
