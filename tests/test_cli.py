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
    assert "schemes (2):" in out and "nessyahu-tadmor" in out and "  lagrangian " in out
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


BAD_INPUT = [
    (["run", "no-such-scene"], ["unknown scene 'no-such-scene'", "burgers-riemann"]),
    (
        ["run", "burgers-riemann", "--set", "model=burger"],
        ["unknown model 'burger'", "did you mean 'burgers'"],
    ),
    (
        ["run", "burgers-riemann", "--set", "scheme=upwind"],
        ["unknown scheme 'upwind'", "nessyahu-tadmor"],
    ),
    (
        ["run", "burgers-riemann", "--set", "reconstructor=superbe"],
        ["unknown reconstructor", "did you mean 'superbee'"],
    ),
    (
        ["run", "burgers-riemann", "--set", "n_cell=100"],
        ["unknown scene key 'n_cell'", "did you mean 'n_cells'"],
    ),
    (["run", "burgers-riemann", "--set", "cfl=0.5"], ["cfl", "(0, 0.5)"]),
    (["run", "burgers-riemann", "--set", "cfl=0.9"], ["cfl", "(0, 0.5)"]),
    (["run", "burgers-riemann", "--set", "n_cells=3"], ["n_cells", ">= 4"]),
    (["run", "burgers-riemann", "--set", "n_cells=abc"], ["n_cells", ">= 4"]),
    (
        ["run", "burgers-riemann", "--set", "initial.states=[nan, 1.0, 0.0]"],
        ["initial.states", "finite"],
    ),
    (["run", "burgers-riemann", "--set", "x_max=-2"], ["x_min < x_max"]),
    (
        ["run", "burgers-riemann", "--set", "boundary.left=walll"],
        ["unknown boundary condition", "did you mean 'wall'"],
    ),
    (["run", "burgers-riemann", "--set", "boundary.left=periodic"], ["periodic", "both sides"]),
    (
        ["run", "burgers-riemann", "--set", "initial.kind=cosine"],
        ["initial.kind", "piecewise-constant"],
    ),
    (["run", "burgers-riemann", "--set", "parameters.g=1"], ["takes no parameters"]),
    (["run", "burgers-riemann", "--bogus"], ["unrecognized arguments"]),
    (["run", "burgers-riemann", "--set", "n_cells=10000000000"], ["n_cells", "<= 50000000"]),
    (["run", "burgers-sine", "--set", "x_min=-1e308", "--set", "x_max=1e308"], ["finite length"]),
    (
        ["run", "burgers-riemann", "--set", 'boundary.left={kind="inflow", state=[1, "a"]}'],
        ["boundary 'inflow' needs state", "1 numbers"],
    ),
    (
        [
            "run",
            "sh-runout-shock",
            "--set",
            "parameters.chute=table",
            "--set",
            "parameters.chute_file=5",
        ],
        ["chute_file", "file name"],
    ),
    (["run", "dam-break-wet", "--set", "parameters.g=1e308"], ["wave speed is not finite"]),
    (
        ["show", "sh-similarity", "--set", "parameters.delta=40"],
        ["must be <= internal friction angle"],
    ),
    (["frobnicate"], ["invalid choice"]),
]


@pytest.mark.parametrize(
    ("args", "fragments"), BAD_INPUT, ids=[" ".join(a[1:]) or a[0] for a, _ in BAD_INPUT]
)
def test_bad_input_is_one_line_exit_2_nothing_written(
    tmp_path: Path, args: list[str], fragments: list[str]
) -> None:
    out = tmp_path / "out"
    extra = ["--out", str(out)] if args[0] == "run" and "--bogus" not in args else []
    process = cli(*args, *extra, cwd=tmp_path)
    assert_one_line_error(process, *fragments)
    assert not out.exists()
    assert not (tmp_path / "conslaw-output").exists()


def test_malformed_scene_file(tmp_path: Path) -> None:
    scene = tmp_path / "broken.toml"
    scene.write_text('model = "burgers"\nn_cells = [1,\n')
    assert_one_line_error(
        cli("run", str(scene), "--out", str(tmp_path / "o")), "not valid TOML", "broken.toml"
    )


def test_unknown_key_in_scene_file(tmp_path: Path) -> None:
    scene = tmp_path / "typo.toml"
    scene.write_text(
        'model = "burgers"\nn_cells = 10\nx_min = 0.0\nx_max = 1.0\nt_end = 0.1\n'
        'recontructor = "mc"\n'
        '[initial]\nkind = "sine"\nmean = 0.0\namplitude = 0.1\n'
    )
    assert_one_line_error(
        cli("run", str(scene)), "unknown scene key 'recontructor'", "did you mean 'reconstructor'"
    )


def test_unwritable_output_directory(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("keep me")
    process = cli("run", "burgers-sine", "--out", str(blocker / "sub"))
    assert_one_line_error(process, "output directory")
    assert blocker.read_text() == "keep me"


def test_show_prints_the_resolved_scene() -> None:
    process = cli("show", "burgers-sine", "--set", "n_cells=123")
    assert process.returncode == 0, process.stderr
    resolved = tomllib.loads(process.stdout)
    assert resolved["n_cells"] == 123 and resolved["cfl"] == 0.45
