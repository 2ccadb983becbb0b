"""All file output: npz, XDMF + HDF5 and VTU time series, CSV, TOML and PNG, written atomically.

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

import contextlib
import errno
import io
import os
import re
import signal
import tempfile
import threading
import weakref
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import tomli_w
from numpy.typing import NDArray

try:
    import fcntl
except ImportError:  # Windows: no advisory locks, a folder is not claimed
    fcntl = None  # type: ignore[assignment]

from conslaw.errors import ConfigError, OutputError
from conslaw.provenance import as_json, record, toml_comment
from conslaw.state import node_arrays

if TYPE_CHECKING:
    from conslaw.config import Scene
    from conslaw.result import RunResult

Array = NDArray[np.float64]
#: Writes a run's figures into a folder and returns their paths.
FigureWriter = Callable[["RunResult", Path], list[Path]]

#: File stem of the time-series files (``solution.xdmf``, ``solution-00003.vtu``, ...).
SERIES = "solution"
#: Field-data names of the margins (one value per output time), as in ``margins.csv``.
MARGIN_FIELDS = ("x_rear", "u_rear", "x_front", "u_front")


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


def check_output_dir(folder: Path) -> Path:
    """Check, without creating anything, that ``folder`` exists as a writable folder or can be
    created (its nearest existing ancestor is a writable folder)."""
    folder = Path(folder)
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
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".probe-"):
            pass
    except OSError as error:
        reason = error.strerror or str(error)
        raise ConfigError(f"output directory '{folder}' is not writable: {reason}") from None
    return folder


def write_npz(path: Path, compressed: bool = True, **arrays: Any) -> Path:
    """Atomic ``numpy.savez_compressed`` (``numpy.savez`` with ``compressed=False``)."""
    return atomic_write_bytes(path, npz_bytes(compressed, **arrays))


def npz_bytes(compressed: bool = True, **arrays: Any) -> bytes:
    """The bytes of ``numpy.savez_compressed`` (``numpy.savez`` with ``compressed=False``)."""
    buffer = io.BytesIO()
    (np.savez_compressed if compressed else np.savez)(buffer, **arrays)
    return buffer.getvalue()


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


def mesh_points_cells(edges: Array) -> tuple[Array, NDArray[np.int64]]:
    """The 1D mesh: the cell faces as points ``(x, 0, 0)``, shape ``(n + 1, 3)``, and one line
    cell per grid cell, ``(n, 2)`` point indices."""
    edges = np.asarray(edges, dtype=np.float64)
    points = np.zeros((edges.size, 3))
    points[:, 0] = edges
    first = np.arange(edges.size - 1, dtype=np.int64)
    return points, np.ascontiguousarray(np.stack([first, first + 1], axis=1))


def cell_fields(result: RunResult, index: int) -> dict[str, Array]:
    """Every cell field of output ``index``: conserved variables, primitive variables, model
    coefficients (as the scheme uses them in that state) and exact cell averages
    (``<variable>_exact``, only where an exact solution applies). A primitive or coefficient
    field named like a conserved variable is the same quantity and is not repeated."""
    state = result.states[index]
    model = result.model
    fields: dict[str, Array] = {name: state.q[v] for v, name in enumerate(model.variables)}
    for name, values in model.primitive_fields(state.q).items():
        fields.setdefault(name, values)
    coefficients = result.coefficients[index]
    for name, values in model.coefficient_fields(state.x, coefficients).items():
        fields.setdefault(name, values)
    exact = result.exact[index]
    if exact is not None:
        for v, name in enumerate(model.variables):
            fields[f"{name}_exact"] = exact[v]
    return {name: np.ascontiguousarray(values, dtype=np.float64) for name, values in fields.items()}


def output_field_data(result: RunResult, index: int) -> dict[str, float]:
    """One value per output: ``time`` and, with front tracking, the margins that exist
    (:data:`MARGIN_FIELDS`)."""
    state = result.states[index]
    data = {"time": state.t}
    if state.margins is not None:
        row = state.margins.row(state.t)[1:]
        data.update({n: v for n, v in zip(MARGIN_FIELDS, row, strict=True) if v == v})
    return data


def write_states(path: Path, result: RunResult, compressed: bool = True) -> Path:
    """Atomic ``states.npz`` of the outputs so far (:func:`states_bytes`)."""
    return atomic_write_bytes(path, states_bytes(result, compressed))


def states_bytes(
    result: RunResult, compressed: bool = True, provenance: dict[str, str] | None = None
) -> bytes:
    """``states.npz`` of the outputs so far (``compressed=False``: stored without compression,
    as during a run, where it is rewritten at every output time).

    Keys: ``t`` (n_out,), ``x`` (n,), ``edges`` (n + 1,), ``q`` (n_out, n_vars, n),
    ``q_exact`` (exact cell averages, NaN where unknown), ``variables``; with front tracking also
    ``margins`` (rows ``t, x_rear, u_rear, x_front, u_front`` after every step, NaN for a margin
    that does not exist); with the Lagrangian scheme also its own mesh at the output times:
    ``nodes`` and ``node_velocities`` (n_out, n_elements + 1) and ``element_depths``
    (n_out, n_elements) (``q`` is then the conservative projection of the elements onto the
    grid). ``provenance`` (default: :func:`conslaw.provenance.record` of the run's scene) is
    stored as the JSON string ``provenance``.
    """
    if provenance is None:
        provenance = record(result.scene)
    exact = np.array(
        [
            e if e is not None else np.full_like(s.q, np.nan)
            for e, s in zip(result.exact, result.states, strict=True)
        ]
    )
    return npz_bytes(
        compressed,
        t=np.array([s.t for s in result.states]),
        x=result.grid.centres(),
        edges=result.grid.edges,
        q=np.array([s.q for s in result.states]),
        q_exact=exact,
        variables=np.array(result.model.variables),
        provenance=np.array(as_json(provenance)),
        **({} if result.margins is None else {"margins": result.margins}),
        **node_arrays(result.states),
    )


def write_h5(path: Path, datasets: dict[str, Any]) -> Path:
    """Atomic HDF5 file with one dataset per entry (built in memory, then renamed into place)."""
    return atomic_write_bytes(path, h5_bytes(datasets))


def h5_bytes(datasets: dict[str, Any]) -> bytes:
    """An HDF5 file with one dataset per entry, built in memory."""
    import h5py

    buffer = io.BytesIO()
    with h5py.File(buffer, "w") as handle:
        for name, values in datasets.items():
            handle.create_dataset(name, data=values)
    return buffer.getvalue()


def _data_item(parent: ET.Element, values_shape: tuple[int, ...], kind: str, text: str) -> None:
    item = ET.SubElement(
        parent,
        "DataItem",
        DataType=kind,
        Dimensions=" ".join(str(d) for d in values_shape),
        Format="HDF",
        Precision="8",
    )
    item.text = text


def xdmf_document(
    mesh_file: str, n_cells: int, entries: list[tuple[float, str, list[str], dict[str, float]]]
) -> bytes:
    """The XDMF 3 index of a series: one uniform grid ``mesh`` (topology and geometry in
    ``mesh_file``) and a temporal collection with one grid per ``(t, data file, cell field
    names, field data)`` entry, each field a cell-centred attribute in the data file and the
    field data as ``Information`` elements."""
    root = ET.Element("Xdmf", Version="3.0")
    root.set("xmlns:xi", "http://www.w3.org/2001/XInclude")
    domain = ET.SubElement(root, "Domain")
    mesh = ET.SubElement(domain, "Grid", Name="mesh", GridType="Uniform")
    topology = ET.SubElement(
        mesh, "Topology", TopologyType="Polyline", NodesPerElement="2",
        NumberOfElements=str(n_cells),
    )  # fmt: skip
    _data_item(topology, (n_cells, 2), "Int", f"{mesh_file}:/cells")
    geometry = ET.SubElement(mesh, "Geometry", GeometryType="XYZ")
    _data_item(geometry, (n_cells + 1, 3), "Float", f"{mesh_file}:/points")
    series = ET.SubElement(
        domain, "Grid", Name=SERIES, GridType="Collection", CollectionType="Temporal"
    )
    pointer = 'xpointer(//Grid[@Name="mesh"]/*[self::Topology or self::Geometry])'
    for t, data_file, names, data in entries:
        grid = ET.SubElement(series, "Grid", Name=f"t={t!r}", GridType="Uniform")
        ET.SubElement(grid, "xi:include", xpointer=pointer)
        ET.SubElement(grid, "Time", Value=repr(float(t)))
        for name in names:
            attribute = ET.SubElement(
                grid, "Attribute", Name=name, AttributeType="Scalar", Center="Cell"
            )
            _data_item(attribute, (n_cells,), "Float", f"{data_file}:/{name}")
        for name, value in data.items():
            ET.SubElement(grid, "Information", Name=name, Value=repr(float(value)))
    ET.indent(root)
    return ET.tostring(root, encoding="utf-8", xml_declaration=True) + b"\n"


def vtu_bytes(
    points: Array, cells: NDArray[np.int64], fields: dict[str, Array], data: dict[str, float]
) -> bytes:
    """A VTU file (meshio, binary, zlib) of line cells with the cell ``fields`` and the field
    ``data`` (meshio 5.3 does not write field data, meshio issue #1546: added here as ASCII
    ``FieldData`` arrays, which meshio and ParaView read)."""
    import meshio

    mesh = meshio.Mesh(points, [("line", cells)], cell_data={k: [v] for k, v in fields.items()})
    with tempfile.TemporaryDirectory(prefix="conslaw-vtu-") as scratch:
        path = Path(scratch) / "mesh.vtu"
        meshio.write(path, mesh, file_format="vtu")
        root = ET.fromstring(path.read_bytes())
    grid = root.find("UnstructuredGrid")
    assert grid is not None
    field_data = ET.Element("FieldData")
    for name, value in data.items():
        array = ET.SubElement(
            field_data, "DataArray", type="Float64", Name=name, NumberOfTuples="1",
            format="ascii",
        )  # fmt: skip
        array.text = repr(float(value))
    grid.insert(0, field_data)
    return ET.tostring(root, encoding="utf-8", xml_declaration=True)


def pvd_document(entries: list[tuple[float, str]]) -> bytes:
    """A ParaView collection (``.pvd``) of ``(time, file)`` entries."""
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    collection = ET.SubElement(root, "Collection")
    for t, name in entries:
        ET.SubElement(collection, "DataSet", timestep=repr(float(t)), part="0", file=name)
    ET.indent(root)
    return ET.tostring(root, encoding="utf-8", xml_declaration=True) + b"\n"


def fields_csv(t: float, x: Array, fields: dict[str, Array]) -> bytes:
    """CSV of one output time: columns ``t``, ``x`` and every field, one row per cell, numbers
    written with 17 significant digits (read back exactly)."""
    table = np.column_stack([np.full(x.shape, t), x, *fields.values()])
    buffer = io.StringIO()
    np.savetxt(buffer, table, fmt="%.17g", delimiter=",")
    return (",".join(["t", "x", *fields]) + "\n" + buffer.getvalue()).encode()


#: Names of the files conslaw writes into a run folder (at the end of a run, those it did not
#: write this time are left over from an earlier run into the same folder, and removed).
#: A temporary file of :func:`write_temporary` (``.<name>.<8 random characters>.tmp``).
_TEMPORARY = re.compile(r"\.(.+)\.[^.]{8}\.tmp")
_OWN_FILE = re.compile(
    rf"^({SERIES}(-(\d{{5}}|mesh)\.(h5|vtu|csv)|\.xdmf|\.pvd)"
    r"|states\.npz|margins\.csv|(profiles|margins|chute|xt)\.png)$"
)


@contextmanager
def signals_held() -> Iterator[None]:
    """Hold SIGINT, SIGTERM and SIGHUP while one output time is written, so that an
    interruption lands between output times and every format holds the same ones; a signal that
    came meanwhile is handed to its previous handler on leaving (only in the main thread, where
    Python runs signal handlers)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending: list[int] = []

    def hold(number: int, frame: Any) -> None:
        pending.append(number)

    names = ("SIGINT", "SIGTERM", "SIGHUP")
    numbers = [getattr(signal, n) for n in names if hasattr(signal, n)]
    previous = {number: signal.signal(number, hold) for number in numbers}
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
        for number in pending[:1]:
            handler = previous[number]
            if callable(handler):
                handler(number, None)
            elif handler == signal.SIG_DFL:
                signal.raise_signal(number)


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
        if self._claim is not None or fcntl is None or not self.folder.is_dir():
            return
        try:
            handle = os.open(self.folder, os.O_RDONLY)
        except OSError:
            return  # not readable, or gone: prepare_output_dir reports what matters
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(handle)
            raise ConfigError(
                f"output folder '{self.folder}' is being written by another conslaw run; "
                "wait for it to end or choose another output folder"
            ) from None
        except OSError:  # no flock here (some network file systems): run unlocked
            os.close(handle)
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
        with signals_held():
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
            with signals_held():
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
