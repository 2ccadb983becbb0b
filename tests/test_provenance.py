"""Provenance: every run's output says what made it and what it read (docs/output.md,
"Provenance"), and its scene.toml runs again from anywhere."""

from __future__ import annotations

import hashlib
import json
import shutil
from pathlib import Path

import numpy as np
from test_cli import cli

import conslaw
from conslaw import __version__
from conslaw.config import load_scene

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "docs" / "examples"


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_scene_toml_and_states_npz_record_versions_and_input_files(tmp_path: Path) -> None:
    inputs = tmp_path / "inputs"
    shutil.copytree(EXAMPLE, inputs)
    out = tmp_path / "runs" / "terrain"
    process = cli(
        "run", "inputs/terrain-avalanche.toml", "--set", "n_cells=60", "--set", "t_end=1.0",
        "--set", "output_times=[]", "--no-plot", "--out", "runs/terrain", cwd=tmp_path,
    )  # fmt: skip
    assert process.returncode == 0, process.stderr
    text = (out / "scene.toml").read_text()
    header = [line for line in text.splitlines() if line.startswith("#")]
    assert f"#   conslaw = {__version__}" in header
    assert f"#   scene sha256 = {sha256(inputs / 'terrain-avalanche.toml')}" in header
    assert f"#   parameters.chute_file sha256 = {sha256(inputs / 'terrain-profile.csv')}" in header
    # Input files named relative to the output folder; the description says what changed.
    assert 'chute_file = "../../inputs/terrain-profile.csv"' in text
    assert "[changed: n_cells=60, t_end=1.0, output_times=[]]" in text
    with np.load(out / "states.npz") as data:
        record = json.loads(str(data["provenance"]))
        first = data["q"].copy()
    assert record["conslaw"] == __version__
    assert record["parameters.chute_file sha256"] == sha256(inputs / "terrain-profile.csv")
    assert {"python", "numpy", "scipy", "numba", "conslaw_commit"} <= set(record)

    # The written scene runs again from another folder, moved together with its inputs, and
    # gives the same states.
    moved = tmp_path / "elsewhere"
    shutil.copytree(tmp_path / "runs", moved / "runs")
    shutil.copytree(inputs, moved / "inputs")
    again = cli("run", str(moved / "runs" / "terrain" / "scene.toml"), "--no-plot", "--out",
                str(tmp_path / "again"), cwd=ROOT)  # fmt: skip
    assert again.returncode == 0, again.stderr
    with np.load(tmp_path / "again" / "states.npz") as data:
        assert np.array_equal(data["q"], first)


def test_the_same_run_writes_the_same_bytes(tmp_path: Path) -> None:
    for folder in ("a", "b"):
        conslaw.run("burgers-sine", n_cells=32, out=tmp_path / folder)
    for name in ("scene.toml", "states.npz"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()


def test_labelled_results_carry_the_provenance() -> None:
    result = conslaw.run("burgers-sine", n_cells=32)
    record = json.loads(result.to_xarray().attrs["provenance"])
    assert record["conslaw"] == __version__
    assert record["scene path"].endswith("burgers-sine.toml")


def test_a_scene_without_overrides_keeps_its_description() -> None:
    plain = load_scene("burgers-sine")
    assert "[changed" not in plain.description
    changed = load_scene("burgers-sine", {"n_cells": 64})
    assert changed.description == f"{plain.description} [changed: n_cells=64]"
    assert load_scene("burgers-sine", {"description": "mine"}).description == "mine"
