"""Test-rig runs: reading the run files and evaluating their forces (sections 4.2.4, 4.4).

One module per job, in the order a run passes through them:

* :mod:`._io` reads one run file (columns, units, metadata) into a :class:`RigRun`;
* :mod:`.params` holds the detection and binning parameters, :mod:`.results` the result
  records and table columns;
* :mod:`.signals` smooths and differentiates, :mod:`.plateaus` finds the constant-velocity
  window of a steady run;
* :mod:`.steady` evaluates a steady run (both average coefficients of section 4.2.4),
  :mod:`.instationary` an instationary run (``mu(v)`` per branch, section 4.4);
* :mod:`.aggregate` averages repeated runs and the ambient conditions (Table 4.2);
* :mod:`.files` finds the run files, :mod:`.batch` evaluates many of them,
  :mod:`.figures` and :mod:`.write` write the figures, tables and provenance record.
"""

from friction_model.rig._io import (
    OPTIONAL_COLUMNS,
    REQUIRED_COLUMNS,
    RigRun,
    RunFormatError,
    read_run,
)
from friction_model.rig.aggregate import aggregate_runs, ambient_table, steady_characteristic
from friction_model.rig.batch import evaluate_folder, evaluate_runs
from friction_model.rig.files import collect_run_files
from friction_model.rig.instationary import evaluate_instationary_run, instationary_characteristic
from friction_model.rig.params import InstationaryParams, WindowParams
from friction_model.rig.plateaus import find_constant_velocity_window
from friction_model.rig.results import (
    AMBIENT_COLUMNS,
    INSTATIONARY_COLUMNS,
    STEADY_COLUMNS,
    EvaluationFailure,
    EvaluationResult,
    InstationaryRunResult,
    SteadyRunResult,
    VelocityWindow,
)
from friction_model.rig.steady import (
    evaluate_steady_run,
    friction_coefficient,
    mean_friction_coefficients,
)
from friction_model.rig.write import write_outputs

__all__ = [
    "AMBIENT_COLUMNS",
    "INSTATIONARY_COLUMNS",
    "OPTIONAL_COLUMNS",
    "REQUIRED_COLUMNS",
    "STEADY_COLUMNS",
    "EvaluationFailure",
    "EvaluationResult",
    "InstationaryParams",
    "InstationaryRunResult",
    "RigRun",
    "RunFormatError",
    "SteadyRunResult",
    "VelocityWindow",
    "WindowParams",
    "aggregate_runs",
    "ambient_table",
    "collect_run_files",
    "evaluate_folder",
    "evaluate_instationary_run",
    "evaluate_runs",
    "evaluate_steady_run",
    "find_constant_velocity_window",
    "friction_coefficient",
    "instationary_characteristic",
    "mean_friction_coefficients",
    "read_run",
    "steady_characteristic",
    "write_outputs",
]
