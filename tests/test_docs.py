"""Generated documentation stays in step with the code."""

from __future__ import annotations

import dataclasses
import importlib.util
from pathlib import Path
from types import ModuleType

from conslaw import registry

ROOT = Path(__file__).resolve().parents[1]


def script(name: str) -> ModuleType:
    """The module of ``scripts/NAME.py``."""
    spec = importlib.util.spec_from_file_location(name, ROOT / "scripts" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_scene_reference_is_generated_from_the_schema() -> None:
    assert (ROOT / "docs" / "scenes.md").read_text() == script("scene_reference").render(), (
        "docs/scenes.md is stale: python scripts/scene_reference.py > docs/scenes.md"
    )


def test_parameter_reference_is_generated_from_the_models() -> None:
    module = script("parameter_reference")
    text = module.render()
    assert (ROOT / "docs" / "parameters.md").read_text() == text, (
        "docs/parameters.md is stale: python scripts/parameter_reference.py > docs/parameters.md"
    )
    assert module.NO_MEANING not in text, "a built-in model parameter has no meaning"
    for name in registry.models.names():
        model = registry.models.get(name)
        assert f"## `{name}`" in text
        for field in dataclasses.fields(model.Parameters):
            assert f"| `{field.name}` |" in text
        for kind in model.initial_kinds:
            assert f"| `{kind}` |" in text


def test_cli_reference_is_generated_from_the_parser() -> None:
    text = script("cli_reference").render()
    assert (ROOT / "docs" / "cli.md").read_text() == text, (
        "docs/cli.md is stale: python scripts/cli_reference.py > docs/cli.md"
    )
    for command in ("list", "show", "run", "convergence", "reproduce"):
        assert f"## `conslaw {command}`" in text
