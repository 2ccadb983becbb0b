"""Numerical constants shared by the compiled kernels and the numpy reference path.

Kept apart from the templates so that importing them does not import a template (and numba's
array machinery) into every process.
"""

#: ``|depth slope| <= DEPTH_SLOPE_LIMIT * depth``: the half-cell averages ``depth -+ slope/4`` keep
#: at least half the depth, so a wet cell always has mass on both sides of its centre and a small
#: enough time step keeps every new depth >= 0 (with the limit 4 a half cell can be empty while
#: the flux at the centre still drains it, and no time step helps).
DEPTH_SLOPE_LIMIT = 2.0

#: A wet new cell shallower than this fraction of the deepest cell of its source family is a
#: *film*: films carry velocities, they do not make them (docs/design.md, "Films"). Its Riemann
#: invariants stay within those of the cells its update reads, which only the cells of the flow
#: (at least this fraction of the deepest) widen by what their source and resistance can change in
#: one step, and its velocity between rest and them. There the staggered average is a small
#: difference of large terms and its velocity can be an artefact (u = -1.9 upslope at depth 3e-5
#: behind a body of depth 1); films on the flanks of the channel of AvaFrame's hockey stick, bounded
#: by the films around them, outran the flow until the time step collapsed. The bound is not
#: conservative, so it acts in films only (a Froude-10 shallow water Riemann problem lost 5 %
#: of its momentum when it acted in wet cells).
FILM = 1e-2

#: A sum of depths that comes out below 0 by no more than this many units of round-off of its
#: terms (relative to the sum of their magnitudes) is 0: the cell was emptied exactly, and only
#: the rounding of the sum says otherwise.
ROUND_OFF = 8.0 * 2.0**-52

#: Tries of one step pair before a run stops: a pair is redone with half its step while a depth
#: would become negative, and with the Courant bound of its staggered values if their Courant
#: number would reach 1/2; after this many tries (2^-60 of the first step at most) the scheme has
#: broken down and the run stops with a message naming the time, step and cell (every scheme's
#: time loop, 1D and 2D).
MAX_RETRIES = 60
