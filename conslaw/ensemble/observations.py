"""What a calibration compares a member with: observed summary figures and an observed deposit,
each with its standard error, and the weighted residuals whose sum of squares is the misfit
(docs/calibration.md, "The misfit").

An observation of a summary figure ``runout_length=33.67`` gives one residual
``(model - observed) / sigma``. An observed deposit gives one residual per cell of the scene: a
1D depth profile (a CSV file of ``x, depth`` rows) is interpolated onto the cell centres and
compared with the final depth; a 2D deposit raster (GeoTIFF or ESRI ASCII grid) is sampled at
the cell centres and its covered area compared with the member's. The residuals are signed, so
that their slopes give the linearised uncertainty (Gauss–Newton; docs/calibration.md).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.ensemble.summary import SUMMARY_1D, SUMMARY_2D
from conslaw.errors import ConfigError
from conslaw.peak_fields import REACHED_DEPTH

Array = NDArray[np.float64]

#: The name of a deposit observation (``--observed deposit=FILE``).
DEPOSIT = "deposit"
#: Summary figures that are not observations of a flow (bookkeeping of the run).
NOT_OBSERVABLE = ("mass_drift", "at_rest", "at_boundary", "steps", "solve_seconds")
#: The figures an observation may name, by dimension (besides :data:`DEPOSIT`).
OBSERVABLE = {
    # 1D max_speed is sampled at the output times only: a fit to it would fit the sampling.
    1: tuple(name for name in SUMMARY_1D if name not in (*NOT_OBSERVABLE, "max_speed")),
    2: tuple(name for name in SUMMARY_2D if name not in NOT_OBSERVABLE),
}
#: The default standard error of an observation, relative to its magnitude (docs/calibration.md).
RELATIVE_ERROR = 0.01
#: A 2D cell counts as covered by the deposit from this depth on (the hazard maps' reached
#: depth, :data:`conslaw.peak_fields.REACHED_DEPTH`).
COVERED_DEPTH = REACHED_DEPTH


@dataclass(frozen=True, eq=False)
class Deposit:
    """An observed deposit.

    Attributes
    ----------
    path : Path
        The file it was read from.
    x : ndarray
        1D: the profile's abscissae (increasing); 2D: the raster cells' x centres (nx,).
    y : ndarray or None
        2D: the raster cells' y centres (ny,), ascending; None for a profile.
    depth : ndarray
        1D: the depth at ``x``; 2D: ``(ny, nx)``, NaN where the raster has no data.
    cell_size : float
        2D: the raster's cell width (0 for a profile).
    """

    path: Path
    x: Array
    y: Array | None
    depth: Array
    cell_size: float = 0.0

    @property
    def magnitude(self) -> float:
        """The scale of a default standard error: the largest observed depth (1D), 1 (2D: the
        residual is ``1 - overlap``, a fraction)."""
        return float(np.nanmax(self.depth)) if self.y is None else 1.0


@dataclass(frozen=True, eq=False)
class Observation:
    """One observation and its standard error.

    Attributes
    ----------
    name : str
        A summary figure (:data:`OBSERVABLE`) or :data:`DEPOSIT`.
    value : float
        The observed figure (NaN for a deposit).
    sigma : float
        Its standard error, in the figure's units (a deposit: see :func:`residuals`).
    deposit : Deposit or None
    """

    name: str
    value: float
    sigma: float
    deposit: Deposit | None = None

    @property
    def folded(self) -> bool:
        """Its residual is a distance, never negative (a 2D deposit's overlap): a minimum shaped
        like a V, which the uncertainty takes as a slope on each side (docs/calibration.md)."""
        return self.deposit is not None and self.deposit.y is not None

    @property
    def shown(self) -> str:
        """The observation as given on the command line."""
        if self.deposit is not None:
            return f"{self.name}={self.deposit.path}"
        return f"{self.name}={self.value:.6g}"


def split_pair(text: str, option: str, form: str) -> tuple[str, str]:
    """``NAME`` and ``VALUE`` of ``NAME=VALUE``; a ConfigError naming ``option`` otherwise."""
    name, separator, value = str(text).partition("=")
    if not separator or not name.strip() or not value.strip():
        raise ConfigError(f"{option} expects {form}, got '{text}'")
    return name.strip(), value.strip()


def parse_number(text: Any, where: str) -> float:
    """``text`` as a finite float; a ConfigError starting with ``where`` otherwise."""
    try:
        number = float(text)
    except (TypeError, ValueError):
        raise ConfigError(f"{where}: expected a finite number, got '{text}'") from None
    if not math.isfinite(number):
        raise ConfigError(f"{where}: expected a finite number, got '{text}'")
    return number


def possible_range(name: str, dimension: int, grid: Any) -> tuple[float, float, str]:
    """The values a summary figure ``name`` of a scene on ``grid`` can take, ``(low, high,
    why)``: a margin or a centre of mass lies in the domain, a run-out length between 0 and the
    domain's length (1D, along the chute) or diagonal (2D), a travel angle in (-90, 90)
    degrees, a peak depth or speed is >= 0; ``(-inf, inf, "")`` where nothing bounds it (the
    drop) or the grid is not known."""
    inf = math.inf
    if name == "travel_angle":
        return -90.0, 90.0, "a travel angle lies in (-90, 90) degrees"
    if name in ("max_depth", "max_speed"):
        return 0.0, inf, f"a {name.replace('_', ' ')} is >= 0"
    if grid is None:
        return -inf, inf, ""
    x_axis = grid.x if dimension == 2 else grid
    x_range = (float(x_axis.x_min), float(x_axis.x_max))
    if name in ("front", "rear", "deposit_centre", "deposit_x"):
        return *x_range, f"it lies in the domain, x in [{x_range[0]:g}, {x_range[1]:g}]"
    if name == "deposit_y":
        low, high = float(grid.y.x_min), float(grid.y.x_max)
        return low, high, f"it lies in the domain, y in [{low:g}, {high:g}]"
    if name == "runout_length":
        length = x_range[1] - x_range[0]
        if dimension == 2:
            length = math.hypot(length, float(grid.y.x_max - grid.y.x_min))
        return 0.0, length, f"a run-out lies between 0 and the domain's extent {length:g}"
    return -inf, inf, ""


def read_observations(
    observed: Mapping[str, Any],
    tolerance: Mapping[str, Any],
    dimension: int,
    grid: Any,
) -> list[Observation]:
    """The observations of a scene of ``dimension`` (1 or 2) on ``grid``, each with its standard
    error: ``tolerance[name]`` if given, else :data:`RELATIVE_ERROR` times the observation's
    magnitude.

    Parameters
    ----------
    observed : mapping of str to float or path
        Figure name -> observed value; ``deposit`` -> a file.
    tolerance : mapping of str to float
        Figure name -> standard error (> 0), in the figure's units.
    dimension : int
    grid : Grid or Grid2D
        The scene's cells (a 2D deposit raster must overlap them).

    Returns
    -------
    list of Observation
        In the order given.
    """
    known = (*OBSERVABLE[dimension], DEPOSIT)
    if not observed:
        raise ConfigError(
            f"--observed: at least one observation is needed, NAME=VALUE with NAME one of "
            f"{', '.join(known)}"
        )
    for name in [*observed, *tolerance]:
        if name not in known:
            option = "--observed" if name in observed else "--tolerance"
            raise ConfigError(
                f"{option} {name}: not a figure of a {dimension}D scene; known: {', '.join(known)}"
            )
    extra = sorted(set(tolerance) - set(observed))
    if extra:
        raise ConfigError(f"--tolerance {extra[0]}: no --observed {extra[0]} to go with it")
    observations = []
    for name, given in observed.items():
        deposit = read_deposit(Path(given), dimension, grid) if name == DEPOSIT else None
        value = math.nan if deposit is not None else parse_number(given, f"--observed {name}")
        low, high, why = possible_range(name, dimension, grid)
        inside = low < value < high if name == "travel_angle" else low <= value <= high
        if deposit is None and not inside:
            raise ConfigError(f"--observed {name}={value:g}: no member can match it ({why})")
        magnitude = deposit.magnitude if deposit is not None else abs(value)
        sigma = RELATIVE_ERROR * magnitude
        if name in tolerance:
            sigma = parse_number(tolerance[name], f"--tolerance {name}")
        if not sigma > 0:
            raise ConfigError(
                f"--tolerance {name}: the observation's error must be > 0"
                + ("" if name in tolerance else f" (an observed {name} of 0 needs one)")
            )
        observations.append(Observation(name, value, sigma, deposit))
    return observations


def read_deposit(path: Path, dimension: int, grid: Any) -> Deposit:
    """An observed deposit: a 1D profile or a 2D raster.

    Parameters
    ----------
    path : Path
        1D: a CSV file of two columns ``x, depth`` (an optional header line), ``x``
        increasing, ``depth >= 0``. 2D: a GeoTIFF or ESRI ASCII grid of depths
        (:func:`conslaw.terrain.raster.read_raster`), in the scene's map coordinates.
    dimension : int
        The scene's, 1 or 2.
    grid : Grid2D or None
        2D: the scene's cells, some of which the deposit must cover.

    Returns
    -------
    Deposit

    Raises
    ------
    ConfigError
        Naming the file: missing, not a table or raster, or no depth.
    """
    where = f"--observed deposit: '{path}'"
    if "\0" in str(path):
        raise ConfigError(f"{where}: a file name cannot hold a NUL byte")
    if not path.is_file():
        raise ConfigError(f"{where}: {'a folder, not a file' if path.is_dir() else 'no such file'}")
    if dimension == 2:
        return _read_raster_deposit(path, where, grid)
    try:
        with warnings.catch_warnings():  # an empty file: the check below says so in one line
            warnings.simplefilter("ignore", UserWarning)
            skip = _header_lines(path)
            table = np.genfromtxt(path, delimiter=",", dtype=float, skip_header=skip)
    except (OSError, ValueError) as error:
        raise ConfigError(f"{where}: not a CSV table of x, depth ({error})") from None
    table = np.atleast_2d(table)
    if table.ndim != 2 or table.shape[1] != 2 or table.shape[0] < 2:
        raise ConfigError(f"{where}: expected two columns x, depth and at least 2 rows")
    x, depth = np.asarray(table[:, 0], dtype=float), np.asarray(table[:, 1], dtype=float)
    if not (np.all(np.isfinite(table)) and np.all(np.diff(x) > 0) and np.all(depth >= 0)):
        raise ConfigError(f"{where}: expected numbers, x increasing and depth >= 0 on every row")
    if not np.max(depth) > 0:
        raise ConfigError(f"{where}: the observed depth is 0 everywhere")
    return Deposit(path, x, None, depth)


def _header_lines(path: Path) -> int:
    """1 if the CSV file's first line is a header (not numbers), else 0."""
    with path.open(encoding="utf-8", errors="replace") as stream:
        first = stream.readline()
    try:
        [float(part) for part in first.split(",")]
    except ValueError:
        return 1
    return 0


def _read_raster_deposit(path: Path, where: str, grid: Any) -> Deposit:
    from conslaw.terrain.raster import read_raster

    band = read_raster(path, where)
    ny, nx = band.shape
    x = np.asarray(band.x_min + (np.arange(nx) + 0.5) * band.cell_size, dtype=np.float64)
    y = np.asarray(band.y_min + (np.arange(ny) + 0.5) * band.cell_size, dtype=np.float64)
    depth = np.where(band.missing, np.nan, band.values)
    deposit = Deposit(path, x, y, depth, band.cell_size)
    covered = _raster_covered(deposit, *grid.centres())
    if not covered.any():
        raise ConfigError(
            f"{where}: no cell of the scene is covered by the observed deposit "
            f"(depth >= {COVERED_DEPTH:g} at the cell centres)"
        )
    return deposit


def _raster_covered(deposit: Deposit, x: Array, y: Array) -> NDArray[np.bool_]:
    """Whether the observed deposit covers each cell centre of the scene, ``(ny, nx)``: the
    raster's cell holding the centre has a depth of at least :data:`COVERED_DEPTH` (a centre
    outside the raster or on a no-data cell is not covered)."""
    assert deposit.y is not None
    size = deposit.cell_size
    columns = np.floor((np.asarray(x) - (deposit.x[0] - size / 2)) / size).astype(int)
    rows = np.floor((np.asarray(y) - (deposit.y[0] - size / 2)) / size).astype(int)
    inside_x = (columns >= 0) & (columns < deposit.x.size)
    inside_y = (rows >= 0) & (rows < deposit.y.size)
    sampled = deposit.depth[np.clip(rows, 0, deposit.y.size - 1)][
        :, np.clip(columns, 0, deposit.x.size - 1)
    ]
    inside = inside_y[:, None] & inside_x[None, :]
    return inside & (np.nan_to_num(sampled, nan=0.0) >= COVERED_DEPTH)


def residuals(
    observations: list[Observation], summary: Mapping[str, float], maps: Mapping[str, Array]
) -> Array:
    """The weighted residuals of one member; the misfit is the sum of their squares.

    A summary figure: ``(m - o) / sigma``. A 1D deposit: ``(h(x_k) - h_obs(x_k)) /
    (sigma sqrt(N))`` at each of the ``N`` cell centres ``x_k`` (the observed profile linearly
    interpolated, 0 outside it), so that its squares sum to ``(RMS(h - h_obs) / sigma)^2``. A
    2D deposit: ``(1 - overlap) / sigma``, the overlap of the covered areas
    (:func:`deposit_agreement`); it is never negative (:func:`folded_rows`).

    Parameters
    ----------
    observations : list of Observation
    summary : mapping
        The member's summary figures (:func:`~conslaw.ensemble.summary.member_summary`).
    maps : mapping
        The member's maps (:func:`~conslaw.ensemble.summary.member_fields`), for a deposit.

    Returns
    -------
    ndarray
        NaN where the member has no value for a figure.
    """
    parts = []
    for observation in observations:
        if observation.deposit is None:
            value = summary.get(observation.name, math.nan)
            parts.append(np.array([(value - observation.value) / observation.sigma]))
        else:
            parts.append(_deposit_residuals(observation, maps))
    return np.concatenate(parts) if parts else np.zeros(0)


def folded_rows(observations: list[Observation], size: int) -> NDArray[np.bool_]:
    """Which of the ``size`` residuals of a member (:func:`residuals`) belong to a folded
    observation (:attr:`Observation.folded`); a 1D deposit has the rows no figure takes."""
    cells = size - sum(o.deposit is None or o.folded for o in observations)
    rows = [np.full(cells if o.deposit is not None and not o.folded else 1, o.folded)
            for o in observations]  # fmt: skip
    return np.concatenate(rows) if rows else np.zeros(0, dtype=bool)


def _deposit_residuals(observation: Observation, maps: Mapping[str, Array]) -> Array:
    deposit = observation.deposit
    assert deposit is not None
    if deposit.y is None:
        if "final_depth" not in maps:
            return np.array([math.nan])
        x = maps["_x"]
        observed = np.interp(x, deposit.x, deposit.depth, left=0.0, right=0.0)
        scale = observation.sigma * math.sqrt(x.size)
        return np.asarray((maps["final_depth"] - observed) / scale, dtype=float)
    overlap = deposit_agreement(observation, maps)["deposit_overlap"]
    return np.array([(1.0 - overlap) / observation.sigma])


def deposit_agreement(observation: Observation, maps: Mapping[str, Array]) -> dict[str, float]:
    """Figures of a member's deposit against the observed one.

    1D: ``deposit_rms``, the RMS of ``h - h_obs`` over the cells. 2D: ``deposit_overlap``, the
    overlap ``|A & B| / |A | B|`` of the covered areas (the Jaccard index; Jaccard 1912),
    ``A`` the member's cells of depth at least :data:`COVERED_DEPTH`, ``B`` the cells whose
    centre lies on an observed cell of at least that depth.

    Parameters
    ----------
    observation : Observation
    maps : mapping
        The member's maps (:func:`~conslaw.ensemble.summary.member_fields`).

    Returns
    -------
    dict of str to float
        Empty for a summary figure; NaN where the member has no map.
    """
    deposit = observation.deposit
    if deposit is None:
        return {}
    if deposit.y is None:
        if "final_depth" not in maps:
            return {"deposit_rms": math.nan}
        observed = np.interp(maps["_x"], deposit.x, deposit.depth, left=0.0, right=0.0)
        return {"deposit_rms": float(np.sqrt(np.mean((maps["final_depth"] - observed) ** 2)))}
    if "deposit" not in maps:
        return {"deposit_overlap": math.nan}
    seen = _raster_covered(deposit, maps["_x"], maps["_y"])
    covered = maps["deposit"] >= COVERED_DEPTH
    union = int(np.sum(seen | covered))
    return {"deposit_overlap": float(np.sum(seen & covered) / union) if union else math.nan}
