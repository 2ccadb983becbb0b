"""Sphinx configuration: the markdown pages of docs/ (MyST), the API from the docstrings.

Build: ``sphinx-build -W -b html docs docs/_build/html`` (warnings are errors, as in CI).
The scene-file reference and the CLI reference are generated from the code at every build
(``scripts/scene_reference.py``, ``scripts/cli_reference.py``); the committed ``scenes.md`` and
``cli.md`` are the same text for readers on the web, and a test keeps them current.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

project = "conslaw"
author = "the conslaw developers"
copyright = "2026, the conslaw developers"
extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    # A copy of MathJax in _static: the equations render without a network connection.
    "sphinx-mathjax-offline",
    "numpydoc",
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "validation_intro.md",  # the opening of validation.md (scripts/validation.py)
    "figures/**.md",  # tables written next to the figures
    "examples",
]
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
autodoc_member_order = "bysource"
autodoc_typehints = "none"
html_theme = "alabaster"
html_static_path: list[str] = []

#: Pages whose text is generated from the code at build time: docname -> renderer module.
GENERATED_PAGES = {"scenes": "scene_reference", "cli": "cli_reference"}


def _generated_page(app: Any, docname: str, source: list[str]) -> None:
    """Replace the source of a generated page by what its script renders now."""
    module = GENERATED_PAGES.get(docname)
    if module is not None:
        source[0] = __import__(module).render()


def setup(app: Any) -> None:
    app.connect("source-read", _generated_page)
