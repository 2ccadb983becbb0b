"""Terrain surfaces ``z = b(x, y)`` over horizontal map coordinates, with the first and second
derivatives that the Savage–Hutter terrain model needs (docs/design.md, "Savage–Hutter on
terrain").

Every surface answers :meth:`TerrainSurface.derivatives` at any points: ``(b, b_x, b_y, b_xx,
b_xy, b_yy)``. A plane and a paraboloid bowl have them in closed form; a digital elevation
model is interpolated by a bicubic spline through its cell centres (scipy's
``RectBivariateSpline``), whose first derivatives are continuous and second derivatives
piecewise linear.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError
from conslaw.grid2d import Grid2D
from conslaw.terrain.dem import DigitalElevationModel
from conslaw.terrain.generated import plane_to_flat_profile

if TYPE_CHECKING:
    from scipy.interpolate import RectBivariateSpline

Array = NDArray[np.float64]


class TerrainSurface(Protocol):
    """A surface ``z = b(x, y)`` in metres over map coordinates in metres."""

    def derivatives(self, x: Array, y: Array) -> tuple[Array, ...]:
        """``(b, b_x, b_y, b_xx, b_xy, b_yy)`` at the points ``(x, y)`` (broadcast)."""
        ...

    def covers(self, x_min: float, x_max: float, y_min: float, y_max: float) -> str | None:
        """``None`` if the surface is defined on the whole rectangle, else what is missing."""
        ...


#: Cells of linear extrapolation around a gridded surface before its spline is fitted.
PADDING = 2


def _extended(centres: Array) -> Array:
    """``centres`` continued by :data:`PADDING` equal steps on both ends."""
    step = centres[1] - centres[0]
    before = centres[0] - step * np.arange(PADDING, 0, -1)
    after = centres[-1] + step * np.arange(1, PADDING + 1)
    return np.concatenate([before, centres, after])


@dataclass(frozen=True)
class InclinedPlane:
    """The plane descending at ``angle`` degrees toward +x: ``b = -x tan(angle)`` (the chute
    ``plane`` of the 1D and 2D chute models, in map coordinates)."""

    angle: float

    def derivatives(self, x: Array, y: Array) -> tuple[Array, ...]:
        """Closed form: ``b_x = -tan(angle)``, every other derivative 0."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        slope = math.tan(math.radians(self.angle))
        zero = np.zeros(x.shape)
        return -slope * x, np.full(x.shape, -slope), zero, zero, zero, zero

    def covers(self, x_min: float, x_max: float, y_min: float, y_max: float) -> str | None:
        """A plane covers every rectangle."""
        return None


@dataclass(frozen=True)
class ParaboloidBowl:
    """The bowl ``b = (x^2 + y^2) / (2 R)`` around the origin: the slope angle at distance
    ``r`` is ``atan(r / R)``, the curvature ``1/R`` in every direction at the bottom."""

    radius: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.radius) and self.radius > 0.0):
            raise ConfigError(f"parameters.bowl_radius: must be > 0, got {self.radius!r}")

    def derivatives(self, x: Array, y: Array) -> tuple[Array, ...]:
        """Closed form: ``b_x = x / R``, ``b_y = y / R``, ``b_xx = b_yy = 1/R``, ``b_xy = 0``."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        curvature = 1.0 / self.radius
        return (
            0.5 * curvature * (x * x + y * y),
            curvature * x,
            curvature * y,
            np.full(x.shape, curvature),
            np.zeros(x.shape),
            np.full(x.shape, curvature),
        )

    def covers(self, x_min: float, x_max: float, y_min: float, y_max: float) -> str | None:
        """A bowl covers every rectangle."""
        return None


@dataclass(frozen=True)
class PlaneToFlat:
    """An inclined plane of ``angle`` degrees descending toward +x, turning through a circular
    arc of radius ``radius`` (m) into a flat run-out at ``z = 0`` from ``x = transition_end``
    (the layout of Gray, Wieland & Hutter 1999;
    :func:`conslaw.terrain.generated.plane_to_flat_profile`), the same across y. On the arc,
    ``b_xx = R^2 / (R^2 - (x_b - x)^2)^(3/2)``, the curvature of the circle over ``c^3``."""

    angle: float
    radius: float
    transition_end: float

    def derivatives(self, x: Array, y: Array) -> tuple[Array, ...]:
        """The profile and its first derivative from the generator, the second in closed
        form (0 on the plane and the run-out)."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        z, slope = plane_to_flat_profile(
            x,
            slope_angle=self.angle,
            transition_radius=self.radius,
            transition_end=self.transition_end,
        )
        arc_width = self.radius * math.sin(math.radians(self.angle))
        to_end = self.transition_end - x
        on_arc = (to_end > 0.0) & (to_end < arc_width)
        root = np.sqrt(np.maximum(self.radius**2 - to_end**2, 0.0))
        safe = np.where(on_arc, root, 1.0)
        bend = np.where(on_arc, self.radius**2 / (safe * safe * safe), 0.0)
        zero = np.zeros(x.shape)
        return z, slope, zero, bend, zero, zero

    def covers(self, x_min: float, x_max: float, y_min: float, y_max: float) -> str | None:
        """The profile covers every rectangle (the plane continues upslope)."""
        return None


