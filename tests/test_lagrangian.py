"""The Lagrangian moving-grid scheme (Savage & Hutter 1989; docs/design.md, "The Lagrangian moving
grid"): the similarity
solution and its order, the run-out shock with and without artificial viscosity, breakdown
detection, the projection, scheme options, ``conslaw compare`` and clear refusals."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from test_cli import assert_one_line_error, cli

import conslaw
from conslaw import registry
from conslaw.config import load_scene, scheme_variants
from conslaw.errors import ConfigError, SchemeBreakdownError
from conslaw.grid import Grid
from conslaw.schemes.base import BoundarySpec
from conslaw.schemes.lagrangian.scheme import GROWTH_LIMIT, LagrangianScheme
from conslaw.schemes.projection import project_onto_grid
from conslaw.state import LagrangianNodes, State
from conslaw.studies.comparison import compare
from conslaw.studies.convergence import convergence_study


def local_extrema(values: np.ndarray) -> int:
    """Number of strict local extrema of a sequence (sign changes of its differences)."""
    steps = np.diff(values)
    steps = steps[steps != 0.0]
    return int(np.sum(steps[:-1] * steps[1:] < 0.0))


def lagrangian_scheme(model_name: str = "savage-hutter", boundary: str = "outflow", **options):
    model = registry.models.get(model_name)()
    side = BoundarySpec(registry.boundaries.get(boundary))
    return LagrangianScheme(
        model, registry.reconstructors.get("mc"), Grid(0.0, 1.0, 16), side, side, 0.45, **options
    )


# ---------------------------------------------------------------------- similarity solution
@pytest.fixture(scope="module")
def similarity() -> conslaw.RunResult:
    return conslaw.run("sh-similarity-lagrangian")


def test_similarity_90_elements(similarity: conslaw.RunResult) -> None:
    """Paper set-up (zeta = 40, phi = delta = 30, eps = 0.1, t = 6), 90 elements, mu = 0: L1(h)
    against the exact cell averages on the scene's 90-cell grid, and both margins (the end
    nodes) within half an element length of the exact ones (the element length at t = 6,
    0.084, is the stricter of it and the grid's dx = 0.2)."""
    result = similarity
    assert result.final.t == 6.0 and result.final.nodes is not None
    assert result.final.nodes.n_elements == 90
    l1 = result.headline_error()
    rear, front = result.exact_solution.margins(6.0)
    nodes = result.final.nodes.positions
    element = (front - rear) / 90
    print(
        f"L1(h) = {l1:.4e}; margin errors / element length: rear {(nodes[0] - rear) / element:+.4f}"
        f", front {(nodes[-1] - front) / element:+.4f} (element {element:.4f}, dx 0.2)"
    )
    assert l1 < 2.5e-6  # measured 1.907e-6; the NT scheme with front tracking has 4.4e-4
    assert abs(nodes[0] - rear) <= 0.5 * element
    assert abs(nodes[-1] - front) <= 0.5 * element
    assert np.all(np.diff(result.final.nodes.velocities) > 0.0)  # active state throughout
    assert abs(result.mass_drift[0]) <= 1e-12


def test_similarity_second_order_through_the_convergence_tool() -> None:
    """Observed L1 order for 90/180/360 elements from the convergence tool (measured 1.99 and
    1.98), with the margin errors falling."""
    study = convergence_study(
        "sh-similarity-lagrangian", [90, 180, 360], repeats=1, measure_import=False
    )
    print(study.table())
    orders = [row.order_l1 for row in study.rows[1:]]
    assert all(order is not None and order > 1.9 for order in orders)
    margins = [row.margin_error for row in study.rows]
    assert margins[0] > margins[1] > margins[2]
    assert all(row.reconstructor == "-" for row in study.rows)


def test_output_keeps_the_nodes_and_the_readers_keys(
    similarity: conslaw.RunResult, tmp_path: Path
) -> None:
    result = conslaw.run("sh-similarity-lagrangian", out=tmp_path)
    with np.load(tmp_path / "states.npz") as data:
        for key in ("t", "x", "edges", "q", "q_exact", "variables", "margins"):
            assert key in data
        assert data["q"].shape == (1, 2, 90)
        assert data["nodes"].shape == (1, 91) and data["node_velocities"].shape == (1, 91)
        assert data["element_depths"].shape == (1, 90)
        np.testing.assert_array_equal(data["nodes"][-1], result.final.nodes.positions)
        np.testing.assert_array_equal(data["q"][-1], similarity.final.q)


# ---------------------------------------------------------------------- run-out shock
def test_runout_without_viscosity_oscillates_behind_the_shock() -> None:
    """mu = 0, 200 elements: new extrema of the element depths in the deposit behind the
    upward-moving shock (on the flat run-out, x >= 25.5, at t = 20); with mu = 0.02 the deposit
    is monotone, as with the NT scheme on its grid."""
    counts = {}
    for mu in (0.0, 0.02):
        result = conslaw.run(
            "sh-runout-shock", scheme="lagrangian", n_cells=200, output_times=[],
            **{"scheme_options.viscosity": mu},
        )  # fmt: skip
        nodes = result.final.nodes
        centres = 0.5 * (nodes.positions[:-1] + nodes.positions[1:])
        counts[mu] = local_extrema(nodes.depths[centres >= 25.5])
    nt = conslaw.run("sh-runout-shock", output_times=[])
    nt_count = local_extrema(nt.final.q[0][nt.final.x >= 25.5])
    print(f"extrema on the run-out: mu=0 {counts[0.0]}, mu=0.02 {counts[0.02]}, NT {nt_count}")
    assert counts[0.0] >= 20  # measured 49 of 133 elements
    assert counts[0.02] == 0 and nt_count == 0


def test_runout_with_viscosity_reaches_t20_with_mass_to_round_off() -> None:
    """mu = 0.02 with the scene's 500 elements runs to t = 20; mass (the projection on the
    grid, and the element volumes) is conserved to 1e-12; h >= 0; the front is at rest."""
    result = conslaw.run(
        "sh-runout-shock", scheme="lagrangian", **{"scheme_options.viscosity": 0.02}
    )
    assert [s.t for s in result.states] == [0.0, 4.0, 8.0, 12.0, 16.0, 20.0]
    print(f"mass drift {result.mass_drift[0]:.2e} after {result.steps} steps")
    assert abs(result.mass_drift[0]) <= 1e-12
    nodes = result.final.nodes
    total = np.sum(result.initial.nodes.volumes)
    assert abs(np.sum(nodes.volumes) - total) <= 1e-12 * total
    assert np.all(result.final.q[0] >= 0.0) and np.all(np.diff(nodes.positions) > 0.0)
    assert nodes.velocities[-1] == 0.0  # Coulomb friction holds the front in the run-out


# ---------------------------------------------------------------------- breakdown
def test_breakdown_is_one_line_and_earlier_output_stays(tmp_path: Path) -> None:
    """sh-similarity keeps its thin layer, so the Lagrangian body is the whole domain and the
    front runs into the layer without viscosity: the run stops with the time, step and element;
    the files of an earlier run in the same folder are unchanged."""
    out = tmp_path / "run"
    good = cli("run", "sh-similarity-lagrangian", "--no-plot", "--out", str(out))
    assert good.returncode == 0, good.stderr
    before = {path.name: path.read_bytes() for path in out.iterdir()}
    broken = cli("run", "sh-similarity", "--set", "scheme=lagrangian", "--out", str(out))
    assert_one_line_error(broken, "t=", "step", "element", "viscosity")
    assert {path.name: path.read_bytes() for path in out.iterdir()} == before


def test_breakdown_carries_the_last_state_and_the_completed_outputs() -> None:
    with pytest.raises(SchemeBreakdownError) as error:
        conslaw.run("sh-similarity", scheme="lagrangian", output_times=[1.0])
    assert f"over {GROWTH_LIMIT:g} times" in str(error.value)
    assert [s.t for s in error.value.completed_states] == [1.0]
    last = error.value.state
    assert 1.0 < last.t < 6.0 and last.nodes is not None
    assert np.all(np.isfinite(last.q)) and np.all(np.diff(last.nodes.positions) > 0.0)


def test_crossing_nodes_stop_the_step_naming_the_element() -> None:
    scheme = lagrangian_scheme()
    positions = np.linspace(0.3, 0.7, 9)
    velocities = np.zeros(9)
    velocities[4], velocities[5] = 10.0, -10.0  # element 4 closes within dt = 0.01
    nodes = LagrangianNodes(positions, velocities, np.full(8, 0.01))
    state = State(0.0, scheme.grid.centres(), np.zeros((2, 16)), nodes=nodes)
    with pytest.raises(SchemeBreakdownError, match=r"element 4 collapsed .* t=0.01, step 1"):
        scheme.step(state, 0.01)


# ---------------------------------------------------------------------- set-up and options
def test_burgers_is_refused_at_set_up() -> None:
    with pytest.raises(ConfigError, match="depth-averaged model"):
        lagrangian_scheme("burgers")
    process = cli("run", "burgers-riemann", "--set", "scheme=lagrangian")
    assert_one_line_error(process, "'lagrangian'", "'burgers'", "depth-averaged")


def test_refusals_name_the_reason() -> None:
    with pytest.raises(ConfigError, match="periodic"):
        lagrangian_scheme("shallow-water", boundary="periodic")
    with pytest.raises(ConfigError, match="bed source"):
        conslaw.run("lake-at-rest", scheme="lagrangian")
    with pytest.raises(ConfigError, match="touches the left boundary, where 'inflow'"):
        conslaw.run(
            "dam-break-dry", scheme="lagrangian",
            **{"boundary.left": {"kind": "inflow", "state": [1.0, 0.0]}},
        )  # fmt: skip
    with pytest.raises(ConfigError, match="2 separate bodies"):
        conslaw.run(
            "dam-break-dry", scheme="lagrangian",
            **{"initial.breakpoints": [-1.0, 0.0, 1.0],
               "initial.states": [[1, 0], [0, 0], [1, 0], [0, 0]]},
        )  # fmt: skip


def test_scheme_options_are_checked_against_the_scheme() -> None:
    with pytest.raises(ConfigError, match=r"has no option 'viscosty'.*did you mean 'viscosity'"):
        load_scene("sh-similarity-lagrangian", {"scheme_options.viscosty": 0.02})
    with pytest.raises(ConfigError, match="must be >= 0"):
        load_scene("sh-similarity-lagrangian", {"scheme_options.viscosity": -0.1})
    with pytest.raises(ConfigError, match="'nessyahu-tadmor' takes no options"):
        load_scene("sh-similarity", {"scheme_options.viscosity": 0.02})
    with pytest.raises(ConfigError, match="allowed: flux, gradient"):
        load_scene("sh-similarity-lagrangian", {"scheme_options.pressure": "fluxx"})
    scene = load_scene("sh-similarity-lagrangian", {"scheme_options.viscosity": 0.02})
    assert scene.scheme_options == {"viscosity": 0.02, "pressure": "gradient"}
    assert scene.to_table()["scheme_options"] == {"viscosity": 0.02, "pressure": "gradient"}
    assert scene.scheme_label == "lagrangian(viscosity=0.02)"
    nt, mu = scheme_variants("sh-similarity-lagrangian", ["nessyahu-tadmor", "lagrangian"])
    assert nt.scheme_options == {} and mu.scheme_options["viscosity"] == 0.0
    with pytest.raises(ConfigError, match="none of the schemes"):
        scheme_variants("sh-similarity", ["nessyahu-tadmor"], {"scheme_options.viscosity": 1})


def test_material_at_rest_stays_at_rest_bit_for_bit() -> None:
    """sh-at-rest (zeta = 20 < delta = 30): Coulomb friction holds every node exactly."""
    result = conslaw.run("sh-at-rest", scheme="lagrangian", t_end=100.0)
    start, end = result.initial.nodes, result.final.nodes
    assert result.steps > 1000
    assert np.all(end.velocities == 0.0)
    np.testing.assert_array_equal(end.positions, start.positions)
    np.testing.assert_array_equal(result.final.q, result.initial.q)


def test_wall_and_open_ends() -> None:
    """A body against a wall keeps its end node there at rest; at an outflow boundary the end
    node is open (no depth gradient): the dam's still water stays at rest before the
    rarefaction (speed 1) arrives."""
    for boundary in ("wall", "outflow"):
        result = conslaw.run("dam-break-dry", scheme="lagrangian", n_cells=100, t_end=1.0,
                             **{"boundary.left": boundary})  # fmt: skip
        nodes = result.final.nodes
        assert nodes.ends == ("wall" if boundary == "wall" else "open", "free")
        assert nodes.positions[0] == -5.0 and nodes.velocities[0] == 0.0
        still = nodes.positions < -3.0
        assert np.max(np.abs(nodes.velocities[still])) < 1e-12
        assert result.margins is not None and np.isnan(result.margins[-1, 1])


def test_step_on_a_plain_state_uses_the_wet_cells_as_elements() -> None:
    scheme = lagrangian_scheme("shallow-water")
    x = scheme.grid.centres()
    h = np.where(np.abs(x - 0.5) < 0.2, 1.0 - ((x - 0.5) / 0.2) ** 2, 0.0)
    state = State(0.0, x, np.vstack([h, np.zeros_like(h)]))
    dt = scheme.stable_dt(state)
    new = scheme.step(state, dt)
    assert new.nodes is not None and new.nodes.n_elements == int(np.sum(h > 0))
    assert new.t == dt and np.all(new.q[0] >= 0.0)
    assert abs(new.q[0].sum() - h.sum()) <= 1e-14 * h.sum()


def test_projection_is_exact_and_conservative(rng: np.random.Generator) -> None:
    """Random mesh: the projected mass and momentum are the element integrals to round-off, and
    a linear profile between two free margins is reproduced as exact cell averages."""
    positions = np.sort(rng.uniform(0.1, 0.9, 41))
    volumes = rng.uniform(0.0, 1.0, 40) * np.diff(positions)
    velocities = rng.normal(size=41)
    edges = np.linspace(0.0, 1.0, 38)
    q = project_onto_grid(positions, velocities, volumes, edges)
    assert np.all(q[0] >= 0.0)
    assert abs(q[0].sum() * (edges[1] - edges[0]) - volumes.sum()) <= 1e-14 * volumes.sum()
    # h = x - 0.2 on [0.2, 0.6] (one free margin at 0.2, the other a cut) and u = 2:
    nodes = np.linspace(0.2, 0.6, 9)
    mass = 0.5 * (nodes[1:] - 0.2) ** 2 - 0.5 * (nodes[:-1] - 0.2) ** 2
    q = project_onto_grid(nodes, np.full(9, 2.0), mass, edges, True, False)
    clipped = np.clip(edges, 0.2, 0.6)
    exact = np.diff(0.5 * (clipped - 0.2) ** 2) / np.diff(edges)
    # The last element has no free margin: it is constant (a zero-gradient end), not linear.
    inner = edges[1:] <= nodes[-2]
    assert inner.sum() > 10
    np.testing.assert_allclose(q[0, inner], exact[inner], rtol=0, atol=1e-15)
    np.testing.assert_allclose(q[1], 2.0 * q[0], rtol=0, atol=1e-15)


# ---------------------------------------------------------------------- conslaw compare
def test_compare_writes_one_figure_and_a_table(tmp_path: Path) -> None:
    process = cli(
        "compare", "sh-similarity-lagrangian", "--scheme", "nessyahu-tadmor,lagrangian",
        "--out", str(tmp_path),
    )  # fmt: skip
    assert process.returncode == 0, process.stderr
    rows = [line for line in process.stdout.splitlines() if line.startswith("| ")]
    assert rows[0].startswith("| scheme | N | steps | L1(h)")
    assert rows[1].startswith("| nessyahu-tadmor, mc | 90 |")
    assert rows[2].startswith("| lagrangian(viscosity=0.0) | 90 |")
    assert "reached t = 6" in rows[2] and "e-06" in rows[2]
    assert (tmp_path / "compare-sh-similarity-lagrangian.png").read_bytes()[:4] == b"\x89PNG"
    assert "exact cell averages" in (tmp_path / "compare-sh-similarity-lagrangian.md").read_text()


def test_compare_bad_input_is_one_line_and_writes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "compare"
    process = cli("compare", "sh-similarity-lagrangian", "--scheme", "lagrangen", "--out", str(out))
    assert_one_line_error(process, "unknown scheme 'lagrangen'", "did you mean 'lagrangian'")
    assert not out.exists()


def test_compare_reports_a_breakdown_and_keeps_the_states() -> None:
    """The Lagrangian scheme breaks down on sh-similarity's thin layer after t = 2; the comparison
    goes on, its row says where, and it keeps the output at t = 1 and the last good state."""
    comparison = compare(
        "sh-similarity", ["nessyahu-tadmor", "lagrangian"], {"output_times": [1.0]}
    )
    finished, broken = comparison.runs
    assert finished.result is not None and finished.result.final.t == 6.0
    assert broken.result is None and "element" in broken.breakdown
    assert broken.states[0].t == 1.0 and 1.0 < broken.states[1].t < 6.0
    rows = comparison.table().splitlines()
    assert "reached t = 6" in rows[2] and "| breakdown: element" in rows[3]
