"""The compiled Jiang–Tadmor kernels of one model (and a plugin's reconstructor, if the scene
uses one), generated from ``kernel_template.py`` by the kernel toolkit (docs/design.md,
"Compiled kernels")."""

from __future__ import annotations

from pathlib import Path
from types import ModuleType

from conslaw import pointwise
from conslaw.kernelgen import generate
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor

TEMPLATE = Path(__file__).with_name("kernel_template.py")
BED_TEMPLATE = Path(__file__).with_name("bed_kernel_template.py")
FLAT_TEMPLATE_MODULE = "conslaw.schemes.jiang_tadmor.kernel_template"


def jt_kernels(model: Model, reconstructor: Reconstructor) -> ModuleType:
    """The Jiang–Tadmor kernels of a 2D model: its x and y pointwise functions, its correction
    and depth rows; every built-in reconstructor shares them (its code is a run-time parameter),
    a plugin's reconstructor has its own.

    Parameters
    ----------
    model : Model
        A 2D model without a bed (:func:`~conslaw.schemes.jiang_tadmor.scheme.compiles`).
    reconstructor : Reconstructor
        A built-in reconstructor (``code`` set) or a plugin's (``code`` None: its
        ``slope_point`` is compiled in, ``CUSTOM_SLOPES``).

    Returns
    -------
    ModuleType
        The generated module of ``kernel_template.py`` (written and compiled once, then loaded
        from the kernel cache).
    """
    model_class = type(model)
    custom = reconstructor.code is None
    bindings = {
        "_flux_point": model_class.flux_point,
        "_jacobian_point": model_class.jacobian_point,
        "_max_speed_point": model_class.max_speed_point,
        "_flux_y_point": model_class.flux_y_point,
        "_jacobian_y_point": model_class.jacobian_y_point,
        "_max_speed_y_point": model_class.max_speed_y_point,
        "_correct_point": model_class.correct_point or pointwise.unbound,
        "_slope_point": reconstructor.slope_point if custom else pointwise.slope_point,
        "_source_point": model_class.source_point or pointwise.unbound,
        "_resistance_point": model_class.resistance_point or pointwise.unbound,
    }
    uses = model.capabilities()
    constants = {
        "NV": int(model.n_vars),
        "NAUX": int(model.n_aux),
        "NPARAMS": len(model.param_vector()),
        "HAS_CORRECTION": bool(uses["correction"]),
        "DEPTH": -1 if model.depth_index is None else int(model.depth_index),
        "MOMENTUM": -1 if model.momentum_index is None else int(model.momentum_index),
        "MOMENTUM_Y": -1 if model.momentum_y_index is None else int(model.momentum_y_index),
        "DRY_DEPTH": float(model.dry_depth()),
        "CUSTOM_SLOPES": custom,
        "HAS_RESISTANCE": bool(uses["resistance"]),
        "SURFACE_METRIC": model.tangent_slope_rows is not None,
        "SKIP_EMPTY": bool(model.empty_stays_empty) and model.depth_index is not None,
    }
    return generate(TEMPLATE, bindings, constants)  # type: ignore[arg-type]


def jt_bed_kernels(model: Model, reconstructor: Reconstructor) -> ModuleType:
    """The Jiang–Tadmor kernels of a 2D depth-averaged model over a bed: ``bed_kernel_template.py``
    with its import of the flat template redirected to :func:`jt_kernels` of the same model and
    reconstructor, whose per-row functions it calls, and the model's source, well-balanced
    sources and coefficient rows bound.

    Parameters
    ----------
    model : Model
        A 2D model with a bed (:func:`~conslaw.schemes.jiang_tadmor.scheme.compiles`).
    reconstructor : Reconstructor
        As for :func:`jt_kernels`.

    Returns
    -------
    ModuleType
        The generated module of ``bed_kernel_template.py``.
    """
    model_class = type(model)
    assert model.surface_aux is not None and model.surface_aux_y is not None
    bindings = {
        "_source_point": model_class.source_point,
        "_balanced_source_point": model_class.balanced_source_point,
        "_balanced_source_y_point": model_class.balanced_source_y_point,
    }
    constants = {
        "SURFACE_BED": int(model.surface_aux[0]),
        "SURFACE_X": int(model.surface_aux[1]),
        "SURFACE_Y": int(model.surface_aux_y[0]),
        "SURFACE_TWIST": int(model.surface_aux_y[1]),
    }
    flat = jt_kernels(model, reconstructor)
    return generate(
        BED_TEMPLATE,
        bindings,  # type: ignore[arg-type]
        constants,
        imports={FLAT_TEMPLATE_MODULE: flat},
    )


FIELD_TEMPLATE = Path(__file__).with_name("field_kernel_template.py")


def varying_rows(model: Model) -> tuple[int, int] | None:
    """``(first, count)`` of the coefficient rows ``model`` sets per cell and per staggered cell
    (``varying_aux_rows``), which the field kernel takes as one run of rows; None if they are
    not consecutive."""
    rows = tuple(int(row) for row in model.varying_aux_rows)
    if not rows:
        return 0, 0
    if rows != tuple(range(rows[0], rows[0] + len(rows))):
        return None
    return rows[0], len(rows)


def jt_field_kernels(model: Model, reconstructor: Reconstructor) -> ModuleType:
    """The Jiang–Tadmor kernels of a 2D depth-averaged model with coefficients at every point, a
    source and optionally a resistance: ``field_kernel_template.py`` with its import of the flat
    template redirected to :func:`jt_kernels` of the same model and reconstructor (which binds
    the source and the resistance), and the model's 2D coefficient hooks bound.

    Parameters
    ----------
    model : Model
        A 2D model the field kernel covers (:func:`~conslaw.schemes.jiang_tadmor.scheme.
        on_field`).
    reconstructor : Reconstructor
        As for :func:`jt_kernels`.

    Returns
    -------
    ModuleType
        The generated module of ``field_kernel_template.py``.
    """
    model_class = type(model)
    uses = model.capabilities()
    rows = varying_rows(model)
    assert rows is not None
    bindings = {
        "_coefficients_2d_point": model_class.coefficients_2d_point or pointwise.unbound,
        "_corner_coefficients_point": model_class.corner_coefficients_point or pointwise.unbound,
    }
    tangent = model.tangent_slope_rows
    constants = {
        "HAS_DYNAMIC": bool(uses["dynamic_coefficients"]),
        "HAS_INTERFACE": bool(uses["interface_coefficients"]),
        "VARYING_FIRST": rows[0],
        "VARYING_COUNT": rows[1],
        "TANGENT_X": -1 if tangent is None else int(tangent[0]),
        "TANGENT_Y": -1 if tangent is None else int(tangent[1]),
    }
    flat = jt_kernels(model, reconstructor)
    return generate(FIELD_TEMPLATE, bindings, constants, imports={FLAT_TEMPLATE_MODULE: flat})
