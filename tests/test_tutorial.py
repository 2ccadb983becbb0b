"""The "adding a model" tutorial (docs/tutorial-model.md), executed: its files are written out,
the model is registered through its entry point exactly as ``pip install`` would register it
(a ``.dist-info`` folder on the path), and then listed, run, checked by the tutorial's own script
and by the registry-wide property tests."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TUTORIAL = ROOT / "docs" / "tutorial-model.md"
#: Reconstructors left out of the quick property run (the slow test runs them all).
OTHER_RECONSTRUCTORS = ("none", "minmod", "superbee", "vanleer", "weno3", "weno5")


def tutorial_files() -> dict[str, str]:
    """Every fenced block of the tutorial whose first line is ``# file: NAME``."""
    blocks = re.findall(r"```[a-z]+\n# file: (\S+)\n(.*?)```", TUTORIAL.read_text(), re.DOTALL)
    return {name: body for name, body in blocks}


@pytest.fixture(scope="module")
def plugin(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, str]]:
    """The tutorial's package, installed by path: its files and the entry points of its
    ``pyproject.toml`` in a ``.dist-info`` folder. Returns the folder and the environment."""
    folder = tmp_path_factory.mktemp("tutorial")
    files = tutorial_files()
    for name, body in files.items():
        (folder / name).write_text(body)
    project = tomllib.loads(files["pyproject.toml"])["project"]
    info = folder / f"{project['name'].replace('-', '_')}-{project['version']}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: {project['name']}\nVersion: {project['version']}\n"
    )
    lines = []
    for group, entries in project["entry-points"].items():
        lines.append(f"[{group}]")
        lines += [f"{name} = {target}" for name, target in entries.items()]
    (info / "entry_points.txt").write_text("\n".join(lines) + "\n")
    path = os.pathsep.join([str(folder), os.environ.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return folder, {**os.environ, "PYTHONPATH": path}


def run(
    arguments: list[str], cwd: Path, env: dict[str, str], timeout: float = 600
) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        arguments, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout
    )


def test_the_tutorial_has_its_files() -> None:
    assert set(tutorial_files()) == {
        "conslaw_traffic.py",
        "pyproject.toml",
        "traffic-jam.toml",
        "check_traffic.py",
    }


def test_the_model_is_registered_through_its_entry_point(
    plugin: tuple[Path, dict[str, str]],
) -> None:
    folder, env = plugin
    listing = run([sys.executable, "-m", "conslaw.cli", "list"], folder, env)
    assert listing.returncode == 0, listing.stderr
    assert "  traffic " in listing.stdout and "LWR traffic flow" in listing.stdout
    assert "skipped" not in listing.stderr


def test_the_scene_runs_and_the_check_script_passes(plugin: tuple[Path, dict[str, str]]) -> None:
    folder, env = plugin
    command = [sys.executable, "-m", "conslaw.cli", "run", "traffic-jam.toml", "--out", "jam"]
    process = run(command, folder, env)
    assert process.returncode == 0, process.stderr
    assert (folder / "jam" / "states.npz").exists() and (folder / "jam" / "profiles.png").exists()
    check = run([sys.executable, "check_traffic.py"], folder, env)
    assert check.returncode == 0, check.stdout + check.stderr
    assert "Rankine-Hugoniot: -0.4000" in check.stdout


def test_bad_parameters_of_the_tutorial_model_are_one_line(
    plugin: tuple[Path, dict[str, str]],
) -> None:
    folder, env = plugin
    command = [sys.executable, "-m", "conslaw.cli", "run", "traffic-jam.toml"]
    process = run([*command, "--set", "parameters.v_max=-1"], folder, env)
    assert process.returncode == 2 and "parameters.v_max: must be > 0" in process.stderr
    assert len(process.stderr.strip().splitlines()) == 1


def _property_tests(env: dict[str, str], selection: str) -> subprocess.CompletedProcess[str]:
    command = [sys.executable, "-m", "pytest", "tests/test_properties.py", "-k", selection]
    return run([*command, "-n", "0", "-q", "-p", "no:cacheprovider"], ROOT, env, timeout=1800)


def test_the_registry_wide_property_tests_cover_the_model(
    plugin: tuple[Path, dict[str, str]],
) -> None:
    """The property tests pick the plugin up from the registry (MC slopes here; every
    reconstructor in the slow test below)."""
    _, env = plugin
    others = " and ".join(f"not {name}" for name in OTHER_RECONSTRUCTORS)
    process = _property_tests(env, f"traffic and {others}")
    assert process.returncode == 0, process.stdout[-3000:]
    passed = int(re.search(r"(\d+) passed", process.stdout).group(1))
    assert passed >= 6, process.stdout[-2000:]


@pytest.mark.slow
def test_every_property_test_passes_for_the_model(plugin: tuple[Path, dict[str, str]]) -> None:
    _, env = plugin
    process = _property_tests(env, "traffic")
    assert process.returncode == 0, process.stdout[-3000:]
