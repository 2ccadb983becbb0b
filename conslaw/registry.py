"""Registries: names -> models, schemes, reconstructors, boundary conditions, scenes.

Third-party packages add entries through entry-point groups (``conslaw.models``,
``conslaw.schemes``, ``conslaw.reconstructors``, ``conslaw.boundaries``); conslaw's own models are
registered the same way (see ``pyproject.toml``). Every registration checks the contract, so a
broken plugin is refused with a clear message instead of failing deep inside a run.
"""

from __future__ import annotations

import dataclasses
import threading
import warnings
from collections.abc import Callable, Iterator
from importlib import resources
from importlib.metadata import entry_points
from pathlib import Path
from typing import TYPE_CHECKING, Any, Generic, TypeVar

from conslaw.boundary import BoundaryCondition, builtin_boundary_conditions
from conslaw.errors import ConfigError, ConslawError, unknown_name_message
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor, builtin_reconstructors

if TYPE_CHECKING:
    from conslaw.schemes.base import Scheme

T = TypeVar("T")


class ContractError(ConslawError, TypeError):
    """A plugin does not implement the interface it registers for."""


class Registry(Generic[T]):
    """A name -> object map for one kind of plugin, filled lazily from an entry-point group."""

    def __init__(
        self,
        kind: str,
        group: str | None,
        check: Callable[[str, Any], T],
        builtins: Callable[[], list[tuple[str, T]]] | None = None,
    ) -> None:
        self.kind = kind
        self.group = group
        self._check = check
        self._builtins = builtins
        self._entries: dict[str, T] = {}
        # Plugins found but not imported yet: a run imports only the plugins it names (the
        # terrain model's GeoTIFF and polygon libraries are not for a 1D scene).
        self._pending: dict[str, Any] = {}
        self._discovered = False
        self._discovering = False
        # Another thread waits until an entry is loaded; the loading thread itself (a plugin
        # whose check asks the registry again) sees what is registered so far.
        self._lock = threading.RLock()

    def register(self, name: str, obj: Any) -> T:
        """Check ``obj`` against the contract and register it under ``name``."""
        if not isinstance(name, str) or not name:
            raise ContractError(f"{self.kind} names must be non-empty strings, got {name!r}")
        checked = self._check(name, obj)
        self._entries[name] = checked
        self._pending.pop(name, None)
        return checked

    def _discover(self) -> None:
        """Register the built-in entries and note (without importing them) the plugins of the
        entry-point group; a plugin of a built-in's name replaces it when it is loaded."""
        if self._discovered:
            return
        with self._lock:
            if self._discovered or self._discovering:
                return
            self._discovering = True
            try:
                if self._builtins is not None:
                    for name, obj in self._builtins():
                        self.register(name, obj)
                if self.group is not None:
                    for point in entry_points(group=self.group):
                        self._pending[point.name] = point
            finally:
                self._discovering = False
                self._discovered = True

    def _load_plugin(self, name: str, stacklevel: int = 3) -> None:
        """Import and check the pending plugin ``name`` (if any); a broken plugin is skipped
        with a warning (naming the line that asked for it, ``stacklevel``), so that it cannot
        break runs that do not use it; a built-in of the same name then stays."""
        with self._lock:
            point = self._pending.pop(name, None)
            if point is None:
                return
            try:
                self.register(name, point.load())
            except Exception as error:  # a broken plugin must not break unrelated runs
                warnings.warn(
                    f"conslaw: skipped {self.kind} plugin '{point.name}' ({point.value}): {error}",
                    stacklevel=stacklevel,
                )

    def _load_all(self) -> None:
        self._discover()
        with self._lock:  # a plugin another thread is importing is registered on return
            for name in list(self._pending):
                self._load_plugin(name, stacklevel=4)

    def get(self, name: str) -> T:
        """The entry called ``name``; ConfigError naming the allowed values otherwise."""
        self._discover()
        if isinstance(name, str):
            self._load_plugin(name)
        if not isinstance(name, str) or name not in self._entries:
            raise ConfigError(unknown_name_message(self.kind, str(name), self.names()))
        return self._entries[name]

    def names(self) -> list[str]:
        """Registered names, sorted (every plugin is imported and checked)."""
        self._load_all()
        return sorted(self._entries)

    def __contains__(self, name: object) -> bool:
        self._discover()
        if isinstance(name, str):
            self._load_plugin(name)
        return name in self._entries

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())


