"""Numbers quoted in docs/paper.md and docs/design.md for the Lagrangian scheme:

    python scripts/lagrangian_check.py

1. sh-runout-shock at t = 20: the deposit (largest depth and where, the shock as the largest
   rise of the depth downslope, the front) with NT and with the Lagrangian scheme (mu = 0.02,
   the pressure gradient of Savage & Hutter (1989) and the conservative pressure flux); new extrema
   of the
   element depths on the flat run-out (x >= 25.5) without viscosity; where mu = 0 breaks down.
2. The dry dam break (Ritter): the front of the Lagrangian scheme against the exact x = 4 at t = 2.
"""

from __future__ import annotations

import numpy as np

import conslaw


def local_extrema(values: np.ndarray) -> int:
    steps = np.diff(values)
    steps = steps[steps != 0.0]
    return int(np.sum(steps[:-1] * steps[1:] < 0.0))


def deposit(result: conslaw.RunResult) -> str:
    state = result.final
    if state.nodes is not None:
        x = 0.5 * (state.nodes.positions[:-1] + state.nodes.positions[1:])
        h = state.nodes.depths
        front = state.nodes.positions[-1]
    else:
        x, h = state.x, state.q[0]
        front = x[np.flatnonzero(h > 1e-6)[-1]] + 0.5 * result.grid.dx  # last cell with h > 1e-6
    peak = int(np.argmax(h))
    rise = int(np.argmax(np.diff(h[: peak + 1]))) if peak > 0 else 0
    shock = 0.5 * (x[rise] + x[rise + 1])
    return f"max h {h[peak]:.3f} at x = {x[peak]:.2f}, shock at x = {shock:.2f}, front {front:.2f}"


def main() -> None:
    print("sh-runout-shock, t = 20")
    print(f"  nessyahu-tadmor, mc, 500 cells: {deposit(conslaw.run('sh-runout-shock'))}")
    for pressure in ("gradient", "flux"):
        result = conslaw.run(
            "sh-runout-shock",
            scheme="lagrangian",
            **{"scheme_options.viscosity": 0.02, "scheme_options.pressure": pressure},
        )
        print(f"  lagrangian, mu = 0.02, pressure = {pressure}, 500: {deposit(result)}")
    for n in (200, 500, 1000):
        try:
            result = conslaw.run("sh-runout-shock", scheme="lagrangian", n_cells=n)
        except conslaw.SchemeBreakdownError as error:
            print(f"  lagrangian, mu = 0, {n} elements: breakdown: {error}")
            continue
        nodes = result.final.nodes
        centres = 0.5 * (nodes.positions[:-1] + nodes.positions[1:])
        runout = centres >= 25.5
        print(
            f"  lagrangian, mu = 0, {n} elements: reached t = 20; "
            f"{local_extrema(nodes.depths[runout])} local extrema of h among the "
            f"{runout.sum()} elements on the run-out (x >= 25.5)"
        )
    print("dam-break-dry (Ritter), t = 2, exact front at x = 4, velocity 2")
    for n in (100, 200, 400):
        result = conslaw.run("dam-break-dry", scheme="lagrangian", n_cells=n)
        _, _, _, front, velocity = result.margins[-1]
        print(
            f"  {n} elements: front {front:.3f}, velocity {velocity:.3f}, "
            f"L1(h) {result.headline_error():.3e}"
        )


if __name__ == "__main__":
    main()
