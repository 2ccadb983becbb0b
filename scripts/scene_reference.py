"""Print the scene-file reference (docs/scenes.md) from the scene schema in conslaw.config.

python scripts/scene_reference.py > docs/scenes.md
"""

from __future__ import annotations

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
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(render(), end="")
