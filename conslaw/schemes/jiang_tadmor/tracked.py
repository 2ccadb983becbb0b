"""The Jiang–Tadmor scheme with the margins of the depth tracked (``jiang-tadmor-ft``): the steps
of :class:`~conslaw.schemes.jiang_tadmor.scheme.JiangTadmor`, then after every step pair the
covered region moved with the flow and the film outside it gathered back
(:mod:`~conslaw.schemes.jiang_tadmor.margins`; docs/design.md, "Margins in two dimensions").
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from conslaw.errors import ConfigError
from conslaw.grid2d import Grid2D
from conslaw.model import Model
from conslaw.reconstruct import Reconstructor
from conslaw.schemes.jiang_tadmor.margins import MarginTracker
from conslaw.schemes.jiang_tadmor.reference import KINDS
from conslaw.schemes.jiang_tadmor.scheme import Array, JiangTadmor

#: Side kinds the tracker takes: material enters through neither.
TRACKED_SIDES = ("outflow", "wall")
#: Cells (of the larger size) by which gathering may move the centre of mass of the depth over a
#: run before the run is told that its margins lagged the material: a film gathered from all
#: round a margin moves it by a few hundredths of a cell (the similarity cap: 0.05 at 24 x 15,
#: 0.02 at 48 x 30), material the margin lagged by tenths (terrain-bowl: 0.48).
LAG_NOTE_CELLS = 0.1


class JiangTadmorTracked(JiangTadmor):
    """:class:`JiangTadmor` with the margins of the depth tracked by a level set
    (:class:`~conslaw.schemes.jiang_tadmor.margins.MarginTracker`): outside the covered region
    the depth and momenta are exactly 0, with no thin film ahead of a margin.

    Parameters
    ----------
    model, reconstructor, grid, boundaries
        As :class:`JiangTadmor`.
    *others, **options
        ``cfl``, ``threads``, ``chunks`` and ``inflow``, as :class:`JiangTadmor`.

    Raises
    ------
    ConfigError
        If the model has no depth and two momenta, if a side is periodic or an inflow
        (material would enter where no margin is tracked), or as :class:`JiangTadmor`.

    Notes
    -----
    The margin moves with the velocity of the flow next to it (a material margin). A margin
    whose speed peaks at the tip while the depth vanishes (a dam break onto a dry bed, where the
    velocity grows across the rarefaction) is followed with the velocity of the nearest cells
    deep enough to carry one (:data:`~conslaw.schemes.jiang_tadmor.margins.VELOCITY_DEPTH_SHARE`
    of the deepest), which lags such a tip: use it for granular margins of finite slope
    (docs/design.md, "Margins in two dimensions").
    """

    name: ClassVar[str] = "jiang-tadmor-ft"
    description: ClassVar[str] = (
        "Jiang-Tadmor scheme in 2D with the depth's margins tracked by a level set (no thin film)"
    )
    boundary_kinds: ClassVar[tuple[str, ...]] = tuple(k for k in KINDS if k in TRACKED_SIDES)

    def __init__(
        self,
        model: Model,
        reconstructor: Reconstructor,
        grid: Grid2D,
        boundaries: Mapping[str, str],
        *others: Any,
        **options: Any,
    ) -> None:
        rows = (model.depth_index, model.momentum_index, model.momentum_y_index)
        if any(row is None for row in rows):
            raise ConfigError(
                f"scheme '{self.name}' tracks the margins of a depth: model '{model.name}' has "
                "no depth and two momenta"
            )
        for side, kind in boundaries.items():
            if kind not in TRACKED_SIDES:
                raise ConfigError(
                    f"boundary.{side} = '{kind}': scheme '{self.name}' takes only "
                    f"{' or '.join(TRACKED_SIDES)} sides (material would enter where no margin "
                    "is tracked)"
                )
        super().__init__(model, reconstructor, grid, boundaries, *others, **options)
        depth, momentum_x, momentum_y = (int(row) for row in rows)  # type: ignore[arg-type]
        self.tracker = MarginTracker(grid, depth, momentum_x, momentum_y)

    def initial_values(self, initial: Any) -> Array | None:
        """As :meth:`JiangTadmor.initial_values`; also starts the tracked region as the one
        the initial data cover
        (:meth:`~conslaw.schemes.jiang_tadmor.margins.MarginTracker.start_from_initial`).

        Parameters
        ----------
        initial : InitialCondition2D
            The scene's initial condition.

        Returns
        -------
        numpy.ndarray
            As :meth:`JiangTadmor.initial_values`, and otherwise the cell averages the region
            was started from (computed once).
        """
        values = super().initial_values(initial)
        if values is not None:
            self.tracker.start_from_values(values)
            return values
        averages = np.asarray(initial.cell_averages(self.grid, self.model), dtype=np.float64)
        self.tracker.start_from_initial(initial, self.model, averages)
        return averages

    def _advance_pair(self, t: float, t_end: float, steps: int) -> tuple[float, int]:
        """One accepted step pair from ``t`` (:meth:`JiangTadmor._advance_pair`), then the
        region moved over it and the material outside gathered in."""
        if self.tracker.level is None:
            self.tracker.start_from_values(self._values(0))
        before = self._values(0).copy()
        new_t, new_steps = super()._advance_pair(t, t_end, steps)
        after = self._values(0).copy()
        if self.tracker.follow(before, after, new_t - t):
            self._load(after, 0)
        return new_t, new_steps

    def notes(self) -> list[str]:
        """What a run on this scheme should be told: that its tracked margins lagged the
        material, if gathering moved the centre of mass of the depth by more than
        :data:`LAG_NOTE_CELLS` cells over the run or material lay more than
        :data:`~conslaw.schemes.jiang_tadmor.margins.MAX_GATHER` cells out.

        Returns
        -------
        list of str
            One line each (none for a run whose margins followed the material).
        """
        tracker = self.tracker
        cell = max(self.grid.dx, self.grid.dy)
        if tracker.gathered_shift <= LAG_NOTE_CELLS * cell and tracker.joined == 0:
            return []
        return [
            "the tracked margins lagged the material: gathering it back moved its centre of "
            f"mass by {tracker.gathered_shift:.3g} ({tracker.gathered_shift / cell:.2g} cells) "
            f"over the run, up to {100 * tracker.largest_gathered:.2g} % of it in one step pair, "
            f"and {tracker.joined} cells joined the region late; the flow spreads faster at its "
            "edges than the margins follow (a released block), so compare with scheme "
            'jiang-tadmor (docs/design.md, "Margins in two dimensions")'
        ]
