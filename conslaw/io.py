"""All file output: npz, XDMF + HDF5 and VTU time series, CSV, TOML and PNG, written atomically.

The public face of :mod:`conslaw.output`, whose modules hold one format each (``npz``, ``xdmf``,
``vtu``, ``tables``), what an output holds (``fields``), safe writing (``files``) and the writer
of a run's folder (``writer``).

Every file is written under a temporary name in the destination folder and renamed into place, so
a run that fails or is interrupted never leaves a half-written file, and files written earlier stay
intact. :class:`RunWriter` writes each output time as the run reaches it (it is the
``on_output`` callback of :func:`conslaw.simulation.simulate`): after an interruption every
output time reached before is complete and readable.

What a run writes into its folder, by ``output.formats`` (nothing else):

``npz``
    ``states.npz``: every output so far (rewritten at each output time; see :func:`write_states`).
``xdmf``
    ``solution.xdmf`` (XDMF 3 temporal collection, for ParaView and
    ``meshio.xdmf.TimeSeriesReader``), ``solution-mesh.h5`` (points and cells) and one
    ``solution-NNNNN.h5`` per output time (the cell fields). meshio's own
    ``TimeSeriesWriter`` writes the XML only when it is closed, so an interrupted run would leave
    no readable series (and it puts the HDF5 file in the current folder, meshio issue #1442);
    here each time's HDF5 file is complete before the small XML index is rewritten to list it.
``vtu``
    one ``solution-NNNNN.vtu`` per output time (through meshio) and ``solution.pvd``, the
    ParaView collection with the times, rewritten after each.
``csv``
    one ``solution-NNNNN.csv`` per output time (``t``, ``x`` and every cell field) and, with
    front tracking, ``margins.csv``.

The mesh of a 1D run is the cell faces as points ``(x, 0, 0)`` and one line cell per grid cell.
The cell fields (:func:`cell_fields`): the conserved variables, the primitive ones
(``Model.primitive_fields``: ``h``, ``u`` for depth-averaged models), the model coefficients
(``Model.coefficient_fields``: ``zeta`` in degrees, ``beta``, ``K``, ``lambda_kappa`` for
Savage–Hutter; ``bed``, ``bed_slope`` for shallow water) and, where an exact solution applies,
its cell averages (``h_exact``, ...). The time and, with front tracking, the margins
(``x_rear``, ``u_rear``, ``x_front``, ``u_front``) are field data (one value per output): VTU
``FieldData``, XDMF ``Information`` elements and datasets in the time's HDF5 file.
Every run also writes ``scene.toml`` (the resolved scene) with its first output, and, with
``output.plot``, the figures at the end.
"""

from __future__ import annotations

from conslaw.output.fields import (
    MARGIN_FIELDS,
    SERIES,
    cell_fields,
    mesh_points_cells,
    output_field_data,
)
from conslaw.output.files import (
    OutputCommit,
    atomic_write_bytes,
    check_output_dir,
    prepare_output_dir,
    toml_bytes,
    write_figure,
    write_temporary,
    write_toml,
)
from conslaw.output.npz import npz_bytes, states_bytes, write_npz, write_states
from conslaw.output.tables import MARGIN_COLUMNS, fields_csv, margins_csv_bytes, write_margins_csv
from conslaw.output.vtu import pvd_document, vtu_bytes
from conslaw.output.writer import FigureWriter, RunWriter, write_run
from conslaw.output.xdmf import h5_bytes, write_h5, xdmf_document

__all__ = [
    "MARGIN_COLUMNS",
    "MARGIN_FIELDS",
    "SERIES",
    "FigureWriter",
    "OutputCommit",
    "RunWriter",
    "atomic_write_bytes",
    "cell_fields",
    "check_output_dir",
    "fields_csv",
    "h5_bytes",
    "margins_csv_bytes",
    "mesh_points_cells",
    "npz_bytes",
    "output_field_data",
    "prepare_output_dir",
    "pvd_document",
    "states_bytes",
    "toml_bytes",
    "vtu_bytes",
    "write_figure",
    "write_h5",
    "write_margins_csv",
    "write_npz",
    "write_run",
    "write_states",
    "write_temporary",
    "write_toml",
    "xdmf_document",
]
