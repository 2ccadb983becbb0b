"""The fused compiled NT kernel: blocks of cells, rotated buffers, no allocation per step.

The property tests compare the compiled step with the numpy reference on grids of up to 64 cells,
all inside the kernel's first block of cells. Here the grids span several blocks (the last one
partial), and the model variants with a bed (balanced source, surface reconstruction) and with a
per-cell earth-pressure coefficient are included.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import make_scheme
from numba.core.runtime import _nrt_python, rtsys

from conslaw import registry
from conslaw.errors import InadmissibleStateError
from conslaw.grid import Grid
from conslaw.schemes.base import BoundarySpec
from conslaw.schemes.nessyahu_tadmor.scheme import NessyahuTadmor
from conslaw.state import State

CASES = {
    "burgers, weno5, periodic": ("burgers", {}, "weno5", "periodic"),
    "shallow water, mc, outflow": ("shallow-water", {}, "mc", "outflow"),
    "shallow water over a bump, mc, wall": (
        "shallow-water",
        {"bump_height": 0.5, "bump_centre": 0.0, "bump_width": 1.0},
        "mc",
        "wall",
    ),
    "savage-hutter with K_act != K_pass, superbee, outflow": (
        "savage-hutter",
        {"phi": 35.0, "delta": 25.0, "epsilon": 0.5},
        "superbee",
        "outflow",
    ),
}


def scheme_for(case: str, n_cells: int) -> NessyahuTadmor:
    model_name, parameters, reconstructor, boundary = CASES[case]
    model = registry.models.get(model_name)(**parameters)
    side = BoundarySpec(registry.boundaries.get(boundary))
    return NessyahuTadmor(
        model, registry.reconstructors.get(reconstructor), Grid(-5.0, 5.0, n_cells), side, side
    )


def test_a_plugin_reconstructor_steps_as_the_built_in_one(rng: np.random.Generator) -> None:
    """A reconstructor without a built-in code (as a plugin registers one) is compiled into the
    kernel; its steps equal, to the last bit, those of the built-in reconstructor with the same
    slope function, which the kernel picks at run time."""
    built_in = scheme_for("burgers, weno5, periodic", 300)
    plugin = replace(built_in.reconstructor, name="plugin-weno5", code=None)
    side = BoundarySpec(registry.boundaries.get("periodic"))
    compiled_in = NessyahuTadmor(built_in.model, plugin, built_in.grid, side, side)
    assert compiled_in.kernels.__name__ != built_in.kernels.__name__
    state = rough_state(built_in, rng)
    dt = 0.9 * built_in.stable_dt(state)
    assert np.array_equal(compiled_in.step(state, dt).q, built_in.step(state, dt).q)
    assert not np.array_equal(compiled_in.step(state, dt).q, state.q)


def rough_state(scheme: NessyahuTadmor, rng: np.random.Generator) -> State:
    """Smooth waves, jumps, and (for a depth model) dry stretches at rest."""
    x = scheme.grid.centres()
    n = x.size
    smooth = np.sin(0.7 * x) + 0.3 * np.cos(2.3 * x)
    jumps = np.where(rng.random(n) < 0.05, rng.normal(size=n), 0.0).cumsum()
    model = scheme.model
    if model.depth_index is None:
        q = (0.4 * smooth + 0.2 * jumps)[None, :]
    else:
        depth = np.maximum(1.0 + 0.3 * smooth + 0.1 * jumps, 0.0)
        depth[(x > -1.0) & (x < -0.3)] = 0.0
        momentum = np.where(depth > 0.0, depth * 0.5 * np.cos(1.3 * x), 0.0)
        q = np.vstack([depth, momentum])
    return State(0.0, x, np.ascontiguousarray(q), 0.0)


@pytest.mark.parametrize("case", list(CASES))
def test_compiled_step_matches_reference_across_blocks(case: str, rng: np.random.Generator) -> None:
    """Both cell families (n and n + 1 cells) over three blocks, the last one partial:
    compiled and numpy steps agree to ``1e-12 max|q|``."""
    probe = scheme_for(case, 16)
    block = probe.kernels.BLOCK
    scheme = scheme_for(case, 2 * block + 45)
    state = rough_state(scheme, rng)
    for family in ("offset 0 -> 1/2", "offset 1/2 -> 0"):
        dt = 0.9 * scheme.stable_dt(state)
        compiled = scheme.step(state, dt)
        reference = scheme.reference_step(state, dt)
        error = np.abs(compiled.q - reference.q).max()
        assert error <= 1e-12 * np.abs(state.q).max(), f"{case}, {family}: {error:.3e}"
        state = compiled


def test_advance_across_blocks_equals_repeated_steps() -> None:
    """The fused time loop (rotating its three buffers) takes the same steps as the one-step
    interface, on a dam break over several blocks."""
    scheme = scheme_for("shallow water, mc, outflow", 3 * 256 + 1)
    x = scheme.grid.centres()
    depth = np.where(x < 0.0, 3.0, 1.0)
    state = State(0.0, x, np.vstack([depth, np.zeros_like(x)]), 0.0)
    t_end = 0.4
    fused = scheme.advance(state, t_end)
    current = state
    for _ in range(fused.steps // 2):
        dt = scheme.stable_dt(current)
        if 2 * dt >= t_end - current.t:
            dt = 0.5 * (t_end - current.t)
        half = scheme.step(current, dt)
        if dt >= 0.5 * scheme.stable_dt(half) / scheme.cfl:
            # The second half step would reach Courant number 1/2: the pair is redone.
            dt = scheme.stable_dt(half)
            half = scheme.step(current, dt)
        current = scheme.step(half, dt)
    assert current.t == pytest.approx(t_end, rel=1e-14)
    np.testing.assert_allclose(current.q, fused.state.q, rtol=0.0, atol=1e-13)


def test_inadmissible_cell_in_a_later_block_is_named() -> None:
    scheme = make_scheme(n_cells=700, boundary="outflow")
    q = np.full((1, 700), 0.5)
    q[0, 555] = np.nan
    with pytest.raises(InadmissibleStateError, match=r"step 0, cell 555 "):
        scheme.advance(State(0.0, scheme.grid.centres(), q), 0.1)


def test_no_allocation_per_step() -> None:
    """Advancing 100 times as many step pairs makes as many allocations: none per step."""
    scheme = scheme_for("shallow water over a bump, mc, wall", 600)
    state = rough_state(scheme, np.random.default_rng(7))
    dt = scheme.stable_dt(state)
    scheme.advance(state, 2 * dt)  # compile or load
    enabled = _nrt_python.memsys_stats_enabled()
    _nrt_python.memsys_enable_stats()
    try:
        counts, steps = [], []
        for pairs in (2, 200):
            before = rtsys.get_allocation_stats().alloc
            steps.append(scheme.advance(state, pairs * 2 * dt).steps)
            counts.append(rtsys.get_allocation_stats().alloc - before)
    finally:
        if not enabled:
            _nrt_python.memsys_disable_stats()
    assert steps[1] >= 50 * steps[0]
    assert counts[0] == counts[1], f"allocations for {steps} steps: {counts}"


def test_film_velocity_bound_matches_reference_in_a_later_block(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A cap sliding down an 89-degree chute leaves a thin tail in the kernel's second block of
    cells. The kernel bounds tail velocities in a second pass over the block
    (``bound_film_velocities``); every step equals the numpy reference to ``1e-12 max|q|``, and
    the bound changes at least one new cell in that block (checked against the reference with
    the bound switched off, ``FILM = 0``)."""
    from stability_cases import _cap, scheme

    import conslaw.schemes.nessyahu_tadmor.scheme as nt_module

    nt = scheme("savage-hutter", {"zeta": 89.0, "phi": 30.0, "delta": 30.0}, Grid(0, 60, 600))
    block = nt.kernels.BLOCK
    height = _cap(nt.grid, 34.0, 1.0, 1.0)
    state = State(0.0, nt.grid.centres(), np.vstack([height, 0.0 * height]))
    bounded_cells = []
    for _ in range(10):
        dt = nt.stable_dt(state)
        compiled = nt.step(state, dt)
        reference = nt.reference_step(state, dt)
        error = np.abs(compiled.q - reference.q).max()
        assert error <= 1e-12 * np.abs(state.q).max(), f"t={state.t}: {error:.3e}"
        with monkeypatch.context() as patch:
            patch.setattr(nt_module, "FILM", 0.0)
            unbounded = nt.reference_step(state, dt)
        bounded_cells.extend(np.flatnonzero(unbounded.q[1] != reference.q[1]))
        state = compiled
    assert any(block <= cell < 2 * block for cell in bounded_cells), bounded_cells


