"""The writer of a run's folder: every format of ``output.formats`` at each output time, all or
nothing, one run per folder at a time (docs/output.md)."""

from __future__ import annotations

import contextlib
import os
import re
import weakref
from collections.abc import Callable
from contextlib import suppress
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from conslaw import signals
from conslaw.errors import OutputError
from conslaw.output.fields import SERIES, cell_fields, mesh_points_cells, output_field_data
from conslaw.output.files import OutputCommit, hold_folder, prepare_output_dir, toml_bytes
from conslaw.output.npz import states_bytes
from conslaw.output.tables import fields_csv, margins_csv_bytes
from conslaw.output.vtu import pvd_document, vtu_bytes
from conslaw.output.xdmf import h5_bytes, xdmf_document
from conslaw.provenance import record, toml_comment

#: Writes a run's figures into a folder and returns their paths.
FigureWriter = Callable[["RunResult", Path], list[Path]]

if TYPE_CHECKING:
    from conslaw.config import Scene
    from conslaw.result import RunResult

Array = NDArray[np.float64]


#: Names of the files conslaw writes into a run folder (at the end of a run, those it did not
#: write this time are left over from an earlier run into the same folder, and removed).
#: A temporary file of :func:`write_temporary` (``.<name>.<8 random characters>.tmp``).
_TEMPORARY = re.compile(r"\.(.+)\.[^.]{8}\.tmp")
_OWN_FILE = re.compile(
    rf"^({SERIES}(-(\d{{5}}|mesh)\.(h5|vtu|csv)|\.xdmf|\.pvd)"
    r"|states\.npz|margins\.csv|(profiles|margins|chute|xt|map|cuts)\.png|hazard\.json"
    r"|(peak_depth|peak_speed|peak_pressure|deposit)\.(tif|png)|flow_depth\.gif)$"
)


