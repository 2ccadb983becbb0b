"""Property-based tests of the models and of the Nessyahu–Tadmor scheme, over the registries.

Every test is parametrised over the model and reconstructor names of ``conslaw.registry`` (the
boundary kind, where it matters, is drawn per example), so a newly registered plugin is covered
without editing this file. Each property runs 200 Hypothesis examples per parametrisation. Grids
are small (8..64 cells) and runs short (a few step pairs): the properties are local, and the
suite has to stay fast. Models enter a property only if it holds for them (see the lists below).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st
from numpy.typing import NDArray
from strategies import (
    MODEL_NAMES,
    PARAMETER_FAMILIES,
    RECONSTRUCTOR_NAMES,
    X_MAX,
    X_MIN,
    admissible_states,
    cell_aux,
    cfl_numbers,
    constant_states,
    model_instance,
    model_with,
    wide_states,
)

from conslaw import registry
from conslaw.grid import Grid
from conslaw.model import Model
from conslaw.schemes.base import BoundarySpec
from conslaw.schemes.nessyahu_tadmor.constants import FILM
from conslaw.schemes.nessyahu_tadmor.scheme import NessyahuTadmor
from conslaw.state import State

Array = NDArray[np.float64]

EXAMPLES = settings(max_examples=200, deadline=None)

#: Boundary kinds drawn by the advance properties (both mirror symmetric, neither adds mass).
OPEN_OR_PERIODIC = ("periodic", "outflow")
#: Boundary kinds drawn by the compiled-versus-reference comparison (each needs its own ghosts).
STEP_BOUNDARIES = ("periodic", "outflow", "wall")

#: Parameter sets tried for mirror symmetry besides each model's defaults and the examples of its
#: parameter families: level (zeta = 0) Savage–Hutter, with one and with two earth-pressure
#: coefficients. Only those that pass :func:`has_no_preferred_direction` are used.
MIRROR_CANDIDATES: dict[str, list[dict[str, object]]] = {
    "savage-hutter": [{"zeta": 0.0}, {"zeta": 0.0, "phi": 35.0, "delta": 25.0}],
}


def _uses(name: str, term: str) -> bool:
    """Whether the default instance of model ``name`` uses ``term`` (see ``Model.capabilities``)."""
    return bool(model_instance(name).capabilities()[term])


def _homogeneous_coefficients(name: str) -> bool:
    """Whether the model's coefficients are the same in every cell of a test grid."""
    aux = cell_aux(model_instance(name), 16)
    return bool(np.all(aux == aux[:, :1]))


#: Models whose cell sums the scheme conserves exactly: no source of either kind and no pointwise
#: correction (a dry-cell or stopping correction changes the sums by design).
CONSERVATIVE_MODELS = [
    name
    for name in MODEL_NAMES
    if not any(_uses(name, term) for term in ("source", "balanced_source", "correction"))
]
#: Models for which constant states are steady: no source, no surface reconstruction, the same
#: coefficients everywhere (a correction is allowed if it leaves the constant state alone).
HOMOGENEOUS_MODELS = [
    name
    for name in MODEL_NAMES
    if not any(_uses(name, term) for term in ("source", "balanced_source", "surface"))
    and _homogeneous_coefficients(name)
]

#: Latest end time of a run (the domain has length 1 and the speeds are O(1..10)).
MAX_END_TIME = 1.0
#: Smallest depth of the states whose Jacobian is tested (dry states may have none).
WET_DEPTH = 0.1
#: Largest Courant number of the TVD property; see ``test_minmod_burgers_advance_is_tvd``.
TVD_CFL = 0.2

_SCHEMES: dict[tuple[object, ...], NessyahuTadmor] = {}


# ---------------------------------------------------------------------- helpers
def scheme_for(
    model_name: str,
    reconstructor: str,
    n_cells: int,
    boundary: str = "periodic",
    cfl: float = 0.45,
    parameters: tuple[tuple[str, object], ...] = (),
) -> NessyahuTadmor:
    """A cached NT scheme on ``[X_MIN, X_MAX]`` with ``boundary`` on both sides (the model with
    ``parameters``, its defaults if empty)."""
    key = (model_name, reconstructor, n_cells, boundary, cfl, parameters)
    if key not in _SCHEMES:
        side = BoundarySpec(registry.boundaries.get(boundary))
        _SCHEMES[key] = NessyahuTadmor(
            model_with(model_name, dict(parameters)),
            registry.reconstructors.get(reconstructor),
            Grid(X_MIN, X_MAX, n_cells),
            side,
            side,
            cfl=cfl,
        )
    return _SCHEMES[key]


def primary_state(scheme: NessyahuTadmor, q: Array) -> State:
    """The state ``q`` at ``t = 0`` on the primary cells of ``scheme``'s grid."""
    return State(0.0, scheme.grid.centres(), q, 0.0)


def step_size(scheme: NessyahuTadmor, state: State, cfl: float | None = None) -> float:
    """``cfl dx / a_max``, or ``dx`` for a state at rest (any step is stable then)."""
    dt = scheme.stable_dt(state, cfl)
    return scheme.grid.dx if np.isinf(dt) else dt


def end_time(scheme: NessyahuTadmor, state: State, pairs: float) -> float:
    """A time about ``pairs`` step pairs ahead (a fractional part shortens the last pair).

    At most ``MAX_END_TIME``: for data near zero (speeds like 1e-300) ``cfl dx / a_max`` is
    astronomically large, and ``dt / dx`` would overflow.
    """
    return min(2.0 * pairs * step_size(scheme, state), MAX_END_TIME)


