"""Hypothesis strategies over the plugin registries: states, parameters, chutes, bodies, scenes.

Everything here is driven by :mod:`conslaw.registry`, so a newly registered model or reconstructor
is drawn (or parametrised over) without editing the tests.

- :func:`admissible_states`: values inside a per-model box (``VALUE_BOXES``; by default
  ``[-10, 10]`` for every variable and ``[0, 10]`` for the model's ``depth_index`` row);
  inadmissible cells of a model with a depth are brought to rest (dry cells carry no momentum),
  and the result is filtered with ``Model.is_admissible``. A new model whose admissible set is much
  smaller than this box should add a box here; until it does, Hypothesis reports a
  ``filter_too_much`` health-check failure instead of silently testing nothing.
- :func:`wide_states`: the extreme end of the admissible set: depths exactly 0 (dry) or anywhere
  in ``[1e-12, 1e3]`` on a log scale, velocities up to Froude number 100 or up to 10 in absolute
  value (Froude numbers of 1e7 in the thinnest layers); for a model without a depth, magnitudes
  from 1e-12 to 1e3 of either sign.
- :func:`model_parameters`: valid parameters per model (``PARAMETER_STRATEGIES``; a model without
  an entry is used with its defaults), e.g. Savage–Hutter on any plane chute from -89 to 89
  degrees; :func:`chute_parameters` and :func:`chute_tables` for the chute geometry.
- :func:`bodies`: one compact body of material with dry cells around it (front tracking).
- :func:`scene_tables`: raw scene tables that :func:`conslaw.config.validate` accepts.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cache

import numpy as np
from hypothesis import reject, strategies as st
from hypothesis.extra import numpy as hnp
from numpy.typing import NDArray

from conslaw import registry
from conslaw.grid import Grid
from conslaw.model import Model

Array = NDArray[np.float64]

#: Domain of every grid built by the property tests.
X_MIN, X_MAX = 0.0, 1.0
#: Smallest and largest number of cells drawn (small: the properties are local).
MIN_CELLS, MAX_CELLS = 8, 64
#: Value range of the default box, per conserved variable.
DEFAULT_BOX = (-10.0, 10.0)
#: Value range of the default box for a depth variable (``Model.depth_index``).
DEFAULT_DEPTH_BOX = (0.0, 10.0)
#: Per-model boxes ``((lo, hi) per variable)`` whose points are (almost all) admissible.
VALUE_BOXES: dict[str, tuple[tuple[float, float], ...]] = {
    "burgers": ((-10.0, 10.0),),
}

#: The one-dimensional models (the 2D ones have their own tests: test_jiang_tadmor*.py,
#: test_scene_2d.py).
MODEL_NAMES: list[str] = [
    name for name in registry.models.names() if registry.models.get(name).flux_y_point is None
]
RECONSTRUCTOR_NAMES: list[str] = registry.reconstructors.names()


@cache
def model_instance(name: str) -> Model:
    """The registered model ``name`` with its default parameters (one instance per name)."""
    return registry.models.get(name)()


def value_box(name: str, min_depth: float = 0.0) -> tuple[tuple[float, float], ...]:
    """Per-variable ``(lo, hi)`` ranges of the values drawn for model ``name``.

    ``min_depth`` raises the lower end of the depth variable's range (wet states only).
    """
    model = model_instance(name)
    box = list(VALUE_BOXES.get(name, (DEFAULT_BOX,) * model.n_vars))
    if name not in VALUE_BOXES and model.depth_index is not None:
        box[model.depth_index] = DEFAULT_DEPTH_BOX
    if model.depth_index is not None:
        lo, hi = box[model.depth_index]
        box[model.depth_index] = (max(lo, min_depth), hi)
    return tuple(box)


def cell_aux(model: Model, n: int) -> Array:
    """The model's coefficients of the primary cells of the test grid with ``n`` cells."""
    grid = Grid(X_MIN, X_MAX, n)
    return np.ascontiguousarray(model.aux(grid.centres(), grid.dx), dtype=np.float64)


def _admissible_columns(model: Model, q: Array) -> NDArray[np.bool_]:
    """Which columns of ``q`` are finite and admissible on the test grid."""
    ok = model.is_admissible(q, cell_aux(model, q.shape[1]))
    return np.asarray(ok & np.all(np.isfinite(q), axis=0))