# ---------------------------------------------------------------------- contract checks
def check_model(name: str, obj: Any) -> type[Model]:
    """A model must subclass Model, name its variables and provide module-level kernels."""
    from conslaw.kernelgen.generation import import_path

    if not (isinstance(obj, type) and issubclass(obj, Model)):
        raise ContractError(f"model '{name}' must be a subclass of conslaw.model.Model")
    for attribute in ("name", "description"):
        if not isinstance(getattr(obj, attribute, None), str):
            raise ContractError(f"model '{name}' needs a string class attribute '{attribute}'")
    if obj.name != name:
        raise ContractError(f"model registered as '{name}' calls itself '{obj.name}'")
    variables = getattr(obj, "variables", None)
    if not (
        isinstance(variables, tuple) and variables and all(isinstance(v, str) for v in variables)
    ):
        raise ContractError(f"model '{name}' needs 'variables', a non-empty tuple of names")
    if len(getattr(obj, "reflect_signs", ())) != len(variables):
        raise ContractError(f"model '{name}' needs one 'reflect_signs' entry per variable")
    if not dataclasses.is_dataclass(obj.Parameters):
        raise ContractError(f"model '{name}': 'Parameters' must be a dataclass")
    required = ["flux_point", "jacobian_point", "max_speed_point"]
    if obj.has_source:
        required.append("source_point")
    for attribute in required:
        function = getattr(obj, attribute, None)
        if function is None:
            raise ContractError(f"model '{name}' lacks the pointwise kernel '{attribute}'")
        try:
            import_path(function)
        except (TypeError, AttributeError, ImportError) as error:
            raise ContractError(f"model '{name}', {attribute}: {error}") from None
    return obj


def check_scheme(name: str, obj: Any) -> type[Scheme]:
    """A scheme must subclass Scheme and implement stable_dt and step."""
    from conslaw.schemes.base import Scheme

    if not (isinstance(obj, type) and issubclass(obj, Scheme)):
        raise ContractError(f"scheme '{name}' must be a subclass of conslaw.schemes.Scheme")
    if getattr(obj, "__abstractmethods__", None):
        missing = ", ".join(sorted(obj.__abstractmethods__))
        raise ContractError(f"scheme '{name}' does not implement: {missing}")
    return obj


def check_reconstructor(name: str, obj: Any) -> Reconstructor:
    """A reconstructor is a Reconstructor whose slope function is module-level compiled code."""
    from conslaw.kernelgen.generation import import_path

    if callable(obj) and not isinstance(obj, Reconstructor):
        obj = obj()
    if not isinstance(obj, Reconstructor):
        raise ContractError(f"reconstructor '{name}' must be a conslaw.reconstruct.Reconstructor")
    try:
        import_path(obj.slope_point)
    except (TypeError, AttributeError, ImportError) as error:
        raise ContractError(f"reconstructor '{name}': {error}") from None
    if obj.code is not None:
        # The kernels run the built-in slope of the code: it must be this object's own.
        from conslaw.reconstruct import builtin_reconstructors

        owners = {r.code: r.slope_point for r in builtin_reconstructors()}
        if owners.get(obj.code) is not obj.slope_point:
            raise ContractError(
                f"reconstructor '{name}': code {obj.code} belongs to another slope function; "
                "a plugin's reconstructor has code None"
            )
    return obj