def periodic_total_variation(q: Array) -> float:
    """``sum_j |q_{j+1} - q_j|`` with the wrap-around difference (the TV of periodic data)."""
    return float(np.sum(np.abs(np.roll(q, -1, axis=-1) - q)))


def mirror(q: Array, signs: Array) -> Array:
    """The mirror image ``x -> X_MIN + X_MAX - x`` of cell data, each variable times its sign."""
    return np.ascontiguousarray(q[:, ::-1] * signs[:, None])


def mirror_symmetric_scheme(scheme: NessyahuTadmor) -> NessyahuTadmor:
    """A copy of ``scheme`` (outflow on both sides) whose coefficients are the mirror images of
    themselves to the last bit (asserting that this changes them by round-off only).

    Each padded coefficient row ``a`` becomes ``(a + s a[::-1]) / 2`` (``s`` the model's
    ``aux_reflect_signs``), and the left quarter point becomes the mirror of the right one. The
    change is round-off of the coefficients; it isolates the scheme's own arithmetic from the
    round-off in which a model evaluates its bed at ``x`` and at the mirror image of ``x``.
    """
    model = scheme.model
    copy = NessyahuTadmor(
        model, scheme.reconstructor, scheme.grid, scheme.left, scheme.right, scheme.cfl
    )
    odd = np.array(model.aux_reflect_signs or (1.0,) * model.n_aux, dtype=np.float64)[:, None]
    for offset, rows in copy._aux.items():
        centre, left, right = rows
        centre = 0.5 * (centre + odd * centre[:, ::-1])
        left = 0.5 * (left + odd * right[:, ::-1])
        right = odd * left[:, ::-1]
        # Only round-off may change: a coefficient placed on the wrong side (a ghost, a quarter
        # point, a staggered cell) must still fail the property, not be averaged away.
        for before, after in zip(rows, (centre, left, right), strict=True):
            size = np.abs(before).max(axis=1, keepdims=True)
            assert np.all(np.abs(after - before) <= 1e-13 * size), (
                f"coefficients not mirror symmetric beyond round-off (offset {offset}): "
                f"{np.abs(after - before).max():.3e}"
            )
        copy._aux[offset] = tuple(np.ascontiguousarray(a) for a in (centre, left, right))
    return copy


def assert_close(actual: Array, expected: Array, atol: float, what: str) -> None:
    """``|actual - expected| <= atol`` everywhere, with the worst cell in the message."""
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    error = np.abs(actual - expected)
    worst = np.unravel_index(int(np.argmax(error)), error.shape) if error.size else ()
    assert np.all(error <= atol), (
        f"{what}: max error {error.max():.3e} > {atol:.3e} at {worst}: "
        f"{actual[worst]!r} vs {expected[worst]!r}"
    )


def scale(q: Array) -> float:
    """``max |q|`` (0 for all-zero data)."""
    return float(np.max(np.abs(q))) if q.size else 0.0


# ---------------------------------------------------------------------- (a) conservation
def capped_rarefactions(depth: Array, velocity: Array, film_margin: float) -> tuple[Array, bool]:
    """Velocities of a periodic shallow-water row whose neighbours open no near-vacuum.

    Two neighbours ``l, r`` that draw apart make two rarefactions with the middle depth
    ``h_*``, ``(g h_*)^(1/2) = (c_l + c_r) / 2 - (u_r - u_l) / 4`` (Toro 2001, "Shock-Capturing
    Methods for Free-Surface Shallow Flows", section 5.3; ``c = (g h)^(1/2)``). Each rise
    ``u_{i+1} - u_i`` is capped so that ``h_* >= film_margin * FILM * max(depth)``: no cell
    thins to a film (docs/design.md, "Films"). Returns the capped velocities and whether the
    pair across the periodic seam also meets the cap."""
    gravity = 9.81
    speed = np.sqrt(gravity * depth)
    least = np.sqrt(gravity * film_margin * FILM * depth.max())
    rise = 2.0 * (speed + np.roll(speed, -1)) - 4.0 * least
    capped = velocity.copy()
    for i in range(len(capped) - 1):
        capped[i + 1] = min(capped[i + 1], capped[i] + rise[i])
    return capped, bool(capped[0] - capped[-1] <= rise[-1])


