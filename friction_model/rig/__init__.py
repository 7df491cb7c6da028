"""Test-rig runs: reading the run files and evaluating their forces (sections 4.2.4, 4.4).

:mod:`._io` reads one run (columns, units, metadata); :mod:`.evaluation` finds the
constant-velocity plateaus, evaluates steady and instationary runs, aggregates repeats and
writes the tables and figures.
"""

from friction_model.rig.evaluation import *  # noqa: F403
from friction_model.rig.evaluation import __all__ as _evaluation

__all__ = [*_evaluation]
