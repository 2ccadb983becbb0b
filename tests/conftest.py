"""Shared fixtures: scheme construction for tests."""

from __future__ import annotations

import numpy as np
import pytest

from conslaw import registry
from conslaw.grid import Grid
from conslaw.schemes.base import BoundarySpec
from conslaw.schemes.nessyahu_tadmor import NessyahuTadmor


def make_scheme(
    model_name: str = "burgers",
    reconstructor: str = "mc",
    n_cells: int = 32,
    boundary: str = "periodic",
    cfl: float = 0.45,
    x_min: float = 0.0,
    x_max: float = 1.0,
    **boundary_options: object,
) -> NessyahuTadmor:
    """An NT scheme on [x_min, x_max] with the same boundary condition on both sides."""
    model = registry.models.get(model_name)()
    side = BoundarySpec(registry.boundaries.get(boundary), dict(boundary_options))
    return NessyahuTadmor(
        model,
        registry.reconstructors.get(reconstructor),
        Grid(x_min, x_max, n_cells),
        side,
        side,
        cfl,
    )


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20011)
