"""conslaw: hyperbolic conservation laws in 1D with Nessyahu–Tadmor central schemes.

Quick start::

    import conslaw
    result = conslaw.run("burgers-riemann", n_cells=800)
    print(result.headline_error())
"""

from typing import TYPE_CHECKING

from conslaw.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from conslaw.config import Scene, load_scene
    from conslaw.errors import (
        ConfigError,
        ConslawError,
        InadmissibleStateError,
        SchemeBreakdownError,
    )
    from conslaw.grid import Grid
    from conslaw.model import Model
    from conslaw.simulation import RunResult, run, simulate
    from conslaw.simulation2d import run_2d
    from conslaw.state import State

#: Where each public name lives; a submodule is imported on first use (PEP 562), so that the
#: command line starts its figure process before numba and the kernels are imported
#: (docs/performance.md, "The whole conslaw run process").
_HOMES = {
    "Scene": "config",
    "load_scene": "config",
    "ConfigError": "errors",
    "ConslawError": "errors",
    "InadmissibleStateError": "errors",
    "SchemeBreakdownError": "errors",
    "Grid": "grid",
    "Model": "model",
    "RunResult": "simulation",
    "run": "simulation",
    "simulate": "simulation",
    "run_2d": "simulation2d",
    "State": "state",
}

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

__getattr__ = lazy_exports(__name__, _HOMES)


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