def test_bound_film_velocities_updates_counts_and_speeds() -> None:
    """The second pass over a block recounts what it changes: two films over a dry bed whose
    velocity range is [.., 0] are stopped (u = 1 and an overflowing u, both bounded to 0).
    Both leave the count of moving cells, the overflowing one the count of cells without a finite
    wave speed, and the SPEED row gets the wave speed of the bounded state."""
    from stability_cases import scheme

    nt = scheme("shallow-water", {}, Grid(0.0, 6.0, 6), "outflow")
    kernels = nt.kernels
    ng = kernels.NG
    src = np.zeros((2, 6 + 2 * ng + 1))
    src[:, ng - 1] = [1.0, -5.0]  # deep, supercritical to the left: range [-7, -3]
    src[:, ng] = [1e-6, -5e-6]  # thin, the same velocity; the cells to the right are dry
    dst = np.zeros_like(src)
    dst[:, ng] = [1e-6, 1e-6]  # a film moving right, u = 1 above the range
    dst[:, ng + 1] = [1e-10, 1e308]  # a thinner film whose velocity overflows
    speeds = kernels.SPEED * kernels.STRIDE + np.arange(2)
    work = np.zeros(kernels.work_size(nt.n_staggered))
    work[speeds] = [1.0 + 1e-3, np.inf]  # |u| + sqrt(g h) before the bound
    aux = nt._aux[0.0][0]
    film = 1e-2  # FILM times the deepest source cell: the cell of depth 1 is flow
    moving_change, bad_change = kernels.bound_film_velocities(
        src, dst, ng, ng, 2, 0.01, aux, aux, nt.params, work, film
    )
    assert (moving_change, bad_change) == (-2, -1)
    np.testing.assert_array_equal(dst[1, ng : ng + 2], [0.0, 0.0])
    np.testing.assert_array_equal(dst[0, ng : ng + 2], [1e-6, 1e-10])
    np.testing.assert_allclose(work[speeds], np.sqrt([1e-6, 1e-10]), rtol=1e-15)