@pytest.mark.parametrize("reconstructor", ["mc", "superbee", "weno5"])
@settings(max_examples=60, deadline=None)
@given(
    depth=st.lists(st.floats(0.5, 10.0), min_size=8, max_size=48),
    velocity=st.lists(st.floats(-5.0, 5.0), min_size=8, max_size=48),
    pairs=st.floats(0.5, 3.0),
)
def test_wet_shallow_water_conserves_momentum(
    reconstructor: str, depth: list[float], velocity: list[float], pairs: float
) -> None:
    """Shallow water on a flat periodic bed with every depth in [0.5, 10] (no dry cell, so the
    dry-cell correction never acts; no film, a cell thinner than ``FILM`` = 1e-2 of the deepest,
    at the start, and no pair of neighbours drawing apart fast enough to thin one to a film,
    :func:`capped_rarefactions`) conserves mass and momentum to round-off, Froude numbers up to
    about 7 and colliding shocks included. Guards the velocity bound of films, which is not
    conservative and must act on films only: it once acted in wet cells and took 5 % of the
    momentum of a Froude-10 Riemann problem. (Near a vacuum a rarefaction makes films whose
    computed velocities leave the Riemann invariants around them, and there the bound changes the
    momentum: docs/design.md, "Films".)"""
    n = min(len(depth), len(velocity))
    h = np.array(depth[:n])
    u, seam_ok = capped_rarefactions(h, np.array(velocity[:n]), film_margin=2.0)
    assume(seam_ok)
    q = np.vstack([h, h * u])
    scheme = scheme_for("shallow-water", reconstructor, n, "periodic")
    state = primary_state(scheme, q)
    result = scheme.advance(state, end_time(scheme, state, pairs))
    change = np.abs(result.state.q.sum(axis=1) - q.sum(axis=1))
    tolerance = 4e-15 * max(result.steps, 1) * np.abs(result.state.q).sum(axis=1).clip(min=1.0)
    assert np.all(change <= tolerance), f"totals changed by {change} (tolerance {tolerance})"


def test_rarefaction_cap_keeps_the_vacuum_example_out() -> None:
    """The example that once lost momentum (a 0.125 m cell at -4 m/s next to one at rest, the
    deepest 3 m: a middle depth of 1.2e-3 m, a film) is capped: after capping, every rise keeps
    the middle depth at twice the film depth or more."""
    h = np.array([0.125, 0.125, 0.125, 3.0, 3.0, 1.0, 1.0, 1.0])
    u = np.array([-4.0, 0.0, 1.0, 3.0, 0.0, 0.0, 0.0, 2.0])
    capped, _ = capped_rarefactions(h, u, film_margin=2.0)
    c = np.sqrt(9.81 * h)
    middle = ((c[:-1] + c[1:]) / 2 - np.maximum(np.diff(capped), 0.0) / 4) ** 2 / 9.81
    assert capped[1] < u[1]
    assert np.all(middle >= 2.0 * FILM * h.max() * (1 - 1e-12))


@pytest.mark.parametrize("reconstructor", RECONSTRUCTOR_NAMES)
@pytest.mark.parametrize("model_name", CONSERVATIVE_MODELS)
@EXAMPLES
@given(data=st.data(), pairs=st.floats(0.5, 3.0))
def test_periodic_advance_conserves_every_variable(
    model_name: str, reconstructor: str, data: st.DataObject, pairs: float
) -> None:
    """On a periodic grid the cell sums of every conserved variable are constant in time.

    The NT update (eq. 10) is in conservation form: each staggered average is the mean of the two
    underlying halves minus a flux difference, the slope terms ``(w'_L - w'_R)/8`` telescope, and
    with periodic ghosts every flux enters once with each sign. So ``sum_j q_j dx`` is exact up to
    round-off, for every reconstructor and every model without source or pointwise correction
    (those change the sums by design and are left out). Tolerance ``1e-13 sum_j |q_j|`` per
    variable.
    """
    q = data.draw(admissible_states(model_name), label="q")
    scheme = scheme_for(model_name, reconstructor, q.shape[1])
    state = primary_state(scheme, q)
    result = scheme.advance(state, end_time(scheme, state, pairs))
    assert result.steps >= 2
    before, after = q.sum(axis=1), result.state.q.sum(axis=1)
    tolerance = 1e-13 * np.abs(q).sum(axis=1)
    assert np.all(np.abs(after - before) <= tolerance), (
        f"sums changed by {after - before} (tolerance {tolerance}) after {result.steps} steps"
    )


# ---------------------------------------------------------------------- (b) constant states
@pytest.mark.parametrize("reconstructor", RECONSTRUCTOR_NAMES)
@pytest.mark.parametrize("model_name", HOMOGENEOUS_MODELS)
@EXAMPLES
@given(data=st.data(), boundary=st.sampled_from(OPEN_OR_PERIODIC), pairs=st.floats(0.5, 3.0))
def test_advance_preserves_constant_states_exactly(
    model_name: str, reconstructor: str, data: st.DataObject, boundary: str, pairs: float
) -> None:
    """A constant state is a steady solution and the scheme keeps it bit for bit.

    With equal cell averages every slope is exactly zero (each limiter and WENO slope is zero for
    equal arguments), the predictor returns the state, both fluxes are the same number, and the
    update is ``(c + c)/2 = c``, exact in binary floating point; periodic and outflow ghosts copy
    the constant. Any stray term (an asymmetric stencil, an uninitialised ghost) breaks this.
    Models with a source or position-dependent coefficients have no constant steady states in
    general and are left out; with a pointwise correction, only constant states that the
    correction leaves unchanged are steady.
    """
    model = model_instance(model_name)
    q = data.draw(constant_states(model_name), label="q")
    scheme = scheme_for(model_name, reconstructor, q.shape[1], boundary)
    state = primary_state(scheme, q)
    t_end = end_time(scheme, state, pairs)
    if model.capabilities()["correction"]:
        assume(np.array_equal(model.correct(q, cell_aux(model, q.shape[1]), t_end), q))
    result = scheme.advance(state, t_end)
    assert np.array_equal(result.state.q, q), (
        f"constant {q[:, 0]} changed: max error {np.max(np.abs(result.state.q - q)):.3e}"
    )


