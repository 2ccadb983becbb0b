"""Where a run's output came from: the software that made it and the input files it read.

Recorded with every run's output (docs/output.md, "Provenance"): as comment lines at the top of
``scene.toml`` (which stays a loadable scene), as the ``provenance`` entry of ``states.npz`` (a
JSON object) and as an attribute of :meth:`conslaw.result.RunResult.to_xarray`. Nothing in it
depends on the time of the run, so that the same run writes the same bytes.
"""

from __future__ import annotations

import functools
import hashlib
import json
import platform
import subprocess
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from conslaw.config import Scene

#: Read in blocks of this size when hashing an input file.
_BLOCK = 1 << 20


@functools.lru_cache(maxsize=1)
def source_commit() -> str:
    """The git commit of the conslaw source tree this package runs from (with ``+`` if its
    files differ from it), or ``""`` for an installed copy outside a git checkout."""
    root = Path(__file__).resolve().parents[1]
    if not (root / ".git").exists():
        return ""
    try:
        commit = subprocess.run(
            ["git", "-C", str(root), "rev-parse", "HEAD"],
            capture_output=True, text=True, timeout=10, check=True,
        ).stdout.strip()  # fmt: skip
        changed = subprocess.run(
            ["git", "-C", str(root), "status", "--porcelain", "--untracked-files=no"],
            capture_output=True, text=True, timeout=10, check=True,
        ).stdout.strip()  # fmt: skip
    except (OSError, subprocess.SubprocessError):
        return ""
    return commit + ("+" if changed else "")


def file_sha256(path: str | Path) -> str:
    """The SHA-256 of a file's bytes (hex), or ``""`` if it cannot be read."""
    digest = hashlib.sha256()
    try:
        with open(path, "rb") as stream:
            for block in iter(lambda: stream.read(_BLOCK), b""):
                digest.update(block)
    except OSError:
        return ""
    return digest.hexdigest()


def input_files(scene: Scene) -> dict[str, str]:
    """The files a scene reads: ``scene`` (its TOML, if it came from one) and every
    ``parameters.*_file``, as given paths."""
    files = {"scene": scene.source_file} if scene.source_file else {}
    for key, value in scene.parameters.items():
        if key.endswith("_file") and isinstance(value, str) and value:
            files[f"parameters.{key}"] = value
    return files


def record(scene: Scene) -> dict[str, str]:
    """Software versions and input files (path and SHA-256) of a run of ``scene``."""
    import numba
    import numpy
    import scipy

    from conslaw import __version__

    entries = {
        "conslaw": __version__,
        "conslaw_commit": source_commit(),
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "numba": numba.__version__,
    }
    for key, path in input_files(scene).items():
        entries[f"{key} path"] = str(path)
        entries[f"{key} sha256"] = file_sha256(path)
    return entries


def as_json(entries: dict[str, str]) -> str:
    """The record as one JSON object (the ``provenance`` entry of ``states.npz``)."""
    return json.dumps(entries, sort_keys=False)


def toml_comment(entries: dict[str, str]) -> str:
    """The record as TOML comment lines, for the top of ``scene.toml``."""
    lines = ["# Written by conslaw; what made this run and what it read:"]
    lines += [f"#   {key} = {value}" for key, value in entries.items() if value]
    return "\n".join(lines) + "\n"
