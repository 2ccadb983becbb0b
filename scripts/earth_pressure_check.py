"""The checks of the Savage–Hutter earth pressure with phi > delta (docs/validation.md, "Earth
pressure"): uniform layers, the dam break down an incline, the run-out coming to rest, a cap at
rest, and the similarity solution with front tracking. Prints markdown tables.

Usage: ``python scripts/earth_pressure_check.py [CHECK ...]``, each CHECK a key of ``CHECKS``
(uniform, dam-break, dam-break-first-order, run-out, run-out-sweep, run-out-film, run-out-cfl,
cap, similarity, passive-limit; all by default).
"""

from __future__ import annotations

import math
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

import conslaw
from conslaw import registry
from conslaw.analysis import observed_orders

RECONSTRUCTORS = registry.reconstructors.names()

UNIFORM = """
model = "savage-hutter"
reconstructor = "{reconstructor}"
n_cells = {n}
x_min = 0.0
x_max = 10.0
t_end = 10.0
exact = false
[boundary]
left = "periodic"
right = "periodic"
[parameters]
epsilon = 1.0
phi = {phi}
delta = {delta}
chute = "plane"
zeta = 30.0
[initial]
kind = "piecewise-constant"
breakpoints = []
states = [[1.0, 1.0]]
"""


def scene_file(text: str) -> Path:
    """A scene written to a temporary file."""
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as handle:
        handle.write(text)
    return Path(handle.name)


def uniform() -> None:
    """h = 1, u = 1, periodic, on a 30-degree plane: the largest |h - 1| and |u - (1 + s t)| at
    t = 10 over every reconstructor, for each phi, delta and N."""
    print("| phi | delta | N | max |h - 1| | max |u - (1 + s t)| |")
    print("|---|---|---|---|---|")
    for phi in (30.0, 30.01, 35.0, 45.0):
        for delta in (29.99, 30.0):
            for n in (100, 1600):
                worst_h = worst_u = 0.0
                for reconstructor in RECONSTRUCTORS:
                    path = scene_file(
                        UNIFORM.format(reconstructor=reconstructor, n=n, phi=phi, delta=delta)
                    )
                    result = conslaw.run(path)
                    zeta, tan_delta = math.radians(30.0), math.tan(math.radians(delta))
                    s = math.sin(zeta) - tan_delta * math.cos(zeta)
                    exact_u = max(1.0 + s * 10.0, 0.0)
                    q = result.final.q
                    worst_h = max(worst_h, float(np.abs(q[0] - 1.0).max()))
                    worst_u = max(worst_u, float(np.abs(q[1] / q[0] - exact_u).max()))
                print(f"| {phi} | {delta} | {n} | {worst_h:.1e} | {worst_u:.1e} |")


def dam_break() -> None:
    """sh-dam-break-incline (phi = 30) and the same with phi = delta = 25: L1(h) at t = 2, the
    observed orders, the ratio to the phi = delta run, and the largest h at 20 times."""
    cells = (200, 400, 800, 1600)
    times = [0.1 * k for k in range(1, 21)]
    print("| reconstructor | L1 N=200 | 400 | 800 | 1600 | orders | L1 / L1(phi=delta) | max h |")
    print("|---|---|---|---|---|---|---|---|")
    for reconstructor in RECONSTRUCTORS:
        errors, ratios, highest = [], [], 0.0
        for n in cells:
            runs = {}
            for phi in (30.0, 25.0):
                runs[phi] = conslaw.run(
                    "sh-dam-break-incline", n_cells=n, reconstructor=reconstructor,
                    output_times=times, parameters__phi=phi,
                )  # fmt: skip
            highest = max(highest, max(float(s.q[0].max()) for s in runs[30.0].states))
            errors.append(runs[30.0].headline_error())
            ratios.append(runs[30.0].headline_error() / runs[25.0].headline_error())
        orders = observed_orders(cells, errors)
        print(
            f"| {reconstructor} | " + " | ".join(f"{e:.3e}" for e in errors)
            + " | " + ", ".join(f"{o:.2f}" for o in orders)
            + f" | {min(ratios):.2f}-{max(ratios):.2f} | {highest:.6f} |"
        )  # fmt: skip


