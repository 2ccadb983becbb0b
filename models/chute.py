"""Chute geometry in chute-fitted coordinates: inclination ``zeta(x)`` and ``lambda kappa(x)``.

``x`` is the arc length along the bed (downslope), ``zeta`` the inclination angle (positive where
the bed descends in +x), and ``lambda kappa = -d zeta / dx`` the scaled curvature (docs/design.md,
"Savage–Hutter specifics").

Three kinds:

- ``plane``: constant ``zeta``.
- ``paper``: the chute of Tai et al. (2001) Fig. 3: ``zeta_start`` up to ``transition_start``,
  falling linearly to ``zeta_end`` at ``transition_end``, constant after.
- ``table``: a CSV file with a header, either ``x,zeta`` (arc length, degrees) or ``x,z``
  (horizontal position, elevation: a terrain profile, e.g. from a DEM). For ``x,z`` the arc length
  and the angle are derived from a smoothing spline of the profile (scipy's
  ``make_smoothing_spline``, smoothing chosen by generalised cross-validation), so that noise in
  the elevations does not become noise in the curvature; a profile of more than
  ``MAX_SPLINE_ROWS`` rows is first averaged over that many groups of consecutive rows (the
  cross-validation costs about 1 ms per row). For ``x,zeta`` the angle is interpolated
  by a monotone cubic (PCHIP); its derivative gives the curvature. Outside the table the chute
  continues with the end angles and no curvature. An empty file, or one above
  ``MAX_TABLE_BYTES``, is refused.
"""

from __future__ import annotations

import functools
import io
import math
import os
import stat
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from conslaw.errors import ConfigError, finite_number

Array = NDArray[np.float64]


class Chute:
    """Base class: ``zeta(x)`` in radians and ``curvature(x) = -d zeta/dx``."""

    def zeta(self, x: Array) -> Array:
        """Inclination angle in radians at arc length x."""
        raise NotImplementedError

    def curvature(self, x: Array) -> Array:
        """``lambda kappa = -d zeta / dx`` at arc length x."""
        raise NotImplementedError

    def uncovered(self, x_min: float, x_max: float) -> str | None:
        """What of ``[x_min, x_max]`` the chute's own data do not cover (None: all of it; a
        chute given by a formula covers every x)."""
        return None

    def features(self) -> list[tuple[float, float, str]]:
        """Stretches of arc length worth marking in a figure: ``(start, end, label)``."""
        return []

    def elevation_profile(self, x: Array) -> tuple[Array, Array]:
        """Horizontal position and elevation of the bed at arc lengths x (for drawing), from
        ``dX/dx = cos zeta``, ``dZ/dx = -sin zeta`` integrated from ``x[0]`` (trapezoid rule on a
        fine grid)."""
        x = np.asarray(x, dtype=np.float64)
        fine = np.linspace(x.min(), x.max(), 20 * x.size + 1)
        angle = self.zeta(fine)
        step = np.diff(fine)
        horizontal = np.concatenate(
            [[0.0], np.cumsum(0.5 * step * (np.cos(angle[1:]) + np.cos(angle[:-1])))]
        )
        vertical = np.concatenate(
            [[0.0], -np.cumsum(0.5 * step * (np.sin(angle[1:]) + np.sin(angle[:-1])))]
        )
        return np.interp(x, fine, horizontal), np.interp(x, fine, vertical)


def _angle(value: float, name: str) -> float:
    value = finite_number(value, f"parameters.{name} (an angle in degrees)")
    if not -90.0 < value < 90.0:
        raise ConfigError(f"parameters.{name}: angle must be in (-90, 90) degrees, got {value}")
    return math.radians(value)


@dataclass(frozen=True)
class PlaneChute(Chute):
    """Constant inclination (radians)."""

    angle: float

    def zeta(self, x: Array) -> Array:
        return np.full(np.shape(x), self.angle)

    def curvature(self, x: Array) -> Array:
        return np.zeros(np.shape(x))


@dataclass(frozen=True)
class PaperChute(Chute):
    """Plane, linear transition of the angle, flat (or other) run-out (angles in radians)."""

    angle_start: float
    transition_start: float
    transition_end: float
    angle_end: float

    def features(self) -> list[tuple[float, float, str]]:
        """The curved transition between the two planes."""
        return [(self.transition_start, self.transition_end, "curved transition")]

    def zeta(self, x: Array) -> Array:
        return np.interp(
            np.asarray(x, dtype=np.float64),
            [self.transition_start, self.transition_end],
            [self.angle_start, self.angle_end],
        )

    def curvature(self, x: Array) -> Array:
        x = np.asarray(x, dtype=np.float64)
        rate = (self.angle_start - self.angle_end) / (self.transition_end - self.transition_start)
        inside = (x > self.transition_start) & (x < self.transition_end)
        return np.where(inside, rate, 0.0)


