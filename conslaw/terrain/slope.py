"""The slope of a DEM: the elevation gradient, the cosine of the slope angle, the slope angle.

The gradient is ``numpy.gradient`` with ``edge_order=2``: central differences inside, one-sided
second-order differences on the edge cells, so a plane and a paraboloid give their exact slopes
(to round-off) on every cell, the edges included.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from conslaw.terrain.dem import DigitalElevationModel


def elevation_gradient(
    dem: DigitalElevationModel,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(dz/dx, dz/dy)`` on the cells of ``dem``, each ``(ny, nx)``.

    Second-order differences (``numpy.gradient``, ``edge_order=2``):
    ``dz/dx ≈ (z[k, j+1] - z[k, j-1]) / (2 c)`` inside, one-sided on the edges; ``dz/dy``
    along the rows the same way (y ascending, so a surface rising to the north has
    ``dz/dy > 0``).
    """
    dz_dy, dz_dx = np.gradient(dem.elevation, dem.cell_size, dem.cell_size, edge_order=2)
    return np.asarray(dz_dx, dtype=np.float64), np.asarray(dz_dy, dtype=np.float64)


def slope_cosine(dem: DigitalElevationModel) -> NDArray[np.float64]:
    r"""The cosine of the slope angle θ of each cell, ``(ny, nx)``:

    .. math:: \cos\theta = \frac{1}{\sqrt{1 + (\partial z/\partial x)^2
              + (\partial z/\partial y)^2}},

    the z component of the unit upward normal ``(-z_x, -z_y, 1) / |(-z_x, -z_y, 1)|`` of the
    surface ``z(x, y)``, with the gradient of :func:`elevation_gradient`. A slope-normal
    thickness ``h`` of a layer is ``d cos θ`` for its vertical thickness ``d``.
    """
    dz_dx, dz_dy = elevation_gradient(dem)
    result: NDArray[np.float64] = 1.0 / np.sqrt(1.0 + dz_dx * dz_dx + dz_dy * dz_dy)
    return result


def slope_angle(dem: DigitalElevationModel) -> NDArray[np.float64]:
    """The slope angle θ of each cell in degrees, ``(ny, nx)``:
    ``θ = arctan |∇z|`` with the gradient of :func:`elevation_gradient`."""
    dz_dx, dz_dy = elevation_gradient(dem)
    result: NDArray[np.float64] = np.degrees(np.arctan(np.hypot(dz_dx, dz_dy)))
    return result