# ---------------------------------------------------------------------- (c) TVD
@EXAMPLES
@given(
    q=admissible_states("burgers"),
    cfl=cfl_numbers(0.01, TVD_CFL),
    pairs=st.floats(0.5, 4.0),
)
def test_minmod_burgers_advance_is_tvd(q: Array, cfl: float, pairs: float) -> None:
    """Burgers + minmod slopes on a periodic grid never increases the total variation.

    Nessyahu & Tadmor (1990, J. Comput. Phys. 87:408-463) prove the scalar scheme with limited
    slopes TVD under a CFL restriction strictly below the stability limit 1/2, the constant
    depending on the limiter. For this implementation (slopes ``u'_j = minmod(Du_{j-1/2},
    Du_{j+1/2})``, predictor ``p_j = u_j - (dt/2dx) a(u_j) u'_j``) a sufficient bound follows
    directly. Each staggered value is ``u_{j+1/2} = u_j + Du_{j+1/2} (1/2 - r/8 - mu)`` with
    ``r = (u'_{j+1} - u'_j)/Du_{j+1/2}`` in ``[-1, 1]`` (both slopes are ``s Du_{j+1/2}`` with
    ``s`` in ``[0, 1]``) and ``mu = dt/dx (f(p_{j+1}) - f(p_j))/Du_{j+1/2}``. If
    ``|r/8 + mu| <= 1/2`` every new value lies between its two neighbours and each new difference
    is a sum of nonnegative fractions of old ones, so the TV cannot grow. For Burgers, with
    Courant number ``c = dt max|u| / dx``: ``|a(u_{j+1}) s_{j+1} - a(u_j) s_j| <= 2 max|u|``
    gives ``|p_{j+1} - p_j| <= (1 + c) |Du_{j+1/2}|``, and ``|u'_j| <= 2 max|u|`` gives
    ``|p_j| <= (1 + c) max|u|``, so ``|mu| <= c (1 + c)^2``. Hence ``1/8 + c (1 + c)^2 <= 1/2``,
    i.e. ``c <= 0.2428``, suffices; the same bound keeps ``max|u|`` from growing, so the second
    half step of a pair meets it too. Drawn here: ``cfl`` in (0.01, 0.2]. Tolerance: round-off
    only, ``1e-12 (1 + TV_0)``.
    """
    scheme = scheme_for("burgers", "minmod", q.shape[1], "periodic", cfl)
    state = primary_state(scheme, q)
    result = scheme.advance(state, end_time(scheme, state, pairs))
    tv0 = periodic_total_variation(q)
    tv1 = periodic_total_variation(result.state.q)
    assert tv1 <= tv0 + 1e-12 * (1.0 + tv0), (
        f"TV grew from {tv0!r} to {tv1!r} (cfl={cfl}, {result.steps} steps)"
    )


@EXAMPLES
@given(q=admissible_states("burgers"), cfl=cfl_numbers(0.01, TVD_CFL))
def test_minmod_burgers_each_step_is_tvd_and_bounded(q: Array, cfl: float) -> None:
    """Every single staggered step (both cell families) is TVD and keeps values within bounds.

    The argument of :func:`test_minmod_burgers_advance_is_tvd` is per step: under the same CFL
    bound each new value lies between the two old values it straddles, so the TV does not grow
    and no new extrema appear, on the primary and on the staggered family alike. Three step pairs
    with one ``dt`` per pair, as :meth:`NessyahuTadmor.advance` takes them.
    """
    scheme = scheme_for("burgers", "minmod", q.shape[1], "periodic", cfl)
    state = primary_state(scheme, q)
    lo, hi = float(q.min()), float(q.max())
    slack = 1e-12 * (1.0 + scale(q))
    for pair in range(3):
        dt = step_size(scheme, state)
        for half in range(2):
            new = scheme.step(state, dt)
            tv0, tv1 = periodic_total_variation(state.q), periodic_total_variation(new.q)
            where = f"pair {pair}, half step {half}, cfl={cfl}"
            assert tv1 <= tv0 + 1e-12 * (1.0 + tv0), f"TV grew {tv0!r} -> {tv1!r} ({where})"
            assert new.q.min() >= lo - slack and new.q.max() <= hi + slack, (
                f"new extremum [{new.q.min()!r}, {new.q.max()!r}] outside [{lo!r}, {hi!r}] "
                f"({where})"
            )
            state = new


#: Scalar models without a source: staggered Lax–Friedrichs is monotone for them (below).
SCALAR_MODELS = [
    name
    for name in MODEL_NAMES
    if model_instance(name).n_vars == 1
    and not any(_uses(name, term) for term in ("source", "balanced_source", "resistance"))
]