@dataclass(frozen=True)
class ChannelledPlaneToFlat:
    """:class:`PlaneToFlat` with a Gaussian channel along ``y = 0`` of depth ``depth`` (m) and
    half-width ``half_width`` (m) that fades out through the transition arc
    (:func:`conslaw.terrain.generated.channelled_slope`): ``b = b_p(x) - D f(x) g(y)``, ``g =
    exp(-(y/w)^2)``, ``f = 1 - xi^2 (3 - 2 xi)`` with ``xi`` the position along the arc from 0
    to 1; every derivative in closed form."""

    profile: PlaneToFlat
    depth: float
    half_width: float

    def derivatives(self, x: Array, y: Array) -> tuple[Array, ...]:
        """``b_p - D f g`` and its derivatives: ``b_x = b_p' - D f' g``, ``b_y = -D f g'``,
        ``b_xx = b_p'' - D f'' g``, ``b_xy = -D f' g'``, ``b_yy = -D f g''``."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        z, slope, _, bend, _, _ = self.profile.derivatives(x, y)
        end = self.profile.transition_end
        span = self.profile.radius * math.sin(math.radians(self.profile.angle))
        xi = (x - (end - span)) / span
        inside = (xi > 0.0) & (xi < 1.0)
        xi = np.clip(xi, 0.0, 1.0)
        fade = 1.0 - xi * xi * (3.0 - 2.0 * xi)
        fade_x = np.where(inside, -6.0 * xi * (1.0 - xi) / span, 0.0)
        fade_xx = np.where(inside, -6.0 * (1.0 - 2.0 * xi) / (span * span), 0.0)
        w2 = self.half_width * self.half_width
        across = np.exp(-y * y / w2)
        across_y = -2.0 * y / w2 * across
        across_yy = (4.0 * y * y / (w2 * w2) - 2.0 / w2) * across
        d = self.depth
        return (
            z - d * fade * across,
            slope - d * fade_x * across,
            -d * fade * across_y,
            bend - d * fade_xx * across,
            -d * fade_x * across_y,
            -d * fade * across_yy,
        )

    def covers(self, x_min: float, x_max: float, y_min: float, y_max: float) -> str | None:
        """The channelled profile covers every rectangle."""
        return None


@dataclass(frozen=True)
class GriddedSurface:
    """A surface sampled at cell centres ``x_centres`` (ascending, equally spaced) by
    ``y_centres`` (likewise), ``elevation`` of shape ``(ny, nx)``, interpolated by a bicubic
    spline through the samples (``RectBivariateSpline`` with ``s = 0``; at least 4 x 4
    samples). The samples are first continued by :data:`PADDING` cells on every side by linear
    extrapolation (``2 z_edge - z_mirror``), so that the spline covers the outer half cells of
    the DEM and the quarter points beyond them (FITPACK clamps a spline outside its knots)."""

    x_centres: Array
    y_centres: Array
    elevation: Array
    _spline: RectBivariateSpline = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        ny, nx = np.shape(self.elevation)
        if nx < 4 or ny < 4:
            raise ConfigError(
                f"terrain: a gridded surface needs at least 4 x 4 samples, got {nx} x {ny}"
            )
        elevation = np.pad(
            np.asarray(self.elevation, dtype=np.float64),
            PADDING,
            mode="reflect",
            reflect_type="odd",
        )
        from scipy.interpolate import RectBivariateSpline  # on first use (a DEM scene)

        spline = RectBivariateSpline(
            _extended(self.y_centres), _extended(self.x_centres), elevation, s=0
        )
        object.__setattr__(self, "_spline", spline)

    def derivatives(self, x: Array, y: Array) -> tuple[Array, ...]:
        """The spline and its derivatives (its rows are y, its columns x)."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        flat_x, flat_y = x.ravel(), y.ravel()

        def value(d_x: int, d_y: int) -> Array:
            return self._spline.ev(flat_y, flat_x, dx=d_y, dy=d_x).reshape(x.shape)

        return value(0, 0), value(1, 0), value(0, 1), value(2, 0), value(1, 1), value(0, 2)

    def covers(self, x_min: float, x_max: float, y_min: float, y_max: float) -> str | None:
        """The domain must lie within the DEM: between the outermost cell centres plus half a
        cell (the linear continuation of :data:`PADDING` cells serves only the outer half
        cells and their quarter points)."""
        half_x = 0.5 * (self.x_centres[1] - self.x_centres[0])
        half_y = 0.5 * (self.y_centres[1] - self.y_centres[0])
        low_x, high_x = self.x_centres[0] - half_x, self.x_centres[-1] + half_x
        low_y, high_y = self.y_centres[0] - half_y, self.y_centres[-1] + half_y
        tolerance = 1e-9 * max(abs(high_x - low_x), abs(high_y - low_y))
        if (
            x_min < low_x - tolerance
            or x_max > high_x + tolerance
            or y_min < low_y - tolerance
            or y_max > high_y + tolerance
        ):
            return (
                f"the domain [{x_min:g}, {x_max:g}] x [{y_min:g}, {y_max:g}] leaves the terrain "
                f"[{low_x:g}, {high_x:g}] x [{low_y:g}, {high_y:g}]"
            )
        return None

    def cell_averages(self, x_edges: Array, y_edges: Array) -> Array:
        """The mean of the spline over every cell ``[x_edges[j], x_edges[j + 1]] x
        [y_edges[k], y_edges[k + 1]]``, ``(len(y_edges) - 1, len(x_edges) - 1)``: exact, as
        the tensor product of the B-spline basis functions' integrals over the edges
        (``scipy.interpolate.BSpline.antiderivative``) with the spline's coefficients; a
        plane's averages are its values at the cell centres.

        Parameters
        ----------
        x_edges, y_edges : numpy.ndarray
            Ascending, within the spline's samples and their padding.

        Returns
        -------
        numpy.ndarray
        """
        from scipy.interpolate import BSpline

        knots_y, knots_x, coefficients = self._spline.tck
        degree_y, degree_x = self._spline.degrees

        def basis_means(knots: Array, degree: int, edges: Array) -> Array:
            count = len(knots) - degree - 1
            integral = BSpline(knots, np.eye(count), degree).antiderivative()(edges)
            return np.diff(integral, axis=0) / np.diff(edges)[:, None]

        along_x = basis_means(knots_x, degree_x, np.asarray(x_edges, dtype=np.float64))
        along_y = basis_means(knots_y, degree_y, np.asarray(y_edges, dtype=np.float64))
        table = coefficients.reshape(along_y.shape[1], along_x.shape[1])
        return np.asarray(along_y @ table @ along_x.T, dtype=np.float64)

    @classmethod
    def from_dem(
        cls, dem: DigitalElevationModel, smoothing: float = 0.0, grid: Grid2D | None = None
    ) -> GriddedSurface:
        """The spline through the cell centres of ``dem``, after a Gaussian filter of
        standard deviation ``smoothing`` cells (``scipy.ndimage.gaussian_filter``, the edges
        continued by their nearest values) if it is above 0; on a ``grid`` of cells larger than
        the DEM's, the spline through that spline's means over the grid's cells
        (:meth:`cell_averages`): the terrain at the resolution a scheme on ``grid`` can
        resolve (docs/design.md, "Savage–Hutter on terrain").

        Parameters
        ----------
        dem : DigitalElevationModel
        smoothing : float
            Cells; 0 for none.
        grid : Grid2D, optional
            The cells a scheme runs on; None (or cells no larger than the DEM's): the DEM's own.

        Returns
        -------
        GriddedSurface
        """
        x, y = dem.centres()
        elevation = np.asarray(dem.elevation, dtype=np.float64)
        if smoothing > 0.0:
            from scipy.ndimage import gaussian_filter

            elevation = gaussian_filter(elevation, smoothing, mode="nearest")
        surface = cls(x, y, elevation)
        if grid is None or not coarser(grid, dem.cell_size):
            return surface
        x_grid, y_grid = grid.centres()
        averages = surface.cell_averages(grid.x.edges, grid.y.edges)
        return cls(x_grid, y_grid, averages)


def coarser(grid: Grid2D, cell_size: float) -> bool:
    """Whether the cells of ``grid`` are larger than ``cell_size`` (by more than 1e-9 of it).

    Parameters
    ----------
    grid : Grid2D
    cell_size : float

    Returns
    -------
    bool
    """
    return max(grid.dx, grid.dy) > cell_size * (1.0 + 1e-9)
