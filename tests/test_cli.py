"""The command line: list, run, and one-line errors with exit code 2 for bad input."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

CONSLAW = shutil.which("conslaw") or ""


def cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """Run the installed console script (falls back to ``python -m conslaw.cli``)."""
    command = [CONSLAW] if CONSLAW else [sys.executable, "-m", "conslaw.cli"]
    return subprocess.run(
        [*command, *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=300,
        env={**os.environ, "COLUMNS": "200"},
    )


def assert_one_line_error(process: subprocess.CompletedProcess[str], *fragments: str) -> None:
    assert process.returncode == 2, process.stderr
    lines = process.stderr.strip().splitlines()
    assert len(lines) == 1, process.stderr
    assert "Traceback" not in process.stderr
    assert lines[0].startswith("conslaw: error: ")
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


def test_list_shows_every_registered_name() -> None:
    process = cli("list")
    assert process.returncode == 0, process.stderr
    out = process.stdout
    assert "reconstructors (7):" in out
    for name in ("none", "minmod", "superbee", "vanleer", "mc", "weno3", "weno5"):
        assert f"  {name} " in out
    assert "schemes (3):" in out and "nessyahu-tadmor" in out and "  lagrangian " in out
    assert "  front-tracking " in out
    assert "  burgers " in out and "  shallow-water " in out
    assert "boundary conditions (4):" in out
    for name in ("periodic", "outflow", "wall", "inflow"):
        assert f"  {name} " in out
    for scene in (
        "burgers-riemann",
        "burgers-sine",
        "dam-break-wet",
        "dam-break-dry",
        "lake-at-rest",
    ):
        assert f"  {scene} " in out
    assert "initial conditions (4):" in out
    for kind in ("piecewise-constant", "sine", "parabolic-cap", "still-water"):
        assert f"  {kind} " in out
    assert "(savage-hutter only)" in out


def test_run_writes_npz_resolved_toml_and_png(tmp_path: Path) -> None:
    out = tmp_path / "run"
    process = cli("run", "burgers-riemann", "--set", "n_cells=1600", "--out", str(out))
    assert process.returncode == 0, process.stderr
    assert "L1=" in process.stdout
    with np.load(out / "states.npz") as data:
        assert data["q"].shape == (2, 1, 1600)
        np.testing.assert_array_equal(data["t"], [0.5, 1.0])
        l1 = np.sum(np.abs(data["q"][-1, 0] - data["q_exact"][-1, 0])) * (4 / 1600) / 4
        assert l1 <= 6e-4
    resolved = tomllib.loads((out / "scene.toml").read_text())
    assert resolved["n_cells"] == 1600 and resolved["reconstructor"] == "mc"
    assert resolved["boundary"] == {"left": "outflow", "right": "outflow"}
    assert (out / "profiles.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_resolved_scene_reruns_to_the_same_result(tmp_path: Path) -> None:
    first = tmp_path / "a"
    assert (
        cli(
            "run", "burgers-sine", "--set", "n_cells=64", "--no-plot", "--out", str(first)
        ).returncode
        == 0
    )
    second = tmp_path / "b"
    process = cli("run", str(first / "scene.toml"), "--no-plot", "--out", str(second))
    assert process.returncode == 0, process.stderr
    with np.load(first / "states.npz") as a, np.load(second / "states.npz") as b:
        np.testing.assert_array_equal(a["q"], b["q"])


# The bad-input cases (one error line, exit code 2, nothing written) are collected in
# tests/test_bad_input.py.


def test_show_prints_the_resolved_scene() -> None:
    process = cli("show", "burgers-sine", "--set", "n_cells=123")
    assert process.returncode == 0, process.stderr
    resolved = tomllib.loads(process.stdout)
    assert resolved["n_cells"] == 123 and resolved["cfl"] == 0.45


def test_version() -> None:
    import conslaw

    process = cli("--version")
    assert process.returncode == 0 and process.stdout.strip() == f"conslaw {conslaw.__version__}"


def test_a_result_prints_in_one_short_line() -> None:
    import conslaw

    result = conslaw.run("burgers-riemann", n_cells=40)
    text = repr(result)
    assert "\n" not in text and len(text) < 200, text
    assert text.startswith("<RunResult burgers-riemann: burgers, nessyahu-tadmor, N=40")


def test_a_compile_notice_says_which_kernel_of_a_model_it_builds() -> None:
    """Parameters choose among a model's kernels (a bed or none, phi = delta or above): the
    notice names the one, so that a second compile for the same model is explained."""
    from conslaw.config import load_scene
    from conslaw.simulation import build, kernel_label

    labels = {}
    for name in ("sh-runout-shock", "sh-runout-phi35", "dam-break-wet", "lake-at-rest",
                 "burgers-riemann"):  # fmt: skip
        scene = load_scene(name)
        labels[name] = kernel_label(scene, build(scene)[0])
    assert labels == {
        "sh-runout-shock": "savage-hutter, phi = delta",
        "sh-runout-phi35": "savage-hutter, phi > delta",
        "dam-break-wet": "shallow-water, flat bed",
        "lake-at-rest": "shallow-water, with a bed",
        "burgers-riemann": "burgers",
    }


def test_python_dash_m_conslaw_is_the_command() -> None:
    """``python -m conslaw`` runs the same command as the console script."""
    module = subprocess.run(
        [sys.executable, "-m", "conslaw", "list"], capture_output=True, text=True, timeout=300
    )
    assert module.returncode == 0, module.stderr
    assert module.stdout == cli("list").stdout


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["show", "sh2d-similarity", "--set", "initial.radii=[0.01, 1]"], "initial.radii"),
        (
            ["show", "terrain-plane-to-flat", "--set",
             "initial.polygon=[[1e6, 0.0], [2e6, 0.0], [2e6, 1.0]]"],
            "initial.polygon",
        ),
        (["show", "sh-similarity", "--set", "initial.height=-1"], "initial"),
    ],
)  # fmt: skip
def test_show_refuses_what_a_run_would_refuse_before_its_first_step(
    args: list[str], fragment: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """``conslaw show`` builds the initial data too: a scene it prints would start."""
    from conslaw.cli import main

    assert main(args) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and fragment in lines[0], captured.err
