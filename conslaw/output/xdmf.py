"""XDMF 3 time series with one HDF5 file per output time, for ParaView and meshio (see
:mod:`conslaw.io` for why not meshio's own writer)."""

from __future__ import annotations

import io
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

from conslaw.output.fields import SERIES
from conslaw.output.files import atomic_write_bytes


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
    mesh_file: str,
    n_cells: int,
    entries: list[tuple[float, str, list[str], dict[str, float]]],
    quadrilaterals: tuple[int, int] | None = None,
) -> bytes:
    """The XDMF 3 index of a series: one uniform grid ``mesh`` (topology and geometry in
    ``mesh_file``) and a temporal collection with one grid per ``(t, data file, cell field
    names, field data)`` entry, each field a cell-centred attribute in the data file and the
    field data as ``Information`` elements.

    The mesh is ``n_cells`` line cells on ``n_cells + 1`` points (1D), or, with
    ``quadrilaterals = (nx, ny)``, ``nx ny`` quadrilateral cells on ``(nx + 1)(ny + 1)``
    points (2D)."""
    root = ET.Element("Xdmf", Version="3.0")
    root.set("xmlns:xi", "http://www.w3.org/2001/XInclude")
    domain = ET.SubElement(root, "Domain")
    mesh = ET.SubElement(domain, "Grid", Name="mesh", GridType="Uniform")
    if quadrilaterals is None:
        kind, corners, n_points = "Polyline", 2, n_cells + 1
    else:
        nx, ny = quadrilaterals
        kind, corners, n_points = "Quadrilateral", 4, (nx + 1) * (ny + 1)
    topology = ET.SubElement(
        mesh, "Topology", TopologyType=kind, NodesPerElement=str(corners),
        NumberOfElements=str(n_cells),
    )  # fmt: skip
    _data_item(topology, (n_cells, corners), "Int", f"{mesh_file}:/cells")
    geometry = ET.SubElement(mesh, "Geometry", GeometryType="XYZ")
    _data_item(geometry, (n_points, 3), "Float", f"{mesh_file}:/points")
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
