"""Hazard maps as figures: a field (peak flow depth, peak velocity, ...) in colour over a
hillshade of the DEM, with elevation contours and the release outline.

Made without pyplot, like :mod:`conslaw.plotting`: the backend is left alone.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.axes import Axes
from matplotlib.colors import LightSource
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from numpy.typing import ArrayLike, NDArray

from conslaw.errors import ConfigError
from conslaw.terrain.dem import DigitalElevationModel
from conslaw.terrain.slope import elevation_gradient

#: The number of elevation contour lines an automatic interval aims for (inclusive).
CONTOUR_LINES = (10, 20)
#: Contour intervals are these times a power of ten.
NICE_STEPS = (1.0, 2.0, 2.5, 4.0, 5.0)
#: The grey scale of the hillshade runs from -HILLSHADE_FLOOR (black) to 1 (white): a slope in
#: full shadow (0) is dark grey, so the colours and contours drawn over it stay readable.
HILLSHADE_FLOOR = 0.6
#: Share of the largest absolute value below which a cell of the field is left transparent
#: when no threshold is given (round-off, a scheme's thin layer).
RELATIVE_THRESHOLD = 1e-6


def hillshade(
    dem: DigitalElevationModel, *, azimuth: float = 315.0, altitude: float = 45.0
) -> NDArray[np.float64]:
    r"""Illumination of each cell in [0, 1], ``(ny, nx)`` y ascending: the Lambertian

    .. math:: I = \max\bigl(0, \mathbf n \cdot \mathbf s\bigr), \qquad
              \mathbf n = \frac{(-z_x, -z_y, 1)}{\sqrt{1 + z_x^2 + z_y^2}},

    with the gradient of :func:`~conslaw.terrain.slope.elevation_gradient` (``z_y`` towards the
    north) and :math:`\mathbf s` the unit vector towards a light from ``azimuth`` (degrees
    clockwise from north; 315 is the north-west of map convention) at ``altitude`` degrees above
    the horizon (``matplotlib.colors.LightSource.direction``). Unlike
    ``LightSource.hillshade`` the values are not stretched to the range of the DEM, so a slope
    has the same shade on every map; a flat cell has :math:`\sin(\text{altitude})`.
    """
    direction = LightSource(azdeg=azimuth, altdeg=altitude).direction
    dz_dx, dz_dy = elevation_gradient(dem)
    along_normal = -dz_dx * direction[0] - dz_dy * direction[1] + direction[2]
    shade = along_normal / np.sqrt(1.0 + dz_dx * dz_dx + dz_dy * dz_dy)
    return np.clip(shade, 0.0, 1.0)


def contour_levels(low: float, high: float, interval: float) -> NDArray[np.float64]:
    """The multiples of ``interval`` in ``[low, high]``."""
    first, last = math.ceil(low / interval), math.floor(high / interval)
    return np.arange(first, last + 1, dtype=np.float64) * interval


def nice_contour_interval(low: float, high: float) -> float | None:
    """The largest interval of :data:`NICE_STEPS` times a power of ten that gives between
    :data:`CONTOUR_LINES` contour lines on ``[low, high]`` (else the one closest to 15 lines);
    ``None`` for a flat range."""
    span = high - low
    if not (math.isfinite(span) and span > 0.0):
        return None
    exponent = math.floor(math.log10(span / CONTOUR_LINES[1]))
    candidates = sorted(
        step * 10.0**power for power in range(exponent - 1, exponent + 3) for step in NICE_STEPS
    )
    counts = {interval: contour_levels(low, high, interval).size for interval in candidates}
    fitting = [s for s in candidates if CONTOUR_LINES[0] <= counts[s] <= CONTOUR_LINES[1]]
    if fitting:
        return max(fitting)
    return min(candidates, key=lambda s: (abs(counts[s] - 15), -s))


def hazard_map_figure(
    dem: DigitalElevationModel,
    field: ArrayLike,
    *,
    label: str,
    release_mask: ArrayLike | None = None,
    contour_interval: float | None = None,
    threshold: float | None = None,
) -> Figure:
    """A map of ``field`` over the terrain.

    The field in colour (viridis) where ``|field| > threshold``, transparent elsewhere, over a
    hillshade of the DEM (:func:`hillshade`); elevation contours every ``contour_interval``
    metres (if ``None``, a round interval giving 10 to 20 lines, :func:`nice_contour_interval`),
    every other one labelled; the outline of ``release_mask`` (its contour at 0.5) in red;
    equal aspect, axes in metres ("easting (m)"/"northing (m)" with a CRS, "x (m)"/"y (m)"
    without); a colourbar labelled ``label``.

    Parameters
    ----------
    dem : DigitalElevationModel
        The terrain.
    field : array_like, shape (ny, nx)
        Values on the DEM's cells (y ascending).
    label : str
        Colourbar label with units, e.g. ``"peak flow depth (m)"``.
    release_mask : array_like of bool, shape (ny, nx), optional
        The released cells (:func:`~conslaw.terrain.release.release_mask`).
    contour_interval : float, optional
        Elevation between contour lines, m (> 0).
    threshold : float, optional
        Cells with ``|field| <= threshold`` (or not finite) are not coloured; by default
        :data:`RELATIVE_THRESHOLD` times the largest ``|field|``.

    Returns
    -------
    matplotlib.figure.Figure
        Save it with ``figure.savefig(...)``.

    Raises
    ------
    ConfigError
        ``field`` or ``release_mask`` not of the DEM's shape, a contour interval not > 0.
    """
    values = _on_cells(dem, field, "field")
    figure = Figure(figsize=(8.0, max(3.5, min(10.0, 7.0 * dem.ny / dem.nx + 1.0))))
    figure.set_layout_engine("constrained")
    axes = figure.add_subplot()
    extent = (dem.x_min, dem.x_max, dem.y_min, dem.y_max)
    axes.imshow(
        hillshade(dem), cmap="gray", vmin=-HILLSHADE_FLOOR, vmax=1.0, origin="lower", extent=extent,
        interpolation="bilinear",
    )  # fmt: skip
    finite = np.isfinite(values)
    largest = float(np.max(np.abs(values[finite]))) if finite.any() else 0.0
    limit = RELATIVE_THRESHOLD * largest if threshold is None else float(threshold)
    shown = np.ma.masked_where(~finite | ~(np.abs(np.where(finite, values, 0.0)) > limit), values)
    empty = shown.count() == 0  # nothing to colour: a fixed scale, not an empty autoscale
    image = axes.imshow(
        shown, cmap="viridis", origin="lower", extent=extent, interpolation="nearest",
        alpha=0.85, vmin=0.0 if empty else None, vmax=1.0 if empty else None,
    )  # fmt: skip
    _draw_contours(axes, dem, contour_interval)
    if release_mask is not None:
        _draw_release(axes, dem, _on_cells(dem, release_mask, "release_mask"))
    named = dem.crs is not None
    axes.set_xlabel("easting (m)" if named else "x (m)")
    axes.set_ylabel("northing (m)" if named else "y (m)")
    axes.set_xlim(dem.x_min, dem.x_max)
    axes.set_ylim(dem.y_min, dem.y_max)
    axes.set_aspect("equal")
    figure.colorbar(image, ax=axes, label=label, shrink=0.85)
    return figure


def _on_cells(dem: DigitalElevationModel, values: ArrayLike, name: str) -> NDArray[np.float64]:
    """``values`` as float64 after checking they are of the DEM's shape."""
    array = np.asarray(values)
    if array.shape != dem.shape or array.dtype.kind not in "biuf":
        raise ConfigError(
            f"hazard map: {name} must be a numeric array of the DEM's shape {dem.shape}, got "
            f"{array.dtype} of shape {array.shape}"
        )
    return array.astype(np.float64)


