"""Ensembles of a scene: many members with varied parameters, run on local processes or a Dask
cluster, kept as one labelled dataset, with exceedance maps, run-out distributions and
sensitivities (docs/ensembles.md).

>>> from conslaw.ensemble import run_study                     # doctest: +SKIP
>>> study = run_study("sh-runout-shock", ["parameters.delta=uniform:20:28"], 64, "study")
>>> study.dataset.runout_length.quantile([0.05, 0.5, 0.95])  # doctest: +SKIP
"""

from conslaw.ensemble.design import Variation, parse_variation
from conslaw.ensemble.study import StudyInterrupted, StudyResult, run_study

__all__ = ["StudyInterrupted", "StudyResult", "Variation", "parse_variation", "run_study"]
