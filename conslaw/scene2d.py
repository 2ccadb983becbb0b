"""Two-dimensional scene files: TOML, validated into a frozen :class:`Scene2D`
(docs/scenes.md, "Two-dimensional scenes").

A scene is two-dimensional when its model is (``Model.n_dims == 2``: the model has a y flux).
Its keys are those of a 1D scene (:mod:`conslaw.config`) with the domain and the boundary in
both directions: ``n_cells = [nx, ny]``, ``x_min``, ``x_max``, ``y_min``, ``y_max``, and
``[boundary]`` with ``left``, ``right``, ``bottom`` and ``top``. The scheme is a registered 2D
scheme (``jiang-tadmor``); the initial condition one of :mod:`conslaw.initial2d`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from conslaw import registry
from conslaw.config import (
    DEFAULTS,
    MAX_STEPS,
    REQUIRED,
    Scene,
    apply_overrides,
    described_with,
    interval_times,
    is_two_dimensional,
    load_scene,
    plain_values,
    read_scene_file,
    resolve_files,
    scene_model,
    scene_path,
)
from conslaw.errors import ConfigError, finite_number, unknown_name_message
from conslaw.grid import MAX_CELLS
from conslaw.grid2d import Grid2D
from conslaw.initial2d import InitialCondition2D
from conslaw.stopping import StopRule, stop_rule

if TYPE_CHECKING:
    from conslaw.model import Model

SIDES_2D = ("left", "right", "bottom", "top")
#: File formats of a 2D run (``output.formats``; docs/output.md).
OUTPUT_FORMATS_2D = ("npz", "xdmf", "geotiff", "gif")

#: Every top-level key of a 2D scene with its default (REQUIRED: the scene must give it).
DEFAULTS_2D: dict[str, Any] = {
    "description": "",
    "model": REQUIRED,
    "parameters": {},
    "scheme": "jiang-tadmor",
    "scheme_options": {},
    "reconstructor": "mc",
    "cfl": 0.45,
    "n_cells": REQUIRED,
    "x_min": REQUIRED,
    "x_max": REQUIRED,
    "y_min": REQUIRED,
    "y_max": REQUIRED,
    "t_end": REQUIRED,
    "output_times": [],
    "output_interval": 0.0,
    "exact": True,
    "max_steps": 100_000_000,
    "boundary": {side: "outflow" for side in SIDES_2D},
    "initial": REQUIRED,
    "output": {"formats": ["npz"], "plot": True},
    "stop": {},
}

#: One-line meaning of the keys that differ from a 1D scene's.
KEY_HELP_2D: dict[str, str] = {
    "scheme": "registered 2D scheme (built in: jiang-tadmor; jiang-tadmor-ft, the same with the "
    'margins of the depth tracked, docs/design.md "Margins in two dimensions")',
    "scheme_options": "jiang-tadmor and jiang-tadmor-ft: threads (default: every core) and "
    "chunks of rows per step (default: 2 per thread), integers >= 1; the results do not depend "
    "on them",
    "cfl": "target Courant number per direction, 0 < cfl < 0.5 (stable; Jiang & Tadmor 1998); "
    "values stay within the initial range only with none at <= 0.25 or minmod at <= 0.125 "
    '(docs/design.md, "The 2D time step and the maximum principle")',
    "n_cells": "[nx, ny]: cells along x and along y, integers >= 4",
    "y_min": "lower end of the domain in y",
    "y_max": "upper end of the domain in y",
    "boundary": "table: left, right, bottom, top = periodic, outflow, wall or "
    '{ kind = "inflow", state = [...] } (a fixed state in the ghost cells)',
    "initial": "table: kind (dam-break, circle, or the model's own) and its options",
    "output": "table: formats = a list (at least one) of npz (states.npz), xdmf (solution.xdmf "
    "+ HDF5, quadrilateral cells); plot = PNG maps and cuts at the end (bool)",
    "stop": "table: at_rest = end the run at the first output time at which the material is at "
    "rest, t_end the cap (bool; default true for a model on terrain, savage-hutter-terrain, "
    "else false; needs a model with a depth and a momentum); energy_fraction = at rest when "
    "the kinetic energy is at most this fraction of its peak so far, or every momentum is 0, "
    'in [0, 1) (default 0.01, AvaFrame\'s stopCrit; docs/terrain.md, "Stopping at rest")',
}


@dataclass(frozen=True)
class Scene2D:
    """A validated 2D scene: everything a run needs, with defaults filled in."""

    name: str
    description: str
    model: str
    parameters: Mapping[str, Any]
    scheme: str
    reconstructor: str
    cfl: float
    nx: int
    ny: int
    x_min: float
    x_max: float
    y_min: float
    y_max: float
    t_end: float
    output_times: tuple[float, ...]
    exact: bool
    boundaries: Mapping[str, str]
    initial: InitialCondition2D
    output_formats: tuple[str, ...]
    plot: bool
    scheme_options: Mapping[str, Any] = field(default_factory=dict)
    max_steps: int = DEFAULTS_2D["max_steps"]
    #: The state of every inflow side.
    inflow: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    #: When the run ends before t_end (``[stop]``; :mod:`conslaw.stopping`).
    stop: StopRule = field(default_factory=StopRule)
    #: The scene file it was read from ("" for a scene built in Python).
    source_file: str = ""
    validated_model: tuple[Mapping[str, Any], Model] | None = field(
        default=None, compare=False, repr=False
    )

    @property
    def n_cells(self) -> int:
        """``nx ny``."""
        return self.nx * self.ny

    def model_instance(self) -> Model:
        """The model validation built, or a new one from the parameters
        (:func:`conslaw.config.scene_model`)."""
        return scene_model(self.model, self.parameters, self.validated_model)

    def to_table(self) -> dict[str, Any]:
        """The resolved scene as a TOML-ready mapping (written next to every output)."""
        return {
            "description": self.description,
            "model": self.model,
            "scheme": self.scheme,
            **({"scheme_options": dict(self.scheme_options)} if self.scheme_options else {}),
            "reconstructor": self.reconstructor,
            "cfl": self.cfl,
            "n_cells": [self.nx, self.ny],
            "x_min": self.x_min,
            "x_max": self.x_max,
            "y_min": self.y_min,
            "y_max": self.y_max,
            "t_end": self.t_end,
            "output_times": list(self.output_times),
            "exact": self.exact,
            "max_steps": self.max_steps,
            "parameters": dict(self.parameters),
            "boundary": {
                side: (
                    {"kind": "inflow", "state": list(self.inflow[side])}
                    if side in self.inflow
                    else kind
                )
                for side, kind in self.boundaries.items()
            },
            "initial": self.initial.to_table(),
            "output": {"formats": list(self.output_formats), "plot": self.plot},
            "stop": self.stop.to_table(),
        }


def _number(table: Mapping[str, Any], key: str) -> float:
    return finite_number(table[key], f"scene key '{key}'")


def _name(value: Any, key: str, known: registry.Registry[Any]) -> str:
    if not isinstance(value, str):
        raise ConfigError(f"scene key '{key}': expected a name, got {value!r}")
    known.get(value)  # raises with the allowed names
    return value


def _table(value: Any, key: str, allowed: tuple[str, ...]) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise ConfigError(f"scene key '{key}': expected a table, got {value!r}")
    for inner in value:
        if inner not in allowed:
            raise ConfigError(unknown_name_message(f"key in [{key}]", inner, allowed))
    return value


def _filled(raw: Mapping[str, Any]) -> dict[str, Any]:
    for key in raw:
        if key not in DEFAULTS_2D:
            raise ConfigError(unknown_name_message("scene key (2D scene)", key, DEFAULTS_2D))
    table = {**DEFAULTS_2D, **raw}
    for key, value in table.items():
        if value is REQUIRED:
            raise ConfigError(f"scene key '{key}' is required in a 2D scene")
    return table


def _cells(value: Any) -> tuple[int, int]:
    if not (
        isinstance(value, list)
        and len(value) == 2
        and all(isinstance(n, int) and not isinstance(n, bool) and n >= 4 for n in value)
    ):
        raise ConfigError(
            f"scene key 'n_cells': a 2D scene needs [nx, ny], integers >= 4, got {value!r}"
        )
    nx, ny = value
    if nx * ny > MAX_CELLS:
        raise ConfigError(f"scene key 'n_cells': nx * ny must be <= {MAX_CELLS}, got {nx * ny}")
    return nx, ny


def _extent(table: Mapping[str, Any], low: str, high: str, cells: int) -> tuple[float, float]:
    lowest, highest = _number(table, low), _number(table, high)
    if not (highest > lowest and math.isfinite(highest - lowest)):
        raise ConfigError(
            f"scene keys '{low}', '{high}': need {low} < {high} a finite length apart, "
            f"got {lowest}, {highest}"
        )
    finest = 64.0 * math.ulp(max(abs(lowest), abs(highest)))
    if not (highest - lowest) / cells > finest:
        raise ConfigError(
            f"scene keys '{low}', '{high}', 'n_cells': cells that narrow cannot be told apart "
            "there; move the domain nearer 0 or use fewer cells"
        )
    return lowest, highest


def _times(table: Mapping[str, Any]) -> tuple[float, list[float]]:
    t_end = _number(table, "t_end")
    if not t_end > 0.0:
        raise ConfigError(f"scene key 't_end': must be > 0, got {t_end}")
    listed = table["output_times"]
    if not isinstance(listed, list):
        raise ConfigError(f"scene key 'output_times': expected a list of numbers, got {listed!r}")
    times = sorted(
        {finite_number(t, "scene key 'output_times'") for t in listed}
        | {t_end}
        | set(interval_times(_number(table, "output_interval"), t_end))
    )
    if times[0] < 0.0 or times[-1] > t_end:
        raise ConfigError(f"scene key 'output_times': every time must be in [0, t_end={t_end}]")
    return t_end, times


def _boundaries(
    value: Any, kinds: tuple[str, ...], scheme: str
) -> tuple[dict[str, str], dict[str, tuple[float, ...]]]:
    """The kind of every side (one of ``kinds``, those of the 2D scheme named ``scheme``), and
    the state of every inflow side (``{ kind = "inflow", state = [...] }``)."""
    given = _table(value, "boundary", SIDES_2D)
    sides: dict[str, str] = {}
    inflow: dict[str, tuple[float, ...]] = {}
    for side in SIDES_2D:
        entry = given.get(side, "outflow")
        if isinstance(entry, Mapping):
            entry = dict(_table(entry, f"boundary.{side}", ("kind", "state")))
            state = entry.get("state")
            if entry.get("kind") != "inflow" or not isinstance(state, list):
                raise ConfigError(
                    f'boundary.{side}: a table is {{ kind = "inflow", state = [...] }}, '
                    f"got {entry!r}"
                )
            inflow[side] = tuple(finite_number(v, f"boundary.{side}.state") for v in state)
            entry = "inflow"
        if not isinstance(entry, str) or entry not in kinds:
            raise ConfigError(
                f"boundary.{side}: {entry!r} is not one of {', '.join(kinds)} (the sides of "
                f"2D scheme '{scheme}')"
            )
        if entry == "inflow" and side not in inflow:
            raise ConfigError(
                f'boundary.{side}: an inflow side is written {{ kind = "inflow", state = [...] }}'
            )
        sides[side] = entry
    for low, high in (("left", "right"), ("bottom", "top")):
        if (sides[low] == "periodic") != (sides[high] == "periodic"):
            raise ConfigError(f"boundary.{low} and boundary.{high}: periodic on both or neither")
    return sides, inflow


def _output(value: Any) -> tuple[list[str], bool]:
    output = _table(value, "output", ("formats", "plot"))
    formats = output.get("formats", ["npz"])
    if not isinstance(formats, list) or any(f not in OUTPUT_FORMATS_2D for f in formats):
        raise ConfigError(
            f"output.formats: a 2D scene writes {', '.join(OUTPUT_FORMATS_2D)}, got {formats!r}"
        )
    if not formats:
        raise ConfigError(
            f"output.formats: an empty list writes no states; give at least one of "
            f"{', '.join(OUTPUT_FORMATS_2D)}"
        )
    plot = output.get("plot", True)
    if not isinstance(plot, bool):
        raise ConfigError(f"output.plot: expected true or false, got {plot!r}")
    return list(dict.fromkeys(formats)), plot


def _scheme_options(value: Any, scheme_class: Any) -> dict[str, Any]:
    options = _table(value, "scheme_options", tuple(scheme_class.options))
    for key, option in options.items():
        if isinstance(option, bool) or not isinstance(option, int) or option < 1:
            raise ConfigError(f"scheme_options.{key}: expected an integer >= 1, got {option!r}")
    return dict(options)


def validate_2d(
    name: str,
    raw: Mapping[str, Any],
    model_object: Model | None = None,
    folder: Path | None = None,
) -> Scene2D:
    """Validate a raw 2D scene mapping (after overrides) into a :class:`Scene2D`; a
    ConfigError naming the key otherwise. ``model_object``: the model of the mapping's model
    and parameters if the caller has one (it is not built a second time). ``folder``: where
    the scene file lives (relative ``*_file`` parameters and initial options are looked up
    there first, :func:`~conslaw.config.resolve_files`)."""
    table = _filled(plain_values(raw))
    model = _name(table["model"], "model", registry.models)
    model_class = registry.models.get(model)
    if model_class.flux_y_point is None:
        raise ConfigError(f"scene key 'model': '{model}' is one-dimensional (a 1D scene)")
    scheme = _name(table["scheme"], "scheme", registry.schemes_2d)
    scheme_class = registry.schemes_2d.get(scheme)
    reconstructor = _name(table["reconstructor"], "reconstructor", registry.reconstructors)
    if not isinstance(table["description"], str):
        raise ConfigError("scene key 'description': expected a string")
    parameters = table["parameters"]
    if not isinstance(parameters, Mapping):
        raise ConfigError(f"scene key 'parameters': expected a table, got {parameters!r}")
    cfl = _number(table, "cfl")
    if not 0.0 < cfl < 0.5:
        raise ConfigError(f"scene key 'cfl': must be in (0, 0.5), got {cfl}")
    nx, ny = _cells(table["n_cells"])
    x_min, x_max = _extent(table, "x_min", "x_max", nx)
    y_min, y_max = _extent(table, "y_min", "y_max", ny)
    t_end, times = _times(table)
    if not isinstance(table["exact"], bool):
        raise ConfigError(f"scene key 'exact': expected true or false, got {table['exact']!r}")
    max_steps = table["max_steps"]
    if isinstance(max_steps, bool) or not isinstance(max_steps, int):
        raise ConfigError(f"scene key 'max_steps': expected an integer >= 1, got {max_steps!r}")
    if not 1 <= max_steps <= MAX_STEPS:
        raise ConfigError(f"scene key 'max_steps': expected 1 to {MAX_STEPS}, got {max_steps}")
    boundaries, inflow = _boundaries(
        table["boundary"], scheme_class.boundary_kinds, scheme_class.name
    )
    scheme_options = _scheme_options(table["scheme_options"], scheme_class)
    parameters = resolve_files(parameters, folder)
    if model_object is None or model_object.name != model:
        model_object = model_class(**parameters)  # validates its own parameters
    grid = Grid2D.from_bounds(x_min, x_max, nx, y_min, y_max, ny)
    model_object.check_domain_2d(grid)
    model_object.check_boundaries_2d(boundaries)
    initial_table = table["initial"]
    if isinstance(initial_table, Mapping):
        initial_table = resolve_files(initial_table, folder, "initial")
    initial = InitialCondition2D.from_table(initial_table, model_class)
    formats, plot = _output(table["output"])
    stop = stop_rule(table["stop"], model_object)
    for terrain_only in ("geotiff", "gif"):
        if terrain_only in formats and model_object.scene_dem(grid) is None:
            raise ConfigError(
                f"output.formats: '{terrain_only}' writes the hazard maps of a model on terrain; "
                f"'{model}' has none"
            )
    return Scene2D(
        name=name, description=table["description"], model=model, parameters=parameters,
        scheme=scheme, reconstructor=reconstructor, cfl=cfl, nx=nx, ny=ny, x_min=x_min,
        x_max=x_max, y_min=y_min, y_max=y_max, t_end=t_end, output_times=tuple(times),
        exact=table["exact"], boundaries=boundaries, initial=initial,
        output_formats=tuple(formats), plot=plot, scheme_options=scheme_options,
        max_steps=max_steps, inflow=inflow, stop=stop,
        validated_model=(parameters, model_object),
    )  # fmt: skip


def load_scene_2d(name_or_path: str | Path, overrides: Mapping[str, Any] | None = None) -> Scene2D:
    """Read, override and validate a 2D scene (a built-in name or a ``.toml`` path)."""
    name, path = scene_path(name_or_path)
    raw = read_scene_file(path)
    table = apply_overrides(raw, overrides or {}, DEFAULTS_2D)
    if not model_dimension(name, table) == 2:
        raise ConfigError(
            f"scene '{name}' is one-dimensional (model '{table['model']}'): run it with "
            "conslaw.run or read it with conslaw.config.load_scene (conslaw run takes either)"
        )
    if overrides and "description" not in overrides:
        table["description"] = described_with(str(raw.get("description", "")), overrides)
    return dataclasses.replace(validate_2d(name, table, folder=path.parent), source_file=str(path))


def load_any_scene(
    name_or_path: str | Path, overrides: Mapping[str, Any] | None = None
) -> Scene | Scene2D:
    """A 1D :class:`~conslaw.config.Scene` or a :class:`Scene2D`, by the scene's model."""
    name, path = scene_path(name_or_path)
    raw = read_scene_file(path)
    dimension = model_dimension(
        name, apply_overrides(raw, overrides or {}, {**DEFAULTS, **DEFAULTS_2D})
    )
    # every key of either dimension is accepted here; a table filled by a dotted override
    # (boundary.left = ...) starts from the defaults of the model's own dimension
    own, other = (DEFAULTS, DEFAULTS_2D) if dimension == 1 else (DEFAULTS_2D, DEFAULTS)
    table = apply_overrides(raw, overrides or {}, {**other, **own})
    shaped = two_dimensional_keys(table)
    if dimension == 1 and shaped:
        raise ConfigError(
            f"scene '{name}': model '{table['model']}' is one-dimensional but the scene is "
            f"two-dimensional ({', '.join(shaped)}); 2D models: {', '.join(_models_of(2))}"
        )
    if dimension == 2 and not shaped:
        raise ConfigError(
            f"scene '{name}': model '{table['model']}' is two-dimensional but the scene is "
            f"one-dimensional (no y_min, y_max; n_cells a number); 1D models: "
            f"{', '.join(_models_of(1))}"
        )
    if dimension == 2:
        return load_scene_2d(name_or_path, overrides)
    return load_scene(name_or_path, overrides)


