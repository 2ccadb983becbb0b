"""Print the scene-file reference (docs/scenes.md) from the scene schema in conslaw.config.

python scripts/scene_reference.py > docs/scenes.md
"""

from __future__ import annotations

from conslaw import registry
from conslaw.config import DEFAULTS, KEY_HELP, REQUIRED
from conslaw.initial import INITIAL_KINDS


def render() -> str:
    """The markdown page."""
    lines = [
        "# Scene files",
        "",
        "A scene is a TOML file. It names only what it needs; the defaults below fill the rest.",
        "Unknown keys are errors (with a *did you mean*). Any key can be overridden on the command",
        "line with `--set key=value` (nested keys with a dot: `--set boundary.left=wall`) or from",
        "Python as `conslaw.run(scene, key=value)`. `conslaw show SCENE` prints a scene with every",
        "default filled in.",
        "",
        "This page is generated from `conslaw.config` by "
        "`python scripts/scene_reference.py > docs/scenes.md`.",
        "",
        "| key | default | meaning |",
        "|---|---|---|",
    ]
    for key, default in DEFAULTS.items():
        shown = "required" if default is REQUIRED else f"`{default!r}`"
        lines.append(f"| `{key}` | {shown} | {KEY_HELP[key]} |")
    lines += [
        "",
        "## Initial conditions (`[initial]`)",
        "",
        "| kind | required keys | optional keys (default) | meaning |",
        "|---|---|---|---|",
    ]
    for kind, (required, optional, description) in INITIAL_KINDS.items():
        extra = ", ".join(f"{k} ({v!r})" for k, v in optional.items()) or "-"
        lines.append(f"| `{kind}` | {', '.join(required)} | {extra} | {description} |")
    lines += [
        "",
        "## Scheme options (`[scheme_options]`)",
        "",
        "Checked against the options the scene's scheme declares (unknown keys are errors);",
        "override with `--set scheme_options.KEY=VALUE`. In `conslaw compare` and",
        "`conslaw convergence`, options can follow a scheme name: `lagrangian:viscosity=0.02`.",
        "",
        "| scheme | option | default | meaning |",
        "|---|---|---|---|",
    ]
    for name in registry.schemes.names():
        options = registry.schemes.get(name).options
        if not options:
            lines.append(f"| `{name}` | - | - | no options |")
        for key, option in options.items():
            lines.append(f"| `{name}` | `{key}` | `{option.default!r}` | {option.description} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(render(), end="")