def dam_break_first_order() -> None:
    """The first-order scheme (``none``) on sh-dam-break-incline from 200 to 6400 cells, phi = 30
    and phi = delta = 25: L1(h) at t = 2 (the output times of :func:`dam_break`), the observed
    order, L1 / dx and L1 / (dx ln(1/dx)) (the rate of a monotone scheme at the corners of a
    rarefaction), and the share of L1 behind the fan's rear corner (x < -0.8), in the fan, and
    in the last 0.5 before the front."""
    cells = (200, 400, 800, 1600, 3200, 6400)
    times = [0.1 * k for k in range(1, 21)]
    print("| phi | N | L1 | order | L1 / dx | L1 / (dx ln(1/dx)) | rear, fan, front share |")
    print("|---|---|---|---|---|---|---|")
    for phi in (30.0, 25.0):
        errors = []
        for n in cells:
            result = conslaw.run(
                "sh-dam-break-incline", n_cells=n, reconstructor="none", output_times=times,
                parameters__phi=phi,
            )  # fmt: skip
            error = result.headline_error()
            assert error is not None
            errors.append(error)
            x, exact = result.states[-1].x, result.exact[-1]
            assert exact is not None
            local = np.abs(result.states[-1].q[0] - exact[0])
            front = float(x[np.nonzero(exact[0] > 0.0)[0].max()])
            shares = [x < -0.8, (x >= -0.8) & (x < front - 0.5), x >= front - 0.5]
            share = ", ".join(f"{local[mask].sum() / local.sum():.2f}" for mask in shares)
            dx = result.grid.dx
            order = "" if n == cells[0] else f"{observed_orders(cells[:2], errors[-2:])[0]:.2f}"
            print(
                f"| {phi} | {n} | {error:.3e} | {order} | {error / dx:.3f} | "
                f"{error / (dx * math.log(1.0 / dx)):.3f} | {share} |"
            )


def run_out_to(phi: float, times: list[float], **overrides: Any) -> conslaw.RunResult:
    """sh-runout-shock with ``phi`` (delta = 30) to the last of ``times``, output at each."""
    return conslaw.run(
        "sh-runout-shock", parameters__phi=phi, output_times=times, t_end=times[-1], **overrides
    )


def run_out() -> None:
    """sh-runout-shock with phi = 32, 35, 40: when every momentum is 0, whether the state then
    stays bit for bit, and the mass drift; then the same with output times to t = 3200 (where
    the last cell stops depends on the output times, which shorten step pairs)."""
    times = [0.0, 4.0, 8.0, 12.0, 16.0, 20.0, 50.0, 100.0, 200.0]
    print("| phi | moving cells at t = 20, 50, 100, 200 | t=200 equals t=100 bit for bit | mass |")
    print("|---|---|---|---|")
    for phi in (32.0, 35.0, 40.0):
        result = run_out_to(phi, times)
        moving = [int(np.count_nonzero(s.q[1])) for s in result.states[5:]]
        same = np.array_equal(result.states[-1].q, result.states[-2].q)
        print(f"| {phi} | {moving} | {same} | {result.mass_drift[0]:.1e} |")
    long_times = [0.0, 50.0, 100.0, 200.0, 400.0, 800.0, 1600.0, 3200.0]
    print()
    print("| phi | moving cells at t = 50, 100, ..., 3200 | deepest moving cell at t = 3200 |")
    print("|---|---|---|")
    for phi in (32.0, 35.0, 40.0):
        result = run_out_to(phi, long_times)
        moving = [int(np.count_nonzero(s.q[1])) for s in result.states[1:]]
        final = result.states[-1].q
        deepest = float(final[0][final[1] != 0.0].max(initial=0.0))
        print(f"| {phi} | {moving} | {deepest:.1e} |")


