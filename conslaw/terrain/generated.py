r"""DEMs from formulas, in metres, for avalanche scenes and tests (nothing to download).

:func:`inclined_plane_to_flat` is the layout of the chute experiments of Gray, Wieland & Hutter
(1999, Proc. R. Soc. Lond. A 455, 1841–1874): an inclined plane that turns through a circular
arc, tangentially, into a horizontal run-out; here scaled to a real slope. Flow runs in +x, the
slope falls towards the east. :func:`channelled_slope` cuts a channel into that profile;
:func:`bowl` is a paraboloid.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from conslaw.errors import ConfigError, finite_number
from conslaw.terrain.dem import DigitalElevationModel, dem_from_function


def _angle(value: float, name: str) -> float:
    """``value`` in radians after checking ``0 < value < 90`` degrees."""
    degrees = finite_number(value, name)
    if not 0.0 < degrees < 90.0:
        raise ConfigError(f"{name} must be in (0, 90) degrees, got {value!r}")
    return math.radians(degrees)


def _positive(value: float, name: str, allow_zero: bool = False) -> float:
    """``value`` after checking that it is a finite number > 0 (>= 0 with ``allow_zero``)."""
    number = finite_number(value, name)
    if number < 0.0 or (number == 0.0 and not allow_zero):
        raise ConfigError(f"{name} must be {'>=' if allow_zero else '>'} 0 m, got {value!r}")
    return number


def plane_to_flat_profile(
    x: ArrayLike, *, slope_angle: float, transition_radius: float, transition_end: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    r"""Elevation z(x) and slope dz/dx of a plane turning through a circular arc into a flat.

    With :math:`\theta` the slope angle, :math:`R` the arc's radius, :math:`x_b` the end of the
    arc (``transition_end``) and :math:`x_a = x_b - R\sin\theta` its start:

    .. math::

        z(x) = \begin{cases}
            (x_a - x)\tan\theta + R(1 - \cos\theta), & x \le x_a \quad\text{(plane)},\\
            R - \sqrt{R^2 - (x_b - x)^2}, & x_a < x < x_b \quad\text{(arc)},\\
            0, & x \ge x_b \quad\text{(run-out)},
        \end{cases}

    the arc centred at :math:`(x_b, R)`, tangent to the plane at :math:`x_a` and to the
    run-out at :math:`x_b`: z and dz/dx are continuous (C1),
    :math:`dz/dx = -(x_b - x)/\sqrt{R^2 - (x_b - x)^2}` on the arc.
    """
    theta = _angle(slope_angle, "slope_angle")
    radius = _positive(transition_radius, "transition_radius")
    end = finite_number(transition_end, "transition_end")
    x = np.asarray(x, dtype=np.float64)
    arc_width = radius * math.sin(theta)
    start = end - arc_width
    before_end = np.clip(end - x, 0.0, arc_width)
    root = np.sqrt(radius * radius - before_end * before_end)
    z = (radius - root) + np.maximum(start - x, 0.0) * math.tan(theta)
    slope = np.where(x <= start, -math.tan(theta), -before_end / root)
    return z, slope


def _profile_layout(
    length: float, runout_length: float, slope_angle: float, transition_radius: float
) -> tuple[float, float]:
    """``(x_a, x_b)``: start and end of the transition arc, checked to leave a plane."""
    length = _positive(length, "length")
    runout = _positive(runout_length, "runout_length", allow_zero=True)
    arc_width = _positive(transition_radius, "transition_radius") * math.sin(
        _angle(slope_angle, "slope_angle")
    )
    end = length - runout
    if not end - arc_width > 0.0:
        raise ConfigError(
            f"length {length:g} m leaves no inclined plane: the run-out takes {runout:g} m and "
            f"the transition arc {arc_width:.4g} m"
        )
    return end - arc_width, end


def inclined_plane_to_flat(
    *,
    length: float = 1000.0,
    width: float = 500.0,
    cell_size: float = 5.0,
    slope_angle: float = 40.0,
    transition_radius: float = 200.0,
    runout_length: float = 300.0,
    crs: str | None = None,
) -> DigitalElevationModel:
    r"""An inclined plane running through a circular arc into a flat run-out (Gray, Wieland &
    Hutter 1999 layout), uniform across y.

    ``z(x, y) = z(x)`` of :func:`plane_to_flat_profile` on
    :math:`[0, L] \times [-W/2, W/2]`, with the arc ending at :math:`x_b = L - L_r`
    (:math:`L_r` the run-out length): the plane from :math:`x = 0` to
    :math:`x_a = x_b - R\sin\theta`, then the arc, then the flat :math:`z = 0`. The defaults
    (1000 m x 500 m at 5 m cells, 40 degrees, R = 200 m, 300 m of run-out) give a plane of
    571 m and a drop of 526 m.

    Parameters
    ----------
    length, width : float
        Extent in x (downslope) and y (across), m; whole numbers of cells.
    cell_size : float
        Cell width, m.
    slope_angle : float
        Inclination of the plane, degrees in (0, 90).
    transition_radius : float
        Radius R of the arc, m.
    runout_length : float
        Length of the flat run-out, m (>= 0).
    crs : str or None
        CRS to attach (a projected one in metres), or none.
    """
    _, end = _profile_layout(length, runout_length, slope_angle, transition_radius)

    def elevation(x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
        z, _ = plane_to_flat_profile(
            x, slope_angle=slope_angle, transition_radius=transition_radius, transition_end=end
        )
        return z

    half = _positive(width, "width") / 2.0
    return dem_from_function(elevation, (0.0, length), (-half, half), cell_size, crs)


def channelled_slope(
    *,
    length: float = 1000.0,
    width: float = 500.0,
    cell_size: float = 5.0,
    slope_angle: float = 40.0,
    transition_radius: float = 200.0,
    runout_length: float = 300.0,
    channel_depth: float = 15.0,
    channel_half_width: float = 50.0,
    crs: str | None = None,
) -> DigitalElevationModel:
    r"""The profile of :func:`inclined_plane_to_flat` with a Gaussian channel along y = 0 whose
    depth fades out through the transition arc:

    .. math::

        z(x, y) = z_p(x) - D\, f(x)\, e^{-(y/b)^2}, \qquad
        f(x) = 1 - \xi^2 (3 - 2\xi), \quad
        \xi = \min\bigl(1, \max\bigl(0, (x - x_a)/(x_b - x_a)\bigr)\bigr),

    with :math:`z_p` the profile, :math:`D` the channel depth on the plane, :math:`b` its
    half-width (depth :math:`D/e` at :math:`|y| = b`) and :math:`x_a, x_b` the ends of the arc.
    ``f`` is 1 on the plane, 0 on the run-out (which stays flat, z = 0), with
    :math:`f'(x_a) = f'(x_b) = 0`, so z is C1. The cross-slope is
    :math:`\partial z/\partial y = 2 D f(x) (y/b^2) e^{-(y/b)^2}`, steepest at
    :math:`|y| = b/\sqrt 2`.

    Parameters are those of :func:`inclined_plane_to_flat` and ``channel_depth`` (D, m, >= 0)
    and ``channel_half_width`` (b, m).
    """
    start, end = _profile_layout(length, runout_length, slope_angle, transition_radius)
    depth = _positive(channel_depth, "channel_depth", allow_zero=True)
    half_width = _positive(channel_half_width, "channel_half_width")

    def elevation(x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
        z, _ = plane_to_flat_profile(
            x, slope_angle=slope_angle, transition_radius=transition_radius, transition_end=end
        )
        xi = np.clip((x - start) / (end - start), 0.0, 1.0)
        fade = 1.0 - xi * xi * (3.0 - 2.0 * xi)
        result: NDArray[np.float64] = z - depth * fade * np.exp(-((y / half_width) ** 2))
        return result

    half = _positive(width, "width") / 2.0
    return dem_from_function(elevation, (0.0, length), (-half, half), cell_size, crs)


def bowl_radius(size: float, max_slope_angle: float) -> float:
    r"""Radius of curvature :math:`R = \sqrt 2\,(s/2) / \tan\theta_\max` of the bowl of
    :func:`bowl` on a square of side ``s``."""
    half = _positive(size, "size") / 2.0
    return math.sqrt(2.0) * half / math.tan(_angle(max_slope_angle, "max_slope_angle"))


def bowl(
    *,
    size: float = 1000.0,
    cell_size: float = 5.0,
    max_slope_angle: float = 35.0,
    crs: str | None = None,
) -> DigitalElevationModel:
    r"""A paraboloid bowl on the square :math:`[-s/2, s/2]^2`:

    .. math:: z(x, y) = \frac{x^2 + y^2}{2R}, \qquad \tan\theta = \frac{r}{R},

    the slope angle θ growing with the distance :math:`r = \sqrt{x^2 + y^2}` from the centre to
    ``max_slope_angle`` at the corners of the square (:math:`r = \sqrt 2\, s/2`), so
    :math:`R = \sqrt 2\,(s/2)/\tan\theta_\max` (:func:`bowl_radius`). With the defaults
    (1000 m at 5 m cells, 35 degrees) R = 1010 m, 26.3 degrees at the middles of the sides and a
    rim 248 m above the centre at the corners.

    Parameters
    ----------
    size : float
        Side s of the square, m; a whole number of cells.
    cell_size : float
        Cell width, m.
    max_slope_angle : float
        Slope angle at the corners, degrees in (0, 90).
    crs : str or None
        CRS to attach (a projected one in metres), or none.
    """
    radius = bowl_radius(size, max_slope_angle)

    def elevation(x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
        result: NDArray[np.float64] = (x * x + y * y) / (2.0 * radius)
        return result

    half = size / 2.0
    return dem_from_function(elevation, (-half, half), (-half, half), cell_size, crs)
