"""The members of an ensemble: which scene keys vary, by which distribution, and the sample
design that draws their values (docs/ensembles.md, "Varied parameters and designs").

A variation is written ``KEY=DISTRIBUTION:ARGS`` (``parameters.delta=uniform:20:30``). The
design draws ``n`` points of the unit cube with :mod:`scipy.stats.qmc` (Latin hypercube, scrambled
Sobol', a full grid or plain random points) and maps each coordinate through the inverse
distribution function of its variation (McKay, Beckman & Conover 1979 for the Latin hypercube;
Owen 1998 for scrambled Sobol' points). The same seed gives the same members.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from conslaw.config import MAX_NESTING
from conslaw.errors import ConfigError, shown

Array = NDArray[np.float64]

#: Sample designs, by name.
DESIGNS = ("lhs", "sobol", "grid", "random")

#: Distributions and the arguments each takes after its name.
DISTRIBUTIONS = {
    "uniform": "LOW:HIGH",
    "loguniform": "LOW:HIGH (both > 0)",
    "normal": "MEAN:STD",
    "triangular": "LOW:MODE:HIGH",
    "choice": "V1,V2,... (equally likely)",
}


@dataclass(frozen=True)
class Variation:
    """One varied scene key: its name and the distribution its members' values follow.

    Attributes
    ----------
    key : str
        A scene key as ``--set`` takes it (``parameters.delta``, ``initial.height``).
    kind : str
        One of :data:`DISTRIBUTIONS`.
    arguments : tuple of float
        The distribution's arguments (:data:`DISTRIBUTIONS`; for ``choice``, the values).
    """

    key: str
    kind: str
    arguments: tuple[float, ...]

    @property
    def text(self) -> str:
        """The variation as written on the command line."""
        separator = "," if self.kind == "choice" else ":"
        return f"{self.key}={self.kind}:{separator.join(f'{a:.17g}' for a in self.arguments)}"

    def values(self, unit: Array) -> Array:
        """The values at points ``unit`` of (0, 1): the inverse distribution function."""
        from scipy import stats  # on first use: the command line imports this module

        low, *rest = self.arguments
        if self.kind == "uniform":
            return low + unit * (rest[0] - low)
        if self.kind == "loguniform":
            return np.asarray(stats.loguniform(low, rest[0]).ppf(unit), dtype=float)
        if self.kind == "normal":
            return np.asarray(stats.norm(low, rest[0]).ppf(unit), dtype=float)
        if self.kind == "triangular":
            mode, high = rest
            shape = (mode - low) / (high - low)
            return np.asarray(stats.triang(shape, loc=low, scale=high - low).ppf(unit), dtype=float)
        choices = np.asarray(self.arguments)
        index = np.minimum((unit * len(choices)).astype(int), len(choices) - 1)
        return np.asarray(choices[index], dtype=float)


def parse_variation(text: str) -> Variation:
    """A :class:`Variation` from ``KEY=DISTRIBUTION:ARGS``; a ConfigError naming what is wrong.

    Examples
    --------
    >>> parse_variation("parameters.delta=uniform:20:30").arguments
    (20.0, 30.0)
    """
    key, separator, spec = text.partition("=")
    key = key.strip()
    if not separator or not key:
        raise ConfigError(f"--vary expects KEY=DISTRIBUTION:ARGS, got {shown(text)}")
    if key.count(".") >= MAX_NESTING:
        raise ConfigError(
            f"--vary {shown(key, 40)}: {key.count('.') + 1} parts; at most {MAX_NESTING}"
        )
    kind, _, argument_text = spec.strip().partition(":")
    if kind not in DISTRIBUTIONS:
        known = ", ".join(f"{name}:{args}" for name, args in DISTRIBUTIONS.items())
        raise ConfigError(f"--vary {key}: unknown distribution '{kind}'; known: {known}")
    parts = argument_text.split("," if kind == "choice" else ":")
    try:
        arguments = tuple(float(part) for part in parts)
    except ValueError:
        raise ConfigError(
            f"--vary {key}: {kind} takes {DISTRIBUTIONS[kind]} as numbers, got '{argument_text}'"
        ) from None
    _check_arguments(key, kind, arguments)
    return Variation(key, kind, arguments)


def _check_arguments(key: str, kind: str, arguments: tuple[float, ...]) -> None:
    expected = {"uniform": 2, "loguniform": 2, "normal": 2, "triangular": 3}.get(kind)
    where = f"--vary {key}: {kind} takes {DISTRIBUTIONS[kind]}"
    if expected is not None and len(arguments) != expected:
        raise ConfigError(f"{where}, got {len(arguments)} numbers")
    if not all(math.isfinite(value) for value in arguments) or not arguments:
        raise ConfigError(f"{where}, finite, got {arguments}")
    if kind in ("uniform", "loguniform") and not arguments[0] < arguments[1]:
        raise ConfigError(f"{where} with LOW < HIGH, got {arguments[0]:g} and {arguments[1]:g}")
    if kind == "loguniform" and not arguments[0] > 0:
        raise ConfigError(f"{where}, got LOW = {arguments[0]:g}")
    if kind == "normal" and not arguments[1] > 0:
        raise ConfigError(f"{where} with STD > 0, got {arguments[1]:g}")
    if kind == "triangular" and not arguments[0] <= arguments[1] <= arguments[2]:
        raise ConfigError(f"{where} with LOW <= MODE <= HIGH, got {arguments}")
    if kind == "triangular" and not arguments[0] < arguments[2]:
        raise ConfigError(f"{where} with LOW < HIGH, got {arguments}")


#: Most members of one study (each is checked, and held in memory, before anything runs).
MAX_SAMPLES = 10_000_000
#: Largest seed: 64 bits (numpy and scipy take larger ones, but a seed is a label to repeat a
#: study by, and every file that keeps it holds this many bits).
MAX_SEED = 2**64 - 1


def check_seed(seed: object) -> int:
    """``seed`` as an int if it is an integer from 0 to :data:`MAX_SEED`; a ConfigError naming
    ``--seed`` otherwise (checked before anything runs: a seed numpy refuses, or one a file
    cannot hold, would stop a study after its members ran)."""
    import operator

    try:
        number = operator.index(seed)  # type: ignore[arg-type]
    except TypeError:
        number = None
    if isinstance(seed, bool) or number is None or not 0 <= number <= MAX_SEED:
        raise ConfigError(f"--seed: expected an integer from 0 to 2**64 - 1, got {shown(seed)}")
    return int(number)


def unit_points(design: str, samples: int, dimensions: int, seed: int) -> Array:
    """``samples`` points of the open unit cube ``(0, 1)^dimensions``, rows are members.

    ``lhs``: a Latin hypercube (every parameter's range cut into ``samples`` equal-probability
    bins, one point in each); ``sobol``: scrambled Sobol' points (balanced when ``samples`` is a
    power of 2, refused otherwise); ``grid``: every combination of ``k`` bin midpoints per
    parameter, ``samples = k ** dimensions``; ``random``: independent uniform points.
    """
    if design not in DESIGNS:
        raise ConfigError(f"--design: unknown design '{design}'; known: {', '.join(DESIGNS)}")
    if samples < 1:
        raise ConfigError(f"--samples: expected an integer >= 1, got {samples}")
    if samples > MAX_SAMPLES:
        raise ConfigError(
            f"--samples {shown(samples)}: at most {MAX_SAMPLES} members in one study (every "
            "member's values, task and figures are held in memory); split it into studies with "
            "different --seed values"
        )
    if design == "grid":
        return _grid_points(samples, dimensions)
    from scipy.stats import qmc  # on first use: the command line imports this module

    if design == "sobol":
        if samples & (samples - 1):
            below = 1 << (samples.bit_length() - 1)
            raise ConfigError(
                f"--samples {samples}: a Sobol' design needs a power of 2 (its balance holds "
                f"only then): {below} or {below * 2}"
            )
        points = qmc.Sobol(dimensions, scramble=True, seed=seed).random(samples)
    elif design == "lhs":
        points = qmc.LatinHypercube(dimensions, seed=seed).random(samples)
    else:
        points = np.random.default_rng(seed).random((samples, dimensions))
    # The open cube: an inverse distribution function is infinite at 0 and 1.
    tiny = np.finfo(float).eps
    return np.clip(points, tiny, 1.0 - tiny)


def _grid_points(samples: int, dimensions: int) -> Array:
    per_axis = round(samples ** (1.0 / dimensions))
    if per_axis**dimensions != samples:
        options = sorted({max(per_axis - 1, 1) ** dimensions, (per_axis + 1) ** dimensions})
        raise ConfigError(
            f"--samples {samples}: a grid over {dimensions} parameters needs k^{dimensions} "
            f"members (k points per parameter), e.g. {' or '.join(map(str, options))}"
        )
    midpoints = (np.arange(per_axis) + 0.5) / per_axis
    mesh = np.meshgrid(*([midpoints] * dimensions), indexing="ij")
    return np.stack([axis.ravel() for axis in mesh], axis=1)


def draw(variations: Sequence[Variation], design: str, samples: int, seed: int) -> Array:
    """The members' values, ``(samples, len(variations))``: :func:`unit_points` through each
    variation's inverse distribution function."""
    keys = [variation.key for variation in variations]
    repeated = sorted({key for key in keys if keys.count(key) > 1})
    if repeated:
        raise ConfigError(f"--vary: {', '.join(repeated)} given more than once")
    if not variations:
        raise ConfigError("--vary: at least one varied key is needed (KEY=DISTRIBUTION:ARGS)")
    unit = unit_points(design, samples, len(variations), seed)
    columns = [variation.values(unit[:, i]) for i, variation in enumerate(variations)]
    return np.stack(columns, axis=1)
