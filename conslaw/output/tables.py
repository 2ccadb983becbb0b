"""CSV tables: the cell fields of one output time and the margin trajectories."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.output.files import atomic_write_bytes

Array = NDArray[np.float64]


MARGIN_COLUMNS = ("t", "x_rear", "u_rear", "x_front", "u_front")


def write_margins_csv(path: Path, margins: Any) -> Path:
    """Atomic CSV of the margin history (columns :data:`MARGIN_COLUMNS`, empty for NaN)."""
    return atomic_write_bytes(path, margins_csv_bytes(margins))


def margins_csv_bytes(margins: Any) -> bytes:
    """CSV of the margin history (columns :data:`MARGIN_COLUMNS`, empty for NaN)."""
    lines = [",".join(MARGIN_COLUMNS)]
    for row in np.asarray(margins):
        lines.append(",".join("" if np.isnan(v) else repr(float(v)) for v in row))
    return ("\n".join(lines) + "\n").encode()


def fields_csv(t: float, x: Array, fields: dict[str, Array]) -> bytes:
    """CSV of one output time: columns ``t``, ``x`` and every field, one row per cell, numbers
    written with 17 significant digits (read back exactly)."""
    table = np.column_stack([np.full(x.shape, t), x, *fields.values()])
    buffer = io.StringIO()
    np.savetxt(buffer, table, fmt="%.17g", delimiter=",")
    return (",".join(["t", "x", *fields]) + "\n" + buffer.getvalue()).encode()
