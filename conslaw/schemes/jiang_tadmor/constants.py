"""Numerical constants of the Jiang–Tadmor kernel and its numpy reference (kept apart from the
template, so that importing them does not import a template)."""

#: Relative margin of the quarter-velocity rule (``reference.quarter_velocity_outside``): a
#: quarter velocity outside the range of its cell's neighbours by less than this times the largest
#: velocity of the range is round-off of the 1D bound along each direction, not a new extreme.
QUARTER_MARGIN = 1e-12

#: The smallest normal double: a momentum below it has lost its relative precision (subnormal),
#: so a quarter's momentum within this of the range's bound is inside.
TINY = 2.2250738585072014e-308