def model_dimension(name: str, table: Mapping[str, Any]) -> int:
    """1 or 2: the space dimension of a raw scene's model (2 for a model with a y flux); a
    ConfigError naming the key if the model is missing or unknown."""
    model = table.get("model")
    if model is None:
        raise ConfigError(f"scene '{name}': scene key 'model' is required")
    _name(model, "model", registry.models)
    return 2 if is_two_dimensional(table) else 1


def two_dimensional_keys(table: Mapping[str, Any]) -> list[str]:
    """What in a raw scene belongs to a 2D scene only: ``y_min``, ``y_max``, ``n_cells`` as
    ``[nx, ny]``, a ``bottom`` or ``top`` side (empty for a 1D scene)."""
    keys = [key for key in ("y_min", "y_max") if key in table]
    if isinstance(table.get("n_cells"), list):
        keys.append("n_cells = [nx, ny]")
    boundary = table.get("boundary")
    if isinstance(boundary, Mapping):
        keys += [f"boundary.{side}" for side in ("bottom", "top") if side in boundary]
    return keys


def _models_of(dimension: int) -> list[str]:
    """The registered models of one space dimension, by name."""
    return [
        model
        for model in sorted(registry.models)
        if (registry.models.get(model).flux_y_point is not None) == (dimension == 2)
    ]