def _dry_columns_at_rest(model: Model, q: Array) -> Array:
    """``q`` with every non-depth variable set to 0 in its inadmissible columns.

    For a model with a depth variable the usual reason for an inadmissible column is a dry (or
    nearly dry) cell that still carries momentum; such a cell at rest is the admissible dry state.
    """
    if model.depth_index is None:
        return q
    bad = ~_admissible_columns(model, q)
    if bad.any():
        q = q.copy()
        others = [v for v in range(model.n_vars) if v != model.depth_index]
        q[np.ix_(others, np.nonzero(bad)[0])] = 0.0
    return q


def grid_sizes(min_cells: int = MIN_CELLS, max_cells: int = MAX_CELLS) -> st.SearchStrategy[int]:
    """Numbers of grid cells."""
    return st.integers(min_value=min_cells, max_value=max_cells)


def _values(lo: float, hi: float) -> st.SearchStrategy[float]:
    """Finite floats in ``[lo, hi]``, zero included but no subnormals.

    Subnormal inputs carry fewer than 53 significant bits, so no relative round-off bound
    (``1e-13 * sum|q|`` and the like) can hold for them; they are a floating-point artefact, not
    a state of interest.
    """
    return st.floats(
        min_value=lo, max_value=hi, allow_nan=False, allow_infinity=False, allow_subnormal=False
    )


@st.composite
def admissible_states(
    draw: st.DrawFn,
    model_name: str,
    n_cells: st.SearchStrategy[int] | None = None,
    min_depth: float = 0.0,
) -> Array:
    """Arrays ``q`` of shape ``(n_vars, n)``, finite, admissible in every cell for ``model_name``.

    Hypothesis' array strategy repeats a "fill" value, so the draws mix rough data with long
    constant runs (Riemann-like data) and fully constant arrays. ``min_depth`` > 0 keeps a depth
    variable away from dry states (where a flux Jacobian may not exist).
    """
    model = model_instance(model_name)
    n = draw(n_cells if n_cells is not None else grid_sizes())
    rows = [
        draw(hnp.arrays(np.float64, (n,), elements=_values(lo, hi)))
        for lo, hi in value_box(model_name, min_depth)
    ]
    q = _dry_columns_at_rest(model, np.ascontiguousarray(np.stack(rows), dtype=np.float64))
    if not _admissible_columns(model, q).all():
        # Counted by Hypothesis' filter health check (the box does not fit the admissible set).
        reject()
    return q


@st.composite
def constant_states(
    draw: st.DrawFn,
    model_name: str,
    n_cells: st.SearchStrategy[int] | None = None,
) -> Array:
    """Spatially constant admissible arrays ``q`` (one admissible state repeated in every cell)."""
    model = model_instance(model_name)
    n = draw(n_cells if n_cells is not None else grid_sizes())
    column = np.array([draw(_values(lo, hi)) for lo, hi in value_box(model_name)], dtype=np.float64)
    q = _dry_columns_at_rest(model, np.ascontiguousarray(np.repeat(column[:, None], n, axis=1)))
    if not _admissible_columns(model, q).all():
        reject()
    return q


def model_names() -> st.SearchStrategy[str]:
    """Names of the registered models."""
    return st.sampled_from(MODEL_NAMES)


def reconstructor_names() -> st.SearchStrategy[str]:
    """Names of the registered reconstructors."""
    return st.sampled_from(RECONSTRUCTOR_NAMES)


def cfl_numbers(
    low: float = 0.01, high: float = 0.49, *, exclude_low: bool = True
) -> st.SearchStrategy[float]:
    """CFL numbers in ``(low, high]`` (``[low, high]`` with ``exclude_low=False``)."""
    return st.floats(
        min_value=low,
        max_value=high,
        exclude_min=exclude_low,
        allow_nan=False,
        allow_infinity=False,
    )


# ---------------------------------------------------------------------- extreme states
#: Depths drawn by :func:`wide_states`: exactly 0 or log-uniform in this range.
DEPTH_RANGE = (1e-12, 1e3)
#: Magnitudes drawn for the variables of a model without a depth.
MAGNITUDE_RANGE = (1e-12, 1e3)
#: Largest Froude number ``|u| / c`` (``c`` the model's wave speed at rest) drawn.
MAX_FROUDE = 100.0
#: Largest absolute velocity drawn (independently of the depth).
MAX_SPEED = 10.0


