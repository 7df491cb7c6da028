"""The discrepancy workflow: find where model and measurement disagree, name the missing effect.

The thesis did this by hand twice (the velocity step of Fig. 5.7
needed the friction relaxation of Eq. 5.12; the stick-slip frequency needed the frequency
dependence of the rubber modulus, section 5.3.2); this package does it on data:

1. calibrate the base model on training data, holding out whole conditions or runs;
2. say where simulation and measurement disagree (:func:`where_analysis`,
   :func:`residual_spectrum`);
3. fit every candidate effect of the library (:func:`candidates`; add your own with
   :func:`register_candidate`), score it on held-out data (RSS, AICc, BIC);
4. name a winner only when the evidence is strong, else say ``ambiguous``, ``no missing
   effect found`` or ``unexplained residual``;
5. add the winner and repeat;
6. show the gap shrink (:func:`write_result`).

Public API
----------
:func:`run_discrepancy`, :class:`DiscrepancyResult`, :func:`write_result`,
:class:`Problem` (protocol), :class:`SteadyProblem` (:func:`read_steady_table`),
:class:`TransientProblem` (:class:`TransientRun`, :func:`read_transient_table`,
:func:`read_elements_table`, :func:`run_from_table`,
:func:`runs_from_elements`), :class:`StickSlipProblem` (:func:`stick_slip_case`,
:func:`thesis_stick_slip_problem`), :class:`Candidate`,
:class:`ParameterSpec`, :func:`register_candidate`, :func:`unregister_candidate`,
:func:`candidates`, :func:`get_candidate`, :func:`where_analysis`,
:func:`residual_spectrum`, scores :func:`chi_square` and (from
:mod:`friction_model.model_selection`) :func:`aicc_known_sigma`, :func:`bic_known_sigma`,
:func:`reduced_chi_square`, resampling :func:`group_folds`,
:func:`block_bootstrap_weights`.

Examples
--------
A steady table made by the base model itself, with 2 % scatter: nothing is missing.

>>> import itertools
>>> import numpy as np, pandas as pd
>>> from friction_model.contact.drywet import DryWetParameters, friction_table
>>> from friction_model.contact.effects import Effects
>>> from friction_model.geometry import BlockGeometry
>>> rows = pd.DataFrame(list(itertools.product([1.0, 2.0, 3.0, 5.0], [2.5], [-8.0, -4.0, -2.0],
...     [40.0, 90.0], [0.0])), columns=["velocity_mps", "pressure_bar", "temperature_C",
...     "humidity_pct", "salinity_pct"])
>>> mu = friction_table(BlockGeometry(n_sipes=0), rows,
...     DryWetParameters(effects=Effects.none()))["mu"].to_numpy()
>>> scatter = 1.0 + 0.02 * np.random.default_rng(3).standard_normal(len(rows))
>>> table = rows.assign(n_sipes=0, mu=mu * scatter, mu_std=0.02 * mu)
>>> result = run_discrepancy(SteadyProblem(table), n_bootstrap=20, n_permutations=99)
>>> result.verdict
'no missing effect found'
"""

from friction_model.discrepancy._problem import (
    Candidate,
    ParameterSpec,
    Problem,
    candidates,
    get_candidate,
    register_candidate,
    unregister_candidate,
)
from friction_model.discrepancy._report import write_result
from friction_model.discrepancy._scoring import (
    block_bootstrap_weights,
    chi_square,
    group_folds,
)
from friction_model.discrepancy._where import residual_spectrum, where_analysis
from friction_model.discrepancy._workflow import DiscrepancyResult, run_discrepancy
from friction_model.discrepancy.steady import SteadyProblem, read_steady_table
from friction_model.discrepancy.stickslip import (
    StickSlipProblem,
    StickSlipResult,
    predicted_stick_slip_problem,
    stick_slip_case,
    thesis_stick_slip_problem,
)
from friction_model.discrepancy.transient import (
    TransientProblem,
    TransientRun,
    read_elements_table,
    read_transient_table,
    run_from_table,
    runs_from_elements,
)
from friction_model.model_selection import (
    aicc_known_sigma,
    bic_known_sigma,
    reduced_chi_square,
)

__all__ = [
    "Candidate",
    "DiscrepancyResult",
    "ParameterSpec",
    "Problem",
    "SteadyProblem",
    "StickSlipProblem",
    "StickSlipResult",
    "TransientProblem",
    "TransientRun",
    "aicc_known_sigma",
    "bic_known_sigma",
    "block_bootstrap_weights",
    "candidates",
    "chi_square",
    "get_candidate",
    "group_folds",
    "predicted_stick_slip_problem",
    "read_elements_table",
    "read_steady_table",
    "read_transient_table",
    "reduced_chi_square",
    "register_candidate",
    "residual_spectrum",
    "run_discrepancy",
    "run_from_table",
    "runs_from_elements",
    "stick_slip_case",
    "thesis_stick_slip_problem",
    "unregister_candidate",
    "where_analysis",
    "write_result",
]
