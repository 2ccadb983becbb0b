"""An ensemble as one labelled dataset (xarray): per member its varied values, status, summary
figures and, if kept, its maps; written to netCDF or Zarr (docs/ensembles.md, "The dataset").

Members not yet run have status ``pending`` and NaN figures, so that the dataset of an
interrupted study has the shape of the finished one.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from conslaw.ensemble.design import Variation
from conslaw.ensemble.member import MemberOutcome
from conslaw.ensemble.summary import FIELD_NAMES, SUMMARY_1D, SUMMARY_2D
from conslaw.output.files import write_temporary

if TYPE_CHECKING:
    import xarray

    from conslaw.ensemble.store import StudyFolder, StudySpec

Array = NDArray[np.float64]

#: Dataset formats, by file suffix.
FORMATS = {"netcdf": "study.nc", "zarr": "study.zarr"}


def check_format(file_format: str) -> None:
    """A ConfigError, before anything runs, for an unknown format or a missing writer."""
    from conslaw.errors import ConfigError

    if file_format not in FORMATS:
        raise ConfigError(f"--format: expected one of {', '.join(FORMATS)}, got '{file_format}'")
    if file_format == "zarr":
        try:
            import zarr  # noqa: F401
        except ImportError:
            raise ConfigError("--format zarr needs the zarr package: pip install zarr") from None


def variable_names(variations: Sequence[Variation]) -> list[str]:
    """The dataset name of each varied key: its last part (``delta`` for
    ``parameters.delta``), or the whole key with ``_`` for ``.`` where last parts repeat or
    meet a summary figure's name."""
    taken = set(SUMMARY_1D) | set(SUMMARY_2D) | {"status", "message", "digest", "worker"}
    last = [variation.key.rsplit(".", 1)[-1] for variation in variations]
    names = []
    for variation, short in zip(variations, last, strict=True):
        clash = last.count(short) > 1 or short in taken
        names.append(variation.key.replace(".", "_") if clash else short)
    return names


def build_dataset(
    spec: StudySpec,
    variations: Sequence[Variation],
    values: Array,
    outcomes: Mapping[int, MemberOutcome],
    folder: StudyFolder | None = None,
) -> xarray.Dataset:
    """The study's dataset from its members' values and the outcomes so far.

    Parameters
    ----------
    spec : StudySpec
    variations : sequence of Variation
    values : numpy.ndarray
        ``(samples, len(variations))`` the members' varied values.
    outcomes : mapping of int to MemberOutcome
        The finished members (by index).
    folder : StudyFolder, optional
        Where the members' maps are (with ``spec.fields``).

    Returns
    -------
    xarray.Dataset
        Dimension ``member``; variables: one per varied key (attribute ``scene_key``), the
        summary figures, ``status``, ``message``, ``digest``, ``wall_seconds``, ``worker`` and,
        with ``spec.fields``, the maps over ``x`` (and ``y``).
    """
    import xarray as xr

    samples = len(values)
    members = np.arange(samples)
    data: dict[str, Any] = {}
    for i, (variation, name) in enumerate(zip(variations, variable_names(variations), strict=True)):
        attrs = {"scene_key": variation.key, "distribution": variation.text}
        data[name] = xr.Variable("member", values[:, i], attrs)
    dimension = int(spec.extra.get("dimension", 1))
    figures = SUMMARY_2D if dimension == 2 else SUMMARY_1D
    for figure, (long_name, units) in figures.items():
        column = np.full(samples, np.nan)
        for index, outcome in outcomes.items():
            column[index] = outcome.summary.get(figure, np.nan)
        data[figure] = xr.Variable("member", column, {"long_name": long_name, "units": units})
    text = {"status": "pending", "message": "", "digest": "", "worker": ""}
    for name, blank in text.items():
        column_text = [blank] * samples
        for index, outcome in outcomes.items():
            column_text[index] = getattr(outcome, name)
        data[name] = xr.Variable("member", np.array(column_text, dtype=str))
    seconds = np.full(samples, np.nan)
    for index, outcome in outcomes.items():
        seconds[index] = outcome.wall_seconds
    data["wall_seconds"] = xr.Variable(
        "member", seconds, {"long_name": "member's time in its worker", "units": "s"}
    )
    coords: dict[str, Any] = {"member": members}
    if spec.fields and folder is not None:
        axes = spec.extra.get("axes", {})
        data.update(_field_variables(dimension, samples, outcomes, folder, coords, axes))
    return xr.Dataset(data, coords=coords, attrs=_attributes(spec))


