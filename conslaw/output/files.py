"""Writing files safely: atomically (a temporary name, then a rename), several at once as one
commit, into a checked output folder (docs/output.md, "Nothing lost")."""

from __future__ import annotations

import errno
import io
import os
import tempfile
from pathlib import Path
from typing import Any

import tomli_w

from conslaw.errors import ConfigError

try:
    import fcntl
except ImportError:  # Windows: no advisory locks; outputs are written unlocked
    fcntl = None  # type: ignore[assignment]


def _file_mode() -> int:
    """The mode ``open`` gives a new file: ``0o666`` less the process's umask (read once: a
    umask of 0 for a moment on every write would reach files other threads create then)."""
    global _FILE_MODE
    if _FILE_MODE is None:
        umask = os.umask(0)
        os.umask(umask)
        _FILE_MODE = 0o666 & ~umask
    return _FILE_MODE


_FILE_MODE: int | None = None


def atomic_write_bytes(path: Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file and an atomic rename (with the
    permissions of a file made by ``open``, not the owner-only ones of the temporary file)."""
    path = Path(path)
    temporary = write_temporary(path, data)
    try:
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return path


def write_temporary(path: Path, data: bytes) -> Path:
    """``data`` in a new temporary file beside ``path`` (removed again if writing fails), with
    the permissions of a file made by ``open``; the caller renames it into place."""
    path = Path(path)
    handle, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    temporary = Path(name)
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        os.chmod(temporary, _file_mode())
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return temporary


class OutputCommit:
    """The files of one output time, put in place together or not at all.

    :meth:`put` writes each file under a temporary name beside its destination; :meth:`apply`
    renames them all into place: first the files whose names are new (if one of those renames
    fails, the ones already in place are removed again), then those that replace a file (data
    files before the indexes that list them, in the order they were put). :meth:`undo` removes
    the temporary files. A write that fails (a full disk) therefore leaves every file of the
    folder as it was before this output.
    """

    def __init__(self) -> None:
        self._staged: list[tuple[Path, Path]] = []

    def put(self, path: Path, data: bytes) -> Path:
        """Stage ``data`` for ``path``; returns ``path``. An OSError names ``path``."""
        try:
            temporary = write_temporary(path, data)
        except OSError as error:
            if error.filename is None:
                error.filename = str(path)
            raise
        self._staged.append((temporary, Path(path)))
        return Path(path)

    def apply(self) -> None:
        """Rename every staged file into place (new names first; see the class)."""
        new = [pair for pair in self._staged if not pair[1].exists()]
        placed: list[Path] = []
        try:
            for temporary, path in new:
                os.replace(temporary, path)
                placed.append(path)
        except BaseException:
            for path in placed:
                path.unlink(missing_ok=True)
            raise
        self._staged = [pair for pair in self._staged if pair not in new]
        while self._staged:
            temporary, path = self._staged[0]
            os.replace(temporary, path)
            self._staged.pop(0)

    def undo(self) -> None:
        """Remove the staged files not yet in place."""
        for temporary, _ in self._staged:
            temporary.unlink(missing_ok=True)
        self._staged.clear()


def _check_no_nul(folder: Path) -> None:
    """A ConfigError for a folder name holding a NUL byte (no file system takes one; Python's
    file functions raise ValueError)."""
    if "\0" in str(folder):
        raise ConfigError(f"output directory {str(folder)!r}: a name cannot hold a NUL byte")


def check_output_dir(folder: Path) -> Path:
    """Check, without creating anything, that ``folder`` exists as a writable folder or can be
    created (its nearest existing ancestor is a writable folder)."""
    folder = Path(folder)
    _check_no_nul(folder)
    probe = folder
    try:
        os.stat(folder)
    except OSError as error:
        if error.errno not in (errno.ENOENT, errno.ENOTDIR):  # too long a name, a loop, ...
            raise ConfigError(
                f"output directory '{folder}' cannot be used: {error.strerror}"
            ) from None
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
    _check_no_nul(folder)
    if folder.exists() and not folder.is_dir():
        raise ConfigError(f"output directory '{folder}' is a file, not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".probe-"):
            pass
    except OSError as error:
        reason = error.strerror or str(error)
        raise ConfigError(f"output directory '{folder}' is not writable: {reason}") from None
    return folder


def write_toml(path: Path, document: dict[str, Any]) -> Path:
    """Atomic TOML file."""
    return atomic_write_bytes(path, toml_bytes(document))


def toml_bytes(document: dict[str, Any]) -> bytes:
    """A TOML document as UTF-8 bytes."""
    return tomli_w.dumps(document).encode()


def write_figure(path: Path, figure: Any) -> Path:
    """Atomic PNG of a matplotlib figure."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=120)
    return atomic_write_bytes(path, buffer.getvalue())


def hold_folder(folder: Path, holder: str = "conslaw run") -> int | None:
    """Hold ``folder`` for one writer: an advisory lock (``flock``) on it; returns the open
    descriptor to close when done (None where there is no lock: no ``flock`` on this system or
    file system, or a folder that cannot be opened). A folder another writer holds, in this
    process or another, is a ConfigError naming it and ``holder``, before anything is written
    (docs/output.md, "Nothing lost")."""
    if fcntl is None or not Path(folder).is_dir():
        return None
    try:
        handle = os.open(folder, os.O_RDONLY)
    except OSError:
        return None  # not readable, or gone: prepare_output_dir reports what matters
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(handle)
        raise ConfigError(
            f"output folder '{folder}' is being written by another {holder}; wait for it to "
            "end or choose another output folder"
        ) from None
    except OSError:  # no flock here (some network file systems): unlocked
        os.close(handle)
        return None
    return handle
