"""The compiled Nessyahu–Tadmor kernels of one model, reconstructor and boundary pair, generated
from ``kernel_template.py`` by the kernel toolkit (docs/design.md, "Compiled kernels")."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any

from conslaw.kernelgen import generate
from conslaw.model import Model

TEMPLATE = Path(__file__).with_name("kernel_template.py")


def scheme_bindings(
    model: Model, slope_point: Callable[..., Any], fill_left: Any, fill_right: Any
) -> dict[str, Callable[..., Any]]:
    """Bindings of the template: the model's pointwise functions, the reconstructor's slope
    and the boundary conditions' ghost fills."""
    bindings = model.kernel_bindings()
    bindings.update(
        {"_slope_point": slope_point, "_fill_left": fill_left, "_fill_right": fill_right}
    )
    return bindings


def nt_kernels(
    model: Model, slope_point: Callable[..., Any], fill_left: Any, fill_right: Any
) -> ModuleType:
    """The fused Nessyahu–Tadmor kernels for one model, reconstructor and boundary pair."""
    bindings = scheme_bindings(model, slope_point, fill_left, fill_right)
    return generate(TEMPLATE, bindings, model.kernel_constants())
