"""conslaw: hyperbolic conservation laws in 1D with Nessyahu–Tadmor central schemes.

Quick start::

    import conslaw
    result = conslaw.run("burgers-riemann", n_cells=800)
    print(result.headline_error())
"""

from conslaw.config import Scene, load_scene
from conslaw.errors import ConfigError, ConslawError, InadmissibleStateError, SchemeBreakdownError
from conslaw.grid import Grid
from conslaw.model import Model
from conslaw.simulation import RunResult, run, simulate
from conslaw.simulation2d import run_2d
from conslaw.state import State

__version__ = "0.1.0"

__all__ = [
    "ConfigError",
    "ConslawError",
    "Grid",
    "InadmissibleStateError",
    "Model",
    "RunResult",
    "Scene",
    "SchemeBreakdownError",
    "State",
    "load_scene",
    "run",
    "run_2d",
    "simulate",
]
