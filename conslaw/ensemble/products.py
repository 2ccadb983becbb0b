"""What a study's dataset gives a hazard analyst (docs/ensembles.md, "Products"): exceedance
probabilities of the maps, the distribution of the run-out and travel angle, and the
sensitivity of every summary figure to every varied key (Spearman rank correlations).

Only finished members count; each product says how many there were.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from conslaw.ensemble.dataset import write_netcdf
from conslaw.errors import ConfigError
from conslaw.output.files import atomic_write_bytes, write_figure

if TYPE_CHECKING:
    import xarray

Array = NDArray[np.float64]

#: Summary figures drawn as distributions, in order of preference.
DISTRIBUTION_FIGURES = (
    "runout_length",
    "travel_angle",
    "front",
    "deposit_centre",
    "deposit_x",
    "deposit_y",
)


def finished(dataset: xarray.Dataset) -> xarray.Dataset:
    """The members that finished (status ``finished``)."""
    return dataset.isel(member=np.flatnonzero(dataset.status.values == "finished"))


def varied_names(dataset: xarray.Dataset) -> list[str]:
    """The dataset's variables that hold the varied keys (those with a ``scene_key``)."""
    return [str(name) for name in dataset.data_vars if "scene_key" in dataset[name].attrs]


def exceedance(dataset: xarray.Dataset, field: str, threshold: float) -> xarray.DataArray:
    """``P(field > threshold)`` at every cell: the fraction of the finished members whose map
    exceeds ``threshold`` there.

    Parameters
    ----------
    dataset : xarray.Dataset
        A study's dataset with maps (``--fields``).
    field : str
        A map: ``max_depth``, ``final_depth`` (1D); ``peak_depth``, ``peak_speed``,
        ``peak_pressure``, ``deposit`` (2D).
    threshold : float

    Returns
    -------
    xarray.DataArray
        Over ``x`` (and ``y``), attributes naming the field, threshold and member count.
    """
    if field not in dataset or "member" not in dataset[field].dims or dataset[field].ndim < 2:
        maps = [str(name) for name in dataset.data_vars if dataset[name].ndim >= 2]
        known = ", ".join(maps) if maps else "none: run the study with --fields"
        raise ConfigError(f"--threshold {field}: not a map of this study (maps: {known})")
    done = finished(dataset)[field]
    kept = done.notnull().all(dim=[d for d in done.dims if d != "member"])
    values = done.isel(member=np.flatnonzero(kept.values))
    if values.sizes["member"] == 0:
        raise ConfigError(f"--threshold {field}: no finished member kept this map")
    probability = (values > threshold).mean(dim="member")
    probability.attrs = {
        "long_name": f"P({field} > {threshold:g})",
        "field": field,
        "threshold": threshold,
        "members": int(values.sizes["member"]),
    }
    return probability


def rank_correlations(dataset: xarray.Dataset) -> xarray.DataArray:
    """Spearman's rank correlation of every summary figure with every varied key, over the
    finished members (NaN where a figure is constant or missing).

    Returns
    -------
    xarray.DataArray
        Dimensions ``figure`` x ``parameter``.
    """
    import xarray as xr

    done = finished(dataset)
    parameters = varied_names(dataset)
    figures = [
        name
        for name in dataset.data_vars
        if dataset[name].dims == ("member",)
        and name not in parameters
        and np.issubdtype(dataset[name].dtype, np.floating)
        and name not in ("wall_seconds", "solve_seconds", "steps")
    ]
    table = np.full((len(figures), len(parameters)), np.nan)
    for i, figure in enumerate(figures):
        y = done[figure].values
        for j, parameter in enumerate(parameters):
            x = done[parameter].values
            usable = np.isfinite(x) & np.isfinite(y)
            if usable.sum() > 2 and np.ptp(y[usable]) > 0 and np.ptp(x[usable]) > 0:
                table[i, j] = stats.spearmanr(x[usable], y[usable]).statistic
    return xr.DataArray(
        table,
        dims=("figure", "parameter"),
        coords={"figure": figures, "parameter": parameters},
        attrs={"long_name": "Spearman rank correlation", "members": int(done.sizes["member"])},
    )


def quantile_table(dataset: xarray.Dataset) -> list[tuple[str, int, float, float, float]]:
    """(figure, members with a value, 5 %, 50 %, 95 % quantiles) of the distribution figures."""
    done = finished(dataset)
    rows = []
    for name in DISTRIBUTION_FIGURES:
        if name in done:
            values = done[name].values[np.isfinite(done[name].values)]
            if values.size:
                low, mid, high = np.quantile(values, [0.05, 0.5, 0.95])
                rows.append((name, int(values.size), float(low), float(mid), float(high)))
    return rows


