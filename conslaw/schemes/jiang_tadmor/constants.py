"""Numerical constants of the Jiang–Tadmor kernel and its numpy reference (kept apart from the
template, so that importing them does not import a template)."""

#: Relative margin of the quarter-velocity rule (``reference.quarter_velocity_outside``): a
#: quarter velocity outside the range of its cell's neighbours by less than this times the largest
#: velocity of the range is round-off of the 1D bound along each direction, not a new extreme.
QUARTER_MARGIN = 1e-12
