"""``states.npz``: every output of a run in one numpy archive (docs/output.md)."""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from conslaw.output.files import atomic_write_bytes
from conslaw.provenance import as_json, record
from conslaw.state import node_arrays

if TYPE_CHECKING:
    from conslaw.result import RunResult


def write_npz(path: Path, compressed: bool = True, **arrays: Any) -> Path:
    """Atomic ``numpy.savez_compressed`` (``numpy.savez`` with ``compressed=False``)."""
    return atomic_write_bytes(path, npz_bytes(compressed, **arrays))


def npz_bytes(compressed: bool = True, **arrays: Any) -> bytes:
    """The bytes of ``numpy.savez_compressed`` (``numpy.savez`` with ``compressed=False``)."""
    buffer = io.BytesIO()
    (np.savez_compressed if compressed else np.savez)(buffer, **arrays)
    return buffer.getvalue()


def exact_or_nan(exact: Sequence[Any], values: Sequence[Any]) -> Any:
    """The exact cell averages of every output as one array, NaN where there are none."""
    return np.array(
        [
            e if e is not None else np.full_like(v, np.nan)
            for e, v in zip(exact, values, strict=True)
        ]
    )


def write_states(path: Path, result: RunResult, compressed: bool = True) -> Path:
    """Atomic ``states.npz`` of the outputs so far (:func:`states_bytes`)."""
    return atomic_write_bytes(path, states_bytes(result, compressed))


def states_bytes(
    result: RunResult, compressed: bool = True, provenance: dict[str, str] | None = None
) -> bytes:
    """``states.npz`` of the outputs so far (``compressed=False``: stored without compression,
    as during a run, where it is rewritten at every output time).

    Keys: ``t`` (n_out,), ``x`` (n,), ``edges`` (n + 1,), ``q`` (n_out, n_vars, n),
    ``q_exact`` (exact cell averages, NaN where unknown), ``variables``; with front tracking also
    ``margins`` (rows ``t, x_rear, u_rear, x_front, u_front`` after every step, NaN for a margin
    that does not exist); with the Lagrangian scheme also its own mesh at the output times:
    ``nodes`` and ``node_velocities`` (n_out, n_elements + 1) and ``element_depths``
    (n_out, n_elements) (``q`` is then the conservative projection of the elements onto the
    grid). ``provenance`` (default: :func:`conslaw.provenance.record` of the run's scene) is
    stored as the JSON string ``provenance``.
    """
    if provenance is None:
        provenance = record(result.scene)
    exact = exact_or_nan(result.exact, [state.q for state in result.states])
    return npz_bytes(
        compressed,
        t=np.array([s.t for s in result.states]),
        x=result.grid.centres(),
        edges=result.grid.edges,
        q=np.array([s.q for s in result.states]),
        q_exact=exact,
        variables=np.array(result.model.variables),
        provenance=np.array(as_json(provenance)),
        **({} if result.margins is None else {"margins": result.margins}),
        **node_arrays(result.states),
    )
