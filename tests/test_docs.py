"""Generated documentation stays in step with the code."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_scene_reference_is_generated_from_the_schema() -> None:
    spec = importlib.util.spec_from_file_location(
        "scene_reference", ROOT / "scripts" / "scene_reference.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert (ROOT / "docs" / "scenes.md").read_text() == module.render(), (
        "docs/scenes.md is stale: python scripts/scene_reference.py > docs/scenes.md"
    )


def test_cli_reference_is_generated_from_the_parser() -> None:
    spec = importlib.util.spec_from_file_location(
        "cli_reference", ROOT / "scripts" / "cli_reference.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    text = module.render()
    assert (ROOT / "docs" / "cli.md").read_text() == text, (
        "docs/cli.md is stale: python scripts/cli_reference.py > docs/cli.md"
    )
    for command in ("list", "show", "run", "convergence", "reproduce"):
        assert f"## `conslaw {command}`" in text