@pytest.mark.parametrize(
    ("model", "parameters", "boundary"),
    [
        ("shallow-water", {}, "outflow"),
        ("savage-hutter", {"zeta": 89.0, "phi": 30.0, "delta": 30.0}, "wall"),
    ],
)
def test_step_returns_the_counts_and_speed_of_its_new_state(
    model: str, parameters: dict[str, float], boundary: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """On random states with thin layers, dry cells and fast flows (over three blocks), what
    ``nt_step`` returns for the time loop (the largest wave speed, the first bad cell, the number
    of moving cells) is what its new state has, although the thin-tail bound changes cells after
    the block's loop counted them. The bound acts in most of these steps and changes the largest
    wave speed in some (found with the reference step with ``FILM = 0``)."""
    from stability_cases import scheme

    import conslaw.schemes.nessyahu_tadmor.scheme as nt_module
    from conslaw.schemes.nessyahu_tadmor.scheme import GHOSTS

    nt = scheme(model, parameters, Grid(0.0, 60.0, 600), boundary)
    kernels = nt.kernels
    aux = nt._aux[0.0]
    aux_dst = nt._aux[0.5][0]
    rng = np.random.default_rng(3)
    bounded = speed_changed = admissible = 0
    for trial in range(100):
        depth = 10.0 ** rng.uniform(-14.0, 1.0, 600)
        depth[rng.random(600) < 0.2] = 0.0
        velocity = rng.normal(0.0, 3.0, 600) * (100.0 if trial % 2 else 1.0)
        state = State(0.0, nt.grid.centres(), np.vstack([depth, depth * velocity]), 0.0)
        dt = 0.9 * nt.stable_dt(state)
        src = np.zeros_like(nt._w0)
        dst = np.zeros_like(nt._w1)
        src[:, GHOSTS : GHOSTS + 600] = state.q
        largest, bad, _, moving = kernels.nt_step(
            src, dst, kernels.Family(600, *aux), kernels.Family(nt.n_staggered, *nt._aux[0.5]),
            -1, dt, nt.grid.dx, nt.params, kernels.Boundary(nt.bc_left, nt.bc_right),
            np.zeros(kernels.work_size(nt.n_staggered)),
        )  # fmt: skip
        # (largest, -1), or (-1, i) at the first inadmissible new cell (a negative depth: the
        # time loop would halve dt), as the kernel's own pass over the new state finds them.
        assert (largest, bad) == kernels.max_speed(dst, nt.n_staggered, aux_dst, nt.params)
        assert moving == kernels.count_moving(dst, nt.n_staggered)
        admissible += bad == -1
        reference = nt.reference_step(state, dt)
        with monkeypatch.context() as patch:
            patch.setattr(nt_module, "FILM", 0.0)
            unbounded = nt.reference_step(state, dt)
        if np.any(unbounded.q[1] != reference.q[1]):
            bounded += 1
            new_aux = aux_dst[:, GHOSTS : GHOSTS + nt.n_staggered]
            speed_changed += bad == -1 and (
                nt.model.max_wave_speed(unbounded.q, new_aux).max()
                != nt.model.max_wave_speed(reference.q, new_aux).max()
            )
    assert admissible >= 30 and bounded >= 50 and speed_changed >= 1, (
        admissible, bounded, speed_changed,
    )  # fmt: skip
