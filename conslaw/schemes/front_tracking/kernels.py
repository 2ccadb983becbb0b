"""The compiled front-tracking kernels: ``kernel_template.py`` with its import of the NT template
redirected to the NT kernel module of the same model, boundary pair and (plugin) reconstructor,
whose per-cell functions it calls (docs/design.md, "Compiled kernels")."""

from __future__ import annotations

from pathlib import Path
from types import ModuleType
from typing import Any

from conslaw.kernelgen import generate
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor
from conslaw.schemes.nessyahu_tadmor.kernels import nt_kernels

TEMPLATE = Path(__file__).with_name("kernel_template.py")
NT_TEMPLATE_MODULE = "conslaw.schemes.nessyahu_tadmor.kernel_template"


def ft_kernels(
    model: Model, reconstructor: Reconstructor, fill_left: Any, fill_right: Any
) -> ModuleType:
    """The front-tracking kernels for one model and boundary pair (every built-in
    reconstructor shares them)."""
    nt = nt_kernels(model, reconstructor, fill_left, fill_right)
    return generate(TEMPLATE, {}, imports={NT_TEMPLATE_MODULE: nt})
