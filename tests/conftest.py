"""Shared fixtures: scheme construction for tests; the hypothesis profiles."""

from __future__ import annotations

import os
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

from conslaw import registry
from conslaw.grid import Grid
from conslaw.schemes.base import BoundarySpec
from conslaw.schemes.nessyahu_tadmor.scheme import NessyahuTadmor

# CI draws the same examples on every run (.ci/run sets HYPOTHESIS_PROFILE=ci), so that a red CI
# means the change broke something, not that a new random draw found an old edge case; local
# runs keep drawing new examples, which is how those edge cases are found (and then fixed, with
# the example kept as a test).
#
# No example fails for the wall time it took: no deadline per example (hypothesis's default is
# 200 ms, which a loaded machine misses), and slow data generation is no failure (the
# ``too_slow`` health check times the first examples' generation). Set for every test here,
# whatever its own settings leave out.
WALL_CLOCK_FREE = {"deadline": None, "suppress_health_check": [HealthCheck.too_slow]}
settings.register_profile("default", **WALL_CLOCK_FREE)
settings.register_profile("ci", derandomize=True, **WALL_CLOCK_FREE)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))

# The interval of the progress lines (docs/cli.md, "Progress") is the tests' to set: one set in
# the developer's shell would add lines to what the tests read (or, not a number, fail them).
os.environ.pop("CONSLAW_PROGRESS_SECONDS", None)


def make_scheme(
    model_name: str = "burgers",
    reconstructor: str = "mc",
    n_cells: int = 32,
    boundary: str = "periodic",
    cfl: float = 0.45,
    x_min: float = 0.0,
    x_max: float = 1.0,
    **boundary_options: object,
) -> NessyahuTadmor:
    """An NT scheme on [x_min, x_max] with the same boundary condition on both sides."""
    model = registry.models.get(model_name)()
    side = BoundarySpec(registry.boundaries.get(boundary), dict(boundary_options))
    return NessyahuTadmor(
        model,
        registry.reconstructors.get(reconstructor),
        Grid(x_min, x_max, n_cells),
        side,
        side,
        cfl,
    )


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20011)


# ----------------------------------------------------------- hypothesis examples per model
#: Examples run per model in this session (in a worker under pytest-xdist; merged on the
#: controller from each worker's ``workeroutput``).
EXAMPLES_PER_MODEL: dict[str, int] = {}
#: The key for property tests that are not about one model (chutes, scenes, reconstructors).
NOT_MODEL_SPECIFIC = "(not model-specific)"
#: What every CI run asks for.
EXAMPLES_TARGET = 1000


def _models_of(test_name: str, arguments: dict[str, object]) -> list[str]:
    """The models one example exercises: model names among the test's arguments (or the
    ``model`` attribute of an argument), else model names in the test's name."""
    names = registry.models.names()
    found: list[str] = []
    for value in arguments.values():
        for candidate in (value, getattr(value, "model", None)):
            if isinstance(candidate, str) and candidate in names and candidate not in found:
                found.append(candidate)
    if not found:
        found = [name for name in names if name.replace("-", "_") in test_name]
    return found or [NOT_MODEL_SPECIFIC]


def _counting(inner: Any, test_name: str) -> Any:
    """``inner`` (one example of a hypothesis test), counting each call per model."""

    def run_example(*args: object, **kwargs: object) -> object:
        result = inner(*args, **kwargs)
        # Counted once the example has run through: examples rejected by assume() or a filter
        # raise inside and are not counted.
        for model in _models_of(test_name, kwargs):
            EXAMPLES_PER_MODEL[model] = EXAMPLES_PER_MODEL.get(model, 0) + 1
        return result

    run_example.counted = True  # type: ignore[attr-defined]
    return run_example


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Count every example of every hypothesis test, per model (reported at the end). The
    parametrized items of one test share its function: it is wrapped once."""
    for item in items:
        function = getattr(item, "obj", None)
        if getattr(function, "is_hypothesis_test", False):
            handle = function.hypothesis  # type: ignore[union-attr]
            if not getattr(handle.inner_test, "counted", False):
                handle.inner_test = _counting(handle.inner_test, function.__name__)  # type: ignore[union-attr]


def pytest_sessionfinish(session: pytest.Session) -> None:
    workeroutput = getattr(session.config, "workeroutput", None)
    if workeroutput is not None:  # an xdist worker: hand the counts to the controller
        workeroutput["examples_per_model"] = dict(EXAMPLES_PER_MODEL)


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node: object, error: object) -> None:
    """(xdist controller) add a finished worker's counts."""
    counts = getattr(node, "workeroutput", {}).get("examples_per_model", {})
    for model, count in counts.items():
        EXAMPLES_PER_MODEL[model] = EXAMPLES_PER_MODEL.get(model, 0) + count


def pytest_terminal_summary(terminalreporter: object) -> None:
    if not EXAMPLES_PER_MODEL:
        return
    write = terminalreporter.write_line  # type: ignore[attr-defined]
    write(f"hypothesis examples per model (target >= {EXAMPLES_TARGET} per model in a full run):")
    for model in sorted(EXAMPLES_PER_MODEL):
        write(f"  {model}: {EXAMPLES_PER_MODEL[model]}")
