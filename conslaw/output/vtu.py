"""VTU files (through meshio) and the ParaView ``.pvd`` collection of their times."""

from __future__ import annotations

import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


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