@pytest.mark.parametrize("model_name", SCALAR_MODELS)
@EXAMPLES
@given(data=st.data(), cfl=cfl_numbers(0.01, 0.49), pairs=st.floats(0.5, 4.0))
def test_first_order_scheme_is_monotone_for_scalar_models(
    model_name: str, data: st.DataObject, cfl: float, pairs: float
) -> None:
    """With zero slopes (``reconstructor = "none"``) every scalar model's run is TVD and keeps
    its values within the initial range, at every CFL number below 1/2.

    The step is then staggered Lax–Friedrichs, ``u_{j+1/2} = (u_j + u_{j+1})/2 - dt/dx (f(u_{j+1})
    - f(u_j))``, nondecreasing in both arguments when ``dt/dx max|f'| <= 1/2`` (the scheme's CFL
    condition, eq. 17): a monotone conservative scheme, hence TVD and bounded by the data
    (Harten, Hyman & Lax 1976; Crandall & Majda 1980). Unlike the minmod property, no bound
    stricter than the stability limit is needed. Tolerance: round-off, ``1e-12 (1 + TV_0)``.
    """
    q = data.draw(admissible_states(model_name), label="q")
    scheme = scheme_for(model_name, "none", q.shape[1], "periodic", cfl)
    state = primary_state(scheme, q)
    result = scheme.advance(state, end_time(scheme, state, pairs))
    tv0 = periodic_total_variation(q)
    tv1 = periodic_total_variation(result.state.q)
    assert tv1 <= tv0 + 1e-12 * (1.0 + tv0), f"TV grew {tv0!r} -> {tv1!r} (cfl={cfl})"
    slack = 1e-12 * (1.0 + scale(q))
    assert result.state.q.min() >= q.min() - slack and result.state.q.max() <= q.max() + slack


def coulomb_slab_velocity(u0: float, t: float, zeta: float, delta: float) -> tuple[float, bool]:
    """Velocity of a uniform slab on a plane after time ``t`` (angles in radians), and whether
    it passed through rest and was pulled back the other way by gravity (a reversal).

    ``du/dt = sin zeta - sgn(u) tan delta cos zeta`` with the set-valued ``sgn(0)`` of Coulomb
    friction (docs/design.md, "Savage–Hutter specifics"): at rest it stays at rest while ``|tan
    zeta| <= tan delta``.
    """
    drive, friction = math.sin(zeta), math.tan(delta) * math.cos(zeta)
    if u0 == 0.0:
        if abs(drive) <= friction:
            return 0.0, False
        return (drive - math.copysign(friction, drive)) * t, False
    acceleration = drive - math.copysign(friction, u0)
    stop = -u0 / acceleration if acceleration * u0 < 0.0 else math.inf
    if t <= stop:
        return u0 + acceleration * t, False
    later, _ = coulomb_slab_velocity(0.0, t - stop, zeta, delta)
    return later, later != 0.0


@pytest.mark.parametrize("reconstructor", RECONSTRUCTOR_NAMES)
@settings(max_examples=60, deadline=None)
@given(
    zeta=st.floats(-89.0, 89.0),
    delta=st.floats(1.0, 60.0),
    phi_above_delta=st.just(0.0) | st.floats(0.0, 20.0),
    epsilon=st.floats(0.01, 10.0),
    depth=st.floats(1e-3, 1e3),
    u0=st.just(0.0) | st.floats(1e-6, 10.0) | st.floats(-10.0, -1e-6),  # h u0 stays normal
    t_end=st.floats(0.0, 3.0),
    n=st.integers(8, 32),
)
def test_uniform_slab_follows_the_coulomb_law(
    reconstructor: str,
    zeta: float,
    delta: float,
    phi_above_delta: float,
    epsilon: float,
    depth: float,
    u0: float,
    t_end: float,
    n: int,
) -> None:
    """A uniform slab on a plane (periodic) stays uniform bit for bit, and its velocity follows
    ``du/dt = sin zeta - sgn(u) tan delta cos zeta`` with the Coulomb stopping rule.

    Uniform data have zero slopes and equal fluxes, so each step is the ODE step
    ``m <- resist(m + dt h sin zeta, dt h tan delta cos zeta)`` in every cell: exact while the
    direction of motion is kept, and exact through a stop that lasts (friction holds the slab,
    never reverses it). If gravity pulls the slab back through rest (``|tan zeta| > tan delta``),
    the step in which it stops is off by at most ``dt h (|sin zeta| + tan delta cos zeta)``
    (``dt <= dx / (2 c)`` by the CFL condition). Round-off: ``4 eps`` per step of the velocity's
    scale (and 4 subnormal spacings per step for subnormal velocities). Any phi from delta to
    delta + 20 degrees: the earth pressure, whichever of K_act and K_pass the velocity slope
    selects, cannot act on a layer of uniform depth.
    """
    phi = delta + phi_above_delta
    parameters = (("chute", "plane"), ("delta", delta), ("epsilon", epsilon), ("phi", phi),
                  ("zeta", zeta))  # fmt: skip
    scheme = scheme_for("savage-hutter", reconstructor, n, "periodic", parameters=parameters)
    q = np.vstack([np.full(n, depth), np.full(n, depth * u0)])
    result = scheme.advance(primary_state(scheme, q), t_end)
    final = result.state.q
    assert np.all(final == final[:, :1]), "the uniform slab became non-uniform"
    assert final[0, 0] == depth
    z, d = math.radians(zeta), math.radians(delta)
    exact, reversed_ = coulomb_slab_velocity(u0, t_end, z, d)
    drive, friction = abs(math.sin(z)), math.tan(d) * math.cos(z)
    speed_scale = abs(u0) + (drive + friction) * t_end
    # Relative round-off, and below the normal range the absolute spacing of subnormals: of the
    # momentum, which the velocity divides by the depth (a t_end of 2e-313 gave a velocity 1
    # subnormal off, 5e-324, against a relative tolerance of 0; at depth 0.125, 10 subnormals).
    tolerance = (
        4
        * max(result.steps, 1)
        * (
            np.finfo(float).eps * speed_scale
            + np.finfo(float).smallest_subnormal * max(1.0, 1.0 / depth)
        )
    )
    if reversed_:
        aux = scheme.model.aux(scheme.grid.centres()[:1], scheme.grid.dx)
        wave = scheme.model.max_wave_speed(np.array([[depth], [0.0]]), aux)[0]
        tolerance += scheme.grid.dx / (2 * wave) * (drive + friction)
    u = final[1, 0] / depth
    assert abs(u - exact) <= tolerance, f"u = {u!r}, exact {exact!r} after {result.steps} steps"
    knife_edge = abs(drive - friction) <= 1e-12 * (drive + friction)
    if not reversed_ and exact == 0.0 and not knife_edge:
        # At rest means exactly at rest (unless gravity and friction balance to the last bits,
        # where the rounding of sin, tan and cos decides).
        assert final[1, 0] == 0.0