def _draw_contours(axes: Axes, dem: DigitalElevationModel, interval: float | None) -> None:
    """Elevation contours every ``interval`` m (a round one if ``None``), every other one
    labelled."""
    low, high = float(dem.elevation.min()), float(dem.elevation.max())
    if interval is None:
        interval = nice_contour_interval(low, high)
        if interval is None:
            return
    elif not (math.isfinite(interval) and interval > 0.0):
        raise ConfigError(f"hazard map: contour_interval must be > 0 m, got {interval!r}")
    levels = contour_levels(low, high, interval)
    if levels.size == 0:
        return
    x, y = dem.centres()
    lines = axes.contour(
        x, y, dem.elevation, levels=levels, colors="black", linewidths=0.4, alpha=0.6
    )
    axes.clabel(lines, levels[::2], fontsize=6, fmt="%g")


def _draw_release(axes: Axes, dem: DigitalElevationModel, mask: NDArray[np.float64]) -> None:
    """The outline of the released cells (the contour of the mask at 0.5), red; the mask is
    padded with a ring of unreleased cells so that a release on the DEM's edge is closed."""
    if not mask.any():
        return
    x, y = dem.centres()
    step = dem.cell_size
    x_padded = np.concatenate(([x[0] - step], x, [x[-1] + step]))
    y_padded = np.concatenate(([y[0] - step], y, [y[-1] + step]))
    released = np.pad(np.where(mask != 0.0, 1.0, 0.0), 1)
    axes.contour(x_padded, y_padded, released, levels=[0.5], colors="red", linewidths=1.2)
    outline = Line2D([], [], color="red", linewidth=1.2, label="release area")
    axes.legend(handles=[outline], loc="upper right", fontsize="small")
