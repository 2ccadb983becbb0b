"""All file output: atomic writes of npz, TOML and PNG.

Every file is written under a temporary name in the destination folder and renamed into place, so
a run that fails or is interrupted never leaves a half-written file, and files written earlier stay
intact.
"""

from __future__ import annotations

import io
import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from conslaw import tomlwrite
from conslaw.errors import ConfigError
from conslaw.state import node_arrays

if TYPE_CHECKING:
    from conslaw.simulation import RunResult


def atomic_write_bytes(path: Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file and an atomic rename."""
    path = Path(path)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return path


def check_output_dir(folder: Path) -> Path:
    """Check, without creating anything, that ``folder`` exists as a writable folder or can be
    created (its nearest existing ancestor is a writable folder)."""
    folder = Path(folder)
    probe = folder
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK | os.X_OK):
        reason = "not a folder" if probe.exists() and not probe.is_dir() else "permission denied"
        raise ConfigError(f"output directory '{folder}' is not writable: {reason} ('{probe}')")
    return folder


def prepare_output_dir(folder: Path) -> Path:
    """Create ``folder`` if needed and check that it is writable, before any work is done."""
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".probe-"):
            pass
    except OSError as error:
        reason = error.strerror or str(error)
        raise ConfigError(f"output directory '{folder}' is not writable: {reason}") from None
    return folder


def write_npz(path: Path, **arrays: Any) -> Path:
    """Atomic ``numpy.savez_compressed``."""
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    return atomic_write_bytes(path, buffer.getvalue())


def write_toml(path: Path, document: dict[str, Any]) -> Path:
    """Atomic TOML file."""
    return atomic_write_bytes(path, tomlwrite.dumps(document).encode())


def write_figure(path: Path, figure: Any) -> Path:
    """Atomic PNG of a matplotlib figure."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=120)
    return atomic_write_bytes(path, buffer.getvalue())


MARGIN_COLUMNS = ("t", "x_rear", "u_rear", "x_front", "u_front")


def write_margins_csv(path: Path, margins: Any) -> Path:
    """Atomic CSV of the margin history (columns :data:`MARGIN_COLUMNS`, empty for NaN)."""
    lines = [",".join(MARGIN_COLUMNS)]
    for row in np.asarray(margins):
        lines.append(",".join("" if np.isnan(v) else repr(float(v)) for v in row))
    return atomic_write_bytes(path, ("\n".join(lines) + "\n").encode())


def write_run(result: RunResult, folder: Path) -> list[Path]:
    """Write the states (npz), the resolved scene (TOML) and, if asked, the profile plot (PNG).

    ``states.npz`` holds ``t`` (n_out,), ``x`` (n,), ``q`` (n_out, n_vars, n), ``variables``,
    ``edges``, and ``q_exact`` (exact cell averages, NaN where unknown); with front tracking also
    ``margins`` (rows ``t, x_rear, u_rear, x_front, u_front`` after every step, NaN for a margin
    that does not exist), which is also written as ``margins.csv`` and plotted in
    ``margins.png``; with the Lagrangian scheme also its own mesh at the output times: ``nodes``
    and ``node_velocities`` (n_out, n_elements + 1) and ``element_depths`` (n_out, n_elements)
    (``q`` is then the conservative projection of the elements onto the grid).
    """
    folder = prepare_output_dir(folder)
    written = []
    scene = result.scene
    if "npz" in scene.output_formats:
        exact = np.array(
            [
                e if e is not None else np.full_like(s.q, np.nan)
                for e, s in zip(result.exact, result.states, strict=True)
            ]
        )
        written.append(
            write_npz(
                folder / "states.npz",
                t=np.array([s.t for s in result.states]),
                x=result.grid.centres(),
                edges=result.grid.edges,
                q=np.array([s.q for s in result.states]),
                q_exact=exact,
                variables=np.array(result.model.variables),
                **({} if result.margins is None else {"margins": result.margins}),
                **node_arrays(result.states),
            )
        )
    if result.margins is not None:
        written.append(write_margins_csv(folder / "margins.csv", result.margins))
    written.append(write_toml(folder / "scene.toml", scene.to_table()))
    if scene.plot:
        import matplotlib.pyplot as plt

        from conslaw.plotting import chute_figure, margins_figure, profiles_figure

        figures = [("profiles.png", profiles_figure)]
        if result.margins is not None:
            figures.append(("margins.png", margins_figure))
        if getattr(result.model, "chute", None) is not None:
            figures.append(("chute.png", chute_figure))
        for name, build in figures:
            figure = build(result)
            written.append(write_figure(folder / name, figure))
            plt.close(figure)
    return written
