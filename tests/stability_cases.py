"""The stiff and extreme catalogue of docs/stability.md, each case with its expected outcome.

Every case builds its set-up, runs it, and returns an :class:`Observation`: what happened (the run
ended normally, it stopped with a clear error, or the material came to rest and stayed), the
numbers measured, and each physical expectation with whether it held. ``tests/test_stability.py``
asserts the expected outcome and every expectation; ``scripts/stability_table.py`` prints the
table of ``docs/stability.md`` from the same functions. Expectations come from the physics (exact
solutions, conservation, invariant regions of the Riemann invariants, the Coulomb law), never from
what the code happened to do.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from conslaw import registry
from conslaw.errors import ConslawError, InadmissibleStateError, SchemeBreakdownError
from conslaw.grid import Grid
from conslaw.schemes.base import BoundarySpec
from conslaw.schemes.nessyahu_tadmor.scheme import NessyahuTadmor
from conslaw.state import State
from conslaw_models.burgers_exact import BurgersRiemannFans
from conslaw_models.savage_hutter import cap_profile
from conslaw_models.shallow_water_exact import DamBreak

Array = NDArray[np.float64]

RUNS_CLEAN = "runs clean"
STOPS_CLEARLY = "stops clearly"
COMES_TO_REST = "comes to rest and stays"
EPS = float(np.finfo(np.float64).eps)


@dataclass
class Observation:
    """What a case did: its outcome, the numbers measured, and each expectation checked."""

    outcome: str
    facts: dict[str, object] = field(default_factory=dict)
    checks: dict[str, bool] = field(default_factory=dict)

    def check(self, name: str, holds: bool | np.bool_) -> None:
        """Record whether the expectation ``name`` holds."""
        self.checks[name] = bool(holds)

    def failed(self) -> list[str]:
        """The expectations that do not hold."""
        return [name for name, holds in self.checks.items() if not holds]


@dataclass(frozen=True)
class Case:
    """A catalogue entry: catalogue item, set-up, expected outcome, and how to run it."""

    key: str
    item: str
    setup: str
    expected: str
    run: Callable[[], Observation]


def scheme(
    model: str,
    parameters: dict[str, object],
    grid: Grid,
    boundary: str = "wall",
    reconstructor: str = "mc",
    cfl: float = 0.45,
) -> NessyahuTadmor:
    """The NT scheme for a case (the same boundary on both sides)."""
    side = BoundarySpec(registry.boundaries.get(boundary))
    return NessyahuTadmor(
        registry.models.get(model)(**parameters),
        registry.reconstructors.get(reconstructor),
        grid,
        side,
        side,
        cfl,
    )


def relative_change(before: Array, after: Array) -> float:
    """``|sum after - sum before| / sum |before|`` (0 for an all-zero row)."""
    size = float(np.abs(before).sum())
    return abs(float(after.sum() - before.sum())) / size if size > 0 else 0.0


def velocity(q: Array, dry: float) -> Array:
    """``hu / h`` where ``h >= dry``, else 0."""
    wet = q[0] >= dry
    return np.where(wet, q[1] / np.where(wet, q[0], 1.0), 0.0)


def finite_and_positive(observation: Observation, q: Array) -> None:
    """The checks every depth-averaged run must pass."""
    observation.check("every value finite", np.all(np.isfinite(q)))
    observation.check("h >= 0", q[0].min() >= 0.0)
    observation.facts["min h"] = float(q[0].min())


# ---------------------------------------------------------------------- shallow water
def dam_break(h_right: float, reconstructor: str = "mc", cfl: float = 0.45) -> Observation:
    """Shallow water, g = 1, h = 1 | h_right at rest on [-1, 1], walls, 400 cells, t = 0.4.

    Expectations: mass to round-off (closed domain); h >= 0; no velocity spike in the thin layer:
    ``|u| <= 2 sqrt(g h_L)``, the largest velocity of the exact solution (Ritter's front speed;
    ``u + 2c`` is at most ``2 sqrt(g h_L)`` in the exact solution, and second-order slopes may
    exceed that invariant region by up to 2 %, superbee); the step does not collapse: at most
    10 % more steps than a signal speed of ``2 sqrt(g h_L)`` allows; L1 error against the exact
    (Ritter or Stoker) cell averages at most that of first-order staggered Lax–Friedrichs.
    """
    grid = Grid(-1.0, 1.0, 400)
    t_end = 0.4
    exact = DamBreak(0.0, 1.0, h_right, 1.0).cell_averages(grid.edges, t_end)[0]
    errors = {}
    for name in (reconstructor, "none"):
        nt = scheme("shallow-water", {"g": 1.0}, grid, "wall", name, cfl)
        x = grid.centres()
        h = np.where(x < 0.0, 1.0, h_right)
        q0 = np.vstack([h, np.zeros_like(h)])
        result = nt.advance(State(0.0, x, q0), t_end)
        errors[name] = float(np.abs(result.state.q[0] - exact).mean())
        if name == reconstructor:
            kept, kept_q0, steps = result.state.q, q0, result.steps
    observation = Observation(RUNS_CLEAN)
    finite_and_positive(observation, kept)
    c = np.sqrt(np.maximum(kept[0], 0.0))
    u = velocity(kept, 1e-10)
    mass = relative_change(kept_q0[0], kept[0])
    bound = 2.0  # 2 sqrt(g h_L)
    step_limit = 2 * math.ceil(1.1 * t_end * bound / (2 * cfl * grid.dx)) + 2
    observation.facts.update(
        {
            "steps": steps,
            "mass change": mass,
            "max |u|": float(np.abs(u).max()),
            "max u+2c": float((u + 2 * c).max()),
            "L1(h)": errors[reconstructor],
            "L1(h), none": errors["none"],
        }
    )
    observation.check("mass to round-off", mass <= 8 * EPS)
    observation.check("|u| <= 2 sqrt(g h_L)", np.abs(u).max() <= bound)
    observation.check(f"steps <= {step_limit} (no collapse)", steps <= step_limit)
    observation.check("L1 <= first-order L1", errors[reconstructor] <= errors["none"])
    return observation


def froude_100() -> Observation:
    """Shallow water, g = 1, h = 1 | 0.5 | 1 (jumps at 0.25 and 0.75) all moving at u = 100
    (Froude numbers 100 and 141), periodic on [0, 1], t = 0.01, 200 / 400 / 800 cells.

    Galilean invariance: the solution is the pair of dam breaks at rest carried at u = 100, and at
    t = 0.01 it has gone round the domain exactly once, so the exact solution is the one at rest.
    Expectations: mass and momentum to round-off (periodic, nothing dries); h >= 0; no spurious
    velocity, ``|u - 100| <= 2 (sqrt(g h_max) - sqrt(g h_min))`` (the exact solution's range);
    the L1 error against the exact solution decreases under refinement.
    """
    observation = Observation(RUNS_CLEAN)
    errors = []
    bound = 2.0 * (1.0 - math.sqrt(0.5))
    for n in (200, 400, 800):
        grid = Grid(0.0, 1.0, n)
        nt = scheme("shallow-water", {"g": 1.0}, grid, "periodic")
        x = grid.centres()
        h = np.where((x > 0.25) & (x < 0.75), 0.5, 1.0)
        q0 = np.vstack([h, 100.0 * h])
        result = nt.advance(State(0.0, x, q0), 0.01)
        q = result.state.q
        rest_left = DamBreak(0.25, 1.0, 0.5, 1.0).cell_averages(grid.edges, 0.01)[0]
        rest_right = DamBreak(0.75, 0.5, 1.0, 1.0).cell_averages(grid.edges, 0.01)[0]
        exact = np.where(x < 0.5, rest_left, rest_right)
        errors.append(float(np.abs(q[0] - exact).mean()))
        finite_and_positive(observation, q)
        changes = [relative_change(q0[v], q[v]) for v in (0, 1)]
        spread = float(np.abs(velocity(q, 1e-10) - 100.0).max())
        observation.check(f"mass and momentum to round-off ({n} cells)", max(changes) <= 1e-13)
        observation.check(f"|u - 100| <= {bound:.3f} ({n} cells)", spread <= bound)
        if n == 800:
            observation.facts.update(
                {"steps": result.steps, "mass, momentum change": changes, "max |u - 100|": spread}
            )
    observation.facts["L1(h) at 200/400/800"] = errors
    observation.check("L1 decreases under refinement", errors[0] > errors[1] > errors[2])
    return observation


def depth_ratio_1e6() -> Observation:
    """Shallow water dam break h = 1 | 1e-6 (Stoker: a rarefaction and a tiny shock), outflow,
    [-1, 1], t = 0.4, 200 / 400 / 800 cells, mc.

    Expectations: h >= 0, mass to round-off while no wave reaches the boundary; converges to the
    exact Stoker cell averages: L1 error halves at least every doubling beyond the first
    (observed order >= 0.8; first order is expected for discontinuous solutions)."""
    observation = Observation(RUNS_CLEAN)
    errors = []
    for n in (200, 400, 800):
        grid = Grid(-1.0, 1.0, n)
        nt = scheme("shallow-water", {"g": 1.0}, grid, "outflow")
        x = grid.centres()
        h = np.where(x < 0.0, 1.0, 1e-6)
        q0 = np.vstack([h, np.zeros_like(h)])
        q = nt.advance(State(0.0, x, q0), 0.4).state.q
        exact = DamBreak(0.0, 1.0, 1e-6, 1.0).cell_averages(grid.edges, 0.4)[0]
        errors.append(float(np.abs(q[0] - exact).mean()))
        finite_and_positive(observation, q)
        if n == 800:
            observation.facts["mass change"] = relative_change(q0[0], q[0])
    orders = [math.log2(a / b) for a, b in itertools.pairwise(errors)]
    observation.facts.update({"L1(h) at 200/400/800": errors, "orders": orders})
    observation.check("mass to round-off", observation.facts["mass change"] <= 8 * EPS)  # type: ignore[operator]
    observation.check("observed order >= 0.8", orders[-1] >= 0.8)
    return observation


def long_run_lake(steps_wanted: int = 1_000_000) -> Observation:
    """Lake at rest h + b = 1 over a bump (height 0.5), walls, 16 cells on [-5, 5], for 10^6
    steps: the surface stays flat, the water at rest and the mass constant to round-off
    accumulated like a random walk, ``eps sqrt(steps) N`` (3.6e-12); a drift, an error growing
    with every step, would reach ``eps steps N`` = 3.6e-9."""
    grid = Grid(-5.0, 5.0, 16)
    params = {"g": 1.0, "bump_height": 0.5, "bump_centre": 0.0, "bump_width": 1.0}
    nt = scheme("shallow-water", params, grid, "wall")
    bed = nt.model.aux(grid.centres(), grid.dx)[0]
    q0 = np.vstack([1.0 - bed, np.zeros(16)])
    state = State(0.0, grid.centres(), q0)
    dt = nt.stable_dt(state)
    result = nt.advance(state, dt * steps_wanted)
    q = result.state.q
    observation = Observation(RUNS_CLEAN)
    finite_and_positive(observation, q)
    surface = q[0] + bed
    observation.facts.update(
        {
            "steps": result.steps,
            "max |surface - 1|": float(np.abs(surface - 1.0).max()),
            "max |hu|": float(np.abs(q[1]).max()),
            "mass change": relative_change(q0[0], q[0]),
        }
    )
    walk = EPS * math.sqrt(result.steps) * grid.n_cells
    observation.check("at least 10^6 steps", result.steps >= steps_wanted)
    observation.check("surface flat to eps sqrt(steps) N", np.abs(surface - 1.0).max() <= walk)
    observation.check("at rest to eps sqrt(steps) N", np.abs(q[1]).max() <= walk)
    observation.check("mass to eps sqrt(steps) N", observation.facts["mass change"] <= walk)  # type: ignore[operator]
    return observation


def million_cells() -> Observation:
    """Shallow-water dry dam break h = 1 | 0 on 10^6 cells (walls, [-1, 1]) to t = 8 cfl dx.

    Expectations: h >= 0, finite, mass to round-off (the sum of 10^6 terms: ``eps sqrt(N)``
    typical, bound ``8 eps`` relative taken), the dry side untouched beyond the distance the
    fastest wave can travel."""
    grid = Grid(-1.0, 1.0, 1_000_000)
    nt = scheme("shallow-water", {"g": 1.0}, grid, "wall")
    x = grid.centres()
    h = np.where(x < 0.0, 1.0, 0.0)
    q0 = np.vstack([h, np.zeros_like(h)])
    t_end = 8 * 0.45 * grid.dx / 1.0
    result = nt.advance(State(0.0, x, q0), t_end)
    q = result.state.q
    observation = Observation(RUNS_CLEAN)
    finite_and_positive(observation, q)
    reach = 2.0 * t_end + 2 * grid.dx  # 2 sqrt(g h_L) t, plus the stencil
    observation.facts.update({"steps": result.steps, "mass change": relative_change(q0[0], q[0])})
    observation.check("mass to round-off", observation.facts["mass change"] <= 8 * EPS)  # type: ignore[operator]
    observation.check("nothing beyond the fastest wave", np.all(q[:, x > reach] == 0.0))
    return observation


# ---------------------------------------------------------------------- Savage–Hutter
def _cap(grid: Grid, centre: float, radius: float, height: float) -> Array:
    from conslaw.exact import piecewise_cell_averages

    return piecewise_cell_averages(grid.edges, *cap_profile(centre, radius, height))[0]


def sliding_body(zeta: float, delta: float, epsilon: float, t_end: float = 2.0) -> Observation:
    """Savage–Hutter, plane chute at ``zeta``, ``delta = phi``, a parabolic cap at rest (height 1,
    radius 1) on [0, 20] with walls far away, 200 and 400 cells.

    ``epsilon`` is small enough that the pressure gradient (``eps cos zeta K |h_x| <= 2 beta``)
    is below the net driving force ``|s|``, ``s = sin zeta - sgn tan delta cos zeta``, so every
    part of the body slides the same way. Expectations: no momentum against ``s`` at 10 sampled
    times; total momentum ``M s t`` (internal pressure forces cancel, friction has one sign),
    which the scheme meets to its discretisation error (the quarter-point source integration of
    eqs. 13-14 sums predicted, not current, depths): ``|P / (M s t) - 1| <= 1e-3`` at 200 and 400
    cells (a friction acting the wrong way or a lost tail would be O(1)); mass to round-off;
    h >= 0.
    """
    observation = Observation(RUNS_CLEAN)
    direction = 1.0 if zeta > 0 else -1.0
    z, d = math.radians(zeta), math.radians(delta)
    s = math.sin(z) - direction * math.tan(d) * math.cos(z)
    deviations = []
    for n in (200, 400):
        grid = Grid(0.0, 20.0, n)
        centre = 4.0 if direction > 0 else 16.0
        params = {"zeta": zeta, "phi": delta, "delta": delta, "epsilon": epsilon}
        nt = scheme("savage-hutter", params, grid, "wall")
        h = _cap(grid, centre, 1.0, 1.0)
        q0 = np.vstack([h, np.zeros_like(h)])
        state = State(0.0, grid.centres(), q0)
        wrong_sign = 0.0
        steps = 0
        for t in np.linspace(0.0, t_end, 11)[1:]:
            result = nt.advance(state, float(t))
            state, steps = result.state, steps + result.steps
            wrong_sign = max(wrong_sign, float(np.max(-direction * state.q[1])))
        q = state.q
        finite_and_positive(observation, q)
        expected = q0[0].sum() * grid.dx * s * t_end
        deviations.append(float(q[1].sum() * grid.dx / expected - 1.0))
        observation.check(f"never moves against s ({n} cells)", wrong_sign <= 0.0)
        observation.check(f"mass to round-off ({n} cells)", relative_change(q0[0], q[0]) <= 8 * EPS)
        if n == 200:
            observation.facts.update({"steps": steps, "s": s})
    observation.facts["P / (M s t) - 1 at 200/400"] = deviations
    observation.check("|P / (M s t) - 1| <= 1e-3", max(map(abs, deviations)) <= 1e-3)
    return observation


def _pile_stays(
    params: dict[str, object], grid: Grid, h: Array, u0: float, steps_wanted: int
) -> Observation:
    """Run a pile of depth ``h`` with velocity ``u0`` for one step pair, then ``steps_wanted``
    more steps; the material must be at rest after the first pair and stay so bit for bit."""
    nt = scheme("savage-hutter", params, grid, "wall")
    q0 = np.vstack([h, h * u0])
    state = State(0.0, grid.centres(), q0)
    dt = nt.stable_dt(state)
    first = nt.advance(state, 2 * dt)
    rest = first.state
    later = nt.advance(rest, rest.t + nt.stable_dt(rest) * steps_wanted)
    q = later.state.q
    observation = Observation(COMES_TO_REST)
    finite_and_positive(observation, q)
    z = math.radians(float(params.get("zeta", 40.0)))  # type: ignore[arg-type]
    d = math.radians(float(params["delta"]))  # type: ignore[arg-type]
    stiffness = dt * math.tan(d) * math.cos(z) / abs(u0) if u0 else math.inf
    observation.facts.update(
        {
            "dt tan(delta) cos(zeta) / |u0|": stiffness,
            "max |hu| after the first pair": float(np.abs(rest.q[1]).max()),
            "steps at rest": later.steps,
            "max |hu| at the end": float(np.abs(q[1]).max()),
            "mass change": relative_change(q0[0], q[0]),
        }
    )
    observation.check("at rest after the first step pair", np.all(rest.q[1] == 0.0))
    observation.check(f"at least {steps_wanted} steps at rest", later.steps >= steps_wanted)
    observation.check("hu = 0 exactly at the end", np.all(q[1] == 0.0))
    observation.check("h unchanged bit for bit", np.array_equal(q[0], rest.q[0]))
    observation.check("never moved against u0", np.all(u0 * rest.q[1] >= 0.0))
    return observation


def stiff_stop() -> Observation:
    """A pile (eps = 0.1, height 0.5, radius 2) moving at u0 = 1e-3 on a 5-degree slope with
    delta = phi = 30: friction removes more than all its momentum in one step (stiff,
    ``dt tan delta cos zeta > |u0|``), so it stops in the first step pair, then stays at rest bit
    for bit for 10^5 steps (``|tan zeta| < tan delta`` and the pressure gradient
    ``eps cos zeta K |h_x| <= 0.08`` is far below the friction 0.58)."""
    grid = Grid(0.0, 10.0, 100)
    params = {"epsilon": 0.1, "phi": 30.0, "delta": 30.0, "zeta": 5.0}
    return _pile_stays(params, grid, _cap(grid, 5.0, 2.0, 0.5), 1e-3, 100_000)


def delta_above_zeta() -> Observation:
    """A pile at rest (eps = 0.1, height 0.5, radius 2) on a 20-degree slope with
    delta = phi = 30 > zeta: it never moves; 10^5 steps, hu = 0 and h unchanged bit for bit."""
    grid = Grid(0.0, 10.0, 100)
    params = {"epsilon": 0.1, "phi": 30.0, "delta": 30.0, "zeta": 20.0}
    return _pile_stays(params, grid, _cap(grid, 5.0, 2.0, 0.5), 0.0, 100_000)


def held_upslope_source() -> Observation:
    """u = 0 with s < 0 everywhere: a pile at rest on zeta = -20 degrees (the bed rises in +x, the
    driving force points to -x everywhere) with delta = phi = 30: friction holds it; 10^5 steps
    at rest bit for bit. (With delta < |zeta| it slides in -x: see ``slides-negative-zeta``.)"""
    grid = Grid(0.0, 10.0, 100)
    params = {"epsilon": 0.1, "phi": 30.0, "delta": 30.0, "zeta": -20.0}
    return _pile_stays(params, grid, _cap(grid, 5.0, 2.0, 0.5), 0.0, 100_000)


def comes_to_rest() -> Observation:
    """A slab (h = 1 on [5, 10], eps = 0.01) sliding at u = 1 on a horizontal bed, delta = 30:
    friction decelerates every part at tan(delta). The bulk stops at u0 / tan(delta) = 1.73 and
    the front, which the pressure pushes ahead at most ``2c`` faster (Riemann invariant), by
    (u0 + 2c) / tan(delta); never reversed (hu >= 0 at 30 sampled times); then at rest bit for
    bit for 10^5 steps."""
    grid = Grid(0.0, 20.0, 100)
    params = {"epsilon": 0.01, "phi": 30.0, "delta": 30.0, "zeta": 0.0}
    nt = scheme("savage-hutter", params, grid, "wall")
    x = grid.centres()
    h = np.where((x > 5) & (x < 10), 1.0, 0.0)
    q0 = np.vstack([h, h])
    state = State(0.0, x, q0)
    reversed_ = False
    stopped_at = math.nan
    for t in np.linspace(0.1, 3.0, 30):
        state = nt.advance(state, float(t)).state
        reversed_ |= bool(np.any(state.q[1] < 0.0))
        if math.isnan(stopped_at) and np.all(state.q[1] == 0.0):
            stopped_at = float(t)
    rest = state
    later = nt.advance(rest, rest.t + nt.stable_dt(rest) * 100_000)
    q = later.state.q
    observation = Observation(COMES_TO_REST)
    finite_and_positive(observation, q)
    tan_delta = math.tan(math.radians(30.0))
    earliest = 1.0 / tan_delta
    aux = nt.model.aux(x[:1], grid.dx)
    celerity = float(nt.model.max_wave_speed(np.array([[1.0], [0.0]]), aux)[0])
    latest = (1.0 + 2.0 * celerity) / tan_delta
    observation.facts.update(
        {"at rest by t (sampled every 0.1)": stopped_at, "steps at rest": later.steps}
    )
    observation.check("never reversed", not reversed_)
    observation.check(
        f"stops between u0/tan(delta) = {earliest:.2f} and (u0 + 2c)/tan(delta) = {latest:.2f}",
        earliest - 0.1 <= stopped_at <= latest + 0.1,
    )
    observation.check("at least 10^5 steps at rest", later.steps >= 100_000)
    observation.check("hu = 0 exactly at the end", np.all(q[1] == 0.0))
    observation.check("h unchanged bit for bit", np.array_equal(q[0], rest.q[0]))
    observation.check("mass to round-off", relative_change(q0[0], q[0]) <= 8 * EPS)
    return observation


def delta_near_phi() -> Observation:
    """Savage–Hutter similarity set-up (eps = 0.1, zeta = 40, phi = 30, cap height 1, radius 2,
    superbee, 90 cells, t = 6) with delta = phi and delta = phi - 1e-9 degrees: the earth-pressure
    coefficients are real (``K_act <= K_pass``, equal at delta = phi) and the two runs agree to
    within the change of K (``|h_1 - h_2| <= max h |K_pass - K_act| / K``, a relative change of
    the pressure coefficient changing the solution by the same order)."""
    from conslaw_models.savage_hutter import earth_pressure_coefficients

    grid = Grid(0.0, 18.0, 90)
    h0 = _cap(grid, 4.0, 2.0, 1.0)
    runs = {}
    for label, delta in (("delta = phi", 30.0), ("delta = phi - 1e-9", 30.0 - 1e-9)):
        params = {"epsilon": 0.1, "zeta": 40.0, "phi": 30.0, "delta": delta}
        nt = scheme("savage-hutter", params, grid, "outflow", "superbee", 0.3)
        runs[label] = nt.advance(State(0.0, grid.centres(), np.vstack([h0, 0 * h0])), 6.0)
    k_act, k_pass = earth_pressure_coefficients(math.radians(30.0), math.radians(30.0 - 1e-9))
    a, b = (r.state.q for r in runs.values())
    difference = float(np.abs(a[0] - b[0]).max())
    bound = float(a[0].max()) * (k_pass - k_act) / k_act
    observation = Observation(RUNS_CLEAN)
    finite_and_positive(observation, b)
    observation.facts.update(
        {"K_act, K_pass at phi - 1e-9": (k_act, k_pass), "max |h_1 - h_2|": difference}
    )
    observation.check("K real, K_act <= K_pass", math.isfinite(k_act) and k_act <= k_pass)
    observation.check("runs agree within the change of K", difference <= bound)
    return observation


# ---------------------------------------------------------------------- Burgers
def burgers_1e8() -> Observation:
    """Burgers Riemann data ``u = 2 | 1 | -1`` (two shocks, apart until t = 0.13) scaled by
    2^27 = 1.3e8, with ``t = 0.1`` scaled by 2^-27, outflow, 200 cells, mc.

    Burgers is invariant under ``u -> a u, t -> t / a``, and with a power of two the scheme is too,
    in floating point: every product and quotient scales exactly. Expectations: the scaled run
    equals 2^27 times the unit run bit for bit, and the unit run's L1 error against the exact
    solution is that of a resolved Riemann problem (<= 2 dx, the shock smeared over about two
    cells)."""
    grid = Grid(0.0, 1.0, 200)
    scale = 2.0**27
    exact = BurgersRiemannFans((0.3, 0.5), (2.0, 1.0, -1.0))
    results = {}
    for factor in (1.0, scale):
        nt = scheme("burgers", {}, grid, "outflow")
        x = grid.centres()
        q0 = factor * exact.cell_averages(grid.edges, 0.0)
        results[factor] = nt.advance(State(0.0, x, q0), 0.1 / factor)
    unit, big = results[1.0].state.q, results[scale].state.q
    error = float(np.abs(unit[0] - exact.cell_averages(grid.edges, 0.1)[0]).mean())
    observation = Observation(RUNS_CLEAN)
    observation.check("every value finite", np.all(np.isfinite(big)))
    observation.facts.update(
        {"max |u|": float(np.abs(big).max()), "steps": results[scale].steps, "L1 (unit run)": error}
    )
    identical = np.array_equal(big, scale * unit)
    observation.check("scaled run = 2^27 x unit run, bit for bit", identical)
    observation.check("L1 (unit run) <= 2 dx", error <= 2 * grid.dx)
    return observation


def burgers_long_run(steps_wanted: int = 1_000_000) -> Observation:
    """Burgers ``u = 1 + 0.1 sin(2 pi x)``, periodic, 16 cells, mc, 10^6 steps (the sine breaks
    and the shock travels round the domain ~10^4 times). Expectation: the total stays constant
    to round-off accumulated over the steps: each step changes the sum by a few rounding errors
    of its terms, which add up like a random walk (``eps sqrt(steps) N``, about 4e-12 here); the
    bound taken is that (the worst case ``eps steps N`` would be 3.6e-9)."""
    grid = Grid(0.0, 1.0, 16)
    nt = scheme("burgers", {}, grid, "periodic")
    x = grid.centres()
    q0 = (1.0 + 0.1 * np.sin(2 * np.pi * x))[None, :]
    state = State(0.0, x, q0)
    t_end = steps_wanted * nt.stable_dt(state) * 1.1 / 2 * 2
    result = nt.advance(state, t_end)
    change = relative_change(q0[0], result.state.q[0])
    bound = EPS * math.sqrt(result.steps) * grid.n_cells
    observation = Observation(RUNS_CLEAN)
    observation.check("every value finite", np.all(np.isfinite(result.state.q)))
    observation.facts.update({"steps": result.steps, "relative change of the total": change})
    observation.check("at least 10^6 steps", result.steps >= steps_wanted)
    observation.check("total to eps sqrt(steps) N", change <= bound)
    return observation


# ---------------------------------------------------------------------- clear stops
def _stop(run: Callable[[], object], kind: type[ConslawError], *fragments: str) -> Observation:
    """Run ``run``; expect a ``kind`` error whose message contains ``fragments``."""
    observation = Observation(RUNS_CLEAN)
    try:
        run()
    except ConslawError as error:
        observation.outcome = STOPS_CLEARLY
        message = str(error)
        observation.facts["message"] = message
        observation.check(f"{kind.__name__}", isinstance(error, kind))
        observation.check("one line", "\n" not in message)
        for fragment in fragments:
            observation.check(f"names '{fragment}'", fragment in message)
    return observation


def nan_in_the_data() -> Observation:
    """A NaN in the middle of a running shallow-water state (cell 20 of 40): the run stops with
    InadmissibleStateError naming time, step, cell, position and values."""
    nt = scheme("shallow-water", {"g": 1.0}, Grid(0.0, 1.0, 40), "wall")
    q = np.vstack([np.ones(40), np.zeros(40)])
    q[1, 20] = np.nan
    return _stop(
        lambda: nt.advance(State(0.0, nt.grid.centres(), q), 0.1),
        InadmissibleStateError, "t=0", "step 0", "cell 20", "x=0.5125", "hu=nan",
    )  # fmt: skip


def overflow() -> Observation:
    """Gravity 1e308 (finite, valid input): the wave speed overflows; the run stops with
    InadmissibleStateError saying so, instead of running with inf."""
    nt = scheme("shallow-water", {"g": 1e308}, Grid(0.0, 1.0, 40), "wall")
    q = np.vstack([np.full(40, 10.0), np.zeros(40)])
    return _stop(
        lambda: nt.advance(State(0.0, nt.grid.centres(), q), 0.1),
        InadmissibleStateError, "not finite", "cell 0",
    )  # fmt: skip


def time_step_collapse() -> Observation:
    """Burgers with |u| = 1e300 asked to run to t = 1: dt = 0.45 dx / 1e300 is below the floor
    1e-14 dx; the run stops with SchemeBreakdownError naming time, step, the fastest cell and
    what to try instead of hanging."""
    nt = scheme("burgers", {}, Grid(0.0, 1.0, 16), "periodic")
    q = np.full((1, 16), 1e300)
    return _stop(
        lambda: nt.advance(State(0.0, nt.grid.centres(), q), 1.0),
        SchemeBreakdownError, "fell below the floor", "t=0", "step 0",
        "the fastest cell 0 (x=0.03125): u=1e+300", "likely remedies",
    )  # fmt: skip


CASES: list[Case] = [
    Case("dry-bed", "Dry bed next to deep flow", "shallow water h = 1 | 0, walls, 400 cells, "
         "every reconstructor (mc shown)", RUNS_CLEAN, lambda: dam_break(0.0)),
    Case("thin-1e-12", "h down to 1e-12 next to h = 1", "shallow water h = 1 | 1e-12, walls, "
         "400 cells, mc", RUNS_CLEAN, lambda: dam_break(1e-12)),
    Case("depth-ratio-1e6", "Depth ratio 1e6", "shallow water h = 1 | 1e-6 (Stoker), outflow, "
         "200/400/800 cells", RUNS_CLEAN, depth_ratio_1e6),
    Case("froude-100", "Froude number 10-100", "shallow water h = 1 | 0.5 | 1 at u = 100, "
         "periodic, 200/400/800 cells", RUNS_CLEAN, froude_100),
    Case("zeta-89", "zeta -> 89 degrees", "Savage-Hutter cap at rest on a 89-degree plane, "
         "delta = phi = 30, eps = 1, 200/400 cells", RUNS_CLEAN,
         lambda: sliding_body(89.0, 30.0, 1.0)),
    Case("slides-negative-zeta", "u = 0 with s < 0 everywhere (slides)", "Savage-Hutter cap "
         "at rest on zeta = -40, delta = phi = 30, eps = 0.01", RUNS_CLEAN,
         lambda: sliding_body(-40.0, 30.0, 0.01)),
    Case("held-negative-zeta", "u = 0 with s < 0 everywhere (held)", "Savage-Hutter pile at "
         "rest on zeta = -20, delta = phi = 30, 10^5 steps", COMES_TO_REST, held_upslope_source),
    Case("delta-near-phi", "delta = phi and delta just below phi", "similarity set-up with "
         "delta = 30 and 30 - 1e-9, phi = 30", RUNS_CLEAN, delta_near_phi),
    Case("delta-above-zeta", "delta > zeta (must not move)", "pile at rest on zeta = 20, "
         "delta = phi = 30, 10^5 steps", COMES_TO_REST, delta_above_zeta),
    Case("stiff-stop", "Stops in one step, stays 10^5 steps", "pile at u0 = 1e-3 on zeta = 5, "
         "delta = phi = 30, eps = 0.1: dt tan(delta) cos(zeta) > |u0|", COMES_TO_REST, stiff_stop),
    Case("comes-to-rest", "Comes to rest and stays 10^5 steps", "slab at u = 1 on a flat bed, "
         "delta = 30, eps = 0.01", COMES_TO_REST, comes_to_rest),
    Case("long-run-burgers", "10^6 steps on a small grid, no drift", "Burgers sine, periodic, "
         "16 cells", RUNS_CLEAN, burgers_long_run),
    Case("long-run-lake", "10^6 steps on a small grid, no drift", "lake at rest over a bump, "
         "walls, 16 cells", RUNS_CLEAN, long_run_lake),
    Case("million-cells", "10^6 cells", "shallow-water dry dam break, 10^6 cells, "
         "t = 8 cfl dx (12 steps)",
         RUNS_CLEAN, million_cells),
    Case("cfl-0.49", "CFL 0.49", "shallow water h = 1 | 0 at CFL 0.49, walls, 400 cells",
         RUNS_CLEAN, lambda: dam_break(0.0, "mc", 0.49)),
    Case("burgers-1e8", "Burgers with |u| ~ 1e8", "Riemann data 2 | 1 | -1 times 2^27 "
         "(t times 2^-27), outflow, 200 cells", RUNS_CLEAN, burgers_1e8),
    Case("nan", "NaN in the state", "shallow water, hu = NaN in cell 20", STOPS_CLEARLY,
         nan_in_the_data),
    Case("overflow", "Wave speed overflows", "shallow water with g = 1e308", STOPS_CLEARLY,
         overflow),
    Case("dt-floor", "Time step below its floor", "Burgers with |u| = 1e300, t_end = 1",
         STOPS_CLEARLY, time_step_collapse),
]  # fmt: skip