class RunWriter:
    """Writes a run's files as the run reaches each output time.

    Pass it as ``on_output`` to :func:`conslaw.simulation.simulate` and call :meth:`finish` at
    the end (figures, removal of series files an earlier run left behind). The folder is made
    with the first output, so a run that fails before writes nothing. See the module docstring
    for the files of every format. ``figures(result, folder)`` writes the figures and returns
    their paths (with ``output.plot``; e.g. :func:`conslaw.figure_worker.write_figures`).
    """

    def __init__(self, folder: Path, scene: Scene, figures: FigureWriter | None = None) -> None:
        self.folder = Path(folder)
        self.scene = scene
        self.figures = figures
        self.formats = scene.output_formats
        self.last_time: float | None = None
        self._claim: int | None = None
        self._files: dict[Path, None] = {}
        self._mesh: tuple[Array, NDArray[np.int64]] | None = None
        self._xdmf: list[tuple[float, str, list[str], dict[str, float]]] = []
        self._pvd: list[tuple[float, str]] = []
        self._provenance: dict[str, str] | None = None

    @property
    def provenance(self) -> dict[str, str]:
        """What made the run and what it read (:mod:`conslaw.provenance`), taken once, at the
        first output."""
        if self._provenance is None:
            self._provenance = record(self.scene)
        return self._provenance

    @property
    def files(self) -> list[Path]:
        """Every file written so far, in the order first written."""
        return list(self._files)

    def claim(self) -> None:
        """Hold the output folder for this run (if it exists yet; :meth:`output` claims it when
        it makes it): an advisory lock (``flock``) on the folder, released by :meth:`release`,
        :meth:`finish` or the end of the process. A folder another run holds, in this process or
        another, is a ConfigError naming it, before anything is written (docs/output.md)."""
        if self._claim is not None:
            return
        handle = hold_folder(self.folder)
        if handle is None:
            return
        self._claim = handle
        # Closed when the writer is dropped without release() (a failed run in a notebook).
        self._finalizer = weakref.finalize(self, os.close, handle)

    def release(self) -> None:
        """Let other runs write into the folder again."""
        if self._claim is not None:
            self._finalizer()  # closes the descriptor once
            self._claim = None

    def scene_bytes(self) -> bytes:
        """``scene.toml``: the provenance as comment lines, then the resolved scene, with input
        files named relative to the output folder (so that the folder and its inputs can move
        together and the scene still runs from it)."""
        table = self.scene.to_table()
        for key, value in table["parameters"].items():
            if key.endswith("_file") and isinstance(value, str) and Path(value).is_absolute():
                # On another drive (Windows) relpath fails: the absolute path stays.
                with contextlib.suppress(ValueError):
                    table["parameters"][key] = os.path.relpath(value, self.folder.resolve())
        return toml_comment(self.provenance).encode() + toml_bytes(table)

    def _wrote(self, path: Path) -> None:
        self._files.pop(path, None)
        self._files[path] = None

    def __call__(self, result: RunResult) -> None:
        """Write the newest output of ``result`` (its last state) and the files holding the
        whole history (``states.npz``, ``margins.csv``), all or nothing."""
        self.write(result, len(result.states) - 1, history=True)

    def write(self, result: RunResult, index: int, history: bool) -> None:
        """Output ``index`` of ``result`` (and, with ``history``, ``states.npz`` and
        ``margins.csv`` of the outputs up to it) as one :class:`OutputCommit`: if any file
        cannot be written, none is put in place and :class:`~conslaw.errors.OutputError` names
        the cause. The first output also removes what an earlier run left in the folder under
        conslaw's names, once the new files are in place, so the folder holds either the
        earlier run intact or this run's outputs so far, never a mixture."""
        first = not self._files
        t = result.states[index].t
        if first:
            self.claim()  # before the writability probe, if the folder exists
            prepare_output_dir(self.folder)
            self.claim()
        commit = OutputCommit()
        kept = (dict(self._files), len(self._xdmf), len(self._pvd))
        with signals.held():
            try:
                self._check_folder()
                if first:
                    commit.put(self.folder / "scene.toml", self.scene_bytes())
                    self._wrote(self.folder / "scene.toml")
                self.output(result, index, commit)
                if history:
                    self.history(result, commit)
                commit.apply()
            except BaseException as error:
                commit.undo()
                self._files = kept[0]
                del self._xdmf[kept[1] :], self._pvd[kept[2] :]
                if isinstance(error, OSError):
                    message = self._failure(f"the output at t={t:.6g}", error)
                    raise OutputError(message) from None
                raise
            self.last_time = t
            if first:
                self._remove_earlier_run()

    def _failure(self, what: str, error: OSError) -> str:
        reason = error.strerror or str(error)
        name = f" ({Path(error.filename).name})" if error.filename else ""
        return f"cannot write {what} into '{self.folder}': {reason}{name}"

    def _check_folder(self) -> None:
        """The claimed folder is still the one at the output path (not removed or replaced)."""
        if self._claim is None:
            return
        held, there = os.fstat(self._claim), os.stat(self.folder)
        if (held.st_dev, held.st_ino) != (there.st_dev, there.st_ino):
            raise FileNotFoundError(0, "the folder was removed or replaced during the run")

    def _remove_earlier_run(self) -> None:
        """Remove files under conslaw's names that this run did not write (an earlier run's),
        and temporary files a killed run left; as far as possible (what cannot be removed
        stays)."""
        for entry in self.folder.iterdir():
            stale = _OWN_FILE.match(entry.name) and entry not in self._files
            temporary = _TEMPORARY.fullmatch(entry.name)
            own = temporary is not None and (
                _OWN_FILE.match(temporary.group(1)) or temporary.group(1) == "scene.toml"
            )
            if stale or own:
                with suppress(OSError):
                    entry.unlink(missing_ok=True)

    def output(self, result: RunResult, index: int, commit: OutputCommit) -> None:
        """Stage the series files of output ``index`` (XDMF/HDF5, VTU, CSV), then their
        indexes, in ``commit``."""
        if not {"xdmf", "vtu", "csv"} & set(self.formats):
            return
        state = result.states[index]
        fields = cell_fields(result, index)
        data = output_field_data(result, index)
        stem = f"{SERIES}-{index:05d}"
        if self._mesh is None:
            self._mesh = mesh_points_cells(result.grid.edges)
        points, cells = self._mesh
        folder = self.folder
        if "xdmf" in self.formats:
            mesh_file = f"{SERIES}-mesh.h5"
            if not self._xdmf:
                mesh = {"points": points, "cells": cells}
                self._wrote(commit.put(folder / mesh_file, h5_bytes(mesh)))
            self._wrote(commit.put(folder / f"{stem}.h5", h5_bytes({**fields, **data})))
            self._xdmf.append((state.t, f"{stem}.h5", list(fields), data))
            document = xdmf_document(mesh_file, cells.shape[0], self._xdmf)
            self._wrote(commit.put(folder / f"{SERIES}.xdmf", document))
        if "vtu" in self.formats:
            vtu = commit.put(folder / f"{stem}.vtu", vtu_bytes(points, cells, fields, data))
            self._wrote(vtu)
            self._pvd.append((state.t, vtu.name))
            self._wrote(commit.put(folder / f"{SERIES}.pvd", pvd_document(self._pvd)))
        if "csv" in self.formats:
            table = fields_csv(state.t, state.x, fields)
            self._wrote(commit.put(folder / f"{stem}.csv", table))

    def history(self, result: RunResult, commit: OutputCommit, final: bool = False) -> None:
        """Stage ``states.npz`` (npz) and ``margins.csv`` (csv, front tracking) of the outputs
        so far in ``commit``.

        ``states.npz`` holds every output so far, so it is rewritten at every output time:
        uncompressed during the run (a copy at memory speed; the cost still grows with the
        number of outputs times the grid, so for very many output times of a large grid prefer
        xdmf or vtu, whose cost per output is fixed), compressed once at the end (``final``)."""
        if "npz" in self.formats:
            data = states_bytes(result, compressed=final, provenance=self.provenance)
            self._wrote(commit.put(self.folder / "states.npz", data))
        if "csv" in self.formats and result.margins is not None:
            data = margins_csv_bytes(result.margins)
            self._wrote(commit.put(self.folder / "margins.csv", data))

    def finish(self, result: RunResult) -> list[Path]:
        """The compressed history and the figures (with ``output.plot``); returns every file
        written. An OSError is an :class:`~conslaw.errors.OutputError` (the outputs of the run
        stay complete: the compressed ``states.npz`` replaces the other only when written)."""
        if not self._files:
            self.release()
            return []
        try:
            with signals.held():
                self._check_folder()
                commit = OutputCommit()
                try:
                    self.history(result, commit, final=True)
                    commit.apply()
                finally:
                    commit.undo()
            if self.scene.plot and self.figures is not None:
                for path in self.figures(result, self.folder):
                    self._wrote(path)
        except OSError as error:
            raise OutputError(self._failure("the final files", error)) from None
        finally:
            self.release()
        return self.files


def write_run(result: RunResult, folder: Path, figures: FigureWriter | None = None) -> list[Path]:
    """Write every file of a finished run at once (what :class:`RunWriter` writes during a
    run): the formats of ``output.formats``, the resolved scene and (with ``figures``) the
    figures."""
    writer = RunWriter(folder, result.scene, figures)
    try:
        writer.claim()
        last = len(result.states) - 1
        for index in range(last + 1):
            # The history with the last output: an earlier run's states.npz stays until then.
            writer.write(result, index, history=index == last)
        return writer.finish(result)
    finally:
        writer.release()
