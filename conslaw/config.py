"""Scene files: TOML, validated into a frozen :class:`Scene`.

A scene names only what it needs; :data:`DEFAULTS` fills the rest. Unknown keys are errors with a
"did you mean". Every top-level key can be overridden (``conslaw run SCENE --set n_cells=800``,
``conslaw.run("burgers-sine", n_cells=800)``); nested keys with a dot (``boundary.left=wall``).
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import math
import os
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from conslaw import registry
from conslaw.errors import ConfigError, finite_number, shown, unknown_name_message
from conslaw.grid import MAX_CELLS
from conslaw.initial import InitialCondition

if TYPE_CHECKING:
    from conslaw.model import Model

REQUIRED = object()

#: Largest ``max_steps`` (a TOML integer is 64-bit; no run gets anywhere near it).
MAX_STEPS = 10**15

#: Every top-level scene key with its default (REQUIRED: the scene must give it).
DEFAULTS: dict[str, Any] = {
    "description": "",
    "model": REQUIRED,
    "parameters": {},
    "scheme": "nessyahu-tadmor",
    "scheme_options": {},
    "reconstructor": "mc",
    "cfl": 0.45,
    "front_tracking": False,
    "n_cells": REQUIRED,
    "x_min": REQUIRED,
    "x_max": REQUIRED,
    "t_end": REQUIRED,
    "output_times": [],
    "output_interval": 0.0,
    "exact": True,
    "max_steps": 100_000_000,
    "boundary": {"left": "outflow", "right": "outflow"},
    "initial": REQUIRED,
    "output": {"formats": ["npz"], "plot": True},
}

#: One-line meaning of every top-level key (used by ``conslaw show --keys`` and the docs).
KEY_HELP: dict[str, str] = {
    "description": "one line shown by `conslaw list`",
    "model": "registered model name (`conslaw list`)",
    "parameters": "model parameters; a relative *_file path is looked up next to the scene first",
    "scheme": "registered scheme name (`conslaw list`; built in: nessyahu-tadmor, "
    "front-tracking, lagrangian)",
    "scheme_options": "table of the options the scheme declares (lagrangian: viscosity, "
    "pressure; see Scheme options below)",
    "reconstructor": "registered slope reconstruction of the central schemes (`conslaw list`; "
    "built in: none, minmod, superbee, vanleer, mc, weno3, weno5)",
    "cfl": "target Courant number, 0 < cfl < 0.5 (paper eq. 17; lagrangian: its time-step factor)",
    "front_tracking": 'true: the front-tracking scheme (the same as scheme = "front-tracking"; '
    "NOC-FT, models with depth)",
    "n_cells": "number of cells, integer >= 4",
    "x_min": "left end of the domain",
    "x_max": "right end of the domain",
    "t_end": "final time",
    "output_times": "times (<= t_end) at which states are saved; t_end is always saved",
    "output_interval": "> 0: also save every output_interval from t = 0 (0, dt, 2 dt, ... <= "
    "t_end; at most 10000 times); 0: only output_times",
    "exact": "compare with the model's exact solution when it has one",
    "max_steps": "stop the run with an error once it has taken more time steps than this "
    "before t_end (integer >= 1; checked at every progress report: nessyahu-tadmor every "
    "4e6/n_cells steps, front tracking every 1e6/n_cells, lagrangian every 200, and at every "
    "output time), or earlier, once 1e4 steps show that the run would need more than ten "
    "times this many (once 1e6 steps show it would need more than twice this many)",
    "boundary": "table: left, right = a boundary name or { kind = ..., options }",
    "initial": "table: kind (piecewise-constant, sine) and its options",
    "output": (
        "table: formats = files written at each output time, a list (at least one) of npz "
        "(states.npz), "
        "xdmf (solution.xdmf + HDF5), vtu (solution-NNNNN.vtu + solution.pvd), csv "
        "(solution-NNNNN.csv, margins.csv); plot = PNG figures at the end (bool)"
    ),
}

#: File formats a scene may ask for (``output.formats``); see :mod:`conslaw.io`.
OUTPUT_FORMATS = ("npz", "xdmf", "vtu", "csv")
OUTPUT_KEYS = ("formats", "plot")


@dataclass(frozen=True)
class BoundarySide:
    """A boundary condition name and its options, as written in the scene."""

    kind: str
    options: Mapping[str, Any] = field(default_factory=dict)

    def to_toml(self) -> Any:
        """``"name"`` or an inline table ``{ kind = "name", ... }``."""
        return {"kind": self.kind, **self.options} if self.options else self.kind


def scene_model(
    name: str,
    parameters: Mapping[str, Any],
    validated: tuple[Mapping[str, Any], Model] | None,
) -> Model:
    """The model ``name`` with ``parameters``: ``validated``'s, if it was built from exactly
    this ``parameters`` object, else a new one (which validates its parameters)."""
    if validated is not None:
        built_from, model = validated
        if built_from is parameters and model.name == name:
            return model
    return registry.models.get(name)(**parameters)


@dataclass(frozen=True)
class Scene:
    """A validated scene: everything a run needs, with defaults filled in."""

    name: str
    description: str
    model: str
    parameters: Mapping[str, Any]
    scheme: str
    reconstructor: str
    cfl: float
    n_cells: int
    x_min: float
    x_max: float
    t_end: float
    output_times: tuple[float, ...]
    exact: bool
    left: BoundarySide
    right: BoundarySide
    initial: InitialCondition
    output_formats: tuple[str, ...]
    plot: bool
    front_tracking: bool = False
    scheme_options: Mapping[str, Any] = field(default_factory=dict)
    max_steps: int = DEFAULTS["max_steps"]
    #: The scene file it was read from ("" for a scene built in Python).
    source_file: str = ""
    #: ``(parameters, model)``: the model that validation built from exactly this
    #: ``parameters`` object, which the run then uses (:meth:`model_instance`).
    validated_model: tuple[Mapping[str, Any], Model] | None = field(
        default=None, compare=False, repr=False
    )

    def model_instance(self) -> Model:
        """The scene's model: the one validation built, if the scene still has the parameters
        it was built from (a scene made with ``dataclasses.replace(scene, parameters=...)`` has
        others and gets a new one), else a new one (which validates its parameters)."""
        return scene_model(self.model, self.parameters, self.validated_model)

    @property
    def scheme_label(self) -> str:
        """The scheme with its options that differ from their defaults (and those it always
        names), e.g. ``lagrangian(viscosity=0.02)``."""
        declared = registry.schemes.get(self.scheme).options
        shown = [
            f"{key}={value!r}"
            for key, value in self.scheme_options.items()
            if key not in declared or declared[key].always_shown or value != declared[key].default
        ]
        return f"{self.scheme}({', '.join(shown)})" if shown else self.scheme

    @property
    def reconstructor_label(self) -> str:
        """The reconstructor for reports, or "-" for a scheme that uses none."""
        uses = getattr(registry.schemes.get(self.scheme), "uses_reconstructor", True)
        return self.reconstructor if uses else "-"

    def to_table(self) -> dict[str, Any]:
        """The resolved scene as a TOML-ready mapping (written next to every output)."""
        return {
            "description": self.description,
            "model": self.model,
            "scheme": self.scheme,
            **({"scheme_options": dict(self.scheme_options)} if self.scheme_options else {}),
            "reconstructor": self.reconstructor,
            "cfl": self.cfl,
            "n_cells": self.n_cells,
            "x_min": self.x_min,
            "x_max": self.x_max,
            "t_end": self.t_end,
            "output_times": list(self.output_times),
            "exact": self.exact,
            "max_steps": self.max_steps,
            "parameters": dict(self.parameters),
            "boundary": {"left": self.left.to_toml(), "right": self.right.to_toml()},
            "initial": {"kind": self.initial.kind, **self.initial.options},
            "output": {"formats": list(self.output_formats), "plot": self.plot},
        }


#: Deepest nesting of arrays and tables a scene (or a ``--set`` value) may have.
MAX_NESTING = 50


def parse_value(text: str) -> Any:
    """A ``--set`` value: a TOML value (number, bool, list, string in quotes) or a bare string."""
    if "\n" in text or "\r" in text:
        raise ConfigError(f"--set value {text[:40]!r}...: a value is one line")
    _check_nesting(text, "a --set value")
    try:
        return tomllib.loads(f"value = {text}")["value"]
    except tomllib.TOMLDecodeError:
        return text


def _check_nesting(text: str, what: str) -> None:
    """A ConfigError if the brackets of ``text`` nest deeper than ``MAX_NESTING`` (the TOML
    parser would recurse until Python's limit). Brackets inside strings count too: a bound, not
    a parse."""
    depth = deepest = 0
    for character in text:
        if character in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif character in "]}":
            depth = max(depth - 1, 0)
    if deepest > MAX_NESTING:
        raise ConfigError(f"{what} nests arrays or tables {deepest} deep; at most {MAX_NESTING}")


def nesting_depth(value: Any) -> int:
    """How deep lists, tuples and mappings nest in ``value`` (0 for a number or string),
    counted without recursion (a dotted key 5000 parts long makes tables 5000 deep, beyond what
    ``copy.deepcopy`` and the validation can recurse through) and only to just past
    ``MAX_NESTING`` (a list that holds itself is not followed forever)."""
    deepest = 0
    pending: list[tuple[Any, int]] = [(value, 0)]
    while pending:
        item, depth = pending.pop()
        if isinstance(item, Mapping):
            children: Any = item.values()
        elif isinstance(item, list | tuple):
            children = item
        else:
            continue
        deepest = max(deepest, depth + 1)
        if deepest > MAX_NESTING:
            return deepest
        pending.extend((child, depth + 1) for child in children)
    return deepest


def scene_path(name_or_path: str | Path) -> tuple[str, Path]:
    """Resolve a built-in scene name or a path to a ``.toml`` file."""
    text = str(name_or_path)
    if text in registry.scenes:
        return text, registry.scenes.get(text)
    if "\0" in text:
        raise ConfigError(f"scene {text!r}: a file name cannot hold a NUL byte")
    path = Path(text)
    if path.suffix == ".toml":
        if not path.is_file():
            raise ConfigError(f"scene file '{path}' {_why_not_a_file(path)}")
        return path.stem, path
    raise ConfigError(unknown_name_message("scene", text, registry.scenes.names()))


def _why_not_a_file(path: Path) -> str:
    """Why ``path`` cannot be read as a file, for a one-line message."""
    try:
        os.stat(path)
    except OSError as error:
        if path.is_symlink():
            return f"is a symbolic link that leads nowhere ({error.strerror})"
        return "does not exist"
    return "is not a regular file (a folder or a device)"


def read_scene_file(path: Path) -> dict[str, Any]:
    """Parse a scene file; malformed TOML is a ConfigError naming the file.

    TOML is UTF-8 (https://toml.io/en/v1.0.0, "Spec"); a leading UTF-8 byte-order mark, as some
    Windows editors write, is skipped. A file in another encoding (UTF-16, Latin-1) or a binary
    file is a ConfigError saying so.
    """
    try:
        data = path.read_bytes()
    except OSError as error:
        raise ConfigError(f"cannot read scene file '{path}': {error.strerror}") from None
    text = scene_text(data, f"scene file '{path}'")
    _check_nesting(text, f"scene file '{path}'")
    try:
        parsed = _parsed_toml(text)
    except tomllib.TOMLDecodeError as error:
        raise ConfigError(f"scene file '{path}' is not valid TOML: {error}") from None
    if nesting_depth(parsed) > MAX_NESTING:
        raise ConfigError(
            f"scene file '{path}' nests tables or arrays more than {MAX_NESTING} deep (a dotted "
            "key of that many parts?)"
        )
    return copy.deepcopy(parsed)


@functools.lru_cache(maxsize=64)
def _parsed_toml(text: str) -> dict[str, Any]:
    """The TOML document ``text``, parsed once per text (an ensemble reads its scene file once
    per member); callers get a deep copy."""
    return tomllib.loads(text)


def scene_text(data: bytes, what: str) -> str:
    """The text of a scene file's bytes (UTF-8, a byte-order mark skipped); ``what`` names the
    file in the ConfigError raised for any other encoding."""
    utf8 = "TOML files are UTF-8: save it as UTF-8"
    if data.startswith((b"\xff\xfe\0\0", b"\0\0\xfe\xff")):
        raise ConfigError(f"{what} is UTF-32 text; {utf8}")
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise ConfigError(f"{what} is UTF-16 text; {utf8}")
    if b"\0" in data:
        raise ConfigError(
            f"{what} is not UTF-8 text (it holds NUL bytes: UTF-16 or UTF-32, or not text); {utf8}"
        )
    try:
        return data.decode("utf-8").removeprefix("\ufeff")
    except UnicodeDecodeError as error:
        line = data[: error.start].count(b"\n") + 1
        byte = data[error.start]
        raise ConfigError(
            f"{what} is not UTF-8 text (byte 0x{byte:02x} on line {line}, e.g. Latin-1); {utf8}"
        ) from None


def plain_values(value: Any) -> Any:
    """``value`` with every numpy scalar (``numpy.float64(25.0)``, ``numpy.int64(800)``,
    ``numpy.True_``) replaced by the Python number or bool it holds and every numpy array by
    lists (``output_times=numpy.linspace(0, 20, 5)``), inside lists, tuples and mappings too:
    a scene given from Python with numbers from numpy holds what a TOML file would (the
    model's flags stay Python bools, the kernels' constants Python literals)."""
    numeric = (np.number, np.bool_, np.str_)
    if isinstance(value, numeric) or (
        isinstance(value, np.ndarray) and value.dtype.kind in "biufU"
    ):
        return value.tolist()  # a scalar's Python value; an array as (nested) lists
    if isinstance(value, Mapping):
        return {key: plain_values(item) for key, item in value.items()}
    if isinstance(value, list | tuple):  # a namedtuple too: its values, as a tuple
        return (list if isinstance(value, list) else tuple)(plain_values(v) for v in value)
    return value  # datetime64, timedelta64 and the rest: refused by the validation


def apply_overrides(
    table: dict[str, Any],
    overrides: Mapping[str, Any],
    defaults: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """Copy of ``table`` with ``overrides`` (keys may be dotted: ``boundary.left``); the top
    keys must be keys of ``defaults`` (default :data:`DEFAULTS`, a 1D scene's; a 2D scene's
    table is :data:`conslaw.scene2d.DEFAULTS_2D`)."""
    known = DEFAULTS if defaults is None else defaults
    result = {k: (dict(v) if isinstance(v, Mapping) else v) for k, v in table.items()}
    for dotted, value in dict(overrides).items():
        parts = str(dotted).split(".")
        if len(parts) > MAX_NESTING:
            raise ConfigError(
                f"scene key {shown(str(dotted), 40)}: {len(parts)} parts; at most {MAX_NESTING}"
            )
        if nesting_depth(value) > MAX_NESTING:
            raise ConfigError(
                f"scene key {shown(str(dotted), 40)}: its value nests lists or tables more than "
                f"{MAX_NESTING} deep"
            )
        value = plain_values(value)
        if parts[0] not in known:
            raise ConfigError(unknown_name_message("scene key", parts[0], known))
        target = result
        for part in parts[:-1]:
            existing = target.get(part)
            if existing is None:
                existing = dict(known.get(part, {})) if target is result else {}
            if not isinstance(existing, Mapping):
                raise ConfigError(f"scene key '{dotted}': '{part}' is not a table")
            target[part] = dict(existing)
            target = target[part]
        target[parts[-1]] = value
    return result


def _number(table: Mapping[str, Any], key: str) -> float:
    return finite_number(table[key], f"scene key '{key}'")


def _name(table: Mapping[str, Any], key: str, known: registry.Registry[Any]) -> str:
    value = table[key]
    if not isinstance(value, str):
        raise ConfigError(f"scene key '{key}': expected a name, got {value!r}")
    known.get(value)  # raises with the allowed names
    return value


def _boundary_side(value: Any, side: str) -> BoundarySide:
    if isinstance(value, str):
        kind, options = value, {}
    elif isinstance(value, Mapping) and "kind" in value:
        kind = value["kind"]
        options = {k: v for k, v in value.items() if k != "kind"}
    else:
        raise ConfigError(
            f"boundary.{side}: expected a name or {{ kind = ..., ... }}, got {value!r}; "
            f"allowed: {', '.join(registry.boundaries.names())}"
        )
    if not isinstance(kind, str):
        raise ConfigError(f"boundary.{side}: expected a name, got {kind!r}")
    condition = registry.boundaries.get(kind)
    for key in options:
        if key not in condition.options:
            raise ConfigError(
                unknown_name_message(f"option of boundary '{kind}'", key, condition.options)
                if condition.options
                else f"boundary.{side}: '{kind}' takes no options, got '{key}'"
            )
    return BoundarySide(kind, options)


def _scheme_options(value: Any, scheme: str) -> dict[str, Any]:
    """The ``[scheme_options]`` table checked against the options ``scheme`` declares, with its
    defaults filled in."""
    if not isinstance(value, Mapping):
        raise ConfigError(f"scene key 'scheme_options': expected a table, got {value!r}")
    scheme_class = registry.schemes.get(scheme)
    return dict(scheme_class.resolve_options(value))


def _check_table(value: Any, key: str, allowed: tuple[str, ...]) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise ConfigError(f"scene key '{key}': expected a table, got {value!r}")
    for inner in value:
        if inner not in allowed:
            raise ConfigError(unknown_name_message(f"key in [{key}]", inner, allowed))
    return value


def resolve_files(
    parameters: Mapping[str, Any], folder: Path | None, table: str = "parameters"
) -> dict[str, Any]:
    """Parameters whose name ends in ``_file`` are paths. A relative one is looked up first next
    to the scene file (so a scene and its tables travel together), and otherwise taken relative
    to the current folder (as for a ``--set`` on the command line). ``table`` names the scene's
    table in messages (``parameters``, ``initial``)."""
    resolved = dict(parameters)
    for key, value in parameters.items():
        if not key.endswith("_file") or not isinstance(value, str) or not value:
            continue
        try:
            path = Path(value).expanduser()
        except RuntimeError:  # ~user of an unknown user
            raise ConfigError(
                f"{table}.{key}: cannot expand '{value}' (no such user's home folder)"
            ) from None
        if not path.is_absolute() and folder is not None and (folder / path).exists():
            resolved[key] = str((folder / path).resolve())
    return resolved


def _filled(raw: Mapping[str, Any]) -> dict[str, Any]:
    """The scene's keys with the defaults filled in; unknown and missing required keys are
    errors."""
    for key in raw:
        if key not in DEFAULTS:
            raise ConfigError(unknown_name_message("scene key", key, DEFAULTS))
    table = dict(DEFAULTS)
    table.update(raw)
    for key, value in table.items():
        if value is REQUIRED:
            raise ConfigError(f"scene key '{key}' is required ({KEY_HELP[key]})")
    return table


def _domain(table: Mapping[str, Any]) -> tuple[float, int, float, float, float, list[float]]:
    """``cfl, n_cells, x_min, x_max, t_end`` and the sorted output times (t_end included)."""
    cfl = _number(table, "cfl")
    if not 0.0 < cfl < 0.5:
        raise ConfigError(f"scene key 'cfl': must be in (0, 0.5) (paper eq. 17), got {cfl}")
    n_cells = table["n_cells"]
    if isinstance(n_cells, bool) or not isinstance(n_cells, int) or not 4 <= n_cells <= MAX_CELLS:
        raise ConfigError(
            f"scene key 'n_cells': expected an integer >= 4 and <= {MAX_CELLS}, got {n_cells!r}"
        )
    x_min, x_max = _number(table, "x_min"), _number(table, "x_max")
    if not (x_max > x_min and math.isfinite(x_max - x_min)):
        raise ConfigError(
            f"scene keys 'x_min', 'x_max': need x_min < x_max a finite length apart, "
            f"got {x_min}, {x_max}"
        )
    dx = (x_max - x_min) / n_cells
    finest = 64.0 * math.ulp(max(abs(x_min), abs(x_max)))
    if not dx > finest:
        raise ConfigError(
            f"scene keys 'x_min', 'x_max', 'n_cells': cells {dx:.3g} wide cannot be told apart "
            f"at x = {max(abs(x_min), abs(x_max)):.3g} (floating-point spacing there "
            f"{finest / 64:.3g}); move the domain nearer 0 or use fewer cells"
        )
    t_end = _number(table, "t_end")
    if not t_end > 0.0:
        raise ConfigError(f"scene key 't_end': must be > 0, got {t_end}")
    times_raw = table["output_times"]
    if not isinstance(times_raw, list):
        raise ConfigError(
            f"scene key 'output_times': expected a list of numbers, got {times_raw!r}"
        )
    times = sorted(
        {_number({"output_times": t}, "output_times") for t in times_raw}
        | {t_end}
        | set(interval_times(_number(table, "output_interval"), t_end))
    )
    if times[0] < 0.0 or times[-1] > t_end:
        raise ConfigError(f"scene key 'output_times': every time must be in [0, t_end={t_end}]")
    return cfl, n_cells, x_min, x_max, t_end, times


#: Most output times an ``output_interval`` may give.
MAX_INTERVAL_TIMES = 10_000


def interval_times(interval: float, t_end: float) -> list[float]:
    """The output times of ``output_interval``: ``k * interval`` for ``k = 0, 1, ...`` up to
    ``t_end`` (a time within 1e-9 interval of ``t_end`` is ``t_end`` itself); none for 0."""
    if interval == 0.0:
        return []
    if interval < 0.0:
        raise ConfigError(
            f"scene key 'output_interval': must be > 0 (or 0 for none), got {interval}"
        )
    count = math.floor(t_end / interval * (1.0 + 1e-12) + 1e-9)
    if count + 1 > MAX_INTERVAL_TIMES:
        raise ConfigError(
            f"scene key 'output_interval': {interval} gives {count + 1:.3g} output times up to "
            f"t_end={t_end}; at most {MAX_INTERVAL_TIMES}"
        )
    # Twelve significant digits: 3 * 0.1 is the output time 0.3, not 0.30000000000000004.
    times = [float(f"{k * interval:.12g}") for k in range(count + 1)]
    return [float(t_end) if abs(t - t_end) <= 1e-9 * interval else t for t in times if t <= t_end]


def _scheme_with_front_tracking(
    raw: Mapping[str, Any], table: Mapping[str, Any], scheme: str
) -> tuple[str, bool]:
    """The scheme, with the ``front_tracking`` flag of earlier scene files (with
    nessyahu-tadmor it means the front-tracking scheme), and whether it tracks fronts."""
    front_tracking = table["front_tracking"]
    if not isinstance(front_tracking, bool):
        raise ConfigError(
            f"scene key 'front_tracking': expected true or false, got {front_tracking!r}"
        )
    if raw.get("front_tracking") is False and scheme == "front-tracking":
        raise ConfigError(
            "scene key 'front_tracking': false contradicts scheme = \"front-tracking\" (choose "
            'the scheme alone, e.g. scheme = "nessyahu-tadmor")'
        )
    if front_tracking and scheme == "nessyahu-tadmor":
        scheme = "front-tracking"
    elif front_tracking and scheme != "front-tracking":
        raise ConfigError(
            f"scene key 'front_tracking': front tracking is the scheme 'front-tracking' (write "
            f"scheme = \"front-tracking\"), it cannot be combined with '{scheme}'"
        )
    return scheme, scheme == "front-tracking"


def _max_steps(table: Mapping[str, Any]) -> int:
    max_steps = table["max_steps"]
    if (
        isinstance(max_steps, bool)
        or not isinstance(max_steps, int)
        or not 1 <= max_steps <= MAX_STEPS
    ):
        raise ConfigError(
            f"scene key 'max_steps': expected an integer >= 1 and <= {MAX_STEPS}, got {max_steps!r}"
        )
    return max_steps


def _boundaries(table: Mapping[str, Any]) -> tuple[BoundarySide, BoundarySide]:
    boundary = _check_table(table["boundary"], "boundary", ("left", "right"))
    left = _boundary_side(boundary.get("left", "outflow"), "left")
    right = _boundary_side(boundary.get("right", "outflow"), "right")
    if (left.kind == "periodic") != (right.kind == "periodic"):
        raise ConfigError(
            f"boundary: 'periodic' must be used on both sides, got left='{left.kind}', "
            f"right='{right.kind}'"
        )
    return left, right


def _output(table: Mapping[str, Any]) -> tuple[list[str], bool]:
    """The ``[output]`` table: the formats (in order, once each) and whether to plot."""
    output = _check_table(table["output"], "output", OUTPUT_KEYS)
    formats = output.get("formats", ["npz"])
    if not isinstance(formats, list) or any(
        not isinstance(f, str) or f not in OUTPUT_FORMATS for f in formats
    ):
        raise ConfigError(
            f"output.formats: expected a list of {', '.join(OUTPUT_FORMATS)}, got {formats!r}"
        )
    if not formats:
        raise ConfigError(
            f"output.formats: an empty list writes no states; give at least one of "
            f"{', '.join(OUTPUT_FORMATS)}"
        )
    plot = output.get("plot", True)
    if not isinstance(plot, bool):
        raise ConfigError(f"output.plot: expected true or false, got {plot!r}")
    return list(dict.fromkeys(formats)), plot


def validate(
    name: str, raw: Mapping[str, Any], folder: Path | None = None, model_object: Model | None = None
) -> Scene:
    """Validate a raw scene mapping (after overrides) into a :class:`Scene`.

    ``folder`` is where the scene file lives (relative ``*_file`` parameters are resolved there).
    ``model_object``: the model of the mapping's model and parameters if the caller has one
    (it is not built a second time).
    """
    table = _filled(plain_values(raw))
    model = _name(table, "model", registry.models)
    scheme = _name(table, "scheme", registry.schemes)
    scheme_options = _scheme_options(table["scheme_options"], scheme)
    reconstructor = _name(table, "reconstructor", registry.reconstructors)
    if not isinstance(table["description"], str):
        raise ConfigError("scene key 'description': expected a string")
    parameters = table["parameters"]
    if not isinstance(parameters, Mapping):
        raise ConfigError(f"scene key 'parameters': expected a table, got {parameters!r}")
    parameters = resolve_files(parameters, folder)
    cfl, n_cells, x_min, x_max, t_end, times = _domain(table)
    scheme, front_tracking = _scheme_with_front_tracking(raw, table, scheme)
    if not isinstance(table["exact"], bool):
        raise ConfigError(f"scene key 'exact': expected true or false, got {table['exact']!r}")
    max_steps = _max_steps(table)
    left, right = _boundaries(table)
    parameters = dict(parameters)
    if model_object is None or model_object.name != model:
        model_object = registry.models.get(model)(**parameters)  # validates its own parameters
    if front_tracking and (model_object.depth_index is None or model_object.n_vars != 2):
        raise ConfigError(
            f"scene key 'front_tracking': needs a model with a depth variable, q = (h, hu); "
            f"'{model}' has none"
        )
    initial = InitialCondition.from_table(table["initial"], registry.models.get(model))
    formats, plot = _output(table)
    return Scene(
        name=name, description=table["description"], model=model, parameters=parameters,
        scheme=scheme, reconstructor=reconstructor, cfl=cfl, n_cells=n_cells, x_min=x_min,
        x_max=x_max, t_end=t_end, output_times=tuple(times), exact=table["exact"], left=left,
        right=right, initial=initial, output_formats=tuple(formats), plot=plot,
        front_tracking=front_tracking, scheme_options=scheme_options, max_steps=max_steps,
        validated_model=(parameters, model_object),
    )  # fmt: skip


def is_two_dimensional(table: Mapping[str, Any]) -> bool:
    """Whether a raw scene names a registered 2D model (one with a y flux;
    :mod:`conslaw.scene2d` reads such scenes)."""
    model = table.get("model")
    return (
        isinstance(model, str)
        and model in registry.models
        and registry.models.get(model).flux_y_point is not None
    )


def load_scene(name_or_path: str | Path, overrides: Mapping[str, Any] | None = None) -> Scene:
    """Read, override and validate a 1D scene (a built-in name or a ``.toml`` path); a 2D
    scene is a ConfigError pointing to :func:`conslaw.scene2d.load_scene_2d`."""
    name, path = scene_path(name_or_path)
    raw = read_scene_file(path)
    table = apply_overrides(raw, overrides or {})
    if is_two_dimensional(table):
        raise ConfigError(
            f"scene '{name}' is two-dimensional (model '{table['model']}'): run it with "
            "conslaw.run_2d or read it with conslaw.scene2d.load_scene_2d (conslaw run takes "
            "either)"
        )
    if overrides and "description" not in overrides:
        table["description"] = described_with(str(raw.get("description", "")), overrides)
    return dataclasses.replace(validate(name, table, path.parent), source_file=str(path))


def described_with(description: str, overrides: Mapping[str, Any]) -> str:
    """A scene's description with what the overrides changed, so that the ``scene.toml``
    written next to the output does not describe a scene that was not run."""
    changed = ", ".join(
        f"{key}={value!r}"[:60] for key, value in overrides.items() if key != "description"
    )
    return f"{description} [changed: {changed}]" if description else f"[changed: {changed}]"


def parse_scheme_spec(spec: str) -> tuple[str, dict[str, Any]]:
    """``"name"`` or ``"name:key=value:key=value"`` (a scheme with options, as in
    ``--scheme nessyahu-tadmor,lagrangian:viscosity=0.02``) -> ``(name, options)``."""
    name, *parts = str(spec).split(":")
    options: dict[str, Any] = {}
    for part in parts:
        key, separator, value = part.partition("=")
        if not separator or not key.strip():
            raise ConfigError(f"--scheme: expected name or name:key=value, got '{spec}'")
        options[key.strip()] = parse_value(value.strip())
    if not name.strip():
        raise ConfigError(f"--scheme: expected a scheme name, got '{spec}'")
    return name.strip(), options


def scheme_variants(
    name_or_path: str | Path,
    specs: list[str],
    overrides: Mapping[str, Any] | None = None,
) -> list[Scene]:
    """One validated scene per scheme spec (:func:`parse_scheme_spec`), all else equal.

    The scene's own ``[scheme_options]`` (after overrides) go to every variant whose scheme
    declares them; a key that none of the schemes declares is an error. Options in a spec come
    on top. Every variant is validated before any is returned.
    """
    name, path = scene_path(name_or_path)
    raw = apply_overrides(read_scene_file(path), overrides or {})
    base = raw.get("scheme_options", {})
    if not isinstance(base, Mapping):
        raise ConfigError(f"scene key 'scheme_options': expected a table, got {base!r}")
    parsed = [parse_scheme_spec(spec) for spec in specs]
    if not parsed:
        raise ConfigError("--scheme: expected at least one scheme")
    classes = [registry.schemes.get(scheme) for scheme, _ in parsed]
    for key in base:
        if not any(key in scheme_class.options for scheme_class in classes):
            names = ", ".join(scheme for scheme, _ in parsed)
            raise ConfigError(f"scheme_options.{key}: none of the schemes ({names}) has it")
    variants = []
    for (scheme, options), scheme_class in zip(parsed, classes, strict=True):
        table = dict(raw)
        table["scheme"] = scheme
        kept = {key: value for key, value in base.items() if key in scheme_class.options}
        table["scheme_options"] = {**kept, **options}
        variants.append(validate(name, table, path.parent))
    return variants
