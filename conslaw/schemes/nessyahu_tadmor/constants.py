"""Numerical constants shared by the compiled kernels and the numpy reference path.

Kept apart from the templates so that importing them does not import a template (and numba's
array machinery) into every process.
"""

#: ``|depth slope| <= DEPTH_SLOPE_LIMIT * depth``: the half-cell averages ``depth -+ slope/4`` keep
#: at least half the depth, so a wet cell always has mass on both sides of its centre and a small
#: enough time step keeps every new depth >= 0 (with the limit 4 a half cell can be empty while
#: the flux at the centre still drains it, and no time step helps).
DEPTH_SLOPE_LIMIT = 2.0

#: The velocity bound (new velocities within the Riemann-invariant range of their four source
#: cells) acts only in a thin tail: a new cell shallower than this fraction of the deepest of its
#: source cells. There the staggered average is a small difference of large terms and its velocity
#: can be an artefact (u = -1.9 upslope at depth 3e-5 behind a body of depth 1); elsewhere the
#: clamp, which is not conservative, would change the momentum of a wet flow (a Froude-10 shallow
#: water Riemann problem lost 5 % of its momentum).
THIN_TAIL = 1e-3

#: A sum of depths that comes out below 0 by no more than this many units of round-off of its
#: terms (relative to the sum of their magnitudes) is 0: the cell was emptied exactly, and only
#: the rounding of the sum says otherwise.
ROUND_OFF = 8.0 * 2.0**-52
