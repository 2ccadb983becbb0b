"""The Jiang–Tadmor staggered central step in numpy (Jiang & Tadmor 1998, SIAM J. Sci. Comput.
19, 1892–1917, the 2D form of the Nessyahu–Tadmor scheme of Tai et al. 2001, eqs. 10–15).

Cell averages alternate between the primary cells and the cells staggered by half a cell in both
directions (:class:`~conslaw.grid2d.Grid2D`). A new cell is centred on the common corner of four
source cells ``a`` (lower left), ``b`` (lower right), ``c`` (upper left), ``d`` (upper right),
with undivided slopes ``w'`` in x and ``w*`` in y (``w(x, y) = w + w' (x - x_j)/dx + w* (y -
y_k)/dy`` in each source cell)::

    w_new = (a + b + c + d)/4 + ((w'_a - w'_b) + (w'_c - w'_d))/16
            + ((w*_a - w*_c) + (w*_b - w*_d))/16
            - dt/(2 dx) ((f(p_b) - f(p_a)) + (f(p_d) - f(p_c)))
            - dt/(2 dy) ((g(p_c) - g(p_a)) + (g(p_d) - g(p_b)))
    p = w + dt/2 (-A(w) w'/dx - B(w) w*/dy)                   (the predictor at t + dt/2)

the fluxes through each half edge taken by the midpoint rule in time and along the edge. The sums
are grouped so that data that do not depend on y give the 1D Nessyahu–Tadmor step bit for bit
(``(a + b + a + b)/4 = (a + b)/2``, the y terms cancel exactly). The time step keeps the Courant
number below 1/2 in each direction, ``dt max|a_x| / dx`` and ``dt max|a_y| / dy``: then no wave
from the corner cells reaches the edges of the new cell, whose flux integrals use the corner
values only (Jiang & Tadmor 1998, section 2).

The reference is written for testing the compiled 2D kernel, not for speed. Boundaries per side:
periodic (on both sides of a direction), outflow (zero gradient) or wall (the mirror image, with
the signs ``Model.reflect_signs`` across an x wall and ``Model.reflect_signs_y`` across a y wall,
as the 1D ``wall`` condition: a primary family mirrors about the cell face, a staggered one about
the centre of its end cell, which straddles the wall). Sources come with the kernel.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, SchemeBreakdownError
from conslaw.grid2d import Grid2D
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor
from conslaw.reconstruct.base import STENCIL_HALF_WIDTH

Array = NDArray[np.float64]

#: Ghost cells per side: the slope stencil's half width and the staggered shift.
GHOSTS = STENCIL_HALF_WIDTH + 1
#: Courant number per direction that a step must stay below.
CFL_LIMIT = 0.5
SIDES = ("left", "right", "bottom", "top")
KINDS = ("periodic", "outflow", "wall")


class JiangTadmorReference:
    """The Jiang–Tadmor step for a two-dimensional model (``Model.n_dims == 2``).

    Parameters
    ----------
    model : Model
        With x and y fluxes, Jacobians and wave speeds, no source (for now).
    reconstructor : Reconstructor
        Limits the slopes in x and in y separately (any of the registry's).
    grid : Grid2D
    boundaries : mapping
        ``left``, ``right``, ``bottom``, ``top`` -> ``"periodic"`` or ``"outflow"``.
    cfl : float
        Courant number per direction, in (0, 1/2).
    """

    def __init__(
        self,
        model: Model,
        reconstructor: Reconstructor,
        grid: Grid2D,
        boundaries: Mapping[str, str],
        cfl: float = 0.45,
    ) -> None:
        if model.n_dims != 2:
            raise ConfigError(f"jiang-tadmor needs a 2D model; '{model.name}' is 1D")
        if model.capabilities()["source"] or model.n_aux:
            raise ConfigError(f"jiang-tadmor (reference): '{model.name}' has a source or aux")
        if set(boundaries) != set(SIDES):
            raise ConfigError(f"boundaries: need {', '.join(SIDES)}, got {sorted(boundaries)}")
        for side, kind in boundaries.items():
            if kind not in KINDS:
                raise ConfigError(f"boundary.{side}: '{kind}' is not one of {', '.join(KINDS)}")
        for low, high in (("left", "right"), ("bottom", "top")):
            if (boundaries[low] == "periodic") != (boundaries[high] == "periodic"):
                raise ConfigError(f"boundary.{low} and boundary.{high}: periodic on both or none")
        if not 0.0 < cfl < CFL_LIMIT:
            raise ConfigError(f"cfl must be in (0, {CFL_LIMIT}), got {cfl!r}")
        self.model = model
        self.reconstructor = reconstructor
        self.grid = grid
        self.boundaries = dict(boundaries)
        self.cfl = float(cfl)
        self.periodic_x = boundaries["left"] == "periodic"
        self.periodic_y = boundaries["bottom"] == "periodic"

    def family_shape(self, staggered: bool) -> tuple[int, int]:
        """``(rows, columns)`` of the primary or the staggered family."""
        return self.grid.shape_at(0.5 if staggered else 0.0, self.periodic_x, self.periodic_y)

    def padded(self, q: Array, staggered: bool) -> Array:
        """``q`` (one family, ``(n_vars, rows, columns)``) with GHOSTS ghost cells on every
        side: a periodic copy, the edge cell repeated (outflow), or the mirror image (wall)."""
        signs_x = np.asarray(self.model.reflect_signs, dtype=np.float64)
        signs_y = np.asarray(
            self.model.reflect_signs_y or self.model.reflect_signs, dtype=np.float64
        )
        w = q
        directions = ((2, "left", "right", signs_x), (1, "bottom", "top", signs_y))
        for axis, low, high, signs in directions:
            width = [(0, 0)] * 3
            if self.boundaries[low] == "periodic":  # both ends at once: each copies the other
                width[axis] = (GHOSTS, GHOSTS)
                w = np.pad(w, width, mode="wrap")
                continue
            for end, side in ((0, low), (1, high)):
                width[axis] = (GHOSTS, 0) if end == 0 else (0, GHOSTS)
                kind = self.boundaries[side]
                # A wall mirrors about the face, or about the centre of a staggered end cell.
                mode = "edge" if kind == "outflow" else "reflect" if staggered else "symmetric"
                w = np.pad(w, width, mode=mode)  # type: ignore[call-overload]
                if kind == "wall":
                    ghosts = [slice(None)] * 3
                    ghosts[axis] = slice(0, GHOSTS) if end == 0 else slice(-GHOSTS, None)
                    w[tuple(ghosts)] *= signs.reshape(-1, 1, 1)
        return w

    def courant_numbers(self, q: Array, dt: float) -> tuple[float, float]:
        """``dt max|a_x| / dx`` and ``dt max|a_y| / dy`` of the cells of ``q``."""
        flat = q.reshape(q.shape[0], -1)
        speed_x = float(np.max(self.model.max_wave_speed(flat)))
        speed_y = float(np.max(self.model.max_wave_speed(flat, direction="y")))
        return dt * speed_x / self.grid.dx, dt * speed_y / self.grid.dy

    def stable_dt(self, q: Array) -> float:
        """The largest ``dt`` with both Courant numbers at most ``cfl`` (inf at rest)."""
        unit_x, unit_y = self.courant_numbers(q, 1.0)
        largest = max(unit_x, unit_y)
        return np.inf if largest == 0.0 else self.cfl / largest

    def _slopes(self, w: Array, rows: slice, columns: slice) -> tuple[Array, Array]:
        """Limited undivided slopes in x and in y of the padded cells ``w[:, rows, columns]``."""
        half = STENCIL_HALF_WIDTH
        wide_x = w[:, rows, columns.start - half : columns.stop + half]
        slopes_x = self.reconstructor.slopes(wide_x)
        wide_y = w[:, rows.start - half : rows.stop + half, columns]
        slopes_y = self.reconstructor.slopes(wide_y.swapaxes(1, 2)).swapaxes(1, 2)
        return slopes_x, slopes_y

    def step(self, q: Array, staggered: bool, dt: float) -> Array:
        """One step from the family of ``q`` (``staggered`` or primary) to the other, ``dt``
        given; the new family's values, shape ``(n_vars, rows, columns)``.

        Raises
        ------
        SchemeBreakdownError
            If a Courant number of ``q`` reaches 1/2 with this ``dt``.
        """
        if max(self.courant_numbers(q, dt)) >= CFL_LIMIT:
            raise SchemeBreakdownError(
                f"dt={dt:g} makes a Courant number reach {CFL_LIMIT} (Jiang & Tadmor 1998)"
            )
        n_rows, n_columns = self.family_shape(not staggered)
        w = self.padded(q, staggered)
        first = GHOSTS + (0 if staggered else -1)
        rows = slice(first, first + n_rows + 1)
        columns = slice(first, first + n_columns + 1)
        slopes_x, slopes_y = self._slopes(w, rows, columns)
        values = w[:, rows, columns]
        predicted = self._predictor(values, slopes_x, slopes_y, dt)
        nv = values.shape[0]
        f = self.model.flux(predicted.reshape(nv, -1)).reshape(predicted.shape)
        g = self.model.flux(predicted.reshape(nv, -1), direction="y").reshape(predicted.shape)

        def corners(array: Array) -> tuple[Array, Array, Array, Array]:
            return array[:, :-1, :-1], array[:, :-1, 1:], array[:, 1:, :-1], array[:, 1:, 1:]

        a, b, c, d = corners(values)
        xa, xb, xc, xd = corners(slopes_x)
        ya, yb, yc, yd = corners(slopes_y)
        fa, fb, fc, fd = corners(f)
        ga, gb, gc, gd = corners(g)
        return (
            0.25 * ((a + b) + (c + d))
            + 0.0625 * ((xa - xb) + (xc - xd))
            + 0.0625 * ((ya - yc) + (yb - yd))
            - 0.5 * (dt / self.grid.dx) * ((fb - fa) + (fd - fc))
            - 0.5 * (dt / self.grid.dy) * ((gc - ga) + (gd - gb))
        )

    def _predictor(self, values: Array, slopes_x: Array, slopes_y: Array, dt: float) -> Array:
        """``w + dt/2 (-A(w) w'/dx - B(w) w*/dy)`` at every source cell."""
        nv = values.shape[0]
        flat = values.reshape(nv, -1)
        along_x = np.einsum(
            "rcm,cm->rm", self.model.flux_jacobian(flat), slopes_x.reshape(nv, -1)
        ) * (1.0 / self.grid.dx)
        along_y = np.einsum(
            "rcm,cm->rm", self.model.flux_jacobian(flat, direction="y"), slopes_y.reshape(nv, -1)
        ) * (1.0 / self.grid.dy)
        rate = -(along_x + along_y)
        return (flat + 0.5 * dt * rate).reshape(values.shape)

    def advance(self, q: Array, t: float, t_end: float) -> tuple[Array, float, int]:
        """Advance primary-family values ``q`` from ``t`` to exactly ``t_end`` by step pairs of
        one ``dt`` each (the last pair shortened to land on ``t_end``); the values, the time and
        the number of steps."""
        steps = 0
        while t < t_end:
            dt = min(self.stable_dt(q), 0.5 * (t_end - t))
            last = 2.0 * dt >= t_end - t
            middle = self.step(q, False, dt)
            q = self.step(middle, True, dt)
            t = t_end if last else t + 2.0 * dt
            steps += 2
        return q, t, steps
