"""Print the model reference (docs/parameters.md) from the registered models' own classes.

python scripts/parameter_reference.py > docs/parameters.md

Each model's ``Parameters`` dataclass gives the keys of ``[parameters]`` with their defaults and
meanings (declared with :func:`conslaw.model.parameter`), and ``initial_kinds`` the model's own
initial conditions.
"""

from __future__ import annotations

import dataclasses
import inspect

from conslaw import registry
from conslaw.model import Model

NO_MEANING = "(not documented by the model)"


def first_paragraph(cls: type) -> str:
    """The first paragraph of a class docstring, on one line."""
    text = inspect.getdoc(cls) or ""
    return " ".join(text.split("\n\n")[0].split())


def model_section(model: type[Model]) -> list[str]:
    """The reference of one model: variables, parameters, initial conditions."""
    lines = [
        f"## `{model.name}`",
        "",
        first_paragraph(model),
        "",
        f"Conserved variables: {', '.join(f'`{v}`' for v in model.variables)}.",
    ]
    if model.dimensionless:
        lines.append("The equations are scaled (dimensionless):")
        lines.append("")
        for name, meaning in model.long_names.items():
            lines.append(f"- `{name}`: {meaning}")
    lines.append("")
    fields = dataclasses.fields(model.Parameters)
    if fields:
        lines += [
            "| key in `[parameters]` | default | meaning |",
            "|---|---|---|",
        ]
        for field in fields:
            meaning = model.parameter_meanings.get(
                field.name, field.metadata.get("meaning", NO_MEANING)
            )
            lines.append(f"| `{field.name}` | `{field.default!r}` | {meaning} |")
    else:
        lines.append("No parameters.")
    if model.initial_kinds:
        lines += [
            "",
            "| initial `kind` | required keys | optional keys (default) | meaning |",
            "|---|---|---|---|",
        ]
        for kind, (required, optional, description) in model.initial_kinds.items():
            extra = ", ".join(f"{k} ({v!r})" for k, v in optional.items()) or "-"
            lines.append(f"| `{kind}` | {', '.join(required)} | {extra} | {description} |")
    return [*lines, ""]


def render() -> str:
    """The markdown page."""
    lines = [
        "# Models and their parameters",
        "",
        "What each model solves and the keys of a scene's `[parameters]` table, with defaults,",
        "units and admissible ranges; a value outside its range is refused with a one-line error",
        "naming the key. Set them in the scene file or with `--set parameters.KEY=VALUE`",
        "(`conslaw.run(scene, parameters__KEY=VALUE)` from Python). The initial conditions",
        "every model accepts are in [scene files](scenes.md); a model's own ones are listed with",
        "it. The equations are in [equations](equations.md).",
        "",
        "This page is generated from the models' classes by "
        "`python scripts/parameter_reference.py > docs/parameters.md`.",
        "",
    ]
    for name in registry.models.names():
        lines += model_section(registry.models.get(name))
    return "\n".join(lines)


if __name__ == "__main__":
    print(render(), end="")
