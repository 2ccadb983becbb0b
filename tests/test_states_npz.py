"""``states.npz`` says what its variables are (``variable_meanings``: on terrain the first is
the volume per map area H, not the slope-normal thickness) and holds ``q_exact`` only for a
scene with an exact solution, never an array of NaN (docs/output.md, "Output files" and "2D
runs")."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import conslaw


def test_on_terrain_the_states_say_their_thickness_is_h_over_cos(tmp_path: Path) -> None:
    """``terrain-plane-to-flat``: ``variables`` unchanged, ``variable_meanings[0]`` the
    volume per map area H = slope-normal thickness / cos(slope), and no ``q_exact`` (the
    scene has no exact solution)."""
    conslaw.run_2d(
        "terrain-plane-to-flat",
        out=tmp_path,
        n_cells=[40, 20],
        t_end=10.0,
        output_times=[5.0],
        output__formats=["npz"],
        output__plot=False,
    )
    with np.load(tmp_path / "states.npz") as states:
        assert states["variables"].tolist() == ["h", "hu", "hv"]
        assert states["variable_meanings"].tolist() == [
            "volume per map area H = slope-normal thickness / cos(slope) (m)",
            "H times the map x velocity (m^2/s)",
            "H times the map y velocity (m^2/s)",
        ]
        assert "q_exact" not in states.files
        assert states["q"].shape == (2, 3, 20, 40)


def test_q_exact_is_kept_for_a_scene_with_an_exact_solution(tmp_path: Path) -> None:
    """``sh2d-similarity`` has an exact solution: ``q_exact`` is there, finite, of the shape
    of ``q``; the variables' meanings are the chute model's (slope-normal depth)."""
    conslaw.run_2d(
        "sh2d-similarity",
        out=tmp_path,
        n_cells=[24, 16],
        t_end=1.0,
        output_times=[1.0],
        output__plot=False,
    )
    with np.load(tmp_path / "states.npz") as states:
        assert states["q_exact"].shape == states["q"].shape
        assert np.all(np.isfinite(states["q_exact"]))
        assert states["variable_meanings"][0] == "depth normal to the bed / H (dimensionless)"


def test_a_1d_run_without_an_exact_solution_has_no_q_exact(tmp_path: Path) -> None:
    """1D alike: ``sh-runout-shock`` (no exact solution) writes no ``q_exact``;
    ``burgers-riemann`` does, finite (tests/test_cli.py reads it)."""
    conslaw.run("sh-runout-shock", out=tmp_path / "a", n_cells=100, output__plot=False)
    with np.load(tmp_path / "a" / "states.npz") as states:
        assert "q_exact" not in states.files
        assert states["variables"].tolist() == ["h", "hu"]
        assert states["variable_meanings"].shape == (2,)
    conslaw.run("burgers-riemann", out=tmp_path / "b", n_cells=100, output__plot=False)
    with np.load(tmp_path / "b" / "states.npz") as states:
        assert np.all(np.isfinite(states["q_exact"]))
        assert states["variable_meanings"].tolist() == ["u"]