def run_out_sweep() -> None:
    """sh-runout-shock at other resolutions and friction angles (delta = 30): the first output
    time at which every momentum is 0 (of t = 50, 100, 200, 400), and whether the state then
    stays bit for bit to t = 400."""
    times = [0.0, 20.0, 50.0, 100.0, 200.0, 400.0]
    print("| phi | N | at rest from t = | then bit for bit | mass |")
    print("|---|---|---|---|---|")
    for phi in (31.0, 32.0, 33.0, 35.0, 37.0, 40.0, 45.0):
        for n_cells in (250, 400, 500, 700):
            result = run_out_to(phi, times, n_cells=n_cells)
            states, mass = result.states[2:], result.mass_drift[0]
            # The first output from which no momentum is left (len(states): none such).
            first = max((k + 1 for k, s in enumerate(states) if np.any(s.q[1])), default=0)
            at_rest = first < len(states)
            since = f"{states[first].t:g}" if at_rest else "never"
            same = at_rest and all(np.array_equal(s.q, states[first].q) for s in states[first:])
            print(f"| {phi} | {n_cells} | {since} | {same} | {mass:.1e} |")


def run_out_film() -> None:
    """The runs of ``run_out_sweep`` that do not come to rest (phi = 45 at 250 and 700 cells):
    the moving cells at t = 400 (position, depth, velocity) and the deposit cell below them."""
    times = [0.0, 20.0, 50.0, 100.0, 200.0, 400.0]
    print("| phi | N | moving cells at t = 400: x, h, u | deposit cell below: x, h |")
    print("|---|---|---|---|")
    for n_cells in (250, 700):
        result = run_out_to(45.0, times, n_cells=n_cells)
        x = result.grid.centres()
        h, m = result.final.q
        moving = np.flatnonzero(m)
        if not moving.size:
            print(f"| 45.0 | {n_cells} | none | - |")
            continue
        cells = "; ".join(f"{x[i]:.2f}, {h[i]:.1e}, {m[i] / h[i]:.2f}" for i in moving)
        below = moving[-1] + 1
        print(f"| 45.0 | {n_cells} | {cells} | {x[below]:.2f}, {h[below]:.1e} |")


def run_out_cfl() -> None:
    """The deposit of the run-out at t = 60 against the Courant number (a treatment of the
    passive pressure must not make it depend on the time step): its extent (depth above 1e-3),
    its largest depth, and how many cells still move."""
    print("| scene | phi | CFL | deposit from | to | largest depth | moving cells |")
    print("|---|---|---|---|---|---|---|")
    for scene, phi in (("sh-runout-phi35", 35.0), ("sh-runout-shock", 40.0)):
        for cfl in (0.45, 0.3, 0.15):
            result = conslaw.run(
                scene, cfl=cfl, parameters__phi=phi, t_end=60.0, output_times=[0.0, 60.0]
            )
            h, m = result.final.q
            x = result.grid.centres()[h > 1e-3]
            print(
                f"| {scene} | {phi} | {cfl} | {x.min():.2f} | {x.max():.2f} | {h.max():.4f} "
                f"| {np.count_nonzero(m)} |"
            )


def cap() -> None:
    """A cap at rest (sh-at-rest with zeta = 25, delta = 30, walls) for 10^4 steps, with and
    without front tracking, every reconstructor: whether every momentum is 0 and h (and the
    margins) are unchanged bit for bit."""
    print("| phi | front tracking | steps | held bit for bit (every reconstructor) |")
    print("|---|---|---|---|")
    for phi in (30.0, 35.0, 45.0):
        for tracking in (False, True):
            held, steps = [], 0
            for reconstructor in RECONSTRUCTORS:
                result = conslaw.run(
                    "sh-at-rest", reconstructor=reconstructor, front_tracking=tracking,
                    parameters__zeta=25.0, parameters__phi=phi, t_end=2000.0,
                    output_times=[0.0, 2000.0], boundary__left="wall", boundary__right="wall",
                )  # fmt: skip
                first, last = result.states
                same = np.array_equal(first.q[0], last.q[0]) and not np.any(last.q[1])
                if tracking:
                    same = same and first.margins == last.margins
                held.append(same)
                steps = result.steps
            print(f"| {phi} | {tracking} | {steps} | {all(held)} |")


