"""Generation of compiled kernels from templates.

numba caches compiled code on disk only for functions defined at module level in a real source file,
not for closures or for functions taking other compiled functions as arguments. So a kernel that is
generic over the model, the reconstructor and the boundary conditions is produced by writing a small
module per combination: the template's text with its binding block replaced by imports of the chosen
module-level functions. The file name carries a hash of the template and of every bound module's
source, so editing the physics invalidates the cache.

Cache folder: ``$CONSLAW_CACHE_DIR``, else ``$XDG_CACHE_HOME/conslaw/kernels``, else
``~/.cache/conslaw/kernels``; a temporary folder if none of these is writable.
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import inspect
import os
import sys
import tempfile
from collections.abc import Callable, Mapping
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from conslaw.model import Model

_TEMPLATE_DIR = Path(__file__).resolve().parent
_BEGIN = "# --- bindings ---"
_END = "# --- end bindings ---"
#: In a template that continues another (``base``), the end of the header that only serves
#: linting (its imports of the base template's names); the generated module drops it.
_HEADER_END = "# --- end of continuation header ---"
_loaded: dict[str, ModuleType] = {}


def cache_dir() -> Path:
    """Folder of the generated kernel modules (created if needed)."""
    candidates = []
    if os.environ.get("CONSLAW_CACHE_DIR"):
        candidates.append(Path(os.environ["CONSLAW_CACHE_DIR"]))
    xdg = os.environ.get("XDG_CACHE_HOME")
    candidates.append((Path(xdg) if xdg else Path.home() / ".cache") / "conslaw" / "kernels")
    candidates.append(Path(tempfile.gettempdir()) / f"conslaw-kernels-{os.getuid()}")
    for folder in candidates:
        try:
            folder.mkdir(parents=True, exist_ok=True)
            probe = folder / f".probe-{os.getpid()}"
            probe.write_text("")
            probe.unlink()
            return folder
        except OSError:
            continue
    raise OSError("no writable folder for conslaw's compiled kernels; set CONSLAW_CACHE_DIR")


def import_path(function: Callable[..., Any]) -> tuple[str, str]:
    """``(module, name)`` under which a compiled function can be imported.

    Raises
    ------
    TypeError
        If the function is not reachable as a module-level attribute (a closure, a lambda, ...).
    """
    python_function = getattr(function, "py_func", function)
    module_name = python_function.__module__
    name = python_function.__name__
    module = importlib.import_module(module_name)
    if getattr(module, name, None) is not function:
        raise TypeError(
            f"{module_name}.{name} must be a module-level numba function (njit) to be compiled "
            "into a kernel"
        )
    return module_name, name


def _module_source(module_name: str) -> str:
    """The source of the module and of every module beside it in its package folder, so that
    editing a helper the bound function imports from a sibling module also recompiles."""
    module = importlib.import_module(module_name)
    try:
        path = Path(inspect.getfile(module))
    except (OSError, TypeError):
        return module_name
    return "\0".join(
        f"{sibling.name}\0{sibling.read_text()}" for sibling in sorted(path.parent.glob("*.py"))
    )


def generate(
    template: str,
    bindings: Mapping[str, Callable[..., Any]],
    constants: Mapping[str, bool | int | float] | None = None,
    base: str | None = None,
) -> ModuleType:
    """Write (once) and import the module of ``template`` with ``bindings`` in place.

    Parameters
    ----------
    template : str
        File name of a template in this package (e.g. ``"nt_template.py"``).
    bindings : mapping
        Placeholder name -> module-level compiled function.
    constants : mapping, optional
        Module-level constants (compile-time for numba: dead branches are removed).
    base : str, optional
        A template that ``template`` continues: the generated module is the base template
        followed by ``template`` after its continuation header (so the continuation calls the
        base's functions, compiled with the same bindings and constants, in the same module).
    """
    constants = dict(constants or {})
    text = (_TEMPLATE_DIR / template).read_text()
    if base is not None:
        _, continuation = text.split(_HEADER_END, 1)
        text = (_TEMPLATE_DIR / base).read_text() + continuation
    head, rest = text.split(_BEGIN, 1)
    _, tail = rest.split(_END, 1)
    lines = [_BEGIN]
    sources = [text]
    modules = set()
    for placeholder, function in sorted(bindings.items()):
        module_name, name = import_path(function)
        lines.append(f"from {module_name} import {name} as {placeholder}")
        modules.add(module_name)
    # The kernels package itself (templates, scratch arrays) is part of every kernel's source.
    modules.add(__name__)
    sources.extend(_module_source(module_name) for module_name in sorted(modules))
    for key, value in sorted(constants.items()):
        lines.append(f"{key} = {value!r}")
    lines.append(_END)
    body = head + "\n".join(lines) + tail
    digest = hashlib.sha256("\0".join([body, *sources]).encode()).hexdigest()[:20]
    module_name = f"conslaw_kernel_{Path(template).stem}_{digest}"
    if module_name in _loaded:
        return _loaded[module_name]
    path = cache_dir() / f"{module_name}.py"
    if not path.exists() or path.read_text() != body:
        temporary = path.with_suffix(f".{os.getpid()}.tmp")
        temporary.write_text(body)
        os.replace(temporary, path)
    spec = importlib.util.spec_from_file_location(module_name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    # numba's cache re-imports the module by name when it loads a cached function.
    sys.modules[module_name] = module
    spec.loader.exec_module(module)
    _loaded[module_name] = module
    return module


def _model_bindings(model_class: type[Model]) -> dict[str, Callable[..., Any]]:
    from conslaw.kernels import placeholders
    from conslaw.kernels.defaults import finite_point

    return {
        "_flux_point": model_class.flux_point,
        "_jacobian_point": model_class.jacobian_point,
        "_max_speed_point": model_class.max_speed_point,
        "_source_point": model_class.source_point or placeholders.source_point,
        "_admissible_point": model_class.admissible_point or finite_point,
    }


def _model_constants(model: Model) -> dict[str, bool | int | float]:
    uses = model.capabilities()
    bed, bed_slope = model.surface_aux if uses["surface"] and model.surface_aux else (-1, -1)
    depth = model.depth_index
    return {
        "NV": int(model.n_vars),
        "NAUX": int(model.n_aux),
        "NPARAMS": len(model.param_vector()),
        "HAS_SOURCE": uses["source"],
        "HAS_BALANCED_SOURCE": uses["balanced_source"],
        "HAS_CORRECTION": uses["correction"],
        "HAS_RESISTANCE": uses["resistance"],
        "HAS_DYNAMIC_COEFFICIENTS": uses["dynamic_coefficients"],
        "HAS_INTERFACE_COEFFICIENTS": uses["interface_coefficients"],
        "HAS_REST_COEFFICIENTS": uses["rest_coefficients"],
        "DEPTH": -1 if depth is None else int(depth),
        "MOMENTUM": -1 if model.momentum_index is None else int(model.momentum_index),
        "DRY_DEPTH": float(model.dry_depth()),
        "SURFACE_BED": int(bed),
        "SURFACE_SLOPE": int(bed_slope),
    }


def model_array_kernels(model: Model) -> ModuleType:
    """Compiled loops over the cells of a model's pointwise functions (its array methods)."""
    from conslaw.kernels import placeholders

    model_class = type(model)
    bindings = _model_bindings(model_class)
    bindings["_balanced_source_point"] = (
        model_class.balanced_source_point or placeholders.balanced_source_point
    )
    bindings["_correct_point"] = model_class.correct_point or placeholders.correct_point
    bindings["_resistance_point"] = model_class.resistance_point or placeholders.resistance_point
    bindings["_coefficients_point"] = (
        model_class.coefficients_point or placeholders.coefficients_point
    )
    bindings["_interface_coefficients_point"] = (
        model_class.interface_coefficients_point or placeholders.interface_coefficients_point
    )
    bindings["_rest_coefficients_point"] = (
        model_class.rest_coefficients_point or placeholders.rest_coefficients_point
    )
    constants = _model_constants(model)
    keys = (
        "NV", "NAUX", "HAS_SOURCE", "HAS_BALANCED_SOURCE", "HAS_CORRECTION", "HAS_RESISTANCE",
        "HAS_DYNAMIC_COEFFICIENTS", "HAS_INTERFACE_COEFFICIENTS", "HAS_REST_COEFFICIENTS",
    )  # fmt: skip
    return generate("arrays_template.py", bindings, {key: constants[key] for key in keys})


def _scheme_bindings(
    model: Model, slope_point: Callable[..., Any], fill_left: Any, fill_right: Any
) -> dict[str, Callable[..., Any]]:
    """Bindings of the NT template: the model's point functions, the reconstructor's slope and
    the boundary conditions."""
    from conslaw.kernels import placeholders

    model_class = type(model)
    bindings = _model_bindings(model_class)
    bindings.update(
        {
            "_slope_point": slope_point,
            "_fill_left": fill_left,
            "_fill_right": fill_right,
            "_balanced_source_point": model_class.balanced_source_point
            or placeholders.balanced_source_point,
            "_correct_point": model_class.correct_point or placeholders.correct_point,
            "_resistance_point": model_class.resistance_point or placeholders.resistance_point,
            "_coefficients_point": model_class.coefficients_point
            or placeholders.coefficients_point,
            "_interface_coefficients_point": model_class.interface_coefficients_point
            or placeholders.interface_coefficients_point,
            "_rest_coefficients_point": model_class.rest_coefficients_point
            or placeholders.rest_coefficients_point,
        }
    )
    return bindings


def nt_kernels(
    model: Model, slope_point: Callable[..., Any], fill_left: Any, fill_right: Any
) -> ModuleType:
    """The fused Nessyahu–Tadmor kernels for one model, reconstructor and boundary pair."""
    bindings = _scheme_bindings(model, slope_point, fill_left, fill_right)
    return generate("nt_template.py", bindings, _model_constants(model))


def ft_kernels(
    model: Model, slope_point: Callable[..., Any], fill_left: Any, fill_right: Any
) -> ModuleType:
    """The compiled front-tracking kernels: the NT kernels continued by ``ft_template.py``."""
    bindings = _scheme_bindings(model, slope_point, fill_left, fill_right)
    return generate("ft_template.py", bindings, _model_constants(model), base="nt_template.py")