def log_uniform(lo: float, hi: float) -> st.SearchStrategy[float]:
    """Positive floats whose decimal exponent is uniform in ``[log10 lo, log10 hi]``."""
    return st.floats(np.log10(lo), np.log10(hi)).map(lambda e: float(10.0**e))


def signed_magnitudes(lo: float, hi: float) -> st.SearchStrategy[float]:
    """0, or ``+-m`` with ``m`` log-uniform in ``[lo, hi]``."""
    return st.one_of(
        st.just(0.0),
        st.tuples(st.sampled_from((-1.0, 1.0)), log_uniform(lo, hi)).map(
            lambda pair: pair[0] * pair[1]
        ),
    )


def depths() -> st.SearchStrategy[float]:
    """A dry cell (0) or a depth log-uniform in :data:`DEPTH_RANGE`."""
    return st.one_of(st.just(0.0), log_uniform(*DEPTH_RANGE))


Sampler = Callable[[np.random.Generator, int], Array]


def _cell_array(
    draw: st.DrawFn, n: int, elements: st.SearchStrategy[float], sample: Sampler
) -> Array:
    """``n`` cell values: up to 5 constant pieces (1 cell to all ``n``) drawn by Hypothesis,
    then, if drawn, a drawn fraction of the cells replaced by noise from ``sample`` (a numpy
    generator with a drawn seed, same distribution as ``elements``).

    Pieces give Riemann data, single-cell spikes and dips, and constant states, and they shrink
    well; the noise gives rough data at a fraction of the cost of drawing every cell through
    Hypothesis (which dominated the run time of the properties).
    """
    pieces = draw(st.integers(1, min(5, n)))
    cuts = sorted(draw(st.sets(st.integers(1, n - 1), max_size=pieces - 1))) if n > 1 else []
    values = [draw(elements) for _ in range(len(cuts) + 1)]
    out = np.repeat(np.asarray(values, dtype=np.float64), np.diff([0, *cuts, n]))
    if draw(st.booleans()):
        rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
        noisy = rng.random(n) < draw(st.sampled_from((0.1, 0.5, 1.0)))
        out = np.where(noisy, sample(rng, n), out)
    return out


def _log_uniform_sample(lo: float, hi: float) -> Sampler:
    return lambda rng, n: 10.0 ** rng.uniform(np.log10(lo), np.log10(hi), n)


def _depth_sample(rng: np.random.Generator, n: int) -> Array:
    dry = rng.random(n) < 0.2
    return np.where(dry, 0.0, _log_uniform_sample(*DEPTH_RANGE)(rng, n))


def _signed_sample(rng: np.random.Generator, n: int) -> Array:
    zero = rng.random(n) < 0.1
    sign = rng.choice((-1.0, 1.0), n)
    return np.where(zero, 0.0, sign * _log_uniform_sample(*MAGNITUDE_RANGE)(rng, n))


def _uniform_sample(lo: float, hi: float) -> Sampler:
    return lambda rng, n: rng.uniform(lo, hi, n)


def speeds_at_rest(model: Model, depth: Array, aux: Array) -> Array:
    """The model's wave speed of a layer of depth ``depth`` at rest, per cell (``sqrt(g h)``,
    ``sqrt(beta h)``, ...): the unit of the Froude number."""
    assert model.depth_index is not None
    q = np.zeros((model.n_vars, depth.size))
    q[model.depth_index] = depth
    return model.max_wave_speed(q, aux)


