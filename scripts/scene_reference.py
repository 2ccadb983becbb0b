"""Print the scene-file reference (docs/scenes.md) from the scene schema in conslaw.config.

python scripts/scene_reference.py > docs/scenes.md
"""

from __future__ import annotations

from typing import Any

from conslaw import registry
from conslaw.config import DEFAULTS, KEY_HELP, REQUIRED
from conslaw.initial import INITIAL_KINDS
from conslaw.initial2d import INITIAL_KINDS_2D
from conslaw.scene2d import DEFAULTS_2D, KEY_HELP_2D


def render() -> str:
    """The markdown page."""
    lines = [
        "# Scene files",
        "",
        "A scene is a TOML file. It names only what it needs; the defaults below fill the rest.",
        "Unknown keys are errors (with a *did you mean*). Any key can be overridden on the command",
        "line with `--set key=value` (nested keys with a dot: `--set boundary.left=wall`) or from",
        "Python as `conslaw.run(scene, key=value)` (numpy numbers and arrays are taken as the",
        "Python numbers and lists they hold). `conslaw show SCENE` prints a scene with every",
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
    lines += _kind_rows(INITIAL_KINDS)
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
    return "\n".join(lines + _two_dimensional()) + "\n"


def _kind_rows(kinds: dict[str, Any]) -> list[str]:
    """One table row per initial-condition kind."""
    rows = []
    for kind, (required, optional, description) in kinds.items():
        extra = ", ".join(f"{k} ({v!r})" for k, v in optional.items()) or "-"
        rows.append(f"| `{kind}` | {', '.join(required)} | {extra} | {description} |")
    return rows


def _two_dimensional() -> list[str]:
    """The section on 2D scenes (``conslaw.scene2d``, ``conslaw.initial2d``)."""
    lines = [
        "",
        "## Two-dimensional scenes",
        "",
        "A scene whose model is two-dimensional (`shallow-water-2d`, `burgers-2d`,",
        "`savage-hutter-2d`: models with a y flux) is read by `conslaw.scene2d` and run by",
        '`conslaw run` like any other (progress as in docs/cli.md, "Progress", with the moving',
        'cells; errors against the exact solution; files in one folder, docs/output.md, "2D',
        "runs\"). Its keys are a 1D scene's with the domain and the boundary in both directions;",
        "the keys that differ:",
        "",
        "| key | default | meaning |",
        "|---|---|---|",
    ]
    for key, default in DEFAULTS_2D.items():
        if key in KEY_HELP_2D or key not in DEFAULTS:
            shown = "required" if default is REQUIRED else f"`{default!r}`"
            lines.append(f"| `{key}` | {shown} | {KEY_HELP_2D.get(key, KEY_HELP.get(key))} |")
    lines += [
        "",
        "The other keys (`description`, `model`, `parameters`, `reconstructor`, `t_end`,",
        "`output_times`, `output_interval`, `exact`, `max_steps`) mean what they mean in a 1D",
        "scene; `front_tracking` is not a key of a 2D scene. `--set initial.kind=...` keeps the",
        "other keys of `[initial]`: to switch kinds, set the table whole, e.g. `--set",
        "'initial={kind=\"circle\", centre=[0,0], radius=1, inside=[2,0,0], outside=[1,0,0]}'`.",
        "Initial conditions of 2D scenes (and the 2D models' own, `conslaw list`):",
        "",
        "| kind | required keys | optional keys (default) | meaning |",
        "|---|---|---|---|",
    ]
    kinds = dict(INITIAL_KINDS_2D)
    for name in registry.models.names():
        model = registry.models.get(name)
        if model.flux_y_point is not None:
            kinds.update(
                {k: (r, o, f"{d} ({name})") for k, (r, o, d) in model.initial_kinds.items()}
            )
    lines += _kind_rows(kinds)
    lines += [
        "",
        "Exact solutions of 2D scenes: a `dam-break` along an axis between states at rest",
        "(Stoker or Ritter along the normal; Burgers: the Riemann solution), stripes of dam breaks",
        "along any normal on a periodic domain until the waves of neighbouring dams meet,",
        "`thacker` (Thacker 1981) while the water stays inside the domain, `still-water` between",
        "walls, `product-wave` before it breaks, a Savage–Hutter `cap` on a plane chute without",
        "bed friction (the similarity solution of Savage & Hutter 1991) while it stays inside the",
        "domain. The error printed is",
        "`L1 = mean |h - h_exact|` over the cells of the first variable's exact cell averages",
        "(Gauss points on 8 x 8 sub-cells where the solution is not along an axis).",
    ]
    return lines


if __name__ == "__main__":
    print(render(), end="")