def _attributes(spec: StudySpec) -> dict[str, Any]:
    from conslaw import __version__

    return {
        "title": f"conslaw ensemble of {spec.scene}",
        "scene": spec.scene,
        "settings": json.dumps(spec.settings, sort_keys=True),
        "vary": json.dumps(spec.vary),
        "design": spec.design,
        "samples": spec.samples,
        # As text: netCDF 3 attributes hold 32-bit integers, a seed 64 bits.
        "seed": str(spec.seed),
        "conslaw_version": __version__,
    }


def _field_variables(
    dimension: int,
    samples: int,
    outcomes: Mapping[int, MemberOutcome],
    folder: StudyFolder,
    coords: dict[str, Any],
    spec_axes: Mapping[str, str],
) -> dict[str, Any]:
    import xarray as xr

    stored = {index: folder.load_fields(index) for index in sorted(outcomes)}
    stored = {index: maps for index, maps in stored.items() if maps}
    if not stored:
        return {}
    first = next(iter(stored.values()))
    axes = ("member", "y", "x") if dimension == 2 else ("member", "x")
    names = dict(spec_axes)
    for axis in axes[1:]:
        coords[axis] = xr.Variable(axis, first[f"_{axis}"], {"long_name": names.get(axis, axis)})
    template = next(values for name, values in first.items() if not name.startswith("_"))
    shape = (samples, *template.shape)
    variables = {}
    for name, long_name in FIELD_NAMES[dimension].items():
        block = np.full(shape, np.nan)
        for index, maps in stored.items():
            if name in maps:
                block[index] = maps[name]
        variables[name] = xr.Variable(axes, block, {"long_name": long_name})
    return variables


def write_dataset(dataset: xarray.Dataset, folder: Path, file_format: str) -> Path:
    """Write ``dataset`` into ``folder`` (``study.nc`` or ``study.zarr``) so that a reader
    never sees half of it: netCDF through a temporary file and a rename; Zarr into a new
    folder, renamed into place after the old one is moved aside.

    Returns
    -------
    Path
        The file or folder written.
    """
    path = Path(folder) / FORMATS[file_format]
    if file_format == "netcdf":
        return write_netcdf(dataset, path)
    staging = Path(tempfile.mkdtemp(dir=folder, prefix=".study.zarr."))
    try:
        # Zarr format 2: fixed-width strings have a specification there (not yet in format 3).
        dataset.to_zarr(staging / "data.zarr", mode="w", consolidated=True, zarr_format=2)
        old = path.with_name(f".{path.name}.old")
        shutil.rmtree(old, ignore_errors=True)
        if path.exists():
            os.replace(path, old)
        os.replace(staging / "data.zarr", path)
        shutil.rmtree(old, ignore_errors=True)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return path


def write_netcdf(dataset: xarray.Dataset, path: Path) -> Path:
    """``dataset`` as netCDF (scipy's netCDF3 writer) at ``path``, through a temporary file
    and a rename."""
    temporary = write_temporary(path, b"")
    try:
        dataset.to_netcdf(temporary, engine="scipy", format="NETCDF3_64BIT")
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
    return path


def read_dataset(path: Path) -> xarray.Dataset:
    """A study's dataset from ``study.nc`` or ``study.zarr`` (loaded into memory)."""
    import xarray as xr

    path = Path(path)
    if path.is_dir():
        return xr.open_zarr(path).load()
    with xr.open_dataset(path, engine="scipy") as stored:
        return stored.load()
