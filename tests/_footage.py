"""Settings the tests' synthetic footage shares.

STEADY_SETTLE_S: how long the rigid block model runs before a ``dynamics="steady"`` clip
freezes its state (the mean of the last 30 % of the run). Tests that hold the pipeline to
the renderer's own ground truth do not need the block settled to the thesis's steady state,
only a deflected block that the truth describes; 4 ms instead of the default 20 ms makes the
simulation about five times cheaper (the elements are already deflected by a few degrees).
Tests that check the dynamics themselves keep the default.
"""

STEADY_SETTLE_S = 0.004