@st.composite
def wide_states(
    draw: st.DrawFn,
    model: Model,
    n_cells: st.SearchStrategy[int] | None = None,
    x_min: float = X_MIN,
    x_max: float = X_MAX,
) -> Array:
    """Admissible arrays ``q`` at the extremes: dry cells, depths from 1e-12 to 1e3 side by side,
    Froude numbers up to :data:`MAX_FROUDE` and velocities up to :data:`MAX_SPEED` in any layer.

    For a model with ``depth_index`` and ``momentum_index``, each cell's velocity is either
    ``Fr c(h)`` (``Fr`` in ``[-100, 100]``, ``c`` the wave speed at rest) or an absolute ``u`` in
    ``[-10, 10]``; the momentum is ``h u``, and 0 in dry cells (``h`` below the model's dry
    tolerance). Other variables (and every variable of a model without a depth) are 0 or
    ``+-m`` with ``m`` log-uniform in :data:`MAGNITUDE_RANGE`.
    """
    n = draw(n_cells if n_cells is not None else grid_sizes())
    magnitudes = signed_magnitudes(*MAGNITUDE_RANGE)
    rows = [_cell_array(draw, n, magnitudes, _signed_sample) for _ in model.variables]
    depth, momentum = model.depth_index, model.momentum_index
    if depth is not None:
        rows[depth] = _cell_array(draw, n, depths(), _depth_sample)
    if depth is not None and momentum is not None:
        grid = Grid(x_min, x_max, n)
        aux = np.ascontiguousarray(model.aux(grid.centres(), grid.dx), dtype=np.float64)
        froude = _cell_array(
            draw, n, st.floats(-MAX_FROUDE, MAX_FROUDE), _uniform_sample(-MAX_FROUDE, MAX_FROUDE)
        )
        absolute = _cell_array(
            draw, n, st.floats(-MAX_SPEED, MAX_SPEED), _uniform_sample(-MAX_SPEED, MAX_SPEED)
        )
        by_froude = (
            _cell_array(draw, n, st.sampled_from((0.0, 1.0)), _uniform_sample(0.0, 1.0)) > 0.5
        )
        velocity = np.where(by_froude, froude * speeds_at_rest(model, rows[depth], aux), absolute)
        rows[momentum] = rows[depth] * velocity
        rows[momentum][rows[depth] < model.dry_depth()] = 0.0
    q = np.ascontiguousarray(np.stack(rows), dtype=np.float64)
    grid = Grid(x_min, x_max, n)
    aux = np.ascontiguousarray(model.aux(grid.centres(), grid.dx), dtype=np.float64)
    if not (np.all(np.isfinite(q)) and model.is_admissible(q, aux).all()):
        reject()
    return q


# ---------------------------------------------------------------------- chutes
def chute_parameters(kind: str | None = None) -> st.SearchStrategy[dict[str, object]]:
    """Savage–Hutter chute parameters: a ``plane`` of any inclination in ``[-89, 89]`` degrees,
    or the ``paper`` chute (a plane, a linear change of angle, a run-out) with random angles and
    transition. A ``table`` chute needs a file: see :func:`chute_tables`."""
    angle = st.floats(-89.0, 89.0)
    plane = st.fixed_dictionaries({"chute": st.just("plane"), "zeta": angle})
    paper = st.tuples(angle, angle, st.floats(0.05, 0.6), st.floats(0.05, 0.4)).map(
        lambda t: {
            "chute": "paper", "zeta": t[0], "zeta_end": t[1],
            "transition_start": t[2], "transition_end": t[2] + t[3],
        }
    )  # fmt: skip
    return {"plane": plane, "paper": paper, None: st.one_of(plane, paper)}[kind]


@st.composite
def chute_tables(draw: st.DrawFn) -> tuple[str, Array, Array]:
    """A chute table ``(header, x, values)``: ``x,zeta`` with angles in ``(-89, 89)`` degrees or
    a terrain profile ``x,z``, 5 to 40 rows with strictly increasing ``x``."""
    n = draw(st.integers(5, 40))
    gaps = np.array(draw(st.lists(st.floats(0.05, 2.0), min_size=n - 1, max_size=n - 1)))
    x = np.concatenate([[draw(st.floats(-5.0, 5.0))], gaps]).cumsum()
    if draw(st.booleans()):
        values = np.array(draw(st.lists(st.floats(-89.0, 89.0), min_size=n, max_size=n)))
        return "x,zeta", x, values
    slopes = np.array(draw(st.lists(st.floats(-3.0, 3.0), min_size=n - 1, max_size=n - 1)))
    z = np.concatenate([[0.0], np.cumsum(slopes * gaps)])
    return "x,z", x, z


def chute_table_text(header: str, x: Array, values: Array) -> str:
    """The CSV text of a chute table (round-trip exact: ``repr`` of every float)."""
    rows = "\n".join(f"{a!r},{b!r}" for a, b in zip(x.tolist(), values.tolist(), strict=True))
    return f"{header}\n{rows}\n"