# ---------------------------------------------------------------------- (d), (e) model physics
@pytest.mark.parametrize("model_name", MODEL_NAMES)
@EXAMPLES
@given(data=st.data())
def test_flux_jacobian_matches_finite_differences(model_name: str, data: st.DataObject) -> None:
    """``flux_jacobian`` is the derivative of ``flux``: compare with central differences.

    The predictor (eq. 15) uses ``A(q) q'``; a Jacobian that is not ``df/dq`` makes the scheme
    first order or unstable while every conservation test still passes. The step in variable k is
    ``eps^(1/3) max(|q_k|, 1)``, whose truncation plus round-off error (~1e-10 for these value
    ranges) is far below the tolerance ``1e-6 (1 + max|A|)`` per cell.
    """
    model = model_instance(model_name)
    q = data.draw(admissible_states(model_name, min_depth=WET_DEPTH), label="q")
    aux = cell_aux(model, q.shape[1])
    jacobian = model.flux_jacobian(q, aux)
    assert jacobian.shape == (model.n_vars, model.n_vars, q.shape[1])
    numerical = np.empty_like(jacobian)
    for k in range(model.n_vars):
        h = np.cbrt(np.finfo(np.float64).eps) * np.maximum(np.abs(q[k]), 1.0)
        plus, minus = q.copy(), q.copy()
        plus[k] += h
        minus[k] -= h
        assume(model.is_admissible(plus, aux).all() and model.is_admissible(minus, aux).all())
        numerical[:, k, :] = (model.flux(plus, aux) - model.flux(minus, aux)) / (plus[k] - minus[k])
    tolerance = 1e-6 * (1.0 + np.abs(jacobian).max(axis=(0, 1)))
    error = np.abs(numerical - jacobian).max(axis=(0, 1))
    cell = int(np.argmax(error / tolerance))
    assert np.all(error <= tolerance), (
        f"cell {cell}, q={q[:, cell]}: analytic {jacobian[:, :, cell]} vs "
        f"finite differences {numerical[:, :, cell]}"
    )


def _eigenvalue_moduli(jacobian: Array) -> Array:
    """``|eigenvalues|`` of every cell's Jacobian, shape ``(n, n_vars)``."""
    return np.abs(np.linalg.eigvals(np.moveaxis(jacobian, 2, 0)))


@pytest.mark.parametrize("model_name", MODEL_NAMES)
@EXAMPLES
@given(data=st.data())
def test_max_wave_speed_bounds_jacobian_eigenvalues(model_name: str, data: st.DataObject) -> None:
    """``max_wave_speed`` is an upper bound of ``|eigenvalue|`` of the flux Jacobian per cell.

    The CFL condition (eqs. 17-18) is only a stability condition if ``a_max`` bounds every
    characteristic speed; an underestimate lets the step exceed Courant number 1/2.
    """
    model = model_instance(model_name)
    q = data.draw(admissible_states(model_name, min_depth=WET_DEPTH), label="q")
    aux = cell_aux(model, q.shape[1])
    moduli = _eigenvalue_moduli(model.flux_jacobian(q, aux)).max(axis=1)
    speed = model.max_wave_speed(q, aux)
    assert np.all(np.isfinite(speed)) and np.all(speed >= 0.0)
    bad = moduli > speed * (1.0 + 1e-12)
    assert not bad.any(), (
        f"cells {np.nonzero(bad)[0]}: |eigenvalue| {moduli[bad]} > max_wave_speed {speed[bad]}"
    )


@pytest.mark.parametrize("model_name", MODEL_NAMES)
@EXAMPLES
@given(data=st.data())
def test_max_wave_speed_is_attained_by_an_eigenvalue(model_name: str, data: st.DataObject) -> None:
    """``max_wave_speed`` is the largest ``|eigenvalue|``, not merely a bound (model contract).

    :class:`conslaw.model.Model` documents ``max_speed_point`` as ``max |eigenvalue of df/dq|``;
    an overestimate is safe but shrinks every time step and adds diffusion. Tolerance 1e-9
    relative to the Jacobian's size (eigenvalues of a non-normal matrix are less accurate).
    """
    model = model_instance(model_name)
    q = data.draw(admissible_states(model_name, min_depth=WET_DEPTH), label="q")
    aux = cell_aux(model, q.shape[1])
    jacobian = model.flux_jacobian(q, aux)
    moduli = _eigenvalue_moduli(jacobian).max(axis=1)
    speed = model.max_wave_speed(q, aux)
    size = np.maximum(speed, np.abs(jacobian).max(axis=(0, 1)))
    bad = moduli < speed - 1e-9 * size
    assert not bad.any(), (
        f"cells {np.nonzero(bad)[0]}: max |eigenvalue| {moduli[bad]} < max_wave_speed {speed[bad]}"
    )


