"""Ensembles of a scene: many members with varied parameters, run on local processes or a Dask
cluster, kept as one labelled dataset, with exceedance maps, run-out distributions and
sensitivities (docs/ensembles.md).

>>> from conslaw.ensemble import run_study                     # doctest: +SKIP
>>> study = run_study("sh-runout-shock", ["parameters.delta=uniform:20:28"], 64, "study")
>>> study.dataset.runout_length.quantile([0.05, 0.5, 0.95])  # doctest: +SKIP
"""

from __future__ import annotations

from conslaw.lazy_exports import lazy_exports

#: Where each public name lives; a submodule is imported on first use (PEP 562), so that the
#: command line, which imports a few constants of this package, pays for no more.
_HOMES = {
    "StudyInterrupted": "study",
    "StudyResult": "study",
    "run_study": "study",
    "Variation": "design",
    "parse_variation": "design",
}

__all__ = sorted(_HOMES)


__getattr__ = lazy_exports(__name__, _HOMES)
