"""Numerical constants of the Jiang–Tadmor kernel and its numpy reference (kept apart from the
template, so that importing them does not import a template)."""

#: Relative margin of the quarter-velocity rule (``reference.quarter_velocity_outside``): a
#: quarter velocity outside the range of its cell's neighbours by less than this times the largest
#: velocity of the range is round-off of the 1D bound along each direction, not a new extreme.
QUARTER_MARGIN = 1e-12

#: Relative margin of the speed bound of films (``JiangTadmorReference._bound_velocities``): a
#: film's speed above the largest speed of its window by less than this is round-off of the bounds
#: along x and y (which imply the speed bound where the data vary along one axis), not an extreme.
SPEED_MARGIN = 1e-12

#: The smallest normal double: a momentum below it has lost its relative precision (subnormal),
#: so a quarter's momentum within this of the range's bound is inside.
TINY = 2.2250738585072014e-308

#: A cell over a bed is still (its bed read as still water over flat quarters, its depth's
#: quarters free to be empty) while every velocity is below this fraction of its wave speed.
STILL = 1e-9

#: Columns of a family's per-row statistics (``kernel_template.row_statistics``, read by the time
#: loop of :class:`~conslaw.schemes.jiang_tadmor.scheme.JiangTadmor`): the largest wave speed in
#: x, in y, the smallest and the largest depth; :data:`STATISTICS` columns in all.
SPEED_X = 0
SPEED_Y = 1
LOWEST = 2
DEEPEST = 3
STATISTICS = 4
