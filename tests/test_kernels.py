"""The fused compiled NT kernel: blocks of cells, rotated buffers, no allocation per step.

The property tests compare the compiled step with the numpy reference on grids of up to 64 cells,
all inside the kernel's first block of cells. Here the grids span several blocks (the last one
partial), and the model variants with a bed (balanced source, surface reconstruction) and with a
per-cell earth-pressure coefficient are included.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import make_scheme
from numba.core.runtime import _nrt_python, rtsys

from conslaw import registry
from conslaw.errors import InadmissibleStateError
from conslaw.grid import Grid
from conslaw.schemes.base import BoundarySpec
from conslaw.schemes.nessyahu_tadmor import NessyahuTadmor
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


def test_thin_tail_velocity_bound_matches_reference_in_a_later_block(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A cap sliding down an 89-degree chute leaves a thin tail in the kernel's second block of
    cells. The kernel bounds tail velocities in a second pass over the block
    (``bound_tail_velocities``); every step equals the numpy reference to ``1e-12 max|q|``, and
    the bound changes at least one new cell in that block (checked against the reference with
    the bound switched off, ``THIN_TAIL = 0``)."""
    from stability_cases import _cap, scheme

    import conslaw.schemes.nessyahu_tadmor as nt_module

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
            patch.setattr(nt_module, "THIN_TAIL", 0.0)
            unbounded = nt.reference_step(state, dt)
        bounded_cells.extend(np.flatnonzero(unbounded.q[1] != reference.q[1]))
        state = compiled
    assert any(block <= cell < 2 * block for cell in bounded_cells), bounded_cells