# ---------------------------------------------------------------------- model parameters
def _savage_hutter_coulomb() -> st.SearchStrategy[dict[str, object]]:
    """Savage–Hutter with ``delta = phi`` (one earth-pressure coefficient) on a plane chute of any
    inclination in ``[-89, 89]`` degrees or on the paper's curved chute."""
    plane = st.fixed_dictionaries({"chute": st.just("plane"), "zeta": st.floats(-89.0, 89.0)})
    return st.tuples(
        st.floats(1.0, 60.0), log_uniform(1e-2, 10.0), st.one_of(plane, chute_parameters("paper"))
    ).map(lambda t: {"phi": t[0], "delta": t[0], "epsilon": t[1], **t[2]})


def _savage_hutter_earth_pressure() -> st.SearchStrategy[dict[str, object]]:
    """Savage–Hutter with ``0 < delta < phi``: active and passive earth pressure differ, so the
    coefficient switches with the sign of the velocity slope (eq. 5). phi up to 85 degrees
    (``K_pass = 4 sec^2 phi`` grows without bound towards 90, and the time step with it). delta
    stays above 0: a frictionless bed has no resistance and so other compiled capabilities (its
    own family would compile a kernel per reconstructor); tests/test_earth_pressure.py covers
    delta = 0 < phi."""
    return st.tuples(
        st.floats(5.0, 85.0),
        st.floats(0.0, 0.999, exclude_min=True),
        log_uniform(1e-2, 10.0),
        st.floats(-60, 60),
    ).map(
        lambda t: {
            "phi": t[0], "delta": t[0] * t[1], "epsilon": t[2], "chute": "plane", "zeta": t[3],
        }
    )  # fmt: skip


def _shallow_water_flat() -> st.SearchStrategy[dict[str, object]]:
    """Shallow water on a flat bed, gravity log-uniform in ``[0.01, 100]``."""
    return log_uniform(1e-2, 1e2).map(lambda g: {"g": g})


def _shallow_water_bed() -> st.SearchStrategy[dict[str, object]]:
    """Shallow water over a Gaussian bump (or hollow) inside the unit test domain."""
    return st.tuples(
        log_uniform(1e-2, 1e2), st.floats(-2.0, 2.0).filter(lambda b: b != 0.0),
        st.floats(0.2, 0.8), st.floats(0.05, 0.5),
    ).map(
        lambda t: {"g": t[0], "bump_height": t[1], "bump_centre": t[2], "bump_width": t[3]}
    )  # fmt: skip


@dataclass(frozen=True)
class ParameterFamily:
    """Parameters of one model that share its compiled capabilities (``Model.capabilities``), so
    all their examples share one compiled kernel per reconstructor: a representative set
    (``example``, used to probe which schemes accept the family) and a strategy."""

    example: dict[str, object]
    strategy: st.SearchStrategy[dict[str, object]]


def _families() -> dict[str, dict[str, ParameterFamily]]:
    known = {
        "savage-hutter": {
            "coulomb": ParameterFamily({}, _savage_hutter_coulomb()),
            "earth-pressure": ParameterFamily(
                {"phi": 35.0, "delta": 25.0, "zeta": 30.0}, _savage_hutter_earth_pressure()
            ),
        },
        "shallow-water": {
            "flat": ParameterFamily({}, _shallow_water_flat()),
            "bed": ParameterFamily(
                {"bump_height": 0.5, "bump_centre": 0.5, "bump_width": 0.2}, _shallow_water_bed()
            ),
        },
    }
    return {
        name: known.get(name, {"default": ParameterFamily({}, st.just({}))}) for name in MODEL_NAMES
    }


#: Parameter families per model name (a model without an entry is tested with its defaults,
#: family ``"default"``).
PARAMETER_FAMILIES: dict[str, dict[str, ParameterFamily]] = _families()


def model_parameters(name: str, family: str) -> st.SearchStrategy[dict[str, object]]:
    """Valid parameter dictionaries of model ``name`` in parameter family ``family``."""
    return PARAMETER_FAMILIES[name][family].strategy


def model_families() -> list[tuple[str, str]]:
    """Every ``(model name, parameter family)`` pair (see :data:`PARAMETER_FAMILIES`)."""
    return [(name, family) for name in MODEL_NAMES for family in PARAMETER_FAMILIES[name]]


