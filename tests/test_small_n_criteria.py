"""AICc at small n in the discrepancy workflow (issue 26): where AICc is undefined
(n <= k + 1) it must not decide anything by arithmetic accident."""

from __future__ import annotations

import math

import pandas as pd

from friction_model.contact.drywet import DryWetParameters
from friction_model.contact.effects import Effects
from friction_model.discrepancy import SteadyProblem, run_discrepancy
from friction_model.discrepancy._steady_curves import steady_mu
from friction_model.model_selection import aicc_known_sigma


def test_a_second_effect_is_not_named_where_its_aicc_is_undefined():
    """Four rows (two conditions x two velocities) with the humidity layer planted: the
    base model plus one effect has k = 2 (AICc defined at n = 4), the look-ahead with a
    second effect k = 3, where AICc is infinite: no second effect may be named there."""
    rows = [(1.0, -2.0, 90.0), (5.0, -2.0, 90.0), (1.0, -8.0, 40.0), (5.0, -8.0, 40.0)]
    table = pd.DataFrame(rows, columns=["velocity_mps", "temperature_C", "humidity_pct"])
    table = table.assign(pressure_bar=2.5, salinity_pct=0.0, n_sipes=3)
    planted = DryWetParameters().with_(effects=Effects.none().with_(humidity_water_layer=1.0))
    mu = steady_mu(table, planted)
    problem = SteadyProblem(table.assign(mu=mu, mu_std=0.002 * mu))
    assert math.isinf(aicc_known_sigma(0.0, 3, 4)) and math.isfinite(aicc_known_sigma(0.0, 2, 4))
    result = run_discrepancy(problem, max_effects=2, n_bootstrap=20, n_permutations=49, seed=0)
    assert len(result.missing_effects) <= 1
    for rnd in result.rounds:
        ahead = rnd.get("look_ahead_criteria")
        if ahead is not None:
            assert not ahead["beats_runner_up"]  # inf - inf is no margin