# ---------------------------------------------------------------------- (f) compiled vs reference
@pytest.mark.parametrize("reconstructor", RECONSTRUCTOR_NAMES)
@pytest.mark.parametrize("model_name", MODEL_NAMES)
@EXAMPLES
@given(
    data=st.data(),
    boundary=st.sampled_from(STEP_BOUNDARIES),
    cfl=cfl_numbers(0.01, 0.49, exclude_low=False),
)
def test_compiled_step_matches_reference_step(
    model_name: str, reconstructor: str, data: st.DataObject, boundary: str, cfl: float
) -> None:
    """The fused compiled step and the independent numpy ``reference_step`` agree to round-off.

    Both implement eqs. (10)-(15) from the same pointwise physics but with separate ghost-cell,
    stencil and staggering code; agreement on both cell families (offset 0 -> 1/2 -> 0, which on
    bounded domains also changes the cell count n <-> n + 1) checks the compiled index
    arithmetic. Tolerance ``1e-12 max|q|``, absolute.
    """
    q = data.draw(admissible_states(model_name), label="q")
    scheme = scheme_for(model_name, reconstructor, q.shape[1], boundary)
    state = primary_state(scheme, q)
    for family in ("offset 0 -> 1/2", "offset 1/2 -> 0"):
        dt = step_size(scheme, state, cfl)
        compiled = scheme.step(state, dt)
        reference = scheme.reference_step(state, dt)
        assert compiled.offset == reference.offset != state.offset
        assert compiled.t == reference.t == state.t + dt
        np.testing.assert_array_equal(compiled.x, reference.x)
        assert_close(compiled.q, reference.q, 1e-12 * scale(state.q), family)
        state = compiled


# ---------------------------------------------------------------------- (g) mirror symmetry
@pytest.mark.parametrize("reconstructor", RECONSTRUCTOR_NAMES)
@EXAMPLES
@given(w=admissible_states("burgers", st.integers(5, 64)))
def test_slopes_are_mirror_symmetric(reconstructor: str, w: Array) -> None:
    """Every reconstructor's slope commutes with the reflection ``w_j -> -w_{-j}``.

    A slope is ``dx`` times a derivative; the mirrored data ``-w(-x)`` has the derivative
    ``+w'(-x)``, so ``slope(-w_{j+2}, ..., -w_{j-2}) = slope(w_{j-2}, ..., w_{j+2})`` (the
    limiter is odd in its data and odd under reversal of the stencil). A limiter or WENO weight
    that favours one side breaks the reflection symmetry of the scheme.
    """
    recon = registry.reconstructors.get(reconstructor)
    plain = recon.slopes(w)
    mirrored = recon.slopes(-w[:, ::-1])[:, ::-1]
    assert_close(mirrored, plain, 1e-13 * scale(w), f"slopes of {reconstructor}")


def has_no_preferred_direction(model: Model) -> bool:
    """Whether ``x -> X_MIN + X_MAX - x`` maps solutions of ``model`` to solutions: its
    coefficients on the test grid are their own mirror image (``aux_reflect_signs``), and for
    sample states the flux is odd, ``f(Rq) = -R f(q)``, the source even, ``s(Rq) = R s(q)``, and
    the resistance the same (``R`` the ``reflect_signs``). Checked numerically, so a new model or
    parameter set is classified without a list."""
    grid = Grid(X_MIN, X_MAX, 16)
    aux = np.asarray(model.aux(grid.centres(), grid.dx), dtype=np.float64)
    odd = np.asarray(model.aux_reflect_signs or (1.0,) * model.n_aux)[:, None]
    mirrored_aux = np.ascontiguousarray(aux[:, ::-1] * odd)
    if not np.allclose(mirrored_aux, aux, rtol=1e-12, atol=1e-14):
        return False
    rng = np.random.default_rng(11)
    q = rng.uniform(-2.0, 2.0, (model.n_vars, 16))
    if model.depth_index is not None:
        q[model.depth_index] = rng.uniform(0.1, 2.0, 16)
    signs = np.asarray(model.reflect_signs, dtype=np.float64)[:, None]
    reflected = np.ascontiguousarray(q * signs)
    reflected_aux = np.ascontiguousarray(aux * odd)  # the same points, seen in the mirror
    checks = [
        (model.flux(reflected, reflected_aux), -signs * model.flux(q, aux)),
        (model.source(reflected, reflected_aux), signs * model.source(q, aux)),
        (model.resistance(reflected, reflected_aux), model.resistance(q, aux)),
    ]
    return all(np.allclose(a, b, rtol=1e-12, atol=1e-14) for a, b in checks)


def _mirror_cases() -> list[tuple[str, tuple[tuple[str, object], ...]]]:
    cases = []
    for name in MODEL_NAMES:
        candidates = [{}, *(f.example for f in PARAMETER_FAMILIES[name].values())]
        candidates += MIRROR_CANDIDATES.get(name, [])
        for parameters in candidates:
            key = tuple(sorted(parameters.items()))
            if (name, key) not in cases and has_no_preferred_direction(
                model_with(name, parameters)
            ):
                cases.append((name, key))
    return cases


#: ``(model, parameters)`` without a preferred direction (see :func:`has_no_preferred_direction`).
MIRROR_CASES = _mirror_cases()