def similarity() -> None:
    """sh-similarity-ft with phi = 35 (and 30): margin errors at t = 6 in cells, L1(h), orders."""
    print("| phi | N | L1(h) | rear error / dx | front error / dx | largest margin error |")
    print("|---|---|---|---|---|---|")
    for phi in (30.0, 35.0):
        margins = []
        for n in (90, 180, 360):
            result = conslaw.run("sh-similarity-ft", parameters__phi=phi, n_cells=n)
            assert result.exact_solution is not None and result.final.margins is not None
            rear, front = result.exact_solution.margins(result.final.t)  # type: ignore[attr-defined]
            dx = result.grid.dx
            tracked = result.final.margins
            assert tracked.rear is not None and tracked.front is not None
            rear_error, front_error = tracked.rear.position - rear, tracked.front.position - front
            margins.append(max(abs(rear_error), abs(front_error)))
            print(
                f"| {phi} | {n} | {result.headline_error():.3e} | {rear_error / dx:+.3f} "
                f"| {front_error / dx:+.3f} | {margins[-1]:.2e} |"
            )
        orders = observed_orders((90, 180, 360), margins)
        print(f"| {phi} | orders of the margin error | | | | {orders[0]:.2f}, {orders[1]:.2f} |")


def passive_limit() -> None:
    """The passive pressure applied in full at a cap's foot held by friction (docs/validation.md,
    "Wrong answers with phi well above delta"): the foot's velocity after the first step, and
    the largest speed at t = 0.5 against the Lagrangian scheme's."""
    from conslaw.config import load_scene
    from conslaw.simulation import build

    print("| phi | delta | K_pass/K_act | foot u after step 1 | NT max u | Lagrangian max u |")
    print("|---|---|---|---|---|---|")
    for phi, delta, t_end in ((45.0, 30.0, 0.5), (85.0, 60.0, 0.05)):
        overrides = {"parameters.phi": phi, "parameters.delta": delta, "parameters.epsilon": 1.0}
        model, _, scheme, initial, _ = build(load_scene("sh-at-rest", overrides))
        first = scheme.reference_step(initial, scheme.stable_dt(initial))  # type: ignore[attr-defined]
        depth, momentum = first.q
        foot = float(np.max(np.where(depth > 0.0, momentum / np.maximum(depth, 1e-300), 0.0)))
        speeds = []
        for scheme_name in ("nessyahu-tadmor", "lagrangian"):
            result = conslaw.run(
                "sh-at-rest", scheme=scheme_name, t_end=t_end, output_times=[0.0, t_end],
                parameters__phi=phi, parameters__delta=delta, parameters__epsilon=1.0,
            )  # fmt: skip
            h, m = result.states[-1].q
            speeds.append(float(np.max(np.abs(np.where(h > 1e-8, m / np.maximum(h, 1e-300), 0)))))
        ratio = model.k_passive / model.k_active  # type: ignore[attr-defined]
        print(f"| {phi} | {delta} | {ratio:.0f} | {foot:.2f} | {speeds[0]:.3g} | {speeds[1]:.3g} |")


CHECKS = {
    "uniform": uniform, "dam-break": dam_break, "dam-break-first-order": dam_break_first_order,
    "run-out": run_out,
    "run-out-sweep": run_out_sweep, "run-out-film": run_out_film, "run-out-cfl": run_out_cfl,
    "cap": cap,
    "similarity": similarity, "passive-limit": passive_limit,
}  # fmt: skip

if __name__ == "__main__":
    for name in sys.argv[1:] or list(CHECKS):
        print(f"\n### {name}\n")
        CHECKS[name]()
