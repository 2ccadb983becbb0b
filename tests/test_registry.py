"""The registry: entry points, contract checks, clear errors for unknown names."""

from __future__ import annotations

import subprocess
import sys
from importlib.metadata import entry_points

import pytest
from strategies import MODEL_NAMES

from conslaw import registry
from conslaw.errors import ConfigError
from conslaw.model import Model
from conslaw.registry import ContractError, Registry, check_model
from conslaw_models.burgers import Burgers


def test_burgers_is_registered_through_its_entry_point() -> None:
    names = {point.name for point in entry_points(group="conslaw.models")}
    assert "burgers" in names
    assert registry.models.get("burgers") is Burgers


def test_unknown_name_lists_the_allowed_values_and_a_close_match() -> None:
    with pytest.raises(ConfigError) as error:
        registry.reconstructors.get("wen05")
    message = str(error.value)
    assert "allowed: mc, minmod, none, superbee, vanleer, weno3, weno5" in message
    assert "did you mean 'weno5'" in message


def test_contract_refuses_a_model_without_kernels() -> None:
    class Incomplete(Model):
        name = "incomplete"
        description = "no kernels"
        variables = ("u",)
        reflect_signs = (1.0,)

    with pytest.raises(ContractError, match="flux_point"):
        check_model("incomplete", Incomplete)


def test_contract_refuses_a_closure_kernel() -> None:
    from numba import njit

    @njit
    def local_flux(q, aux, params, out):  # type: ignore[no-untyped-def]
        out[0] = q[0]

    class Closure(Burgers):
        name = "closure"
        flux_point = staticmethod(local_flux)

    with pytest.raises(ContractError, match="module-level"):
        check_model("closure", Closure)


def test_contract_refuses_mismatched_names_and_non_models() -> None:
    with pytest.raises(ContractError, match="calls itself"):
        check_model("burgerz", Burgers)
    with pytest.raises(ContractError, match="subclass"):
        check_model("x", object)


def test_a_broken_plugin_is_skipped_with_a_warning(monkeypatch: pytest.MonkeyPatch) -> None:
    class FakePoint:
        name = "broken"
        value = "nowhere:Nothing"

        def load(self) -> object:
            raise ImportError("no module named nowhere")

    import conslaw.registry as module

    monkeypatch.setattr(module, "entry_points", lambda group: [FakePoint()])
    fresh: Registry[type[Model]] = Registry("model", "conslaw.models", check_model)
    with pytest.warns(UserWarning, match="skipped model plugin 'broken'"):
        assert fresh.names() == []


def test_a_plugin_is_imported_only_when_named(monkeypatch: pytest.MonkeyPatch) -> None:
    """Looking up one plugin imports that plugin only: a broken one that is not asked for
    raises no warning until every name is listed."""
    import warnings

    class Point:
        def __init__(self, name: str, target: object) -> None:
            self.name, self.value, self.target = name, f"somewhere:{name}", target

        def load(self) -> object:
            if isinstance(self.target, Exception):
                raise self.target
            return self.target

    import conslaw.registry as module

    points = [Point("broken", ImportError("no module named nowhere")), Point("burgers", Burgers)]
    monkeypatch.setattr(module, "entry_points", lambda group: points)
    fresh: Registry[type[Model]] = Registry("model", "conslaw.models", check_model)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert fresh.get("burgers") is Burgers
        assert "burgers" in fresh
    with pytest.warns(UserWarning, match="skipped model plugin 'broken'"):
        assert fresh.names() == ["burgers"]


