"""What numba's set-up costs a fresh process before the first compiled call returns, with the
function already in numba's cache (docs/performance.md, "The whole conslaw run process").

    python benchmarks/numba_first_call.py [--runs 5]

Writes a one-line ``@njit(cache=True)`` function into a temporary folder, calls it once to fill
the cache, then in ``--runs`` fresh processes times ``import numba`` and the first call (the
cache load and numba's target set-up), and in as many others ``import scipy.linalg`` after
numpy and numba (what numba's BLAS check imports at its set-up). Prints the medians.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

KERNEL = (
    "import numba\n\n\n@numba.njit(cache=True)\ndef first(values):\n    return values[0] + 1.0\n"
)

FIRST_CALL = (
    "import json, sys, time\n"
    "import numpy\n"
    "started = time.perf_counter()\n"
    "import numba\n"
    "imported = time.perf_counter()\n"
    "import kernel\n"
    "kernel.first(numpy.zeros(3))\n"
    "called = time.perf_counter()\n"
    "print(json.dumps([imported - started, called - imported]))\n"
)

SCIPY_LINALG = (
    "import json, time\n"
    "import numpy, numba\n"
    "started = time.perf_counter()\n"
    "import scipy.linalg\n"
    "print(json.dumps(time.perf_counter() - started))\n"
)


def measured(code: str, folder: Path) -> Any:
    """The JSON a fresh Python process running ``code`` in ``folder`` prints."""
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=folder, check=True, capture_output=True, text=True
    )
    return json.loads(done.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="numba-first-call-") as name:
        folder = Path(name)
        (folder / "kernel.py").write_text(KERNEL)
        measured(FIRST_CALL, folder)  # compiles and fills the cache
        calls = [measured(FIRST_CALL, folder) for _ in range(args.runs)]
        linalg = [measured(SCIPY_LINALG, folder) for _ in range(args.runs)]
    imports = statistics.median(float(c[0]) for c in calls)
    first = statistics.median(float(c[1]) for c in calls)
    print(f"import numba: {imports:.3f} s (median of {args.runs})")
    print(f"first call of a cached one-line function: {first:.3f} s")
    print(f"of which import scipy.linalg (numba's BLAS check): {statistics.median(linalg):.3f} s")


if __name__ == "__main__":
    main()