def check_boundary(name: str, obj: Any) -> BoundaryCondition:
    """A boundary condition provides module-level compiled fill functions."""
    from conslaw.kernelgen.generation import import_path

    if callable(obj) and not isinstance(obj, BoundaryCondition):
        obj = obj()
    if not isinstance(obj, BoundaryCondition):
        raise ContractError(
            f"boundary condition '{name}' must be a conslaw.boundary.BoundaryCondition"
        )
    for function in (obj.fill_left, obj.fill_right):
        try:
            import_path(function)
        except (TypeError, AttributeError, ImportError) as error:
            raise ContractError(f"boundary condition '{name}': {error}") from None
    return obj


def check_scene(name: str, obj: Any) -> Path:
    """A scene is a TOML file."""
    path = Path(obj)
    if path.suffix != ".toml":
        raise ContractError(f"scene '{name}' must be a .toml file, got {obj!r}")
    return path


def _builtin_schemes() -> list[tuple[str, Any]]:
    from conslaw.schemes.front_tracking.scheme import FrontTrackingNT
    from conslaw.schemes.lagrangian.scheme import LagrangianScheme
    from conslaw.schemes.nessyahu_tadmor.scheme import NessyahuTadmor

    return [(scheme.name, scheme) for scheme in (NessyahuTadmor, FrontTrackingNT, LagrangianScheme)]


def check_scheme_2d(name: str, obj: Any) -> Any:
    """A 2D scheme is a class with ``name``, ``options`` (option name -> description),
    ``boundary_kinds`` and the methods ``advance`` and ``initial_values``."""
    if not isinstance(obj, type):
        raise ContractError(f"2D scheme '{name}' must be a class")
    if getattr(obj, "name", None) != name:
        called = getattr(obj, "name", None)
        raise ContractError(f"2D scheme registered as '{name}' calls itself {called!r}")
    for attribute in ("options", "boundary_kinds"):
        if not hasattr(obj, attribute):
            raise ContractError(f"2D scheme '{name}' needs the class attribute '{attribute}'")
    for method in ("advance", "initial_values"):
        if not callable(getattr(obj, method, None)):
            raise ContractError(f"2D scheme '{name}' does not implement '{method}'")
    return obj


def _builtin_schemes_2d() -> list[tuple[str, Any]]:
    from conslaw.schemes.jiang_tadmor import JiangTadmor, JiangTadmorTracked

    return [(scheme.name, scheme) for scheme in (JiangTadmor, JiangTadmorTracked)]


def _builtin_scenes() -> list[tuple[str, Any]]:
    folder = resources.files("conslaw.scenes")
    return sorted(
        (Path(str(entry)).stem, Path(str(entry)))
        for entry in folder.iterdir()
        if str(entry).endswith(".toml")
    )


models: Registry[type[Model]] = Registry("model", "conslaw.models", check_model)
schemes: Registry[type[Scheme]] = Registry(
    "scheme", "conslaw.schemes", check_scheme, _builtin_schemes
)
schemes_2d: Registry[Any] = Registry(
    "2D scheme", "conslaw.schemes_2d", check_scheme_2d, _builtin_schemes_2d
)
reconstructors: Registry[Reconstructor] = Registry(
    "reconstructor",
    "conslaw.reconstructors",
    check_reconstructor,
    lambda: [(r.name, r) for r in builtin_reconstructors()],
)
boundaries: Registry[BoundaryCondition] = Registry(
    "boundary condition",
    "conslaw.boundaries",
    check_boundary,
    lambda: [(b.name, b) for b in builtin_boundary_conditions()],
)
scenes: Registry[Path] = Registry("scene", "conslaw.scenes", check_scene, _builtin_scenes)


def description_of(kind: str, name: str) -> str:
    """One-line description of a registered entry."""
    if kind == "models":
        return models.get(name).description
    if kind == "schemes":
        return str(getattr(schemes.get(name), "description", ""))
    if kind == "schemes_2d":
        return str(getattr(schemes_2d.get(name), "description", ""))
    if kind == "reconstructors":
        return reconstructors.get(name).description
    if kind == "boundaries":
        return boundaries.get(name).description
    if kind == "scenes":
        import tomllib

        with open(scenes.get(name), "rb") as handle:
            return str(tomllib.load(handle).get("description", ""))
    raise KeyError(kind)
