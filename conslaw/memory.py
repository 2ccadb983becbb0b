"""How much memory a run needs and how much this process may still use, checked before a run
allocates anything (docs/output.md, "Nothing lost": a run too large for the machine is one line,
not a MemoryError half-way)."""

from __future__ import annotations

import os
from pathlib import Path

#: Copies of the state a run holds at once, besides those of its output times: the scheme's three
#: buffers, the initial and the current state and temporaries of the same size.
STATE_COPIES = 7
#: Copies of the model's coefficients: cell centres and two quarter points for each of the two
#: cell families, and temporaries.
AUX_COPIES = 8
#: Fixed cost of the process beyond the arrays of the run (interpreter, numba, matplotlib).
BASE_BYTES = 300 * 2**20


def run_bytes(n_cells: int, n_vars: int, n_aux: int, n_outputs: int) -> int:
    """A generous estimate of the bytes a run of ``n_cells`` cells needs: its state copies and
    coefficient rows, and per output time the stored state, its exact cell averages and its
    coefficients (float64)."""
    per_cell = n_vars * (STATE_COPIES + 2 * n_outputs) + n_aux * (AUX_COPIES + n_outputs)
    return BASE_BYTES + 8 * n_cells * per_cell


def available_bytes() -> int | None:
    """The memory this process may still allocate: the least of what the address-space limit
    (``RLIMIT_AS``), the control group's limit and the system's available memory leave, or None
    where none of them can be read (not Linux)."""
    room: list[int] = []
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft != resource.RLIM_INFINITY:
            room.append(soft - _virtual_size())
    except (ImportError, OSError, ValueError):
        pass
    limit = _read_int(Path("/sys/fs/cgroup/memory.max"))
    used = _read_int(Path("/sys/fs/cgroup/memory.current"))
    if limit is not None and used is not None:
        room.append(limit - used)
    meminfo = _meminfo_available()
    if meminfo is not None:
        room.append(meminfo)
    return min(room) if room else None


def _virtual_size() -> int:
    """This process's virtual memory size in bytes (Linux ``/proc/self/statm``)."""
    pages = int(Path("/proc/self/statm").read_text().split()[0])
    return pages * os.sysconf("SC_PAGE_SIZE")


def _read_int(path: Path) -> int | None:
    try:
        text = path.read_text().strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None


def _meminfo_available() -> int | None:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None