#: A chute table larger than this is refused (a 1D profile at 1 m spacing over 100 km is 5 MB).
MAX_TABLE_BYTES = 200 * 1024 * 1024
#: A profile ``x,z`` with more rows is averaged in this many groups of consecutive rows before the
#: smoothing spline is fitted (its cross-validation costs about 1 ms per row).
MAX_SPLINE_ROWS = 2000


def _read_table(path: Path) -> np.ndarray:
    """The CSV table at ``path`` as a structured array with the header's names. UTF-8 (a
    byte-order mark is skipped); comment lines (``#``) and blank lines before the header are
    skipped, as a DEM export may start with them."""
    try:
        size = path.stat().st_size
        if size > MAX_TABLE_BYTES:
            raise ConfigError(
                f"parameters.chute_file: '{path}' is {size / 2**20:.0f} MiB; a chute table may "
                f"have at most {MAX_TABLE_BYTES // 2**20} MiB (thin the profile)"
            )
        raw = path.read_bytes()
    except OSError as error:
        raise ConfigError(f"parameters.chute_file: cannot read '{path}': {error}") from None
    if not raw:
        raise ConfigError(f"parameters.chute_file: '{path}' is empty")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise ConfigError(
            f"parameters.chute_file: cannot read '{path}': not UTF-8 text ({error.reason} at "
            f"byte {error.start})"
        ) from None
    lines = text.splitlines()
    while lines and (not lines[0].strip() or lines[0].lstrip().startswith("#")):
        lines.pop(0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy warns instead of failing on some broken tables
        try:
            return np.genfromtxt(
                io.StringIO("\n".join(lines)), delimiter=",", names=True, dtype=float
            )
        except (ValueError, IndexError, UserWarning) as error:
            # numpy's message may span lines ("Some errors were detected !\n Line #23 ...").
            reason = "; ".join(part.strip() for part in str(error).splitlines() if part.strip())
            raise ConfigError(
                f"parameters.chute_file: cannot read '{path}': {reason[:200]}"
            ) from None


def binned_profile(x: Array, z: Array, rows: int) -> tuple[Array, Array]:
    """A profile of at most ``rows`` rows: the means of ``x`` and ``z`` over groups of
    consecutive rows (the table itself if it is short enough). The first and last rows are
    kept as they are, so the binned profile spans the same ``x``."""
    if x.size <= rows:
        return x, z
    inner, groups = x.size - 2, rows - 2
    edges = (np.arange(groups + 1) * inner) // groups  # group g is rows edges[g] .. edges[g+1]-1
    counts = np.diff(edges).astype(np.float64)
    inner_x = np.add.reduceat(x[1:-1], edges[:-1]) / counts
    inner_z = np.add.reduceat(z[1:-1], edges[:-1]) / counts
    return np.concatenate([x[:1], inner_x, x[-1:]]), np.concatenate([z[:1], inner_z, z[-1:]])


class TableChute(Chute):
    """A chute from a CSV table (``x,zeta`` in degrees, or a profile ``x,z``)."""

    def __init__(self, path: str | Path) -> None:
        if not isinstance(path, str | Path) or not str(path):
            raise ConfigError(f"parameters.chute_file: expected a file name, got {path!r}")
        if "\0" in str(path):
            raise ConfigError(
                f"parameters.chute_file: {str(path)!r}: a name cannot hold a NUL byte"
            )
        path = Path(path)
        if path.exists() and not path.is_file():
            # A folder, or a device such as /dev/zero that would be read forever.
            raise ConfigError(f"parameters.chute_file: '{path}' is not a regular file")
        data = _read_table(path)
        names = tuple(data.dtype.names or ())
        if names not in (("x", "zeta"), ("x", "z")):
            raise ConfigError(
                f"parameters.chute_file: '{path}' needs a header 'x,zeta' (degrees) or 'x,z' "
                f"(elevation), got {','.join(names) or 'none'}"
            )
        data = np.atleast_1d(data)
        x = np.asarray(data["x"], dtype=np.float64)
        values = np.asarray(data[names[1]], dtype=np.float64)
        if x.size < 5:
            raise ConfigError(
                f"parameters.chute_file: '{path}' needs at least 5 rows, got {x.size}"
            )
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(values))):
            raise ConfigError(f"parameters.chute_file: '{path}' has empty or non-finite entries")
        if np.any(np.diff(x) <= 0):
            raise ConfigError(f"parameters.chute_file: x must be strictly increasing in '{path}'")
        # Imported here: scipy.interpolate costs about 0.4 s, and only a table chute needs it.
        from scipy.interpolate import PchipInterpolator, make_smoothing_spline

        # One row's spacing along the bed: how far a domain may reach past the table's ends.
        steps = np.diff(x) if names[1] == "zeta" else np.hypot(np.diff(x), np.diff(values))
        self._row_spacing = float(np.max(steps))
        if names[1] == "zeta":
            if np.any(np.abs(values) >= 90):
                raise ConfigError(f"parameters.chute_file: angles must be in (-90, 90) in '{path}'")
            self._s = x
            self._angle = PchipInterpolator(x, np.radians(values), extrapolate=False)
        else:
            x, values = binned_profile(x, values, MAX_SPLINE_ROWS)
            try:
                # Underflow is harmless (a bump of 1e-199 m is a flat bed); overflow and
                # invalid values are not.
                with np.errstate(all="raise", under="ignore"), warnings.catch_warnings():
                    warnings.simplefilter("error")
                    spline = make_smoothing_spline(x, values)
                    slope = spline.derivative()
                    fine = np.linspace(x[0], x[-1], 50 * x.size + 1)
                    metric = np.sqrt(1.0 + slope(fine) ** 2)
                    arc = np.concatenate(
                        [[0.0], np.cumsum(0.5 * np.diff(fine) * (metric[1:] + metric[:-1]))]
                    )
                if not (np.all(np.isfinite(arc)) and np.all(np.diff(arc) > 0)):
                    raise FloatingPointError("the arc length is not finite and increasing")
            except (ValueError, FloatingPointError, ArithmeticError, Warning) as error:
                reason = " ".join(str(error).split())[:160]
                raise ConfigError(
                    f"parameters.chute_file: cannot fit a smooth bed to the profile in '{path}' "
                    f"({reason}); check its units and spacing"
                ) from None
            arc += x[0]
            self._s = arc
            self._angle = PchipInterpolator(arc, -np.arctan(slope(fine)), extrapolate=False)
        self._rate = self._angle.derivative()

    def zeta(self, x: Array) -> Array:
        x = np.clip(np.asarray(x, dtype=np.float64), self._s[0], self._s[-1])
        return np.asarray(self._angle(x))

    def uncovered(self, x_min: float, x_max: float) -> str | None:
        """The domain's part beyond the table's arc lengths ``[s_0, s_end]``, where the chute
        would continue as a plane at the angle of the table's nearer end."""
        first, last = float(self._s[0]), float(self._s[-1])
        slack = self._row_spacing  # the arc length of a profile comes from a smoothed fit
        if x_min >= first - slack and x_max <= last + slack:
            return None
        return (
            f"the chute table covers arc lengths x in [{first:.6g}, {last:.6g}] (along the "
            f"smoothed profile, give or take one row), the domain is [{x_min:.6g}, {x_max:.6g}]"
        )

    def curvature(self, x: Array) -> Array:
        x = np.asarray(x, dtype=np.float64)
        inside = (x >= self._s[0]) & (x <= self._s[-1])
        rate = np.asarray(self._rate(np.clip(x, self._s[0], self._s[-1])))
        return np.where(inside, -rate, 0.0)


