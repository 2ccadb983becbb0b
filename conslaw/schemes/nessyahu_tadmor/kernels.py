"""The compiled Nessyahu–Tadmor kernels of one model and boundary pair (and a plugin's
reconstructor, if the scene uses one), generated from ``kernel_template.py`` by the kernel
toolkit (docs/design.md, "Compiled kernels")."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw import pointwise
from conslaw.kernelgen import generate
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor

TEMPLATE = Path(__file__).with_name("kernel_template.py")


def scheme_bindings(
    model: Model, reconstructor: Reconstructor, fill_left: Any, fill_right: Any
) -> dict[str, Callable[..., Any]]:
    """Bindings of the template: the model's pointwise functions, a plugin reconstructor's
    slope (the built-in ones are chosen at run time) and the boundary conditions' ghost fills."""
    bindings = model.kernel_bindings()
    custom = reconstructor.code is None
    bindings.update(
        {
            "_slope_point": reconstructor.slope_point if custom else pointwise.slope_point,
            "_fill_left": fill_left,
            "_fill_right": fill_right,
        }
    )
    return bindings


def scheme_constants(model: Model, reconstructor: Reconstructor) -> dict[str, Any]:
    """Compile-time constants of the template: the model's, and whether the reconstructor is a
    plugin's (``CUSTOM_SLOPES``)."""
    constants = model.kernel_constants()
    constants["CUSTOM_SLOPES"] = reconstructor.code is None
    return constants


def kernel_parameters(model: Model, reconstructor: Reconstructor) -> NDArray[np.float64]:
    """The kernels' parameter vector: the model's parameters, then the reconstructor's code
    (``SLOPE_CODE`` of the template; -1 for a plugin's)."""
    code = -1.0 if reconstructor.code is None else float(reconstructor.code)
    return np.append(model.param_vector(), code)


def nt_kernels(
    model: Model, reconstructor: Reconstructor, fill_left: Any, fill_right: Any
) -> ModuleType:
    """The fused Nessyahu–Tadmor kernels for one model and boundary pair: every built-in
    reconstructor shares them, a plugin's reconstructor has its own."""
    bindings = scheme_bindings(model, reconstructor, fill_left, fill_right)
    return generate(TEMPLATE, bindings, scheme_constants(model, reconstructor))
