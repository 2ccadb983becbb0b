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


def exact_arrays(exact: Sequence[Any], values: Sequence[Any]) -> dict[str, Any]:
    """``{"q_exact": ...}``, the exact cell averages of every output as one array (NaN at an
    output time without them), or ``{}`` when no output has them (a scene without an exact
    solution: no array of NaN is written).

    Parameters
    ----------
    exact : sequence of numpy.ndarray or None
        The exact cell averages at each output time (``result.exact``), None where unknown.
    values : sequence of numpy.ndarray
        The cell averages at the same times (for the shape of a missing one).

    Returns
    -------
    dict
        The ``q_exact`` entry of ``states.npz``, if any.
    """
    if all(e is None for e in exact):
        return {}
    return {
        "q_exact": np.array(
            [
                e if e is not None else np.full_like(v, np.nan)
                for e, v in zip(exact, values, strict=True)
            ]
        )
    }


def variable_meanings(model: Any) -> Any:
    """What each variable of ``model`` is, with its units where the model has them
    (``Model.long_names``; the name where it has none), as the ``variable_meanings`` array of
    ``states.npz``, in the order of ``variables``.

    Parameters
    ----------
    model : Model

    Returns
    -------
    numpy.ndarray of str
        ``(n_vars,)``.
    """
    return np.array([model.long_names.get(name, name) for name in model.variables])


def write_states(path: Path, result: RunResult, compressed: bool = True) -> Path:
    """Atomic ``states.npz`` of the outputs so far (:func:`states_bytes`)."""
    return atomic_write_bytes(path, states_bytes(result, compressed))


def states_bytes(
    result: RunResult, compressed: bool = True, provenance: dict[str, str] | None = None
) -> bytes:
    """``states.npz`` of the outputs so far (``compressed=False``: stored without compression,
    as during a run, where it is rewritten at every output time).

    Keys: ``t`` (n_out,), ``x`` (n,), ``edges`` (n + 1,), ``q`` (n_out, n_vars, n),
    ``q_exact`` (exact cell averages, NaN at an output time without them; no key at all for a
    scene without an exact solution), ``variables``, ``variable_meanings`` (what each variable
    is, :func:`variable_meanings`); with front tracking also
    ``margins`` (rows ``t, x_rear, u_rear, x_front, u_front`` after every step, NaN for a margin
    that does not exist); with the Lagrangian scheme also its own mesh at the output times:
    ``nodes`` and ``node_velocities`` (n_out, n_elements + 1) and ``element_depths``
    (n_out, n_elements) (``q`` is then the conservative projection of the elements onto the
    grid). ``provenance`` (default: :func:`conslaw.provenance.record` of the run's scene) is
    stored as the JSON string ``provenance``.
    """
    if provenance is None:
        provenance = record(result.scene)
    exact = exact_arrays(result.exact, [state.q for state in result.states])
    return npz_bytes(
        compressed,
        t=np.array([s.t for s in result.states]),
        x=result.grid.centres(),
        edges=result.grid.edges,
        q=np.array([s.q for s in result.states]),
        **exact,
        variables=np.array(result.model.variables),
        variable_meanings=variable_meanings(result.model),
        provenance=np.array(as_json(provenance)),
        **({} if result.margins is None else {"margins": result.margins}),
        **node_arrays(result.states),
    )