@cache
def _model_with(name: str, items: tuple[tuple[str, object], ...]) -> Model:
    return registry.models.get(name)(**dict(items))


def model_with(name: str, parameters: dict[str, object]) -> Model:
    """The model ``name`` with ``parameters`` (instances are shared between equal parameters)."""
    return _model_with(name, tuple(sorted(parameters.items())))


# ---------------------------------------------------------------------- bodies
#: Cells kept dry between a body and the boundary (the front-tracking clearance plus one).
BODY_CLEARANCE = 4


@st.composite
def bodies(draw: st.DrawFn, model: Model, n_cells: st.SearchStrategy[int] | None = None) -> Array:
    """One compact body on a dry bed: at least 5 wet cells (depth log-uniform in ``[1e-3, 10]``,
    the edge cells below half their inner neighbour's; velocity in ``[-2, 2]``), at least
    :data:`BODY_CLEARANCE` dry cells at rest on each side."""
    assert model.depth_index is not None and model.momentum_index is not None
    n = draw(n_cells if n_cells is not None else st.integers(16, 48))
    # At least 5 cells: with its two edge cells below half their neighbours, a 3-cell body is
    # shorter than 2 cells after a step or two, and front tracking stops at once.
    length = draw(st.integers(5, n - 2 * BODY_CLEARANCE))
    start = draw(st.integers(BODY_CLEARANCE, n - BODY_CLEARANCE - length))
    h = np.zeros(n)
    u = np.zeros(n)
    h[start : start + length] = _cell_array(
        draw, length, log_uniform(1e-3, 10.0), _log_uniform_sample(1e-3, 10.0)
    )
    u[start : start + length] = _cell_array(
        draw, length, st.floats(-2.0, 2.0), _uniform_sample(-2.0, 2.0)
    )
    # The edge cells hold less than half their inner neighbour's depth: a margin, not a step
    # (front tracking refuses a step edge, front_tracking.STEP_RATIO).
    for edge, inner in ((start, start + 1), (start + length - 1, start + length - 2)):
        h[edge] = min(h[edge], draw(st.floats(0.05, 0.45)) * h[inner])
    q = np.zeros((model.n_vars, n))
    q[model.depth_index] = h
    q[model.momentum_index] = h * u
    return q


# ---------------------------------------------------------------------- scenes
@st.composite
def scene_tables(draw: st.DrawFn, model_name: str | None = None) -> dict[str, object]:
    """Raw scene tables (as read from a TOML file) that :func:`conslaw.config.validate` accepts:
    any registered model with parameters from its families, reconstructor, CFL number, boundary
    pair, a small grid and a piecewise-constant initial condition of admissible states."""
    name = model_name if model_name is not None else draw(model_names())
    family = draw(st.sampled_from([f for m, f in model_families() if m == name]))
    parameters = draw(model_parameters(name, family))
    model = model_with(name, parameters)
    n = draw(st.integers(8, 40))
    x_min = draw(st.floats(-10.0, 10.0))
    length = draw(log_uniform(0.1, 100.0))
    fractions = draw(st.lists(st.floats(0.05, 0.95), min_size=0, max_size=3))
    # Distinct fractions can round to the same breakpoint far from the origin: keep distinct points.
    breakpoints = sorted({x_min + b * length for b in fractions})
    states = draw(admissible_states(name, st.just(MIN_CELLS)))[:, : len(breakpoints) + 1]
    boundary = draw(st.sampled_from(("periodic", "outflow", "wall")))
    side = draw(st.sampled_from(("outflow", "wall"))) if boundary != "periodic" else boundary
    scene: dict[str, object] = {
        "model": name,
        "parameters": parameters,
        "reconstructor": draw(reconstructor_names()),
        "cfl": draw(cfl_numbers(0.05, 0.49)),
        "n_cells": n,
        "x_min": x_min,
        "x_max": x_min + length,
        "t_end": draw(log_uniform(1e-3, 1.0)),
        "max_steps": draw(st.integers(1, 10**15)),
        "boundary": {"left": boundary, "right": side},
        "initial": {
            "kind": "piecewise-constant",
            "breakpoints": breakpoints,
            "states": [
                [float(v) for v in states[:, k]] if model.n_vars > 1 else float(states[0, k])
                for k in range(states.shape[1])
            ],
        },
        "output": {"plot": False},
    }
    return scene
