"""Every scheme on every model it accepts, on extreme data: finite, admissible, h >= 0, conserved.

The cases are built from the registries: every registered scheme plus front tracking
(``front-tracking``), every model parameter family of
``strategies.PARAMETER_FAMILIES`` (each family keeps one compiled kernel per reconstructor) and
every reconstructor. A scheme declares what it works with by refusing the rest at construction
with a ConfigError (``Scheme`` docstring); the cases are exactly the accepted combinations, and
``Scheme.uses_reconstructor`` / ``Scheme.needs_single_body`` say whether the reconstructor matters
and which data to draw. So a new model, reconstructor or scheme is covered without editing this
file. The default run narrows the compiled cases (one boundary kind per reconstructor, front
tracking with one reconstructor; see :func:`_parameters`); ``pytest -m slow`` runs them whole.

Data (``strategies.wide_states``): dry cells next to depths from 1e-12 to 1e3, Froude numbers up
to 100 and velocities up to 10 in any layer; for front tracking, one body on a dry bed
(``strategies.bodies``). Each example runs 1 to 4 step pairs, one pair per ``advance`` call, and
checks the state after every pair.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from hypothesis import event, given, settings, strategies as st
from numpy.typing import NDArray
from strategies import (
    X_MAX,
    X_MIN,
    bodies,
    model_families,
    model_parameters,
    model_with,
    wide_states,
)

from conslaw import registry
from conslaw.errors import ConfigError, SchemeBreakdownError
from conslaw.grid import Grid
from conslaw.model import Model
from conslaw.schemes.base import BoundarySpec, Scheme
from conslaw.schemes.front_tracking.scheme import FrontTrackingNT
from conslaw.schemes.nessyahu_tadmor.scheme import NessyahuTadmor
from conslaw.state import State

Array = NDArray[np.float64]

#: Every registered scheme (front tracking among them).
SCHEME_VARIANTS: dict[str, type[Scheme]] = {
    name: registry.schemes.get(name) for name in registry.schemes.names()
}
#: Boundary kinds drawn (inflow needs a state of its own and adds mass: not drawn).
BOUNDARY_KINDS = ("periodic", "wall", "outflow")
#: Front tracking in the default run: this reconstructor, outflow boundaries; every other
#: combination runs with ``-m slow``. Each combination is a compiled kernel of its own (about
#: 11 s to compile cold; 42 of them would add about 4 minutes to CI), and none of the
#: front-tracking logic depends on them: the margin cells are reconstructed by the
#: front-tracking code whatever the reconstructor (which only gives the inner slopes, tested on
#: every model by the NT cases), and the body keeps 3 cells away from the boundary, so the ghost
#: cells it could read are dry.
FRONT_TRACKING_DEFAULT = {"reconstructors": ("weno5",), "boundaries": ("outflow",)}
#: Examples per case. The cases per model (scheme x family x reconstructor) multiply this;
#: see the report of ``--hypothesis-show-statistics`` for the totals per model.
WIDE_EXAMPLES = settings(max_examples=50, deadline=None)
#: How a scheme that follows one body says it stopped at its documented limits: front tracking
#: when a margin comes within three cells of the boundary or the body shrinks below two cells;
#: the Lagrangian scheme when a margin leaves the domain, or when the mesh breaks (crossing nodes,
#: unbounded oscillations: a shock without artificial viscosity, design.md).
DOCUMENTED_LIMITS = (
    "margin reached",
    "shorter than 2 cells",
    "left the domain",
    "collapsed (node",
    "the oscillations grow without bound",
)
#: Round-off allowed in a conserved total per time step, relative to the total of |q|: the update
#: of one cell (eq. 10) is a handful of additions of terms no larger than the cell's neighbours
#: (the CFL condition bounds dt/dx times a flux by the values), each rounded to half an ulp.
ROUND_OFF_PER_STEP = 4e-15


def build_scheme(
    scheme_class: type[Scheme], model: Model, reconstructor: str, n_cells: int, boundary: str
) -> Scheme:
    """``scheme_class`` on ``[X_MIN, X_MAX]`` with ``n_cells`` cells and ``boundary`` both sides."""
    side = BoundarySpec(registry.boundaries.get(boundary))
    return scheme_class(
        model,
        registry.reconstructors.get(reconstructor),
        Grid(X_MIN, X_MAX, n_cells),
        side,
        side,
        0.45,
    )


@dataclass(frozen=True)
class Case:
    """One accepted (scheme, model, parameter family, reconstructor) and its boundary kinds."""

    scheme: str
    model: str
    family: str
    reconstructor: str
    boundaries: tuple[str, ...]

    def __str__(self) -> str:
        return f"{self.scheme}-{self.model}-{self.family}-{self.reconstructor}"


def _accepted_boundaries(scheme_class: type[Scheme], model: Model, reconstructor: str) -> tuple:
    accepted = []
    for kind in BOUNDARY_KINDS:
        try:
            build_scheme(scheme_class, model, reconstructor, 16, kind)
        except ConfigError:
            continue
        accepted.append(kind)
    return tuple(accepted)


def _cases() -> list[Case]:
    from strategies import PARAMETER_FAMILIES

    cases = []
    for scheme_name, scheme_class in SCHEME_VARIANTS.items():
        reconstructors = registry.reconstructors.names()
        if not scheme_class.uses_reconstructor:
            reconstructors = reconstructors[:1]
        for model_name, family in model_families():
            model = model_with(model_name, PARAMETER_FAMILIES[model_name][family].example)
            if scheme_class.needs_single_body and model.momentum_index is None:
                continue
            for reconstructor in reconstructors:
                accepted = _accepted_boundaries(scheme_class, model, reconstructor)
                if accepted:
                    cases.append(Case(scheme_name, model_name, family, reconstructor, accepted))
    return cases


CASES = _cases()


def _parameters(case: Case, index: int) -> object:
    """``case`` for the default run, narrowed, and the whole of it marked slow.

    Every (scheme, model family, reconstructor, boundary) combination is a compiled kernel of
    its own (about 10 s to compile cold), too many for the default run. There, the boundary
    kinds are spread over the reconstructors (``index``, the case's position among its model
    family's cases, picks the kind), so that every reconstructor and every boundary kind still
    meets every model family; front tracking is narrowed to :data:`FRONT_TRACKING_DEFAULT`. The
    whole case runs with ``-m slow``. Schemes without compiled kernels keep every case whole.
    """
    if not issubclass(SCHEME_VARIANTS[case.scheme], NessyahuTadmor):
        return [pytest.param(case, id=str(case))]  # numpy only: nothing to compile
    whole = pytest.param(case, id=f"{case}-all", marks=pytest.mark.slow)
    if case.scheme == "front-tracking":
        fast = FRONT_TRACKING_DEFAULT
        if case.reconstructor not in fast["reconstructors"]:
            return [whole]
        kept = tuple(b for b in case.boundaries if b in fast["boundaries"])
    else:
        kept = (case.boundaries[index % len(case.boundaries)],)
    if kept == case.boundaries:
        return [pytest.param(case, id=str(case))]
    narrowed = Case(case.scheme, case.model, case.family, case.reconstructor, kept)
    return [pytest.param(narrowed, id=str(case)), whole]


def _case_parameters() -> list[object]:
    positions: dict[tuple[str, str, str], int] = {}
    parameters: list[object] = []
    for case in CASES:
        family = (case.scheme, case.model, case.family)
        positions[family] = positions.get(family, -1) + 1
        parameters.extend(_parameters(case, positions[family]))
    return parameters


#: The parametrization of the property: narrowed cases in the default run, whole ones slow.
CASE_PARAMETERS = _case_parameters()


def wall_conserved_rows(model: Model) -> tuple[int, ...]:
    """Rows of the even variables (``reflect_signs`` +1): no flux through a wall.

    A wall makes the data mirror symmetric, ``q(-x) = R q(x)``, and for a model whose physics
    commutes with the mirror (``f(Rq) = -R f(q)``) the flux of an even row is then odd in x and
    continuous at the wall (Rankine–Hugoniot for a standing shock), hence 0 there. An odd row (a
    momentum; Burgers' u, whose standing shock at a wall has flux u^2/2 != 0) has no such bound.
    """
    signs = np.asarray(model.reflect_signs)
    return tuple(int(r) for r in np.nonzero(signs > 0)[0])


def conserved_rows(model: Model, boundary: str) -> tuple[int, ...]:
    """Rows whose totals the scheme must conserve to round-off with ``boundary`` on both sides.

    ``Model.conserved_rows`` (no source, no resistance), less every row but the depth when the
    model has a pointwise correction (it zeroes the momentum of dry cells, by design); at walls,
    only rows with no flux through a wall; none on an open (outflow) domain.
    """
    if boundary == "outflow":
        return ()
    rows = set(model.conserved_rows())
    if model.capabilities()["correction"]:
        rows &= {model.depth_index}
    if boundary == "wall":
        rows &= set(wall_conserved_rows(model))
    return tuple(sorted(rows))


def pair_by_pair(scheme: Scheme, state: State, pairs: int) -> list[State]:
    """The states after each of ``pairs`` step pairs (one ``advance`` call per pair, to the time
    two stable steps ahead; for a state at rest, ``dx`` ahead)."""
    states = [state]
    for _ in range(pairs):
        dt = scheme.stable_dt(state)
        if not np.isfinite(dt):
            dt = scheme.grid.dx
        state = scheme.advance(state, state.t + 2.0 * dt).state
        states.append(state)
    return states


def check_state(scheme: Scheme, state: State, pair: int) -> None:
    """Finite, admissible for the model, depth >= 0; with margins, no material outside them."""
    model = scheme.model
    where = f"after step pair {pair} (t={state.t:.6g})"
    assert np.all(np.isfinite(state.q)), f"not finite {where}: {state.q}"
    scheme.check_admissible(state, step=2 * pair)
    if model.depth_index is not None:
        depth = state.q[model.depth_index]
        assert depth.min() >= 0.0, f"negative depth {depth.min()!r} {where}"
    if state.margins is not None:
        left_edges = state.x - 0.5 * scheme.grid.dx
        right_edges = state.x + 0.5 * scheme.grid.dx
        outside = np.zeros(state.n_cells, dtype=bool)
        if state.margins.rear is not None:
            outside |= right_edges <= state.margins.rear.position
        if state.margins.front is not None:
            outside |= left_edges >= state.margins.front.position
        assert np.all(state.q[:, outside] == 0.0), f"material outside the margins {where}"


@pytest.mark.parametrize("case", CASE_PARAMETERS)
@WIDE_EXAMPLES
@given(data=st.data())
def test_extreme_data_stay_finite_admissible_and_conserved(case: Case, data: st.DataObject) -> None:
    """After every step pair: every value finite, every cell admissible (no momentum in a dry
    cell), every depth >= 0; on a periodic or walled domain the conserved totals (mass; every
    variable of a model without source, resistance or correction) unchanged to round-off,
    ``ROUND_OFF_PER_STEP * steps * sum|q|``.

    A scheme that follows one body may stop with a SchemeBreakdownError at its documented limits
    (:data:`DOCUMENTED_LIMITS`); nothing else may stop a run, and nothing may come out NaN,
    negative or inadmissible.
    """
    parameters = data.draw(model_parameters(case.model, case.family), label="parameters")
    model = model_with(case.model, parameters)
    boundary = data.draw(st.sampled_from(case.boundaries), label="boundary")
    scheme_class = SCHEME_VARIANTS[case.scheme]
    if scheme_class.needs_single_body:
        q = data.draw(bodies(model), label="q")
    else:
        q = data.draw(wide_states(model), label="q")
    scheme = build_scheme(scheme_class, model, case.reconstructor, q.shape[1], boundary)
    state = State(0.0, scheme.grid.centres(), q)
    if isinstance(scheme, FrontTrackingNT):
        state = scheme.initial_margins(state)
    pairs = data.draw(st.integers(1, 4), label="pairs")
    try:
        states = pair_by_pair(scheme, state, pairs)
    except SchemeBreakdownError as stop:
        assert scheme_class.needs_single_body, f"the run stopped: {stop}"
        assert any(limit in str(stop) for limit in DOCUMENTED_LIMITS), str(stop)
        event(f"{case.scheme} stopped at its documented limits")
        return
    for pair, later in enumerate(states[1:], start=1):
        check_state(scheme, later, pair)
    rows = list(conserved_rows(model, boundary))
    if not rows:
        return
    steps = 2 * pairs
    scale = np.max([np.abs(s.q[rows]).sum(axis=1) for s in states], axis=0)
    if model.capabilities()["surface"] and model.surface_aux is not None:
        # The depth's slopes come from the surface h + b (surface gradient method): their
        # round-off is eps |b|, not eps h, and the predicted mass flux m - dt/2 (g h - u^2) h'
        # carries it on times the velocity (dt/dx |u| <= 1/2).
        bed = model.aux(scheme.grid.centres(), scheme.grid.dx)[model.surface_aux[0]]
        d, m = model.depth_index, model.momentum_index
        wet = [s.q[d] >= model.dry_depth() for s in states]
        speed = max(float(np.max(np.abs(s.q[m][w] / s.q[d][w]), initial=0.0))
                    for s, w in zip(states, wet, strict=True))  # fmt: skip
        scale = scale + np.abs(bed).sum() * (1.0 + speed) * np.isin(rows, [d])
    change = states[-1].q[rows].sum(axis=1) - q[rows].sum(axis=1)
    tolerance = ROUND_OFF_PER_STEP * steps * scale
    assert np.all(np.abs(change) <= tolerance), (
        f"totals of rows {rows} changed by {change} (tolerance {tolerance}) with {boundary} "
        f"boundaries"
    )