def test_preferred_direction_is_detected() -> None:
    """The classifier of the mirror property: Burgers, flat shallow water and level
    Savage–Hutter have no preferred direction; Savage–Hutter on a 40-degree slope and shallow water
    over an off-centre bump have one."""
    assert has_no_preferred_direction(model_with("burgers", {}))
    assert has_no_preferred_direction(model_with("shallow-water", {}))
    assert has_no_preferred_direction(model_with("savage-hutter", {"zeta": 0.0}))
    assert not has_no_preferred_direction(model_with("savage-hutter", {}))
    assert not has_no_preferred_direction(
        model_with("shallow-water", {"bump_height": 0.5, "bump_centre": 0.3, "bump_width": 0.2})
    )


@pytest.mark.parametrize("reconstructor", RECONSTRUCTOR_NAMES)
@pytest.mark.parametrize(
    ("model_name", "parameters"),
    MIRROR_CASES,
    ids=[f"{name}{dict(p) or ''}".replace(" ", "") for name, p in MIRROR_CASES],
)
@settings(max_examples=100, deadline=None)
@given(data=st.data(), pairs=st.floats(0.5, 3.0))
def test_mirrored_data_gives_the_mirrored_solution(
    model_name: str,
    parameters: tuple[tuple[str, object], ...],
    reconstructor: str,
    data: st.DataObject,
    pairs: float,
) -> None:
    """Advancing the mirror image of the data gives the mirror image of the solution.

    For Burgers ``u(x, t)`` a solution implies ``-u(-x, t)`` is one, for shallow water on a flat
    bed ``(h, hu)(x, t)`` implies ``(h, -hu)(-x, t)`` (the ``reflect_signs``); the same for a bed
    and a chute that are their own mirror images. Periodic and outflow conditions are themselves
    mirror symmetric, the time steps depend on the wave speeds only, and the update (eq. 10) is
    symmetric under exchanging the two straddled cells when the slopes are mirror symmetric
    (:func:`test_slopes_are_mirror_symmetric`). So the scheme must commute with the reflection; a
    one-sided stencil offset, a ghost cell filled from the wrong side or a friction or
    earth-pressure rule that favours a direction breaks this. Coefficients that vary in x (a
    bump) are only drawn with outflow boundaries: on a periodic domain a bed that is not itself
    periodic has a seam, whose straddling cell sees the bed on one side only, so the periodic
    problem has no mirror symmetry.

    The scheme's coefficients are made mirror symmetric to the last bit
    (:func:`mirror_symmetric_scheme`): the bed a model computes at ``x`` and at its mirror image
    differs by round-off (quadrature nodes summed in the other order), and the flow amplifies
    that without bound near a wet-dry front (CI found 1e-16 grown to 5.5e-13 in 8 steps of a 1e-6
    film beside a 1 m column on a bump, 4e-12 in 54 steps of a wetting front). With symmetric
    coefficients the two runs agree to round-off of the state, ``1e-13 max|q|``. The data are
    the extreme states of :func:`strategies.wide_states` (Froude numbers up to 100).
    """
    model = model_with(model_name, dict(parameters))
    aux = cell_aux(model, 16)
    kinds = OPEN_OR_PERIODIC if np.all(aux == aux[:, :1]) else ("outflow",)
    boundary = data.draw(st.sampled_from(kinds), label="boundary")
    signs = np.asarray(model.reflect_signs, dtype=np.float64)
    q = data.draw(wide_states(model), label="q")
    scheme = scheme_for(model_name, reconstructor, q.shape[1], boundary, parameters=parameters)
    if boundary == "outflow":
        scheme = mirror_symmetric_scheme(scheme)
    state = primary_state(scheme, q)
    t_end = end_time(scheme, state, pairs)
    result = scheme.advance(state, t_end)
    mirrored = scheme.advance(primary_state(scheme, mirror(q, signs)), t_end)
    assert mirrored.steps == result.steps
    assert_close(
        mirrored.state.q,
        mirror(result.state.q, signs),
        1e-13 * scale(q),
        f"mirror symmetry of {reconstructor}/{boundary}",
    )


@pytest.mark.parametrize(
    ("name", "family"), [(m, f) for m in MODEL_NAMES for f in PARAMETER_FAMILIES[m]]
)
@settings(max_examples=50, deadline=None)
@given(data=st.data())
def test_a_model_that_says_its_coefficients_are_uniform_gives_the_same_everywhere(
    name: str, family: str, data: st.DataObject
) -> None:
    """``Model.uniform_aux()`` lets front tracking ask for the coefficients once (at a margin
    anywhere): when a model says so, ``aux(x, dx)`` is the same column, bit for bit, at any
    positions and cell widths."""
    model = model_with(name, data.draw(PARAMETER_FAMILIES[name][family].strategy, "parameters"))
    if not model.uniform_aux():
        return
    # The centres of the test grid (where the parameter families put their beds and bends),
    # and positions drawn around it.
    drawn = data.draw(st.lists(st.floats(2 * X_MIN - X_MAX, 2 * X_MAX - X_MIN), max_size=16), "x")
    x = np.concatenate([Grid(X_MIN, X_MAX, 16).centres(), drawn])
    dx = data.draw(st.floats(1e-6, 10.0), "dx")
    first = model.aux(x[:1], 1.0)
    np.testing.assert_array_equal(model.aux(x, dx), np.repeat(first, x.size, axis=1))
