"""Calibration of one shared parameter set on Table 4.6 of the thesis."""

import numpy as np
import pytest

from friction_model import (
    DryWetParameters,
    calibrate_table_4_6,
    evaluate_on_table_4_6,
    table_4_6_targets,
)


def test_targets_are_table_4_6():
    # Table 4.6 evaluated by hand at v = 1 and 4 m/s
    t = table_4_6_targets([1.0, 4.0]).set_index(["curve", "velocity_mps"])["mu_target"]
    assert t[("cold-dry 2.5 bar", 1.0)] == pytest.approx(0.295, abs=1e-12)
    assert t[("cold-dry 5 bar", 4.0)] == pytest.approx(0.125 / 2 + 0.05, abs=1e-12)
    assert t[("warm-humid 2.5 bar", 4.0)] == pytest.approx(0.03 * 2 + 0.075, abs=1e-12)
    assert t[("warm-humid 5 bar", 1.0)] == pytest.approx(0.06, abs=1e-12)


def test_default_parameters_meet_the_target():
    # The target: RMSE <= 0.015 on each curve with the right shape.
    table, rmse = evaluate_on_table_4_6(DryWetParameters())
    for name in ("cold-dry 2.5 bar", "cold-dry 5 bar", "warm-humid 2.5 bar", "warm-humid 5 bar"):
        assert rmse[name] <= 0.015, (name, rmse[name])
    for name, g in table.groupby("curve"):
        g = g.sort_values("velocity_mps")
        mu, target = g["mu_model"].to_numpy(), g["mu_target"].to_numpy()
        change, target_change = mu[-1] - mu[0], target[-1] - target[0]
        # the model must change in the measured direction by a good part of the measured
        # change from 1 to 7 m/s: it reaches 50-56 % on the warm/humid curves and more on
        # the cold/dry ones; 45 % leaves room for grid effects (about 1 %)
        assert np.sign(change) == np.sign(target_change)
        assert abs(change) >= 0.45 * abs(target_change), (name, change, target_change)


def test_calibration_from_a_perturbed_start_recovers_the_fit():
    # Start 40-60 % away from the calibrated values: one bounded least-squares run must get
    # back under the target on every curve.
    start = DryWetParameters(
        boundary_shear_Pa=2.0e4,
        critical_film_m=2.0e-7,
        contact_fraction_ref=0.4,
        contact_pressure_exponent=0.4,
    )
    _, rmse_start = evaluate_on_table_4_6(start)
    result = calibrate_table_4_6(start=start, n_starts=1)
    assert rmse_start["all"] > 0.02
    assert max(v for k, v in result.rmse.items() if k != "all") <= 0.015
    assert np.isfinite(result.params.boundary_shear_Pa)
    assert "RMSE" in result.summary()