def distribution_figure(dataset: xarray.Dataset) -> Any:
    """The empirical distribution functions of the run-out figures, one panel each, with the
    5/50/95 % quantiles marked."""
    from matplotlib.figure import Figure

    rows = quantile_table(dataset)
    figure = Figure(figsize=(4.2 * max(len(rows), 1), 3.4), layout="constrained")
    axes = figure.subplots(1, max(len(rows), 1), squeeze=False)[0]
    done = finished(dataset)
    for axis, (name, count, low, mid, high) in zip(axes, rows, strict=False):
        values = np.sort(done[name].values[np.isfinite(done[name].values)])
        axis.step(values, np.arange(1, count + 1) / count, where="post", color="C0")
        for level, value in ((0.05, low), (0.5, mid), (0.95, high)):
            axis.axvline(value, color="0.5", lw=0.8, ls="--")
            axis.annotate(f"{level:.0%}", (value, 0.02), fontsize=7, color="0.3")
        units = done[name].attrs.get("units", "")
        axis.set_xlabel(f"{name} ({units})" if units and units != "1" else name)
        axis.set_ylabel("fraction of members at or below")
        axis.set_title(done[name].attrs.get("long_name", name), fontsize=8)
    cut = int(np.sum(done["at_boundary"].values == 1.0)) if "at_boundary" in done else 0
    note = f" ({cut} reached an end of the domain: cut short)" if cut else ""
    title = dataset.attrs.get("title", "ensemble")
    figure.suptitle(f"{title}: {done.sizes['member']} members{note}")
    return figure


def sensitivity_figure(dataset: xarray.Dataset, figure_name: str) -> Any:
    """``figure_name`` against every varied key, one scatter panel each, titled with the rank
    correlation."""
    from matplotlib.figure import Figure

    done = finished(dataset)
    parameters = varied_names(dataset)
    correlations = rank_correlations(dataset)
    figure = Figure(figsize=(3.6 * len(parameters), 3.2), layout="constrained")
    axes = figure.subplots(1, len(parameters), squeeze=False)[0]
    for axis, parameter in zip(axes, parameters, strict=True):
        axis.plot(done[parameter].values, done[figure_name].values, ".", ms=3, alpha=0.6)
        rho = float(correlations.sel(figure=figure_name, parameter=parameter))
        axis.set_title(f"rank correlation {rho:+.2f}", fontsize=9)
        axis.set_xlabel(done[parameter].attrs.get("scene_key", parameter))
        axis.set_ylabel(figure_name)
    return figure


def exceedance_figure(probability: xarray.DataArray) -> Any:
    """A profile (1D) or a map (2D) of an exceedance probability."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(6.4, 4.0), layout="constrained")
    axis = figure.add_subplot()
    if probability.ndim == 1:
        axis.plot(probability["x"].values, probability.values, color="C3")
        axis.set_xlabel(probability["x"].attrs.get("long_name", "x"))
        axis.set_ylim(-0.02, 1.02)
        axis.set_ylabel(probability.attrs["long_name"])
    else:
        x, y = probability["x"].values, probability["y"].values
        mesh = axis.pcolormesh(x, y, probability.values, vmin=0, vmax=1, cmap="magma_r")
        axis.set_aspect("equal")
        axis.set_xlabel(probability["x"].attrs.get("long_name", "x"))
        axis.set_ylabel(probability["y"].attrs.get("long_name", "y"))
        figure.colorbar(mesh, ax=axis, label=probability.attrs["long_name"])
    axis.set_title(f"{probability.attrs['long_name']} over {probability.attrs['members']} members")
    return figure


def write_products(
    dataset: xarray.Dataset, folder: Path, thresholds: dict[str, float], plot: bool = True
) -> list[Path]:
    """The products of a finished study in ``folder``: ``sensitivity.json`` (rank
    correlations), ``exceedance.nc`` (one variable per threshold) and, with ``plot``,
    ``distribution.png``, ``sensitivity.png`` and ``exceedance-FIELD.png``.

    Returns
    -------
    list of Path
        The files written.
    """
    import xarray as xr

    files = []
    correlations = rank_correlations(dataset)
    table = {
        str(figure): {str(p): _number(correlations.sel(figure=figure, parameter=p))
                      for p in correlations["parameter"].values}
        for figure in correlations["figure"].values
    }  # fmt: skip
    body = json.dumps({"members": correlations.attrs["members"], "spearman": table}, indent=2)
    files.append(atomic_write_bytes(folder / "sensitivity.json", body.encode()))
    probabilities = {
        f"p_{field}": exceedance(dataset, field, value) for field, value in thresholds.items()
    }
    if probabilities:
        files.append(write_netcdf(xr.Dataset(probabilities), folder / "exceedance.nc"))
    if not plot or finished(dataset).sizes["member"] == 0:
        return files
    rows = quantile_table(dataset)
    if rows:
        files.append(write_figure(folder / "distribution.png", distribution_figure(dataset)))
        sensitivity = sensitivity_figure(dataset, rows[0][0])
        files.append(write_figure(folder / "sensitivity.png", sensitivity))
    for name, probability in probabilities.items():
        path = folder / f"exceedance-{name[2:]}.png"
        files.append(write_figure(path, exceedance_figure(probability)))
    return files


def _number(value: Any) -> float | None:
    number = float(value)
    return None if np.isnan(number) else number
