"""Numerical constants shared by the compiled kernels and the numpy reference path.

Kept apart from the templates so that importing them does not import a template (and numba's
array machinery) into every process.
"""

#: ``|depth slope| <= DEPTH_SLOPE_LIMIT * depth``: the half-cell averages ``depth -+ slope/4`` keep
#: at least half the depth, so a wet cell always has mass on both sides of its centre and a small
#: enough time step keeps every new depth >= 0 (with the limit 4 a half cell can be empty while
#: the flux at the centre still drains it, and no time step helps).
DEPTH_SLOPE_LIMIT = 2.0