def test_a_broken_plugin_does_not_remove_the_built_in_of_its_name(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A plugin that fails to load under a built-in's name is skipped with a warning that
    names the line asking for it; the built-in stays."""
    import conslaw.registry as module
    from conslaw.reconstruct import builtin_reconstructors
    from conslaw.registry import check_reconstructor

    class Broken:
        name, value = "none", "nowhere:Nothing"

        def load(self) -> object:
            raise ImportError("no module named nowhere")

    monkeypatch.setattr(module, "entry_points", lambda group: [Broken()])
    fresh = Registry(
        "reconstructor", "conslaw.reconstructors", check_reconstructor,
        lambda: [(r.name, r) for r in builtin_reconstructors()],
    )  # fmt: skip
    with pytest.warns(UserWarning, match="skipped reconstructor plugin 'none'") as caught:
        assert fresh.get("none").name == "none"
    assert caught[0].filename == __file__
    assert "none" in fresh and "none" in fresh.names()


def test_a_one_dimensional_run_does_not_import_the_terrain_libraries() -> None:
    """Reading and running a 1D scene in a fresh interpreter imports neither the terrain model
    nor rasterio, shapely or pyogrio (the registry loads the model it is asked for)."""
    script = (
        "import sys, conslaw\n"
        "conslaw.run('burgers-sine', n_cells=16)\n"
        "print(sorted(name for name in ('rasterio', 'shapely', 'pyogrio', "
        "'conslaw_models.savage_hutter_terrain') if name in sys.modules))\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_every_registered_model_runs_with_every_reconstructor() -> None:
    """Smoke test over the registry: a new plugin is exercised automatically."""
    import numpy as np
    from conftest import make_scheme

    from conslaw.state import State

    for model_name in MODEL_NAMES:
        model = registry.models.get(model_name)()
        for reconstructor in registry.reconstructors.names():
            scheme = make_scheme(model_name, reconstructor, n_cells=16, boundary="outflow")
            q = np.ones((model.n_vars, 16))
            result = scheme.advance(State(0.0, scheme.grid.centres(), q), 0.01)
            assert np.all(np.isfinite(result.state.q))


def test_every_registered_scheme_runs_or_refuses_every_model() -> None:
    """Smoke test over schemes x models: a scheme either refuses a model at construction with a
    ConfigError, or advances a body of material inside the domain (a cap, at rest) with finite
    values and its total conserved to round-off."""
    import numpy as np

    from conslaw.errors import ConfigError
    from conslaw.grid import Grid
    from conslaw.schemes.base import BoundarySpec
    from conslaw.state import State

    grid = Grid(0.0, 1.0, 32)
    side = BoundarySpec(registry.boundaries.get("outflow"))
    x = grid.centres()
    cap = np.maximum(0.0, 1.0 - ((x - 0.5) / 0.25) ** 2)
    refused, ran = set(), set()
    for scheme_name in registry.schemes.names():
        for model_name in registry.models.names():
            model = registry.models.get(model_name)()
            try:
                scheme = registry.schemes.get(scheme_name)(
                    model, registry.reconstructors.get("mc"), grid, side, side, 0.45
                )
            except ConfigError:
                refused.add((scheme_name, model_name))
                continue
            row = model.depth_index or 0
            q = np.zeros((model.n_vars, grid.n_cells))
            q[row] = cap
            start = scheme.initial_state(State(0.0, x, q))
            end = scheme.advance(start, 0.05).state
            assert np.all(np.isfinite(end.q)), (scheme_name, model_name)
            total = start.q[row].sum()
            assert abs(end.q[row].sum() - total) <= 1e-13 * total, (scheme_name, model_name)
            ran.add((scheme_name, model_name))
    assert ("lagrangian", "burgers") in refused
    assert {("lagrangian", "savage-hutter"), ("lagrangian", "shallow-water")} <= ran
    assert {s for s, _ in ran} == set(registry.schemes.names())


def test_threads_see_every_entry_in_a_fresh_interpreter() -> None:
    """Four threads asking a fresh registry at once all see every model (the entries are filled
    before any thread reads them)."""
    script = (
        "import threading\n"
        "from conslaw import registry\n"
        "seen = []\n"
        "def ask():\n"
        "    seen.append(tuple(registry.models.names()))\n"
        "threads = [threading.Thread(target=ask) for _ in range(4)]\n"
        "[t.start() for t in threads]\n"
        "[t.join() for t in threads]\n"
        "print(sorted(set(seen)))\n"
    )
    for _ in range(3):
        done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        assert done.stdout.strip() == (
            "[('burgers', 'burgers-2d', 'savage-hutter', 'savage-hutter-2d', "
            "'savage-hutter-terrain', 'shallow-water', 'shallow-water-2d')]"
        )


def test_a_reconstructor_with_another_slope_under_a_built_in_code_is_refused() -> None:
    """The kernels run the built-in slope of a reconstructor's code: a plugin that copies a
    built-in (``dataclasses.replace``) but brings its own slope must say code None."""
    from dataclasses import replace as copy_with

    from conslaw.reconstruct import limiters

    mc = registry.reconstructors.get("mc")
    wrong = copy_with(mc, name="my-limiter", slope_point=limiters.slope_minmod)
    with pytest.raises(registry.ContractError, match="code 4 belongs to another slope"):
        registry.check_reconstructor("my-limiter", wrong)
    assert registry.check_reconstructor("my-limiter", copy_with(wrong, code=None)).code is None
    assert registry.check_reconstructor("mc", mc) is mc
