"""2D scenes end to end: scene files, initial conditions, exact solutions, the runner, the files
of ``conslaw run`` (npz, XDMF + HDF5 read back with meshio, PNG maps) and bad input."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import meshio
import numpy as np
import pytest
import tomli_w
from hypothesis import given, settings, strategies as st

from conslaw import registry
from conslaw.cli import main
from conslaw.config import load_scene
from conslaw.errors import ConfigError
from conslaw.grid import Grid
from conslaw.grid2d import Grid2D
from conslaw.initial import piecewise_constant_averages
from conslaw.initial2d import area_below
from conslaw.scene2d import load_any_scene, load_scene_2d
from conslaw.simulation import simulate
from conslaw.simulation2d import run_2d, simulate_2d

SCENES_2D = [
    "sw2d-dam-break-x",
    "sw2d-dam-break-y",
    "sw2d-dam-break-diagonal",
    "sw2d-radial-dam-break",
    "sw2d-lake-island",
    "sw2d-thacker",
    "burgers2d-smooth",
    "burgers2d-shock",
    "sh2d-similarity",
    "sh2d-runout",
    "terrain-plane-to-flat",
    "terrain-channel",
    "terrain-bowl",
]


def small(name: str, **overrides: object) -> object:
    """A built-in 2D scene with overrides (no figures)."""
    return load_scene_2d(name, {"output.plot": False, **overrides})


# ------------------------------------------------------------------ initial conditions
@settings(max_examples=200, deadline=None)
@given(
    a=st.floats(-3.0, 3.0).filter(lambda v: abs(v) > 1e-3),
    b=st.floats(-3.0, 3.0).filter(lambda v: abs(v) > 1e-3),
    level=st.floats(-4.0, 4.0),
)
def test_the_area_below_a_line_is_exact(a: float, b: float, level: float) -> None:
    x_edges, y_edges = np.linspace(-1.0, 1.0, 6), np.linspace(-0.5, 1.0, 4)
    below = area_below(a, b, level, x_edges, y_edges)
    above = area_below(-a, -b, -level, x_edges, y_edges)
    # The two sides of the line fill every cell (the line itself has no area).
    np.testing.assert_allclose(below + above, 1.0, rtol=0, atol=1e-12)
    parts = 400
    offsets = (np.arange(parts) + 0.5) / parts
    x = x_edges[:-1, None] + np.diff(x_edges)[:, None] * offsets  # (nx, parts)
    y = y_edges[:-1, None] + np.diff(y_edges)[:, None] * offsets  # (ny, parts)
    inside = a * x[None, :, None, :] + b * y[:, None, :, None] < level
    sampled = inside.mean(axis=(2, 3))
    # Midpoint sampling of a step: off by at most a strip of sub-cells along the line.
    assert np.max(np.abs(below - sampled)) <= 2.5 / parts


@pytest.mark.parametrize("normal", [[1.0, 0.0], [0.0, 1.0]])
def test_a_dam_along_an_axis_has_the_1d_cell_averages_bit_for_bit(normal: list[float]) -> None:
    scene = small(
        "sw2d-dam-break-x",
        **{"initial.normal": normal, "initial.position": 0.33, "n_cells": [40, 40],
           "y_min": -5.0, "y_max": 5.0},
    )  # fmt: skip
    grid = Grid2D.from_bounds(-5.0, 5.0, 40, -5.0, 5.0, 40)
    q = scene.initial.cell_averages(grid, scene.model_instance())
    states = np.array([[3.0, 1.0], [0.0, 0.0]])
    along = piecewise_constant_averages(Grid(-5.0, 5.0, 40).edges, np.array([0.33]), states)
    if normal[0] == 1.0:
        assert np.array_equal(q[:2], np.repeat(along[:, None, :], 40, axis=1))
    else:
        assert np.array_equal(q[[0, 2]], np.repeat(along[:, :, None], 40, axis=2))


def test_a_circle_of_constant_state_averages_between_its_states() -> None:
    scene = small("sw2d-radial-dam-break", **{"n_cells": [40, 40]})
    grid = Grid2D.from_bounds(-1.0, 1.0, 40, -1.0, 1.0, 40)
    q = scene.initial.cell_averages(grid, scene.model_instance())
    assert q[0].min() == 0.1 and q[0].max() == 1.0 and not q[1:].any()
    # The volume: the circle's area times the jump, to the sub-cell sampling's accuracy.
    volume = (q[0] - 0.1).sum() * grid.cell_area
    assert abs(volume - 0.9 * math.pi * 0.25) < 1e-3
    np.testing.assert_array_equal(q[0], q[0].T)  # symmetric about the diagonal


# ------------------------------------------------------------------ scene files
@pytest.mark.parametrize("name", SCENES_2D)
def test_every_builtin_2d_scene_validates_and_round_trips(name: str, tmp_path: Path) -> None:
    scene = load_any_scene(name)
    assert scene.name == name
    written = tmp_path / f"{name}.toml"
    written.write_text(tomli_w.dumps(scene.to_table()))
    again = load_any_scene(written)
    assert dataclasses.replace(again, name=name, source_file=scene.source_file) == scene


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"n_cells": 100}, "scene key 'n_cells': a 2D scene needs [nx, ny]"),
        ({"n_cells": [100, 3]}, "scene key 'n_cells'"),
        ({"y_max": -9.0}, "scene keys 'y_min', 'y_max'"),
        ({"boundary.top": "periodic"}, "boundary.bottom and boundary.top"),
        ({"boundary.left": "inflow"}, "boundary.left"),
        ({"output.formats": ["vtu"]}, "output.formats: a 2D scene writes npz, xdmf"),
        ({"scheme": "nessyahu-tadmor"}, "unknown 2D scheme 'nessyahu-tadmor'"),
        ({"front_tracking": True}, "front_tracking"),
        ({"initial.kind": "sine"}, "initial.kind"),
        ({"initial.states": [[1.0, 0.0, 0.0]]}, "initial.states: expected two states"),
        ({"initial.normal": [0.0, 0.0]}, "initial.normal"),
        ({"scheme_options.threads": 0}, "scheme_options.threads"),
        ({"scheme_options.chunk": 2}, "scheme_options"),
        ({"scheme_options.chunks": 10**6}, "scheme_options.chunks must be in [1, 8]"),
        ({"cfl": 0.5}, "scene key 'cfl'"),
        ({"parameters.g": -1.0}, "parameters.g"),
    ],
)
def test_bad_2d_scenes_name_the_key(overrides: dict[str, object], message: str) -> None:
    with pytest.raises(ConfigError, match=None) as caught:
        scene = load_scene_2d("sw2d-dam-break-x", overrides)
        simulate_2d(scene)
    assert message in str(caught.value), str(caught.value)


def test_a_1d_loader_refuses_a_2d_scene_in_one_line() -> None:
    with pytest.raises(ConfigError, match="two-dimensional"):
        load_scene("sw2d-dam-break-x")
    with pytest.raises(ConfigError, match=r"'dam-break-wet' is one-dimensional.*conslaw\.run"):
        load_scene_2d("dam-break-wet")


@pytest.mark.parametrize(
    ("name", "model", "message"),
    [
        ("sw2d-dam-break-x", "shallow-water", "model 'shallow-water' is one-dimensional but the"),
        ("dam-break-wet", "shallow-water-2d", "model 'shallow-water-2d' is two-dimensional but"),
        ("sw2d-dam-break-x", "shallow-waters", "unknown model 'shallow-waters'"),
    ],
)
def test_a_model_of_the_other_dimension_is_named_as_such(
    name: str, model: str, message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """``--set model=...`` of the other dimension says so, rather than naming a key the model's
    scenes do not have."""
    with pytest.raises(ConfigError, match=message):
        load_any_scene(name, {"model": model})
    assert main(["show", name, "--set", f"model={model}"]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and message in error


def test_a_2d_result_prints_in_one_line() -> None:
    result = run_2d("burgers2d-smooth", n_cells=[16, 16], output_times=[])
    shown = repr(result)
    assert shown.count("\n") == 0 and len(shown) < 200
    assert "16 x 16 cells" in shown and f"L1 error {result.headline_error():.4g}" in shown


# ------------------------------------------------------------------ runs
@pytest.mark.parametrize(("name", "axis"), [("sw2d-dam-break-x", 2), ("sw2d-dam-break-y", 1)])
def test_an_axis_dam_break_equals_the_1d_run(name: str, axis: int) -> None:
    cells = [100, 4] if axis == 2 else [4, 100]
    result = simulate_2d(small(name, n_cells=cells, t_end=0.5))
    one_d = simulate(
        dataclasses.replace(load_scene("dam-break-wet", {"n_cells": 100, "t_end": 0.5}), plot=False)
    )
    q = result.final.q
    momentum = 1 if axis == 2 else 2
    for line in range(4):
        cut = (slice(None), line, slice(None)) if axis == 2 else (slice(None), slice(None), line)
        h_cut, m_cut = q[0][cut[1:]], q[momentum][cut[1:]]
        np.testing.assert_allclose(h_cut, one_d.final.q[0], rtol=0, atol=1e-13)
        np.testing.assert_allclose(m_cut, one_d.final.q[1], rtol=0, atol=1e-13)
    assert not q[3 - momentum].any()
    # The exact solution along the axis is the 1D one.
    assert result.errors[-1] is not None and one_d.errors[-1] is not None
    assert result.errors[-1].l1 == pytest.approx(one_d.errors[-1].l1, rel=1e-9)


def test_the_diagonal_dam_break_is_symmetric_and_converges_at_first_order() -> None:
    errors = []
    for n in (32, 64):
        result = simulate_2d(small("sw2d-dam-break-diagonal", n_cells=[n, n], output_times=[]))
        h = result.final.q[0]
        assert np.max(np.abs(h - h.T)) <= 1e-12
        exact = result.exact[-1]
        assert exact is not None
        error = np.abs(h - exact[0])
        assert np.max(np.abs(error - error.T)) <= 1e-12  # error map symmetric about the diagonal
        errors.append(result.errors[-1].l1)
    order = math.log2(errors[0] / errors[1])
    assert order >= 0.7, errors


def test_the_lake_with_an_island_stays_at_rest() -> None:
    result = simulate_2d(small("sw2d-lake-island", n_cells=[24, 24], t_end=1.5))
    q = result.final.q
    assert result.steps >= 20
    assert np.max(np.abs(q[1:])) <= 1e-12
    assert (q[0] == 0.0).any() and q[0].min() >= 0.0  # the island stays dry


def test_thacker_stays_close_to_the_exact_solution_with_no_negative_depth() -> None:
    result = simulate_2d(small("sw2d-thacker", n_cells=[24, 24], t_end=0.5, output_times=[0.25]))
    assert all(state.q[0].min() >= 0.0 for state in result.states)
    errors = [error.l1 for error in result.errors if error is not None]
    assert len(errors) == 2 and max(errors) < 5e-3, errors


def test_burgers_before_and_after_the_shock() -> None:
    smooth = simulate_2d(small("burgers2d-smooth", n_cells=[40, 40]))
    assert smooth.errors[-1] is not None and smooth.errors[-1].l1 < 5e-3
    shock = simulate_2d(small("burgers2d-shock", n_cells=[40, 40], output_times=[]))
    assert shock.exact_solution is None and "breaks" in str(shock.exact_note)
    u = shock.final.q[0]
    # Periodic: the total is conserved; no new extrema (the scheme is bounded by the data).
    assert abs(shock.mass_drift[0]) <= 1e-13
    assert u.max() <= 1.5 + 1e-12 and u.min() >= -0.5 - 1e-12


def test_conslaw_run_writes_npz_xdmf_and_maps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    code = main([
        "run", "sw2d-dam-break-x", "--out", str(out), "--set", "n_cells=[60, 4]",
        "--set", "t_end=0.5", "--set", "output_times=[0.25]",
        "--set", 'output.formats=["npz", "xdmf"]',
    ])  # fmt: skip
    printed = capsys.readouterr().out
    assert code == 0
    assert "60 x 4 cells" in printed and "L1=" in printed
    states = np.load(out / "states.npz")
    assert states["q"].shape == (2, 3, 4, 60)
    np.testing.assert_array_equal(states["t"], [0.25, 0.5])
    assert not np.isnan(states["q_exact"]).any()
    with meshio.xdmf.TimeSeriesReader(str(out / "solution.xdmf")) as reader:
        points, cells = reader.read_points_cells()
        assert cells[0].type == "quad" and cells[0].data.shape == (240, 4)
        assert points.shape == (61 * 5, 3)
        for k in range(reader.num_steps):
            t, _, cell_data = reader.read_data(k)
            assert t == states["t"][k]
            np.testing.assert_array_equal(cell_data["h"][0], states["q"][k, 0].ravel())
            # Each quadrilateral's centre is its cell's centre.
            centre = points[cells[0].data].mean(axis=1)
            np.testing.assert_allclose(centre[:60, 0], states["x"], rtol=0, atol=1e-12)
    for figure in ("map.png", "cuts.png"):
        assert (out / figure).stat().st_size > 1000


def test_conslaw_run_with_a_bad_2d_key_is_one_line_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "bad"
    code = main(["run", "sw2d-radial-dam-break", "--out", str(out), "--set", "n_cells=[10]"])
    error = capsys.readouterr().err
    assert code == 2 and error.count("\n") == 1 and "n_cells" in error
    assert not out.exists()


def test_the_2d_models_and_scheme_are_registered() -> None:
    assert {"shallow-water-2d", "burgers-2d"} <= set(registry.models.names())
    assert registry.schemes_2d.names() == ["jiang-tadmor", "jiang-tadmor-ft"]


def test_convergence_on_a_2d_scene_measures_orders_and_refuses_without_exact() -> None:
    from conslaw.studies.convergence import convergence_study

    study = convergence_study(
        "burgers2d-smooth", [16, 32], ["mc"], None, repeats=1, measure_import=False
    )
    assert [row.n_cells for row in study.rows] == [16, 32]
    order = study.rows[1].order_l1
    assert order is not None and order > 1.5, study.table()  # smooth: second order
    with pytest.raises(ConfigError, match="no exact solution"):
        convergence_study("sw2d-radial-dam-break", [16, 32], repeats=1, measure_import=False)


# ------------------------------------------------------------------ inflow sides
@pytest.mark.parametrize("reconstructor", ["mc", "weno5"])
def test_inflow_sides_in_the_kernel_are_the_reference_bit_for_bit(reconstructor: str) -> None:
    from conslaw.schemes.jiang_tadmor import JiangTadmor, JiangTadmorReference
    from conslaw_models.shallow_water_2d import ShallowWater2D

    grid = Grid2D.from_bounds(0.0, 1.0, 20, 0.0, 1.0, 16)
    boundaries = {"left": "inflow", "right": "outflow", "bottom": "inflow", "top": "wall"}
    inflow = {"left": [1.5, 0.6, 0.1], "bottom": [1.2, 0.0, 0.3]}
    limiter = registry.reconstructors.get(reconstructor)
    model = ShallowWater2D()
    x, y = grid.centres()
    q = np.zeros((3, 16, 20))
    q[0] = 1.0 + 0.2 * np.sin(6.0 * x)[None, :] * np.cos(5.0 * y)[:, None]
    q[1] = 0.1 * q[0]
    compiled = JiangTadmor(model, limiter, grid, boundaries, inflow=inflow, threads=1)
    reference = JiangTadmorReference(model, limiter, grid, boundaries, inflow=inflow)
    assert compiled.compiled
    q_compiled, t_compiled, steps_compiled = compiled.advance(q, 0.0, 0.3)
    q_reference, t_reference, steps_reference = reference.advance(q, 0.0, 0.3)
    assert (t_compiled, steps_compiled) == (t_reference, steps_reference)
    np.testing.assert_array_equal(q_compiled, q_reference)
    # The inflow reaches the domain: the cells next to the left side have moved towards it.
    assert abs(q_compiled[0, 8, 0] - 1.5) < abs(q[0, 8, 0] - 1.5)


def test_an_inflow_scene_along_x_equals_the_1d_inflow_run(tmp_path: Path) -> None:
    one_d = simulate(
        dataclasses.replace(
            load_scene(
                "dam-break-wet",
                {
                    "n_cells": 80, "t_end": 1.0,
                    "boundary.left": {"kind": "inflow", "state": [3.5, 1.0]},
                },
            ),
            plot=False,
        )
    )  # fmt: skip
    scene = small(
        "sw2d-dam-break-x",
        **{
            "n_cells": [80, 4], "t_end": 1.0, "y_max": 4.0,  # dy > dx: x sets the step
            "boundary.left": {"kind": "inflow", "state": [3.5, 1.0, 0.0]},
        },
    )  # fmt: skip
    result = simulate_2d(scene)
    assert result.steps == one_d.steps
    assert result.exact_solution is None and "outflow" in str(result.exact_note)
    for row in range(4):
        np.testing.assert_allclose(result.final.q[[0, 1], row, :], one_d.final.q, atol=1e-13)
    written = tmp_path / "inflow.toml"
    written.write_text(tomli_w.dumps(scene.to_table()))
    assert load_any_scene(written).inflow == {"left": (3.5, 1.0, 0.0)}


@pytest.mark.parametrize(
    ("side", "message"),
    [
        ({"kind": "inflow"}, "boundary.left"),
        ({"kind": "inflow", "state": [1.0, 0.0]}, "boundary.left: the inflow state must be 3"),
        ({"kind": "inflow", "state": [-1.0, 0.0, 0.0]}, "not admissible"),
        ({"kind": "wall", "state": [1.0, 0.0, 0.0]}, "boundary.left"),
        ("inflow", "boundary.left: an inflow side is written"),
    ],
)
def test_a_bad_inflow_side_names_it(side: object, message: str) -> None:
    with pytest.raises(ConfigError) as caught:
        simulate_2d(small("sw2d-dam-break-x", **{"boundary.left": side}))
    assert message in str(caught.value), str(caught.value)
