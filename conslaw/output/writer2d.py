"""The writer of a 2D run's folder (docs/output.md, "2D runs"): ``states.npz`` and the XDMF +
HDF5 series of quadrilateral cells, with the same guarantees as a 1D run's
(:class:`~conslaw.output.writer.RunWriter`: all or nothing at each output time, one run per
folder at a time, an earlier run's files replaced only once the new ones are in place)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from conslaw.output.fields import SERIES
from conslaw.output.fields2d import cell_fields_2d, quad_mesh, states_bytes_2d
from conslaw.output.files import OutputCommit
from conslaw.output.writer import RunWriter
from conslaw.output.xdmf import h5_bytes, xdmf_document


class RunWriter2D(RunWriter):
    """:class:`~conslaw.output.writer.RunWriter` for a
    :class:`~conslaw.simulation2d.RunResult2D`: pass it as ``on_output`` to
    :func:`conslaw.simulation2d.simulate_2d` and call :meth:`finish` at the end.
    ``figures(result, folder)`` draws the figures (:func:`conslaw.plotting2d.write_figures_2d`);
    ``final_files(result, folder, formats)`` gives files written with the final history, all
    or nothing (the hazard maps, :func:`conslaw.terrain.hazard_maps.hazard_output_files`).
    """

    def __init__(
        self, folder: Path, scene: Any, figures: Any = None, final_files: Any = None
    ) -> None:
        super().__init__(folder, scene, figures)
        self._mesh_2d: Any = None
        self._final_files = final_files

    def __call__(self, result: Any) -> None:
        """Write the newest output of ``result`` and ``states.npz``, all or nothing."""
        super().__call__(result)

    def output(self, result: Any, index: int, commit: OutputCommit) -> None:
        """Stage output ``index`` as ``solution-NNNNN.h5`` (the cell fields and the time) and
        the rewritten ``solution.xdmf`` (xdmf), the mesh with the first."""
        if "xdmf" not in self.formats:
            return
        grid = result.grid
        if self._mesh_2d is None:
            self._mesh_2d = quad_mesh(grid.x.edges, grid.y.edges)
        points, cells = self._mesh_2d
        state = result.states[index]
        fields = cell_fields_2d(result, index)
        data = {"t": float(state.t)}
        stem = f"{SERIES}-{index:05d}"
        mesh_file = f"{SERIES}-mesh.h5"
        if not self._xdmf:
            mesh = {"points": points, "cells": cells}
            self._wrote(commit.put(self.folder / mesh_file, h5_bytes(mesh)))
        self._wrote(commit.put(self.folder / f"{stem}.h5", h5_bytes({**fields, **data})))
        self._xdmf.append((state.t, f"{stem}.h5", list(fields), data))
        document = xdmf_document(
            mesh_file, cells.shape[0], self._xdmf, (grid.x.n_cells, grid.y.n_cells)
        )
        self._wrote(commit.put(self.folder / f"{SERIES}.xdmf", document))

    def finish(self, result: Any) -> list[Path]:
        """As :meth:`RunWriter.finish`: the compressed ``states.npz`` and the figures."""
        return super().finish(result)

    def history(self, result: Any, commit: OutputCommit, final: bool = False) -> None:
        """Stage ``states.npz`` of the outputs so far (npz), compressed at the end; at the end
        also the ``final_files``."""
        if "npz" in self.formats:
            data = states_bytes_2d(result, self.provenance, compressed=final)
            self._wrote(commit.put(self.folder / "states.npz", data))
        if final and self._final_files is not None:
            for path, data in self._final_files(result, self.folder, self.formats).items():
                self._wrote(commit.put(path, data))