CHUTE_KINDS = ("plane", "paper", "table")


@functools.lru_cache(maxsize=8)
def _table_chute(name: str, version: tuple[str, int, int, int]) -> TableChute:
    """The chute of the table ``name``, read and fitted once per ``version`` of the file (its
    real path, modification time, size and inode): a scene's model is built more than once
    (validation, the check of a Scene, the run)."""
    return TableChute(name)


def make_chute(
    kind: str,
    zeta: float,
    transition_start: float,
    transition_end: float,
    zeta_end: float,
    chute_file: str,
) -> Chute:
    """Build a chute from the Savage–Hutter parameters (angles in degrees)."""
    if kind == "plane":
        return PlaneChute(_angle(zeta, "zeta"))
    if kind == "paper":
        for name, value in (
            ("transition_start", transition_start),
            ("transition_end", transition_end),
        ):
            finite_number(value, f"parameters.{name}")
        if not transition_end > transition_start:
            raise ConfigError(
                "parameters.transition_end must be > transition_start, got "
                f"{transition_start}, {transition_end}"
            )
        return PaperChute(
            _angle(zeta, "zeta"), float(transition_start), float(transition_end),
            _angle(zeta_end, "zeta_end"),
        )  # fmt: skip
    if kind == "table":
        if not chute_file:
            raise ConfigError("parameters.chute_file is required with chute = 'table'")
        if not isinstance(chute_file, str | Path):
            raise ConfigError(f"parameters.chute_file: expected a file name, got {chute_file!r}")
        try:
            status = os.stat(chute_file)
        except (OSError, ValueError):
            return TableChute(chute_file)  # which names the problem
        if not stat.S_ISREG(status.st_mode):
            return TableChute(chute_file)
        version = (os.path.realpath(chute_file), status.st_mtime_ns, status.st_size, status.st_ino)
        return _table_chute(str(chute_file), version)
    raise ConfigError(
        f"parameters.chute: unknown chute '{kind}'; allowed: {', '.join(CHUTE_KINDS)}"
    )
