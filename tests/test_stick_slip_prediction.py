"""Stick-slip predicted from the one rubber and its discrepancy case.

Independent truths: the clamped-free frequency equation (N = 0) and the buckling load (the
loaded first frequency vanishes there) for the loaded mode; bisection for the strength the
modulus candidate would need; a recomputation of the frozen prediction (slow).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.optimize

from friction_model.compound import REFERENCE_COMPOUND
from friction_model.discrepancy import predicted_stick_slip_problem, stick_slip_case
from friction_model.discrepancy.stickslip import PLAUSIBLE_EXTRA_MODULUS_STRENGTH
from friction_model.dynamics.element_step import modulus_scaled_frequency_Hz
from friction_model.dynamics.stick_slip import (
    K4_INTERVAL_S_PER_M,
    PREDICTED_EXTRA_MODULUS_HZ,
    PREDICTED_STICK_SLIP_HZ,
    loaded_first_frequency_Hz,
    predict_stick_slip,
)
from friction_model.dynamics.timoshenko import (
    TimoshenkoParams,
    buckling_load,
    natural_frequencies_timoshenko,
)


def _p(**kw):
    c = REFERENCE_COMPOUND
    return TimoshenkoParams(
        E_Pa=c.E0_Pa,
        density_kg_m3=c.density_kg_m3,
        kelvin_voigt_s=0.0,
        contact_stiffness_N_m=1.0,
        **kw,
    )


def test_loaded_first_frequency_limits():
    p = _p()
    # N = 0: the frequency equation of the clamped-free beam; O(h^2) grid error < 1e-3
    assert loaded_first_frequency_Hz(p, 0.0) == pytest.approx(
        natural_frequencies_timoshenko(p, 1)[0], rel=1e-3
    )
    # towards the buckling load the first frequency goes to zero (f^2 ~ 1 - N / N_cr)
    f0 = loaded_first_frequency_Hz(p, 0.0)
    assert loaded_first_frequency_Hz(p, 0.99 * buckling_load(p)) < 0.15 * f0
    assert loaded_first_frequency_Hz(p, 0.5 * buckling_load(p)) < f0


def test_predicted_case_is_an_unexplained_residual():
    problem = predicted_stick_slip_problem()
    f_pred = PREDICTED_STICK_SLIP_HZ[50.0]
    result = stick_slip_case(problem)
    assert result.missing_effects == ()
    assert result.verdict.startswith("unexplained residual")
    assert result.gap_before_Hz == pytest.approx(1500.0 - f_pred, rel=1e-12)
    # independent of the constants the code reads: the rig's 1500 Hz (section 5.3.2) against
    # the README's published 826 Hz (held to the model by the slow recomputation below)
    assert result.gap_before_Hz == pytest.approx(1500.0 - 826.0, abs=1e-9)
    assert result.gap_after_Hz == result.gap_before_Hz
    # the gap in units of the stated uncertainty: rounding of the rig value (50 Hz wide,
    # uniform), the k4 range 793-857 Hz (uniform), the method's 5 Hz, typed from the README
    sigma = np.sqrt((50 / np.sqrt(3)) ** 2 + ((857 - 793) / 2 / np.sqrt(3)) ** 2 + 5**2)
    assert result.chi2_base == pytest.approx((674.0 / sigma) ** 2, rel=1e-9)  # 19.5 sigma
    fit = result.candidates["frequency_dependent_modulus"]
    # the loaded element's limit cycle passes 1500 Hz between the frozen s = 0.5 (1191 Hz)
    # and s = 1.0 (1547 Hz): the fitted extra strength lies there, above the plausible cap
    assert 0.5 < fit["value"] < 1.0
    # the chord between the two frozen points reaches 1500 Hz at s = 0.934; the table's
    # slopes on either side (712 and 586 Hz per unit s) bend the curve through the points
    # by less than 0.02 in s there
    chord = 0.5 + 0.5 * (1500.0 - 1190.9) / (1547.0 - 1190.9)
    assert fit["value"] == pytest.approx(chord, abs=0.02)
    assert problem.predict(np.empty(0), {"frequency_dependent_modulus": (fit["value"],)})[
        0
    ] == pytest.approx(1500.0, abs=1e-3)
    assert fit["interval"][0] > PLAUSIBLE_EXTRA_MODULUS_STRENGTH
    # the free-beam scaling f = f_c sqrt(E(f) / E0) of the thesis case would ask for 2.5:
    # the loaded column is far more sensitive to E
    need_free = scipy.optimize.bisect(
        lambda s: modulus_scaled_frequency_Hz(f_pred, strength=s) - 1500.0, 0.1, 5.0, xtol=1e-12
    )
    assert need_free > 2 * fit["value"]


def test_plausible_cap_is_a_compound_with_loss_factor_0_3():
    # at 1.5 kHz, tan(delta) 0.3 instead of 0.2 multiplies E(f) by 1500^(n(0.3) - n(0.2));
    # the candidate's 1 + s alpha log10(1500) matches it at s = 0.598 (round-off)
    from friction_model.compound import Compound
    from friction_model.dynamics.element_step import MODULUS_ALPHA

    ratio = 1500.0 ** (
        Compound(loss_factor=0.3).modulus_exponent - Compound(loss_factor=0.2).modulus_exponent
    )
    s = (ratio - 1.0) / (MODULUS_ALPHA * np.log10(1500.0))
    assert PLAUSIBLE_EXTRA_MODULUS_STRENGTH == pytest.approx(s, rel=1e-12)
    assert 0.55 < s < 0.65


@pytest.mark.slow
@pytest.mark.parametrize("s", [0.5, 1.0])
def test_frozen_extra_modulus_predictions_are_reproduced(s):
    out = predict_stick_slip(extra_modulus_strength=s)
    # same method tolerance as the base prediction
    assert out["frequency_Hz"] == pytest.approx(PREDICTED_EXTRA_MODULUS_HZ[s], abs=5.0)


@pytest.mark.slow
@pytest.mark.parametrize("k4", [K4_INTERVAL_S_PER_M[0], 50.0, K4_INTERVAL_S_PER_M[1]])
def test_frozen_prediction_is_reproduced(k4):
    out = predict_stick_slip(k4_s_per_m=k4)
    # method tolerance: BDF rtol 1e-5 and zero crossings over 30 ms (~ +-1 period in 25)
    assert out["frequency_Hz"] == pytest.approx(PREDICTED_STICK_SLIP_HZ[k4], abs=5.0)
    # the limit cycle runs below the linear first mode at E(f) (quasi-stick lengthens it)
    assert out["frequency_Hz"] < out["linear_mode_Hz"]
