"""The shape rules of docs/design.md ("Style") that no linter checks: no function of the package,
its plugins, scripts or benchmarks is longer than 80 lines (decorators not counted, docstring
counted). At most 12 parameters per function is ruff's PLR0913 (pyproject.toml)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("conslaw", "models", "scripts", "benchmarks")
MAX_LINES = 80


def long_functions(source: str, limit: int) -> list[tuple[str, int, int]]:
    """``(name, first line, length)`` of every function in ``source`` longer than ``limit``."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            length = (node.end_lineno or node.lineno) - node.lineno + 1
            if length > limit:
                found.append((node.name, node.lineno, length))
    return found


def test_the_rule_finds_a_long_function() -> None:
    """The check itself: an 81-line function is found, an 80-line one is not."""
    body = "".join(f"    x{i} = {i}\n" for i in range(78))
    assert long_functions(f"def f():\n{body}    return 0\n", MAX_LINES) == []
    assert long_functions(f"def f():\n{body}    y = 1\n    return 0\n", MAX_LINES) == [("f", 1, 81)]


@pytest.mark.parametrize("folder", FOLDERS)
def test_no_function_is_longer_than_80_lines(folder: str) -> None:
    offenders = [
        f"{path.relative_to(ROOT)}:{line} {name} ({length} lines)"
        for path in sorted((ROOT / folder).rglob("*.py"))
        for name, line, length in long_functions(path.read_text(), MAX_LINES)
    ]
    assert offenders == []
